// Tests of the C++ wrappers in dcol.hpp that have no other C++ test: alpha_below, intersect,
// distance_gradient, derivatives, gradient_mrp, jacobian_mrp, proximity_batch and dcol::Scene.
// Values are checked against analytic truth (two spheres) or against the C functions and the
// chain rule; batch and scene results against single dcol_proximity calls, bit for bit; errors
// against the status the C contract names. C++11, built with the strict flags (and the
// sanitizers, and run under valgrind, like the C tests).
#include <dcol.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "check.h"

namespace {

static_assert(!std::is_copy_constructible<dcol::Scene>::value, "Scene is move-only");
static_assert(!std::is_copy_assignable<dcol::Scene>::value, "Scene is move-only");
static_assert(std::is_nothrow_move_constructible<dcol::Scene>::value, "Scene moves");
static_assert(std::is_nothrow_move_assignable<dcol::Scene>::value, "Scene moves");

const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool close(double a, double b, double tol) { return std::fabs(a - b) <= tol * (1.0 + std::fabs(b)); }

bool same_bits(const double *a, const double *b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

// Field by field (the struct has padding, which memcmp must not look at).
bool same_result(const dcol_proximity_result &a, const dcol_proximity_result &b) {
  return same_bits(&a.alpha, &b.alpha, 1) && same_bits(a.point, b.point, 3) &&
         same_bits(a.contact1, b.contact1, 3) && same_bits(a.contact2, b.contact2, 3) &&
         a.iterations == b.iterations;
}

// The same proximity to the solver's tolerance (alpha* within 1e-12 relative, the points within
// 1e-11 for these unit-size shapes): a scene's pairs of polytopes start from their last answer
// (dcol_cache), which agrees with a cold one to that.
bool close_result(const dcol_proximity_result &a, const dcol_proximity_result &b) {
  bool ok = std::fabs(a.alpha - b.alpha) <= 1e-12 * std::fabs(b.alpha) && a.iterations == b.iterations;
  for (int i = 0; i < 3; ++i) {
    ok = ok && std::fabs(a.point[i] - b.point[i]) <= 1e-11 &&
         std::fabs(a.contact1[i] - b.contact1[i]) <= 1e-11 &&
         std::fabs(a.contact2[i] - b.contact2[i]) <= 1e-11;
  }
  return ok;
}

bool is_zero(const dcol_proximity_result &r) {
  const dcol_proximity_result z = dcol_proximity_result();
  return same_result(r, z);
}

// Runs `body`, which must throw dcol::Error with `status` and a message naming `function`.
#define EXPECT_ERROR(body, want_status, function)                                               \
  do {                                                                                          \
    bool thrown_ = false;                                                                       \
    try {                                                                                       \
      body;                                                                                     \
    } catch (const dcol::Error &e_) {                                                           \
      thrown_ = true;                                                                           \
      CHECK_MSG(e_.status() == (want_status), "status %d, message %s",                         \
                static_cast<int>(e_.status()), e_.what());                                      \
      CHECK_MSG(std::string(e_.what()).find(function) != std::string::npos, "message %s",      \
                e_.what());                                                                     \
    }                                                                                           \
    CHECK_MSG(thrown_, "%s did not throw", #body);                                              \
  } while (0)

// Two spheres: R1 = 0.5 at r1, R2 = 0.3 at r1 + delta.
const double R1 = 0.5, R2 = 0.3;
const std::array<double, 3> r1 = {{0.1, 0.2, -0.3}};
const std::array<double, 3> delta = {{1.2, 0.5, -0.4}};  // |delta| = sqrt(1.85)

std::array<double, 3> plus(const std::array<double, 3> &a, const std::array<double, 3> &b,
                           double s = 1.0) {
  return {{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]}};
}

double norm(const std::array<double, 3> &a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

void test_alpha_below_intersect() {
  const dcol::Shape s1 = dcol::Shape::sphere(R1), s2 = dcol::Shape::sphere(R2);
  const double d = norm(delta);
  const dcol_pose p1 = dcol::pose(r1);
  // Scale delta so alpha = |delta'| / (R1 + R2) takes chosen values on both sides of 1.
  const double alphas[] = {0.3, 0.75, 0.98, 1.02, 1.25, 3.0};
  for (double alpha : alphas) {
    const dcol_pose p2 = dcol::pose(plus(r1, delta, alpha * (R1 + R2) / d));
    CHECK_MSG(close(dcol::proximity(s1, p1, s2, p2).alpha, alpha, 1e-7), "alpha %g", alpha);
    CHECK_MSG(dcol::intersect(s1, p1, s2, p2) == (alpha < 1.0), "alpha %g", alpha);
    CHECK_MSG(dcol::intersect(s2, p2, s1, p1) == (alpha < 1.0), "alpha %g (swapped)", alpha);
    // Thresholds away from alpha by 5 %, both sides.
    CHECK_MSG(dcol::alpha_below(s1, p1, s2, p2, alpha * 1.05), "alpha %g", alpha);
    CHECK_MSG(!dcol::alpha_below(s1, p1, s2, p2, alpha * 0.95), "alpha %g", alpha);
    // Same answers as the C function.
    std::int32_t below = -1;
    CHECK(dcol_alpha_below(s1.get(), &p1, s2.get(), &p2, 1.0, nullptr, &below) == DCOL_OK);
    CHECK(below == (alpha < 1.0 ? 1 : 0));
  }
  // A box and a cone too: intersect agrees with proximity away from alpha = 1.
  const dcol::Shape box = dcol::Shape::box(0.4, 0.3, 0.2), cone = dcol::Shape::cone(1.0, 0.5);
  for (int i = 0; i < 20; ++i) {
    const double x = 0.2 + 0.1 * i;
    const dcol_pose pb = dcol::pose({0, 0, 0}, {{0.9, 0.1, 0.3, -0.2}});
    const dcol_pose pc = dcol::pose({x, 0.3, 0.1}, {{0.8, -0.2, 0.1, 0.4}});
    const double a = dcol::proximity(box, pb, cone, pc).alpha;
    if (std::fabs(a - 1.0) > 1e-3) CHECK_MSG(dcol::intersect(box, pb, cone, pc) == (a < 1.0), "x %g", x);
  }

  const dcol_pose p2 = dcol::pose(plus(r1, delta));
  dcol_pose bad = p1;
  bad.position[1] = kNaN;
  EXPECT_ERROR(dcol::intersect(s1, bad, s2, p2), DCOL_ERROR_INVALID_POSE, "dcol_intersect");
  EXPECT_ERROR(dcol::alpha_below(s1, p1, s2, bad, 1.0), DCOL_ERROR_INVALID_POSE, "dcol_alpha_below");
  EXPECT_ERROR(dcol::alpha_below(s1, p1, s2, p2, -1.0), DCOL_ERROR_INVALID_OPTIONS, "threshold");
  EXPECT_ERROR(dcol::alpha_below(s1, p1, s2, p2, kNaN), DCOL_ERROR_INVALID_OPTIONS, "threshold");
  dcol_options o = dcol_options_default();
  o.tolerance = 0.0;
  EXPECT_ERROR(dcol::intersect(s1, p1, s2, p2, &o), DCOL_ERROR_INVALID_OPTIONS, "dcol_intersect");
}

void test_distance_gradient() {
  const dcol::Shape s1 = dcol::Shape::sphere(R1), s2 = dcol::Shape::sphere(R2);
  const double d = norm(delta);
  const dcol_pose p1 = dcol::pose(r1, {{0.9, 0.1, -0.2, 0.3}}), p2 = dcol::pose(plus(r1, delta));
  const dcol::DistanceGradient g = dcol::distance_gradient(s1, p1, s2, p2);
  CHECK_MSG(close(g.result.distance, d - R1 - R2, 1e-7), "distance %.17g, expected %.17g",
            g.result.distance, d - R1 - R2);
  for (int k = 0; k < 3; ++k) {
    const double u = delta[k] / d;  // d distance / d r2 = u, d / d r1 = -u
    CHECK_MSG(close(g.gradient[7 + k], u, 1e-6), "d/dr2[%d] = %.17g, expected %.17g", k,
              g.gradient[7 + k], u);
    CHECK_MSG(close(g.gradient[k], -u, 1e-6), "d/dr1[%d] = %.17g", k, g.gradient[k]);
    CHECK(close(g.result.closest1[k], r1[k] + R1 * u, 1e-6));
    CHECK(close(g.result.closest2[k], r1[k] + delta[k] - R2 * u, 1e-6));
    CHECK(close(g.result.normal[k], u, 1e-6));
  }
  for (int k = 0; k < 4; ++k) {  // spheres: the attitude does not matter
    CHECK(std::fabs(g.gradient[3 + k]) < 1e-6);
    CHECK(std::fabs(g.gradient[10 + k]) < 1e-6);
  }
  // The distance is dcol::distance's, bit for bit.
  const dcol_distance_result plain = dcol::distance(s1, p1, s2, p2);
  CHECK(same_bits(&plain.distance, &g.result.distance, 1));

  // Overlapping: distance 0, gradient all zeros.
  const dcol::DistanceGradient o =
      dcol::distance_gradient(s1, p1, s2, dcol::pose(plus(r1, delta, 0.5 / d)));
  CHECK(o.result.distance == 0.0);
  for (double v : o.gradient) CHECK(v == 0.0);

  dcol_pose bad = p2;
  bad.quaternion[0] = kNaN;
  EXPECT_ERROR(dcol::distance_gradient(s1, p1, s2, bad), DCOL_ERROR_INVALID_POSE,
               "dcol_distance_gradient");
}

void test_derivatives() {
  const dcol::Shape s1 = dcol::Shape::sphere(R1), s2 = dcol::Shape::sphere(R2);
  const double d = norm(delta);
  const dcol_pose p1 = dcol::pose(r1), p2 = dcol::pose(plus(r1, delta));
  const dcol_derivatives_result D = dcol::derivatives(s1, p1, s2, p2);
  CHECK(close(D.proximity.alpha, d / (R1 + R2), 1e-8));
  for (int k = 0; k < 3; ++k) {
    const double u = delta[k] / d;
    // d alpha / d r2 = (r2 - r1) / (|r2 - r1| (R1 + R2)); d alpha / d r1 = its negative.
    CHECK_MSG(close(D.gradient[7 + k], u / (R1 + R2), 1e-6), "d alpha/dr2[%d] = %.17g", k,
              D.gradient[7 + k]);
    CHECK(close(D.gradient[k], -u / (R1 + R2), 1e-6));
    CHECK(close(D.jacobian[3][7 + k], u / (R1 + R2), 1e-6));
  }
  // Contact points p1 = r1 + R1 u, p2 = r2 - R2 u with u = (r2 - r1) / |r2 - r1|:
  // d p1 / d r2 = R1 (I - u u^T) / |delta|, d p1 / d r1 = I - that; d p2 / d r2 = I - R2 (..),
  // d p2 / d r1 = R2 (I - u u^T) / |delta|.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double P = (i == j ? 1.0 : 0.0) - delta[i] * delta[j] / (d * d);
      const double I = i == j ? 1.0 : 0.0;
      CHECK_MSG(close(D.contact_jacobian1[i][7 + j], R1 * P / d, 1e-6), "dp1/dr2 (%d, %d)", i, j);
      CHECK_MSG(close(D.contact_jacobian1[i][j], I - R1 * P / d, 1e-6), "dp1/dr1 (%d, %d)", i, j);
      CHECK_MSG(close(D.contact_jacobian2[i][7 + j], I - R2 * P / d, 1e-6), "dp2/dr2 (%d, %d)", i, j);
      CHECK_MSG(close(D.contact_jacobian2[i][j], R2 * P / d, 1e-6), "dp2/dr1 (%d, %d)", i, j);
    }
  }

  // On general shapes: dcol::derivatives, dcol::jacobian, dcol::gradient and dcol::proximity
  // share one solve by default (the geometric solvers): the same proximity, gradient and
  // Jacobian, bit for bit. The interior-point method agrees to the solvers' accuracy.
  const dcol::Shape box = dcol::Shape::box(0.4, 0.3, 0.2), cap = dcol::Shape::capsule(0.2, 0.8);
  const dcol_pose pb = dcol::pose({0.1, 0, 0}, {{0.9, 0.1, 0.3, -0.2}});
  const dcol_pose pc = dcol::pose({1.3, 0.4, -0.2}, {{0.8, -0.2, 0.1, 0.4}});
  dcol_options ipm = dcol_options_default();
  ipm.method = DCOL_METHOD_INTERIOR_POINT;
  const dcol_derivatives_result E = dcol::derivatives(box, pb, cap, pc);
  const dcol::Gradient g = dcol::gradient(box, pb, cap, pc);
  const dcol::Jacobian J = dcol::jacobian(box, pb, cap, pc);
  CHECK(same_result(E.proximity, dcol::proximity(box, pb, cap, pc)));
  CHECK(same_result(E.proximity, g.result));
  CHECK(same_bits(E.gradient, g.gradient.data(), 14));
  CHECK(same_bits(&E.jacobian[0][0], J.jacobian.data(), 56));
  CHECK(E.proximity.solver != DCOL_SOLVER_INTERIOR_POINT);
  CHECK(E.proximity.derivatives == DCOL_DERIVATIVES_EXACT);
  const dcol::Gradient gi = dcol::gradient(box, pb, cap, pc, &ipm);
  CHECK(std::fabs(gi.result.alpha - E.proximity.alpha) <= 1e-10 * std::fmax(1.0, gi.result.alpha));
  for (int k = 0; k < 14; ++k)
    CHECK(std::fabs(gi.gradient[k] - E.gradient[k]) <= 1e-6 * std::fmax(1.0, std::fabs(E.gradient[k])));

  dcol_pose bad = pc;
  bad.position[2] = kNaN;
  EXPECT_ERROR(dcol::derivatives(box, pb, cap, bad), DCOL_ERROR_INVALID_POSE, "dcol_derivatives");
  // NOT_CONVERGED throws (the C function has the last iterate).
  dcol_options one = dcol_options_default();
  one.max_iterations = 1;
  one.method = DCOL_METHOD_INTERIOR_POINT;  // the iteration limit is the interior-point solver's
  dcol_derivatives_result C;
  const dcol_status st = dcol_derivatives(box.get(), &pb, cap.get(), &pc, &one, &C);
  CHECK_MSG(st == DCOL_ERROR_NOT_CONVERGED, "status %d", static_cast<int>(st));
  EXPECT_ERROR(dcol::derivatives(box, pb, cap, pc, &one), DCOL_ERROR_NOT_CONVERGED,
               "dcol_derivatives");
}

// q(p) = [1 - p.p, 2 p] / (1 + p.p) and dq/dp (4 x 3).
void mrp_to_quaternion(const std::array<double, 3> &p, std::array<double, 4> &q, double dq[4][3]) {
  const double s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2], n = 1.0 + s;
  q[0] = (1.0 - s) / n;
  for (int i = 0; i < 3; ++i) q[1 + i] = 2.0 * p[i] / n;
  for (int j = 0; j < 3; ++j) {
    dq[0][j] = -4.0 * p[j] / (n * n);
    for (int i = 0; i < 3; ++i) dq[1 + i][j] = (i == j ? 2.0 / n : 0.0) - 4.0 * p[i] * p[j] / (n * n);
  }
}

