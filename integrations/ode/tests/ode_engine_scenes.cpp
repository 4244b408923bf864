// Scenes written with ODE's own geoms only, each run with ODE's narrow phase (`native`) or with
// dcol's (`dcol`: dcol_ode::use_dcol() after dInitODE2, the one call), run by ctest:
//
//   ode_engine_scenes pyramid MODE    55 boxes (10 layers) on ODE's plane stand for 10 s: every box
//                                     within 5 mm of its start at every step
//   ode_engine_scenes pile MODE [--seed N]
//                                     48 bodies (spheres, boxes, capsules, cylinders, hulls of 12 to
//                                     200 points) dropped into a walled bin: after 5 s every body at
//                                     rest (speed < 0.05 m/s), inside the bin, above the floor, and
//                                     no pair deeper than 5 mm (dcol_signed_distance on shapes made
//                                     from the scene's own sizes)
//   ode_engine_scenes slope MODE      a 30 degree slope (ODE's plane): a box with friction 0.8 holds
//                                     (creep < 1 mm in 5 s), with 0.3 slides at g (sin - 0.3 cos)
//                                     within 5 %; a sphere and a cylinder roll at 5/7 and 2/3 of
//                                     g sin within 5 %
//   ... --csv FILE                    also write heights (slope: distances) over time
//
// MODE = native | dcol. With dcol every pair of the scene must reach dcol (collider_calls() > 0, no
// pair rejected, no pair left to ODE's collider); with native none may. Exit status 0 when every
// check holds; every check prints its numbers.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "engine_scenes.hpp"
#include "ode_scenes.hpp"

namespace {

using engine_scenes::check;
using ode_scenes::Body;
using ode_scenes::Settings;
using ode_scenes::World;
using ode_scenes::pile_settings;
using ode_scenes::pyramid_settings;
using ode_scenes::slope_settings;

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

void print_settings(const char *scene, const Settings &s) {
  std::printf("%s: dt %.4f s, dWorldQuickStep %d iterations, ERP %.2f, CFM %.0e, %d contacts per pair, "
              "mu %.2f (dContactApprox1), damping linear %.3f angular %.3f\n",
              scene, s.dt, s.iterations, s.erp, s.cfm, s.max_contacts, s.mu, s.linear_damping, s.angular_damping);
}

int pyramid(const char *csv) {
  const Settings s = pyramid_settings();
  print_settings("pyramid", s);
  World w(s);
  ode_scenes::build_pyramid(w, false);
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) std::fprintf(out, "t,max_displacement,top_z\n");
  const int steps = static_cast<int>(std::lround(10.0 / s.dt));
  double worst = 0;
  const double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    double d = 0;
    for (const Body &b : w.bodies) {
      const dReal *p = dBodyGetPosition(b.body);
      d = std::max(d, std::sqrt((p[0] - b.start[0]) * (p[0] - b.start[0]) + (p[1] - b.start[1]) * (p[1] - b.start[1]) +
                                (p[2] - b.start[2]) * (p[2] - b.start[2])));
    }
    worst = std::max(worst, d);
    if (out && k % 4 == 0) std::fprintf(out, "%.4f,%.6e,%.6f\n", k * s.dt, d, dBodyGetPosition(w.bodies.back().body)[2]);
  }
  const double per_step = (now() - t0) / steps;
  if (out) std::fclose(out);
  double final_worst = 0;
  int worst_box = 0;
  for (std::size_t i = 0; i < w.bodies.size(); ++i) {
    const Body &b = w.bodies[i];
    const dReal *p = dBodyGetPosition(b.body);
    const double d = std::sqrt((p[0] - b.start[0]) * (p[0] - b.start[0]) + (p[1] - b.start[1]) * (p[1] - b.start[1]) +
                               (p[2] - b.start[2]) * (p[2] - b.start[2]));
    if (d > final_worst) {
      final_worst = d;
      worst_box = static_cast<int>(i);
    }
  }
  const dReal *top = dBodyGetPosition(w.bodies.back().body);
  std::printf("pyramid of %zu boxes after 10 s: largest displacement from the start %.3e m (box %d), largest at any time "
              "%.3e m; top box z %.6f (start %.6f); %.1f us per step\n",
              w.bodies.size(), final_worst, worst_box, worst, top[2], w.bodies.back().start[2], per_step * 1e6);
  check(w.bodies.size() == 55, "55 boxes");
  check(final_worst < 0.005 && worst < 0.005, "every box of the pyramid within 5 mm of its start, all 10 s");
  return 0;
}

