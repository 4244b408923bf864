// dcol_ode::create_convex and plain convexes under use_dcol(): a recorded convex goes to dcol
// (analytic depth and contact centre, its origin outside the points: the shift), plain
// dCreateConvex geoms keep ODE's own answers bit for bit in both orders (recorded before
// use_dcol()) and never reach dcol, dGeomSetConvex on a recorded convex drops the record, flat
// points leave the geom unrecorded, forget() drops a record.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "engine_scenes.hpp"
#include "override_test_util.hpp"

namespace {

using namespace override_test;

// The cube about a point 0.4 off its centre along x (the geom's origin outside the cube).
dReal g_shifted_points[24];
dReal g_shifted_planes[24];

// Convexes: a recorded one goes to dcol (the cube on a plane and against a sphere: analytic), a
// plain one keeps ODE's answers (recorded before the override) bit for bit, dGeomSetConvex drops
// the record, forget() too.
struct ConvexNative {
  int cls;
  dReal p[3];
  dMatrix3 R;
  Answer native, reversed;  // dCollide(convex, other) and dCollide(other, convex)
};
std::vector<ConvexNative> g_convex_native;

void record_convex_native() {
  const int classes[6] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass, dPlaneClass};
  for (int cls : classes)
    for (int k = 0; k < 10; ++k) {
      dGeomID a = dCreateConvex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
      dGeomID b = make_geom(cls, false);
      if (cls == dPlaneClass) {
        random_attitude(a);
        dGeomSetPosition(a, 0, 0, unif(0.1, 0.3));
      } else {
        random_pose_pair(a, b, 0.6);
      }
      ConvexNative s;
      s.cls = cls;
      std::memcpy(s.p, dGeomGetPosition(a), sizeof s.p);
      std::memcpy(s.R, dGeomGetRotation(a), sizeof(dMatrix3));
      s.native.n = dCollide(a, b, 8, s.native.c, sizeof(dContactGeom));
      s.reversed.n = dCollide(b, a, 8, s.reversed.c, sizeof(dContactGeom));
      g_convex_native.push_back(s);
      if (cls != dPlaneClass) {  // the other geom's pose in the next entry
        ConvexNative t = s;
        std::memcpy(t.p, dGeomGetPosition(b), sizeof t.p);
        std::memcpy(t.R, dGeomGetRotation(b), sizeof(dMatrix3));
        t.cls = -1;
        g_convex_native.push_back(t);
      }
      destroy(a);
      destroy(b);
    }
}

