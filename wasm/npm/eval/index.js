// laminar-brdf/eval: the evaluation-only package (eq. 8 and its components
// in f64 and f32x8, parameter checks, a fitted model's prediction from its
// parameters and normalisation constants). No fitting, no file readers: a
// page that only draws a fitted model loads this, a few tens of KiB.
import { loadBuild, simdSupported } from '../loader.js';

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
