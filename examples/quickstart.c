/* dcol quickstart: two shapes, their proximity, and its gradient.
 *
 *   ./scripts/demo.sh        (builds, installs into build/install and runs this program)
 *
 * or, against an installed dcol:
 *   cc -std=c99 quickstart.c $(pkg-config --cflags --libs dcol) -o quickstart && ./quickstart
 */
#include <dcol.h>

#include <stdio.h>

static void print3(const char *name, const double v[3]) {
  printf("  %-9s = [% .6f, % .6f, % .6f]\n", name, v[0], v[1], v[2]);
}

int main(void) {
  dcol_shape *box = NULL, *capsule = NULL;
  /* Positions in metres; quaternions [w, x, y, z], world-from-body (need not be unit length). */
  dcol_pose box_pose = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}};
  dcol_pose capsule_pose = {{1.5, 0.4, 0.2}, {0.9239, 0.0, 0.0, 0.3827}}; /* 45 deg about z */
  dcol_proximity_result result;
  double gradient[14];
  dcol_status status;
  int32_t intersecting = 0;
  int i;

  printf("dcol %s\n", dcol_version());

  /* Shapes are built once, validated, and then immutable. */
  status = dcol_shape_new_box(0.5, 0.4, 0.3, &box);
  if (status == DCOL_OK) status = dcol_shape_new_capsule(0.2, 0.8, &capsule);
  if (status != DCOL_OK) {
    fprintf(stderr, "could not build a shape: %s\n", dcol_last_error_message());
    return 1;
  }

  /* Proximity: alpha > 1 separated, alpha < 1 interpenetrating. options == NULL: defaults. */
  status = dcol_proximity(box, &box_pose, capsule, &capsule_pose, NULL, &result);
  printf("dcol_proximity: %s\n", dcol_status_string(status));
  if (status != DCOL_OK) {
    fprintf(stderr, "%s\n", dcol_last_error_message());
    dcol_shape_free(box);
    dcol_shape_free(capsule);
    return 1;
  }
  printf("  alpha     = %.12f (%s)\n", result.alpha,
         result.alpha > 1.0 ? "separated" : "in contact or interpenetrating");
  print3("point", result.point);
  print3("contact1", result.contact1);
  print3("contact2", result.contact2);
  printf("  iterations = %u\n", (unsigned)result.iterations);

  /* The gradient of alpha with respect to (r1, q1, r2, q2). */
  status = dcol_gradient(box, &box_pose, capsule, &capsule_pose, NULL, &result, gradient);
  printf("dcol_gradient: %s\n", dcol_status_string(status));
  if (status == DCOL_OK) {
    const char *labels[4] = {"d/dr1", "d/dq1", "d/dr2", "d/dq2"};
    const int start[5] = {0, 3, 7, 10, 14};
    for (i = 0; i < 4; i++) {
      int k;
      printf("  %-9s =", labels[i]);
      for (k = start[i]; k < start[i + 1]; k++) printf(" % .6f", gradient[k]);
      printf("\n");
    }
  } else {
    printf("  (no gradient: %s)\n", dcol_last_error_message());
  }

  /* A yes/no question is cheaper: dcol_intersect stops as soon as bounds on alpha decide. */
  if (dcol_intersect(box, &box_pose, capsule, &capsule_pose, NULL, &intersecting) == DCOL_OK)
    printf("dcol_intersect: %s\n", intersecting ? "interpenetrating" : "not interpenetrating");

  dcol_shape_free(box);
  dcol_shape_free(capsule);
  return 0;
}
