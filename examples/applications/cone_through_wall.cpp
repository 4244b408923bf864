// A cone through a square hole in a wall (DCOL paper, "Cone Through an Opening"). The cone has
// full 3D translation and rotation: its state at each of N = 50 knots is its position and the
// modified Rodrigues parameters (MRP) of its attitude, and the constraint Jacobian comes straight
// from dcol_gradient_mrp. The wall is four boxes around a square hole whose side (0.84 m) is
// smaller than the diameter of the cone's base (0.9 m): the cone cannot pass with its axis along
// the direction of travel, as it starts and ends, and the optimiser has to tilt it (its base
// then crosses along a diagonal of the hole) and turn it back. Objective, fixed ends, speed
// limits and the straight-line initial guess as in piano_mover (app_trajopt.hpp).
//
// Usage: cone_through_wall [out.csv]   (default cone_through_wall.csv in the current directory)
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "app_trajopt.hpp"

namespace {

app::Obstacle block(double cx, double cy, double cz, double hx, double hy, double hz) {
  char line[128];
  std::snprintf(line, sizeof line, "box %g %g %g 0 %g %g %g", cx, cy, cz, hx, hy, hz);
  return app::Obstacle{app::make_box(hx, hy, hz), app::make_pose(cx, cy, cz), line};
}

dcol_pose cone_pose(const double *x) {
  double q[4];
  app::mrp_to_quat(x + 3, q);
  return app::make_pose(x[0], x[1], x[2], q[0], q[1], q[2], q[3]);
}

}  // namespace

int main(int argc, char **argv) {
  try {
    const double H = 0.6, beta = std::atan(0.75);  // base radius H tan(beta) = 0.45
    const app::Shape cone = app::make_cone(H, beta);
    // The wall: the plane x = 0, 0.1 m thick, out to 3 m; the hole |y|, |z| <= a.
    const double a = 0.42, t = 0.05, e = 3.0, m = 0.5 * (e + a), h = 0.5 * (e - a);
    std::vector<app::Obstacle> wall;
    wall.push_back(block(0, 0, m, t, e, h));   // above the hole
    wall.push_back(block(0, 0, -m, t, e, h));  // below
    wall.push_back(block(0, m, 0, t, h, a));   // left
    wall.push_back(block(0, -m, 0, t, h, a));  // right

    app::TrajSpec spec;
    spec.N = 50;
    spec.nx = 6;
    spec.start = {-1.5, 0, 0, 0, 0, 0};
    spec.goal = {1.5, 0, 0, 0, 0, 0};
    spec.weights = {1, 1, 1, 1, 1, 1};
    spec.step_limit = {0.15, 0.15, 0.15, 0.06, 0.06, 0.06};
    // The straight line runs along the hole's axis of symmetry: which way the cone tilts is
    // then decided by rounding (a change of dcol in the last bits of alpha* or its gradient
    // turned a solve of 483 iterations into one that stopped at the limit, or a false
    // "infeasible"). The guess tilts the cone about the hole's diagonal instead, by up to
    // 4 atan(0.02 sqrt 2) = 6.5 deg at the wall (MRP, zero at both ends); docs/applications.md
    // has the solves under perturbed gradients.
    spec.guess_bump = {0, 0, 0, 0, 0.02, 0.02};
    spec.robot = cone.get();
    spec.obstacles = &wall;
    spec.pose = cone_pose;
    spec.alpha_grad = [&](const double *x, int j, double *g) {
      const app::Obstacle &o = wall[static_cast<size_t>(j)];
      const double zero[3] = {0, 0, 0};
      double g12[12];
      const double alpha =
          app::gradient_mrp(cone.get(), x, x + 3, o.shape.get(), o.pose.position, zero, g12);
      for (int i = 0; i < 6; ++i) g[i] = g12[i];
      return alpha;
    };

    const app::TrajResult r = app::solve_trajectory(spec);
    int code = app::report_trajectory("cone_through_wall", spec, r);
    // How far the optimiser had to turn the cone: the largest angle between its axis and x.
    double tilt = 0.0;
    for (int k = 0; k < spec.N; ++k) {
      const dcol_pose p = cone_pose(&r.x[static_cast<size_t>(k) * 6]);
      const double ex[3] = {1, 0, 0};
      double axis[3];
      app::quat_rotate(p.quaternion, ex, axis);
      tilt = std::fmax(tilt, std::acos(std::fmax(-1.0, std::fmin(1.0, axis[0]))));
    }
    std::printf("cone_through_wall: largest tilt of the cone's axis from the x axis: %.1f deg\n",
                tilt * 180.0 / 3.14159265358979323846);
    app::Csv csv(argc, argv, "cone_through_wall.csv");
    char robot[64];
    std::snprintf(robot, sizeof robot, "cone %g %.9g", H, beta);
    app::write_trajectory_csv(csv, spec, r.x, robot, "knot,x,y,z,p1,p2,p3");
    std::printf("cone_through_wall: trajectory written to %s\n", csv.path.c_str());
    return code;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "cone_through_wall: %s\n", e.what());
    return 1;
  }
}
