/* C99 tests of the C API extensions: dcol_alpha_below, dcol_intersect, dcol_distance_gradient,
 * dcol_derivatives, dcol_gradient_mrp, dcol_jacobian_mrp, dcol_proximity_batch and the
 * dcol_scene functions. For each: every bad-input class (status, message naming the function,
 * the argument and its value, outputs left untouched), and the results against the single-call
 * functions (bit for bit where the contract says so), closed forms, the chain rule and finite
 * differences. Arrays handed to the library are allocated with exactly the documented number of
 * elements, so ASan and valgrind catch any read or write past them. */
#include "dcol.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

/* Byte pattern that pre-fills outputs, so that a write by a failing call is detected. */
#define SENTINEL 0xA5
#define NSHAPES 8

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

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

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

/* Bitwise equality of doubles (NaN-safe, distinguishes -0). */
static int same_doubles(const double *a, const double *b, size_t n) {
  return memcmp(a, b, n * sizeof(double)) == 0;
}

/* Field-by-field bitwise equality (the struct has padding, which memcmp must not see). */
static int same_result(const dcol_proximity_result *a, const dcol_proximity_result *b) {
  return same_doubles(&a->alpha, &b->alpha, 1) && same_doubles(a->point, b->point, 3) &&
         same_doubles(a->contact1, b->contact1, 3) && same_doubles(a->contact2, b->contact2, 3) &&
         a->iterations == b->iterations;
}

/* The same proximity to the solver's tolerance: alpha* within 1e-12 relative, the points
 * within 1e-11 (the scene's shapes are of unit size), the same iterations. A scene's pairs of
 * polytopes start from their last answer (dcol_cache), which agrees with a cold one to that. */
static int close_result(const dcol_proximity_result *a, const dcol_proximity_result *b) {
  int i, ok = fabs(a->alpha - b->alpha) <= 1e-12 * fabs(b->alpha) && a->iterations == b->iterations;
  for (i = 0; i < 3; i++) {
    ok = ok && fabs(a->point[i] - b->point[i]) <= 1e-11 && fabs(a->contact1[i] - b->contact1[i]) <= 1e-11 &&
         fabs(a->contact2[i] - b->contact2[i]) <= 1e-11;
  }
  return ok;
}

/* The last error message must name the function and contain both needles. */
static void expect_error(int line, const char *func, dcol_status st, dcol_status want,
                         int outputs_untouched, const char *needle1, const char *needle2) {
  const char *msg = dcol_last_error_message();
  CHECK_MSG(st == want, "line %d, %s: status %d, want %d (%s)", line, func, (int)st, (int)want,
            msg);
  CHECK_MSG(outputs_untouched, "line %d, %s: outputs written on error", line, func);
  CHECK_MSG(contains(msg, func), "line %d: message lacks %s: %s", line, func, msg);
  CHECK_MSG(contains(msg, needle1), "line %d: message lacks %s: %s", line, needle1, msg);
  CHECK_MSG(contains(msg, needle2), "line %d: message lacks %s: %s", line, needle2, msg);
}

/* A deterministic generator (xorshift64) for the random scenes and poses. */
static uint64_t rng_state = 0x9E3779B97F4A7C15u;
static double rnd(void) {
  rng_state ^= rng_state << 13;
  rng_state ^= rng_state >> 7;
  rng_state ^= rng_state << 17;
  return (double)(rng_state >> 11) / 9007199254740992.0;
}
static double rnd_in(double a, double b) { return a + (b - a) * rnd(); }

static dcol_pose random_pose(double extent) {
  dcol_pose p;
  int k;
  for (k = 0; k < 3; k++) p.position[k] = rnd_in(0.0, extent);
  for (k = 0; k < 4; k++) p.quaternion[k] = rnd_in(-1.0, 1.0);
  return p;
}

