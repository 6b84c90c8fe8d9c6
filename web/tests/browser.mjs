// Drives the built page in Debian's Chromium (headless, through
// playwright-core): loads the built-in example, fits it, checks that the
// page shows exactly the fit of `laminar fit` on the same data, moves a
// slider and checks that the lobe is redrawn, saves a screenshot, and
// measures the package's speed in the browser.
//
// Then compares every model and checks the ranking against `laminar fit`
// with every model; and, given Cornell's krylon_blue_RGB.astm, fits its
// three channels jointly (exp2, relative noise) and checks the page's
// material, tables and spectrum against `laminar fit-joint --fits`.
//
// node web/tests/browser.mjs DIST EXPECTED_FITS_JSON SCREENSHOT.png EXPECTED_COMPARISON_JSON [KRYLON_BLUE_RGB.astm EXPECTED_JOINT_JSON]
// prints one JSON line of measurements; exits non-zero on any failure.
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { extname, join, normalize } from 'node:path';
import { chromium } from 'playwright-core';

const [dist, expectedFile, screenshot, comparisonFile, jointData, jointFile] = process.argv.slice(2);
const expected = await readFile(expectedFile, 'utf8');
const comparison = await readFile(comparisonFile, 'utf8');
const BENCH = new URL('../../wasm/bench/speed.js', import.meta.url);
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css', '.wasm': 'application/wasm' };

