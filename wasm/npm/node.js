// laminar-brdf in node (package.json's "node" condition): index.js beside it,
// reading each build's .wasm from disk (a browser fetches it by URL).
import { readFile } from 'node:fs/promises';
import { load as loadFrom, simdSupported } from './index.js';

export { simdSupported };

/** Loads and initialises one build (`simd` forces the choice) and returns its exports. */
export function load(options = {}) {
  return loadFrom({ read: readFile, ...options });
}
