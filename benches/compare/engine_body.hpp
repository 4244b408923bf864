// engine_body.hpp: a compare_common.h body as an ODE geom and as a Bullet convex shape, for the
// contact-query comparison in bench_compare.cpp (dcol_contacts vs ODE's dCollide vs Bullet's
// GJK/EPA). Both are built only for the kinds the engines have: sphere, box, polytope, capsule,
// cylinder (engine_kind()).
//
// Frames: dcol's capsule and cylinder have axis x. ODE's (dCreateCapsule, dCreateCylinder) have
// axis z: the geom's rotation is R M with M = [[0,0,-1],[0,1,0],[1,0,0]] (ODE's z is dcol's -x, as
// in fcl_body.hpp). Bullet's btCapsuleShapeX / btCylinderShapeX have axis x: no change.
// Polytopes: ODE's dCreateConvex from the vertices and, per face, its counter-clockwise vertex
// loop and its plane (unit normal from the loop, Newell's method); Bullet's btConvexHullShape
// from the vertices. Bullet's collision margin is set to 0 on boxes, cylinders and hulls (boxes
// and cylinders keep their outer size; a hull would otherwise grow by 0.04); spheres and
// capsules keep theirs, which is their radius. Bullet is single precision (btScalar float on
// Debian): poses and sizes are rounded to float once, when the shapes are built.
#ifndef DCOL_BENCH_ENGINE_BODY_HPP
#define DCOL_BENCH_ENGINE_BODY_HPP

#include <cmath>
#include <memory>
#include <vector>

#include "compare_common.h"

inline bool engine_kind(int k) {
  return k == CMP_SPHERE || k == CMP_BOX || k == CMP_POLYTOPE || k == CMP_CAPSULE ||
         k == CMP_CYLINDER;
}

// ---- ODE ----------------------------------------------------------------------------------
#ifdef DCOL_BENCH_HAVE_ODE
#include <ode/ode.h>

struct OdeBody {
  dGeomID geom = nullptr;
  // dCreateConvex keeps pointers to these
  std::vector<dReal> planes, points;
  std::vector<unsigned> polygons;
  OdeBody() = default;
  OdeBody(const OdeBody&) = delete;
  OdeBody& operator=(const OdeBody&) = delete;
  ~OdeBody() {
    if (geom) dGeomDestroy(geom);
  }
};

inline std::unique_ptr<OdeBody> to_ode(const cmp_body& body) {
  const cmp_shape& s = *body.shape;
  auto out = std::make_unique<OdeBody>();
  bool axial = false;
  switch (s.kind) {
    case CMP_SPHERE:
      out->geom = dCreateSphere(nullptr, s.radius);
      break;
    case CMP_BOX:
      out->geom = dCreateBox(nullptr, 2 * s.half[0], 2 * s.half[1], 2 * s.half[2]);
      break;
    case CMP_CAPSULE:
      out->geom = dCreateCapsule(nullptr, s.radius, s.length);
      axial = true;
      break;
    case CMP_CYLINDER:
      out->geom = dCreateCylinder(nullptr, s.radius, s.length);
      axial = true;
      break;
    case CMP_POLYTOPE: {
      for (size_t u = 0; u < 3 * s.nv; ++u) out->points.push_back(s.V[u]);
      for (size_t f = 0; f < s.nfaces; ++f) {
        const size_t a = s.face_start[f], e = s.face_start[f + 1];
        out->polygons.push_back(static_cast<unsigned>(e - a));
        double n[3] = {0, 0, 0};
        for (size_t k = a; k < e; ++k) {
          const double* p = &s.V[3 * s.face_index[k]];
          const double* q = &s.V[3 * s.face_index[k + 1 < e ? k + 1 : a]];
          n[0] += (p[1] - q[1]) * (p[2] + q[2]);
          n[1] += (p[2] - q[2]) * (p[0] + q[0]);
          n[2] += (p[0] - q[0]) * (p[1] + q[1]);
          out->polygons.push_back(static_cast<unsigned>(s.face_index[k]));
        }
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double d = 0;
        for (size_t k = a; k < e; ++k)
          for (int q = 0; q < 3; ++q) d += n[q] / len * s.V[3 * s.face_index[k] + q] / double(e - a);
        for (int q = 0; q < 3; ++q) out->planes.push_back(n[q] / len);
        out->planes.push_back(d);
      }
      out->geom = dCreateConvex(nullptr, out->planes.data(), static_cast<unsigned>(s.nfaces),
                                out->points.data(), static_cast<unsigned>(s.nv),
                                out->polygons.data());
      break;
    }
    default:
      return nullptr;
  }
  // R (row-major, world-from-body), times M for the axial shapes; dMatrix3 is 3x4 row-major
  static const double M[9] = {0, 0, -1, 0, 1, 0, 1, 0, 0};
  dMatrix3 Rm;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double v = body.R[3 * i + j];
      if (axial) {
        v = 0;
        for (int k = 0; k < 3; ++k) v += body.R[3 * i + k] * M[3 * k + j];
      }
      Rm[4 * i + j] = v;
    }
    Rm[4 * i + 3] = 0;
  }
  dGeomSetRotation(out->geom, Rm);
  dGeomSetPosition(out->geom, body.pose.position[0], body.pose.position[1],
                   body.pose.position[2]);
  return out;
}
#endif

