// ODE's own colliders for plain convexes (dCreateConvex geoms the adapter has no points for).
//
// dSetColliderOverride replaces ODE's collider for a pair of classes, and ODE has no getter for
// the collider it replaces. libode exports its collider functions, though (C++ names such as
// dCollideConvexBoxCCD(dxGeom*, dxGeom*, int, dContactGeom*, int)), and which of them ODE's table
// holds depends on how ODE was built (with libccd or without). So before the overrides, each
// candidate found in the process by its symbol name is run on a probe pair (a plain convex cube
// against a geom of the other class, overlapping) and the one whose contacts equal dCollide's
// bit for bit is kept for that pair. A pair with no match (another ODE version, or a build with no
// collider for it) has no native collider: such pairs get no contacts and are counted.
#include <dlfcn.h>

#include <cmath>
#include <cstring>

#include "dcol_ode_internal.hpp"

namespace dcol_ode {
namespace detail {
namespace {

// The six classes a plain convex meets here, as an index.
const int kOthers[6] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass, dPlaneClass};

int other_index(int cls) {
  for (int i = 0; i < 6; ++i)
    if (kOthers[i] == cls) return i;
  return -1;
}

struct Candidate {
  const char *symbol;  // the function's mangled name in libode
  bool convex_first;   // its first geom argument is the convex (else the other geom)
};

// ODE 0.16's colliders for a convex against each class (collision_kernel.cpp, initColliders):
// the libccd one first, then the one ODE uses without libccd.
const Candidate kCandidates[6][2] = {
    {{"_Z23dCollideConvexSphereCCDP6dxGeomS0_iP12dContactGeomi", true},
     {"_Z20dCollideSphereConvexP6dxGeomS0_iP12dContactGeomi", false}},
    {{"_Z20dCollideConvexBoxCCDP6dxGeomS0_iP12dContactGeomi", true},
     {"_Z17dCollideConvexBoxP6dxGeomS0_iP12dContactGeomi", true}},
    {{"_Z24dCollideConvexCapsuleCCDP6dxGeomS0_iP12dContactGeomi", true},
     {"_Z21dCollideConvexCapsuleP6dxGeomS0_iP12dContactGeomi", true}},
    {{"_Z25dCollideConvexCylinderCCDP6dxGeomS0_iP12dContactGeomi", true}, {nullptr, true}},
    {{"_Z23dCollideConvexConvexCCDP6dxGeomS0_iP12dContactGeomi", true},
     {"_Z20dCollideConvexConvexP6dxGeomS0_iP12dContactGeomi", true}},
    {{"_Z19dCollideConvexPlaneP6dxGeomS0_iP12dContactGeomi", true}, {nullptr, true}},
};

struct Native {
  dColliderFn *fn = nullptr;
  bool convex_first = true;
};
Native g_native[6];

// Calls `fn` on (convex, other) in its own argument order and returns the contacts as
// dCollide(o1, o2) reports them (normal into o1, g1 = o1): when the function's first geom is not
// o1, the normals turn and g1/g2, side1/side2 swap, as dCollide does for a reversed entry.
int call(const Native &n, dGeomID o1, dGeomID convex, dGeomID other, int flags, dContactGeom *contact, int skip) {
  dGeomID a = n.convex_first ? convex : other;
  dGeomID b = n.convex_first ? other : convex;
  const int count = n.fn(a, b, flags, contact, skip);
  if (a != o1) {
    for (int i = 0; i < count; ++i) {
      dContactGeom *c = reinterpret_cast<dContactGeom *>(reinterpret_cast<char *>(contact) + i * skip);
      for (int k = 0; k < 3; ++k) c->normal[k] = -c->normal[k];
      dGeomID g = c->g1;
      c->g1 = c->g2;
      c->g2 = g;
      const int s = c->side1;
      c->side1 = c->side2;
      c->side2 = s;
    }
  }
  return count;
}

bool same(const dContactGeom &x, const dContactGeom &y) {
  return std::memcmp(x.pos, y.pos, sizeof(dReal) * 3) == 0 && std::memcmp(x.normal, y.normal, sizeof(dReal) * 3) == 0 &&
         std::memcmp(&x.depth, &y.depth, sizeof(dReal)) == 0 && x.g1 == y.g1 && x.g2 == y.g2;
}

// A cube of side 0.6 as ODE's convex (arrays ODE keeps pointers to: static).
const dReal kCubePlanes[24] = {1, 0, 0, 0.3, -1, 0, 0, 0.3, 0, 1, 0, 0.3, 0, -1, 0, 0.3, 0, 0, 1, 0.3, 0, 0, -1, 0.3};
const dReal kCubePoints[24] = {-0.3, -0.3, -0.3, 0.3, -0.3, -0.3, -0.3, 0.3, -0.3, 0.3, 0.3, -0.3,
                               -0.3, -0.3, 0.3,  0.3, -0.3, 0.3,  -0.3, 0.3, 0.3,  0.3, 0.3, 0.3};
const unsigned kCubePolygons[30] = {4, 1, 3, 7, 5, 4, 0, 4, 6, 2, 4, 2, 6, 7, 3, 4, 0, 1, 5, 4, 4, 4, 5, 7, 6, 4, 0, 2, 3, 1};

dGeomID probe_geom(int cls) {
  switch (cls) {
    case dSphereClass: return dCreateSphere(0, 0.3);
    case dBoxClass: return dCreateBox(0, 0.5, 0.6, 0.7);
    case dCapsuleClass: return dCreateCapsule(0, 0.2, 0.6);
    case dCylinderClass: return dCreateCylinder(0, 0.3, 0.6);
    case dConvexClass: return dCreateConvex(0, kCubePlanes, 6, kCubePoints, 8, kCubePolygons);
    default: return dCreatePlane(0, 0.1, 0.05, 1.0, 0.0);
  }
}

}  // namespace

void find_native_colliders() {
  for (int i = 0; i < 6; ++i) {
    g_native[i] = Native();
    dGeomID convex = probe_geom(dConvexClass);
    dGeomID other = probe_geom(kOthers[i]);
    // Tilted and overlapping by about a tenth of their size, so that every collider answers
    // and different colliders answer differently.
    dMatrix3 R;
    dRFromEulerAngles(R, 0.3, 0.2, 0.1);
    dGeomSetRotation(convex, R);
    dGeomSetPosition(convex, 0.02, 0.01, 0.25);
    if (kOthers[i] != dPlaneClass) {
      dRFromEulerAngles(R, -0.2, 0.25, 0.4);
      dGeomSetRotation(other, R);
      dGeomSetPosition(other, -0.03, 0.04, -0.3);
    }
    dContactGeom want[8], got[8];
    const int n_want = dCollide(convex, other, 8, want, sizeof(dContactGeom));
    for (int c = 0; c < 2 && n_want > 0; ++c) {
      const Candidate &cand = kCandidates[i][c];
      if (!cand.symbol) continue;
      Native n;
      n.fn = reinterpret_cast<dColliderFn *>(dlsym(RTLD_DEFAULT, cand.symbol));
      n.convex_first = cand.convex_first;
      if (!n.fn) continue;
      const int n_got = call(n, convex, convex, other, 8, got, sizeof(dContactGeom));
      bool match = n_got == n_want;
      for (int k = 0; match && k < n_got; ++k) match = same(want[k], got[k]);
      if (match) {
        g_native[i] = n;
        break;
      }
    }
    dGeomDestroy(convex);
    dGeomDestroy(other);
  }
}

int collide_native(dGeomID o1, dGeomID o2, int flags, dContactGeom *contact, int skip) {
  ++counters().native_calls;
  // Two convexes: ODE's own table calls its collider as (o1, o2) of dCollide, but an override of
  // a class against itself is entered reversed (dSetColliderOverride(i, i) leaves reverse = 1), so
  // here o1 and o2 are dCollide's swapped: call it on (o2, o1), and call() turns the contacts
  // back into this call's order, which dCollide then reverses again.
  const bool first_is_convex = dGeomGetClass(o1) == dConvexClass && dGeomGetClass(o2) != dConvexClass;
  dGeomID convex = first_is_convex ? o1 : o2;
  dGeomID other = first_is_convex ? o2 : o1;
  const int i = other_index(dGeomGetClass(other));
  if (i < 0 || !g_native[i].fn) {
    ++counters().native_missing;
    return 0;
  }
  return call(g_native[i], o1, convex, other, flags, contact, skip);
}

}  // namespace detail
}  // namespace dcol_ode
