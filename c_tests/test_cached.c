/* The warm-start cache (dcol_cache) and the _cached queries through the C ABI: on a
 * trajectory of two polytopes (a box and a 24-point hull moving 1 mm and 1 degree per step)
 * each cached query gives the plain query's answer (alpha* within 1e-12 relative, distances
 * within 1e-12 of the length scale, derivatives within 1e-9 of their largest entry) and most
 * answers come from the cache (DCOL_SOLVER_POLISH where the cold ray cast answers); a cache
 * holding garbage gives the cold answer; a NULL cache is DCOL_ERROR_NULL_POINTER and writes
 * nothing. dcol_intersect_cached gives dcol_intersect's decision on every step (and alpha* < 1
 * of dcol_proximity wherever alpha* is more than 1e-9 from 1). */
#include <math.h>
#include <string.h>

#include "check.h"
#include "dcol.h"

static double max_abs_diff(const double *a, const double *b, int n) {
  double worst = 0.0, scale = 1e-300;
  int i;
  for (i = 0; i < n; ++i) {
    double d = fabs(a[i] - b[i]);
    if (d > worst) worst = d;
    if (fabs(b[i]) > scale) scale = fabs(b[i]);
  }
  return worst / scale;
}

static void turn(double q[4], const double axis[3], double deg) {
  /* q <- w q with w the turn by `deg` about the unit `axis`. */
  const double h = deg * 3.14159265358979323846 / 360.0;
  const double w[4] = {cos(h), axis[0] * sin(h), axis[1] * sin(h), axis[2] * sin(h)};
  const double p[4] = {q[0], q[1], q[2], q[3]};
  q[0] = w[0] * p[0] - w[1] * p[1] - w[2] * p[2] - w[3] * p[3];
  q[1] = w[0] * p[1] + w[1] * p[0] + w[2] * p[3] - w[3] * p[2];
  q[2] = w[0] * p[2] - w[1] * p[3] + w[2] * p[0] + w[3] * p[1];
  q[3] = w[0] * p[3] + w[1] * p[2] - w[2] * p[1] + w[3] * p[0];
}

