/* C99 tests of the whole C API (include/dcol.h): every function, every bad-input class of the
 * contract (status, message naming the argument and value, outputs left untouched), the
 * NOT_CONVERGED path, and known closed-form answers. */
#include "dcol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"

/* Byte pattern that pre-fills outputs, so that a write by a failing call is detected. */
#define SENTINEL 0xA5

static int contains(const char *haystack, const char *needle) {
  return strstr(haystack ? haystack : "", needle) != NULL;
}

static int untouched(const void *p, size_t n) {
  const unsigned char *b = (const unsigned char *)p;
  size_t i;
  for (i = 0; i < n; i++) {
    if (b[i] != SENTINEL) return 0;
  }
  return 1;
}

static dcol_pose pose_at(double x, double y, double z) {
  dcol_pose p;
  p.position[0] = x;
  p.position[1] = y;
  p.position[2] = z;
  p.quaternion[0] = 1.0;
  p.quaternion[1] = 0.0;
  p.quaternion[2] = 0.0;
  p.quaternion[3] = 0.0;
  return p;
}

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

/* The gradient, Jacobian and distance may still be under construction in the core: until they
 * are, they report DCOL_ERROR_INTERNAL with "not yet built". Anything else must be right. */
static int not_yet_built(dcol_status st) {
  return st == DCOL_ERROR_INTERNAL && contains(dcol_last_error_message(), "not yet built");
}

/* ------------------------------------------------------------------------------------------ */

static void test_version_and_status(void) {
  char buf[64];
  int i, j;
  const char *names[7] = {"DCOL_OK",
                          "DCOL_ERROR_NULL_POINTER",
                          "DCOL_ERROR_INVALID_SHAPE",
                          "DCOL_ERROR_INVALID_POSE",
                          "DCOL_ERROR_INVALID_OPTIONS",
                          "DCOL_ERROR_NOT_CONVERGED",
                          "DCOL_ERROR_INTERNAL"};

  /* Nothing has failed on this thread yet. */
  CHECK(dcol_last_error_message() != NULL);
  CHECK(strcmp(dcol_last_error_message(), "") == 0);

  CHECK(dcol_version() != NULL);
  CHECK(strcmp(dcol_version(), DCOL_VERSION_STRING) == 0);
  sprintf(buf, "%d.%d.%d", DCOL_VERSION_MAJOR, DCOL_VERSION_MINOR, DCOL_VERSION_PATCH);
  CHECK_MSG(strcmp(dcol_version(), buf) == 0, "library %s, header %s", dcol_version(), buf);

  /* The fixed values of the contract. */
  CHECK(DCOL_OK == 0);
  CHECK(DCOL_ERROR_NULL_POINTER == 1);
  CHECK(DCOL_ERROR_INVALID_SHAPE == 2);
  CHECK(DCOL_ERROR_INVALID_POSE == 3);
  CHECK(DCOL_ERROR_INVALID_OPTIONS == 4);
  CHECK(DCOL_ERROR_NOT_CONVERGED == 5);
  CHECK(DCOL_ERROR_INTERNAL == 6);

  for (i = 0; i <= 6; i++) {
    const char *s = dcol_status_string((dcol_status)i);
    CHECK(s != NULL && s[0] != '\0');
    CHECK_MSG(contains(s, names[i]), "status %d: %s", i, s);
    for (j = 0; j < i; j++) CHECK(strcmp(s, dcol_status_string((dcol_status)j)) != 0);
  }
  CHECK(contains(dcol_status_string((dcol_status)7), "unknown"));
  CHECK(contains(dcol_status_string((dcol_status)-1), "unknown"));
  CHECK(contains(dcol_status_string((dcol_status)1000000), "unknown"));

  {
    dcol_options o = dcol_options_default();
    CHECK(o.tolerance > 0.0 && o.tolerance < 1e-6);
    CHECK(o.max_iterations >= 10);
  }
}

/* ------------------------------------------------------------------------------------------ */

