// dcol.hpp: a header-only C++11 wrapper of the C API in dcol.h (RAII shapes, exceptions).
//
//   const dcol::Shape box = dcol::Shape::box(0.5, 0.5, 0.5);
//   const dcol::Shape ball = dcol::Shape::sphere(0.5);
//   dcol_proximity_result r = dcol::proximity(box, dcol::pose({0, 0, 0}),
//                                             ball, dcol::pose({2, 0, 0}));   // r.alpha == 2
//
// It wraps every function of dcol.h. Each wrapper takes the C arguments in the C order (outputs
// become the return value; `options` defaults to nullptr, the defaults) and throws dcol::Error
// when the C call does not return DCOL_OK, including DCOL_ERROR_NOT_CONVERGED: to get the last
// iterate, call the C function directly. The exceptions are per-item statuses, which are
// returned, not thrown: dcol::proximity_batch (one status per pair) and
// dcol::Scene::pairs_within (a pair whose solve did not converge). The plain C structs
// (dcol_pose, dcol_options, dcol_proximity_result, dcol_distance_result,
// dcol_signed_distance_result, dcol_contact, dcol_derivatives_result, dcol_scene_pair, dcol_scene_stats) are used as is.
//
// Shapes are move-only and free themselves; like the C shapes they are immutable and may be
// shared between threads. A dcol::Scene is move-only, frees itself, keeps its own copies of the
// shapes added to it (a Shape may be destroyed right after Scene::add) and, like the C scene, must
// be used by one thread at a time. A moved-from Shape or Scene holds nothing: passing or using it
// throws dcol::Error with DCOL_ERROR_NULL_POINTER (in a batch: that pair's status).
#ifndef DCOL_HPP
#define DCOL_HPP

#include <array>
#include <cstddef>
#include <cstdint>
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

  /// The convex hull of `points` (body frame) padded by a ball of `radius` >= 0 (0: the hull
  /// itself): duplicate, interior and coplanar points are fine; the points must surround the
  /// origin strictly (dcol::Error's message gives the centroid to shift them by otherwise).
  static Shape convex_hull(const std::vector<std::array<double, 3>> &points, double radius = 0.0) {
    std::vector<double> flat = flatten(points);
    return build([&](dcol_shape **out) {
      return dcol_shape_new_convex_hull(flat.data(), points.size(), radius, out);
    });
  }

  /// The half-space { u : u_z <= depth } (body frame), outward normal +e_z, plane `depth` above
  /// the origin: a floor with top surface z = 0 sits at (0, 0, -depth).
  static Shape halfspace(double depth) {
    return build([&](dcol_shape **out) { return dcol_shape_new_halfspace(depth, out); });
  }

  /// The C handle (still owned by this object).
  const dcol_shape *get() const noexcept { return handle_.get(); }

  /// How many numbers describe the shape: its constructor's arguments (see
  /// dcol_shape_parameter_count for the order of each kind).
  std::size_t parameter_count() const noexcept { return dcol_shape_parameter_count(get()); }

  /// The constructor's arguments, in the order given (an ellipsoid's P symmetrised).
  std::vector<double> parameters() const {
    std::vector<double> p(parameter_count());
    check(dcol_shape_parameters(get(), p.data(), p.size()));
    return p;
  }

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

/// The signed distance (minus the penetration depth when overlapping), the normal from shape 1
/// to shape 2 and the witness points.
inline dcol_signed_distance_result signed_distance(const Shape &shape1, const dcol_pose &pose1,
                                                   const Shape &shape2, const dcol_pose &pose2,
                                                   const dcol_options *options = nullptr) {
  dcol_signed_distance_result d;
  check(dcol_signed_distance(shape1.get(), &pose1, shape2.get(), &pose2, options, &d));
  return d;
}

/// The signed distance (as dcol::signed_distance) and its gradient with respect to
/// (r1, q1, r2, q2).
struct SignedDistanceGradient {
  dcol_signed_distance_result result;
  std::array<double, 14> gradient;
};

inline SignedDistanceGradient signed_distance_gradient(const Shape &shape1,
                                                       const dcol_pose &pose1,
                                                       const Shape &shape2,
                                                       const dcol_pose &pose2,
                                                       const dcol_options *options = nullptr) {
  SignedDistanceGradient g;
  check(dcol_signed_distance_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options,
                                      &g.result, g.gradient.data()));
  return g;
}

