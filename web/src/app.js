// The page: load measurements, fit them in a worker, show the fit and an
// interactive lobe. All numbers come from laminar-brdf.
//
// The evaluation-only package (laminar-brdf/eval, about 40 KiB gzip) loads
// first, so the lobe viewer works at once; the whole package (measurements,
// prediction; about 570 KiB gzip) follows, and the controls that need it are
// enabled when it has arrived.
import { load as loadEvaluation } from './laminar-brdf/eval/index.js';
import { load } from './laminar-brdf/index.js';
import { lobe, scatter, spectrum } from './plot.js';
import { measurementsFrom } from './source.js';

const E = await loadEvaluation();
let L = null; // the whole package, once it has arrived
const $ = (id) => document.getElementById(id);
const DEG = Math.PI / 180;
/** How the page shows a number (the browser test formats the CLI's the same way). */
// A number to 5 digits; a word (`not_identified`) as words; '–' for none.
export const fmt = (v) =>
  v === null || v === undefined ? '–' : typeof v === 'string' ? v.replace(/_/g, ' ') : Number(v).toPrecision(5);

$('build').textContent = `laminar-brdf ${E.version()}, ${E.simd ? 'SIMD (+simd128)' : 'plain'} build`;
const NEEDS_WHOLE = ['files', 'example'];
for (const id of NEEDS_WHOLE) $(id).disabled = true;

let source = null; // see source.js
let fitting = null; // { channel, model, models, joint, noise, source } of the last fit asked for
let busy = false; // a fit is under way
const worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module' });

function status(id, text, error = false) {
  $(id).textContent = text;
  $(id).classList.toggle('error', error);
}

/** Reads the source into a Measurements to list its channels; errors are shown. */
function useSource(s) {
  let m;
  try {
    m = measurementsFrom(L, s);
    source = s;
    const channels = m.channels;
    $('channel').replaceChildren(...channels.map((c) => new Option(c, c)));
    const what = s.kind === 'file' ? s.name : `CUReT sample ${s.sample} of ${s.brdfName}`;
    status('loaded', `${what}: ${m.length} measurements, channels ${channels.join(', ')}.`);
    enableFits();
  } catch (e) {
    source = null;
    enableFits();
    status('loaded', String(e.message ?? e), true);
  } finally {
    m?.free();
  }
}

/** The fit buttons: enabled when a source is loaded and no fit is under
 * way; the joint fit when the source has two channels or more. */
function enableFits() {
  $('fit').disabled = busy || source === null;
  $('compare').disabled = busy || source === null;
  $('fit-joint').disabled = busy || source === null || $('channel').options.length < 2;
}

function fileSource(name, bytes) {
  return { kind: 'file', name, bytes, angles: $('angles').value, quantity: $('quantity').value };
}

async function loadFiles(files) {
  const byName = new Map([...files].map((f) => [f.name, f]));
  // A long CSV, NIST's BRDF CSV, an ASTM E1392 .astm or RGL's .bsdf.
  const file = [...files].find((f) => /\.(csv|astm|bsdf)$/i.test(f.name));
  const brdf = [...files].find((f) => /brdf\.dat$/i.test(f.name));
  $('curet-sample').hidden = true;
  if (file) return useSource(fileSource(file.name, new Uint8Array(await file.arrayBuffer())));
  if (brdf && byName.has('table.txt')) {
    const table = new Uint8Array(await byName.get('table.txt').arrayBuffer());
    const bytes = new Uint8Array(await brdf.arrayBuffer());
    try {
      const samples = L.curetSamples(table, brdf.name, bytes);
      $('sample').replaceChildren(...[...samples].map((s) => new Option(s, s)));
      $('curet-sample').hidden = false;
      return useSource({ kind: 'curet', table, brdfName: brdf.name, brdf: bytes, sample: samples[0] });
    } catch (e) {
      return status('loaded', String(e.message ?? e), true);
    }
  }
  status('loaded', 'Give a .csv, .astm or .bsdf file, or CUReT\'s table.txt together with a BRDF file such as abrdf.dat.', true);
}

