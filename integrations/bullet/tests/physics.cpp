// Physics scenes written with Bullet's own shapes only, each run with Bullet's narrow phase
// (native) and with dcol's (dcol: use_dcol), run by ctest (bullet_pyramid_*, bullet_pile_*,
// bullet_slope_*). Scene parameters: scenes.hpp (the same for both narrow phases).
//
//   bullet_physics pyramid native|dcol [--csv F]   55 boxes in 10 layers on a plane stand for
//                                                  10 s: every box within 5 mm of its start
//   bullet_physics pile native|dcol [--seed N] [--csv F]
//                                                  48 mixed bodies dropped into a walled bin:
//                                                  after 5 s every body at rest (speed < 0.05
//                                                  m/s), inside the bin, above the floor, and no
//                                                  pair deeper than 5 mm (dcol_signed_distance on
//                                                  the mapped dcol shapes)
//   bullet_physics slope native|dcol [--csv F]     on a 30 degree slope: a box with friction 0.8
//                                                  holds (creep < 1 mm in 5 s), with 0.3 slides at
//                                                  g (sin - 0.3 cos) within 5 %; a sphere and a
//                                                  cylinder roll down at 5/7 and 2/3 of g sin
//                                                  within 5 %
//
// With dcol, every pair call must be dcol's (algorithm_calls() > 0, no fallback).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "engine_scenes.hpp"
#include "scenes.hpp"

namespace {

using bullet_scenes::at;
using bullet_scenes::World;
using engine_scenes::check;
using engine_scenes::now;

const char *label(bool dcol) { return dcol ? "dcol" : "native"; }

void report_calls(bool dcol, const dcol_bullet::Stats &s0) {
  const dcol_bullet::Stats s = dcol_bullet::stats();
  std::printf("  dcol: %lu pair calls (%lu decided apart without a query, %lu queried and apart, %lu answers reused), "
              "%lu fallback pairs, %lu fallback calls, %lu not converged, %lu errors, %lu shapes built\n",
              s.calls - s0.calls, s.early_outs - s0.early_outs, s.apart - s0.apart, s.reused - s0.reused,
              s.fallback_pairs - s0.fallback_pairs,
              s.fallback_calls - s0.fallback_calls, s.not_converged - s0.not_converged, s.errors - s0.errors,
              s.shapes_built - s0.shapes_built);
  if (dcol) {
    check(s.calls > s0.calls, "dcol answered the pairs (algorithm_calls() > 0)");
    check(s.fallback_pairs == s0.fallback_pairs && s.fallback_calls == s0.fallback_calls,
          "no pair went to Bullet's algorithm");
    check(s.errors == s0.errors, "no dcol errors");
  } else {
    check(s.calls == s0.calls, "native: dcol not called");
  }
}

// ---------------------------------------------------------------------------------------------

int pyramid(bool dcol, const char *csv) {
  World w(dcol, bullet_scenes::pyramid_params());
  const std::vector<btRigidBody *> boxes = bullet_scenes::build_pyramid(w);
  std::vector<btVector3> start;
  for (btRigidBody *b : boxes) start.push_back(b->getWorldTransform().getOrigin());
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) std::fprintf(out, "t,top_z,max_displacement\n");
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  const int steps = static_cast<int>(std::lround(10.0 / w.params.dt));
  double worst = 0;
  const double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    double d = 0;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      d = std::max(d, double((boxes[i]->getWorldTransform().getOrigin() - start[i]).length()));
    }
    worst = std::max(worst, d);
    if (out && k % 4 == 0) {
      std::fprintf(out, "%.4f,%.6f,%.6e\n", k * w.params.dt, double(boxes.back()->getWorldTransform().getOrigin().z()), d);
    }
  }
  const double elapsed = now() - t0;
  if (out) std::fclose(out);
  double final_worst = 0;
  std::size_t worst_box = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const double d = (boxes[i]->getWorldTransform().getOrigin() - start[i]).length();
    if (d > final_worst) {
      final_worst = d;
      worst_box = i;
    }
  }
  std::printf("pyramid (%s): 55 boxes, 10 s at dt %.5f s, %d iterations: largest displacement %.3e m (box %zu at "
              "the end), %.3e m at any time; top box z %.6f (start %.6f); %.1f us per step\n",
              label(dcol), w.params.dt, w.params.iterations, final_worst, worst_box, worst,
              double(boxes.back()->getWorldTransform().getOrigin().z()), double(start.back().z()), elapsed / steps * 1e6);
  check(final_worst <= 5e-3, "every box within 5 mm of its start after 10 s");
  report_calls(dcol, s0);
  return 0;
}

