// node wasm/bench/node.mjs [PACKAGE_DIR]: the package's speed in node.
import { pathToFileURL } from 'node:url';
import { measure } from './speed.js';

const dir = process.argv[2] ?? new URL('../../target/npm', import.meta.url).pathname;
const { load } = await import(pathToFileURL(`${dir}/node.js`).href);
console.log(JSON.stringify({ node: process.version, ...(await measure(load)) }, null, 1));