$('files').addEventListener('change', (e) => loadFiles(e.target.files));
const drop = $('drop');
drop.addEventListener('dragover', (e) => {
  e.preventDefault();
  drop.classList.add('over');
});
drop.addEventListener('dragleave', () => drop.classList.remove('over'));
drop.addEventListener('drop', (e) => {
  e.preventDefault();
  drop.classList.remove('over');
  if (!L) return status('loaded', 'The fitting module is still loading: drop the files again in a moment.', true);
  loadFiles(e.dataTransfer.files);
});
$('example').addEventListener('click', () => {
  $('angles').value = 'rad';
  $('quantity').value = 'radiance';
  $('curet-sample').hidden = true;
  useSource(fileSource('example.csv', new TextEncoder().encode(L.exampleCsv())));
});
for (const id of ['angles', 'quantity']) {
  $(id).addEventListener('change', () => source?.kind === 'file' && useSource(fileSource(source.name, source.bytes)));
}
$('sample').addEventListener('change', () => useSource({ ...source, sample: Number($('sample').value) }));

// Fitting, in the worker: one fit (or one comparison) at a time.
function startFit(models, joint = false) {
  fitting = { channel: $('channel').value, model: $('model').value, models, joint, noise: $('noise').value, source };
  if (joint && !MODELS.find((m) => m.name === fitting.model)?.correlation) {
    const layered = MODELS.filter((m) => m.correlation).map((m) => m.name);
    return status('fit-status', `The joint fit takes a layered model (${layered.join(', ')}), not ${fitting.model}.`, true);
  }
  busy = true;
  enableFits();
  $('progress').removeAttribute('value');
  status('fit-status', joint ? 'fitting every channel, bootstrapping…' : 'searching the grid…');
  worker.postMessage(fitting);
}
$('fit').addEventListener('click', () => startFit(null));
$('compare').addEventListener('click', () => startFit(MODELS.map((m) => m.name)));
$('fit-joint').addEventListener('click', () => startFit(null, true));
worker.onmessage = ({ data }) => {
  if (data.progress) {
    const [done, total] = data.progress;
    $('progress').max = total;
    $('progress').value = done;
    status('fit-status', done < total ? `grid: ${done} of ${total} σ/T values` : 'refining, intervals…');
    return;
  }
  busy = false;
  enableFits();
  if (data.error) {
    $('progress').value = 0;
    return status('fit-status', data.error, true);
  }
  $('progress').value = $('progress').max;
  status('fit-status', `done in ${(data.ms / 1000).toFixed(2)} s`);
  $('results').hidden = fitting.joint;
  $('joint-results').hidden = !fitting.joint;
  if (fitting.joint) showJoint(data.json);
  else showFit(data.json);
};

/** The searched parameters in the model's order (σ/T, β, n, a). */
export const parameterOrder = (entry) =>
  Object.keys(entry.fitted.params).filter((k) => k in entry.parameters).map((k) => [k, entry.parameters[k]]);

/** Table rows of `cells`, each row's `data-key` its first cell. */
function tableRows(rows) {
  return rows.map((cells) => {
    const tr = document.createElement('tr');
    tr.dataset.key = cells[0];
    for (const c of cells) tr.appendChild(Object.assign(document.createElement('td'), { textContent: c }));
    return tr;
  });
}

/** What the residuals say of a fit (`fit` in `laminar fit --format markdown`). */
export const adequacyText = (a) => {
  if (!a) return '–';
  if (!a.lack_of_fit) return 'ok';
  const p = [['χ²', a.chi2_p], ['runs', a.runs_p]].filter(([, v]) => v !== null && v < 0.01);
  return `lack of fit (${p.map(([k, v]) => `${k} p = ${v.toExponential(1)}`).join(', ')})`;
};

/** The comparison table's rows of a fitted-model file's fits (the browser test forms the CLI's the same way). */
export const rankingRows = (fits) => fits.map((e) => [
  e.model, e.rank ? String(e.rank.rank) : '–', fmt(e.rank?.delta), fmt(e.rank?.weight),
  fmt(e.cross_validation?.rms), fmt(e.cross_validation?.in_sample), fmt(e.rms), adequacyText(e.adequacy),
]);

