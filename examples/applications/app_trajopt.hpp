// app_trajopt.hpp: the direct transcription shared by the Ipopt examples. The decision variables
// are the robot's states at N knots (nx numbers each); the first and the last knot are fixed; the
// objective is the weighted sum of squared differences of consecutive knots (smoothness); the
// constraints are alpha*(robot, obstacle j) >= 1 at every free knot, with the Jacobian rows
// computed exactly from dcol's gradient, plus optional limits on the change of some components
// between consecutive knots (a speed limit: it keeps the knots close enough that the
// constraints at the knots also guard the motion between them).
#ifndef DCOL_APP_TRAJOPT_HPP
#define DCOL_APP_TRAJOPT_HPP

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "app_common.hpp"

namespace app {

struct Obstacle {
  Shape shape;
  dcol_pose pose;
  std::string csv;  // "type x y z yaw parameters" for the plots
};

struct TrajSpec {
  int N = 50;   // knots
  int nx = 0;   // numbers per knot
  std::vector<double> start, goal, weights;  // nx each
  std::vector<double> step_limit;            // nx each; <= 0: no limit on that component
  /// Amplitudes (nx each; empty: none) of a smooth bump `amplitude * sin(pi t)` added to the
  /// straight-line guess (t = 0 at the start, 1 at the goal): a guess on a symmetry of the
  /// problem (a cone centred in a square hole) leaves the way round it to rounding, and a bump
  /// the size of the answer's deviation picks one.
  std::vector<double> guess_bump;
  const dcol_shape *robot = nullptr;
  const std::vector<Obstacle> *obstacles = nullptr;
  /// The robot's pose at a state.
  std::function<dcol_pose(const double *x)> pose;
  /// alpha*(robot, obstacle j) at state x and its gradient with respect to x (nx numbers).
  std::function<double(const double *x, int j, double *grad)> alpha_grad;
};

struct TrajResult {
  std::vector<double> x;  // N * nx
  Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;
  long iterations = 0;
  double wall_seconds = 0.0;
};

class TrajNlp : public Ipopt::TNLP {
 public:
  explicit TrajNlp(const TrajSpec &spec) : s_(spec) {
    nobs_ = static_cast<int>(s_.obstacles->size());
    for (int i = 0; i < s_.nx; ++i)
      if (s_.step_limit[i] > 0.0) limited_.push_back(i);
    ncol_ = (s_.N - 2) * nobs_;
    m_ = ncol_ + (s_.N - 1) * static_cast<int>(limited_.size());
    alpha_.resize(ncol_);
    grad_.resize(static_cast<size_t>(ncol_) * s_.nx);
  }
  std::vector<double> solution;

  bool get_nlp_info(Ipopt::Index &n, Ipopt::Index &m, Ipopt::Index &nnz_jac_g,
                    Ipopt::Index &nnz_h_lag, IndexStyleEnum &index_style) override {
    n = s_.N * s_.nx;
    m = m_;
    nnz_jac_g = ncol_ * s_.nx + 2 * (m_ - ncol_);
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
    for (int i = 0; i < s_.nx; ++i) {
      x_l[i] = x_u[i] = s_.start[i];
      x_l[(s_.N - 1) * s_.nx + i] = x_u[(s_.N - 1) * s_.nx + i] = s_.goal[i];
    }
    for (int c = 0; c < ncol_; ++c) {
      g_l[c] = 1.0;
      g_u[c] = 1e19;
    }
    for (int c = ncol_; c < m; ++c) {
      const double lim = s_.step_limit[limited_[(c - ncol_) % limited_.size()]];
      g_l[c] = -lim;
      g_u[c] = lim;
    }
    return true;
  }