/// The proximity result and d alpha* / d(parameters) of each shape (see
/// Shape::parameters: the constructors' arguments, in order), as dcol_shape_gradient; the kind
/// of derivative is result.derivatives.
struct ShapeGradient {
  dcol_proximity_result result;
  std::vector<double> d_shape1;
  std::vector<double> d_shape2;
};

inline ShapeGradient shape_gradient(const Shape &shape1, const dcol_pose &pose1,
                                    const Shape &shape2, const dcol_pose &pose2,
                                    const dcol_options *options = nullptr) {
  ShapeGradient g{{}, std::vector<double>(shape1.parameter_count()),
                  std::vector<double>(shape2.parameter_count())};
  check(dcol_shape_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options, &g.result,
                            g.d_shape1.data(), g.d_shape2.data()));
  return g;
}

/// The distance and d distance / d(parameters) of each shape (as dcol_distance_shape_gradient;
/// zeros when the shapes touch or overlap).
struct DistanceShapeGradient {
  dcol_distance_result result;
  std::vector<double> d_shape1;
  std::vector<double> d_shape2;
};

inline DistanceShapeGradient distance_shape_gradient(const Shape &shape1, const dcol_pose &pose1,
                                                     const Shape &shape2, const dcol_pose &pose2,
                                                     const dcol_options *options = nullptr) {
  DistanceShapeGradient g{{}, std::vector<double>(shape1.parameter_count()),
                          std::vector<double>(shape2.parameter_count())};
  check(dcol_distance_shape_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options,
                                     &g.result, g.d_shape1.data(), g.d_shape2.data()));
  return g;
}

/// The signed distance and d sd / d(parameters) of each shape (as
/// dcol_signed_distance_shape_gradient).
struct SignedDistanceShapeGradient {
  dcol_signed_distance_result result;
  std::vector<double> d_shape1;
  std::vector<double> d_shape2;
};

inline SignedDistanceShapeGradient signed_distance_shape_gradient(
    const Shape &shape1, const dcol_pose &pose1, const Shape &shape2, const dcol_pose &pose2,
    const dcol_options *options = nullptr) {
  SignedDistanceShapeGradient g{{}, std::vector<double>(shape1.parameter_count()),
                                std::vector<double>(shape2.parameter_count())};
  check(dcol_signed_distance_shape_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options,
                                            &g.result, g.d_shape1.data(), g.d_shape2.data()));
  return g;
}

/// The contact manifold (as dcol_contacts): the points where the signed distance is at most
/// `margin`, at most `capacity` of them (and at most DCOL_MAX_CONTACTS), one normal from shape 1
/// to shape 2; empty when the shapes are farther apart than the margin.
inline std::vector<dcol_contact> contacts(const Shape &shape1, const dcol_pose &pose1,
                                          const Shape &shape2, const dcol_pose &pose2,
                                          double margin, const dcol_options *options = nullptr,
                                          std::size_t capacity = DCOL_MAX_CONTACTS) {
  std::vector<dcol_contact> out(capacity);
  std::size_t count = 0;
  check(dcol_contacts(shape1.get(), &pose1, shape2.get(), &pose2, margin, options,
                      capacity > 0 ? out.data() : nullptr, capacity, &count));
  out.resize(count);
  return out;
}

/// The distance (as dcol::distance) and its gradient with respect to (r1, q1, r2, q2); all zeros
/// when the shapes touch or overlap.
struct DistanceGradient {
  dcol_distance_result result;
  std::array<double, 14> gradient;
};

inline DistanceGradient distance_gradient(const Shape &shape1, const dcol_pose &pose1,
                                          const Shape &shape2, const dcol_pose &pose2,
                                          const dcol_options *options = nullptr) {
  DistanceGradient g;
  check(dcol_distance_gradient(shape1.get(), &pose1, shape2.get(), &pose2, options, &g.result,
                               g.gradient.data()));
  return g;
}

/// Is alpha* < `threshold` (positive, finite)? Answered from bounds or an early-exit solve; equal
/// to `proximity(...).alpha < threshold` except within about the solver tolerance of the
/// threshold. A bad threshold throws dcol::Error with DCOL_ERROR_INVALID_OPTIONS.
inline bool alpha_below(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                        const dcol_pose &pose2, double threshold,
                        const dcol_options *options = nullptr) {
  std::int32_t below = 0;
  check(dcol_alpha_below(shape1.get(), &pose1, shape2.get(), &pose2, threshold, options, &below));
  return below != 0;
}

