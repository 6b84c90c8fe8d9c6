// A minimal app a user would bundle with Vite: both entry points of the
// packed package, each build. Writes one JSON line into #out (the driver,
// web/tests/bundler.mjs, reads it) and sets body[data-done].
import { load } from 'laminar-brdf';
import { load as loadEvaluation } from 'laminar-brdf/eval';

const ANGLES = new Float64Array([0.3, 0.2, 0.5, 0.9, 0.4, 2.5]); // (θi, θs, φs), two geometries
// Each value's IEEE bits in hex, so that the driver compares bits.
function bits(x) {
  const view = new DataView(new ArrayBuffer(8));
  view.setFloat64(0, x);
  return view.getBigUint64(0).toString(16).padStart(16, '0');
}
const result = {};
try {
  for (const simd of [false, true]) {
    for (const [name, loader] of [['whole', load], ['eval', loadEvaluation]]) {
      const L = await loader({ simd });
      const total = L.totalRadiance('exp', ANGLES, 1.2, 0.4, 1.4, 0.3);
      result[`${name}/${L.simd ? 'simd' : 'plain'}`] = Array.from(total, bits);
    }
  }
} catch (e) {
  result.error = String(e);
}
document.getElementById('out').textContent = JSON.stringify(result);
document.body.dataset.done = 'true';