  bool get_starting_point(Ipopt::Index, bool init_x, Ipopt::Number *x, bool init_z,
                          Ipopt::Number *, Ipopt::Number *, Ipopt::Index, bool init_lambda,
                          Ipopt::Number *) override {
    if (!init_x || init_z || init_lambda) return false;
    // The naive guess: the straight line from start to goal (plus the spec's bump, zero at
    // both ends).
    for (int k = 0; k < s_.N; ++k) {
      const double t = static_cast<double>(k) / (s_.N - 1);
      for (int i = 0; i < s_.nx; ++i) {
        double v = (1.0 - t) * s_.start[i] + t * s_.goal[i];
        if (static_cast<size_t>(i) < s_.guess_bump.size())
          v += s_.guess_bump[static_cast<size_t>(i)] * std::sin(3.14159265358979323846 * t);
        x[k * s_.nx + i] = v;
      }
    }
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number *x, bool, Ipopt::Number &f) override {
    f = 0.0;
    for (int k = 0; k + 1 < s_.N; ++k)
      for (int i = 0; i < s_.nx; ++i) {
        const double d = x[(k + 1) * s_.nx + i] - x[k * s_.nx + i];
        f += s_.weights[i] * d * d;
      }
    return true;
  }

  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number *x, bool, Ipopt::Number *g) override {
    std::fill(g, g + n, 0.0);
    for (int k = 0; k + 1 < s_.N; ++k)
      for (int i = 0; i < s_.nx; ++i) {
        const double d = 2.0 * s_.weights[i] * (x[(k + 1) * s_.nx + i] - x[k * s_.nx + i]);
        g[(k + 1) * s_.nx + i] += d;
        g[k * s_.nx + i] -= d;
      }
    return true;
  }

  bool eval_g(Ipopt::Index, const Ipopt::Number *x, bool new_x, Ipopt::Index m,
              Ipopt::Number *g) override {
    if (new_x || !cached_) update(x);
    for (int c = 0; c < ncol_; ++c) g[c] = alpha_[c];
    const int nl = static_cast<int>(limited_.size());
    for (int c = ncol_; c < m; ++c) {
      const int k = (c - ncol_) / nl, i = limited_[(c - ncol_) % nl];
      g[c] = x[(k + 1) * s_.nx + i] - x[k * s_.nx + i];
    }
    return true;
  }

  bool eval_jac_g(Ipopt::Index, const Ipopt::Number *x, bool new_x, Ipopt::Index m,
                  Ipopt::Index, Ipopt::Index *iRow, Ipopt::Index *jCol,
                  Ipopt::Number *values) override {
    const int nl = static_cast<int>(limited_.size());
    if (values == nullptr) {
      int e = 0;
      for (int c = 0; c < ncol_; ++c) {
        const int k = 1 + c / nobs_;
        for (int i = 0; i < s_.nx; ++i, ++e) {
          iRow[e] = c;
          jCol[e] = k * s_.nx + i;
        }
      }
      for (int c = ncol_; c < m; ++c) {
        const int k = (c - ncol_) / nl, i = limited_[(c - ncol_) % nl];
        iRow[e] = c;
        jCol[e++] = (k + 1) * s_.nx + i;
        iRow[e] = c;
        jCol[e++] = k * s_.nx + i;
      }
      return true;
    }
    if (new_x || !cached_) update(x);
    int e = 0;
    for (int c = 0; c < ncol_; ++c)
      for (int i = 0; i < s_.nx; ++i) values[e++] = grad_[static_cast<size_t>(c) * s_.nx + i];
    for (int c = ncol_; c < m; ++c) {
      values[e++] = 1.0;
      values[e++] = -1.0;
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number *x,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Index,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Number,
                         const Ipopt::IpoptData *, Ipopt::IpoptCalculatedQuantities *) override {
    solution.assign(x, x + n);
  }

 private:
  // alpha* and its gradient for every (free knot, obstacle) pair at x.
  void update(const double *x) {
    for (int c = 0; c < ncol_; ++c) {
      const int k = 1 + c / nobs_, j = c % nobs_;
      alpha_[c] = s_.alpha_grad(x + k * s_.nx, j, &grad_[static_cast<size_t>(c) * s_.nx]);
    }
    cached_ = true;
  }

  const TrajSpec &s_;
  int nobs_ = 0, ncol_ = 0, m_ = 0;
  std::vector<int> limited_;
  std::vector<double> alpha_, grad_;
  bool cached_ = false;
};

/// Solves the transcription with Ipopt (limited-memory Hessian) from the straight-line guess.
inline TrajResult solve_trajectory(const TrajSpec &spec, int max_iter = 3000) {
  TrajResult res;
  Ipopt::SmartPtr<TrajNlp> nlp = new TrajNlp(spec);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> ipopt = IpoptApplicationFactory();
  ipopt->Options()->SetStringValue("hessian_approximation", "limited-memory");
  ipopt->Options()->SetNumericValue("tol", 1e-6);
  ipopt->Options()->SetNumericValue("constr_viol_tol", 1e-8);
  ipopt->Options()->SetIntegerValue("max_iter", max_iter);
  ipopt->Options()->SetIntegerValue("print_level", 4);
  ipopt->Options()->SetStringValue("sb", "yes");  // no banner
  const Clock::time_point t0 = Clock::now();
  if (ipopt->Initialize() != Ipopt::Solve_Succeeded) throw std::runtime_error("Ipopt: init failed");
  res.status = ipopt->OptimizeTNLP(nlp);
  res.wall_seconds = seconds_since(t0);
  if (Ipopt::IsValid(ipopt->Statistics())) res.iterations = ipopt->Statistics()->IterationCount();
  res.x = nlp->solution;
  return res;
}

inline const char *status_name(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    default: return "other Ipopt status";
  }
}

