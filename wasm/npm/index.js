// laminar-wasm: loads the +simd128 build where the engine has WebAssembly
// SIMD, the plain build elsewhere. Works in browsers (fetches the .wasm
// beside this file) and in node (reads it from disk).

// A module whose one function returns a v128 (i32.const 0, i8x16.splat,
// i8x16.popcnt): it validates only where SIMD is supported (the probe of
// the wasm-feature-detect package).
const SIMD_PROBE = new Uint8Array([
  0, 97, 115, 109, 1, 0, 0, 0, 1, 5, 1, 96, 0, 1, 123, 3, 2, 1, 0, 10, 10, 1, 8, 0, 65, 0, 253, 15,
  253, 98, 11,
]);

/** Whether this engine runs WebAssembly SIMD (the `+simd128` build). */
export function simdSupported() {
  return WebAssembly.validate(SIMD_PROBE);
}

/**
 * Loads and initialises one build (`simd` forces the choice) and returns its
 * exports, with `simd` saying which build it is.
 */
export async function load(options = {}) {
  const simd = options.simd ?? simdSupported();
  const glue = simd ? await import('./simd/laminar_wasm.js') : await import('./plain/laminar_wasm.js');
  const url = new URL(`./${simd ? 'simd' : 'plain'}/laminar_wasm_bg.wasm`, import.meta.url);
  const source = url.protocol === 'file:' ? await (await import('node:fs/promises')).readFile(url) : url;
  await glue.default({ module_or_path: source });
  return Object.freeze({ ...glue, simd });
}
