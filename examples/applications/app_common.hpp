// app_common.hpp: code shared by the application examples (examples/applications): owned shapes,
// dcol calls timed so that each example can report the share of its time spent inside dcol,
// small quaternion helpers, and the output of a CSV file.
#ifndef DCOL_APP_COMMON_HPP
#define DCOL_APP_COMMON_HPP

#include <dcol.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

namespace app {

// ---------------------------------------------------------------------------------------------
// Timing.

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Time spent inside dcol calls made through the wrappers below, and their number.
struct DcolClock {
  double seconds = 0.0;
  long calls = 0;
  long not_converged = 0;
};

inline DcolClock &dcol_clock() {
  static DcolClock clock;
  return clock;
}

/// Prints the summary every example ends with (iterations, wall time, share inside dcol).
inline void print_timing(const char *what, long iterations, double wall_seconds) {
  const DcolClock &c = dcol_clock();
  std::printf("%s: %ld iterations, wall time %.3f s, %ld dcol calls taking %.3f s (%.1f %% of the "
              "wall time), %ld calls did not converge\n",
              what, iterations, wall_seconds, c.calls, c.seconds,
              wall_seconds > 0.0 ? 100.0 * c.seconds / wall_seconds : 0.0, c.not_converged);
}

// ---------------------------------------------------------------------------------------------
// Shapes.

struct ShapeDeleter {
  void operator()(dcol_shape *s) const { dcol_shape_free(s); }
};
using Shape = std::unique_ptr<dcol_shape, ShapeDeleter>;

/// Throws std::runtime_error with dcol's last error message unless `status` is DCOL_OK.
inline void check(dcol_status status, const char *what) {
  if (status != DCOL_OK)
    throw std::runtime_error(std::string(what) + ": " + dcol_last_error_message());
}

inline Shape make_box(double a, double b, double c) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_box(a, b, c, &s), "box");
  return Shape(s);
}
inline Shape make_sphere(double r) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_sphere(r, &s), "sphere");
  return Shape(s);
}
inline Shape make_capsule(double r, double l) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_capsule(r, l, &s), "capsule");
  return Shape(s);
}
inline Shape make_cylinder(double r, double l) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_cylinder(r, l, &s), "cylinder");
  return Shape(s);
}
inline Shape make_cone(double h, double beta) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_cone(h, beta, &s), "cone");
  return Shape(s);
}
/// The ellipsoid with semi-axes (a, b, c) along the body axes.
inline Shape make_ellipsoid(double a, double b, double c) {
  const double P[9] = {1.0 / (a * a), 0, 0, 0, 1.0 / (b * b), 0, 0, 0, 1.0 / (c * c)};
  dcol_shape *s = nullptr;
  check(dcol_shape_new_ellipsoid(P, &s), "ellipsoid");
  return Shape(s);
}
/// The convex hull of n points (3n numbers, body frame), padded by `r`.
inline Shape make_hull(const double *points, std::size_t n, double r) {
  dcol_shape *s = nullptr;
  check(dcol_shape_new_convex_hull(points, n, r, &s), "convex hull");
  return Shape(s);
}
/// A padded rectangle: half-sides (a, b) in the body x-y plane, padded by `r`.
inline Shape make_padded_rect(double a, double b, double r) {
  const double C[8] = {1, 0, 0, 1, -1, 0, 0, -1};
  const double d[4] = {a, b, a, b};
  dcol_shape *s = nullptr;
  check(dcol_shape_new_polygon(C, d, 4, r, &s), "polygon");
  return Shape(s);
}

// ---------------------------------------------------------------------------------------------
// Timed queries. A solve that stops at the iteration limit still gives its last iterate (see
// dcol.h); it is counted and used, any other failure throws.

inline double proximity(const dcol_shape *s1, const dcol_pose &p1, const dcol_shape *s2,
                        const dcol_pose &p2) {
  dcol_proximity_result r;
  const Clock::time_point t0 = Clock::now();
  const dcol_status st = dcol_proximity(s1, &p1, s2, &p2, nullptr, &r);
  DcolClock &c = dcol_clock();
  c.seconds += seconds_since(t0);
  ++c.calls;
  if (st == DCOL_ERROR_NOT_CONVERGED) ++c.not_converged;
  else check(st, "dcol_proximity");
  return r.alpha;
}

