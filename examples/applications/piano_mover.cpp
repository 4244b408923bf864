// The "piano mover" problem of the DCOL paper: a 2.6 m long piano (a thin box) turns the 90 degree
// corner of an L-shaped hallway 1 m wide whose walls are boxes. Direct transcription with N = 50
// knots of the planar pose (x, y, yaw); the objective is smoothness (the sum of squared
// differences of consecutive knots); start and goal are fixed; alpha*(piano, wall) >= 1 at every
// knot, with the constraint Jacobian from dcol_gradient chained through the planar pose; Ipopt
// with a limited-memory Hessian, started from the straight line from start to goal (which
// drives the piano through the inner corner of the hallway).
//
// Usage: piano_mover [out.csv]   (default piano_mover.csv in the current directory)
//
// The hallway: the horizontal leg is 0 <= y <= 1 (x <= 1), the vertical leg 0 <= x <= 1
// (y >= 0); inner corner (0, 1), outer corner (1, 0). A rectangle of length L and width w
// can pass the corner only if L <= 2 (sqrt(2) - w) (at 45 degrees its outer long side lies on
// a chord of the outer corner at distance at most sqrt(2) - w), so the 2.6 m piano must be
// thinner than 0.114 m: it is 0.08 m wide here (half-extents 1.3 x 0.04 x 0.05).
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "app_trajopt.hpp"

namespace {

app::Obstacle wall(double cx, double cy, double hx, double hy) {
  const double hz = 0.5;
  char line[128];
  std::snprintf(line, sizeof line, "box %g %g %g 0 %g %g %g", cx, cy, 0.0, hx, hy, hz);
  return app::Obstacle{app::make_box(hx, hy, hz), app::make_pose(cx, cy, 0.0), line};
}

}  // namespace

int main(int argc, char **argv) {
  try {
    const double kPi = 3.14159265358979323846;
    const app::Shape piano = app::make_box(1.3, 0.04, 0.05);
    std::vector<app::Obstacle> walls;
    walls.push_back(wall(-1.0, -0.25, 3.0, 0.25));  // outer wall of the horizontal leg, y <= 0
    walls.push_back(wall(1.25, 2.0, 0.25, 2.5));    // outer wall of the vertical leg, x >= 1
    walls.push_back(wall(-2.0, 2.75, 2.0, 1.75));   // the inner corner block, x <= 0, y >= 1

    app::TrajSpec spec;
    spec.N = 50;
    spec.nx = 3;
    spec.start = {-1.8, 0.5, 0.0};
    spec.goal = {0.5, 2.5, 0.5 * kPi};
    spec.weights = {1.0, 1.0, 1.0};
    spec.step_limit = {0.2, 0.2, 0.1};
    spec.robot = piano.get();
    spec.obstacles = &walls;
    spec.pose = [](const double *x) { return app::planar_pose(x[0], x[1], x[2]); };
    spec.alpha_grad = [&](const double *x, int j, double *g) {
      double g14[14];
      const dcol_pose p = app::planar_pose(x[0], x[1], x[2]);
      const app::Obstacle &o = walls[static_cast<size_t>(j)];
      const double a = app::gradient(piano.get(), p, o.shape.get(), o.pose, g14);
      // q = [cos(yaw/2), 0, 0, sin(yaw/2)]: dq/dyaw = [-sin(yaw/2)/2, 0, 0, cos(yaw/2)/2].
      g[0] = g14[0];
      g[1] = g14[1];
      g[2] = -0.5 * std::sin(0.5 * x[2]) * g14[3] + 0.5 * std::cos(0.5 * x[2]) * g14[6];
      return a;
    };

    const app::TrajResult r = app::solve_trajectory(spec);
    const int code = app::report_trajectory("piano_mover", spec, r);
    app::Csv csv(argc, argv, "piano_mover.csv");
    app::write_trajectory_csv(csv, spec, r.x, "box 1.3 0.04 0.05", "knot,x,y,yaw");
    std::printf("piano_mover: trajectory written to %s\n", csv.path.c_str());
    return code;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "piano_mover: %s\n", e.what());
    return 1;
  }
}