int main(void) {
  dcol_shape *box = NULL, *hull = NULL;
  double pts[24 * 3];
  unsigned long long seed = 0x2545f4914f6cdd1dULL;
  int i, k, warm = 0, steps = 0;
  dcol_pose p1, p2;
  dcol_cache cp = DCOL_CACHE_INIT, cg = DCOL_CACHE_INIT, cj = DCOL_CACHE_INIT;
  dcol_cache cd = DCOL_CACHE_INIT, cx = DCOL_CACHE_INIT, cxg = DCOL_CACHE_INIT;
  dcol_cache cs = DCOL_CACHE_INIT, cc = DCOL_CACHE_INIT, ci = DCOL_CACHE_INIT;
  int overlapping = 0;
  const double a1[3] = {0.0, 0.6, 0.8}, a2[3] = {0.8, 0.0, 0.6};
  const double ell = 0.6;
  for (i = 0; i < 24 * 3; ++i) {
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    pts[i] = ((double)(seed >> 11) / 9007199254740992.0 - 0.5) * (i % 3 == 0 ? 1.0 : 0.8);
  }
  CHECK(dcol_shape_new_box(0.5, 0.35, 0.25, &box) == DCOL_OK);
  CHECK(dcol_shape_new_convex_hull(pts, 24, 0.0, &hull) == DCOL_OK);
  memset(&p1, 0, sizeof p1);
  memset(&p2, 0, sizeof p2);
  p1.quaternion[0] = 1.0;
  p2.quaternion[0] = 0.9;
  p2.quaternion[1] = 0.3;
  p2.quaternion[3] = 0.2;
  p2.position[0] = 0.95;
  p2.position[1] = 0.2;
  for (k = 0; k < 400; ++k) {
    dcol_proximity_result r0, r1;
    dcol_distance_result d0, d1;
    double g0[14], g1[14], j0[56], j1[56];
    dcol_derivatives_result v0, v1;
    dcol_proximity_result rg0, rg1, rj0, rj1;
    dcol_distance_result dg0, dg1;
    p2.position[0] += (k % 200 < 100 ? 1e-3 : -1e-3);
    turn(p1.quaternion, a1, 1.0);
    turn(p2.quaternion, a2, 1.0);
    CHECK(dcol_proximity(box, &p1, hull, &p2, NULL, &r0) == DCOL_OK);
    CHECK(dcol_proximity_cached(box, &p1, hull, &p2, NULL, &cp, &r1) == DCOL_OK);
    CHECK_MSG(fabs(r1.alpha - r0.alpha) <= 1e-12 * r0.alpha, "step %d: %.17g vs %.17g", k,
              r1.alpha, r0.alpha);
    for (i = 0; i < 3; ++i) CHECK(fabs(r1.point[i] - r0.point[i]) <= 1e-11 * ell);
    warm += r1.solver == DCOL_SOLVER_POLISH && r0.solver != DCOL_SOLVER_POLISH;
    {
      int32_t x0 = -1, x1 = -1;
      CHECK(dcol_intersect(box, &p1, hull, &p2, NULL, &x0) == DCOL_OK);
      CHECK(dcol_intersect_cached(box, &p1, hull, &p2, NULL, &ci, &x1) == DCOL_OK);
      CHECK_MSG(x1 == x0, "step %d: intersect %d cached, %d cold", k, (int)x1, (int)x0);
      if (fabs(r0.alpha - 1.0) > 1e-9) CHECK(x1 == (r0.alpha < 1.0));
      overlapping += x1;
    }
    steps += 1;
    CHECK(dcol_gradient(box, &p1, hull, &p2, NULL, &rg0, g0) == DCOL_OK);
    CHECK(dcol_gradient_cached(box, &p1, hull, &p2, NULL, &cg, &rg1, g1) == DCOL_OK);
    CHECK_MSG(max_abs_diff(g1, g0, 14) <= 1e-9, "step %d gradient", k);
    CHECK(dcol_jacobian(box, &p1, hull, &p2, NULL, &rj0, j0) == DCOL_OK);
    CHECK(dcol_jacobian_cached(box, &p1, hull, &p2, NULL, &cj, &rj1, j1) == DCOL_OK);
    CHECK_MSG(max_abs_diff(j1, j0, 56) <= 1e-9, "step %d jacobian", k);
    CHECK(dcol_derivatives(box, &p1, hull, &p2, NULL, &v0) == DCOL_OK);
    CHECK(dcol_derivatives_cached(box, &p1, hull, &p2, NULL, &cd, &v1) == DCOL_OK);
    CHECK(max_abs_diff(&v1.contact_jacobian1[0][0], &v0.contact_jacobian1[0][0], 42) <= 1e-9);
    CHECK(dcol_distance(box, &p1, hull, &p2, NULL, &d0) == DCOL_OK);
    CHECK(dcol_distance_cached(box, &p1, hull, &p2, NULL, &cx, &d1) == DCOL_OK);
    CHECK_MSG(fabs(d1.distance - d0.distance) <= 1e-12 * ell, "step %d distance", k);
    CHECK(dcol_distance_gradient(box, &p1, hull, &p2, NULL, &dg0, g0) == DCOL_OK);
    CHECK(dcol_distance_gradient_cached(box, &p1, hull, &p2, NULL, &cxg, &dg1, g1) == DCOL_OK);
    CHECK(fabs(dg1.distance - dg0.distance) <= 1e-12 * ell);
    if (dg0.distance > 0.0) CHECK_MSG(max_abs_diff(g1, g0, 14) <= 1e-9, "step %d", k);
    {
      dcol_signed_distance_result s0, s1;
      CHECK(dcol_signed_distance(box, &p1, hull, &p2, NULL, &s0) == DCOL_OK);
      CHECK(dcol_signed_distance_cached(box, &p1, hull, &p2, NULL, &cs, &s1) == DCOL_OK);
      CHECK_MSG(fabs(s1.distance - s0.distance) <= 1e-12 * ell, "step %d signed distance", k);
    }
    {
      dcol_contact m0[8], m1[8];
      size_t n0 = 99, n1 = 99, c;
      CHECK(dcol_contacts(box, &p1, hull, &p2, 0.01, NULL, m0, 8, &n0) == DCOL_OK);
      CHECK(dcol_contacts_cached(box, &p1, hull, &p2, 0.01, NULL, &cc, m1, 8, &n1) == DCOL_OK);
      CHECK_MSG(n0 == n1, "step %d: %d contacts cached, %d cold", k, (int)n1, (int)n0);
      for (c = 0; c < n0 && c < n1; ++c) {
        CHECK(fabs(m1[c].depth - m0[c].depth) <= 1e-9 * ell);
        for (i = 0; i < 3; ++i) CHECK(fabs(m1[c].position[i] - m0[c].position[i]) <= 1e-9 * ell);
      }
    }
  }
  CHECK_MSG(2 * warm > steps, "%d of %d proximity answers warm", warm, steps);
  /* The trajectory crosses alpha* = 1: both decisions occur. */
  CHECK_MSG(overlapping > 0 && overlapping < steps, "%d of %d steps overlapping", overlapping,
            steps);

  /* Garbage in a cache: the cold answer. */
  {
    dcol_cache junk;
    dcol_proximity_result r0, r1;
    unsigned char *bytes = (unsigned char *)&junk;
    for (i = 0; i < (int)sizeof junk; ++i) bytes[i] = (unsigned char)(i * 37 + 11);
    CHECK(dcol_proximity(box, &p1, hull, &p2, NULL, &r0) == DCOL_OK);
    CHECK(dcol_proximity_cached(box, &p1, hull, &p2, NULL, &junk, &r1) == DCOL_OK);
    CHECK(fabs(r1.alpha - r0.alpha) <= 1e-12 * r0.alpha);
    {
      int32_t x0 = -1, x1 = -1;
      for (i = 0; i < (int)sizeof junk; ++i) bytes[i] = (unsigned char)(i * 53 + 7);
      CHECK(dcol_intersect(box, &p1, hull, &p2, NULL, &x0) == DCOL_OK);
      CHECK(dcol_intersect_cached(box, &p1, hull, &p2, NULL, &junk, &x1) == DCOL_OK);
      CHECK(x1 == x0);
    }
  }
  /* A NULL cache: an error naming it, nothing written. */
  {
    dcol_proximity_result r;
    memset(&r, 0, sizeof r);
    CHECK(dcol_proximity_cached(box, &p1, hull, &p2, NULL, NULL, &r) == DCOL_ERROR_NULL_POINTER);
    CHECK(strstr(dcol_last_error_message(), "cache") != NULL);
    CHECK(r.alpha == 0.0);
  }
  {
    int32_t x = 7;
    CHECK(dcol_intersect_cached(box, &p1, hull, &p2, NULL, NULL, &x) == DCOL_ERROR_NULL_POINTER);
    CHECK(strstr(dcol_last_error_message(), "cache") != NULL);
    CHECK(x == 7);
  }
  dcol_shape_free(box);
  dcol_shape_free(hull);
  return check_summary("test_cached");
}
