// A quadrotor through a cluttered hallway (DCOL paper, "Quadrotor"; the model of the
// cluttered_hallway_quadrotor example of DifferentiableCollisions.jl): a 6-DOF rigid-body
// quadrotor flies from hover at the start to hover at the goal past 12 obstacles of all primitive
// types, inside a hallway of 4 boxes.
//
// Model. State x = (r, v, p, w): position and velocity in the world frame, attitude as modified
// Rodrigues parameters (world-from-body), body angular velocity (12 numbers). Control u = the 4
// rotor thrusts [N], 0 <= u_i <= 4. Mass 0.5 kg, inertia diag(0.0023, 0.0023, 0.004) kg m^2, arm
// 0.175 m, torque/thrust ratio 0.0245 m, gravity 9.81 m/s^2:
//   r' = v,  v' = g + R(p) [0, 0, sum u] / m,  p' = G(p) w,  w' = J^-1 (tau - w x J w),
//   tau = [L (u2 - u4), L (u3 - u1), km (u1 - u2 + u3 - u4)],
//   G(p) = ((1 - p.p) I + 2 [p]x + 2 p p^T) / 4.
// Discretised with one RK4 step per interval, dt = 0.08 s, N = 60 knots (4.72 s).
//
// Transcription (direct, multiple shooting at every knot). Variables: x_0, u_0, ..., x_{N-2},
// u_{N-2}, x_{N-1}. Equality constraints: rk4(x_k, u_k) - x_{k+1} = 0, with their Jacobian
// computed EXACTLY by forward-mode automatic differentiation (a small dual-number type, below)
// of the RK4 step: no finite differences. x_0 (hover at the start) and x_{N-1} (hover at the
// goal) are fixed by their bounds. Objective: sum_k 0.5 |u_k - u_hover|^2 (control effort)
// + 0.5 (0.1 |v_k|^2 + |p_k|^2 + 0.1 |w_k|^2) (a small state regularisation). Collision: the
// quadrotor is a flat ellipsoid (semi-axes 0.25, 0.25, 0.1 m, the rotor disc) at its pose, and
// alpha*(quadrotor, obstacle j) >= 1 at every free knot, the Jacobian row (6 entries: r and p)
// from dcol_gradient_mrp, so the attitude matters: the quadrotor may bank to slip through.
// Ipopt, limited-memory Hessian, from the naive guess: positions on the straight line from
// start to goal (which collides), the constant velocity of that line, level attitude, no
// rotation, hover thrust.
//
// Usage: quadrotor_hallway [out.csv]   (default quadrotor_hallway.csv in the current directory)
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app_trajopt.hpp"