void convexes() {
  // Plain convexes: ODE's answers, bit for bit (g1, g2 aside: new geoms).
  int same = 0, cases = 0, contacts = 0;
  const unsigned long calls0 = dcol_ode::collider_calls();
  const dcol_ode::Stats s0 = dcol_ode::stats();
  for (std::size_t i = 0; i < g_convex_native.size(); ++i) {
    const ConvexNative &s = g_convex_native[i];
    dGeomID a = dCreateConvex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
    dGeomSetPosition(a, s.p[0], s.p[1], s.p[2]);
    dGeomSetRotation(a, s.R);
    dGeomID b = make_geom(s.cls, false);
    if (s.cls != dPlaneClass) {
      const ConvexNative &t = g_convex_native[++i];
      dGeomSetPosition(b, t.p[0], t.p[1], t.p[2]);
      dGeomSetRotation(b, t.R);
    }
    dContactGeom c[8], r[8];
    const int n = dCollide(a, b, 8, c, sizeof(dContactGeom));
    const int nr = dCollide(b, a, 8, r, sizeof(dContactGeom));
    auto same_as = [](const dContactGeom *x, int nx, const Answer &y, dGeomID g1, dGeomID g2) {
      bool eq = nx == y.n;
      for (int k = 0; eq && k < nx; ++k)
        eq = std::memcmp(x[k].pos, y.c[k].pos, 3 * sizeof(dReal)) == 0 &&
             std::memcmp(x[k].normal, y.c[k].normal, 3 * sizeof(dReal)) == 0 && x[k].depth == y.c[k].depth &&
             x[k].g1 == g1 && x[k].g2 == g2;
      return eq;
    };
    const bool ok = same_as(c, n, s.native, a, b) && same_as(r, nr, s.reversed, b, a);
    if (!ok) {
      std::printf("  plain convex against %s: %d contacts (ODE before: %d)\n", class_name(s.cls), n, s.native.n);
      for (int k = 0; k < std::max(n, s.native.n) && k < 8; ++k)
        std::printf("    depth %.12f n (%.9f %.9f %.9f) | before %.12f n (%.9f %.9f %.9f)\n", c[k].depth, c[k].normal[0],
                    c[k].normal[1], c[k].normal[2], s.native.c[k].depth, s.native.c[k].normal[0], s.native.c[k].normal[1],
                    s.native.c[k].normal[2]);
    }
    same += ok;
    contacts += n;
    ++cases;
    destroy(a);
    destroy(b);
  }
  const dcol_ode::Stats s1 = dcol_ode::stats();
  std::printf("plain dCreateConvex: %d of %d pairs (both orders) answered as ODE did before use_dcol(), %d contacts; "
              "dcol collider calls %lu, handed to ODE %lu, no ODE collider %lu\n",
              same, cases, contacts, dcol_ode::collider_calls() - calls0, s1.native_calls - s0.native_calls,
              s1.native_missing - s0.native_missing);
  expect(same == cases && contacts > 0, "plain convexes keep ODE's own answers");
  expect(dcol_ode::collider_calls() == calls0 && s1.native_missing == s0.native_missing,
         "plain convexes never reach dcol, and ODE's collider was found for every pair");

  // A recorded convex (the cube about an origin outside it: the record shifts it) on the plane
  // and against a sphere.
  dGeomID cube = dcol_ode::create_convex(0, g_shifted_planes, 6, g_shifted_points, 8, kCubePolygons);
  expect(dcol_ode::is_recorded_convex(cube), "create_convex records the convex");
  dGeomID plane = dCreatePlane(0, 0, 0, 1, 0);
  dMatrix3 R;
  dRFromAxisAndAngle(R, 0, 0, 1, 0.5);  // turned about z: the shift turns with it
  dGeomSetRotation(cube, R);
  dGeomSetPosition(cube, 0, 0, 0.25 - 0.002);
  dContactGeom c[8];
  const unsigned long calls1 = dcol_ode::collider_calls();
  int n = dCollide(cube, plane, 8, c, sizeof(dContactGeom));
  // The cube's centre is 0.4 along the geom's x axis, turned 0.5 rad: (0.4 cos .5, 0.4 sin .5).
  double mx = 0, my = 0;
  for (int i = 0; i < n; ++i) {
    mx += c[i].pos[0] / n;
    my += c[i].pos[1] / n;
  }
  std::printf("recorded convex on the plane: %d contacts, depth %.6f, centre of contacts (%.6f, %.6f) want (%.6f, %.6f)\n",
              n, n ? max_depth(c, n) : 0.0, mx, my, 0.4 * std::cos(0.5), 0.4 * std::sin(0.5));
  expect(n == 4 && std::fabs(max_depth(c, n) - 0.002) < 1e-12 && std::fabs(mx - 0.4 * std::cos(0.5)) < 1e-9 &&
             std::fabs(my - 0.4 * std::sin(0.5)) < 1e-9 && dcol_ode::collider_calls() == calls1 + 1,
         "a recorded convex goes to dcol, its shift turning with it");
  dGeomID ball = dCreateSphere(0, 0.1);
  dGeomSetPosition(ball, 0.4 * std::cos(0.5), 0.4 * std::sin(0.5), 0.25 - 0.002 + 0.25 + 0.1 - 0.01);
  n = dCollide(ball, cube, 8, c, sizeof(dContactGeom));
  expect(n == 1 && std::fabs(c[0].depth - 0.01) < 1e-12 && c[0].normal[2] > 1 - 1e-12, "sphere on a recorded convex: depth and normal");
  // dGeomSetConvex with other points: the record no longer matches ODE's box and is dropped.
  const unsigned long dropped = dcol_ode::stats().dropped_records;
  dGeomSetConvex(cube, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
  dGeomSetPosition(cube, 0, 0, 0.25 - 0.002);  // moved: ODE's box is computed again
  const unsigned long calls2 = dcol_ode::collider_calls();
  n = dCollide(cube, plane, 8, c, sizeof(dContactGeom));
  expect(!dcol_ode::is_recorded_convex(cube) && dcol_ode::stats().dropped_records == dropped + 1 &&
             dcol_ode::collider_calls() == calls2 && n == 4,
         "dGeomSetConvex drops the record: ODE's collider answers");
  // Points that make no hull (the cube's top face only: flat): the geom is made, not recorded.
  const unsigned long unrecorded = dcol_ode::stats().unrecorded_convexes;
  dGeomID flat = dcol_ode::create_convex(0, kCubePlanes, 6, kCubePoints + 12, 4, kCubePolygons);
  expect(flat && !dcol_ode::is_recorded_convex(flat) && dcol_ode::stats().unrecorded_convexes == unrecorded + 1,
         "create_convex with flat points: a plain convex, counted");
  destroy(flat);
  dGeomID cube2 = dcol_ode::create_convex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
  expect(dcol_ode::is_recorded_convex(cube2), "a second recorded convex");
  dcol_ode::forget(cube2);
  expect(!dcol_ode::is_recorded_convex(cube2), "forget() drops the record");
  destroy(cube2);
  destroy(ball);
  destroy(cube);
  destroy(plane);
}

}  // namespace

int main() {
  for (int i = 0; i < 8; ++i) {
    g_shifted_points[3 * i] = kCubePoints[3 * i] + 0.4;
    g_shifted_points[3 * i + 1] = kCubePoints[3 * i + 1];
    g_shifted_points[3 * i + 2] = kCubePoints[3 * i + 2];
  }
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 3; ++j) g_shifted_planes[4 * i + j] = kCubePlanes[4 * i + j];
    g_shifted_planes[4 * i + 3] = kCubePlanes[4 * i + 3] + 0.4 * kCubePlanes[4 * i];
  }
  dInitODE2(0);
  record_convex_native();  // ODE's own answers, before the override
  dcol_ode::use_dcol();
  convexes();
  dcol_ode::release_all();
  dCloseODE();
  std::printf("%d checks, %s\n", checks(), engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
