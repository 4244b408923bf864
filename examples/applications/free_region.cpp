// A convex free region for motion planning (as IRIS and graphs of convex sets grow them): the
// largest-volume ellipsoid around a seed point in a room of 15 fixed obstacles (the room's six
// walls, a table and eight obstacles: two cylinders, two capsules, two cones, two rocks given
// as convex hulls of points, one padded).
//
// The ellipsoid is E = { c + L u : |u| <= 1 } with L lower triangular (positive diagonal), so
// its matrix is P = (L L^T)^-1 (x^T P x <= 1 about c) and its volume (4 pi / 3) det L. The
// decision variables are L's six entries and the centre c; Ipopt maximises log det L =
// sum log L_ii subject to
//   alpha*(E, obstacle j) >= 1 for every obstacle (the ellipsoid and the obstacle, both scaled
//     about their origins, touch no sooner than at scale 1: E avoids the obstacle), and
//   |L^-1 (s - c)| <= 1 (the seed s stays inside E).
// The constraint Jacobian is dcol's: dcol_shape_gradient gives d alpha* / dP (nine entries),
// chained through P = (L L^T)^-1 as d alpha* / dL = -2 P G P L; dcol_gradient gives
// d alpha* / dc (the ellipsoid's position). At start-up the chained Jacobian is compared with
// central differences of alpha* through the constructor, and the run stops if they differ by
// more than 1e-6.
//
// A sanity bound: the best of 200 random ellipsoids about the seed (random orientation and
// axis ratios), each scaled up until it touches an obstacle (bisection on the smallest
// alpha*): a feasible region found by sampling, whose volume the optimum must exceed.
//
// Usage: free_region [out.csv]   (default free_region.csv in the current directory)
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app_common.hpp"

namespace {

const double kPi = 3.14159265358979323846;

struct Obstacle {
  app::Shape shape;
  dcol_pose pose;
  std::string csv;  // "type x y z qw qx qy qz parameters" for the plot
};

using Mat3 = std::array<std::array<double, 3>, 3>;

/// The lower-triangular L from the six variables (L00, L10, L11, L20, L21, L22).
Mat3 lower(const double *x) {
  return {{{x[0], 0, 0}, {x[1], x[2], 0}, {x[3], x[4], x[5]}}};
}
const int kRow[6] = {0, 1, 1, 2, 2, 2}, kCol[6] = {0, 0, 1, 0, 1, 2};

/// The inverse of a lower-triangular matrix (forward substitution).
Mat3 lower_inverse(const Mat3 &L) {
  Mat3 M{};
  for (int j = 0; j < 3; ++j) {
    M[j][j] = 1.0 / L[j][j];
    for (int i = j + 1; i < 3; ++i) {
      double s = 0.0;
      for (int k = j; k < i; ++k) s += L[i][k] * M[k][j];
      M[i][j] = -s / L[i][i];
    }
  }
  return M;
}

Mat3 mul(const Mat3 &A, const Mat3 &B) {
  Mat3 C{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) C[i][j] += A[i][k] * B[k][j];
  return C;
}

/// The ellipsoid of the variables x (L, then c): its shape and pose, and P.
struct Region {
  app::Shape shape;
  dcol_pose pose;
  Mat3 P, Linv;
};

Region region(const double *x) {
  const Mat3 Linv = lower_inverse(lower(x));
  Mat3 P{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) P[i][j] += Linv[k][i] * Linv[k][j];  // L^-T L^-1, symmetric
  const double flat[9] = {P[0][0], P[0][1], P[0][2], P[1][0], P[1][1],
                          P[1][2], P[2][0], P[2][1], P[2][2]};
  dcol_shape *s = nullptr;
  app::check(dcol_shape_new_ellipsoid(flat, &s), "ellipsoid");
  return Region{app::Shape(s), app::make_pose(x[6], x[7], x[8]), P, Linv};
}

/// alpha*(E(x), obstacle) and its gradient with respect to the nine variables.
double alpha_and_gradient(const double *x, const Obstacle &o, double grad[9]) {
  const Region e = region(x);
  double G9[9], g14[14];
  const double alpha =
      app::shape_gradient(e.shape.get(), e.pose, o.shape.get(), o.pose, G9, nullptr);
  app::gradient(e.shape.get(), e.pose, o.shape.get(), o.pose, g14);
  // d alpha / dL = -2 P G P L (G symmetric: the derivative with respect to each entry of P).
  const Mat3 G = {{{G9[0], G9[1], G9[2]}, {G9[3], G9[4], G9[5]}, {G9[6], G9[7], G9[8]}}};
  const Mat3 D = mul(mul(mul(e.P, G), e.P), lower(x));
  for (int v = 0; v < 6; ++v) grad[v] = -2.0 * D[kRow[v]][kCol[v]];
  for (int i = 0; i < 3; ++i) grad[6 + i] = g14[i];
  return alpha;
}

double alpha_only(const double *x, const Obstacle &o) {
  const Region e = region(x);
  return app::proximity(e.shape.get(), e.pose, o.shape.get(), o.pose);
}

double volume(const double *x) { return 4.0 / 3.0 * kPi * x[0] * x[2] * x[5]; }

class RegionNlp : public Ipopt::TNLP {
 public:
  /// `fixed`: the centre held at the seed (by its bounds).
  RegionNlp(const std::vector<Obstacle> &obs, const std::array<double, 3> &seed,
            const std::array<double, 9> &x0, bool fixed)
      : obs_(obs), seed_(seed), x0_(x0), fixed_(fixed) {}
  std::vector<double> solution;
  /// (Ipopt iteration, volume, primal infeasibility) at every iteration.
  std::vector<std::array<double, 3>> history;