// mrp_value[c] for c in the 12 MRP columns from the 14 quaternion columns of one row.
void chain_rule(const double *row14, double dq1[4][3], double dq2[4][3], double out12[12]) {
  for (int k = 0; k < 3; ++k) {
    out12[k] = row14[k];
    out12[6 + k] = row14[7 + k];
    out12[3 + k] = 0.0;
    out12[9 + k] = 0.0;
    for (int i = 0; i < 4; ++i) {
      out12[3 + k] += row14[3 + i] * dq1[i][k];
      out12[9 + k] += row14[10 + i] * dq2[i][k];
    }
  }
}

void test_mrp() {
  const dcol::Shape box = dcol::Shape::box(0.4, 0.3, 0.2), cap = dcol::Shape::capsule(0.2, 0.8);
  const std::array<double, 3> pos1 = {{0.1, 0, 0}}, pos2 = {{1.3, 0.4, -0.2}};
  const std::array<double, 3> zero = {{0, 0, 0}};
  const std::array<double, 3> m1 = {{0.1, 0.3, -0.2}}, m2 = {{-0.25, 0.05, 0.4}};
  struct Case {
    std::array<double, 3> a, b;
  };
  const Case cases[] = {{zero, zero}, {m1, m2}};
  for (const Case &c : cases) {
    std::array<double, 4> q1, q2;
    double dq1[4][3], dq2[4][3];
    mrp_to_quaternion(c.a, q1, dq1);
    mrp_to_quaternion(c.b, q2, dq2);
    const dcol_pose p1 = dcol::pose(pos1, q1), p2 = dcol::pose(pos2, q2);
    const dcol::Gradient gq = dcol::gradient(box, p1, cap, p2);
    const dcol::Jacobian jq = dcol::jacobian(box, p1, cap, p2);
    const dcol::GradientMrp gm = dcol::gradient_mrp(box, pos1, c.a, cap, pos2, c.b);
    const dcol::JacobianMrp jm = dcol::jacobian_mrp(box, pos1, c.a, cap, pos2, c.b);
    CHECK(close(gm.result.alpha, gq.result.alpha, 1e-10));
    CHECK(close(jm.result.alpha, gq.result.alpha, 1e-10));
    double want[12];
    chain_rule(gq.gradient.data(), dq1, dq2, want);
    for (int k = 0; k < 12; ++k)
      CHECK_MSG(close(gm.gradient[k], want[k], 1e-7), "gradient_mrp[%d] = %.17g, expected %.17g", k,
                gm.gradient[k], want[k]);
    for (std::size_t row = 0; row < 4; ++row) {
      chain_rule(&jq.jacobian[row * 14], dq1, dq2, want);
      for (std::size_t k = 0; k < 12; ++k)
        CHECK_MSG(close(jm(row, k), want[k], 1e-7), "jacobian_mrp(%zu, %zu) = %.17g, expected %.17g",
                  row, k, jm(row, k), want[k]);
    }
  }
  // At p = 0 (q = identity) dq/dp is 2 I on the vector part and 0 on w: check that directly.
  const dcol::Gradient g0 = dcol::gradient(box, dcol::pose(pos1), cap, dcol::pose(pos2));
  const dcol::GradientMrp m0 = dcol::gradient_mrp(box, pos1, zero, cap, pos2, zero);
  for (int k = 0; k < 3; ++k) {
    CHECK(close(m0.gradient[3 + k], 2.0 * g0.gradient[4 + k], 1e-7));
    CHECK(close(m0.gradient[9 + k], 2.0 * g0.gradient[11 + k], 1e-7));
    CHECK(close(m0.gradient[6 + k], g0.gradient[7 + k], 1e-7));
  }
  // The test is not vacuous: the attitude matters for a box and a capsule.
  CHECK(std::fabs(m0.gradient[3]) + std::fabs(m0.gradient[4]) + std::fabs(m0.gradient[5]) > 1e-3);

  const std::array<double, 3> bad = {{0, kNaN, 0}}, huge = {{1e200, 0, 0}};
  EXPECT_ERROR(dcol::gradient_mrp(box, pos1, bad, cap, pos2, zero), DCOL_ERROR_INVALID_POSE, "mrp1[1]");
  EXPECT_ERROR(dcol::jacobian_mrp(box, pos1, zero, cap, pos2, huge), DCOL_ERROR_INVALID_POSE, "mrp2");
  EXPECT_ERROR(dcol::jacobian_mrp(box, bad, zero, cap, pos2, zero), DCOL_ERROR_INVALID_POSE,
               "dcol_jacobian_mrp");
}