// The signed distance of two dcol shapes (with the scene's own sizes).
double signed_distance(const dcol_shape *a, const dcol_pose &pa, const dcol_shape *b, const dcol_pose &pb) {
  dcol_signed_distance_result r;
  const dcol_status st = dcol_signed_distance(a, &pa, b, &pb, nullptr, &r);
  if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) return -1e300;
  return r.distance;
}

int pile(unsigned seed, const char *csv, bool recorded) {
  const Settings s = pile_settings();
  print_settings("pile", s);
  World w(s);
  ode_scenes::build_pile(w, seed, recorded);
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) {
    std::fprintf(out, "t");
    for (std::size_t i = 0; i < w.bodies.size(); ++i) std::fprintf(out, ",z%zu", i);
    std::fprintf(out, "\n");
  }
  const int steps = static_cast<int>(std::lround(5.0 / s.dt));
  const double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    if (out && k % 4 == 0) {
      std::fprintf(out, "%.4f", k * s.dt);
      for (const Body &b : w.bodies) std::fprintf(out, ",%.6f", dBodyGetPosition(b.body)[2]);
      std::fprintf(out, "\n");
    }
  }
  const double per_step = (now() - t0) / steps;
  if (out) std::fclose(out);

  // At rest, inside the bin, above the floor.
  const double half = 0.5 * ode_scenes::kBinInner;
  double vmax = 0, wmax = 0, outside = -1e300, zmin = 1e300;
  int moving = 0;
  for (const Body &b : w.bodies) {
    const dReal *v = dBodyGetLinearVel(b.body);
    const dReal *om = dBodyGetAngularVel(b.body);
    const dReal *p = dBodyGetPosition(b.body);
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    vmax = std::max(vmax, speed);
    wmax = std::max(wmax, std::sqrt(om[0] * om[0] + om[1] * om[1] + om[2] * om[2]));
    if (speed >= 0.05) {
      ++moving;
      std::printf("  moving: body %zu (kind %d%s%s) at (%.3f, %.3f, %.3f), speed %.3e m/s, angular %.3e rad/s\n",
                  static_cast<std::size_t>(&b - &w.bodies[0]), b.kind, b.hull ? ", " : "", b.hull ? b.hull->name.c_str() : "",
                  p[0], p[1], p[2], speed, std::sqrt(om[0] * om[0] + om[1] * om[1] + om[2] * om[2]));
    }
    outside = std::max(outside, std::max(std::fabs(p[0]) - half, std::fabs(p[1]) - half));
    zmin = std::min(zmin, p[2]);
  }
  // Depths: every pair of bodies, each body against the floor and the four walls (dcol
  // half-spaces of depth 1 whose boundaries are ODE's five planes).
  std::vector<dcol_shape *> shapes;
  std::vector<dcol_pose> poses(w.bodies.size());
  for (std::size_t i = 0; i < w.bodies.size(); ++i) shapes.push_back(ode_scenes::check_shape(w.bodies[i], &poses[i]));
  dcol_shape *halfspace = nullptr;
  dcol_shape_new_halfspace(1.0, &halfspace);
  const double c = std::sqrt(0.5);
  // Attitudes turning e_z to the planes' normals: +z; -x, +x, -y, +y (the walls at x = +-half,
  // y = +-half, normals into the bin).
  const dcol_pose planes[5] = {{{0, 0, -1}, {1, 0, 0, 0}},
                               {{half + 1, 0, 0}, {c, 0, -c, 0}},
                               {{-half - 1, 0, 0}, {c, 0, c, 0}},
                               {{0, half + 1, 0}, {c, c, 0, 0}},
                               {{0, -half - 1, 0}, {c, -c, 0, 0}}};
  double deepest = 1e300;
  std::string deepest_what;
  bool all_shapes = true;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (!shapes[i]) {
      all_shapes = false;
      continue;
    }
    auto note = [&](double d, const std::string &what) {
      if (d < deepest) {
        deepest = d;
        deepest_what = what;
      }
    };
    note(signed_distance(halfspace, planes[0], shapes[i], poses[i]), "body " + std::to_string(i) + " / floor");
    for (int k = 1; k < 5; ++k)
      note(signed_distance(halfspace, planes[k], shapes[i], poses[i]),
           "body " + std::to_string(i) + " / wall " + std::to_string(k));
    for (std::size_t j = i + 1; j < shapes.size(); ++j)
      if (shapes[j])
        note(signed_distance(shapes[i], poses[i], shapes[j], poses[j]),
             "bodies " + std::to_string(i) + " / " + std::to_string(j));
  }
  for (dcol_shape *x : shapes) dcol_shape_free(x);
  dcol_shape_free(halfspace);
  std::printf("pile of %zu bodies (seed %u) after 5 s: largest speed %.3e m/s (%d at 0.05 or more), largest angular "
              "speed %.3e rad/s, farthest outside the bin %.3e m, lowest centre z %.4f m, deepest pair %.3e m (%s); "
              "%.1f us per step\n",
              w.bodies.size(), seed, vmax, moving, wmax, outside, zmin, -deepest, deepest_what.c_str(), per_step * 1e6);
  check(w.bodies.size() >= 40, "at least 40 bodies");
  check(all_shapes, "a dcol shape for every body (the depth check)");
  check(moving == 0, "every body at rest (speed < 0.05 m/s) after 5 s");
  check(outside < 0 && zmin > 0, "every body inside the bin and above the floor");
  check(deepest > -0.005, "no pair deeper than 5 mm");
  return 0;
}

