// Evaluates the npm package on the cases in CASES.json, in both builds, and
// prints the bit patterns: { plain: { f32: [...], f64: [...] }, simd: ... }
// (f32 as u32, f64 as two u32 halves, high first). cli/tests/web.rs compares
// them with the native library's.
//
// node bitwise.mjs PACKAGE_DIR CASES.json
import { readFile } from 'node:fs/promises';
import { pathToFileURL } from 'node:url';

const [packageDir, casesFile] = process.argv.slice(2);
const { load } = await import(pathToFileURL(`${packageDir}/index.js`).href);
const cases = JSON.parse(await readFile(casesFile, 'utf8'));
const angles = new Float64Array(cases.angles);
const out = {};
for (const simd of [false, true]) {
  const L = await load({ simd });
  const f32 = [];
  const f64 = [];
  for (const model of cases.models) {
    for (const [slope, beta, n, a] of cases.params) {
      f32.push(...new Uint32Array(L.totalRadianceF32(model, angles, slope, beta, n, a).buffer));
      const v = new Uint32Array(L.totalRadiance(model, angles, slope, beta, n, a).buffer);
      for (let k = 0; k < v.length; k += 2) f64.push(v[k + 1], v[k]);
    }
  }
  out[simd ? 'simd' : 'plain'] = { build: L.simd, f32, f64 };
}
console.log(JSON.stringify(out));