  bool get_nlp_info(Ipopt::Index &n, Ipopt::Index &m, Ipopt::Index &nnz_jac_g,
                    Ipopt::Index &nnz_h_lag, IndexStyleEnum &index_style) override {
    n = 9;
    m = static_cast<Ipopt::Index>(obs_.size()) + 1;
    nnz_jac_g = 9 * m;
    nnz_h_lag = 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number *x_l, Ipopt::Number *x_u, Ipopt::Index m,
                       Ipopt::Number *g_l, Ipopt::Number *g_u) override {
    for (int k = 0; k < n; ++k) {
      x_l[k] = -1e19;
      x_u[k] = 1e19;
    }
    for (int k : {0, 2, 5}) x_l[k] = 1e-3;  // the diagonal of L
    if (fixed_)
      for (int i = 0; i < 3; ++i) x_l[6 + i] = x_u[6 + i] = seed_[static_cast<size_t>(i)];
    for (int c = 0; c + 1 < m; ++c) {
      g_l[c] = 1.0;
      g_u[c] = 1e19;
    }
    g_l[m - 1] = -1e19;
    g_u[m - 1] = 1.0;
    return true;
  }

  bool get_starting_point(Ipopt::Index, bool init_x, Ipopt::Number *x, bool init_z,
                          Ipopt::Number *, Ipopt::Number *, Ipopt::Index, bool init_lambda,
                          Ipopt::Number *) override {
    if (!init_x || init_z || init_lambda) return false;
    for (int k = 0; k < 9; ++k) x[k] = x0_[k];
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number *x, bool, Ipopt::Number &f) override {
    f = -(std::log(x[0]) + std::log(x[2]) + std::log(x[5]));
    return true;
  }

  bool eval_grad_f(Ipopt::Index, const Ipopt::Number *x, bool, Ipopt::Number *g) override {
    for (int k = 0; k < 9; ++k) g[k] = 0.0;
    g[0] = -1.0 / x[0];
    g[2] = -1.0 / x[2];
    g[5] = -1.0 / x[5];
    return true;
  }