namespace {

// ---------------------------------------------------------------------------------------------
// Forward-mode automatic differentiation: a value and its 16 partial derivatives (x and u).

constexpr int NX = 12, NU = 4, NZ = NX + NU;

struct Dual {
  double v = 0.0;
  std::array<double, NZ> d{};
  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: implicit, constants in the templated dynamics
  friend Dual operator+(const Dual &a, const Dual &b) {
    Dual c(a.v + b.v);
    for (int i = 0; i < NZ; ++i) c.d[i] = a.d[i] + b.d[i];
    return c;
  }
  friend Dual operator-(const Dual &a, const Dual &b) {
    Dual c(a.v - b.v);
    for (int i = 0; i < NZ; ++i) c.d[i] = a.d[i] - b.d[i];
    return c;
  }
  friend Dual operator-(const Dual &a) { return Dual(0.0) - a; }
  friend Dual operator*(const Dual &a, const Dual &b) {
    Dual c(a.v * b.v);
    for (int i = 0; i < NZ; ++i) c.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return c;
  }
  friend Dual operator/(const Dual &a, const Dual &b) {
    Dual c(a.v / b.v);
    for (int i = 0; i < NZ; ++i) c.d[i] = (a.d[i] - c.v * b.d[i]) / b.v;
    return c;
  }
};

// ---------------------------------------------------------------------------------------------
// The quadrotor.

const double MASS = 0.5, JX = 0.0023, JY = 0.0023, JZ = 0.004, ARM = 0.175, KM = 0.0245,
             GRAV = 9.81, DT = 0.08, UMAX = 4.0, HOVER = MASS * GRAV / 4.0;

template <class T>
void dynamics(const T *x, const T *u, T *xd) {
  const T *v = x + 3, *p = x + 6, *w = x + 9;
  // R(p) e_z from the quaternion [1 - s, 2p] / (1 + s).
  const T s = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  const T qw = (1.0 - s) / (1.0 + s), qx = 2.0 * p[0] / (1.0 + s), qy = 2.0 * p[1] / (1.0 + s),
          qz = 2.0 * p[2] / (1.0 + s);
  const T thrust = u[0] + u[1] + u[2] + u[3];
  const T ez[3] = {2.0 * (qx * qz + qw * qy), 2.0 * (qy * qz - qw * qx),
                   1.0 - 2.0 * (qx * qx + qy * qy)};
  for (int i = 0; i < 3; ++i) xd[i] = v[i];
  for (int i = 0; i < 3; ++i) xd[3 + i] = ez[i] * thrust / MASS;
  xd[5] = xd[5] - GRAV;
  // p' = ((1 - s) w + 2 p x w + 2 (p.w) p) / 4.
  const T pw = p[0] * w[0] + p[1] * w[1] + p[2] * w[2];
  const T pxw[3] = {p[1] * w[2] - p[2] * w[1], p[2] * w[0] - p[0] * w[2],
                    p[0] * w[1] - p[1] * w[0]};
  for (int i = 0; i < 3; ++i) xd[6 + i] = 0.25 * ((1.0 - s) * w[i] + 2.0 * pxw[i] + 2.0 * pw * p[i]);
  // w' = J^-1 (tau - w x J w).
  const T tau[3] = {ARM * (u[1] - u[3]), ARM * (u[2] - u[0]), KM * (u[0] - u[1] + u[2] - u[3])};
  const T Jw[3] = {JX * w[0], JY * w[1], JZ * w[2]};
  const T gyro[3] = {w[1] * Jw[2] - w[2] * Jw[1], w[2] * Jw[0] - w[0] * Jw[2],
                     w[0] * Jw[1] - w[1] * Jw[0]};
  xd[9] = (tau[0] - gyro[0]) / JX;
  xd[10] = (tau[1] - gyro[1]) / JY;
  xd[11] = (tau[2] - gyro[2]) / JZ;
}

/// One RK4 step of length h with the control held constant.
template <class T>
void rk4(const T *x, const T *u, double h, T *out) {
  T k1[NX], k2[NX], k3[NX], k4[NX], y[NX];
  dynamics(x, u, k1);
  for (int i = 0; i < NX; ++i) y[i] = x[i] + 0.5 * h * k1[i];
  dynamics(y, u, k2);
  for (int i = 0; i < NX; ++i) y[i] = x[i] + 0.5 * h * k2[i];
  dynamics(y, u, k3);
  for (int i = 0; i < NX; ++i) y[i] = x[i] + h * k3[i];
  dynamics(y, u, k4);
  for (int i = 0; i < NX; ++i) out[i] = x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
}

/// The RK4 step and its 12 x 16 Jacobian (row-major, columns x then u), by forward-mode AD.
void rk4_jacobian(const double *x, const double *u, double *out, double *jac) {
  Dual xd[NX], ud[NU], yd[NX];
  for (int i = 0; i < NX; ++i) {
    xd[i] = Dual(x[i]);
    xd[i].d[i] = 1.0;
  }
  for (int i = 0; i < NU; ++i) {
    ud[i] = Dual(u[i]);
    ud[i].d[NX + i] = 1.0;
  }
  rk4(xd, ud, DT, yd);
  for (int i = 0; i < NX; ++i) {
    out[i] = yd[i].v;
    for (int j = 0; j < NZ; ++j) jac[i * NZ + j] = yd[i].d[j];
  }
}

/// The largest difference between the AD Jacobian of the RK4 step and central differences
/// (step 1e-6) at a tilted, spinning, moving state with uneven thrusts.
double jacobian_self_check() {
  const double x[NX] = {1, -0.5, 1.2, 2.0, -0.7, 0.4, 0.1, -0.2, 0.15, 1.5, -2.0, 0.8};
  const double u[NU] = {1.0, 1.6, 0.7, 1.3};
  double out[NX], jac[NX * NZ], err = 0.0;
  rk4_jacobian(x, u, out, jac);
  for (int j = 0; j < NZ; ++j) {
    double xp[NX], xm[NX], up[NU], um[NU], fp[NX], fm[NX];
    std::copy(x, x + NX, xp);
    std::copy(x, x + NX, xm);
    std::copy(u, u + NU, up);
    std::copy(u, u + NU, um);
    const double h = 1e-6;
    (j < NX ? xp[j] : up[j - NX]) += h;
    (j < NX ? xm[j] : um[j - NX]) -= h;
    rk4(xp, up, DT, fp);
    rk4(xm, um, DT, fm);
    for (int i = 0; i < NX; ++i)
      err = std::max(err, std::fabs((fp[i] - fm[i]) / (2 * h) - jac[i * NZ + j]));
  }
  return err;
}

dcol_pose body_pose(const double *x) {
  double q[4];
  app::mrp_to_quat(x + 6, q);
  return app::make_pose(x[0], x[1], x[2], q[0], q[1], q[2], q[3]);
}

// ---------------------------------------------------------------------------------------------
// The transcription.

struct Problem {
  int N = 60;
  std::array<double, NX> start{}, goal{};
  const dcol_shape *robot = nullptr;
  const std::vector<app::Obstacle> *obstacles = nullptr;
  std::vector<std::array<double, 3>> obstacle_mrp;
};

class QuadNlp : public Ipopt::TNLP {
 public:
  explicit QuadNlp(const Problem &p) : p_(p) {
    nobs_ = static_cast<int>(p_.obstacles->size());
    n_ = NZ * (p_.N - 1) + NX;
    ndyn_ = NX * (p_.N - 1);
    ncol_ = (p_.N - 2) * nobs_;
  }
  std::vector<double> solution;

