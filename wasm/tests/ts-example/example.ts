// A TypeScript project using the packed npm package: type-checked by
// `tsc` (cli/tests/web.rs), then run by node.
import { load, simdSupported, type FitsFile, type Laminar } from 'laminar-wasm';

const L: Laminar = await load();
const angles = new Float64Array([0.3, 0.2, 0.5, 0.6, 0.4, 1.0]);
const total: Float64Array = L.totalRadiance('exp', angles, 1.2, 0.4, 1.4, 0.3);
const f32: Float32Array = L.totalRadianceF32('gauss', angles, 1.2, 0.4, 1.4, 0.3);

/** The message of the Error `f` throws. */
function thrown(f: () => unknown): string {
  try {
    f();
  } catch (e) {
    return (e as Error).message;
  }
  return 'nothing thrown';
}
const message = thrown(() => L.validateParams(1.2, 1.5, 1.4, 0.3));
const errors = [
  thrown(() => L.totalRadiance('exp', new Float64Array([0.1, 2, 0]), 1.2, 0.4, 1.4, 0.3)),
  thrown(() => L.totalRadiance('exp', new Float64Array([0.1, 0.2]), 1.2, 0.4, 1.4, 0.3)),
  thrown(() => L.totalRadianceF32('lambert', angles, 1.2, 0.4, 1.4, 0.3)),
  thrown(() => L.components('gauss', angles, 0, 0.4, 1.4, 0.3)),
];

const m = L.Measurements.fromCsv('example.csv', new TextEncoder().encode(L.exampleCsv()), 'rad', 'radiance');
let calls = 0;
const json: string = L.fit(m, 'value', 'exp', false, 'off', () => calls++);
const file: FitsFile = JSON.parse(json);
const scene = m.scene('value');
const prediction: Float64Array = L.predict(json, undefined, scene.angles);
errors.push(
  thrown(() => L.predict(json, 'example/value/gauss', scene.angles)),
  thrown(() => L.predict('{}', undefined, scene.angles)),
  thrown(() => L.fit(m, 'r', 'exp')),
);
console.log(JSON.stringify({
  simd: L.simd,
  simdSupported: simdSupported(),
  total: Array.from(total),
  f32: Array.from(f32),
  message,
  errors,
  calls,
  params: file.fits[0].params,
  rms: file.fits[0].rms,
  predicted: prediction.length,
  measured: scene.data.length,
}));
m.free();