/// Do the shapes interpenetrate (alpha* < 1)? Exactly alpha_below with threshold 1.
inline bool intersect(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                      const dcol_pose &pose2, const dcol_options *options = nullptr) {
  std::int32_t intersecting = 0;
  check(dcol_intersect(shape1.get(), &pose1, shape2.get(), &pose2, options, &intersecting));
  return intersecting != 0;
}

/// Everything from one solve: the proximity, the gradient and Jacobian (bit for bit those of
/// dcol::gradient and dcol::jacobian) and the contact-point Jacobians (see dcol_derivatives_result).
inline dcol_derivatives_result derivatives(const Shape &shape1, const dcol_pose &pose1,
                                           const Shape &shape2, const dcol_pose &pose2,
                                           const dcol_options *options = nullptr) {
  dcol_derivatives_result d;
  check(dcol_derivatives(shape1.get(), &pose1, shape2.get(), &pose2, options, &d));
  return d;
}

/// A per-pair warm-start cache for the `*_cached` queries (a dcol_cache, cold when made or
/// cleared). Keep one per pair of shapes; copyable, movable, plain data.
class Cache {
 public:
  Cache() : cache_() {}
  dcol_cache *get() { return &cache_; }
  const dcol_cache *get() const { return &cache_; }
  /// Forgets what the cache holds (the next query is cold).
  void clear() { cache_ = dcol_cache(); }

 private:
  dcol_cache cache_;
};

/// dcol::proximity starting from the pair's last answer (dcol_proximity_cached): the same
/// answer, certified the same way; `cache` then holds this one.
inline dcol_proximity_result proximity_cached(const Shape &shape1, const dcol_pose &pose1,
                                              const Shape &shape2, const dcol_pose &pose2,
                                              Cache &cache, const dcol_options *options = nullptr) {
  dcol_proximity_result r;
  check(dcol_proximity_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                              &r));
  return r;
}

/// dcol::gradient with a warm start (dcol_gradient_cached).
inline Gradient gradient_cached(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                                const dcol_pose &pose2, Cache &cache,
                                const dcol_options *options = nullptr) {
  Gradient g;
  check(dcol_gradient_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                             &g.result, g.gradient.data()));
  return g;
}

/// dcol::jacobian with a warm start (dcol_jacobian_cached).
inline Jacobian jacobian_cached(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                                const dcol_pose &pose2, Cache &cache,
                                const dcol_options *options = nullptr) {
  Jacobian j;
  check(dcol_jacobian_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                             &j.result, j.jacobian.data()));
  return j;
}

/// dcol::derivatives with a warm start (dcol_derivatives_cached).
inline dcol_derivatives_result derivatives_cached(const Shape &shape1, const dcol_pose &pose1,
                                                  const Shape &shape2, const dcol_pose &pose2,
                                                  Cache &cache,
                                                  const dcol_options *options = nullptr) {
  dcol_derivatives_result d;
  check(dcol_derivatives_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                                &d));
  return d;
}

/// dcol::distance with a warm start (dcol_distance_cached).
inline dcol_distance_result distance_cached(const Shape &shape1, const dcol_pose &pose1,
                                            const Shape &shape2, const dcol_pose &pose2,
                                            Cache &cache, const dcol_options *options = nullptr) {
  dcol_distance_result d;
  check(dcol_distance_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                             &d));
  return d;
}

/// dcol::contacts with a warm start (dcol_contacts_cached).
inline std::vector<dcol_contact> contacts_cached(const Shape &shape1, const dcol_pose &pose1,
                                                 const Shape &shape2, const dcol_pose &pose2,
                                                 double margin, Cache &cache,
                                                 const dcol_options *options = nullptr,
                                                 std::size_t capacity = DCOL_MAX_CONTACTS) {
  std::vector<dcol_contact> out(capacity);
  std::size_t count = 0;
  check(dcol_contacts_cached(shape1.get(), &pose1, shape2.get(), &pose2, margin, options,
                             cache.get(), capacity > 0 ? out.data() : nullptr, capacity, &count));
  out.resize(count);
  return out;
}

