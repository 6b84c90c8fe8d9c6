// Opens a bundled app (wasm/tests/vite-app, built by Vite against the packed
// package) in Debian's Chromium (headless, through playwright-core) and
// prints one JSON line: the app's results (#out), the .wasm files the page
// fetched with their HTTP statuses, and any page or console error.
//
// node web/tests/bundler.mjs DIST
// exits non-zero when the app did not finish or an error was seen.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { extname, join, normalize } from 'node:path';
import { chromium } from 'playwright-core';

const [dist] = process.argv.slice(2);
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm' };

const server = createServer(async (req, res) => {
  const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^(\.\.[/\\])+/, '');
  try {
    const file = join(dist, path.endsWith('/') ? `${path}index.html` : path);
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--no-first-run'],
});
const problems = [];
const wasm = [];
let result = null;
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('console', (m) => m.type() === 'error' && problems.push(`console error: ${m.text()}`));
  page.on('response', (r) => {
    if (r.url().endsWith('.wasm')) wasm.push({ path: new URL(r.url()).pathname, status: r.status() });
    if (r.status() >= 400) problems.push(`${r.status()} for ${r.url()}`);
  });
  await page.goto(`http://127.0.0.1:${server.address().port}/`);
  await page.waitForSelector('body[data-done="true"]', { timeout: 60_000 });
  result = JSON.parse(await page.textContent('#out'));
  if (result.error) problems.push(`the app: ${result.error}`);
} catch (e) {
  problems.push(String(e));
} finally {
  await browser.close();
  server.close();
}
console.log(JSON.stringify({ result, wasm, problems }));
process.exit(problems.length === 0 ? 0 : 1);
