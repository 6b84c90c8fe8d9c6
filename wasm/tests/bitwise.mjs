// Evaluates the npm package on the cases in CASES.json, in both builds of the
// whole package and of the evaluation-only one (`laminar-brdf/eval`), and
// prints the bit patterns: { plain: { build, f32: [...], f64: [...] }, simd,
// eval_plain, eval_simd } (f32 as u32, f64 as two u32 halves, high first).
// cli/tests/web.rs compares them with the native library's. `fitted` says
// whether eval's predictFitted equals the whole package's predict bit for
// bit on the built-in example's fits (free and paper objectives, exp and
// gauss), for each pair of builds.
//
// node bitwise.mjs PACKAGE_DIR CASES.json
import { readFile } from 'node:fs/promises';
import { pathToFileURL } from 'node:url';

const [packageDir, casesFile] = process.argv.slice(2);
const whole = await import(pathToFileURL(`${packageDir}/node.js`).href);
const evaluation = await import(pathToFileURL(`${packageDir}/eval/node.js`).href);
const cases = JSON.parse(await readFile(casesFile, 'utf8'));
const angles = new Float64Array(cases.angles);

function bits(L) {
  const f32 = [];
  const f64 = [];
  for (const model of cases.models) {
    for (const [slope, beta, n, a] of cases.params) {
      f32.push(...new Uint32Array(L.totalRadianceF32(model, angles, slope, beta, n, a).buffer));
      const v = new Uint32Array(L.totalRadiance(model, angles, slope, beta, n, a).buffer);
      for (let k = 0; k < v.length; k += 2) f64.push(v[k + 1], v[k]);
    }
  }
  return { build: L.simd, f32, f64 };
}

const out = {};
const loaded = {};
for (const simd of [false, true]) {
  const name = simd ? 'simd' : 'plain';
  loaded[name] = await whole.load({ simd });
  loaded[`eval_${name}`] = await evaluation.load({ simd });
  out[name] = bits(loaded[name]);
  out[`eval_${name}`] = bits(loaded[`eval_${name}`]);
}

// Fits of the built-in example, predicted by both packages at every case angle.
const L = loaded.plain;
const example = L.Measurements.fromCsv('example.csv', new TextEncoder().encode(L.exampleCsv()), 'rad', 'radiance');
const fitted = { compared: 0, differ: 0 };
for (const objective of ['free', 'paper']) {
  for (const model of ['exp', 'gauss']) {
    const json = L.fit(example, 'value', model, { objective });
    const entry = JSON.parse(json).fits[0];
    for (const simd of ['plain', 'simd']) {
      const want = new Uint32Array(loaded[simd].predict(json, undefined, angles).buffer);
      const got = new Uint32Array(loaded[`eval_${simd}`].predictFitted(entry.fitted, angles).buffer);
      fitted.compared += want.length / 2;
      for (let k = 0; k < want.length; k++) if (want[k] !== got[k]) fitted.differ += 1;
    }
  }
}
example.free();
out.fitted = fitted;
console.log(JSON.stringify(out));