/// dcol::signed_distance with a warm start (dcol_signed_distance_cached).
inline dcol_signed_distance_result signed_distance_cached(const Shape &shape1,
                                                          const dcol_pose &pose1,
                                                          const Shape &shape2,
                                                          const dcol_pose &pose2, Cache &cache,
                                                          const dcol_options *options = nullptr) {
  dcol_signed_distance_result d;
  check(dcol_signed_distance_cached(shape1.get(), &pose1, shape2.get(), &pose2, options,
                                    cache.get(), &d));
  return d;
}

/// dcol::intersect with a warm start (dcol_intersect_cached): the same decision; a separating
/// normal kept in `cache` that still separates the shapes answers false from two support calls.
inline bool intersect_cached(const Shape &shape1, const dcol_pose &pose1, const Shape &shape2,
                             const dcol_pose &pose2, Cache &cache,
                             const dcol_options *options = nullptr) {
  std::int32_t intersecting = 0;
  check(dcol_intersect_cached(shape1.get(), &pose1, shape2.get(), &pose2, options, cache.get(),
                              &intersecting));
  return intersecting != 0;
}

/// dcol::distance_gradient with a warm start (dcol_distance_gradient_cached).
inline DistanceGradient distance_gradient_cached(const Shape &shape1, const dcol_pose &pose1,
                                                 const Shape &shape2, const dcol_pose &pose2,
                                                 Cache &cache,
                                                 const dcol_options *options = nullptr) {
  DistanceGradient g;
  check(dcol_distance_gradient_cached(shape1.get(), &pose1, shape2.get(), &pose2, options,
                                      cache.get(), &g.result, g.gradient.data()));
  return g;
}

/// The proximity result and d alpha* / d(r1, p1, r2, p2) for attitudes given as modified
/// Rodrigues parameters p (q = [1 - p.p, 2 p] / (1 + p.p)): 12 numbers.
struct GradientMrp {
  dcol_proximity_result result;
  std::array<double, 12> gradient;
};

inline GradientMrp gradient_mrp(const Shape &shape1, const std::array<double, 3> &position1,
                                const std::array<double, 3> &mrp1, const Shape &shape2,
                                const std::array<double, 3> &position2,
                                const std::array<double, 3> &mrp2,
                                const dcol_options *options = nullptr) {
  GradientMrp g;
  check(dcol_gradient_mrp(shape1.get(), position1.data(), mrp1.data(), shape2.get(),
                          position2.data(), mrp2.data(), options, &g.result, g.gradient.data()));
  return g;
}

/// The proximity result and d(x*, alpha*) / d(r1, p1, r2, p2) for MRP attitudes (see
/// gradient_mrp), 4 x 12 row-major.
struct JacobianMrp {
  dcol_proximity_result result;
  std::array<double, 48> jacobian;
  double operator()(std::size_t row, std::size_t col) const { return jacobian[row * 12 + col]; }
};

inline JacobianMrp jacobian_mrp(const Shape &shape1, const std::array<double, 3> &position1,
                                const std::array<double, 3> &mrp1, const Shape &shape2,
                                const std::array<double, 3> &position2,
                                const std::array<double, 3> &mrp2,
                                const dcol_options *options = nullptr) {
  JacobianMrp j;
  check(dcol_jacobian_mrp(shape1.get(), position1.data(), mrp1.data(), shape2.get(),
                          position2.data(), mrp2.data(), options, &j.result, j.jacobian.data()));
  return j;
}

/// The results of proximity_batch: results[i] and statuses[i] for pair i.
struct BatchResult {
  std::vector<dcol_proximity_result> results;
  std::vector<dcol_status> statuses;
};