void test_batch() {
  std::vector<dcol::Shape> shapes;
  shapes.push_back(dcol::Shape::sphere(0.3));
  shapes.push_back(dcol::Shape::box(0.4, 0.3, 0.2));
  shapes.push_back(dcol::Shape::capsule(0.2, 0.8));
  shapes.push_back(dcol::Shape::cylinder(0.25, 0.6));
  shapes.push_back(dcol::Shape::cone(1.0, 0.5));
  shapes.push_back(dcol::Shape::ellipsoid({{4, 0, 0, 0, 1, 0, 0, 0, 2}}));
  const std::size_t n = 37;
  std::vector<const dcol::Shape *> a(n), b(n);
  std::vector<dcol_pose> pa(n), pb(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    a[i] = &shapes[i % shapes.size()];
    b[i] = &shapes[(i * 5 + 2) % shapes.size()];
    pa[i] = dcol::pose({0.1 * std::sin(t), 0.2 * std::cos(t), 0.0},
                       {{1.0, 0.1 * std::sin(2 * t), 0.2, -0.1 * t / n}});
    pb[i] = dcol::pose({0.3 + 0.05 * t, 0.3 * std::sin(t), 0.2 * std::cos(3 * t)},
                       {{0.7, 0.2, -0.3 * std::cos(t), 0.1}});
  }
  // Pair 5: a NaN pose; pair 11: a null shape; pair 20: a moved-from shape.
  pb[5].quaternion[2] = kNaN;
  a[11] = nullptr;
  dcol::Shape moved_to = dcol::Shape::sphere(0.2);
  dcol::Shape moved_from = dcol::Shape::sphere(0.2);
  moved_to = std::move(moved_from);
  b[20] = &moved_from;

  const std::uint32_t threads[] = {1, 3, 64};
  for (std::uint32_t th : threads) {
    const dcol::BatchResult r = dcol::proximity_batch(a, pa, b, pb, nullptr, th);
    CHECK(r.results.size() == n && r.statuses.size() == n);
    for (std::size_t i = 0; i < n; ++i) {
      if (i == 5) {
        CHECK(r.statuses[i] == DCOL_ERROR_INVALID_POSE && is_zero(r.results[i]));
      } else if (i == 11 || i == 20) {
        CHECK_MSG(r.statuses[i] == DCOL_ERROR_NULL_POINTER && is_zero(r.results[i]), "pair %zu", i);
      } else {
        CHECK_MSG(r.statuses[i] == DCOL_OK, "pair %zu status %d", i, static_cast<int>(r.statuses[i]));
        CHECK_MSG(same_result(r.results[i], dcol::proximity(*a[i], pa[i], *b[i], pb[i])),
                  "pair %zu, %u threads", i, th);
      }
    }
  }
  // Per-pair NOT_CONVERGED is returned with the last iterate, as the C call gives it.
  dcol_options one = dcol_options_default();
  one.max_iterations = 1;
  one.method = DCOL_METHOD_INTERIOR_POINT;  // the iteration limit is the interior-point solver's
  const dcol::BatchResult nc = dcol::proximity_batch(a, pa, b, pb, &one, 2);
  std::size_t not_converged = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (nc.statuses[i] != DCOL_ERROR_NOT_CONVERGED) continue;
    ++not_converged;
    dcol_proximity_result last;
    CHECK(dcol_proximity(a[i]->get(), &pa[i], b[i]->get(), &pb[i], &one, &last) ==
          DCOL_ERROR_NOT_CONVERGED);
    CHECK(same_result(nc.results[i], last));
  }
  CHECK(not_converged > 0);

  // Empty batch; whole-call failures throw.
  const dcol::BatchResult empty = dcol::proximity_batch({}, {}, {}, {});
  CHECK(empty.results.empty() && empty.statuses.empty());
  dcol_options o = dcol_options_default();
  o.tolerance = -1.0;
  EXPECT_ERROR(dcol::proximity_batch(a, pa, b, pb, &o), DCOL_ERROR_INVALID_OPTIONS,
               "dcol_proximity_batch");
  bool length_error = false;
  try {
    pb.pop_back();
    dcol::proximity_batch(a, pa, b, pb);
  } catch (const std::invalid_argument &) {
    length_error = true;
  }
  CHECK(length_error);
}