const server = createServer(async (req, res) => {
  const path = normalize(decodeURIComponent(new URL(req.url, 'http://x').pathname)).replace(/^(\.\.[/\\])+/, '');
  // The page's files, and the speed measurement (not part of the page).
  const file = path === '/__bench/speed.js' ? BENCH : join(dist, path.endsWith('/') ? `${path}index.html` : path);
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': TYPES[extname(path)] ?? 'text/html' });
    res.end(body);
  } catch {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const url = `http://127.0.0.1:${server.address().port}/`;

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--no-first-run'],
});
const problems = [];
function check(ok, what) {
  if (!ok) problems.push(what);
}
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 1400 } });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  page.on('console', (m) => m.type() === 'error' && problems.push(`console error: ${m.text()}`));
  // The page fetches the evaluation-only package before the whole one (the
  // lobe viewer works before the fitting module arrives).
  const wasm = [];
  page.on('request', (r) => r.url().endsWith('.wasm') && wasm.push(new URL(r.url()).pathname));
  await page.goto(url);
  await page.waitForSelector('body[data-lobe="true"]', { timeout: 60_000 });
  await page.waitForSelector('body[data-ready="true"]', { timeout: 60_000 });
  check(wasm.length >= 2 && wasm[0].includes('/laminar-brdf/eval/'), `wasm fetched in the order ${wasm.join(', ')}`);
  const build = await page.textContent('#build');

  await page.click('#example');
  await page.waitForSelector('#fit:enabled');
  check((await page.textContent('#loaded')).includes('200 measurements'), `loaded: ${await page.textContent('#loaded')}`);
  const lobeBefore = await page.getAttribute('#lobe-path', 'd');
  await page.click('#fit');
  await page.waitForSelector('#results:not([hidden])', { timeout: 300_000 });
  const progress = await page.evaluate(() => [document.getElementById('progress').value, document.getElementById('progress').max]);
  // The free objective (the page's default) reports once per fit.
  check(progress[0] === 1 && progress[1] === 1, `progress ended at ${progress}`);

  // The fitted-model file the page made is the CLI's, byte for byte.
  const shownJson = await page.textContent('#fit-json');
  check(shownJson === expected, 'the page\'s fitted-model file differs from `laminar fit --format json`');
  // And the table shows the CLI's numbers.
  const entry = JSON.parse(expected).fits[0];
  const fmt = (v) => (v === null || v === undefined ? '–' : Number(v).toPrecision(5));
  const rows = await page.$$eval('#params tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
  const order = Object.keys(entry.fitted.params).filter((k) => k in entry.parameters);
  const want = order.map((name) => [name, entry.parameters[name]]).map(([name, p]) => [
    name, fmt(p.grid), fmt(p.refined), `[${fmt(p.lo68)}, ${fmt(p.hi68)}]`, `[${fmt(p.lo95)}, ${fmt(p.hi95)}]`, p.interval, p.box ? `[${fmt(p.box[0])}, ${fmt(p.box[1])}]` : '–', p.flags.join(', '),
  ]);
  check(JSON.stringify(rows) === JSON.stringify(want), `parameter table ${JSON.stringify(rows)} != ${JSON.stringify(want)}`);
  check(rows.length === 4, `${rows.length} parameter rows`);
  const points = await page.$$eval('#scatter circle', (c) => c.length);
  check(points === entry.measurements, `${points} scatter points for ${entry.measurements} measurements`);

  // The sliders took the fit's values; moving one redraws the lobe.
  const lobeFitted = await page.getAttribute('#lobe-path', 'd');
  check(lobeFitted !== lobeBefore, 'the lobe did not change to the fitted model');
  await page.$eval('#slider-slope', (s) => {
    s.value = '0.3';
    s.dispatchEvent(new Event('input', { bubbles: true }));
  });
  const lobeMoved = await page.getAttribute('#lobe-path', 'd');
  check(lobeMoved !== lobeFitted, 'moving the σ/T slider did not redraw the lobe');
  // The sphere preview beside it is redrawn too, lit from the upper left.
  const sphere = await page.$eval('#sphere', (c) => {
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const at = (x, y) => d[4 * (y * c.width + x)];
    return { drawn: Number(c.dataset.drawn), upperLeft: at(48, 48), lowerRight: at(112, 112), corner: at(2, 2), width: c.width };
  });
  check(sphere.drawn >= 3, `the sphere was drawn ${sphere.drawn} times (at load, at the fit, at the slider)`);
  check(sphere.upperLeft > 100 && sphere.upperLeft > sphere.lowerRight, `sphere pixels ${JSON.stringify(sphere)}`);
  check(sphere.corner === 24, `the sphere's background is ${sphere.corner}`);
  check((await page.textContent('#value-slope')) === '0.3', 'the σ/T slider\'s value is not shown');
  await page.screenshot({ path: screenshot, fullPage: true });

  // Every model compared: the page's file is the CLI's with every model,
  // and its table ranks them as the file does.
  await page.click('#compare');
  await page.waitForSelector('#comparison:not([hidden])', { timeout: 300_000 });
  await page.waitForSelector('#compare:enabled');
  const pageComparison = await page.textContent('#fit-json');
  if (pageComparison !== comparison) {
    await writeFile(`${comparisonFile}.page`, pageComparison);
    check(false, `the page's comparison differs from \`laminar fit --models …\` (the page's: ${comparisonFile}.page)`);
  }
  const ranked = JSON.parse(comparison).fits;
  const ranking = await page.$$eval('#ranking tbody tr', (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
  const wantRanking = ranked.map((e) => [e.model, String(e.rank.rank), fmt(e.rank.delta), fmt(e.rank.weight), fmt(e.cross_validation.rms)]);
  check(JSON.stringify(ranking.map((r) => r.slice(0, 5))) === JSON.stringify(wantRanking), `ranking ${JSON.stringify(ranking)} != ${JSON.stringify(wantRanking)}`);
  check(ranking.length === ranked.length && ranking.filter((r) => r[1] === '1').length === 1, `ranking ${JSON.stringify(ranking)}`);
  await page.screenshot({ path: screenshot.replace(/\.png$/, '-compare.png'), fullPage: true });

  // A defective file: the page names its line, column and value, and offers no fit.
  await page.setInputFiles('#files', {
    name: 'bad.csv',
    mimeType: 'text/csv',
    buffer: Buffer.from('theta_i,theta_s,phi_s,v\n0.1,0.2,0.3,1\n0.1,abc,0.3,2\n'),
  });
  await page.waitForSelector('#loaded.error');
  const bad = await page.textContent('#loaded');
  check(bad === 'bad.csv:3: column 2 (theta_s): `abc` is not a number', `bad file: ${bad}`);
  check(await page.isDisabled('#fit'), 'the fit button stays enabled after a bad file');

  // An ASTM E1392 file (the Cornell gonioreflectometer's text form): its
  // columns after the geometry become the channels; a defect is named.
  const astm = 'NUM_POINTS 3\nVARS theta_i,phi_i,theta_s,phi_s,450nm,550nm\n\n'
    + '0.5,0,0.4,3.0,0.09,0.03\n0.5,0,0.6,2.0,0.08,0.02\n0.3,0,0.3,3.0,1.2,0.9\n';
  await page.setInputFiles('#files', { name: 'paint.astm', mimeType: 'text/plain', buffer: Buffer.from(astm) });
  await page.waitForFunction(() => document.querySelector('#loaded').textContent.startsWith('paint.astm'));
  const loaded = await page.textContent('#loaded');
  check(loaded === 'paint.astm: 3 measurements, channels 450nm, 550nm.', `ASTM file: ${loaded}`);
  await page.setInputFiles('#files', { name: 'bad.astm', mimeType: 'text/plain', buffer: Buffer.from(astm.replace('0.6,2.0', 'x,2.0')) });
  await page.waitForSelector('#loaded.error');
  const badAstm = await page.textContent('#loaded');
  check(badAstm === 'bad.astm:5: column 3 (theta_s): `x` is not a number', `bad ASTM file: ${badAstm}`);

  // CUReT's two files, when the data are here (CURET_DIR).
  let curet = null;
  if (process.env.CURET_DIR) {
    await page.setInputFiles('#files', ['table.txt', 'abrdf.dat'].map((f) => join(process.env.CURET_DIR, f)));
    await page.waitForSelector('#curet-sample:not([hidden])');
    curet = await page.textContent('#loaded');
    check(/^CUReT sample \d+ of abrdf\.dat: \d+ measurements, channels avg\.$/.test(curet), `CUReT: ${curet}`);
    check(!(await page.isDisabled('#fit')), 'CUReT files loaded but no fit offered');
  }

  // A joint fit of Cornell's blue paint (RGB), when given: the page's
  // material is `laminar fit-joint --fits`'s byte for byte, its tables show
  // that file's numbers, and the spectrum draws each channel's a and bands.
  let joint = null;
  if (jointData) {
    await page.setInputFiles('#files', jointData);
    await page.waitForFunction(() => document.querySelector('#loaded').textContent.startsWith('krylon_blue_RGB.astm'));
    await page.selectOption('#model', 'exp2');
    await page.selectOption('#noise', 'relative');
    await page.waitForSelector('#fit-joint:enabled');
    const started = Date.now();
    await page.click('#fit-joint');
    await page.waitForSelector('#joint-results:not([hidden])', { timeout: 300_000 });
    const seconds = (Date.now() - started) / 1000;
    check(await page.isHidden('#results'), 'the single fit\'s results stay shown beside the joint fit\'s');
    const wantJoint = await readFile(jointFile, 'utf8');
    const pageJoint = await page.textContent('#joint-json');
    if (pageJoint !== wantJoint) {
      await writeFile(`${jointFile}.page`, pageJoint);
      check(false, `the page's joint fit differs from \`laminar fit-joint --fits\` (the page's: ${jointFile}.page)`);
    }
    const material = JSON.parse(wantJoint).materials[0];
    const iv = (v, l) => (v?.intervals ? `[${fmt(v.intervals[`lo${l}`])}, ${fmt(v.intervals[`hi${l}`])}]` : '–');
    const cells = (id) => page.$$eval(`#${id} tbody tr`, (trs) => trs.map((tr) => [...tr.cells].map((c) => c.textContent)));
    const shared = await cells('shared');
    const wantShared = Object.entries(material.shared).map(([k, v]) => [k, fmt(v.value), iv(v, 68), iv(v, 95)]);
    check(JSON.stringify(shared) === JSON.stringify(wantShared), `shared ${JSON.stringify(shared)} != ${JSON.stringify(wantShared)}`);
    check(shared.map((r) => r[0]).join() === 'n,slope,sub_slope', `shared parameters ${shared.map((r) => r[0])}`);
    const channels = await cells('joint-channels');
    const wantChannels = material.channels.map((c) => [c.channel, fmt(c.a?.value), iv(c.a, 68), iv(c.a, 95), fmt(c.beta), fmt(c.amplitude), c.lack_of_fit ? 'lack of fit' : 'ok']);
    check(JSON.stringify(channels) === JSON.stringify(wantChannels), `channels ${JSON.stringify(channels)} != ${JSON.stringify(wantChannels)}`);
    const variants = await cells('variants');
    check(variants.length === Object.keys(material.variants).length && variants[0][1] === fmt(0), `variants ${JSON.stringify(variants)}`);
    const tests = await page.textContent('#joint-tests');
    const p = (v) => (v === null ? 'not tested' : `p = ${Number(v).toPrecision(2)}`);
    check(tests.includes(`chromatic?): ${p(material.chromatic_p)}`) && tests.includes(`shared?): ${p(material.roughness_p)}`), `tests: ${tests}`);
    const figure = await page.evaluate(() => ({
      points: document.querySelectorAll('#spectrum-points circle').length,
      bands: document.querySelectorAll('#spectrum .band68, #spectrum .band95').length,
      series: [...document.querySelectorAll('#scatter .points')].map((g) => [g.dataset.channel, g.childElementCount]),
    }));
    const withA = material.channels.filter((c) => c.a).length;
    check(figure.points === withA && figure.bands === 2, `spectrum: ${JSON.stringify(figure)}`);
    const wantSeries = material.channels.map((c) => [c.channel, material.measurements]);
    check(JSON.stringify(figure.series) === JSON.stringify(wantSeries), `scatter series ${JSON.stringify(figure.series)}`);
    await page.screenshot({ path: screenshot.replace(/\.png$/, '-joint.png'), fullPage: true });
    joint = { seconds, shared, chromatic: material.chromatic_p, roughness: material.roughness_p };
  }

  // Speed in this browser (main thread), as wasm/bench/node.mjs measures it in node.
  const speed = await page.evaluate(async () => {
    const { measure } = await import('/__bench/speed.js');
    return measure((await import('./laminar-brdf/index.js')).load);
  });
  console.log(JSON.stringify({ build, progress, rows, points, bad, curet, joint, chromium: browser.version(), speed }));
} finally {
  await browser.close();
  server.close();
}
if (problems.length) {
  console.error(`browser test failed:\n- ${problems.join('\n- ')}`);
  process.exit(1);
}
