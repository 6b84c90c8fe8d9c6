// The package's speed, measured the same way in node (wasm/bench/node.mjs)
// and in Chromium (web/tests/browser.mjs); wasm/examples/speed.rs measures
// the native library on the same work.

/** K geometries (θi, θs, φs), radians, spread over the domain. */
export function geometries(k) {
  const deg = Math.PI / 180;
  const angles = new Float64Array(3 * k);
  for (let i = 0; i < k; i++) {
    angles[3 * i] = ((i % 89) * deg);
    angles[3 * i + 1] = (((i * 7) % 89) * deg);
    angles[3 * i + 2] = ((i % 360) - 180) * deg;
  }
  return angles;
}

function best(runs, f) {
  let ms = Infinity;
  for (let r = 0; r < runs; r++) {
    const t = performance.now();
    f();
    ms = Math.min(ms, performance.now() - t);
  }
  return ms;
}

/** Evaluations per second and fit times (ms) of both builds. */
export async function measure(load) {
  const k = 100_000;
  const angles = geometries(k);
  const out = {};
  for (const simd of [false, true]) {
    const L = await load({ simd });
    const m = L.Measurements.fromCsv('example.csv', new TextEncoder().encode(L.exampleCsv()), 'rad', 'radiance');
    const rate = (f) => k / (best(5, f) / 1000);
    out[simd ? 'simd' : 'plain'] = {
      f64_per_s: rate(() => L.totalRadiance('exp', angles, 1.2, 0.4, 1.4, 0.3)),
      f32_per_s: rate(() => L.totalRadianceF32('exp', angles, 1.2, 0.4, 1.4, 0.3)),
      search_ms: best(5, () => L.fit(m, 'value', 'exp', { refine: false, uncertainty: 'off' })),
      full_fit_ms: best(3, () => L.fit(m, 'value', 'exp')),
    };
    m.free();
  }
  return out;
}