// Bodies of every kind scattered in a box; pairs_within against a brute-force loop.
void test_scene() {
  const std::size_t n = 24;
  std::vector<dcol_pose> poses(n);
  std::vector<dcol::Shape> kept;  // our own copies, for the brute force
  dcol::Scene scene;
  CHECK(scene.size() == 0);
  CHECK(scene.pairs_within(1.0).empty());
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    poses[i] = dcol::pose({1.7 * std::sin(1.3 * t), 1.5 * std::cos(0.7 * t), 0.4 * std::sin(2.1 * t)},
                          {{1.0, 0.3 * std::sin(t), 0.2 * std::cos(t), 0.1}});
    // A temporary shape destroyed right after add: the scene holds its own copy (ASan and
    // valgrind would catch a dangling pointer).
    const dcol::Shape s = i % 4 == 0   ? dcol::Shape::sphere(0.3)
                          : i % 4 == 1 ? dcol::Shape::box(0.3, 0.2, 0.25)
                          : i % 4 == 2 ? dcol::Shape::capsule(0.15, 0.5)
                                       : dcol::Shape::cylinder(0.2, 0.4);
    CHECK(scene.add(s, poses[i]) == i);
    kept.push_back(i % 4 == 0   ? dcol::Shape::sphere(0.3)
                   : i % 4 == 1 ? dcol::Shape::box(0.3, 0.2, 0.25)
                   : i % 4 == 2 ? dcol::Shape::capsule(0.15, 0.5)
                                : dcol::Shape::cylinder(0.2, 0.4));
  }
  CHECK(scene.size() == n);

  const double thresholds[] = {0.8, 1.0, 1.5, 3.0, 10.0};
  for (int step = 0; step < 2; ++step) {
    if (step == 1) {  // move every third body
      for (std::size_t i = 0; i < n; i += 3) {
        poses[i].position[0] += 0.4;
        poses[i].position[2] -= 0.3;
        scene.set_pose(i, poses[i]);
      }
    }
    for (double th : thresholds) {
      // The thresholds increase, so a step can report more pairs than the buffer (16 at first,
      // then the largest count so far) holds and take the retry path.
      dcol_scene_stats stats;
      const std::vector<dcol_scene_pair> got = scene.pairs_within(th, nullptr, &stats);
      CHECK(stats.pairs_total == n * (n - 1) / 2);
      CHECK(stats.reported == got.size());
      std::size_t k = 0, must = 0;
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
          dcol_proximity_result r;
          CHECK(dcol_proximity(kept[i].get(), &poses[i], kept[j].get(), &poses[j], nullptr, &r) ==
                DCOL_OK);
          const bool reported = k < got.size() && got[k].body1 == i && got[k].body2 == j;
          if (reported) {
            CHECK(got[k].status == DCOL_OK);
            CHECK_MSG(close_result(got[k].proximity, r), "pair (%zu, %zu)", i, j);
            ++k;
          }
          // Within 1e-6 of the threshold either answer is allowed.
          if (r.alpha < th - 1e-6) {
            ++must;
            CHECK_MSG(reported, "pair (%zu, %zu) alpha %.9g not reported at %g", i, j, r.alpha, th);
          } else if (r.alpha > th + 1e-6) {
            CHECK_MSG(!reported, "pair (%zu, %zu) alpha %.9g reported at %g", i, j, r.alpha, th);
          }
        }
      }
      CHECK_MSG(k == got.size(), "%zu of %zu reported pairs matched in order", k, got.size());
      if (th == 10.0) CHECK_MSG(must > 16, "only %zu pairs: the retry path is not exercised", must);
    }
  }

  // A fresh scene whose first step needs more than the initial buffer (all 24 bodies overlap).
  {
    dcol::Scene crowd;
    const dcol::Shape big = dcol::Shape::sphere(5.0);
    for (std::size_t i = 0; i < n; ++i) crowd.add(big, poses[i]);
    const std::vector<dcol_scene_pair> all = crowd.pairs_within(1.0);
    CHECK(all.size() == n * (n - 1) / 2);
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j, ++k)
        CHECK(k < all.size() && all[k].body1 == i && all[k].body2 == j);
  }

  // Errors: a bad threshold is an error (not mistaken for a too-small buffer), an unknown id, a
  // NaN pose, a negative radius; the scene is unchanged.
  EXPECT_ERROR(scene.pairs_within(-1.0), DCOL_ERROR_INVALID_OPTIONS, "threshold");
  EXPECT_ERROR(scene.pairs_within(kNaN), DCOL_ERROR_INVALID_OPTIONS, "threshold");
  dcol_options o = dcol_options_default();
  o.max_iterations = 0;
  EXPECT_ERROR(scene.pairs_within(1.0, &o), DCOL_ERROR_INVALID_OPTIONS, "dcol_scene_pairs_within");
  EXPECT_ERROR(scene.set_pose(n, poses[0]), DCOL_ERROR_INVALID_OPTIONS, "dcol_scene_set_pose");
  dcol_pose bad = poses[0];
  bad.position[0] = kNaN;
  EXPECT_ERROR(scene.set_pose(0, bad), DCOL_ERROR_INVALID_POSE, "dcol_scene_set_pose");
  EXPECT_ERROR(scene.add(kept[0], bad), DCOL_ERROR_INVALID_POSE, "dcol_scene_add");
  EXPECT_ERROR(scene.add(dcol::Shape::sphere(-1.0), poses[0]), DCOL_ERROR_INVALID_SHAPE,
               "dcol_shape_new_sphere");
  CHECK(scene.size() == n);

  // Moves: the new owner works, the moved-from scene throws NULL_POINTER.
  dcol::Scene other = std::move(scene);
  CHECK(other.size() == n);
  CHECK(scene.get() == nullptr);
  EXPECT_ERROR(scene.size(), DCOL_ERROR_NULL_POINTER, "dcol_scene_size");
  EXPECT_ERROR(scene.pairs_within(1.0), DCOL_ERROR_NULL_POINTER, "dcol_scene_pairs_within");
  scene = std::move(other);  // move-assign back (into the empty one)
  CHECK(scene.size() == n);
}

