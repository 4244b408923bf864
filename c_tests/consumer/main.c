/* A minimal program against an installed dcol: two spheres, alpha* = |r2 - r1| / (R1 + R2). */
#include <dcol.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

int main(void) {
  dcol_shape *a = NULL, *b = NULL;
  dcol_pose p1 = {{0, 0, 0}, {1, 0, 0, 0}};
  dcol_pose p2 = {{3, 0, 0}, {1, 0, 0, 0}};
  dcol_proximity_result r;
  dcol_status st;
  int ok;

  if (strcmp(dcol_version(), DCOL_VERSION_STRING) != 0) {
    fprintf(stderr, "header %s, library %s\n", DCOL_VERSION_STRING, dcol_version());
    return 1;
  }
  if (dcol_shape_new_sphere(1.0, &a) != DCOL_OK || dcol_shape_new_sphere(0.5, &b) != DCOL_OK) {
    fprintf(stderr, "%s\n", dcol_last_error_message());
    return 1;
  }
  st = dcol_proximity(a, &p1, b, &p2, NULL, &r);
  ok = st == DCOL_OK && fabs(r.alpha - 2.0) < 1e-9;
  printf("consumer (dcol %s): %s, alpha = %.12f\n", dcol_version(), dcol_status_string(st),
         r.alpha);
  dcol_shape_free(a);
  dcol_shape_free(b);
  return ok ? 0 : 1;
}
