// Where a measurement set comes from, as a plain object the page keeps and
// sends to its worker: { kind: 'file', name, bytes, angles, quantity } (a
// long CSV, an ASTM E1392 .astm, NIST's BRDF CSV or RGL's .bsdf) or
// { kind: 'curet', table, brdfName, brdf, sample }.

/** The laminar `Measurements` of a source (the caller frees it). */
export function measurementsFrom(L, s) {
  return s.kind === 'file'
    ? L.Measurements.fromFile(s.name, s.bytes, s.angles, s.quantity)
    : L.Measurements.fromCuret(s.table, s.brdfName, s.brdf, s.sample);
}