// dcol::contacts: a cube resting 0.01 deep on a wider box gives its four bottom corners.
void test_contacts() {
  const dcol::Shape ground = dcol::Shape::box(1.0, 1.0, 0.5);
  const dcol::Shape cube = dcol::Shape::box(0.5, 0.5, 0.5);
  const std::vector<dcol_contact> cs =
      dcol::contacts(ground, dcol::pose({0, 0, 0}), cube, dcol::pose({0, 0, 0.99}), 0.0);
  CHECK(cs.size() == 4);
  for (const dcol_contact &c : cs) {
    CHECK(close(c.depth, 0.01, 1e-12));
    CHECK(close(c.normal[2], 1.0, 1e-12));
    CHECK(close(std::fabs(c.position[0]), 0.5, 1e-12));
    CHECK(close(c.position[2], 0.495, 1e-12));
  }
  CHECK(dcol::contacts(ground, dcol::pose({0, 0, 0}), cube, dcol::pose({0, 0, 0.99}), 0.0, nullptr, 2)
            .size() == 2);
  CHECK(dcol::contacts(ground, dcol::pose({0, 0, 0}), cube, dcol::pose({0, 0, 3.0}), 0.1).empty());
  EXPECT_ERROR(dcol::contacts(ground, dcol::pose({0, 0, 0}), cube, dcol::pose({0, 0, 1}), kNaN),
               DCOL_ERROR_INVALID_OPTIONS, "dcol_contacts");
}

