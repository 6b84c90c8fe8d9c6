// The loader all entry points share (index.js and node.js: the whole
// package; eval/: the evaluation-only one): picks the +simd128 build where
// the engine has WebAssembly SIMD, the plain build elsewhere. Each entry
// point names its builds' files itself, as `import('./…')` and
// `new URL('./…', import.meta.url)` literals, the forms bundlers (Vite,
// webpack, Rollup, Parcel) follow and rewrite; node.js reads the .wasm from
// disk, so no Node built-in is reachable from the browser's entry.

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
 * Loads and initialises one build (`options.simd` forces the choice):
 * `builds.plain` and `builds.simd` each give `glue()`, the import of its
 * wasm-bindgen module, and `wasm()`, the URL of its `.wasm`, which
 * `options.read(url)` turns into the bytes where given (node.js reads from
 * disk), and which is fetched otherwise. Returns the build's exports, with
 * `simd` saying which build it is.
 */
export async function loadBuild(builds, options = {}) {
  const simd = options.simd ?? simdSupported();
  const build = simd ? builds.simd : builds.plain;
  const module = await build.glue();
  const url = build.wasm();
  await module.default({ module_or_path: options.read ? await options.read(url) : url });
  return Object.freeze({ ...module, ...guardedFits(module), simd });
}

const GUARDED = new WeakMap(); // a build's module → its guarded fits

/**
 * `fit` and `compare` of the whole package, marking their measurements as
 * in use while they run, and `Measurements.prototype.free` refusing a set
 * in use (called from `onProgress`, wasm-bindgen would refuse the free
 * only after it had already let go of the handle, leaving it unusable):
 * an `Error`, after which the set still works and can be freed once the
 * fit returns. Nothing for the evaluation-only package.
 */
function guardedFits(module) {
  const Measurements = module.Measurements;
  if (!Measurements) return {};
  if (GUARDED.has(module)) return GUARDED.get(module);
  const inUse = new Map(); // a set → how many fits of it are running
  const free = Measurements.prototype.free;
  Measurements.prototype.free = function () {
    if (inUse.has(this)) {
      throw new Error('Measurements.free(): a fit of this set is running (free it after the fit returns)');
    }
    return free.call(this);
  };
  const guard = (run) => (m, ...rest) => {
    const held = m instanceof Measurements;
    if (held) inUse.set(m, (inUse.get(m) ?? 0) + 1);
    try {
      return run(m, ...rest);
    } finally {
      if (held) {
        const n = inUse.get(m) - 1;
        if (n === 0) inUse.delete(m);
        else inUse.set(m, n);
      }
    }
  };
  const fits = { fit: guard(module.fit), compare: guard(module.compare) };
  GUARDED.set(module, fits);
  return fits;
}
