// laminar-wasm: the whole package (evaluation, measurements, fitting,
// prediction). `laminar-wasm/eval` is the evaluation-only package.
import { loadBuild, simdSupported } from './loader.js';

export { simdSupported };

/** Loads and initialises one build (`simd` forces the choice) and returns its exports. */
export function load(options = {}) {
  return loadBuild(
    import.meta.url,
    { plain: () => import('./plain/laminar_wasm.js'), simd: () => import('./simd/laminar_wasm.js') },
    options,
  );
}
