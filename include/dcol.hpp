// dcol.hpp: a header-only C++11 wrapper of the C API in dcol.h (RAII shapes, exceptions).
//
//   const dcol::Shape box = dcol::Shape::box(0.5, 0.5, 0.5);
//   const dcol::Shape ball = dcol::Shape::sphere(0.5);
//   dcol_proximity_result r = dcol::proximity(box, dcol::pose({0, 0, 0}),
//                                             ball, dcol::pose({2, 0, 0}));   // r.alpha == 2
//
// Every function throws dcol::Error when the C call does not return DCOL_OK (including
// DCOL_ERROR_NOT_CONVERGED: use the C functions directly to get the last iterate). The plain C
// structs (dcol_pose, dcol_options, dcol_proximity_result, dcol_distance_result) are used as is.
// Shapes are move-only and free themselves; like the C shapes they are immutable and may be
// shared between threads.
#ifndef DCOL_HPP
#define DCOL_HPP

#include <array>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dcol.h"

namespace dcol {

/// A failed call: the status and this thread's last error message.
class Error : public std::runtime_error {
 public:
  Error(dcol_status status, const char *message)
      : std::runtime_error(std::string(dcol_status_string(status)) + ": " + message),
        status_(status) {}
  dcol_status status() const noexcept { return status_; }

 private:
  dcol_status status_;
};

/// Throws dcol::Error unless `status` is DCOL_OK.
inline void check(dcol_status status) {
  if (status != DCOL_OK) throw Error(status, dcol_last_error_message());
}

/// The library's version, "MAJOR.MINOR.PATCH".
inline const char *version() noexcept { return dcol_version(); }

/// An owned, immutable shape.
class Shape {
 public:
  static Shape sphere(double radius) {
    return build([&](dcol_shape **out) { return dcol_shape_new_sphere(radius, out); });
  }
  /// `P` row-major, symmetric positive definite.
  static Shape ellipsoid(const std::array<double, 9> &P) {
    return build([&](dcol_shape **out) { return dcol_shape_new_ellipsoid(P.data(), out); });
  }
  /// Rows of `A` and entries of `b` (same count).
  static Shape polytope(const std::vector<std::array<double, 3>> &A, const std::vector<double> &b) {
    if (A.size() != b.size()) throw std::invalid_argument("dcol::Shape::polytope: A and b differ in length");
    std::vector<double> flat = flatten(A);
    return build([&](dcol_shape **out) {
      return dcol_shape_new_polytope(flat.data(), b.data(), b.size(), out);
    });
  }
  static Shape box(double half_x, double half_y, double half_z) {
    return build([&](dcol_shape **out) { return dcol_shape_new_box(half_x, half_y, half_z, out); });
  }
  static Shape capsule(double radius, double length) {
    return build([&](dcol_shape **out) { return dcol_shape_new_capsule(radius, length, out); });
  }
  static Shape cylinder(double radius, double length) {
    return build([&](dcol_shape **out) { return dcol_shape_new_cylinder(radius, length, out); });
  }
  static Shape cone(double height, double half_angle) {
    return build([&](dcol_shape **out) { return dcol_shape_new_cone(height, half_angle, out); });
  }
  /// Rows of `C` and entries of `d` (same count), padding `radius`.
  static Shape polygon(const std::vector<std::array<double, 2>> &C, const std::vector<double> &d,
                       double radius) {
    if (C.size() != d.size()) throw std::invalid_argument("dcol::Shape::polygon: C and d differ in length");
    std::vector<double> flat = flatten(C);
    return build([&](dcol_shape **out) {
      return dcol_shape_new_polygon(flat.data(), d.data(), d.size(), radius, out);
    });
  }

  /// The C handle (still owned by this object).
  const dcol_shape *get() const noexcept { return handle_.get(); }

 private:
  struct Deleter {
    void operator()(dcol_shape *s) const noexcept { dcol_shape_free(s); }
  };
  explicit Shape(dcol_shape *s) : handle_(s) {}

  template <typename F>
  static Shape build(F make) {
    dcol_shape *out = nullptr;
    check(make(&out));
    return Shape(out);
  }
  template <std::size_t N>
  static std::vector<double> flatten(const std::vector<std::array<double, N>> &rows) {
    std::vector<double> flat;
    flat.reserve(rows.size() * N);
    for (const auto &row : rows) flat.insert(flat.end(), row.begin(), row.end());
    return flat;
  }

  std::unique_ptr<dcol_shape, Deleter> handle_;
};

/// A pose from a position and a quaternion [w, x, y, z] (identity by default).
inline dcol_pose pose(const std::array<double, 3> &position,
                      const std::array<double, 4> &quaternion = {{1.0, 0.0, 0.0, 0.0}}) {
  dcol_pose p;
  for (std::size_t i = 0; i < 3; ++i) p.position[i] = position[i];
  for (std::size_t i = 0; i < 4; ++i) p.quaternion[i] = quaternion[i];
  return p;
}

/// alpha*, x* and the contact points. `options` may be null (defaults).
inline dcol_proximity_result proximity(const Shape &shape1, const dcol_pose &pose1,
                                       const Shape &shape2, const dcol_pose &pose2,
                                       const dcol_options *options = nullptr) {
  dcol_proximity_result r;
  check(dcol_proximity(shape1.get(), &pose1, shape2.get(), &pose2, options, &r));
  return r;
}

/// The proximity result and d alpha* / d(r1, q1, r2, q2).
struct Gradient {
  dcol_proximity_result result;
  std::array<double, 14> gradient;
};

inline Gradient gradient(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                         const dcol_pose &pose2, const dcol_options *options = nullptr) {
  Gradient g;
  check(dcol_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options, &g.result,
                      g.gradient.data()));
  return g;
}

/// The proximity result and d(x*, alpha*) / d(r1, q1, r2, q2), 4 x 14 row-major.
struct Jacobian {
  dcol_proximity_result result;
  std::array<double, 56> jacobian;
  double operator()(std::size_t row, std::size_t col) const { return jacobian[row * 14 + col]; }
};

inline Jacobian jacobian(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                         const dcol_pose &pose2, const dcol_options *options = nullptr) {
  Jacobian j;
  check(dcol_jacobian(shape1.get(), &pose1, shape2.get(), &pose2, options, &j.result,
                      j.jacobian.data()));
  return j;
}

/// The exact distance between the unscaled shapes and the witness points.
inline dcol_distance_result distance(const Shape &shape1, const dcol_pose &pose1,
                                     const Shape &shape2, const dcol_pose &pose2,
                                     const dcol_options *options = nullptr) {
  dcol_distance_result d;
  check(dcol_distance(shape1.get(), &pose1, shape2.get(), &pose2, options, &d));
  return d;
}

}  // namespace dcol

#endif  // DCOL_HPP
