/* C99 tests of the shape parameters and shape gradients (dcol_shape_parameter_count,
 * dcol_shape_parameters, dcol_shape_gradient, dcol_distance_shape_gradient,
 * dcol_signed_distance_shape_gradient): the count and order of every kind's parameters, closed
 * forms, central differences through the C constructors, the kinds reported, NULL buffers,
 * capacity and overlap errors, and outputs left untouched by a failing call. */
#include "dcol.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"

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

static dcol_pose pose_q(double x, double y, double z, double qw, double qx, double qy, double qz) {
  dcol_pose p;
  p.position[0] = x;
  p.position[1] = y;
  p.position[2] = z;
  p.quaternion[0] = qw;
  p.quaternion[1] = qx;
  p.quaternion[2] = qy;
  p.quaternion[3] = qz;
  return p;
}

static dcol_pose pose_at(double x, double y, double z) { return pose_q(x, y, z, 1, 0, 0, 0); }

static int near(double a, double b, double tol) { return fabs(a - b) <= tol; }

static const double BOX_A[18] = {1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};

/* ------------------------------------------------------------------------------------------ */

static void test_parameters(void) {
  dcol_shape *s = NULL;
  double out[40];
  double P[9] = {2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0};
  double b[6] = {0.5, 0.6, 0.7, 0.5, 0.6, 0.7};
  double C[6] = {1, 0, 0, 1, -1, -1};
  double d[3] = {1.0, 1.0, 0.5};
  double pts[27];
  int i;

  CHECK(dcol_shape_parameter_count(NULL) == 0);

  CHECK(dcol_shape_new_sphere(0.5, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 1);
  CHECK(dcol_shape_parameters(s, out, 1) == DCOL_OK && out[0] == 0.5);
  /* Capacity below the count: an error naming the capacity, nothing written. */
  memset(out, SENTINEL, sizeof out);
  CHECK(dcol_shape_parameters(s, out, 0) == DCOL_ERROR_INVALID_OPTIONS);
  CHECK(contains(dcol_last_error_message(), "dcol_shape_parameters") &&
        contains(dcol_last_error_message(), "capacity"));
  CHECK(untouched(out, sizeof out));
  CHECK(dcol_shape_parameters(s, NULL, 1) == DCOL_ERROR_NULL_POINTER);
  CHECK(contains(dcol_last_error_message(), "`out`"));
  CHECK(dcol_shape_parameters(NULL, out, 1) == DCOL_ERROR_NULL_POINTER);
  CHECK(contains(dcol_last_error_message(), "`shape`"));
  dcol_shape_free(s);

  CHECK(dcol_shape_new_ellipsoid(P, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 9);
  CHECK(dcol_shape_parameters(s, out, 40) == DCOL_OK);
  for (i = 0; i < 9; i++) CHECK(out[i] == P[i]);
  dcol_shape_free(s);

  /* A box: its half extents, not its six planes. */
  CHECK(dcol_shape_new_box(0.5, 0.6, 0.7, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 3);
  CHECK(dcol_shape_parameters(s, out, 3) == DCOL_OK);
  CHECK(out[0] == 0.5 && out[1] == 0.6 && out[2] == 0.7);
  CHECK(dcol_shape_parameters(s, out, 2) == DCOL_ERROR_INVALID_OPTIONS);
  dcol_shape_free(s);

  /* The same box as a polytope: A row-major, then b. */
  CHECK(dcol_shape_new_polytope(BOX_A, b, 6, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 24);
  CHECK(dcol_shape_parameters(s, out, 24) == DCOL_OK);
  for (i = 0; i < 18; i++) CHECK(out[i] == BOX_A[i]);
  for (i = 0; i < 6; i++) CHECK(out[18 + i] == b[i]);
  dcol_shape_free(s);

  CHECK(dcol_shape_new_capsule(0.2, 1.5, &s) == DCOL_OK);
  CHECK(dcol_shape_parameters(s, out, 2) == DCOL_OK && out[0] == 0.2 && out[1] == 1.5);
  dcol_shape_free(s);
  CHECK(dcol_shape_new_cylinder(0.3, 1.0, &s) == DCOL_OK);
  CHECK(dcol_shape_parameters(s, out, 2) == DCOL_OK && out[0] == 0.3 && out[1] == 1.0);
  dcol_shape_free(s);
  CHECK(dcol_shape_new_cone(1.0, 0.4, &s) == DCOL_OK);
  CHECK(dcol_shape_parameters(s, out, 2) == DCOL_OK && out[0] == 1.0 && out[1] == 0.4);
  dcol_shape_free(s);
  CHECK(dcol_shape_new_halfspace(0.7, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 1);
  CHECK(dcol_shape_parameters(s, out, 1) == DCOL_OK && out[0] == 0.7);
  dcol_shape_free(s);

  /* A padded polygon: C row-major, d, radius. */
  CHECK(dcol_shape_new_polygon(C, d, 3, 0.1, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 10);
  CHECK(dcol_shape_parameters(s, out, 10) == DCOL_OK);
  for (i = 0; i < 6; i++) CHECK(out[i] == C[i]);
  CHECK(out[6] == 1.0 && out[7] == 1.0 && out[8] == 0.5 && out[9] == 0.1);
  dcol_shape_free(s);

  /* A hull: the points as given (an interior one too), then the radius. */
  for (i = 0; i < 8; i++) {
    pts[3 * i] = (i & 1) ? 0.5 : -0.5;
    pts[3 * i + 1] = (i & 2) ? 0.5 : -0.5;
    pts[3 * i + 2] = (i & 4) ? 0.5 : -0.5;
  }
  pts[24] = 0.0;
  pts[25] = 0.1;
  pts[26] = 0.0;
  CHECK(dcol_shape_new_convex_hull(pts, 9, 0.05, &s) == DCOL_OK);
  CHECK(dcol_shape_parameter_count(s) == 28);
  CHECK(dcol_shape_parameters(s, out, 28) == DCOL_OK);
  for (i = 0; i < 27; i++) CHECK(out[i] == pts[i]);
  CHECK(out[27] == 0.05);
  dcol_shape_free(s);
}

/* α* of a cone (height, half angle) against a capsule (radius, length) at fixed poses. */
static double cone_capsule_alpha(const double *cone, const double *capsule) {
  dcol_shape *a = NULL, *b = NULL;
  dcol_proximity_result r;
  dcol_pose p1 = pose_q(0.1, -0.2, 0.3, 0.9, 0.2, -0.3, 0.1);
  dcol_pose p2 = pose_q(1.3, 0.8, -0.4, 0.5, -0.4, 0.6, 0.3);
  dcol_options o = dcol_options_default();
  o.tolerance = 1e-12;
  CHECK(dcol_shape_new_cone(cone[0], cone[1], &a) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(capsule[0], capsule[1], &b) == DCOL_OK);
  CHECK(dcol_proximity(a, &p1, b, &p2, &o, &r) == DCOL_OK);
  dcol_shape_free(a);
  dcol_shape_free(b);
  return r.alpha;
}

static void test_shape_gradient(void) {
  dcol_shape *ball = NULL, *box = NULL, *cone = NULL, *capsule = NULL, *floor_ = NULL, *other = NULL;
  dcol_proximity_result r, r2;
  dcol_distance_result dr;
  dcol_signed_distance_result sr;
  dcol_pose p1 = pose_at(0, 0, 0), p2 = pose_at(2.4, 0.1, -0.05), bad = pose_at(0, 0, 0);
  dcol_options smooth = dcol_options_default();
  double g1[8], g2[8], buf[8];
  double cone_p[2] = {1.2, 0.4}, capsule_p[2] = {0.3, 0.9};
  double h = 1e-6;
  int k;

  CHECK(dcol_shape_new_sphere(0.7, &ball) == DCOL_OK);
  CHECK(dcol_shape_new_box(0.5, 0.8, 0.3, &box) == DCOL_OK);

  /* A sphere against a box's face: alpha = d / (R + h_x), d/dR = d/dh_x = -alpha / (R + h_x). */
  memset(g2, SENTINEL, sizeof g2);
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, NULL, &r, g1, g2) == DCOL_OK);
  CHECK(near(r.alpha, 2.0, 1e-12));
  CHECK(r.derivatives == DCOL_DERIVATIVES_EXACT);
  CHECK(near(g1[0], -2.0 / 1.2, 1e-12) && near(g2[0], -2.0 / 1.2, 1e-12));
  CHECK(fabs(g2[1]) < 1e-14 && fabs(g2[2]) < 1e-14);
  CHECK(untouched(g2 + 3, sizeof g2 - 3 * sizeof(double))); /* only the 3 parameters */
  /* Either buffer may be NULL, and the other is the same. */
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, NULL, &r2, NULL, buf) == DCOL_OK);
  CHECK(memcmp(buf, g2, 3 * sizeof(double)) == 0 && r2.alpha == r.alpha);
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, NULL, &r2, NULL, NULL) == DCOL_OK);

  /* Bad calls: the status, a message naming the argument, nothing written. */
  memset(&r, SENTINEL, sizeof r);
  memset(g1, SENTINEL, sizeof g1);
  memset(g2, SENTINEL, sizeof g2);
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, NULL, NULL, g1, g2) == DCOL_ERROR_NULL_POINTER);
  CHECK(contains(dcol_last_error_message(), "`result`"));
  CHECK(dcol_shape_gradient(NULL, &p1, box, &p2, NULL, &r, g1, g2) == DCOL_ERROR_NULL_POINTER);
  CHECK(dcol_shape_gradient(ball, &p1, box, NULL, NULL, &r, g1, g2) == DCOL_ERROR_NULL_POINTER);
  bad.quaternion[0] = 0.0;
  CHECK(dcol_shape_gradient(ball, &p1, box, &bad, NULL, &r, g1, g2) == DCOL_ERROR_INVALID_POSE);
  CHECK(contains(dcol_last_error_message(), "pose2"));
  /* The two buffers must not share memory. */
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, NULL, &r, g1, g1) == DCOL_ERROR_INVALID_OPTIONS);
  CHECK(contains(dcol_last_error_message(), "overlaps"));
  CHECK(untouched(&r, sizeof r) && untouched(g1, sizeof g1) && untouched(g2, sizeof g2));

  /* Central differences through the C constructors: a cone and a capsule at general poses. */
  CHECK(dcol_shape_new_cone(cone_p[0], cone_p[1], &cone) == DCOL_OK);
  CHECK(dcol_shape_new_capsule(capsule_p[0], capsule_p[1], &capsule) == DCOL_OK);
  {
    dcol_pose c1 = pose_q(0.1, -0.2, 0.3, 0.9, 0.2, -0.3, 0.1);
    dcol_pose c2 = pose_q(1.3, 0.8, -0.4, 0.5, -0.4, 0.6, 0.3);
    CHECK(dcol_shape_gradient(cone, &c1, capsule, &c2, NULL, &r, g1, g2) == DCOL_OK);
    CHECK(r.derivatives == DCOL_DERIVATIVES_EXACT);
  }
  for (k = 0; k < 2; k++) {
    double up[2], down[2], fd;
    up[0] = cone_p[0];
    up[1] = cone_p[1];
    down[0] = cone_p[0];
    down[1] = cone_p[1];
    up[k] += h;
    down[k] -= h;
    fd = (cone_capsule_alpha(up, capsule_p) - cone_capsule_alpha(down, capsule_p)) / (2 * h);
    CHECK_MSG(near(g1[k], fd, 1e-6 * (1 + fabs(fd))), "cone %d: %.12g vs %.12g", k, g1[k], fd);
    up[0] = capsule_p[0];
    up[1] = capsule_p[1];
    down[0] = capsule_p[0];
    down[1] = capsule_p[1];
    up[k] += h;
    down[k] -= h;
    fd = (cone_capsule_alpha(cone_p, up) - cone_capsule_alpha(cone_p, down)) / (2 * h);
    CHECK_MSG(near(g2[k], fd, 1e-6 * (1 + fabs(fd))), "capsule %d: %.12g vs %.12g", k, g2[k], fd);
  }

  /* Smoothing: the smoothed alpha's derivatives, labelled so. */
  smooth.smoothing = 1e-3;
  CHECK(dcol_shape_gradient(ball, &p1, box, &p2, &smooth, &r, g1, g2) == DCOL_OK);
  CHECK(r.derivatives == DCOL_DERIVATIVES_SMOOTHED);
  CHECK(g1[0] < 0.0 && g2[0] < 0.0 && r.alpha > 2.0);

  /* Coincident origins: zeros, a subgradient. */
  memset(g1, SENTINEL, sizeof g1);
  CHECK(dcol_shape_gradient(ball, &p1, box, &p1, NULL, &r, g1, g2) == DCOL_OK);
  CHECK(r.alpha == 0.0 && r.derivatives == DCOL_DERIVATIVES_SUBGRADIENT && g1[0] == 0.0);

  /* The distance: d = 2.4 - 0.7 - 0.5 along x; overlapping, zeros. */
  CHECK(dcol_distance_shape_gradient(ball, &p1, box, &p2, NULL, &dr, g1, g2) == DCOL_OK);
  CHECK(near(dr.distance, 1.2, 1e-9) && near(g1[0], -1.0, 1e-9) && near(g2[0], -1.0, 1e-9));
  CHECK(fabs(g2[1]) < 1e-9 && fabs(g2[2]) < 1e-9);
  {
    dcol_pose close = pose_at(1.0, 0.0, 0.0);
    CHECK(dcol_distance_shape_gradient(ball, &p1, box, &close, NULL, &dr, g1, g2) == DCOL_OK);
    CHECK(dr.distance == 0.0 && g1[0] == 0.0 && g2[0] == 0.0 && g2[1] == 0.0);
    /* The signed distance of the overlap: 1 - 0.7 - 0.5 = -0.2, d/dR = -1. */
    CHECK(dcol_signed_distance_shape_gradient(ball, &p1, box, &close, NULL, &sr, g1, NULL) ==
          DCOL_OK);
    CHECK(near(sr.distance, -0.2, 1e-9) && near(g1[0], -1.0, 1e-9));
  }
  memset(g1, SENTINEL, sizeof g1);
  CHECK(dcol_distance_shape_gradient(ball, &p1, box, &p2, NULL, NULL, g1, NULL) ==
        DCOL_ERROR_NULL_POINTER);
  CHECK(dcol_signed_distance_shape_gradient(ball, &p1, box, NULL, NULL, &sr, g1, NULL) ==
        DCOL_ERROR_NULL_POINTER);
  CHECK(untouched(g1, sizeof g1));

  /* A half-space: alpha = g / (depth + R); two half-spaces are an error, nothing written. */
  CHECK(dcol_shape_new_halfspace(0.5, &floor_) == DCOL_OK);
  CHECK(dcol_shape_new_halfspace(1.0, &other) == DCOL_OK);
  {
    dcol_pose under = pose_at(0, 0, -0.5), above = pose_at(0.3, 0, 2.0);
    CHECK(dcol_shape_gradient(floor_, &under, ball, &above, NULL, &r, g1, g2) == DCOL_OK);
    CHECK(near(r.alpha, 2.5 / 1.2, 1e-12) && near(g1[0], -r.alpha / 1.2, 1e-12) &&
          near(g2[0], -r.alpha / 1.2, 1e-12));
    memset(g1, SENTINEL, sizeof g1);
    CHECK(dcol_shape_gradient(floor_, &under, other, &above, NULL, &r, g1, NULL) ==
          DCOL_ERROR_INVALID_SHAPE);
    CHECK(untouched(g1, sizeof g1));
  }

  dcol_shape_free(ball);
  dcol_shape_free(box);
  dcol_shape_free(cone);
  dcol_shape_free(capsule);
  dcol_shape_free(floor_);
  dcol_shape_free(other);
}

int main(void) {
  test_parameters();
  test_shape_gradient();
  return check_summary("test_shape_gradient");
}