  bool eval_g(Ipopt::Index, const Ipopt::Number *x, bool new_x, Ipopt::Index,
              Ipopt::Number *g) override {
    if (new_x || !cached_) update(x);
    for (size_t c = 0; c < value_.size(); ++c) g[c] = value_[c];
    return true;
  }

  bool eval_jac_g(Ipopt::Index, const Ipopt::Number *x, bool new_x, Ipopt::Index m,
                  Ipopt::Index, Ipopt::Index *iRow, Ipopt::Index *jCol,
                  Ipopt::Number *values) override {
    if (values == nullptr) {
      for (int c = 0, e = 0; c < m; ++c)
        for (int k = 0; k < 9; ++k, ++e) {
          iRow[e] = c;
          jCol[e] = k;
        }
      return true;
    }
    if (new_x || !cached_) update(x);
    for (size_t e = 0; e < jac_.size(); ++e) values[e] = jac_[e];
    return true;
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index iter, Ipopt::Number obj,
                             Ipopt::Number inf_pr, Ipopt::Number, Ipopt::Number, Ipopt::Number,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Index,
                             const Ipopt::IpoptData *, Ipopt::IpoptCalculatedQuantities *) override {
    history.push_back({static_cast<double>(iter), 4.0 / 3.0 * kPi * std::exp(-obj), inf_pr});
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number *x,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Index,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Number,
                         const Ipopt::IpoptData *, Ipopt::IpoptCalculatedQuantities *) override {
    solution.assign(x, x + n);
  }

  /// Every constraint and its Jacobian row at x.
  void update(const double *x) {
    const size_t m = obs_.size() + 1;
    value_.assign(m, 0.0);
    jac_.assign(9 * m, 0.0);
    for (size_t j = 0; j < obs_.size(); ++j) value_[j] = alpha_and_gradient(x, obs_[j], &jac_[9 * j]);
    // The seed: |w|^2 <= 1 with w = L^-1 (s - c).
    const Mat3 Linv = lower_inverse(lower(x));
    double w[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) w[i] += Linv[i][k] * (seed_[k] - x[6 + k]);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) v[i] += Linv[k][i] * w[k];  // L^-T w
    double *row = &jac_[9 * obs_.size()];
    value_[m - 1] = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    for (int e = 0; e < 6; ++e) row[e] = -2.0 * v[kRow[e]] * w[kCol[e]];
    for (int i = 0; i < 3; ++i) row[6 + i] = -2.0 * v[i];
    cached_ = true;
  }

 private:
  const std::vector<Obstacle> &obs_;
  std::array<double, 3> seed_;
  std::array<double, 9> x0_;
  bool fixed_;
  std::vector<double> value_, jac_;
  bool cached_ = false;
};

/// A quaternion turning body x onto the world direction (a, b, c) (unit), about their cross.
dcol_pose axis_pose(double x, double y, double z, double a, double b, double c) {
  const double d = std::sqrt(a * a + b * b + c * c);
  a /= d;
  b /= d;
  c /= d;
  // q = [1 + a, (0, -c, b)] normalised: the half-way rotation from e_x to (a, b, c).
  double q[4] = {1.0 + a, 0.0, -c, b};
  if (q[0] < 1e-12) q[0] = 0.0, q[1] = 0.0, q[2] = 0.0, q[3] = 1.0;  // (a, b, c) = -e_x
  app::quat_normalize(q);
  return app::make_pose(x, y, z, q[0], q[1], q[2], q[3]);
}

std::string pose_csv(const dcol_pose &p) {
  char s[160];
  std::snprintf(s, sizeof s, "%.9g %.9g %.9g %.9g %.9g %.9g %.9g", p.position[0], p.position[1],
                p.position[2], p.quaternion[0], p.quaternion[1], p.quaternion[2], p.quaternion[3]);
  return s;
}

