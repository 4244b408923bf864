// What the use_dcol() test programs (ode_override_tests.cpp, ode_convex_tests.cpp) share: checks,
// a seeded random source, the test geoms, analytic lowest points.
#ifndef DCOL_ODE_OVERRIDE_TEST_UTIL_HPP
#define DCOL_ODE_OVERRIDE_TEST_UTIL_HPP

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "dcol_ode.hpp"
#include "engine_scenes.hpp"

namespace override_test {

/// Checks made so far.
inline int &checks() {
  static int n = 0;
  return n;
}

inline void expect(bool ok, const std::string &what) {
  ++checks();
  engine_scenes::check(ok, what.c_str());
}

inline double unif() {
  static unsigned long long rng = 0x2545F4914F6CDD1DULL;
  rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
  return double(rng >> 11) / double(1ULL << 53);
}
inline double unif(double a, double b) { return a + (b - a) * unif(); }

inline void random_rotation(dMatrix3 R) {
  dQuaternion q = {unif() - 0.5, unif() - 0.5, unif() - 0.5, unif() - 0.5};
  dNormalize4(q);
  dQtoR(q, R);
}

inline void random_attitude(dGeomID g) {
  dMatrix3 R;
  random_rotation(R);
  dGeomSetRotation(g, R);
}

inline const char *class_name(int c) {
  switch (c) {
    case dSphereClass: return "sphere";
    case dBoxClass: return "box";
    case dCapsuleClass: return "capsule";
    case dCylinderClass: return "cylinder";
    case dConvexClass: return "convex";
    case dPlaneClass: return "plane";
    default: return "other";
  }
}

// A convex cube of half side 0.25 (ODE's arrays: the geom keeps pointers to them).
const dReal kCubePlanes[24] = {1, 0, 0, 0.25, -1, 0, 0, 0.25, 0, 1, 0, 0.25, 0, -1, 0, 0.25, 0, 0, 1, 0.25, 0, 0, -1, 0.25};
const dReal kCubePoints[24] = {-0.25, -0.25, -0.25, 0.25, -0.25, -0.25, -0.25, 0.25, -0.25, 0.25, 0.25, -0.25,
                               -0.25, -0.25, 0.25,  0.25, -0.25, 0.25,  -0.25, 0.25, 0.25,  0.25, 0.25, 0.25};
const unsigned kCubePolygons[30] = {4, 1, 3, 7, 5, 4, 0, 4, 6, 2, 4, 2, 6, 7, 3, 4, 0, 1, 5, 4, 4, 4, 5, 7, 6, 4, 0, 2, 3, 1};

inline dGeomID make_geom(int cls, bool recorded_convex = true) {
  switch (cls) {
    case dSphereClass: return dCreateSphere(0, 0.3);
    case dBoxClass: return dCreateBox(0, 0.5, 0.4, 0.3);
    case dCapsuleClass: return dCreateCapsule(0, 0.15, 0.5);
    case dCylinderClass: return dCreateCylinder(0, 0.2, 0.5);
    case dConvexClass:
      return recorded_convex ? dcol_ode::create_convex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons)
                             : dCreateConvex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
    default: return dCreatePlane(0, 0, 0, 1, 0);
  }
}

// Destroys a geom, first dropping the adapter's record of it (the lifetime rule of create_convex).
inline void destroy(dGeomID g) {
  dcol_ode::forget(g);
  dGeomDestroy(g);
}

// The lowest point of a geom above the plane n.x = d (n unit): the analytic signed height.
inline double lowest(dGeomID g, const double n[3], double d) {
  const dReal *p = dGeomGetPosition(g);
  const dReal *R = dGeomGetRotation(g);
  double nb[3];  // n in the geom's frame: R^T n
  for (int j = 0; j < 3; ++j) nb[j] = R[j] * n[0] + R[4 + j] * n[1] + R[8 + j] * n[2];
  double h = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d;
  switch (dGeomGetClass(g)) {
    case dSphereClass: return h - dGeomSphereGetRadius(g);
    case dBoxClass: {
      dVector3 l;
      dGeomBoxGetLengths(g, l);
      return h - 0.5 * (l[0] * std::fabs(nb[0]) + l[1] * std::fabs(nb[1]) + l[2] * std::fabs(nb[2]));
    }
    case dCapsuleClass: {
      dReal r, l;
      dGeomCapsuleGetParams(g, &r, &l);
      return h - r - 0.5 * l * std::fabs(nb[2]);
    }
    case dCylinderClass: {
      dReal r, l;
      dGeomCylinderGetParams(g, &r, &l);
      return h - 0.5 * l * std::fabs(nb[2]) - r * std::sqrt(std::max(0.0, 1 - nb[2] * nb[2]));
    }
    default: {  // the convex cube (its points)
      double m = 1e300;
      for (int i = 0; i < 8; ++i) {
        const double *b = &kCubePoints[3 * i];
        m = std::min(m, nb[0] * b[0] + nb[1] * b[1] + nb[2] * b[2]);
      }
      return h + m;
    }
  }
}

inline double max_depth(const dContactGeom *c, int n) {
  double m = -1e300;
  for (int i = 0; i < n; ++i) m = std::max(m, c[i].depth);
  return m;
}

// Random overlapping poses of two geoms of the given classes (their centres closer than the sum of
// bounding radii times 0.8).
inline void random_pose_pair(dGeomID a, dGeomID b, double reach) {
  dMatrix3 R;
  random_rotation(R);
  dGeomSetRotation(a, R);
  random_rotation(R);
  dGeomSetRotation(b, R);
  dGeomSetPosition(a, unif(-0.1, 0.1), unif(-0.1, 0.1), unif(-0.1, 0.1));
  double u[3] = {unif(-1, 1), unif(-1, 1), unif(-1, 1)};
  const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  const double r = unif(0.3, 0.8) * reach;
  dGeomSetPosition(b, u[0] / ul * r, u[1] / ul * r, u[2] / ul * r);
}

struct Answer {
  int n;
  dContactGeom c[8];
};

}  // namespace override_test

#endif
