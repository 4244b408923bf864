// The closed-form contacts of a primitive against an engine's plane (integrations/common/
// plane_contacts.hpp, used by the ODE and Bullet adapters instead of a dcol query). Checks:
//   - closed forms (sphere, box, capsule, cylinder, cone) at random attitudes against random
//     tilted planes, deepest points from 0.05 above to 0.05 below, margins 0 and 0.03: contacts
//     exactly when the brute-force deepest point (the surface sampled: a box's corners, the rims
//     at 7 200 angles, the cone's apex) is at depth >= -margin; the reported largest depth within
//     the sampling's error above the brute-force one and never below it; every point's solid
//     point (pos - depth/2 n) on the shape's surface and its plane point (pos + depth/2 n) on the
//     plane (1e-12); the largest depth of dcol's own contacts (dcol_contacts with a dcol
//     half-space), to 1e-12; for boxes, and cylinders and cones on their discs, the same points
//     as dcol's (1e-12);
//   - the reduction (capacities 1 to 4): at most the capacity, the deepest kept;
//   - through dCollide with use_dcol(): ODE's sphere, box, capsule and cylinder against ODE's
//     plane (both orders, capacities 1 to 16) give the closed form's largest depth against
//     dcol_contacts on dcol_ode::shape_of's shape and pose, the plane's normal into g1.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "override_test_util.hpp"
#include "plane_contacts.hpp"