/* One shape of every kind, scaled by s. */
static dcol_shape *make_shape(int kind, double s) {
  static const double TETRA_A[12] = {1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1};
  static const double SQUARE_C[8] = {1, 0, 0, 1, -1, 0, 0, -1};
  double P[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  double b[4], d[4];
  dcol_shape *out = NULL;
  dcol_status st = DCOL_ERROR_INTERNAL;
  int k;
  switch (kind) {
    case 0:
      st = dcol_shape_new_sphere(s, &out);
      break;
    case 1:
      P[0] = 1.0 / (s * s);
      P[4] = 4.0 / (s * s);
      P[8] = 2.0 / (s * s);
      st = dcol_shape_new_ellipsoid(P, &out);
      break;
    case 2:
      st = dcol_shape_new_box(s, 0.7 * s, 0.4 * s, &out);
      break;
    case 3:
      for (k = 0; k < 4; k++) b[k] = s;
      st = dcol_shape_new_polytope(TETRA_A, b, 4, &out);
      break;
    case 4:
      st = dcol_shape_new_capsule(0.3 * s, s, &out);
      break;
    case 5:
      st = dcol_shape_new_cylinder(0.4 * s, s, &out);
      break;
    case 6:
      st = dcol_shape_new_cone(s, 0.5, &out);
      break;
    default:
      for (k = 0; k < 4; k++) d[k] = 0.5 * s;
      st = dcol_shape_new_polygon(SQUARE_C, d, 4, 0.1 * s, &out);
      break;
  }
  CHECK_MSG(st == DCOL_OK && out != NULL, "shape kind %d: %s", kind, dcol_last_error_message());
  return out;
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_alpha_below and dcol_intersect */

static void test_alpha_below_values(void) {
  dcol_shape *a = NULL, *b = NULL, *shapes[NSHAPES];
  dcol_pose p1 = pose_at(0, 0, 0), p2 = pose_at(3, 0, 0);
  const double thresholds[5] = {0.25, 0.8, 1.0, 1.3, 2.5};
  int32_t below = -1, inter = -1;
  int i, j, t, trial, decided = 0;

  CHECK(dcol_shape_new_sphere(1.0, &a) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &b) == DCOL_OK);
  /* Spheres, alpha* = 2 exactly: decided by the closed-form bounds. */
  CHECK(dcol_alpha_below(a, &p1, b, &p2, 2.5, NULL, &below) == DCOL_OK && below == 1);
  CHECK(dcol_alpha_below(a, &p1, b, &p2, 1.5, NULL, &below) == DCOL_OK && below == 0);
  CHECK(dcol_intersect(a, &p1, b, &p2, NULL, &inter) == DCOL_OK && inter == 0);
  p2 = pose_at(1.0, 0.2, 0);
  CHECK(dcol_intersect(a, &p1, b, &p2, NULL, &inter) == DCOL_OK && inter == 1);
  /* Coincident origins: alpha* = 0 < any threshold. */
  p2 = pose_at(0, 0, 0);
  CHECK(dcol_alpha_below(a, &p1, b, &p2, 1e-9, NULL, &below) == DCOL_OK && below == 1);
  dcol_shape_free(a);
  dcol_shape_free(b);

  /* Against dcol_proximity on every pair of kinds at random poses, outside a 1e-6 band. */
  for (i = 0; i < NSHAPES; i++) shapes[i] = make_shape(i, rnd_in(0.4, 1.0));
  for (trial = 0; trial < 4; trial++) {
    for (i = 0; i < NSHAPES; i++) {
      for (j = 0; j < NSHAPES; j++) {
        dcol_pose q1 = random_pose(1.5), q2 = random_pose(1.5);
        dcol_proximity_result r;
        dcol_status st = dcol_proximity(shapes[i], &q1, shapes[j], &q2, NULL, &r);
        CHECK_MSG(st == DCOL_OK, "proximity %d-%d: %s", i, j, dcol_last_error_message());
        for (t = 0; t < 5; t++) {
          double th = thresholds[t] * (trial == 3 ? r.alpha : 1.0); /* trial 3: at alpha* */
          below = -1;
          st = dcol_alpha_below(shapes[i], &q1, shapes[j], &q2, th, NULL, &below);
          CHECK_MSG(st == DCOL_OK, "alpha_below %d-%d: %s", i, j, dcol_last_error_message());
          CHECK(below == 0 || below == 1);
          if (fabs(r.alpha - th) > 1e-6 * (th > 1.0 ? th : 1.0)) {
            CHECK_MSG(below == (r.alpha < th), "%d-%d: alpha %.17g, threshold %.17g, below %d",
                      i, j, r.alpha, th, (int)below);
            decided++;
          }
          if (th == 1.0) {
            inter = -1;
            CHECK(dcol_intersect(shapes[i], &q1, shapes[j], &q2, NULL, &inter) == DCOL_OK);
            CHECK(inter == below);
          }
        }
      }
    }
  }
  CHECK_MSG(decided > 4 * NSHAPES * NSHAPES, "only %d decisions compared", decided);
  for (i = 0; i < NSHAPES; i++) dcol_shape_free(shapes[i]);
}

#define BAD_BELOW(s1, p1, s2, p2, th, o, outp, want, n1, n2)                                    \
  do {                                                                                        \
    int32_t out_;                                                                             \
    dcol_status st_;                                                                          \
    memset(&out_, SENTINEL, sizeof out_);                                                     \
    st_ = dcol_alpha_below(s1, p1, s2, p2, th, o, (outp) ? &out_ : NULL);                     \
    expect_error(__LINE__, "dcol_alpha_below", st_, want, untouched(&out_, sizeof out_), n1,  \
                 n2);                                                                         \
    memset(&out_, SENTINEL, sizeof out_);                                                     \
    if ((th) == 1.0) {                                                                        \
      st_ = dcol_intersect(s1, p1, s2, p2, o, (outp) ? &out_ : NULL);                         \
      expect_error(__LINE__, "dcol_intersect", st_, want, untouched(&out_, sizeof out_),     \
                   strcmp(n1, "`below`") == 0 ? "`intersecting`" : n1, n2);                   \
    }                                                                                         \
  } while (0)

static void test_alpha_below_errors(void) {
  dcol_shape *s = NULL, *c = NULL;
  dcol_pose good = pose_at(0, 0, 0), far = pose_at(3, 0, 0), bad;
  dcol_options o = dcol_options_default(), bad_o;
  const dcol_status NUL = DCOL_ERROR_NULL_POINTER, POSE = DCOL_ERROR_INVALID_POSE,
                    OPT = DCOL_ERROR_INVALID_OPTIONS;

  CHECK(dcol_shape_new_sphere(1.0, &s) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(0.5, 1.0, &c) == DCOL_OK);

  BAD_BELOW(NULL, &good, c, &far, 1.0, &o, 1, NUL, "`shape1`", "NULL");
  BAD_BELOW(s, NULL, c, &far, 1.0, &o, 1, NUL, "`pose1`", "NULL");
  BAD_BELOW(s, &good, NULL, &far, 1.0, &o, 1, NUL, "`shape2`", "NULL");
  BAD_BELOW(s, &good, c, NULL, 1.0, &o, 1, NUL, "`pose2`", "NULL");
  BAD_BELOW(s, &good, c, &far, 1.0, &o, 0, NUL, "`below`", "NULL");

  bad = far;
  bad.position[1] = NAN;
  BAD_BELOW(s, &good, c, &bad, 1.0, &o, 1, POSE, "`pose2->position[1]`", "NaN");
  bad = good;
  bad.quaternion[0] = 0.0;
  BAD_BELOW(s, &bad, c, &far, 1.0, &o, 1, POSE, "`pose1->quaternion`", "zero");

  bad_o = o;
  bad_o.tolerance = -1e-8;
  BAD_BELOW(s, &good, c, &far, 1.0, &bad_o, 1, OPT, "`options->tolerance`", "-1e-8");
  bad_o = o;
  bad_o.max_iterations = 0;
  BAD_BELOW(s, &good, c, &far, 1.0, &bad_o, 1, OPT, "`options->max_iterations`", "= 0:");

  /* The threshold: positive and finite. */
  BAD_BELOW(s, &good, c, &far, 0.0, &o, 1, OPT, "`threshold`", "= 0:");
  BAD_BELOW(s, &good, c, &far, -2.0, &o, 1, OPT, "`threshold`", "= -2:");
  BAD_BELOW(s, &good, c, &far, NAN, &o, 1, OPT, "`threshold`", "NaN");
  BAD_BELOW(s, &good, c, &far, INFINITY, &o, 1, OPT, "`threshold`", "inf");

  /* A threshold the bounds cannot decide, one iteration allowed: the solve cannot certify. */
  {
    dcol_shape *cone = NULL;
    dcol_pose p2 = pose_at(2.5, 0.3, -0.2);
    dcol_proximity_result r;
    int32_t below;
    dcol_status st;
    CHECK(dcol_shape_new_cone(1.0, 0.4, &cone) == DCOL_OK);
    CHECK(dcol_proximity(cone, &good, c, &p2, NULL, &r) == DCOL_OK);
    bad_o = o;
    bad_o.max_iterations = 1;
    bad_o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
    memset(&below, SENTINEL, sizeof below);
    st = dcol_alpha_below(cone, &good, c, &p2, r.alpha * (1.0 + 1e-9), &bad_o, &below);
    CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "status %d", (int)st);
    CHECK(below == 0 || below == 1); /* written from the last iterate */
    CHECK(contains(dcol_last_error_message(), "`options->max_iterations` = 1"));
    dcol_shape_free(cone);
  }

  dcol_shape_free(s);
  dcol_shape_free(c);
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_distance_gradient */

static void test_distance_gradient(void) {
  dcol_shape *a = NULL, *b = NULL, *shapes[NSHAPES];
  dcol_pose p1 = pose_at(0.1, -0.2, 0.3), p2 = pose_at(2.0, 1.0, -0.5), bad;
  dcol_distance_result d, d0;
  double g[14];
  double dx = 1.9, dy = 1.2, dz = -0.8;
  double n = sqrt(dx * dx + dy * dy + dz * dz);
  dcol_options o = dcol_options_default();
  int i, k;

  CHECK(dcol_shape_new_sphere(1.0, &a) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &b) == DCOL_OK);
  /* Spheres: d = |dr| - R1 - R2, grad wrt r2 = dr/|dr|, wrt r1 = -dr/|dr|, rotations 0. */
  CHECK_MSG(dcol_distance_gradient(a, &p1, b, &p2, NULL, &d, g) == DCOL_OK, "%s",
            dcol_last_error_message());
  CHECK(near(d.distance, n - 1.5, 1e-7));
  CHECK_MSG(near(g[7], dx / n, 1e-6) && near(g[8], dy / n, 1e-6) && near(g[9], dz / n, 1e-6),
            "g[7..10] = %g %g %g", g[7], g[8], g[9]);
  CHECK(near(g[0], -dx / n, 1e-6) && near(g[1], -dy / n, 1e-6) && near(g[2], -dz / n, 1e-6));
  for (k = 3; k < 7; k++) CHECK(near(g[k], 0.0, 1e-6) && near(g[k + 7], 0.0, 1e-6));
  /* The result is dcol_distance's, bit for bit. */
  CHECK(dcol_distance(a, &p1, b, &p2, NULL, &d0) == DCOL_OK);
  CHECK(same_doubles(&d.distance, &d0.distance, 1) && same_doubles(d.closest1, d0.closest1, 3) &&
        same_doubles(d.closest2, d0.closest2, 3) && same_doubles(d.normal, d0.normal, 3) &&
        d.iterations == d0.iterations);
  /* Overlapping: distance 0 and a zero gradient. */
  p2 = pose_at(1.0, 0, 0);
  CHECK(dcol_distance_gradient(a, &p1, b, &p2, NULL, &d, g) == DCOL_OK);
  CHECK(d.distance == 0.0);
  for (k = 0; k < 14; k++) CHECK(g[k] == 0.0);

  /* Every kind against central differences of dcol_distance in the position of shape 2 (the
   * translation columns; a finite difference in r2 is exact up to O(h^2)). */
  for (i = 0; i < NSHAPES; i++) shapes[i] = make_shape(i, 0.5);
  for (i = 0; i < NSHAPES; i++) {
    dcol_pose q1 = random_pose(0.1), q2 = pose_at(2.2, 0.3, -0.4);
    double h = 1e-6;
    q2.quaternion[1] = 0.3;
    CHECK(dcol_distance_gradient(shapes[i], &q1, shapes[(i + 3) % NSHAPES], &q2, NULL, &d, g) ==
          DCOL_OK);
    for (k = 0; k < 3; k++) {
      dcol_pose qp = q2, qm = q2;
      dcol_distance_result dp, dm;
      qp.position[k] += h;
      qm.position[k] -= h;
      CHECK(dcol_distance(shapes[i], &q1, shapes[(i + 3) % NSHAPES], &qp, NULL, &dp) == DCOL_OK);
      CHECK(dcol_distance(shapes[i], &q1, shapes[(i + 3) % NSHAPES], &qm, NULL, &dm) == DCOL_OK);
      CHECK_MSG(near(g[7 + k], (dp.distance - dm.distance) / (2 * h), 1e-4),
                "kind %d, column %d: %.9g vs %.9g", i, 7 + k, g[7 + k],
                (dp.distance - dm.distance) / (2 * h));
    }
  }
  for (i = 0; i < NSHAPES; i++) dcol_shape_free(shapes[i]);

  /* Bad inputs: nothing written. */
  {
    struct {
      dcol_distance_result d;
      double g[14];
    } out;
    const char *F = "dcol_distance_gradient";
    dcol_options bad_o = o;
    p2 = pose_at(3, 0, 0);
#define BAD_DG(s1, q1, s2, q2, opt, res, grad, want, n1, n2)                                   \
  do {                                                                                        \
    dcol_status st_;                                                                          \
    memset(&out, SENTINEL, sizeof out);                                                       \
    st_ = dcol_distance_gradient(s1, q1, s2, q2, opt, res, grad);                             \
    expect_error(__LINE__, F, st_, want, untouched(&out, sizeof out), n1, n2);                \
  } while (0)
    BAD_DG(NULL, &p1, b, &p2, NULL, &out.d, out.g, DCOL_ERROR_NULL_POINTER, "`shape1`", "NULL");
    BAD_DG(a, NULL, b, &p2, NULL, &out.d, out.g, DCOL_ERROR_NULL_POINTER, "`pose1`", "NULL");
    BAD_DG(a, &p1, NULL, &p2, NULL, &out.d, out.g, DCOL_ERROR_NULL_POINTER, "`shape2`", "NULL");
    BAD_DG(a, &p1, b, NULL, NULL, &out.d, out.g, DCOL_ERROR_NULL_POINTER, "`pose2`", "NULL");
    BAD_DG(a, &p1, b, &p2, NULL, NULL, out.g, DCOL_ERROR_NULL_POINTER, "`result`", "NULL");
    BAD_DG(a, &p1, b, &p2, NULL, &out.d, NULL, DCOL_ERROR_NULL_POINTER, "`gradient`", "NULL");
    bad = p2;
    bad.quaternion[2] = -INFINITY;
    BAD_DG(a, &p1, b, &bad, NULL, &out.d, out.g, DCOL_ERROR_INVALID_POSE, "`pose2->quaternion[2]`",
           "-inf");
    bad_o.tolerance = INFINITY;
    BAD_DG(a, &p1, b, &p2, &bad_o, &out.d, out.g, DCOL_ERROR_INVALID_OPTIONS,
           "`options->tolerance`", "inf");
#undef BAD_DG
  }
  dcol_shape_free(a);
  dcol_shape_free(b);
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_derivatives */

static void test_derivatives(void) {
  dcol_shape *shapes[NSHAPES];
  dcol_derivatives_result D;
  dcol_proximity_result r;
  double g[14], J[56];
  int i, row, col;

  for (i = 0; i < NSHAPES; i++) shapes[i] = make_shape(i, rnd_in(0.4, 1.0));
  for (i = 0; i < NSHAPES; i++) {
    const dcol_shape *s1 = shapes[i], *s2 = shapes[(i + 5) % NSHAPES];
    dcol_pose q1 = random_pose(0.2), q2 = random_pose(0.2);
    double inv;
    q2.position[0] += 2.0;
    CHECK_MSG(dcol_derivatives(s1, &q1, s2, &q2, NULL, &D) == DCOL_OK, "%s",
              dcol_last_error_message());
    /* By default dcol_derivatives, dcol_jacobian, dcol_gradient and dcol_proximity share one
       solve (the geometric solvers; the interior-point method where they fall back): the same
       proximity and gradient, bit for bit. The interior-point method agrees to the solvers'
       accuracy. */
    {
      dcol_options ipm = dcol_options_default();
      double gi[14];
      int k;
      ipm.method = DCOL_METHOD_INTERIOR_POINT;
      CHECK(dcol_proximity(s1, &q1, s2, &q2, NULL, &r) == DCOL_OK);
      CHECK_MSG(same_result(&D.proximity, &r), "kind %d: proximity differs", i);
      CHECK(dcol_gradient(s1, &q1, s2, &q2, NULL, &r, g) == DCOL_OK);
      CHECK_MSG(same_doubles(D.gradient, g, 14), "kind %d: gradient differs", i);
      CHECK(D.proximity.derivatives == DCOL_DERIVATIVES_EXACT);
      CHECK(dcol_gradient(s1, &q1, s2, &q2, &ipm, &r, gi) == DCOL_OK);
      CHECK_MSG(near(r.alpha, D.proximity.alpha, 1e-10 * fmax(1.0, r.alpha)),
                "kind %d: interior-point alpha %.17g vs %.17g", i, r.alpha, D.proximity.alpha);
      for (k = 0; k < 14; k++)
        CHECK_MSG(near(gi[k], D.gradient[k], 1e-6 * fmax(1.0, fabs(D.gradient[k]))),
                  "kind %d: interior-point gradient[%d] %.17g vs %.17g", i, k, gi[k],
                  D.gradient[k]);
    }
    CHECK(dcol_jacobian(s1, &q1, s2, &q2, NULL, &r, J) == DCOL_OK);
    CHECK_MSG(same_doubles(&D.jacobian[0][0], J, 56), "kind %d: Jacobian differs", i);
    /* The contact Jacobians follow from the chain rule on p_i = r_i + (x - r_i) / alpha. */
    inv = 1.0 / r.alpha;
    for (row = 0; row < 3; row++) {
      for (col = 0; col < 14; col++) {
        double dr1 = (col == row) ? 1.0 : 0.0, dr2 = (col == 7 + row) ? 1.0 : 0.0;
        double e1 = dr1 + (J[row * 14 + col] - dr1) * inv -
                    (r.point[row] - q1.position[row]) * J[3 * 14 + col] * inv * inv;
        double e2 = dr2 + (J[row * 14 + col] - dr2) * inv -
                    (r.point[row] - q2.position[row]) * J[3 * 14 + col] * inv * inv;
        CHECK_MSG(near(D.contact_jacobian1[row][col], e1, 1e-12 * (1.0 + fabs(e1))),
                  "kind %d: dp1[%d][%d] = %.17g, want %.17g", i, row, col,
                  D.contact_jacobian1[row][col], e1);
        CHECK(near(D.contact_jacobian2[row][col], e2, 1e-12 * (1.0 + fabs(e2))));
      }
    }
  }

  /* Contact point of two spheres against central differences (smooth everywhere). */
  {
    dcol_pose q1 = pose_at(0.1, 0.2, -0.1), q2 = pose_at(2.0, 0.7, 0.4);
    const double h = 1e-6;
    int k;
    q1.quaternion[2] = 0.3;
    CHECK(dcol_derivatives(shapes[0], &q1, shapes[1], &q2, NULL, &D) == DCOL_OK);
    for (col = 0; col < 14; col++) {
      dcol_pose a1 = q1, a2 = q2, b1 = q1, b2 = q2;
      dcol_proximity_result rp, rm;
      double *pa = col < 3    ? &a1.position[col]
                   : col < 7  ? &a1.quaternion[col - 3]
                   : col < 10 ? &a2.position[col - 7]
                              : &a2.quaternion[col - 10];
      double *pb = col < 3    ? &b1.position[col]
                   : col < 7  ? &b1.quaternion[col - 3]
                   : col < 10 ? &b2.position[col - 7]
                              : &b2.quaternion[col - 10];
      *pa += h;
      *pb -= h;
      CHECK(dcol_proximity(shapes[0], &a1, shapes[1], &a2, NULL, &rp) == DCOL_OK);
      CHECK(dcol_proximity(shapes[0], &b1, shapes[1], &b2, NULL, &rm) == DCOL_OK);
      for (k = 0; k < 3; k++) {
        double fd1 = (rp.contact1[k] - rm.contact1[k]) / (2 * h);
        double fd2 = (rp.contact2[k] - rm.contact2[k]) / (2 * h);
        CHECK_MSG(near(D.contact_jacobian1[k][col], fd1, 1e-5), "dp1[%d][%d] = %.9g, fd %.9g",
                  k, col, D.contact_jacobian1[k][col], fd1);
        CHECK_MSG(near(D.contact_jacobian2[k][col], fd2, 1e-5), "dp2[%d][%d] = %.9g, fd %.9g",
                  k, col, D.contact_jacobian2[k][col], fd2);
      }
    }
  }

  /* Bad inputs: nothing written. Not converged: the proximity holds the last iterate. */
  {
    dcol_pose good = pose_at(0, 0, 0), far = pose_at(3, 0, 0), bad;
    dcol_options o = dcol_options_default();
    const char *F = "dcol_derivatives";
    dcol_status st;
#define BAD_D(s1, q1, s2, q2, opt, res, want, n1, n2)                                          \
  do {                                                                                        \
    memset(&D, SENTINEL, sizeof D);                                                           \
    st = dcol_derivatives(s1, q1, s2, q2, opt, res);                                          \
    expect_error(__LINE__, F, st, want, untouched(&D, sizeof D), n1, n2);                     \
  } while (0)
    BAD_D(NULL, &good, shapes[1], &far, NULL, &D, DCOL_ERROR_NULL_POINTER, "`shape1`", "NULL");
    BAD_D(shapes[0], NULL, shapes[1], &far, NULL, &D, DCOL_ERROR_NULL_POINTER, "`pose1`", "NULL");
    BAD_D(shapes[0], &good, NULL, &far, NULL, &D, DCOL_ERROR_NULL_POINTER, "`shape2`", "NULL");
    BAD_D(shapes[0], &good, shapes[1], NULL, NULL, &D, DCOL_ERROR_NULL_POINTER, "`pose2`", "NULL");
    BAD_D(shapes[0], &good, shapes[1], &far, NULL, NULL, DCOL_ERROR_NULL_POINTER, "`result`",
          "NULL");
    bad = good;
    bad.position[0] = NAN;
    BAD_D(shapes[0], &bad, shapes[1], &far, NULL, &D, DCOL_ERROR_INVALID_POSE,
          "`pose1->position[0]`", "NaN");
    o.max_iterations = 0;
    BAD_D(shapes[0], &good, shapes[1], &far, &o, &D, DCOL_ERROR_INVALID_OPTIONS,
          "`options->max_iterations`", "= 0:");
#undef BAD_D
    o.max_iterations = 1;
    o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
    far = pose_at(2.5, 0.3, -0.2);
    memset(&D, SENTINEL, sizeof D);
    st = dcol_derivatives(shapes[6], &good, shapes[4], &far, &o, &D);
    CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "status %d", (int)st);
    CHECK(D.proximity.iterations == 1 && isfinite(D.proximity.alpha));
  }
  for (i = 0; i < NSHAPES; i++) dcol_shape_free(shapes[i]);
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_gradient_mrp and dcol_jacobian_mrp */

static void quaternion_from_mrp(const double p[3], double q[4]) {
  double pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  q[0] = (1.0 - pp) / (1.0 + pp);
  q[1] = 2.0 * p[0] / (1.0 + pp);
  q[2] = 2.0 * p[1] / (1.0 + pp);
  q[3] = 2.0 * p[2] / (1.0 + pp);
}

/* dq/dp, 4x3 row-major. */
static void mrp_jacobian(const double p[3], double out[12]) {
  double pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  double d = 1.0 + pp;
  int r, c;
  for (c = 0; c < 3; c++) {
    out[c] = -4.0 * p[c] / (d * d);
    for (r = 0; r < 3; r++) out[(r + 1) * 3 + c] = 2.0 * (r == c) / d - 4.0 * p[r] * p[c] / (d * d);
  }
}

static dcol_pose mrp_pose(const double r[3], const double p[3]) {
  dcol_pose pose;
  memcpy(pose.position, r, sizeof pose.position);
  quaternion_from_mrp(p, pose.quaternion);
  return pose;
}

static void test_mrp(void) {
  dcol_shape *shapes[NSHAPES];
  int i, k, c, row;
  for (i = 0; i < NSHAPES; i++) shapes[i] = make_shape(i, rnd_in(0.4, 1.0));

  for (i = 0; i < NSHAPES; i++) {
    const dcol_shape *s1 = shapes[i], *s2 = shapes[(i + 2) % NSHAPES];
    double r1[3], m1[3], r2[3], m2[3], gq[14], gm[12], Jq[56], Jm[48], dq1[12], dq2[12];
    dcol_proximity_result rq, rm;
    dcol_pose q1, q2;
    for (k = 0; k < 3; k++) {
      r1[k] = rnd_in(0.0, 0.2);
      r2[k] = rnd_in(0.0, 0.2) + (k == 0 ? 2.0 : 0.0);
      m1[k] = rnd_in(-0.6, 0.6);
      m2[k] = rnd_in(-0.6, 0.6);
    }
    q1 = mrp_pose(r1, m1);
    q2 = mrp_pose(r2, m2);
    mrp_jacobian(m1, dq1);
    mrp_jacobian(m2, dq2);

    CHECK_MSG(dcol_gradient_mrp(s1, r1, m1, s2, r2, m2, NULL, &rm, gm) == DCOL_OK, "%s",
              dcol_last_error_message());
    CHECK(dcol_gradient(s1, &q1, s2, &q2, NULL, &rq, gq) == DCOL_OK);
    CHECK(near(rm.alpha, rq.alpha, 1e-12 * rq.alpha));
    /* Chain rule: position columns copied, MRP columns = quaternion columns times dq/dp. */
    for (k = 0; k < 3; k++) {
      CHECK(near(gm[k], gq[k], 1e-9) && near(gm[6 + k], gq[7 + k], 1e-9));
    }
    for (c = 0; c < 3; c++) {
      double e1 = 0.0, e2 = 0.0;
      for (k = 0; k < 4; k++) {
        e1 += gq[3 + k] * dq1[k * 3 + c];
        e2 += gq[10 + k] * dq2[k * 3 + c];
      }
      CHECK_MSG(near(gm[3 + c], e1, 1e-8) && near(gm[9 + c], e2, 1e-8),
                "kind %d, MRP column %d: %.12g %.12g, want %.12g %.12g", i, c, gm[3 + c],
                gm[9 + c], e1, e2);
    }
    /* Central differences of alpha in the MRPs (smooth shapes only: spheres, ellipsoids). */
    if (i <= 1) {
      const double h = 1e-6;
      for (c = 0; c < 3; c++) {
        double mp[3], mm[3];
        dcol_proximity_result a, b;
        memcpy(mp, m2, sizeof mp);
        memcpy(mm, m2, sizeof mm);
        mp[c] += h;
        mm[c] -= h;
        q2 = mrp_pose(r2, mp);
        CHECK(dcol_proximity(s1, &q1, s2, &q2, NULL, &a) == DCOL_OK);
        q2 = mrp_pose(r2, mm);
        CHECK(dcol_proximity(s1, &q1, s2, &q2, NULL, &b) == DCOL_OK);
        CHECK_MSG(near(gm[9 + c], (a.alpha - b.alpha) / (2 * h), 1e-5),
                  "kind %d, column %d: %.9g, fd %.9g", i, 9 + c, gm[9 + c],
                  (a.alpha - b.alpha) / (2 * h));
      }
      q2 = mrp_pose(r2, m2);
    }

    CHECK_MSG(dcol_jacobian_mrp(s1, r1, m1, s2, r2, m2, NULL, &rm, Jm) == DCOL_OK, "%s",
              dcol_last_error_message());
    CHECK(dcol_jacobian(s1, &q1, s2, &q2, NULL, &rq, Jq) == DCOL_OK);
    for (row = 0; row < 4; row++) {
      for (k = 0; k < 3; k++) {
        CHECK(near(Jm[row * 12 + k], Jq[row * 14 + k], 1e-8));
        CHECK(near(Jm[row * 12 + 6 + k], Jq[row * 14 + 7 + k], 1e-8));
      }
      for (c = 0; c < 3; c++) {
        double e1 = 0.0, e2 = 0.0;
        for (k = 0; k < 4; k++) {
          e1 += Jq[row * 14 + 3 + k] * dq1[k * 3 + c];
          e2 += Jq[row * 14 + 10 + k] * dq2[k * 3 + c];
        }
        CHECK_MSG(near(Jm[row * 12 + 3 + c], e1, 1e-7) && near(Jm[row * 12 + 9 + c], e2, 1e-7),
                  "kind %d, row %d, MRP column %d", i, row, c);
      }
    }
    /* The alpha row of the Jacobian is the gradient. */
    for (k = 0; k < 12; k++) CHECK(near(Jm[3 * 12 + k], gm[k], 1e-6));
  }

  /* Bad inputs: nothing written, messages name the C argument. */
  {
    const double r1[3] = {0, 0, 0}, m1[3] = {0.1, 0.2, 0.3}, r2[3] = {3, 0, 0},
                 m2[3] = {0, 0, 0};
    double bad[3];
    struct {
      dcol_proximity_result r;
      double a[48];
    } out;
    dcol_options o = dcol_options_default();
    const dcol_shape *s = shapes[0], *t = shapes[4];
    int which;
    dcol_status st;
    for (which = 0; which < 2; which++) {
      const char *F = which == 0 ? "dcol_gradient_mrp" : "dcol_jacobian_mrp";
      const char *arr = which == 0 ? "`gradient`" : "`jacobian`";
#define MRP_CALL(s1, a1, b1, s2, a2, b2, opt, res, ar)                                         \
  (which == 0 ? dcol_gradient_mrp(s1, a1, b1, s2, a2, b2, opt, res, ar)                       \
              : dcol_jacobian_mrp(s1, a1, b1, s2, a2, b2, opt, res, ar))
#define BAD_M(s1, a1, b1, s2, a2, b2, opt, res, ar, want, n1, n2)                             \
  do {                                                                                        \
    memset(&out, SENTINEL, sizeof out);                                                       \
    st = MRP_CALL(s1, a1, b1, s2, a2, b2, opt, res, ar);                                      \
    expect_error(__LINE__, F, st, want, untouched(&out, sizeof out), n1, n2);                 \
  } while (0)
      const dcol_status NUL = DCOL_ERROR_NULL_POINTER, POSE = DCOL_ERROR_INVALID_POSE;
      BAD_M(NULL, r1, m1, t, r2, m2, NULL, &out.r, out.a, NUL, "`shape1`", "NULL");
      BAD_M(s, NULL, m1, t, r2, m2, NULL, &out.r, out.a, NUL, "`position1`", "NULL");
      BAD_M(s, r1, NULL, t, r2, m2, NULL, &out.r, out.a, NUL, "`mrp1`", "NULL");
      BAD_M(s, r1, m1, NULL, r2, m2, NULL, &out.r, out.a, NUL, "`shape2`", "NULL");
      BAD_M(s, r1, m1, t, NULL, m2, NULL, &out.r, out.a, NUL, "`position2`", "NULL");
      BAD_M(s, r1, m1, t, r2, NULL, NULL, &out.r, out.a, NUL, "`mrp2`", "NULL");
      BAD_M(s, r1, m1, t, r2, m2, NULL, NULL, out.a, NUL, "`result`", "NULL");
      BAD_M(s, r1, m1, t, r2, m2, NULL, &out.r, NULL, NUL, arr, "NULL");
      memcpy(bad, r1, sizeof bad);
      bad[1] = NAN;
      BAD_M(s, bad, m1, t, r2, m2, NULL, &out.r, out.a, POSE, "`position1[1]`", "NaN");
      memcpy(bad, m2, sizeof bad);
      bad[2] = -INFINITY;
      BAD_M(s, r1, m1, t, r2, bad, NULL, &out.r, out.a, POSE, "`mrp2[2]`", "-inf");
      bad[2] = 1e200; /* finite, but p.p overflows */
      BAD_M(s, r1, m1, t, r2, bad, NULL, &out.r, out.a, POSE, "`mrp2[2]`", "overflows");
      o.tolerance = 0.0;
      BAD_M(s, r1, m1, t, r2, m2, &o, &out.r, out.a, DCOL_ERROR_INVALID_OPTIONS,
            "`options->tolerance`", "= 0:");
      o = dcol_options_default();
      /* Not converged: the result holds the last iterate. */
      o.max_iterations = 1;
      o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
      memset(&out, SENTINEL, sizeof out);
      st = MRP_CALL(shapes[6], r1, m1, shapes[4], r2, m2, &o, &out.r, out.a);
      CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "%s: status %d", F, (int)st);
      CHECK(out.r.iterations == 1);
      o = dcol_options_default();
#undef BAD_M
#undef MRP_CALL
    }
  }
  for (i = 0; i < NSHAPES; i++) dcol_shape_free(shapes[i]);
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_proximity_batch */

#define BATCH 61

static void test_batch(void) {
  dcol_shape *shapes[NSHAPES];
  /* Exactly BATCH elements each, on the heap: reading or writing past them is caught. */
  const dcol_shape **s1 = (const dcol_shape **)malloc(BATCH * sizeof *s1);
  const dcol_shape **s2 = (const dcol_shape **)malloc(BATCH * sizeof *s2);
  dcol_pose *p1 = (dcol_pose *)malloc(BATCH * sizeof *p1);
  dcol_pose *p2 = (dcol_pose *)malloc(BATCH * sizeof *p2);
  dcol_proximity_result *res = (dcol_proximity_result *)malloc(BATCH * sizeof *res);
  dcol_proximity_result *single = (dcol_proximity_result *)malloc(BATCH * sizeof *single);
  dcol_status *st = (dcol_status *)malloc(BATCH * sizeof *st);
  dcol_status *single_st = (dcol_status *)malloc(BATCH * sizeof *single_st);
  const uint32_t thread_counts[7] = {0, 1, 2, 3, 7, 1000, 4294967295u};
  dcol_options o = dcol_options_default();
  char before[512];
  int i, t;

  if (!s1 || !s2 || !p1 || !p2 || !res || !single || !st || !single_st) {
    CHECK(!"out of memory");
    return;
  }
  for (i = 0; i < NSHAPES; i++) shapes[i] = make_shape(i, rnd_in(0.3, 1.0));
  for (i = 0; i < BATCH; i++) {
    s1[i] = shapes[i % NSHAPES];
    s2[i] = shapes[(i * 5 + 3) % NSHAPES];
    p1[i] = random_pose(2.0);
    p2[i] = random_pose(2.0);
  }
  /* Bad pairs: each gets its status, its result is untouched, the others are unaffected. */
  s1[3] = NULL;
  s2[10] = NULL;
  p2[5].position[1] = NAN;
  p1[20].quaternion[0] = p1[20].quaternion[1] = p1[20].quaternion[2] = 0.0;
  p1[20].quaternion[3] = 0.0;
  p2[60].quaternion[2] = INFINITY; /* the last pair */
  p2[7] = p1[7];                   /* coincident origins: alpha = 0 */
  for (i = 0; i < BATCH; i++) {
    memset(&single[i], SENTINEL, sizeof single[i]);
    single_st[i] = dcol_proximity(s1[i], &p1[i], s2[i], &p2[i], NULL, &single[i]);
  }
  CHECK(single_st[3] == DCOL_ERROR_NULL_POINTER && single_st[10] == DCOL_ERROR_NULL_POINTER);
  CHECK(single_st[5] == DCOL_ERROR_INVALID_POSE && single_st[20] == DCOL_ERROR_INVALID_POSE);
  CHECK(single_st[60] == DCOL_ERROR_INVALID_POSE && single_st[7] == DCOL_OK);

  strncpy(before, dcol_last_error_message(), sizeof before - 1);
  before[sizeof before - 1] = '\0';
  for (t = 0; t < 7; t++) {
    int mismatches = 0;
    memset(res, SENTINEL, BATCH * sizeof *res);
    memset(st, SENTINEL, BATCH * sizeof *st);
    CHECK_MSG(dcol_proximity_batch(s1, p1, s2, p2, BATCH, NULL, thread_counts[t], res, st) ==
                  DCOL_OK,
              "%s", dcol_last_error_message());
    for (i = 0; i < BATCH; i++) {
      int ok = st[i] == single_st[i];
      if (single_st[i] == DCOL_OK || single_st[i] == DCOL_ERROR_NOT_CONVERGED) {
        ok = ok && same_result(&res[i], &single[i]);
      } else {
        ok = ok && untouched(&res[i], sizeof res[i]);
      }
      if (!ok) {
        mismatches++;
        fprintf(stderr, "threads %u, pair %d: status %d vs %d\n", (unsigned)thread_counts[t], i,
                (int)st[i], (int)single_st[i]);
      }
    }
    CHECK_MSG(mismatches == 0, "threads %u: %d pairs differ from dcol_proximity",
              (unsigned)thread_counts[t], mismatches);
    /* Per-pair failures do not replace the thread's last error message. */
    CHECK(strcmp(before, dcol_last_error_message()) == 0);
  }

  /* Per-pair NOT_CONVERGED, with the last iterate written; options apply to every pair. */
  o.max_iterations = 1;
  o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
  memset(res, SENTINEL, BATCH * sizeof *res);
  CHECK(dcol_proximity_batch(s1, p1, s2, p2, BATCH, &o, 2, res, st) == DCOL_OK);
  for (i = 0; i < BATCH; i++) {
    dcol_proximity_result r;
    dcol_status s_single = dcol_proximity(s1[i], &p1[i], s2[i], &p2[i], &o, &r);
    CHECK_MSG(st[i] == s_single, "pair %d: %d vs %d", i, (int)st[i], (int)s_single);
    if (s_single == DCOL_ERROR_NOT_CONVERGED) CHECK(same_result(&res[i], &r) && r.iterations == 1);
  }
  o = dcol_options_default();

  /* Call-level errors: nothing written, statuses included. */
  {
    const char *F = "dcol_proximity_batch";
    dcol_status call;
#define BAD_B(a, b, c, d, n, opt, r, s, want, n1, n2)                                           \
  do {                                                                                        \
    memset(res, SENTINEL, BATCH * sizeof *res);                                               \
    memset(st, SENTINEL, BATCH * sizeof *st);                                                 \
    call = dcol_proximity_batch(a, b, c, d, n, opt, 4, r, s);                                 \
    expect_error(__LINE__, F, call, want,                                                     \
                 untouched(res, BATCH * sizeof *res) && untouched(st, BATCH * sizeof *st), n1, \
                 n2);                                                                         \
  } while (0)
    const dcol_status NUL = DCOL_ERROR_NULL_POINTER;
    BAD_B(NULL, p1, s2, p2, BATCH, NULL, res, st, NUL, "`shapes1`", "NULL");
    BAD_B(s1, NULL, s2, p2, BATCH, NULL, res, st, NUL, "`poses1`", "NULL");
    BAD_B(s1, p1, NULL, p2, BATCH, NULL, res, st, NUL, "`shapes2`", "NULL");
    BAD_B(s1, p1, s2, NULL, BATCH, NULL, res, st, NUL, "`poses2`", "NULL");
    BAD_B(s1, p1, s2, p2, BATCH, NULL, NULL, st, NUL, "`results`", "NULL");
    BAD_B(s1, p1, s2, p2, BATCH, NULL, res, NULL, NUL, "`statuses`", "NULL");
    o.tolerance = NAN;
    BAD_B(s1, p1, s2, p2, BATCH, &o, res, st, DCOL_ERROR_INVALID_OPTIONS, "`options->tolerance`",
          "NaN");
    o = dcol_options_default();
    o.max_iterations = 0;
    BAD_B(s1, p1, s2, p2, 0, &o, res, st, DCOL_ERROR_INVALID_OPTIONS, "`options->max_iterations`",
          "= 0:");
#undef BAD_B
    /* count == 0: nothing is read or written, NULL arrays are fine. */
    CHECK(dcol_proximity_batch(NULL, NULL, NULL, NULL, 0, NULL, 8, NULL, NULL) == DCOL_OK);
    memset(st, SENTINEL, BATCH * sizeof *st);
    CHECK(dcol_proximity_batch(s1, p1, s2, p2, 0, NULL, 8, res, st) == DCOL_OK);
    CHECK(untouched(st, BATCH * sizeof *st));
    /* A one-pair batch (count < threads). */
    CHECK(dcol_proximity_batch(s1, p1, s2, p2, 1, NULL, 8, res, st) == DCOL_OK);
    CHECK(st[0] == single_st[0] && same_result(&res[0], &single[0]));
  }

  for (i = 0; i < NSHAPES; i++) dcol_shape_free(shapes[i]);
  free((void *)s1);
  free((void *)s2);
  free(p1);
  free(p2);
  free(res);
  free(single);
  free(st);
  free(single_st);
}

/* ------------------------------------------------------------------------------------------ */
/* dcol_scene */

#define BODIES 40

static void test_scene_values(void) {
  dcol_scene *scene = NULL;
  dcol_shape *shapes[BODIES];
  dcol_pose poses[BODIES];
  dcol_scene_pair *pairs = (dcol_scene_pair *)malloc(BODIES * BODIES * sizeof *pairs);
  const double thresholds[3] = {0.5, 1.0, 1.5};
  dcol_scene_stats stats;
  size_t id, n = 0, count;
  int i, j, t, step, compared = 0;

  if (!pairs) {
    CHECK(!"out of memory");
    return;
  }
  CHECK(dcol_scene_new(&scene) == DCOL_OK && scene != NULL);
  CHECK(dcol_scene_size(scene, &n) == DCOL_OK && n == 0);
  /* An empty scene has no pairs; pairs may be NULL with capacity 0. */
  CHECK(dcol_scene_pairs_within(scene, 1.0, NULL, NULL, 0, &count, NULL) == DCOL_OK &&
        count == 0);
  for (i = 0; i < BODIES; i++) {
    /* The scene keeps its own copy: the caller's shape is freed right away (ASan and valgrind
     * would see a use after free), and an equal one is kept for the brute force. */
    double size = rnd_in(0.2, 1.0);
    dcol_shape *own = make_shape(i % NSHAPES, size);
    shapes[i] = make_shape(i % NSHAPES, size);
    poses[i] = random_pose(6.0);
    CHECK(dcol_scene_add(scene, own, &poses[i], &id) == DCOL_OK);
    CHECK(id == (size_t)i);
    dcol_shape_free(own);
  }
  CHECK(dcol_scene_size(scene, &n) == DCOL_OK && n == BODIES);

  for (step = 0; step < 3; step++) {
    if (step > 0) {
      for (i = 0; i < BODIES; i++) {
        if (rnd() < 0.5) {
          poses[i] = random_pose(6.0);
          CHECK(dcol_scene_set_pose(scene, (size_t)i, &poses[i]) == DCOL_OK);
        }
      }
    }
    for (t = 0; t < 3; t++) {
      double th = thresholds[t];
      size_t k = 0, expected = 0;
      dcol_status s;
      memset(&stats, SENTINEL, sizeof stats);
      s = dcol_scene_pairs_within(scene, th, NULL, pairs, BODIES * BODIES, &count, &stats);
      CHECK_MSG(s == DCOL_OK, "%s", dcol_last_error_message());
      CHECK(stats.pairs_total == (size_t)BODIES * (BODIES - 1) / 2);
      CHECK(stats.reported == count);
      CHECK(stats.sphere_candidates <= stats.sweep_candidates);
      CHECK(stats.full_solves + stats.early_exits <= stats.sphere_candidates);
      /* Ordered, body1 < body2. */
      for (k = 0; k < count; k++) {
        CHECK(pairs[k].body1 < pairs[k].body2 && pairs[k].body2 < BODIES);
        CHECK(pairs[k].status == DCOL_OK);
        if (k > 0) {
          CHECK(pairs[k - 1].body1 < pairs[k].body1 ||
                (pairs[k - 1].body1 == pairs[k].body1 && pairs[k - 1].body2 < pairs[k].body2));
        }
      }
      /* Brute force over dcol_proximity: the same pairs, the same results (bit for bit but
       * between polytopes: see close_result), outside a 1e-7 band around the threshold. */
      k = 0;
      for (i = 0; i < BODIES; i++) {
        for (j = i + 1; j < BODIES; j++) {
          dcol_proximity_result r;
          int in_band, listed;
          CHECK(dcol_proximity(shapes[i], &poses[i], shapes[j], &poses[j], NULL, &r) == DCOL_OK);
          while (k < count && (pairs[k].body1 < (size_t)i ||
                               (pairs[k].body1 == (size_t)i && pairs[k].body2 < (size_t)j))) {
            k++;
          }
          listed = k < count && pairs[k].body1 == (size_t)i && pairs[k].body2 == (size_t)j;
          in_band = fabs(r.alpha - th) < 1e-7 * th;
          if (listed) {
            CHECK_MSG(close_result(&pairs[k].proximity, &r), "pair (%d, %d) differs", i, j);
            compared++;
          }
          if (!in_band) {
            CHECK_MSG(listed == (r.alpha <= th), "step %d, t %g, pair (%d, %d): alpha %.17g, %s",
                      step, th, i, j, r.alpha, listed ? "listed" : "not listed");
            expected += r.alpha <= th;
          }
        }
      }
      CHECK(expected <= count + 2 && count <= expected + 2);
    }
  }
  CHECK_MSG(compared > 50, "only %d reported pairs compared", compared);

  dcol_scene_free(scene);
  for (i = 0; i < BODIES; i++) dcol_shape_free(shapes[i]);
  free(pairs);
}

static void test_scene_errors(void) {
  dcol_scene *scene = NULL;
  dcol_shape *ball = NULL;
  dcol_pose good = pose_at(0, 0, 0), near_pose = pose_at(0.5, 0, 0), bad;
  dcol_options o = dcol_options_default();
  dcol_scene_pair pairs[4];
  dcol_scene_stats stats;
  size_t id, count, n;
  dcol_status st;
  const dcol_status NUL = DCOL_ERROR_NULL_POINTER, POSE = DCOL_ERROR_INVALID_POSE,
                    OPT = DCOL_ERROR_INVALID_OPTIONS;

  /* dcol_scene_new / dcol_scene_free. */
  CHECK(dcol_scene_new(NULL) == NUL);
  CHECK(contains(dcol_last_error_message(), "dcol_scene_new") &&
        contains(dcol_last_error_message(), "`out`"));
  dcol_scene_free(NULL); /* a no-op */

  CHECK(dcol_scene_new(&scene) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(1.0, &ball) == DCOL_OK);

  /* dcol_scene_add: nothing added, *id untouched. */
#define BAD_ADD(sc, sh, p, idp, want, n1, n2)                                                   \
  do {                                                                                        \
    memset(&id, SENTINEL, sizeof id);                                                         \
    st = dcol_scene_add(sc, sh, p, idp);                                                      \
    expect_error(__LINE__, "dcol_scene_add", st, want, untouched(&id, sizeof id), n1, n2);    \
    CHECK(dcol_scene_size(scene, &n) == DCOL_OK && n == 0);                                   \
  } while (0)
  BAD_ADD(NULL, ball, &good, &id, NUL, "`scene`", "NULL");
  BAD_ADD(scene, NULL, &good, &id, NUL, "`shape`", "NULL");
  BAD_ADD(scene, ball, NULL, &id, NUL, "`pose`", "NULL");
  BAD_ADD(scene, ball, &good, NULL, NUL, "`id`", "NULL");
  bad = good;
  bad.position[0] = INFINITY;
  BAD_ADD(scene, ball, &bad, &id, POSE, "`pose->position[0]`", "inf");
  bad = good;
  bad.quaternion[0] = 0.0;
  BAD_ADD(scene, ball, &bad, &id, POSE, "`pose->quaternion`", "zero");
#undef BAD_ADD

  CHECK(dcol_scene_add(scene, ball, &good, &id) == DCOL_OK && id == 0);
  CHECK(dcol_scene_add(scene, ball, &near_pose, &id) == DCOL_OK && id == 1);
  dcol_shape_free(ball); /* the scene has its copies */

  /* dcol_scene_set_pose: the scene unchanged on error. */
  bad = good;
  bad.quaternion[3] = NAN;
  st = dcol_scene_set_pose(scene, 0, &bad);
  expect_error(__LINE__, "dcol_scene_set_pose", st, POSE, 1, "`pose->quaternion[3]`", "NaN");
  st = dcol_scene_set_pose(scene, 2, &good);
  expect_error(__LINE__, "dcol_scene_set_pose", st, OPT, 1, "`id` = 2:", "not a body");
  st = dcol_scene_set_pose(scene, (size_t)-1, &good);
  expect_error(__LINE__, "dcol_scene_set_pose", st, OPT, 1, "`id`", "not a body");
  st = dcol_scene_set_pose(NULL, 0, &good);
  expect_error(__LINE__, "dcol_scene_set_pose", st, NUL, 1, "`scene`", "NULL");
  st = dcol_scene_set_pose(scene, 0, NULL);
  expect_error(__LINE__, "dcol_scene_set_pose", st, NUL, 1, "`pose`", "NULL");

  /* dcol_scene_size. */
  st = dcol_scene_size(NULL, &n);
  expect_error(__LINE__, "dcol_scene_size", st, NUL, 1, "`scene`", "NULL");
  st = dcol_scene_size(scene, NULL);
  expect_error(__LINE__, "dcol_scene_size", st, NUL, 1, "`size`", "NULL");
  CHECK(dcol_scene_size(scene, &n) == DCOL_OK && n == 2);

  /* dcol_scene_pairs_within: the two balls overlap (alpha = 0.25), so one pair qualifies. */
  CHECK(dcol_scene_pairs_within(scene, 1.0, NULL, pairs, 4, &count, &stats) == DCOL_OK);
  CHECK(count == 1 && pairs[0].body1 == 0 && pairs[0].body2 == 1);
  CHECK(near(pairs[0].proximity.alpha, 0.25, 1e-9) && pairs[0].status == DCOL_OK);
  CHECK(stats.pairs_total == 1 && stats.reported == 1);
  /* stats may be NULL. */
  CHECK(dcol_scene_pairs_within(scene, 1.0, &o, pairs, 4, &count, NULL) == DCOL_OK && count == 1);

#define BAD_PW(sc, th, opt, pr, cap, cnt, stp, want, n1, n2)                                    \
  do {                                                                                        \
    memset(pairs, SENTINEL, sizeof pairs);                                                    \
    memset(&count, SENTINEL, sizeof count);                                                   \
    memset(&stats, SENTINEL, sizeof stats);                                                   \
    st = dcol_scene_pairs_within(sc, th, opt, pr, cap, cnt, stp);                             \
    expect_error(__LINE__, "dcol_scene_pairs_within", st, want,                               \
                 untouched(pairs, sizeof pairs) && untouched(&count, sizeof count) &&         \
                     untouched(&stats, sizeof stats),                                         \
                 n1, n2);                                                                     \
  } while (0)
  BAD_PW(NULL, 1.0, NULL, pairs, 4, &count, &stats, NUL, "`scene`", "NULL");
  BAD_PW(scene, 1.0, NULL, NULL, 4, &count, &stats, NUL, "`pairs`", "NULL");
  BAD_PW(scene, 1.0, NULL, pairs, 4, NULL, &stats, NUL, "`count`", "NULL");
  BAD_PW(scene, 0.0, NULL, pairs, 4, &count, &stats, OPT, "`threshold`", "= 0:");
  BAD_PW(scene, -1.0, NULL, pairs, 4, &count, &stats, OPT, "`threshold`", "= -1:");
  BAD_PW(scene, NAN, NULL, pairs, 4, &count, &stats, OPT, "`threshold`", "NaN");
  BAD_PW(scene, INFINITY, NULL, pairs, 4, &count, &stats, OPT, "`threshold`", "inf");
  o.tolerance = -1.0;
  BAD_PW(scene, 1.0, &o, pairs, 4, &count, &stats, OPT, "`options->tolerance`", "= -1:");
  o = dcol_options_default();
#undef BAD_PW

  /* Too small a buffer: DCOL_ERROR_INVALID_OPTIONS naming `capacity`, *count = the number
   * needed, nothing else written. Also with pairs == NULL and capacity 0 (a size query). */
  memset(pairs, SENTINEL, sizeof pairs);
  memset(&count, SENTINEL, sizeof count);
  memset(&stats, SENTINEL, sizeof stats);
  st = dcol_scene_pairs_within(scene, 1.0, NULL, NULL, 0, &count, &stats);
  expect_error(__LINE__, "dcol_scene_pairs_within", st, OPT,
               untouched(pairs, sizeof pairs) && untouched(&stats, sizeof stats), "`capacity` = 0",
               "`*count` holds the number needed");
  CHECK(count == 1);
  /* Nothing qualifies at a small threshold: capacity 0 is then enough. */
  CHECK(dcol_scene_pairs_within(scene, 0.1, NULL, NULL, 0, &count, NULL) == DCOL_OK && count == 0);
  {
    /* Three overlapping balls, three pairs, room for two. */
    dcol_shape *b2 = NULL;
    dcol_pose third = pose_at(0.25, 0.3, 0);
    CHECK(dcol_shape_new_sphere(0.5, &b2) == DCOL_OK);
    CHECK(dcol_scene_add(scene, b2, &third, &id) == DCOL_OK && id == 2);
    dcol_shape_free(b2);
    memset(pairs, SENTINEL, sizeof pairs);
    st = dcol_scene_pairs_within(scene, 1.0, NULL, pairs, 2, &count, &stats);
    expect_error(__LINE__, "dcol_scene_pairs_within", st, OPT, untouched(pairs, sizeof pairs),
                 "`capacity` = 2", "3 pairs");
    CHECK(count == 3);
    CHECK(dcol_scene_pairs_within(scene, 1.0, NULL, pairs, 3, &count, NULL) == DCOL_OK &&
          count == 3);
    CHECK(pairs[0].body1 == 0 && pairs[0].body2 == 1 && pairs[1].body1 == 0 &&
          pairs[1].body2 == 2 && pairs[2].body1 == 1 && pairs[2].body2 == 2);
  }

  /* A pair whose solve hits the iteration limit is reported with its status; the call is OK. */
  {
    dcol_scene *s2 = NULL;
    dcol_shape *cone = NULL, *cap = NULL;
    dcol_pose pc = pose_at(0.3, 0.1, -0.05);
    size_t k;
    CHECK(dcol_scene_new(&s2) == DCOL_OK);
    CHECK(dcol_shape_new_cone(1.0, 0.4, &cone) == DCOL_OK);
    CHECK(dcol_shape_new_capsule(0.5, 1.0, &cap) == DCOL_OK);
    CHECK(dcol_scene_add(s2, cone, &good, &id) == DCOL_OK);
    CHECK(dcol_scene_add(s2, cap, &pc, &id) == DCOL_OK);
    o.max_iterations = 1;
    o.method = DCOL_METHOD_INTERIOR_POINT; /* The iteration limit is the interior-point solver's: ask for that solver. */
    st = dcol_scene_pairs_within(s2, 1.0, &o, pairs, 4, &count, &stats);
    CHECK_MSG(st == DCOL_OK, "%s", dcol_last_error_message());
    for (k = 0; k < count; k++) {
      dcol_proximity_result r;
      dcol_status single = dcol_proximity(cone, &good, cap, &pc, &o, &r);
      CHECK(pairs[k].status == single);
      CHECK(pairs[k].proximity.iterations == 1);
    }
    CHECK_MSG(count == 1 && pairs[0].status == DCOL_ERROR_NOT_CONVERGED,
              "count %u, status %d", (unsigned)count, count ? (int)pairs[0].status : -1);
    o = dcol_options_default();
    dcol_shape_free(cone);
    dcol_shape_free(cap);
    dcol_scene_free(s2);
  }

  dcol_scene_free(scene);
}

/* The kind of derivatives in the result, and the smoothing option: the central-path point at a
 * barrier parameter, above the exact alpha* by at most nu * mu relative. */
static void test_smoothing(void) {
  dcol_shape *big = NULL, *small = NULL, *ball = NULL;
  dcol_pose p1 = pose_at(0.0, 0.0, 0.0);
  dcol_pose face = pose_at(2.0, 0.3, 0.1); /* face against face: x* not unique */
  dcol_pose round = pose_at(3.0, 0.2, 0.1);
  dcol_options o = dcol_options_default();
  dcol_proximity_result r, rs;
  double g[14], j[56];
  dcol_status st;
  CHECK(o.smoothing == 0.0);
  CHECK(dcol_shape_new_box(1.0, 1.0, 1.0, &big) == DCOL_OK);
  CHECK(dcol_shape_new_box(0.5, 0.5, 0.5, &small) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &ball) == DCOL_OK);
  CHECK(dcol_proximity(big, &p1, ball, &round, &o, &r) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_NONE);
  CHECK(dcol_jacobian(big, &p1, ball, &round, &o, &r, j) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_EXACT);
  CHECK(dcol_jacobian(big, &p1, small, &face, &o, &r, j) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_SMOOTHED);
  CHECK(fabs(r.alpha - 4.0 / 3.0) < 1e-9);
  CHECK(dcol_gradient(big, &p1, ball, &p1, &o, &r, g) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_SUBGRADIENT);
  o.smoothing = 1e-3;
  CHECK(dcol_gradient(big, &p1, small, &face, &o, &rs, g) == DCOL_OK);
  CHECK(rs.derivatives == DCOL_DERIVATIVES_SMOOTHED);
  CHECK(rs.solver == DCOL_SOLVER_INTERIOR_POINT);
  /* Two boxes: 12 orthant rows. */
  CHECK_MSG(rs.alpha > 4.0 / 3.0 && rs.alpha <= 4.0 / 3.0 * (1.0 + 12.0 * 1e-3), "%.17g", rs.alpha);
  CHECK(fabs(g[7] - 2.0 / 3.0) < 1e-2);
  o.smoothing = -1.0;
  st = dcol_proximity(big, &p1, small, &face, &o, &rs);
  CHECK_MSG(st == DCOL_ERROR_INVALID_OPTIONS, "status %d", (int)st);
  CHECK(contains(dcol_last_error_message(), "smoothing"));
  dcol_shape_free(big);
  dcol_shape_free(small);
  dcol_shape_free(ball);
}