function showFit(json) {
  const fits = JSON.parse(json).fits;
  const compared = fits.length > 1;
  $('comparison').hidden = !compared;
  if (compared) $('ranking').tBodies[0].replaceChildren(...tableRows(rankingRows(fits)));
  // The fit shown in detail: the best ranked of a comparison.
  const entry = compared ? fits.find((e) => e.rank?.rank === 1) ?? fits[0] : fits[0];
  const rows = parameterOrder(entry).map(([name, p]) => [
    name, fmt(p.grid), fmt(p.refined), `[${fmt(p.lo68)}, ${fmt(p.hi68)}]`, `[${fmt(p.lo95)}, ${fmt(p.hi95)}]`, fmt(p.interval), p.box ? `[${fmt(p.box[0])}, ${fmt(p.box[1])}]` : '–', p.flags.join(', '),
  ]);
  $('params').tBodies[0].replaceChildren(...tableRows(rows));
  const free = entry.objective === 'free';
  const refined = entry.rms_refined === null ? '' : `, refined ${fmt(entry.rms_refined)}`;
  const beta = free
    ? `β is eq. 8's; amplitude ${fmt(entry.amplitude)}, weighted χ²/ν ${fmt(entry.chi2_weighted)}. Everything stays in the box searched.`
    : `β is the paper normalisation's balance; eq. 8's is ${fmt(entry.fitted.beta_eq8)}.`;
  $('measures').textContent = `${entry.sample}/${entry.channel}/${entry.model} (${free ? 'free amplitude' : 'paper'} objective): `
    + `Δ_RMS (eq. 15) ${fmt(entry.rms)} (grid ${fmt(entry.rms_grid)}${refined}); `
    + `χ²/ν (eq. 16) ${fmt(entry.chi2_dof)}; ${entry.measurements} measurements. ${beta}`;
  const g = entry.graphics;
  $('adequacy').textContent = `Adequacy: ${adequacyText(entry.adequacy)}.`
    + (g ? ` Graphics measures: cos θi-weighted RMS ${fmt(g.cosine_rms)} (Ngan et al.), cube-root distance ${fmt(g.cube_root)} (Forés et al.).` : '');
  $('fit-json').textContent = json;
  $('download').href = URL.createObjectURL(new Blob([json], { type: 'application/json' }));
  const m = measurementsFrom(L, fitting.source);
  try {
    const scene = m.scene(fitting.channel);
    const select = compared ? `${entry.sample}/${entry.channel}/${entry.model}` : undefined;
    scatter($('scatter'), [{ name: entry.channel, measured: scene.data, model: L.predict(json, select, scene.angles) }]);
  } finally {
    m.free();
  }
  // The lobe viewer draws the tied layered models (an untied fit's σ′/T′
  // has no slider).
  const tied = entry.fitted.beta_eq8 !== null && !('sub_slope' in entry.fitted.params);
  if (tied) {
    const p = entry.fitted.params;
    const correlation = MODELS.find((m) => m.name === entry.model)?.correlation;
    setSliders({ model: correlation, slope: p.slope, beta: entry.fitted.beta_eq8, n: p.n, a: p.a ?? 0 });
  }
}

/** `[lo, hi]` of a jointly fitted value's interval at `level` (68 or 95), as the page shows it. */
const interval = (v, level) => (v?.intervals ? `[${fmt(v.intervals[`lo${level}`])}, ${fmt(v.intervals[`hi${level}`])}]` : '–');

/** A p-value as the page shows it: 'not tested' when there is none. */
const pValue = (p) => (p === null || p === undefined ? 'not tested' : `p = ${Number(p).toPrecision(2)}`);

/** The joint fit's tables of a fitted-model file's material (the browser test forms the CLI's the same way). */
export const jointRows = (material) => ({
  shared: Object.entries(material.shared).map(([name, v]) => [name, fmt(v.value), interval(v, 68), interval(v, 95)]),
  channels: material.channels.map((c) => [
    c.channel, fmt(c.a?.value), interval(c.a, 68), interval(c.a, 95), fmt(c.beta), fmt(c.amplitude), c.lack_of_fit ? 'lack of fit' : 'ok',
  ]),
  variants: Object.entries(material.variants).sort((x, y) => x[1] - y[1]).map(([name, d]) => [name.replace(/_/g, ' '), fmt(d)]),
});

