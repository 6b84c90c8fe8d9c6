// laminar-brdf: the whole package (evaluation, measurements, fitting,
// prediction). `laminar-brdf/eval` is the evaluation-only package.
import { loadBuild, simdSupported } from './loader.js';

export { simdSupported };

/**
 * Loads and initialises one build (`simd` forces the choice; `read(url)`,
 * where given, returns the `.wasm`'s bytes instead of a fetch) and returns
 * its exports. The files are named by literals, the form bundlers rewrite.
 */
export function load(options = {}) {
  return loadBuild(
    {
      plain: {
        glue: () => import('./plain/laminar_wasm.js'),
        wasm: () => new URL('./plain/laminar_wasm_bg.wasm', import.meta.url),
      },
      simd: {
        glue: () => import('./simd/laminar_wasm.js'),
        wasm: () => new URL('./simd/laminar_wasm_bg.wasm', import.meta.url),
      },
    },
    options,
  );
}