/// Proximity of pair i = (*shapes1[i], poses1[i], *shapes2[i], poses2[i]) for every i (all four
/// vectors of equal length, else std::invalid_argument). Each pair has its own status, which is
/// returned, not thrown: DCOL_OK (results[i] equal bit for bit to dcol::proximity on the pair),
/// DCOL_ERROR_NOT_CONVERGED (results[i] holds the last iterate), DCOL_ERROR_NULL_POINTER (a null
/// or moved-from shape), DCOL_ERROR_INVALID_POSE or DCOL_ERROR_INTERNAL (results[i] all zeros).
/// Per-pair failures do not set the last error message. Throws dcol::Error only when the whole
/// call fails (invalid options). `threads` as in dcol_proximity_batch (<= 1: the calling thread).
inline BatchResult proximity_batch(const std::vector<const Shape *> &shapes1,
                                   const std::vector<dcol_pose> &poses1,
                                   const std::vector<const Shape *> &shapes2,
                                   const std::vector<dcol_pose> &poses2,
                                   const dcol_options *options = nullptr,
                                   std::uint32_t threads = 1) {
  const std::size_t count = shapes1.size();
  if (poses1.size() != count || shapes2.size() != count || poses2.size() != count)
    throw std::invalid_argument("dcol::proximity_batch: the four inputs differ in length");
  std::vector<const dcol_shape *> c1(count), c2(count);
  for (std::size_t i = 0; i < count; ++i) {
    c1[i] = shapes1[i] ? shapes1[i]->get() : nullptr;
    c2[i] = shapes2[i] ? shapes2[i]->get() : nullptr;
  }
  BatchResult b;
  b.results.resize(count);  // value-initialised: zeros where the C call writes nothing
  b.statuses.resize(count, DCOL_OK);
  check(dcol_proximity_batch(c1.data(), poses1.data(), c2.data(), poses2.data(), count, options,
                             threads, b.results.data(), b.statuses.data()));
  return b;
}

/// An owned set of bodies for repeated all-pairs threshold queries (see dcol_scene in dcol.h).
/// Move-only; not thread-safe (one thread at a time, as the C scene).
class Scene {
 public:
  /// A new, empty scene.
  Scene() {
    dcol_scene *out = nullptr;
    check(dcol_scene_new(&out));
    handle_.reset(out);
  }

  /// Adds a body with a copy of `shape` at `pose` and returns its id (0, 1, 2, ... in the order
  /// of addition). The scene keeps its own copy: `shape` may be destroyed at once.
  std::size_t add(const Shape &shape, const dcol_pose &pose) {
    std::size_t id = 0;
    check(dcol_scene_add(handle_.get(), shape.get(), &pose, &id));
    return id;
  }

  /// Moves body `id`; an id >= size() throws dcol::Error with DCOL_ERROR_INVALID_OPTIONS.
  void set_pose(std::size_t id, const dcol_pose &pose) {
    check(dcol_scene_set_pose(handle_.get(), id, &pose));
  }

  /// The number of bodies.
  std::size_t size() const {
    std::size_t n = 0;
    check(dcol_scene_size(handle_.get(), &n));
    return n;
  }

  /// Every pair with alpha* <= `threshold` (positive, finite), sorted by (body1 < body2), each
  /// with its full proximity (bit for bit dcol::proximity on the two bodies, lower id first) and
  /// its status: DCOL_OK, or DCOL_ERROR_NOT_CONVERGED (returned, not thrown) for a pair whose
  /// last iterate is <= threshold. Pairs within about the solver tolerance of the threshold may
  /// be reported or not. `stats`, if not null, receives the work done by each level.
  ///
  /// The vector always holds all the pairs: when the C call reports more pairs than the buffer
  /// holds, the step is run again with a buffer of the reported size (the step is deterministic).
  /// The buffer starts at the largest count seen by this Scene, so that happens only when a step
  /// reports more pairs than every earlier one. Errors (bad threshold or options) throw.
  std::vector<dcol_scene_pair> pairs_within(double threshold,
                                            const dcol_options *options = nullptr,
                                            dcol_scene_stats *stats = nullptr) {
    std::vector<dcol_scene_pair> pairs(capacity_hint_);
    for (;;) {
      std::size_t count = 0;
      const dcol_status status = dcol_scene_pairs_within(
          handle_.get(), threshold, options, pairs.empty() ? nullptr : pairs.data(), pairs.size(),
          &count, stats);
      if (status == DCOL_ERROR_INVALID_OPTIONS && count > pairs.size()) {
        // Not an error: the buffer was too small and `count` is the number needed.
        pairs.resize(count);
        continue;
      }
      check(status);
      pairs.resize(count);
      if (count > capacity_hint_) capacity_hint_ = count;
      return pairs;
    }
  }

  /// The C handle (still owned by this object); null after a move.
  dcol_scene *get() noexcept { return handle_.get(); }
  const dcol_scene *get() const noexcept { return handle_.get(); }

 private:
  struct Deleter {
    void operator()(dcol_scene *s) const noexcept { dcol_scene_free(s); }
  };

  std::unique_ptr<dcol_scene, Deleter> handle_;
  std::size_t capacity_hint_ = 16;
};

}  // namespace dcol

#endif  // DCOL_HPP