static const double BOX_A[18] = {1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
static const double SQUARE_C[8] = {1, 0, 0, 1, -1, 0, 0, -1};

static void test_constructors(void) {
  const double P[9] = {4, 0, 0, 0, 1, 0, 0, 0, 0.25};
  const double b[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
  const double d[4] = {1, 1, 1, 1};
  dcol_shape *s[8] = {NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL};
  int i;

  CHECK(dcol_shape_new_sphere(1.0, &s[0]) == DCOL_OK);
  CHECK(dcol_shape_new_ellipsoid(P, &s[1]) == DCOL_OK);
  CHECK(dcol_shape_new_polytope(BOX_A, b, 6, &s[2]) == DCOL_OK);
  CHECK(dcol_shape_new_box(0.5, 1.0, 1.5, &s[3]) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(0.5, 2.0, &s[4]) == DCOL_OK);
  CHECK(dcol_shape_new_cylinder(0.5, 2.0, &s[5]) == DCOL_OK);
  CHECK(dcol_shape_new_cone(1.0, 0.5, &s[6]) == DCOL_OK);
  CHECK(dcol_shape_new_polygon(SQUARE_C, d, 4, 0.1, &s[7]) == DCOL_OK);
  for (i = 0; i < 8; i++) {
    CHECK_MSG(s[i] != NULL, "shape %d", i);
    dcol_shape_free(s[i]);
  }
  dcol_shape_free(NULL); /* a no-op */

  /* A hull of a box's corners with interior, duplicate and face points, padded by 0.1: a
     rounded box, alpha* and the distance against a sphere along x in closed form. */
  {
    double pts[3 * 12];
    dcol_shape *hull = NULL, *ball = NULL;
    dcol_pose p1 = {{0, 0, 0}, {1, 0, 0, 0}}, p2 = {{2, 0, 0}, {1, 0, 0, 0}};
    dcol_proximity_result r;
    dcol_distance_result dr;
    for (i = 0; i < 8; i++) {
      pts[3 * i] = (i & 1) ? 0.5 : -0.5;
      pts[3 * i + 1] = (i & 2) ? 0.3 : -0.3;
      pts[3 * i + 2] = (i & 4) ? 0.2 : -0.2;
    }
    for (i = 24; i < 36; i++) pts[i] = 0.0;       /* the centre, three times */
    pts[33] = 0.5;                                  /* the centre of the +x face */
    CHECK(dcol_shape_new_convex_hull(pts, 12, 0.1, &hull) == DCOL_OK);
    CHECK(dcol_shape_new_sphere(0.4, &ball) == DCOL_OK);
    CHECK(dcol_proximity(hull, &p1, ball, &p2, NULL, &r) == DCOL_OK);
    CHECK_MSG(fabs(r.alpha - 2.0) < 1e-13, "alpha %.17g", r.alpha);
    CHECK(dcol_distance(hull, &p1, ball, &p2, NULL, &dr) == DCOL_OK);
    CHECK_MSG(fabs(dr.distance - 1.0) < 1e-13, "distance %.17g", dr.distance);
    CHECK(fabs(dr.closest1[0] - 0.6) < 1e-13 && fabs(dr.closest2[0] - 1.6) < 1e-13);
    dcol_shape_free(hull);
    dcol_shape_free(ball);
  }
}

/* Checks a failed constructor: its status, *out set to NULL, and a message with both needles. */
static void expect_ctor(int line, dcol_status st, const dcol_shape *out, dcol_status want,
                        const char *arg, const char *value) {
  const char *msg = dcol_last_error_message();
  CHECK_MSG(st == want, "line %d: status %d, want %d (%s)", line, (int)st, (int)want, msg);
  CHECK_MSG(out == NULL, "line %d: *out not set to NULL", line);
  CHECK_MSG(contains(msg, arg), "line %d: message lacks %s: %s", line, arg, msg);
  CHECK_MSG(contains(msg, value), "line %d: message lacks %s: %s", line, value, msg);
}

#define BAD_CTOR(call, want, arg, value)                                                      \
  do {                                                                                        \
    dcol_shape *out = (dcol_shape *)&out_sentinel; /* non-NULL: must be reset to NULL */     \
    dcol_status st_ = call;                                                                   \
    expect_ctor(__LINE__, st_, out, want, arg, value);                                        \
  } while (0)

static void test_constructor_errors(void) {
  int out_sentinel = 0;
  double P[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  double A[18];
  double b[6] = {1, 1, 1, 1, 1, 1};
  double C[8];
  double d[4] = {1, 1, 1, 1};
  double big_A[3 * 257];
  double big_b[257];
  size_t i;
  const dcol_status SHAPE = DCOL_ERROR_INVALID_SHAPE;
  const dcol_status NUL = DCOL_ERROR_NULL_POINTER;
  memcpy(A, BOX_A, sizeof A);
  memcpy(C, SQUARE_C, sizeof C);
  for (i = 0; i < 257; i++) {
    big_A[3 * i] = cos(0.1 * (double)i);
    big_A[3 * i + 1] = sin(0.1 * (double)i);
    big_A[3 * i + 2] = (i % 2) ? 1.0 : -1.0;
    big_b[i] = 1.0;
  }

  /* Non-positive or non-finite sizes. */
  BAD_CTOR(dcol_shape_new_sphere(-1.0, &out), SHAPE, "`radius`", "= -1:");
  BAD_CTOR(dcol_shape_new_sphere(0.0, &out), SHAPE, "`radius`", "= 0:");
  BAD_CTOR(dcol_shape_new_sphere(NAN, &out), SHAPE, "`radius`", "NaN");
  BAD_CTOR(dcol_shape_new_sphere(INFINITY, &out), SHAPE, "`radius`", "inf");
  BAD_CTOR(dcol_shape_new_box(1.0, 0.0, 1.0, &out), SHAPE, "`half_y`", "= 0:");
  BAD_CTOR(dcol_shape_new_box(1.0, 1.0, -2.5, &out), SHAPE, "`half_z`", "= -2.5:");
  BAD_CTOR(dcol_shape_new_capsule(0.5, -1.0, &out), SHAPE, "`length`", "= -1:");
  BAD_CTOR(dcol_shape_new_capsule(NAN, 1.0, &out), SHAPE, "`radius`", "NaN");
  BAD_CTOR(dcol_shape_new_cylinder(0.5, INFINITY, &out), SHAPE, "`length`", "inf");
  BAD_CTOR(dcol_shape_new_cylinder(0.0, 1.0, &out), SHAPE, "`radius`", "= 0:");
  BAD_CTOR(dcol_shape_new_cone(0.0, 0.5, &out), SHAPE, "`height`", "= 0:");
  BAD_CTOR(dcol_shape_new_cone(1.0, 2.0, &out), SHAPE, "`half_angle`", "= 2:");
  BAD_CTOR(dcol_shape_new_cone(1.0, 0.0, &out), SHAPE, "`half_angle`", "= 0:");
  BAD_CTOR(dcol_shape_new_polygon(C, d, 4, 0.0, &out), SHAPE, "`radius`", "= 0:");

  /* Matrices: non-finite, not positive definite, unbounded, origin not strictly inside. */
  P[4] = NAN;
  BAD_CTOR(dcol_shape_new_ellipsoid(P, &out), SHAPE, "`P[4]`", "NaN");
  P[4] = -1.0;
  BAD_CTOR(dcol_shape_new_ellipsoid(P, &out), SHAPE, "`P", "positive definite");
  P[4] = 1.0;
  b[3] = 0.0;
  BAD_CTOR(dcol_shape_new_polytope(A, b, 6, &out), SHAPE, "`b[3]`", "= 0:");
  b[3] = 1.0;
  A[7] = INFINITY;
  BAD_CTOR(dcol_shape_new_polytope(A, b, 6, &out), SHAPE, "`A[7]`", "inf");
  A[7] = 0.0;
  BAD_CTOR(dcol_shape_new_polytope(A, b, 3, &out), SHAPE, "`A", "bounded");
  BAD_CTOR(dcol_shape_new_polytope(A, b, 0, &out), SHAPE, "`m`", "= 0:");
  /* More than 256 facets is fine for a polytope (no facet cap), not for a polygon. */
  {
    dcol_shape *many = NULL;
    CHECK(dcol_shape_new_polytope(big_A, big_b, 257, &many) == DCOL_OK && many != NULL);
    dcol_shape_free(many);
  }
  BAD_CTOR(dcol_shape_new_polygon(big_A, big_b, 257, 0.1, &out), SHAPE, "`m`", "= 257:");
  /* Hulls: too few points, flat, non-finite, the origin outside (the centroid is named). */
  {
    double pts[3 * 9];
    for (i = 0; i < 8; i++) {
      pts[3 * i] = (i & 1) ? 1.0 : -1.0;
      pts[3 * i + 1] = (i & 2) ? 1.0 : -1.0;
      pts[3 * i + 2] = (i & 4) ? 1.0 : -1.0;
    }
    BAD_CTOR(dcol_shape_new_convex_hull(pts, 3, 0.0, &out), SHAPE, "`n` = 3", "at least 4");
    BAD_CTOR(dcol_shape_new_convex_hull(pts, 8, -0.5, &out), SHAPE, "`radius` = -0.5", "non-negative");
    BAD_CTOR(dcol_shape_new_convex_hull(NULL, 8, 0.0, &out), NUL, "`points`", "NULL");
    pts[3 * 5 + 1] = NAN;
    BAD_CTOR(dcol_shape_new_convex_hull(pts, 8, 0.0, &out), SHAPE, "`points[16]`", "NaN");
    pts[3 * 5 + 1] = -1.0;
    for (i = 0; i < 8; i++) pts[3 * i] += 3.0;
    BAD_CTOR(dcol_shape_new_convex_hull(pts, 8, 0.0, &out), SHAPE, "`points`", "(3, 0, 0)");
    for (i = 0; i < 8; i++) pts[3 * i + 2] = 0.5;
    BAD_CTOR(dcol_shape_new_convex_hull(pts, 8, 0.1, &out), SHAPE, "`n` = 8", "one plane");
    CHECK(dcol_shape_new_convex_hull(pts, 8, 0.1, NULL) == NUL);
  }
  d[1] = -1.0;
  BAD_CTOR(dcol_shape_new_polygon(C, d, 4, 0.1, &out), SHAPE, "`d[1]`", "= -1:");
  d[1] = 1.0;
  BAD_CTOR(dcol_shape_new_polygon(C, d, 2, 0.1, &out), SHAPE, "`C", "bounded");
  BAD_CTOR(dcol_shape_new_polygon(C, d, 0, 0.1, &out), SHAPE, "`m`", "= 0:");

  /* NULL arrays: *out is still reset. */
  BAD_CTOR(dcol_shape_new_ellipsoid(NULL, &out), NUL, "`P`", "NULL");
  BAD_CTOR(dcol_shape_new_polytope(NULL, b, 6, &out), NUL, "`A`", "NULL");
  BAD_CTOR(dcol_shape_new_polytope(A, NULL, 6, &out), NUL, "`b`", "NULL");
  BAD_CTOR(dcol_shape_new_polygon(NULL, d, 4, 0.1, &out), NUL, "`C`", "NULL");
  BAD_CTOR(dcol_shape_new_polygon(C, NULL, 4, 0.1, &out), NUL, "`d`", "NULL");

  /* NULL out: nothing to write, the status says so. */
  CHECK(dcol_shape_new_sphere(1.0, NULL) == NUL);
  CHECK(contains(dcol_last_error_message(), "`out`"));
  CHECK(dcol_shape_new_ellipsoid(P, NULL) == NUL);
  CHECK(dcol_shape_new_polytope(A, b, 6, NULL) == NUL);
  CHECK(dcol_shape_new_box(1, 1, 1, NULL) == NUL);
  CHECK(dcol_shape_new_capsule(1, 1, NULL) == NUL);
  CHECK(dcol_shape_new_cylinder(1, 1, NULL) == NUL);
  CHECK(dcol_shape_new_cone(1, 0.5, NULL) == NUL);
  CHECK(dcol_shape_new_polygon(C, d, 4, 0.1, NULL) == NUL);
  CHECK(contains(dcol_last_error_message(), "dcol_shape_new_polygon"));

  /* A successful call leaves the last message alone. */
  {
    dcol_shape *s = NULL;
    char before[512];
    strncpy(before, dcol_last_error_message(), sizeof before - 1);
    before[sizeof before - 1] = '\0';
    CHECK(dcol_shape_new_sphere(1.0, &s) == DCOL_OK);
    CHECK(strcmp(before, dcol_last_error_message()) == 0);
    dcol_shape_free(s);
  }
}

/* ------------------------------------------------------------------------------------------ */

static void test_proximity_values(void) {
  dcol_shape *a = NULL, *b = NULL, *box = NULL;
  dcol_pose p1 = pose_at(0, 0, 0), p2 = pose_at(3, 0, 0);
  dcol_proximity_result r;
  dcol_options o = dcol_options_default();

  CHECK(dcol_shape_new_sphere(1.0, &a) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &b) == DCOL_OK);
  CHECK(dcol_shape_new_box(0.5, 0.5, 0.5, &box) == DCOL_OK);

  /* Spheres: alpha* = |r1 - r2| / (R1 + R2). */
  CHECK(dcol_proximity(a, &p1, b, &p2, NULL, &r) == DCOL_OK);
  CHECK_MSG(near(r.alpha, 2.0, 1e-9), "alpha %.17g", r.alpha);
  CHECK(near(r.contact1[0], 1.0, 1e-6) && near(r.contact2[0], 2.5, 1e-6));
  CHECK(near(r.point[0], 2.0, 1e-6));
  /* Two spheres are a closed form: no interior-point iterations. */
  CHECK(r.iterations == 0 && r.solver == DCOL_SOLVER_CLOSED_FORM);
  {
    dcol_options ipm = dcol_options_default();
    ipm.method = DCOL_METHOD_INTERIOR_POINT;
    CHECK(dcol_proximity(a, &p1, b, &p2, &ipm, &r) == DCOL_OK);
    CHECK_MSG(near(r.alpha, 2.0, 1e-9), "alpha %.17g", r.alpha);
    CHECK(r.iterations >= 1 && r.iterations <= o.max_iterations);
    CHECK(r.solver == DCOL_SOLVER_INTERIOR_POINT);
    ipm.method = 7;
    CHECK(dcol_proximity(a, &p1, b, &p2, &ipm, &r) == DCOL_ERROR_INVALID_OPTIONS);
    CHECK(contains(dcol_last_error_message(), "method"));
  }

  /* The same with explicit default options, and with a non-unit quaternion. */
  p2.quaternion[0] = 3.0;
  {
    dcol_proximity_result r2;
    CHECK(dcol_proximity(a, &p1, b, &p2, &o, &r2) == DCOL_OK);
    CHECK(near(r2.alpha, r.alpha, 1e-12));
  }

  /* Box and sphere from the Rust docs: alpha* = 2. */
  p2 = pose_at(2, 0, 0);
  CHECK(dcol_proximity(box, &p1, b, &p2, NULL, &r) == DCOL_OK);
  CHECK_MSG(near(r.alpha, 2.0, 1e-8), "alpha %.17g", r.alpha);

  /* Coincident origins: alpha* = 0. */
  p2 = pose_at(0, 0, 0);
  CHECK(dcol_proximity(a, &p1, b, &p2, NULL, &r) == DCOL_OK);
  CHECK(r.alpha == 0.0);

  /* The same shape may be both arguments. */
  p2 = pose_at(0, 4, 0);
  CHECK(dcol_proximity(a, &p1, a, &p2, NULL, &r) == DCOL_OK);
  CHECK(near(r.alpha, 2.0, 1e-9));

  dcol_shape_free(a);
  dcol_shape_free(b);
  dcol_shape_free(box);
}

static void test_derivatives_and_distance(void) {
  dcol_shape *a = NULL, *b = NULL;
  dcol_pose p1 = pose_at(0.1, -0.2, 0.3), p2 = pose_at(2.0, 1.0, -0.5);
  dcol_proximity_result r;
  dcol_distance_result dr;
  double g[14], J[56];
  double dx = 1.9, dy = 1.2, dz = -0.8;
  double n = sqrt(dx * dx + dy * dy + dz * dz);
  double R = 1.0 + 0.5;
  dcol_status st;
  int k;

  CHECK(dcol_shape_new_sphere(1.0, &a) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &b) == DCOL_OK);

  /* Spheres: d alpha / d r2 = (r2 - r1) / (|r2 - r1| (R1 + R2)), the quaternion columns are 0. */
  st = dcol_gradient(a, &p1, b, &p2, NULL, &r, g);
  if (not_yet_built(st)) {
    printf("note: dcol_gradient: %s\n", dcol_last_error_message());
  } else {
    CHECK_MSG(st == DCOL_OK, "%s", dcol_last_error_message());
    CHECK(near(r.alpha, n / R, 1e-9));
    CHECK_MSG(near(g[7], dx / (n * R), 1e-6), "g[7] = %.17g", g[7]);
    CHECK(near(g[8], dy / (n * R), 1e-6) && near(g[9], dz / (n * R), 1e-6));
    CHECK(near(g[0], -g[7], 1e-6) && near(g[1], -g[8], 1e-6) && near(g[2], -g[9], 1e-6));
    for (k = 3; k < 7; k++) CHECK(near(g[k], 0.0, 1e-6) && near(g[k + 7], 0.0, 1e-6));
  }

  st = dcol_jacobian(a, &p1, b, &p2, NULL, &r, J);
  if (not_yet_built(st)) {
    printf("note: dcol_jacobian: %s\n", dcol_last_error_message());
  } else {
    CHECK_MSG(st == DCOL_OK, "%s", dcol_last_error_message());
    /* The alpha row is the gradient. */
    CHECK_MSG(near(J[3 * 14 + 7], dx / (n * R), 1e-6), "J[3][7] = %.17g", J[3 * 14 + 7]);
    /* Translating both shapes moves x* with them: d x / d r1 + d x / d r2 = I. */
    CHECK(near(J[0 * 14 + 0] + J[0 * 14 + 7], 1.0, 1e-6));
    CHECK(near(J[1 * 14 + 1] + J[1 * 14 + 8], 1.0, 1e-6));
    CHECK(near(J[2 * 14 + 2] + J[2 * 14 + 9], 1.0, 1e-6));
  }

  st = dcol_distance(a, &p1, b, &p2, NULL, &dr);
  if (not_yet_built(st)) {
    printf("note: dcol_distance: %s\n", dcol_last_error_message());
  } else {
    CHECK_MSG(st == DCOL_OK, "%s", dcol_last_error_message());
    CHECK_MSG(near(dr.distance, n - R, 1e-7), "distance %.17g, want %.17g", dr.distance, n - R);
    CHECK(near(dr.closest1[0], 0.1 + dx / n, 1e-6) && near(dr.closest2[0], 2.0 - 0.5 * dx / n, 1e-6));
    CHECK(near(dr.normal[0], dx / n, 1e-6) && near(dr.normal[1], dy / n, 1e-6));
  }

  dcol_shape_free(a);
  dcol_shape_free(b);
}

/* ------------------------------------------------------------------------------------------ */

/* Every query function through one signature, so that the bad-input checks run on all four. */
enum query { PROXIMITY, GRADIENT, JACOBIAN, DISTANCE };
static const char *QUERY_NAME[4] = {"dcol_proximity", "dcol_gradient", "dcol_jacobian",
                                    "dcol_distance"};

struct outputs {
  dcol_proximity_result prox;
  dcol_distance_result dist;
  double array[56];
};

static dcol_status call(enum query q, const dcol_shape *s1, const dcol_pose *p1,
                        const dcol_shape *s2, const dcol_pose *p2, const dcol_options *o,
                        struct outputs *out, int null_result, int null_array) {
  dcol_proximity_result *res = null_result ? NULL : &out->prox;
  double *arr = null_array ? NULL : out->array;
  switch (q) {
    case PROXIMITY:
      return dcol_proximity(s1, p1, s2, p2, o, res);
    case GRADIENT:
      return dcol_gradient(s1, p1, s2, p2, o, res, arr);
    case JACOBIAN:
      return dcol_jacobian(s1, p1, s2, p2, o, res, arr);
    case DISTANCE:
      return dcol_distance(s1, p1, s2, p2, o, null_result ? NULL : &out->dist);
  }
  return DCOL_ERROR_INTERNAL;
}

static void expect_query(int line, enum query q, dcol_status st, const struct outputs *out,
                         dcol_status want, const char *needle1, const char *needle2) {
  const char *msg = dcol_last_error_message();
  CHECK_MSG(st == want, "line %d, %s: status %d, want %d (%s)", line, QUERY_NAME[q], (int)st,
            (int)want, msg);
  CHECK_MSG(untouched(out, sizeof *out), "line %d, %s: outputs written on error", line,
            QUERY_NAME[q]);
  CHECK_MSG(contains(msg, QUERY_NAME[q]), "line %d: message lacks the function: %s", line, msg);
  CHECK_MSG(contains(msg, needle1), "line %d: message lacks %s: %s", line, needle1, msg);
  CHECK_MSG(contains(msg, needle2), "line %d: message lacks %s: %s", line, needle2, msg);
}

#define BAD_QUERY(q, s1, p1, s2, p2, o, null_result, null_array, want, n1, n2)                 \
  do {                                                                                        \
    struct outputs out_;                                                                      \
    dcol_status st_;                                                                          \
    memset(&out_, SENTINEL, sizeof out_);                                                     \
    st_ = call(q, s1, p1, s2, p2, o, &out_, null_result, null_array);                         \
    expect_query(__LINE__, q, st_, &out_, want, n1, n2);                                      \
  } while (0)

static void test_query_errors(void) {
  dcol_shape *s = NULL, *c = NULL;
  dcol_pose good = pose_at(0, 0, 0), far = pose_at(3, 0, 0), bad;
  dcol_options o = dcol_options_default(), bad_o;
  const dcol_status NUL = DCOL_ERROR_NULL_POINTER, POSE = DCOL_ERROR_INVALID_POSE,
                    OPT = DCOL_ERROR_INVALID_OPTIONS;
  int qi;

  CHECK(dcol_shape_new_sphere(1.0, &s) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(0.5, 1.0, &c) == DCOL_OK);

  for (qi = PROXIMITY; qi <= DISTANCE; qi++) {
    enum query q = (enum query)qi;

    /* NULL pointers, each one. */
    BAD_QUERY(q, NULL, &good, c, &far, &o, 0, 0, NUL, "`shape1`", "NULL");
    BAD_QUERY(q, s, NULL, c, &far, &o, 0, 0, NUL, "`pose1`", "NULL");
    BAD_QUERY(q, s, &good, NULL, &far, &o, 0, 0, NUL, "`shape2`", "NULL");
    BAD_QUERY(q, s, &good, c, NULL, &o, 0, 0, NUL, "`pose2`", "NULL");
    BAD_QUERY(q, s, &good, c, &far, &o, 1, 0, NUL, "`result`", "NULL");
    if (q == GRADIENT) BAD_QUERY(q, s, &good, c, &far, &o, 0, 1, NUL, "`gradient`", "NULL");
    if (q == JACOBIAN) BAD_QUERY(q, s, &good, c, &far, &o, 0, 1, NUL, "`jacobian`", "NULL");

    /* Bad poses: non-finite position or attitude, zero quaternion. */
    bad = far;
    bad.position[1] = NAN;
    BAD_QUERY(q, s, &good, c, &bad, &o, 0, 0, POSE, "`pose2->position[1]`", "NaN");
    bad = good;
    bad.position[2] = -INFINITY;
    BAD_QUERY(q, s, &bad, c, &far, &o, 0, 0, POSE, "`pose1->position[2]`", "-inf");
    bad = far;
    bad.quaternion[3] = INFINITY;
    BAD_QUERY(q, s, &good, c, &bad, &o, 0, 0, POSE, "`pose2->quaternion[3]`", "inf");
    bad = good;
    bad.quaternion[0] = 0.0;
    BAD_QUERY(q, s, &bad, c, &far, &o, 0, 0, POSE, "`pose1->quaternion`", "zero");

    /* Bad options: tolerance not positive and finite, zero iteration limit. */
    bad_o = o;
    bad_o.tolerance = 0.0;
    BAD_QUERY(q, s, &good, c, &far, &bad_o, 0, 0, OPT, "`options->tolerance`", "= 0:");
    bad_o.tolerance = -1e-8;
    BAD_QUERY(q, s, &good, c, &far, &bad_o, 0, 0, OPT, "`options->tolerance`", "-1e-8");
    bad_o.tolerance = NAN;
    BAD_QUERY(q, s, &good, c, &far, &bad_o, 0, 0, OPT, "`options->tolerance`", "NaN");
    bad_o.tolerance = INFINITY;
    BAD_QUERY(q, s, &good, c, &far, &bad_o, 0, 0, OPT, "`options->tolerance`", "inf");
    bad_o = o;
    bad_o.max_iterations = 0;
    BAD_QUERY(q, s, &good, c, &far, &bad_o, 0, 0, OPT, "`options->max_iterations`", "= 0:");
  }

  dcol_shape_free(s);
  dcol_shape_free(c);
}

static void test_not_converged(void) {
  dcol_shape *s = NULL, *c = NULL;
  dcol_pose p1 = pose_at(0, 0, 0), p2 = pose_at(2.5, 0.3, -0.2);
  dcol_options o = dcol_options_default();
  dcol_proximity_result r;
  double g[14];
  dcol_status st;

  CHECK(dcol_shape_new_cone(1.0, 0.4, &s) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(0.5, 1.0, &c) == DCOL_OK);
  o.max_iterations = 1;
  o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
  memset(&r, SENTINEL, sizeof r);
  st = dcol_proximity(s, &p1, c, &p2, &o, &r);
  CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "status %d", (int)st);
  /* The result holds the last iterate. */
  CHECK(!untouched(&r, sizeof r));
  CHECK(r.iterations == 1);
  CHECK(isfinite(r.alpha) && isfinite(r.point[0]));
  CHECK(contains(dcol_last_error_message(), "`options->max_iterations` = 1"));

  memset(&r, SENTINEL, sizeof r);
  st = dcol_gradient(s, &p1, c, &p2, &o, &r, g);
  if (!not_yet_built(st)) {
    CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "status %d", (int)st);
    CHECK(r.iterations == 1);
  }
  dcol_shape_free(s);
  dcol_shape_free(c);
}