// ---------------------------------------------------------------------------------------------

// The deepest penetration among the pile's pairs, from dcol_signed_distance on the geometry the
// narrow phase collided (the floor: a dcol half-space whose top is z = 0): the shapes the adapter
// maps Bullet's to, except that Bullet's own algorithms round a box's edges by its margin against
// anything but a box or the plane (btSphereBoxCollisionAlgorithm and GJK take the box's core
// padded by the margin), so the native run is measured on that rounded box for those pairs.
// Also counts the bodies within 1 mm of another body.
double deepest_pair(const bullet_scenes::Pile &pile, bool dcol, std::string *which, int *touching) {
  std::vector<btRigidBody *> all(pile.statics.begin() + 1, pile.statics.end());
  all.insert(all.end(), pile.bodies.begin(), pile.bodies.end());
  struct Mapped {
    const dcol_shape *shape;
    dcol_pose pose;
    double pad;
    const dcol_shape *rounded;  // a box's core (native runs, against non-boxes)
    double rounded_pad;
  };
  std::vector<Mapped> m(all.size());
  std::vector<dcol_shape *> cores;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const btCollisionShape *s = all[i]->getCollisionShape();
    if (!dcol_bullet::as_dcol(s, all[i]->getWorldTransform(), &m[i].shape, &m[i].pose, &m[i].pad)) {
      *which = "a shape dcol does not map";
      return INFINITY;
    }
    m[i].rounded = m[i].shape;
    m[i].rounded_pad = m[i].pad;
    if (s->getShapeType() == BOX_SHAPE_PROXYTYPE) {
      const btBoxShape *box = static_cast<const btBoxShape *>(s);
      const btVector3 &c = box->getHalfExtentsWithoutMargin();
      dcol_shape *core = nullptr;
      if (dcol_shape_new_box(c.x(), c.y(), c.z(), &core) == DCOL_OK) {
        cores.push_back(core);
        m[i].rounded = core;
        m[i].rounded_pad = box->getMargin();
      }
    }
  }
  dcol_shape *floor = nullptr;
  dcol_shape_new_halfspace(1.0, &floor);
  const dcol_pose floor_pose = {{0, 0, -1}, {1, 0, 0, 0}};
  double deepest = 0;
  std::vector<bool> near(all.size(), false);
  char buf[128];
  for (std::size_t i = 0; i < all.size(); ++i) {
    dcol_signed_distance_result r;
    if (i >= 4 && dcol_signed_distance(floor, &floor_pose, m[i].shape, &m[i].pose, nullptr, &r) != DCOL_ERROR_INVALID_POSE) {
      const double depth = -(r.distance - m[i].pad);
      if (depth > deepest) {
        deepest = depth;
        std::snprintf(buf, sizeof buf, "body %zu and the floor", i - 4);
        *which = buf;
      }
    }
    for (std::size_t j = std::max<std::size_t>(i + 1, 4); j < all.size(); ++j) {
      const int ti = all[i]->getCollisionShape()->getShapeType(), tj = all[j]->getCollisionShape()->getShapeType();
      const bool round = !dcol && (ti == BOX_SHAPE_PROXYTYPE) != (tj == BOX_SHAPE_PROXYTYPE);
      const dcol_shape *si = round ? m[i].rounded : m[i].shape, *sj = round ? m[j].rounded : m[j].shape;
      const double pi = round ? m[i].rounded_pad : m[i].pad, pj = round ? m[j].rounded_pad : m[j].pad;
      if (dcol_signed_distance(si, &m[i].pose, sj, &m[j].pose, nullptr, &r) == DCOL_ERROR_INVALID_POSE) continue;
      const double depth = -(r.distance - pi - pj);
      if (i >= 4 && depth >= -1e-3) near[i] = near[j] = true;
      if (depth > deepest) {
        deepest = depth;
        if (i < 4) {
          std::snprintf(buf, sizeof buf, "wall %zu and body %zu", i, j - 4);
        } else {
          std::snprintf(buf, sizeof buf, "bodies %zu and %zu", i - 4, j - 4);
        }
        *which = buf;
      }
    }
  }
  *touching = 0;
  for (bool b : near) *touching += b ? 1 : 0;
  for (dcol_shape *c : cores) dcol_shape_free(c);
  dcol_shape_free(floor);
  return deepest;
}