  bool get_nlp_info(Ipopt::Index &n, Ipopt::Index &m, Ipopt::Index &nnz_jac_g,
                    Ipopt::Index &nnz_h_lag, IndexStyleEnum &index_style) override {
    n = n_;
    m = ndyn_ + ncol_;
    nnz_jac_g = (p_.N - 1) * NX * (NZ + 1) + ncol_ * 6;
    nnz_h_lag = 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index, Ipopt::Number *x_l, Ipopt::Number *x_u, Ipopt::Index m,
                       Ipopt::Number *g_l, Ipopt::Number *g_u) override {
    for (int k = 0; k < p_.N; ++k) {
      for (int i = 0; i < NX; ++i) {
        const bool fixed = k == 0 || k == p_.N - 1;
        const double v = k == 0 ? p_.start[i] : p_.goal[i];
        x_l[NZ * k + i] = fixed ? v : -1e19;
        x_u[NZ * k + i] = fixed ? v : 1e19;
      }
      if (k + 1 < p_.N)
        for (int i = 0; i < NU; ++i) {
          x_l[NZ * k + NX + i] = 0.0;
          x_u[NZ * k + NX + i] = UMAX;
        }
    }
    for (int c = 0; c < m; ++c) {
      g_l[c] = c < ndyn_ ? 0.0 : 1.0;
      g_u[c] = c < ndyn_ ? 0.0 : 1e19;
    }
    return true;
  }

  bool get_starting_point(Ipopt::Index, bool init_x, Ipopt::Number *z, bool init_z,
                          Ipopt::Number *, Ipopt::Number *, Ipopt::Index, bool init_lambda,
                          Ipopt::Number *) override {
    if (!init_x || init_z || init_lambda) return false;
    const double T = DT * (p_.N - 1);
    for (int k = 0; k < p_.N; ++k) {
      const double t = static_cast<double>(k) / (p_.N - 1);
      double *x = z + NZ * k;
      for (int i = 0; i < NX; ++i) x[i] = 0.0;
      for (int i = 0; i < 3; ++i) {
        x[i] = (1.0 - t) * p_.start[i] + t * p_.goal[i];
        if (k > 0 && k + 1 < p_.N) x[3 + i] = (p_.goal[i] - p_.start[i]) / T;
      }
      if (k + 1 < p_.N)
        for (int i = 0; i < NU; ++i) x[NX + i] = HOVER;
    }
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number *z, bool, Ipopt::Number &f) override {
    f = 0.0;
    for (int k = 0; k < p_.N; ++k) {
      const double *x = z + NZ * k;
      for (int i = 0; i < 3; ++i)
        f += 0.5 * (0.1 * x[3 + i] * x[3 + i] + x[6 + i] * x[6 + i] + 0.1 * x[9 + i] * x[9 + i]);
      if (k + 1 < p_.N)
        for (int i = 0; i < NU; ++i) f += 0.5 * (x[NX + i] - HOVER) * (x[NX + i] - HOVER);
    }
    return true;
  }

  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number *z, bool, Ipopt::Number *g) override {
    std::fill(g, g + n, 0.0);
    for (int k = 0; k < p_.N; ++k) {
      const int o = NZ * k;
      for (int i = 0; i < 3; ++i) {
        g[o + 3 + i] = 0.1 * z[o + 3 + i];
        g[o + 6 + i] = z[o + 6 + i];
        g[o + 9 + i] = 0.1 * z[o + 9 + i];
      }
      if (k + 1 < p_.N)
        for (int i = 0; i < NU; ++i) g[o + NX + i] = z[o + NX + i] - HOVER;
    }
    return true;
  }