Obstacle box(double x, double y, double z, double a, double b, double c) {
  const dcol_pose p = app::make_pose(x, y, z);
  char s[96];
  std::snprintf(s, sizeof s, " %g %g %g", a, b, c);
  return Obstacle{app::make_box(a, b, c), p, "box " + pose_csv(p) + s};
}

Obstacle revolved(const char *kind, const dcol_pose &p, double r_or_h, double l_or_beta) {
  char s[96];
  std::snprintf(s, sizeof s, " %.9g %.9g", r_or_h, l_or_beta);
  const std::string k(kind);
  app::Shape shape = k == "cylinder"  ? app::make_cylinder(r_or_h, l_or_beta)
                     : k == "capsule" ? app::make_capsule(r_or_h, l_or_beta)
                                      : app::make_cone(r_or_h, l_or_beta);
  return Obstacle{std::move(shape), p, k + " " + pose_csv(p) + s};
}

/// A rock: the hull of points on a lumpy sphere of radius `size` (deterministic), padded by `r`.
Obstacle rock(const dcol_pose &p, double size, double r, unsigned long long seed) {
  std::vector<double> pts;
  for (int k = 0; k < 14; ++k) {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    const double u = static_cast<double>(seed >> 11) / 9007199254740992.0;
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    const double v = static_cast<double>(seed >> 11) / 9007199254740992.0;
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    const double w = static_cast<double>(seed >> 11) / 9007199254740992.0;
    const double zc = 2.0 * u - 1.0, ph = 2.0 * kPi * v, rad = size * (0.7 + 0.5 * w);
    const double rc = std::sqrt(std::fmax(0.0, 1.0 - zc * zc));
    pts.push_back(rad * rc * std::cos(ph));
    pts.push_back(rad * rc * std::sin(ph));
    pts.push_back(0.6 * rad * zc);  // flattened
  }
  // About the points' mean (the origin must lie inside the hull).
  double mean[3] = {0, 0, 0};
  for (size_t i = 0; i < pts.size(); ++i) mean[i % 3] += pts[i] / 14.0;
  for (size_t i = 0; i < pts.size(); ++i) pts[i] -= mean[i % 3];
  std::string s = "hull " + pose_csv(p);
  char buf[64];
  std::snprintf(buf, sizeof buf, " %g 14", r);
  s += buf;
  for (double v : pts) {
    std::snprintf(buf, sizeof buf, " %.9g", v);
    s += buf;
  }
  return Obstacle{app::make_hull(pts.data(), 14, r), p, s};
}

std::vector<Obstacle> scene() {
  std::vector<Obstacle> o;
  // The room: x, y in [-2, 2], z in [0, 2.5], walls 0.1 thick.
  o.push_back(box(0, 0, -0.05, 2.1, 2.1, 0.05));   // floor
  o.push_back(box(0, 0, 2.55, 2.1, 2.1, 0.05));    // ceiling
  o.push_back(box(2.05, 0, 1.25, 0.05, 2.1, 1.3));  // walls
  o.push_back(box(-2.05, 0, 1.25, 0.05, 2.1, 1.3));
  o.push_back(box(0, 2.05, 1.25, 2.1, 0.05, 1.3));
  o.push_back(box(0, -2.05, 1.25, 2.1, 0.05, 1.3));
  o.push_back(box(1.2, -1.3, 0.75, 0.5, 0.35, 0.04));  // a table top
  o.push_back(revolved("cylinder", axis_pose(0.9, 0.7, 1.25, 0, 0, 1), 0.25, 2.5));  // a pillar
  o.push_back(revolved("cylinder", axis_pose(-1.0, -0.9, 0.3, 0.3, 1, 0), 0.3, 1.6));  // a log
  o.push_back(revolved("capsule", axis_pose(0.2, -1.0, 1.9, 1, 0.4, 0.3), 0.2, 1.4));
  o.push_back(revolved("capsule", axis_pose(-1.1, 0.9, 1.2, 0.2, -0.3, 1), 0.15, 1.2));
  o.push_back(revolved("cone", axis_pose(1.0, -0.4, 0.45, 0, 0, -1), 0.9, 0.45));  // apex up
  o.push_back(revolved("cone", axis_pose(-0.7, 0.2, 2.05, 0, 0, 1), 0.8, 0.5));    // apex down
  o.push_back(rock(app::make_pose(0.4, 1.3, 0.3), 0.35, 0.0, 11));
  o.push_back(rock(app::make_pose(-0.4, -0.3, 0.2), 0.3, 0.05, 29));
  return o;
}