/* The half-space: the floor {z <= 0} as dcol_shape_new_halfspace(depth) at (0, 0, -depth). */
static void test_halfspace(void) {
  dcol_shape *floor_ = NULL, *box = NULL, *ball = NULL, *other = NULL;
  dcol_pose under = pose_at(0.0, 0.0, -2.0), on = pose_at(0.3, -0.2, 0.49);
  dcol_proximity_result r;
  dcol_signed_distance_result sd;
  dcol_distance_result d;
  dcol_derivatives_result dr;
  dcol_contact c[8];
  double g[14], j[56];
  size_t n = 99;
  int32_t below = -1;
  int i;
  int out_sentinel = 0;

  /* Bad depths: zero, negative, NaN, infinite. */
  BAD_CTOR(dcol_shape_new_halfspace(0.0, &out), DCOL_ERROR_INVALID_SHAPE, "depth", "0");
  BAD_CTOR(dcol_shape_new_halfspace(-1.0, &out), DCOL_ERROR_INVALID_SHAPE, "depth", "-1");
  BAD_CTOR(dcol_shape_new_halfspace(NAN, &out), DCOL_ERROR_INVALID_SHAPE, "depth", "NaN");
  BAD_CTOR(dcol_shape_new_halfspace(INFINITY, &out), DCOL_ERROR_INVALID_SHAPE, "depth", "inf");
  CHECK(dcol_shape_new_halfspace(1.0, NULL) == DCOL_ERROR_NULL_POINTER);

  CHECK(dcol_shape_new_halfspace(2.0, &floor_) == DCOL_OK && floor_ != NULL);
  CHECK(dcol_shape_new_box(0.5, 0.4, 0.25, &box) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &ball) == DCOL_OK);
  CHECK(dcol_shape_new_halfspace(1.0, &other) == DCOL_OK);

  /* A ball 0.01 into the floor: alpha* = n.(rB - rH) / (depth + R) = 2.49 / 2.5. */
  CHECK(dcol_proximity(floor_, &under, ball, &on, NULL, &r) == DCOL_OK);
  CHECK_MSG(near(r.alpha, 2.49 / 2.5, 1e-15), "alpha %.17g", r.alpha);
  CHECK(r.solver == DCOL_SOLVER_CLOSED_FORM && r.iterations == 0);
  CHECK(near(r.point[2], 0.49 - r.alpha * 0.5, 1e-15) && near(r.point[0], 0.3, 1e-15));
  CHECK(dcol_proximity(ball, &on, floor_, &under, NULL, &r) == DCOL_OK);
  CHECK(near(r.alpha, 2.49 / 2.5, 1e-15));

  /* Gradient: d alpha / d r_B = n / (depth + R), d alpha / d r_H = -n / (depth + R). */
  CHECK(dcol_gradient(floor_, &under, ball, &on, NULL, &r, g) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_EXACT);
  CHECK(near(g[2], -0.4, 1e-15) && near(g[9], 0.4, 1e-15) && g[0] == 0.0 && g[7] == 0.0);
  CHECK(dcol_jacobian(floor_, &under, ball, &on, NULL, &r, j) == DCOL_OK);
  CHECK(near(j[3 * 14 + 9], 0.4, 1e-15) && near(j[0 * 14 + 7], 1.0, 1e-15));
  CHECK(dcol_derivatives(floor_, &under, ball, &on, NULL, &dr) == DCOL_OK);
  CHECK(near(dr.proximity.alpha, 2.49 / 2.5, 1e-15));

  /* Signed distance -0.01, normal +z from the floor to the ball; distance 0 (overlap). */
  CHECK(dcol_signed_distance(floor_, &under, ball, &on, NULL, &sd) == DCOL_OK);
  CHECK_MSG(near(sd.distance, -0.01, 1e-15), "sd %.17g", sd.distance);
  CHECK(sd.normal[2] == 1.0 && near(sd.closest1[2], 0.0, 1e-15));
  CHECK(near(sd.closest2[2], -0.01, 1e-15));
  CHECK(dcol_signed_distance(ball, &on, floor_, &under, NULL, &sd) == DCOL_OK);
  CHECK(sd.normal[2] == -1.0 && near(sd.distance, -0.01, 1e-15));
  CHECK(dcol_distance(floor_, &under, ball, &on, NULL, &d) == DCOL_OK);
  CHECK(d.distance == 0.0);
  CHECK(dcol_intersect(floor_, &under, ball, &on, NULL, &below) == DCOL_OK && below == 1);

  /* A box resting 0.01 deep: four contacts of depth 0.01, normal from the box to the floor. */
  on = pose_at(1.0, 2.0, 0.24);
  CHECK(dcol_contacts(box, &on, floor_, &under, 0.0, NULL, c, 8, &n) == DCOL_OK);
  CHECK_MSG(n == 4, "%zu contacts", n);
  for (i = 0; i < (int)n && i < 8; i++) {
    CHECK(near(c[i].depth, 0.01, 1e-15) && c[i].normal[2] == -1.0);
    CHECK(near(c[i].position[2], -0.005, 1e-15));
    CHECK(near(fabs(c[i].position[0] - 1.0), 0.5, 1e-15));
  }

  /* Separated: distance and its gradient. */
  on = pose_at(0.0, 0.0, 1.0);
  CHECK(dcol_distance_gradient(floor_, &under, box, &on, NULL, &d, g) == DCOL_OK);
  CHECK(near(d.distance, 0.75, 1e-15) && near(g[9], 1.0, 1e-15) && near(g[2], -1.0, 1e-15));
  CHECK(dcol_alpha_below(box, &on, floor_, &under, 1.0, NULL, &below) == DCOL_OK && below == 0);

  /* Two half-spaces: every query is DCOL_ERROR_INVALID_SHAPE, never a crash. */
  memset(&r, SENTINEL, sizeof r);
  CHECK(dcol_proximity(floor_, &under, other, &on, NULL, &r) == DCOL_ERROR_INVALID_SHAPE);
  CHECK(contains(dcol_last_error_message(), "two half-spaces"));
  CHECK(untouched(&r, sizeof r));
  CHECK(dcol_gradient(floor_, &under, other, &on, NULL, &r, g) == DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_jacobian(floor_, &under, other, &on, NULL, &r, j) == DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_distance(floor_, &under, other, &on, NULL, &d) == DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_signed_distance(other, &on, floor_, &under, NULL, &sd) ==
        DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_contacts(floor_, &under, other, &on, 0.0, NULL, c, 8, &n) ==
        DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_intersect(floor_, &under, other, &on, NULL, &below) == DCOL_ERROR_INVALID_SHAPE);
  CHECK(dcol_alpha_below(floor_, &under, other, &on, 1e9, NULL, &below) ==
        DCOL_ERROR_INVALID_SHAPE);

  dcol_shape_free(floor_);
  dcol_shape_free(box);
  dcol_shape_free(ball);
  dcol_shape_free(other);
}

int main(void) {
  test_version_and_status();
  test_constructors();
  test_constructor_errors();
  test_proximity_values();
  test_derivatives_and_distance();
  test_query_errors();
  test_not_converged();
  test_halfspace();
  return check_summary("test_api");
}
