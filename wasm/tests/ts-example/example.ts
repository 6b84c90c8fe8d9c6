// A TypeScript project using the packed npm package: type-checked by
// `tsc` (cli/tests/web.rs), then run by node.
import { load, simdSupported, type FitOptions, type FitsFile, type Laminar, type ModelParams } from 'laminar-brdf';
import { load as loadEvaluation, type LaminarEval } from 'laminar-brdf/eval';

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
// The paper objective's grid search: one progress call per σ/T value.
const options: FitOptions = { objective: 'paper', refine: false, uncertainty: 'off', onProgress: () => calls++ };
const json: string = L.fit(m, 'value', 'exp', options);
const file: FitsFile = JSON.parse(json);
// A grid of one σ/T, n and a value: one progress call, those values fitted.
let customCalls = 0;
const custom: FitsFile = JSON.parse(L.fit(m, 'value', 'exp', {
  refine: false, uncertainty: 'off', slope: '1.48', n: '1.44', a: '0.17', path: 'direct-f64', onProgress: () => customCalls++,
}));
// The default, the free-amplitude objective: one progress call per fit.
let freeCalls = 0;
const free: FitsFile = JSON.parse(L.fit(m, 'value', 'exp', { onProgress: () => freeCalls++ }));
const scene = m.scene('value');
const prediction: Float64Array = L.predict(json, undefined, scene.angles);
errors.push(
  thrown(() => L.predict(json, 'example/value/gauss', scene.angles)),
  thrown(() => L.predict('{}', undefined, scene.angles)),
  thrown(() => L.fit(m, 'r', 'exp')),
  thrown(() => L.Measurements.fromCsv('x.csv', new Uint8Array(), 'grad', 'brdf')),
  thrown(() => L.fit(m, 'value', 'exp', { n: '1.5:1.3:x' })),
  thrown(() => L.fit(m, 'value', 'exp', { refine: 'yes' } as unknown as FitOptions)),
  thrown(() => L.fit(m, 'value', 'exp', { objective: 'max' } as unknown as FitOptions)),
);
// Wrong types from JavaScript (casts past the types): TypeErrors naming
// the argument, never a trap or a silent coercion.
const loose = L as unknown as Record<string, (...args: unknown[]) => unknown>;
/** The class and message of what `f` throws. */
function kind(f: () => unknown): string {
  try {
    f();
  } catch (e) {
    return `${(e as Error).constructor.name}: ${(e as Error).message}`;
  }
  return 'nothing thrown';
}
const typeErrors = [
  kind(() => loose.fit(m, 'value', 3)),
  kind(() => loose.totalRadiance('exp', angles, '1.2', 0.4, 1.4, 0.3)),
  kind(() => loose.totalRadiance('exp', 'angles', 1.2, 0.4, 1.4, 0.3)),
  kind(() => loose.totalRadiance('exp', [0.3, '0.2', 0.5], 1.2, 0.4, 1.4, 0.3)),
  kind(() => loose.predict(json, 7, scene.angles)),
  kind(() => (L.Measurements as unknown as Record<string, (...a: unknown[]) => unknown>).fromCsv('x.csv', 'text', 'rad', 'brdf')),
  kind(() => m.scene(5 as unknown as string)),
];
// An array of numbers is taken as a Float64Array.
const fromArray = L.totalRadiance('exp', [0.3, 0.2, 0.5] as unknown as Float64Array, 1.2, 0.4, 1.4, 0.3)[0];
// A fit started from a fit's own onProgress runs, and the outer fit ends
// with its own progress; the Measurements object stays usable.
let outerCalls = 0;
let inner = '';
L.fit(m, 'value', 'exp', {
  objective: 'paper', refine: false, uncertainty: 'off', slope: '1.4:1.56:3',
  onProgress: (done) => {
    outerCalls++;
    if (done === 1) inner = JSON.parse(L.fit(m, 'value', 'rh-exp', { refine: false, uncertainty: 'off' })).fits[0].model;
  },
});
const afterNested = m.channels.join(',');
// Every model of the descriptor is fitted by its name; every correlation's
// name evaluates (the lists the page builds its menus from).
const models = L.models();
const fittedModels = models.map((info) =>
  (JSON.parse(L.fit(m, 'value', info.name, { refine: false, uncertainty: 'off' })) as FitsFile).fits[0].model);
const lobes = L.correlations().map((c) => L.totalRadiance(c, angles, 1.2, 0.4, 1.4, 0.3).length);
// The evaluation-only package: the same totals, and the fitted model's
// prediction from the file's `fitted` entry equal to `predict`'s.
const E: LaminarEval = await loadEvaluation();
const evalTotal: Float64Array = E.totalRadiance('exp', angles, 1.2, 0.4, 1.4, 0.3);
const evalPrediction: Float64Array = E.predictFitted(file.fits[0].fitted, scene.angles);
const evalErrors = [
  thrown(() => E.predictFitted({ ...file.fits[0].fitted, normalisation: { amplitude: -1 } }, scene.angles)),
  kind(() => E.predictFitted({ ...file.fits[0].fitted, params: { slope: 1 } as unknown as ModelParams }, scene.angles)),
];
console.log(JSON.stringify({
  evalSame: evalTotal.every((v, k) => v === total[k]) && evalPrediction.every((v, k) => v === prediction[k]),
  evalSimd: E.simd,
  evalErrors,
  typeErrors,
  fromArray,
  outerCalls,
  inner,
  afterNested,
  models: models.map((info) => info.name),
  modelParams: models.map((info) => info.params.join(',')),
  fittedModels,
  correlations: L.correlations(),
  lobes,
  simd: L.simd,
  simdSupported: simdSupported(),
  total: Array.from(total),
  f32: Array.from(f32),
  message,
  errors,
  calls,
  params: file.fits[0].params,
  custom: custom.fits[0].params,
  customCalls,
  freeCalls,
  freeObjective: free.fits[0].objective,
  freeBox: free.fits[0].parameters.n.box,
  rms: file.fits[0].rms,
  predicted: prediction.length,
  measured: scene.data.length,
}));
m.free();