double min_alpha(const double *x, const std::vector<Obstacle> &obs) {
  double m = 1e300;
  for (const Obstacle &o : obs) m = std::fmin(m, alpha_only(x, o));
  return m;
}

/// The best of `count` random ellipsoids about the seed, each scaled (bisection) until it
/// touches: its variables and volume.
std::array<double, 9> sampled_region(const std::vector<Obstacle> &obs,
                                     const std::array<double, 3> &seed, int count) {
  unsigned long long state = 0x5EEDull;
  auto unif = [&]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  std::array<double, 9> best{};
  double best_volume = 0.0;
  for (int s = 0; s < count; ++s) {
    // A random rotation R (quaternion from four normals) and semi-axes, L = R diag(a) as the
    // lower-triangular factor of R diag(a^2) R^T (the same ellipsoid).
    double q[4];
    for (double &c : q) c = std::sqrt(-2.0 * std::log(1.0 - unif())) * std::cos(2 * kPi * unif());
    app::quat_normalize(q);
    const double a[3] = {std::exp(2.0 * unif() - 1.0), std::exp(2.0 * unif() - 1.0),
                         std::exp(2.0 * unif() - 1.0)};
    double R[3][3];
    for (int j = 0; j < 3; ++j) {
      const double e[3] = {j == 0 ? 1.0 : 0.0, j == 1 ? 1.0 : 0.0, j == 2 ? 1.0 : 0.0};
      double col[3];
      app::quat_rotate(q, e, col);
      for (int i = 0; i < 3; ++i) R[i][j] = col[i];
    }
    double S[3][3];  // R diag(a^2) R^T
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        S[i][j] = 0.0;
        for (int k = 0; k < 3; ++k) S[i][j] += R[i][k] * a[k] * a[k] * R[j][k];
      }
    // Cholesky S = L L^T.
    double L[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j <= i; ++j) {
        double v = S[i][j];
        for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
        L[i][j] = i == j ? std::sqrt(v) : v / L[j][j];
      }
    auto vars = [&](double t) {
      return std::array<double, 9>{t * L[0][0], t * L[1][0], t * L[1][1], t * L[2][0],
                                   t * L[2][1], t * L[2][2], seed[0], seed[1], seed[2]};
    };
    double lo = 0.0, hi = 0.05;
    while (min_alpha(vars(hi).data(), obs) >= 1.0 && hi < 100.0) {
      lo = hi;
      hi *= 2.0;
    }
    if (lo == 0.0) continue;  // the smallest trial already touches (the seed is free, so rare)
    for (int it = 0; it < 30; ++it) {
      const double mid = 0.5 * (lo + hi);
      (min_alpha(vars(mid).data(), obs) >= 1.0 ? lo : hi) = mid;
    }
    const std::array<double, 9> x = vars(lo);
    if (volume(x.data()) > best_volume) {
      best_volume = volume(x.data());
      best = x;
    }
  }
  return best;
}

/// The chained Jacobian against central differences of alpha* at x; the largest relative error.
double check_jacobian(const std::array<double, 9> &x, const std::vector<Obstacle> &obs) {
  double worst = 0.0;
  for (const Obstacle &o : obs) {
    double g[9];
    alpha_and_gradient(x.data(), o, g);
    for (int k = 0; k < 9; ++k) {
      const double h = 1e-6;
      std::array<double, 9> up = x, down = x;
      up[k] += h;
      down[k] -= h;
      const double fd = (alpha_only(up.data(), o) - alpha_only(down.data(), o)) / (2 * h);
      worst = std::fmax(worst, std::fabs(fd - g[k]) / std::fmax(1.0, std::fabs(fd)));
    }
  }
  return worst;
}

