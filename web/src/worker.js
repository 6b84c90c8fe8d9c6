// Fits off the page's thread, posting the fit's progress.
import { load } from './laminar-brdf/index.js';
import { measurementsFrom } from './source.js';

const ready = load();

self.onmessage = async ({ data }) => {
  const L = await ready;
  let m;
  try {
    m = measurementsFrom(L, data.source);
    const start = performance.now();
    const options = { noise: data.noise, onProgress: (done, total) => self.postMessage({ progress: [done, total] }) };
    let json;
    if (data.joint) json = L.fitJoint(m, data.model, options);
    else if (data.models) json = L.compare(m, data.channel, data.models, options);
    else json = L.fit(m, data.channel, data.model, options);
    self.postMessage({ json, ms: performance.now() - start });
  } catch (e) {
    self.postMessage({ error: String(e?.message ?? e) });
  } finally {
    m?.free();
  }
};
