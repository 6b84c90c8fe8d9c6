// laminar-wasm/eval in node (package.json's "node" condition): index.js beside it,
// reading each build's .wasm from disk (a browser fetches it by URL).
import { readFile } from 'node:fs/promises';
import { loadBuild, simdSupported } from '../loader.js';

export { simdSupported };

/** Loads and initialises one build (`simd` forces the choice) and returns its exports. */
export function load(options = {}) {
  return loadBuild(
    {
      plain: {
        glue: () => import('./plain/laminar_wasm.js'),
        wasm: () => readFile(new URL('./plain/laminar_wasm_bg.wasm', import.meta.url)),
      },
      simd: {
        glue: () => import('./simd/laminar_wasm.js'),
        wasm: () => readFile(new URL('./simd/laminar_wasm_bg.wasm', import.meta.url)),
      },
    },
    options,
  );
}
