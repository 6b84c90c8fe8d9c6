// The page's figures, drawn as SVG (no plotting library: three small
// figures, and the page must work offline from plain files).

const NS = 'http://www.w3.org/2000/svg';

function el(parent, name, attrs, text) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  parent.appendChild(e);
  return e;
}

/** A channel's colour: red, green and blue for channels named so, a
 * wavelength's hue for one named by it, else a colour of a cycle. */
export function channelColour(name, k) {
  const named = { r: '#c0392b', red: '#c0392b', g: '#2e8b3e', green: '#2e8b3e', b: '#1f5fbf', blue: '#1f5fbf' };
  if (named[name.toLowerCase()]) return named[name.toLowerCase()];
  const nm = wavelength(name);
  if (nm !== null) {
    // 380 nm violet (hue 270) to 700 nm red (hue 0).
    const hue = Math.max(0, Math.min(270, (270 * (700 - nm)) / 320));
    return `hsl(${hue.toFixed(0)} 75% 42%)`;
  }
  return ['#1f5fbf', '#c0392b', '#2e8b3e', '#8e44ad', '#d08000', '#16a085'][k % 6];
}

/** The wavelength (nm) a channel is named by, its leading number (`450nm`,
 * `532`), as `laminar fit-joint --plot` reads it; else null. */
export function wavelength(name) {
  const m = /^(\d+(?:\.\d+)?)/.exec(name);
  const v = m ? Number(m[1]) : NaN;
  return v > 0 ? v : null;
}

/** Measured against model, both normalised, with the 1:1 line: one series
 * ({ name, measured, model }) per channel, each in its colour. `log`: both
 * axes logarithmic over the decades the values span (at most five below
 * the top; smaller values, and zeros, are drawn at the axes' floor), for
 * data whose near-mirror peak dwarfs the rest. */
export function scatter(svg, series, { log = false } = {}) {
  svg.replaceChildren();
  const [x0, y0, size] = [60, 370, 330];
  const values = series.flatMap((s) => [...s.model, ...s.measured]);
  const top = Math.max(1, ...values);
  let sx;
  let sy;
  let ticks;
  if (log) {
    const hi = Math.ceil(Math.log10(top));
    const smallest = Math.min(...values.filter((v) => v > 0));
    const lo = Math.max(hi - 5, Math.floor(Math.log10(Number.isFinite(smallest) ? smallest : 1e-5)));
    const at = (v) => (Math.max(Math.log10(Math.max(v, 10 ** lo)), lo) - lo) / (hi - lo);
    sx = (v) => x0 + at(v) * size;
    sy = (v) => y0 - at(v) * size;
    const sup = (k) => String(k).replace(/-/g, '⁻').replace(/\d/g, (d) => '⁰¹²³⁴⁵⁶⁷⁸⁹'[d]);
    ticks = Array.from({ length: hi - lo + 1 }, (_, k) => [10 ** (lo + k), `10${sup(lo + k)}`]);
  } else {
    sx = (v) => x0 + (v / top) * size;
    sy = (v) => y0 - (v / top) * size;
    ticks = [];
    for (let t = 0; t <= top + 1e-9; t += top > 1.5 ? 0.5 : 0.2) ticks.push([t, t.toFixed(1)]);
  }
  for (const [t, label] of ticks) {
    el(svg, 'line', { x1: sx(t), y1: y0, x2: sx(t), y2: y0 + 5, stroke: '#333' });
    el(svg, 'text', { x: sx(t), y: y0 + 18, 'text-anchor': 'middle' }, label);
    el(svg, 'line', { x1: x0 - 5, y1: sy(t), x2: x0, y2: sy(t), stroke: '#333' });
    el(svg, 'text', { x: x0 - 8, y: sy(t) + 4, 'text-anchor': 'end' }, label);
  }
  el(svg, 'rect', { x: x0, y: y0 - size, width: size, height: size, fill: 'none', stroke: '#333' });
  const [first, last] = [ticks[0][0], top];
  el(svg, 'line', { x1: sx(first), y1: sy(first), x2: sx(last), y2: sy(last), stroke: '#888', 'stroke-dasharray': '6 4' });
  el(svg, 'text', { x: sx(0.9 * top) + 10, y: sy(0.9 * top) + 24, style: 'fill: #666' }, '1:1');
  series.forEach((s, c) => {
    const colour = series.length > 1 ? channelColour(s.name, c) : '#1f5fbf';
    const dots = el(svg, 'g', { class: 'points', 'data-channel': s.name, fill: colour, 'fill-opacity': 0.6 });
    s.measured.forEach((d, k) => el(dots, 'circle', { cx: sx(d), cy: sy(s.model[k]), r: series.length > 1 ? 1.8 : 2.5 }));
    if (series.length > 1 && series.length <= 8) {
      el(svg, 'text', { x: x0 + 10, y: y0 - size + 18 + 15 * c, style: `fill: ${colour}` }, `● ${s.name}`);
    }
  });
  const scale = log ? ', log scale' : '';
  el(svg, 'text', { x: x0 + size / 2, y: 408, 'text-anchor': 'middle' }, `measured radiance / its max (dimensionless${scale})`);
  el(svg, 'text', { x: 16, y: y0 - size / 2, 'text-anchor': 'middle', transform: `rotate(-90 16 ${y0 - size / 2})` },
    `fitted model, normalised (dimensionless${scale})`);
}

