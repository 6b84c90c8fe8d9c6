/* A C program on the laminar C ABI: the absorptive exponential model at a
 * few geometries in f32, printed as bit patterns (so that a test can
 * compare them with the Rust core's, bit for bit), and what bad input
 * returns; then the firmware path (geometries built once, evaluated with
 * f32 parameters) and a fit on a small grid. Build: cc -I ffi/include ffi/examples/evaluate.c
 * target/release/liblaminar_brdf_ffi.a -lm -lpthread -ldl */

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "laminar.h"

#define COUNT 12

int main(void) {
  LaminarParams params = {.slope = 1.48, .beta = 0.39, .n = 1.44, .a = 0.17};
  LaminarAngles angles[COUNT];
  for (int k = 0; k < COUNT; k++) {
    angles[k].theta_i = 0.1 * k;
    angles[k].theta_s = 0.05 + 0.11 * k;
    angles[k].phi_s = -2.5 + 0.4 * k;
  }
  float out[COUNT];
  LaminarStatus status = laminar_total_radiance_f32(0, params, angles, COUNT, out);
  if (status != LAMINAR_STATUS_OK) {
    fprintf(stderr, "laminar_total_radiance_f32: status %d\n", (int)status);
    return 1;
  }
  for (int k = 0; k < COUNT; k++) {
    unsigned int bits;
    memcpy(&bits, &out[k], sizeof bits);
    printf("%08x %.9g\n", bits, (double)out[k]);
  }
  /* Bad input: a status naming it, and nothing written. */
  LaminarParams bad = params;
  bad.n = 0.5;
  printf("bad n: %d\n", (int)laminar_validate_params(bad));
  angles[3].theta_s = 2.0;
  out[3] = -1.0f;
  printf("bad theta_s: %d, out[3] still %g\n",
         (int)laminar_total_radiance_f32(0, params, angles, COUNT, out), (double)out[3]);
  angles[3].theta_s = 0.38;
  printf("null output: %d\n", (int)laminar_total_radiance_f32(0, params, angles, COUNT, NULL));
  printf("bad correlation: %d\n", (int)laminar_total_radiance_f32(7, params, angles, 0, NULL));

  /* The firmware path: geometries built once, f32 parameters, no f64. */
  LaminarGeometry geometry[COUNT];
  LaminarParamsF32 params32 = {.slope = 1.48f, .beta = 0.39f, .n = 1.44f, .a = 0.17f};
  float fast[COUNT];
  if (laminar_geometry_from_angles(angles, COUNT, geometry) != LAMINAR_STATUS_OK ||
      laminar_evaluate_f32(0, params32, geometry, COUNT, fast) != LAMINAR_STATUS_OK) {
    fprintf(stderr, "firmware path failed\n");
    return 1;
  }
  laminar_total_radiance_f32(0, params, angles, COUNT, out);
  printf("f32 path same bits: %s\n", memcmp(fast, out, sizeof out) == 0 ? "yes" : "no");

  /* A fit on a small grid, of data the model made at one of its points. */
  double slope[20], n[3], a[3], beta[20], data[COUNT];
  for (int i = 0; i < 20; i++) {
    slope[i] = 0.12 + 0.08 * i;
    beta[i] = 0.05 + 0.05 * i;
  }
  for (int i = 0; i < 3; i++) {
    n[i] = 1.30 + 0.1 * i;
    a[i] = 0.25 * i;
  }
  /* The fit's model is the paper's (docs/conventions.md §4): the surface
   * and subsurface terms each divided by their max, then mixed with β. */
  LaminarParams truth = {.slope = slope[7], .beta = beta[11], .n = n[2], .a = a[1]};
  double parts[COUNT * LAMINAR_COMPONENTS], max_surface = 0.0, max_subsurface = 0.0;
  laminar_components_f64(0, truth, angles, COUNT, parts);
  for (int k = 0; k < COUNT; k++) {
    double surface = parts[k * LAMINAR_COMPONENTS + 4], subsurface = parts[k * LAMINAR_COMPONENTS + 5];
    max_surface = surface > max_surface ? surface : max_surface;
    max_subsurface = subsurface > max_subsurface ? subsurface : max_subsurface;
  }
  for (int k = 0; k < COUNT; k++) {
    data[k] = truth.beta * parts[k * LAMINAR_COMPONENTS + 5] / max_subsurface +
              (1.0 - truth.beta) * parts[k * LAMINAR_COMPONENTS + 4] / max_surface;
  }
  LaminarGrid grid = {slope, 20, n, 3, a, 3, beta, 20};
  static LaminarFitScratch scratch;
  LaminarFitResult fit;
  LaminarStatus status_fit = laminar_fit(0, geometry, data, COUNT, grid, &scratch, &fit);
  printf("fit: status %d slope %.2f beta %.2f n %.2f a %.2f rms %.1e\n", (int)status_fit,
         fit.slope, fit.beta, fit.n, fit.a, fit.rms);

  /* The library's data rule: a negative datum beyond the max and a positive
   * one below 1e-100 of it are refused (the fit is left untouched). */
  LaminarFitResult kept = fit;
  double saved = data[5];
  data[5] = -2.0;
  int negative = (int)laminar_fit(0, geometry, data, COUNT, grid, &scratch, &fit);
  data[5] = 1e-101;
  int tiny = (int)laminar_fit(0, geometry, data, COUNT, grid, &scratch, &fit);
  data[5] = saved;
  printf("bad data: %d %d, fit untouched: %s\n", negative, tiny,
         memcmp(&kept, &fit, sizeof fit) == 0 ? "yes" : "no");
  /* The header's limit is a constant C can use. */
  static double most[LAMINAR_FIT_MAX_MEASUREMENTS];
  printf("max measurements: %zu, too many: %d\n", sizeof most / sizeof most[0],
         (int)laminar_fit(0, geometry, data, LAMINAR_FIT_MAX_MEASUREMENTS + 1, grid, &scratch, &fit));
  /* A count no buffer can hold: refused before any pointer is read. */
  printf("huge count: %d\n",
         (int)laminar_total_radiance_f32(0, params, angles, SIZE_MAX / 2, out));
  /* φs in double: any finite value (periodic); in float: [−π, π]. */
  LaminarAngles wide_phi = {.theta_i = 0.1, .theta_s = 0.2, .phi_s = 7.0};
  printf("phi_s 7 (double): %d\n", (int)laminar_validate_angles(wide_phi));
  return 0;
}