int pile(bool dcol, unsigned seed, const char *csv) {
  World w(dcol, bullet_scenes::pile_params());
  const bullet_scenes::Pile p = bullet_scenes::build_pile(w, seed);
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) {
    std::fprintf(out, "t");
    for (std::size_t i = 0; i < p.bodies.size(); ++i) std::fprintf(out, ",z%zu", i);
    std::fprintf(out, "\n");
  }
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  const int steps = static_cast<int>(std::lround(5.0 / w.params.dt));
  const double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    if (out && k % 4 == 0) {
      std::fprintf(out, "%.4f", k * w.params.dt);
      for (const btRigidBody *b : p.bodies) std::fprintf(out, ",%.5f", double(b->getWorldTransform().getOrigin().z()));
      std::fprintf(out, "\n");
    }
  }
  const double elapsed = now() - t0;
  if (out) std::fclose(out);
  double fastest = 0, lowest = INFINITY, outside = -INFINITY;
  int moving = 0;
  for (const btRigidBody *b : p.bodies) {
    const btVector3 o = b->getWorldTransform().getOrigin();
    const double v = b->getLinearVelocity().length();
    fastest = std::max(fastest, v);
    if (v >= 0.05) {
      ++moving;
      std::printf("  moving: %s at (%.3f, %.3f, %.3f), %.3f m/s, spin %.3f rad/s\n", b->getCollisionShape()->getName(),
                  double(o.x()), double(o.y()), double(o.z()), v, double(b->getAngularVelocity().length()));
    }
    lowest = std::min(lowest, double(o.z()));
    outside = std::max(outside, std::max(std::fabs(double(o.x())), std::fabs(double(o.y()))) - bullet_scenes::kBinHalf);
  }
  std::string which;
  int touching = 0;
  const double deepest = deepest_pair(p, dcol, &which, &touching);
  std::printf("pile (%s, seed %u): %zu bodies (%d within 1 mm of another), 5 s at dt %.5f s: fastest %.3e m/s, "
              "lowest centre z %.4f m, centre farthest out %+.4f m from the inner wall, deepest pair %.3e m (%s); "
              "%.1f us per step\n",
              label(dcol), seed, p.bodies.size(), touching, w.params.dt, fastest, lowest, outside, deepest, which.c_str(),
              elapsed / steps * 1e6);
  check(p.bodies.size() >= 40, "at least 40 bodies");
  check(fastest < 0.05, "every body at rest (speed < 0.05 m/s)");
  check(outside < 0 && lowest > 0, "every body inside the bin and above the floor");
  check(deepest <= 5e-3, "no pair deeper than 5 mm");
  report_calls(dcol, s0);
  return 0;
}

// ---------------------------------------------------------------------------------------------

// The acceleration of s(t) = s0 + v0 t + a t^2 / 2 fitted by least squares.
double fit_acceleration(const std::vector<double> &t, const std::vector<double> &s) {
  double m[3][4] = {{0}};
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double b[3] = {1, t[k], 0.5 * t[k] * t[k]};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += b[i] * b[j];
      m[i][3] += b[i] * s[k];
    }
  }
  for (int c = 0; c < 3; ++c) {  // Gauss-Jordan, the matrix is positive definite
    for (int r = 0; r < 3; ++r) {
      if (r == c) continue;
      const double f = m[r][c] / m[c][c];
      for (int j = c; j < 4; ++j) m[r][j] -= f * m[c][j];
    }
  }
  return m[2][3] / m[2][2];
}

struct SlopeRun {
  double accel;  // fitted over t in [0.1, 1.1] s
  double creep;  // distance along the slope after `seconds`
};