// A half-space floor (top surface z = 0): the same cube resting on it, and the errors.
void test_halfspace() {
  const dcol::Shape floor_ = dcol::Shape::halfspace(0.5);
  const dcol::Shape cube = dcol::Shape::box(0.5, 0.5, 0.5);
  const std::vector<dcol_contact> cs =
      dcol::contacts(floor_, dcol::pose({0, 0, -0.5}), cube, dcol::pose({0, 0, 0.49}), 0.0);
  CHECK(cs.size() == 4);
  for (const dcol_contact &c : cs) {
    CHECK(close(c.depth, 0.01, 1e-12));
    CHECK(close(c.normal[2], 1.0, 1e-12));
    CHECK(close(c.position[2], -0.005, 1e-12));
  }
  const dcol_proximity_result r = dcol::proximity(floor_, dcol::pose({0, 0, -0.5}), cube, dcol::pose({0, 0, 0.49}));
  CHECK(close(r.alpha, 0.99 / 1.0, 1e-15));  // (0.49 + 0.5) / (0.5 + 0.5)
  EXPECT_ERROR(dcol::Shape::halfspace(0.0), DCOL_ERROR_INVALID_SHAPE, "dcol_shape_new_halfspace");
  EXPECT_ERROR(dcol::proximity(floor_, dcol::pose({0, 0, 0}), floor_, dcol::pose({0, 0, 1})),
               DCOL_ERROR_INVALID_SHAPE, "dcol_proximity");
}