function showJoint(json) {
  const material = JSON.parse(json).materials[0];
  const rows = jointRows(material);
  $('shared').tBodies[0].replaceChildren(...tableRows(rows.shared));
  $('joint-channels').tBodies[0].replaceChildren(...tableRows(rows.channels));
  $('variants').tBodies[0].replaceChildren(...tableRows(rows.variants));
  const intervals = material.resamples > 0 ? `${material.resamples} bootstrap resamples of the geometries` : 'no resamples, no intervals';
  $('joint-summary').textContent = `${material.sample}/${material.model}, one fit across ${material.channels.length} channels `
    + `(${material.measurements} measurements each, ${material.parameters} parameters; ${intervals}).`;
  $('joint-tests').textContent = `One a for every channel (is the absorption chromatic?): ${pValue(material.chromatic_p)}. `
    + `One σ/T for every channel (is the roughness shared?): ${pValue(material.roughness_p)}. `
    + 'The variants below are ranked by AICc: the joint fit, σ/T per channel, and each channel fitted alone.';
  $('joint-json').textContent = json;
  $('download-joint').href = URL.createObjectURL(new Blob([json], { type: 'application/json' }));
  spectrum($('spectrum'), material.channels);
  const m = measurementsFrom(L, fitting.source);
  try {
    scatter($('scatter'), material.channels.map((c) => {
      const scene = m.scene(c.channel);
      return { name: c.channel, measured: scene.data, model: L.predict(json, `${material.sample}/${c.channel}/${material.model}`, scene.angles) };
    }), { log: true });
  } finally {
    m.free();
  }
  // The lobe viewer draws the tied models (one σ/T): an untied fit's
  // σ′/T′ has no slider, so only a tied material sets them.
  const first = material.channels[0];
  const p = first.fitted.params;
  const correlation = MODELS.find((x) => x.name === material.model)?.correlation;
  if (!('sub_slope' in p)) setSliders({ model: correlation, slope: p.slope, beta: first.fitted.beta_eq8, n: p.n, a: p.a ?? 0 });
}

// The lobe and its sliders.
const SLIDERS = [
  ['theta_i', 'θi (degrees)', 0, 85, 1, 30],
  ['slope', 'σ/T', 0.05, 6, 0.01, 1.2],
  ['beta', 'β (eq. 8)', 0, 1, 0.01, 0.4],
  ['n', 'n', 1, 3, 0.01, 1.5],
  ['a', 'a', 0, 1, 0.01, 0.3],
];
const sliders = $('sliders');
const modelSelect = Object.assign(document.createElement('select'), { id: 'lobe-model' });
// One lobe per correlation function, named as its absorptive model.
modelSelect.append(...E.correlations().map((c) => new Option(c, c)));
const modelLabel = document.createElement('label');
modelLabel.append('surface correlation', modelSelect, document.createElement('span'));
sliders.appendChild(modelLabel);
for (const [id, label, min, max, step, value] of SLIDERS) {
  const row = document.createElement('label');
  const input = Object.assign(document.createElement('input'), { type: 'range', id: `slider-${id}`, min, max, step, value });
  const out = Object.assign(document.createElement('output'), { id: `value-${id}`, textContent: value });
  row.append(label, input, out);
  sliders.appendChild(row);
  input.addEventListener('input', drawLobe);
}
modelSelect.addEventListener('change', drawLobe);

function setSliders(values) {
  modelSelect.value = values.model;
  for (const k of ['slope', 'beta', 'n', 'a']) $(`slider-${k}`).value = values[k];
  drawLobe();
}

const THETAS = Array.from({ length: 91 }, (_, k) => k * DEG);
function drawLobe() {
  const v = Object.fromEntries(SLIDERS.map(([id]) => [id, Number($(`slider-${id}`).value)]));
  for (const [id] of SLIDERS) $(`value-${id}`).textContent = v[id];
  const ti = Math.min(v.theta_i * DEG, Math.PI / 2);
  const at = (phi) => new Float64Array(THETAS.flatMap((t) => [ti, Math.min(t, Math.PI / 2), phi]));
  const eval8 = (phi) => E.totalRadiance(modelSelect.value, at(phi), v.slope, v.beta, v.n, v.a);
  lobe($('lobe'), ti, THETAS, eval8(0), eval8(Math.PI));
  drawSphere(v);
}