// A 30 degree slope: ODE's plane through the origin with normal (sin, 0, cos), downhill along
// (cos, 0, -sin). Returns the distance travelled downhill over time.
struct SlopeRun {
  std::vector<double> t, s, v;
};

SlopeRun slope_run(ode_scenes::Kind kind, double mu, double seconds) {
  const double th = 30.0 * 3.14159265358979323846 / 180.0;
  const double n[3] = {std::sin(th), 0, std::cos(th)}, down[3] = {std::cos(th), 0, -std::sin(th)};
  const Settings s = slope_settings(mu);
  World w(s);
  dCreatePlane(w.space, n[0], n[1], n[2], 0);
  // The body resting on the slope: its centre at its half height along the normal, turned by the
  // slope's angle about y (box: flat on a face; cylinder: axis along y, across the slope).
  double size[3] = {0.2, 0.2, 0.2}, half = 0.1;
  dQuaternion q = {std::cos(th / 2), 0, std::sin(th / 2), 0};
  if (kind == ode_scenes::kSphere) {
    size[0] = 0.1;
  } else if (kind == ode_scenes::kCylinder) {
    size[0] = 0.1;
    size[1] = 0.3;
    // Geom z along world y, then the slope: q = slope * (turn z onto y: -90 degrees about x).
    const dQuaternion z_to_y = {std::sqrt(0.5), -std::sqrt(0.5), 0, 0};
    dQuaternion r;
    dQMultiply0(r, q, z_to_y);
    std::memcpy(q, r, sizeof q);
  }
  const double pos[3] = {half * n[0], 0, half * n[2]};
  Body &b = w.add(kind, size, nullptr, pos, q, false);
  SlopeRun run;
  const int steps = static_cast<int>(std::lround(seconds / s.dt));
  for (int k = 1; k <= steps; ++k) {
    w.step();
    const dReal *p = dBodyGetPosition(b.body);
    const dReal *v = dBodyGetLinearVel(b.body);
    run.t.push_back(k * s.dt);
    run.s.push_back((p[0] - pos[0]) * down[0] + (p[1] - pos[1]) * down[1] + (p[2] - pos[2]) * down[2]);
    run.v.push_back(v[0] * down[0] + v[1] * down[1] + v[2] * down[2]);
  }
  return run;
}

// The acceleration downhill: least squares slope of v(t) over [t0, t1].
double acceleration(const SlopeRun &r, double t0, double t1) {
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < t0 || r.t[i] > t1) continue;
    st += r.t[i];
    sv += r.v[i];
    stt += r.t[i] * r.t[i];
    stv += r.t[i] * r.v[i];
    ++n;
  }
  return (n * stv - st * sv) / (n * stt - st * st);
}