// A rounded cube as a hull of its corners padded by 0.1, on a floor: four contacts at the
// padded face's corners (the padding moves the face down by 0.1), alpha* against a sphere.
void test_convex_hull() {
  std::vector<std::array<double, 3>> corners;
  for (int i = 0; i < 8; ++i)
    corners.push_back({{(i & 1) ? 0.4 : -0.4, (i & 2) ? 0.4 : -0.4, (i & 4) ? 0.4 : -0.4}});
  corners.push_back({{0.0, 0.0, 0.0}});  // an interior point changes nothing
  const dcol::Shape rounded = dcol::Shape::convex_hull(corners, 0.1);
  const dcol::Shape floor_ = dcol::Shape::halfspace(1.0);
  const std::vector<dcol_contact> cs =
      dcol::contacts(floor_, dcol::pose({0, 0, -1.0}), rounded, dcol::pose({0, 0, 0.49}), 0.0);
  CHECK(cs.size() == 4);
  for (const dcol_contact &c : cs) {
    CHECK(close(c.depth, 0.01, 1e-12));
    CHECK(close(std::fabs(c.position[0]), 0.4, 1e-12) && close(std::fabs(c.position[1]), 0.4, 1e-12));
  }
  const dcol::Shape ball = dcol::Shape::sphere(0.5);
  const dcol_proximity_result r = dcol::proximity(rounded, dcol::pose({0, 0, 0}), ball, dcol::pose({0, 3.0, 0}));
  CHECK(close(r.alpha, 3.0 / 1.0, 1e-13));  // 3 / (0.4 + 0.1 + 0.5)
  std::vector<std::array<double, 3>> off = corners;
  for (auto &c : off) c[2] += 2.0;
  EXPECT_ERROR(dcol::Shape::convex_hull(off), DCOL_ERROR_INVALID_SHAPE, "dcol_shape_new_convex_hull");
  EXPECT_ERROR(dcol::Shape::convex_hull({}), DCOL_ERROR_INVALID_SHAPE, "dcol_shape_new_convex_hull");
}