struct Solved {
  std::array<double, 9> x{};
  std::vector<std::array<double, 3>> history;
  bool ok = false;
};

/// Ipopt from x0 (limited-memory Hessian), every constraint re-checked with dcol_proximity at
/// the answer; prints the summary line of the run.
Solved solve(const std::vector<Obstacle> &obs, const std::array<double, 3> &seed,
             const std::array<double, 9> &x0, bool fixed) {
  const char *name = fixed ? "free_region (centre at the seed)" : "free_region";
  app::dcol_clock() = app::DcolClock{};
  Ipopt::SmartPtr<RegionNlp> nlp = new RegionNlp(obs, seed, x0, fixed);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> ipopt = IpoptApplicationFactory();
  ipopt->Options()->SetStringValue("hessian_approximation", "limited-memory");
  ipopt->Options()->SetNumericValue("tol", 1e-8);
  ipopt->Options()->SetNumericValue("constr_viol_tol", 1e-10);
  ipopt->Options()->SetNumericValue("bound_relax_factor", 0.0);
  ipopt->Options()->SetIntegerValue("max_iter", 500);
  ipopt->Options()->SetIntegerValue("print_level", fixed ? 0 : 4);
  ipopt->Options()->SetStringValue("sb", "yes");
  if (ipopt->Initialize() != Ipopt::Solve_Succeeded) throw std::runtime_error("Ipopt: init failed");
  const app::Clock::time_point t0 = app::Clock::now();
  const Ipopt::ApplicationReturnStatus status = ipopt->OptimizeTNLP(nlp);
  const double wall = app::seconds_since(t0);
  long iterations = 0;
  if (Ipopt::IsValid(ipopt->Statistics())) iterations = ipopt->Statistics()->IterationCount();
  Solved r;
  for (int k = 0; k < 9; ++k) r.x[k] = nlp->solution[static_cast<size_t>(k)];
  r.history = nlp->history;
  std::printf("%s: Ipopt status %s after %ld iterations\n", name,
              status == Ipopt::Solve_Succeeded ? "Solve_Succeeded" : "not Solve_Succeeded",
              iterations);
  app::print_timing(name, iterations, wall);
  double worst = 1e300;
  for (const Obstacle &o : obs) worst = std::fmin(worst, alpha_only(r.x.data(), o));
  std::printf("%s: volume %.6f m^3, min alpha* %.12f\n", name, volume(r.x.data()), worst);
  r.ok = status == Ipopt::Solve_Succeeded && worst >= 1.0 - 1e-8;
  return r;
}

void write_region(std::FILE *f, const char *tag, const std::array<double, 9> &x) {
  std::fprintf(f, "# %s %.9g %.9g %.9g", tag, x[6], x[7], x[8]);
  for (int k = 0; k < 6; ++k) std::fprintf(f, " %.9g", x[k]);
  std::fprintf(f, "\n");
}

}  // namespace

