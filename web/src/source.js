// Where a measurement set comes from, as a plain object the page keeps and
// sends to its worker: { kind: 'csv', name, bytes, angles, quantity } or
// { kind: 'curet', table, brdfName, brdf, sample }.

/** The laminar `Measurements` of a source (the caller frees it). */
export function measurementsFrom(L, s) {
  return s.kind === 'csv'
    ? L.Measurements.fromCsv(s.name, s.bytes, s.angles, s.quantity)
    : L.Measurements.fromCuret(s.table, s.brdfName, s.brdf, s.sample);
}