namespace {

using namespace override_test;

enum Kind { kSphere, kBox, kCapsule, kCylinder, kCone };
const char *kNames[5] = {"sphere", "box", "capsule", "cylinder", "cone"};

struct Solid {
  Kind kind;
  double a, b, c;  // sphere R; box half extents; capsule/cylinder R, L; cone H, beta
};

// A rotation matrix (columns: body axes in world) from a unit quaternion (w, x, y, z).
void rotation(const double q[4], double R[3][3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  R[0][0] = 1 - 2 * (y * y + z * z), R[0][1] = 2 * (x * y - w * z), R[0][2] = 2 * (x * z + w * y);
  R[1][0] = 2 * (x * y + w * z), R[1][1] = 1 - 2 * (x * x + z * z), R[1][2] = 2 * (y * z - w * x);
  R[2][0] = 2 * (x * z - w * y), R[2][1] = 2 * (y * z + w * x), R[2][2] = 1 - 2 * (x * x + y * y);
}

double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// World point of body point b.
void world(const dcol_plane::Frame &f, const double b[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = f.c[i] + f.axis[0][i] * b[0] + f.axis[1][i] * b[1] + f.axis[2][i] * b[2];
}

// Distance of world point q from the solid's surface (exact for each shape; body axis x is the
// capsule's, cylinder's and cone's).
double surface_distance(const Solid &s, const dcol_plane::Frame &f, const double q[3]) {
  double d[3] = {q[0] - f.c[0], q[1] - f.c[1], q[2] - f.c[2]};
  const double b[3] = {dot(d, f.axis[0]), dot(d, f.axis[1]), dot(d, f.axis[2])};
  switch (s.kind) {
    case kSphere: return std::fabs(std::sqrt(dot(b, b)) - s.a);
    case kBox: {
      const double h[3] = {s.a, s.b, s.c};
      double out = 0, in = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double e = std::fabs(b[k]) - h[k];
        out += std::max(e, 0.0) * std::max(e, 0.0);
        in = std::max(in, e);
      }
      return out > 0 ? std::sqrt(out) : std::fabs(in);
    }
    case kCapsule: {
      const double t = std::max(-0.5 * s.b, std::min(0.5 * s.b, b[0]));
      const double e[3] = {b[0] - t, b[1], b[2]};
      return std::fabs(std::sqrt(dot(e, e)) - s.a);
    }
    case kCylinder: {
      const double rad = std::hypot(b[1], b[2]) - s.a, ax = std::fabs(b[0]) - 0.5 * s.b;
      if (rad > 0 || ax > 0) return std::hypot(std::max(rad, 0.0), std::max(ax, 0.0));
      return std::fabs(std::max(rad, ax));
    }
    case kCone: {
      // On the base (x = H/4, within the radius) or on the side (rho = (x + 3H/4) tan beta).
      const double H = s.a, tb = std::tan(s.b), rho = std::hypot(b[1], b[2]);
      const double base = std::fabs(b[0] - 0.25 * H) + std::max(0.0, rho - H * tb);
      const double side = std::fabs(rho - (b[0] + 0.75 * H) * tb) * std::cos(s.b) +
                          std::max(0.0, b[0] - 0.25 * H) + std::max(0.0, -0.75 * H - b[0]);
      return std::min(base, side);
    }
  }
  return INFINITY;
}

// Brute force: the deepest of the solid's surface sampled (corners exact; rims at 7 200 angles),
// and the sampling's error bound on it.
double brute_deepest(const Solid &s, const dcol_plane::Frame &f, const dcol_plane::Plane &p, double *bound) {
  double best = -INFINITY;
  auto at = [&](const double b[3]) {
    double w[3];
    world(f, b, w);
    best = std::max(best, p.d - dot(p.n, w));
  };
  const int kAngles = 7200;
  auto rims = [&](const double *xs, const double *rs, int count) {
    for (int j = 0; j < count; ++j)
      for (int i = 0; i < kAngles; ++i) {
        const double t = 2 * M_PI * i / kAngles;
        const double b[3] = {xs[j], rs[j] * std::cos(t), rs[j] * std::sin(t)};
        at(b);
      }
  };
  *bound = 0;
  switch (s.kind) {
    case kSphere:
    case kCapsule: {
      // The balls' centres (exact: a ball's deepest is its centre's depth + R).
      const double half = s.kind == kSphere ? 0 : 0.5 * s.b;
      for (int e = -1; e <= 1; e += 2) {
        const double b[3] = {e * half, 0, 0};
        double w[3];
        world(f, b, w);
        best = std::max(best, p.d - dot(p.n, w) + s.a);
      }
      break;
    }
    case kBox:
      for (int i = 0; i < 8; ++i) {
        const double b[3] = {(i & 1 ? 1 : -1) * s.a, (i & 2 ? 1 : -1) * s.b, (i & 4 ? 1 : -1) * s.c};
        at(b);
      }
      break;
    case kCylinder: {
      const double xs[2] = {-0.5 * s.b, 0.5 * s.b}, rs[2] = {s.a, s.a};
      rims(xs, rs, 2);
      *bound = s.a * (1 - std::cos(M_PI / kAngles));
      break;
    }
    case kCone: {
      const double R = s.a * std::tan(s.b);
      const double xs[2] = {0.25 * s.a, -0.75 * s.a}, rs[2] = {R, 0};
      rims(xs, rs, 2);
      *bound = R * (1 - std::cos(M_PI / kAngles));
      break;
    }
  }
  return best;
}

dcol_shape *dcol_of(const Solid &s) {
  dcol_shape *out = nullptr;
  switch (s.kind) {
    case kSphere: dcol_shape_new_sphere(s.a, &out); break;
    case kBox: dcol_shape_new_box(s.a, s.b, s.c, &out); break;
    case kCapsule: dcol_shape_new_capsule(s.a, s.b, &out); break;
    case kCylinder: dcol_shape_new_cylinder(s.a, s.b, &out); break;
    case kCone: dcol_shape_new_cone(s.a, s.b, &out); break;
  }
  return out;
}

// dcol's contacts of a dcol shape at `pose` against the plane (a half-space of depth 1 whose
// boundary is the plane; its normal points out of the plane into the solid).
int dcol_plane_contacts(const dcol_shape *shape, const dcol_pose &pose, const dcol_plane::Plane &p, dcol_contact *cs,
                        std::size_t cap, double margin = 0) {
  static dcol_shape *hs = nullptr;
  if (!hs) dcol_shape_new_halfspace(1.0, &hs);
  dcol_pose hp;
  double q[4] = {1.0 + p.n[2], -p.n[1], p.n[0], 0.0};
  if (q[0] < 1e-12) q[0] = 0, q[1] = 1, q[2] = 0;
  const double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  for (int k = 0; k < 4; ++k) hp.quaternion[k] = q[k] / ql;
  for (int k = 0; k < 3; ++k) hp.position[k] = (p.d - 1.0) * p.n[k];
  std::size_t n = 0;
  const dcol_status st = dcol_contacts(hs, &hp, shape, &pose, margin, nullptr, cs, cap, &n);
  return st == DCOL_OK ? static_cast<int>(n) : -1;
}

int closed_form(const Solid &s, const dcol_plane::Plane &p, const dcol_plane::Frame &f, double m, dcol_plane::Points &pts) {
  switch (s.kind) {
    case kSphere: return dcol_plane::sphere(p, f.c, s.a, pts, m);
    case kBox: {
      const double h[3] = {s.a, s.b, s.c};
      return dcol_plane::box(p, f, h, pts, m);
    }
    case kCapsule: return dcol_plane::capsule(p, f, 0, s.a, s.b, pts, m);
    case kCylinder: return dcol_plane::cylinder(p, f, 0, s.a, s.b, pts, m);
    case kCone: return dcol_plane::cone(p, f, 0, s.a, s.a * std::tan(s.b), pts, m);
  }
  return -1;
}

void closed_forms() {
  const Solid solids[5] = {{kSphere, 0.3, 0, 0},
                           {kBox, 0.4, 0.25, 0.1},
                           {kCapsule, 0.15, 0.6, 0},
                           {kCylinder, 0.3, 0.5, 0},
                           {kCone, 0.6, 0.5, 0}};
  int cases = 0, touching = 0, same_sets = 0, reduced = 0;
  double worst_surface = 0, worst_dcol = 0;
  for (const Solid &s : solids) {
    dcol_shape *shape = dcol_of(s);
    expect(shape != nullptr, std::string(kNames[s.kind]) + ": dcol makes the shape");
    for (int trial = 0; trial < 600; ++trial) {
      dcol_plane::Plane p;
      double nn[3] = {unif(-0.5, 0.5), unif(-0.5, 0.5), unif(0.2, 1.0)};
      if (trial % 3 == 0) nn[0] = nn[1] = 0;  // a level floor
      const double nl = std::sqrt(dot(nn, nn));
      for (int k = 0; k < 3; ++k) p.n[k] = nn[k] / nl;
      p.d = unif(-0.5, 0.5);
      double q[4] = {unif() - 0.5, unif() - 0.5, unif() - 0.5, unif() - 0.5};
      if (trial % 5 == 1) q[1] = q[2] = q[3] = 0;  // aligned (a face, a cap, a capsule lying flat)
      if (trial % 5 == 2) q[1] = q[3] = 0, q[0] = 1, q[2] = 1;  // axis x along -z: caps and cone base level
      const double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      for (double &x : q) x /= ql;
      double R[3][3];
      rotation(q, R);
      dcol_plane::Frame f;
      for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) f.axis[k][i] = R[i][k];
      for (int i = 0; i < 3; ++i) f.c[i] = unif(-1, 1);
      // The deepest point at a chosen depth (0.05 above to 0.05 below, never within 1e-4 of 0).
      double bound = 0;
      const double now = brute_deepest(s, f, p, &bound);
      double want = unif(-0.05, 0.05);
      if (std::fabs(want) < 1e-4) want = 1e-3;
      if (trial % 5 != 0) want = std::fabs(want);
      for (int i = 0; i < 3; ++i) f.c[i] += (now - want) * p.n[i];
      const double deepest_bf = brute_deepest(s, f, p, &bound);
      dcol_plane::Points pts;
      // A margin of 0.03 in a quarter of the cases (deepest points from 0.05 above: some within it).
      const double margin = trial % 4 == 3 ? 0.03 : 0.0;
      if (margin > 0 && std::fabs(deepest_bf + margin) < 1e-4) continue;
      const int t = closed_form(s, p, f, margin, pts);
      ++cases;
      const std::string what = std::string(kNames[s.kind]) + " case " + std::to_string(trial);
      expect(t == (deepest_bf >= -margin ? 1 : 0), what + ": touching (or within the margin) as the brute force");
      if (t != 1) {
        expect(pts.count == 0, what + ": no points when apart");
        continue;
      }
      ++touching;
      double top = -INFINITY;
      for (int i = 0; i < pts.count; ++i) {
        top = std::max(top, pts.depth[i]);
        double solid[3], plane[3];
        for (int k = 0; k < 3; ++k) {
          solid[k] = pts.pos[i][k] - 0.5 * pts.depth[i] * p.n[k];
          plane[k] = pts.pos[i][k] + 0.5 * pts.depth[i] * p.n[k];
        }
        const double on_surface = surface_distance(s, f, solid), on_plane = std::fabs(dot(p.n, plane) - p.d);
        worst_surface = std::max(worst_surface, std::max(on_surface, on_plane));
        expect(on_surface <= 1e-12 && on_plane <= 1e-12, what + ": point on the surface and on the plane");
        expect(pts.depth[i] >= -margin - 1e-9, what + ": point within the margin and tolerance of the plane");
      }
      expect(top >= deepest_bf - 1e-12 && top <= deepest_bf + bound + 1e-12,
             what + ": largest depth the brute-force deepest");
      // dcol's own contacts (its pose: body x is the frame's axis 0).
      dcol_pose pose;
      for (int i = 0; i < 3; ++i) pose.position[i] = f.c[i];
      for (int k = 0; k < 4; ++k) pose.quaternion[k] = q[k];
      dcol_contact cs[16];
      const int m = dcol_plane_contacts(shape, pose, p, cs, 16, margin);
      expect(m >= 1, what + ": dcol finds contacts too");
      double dtop = -INFINITY;
      for (int i = 0; i < m; ++i) dtop = std::max(dtop, cs[i].depth);
      worst_dcol = std::max(worst_dcol, std::fabs(dtop - top));
      expect(std::fabs(dtop - top) <= 1e-12, what + ": largest depth dcol's");
      const bool disc = (s.kind == kCylinder && std::fabs(dot(p.n, f.axis[0])) >= 0.9 + 1e-9) ||
                        (s.kind == kCone && dot(p.n, f.axis[0]) <= -0.9 - 1e-9);
      if (s.kind == kBox || disc) {
        // The same points as dcol's (either order).
        bool same = m == pts.count;
        for (int i = 0; same && i < pts.count; ++i) {
          double nearest = INFINITY;
          for (int j = 0; j < m; ++j) {
            const double dx = cs[j].position[0] - pts.pos[i][0], dy = cs[j].position[1] - pts.pos[i][1],
                         dz = cs[j].position[2] - pts.pos[i][2];
            nearest = std::min(nearest, std::sqrt(dx * dx + dy * dy + dz * dz) + std::fabs(cs[j].depth - pts.depth[i]));
          }
          same = nearest <= 1e-12;
        }
        if (!same)
          std::printf("  %s: %d points, dcol %d\n", what.c_str(), pts.count, m);
        expect(same, what + ": the same points as dcol's");
        ++same_sets;
      }
      // The reduction: at most cap, the deepest first.
      for (int cap = 1; cap <= 4; ++cap) {
        int order[dcol_plane::kMaxPoints];
        const int k = dcol_plane::reduce(pts, cap, order);
        double kept = -INFINITY;
        for (int i = 0; i < k; ++i) kept = std::max(kept, pts.depth[order[i]]);
        expect(k == std::min(cap, pts.count) && kept == top, what + ": reduced, deepest kept");
        reduced += pts.count > cap;
      }
    }
    dcol_shape_free(shape);
  }
  std::printf("closed forms: %d cases, %d touching, %d compared point for point with dcol, %d reductions; "
              "worst distance from the surface or plane %.2e, largest depth vs dcol %.2e\n",
              cases, touching, same_sets, reduced, worst_surface, worst_dcol);
}

// ODE's own geoms through dCollide (use_dcol): the closed form against dcol_contacts on the shape
// and pose dcol_ode::shape_of gives, both orders, capacities 1 to 16.
void through_ode() {
  const int classes[4] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass};
  int calls = 0;
  double worst = 0;
  for (int cls : classes) {
    for (int trial = 0; trial < 200; ++trial) {
      double nn[3] = {unif(-0.4, 0.4), unif(-0.4, 0.4), 1.0};
      if (trial % 2 == 0) nn[0] = nn[1] = 0;
      const double nl = std::sqrt(dot(nn, nn));
      dcol_plane::Plane p;
      for (int k = 0; k < 3; ++k) p.n[k] = nn[k] / nl;
      p.d = unif(-0.3, 0.3);
      dGeomID plane = dCreatePlane(0, nn[0], nn[1], nn[2], p.d * nl);
      dGeomID g = make_geom(cls);
      if (trial % 4 != 1) random_attitude(g);
      const double h = lowest(g, p.n, p.d);
      const double depth = unif(0.001, 0.05);
      const dReal *at = dGeomGetPosition(g);
      dGeomSetPosition(g, at[0] - (h + depth) * p.n[0], at[1] - (h + depth) * p.n[1], at[2] - (h + depth) * p.n[2]);
      dcol_pose pose;
      const dcol_shape *shape = dcol_ode::shape_of(g, &pose);
      dcol_contact cs[16];
      const int m = dcol_plane_contacts(shape, pose, p, cs, 16);
      double dtop = -INFINITY;
      for (int i = 0; i < m; ++i) dtop = std::max(dtop, cs[i].depth);
      for (int cap = 1; cap <= 16; cap += 5) {
        for (int order = 0; order < 2; ++order) {
          dContactGeom c[16];
          const int k = order == 0 ? dCollide(g, plane, cap, c, sizeof(dContactGeom))
                                   : dCollide(plane, g, cap, c, sizeof(dContactGeom));
          ++calls;
          const std::string what = std::string(class_name(cls)) + " case " + std::to_string(trial);
          expect(k >= 1 && k <= cap, what + ": contacts within the capacity");
          double top = -INFINITY, ndev = 0;
          for (int i = 0; i < k; ++i) {
            top = std::max(top, double(c[i].depth));
            for (int j = 0; j < 3; ++j)
              ndev = std::max(ndev, std::fabs(c[i].normal[j] - (order == 0 ? 1 : -1) * p.n[j]));
            expect(c[i].g1 == (order == 0 ? g : plane) && c[i].g2 == (order == 0 ? plane : g), what + ": g1, g2");
          }
          worst = std::max(worst, std::fabs(top - dtop));
          expect(std::fabs(top - depth) <= 1e-12 && std::fabs(top - dtop) <= 1e-12 && ndev <= 1e-15,
                 what + ": largest depth dcol's and the placed one, the plane's normal into g1");
        }
      }
      destroy(g);
      destroy(plane);
    }
  }
  std::printf("through dCollide: %d calls (4 classes, both orders, capacities 1, 6, 11, 16), "
              "largest depth vs dcol_contacts %.2e\n", calls, worst);
}

}  // namespace

int main() {
  dInitODE2(0);
  dcol_ode::use_dcol();
  closed_forms();
  through_ode();
  dcol_ode::release_all();
  dCloseODE();
  const int failed = engine_scenes::failures();
  std::printf("%d checks, %d failed\n", checks(), failed);
  return failed == 0 ? 0 : 1;
}
