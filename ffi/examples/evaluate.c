/* A C program on the laminar C ABI: the absorptive exponential model at a
 * few geometries in f32, printed as bit patterns (so that a test can
 * compare them with the Rust core's, bit for bit), and what bad input
 * returns. Build: cc -I ffi/include ffi/examples/evaluate.c
 * target/release/liblaminar_ffi.a -lm -lpthread -ldl */

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
  return 0;
}
