// Calls every export of the npm package, in both builds, with arguments
// drawn from a pool of wrong and right values of every JavaScript type
// (seeded: the same calls every run). Each call must return or throw an
// Error; a WebAssembly trap (RuntimeError: unreachable, memory access out
// of bounds) fails, and after every call the module must still evaluate.
// Prints { calls, returned, typeErrors, errors } per build.
//
// node arguments.mjs PACKAGE_DIR CALLS
import { pathToFileURL } from 'node:url';

const [packageDir, callsText] = process.argv.slice(2);
const { load } = await import(pathToFileURL(`${packageDir}/node.js`).href);
const calls = Number(callsText);

// xorshift32: a fixed sequence.
let state = 0x9e3779b9;
function next() {
  state ^= state << 13;
  state ^= state >>> 17;
  state ^= state << 5;
  return (state >>> 0) / 0x100000000;
}
const pick = (pool) => pool[Math.floor(next() * pool.length)];

const out = {};
for (const simd of [false, true]) {
  const L = await load({ simd });
  const csv = new TextEncoder().encode(L.exampleCsv());
  const m = L.Measurements.fromCsv('example.csv', csv, 'rad', 'radiance');
  const fitted = L.fit(m, 'value', 'exp', { objective: 'paper', refine: false, uncertainty: 'off', slope: '1.48', n: '1.44', a: '0.17' });
  const pool = [
    undefined, null, true, 0, -1, 0.3, 1.48, 1e308, NaN, Infinity, 2 ** 53, 10n, Symbol('s'), () => 1,
    '', 'exp', 'gauss', 'rh-exp', 'value', '1.2', 'rad', 'radiance', 'x'.repeat(10_000), '\u0000\u001b[2J',
    [], ['exp', 'jensen'], [0.3, 0.2, 0.5], ['0.3', 0.2, 0.5], [[1]], {}, { length: 1e9 }, { objective: 'paper', refine: 'no' },
    { onProgress: 3 }, { slope: 7 }, new Float64Array([0.3, 0.2, 0.5]), new Float64Array(2), new Float32Array(3),
    new Uint8Array([1, 2, 3]), csv, new ArrayBuffer(8), fitted, '{}', m, JSON.parse(fitted).fits[0].fitted,
    { model: 'exp', params: { slope: 1, beta: '0.5', n: 1.4, a: 0 }, normalisation: {} },
  ];
  const exports = [
    ['validateParams', 4], ['totalRadiance', 6], ['totalRadianceF32', 6], ['components', 6],
    ['curetSamples', 3], ['fit', 4], ['compare', 4], ['fitJoint', 3], ['predict', 3], ['fromCsv', 4], ['fromCuret', 4], ['scene', 1],
    ['predictFitted', 2],
  ];
  const call = (name, args) => {
    if (name === 'fromCsv' || name === 'fromCuret') return L.Measurements[name](...args);
    if (name === 'scene') return m.scene(...args);
    return L[name](...args);
  };
  const tally = { calls: 0, returned: 0, typeErrors: 0, errors: 0 };
  for (let k = 0; k < calls; k++) {
    const [name, arity] = pick(exports);
    const args = Array.from({ length: arity }, () => pick(pool));
    tally.calls++;
    try {
      const r = call(name, args);
      if (r && typeof r.free === 'function' && r !== m) r.free();
      tally.returned++;
    } catch (e) {
      if (e instanceof WebAssembly.RuntimeError || !(e instanceof Error)) {
        console.error(`${simd ? 'simd' : 'plain'} ${name}(${args.map((a) => typeof a).join(', ')}): ${e}`);
        process.exit(1);
      }
      if (e instanceof TypeError) tally.typeErrors++;
      else tally.errors++;
    }
    // Not poisoned: the module still evaluates.
    if (L.totalRadiance('exp', new Float64Array([0.3, 0.2, 0.5]), 1.2, 0.4, 1.4, 0.3).length !== 1) {
      console.error(`after ${name}: the module no longer evaluates`);
      process.exit(1);
    }
  }
  const fail = (what) => {
    console.error(`${simd ? 'simd' : 'plain'}: ${what}`);
    process.exit(1);
  };
  // free() from onProgress during a fit is refused, and the set still works.
  const busy = L.Measurements.fromCsv('example.csv', csv, 'rad', 'radiance');
  let refused = null;
  L.fit(busy, 'value', 'exp', {
    onProgress: () => {
      try {
        busy.free();
      } catch (e) {
        refused = e;
      }
    },
  });
  if (!(refused instanceof Error) || !String(refused.message).includes('a fit of this set is running')) fail(`free() during a fit: ${refused}`);
  if (busy.scene('value').data.length !== busy.length) fail('the set no longer works after the refused free()');
  busy.free();
  // An array the module cannot hold is a RangeError naming the argument,
  // not a trap; the module still evaluates after it.
  for (const [what, call] of [
    ['the input', () => L.totalRadiance('exp', new Float64Array(2 ** 29 - 1), 1.2, 0.4, 1.4, 0.3)],
    ['the outputs', () => L.components('exp', new Float64Array(3 * 2 ** 26), 1.2, 0.4, 1.4, 0.3)],
  ]) {
    try {
      call();
      fail(`${what} too large for the module was accepted`);
    } catch (e) {
      if (!(e instanceof RangeError) || !String(e.message).startsWith('angles: ')) fail(`${what} too large: ${e}`);
    }
    if (L.totalRadiance('exp', new Float64Array([0.3, 0.2, 0.5]), 1.2, 0.4, 1.4, 0.3).length !== 1) fail(`after ${what}: the module no longer evaluates`);
  }
  m.free();
  out[simd ? 'simd' : 'plain'] = tally;
}
console.log(JSON.stringify(out));