// ---- Bullet -------------------------------------------------------------------------------
#ifdef DCOL_BENCH_HAVE_BULLET
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

struct BulletBody {
  std::unique_ptr<btConvexShape> shape;
  btTransform tf;
};

inline std::unique_ptr<BulletBody> to_bullet(const cmp_body& body) {
  const cmp_shape& s = *body.shape;
  auto out = std::make_unique<BulletBody>();
  auto f = [](double v) { return static_cast<btScalar>(v); };
  switch (s.kind) {
    case CMP_SPHERE:
      out->shape = std::make_unique<btSphereShape>(f(s.radius));
      break;
    case CMP_BOX:
      out->shape = std::make_unique<btBoxShape>(btVector3(f(s.half[0]), f(s.half[1]), f(s.half[2])));
      out->shape->setMargin(0);
      break;
    case CMP_CAPSULE:
      out->shape = std::make_unique<btCapsuleShapeX>(f(s.radius), f(s.length));
      break;
    case CMP_CYLINDER:
      out->shape = std::make_unique<btCylinderShapeX>(
          btVector3(f(0.5 * s.length), f(s.radius), f(s.radius)));
      out->shape->setMargin(0);
      break;
    case CMP_POLYTOPE: {
      auto hull = std::make_unique<btConvexHullShape>();
      for (size_t u = 0; u < s.nv; ++u)
        hull->addPoint(btVector3(f(s.V[3 * u]), f(s.V[3 * u + 1]), f(s.V[3 * u + 2])), false);
      hull->recalcLocalAabb();
      hull->setMargin(0);
      out->shape = std::move(hull);
      break;
    }
    default:
      return nullptr;
  }
  btMatrix3x3 R(f(body.R[0]), f(body.R[1]), f(body.R[2]), f(body.R[3]), f(body.R[4]),
                f(body.R[5]), f(body.R[6]), f(body.R[7]), f(body.R[8]));
  out->tf = btTransform(R, btVector3(f(body.pose.position[0]), f(body.pose.position[1]),
                                     f(body.pose.position[2])));
  return out;
}

// What btConvexConvexAlgorithm gets from the detector for one contact point: the deepest point.
struct BulletContact : btDiscreteCollisionDetectorInterface::Result {
  bool hit = false;
  btScalar depth = 0;  // Bullet's distance: < 0 penetrating
  btVector3 normal, point;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3& n, const btVector3& p, btScalar d) override {
    if (d > 0) return;  // separated (within the margins' reach): no contact at margin 0
    if (!hit || d < depth) hit = true, depth = d, normal = n, point = p;
  }
};

// One contact query: GJK, EPA when they overlap. As btConvexConvexAlgorithm (with a contact
// breaking threshold of 0), the maximum distance is the sum of the margins (GJK runs on the shapes
// shrunk by their margins: for spheres and capsules the centre point / segment); reported
// distances > 0 are dropped, so that a contact means touching or penetrating, as dcol_contacts
// with margin 0.
inline void bullet_contact(const BulletBody& a, const BulletBody& b, BulletContact& res) {
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  btGjkPairDetector gjk(a.shape.get(), b.shape.get(), &simplex, &epa);
  btDiscreteCollisionDetectorInterface::ClosestPointInput input;
  input.m_transformA = a.tf;
  input.m_transformB = b.tf;
  const btScalar reach = a.shape->getMargin() + b.shape->getMargin();
  input.m_maximumDistanceSquared = reach * reach;
  gjk.getClosestPoints(input, res, nullptr);
}
#endif

#endif  // DCOL_BENCH_ENGINE_BODY_HPP