  bool eval_g(Ipopt::Index, const Ipopt::Number *z, bool, Ipopt::Index, Ipopt::Number *g) override {
    for (int k = 0; k + 1 < p_.N; ++k) {
      double next[NX];
      rk4(z + NZ * k, z + NZ * k + NX, DT, next);
      for (int i = 0; i < NX; ++i) g[NX * k + i] = next[i] - z[NZ * (k + 1) + i];
    }
    for (int c = 0; c < ncol_; ++c) {
      const int k = 1 + c / nobs_, j = c % nobs_;
      const app::Obstacle &o = (*p_.obstacles)[static_cast<size_t>(j)];
      g[ndyn_ + c] = app::proximity(p_.robot, body_pose(z + NZ * k), o.shape.get(), o.pose);
    }
    return true;
  }

  bool eval_jac_g(Ipopt::Index, const Ipopt::Number *z, bool, Ipopt::Index, Ipopt::Index,
                  Ipopt::Index *iRow, Ipopt::Index *jCol, Ipopt::Number *values) override {
    static const int pose_cols[6] = {0, 1, 2, 6, 7, 8};
    int e = 0;
    if (values == nullptr) {
      for (int k = 0; k + 1 < p_.N; ++k)
        for (int i = 0; i < NX; ++i) {
          for (int j = 0; j < NZ; ++j, ++e) {
            iRow[e] = NX * k + i;
            jCol[e] = NZ * k + j;
          }
          iRow[e] = NX * k + i;
          jCol[e++] = NZ * (k + 1) + i;
        }
      for (int c = 0; c < ncol_; ++c)
        for (int i = 0; i < 6; ++i, ++e) {
          iRow[e] = ndyn_ + c;
          jCol[e] = NZ * (1 + c / nobs_) + pose_cols[i];
        }
      return true;
    }
    for (int k = 0; k + 1 < p_.N; ++k) {
      double next[NX], jac[NX * NZ];
      rk4_jacobian(z + NZ * k, z + NZ * k + NX, next, jac);
      for (int i = 0; i < NX; ++i) {
        for (int j = 0; j < NZ; ++j) values[e++] = jac[i * NZ + j];
        values[e++] = -1.0;
      }
    }
    for (int c = 0; c < ncol_; ++c) {
      const int k = 1 + c / nobs_, j = c % nobs_;
      const app::Obstacle &o = (*p_.obstacles)[static_cast<size_t>(j)];
      const double *x = z + NZ * k;
      double g12[12];
      app::gradient_mrp(p_.robot, x, x + 6, o.shape.get(), o.pose.position,
                        p_.obstacle_mrp[static_cast<size_t>(j)].data(), g12);
      for (int i = 0; i < 6; ++i) values[e++] = g12[i];
    }
    return true;
  }

  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number *z,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Index,
                         const Ipopt::Number *, const Ipopt::Number *, Ipopt::Number,
                         const Ipopt::IpoptData *, Ipopt::IpoptCalculatedQuantities *) override {
    solution.assign(z, z + n);
  }

 private:
  const Problem &p_;
  int nobs_ = 0, n_ = 0, ndyn_ = 0, ncol_ = 0;
};

// `what`: "type params", written as "type x y z yaw params" for the plots.
app::Obstacle make(app::Shape s, double x, double y, double z, double yaw, const char *what) {
  const std::string w(what);
  const size_t sp = w.find(' ');
  char line[160];
  std::snprintf(line, sizeof line, "%s %g %g %g %g %s", w.substr(0, sp).c_str(), x, y, z, yaw,
                w.substr(sp + 1).c_str());
  return app::Obstacle{std::move(s), app::planar_pose(x, y, yaw, z), line};
}

double min_alpha(const Problem &p, const double *x) {
  const dcol_pose pose = body_pose(x);
  double m = 1e300;
  for (const app::Obstacle &o : *p.obstacles)
    m = std::min(m, app::proximity(p.robot, pose, o.shape.get(), o.pose));
  return m;
}

}  // namespace