int main(int argc, char **argv) {
  try {
    const std::vector<Obstacle> obs = scene();
    const std::array<double, 3> seed = {0.1, 0.0, 1.2};
    const std::array<double, 9> x0 = {0.1, 0, 0.1, 0, 0, 0.1, seed[0], seed[1], seed[2]};
    if (min_alpha(x0.data(), obs) < 1.0) throw std::runtime_error("the start touches an obstacle");

    // The chained Jacobian against central differences, at a general ellipsoid near the seed.
    const std::array<double, 9> probe = {0.45, 0.12, 0.3, -0.08, 0.05, 0.25, 0.15, 0.05, 1.15};
    const double jac_err = check_jacobian(probe, obs);
    std::printf("free_region: Jacobian (dcol_shape_gradient chained through P = (L L^T)^-1, and "
                "dcol_gradient) against central differences: largest error %.1e\n",
                jac_err);
    if (!(jac_err < 1e-6)) throw std::runtime_error("the chained Jacobian disagrees");

    // The region about the seed (centre free), then with its centre held at the seed.
    const Solved free = solve(obs, seed, x0, false);
    const Solved held = solve(obs, seed, x0, true);
    const std::array<double, 9> &x = free.x;
    // Every constraint at the answer, re-evaluated with dcol_proximity.
    double worst = 1e300;
    int touching = 0;
    for (const Obstacle &o : obs) {
      const double a = alpha_only(x.data(), o);
      worst = std::fmin(worst, a);
      if (a < 1.0 + 1e-6) ++touching;
    }
    double w[3] = {0, 0, 0};
    const Mat3 Linv = lower_inverse(lower(x.data()));
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) w[i] += Linv[i][k] * (seed[static_cast<size_t>(k)] - x[6 + k]);
    const double seed_gauge = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    std::printf("free_region: volume %.6f m^3 (det L = %.6f), centre (%.4f, %.4f, %.4f); min "
                "alpha* over the %zu obstacles %.12f (must be >= 1 - 1e-8), %d touching (within "
                "1e-6); the seed at gauge %.4f of the region\n",
                volume(x.data()), x[0] * x[2] * x[5], x[6], x[7], x[8], obs.size(), worst,
                touching, seed_gauge);

    const app::Clock::time_point t1 = app::Clock::now();
    const std::array<double, 9> sampled = sampled_region(obs, seed, 200);
    std::printf("free_region: sampling bound: the best of 200 random ellipsoids centred at the "
                "seed, each grown until it touches: volume %.6f m^3 (%.2f s); the optimum centred "
                "at the seed is %.2f times that, the optimum about it %.2f times\n",
                volume(sampled.data()), app::seconds_since(t1),
                volume(held.x.data()) / volume(sampled.data()),
                volume(x.data()) / volume(sampled.data()));

    app::Csv csv(argc, argv, "free_region.csv");
    for (const Obstacle &o : obs) std::fprintf(csv.f, "# obstacle %s\n", o.csv.c_str());
    std::fprintf(csv.f, "# seed %.9g %.9g %.9g\n", seed[0], seed[1], seed[2]);
    write_region(csv.f, "region", x);
    write_region(csv.f, "held", held.x);
    write_region(csv.f, "sampled", sampled);
    {
      // Each obstacle's alpha* against the region and the contact point on the region.
      const Region e = region(x.data());
      for (size_t j = 0; j < obs.size(); ++j) {
        dcol_proximity_result r;
        app::check(dcol_proximity(e.shape.get(), &e.pose, obs[j].shape.get(), &obs[j].pose,
                                  nullptr, &r),
                   "dcol_proximity");
        std::fprintf(csv.f, "# contact %zu %.12f %.9g %.9g %.9g\n", j, r.alpha, r.contact1[0],
                     r.contact1[1], r.contact1[2]);
      }
    }
    std::fprintf(csv.f, "run,iteration,volume,infeasibility\n");
    for (const Solved *r : {&free, &held})
      for (const auto &h : r->history)
        std::fprintf(csv.f, "%s,%.0f,%.9g,%.3g\n", r == &free ? "free" : "held", h[0], h[1], h[2]);
    std::printf("free_region: regions and Ipopt histories written to %s\n", csv.path.c_str());

    const bool ok = free.ok && held.ok && worst >= 1.0 - 1e-8 && seed_gauge <= 1.0 + 1e-8 &&
                    volume(x.data()) >= volume(held.x.data()) * (1.0 - 1e-9) &&
                    volume(held.x.data()) >= volume(sampled.data());
    std::printf("free_region: %s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "free_region: %s\n", e.what());
    return 1;
  }
}
