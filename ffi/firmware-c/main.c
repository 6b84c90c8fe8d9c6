/* A C firmware on the laminar C ABI. The same source is built twice:
 * by Debian's arm-none-eabi-gcc for the Cortex-M4F (QEMU mps2-an386,
 * output over semihosting; startup.c and link.ld), and by the host's cc.
 * ffi/tests/firmware_c.rs runs both and requires the same lines, bit for
 * bit: geometries built once from f32 angles, the f32 fast path at them,
 * the statuses of bad input (outputs untouched), and an on-device fit. */

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "laminar.h"

#define COUNT 16

static unsigned long bits32(float v) {
  uint32_t b;
  memcpy(&b, &v, sizeof b);
  return (unsigned long)b;
}

static void print_bits64(const char *name, double v) {
  uint64_t b;
  memcpy(&b, &v, sizeof b);
  printf("%s %08lx%08lx\n", name, (unsigned long)(b >> 32), (unsigned long)(b & 0xffffffffu));
}

int main(void) {
  /* Geometries built once, at start-up, from f32 angles. */
  LaminarAnglesF32 angles[COUNT];
  for (int k = 0; k < COUNT; k++) {
    angles[k].theta_i = 0.09f * (float)k;
    angles[k].theta_s = 0.05f + 0.09f * (float)k;
    angles[k].phi_s = -3.0f + 0.4f * (float)k;
  }
  static LaminarGeometry geometry[COUNT];
  int s = (int)laminar_geometry_from_angles_f32(angles, COUNT, geometry);
  printf("geometry: %d\n", s);

  /* The fast path: f32 parameters at the prebuilt geometries. */
  const LaminarParamsF32 params[3] = {
      {.slope = 1.48f, .beta = 0.39f, .n = 1.44f, .a = 0.17f},
      {.slope = 0.3f, .beta = 0.9f, .n = 1.05f, .a = 0.0f},
      {.slope = 3.9f, .beta = 0.01f, .n = 2.4f, .a = 1.0f},
  };
  float out[COUNT];
  for (int j = 0; j < 3; j++) {
    for (uint32_t corr = 0; corr < 2; corr++) {
      s = (int)laminar_evaluate_f32(corr, params[j], geometry, COUNT, out);
      printf("eval %d %lu: %d", j, (unsigned long)corr, s);
      for (int k = 0; k < COUNT; k++) printf(" %08lx", bits32(out[k]));
      printf("\n");
    }
  }

  /* Bad input: a status naming it, the output untouched. */
  LaminarParamsF32 bad = params[0];
  bad.n = 0.5f;
  out[0] = -1.0f;
  printf("bad n: %d, out[0] %08lx\n", (int)laminar_evaluate_f32(0, bad, geometry, COUNT, out),
         bits32(out[0]));
  printf("bad correlation: %d\n", (int)laminar_evaluate_f32(7, params[0], geometry, COUNT, out));
  printf("null geometries: %d\n", (int)laminar_evaluate_f32(0, params[0], NULL, COUNT, out));
  LaminarAnglesF32 wide = angles[3];
  wide.phi_s = 4.0f;
  printf("bad phi_s: %d\n", (int)laminar_geometry_from_angles_f32(&wide, 1, geometry));
  printf("huge count: %d\n", (int)laminar_evaluate_f32(0, params[0], geometry, SIZE_MAX / 2, out));

  /* An on-device fit of data the model made at a grid point, on a small
   * grid. The fit's model is the paper's (docs/conventions.md §4): the
   * surface and subsurface terms each divided by their max, mixed with β. */
  static double slope[12], n[3], a[3], beta[20], data[COUNT];
  for (int i = 0; i < 12; i++) slope[i] = 0.2 + 0.2 * i;
  for (int i = 0; i < 20; i++) beta[i] = 0.05 + 0.05 * i;
  for (int i = 0; i < 3; i++) {
    n[i] = 1.3 + 0.1 * i;
    a[i] = 0.25 * i;
  }
  LaminarParamsF32 truth = {.slope = (float)slope[5], .beta = (float)beta[11], .n = (float)n[2], .a = (float)a[1]};
  static float parts[COUNT * LAMINAR_COMPONENTS];
  laminar_components_f32(1, truth, geometry, COUNT, parts);
  double max_surface = 0.0, max_subsurface = 0.0;
  for (int k = 0; k < COUNT; k++) {
    double surface = parts[k * LAMINAR_COMPONENTS + 4], subsurface = parts[k * LAMINAR_COMPONENTS + 5];
    max_surface = surface > max_surface ? surface : max_surface;
    max_subsurface = subsurface > max_subsurface ? subsurface : max_subsurface;
  }
  for (int k = 0; k < COUNT; k++) {
    data[k] = beta[11] * parts[k * LAMINAR_COMPONENTS + 5] / max_subsurface +
              (1.0 - beta[11]) * parts[k * LAMINAR_COMPONENTS + 4] / max_surface;
  }
  LaminarGrid grid = {slope, 12, n, 3, a, 3, beta, 20};
  static LaminarFitScratch scratch;
  LaminarFitResult fit;
  memset(&fit, 0, sizeof fit);
  s = (int)laminar_fit(1, geometry, data, COUNT, grid, &scratch, &fit);
  printf("fit: %d index %lu rh %d %lu\n", s, (unsigned long)fit.index, (int)fit.rh_found,
         (unsigned long)fit.rh_index);
  print_bits64("fit slope", fit.slope);
  print_bits64("fit beta", fit.beta);
  print_bits64("fit n", fit.n);
  print_bits64("fit a", fit.a);
  print_bits64("fit rms", fit.rms);
  print_bits64("fit rh_rms", fit.rh_rms);
  /* The free-amplitude fit (the fitting library's default objective): the
   * raw mix of eq. 8 times an amplitude 3.7, on the same σ/T, n and a
   * axes, β and the amplitude in closed form; then a zero uncertainty and
   * an empty β box. */
  static double raw[COUNT], sigma[COUNT];
  for (int k = 0; k < COUNT; k++) {
    raw[k] = 3.7 * (beta[11] * parts[k * LAMINAR_COMPONENTS + 5] +
                    (1.0 - beta[11]) * parts[k * LAMINAR_COMPONENTS + 4]);
    sigma[k] = 0.01 * raw[k] + 1e-3;
  }
  LaminarFreeGrid free_grid = {slope, 12, n, 3, a, 3, 0.0, 1.0};
  LaminarFreeFitResult free_fit;
  memset(&free_fit, 0, sizeof free_fit);
  s = (int)laminar_fit_free(1, geometry, raw, NULL, COUNT, free_grid, &scratch, &free_fit);
  printf("free fit: %d index %lu rh %d %lu\n", s, (unsigned long)free_fit.index,
         (int)free_fit.rh_found, (unsigned long)free_fit.rh_index);
  print_bits64("free fit slope", free_fit.slope);
  print_bits64("free fit beta", free_fit.beta);
  print_bits64("free fit n", free_fit.n);
  print_bits64("free fit a", free_fit.a);
  print_bits64("free fit amplitude", free_fit.amplitude);
  print_bits64("free fit objective", free_fit.objective);
  print_bits64("free fit rms", free_fit.rms);
  s = (int)laminar_fit_free(1, geometry, raw, sigma, COUNT, free_grid, &scratch, &free_fit);
  printf("free fit weighted: %d index %lu\n", s, (unsigned long)free_fit.index);
  sigma[3] = 0.0;
  printf("free fit bad sigma: %d\n",
         (int)laminar_fit_free(1, geometry, raw, sigma, COUNT, free_grid, &scratch, &free_fit));
  LaminarFreeGrid empty_box = {slope, 12, n, 3, a, 3, 0.7, 0.3};
  printf("free fit empty beta box: %d\n",
         (int)laminar_fit_free(1, geometry, raw, NULL, COUNT, empty_box, &scratch, &free_fit));
  data[4] = -2.0;
  printf("fit bad data: %d\n", (int)laminar_fit(1, geometry, data, COUNT, grid, &scratch, &fit));
  printf("fit too many: %d (at most %d)\n",
         (int)laminar_fit(1, geometry, data, LAMINAR_FIT_MAX_MEASUREMENTS + 1, grid, &scratch, &fit),
         LAMINAR_FIT_MAX_MEASUREMENTS);
  printf("done\n");
  return 0;
}
