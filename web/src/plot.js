// The page's two figures, drawn as SVG (no plotting library: two small
// figures, and the page must work offline from plain files).

const NS = 'http://www.w3.org/2000/svg';

function el(parent, name, attrs, text) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  parent.appendChild(e);
  return e;
}

/** Measured against model, both normalised, with the 1:1 line. */
export function scatter(svg, measured, model) {
  svg.replaceChildren();
  const [x0, y0, size] = [60, 370, 330];
  const top = Math.max(1, ...model, ...measured);
  const sx = (v) => x0 + (v / top) * size;
  const sy = (v) => y0 - (v / top) * size;
  for (let t = 0; t <= top + 1e-9; t += top > 1.5 ? 0.5 : 0.2) {
    el(svg, 'line', { x1: sx(t), y1: y0, x2: sx(t), y2: y0 + 5, stroke: '#333' });
    el(svg, 'text', { x: sx(t), y: y0 + 18, 'text-anchor': 'middle' }, t.toFixed(1));
    el(svg, 'line', { x1: x0 - 5, y1: sy(t), x2: x0, y2: sy(t), stroke: '#333' });
    el(svg, 'text', { x: x0 - 8, y: sy(t) + 4, 'text-anchor': 'end' }, t.toFixed(1));
  }
  el(svg, 'rect', { x: x0, y: y0 - size, width: size, height: size, fill: 'none', stroke: '#333' });
  el(svg, 'line', { x1: sx(0), y1: sy(0), x2: sx(top), y2: sy(top), stroke: '#888', 'stroke-dasharray': '6 4' });
  el(svg, 'text', { x: sx(0.9 * top) + 10, y: sy(0.9 * top) + 24, fill: '#666' }, '1:1');
  const dots = el(svg, 'g', { id: 'points', fill: '#1f5fbf', 'fill-opacity': 0.6 });
  measured.forEach((d, k) => el(dots, 'circle', { cx: sx(d), cy: sy(model[k]), r: 2.5 }));
  el(svg, 'text', { x: x0 + size / 2, y: 408, 'text-anchor': 'middle' }, 'measured radiance / its max (dimensionless)');
  el(svg, 'text', { x: 16, y: y0 - size / 2, 'text-anchor': 'middle', transform: `rotate(-90 16 ${y0 - size / 2})` },
    'fitted model, normalised (dimensionless)');
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