int slope(const char *csv) {
  const double g = 9.81, th = 30.0 * 3.14159265358979323846 / 180.0;
  print_settings("slope (box holding, sphere, cylinder)", slope_settings(0.8));
  print_settings("slope (box sliding)", slope_settings(0.3));
  const SlopeRun hold = slope_run(ode_scenes::kBox, 0.8, 5.0);
  const SlopeRun slide = slope_run(ode_scenes::kBox, 0.3, 2.0);
  const SlopeRun ball = slope_run(ode_scenes::kSphere, 0.8, 2.0);
  const SlopeRun can = slope_run(ode_scenes::kCylinder, 0.8, 2.0);
  double creep = 0;
  for (double x : hold.s) creep = std::max(creep, std::fabs(x));
  const double a_slide = acceleration(slide, 0.25, 2.0), want_slide = g * (std::sin(th) - 0.3 * std::cos(th));
  const double a_ball = acceleration(ball, 0.25, 2.0), want_ball = 5.0 / 7.0 * g * std::sin(th);
  const double a_can = acceleration(can, 0.25, 2.0), want_can = 2.0 / 3.0 * g * std::sin(th);
  std::printf("slope 30 deg: box with mu 0.8 creeps %.3e m in 5 s\n", creep);
  std::printf("  box with mu 0.3 slides at %.4f m/s^2 (g (sin - 0.3 cos) = %.4f, %+.2f %%)\n", a_slide, want_slide,
              100 * (a_slide / want_slide - 1));
  std::printf("  sphere rolls at %.4f m/s^2 (5/7 g sin = %.4f, %+.2f %%)\n", a_ball, want_ball, 100 * (a_ball / want_ball - 1));
  std::printf("  cylinder rolls at %.4f m/s^2 (2/3 g sin = %.4f, %+.2f %%)\n", a_can, want_can, 100 * (a_can / want_can - 1));
  check(creep < 0.001, "the box with friction 0.8 holds on the slope (creep < 1 mm in 5 s)");
  check(std::fabs(a_slide / want_slide - 1) < 0.05, "the box with friction 0.3 slides at g (sin - mu cos) within 5 %");
  check(std::fabs(a_ball / want_ball - 1) < 0.05, "the sphere rolls at 5/7 g sin within 5 %");
  check(std::fabs(a_can / want_can - 1) < 0.05, "the cylinder rolls at 2/3 g sin within 5 %");
  if (csv) {
    FILE *out = std::fopen(csv, "w");
    if (out) {
      std::fprintf(out, "t,box_mu08,box_mu03,sphere,cylinder\n");
      for (std::size_t i = 0; i < slide.t.size(); i += 5)
        std::fprintf(out, "%.4f,%.6e,%.6e,%.6e,%.6e\n", slide.t[i], hold.s[i], slide.s[i], ball.s[i], can.s[i]);
      std::fclose(out);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 3) {
    std::printf("usage: %s pyramid|pile|slope native|dcol [--seed N] [--csv FILE]\n", argv[0]);
    return 2;
  }
  const std::string scene = argv[1], mode = argv[2];
  const char *csv = nullptr;
  unsigned seed = 1;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
    if (!std::strcmp(argv[i], "--seed")) seed = static_cast<unsigned>(std::strtoul(argv[i + 1], nullptr, 10));
  }
  if (mode != "native" && mode != "dcol") {
    std::printf("unknown mode %s\n", mode.c_str());
    return 2;
  }
  dInitODE2(0);
  const bool dcol = mode == "dcol";
  if (dcol) dcol_ode::use_dcol();
  int rc = 2;
  if (scene == "pyramid") rc = pyramid(csv);
  if (scene == "pile") rc = pile(seed, csv, dcol);
  if (scene == "slope") rc = slope(csv);
  const dcol_ode::Stats st = dcol_ode::stats();
  std::printf("narrow phase %s: %lu dcol collider calls, %lu contacts, %lu rejected, %lu pairs left to ODE's collider\n",
              dcol ? "dcol" : "native ODE", st.calls, st.contacts, st.rejected, st.native_calls);
  if (dcol) {
    check(st.calls > 0, "the pairs reached dcol (collider_calls() > 0)");
    check(st.rejected == 0 && st.native_calls == 0, "every pair answered by dcol (none rejected, none left to ODE)");
  } else {
    check(st.calls == 0, "no pair reached dcol in the native run");
  }
  dcol_ode::release_all();
  dCloseODE();
  if (rc != 0) return rc;
  std::printf("%s\n", engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