// The sphere preview: `laminar render`'s scene (docs/conventions.md §12)
// without its environment term, which needs the albedo (not in the
// evaluation-only package). An orthographic view along +z, the light 60°
// off the axis from the upper left; each pixel shows eq. 8's radiance
// f · cos θi at its normal, exposed so that its 99.5th percentile is 0.95,
// sRGB-encoded.
const SPHERE_LIGHT = [60 * DEG, 135 * DEG];
function drawSphere(v) {
  const canvas = $('sphere');
  const size = canvas.width;
  const [polar, azimuth] = SPHERE_LIGHT;
  const l = [Math.sin(polar) * Math.cos(azimuth), Math.sin(polar) * Math.sin(azimuth), Math.cos(polar)];
  const lit = []; // pixel index of each lit point
  const angles = [];
  for (let row = 0; row < size; row++) {
    for (let col = 0; col < size; col++) {
      const x = (2 * (col + 0.5)) / size - 1;
      const y = 1 - (2 * (row + 0.5)) / size;
      const r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const n = [x, y, Math.sqrt(1 - r2)];
      const cosI = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
      if (cosI <= 0) continue;
      // Light and view projected on the tangent plane: their azimuth.
      const lt = l.map((c, k) => c - cosI * n[k]);
      const vt = [0, 0, 1].map((c, k) => c - n[2] * n[k]);
      const norms = Math.hypot(...lt) * Math.hypot(...vt);
      const delta = norms > 1e-300 ? Math.acos(Math.max(-1, Math.min(1, (lt[0] * vt[0] + lt[1] * vt[1] + lt[2] * vt[2]) / norms))) : 0;
      // Lab to paper frame (conventions §1): φs = φv − φi − π, wrapped.
      let phi = delta - Math.PI;
      if (phi <= -Math.PI) phi += 2 * Math.PI;
      angles.push(Math.acos(Math.min(1, cosI)), Math.acos(Math.min(1, n[2])), phi);
      lit.push(row * size + col);
    }
  }
  const radiance = lit.length ? E.totalRadiance(modelSelect.value, new Float64Array(angles), v.slope, v.beta, v.n, v.a) : [];
  const sorted = Float64Array.from(radiance).sort();
  const top = sorted[Math.floor(sorted.length * 0.995)] ?? sorted[sorted.length - 1] ?? 1;
  const exposure = top > 0 ? 0.95 / top : 1;
  const srgb = (x) => {
    const c = Math.min(1, Math.max(0, x * exposure));
    return Math.round(255 * (c <= 0.0031308 ? 12.92 * c : 1.055 * c ** (1 / 2.4) - 0.055));
  };
  const image = canvas.getContext('2d').createImageData(size, size);
  for (let p = 0; p < size * size; p++) {
    image.data.set([24, 24, 24, 255], 4 * p);
    const x = (2 * ((p % size) + 0.5)) / size - 1;
    const y = 1 - (2 * (Math.floor(p / size) + 0.5)) / size;
    if (x * x + y * y < 1) image.data.set([0, 0, 0, 255], 4 * p); // the unlit side
  }
  lit.forEach((p, k) => {
    const g = srgb(radiance[k]);
    image.data.set([g, g, g, 255], 4 * p);
  });
  canvas.getContext('2d').putImageData(image, 0, 0);
  canvas.dataset.drawn = String(Number(canvas.dataset.drawn ?? 0) + 1);
}
drawLobe();
document.body.dataset.lobe = 'true';
L = await load();
// The models to fit, from the library's model descriptor.
const MODELS = L.models();
$('model').append(...MODELS.map((m) => new Option(`${m.name} (${m.description})`, m.name)));
for (const id of NEEDS_WHOLE) $(id).disabled = false;
document.body.dataset.ready = 'true';
