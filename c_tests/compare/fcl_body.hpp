// fcl_body.hpp: a compare_common.h body as an FCL geometry and transform, shared by the
// comparison test (c_tests/compare/test_fcl.cpp) and the time-vs-error benchmark
// (benches/compare/bench_compare.cpp) so that both compare against the same FCL shapes.
//
// Frames: FCL's capsule, cylinder and cone have axis z, and FCL's cone has its origin at half
// height with the apex at +z; dcol's have axis x, and dcol's cone has its origin at the
// centroid with the apex at -3H/4 x. A dcol body point is b = M f + o for the FCL body point f,
// M = [[0,0,-1],[0,1,0],[1,0,0]] (FCL's +z, the cone's apex side, is dcol's -x), o = -H/4 x for
// the cone and 0 otherwise; FCL's pose is then (R M, r + R o). FCL's ellipsoid is axis-aligned
// with radii (a, b, c): dcol's is P = diag(1/a^2, 1/b^2, 1/c^2), both rotated by the pose.
// Padded polygons have no FCL counterpart (the geometry is left empty).
#ifndef DCOL_COMPARE_FCL_BODY_HPP
#define DCOL_COMPARE_FCL_BODY_HPP

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cone.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/ellipsoid.h>
#include <fcl/geometry/shape/sphere.h>

#include <cmath>
#include <memory>
#include <vector>

#include "compare_common.h"

/// An FCL geometry with its world transform.
struct FclBody {
  std::shared_ptr<fcl::CollisionGeometryd> geom;
  fcl::Transform3d tf;
};

/// The FCL geometry and transform of a dcol comparison body (see the frames above).
inline FclBody to_fcl(const cmp_body& body) {
  const cmp_shape& s = *body.shape;
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = body.R[3 * i + j];
  const Eigen::Vector3d r(body.pose.position[0], body.pose.position[1], body.pose.position[2]);
  Eigen::Matrix3d M;
  M << 0, 0, -1, 0, 1, 0, 1, 0, 0;
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  bool axial = false;
  FclBody out;
  switch (s.kind) {
    case CMP_SPHERE:
      out.geom = std::make_shared<fcl::Sphered>(s.radius);
      break;
    case CMP_ELLIPSOID:
      out.geom = std::make_shared<fcl::Ellipsoidd>(s.radii[0], s.radii[1], s.radii[2]);
      break;
    case CMP_BOX:
      out.geom = std::make_shared<fcl::Boxd>(2 * s.half[0], 2 * s.half[1], 2 * s.half[2]);
      break;
    case CMP_POLYTOPE: {
      // the vertices of the H-representation, and per facet a counter-clockwise vertex loop
      auto verts = std::make_shared<std::vector<Eigen::Vector3d>>();
      for (size_t u = 0; u < s.nv; ++u)
        verts->emplace_back(s.V[3 * u], s.V[3 * u + 1], s.V[3 * u + 2]);
      auto faces = std::make_shared<std::vector<int>>();
      for (size_t f = 0; f < s.nfaces; ++f) {
        faces->push_back(static_cast<int>(s.face_start[f + 1] - s.face_start[f]));
        for (size_t k = s.face_start[f]; k < s.face_start[f + 1]; ++k)
          faces->push_back(s.face_index[k]);
      }
      // throw_if_invalid: FCL checks the mesh is closed and convex
      out.geom = std::make_shared<fcl::Convexd>(verts, static_cast<int>(s.nfaces), faces, true);
      break;
    }
    case CMP_CAPSULE:
      out.geom = std::make_shared<fcl::Capsuled>(s.radius, s.length);
      axial = true;
      break;
    case CMP_CYLINDER:
      out.geom = std::make_shared<fcl::Cylinderd>(s.radius, s.length);
      axial = true;
      break;
    case CMP_CONE:
      out.geom = std::make_shared<fcl::Coned>(s.height * std::tan(s.half_angle), s.height);
      axial = true;
      o = Eigen::Vector3d(-0.25 * s.height, 0, 0);
      break;
    default:
      break;
  }
  if (out.geom) out.geom->computeLocalAABB();
  out.tf.setIdentity();
  out.tf.linear() = axial ? Eigen::Matrix3d(R * M) : R;
  out.tf.translation() = r + R * o;
  return out;
}

#endif  // DCOL_COMPARE_FCL_BODY_HPP