// dcol::Shape::parameters and the shape gradients: the C functions' answers, by value.
void test_shape_gradient() {
  const dcol::Shape ball = dcol::Shape::sphere(0.7);
  const dcol::Shape box = dcol::Shape::box(0.5, 0.8, 0.3);
  CHECK(ball.parameter_count() == 1 && box.parameter_count() == 3);
  const std::vector<double> p = box.parameters();
  CHECK(p.size() == 3 && p[0] == 0.5 && p[1] == 0.8 && p[2] == 0.3);
  const dcol_pose p1 = dcol::pose({0, 0, 0}), p2 = dcol::pose({2.4, 0.1, -0.05});
  const dcol::ShapeGradient g = dcol::shape_gradient(ball, p1, box, p2);
  CHECK(close(g.result.alpha, 2.0, 1e-12) && g.result.derivatives == DCOL_DERIVATIVES_EXACT);
  CHECK(g.d_shape1.size() == 1 && g.d_shape2.size() == 3);
  CHECK(close(g.d_shape1[0], -2.0 / 1.2, 1e-12) && close(g.d_shape2[0], -2.0 / 1.2, 1e-12));
  std::vector<double> c1(1), c2(3);
  dcol_proximity_result r;
  CHECK(dcol_shape_gradient(ball.get(), &p1, box.get(), &p2, nullptr, &r, c1.data(), c2.data()) ==
        DCOL_OK);
  CHECK(same_bits(c1.data(), g.d_shape1.data(), 1) && same_bits(c2.data(), g.d_shape2.data(), 3));
  const dcol::DistanceShapeGradient d = dcol::distance_shape_gradient(ball, p1, box, p2);
  CHECK(close(d.result.distance, 1.2, 1e-9) && close(d.d_shape1[0], -1.0, 1e-9) &&
        close(d.d_shape2[0], -1.0, 1e-9));
  const dcol::SignedDistanceShapeGradient s =
      dcol::signed_distance_shape_gradient(ball, p1, box, dcol::pose({1.0, 0, 0}));
  CHECK(close(s.result.distance, -0.2, 1e-9) && close(s.d_shape1[0], -1.0, 1e-9));
  const dcol::Shape floor_ = dcol::Shape::halfspace(0.5);
  const dcol::Shape other = dcol::Shape::halfspace(1.0);
  EXPECT_ERROR(dcol::shape_gradient(floor_, p1, other, p2), DCOL_ERROR_INVALID_SHAPE,
               "dcol_shape_gradient");
  dcol::Shape moved = dcol::Shape::sphere(1.0);
  const dcol::Shape taken = std::move(moved);
  CHECK(moved.parameter_count() == 0 && taken.parameter_count() == 1);
  EXPECT_ERROR(moved.parameters(), DCOL_ERROR_NULL_POINTER, "dcol_shape_parameters");
  EXPECT_ERROR(dcol::shape_gradient(moved, p1, box, p2), DCOL_ERROR_NULL_POINTER,
               "dcol_shape_gradient");
}

// dcol::Cache and the *_cached calls: the C functions' answers, by value, bit for bit.
void test_cached() {
  const dcol::Shape a = dcol::Shape::box(0.5, 0.35, 0.25);
  const dcol::Shape b = dcol::Shape::box(0.3, 0.3, 0.3);
  dcol::Cache cache, c_cache, i_cache;
  dcol_cache raw = DCOL_CACHE_INIT, i_raw = DCOL_CACHE_INIT;
  int overlapping = 0;
  for (int k = 0; k < 50; ++k) {
    const dcol_pose p1 = dcol::pose({0, 0, 0}, {{1.0, 0.01 * k, 0.2, 0.0}});
    const dcol_pose p2 = dcol::pose({1.0 - 1e-3 * k, 0.1, 0.05}, {{1.0, 0.0, 0.3, 0.01 * k}});
    const dcol_proximity_result w = dcol::proximity_cached(a, p1, b, p2, cache);
    dcol_proximity_result c;
    CHECK(dcol_proximity_cached(a.get(), &p1, b.get(), &p2, nullptr, &raw, &c) == DCOL_OK);
    CHECK(same_result(w, c));
    const dcol_proximity_result cold = dcol::proximity(a, p1, b, p2);
    CHECK(close(w.alpha, cold.alpha, 1e-12));
    const dcol::DistanceGradient d = dcol::distance_gradient_cached(a, p1, b, p2, c_cache);
    CHECK(close(d.result.distance, dcol::distance(a, p1, b, p2).distance, 1e-12));
    const bool x = dcol::intersect_cached(a, p1, b, p2, i_cache);
    std::int32_t xc = -1;
    CHECK(dcol_intersect_cached(a.get(), &p1, b.get(), &p2, nullptr, &i_raw, &xc) == DCOL_OK);
    CHECK(x == (xc != 0));
    CHECK(x == dcol::intersect(a, p1, b, p2));
    overlapping += x ? 1 : 0;
  }
  // The poses cross alpha* = 1: both decisions are exercised.
  CHECK(overlapping > 0 && overlapping < 50);
  cache.clear();
  CHECK(std::memcmp(cache.get(), dcol::Cache().get(), sizeof(dcol_cache)) == 0);
}

}  // namespace

int main() {
  try {
    test_alpha_below_intersect();
    test_distance_gradient();
    test_derivatives();
    test_mrp();
    test_batch();
    test_scene();
    test_contacts();
    test_halfspace();
    test_convex_hull();
    test_shape_gradient();
    test_cached();
  } catch (const std::exception &e) {
    std::fprintf(stderr, "unexpected exception: %s\n", e.what());
    return 1;
  }
  return check_summary("cpp_wrapper");
}