struct TrajCheck {
  double min_knots = 1e300, min_between = 1e300;
};

/// Re-evaluates alpha* with dcol_proximity at every knot and at `sub` points between
/// consecutive knots (the states interpolated linearly), against every obstacle.
inline TrajCheck check_trajectory(const TrajSpec &s, const std::vector<double> &x, int sub = 10) {
  TrajCheck c;
  std::vector<double> xi(s.nx);
  for (int k = 0; k < s.N; ++k) {
    for (int t = 0; t < (k + 1 < s.N ? sub + 1 : 1); ++t) {
      const double u = static_cast<double>(t) / (sub + 1);
      for (int i = 0; i < s.nx; ++i)
        xi[i] = t == 0 ? x[k * s.nx + i]
                       : (1.0 - u) * x[k * s.nx + i] + u * x[(k + 1) * s.nx + i];
      const dcol_pose p = s.pose(xi.data());
      for (const Obstacle &o : *s.obstacles) {
        const double a = proximity(s.robot, p, o.shape.get(), o.pose);
        double &m = t == 0 ? c.min_knots : c.min_between;
        m = std::min(m, a);
      }
    }
  }
  return c;
}

/// Writes the obstacles (as "# obstacle ..." lines), the robot (`robot_line`) and the knots.
inline void write_trajectory_csv(Csv &csv, const TrajSpec &s, const std::vector<double> &x,
                                 const char *robot_line, const char *header) {
  for (const Obstacle &o : *s.obstacles) std::fprintf(csv.f, "# obstacle %s\n", o.csv.c_str());
  std::fprintf(csv.f, "# robot %s\n%s,min_alpha\n", robot_line, header);
  for (int k = 0; k < s.N; ++k) {
    std::fprintf(csv.f, "%d", k);
    for (int i = 0; i < s.nx; ++i) std::fprintf(csv.f, ",%.9g", x[k * s.nx + i]);
    const dcol_pose p = s.pose(&x[k * s.nx]);
    double m = 1e300;
    for (const Obstacle &o : *s.obstacles)
      m = std::min(m, proximity(s.robot, p, o.shape.get(), o.pose));
    std::fprintf(csv.f, ",%.9g\n", m);
  }
}

/// Prints the summary and the check; returns the exit code (0 when every check passes).
inline int report_trajectory(const char *name, const TrajSpec &s, const TrajResult &r) {
  std::printf("%s: Ipopt status %s after %ld iterations\n", name, status_name(r.status),
              r.iterations);
  print_timing(name, r.iterations, r.wall_seconds);  // before the check's own dcol calls
  const TrajCheck c = check_trajectory(s, r.x);
  std::printf("%s: min alpha* at the knots %.9f (must be >= 1 - 1e-6), between the knots (10 "
              "interpolated points per interval) %.6f\n",
              name, c.min_knots, c.min_between);
  const bool ok = r.status == Ipopt::Solve_Succeeded && c.min_knots >= 1.0 - 1e-6;
  std::printf("%s: %s\n", name, ok ? "PASS" : "FAIL");
  return ok ? 0 : 1;
}

}  // namespace app

#endif  // DCOL_APP_TRAJOPT_HPP
