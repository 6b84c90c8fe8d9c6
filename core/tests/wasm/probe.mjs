// Prints every probe value of a wasm_probe build: "f32x8 f32 f64" bits in hex, one line each.
import { readFileSync } from 'node:fs';

const { instance } = await WebAssembly.instantiate(readFileSync(process.argv[2]));
const e = instance.exports;
const n = e.probe_count();
const lines = [];
for (let i = 0; i < n; i++) {
  const a = (e.probe_f32x8(i) >>> 0).toString(16);
  const b = (e.probe_f32(i) >>> 0).toString(16);
  const c = BigInt.asUintN(64, e.probe_f64(i)).toString(16);
  lines.push(`${a} ${b} ${c}`);
}
process.stdout.write(lines.join('\n') + '\n');