/**
 * Radiance over the plane of incidence: forward half (φs = 0, the side of
 * the specular direction) on the right, backward half (φs = π) on the left;
 * radius = radiance / its max over the plane. `thetas` in radians.
 */
export function lobe(svg, thetaI, thetas, forward, backward) {
  svg.replaceChildren();
  const [cx, cy, R] = [260, 290, 232];
  const max = Math.max(...forward, ...backward) || 1;
  for (const f of [0.25, 0.5, 0.75, 1]) {
    el(svg, 'path', { d: `M ${cx - R * f} ${cy} A ${R * f} ${R * f} 0 0 1 ${cx + R * f} ${cy}`, fill: 'none', stroke: '#dde' });
    el(svg, 'text', { x: cx + R * f, y: cy + 14, 'text-anchor': 'middle', fill: '#888' }, f.toFixed(2));
  }
  for (const deg of [-60, -30, 0, 30, 60]) {
    const t = (deg * Math.PI) / 180;
    el(svg, 'line', { x1: cx, y1: cy, x2: cx + R * Math.sin(t), y2: cy - R * Math.cos(t), stroke: '#eef' });
    el(svg, 'text', { x: cx + (R + 12) * Math.sin(t), y: cy - (R + 12) * Math.cos(t) + 4, 'text-anchor': 'middle', fill: '#888' },
      `${Math.abs(deg)}°`);
  }
  el(svg, 'line', { x1: cx - R - 5, y1: cy, x2: cx + R + 5, y2: cy, stroke: '#333' });
  const point = (t, v, side) => [cx + side * R * (v / max) * Math.sin(t), cy - R * (v / max) * Math.cos(t)];
  const pts = [
    ...thetas.map((t, k) => point(t, backward[k], -1)).reverse(),
    ...thetas.map((t, k) => point(t, forward[k], 1)),
  ];
  el(svg, 'path', {
    id: 'lobe-path',
    d: 'M ' + pts.map(([x, y]) => `${x.toFixed(2)} ${y.toFixed(2)}`).join(' L '),
    fill: '#1f5fbf22', stroke: '#1f5fbf', 'stroke-width': 2,
  });
  // The light's direction (backward side) and the mirror direction.
  const [lx, ly] = [cx - R * Math.sin(thetaI), cy - R * Math.cos(thetaI)];
  el(svg, 'line', { x1: lx, y1: ly, x2: cx, y2: cy, stroke: '#d08000', 'stroke-width': 2 });
  const [tx, ty] = [cx - 0.55 * R * Math.sin(thetaI), cy - 0.55 * R * Math.cos(thetaI)];
  el(svg, 'text', { x: tx - 8, y: ty, 'text-anchor': 'end', fill: '#d08000' }, `light, θi = ${((thetaI * 180) / Math.PI).toFixed(0)}°`);
  el(svg, 'line', { x1: cx, y1: cy, x2: cx + R * Math.sin(thetaI), y2: cy - R * Math.cos(thetaI), stroke: '#d08000', 'stroke-dasharray': '4 4' });
  el(svg, 'text', { x: 8, y: 18 }, '← backward (φs = π)');
  el(svg, 'text', { x: 512, y: 18, 'text-anchor': 'end' }, 'forward (φs = 0) →');
  el(svg, 'text', { x: cx, y: cy + 32, 'text-anchor': 'middle' }, 'θs from the normal; radius: radiance / its max in this plane');
}

