// A quadrotor through a cluttered hallway (DCOL paper, "Quadrotor"), KINEMATIC version: the
// paper optimises a 6-DOF quadrotor model with its dynamics; here the decision variables are only
// the positions of the quadrotor's outer approximation, a sphere of radius 0.25 m, at N = 50
// knots (the sphere makes the attitude irrelevant to the collision constraints, and no dynamics
// are imposed). The hallway (floor, ceiling and side walls: 4 boxes) holds 12 obstacles of all
// primitive types placed across the straight line from start to goal. Objective, fixed ends,
// speed limits and the straight-line initial guess as in piano_mover (app_trajopt.hpp).
//
// Usage: quadrotor_hallway [out.csv]   (default quadrotor_hallway.csv in the current directory)
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "app_trajopt.hpp"

namespace {

// `what`: "type params", written as "type x y z yaw params" for the plots.
app::Obstacle make(app::Shape s, double x, double y, double z, double yaw, const char *what) {
  const std::string w(what);
  const size_t sp = w.find(' ');
  char line[160];
  std::snprintf(line, sizeof line, "%s %g %g %g %g %s", w.substr(0, sp).c_str(), x, y, z, yaw,
                w.substr(sp + 1).c_str());
  return app::Obstacle{std::move(s), app::planar_pose(x, y, yaw, z), line};
}

}  // namespace

int main(int argc, char **argv) {
  try {
    const double R = 0.25;
    const app::Shape quad = app::make_sphere(R);
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

    app::TrajSpec spec;
    spec.N = 50;
    spec.nx = 3;
    spec.start = {0.3, 0.0, 1.5};
    spec.goal = {10.0, 0.0, 1.5};
    spec.weights = {1, 1, 1};
    spec.step_limit = {0.3, 0.3, 0.3};
    spec.robot = quad.get();
    spec.obstacles = &obs;
    spec.pose = [](const double *x) { return app::make_pose(x[0], x[1], x[2]); };
    spec.alpha_grad = [&](const double *x, int j, double *g) {
      double g14[14];
      const app::Obstacle &o = obs[static_cast<size_t>(j)];
      const double a = app::gradient(quad.get(), app::make_pose(x[0], x[1], x[2]), o.shape.get(),
                                     o.pose, g14);
      for (int i = 0; i < 3; ++i) g[i] = g14[i];
      return a;
    };

    const app::TrajResult r = app::solve_trajectory(spec);
    const int code = app::report_trajectory("quadrotor_hallway", spec, r);
    app::Csv csv(argc, argv, "quadrotor_hallway.csv");
    app::write_trajectory_csv(csv, spec, r.x, "sphere 0.25", "knot,x,y,z");
    std::printf("quadrotor_hallway: trajectory written to %s\n", csv.path.c_str());
    return code;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "quadrotor_hallway: %s\n", e.what());
    return 1;
  }
}