// One body on the slope, from rest; `kind` 0 box, 1 sphere, 2 cylinder (axis across the slope).
SlopeRun slope_run(bool dcol, int kind, double mu, double seconds, FILE *out, const char *name) {
  World w(dcol, bullet_scenes::slope_params());
  btVector3 down, normal;
  bullet_scenes::build_slope(w, &down, &normal);
  btCollisionShape *shape = kind == 0   ? w.own(new btBoxShape(btVector3(0.1f, 0.1f, 0.1f)))
                            : kind == 1 ? w.own(new btSphereShape(0.1f))
                                        : w.own(new btCylinderShape(btVector3(0.1f, 0.15f, 0.1f)));
  const btQuaternion q(btVector3(0, 1, 0), btScalar(bullet_scenes::kSlope));
  btTransform t(q, bullet_scenes::on_slope(down, normal, -2.0, 0.1));
  btRigidBody *b = w.add(shape, 1.0, t);
  b->setFriction(btScalar(mu));
  const btVector3 p0 = t.getOrigin();
  std::vector<double> ts, ss;
  const int steps = static_cast<int>(std::lround(seconds / w.params.dt));
  for (int k = 1; k <= steps; ++k) {
    w.step();
    const double time = k * w.params.dt, s = (b->getWorldTransform().getOrigin() - p0).dot(down);
    if (time >= 0.1 - 1e-9 && time <= 1.1 + 1e-9) {
      ts.push_back(time);
      ss.push_back(s);
    }
    if (out && k % 4 == 0) std::fprintf(out, "%s,%.4f,%.6e\n", name, time, s);
  }
  SlopeRun r;
  r.accel = fit_acceleration(ts, ss);
  r.creep = (b->getWorldTransform().getOrigin() - p0).dot(down);
  return r;
}

int slope(bool dcol, const char *csv) {
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) std::fprintf(out, "body,t,s\n");
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  const double g = bullet_scenes::kG, th = bullet_scenes::kSlope;
  const SlopeRun hold = slope_run(dcol, 0, 0.8, 5.0, out, "box_mu0.8");
  const SlopeRun slide = slope_run(dcol, 0, 0.3, 1.2, out, "box_mu0.3");
  const SlopeRun ball = slope_run(dcol, 1, 0.8, 1.2, out, "sphere");
  const SlopeRun can = slope_run(dcol, 2, 0.8, 1.2, out, "cylinder");
  if (out) std::fclose(out);
  const double want_slide = g * (std::sin(th) - 0.3 * std::cos(th));
  const double want_ball = 5.0 / 7.0 * g * std::sin(th), want_can = 2.0 / 3.0 * g * std::sin(th);
  std::printf("slope (%s), 30 degrees:\n", label(dcol));
  std::printf("  box, friction 0.8: creep %.3e m in 5 s\n", hold.creep);
  std::printf("  box, friction 0.3: %.4f m/s^2 (g(sin - mu cos) = %.4f, error %+.2f %%)\n", slide.accel, want_slide,
              100 * (slide.accel / want_slide - 1));
  std::printf("  sphere rolling:    %.4f m/s^2 (5/7 g sin = %.4f, error %+.2f %%)\n", ball.accel, want_ball,
              100 * (ball.accel / want_ball - 1));
  std::printf("  cylinder rolling:  %.4f m/s^2 (2/3 g sin = %.4f, error %+.2f %%)\n", can.accel, want_can,
              100 * (can.accel / want_can - 1));
  check(std::fabs(hold.creep) < 1e-3, "the box with friction 0.8 holds (creep < 1 mm in 5 s)");
  check(std::fabs(slide.accel / want_slide - 1) <= 0.05, "the box with friction 0.3 slides at g(sin - mu cos) within 5 %");
  check(std::fabs(ball.accel / want_ball - 1) <= 0.05, "the sphere rolls at 5/7 g sin within 5 %");
  check(std::fabs(can.accel / want_can - 1) <= 0.05, "the cylinder rolls at 2/3 g sin within 5 %");
  report_calls(dcol, s0);
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 3 || (std::strcmp(argv[2], "native") && std::strcmp(argv[2], "dcol"))) {
    std::printf("usage: %s pyramid|pile|slope native|dcol [--seed N] [--csv FILE]\n", argv[0]);
    return 2;
  }
  const std::string what = argv[1];
  const bool dcol = !std::strcmp(argv[2], "dcol");
  const char *csv = nullptr;
  unsigned seed = 1;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--csv")) csv = argv[i + 1];
    if (!std::strcmp(argv[i], "--seed")) seed = static_cast<unsigned>(std::strtoul(argv[i + 1], nullptr, 10));
  }
  int rc = 2;
  if (what == "pyramid") rc = pyramid(dcol, csv);
  if (what == "pile") rc = pile(dcol, seed, csv);
  if (what == "slope") rc = slope(dcol, csv);
  if (rc != 0) return rc;
  std::printf("%s\n", engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