/* dcol_signed_distance: separated pairs give the distance, overlapping ones minus the depth,
 * with the witness identity closest2 - closest1 = distance * normal; bad input is refused. */
static void test_signed_distance(void) {
  dcol_shape *a = NULL, *b = NULL, *cube = NULL;
  dcol_pose p1 = pose_at(0.0, 0.0, 0.0);
  dcol_signed_distance_result r;
  dcol_distance_result d;
  dcol_status st;
  int k;
  CHECK(dcol_shape_new_sphere(1.0, &a) == DCOL_OK);
  CHECK(dcol_shape_new_sphere(0.5, &b) == DCOL_OK);
  CHECK(dcol_shape_new_box(1.0, 1.0, 1.0, &cube) == DCOL_OK);
  {
    /* Spheres 1.2 apart: overlap by 0.3 along (0.6, 0, 0.8). */
    dcol_pose p2 = pose_at(0.72, 0.0, 0.96);
    CHECK(dcol_signed_distance(a, &p1, b, &p2, NULL, &r) == DCOL_OK);
    CHECK_MSG(near(r.distance, -0.3, 1e-12), "%.17g", r.distance);
    CHECK(near(r.normal[0], 0.6, 1e-12) && near(r.normal[1], 0.0, 1e-12) &&
          near(r.normal[2], 0.8, 1e-12));
    for (k = 0; k < 3; k++)
      CHECK(near(r.closest2[k] - r.closest1[k], r.distance * r.normal[k], 1e-12));
    {
      /* d sd / d r2 = normal = -d sd / d r1; spheres do not depend on their attitudes. */
      double g[14];
      CHECK(dcol_signed_distance_gradient(a, &p1, b, &p2, NULL, &r, g) == DCOL_OK);
      for (k = 0; k < 3; k++)
        CHECK(near(g[7 + k], r.normal[k], 1e-12) && near(g[k], -r.normal[k], 1e-12));
      for (k = 0; k < 4; k++) CHECK(g[3 + k] == 0.0 && g[10 + k] == 0.0);
    }
  }
  {
    /* A sphere sunk 0.2 into the cube's top face, away from its edges. */
    dcol_pose p2 = pose_at(0.3, -0.2, 1.3);
    CHECK(dcol_signed_distance(cube, &p1, b, &p2, NULL, &r) == DCOL_OK);
    CHECK_MSG(near(r.distance, -0.2, 1e-10), "%.17g", r.distance);
    CHECK(near(r.normal[2], 1.0, 1e-10));
  }
  {
    /* Separated: the distance query's answer. */
    dcol_pose p2 = pose_at(0.0, 3.0, 0.0);
    CHECK(dcol_signed_distance(cube, &p1, b, &p2, NULL, &r) == DCOL_OK);
    CHECK(dcol_distance(cube, &p1, b, &p2, NULL, &d) == DCOL_OK);
    CHECK_MSG(near(r.distance, 1.5, 1e-12) && near(d.distance, r.distance, 1e-12), "%.17g",
              r.distance);
  }
  {
    dcol_pose bad = pose_at(0.0, NAN, 0.0);
    memset(&r, SENTINEL, sizeof r);
    st = dcol_signed_distance(cube, &p1, b, &bad, NULL, &r);
    CHECK_MSG(st == DCOL_ERROR_INVALID_POSE, "status %d", (int)st);
    CHECK(contains(dcol_last_error_message(), "dcol_signed_distance"));
    st = dcol_signed_distance(NULL, &p1, b, &p1, NULL, &r);
    CHECK_MSG(st == DCOL_ERROR_NULL_POINTER, "status %d", (int)st);
    st = dcol_signed_distance(cube, &p1, b, &p1, NULL, NULL);
    CHECK_MSG(st == DCOL_ERROR_NULL_POINTER, "status %d", (int)st);
  }
  dcol_shape_free(a);
  dcol_shape_free(b);
  dcol_shape_free(cube);
}

int main(void) {
  test_alpha_below_values();
  test_alpha_below_errors();
  test_distance_gradient();
  test_derivatives();
  test_mrp();
  test_batch();
  test_scene_values();
  test_scene_errors();
  test_smoothing();
  test_signed_distance();
  return check_summary("test_extensions");
}