int main(int argc, char **argv) {
  try {
    const double jac_err = jacobian_self_check();
    std::printf("quadrotor_hallway: RK4 Jacobian by AD vs central differences: max difference "
                "%.2e\n", jac_err);
    if (!(jac_err < 1e-6)) throw std::runtime_error("the AD Jacobian of the dynamics is wrong");
    const app::Shape quad = app::make_ellipsoid(0.25, 0.25, 0.1);
    std::vector<app::Obstacle> obs;
    // The hallway: -1 <= x <= 11, |y| <= 1.5, 0 <= z <= 3.
    obs.push_back(make(app::make_box(6, 2, 0.25), 5, 0, -0.25, 0, "box 6 2 0.25"));
    obs.push_back(make(app::make_box(6, 2, 0.25), 5, 0, 3.25, 0, "box 6 2 0.25"));
    obs.push_back(make(app::make_box(6, 0.25, 1.5), 5, 1.75, 1.5, 0, "box 6 0.25 1.5"));
    obs.push_back(make(app::make_box(6, 0.25, 1.5), 5, -1.75, 1.5, 0, "box 6 0.25 1.5"));
    // Twelve obstacles, every primitive type, each across or near the straight line z = 1.5,
    // y = 0. Axes of the rods: x in the body frame, turned by the yaw about z.
    obs.push_back(make(app::make_cylinder(0.3, 3.0), 1.2, 0.1, 1.5, 1.5708, "cylinder 0.3 3"));
    obs.push_back(make(app::make_sphere(0.5), 2.0, -0.6, 1.7, 0, "sphere 0.5"));
    obs.push_back(make(app::make_box(0.3, 0.8, 0.6), 2.6, 0.8, 1.3, 0, "box 0.3 0.8 0.6"));
    obs.push_back(make(app::make_capsule(0.2, 2.0), 3.4, -0.4, 1.4, 1.2, "capsule 0.2 2"));
    obs.push_back(make(app::make_cone(1.2, 0.5), 4.2, 0.3, 1.6, 0.3, "cone 1.2 0.5"));
    obs.push_back(make(app::make_ellipsoid(0.4, 0.9, 0.5), 5.0, -0.5, 1.5, 0, "ellipsoid 0.4 0.9 0.5"));
    obs.push_back(make(app::make_padded_rect(0.3, 0.6, 0.1), 5.8, 0.6, 1.5, 0, "polygon 0.3 0.6 0.1"));
    obs.push_back(make(app::make_cylinder(0.25, 3.0), 6.5, -0.2, 1.5, 1.5708, "cylinder 0.25 3"));
    obs.push_back(make(app::make_sphere(0.6), 7.2, 0.7, 1.2, 0, "sphere 0.6"));
    obs.push_back(make(app::make_box(0.25, 0.5, 1.0), 7.9, -0.5, 1.8, 0.4, "box 0.25 0.5 1"));
    obs.push_back(make(app::make_capsule(0.25, 1.5), 8.6, 0.2, 1.5, 0.0, "capsule 0.25 1.5"));
    obs.push_back(make(app::make_ellipsoid(0.3, 0.6, 0.6), 9.2, -0.3, 1.4, 0, "ellipsoid 0.3 0.6 0.6"));

    Problem prob;
    prob.N = 60;
    prob.start = {0.3, 0.0, 1.5};  // the rest zero: hover
    prob.goal = {10.0, 0.0, 1.5};
    prob.robot = quad.get();
    prob.obstacles = &obs;
    for (const app::Obstacle &o : obs) {  // MRP of a unit quaternion: q_v / (1 + q_w)
      const double *q = o.pose.quaternion;
      prob.obstacle_mrp.push_back({q[1] / (1 + q[0]), q[2] / (1 + q[0]), q[3] / (1 + q[0])});
    }

    Ipopt::SmartPtr<QuadNlp> nlp = new QuadNlp(prob);
    Ipopt::SmartPtr<Ipopt::IpoptApplication> ipopt = IpoptApplicationFactory();
    ipopt->Options()->SetStringValue("hessian_approximation", "limited-memory");
    ipopt->Options()->SetNumericValue("tol", 1e-6);
    ipopt->Options()->SetNumericValue("constr_viol_tol", 1e-8);
    ipopt->Options()->SetIntegerValue("max_iter", 3000);
    ipopt->Options()->SetIntegerValue("print_level", 4);
    ipopt->Options()->SetStringValue("sb", "yes");
    const app::Clock::time_point t0 = app::Clock::now();
    if (ipopt->Initialize() != Ipopt::Solve_Succeeded) throw std::runtime_error("Ipopt: init");
    const Ipopt::ApplicationReturnStatus status = ipopt->OptimizeTNLP(nlp);
    const double wall = app::seconds_since(t0);
    const long iters =
        Ipopt::IsValid(ipopt->Statistics()) ? ipopt->Statistics()->IterationCount() : 0;
    const std::vector<double> &z = nlp->solution;
    std::printf("quadrotor_hallway: Ipopt status %s after %ld iterations\n",
                app::status_name(status), iters);
    app::print_timing("quadrotor_hallway", iters, wall);
    if (z.size() != static_cast<size_t>(NZ * (prob.N - 1) + NX))
      throw std::runtime_error("Ipopt returned no solution");

    // The check: alpha* at the knots, and along the flown trajectory between them (10 RK4
    // sub-steps of dt/10 per interval from x_k with u_k), plus the dynamics' defects.
    double min_knots = 1e300, min_between = 1e300, defect = 0.0, umin = 1e300, umax = 0.0,
           tilt = 0.0, vmax = 0.0;
    const int sub = 10;
    for (int k = 0; k < prob.N; ++k) {
      const double *x = &z[static_cast<size_t>(NZ * k)];
      min_knots = std::min(min_knots, min_alpha(prob, x));
      const double ez[3] = {0, 0, 1};
      double up[3];
      app::quat_rotate(body_pose(x).quaternion, ez, up);
      tilt = std::max(tilt, std::acos(std::max(-1.0, std::min(1.0, up[2]))));
      vmax = std::max(vmax, std::sqrt(x[3] * x[3] + x[4] * x[4] + x[5] * x[5]));
      if (k + 1 == prob.N) break;
      const double *u = x + NX;
      for (int i = 0; i < NU; ++i) umin = std::min(umin, u[i]), umax = std::max(umax, u[i]);
      double y[NX], yn[NX];
      std::copy(x, x + NX, y);
      for (int s = 1; s < sub; ++s) {
        rk4(y, u, DT / sub, yn);
        std::copy(yn, yn + NX, y);
        min_between = std::min(min_between, min_alpha(prob, y));
      }
      rk4(x, u, DT, yn);
      for (int i = 0; i < NX; ++i) defect = std::max(defect, std::fabs(yn[i] - x[NZ + i]));
    }
    std::printf("quadrotor_hallway: min alpha* at the knots %.9f (must be >= 1 - 1e-6), between "
                "the knots (9 points per interval along the flown dynamics) %.6f\n",
                min_knots, min_between);
    std::printf("quadrotor_hallway: max dynamics defect %.2e, thrusts in [%.3f, %.3f] N (hover "
                "%.3f), max tilt %.1f deg, max speed %.2f m/s\n",
                defect, umin, umax, HOVER, tilt * 180.0 / 3.14159265358979323846, vmax);
    const bool ok = status == Ipopt::Solve_Succeeded && min_knots >= 1.0 - 1e-6 && defect < 1e-6;
    std::printf("quadrotor_hallway: %s\n", ok ? "PASS" : "FAIL");

    app::Csv csv(argc, argv, "quadrotor_hallway.csv");
    for (const app::Obstacle &o : obs) std::fprintf(csv.f, "# obstacle %s\n", o.csv.c_str());
    std::fprintf(csv.f, "# robot ellipsoid 0.25 0.25 0.1\nknot,t,x,y,z,vx,vy,vz,p1,p2,p3,wx,wy,wz,"
                        "u1,u2,u3,u4,min_alpha\n");
    for (int k = 0; k < prob.N; ++k) {
      const double *x = &z[static_cast<size_t>(NZ * k)];
      std::fprintf(csv.f, "%d,%.4f", k, k * DT);
      for (int i = 0; i < NX; ++i) std::fprintf(csv.f, ",%.9g", x[i]);
      for (int i = 0; i < NU; ++i) std::fprintf(csv.f, ",%.9g", k + 1 < prob.N ? x[NX + i] : HOVER);
      std::fprintf(csv.f, ",%.9g\n", min_alpha(prob, x));
    }
    std::printf("quadrotor_hallway: trajectory written to %s\n", csv.path.c_str());
    return ok ? 0 : 1;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "quadrotor_hallway: %s\n", e.what());
    return 1;
  }
}