/// alpha* and its gradient (14 numbers: r1, q1, r2, q2).
inline double gradient(const dcol_shape *s1, const dcol_pose &p1, const dcol_shape *s2,
                       const dcol_pose &p2, double grad[14]) {
  dcol_proximity_result r;
  const Clock::time_point t0 = Clock::now();
  const dcol_status st = dcol_gradient(s1, &p1, s2, &p2, nullptr, &r, grad);
  DcolClock &c = dcol_clock();
  c.seconds += seconds_since(t0);
  ++c.calls;
  if (st == DCOL_ERROR_NOT_CONVERGED) ++c.not_converged;
  else check(st, "dcol_gradient");
  return r.alpha;
}

/// alpha* and its derivatives with respect to both shapes' parameters (dcol_shape_gradient;
/// either buffer may be null).
inline double shape_gradient(const dcol_shape *s1, const dcol_pose &p1, const dcol_shape *s2,
                             const dcol_pose &p2, double *d_shape1, double *d_shape2) {
  dcol_proximity_result r;
  const Clock::time_point t0 = Clock::now();
  const dcol_status st = dcol_shape_gradient(s1, &p1, s2, &p2, nullptr, &r, d_shape1, d_shape2);
  DcolClock &c = dcol_clock();
  c.seconds += seconds_since(t0);
  ++c.calls;
  if (st == DCOL_ERROR_NOT_CONVERGED) ++c.not_converged;
  else check(st, "dcol_shape_gradient");
  return r.alpha;
}

/// alpha* and its gradient (12 numbers: r1, p1, r2, p2) with MRP attitudes.
inline double gradient_mrp(const dcol_shape *s1, const double r1[3], const double p1[3],
                           const dcol_shape *s2, const double r2[3], const double p2[3],
                           double grad[12]) {
  dcol_proximity_result r;
  const Clock::time_point t0 = Clock::now();
  const dcol_status st = dcol_gradient_mrp(s1, r1, p1, s2, r2, p2, nullptr, &r, grad);
  DcolClock &c = dcol_clock();
  c.seconds += seconds_since(t0);
  ++c.calls;
  if (st == DCOL_ERROR_NOT_CONVERGED) ++c.not_converged;
  else check(st, "dcol_gradient_mrp");
  return r.alpha;
}

// ---------------------------------------------------------------------------------------------
// Poses and quaternions ([w, x, y, z], world-from-body).

inline dcol_pose make_pose(double x, double y, double z, double qw = 1, double qx = 0,
                           double qy = 0, double qz = 0) {
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

/// A planar pose: (x, y) at height z, rotated by `yaw` about the world z axis.
inline dcol_pose planar_pose(double x, double y, double yaw, double z = 0.0) {
  return make_pose(x, y, z, std::cos(0.5 * yaw), 0, 0, std::sin(0.5 * yaw));
}

/// The quaternion of modified Rodrigues parameters p: [1 - p.p, 2p] / (1 + p.p).
inline void mrp_to_quat(const double p[3], double q[4]) {
  const double s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  q[0] = (1.0 - s) / (1.0 + s);
  for (int i = 0; i < 3; ++i) q[i + 1] = 2.0 * p[i] / (1.0 + s);
}

/// c = a * b (Hamilton product).
inline void quat_mul(const double a[4], const double b[4], double c[4]) {
  c[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  c[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  c[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  c[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

inline void quat_normalize(double q[4]) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int i = 0; i < 4; ++i) q[i] /= n;
}

/// v_world = Q(q) v_body.
inline void quat_rotate(const double q[4], const double v[3], double out[3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) out[i] = R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2];
}

/// The normalised linear interpolation of two quaternions (taking the shorter way).
inline void quat_nlerp(const double a[4], const double b[4], double t, double out[4]) {
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  const double sign = dot < 0.0 ? -1.0 : 1.0;
  for (int i = 0; i < 4; ++i) out[i] = (1.0 - t) * a[i] + t * sign * b[i];
  quat_normalize(out);
}

// ---------------------------------------------------------------------------------------------
// Output.

/// Opens argv[1] if given, else `default_name` in the current directory; throws on failure.
struct Csv {
  std::FILE *f = nullptr;
  std::string path;
  Csv(int argc, char **argv, const char *default_name)
      : path(argc > 1 ? argv[1] : default_name) {
    f = std::fopen(path.c_str(), "w");
    if (!f) throw std::runtime_error("cannot open " + path + " for writing");
  }
  ~Csv() {
    if (f) std::fclose(f);
  }
  Csv(const Csv &) = delete;
  Csv &operator=(const Csv &) = delete;
};

}  // namespace app

#endif  // DCOL_APP_COMMON_HPP