/**
 * The absorption spectrum of a joint fit: each channel's a (points and a
 * line) with its 68% and 95% bootstrap bands (shaded), and β (dashed), over
 * the wavelength when every channel is named by one, else the channel's
 * place. `channels`: the `channels` of a fitted-model file's material.
 */
export function spectrum(svg, channels) {
  svg.replaceChildren();
  const [x0, y0, w, h] = [60, 280, 430, 250];
  const nm = channels.map((c) => wavelength(c.channel));
  const byWavelength = nm.every((v) => v !== null) && new Set(nm).size === nm.length;
  const xs = byWavelength ? nm : channels.map((_, k) => k);
  const [lo, hi] = [Math.min(...xs), Math.max(...xs)];
  const span = hi > lo ? hi - lo : 1;
  const sx = (x) => x0 + 20 + ((x - lo) / span) * (w - 40);
  const sy = (v) => y0 - v * h;
  el(svg, 'rect', { x: x0, y: y0 - h, width: w, height: h, fill: 'none', stroke: '#333' });
  for (const t of [0, 0.25, 0.5, 0.75, 1]) {
    el(svg, 'line', { x1: x0 - 5, y1: sy(t), x2: x0, y2: sy(t), stroke: '#333' });
    el(svg, 'text', { x: x0 - 8, y: sy(t) + 4, 'text-anchor': 'end' }, t.toFixed(2));
  }
  // Ticks: each channel when there are few, else every 50 nm.
  const ticks = byWavelength && xs.length > 8
    ? Array.from({ length: Math.floor(hi / 50) - Math.ceil(lo / 50) + 1 }, (_, k) => 50 * (Math.ceil(lo / 50) + k))
    : xs;
  for (const x of ticks) {
    el(svg, 'line', { x1: sx(x), y1: y0, x2: sx(x), y2: y0 + 5, stroke: '#333' });
    const label = byWavelength ? String(x) : channels[x].channel;
    el(svg, 'text', { x: sx(x), y: y0 + 18, 'text-anchor': 'middle' }, label);
  }
  el(svg, 'text', { x: x0 + w / 2, y: y0 + 38, 'text-anchor': 'middle' }, byWavelength ? 'wavelength (nm)' : 'channel');
  const withA = channels.map((c, k) => [c, xs[k]]).filter(([c]) => c.a);
  const band = (level, fill) => {
    const pts = withA.filter(([c]) => c.a.intervals);
    if (pts.length === 0) return;
    const upper = pts.map(([c, x]) => `${sx(x).toFixed(2)} ${sy(c.a.intervals[`hi${level}`]).toFixed(2)}`);
    const lower = pts.map(([c, x]) => `${sx(x).toFixed(2)} ${sy(c.a.intervals[`lo${level}`]).toFixed(2)}`).reverse();
    if (pts.length === 1) {
      const [c, x] = pts[0];
      el(svg, 'rect', { class: `band${level}`, x: sx(x) - 6, y: sy(c.a.intervals[`hi${level}`]), width: 12, height: Math.max(1, sy(c.a.intervals[`lo${level}`]) - sy(c.a.intervals[`hi${level}`])), fill });
      return;
    }
    el(svg, 'path', { class: `band${level}`, d: `M ${[...upper, ...lower].join(' L ')} Z`, fill });
  };
  band(95, '#1f5fbf22');
  band(68, '#1f5fbf44');
  const line = (values, attrs) => el(svg, 'path', { d: 'M ' + values.map(([x, v]) => `${sx(x).toFixed(2)} ${sy(v).toFixed(2)}`).join(' L '), fill: 'none', ...attrs });
  line(channels.map((c, k) => [xs[k], c.beta]), { id: 'spectrum-beta', stroke: '#888', 'stroke-dasharray': '5 4' });
  if (withA.length) line(withA.map(([c, x]) => [x, c.a.value]), { id: 'spectrum-a', stroke: '#1f5fbf', 'stroke-width': 2 });
  const dots = el(svg, 'g', { id: 'spectrum-points', fill: '#1f5fbf' });
  withA.forEach(([c, x]) => el(dots, 'circle', { cx: sx(x), cy: sy(c.a.value), r: 3 }));
  el(svg, 'text', { x: x0 + 10, y: y0 - h + 18, style: 'fill: #1f5fbf' }, 'a (eqs. 10–13), 68% and 95% bands');
  el(svg, 'text', { x: x0 + 10, y: y0 - h + 34, style: 'fill: #888' }, 'β (eq. 8), dashed');
}
