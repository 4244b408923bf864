// coal_body.hpp: a compare_common.h body as a Coal 3 geometry and transform, the same mapping as
// c_tests/compare/fcl_body.hpp (Coal keeps FCL's shape conventions).
//
// Frames: Coal's capsule, cylinder and cone have axis z with half-length parameters (the
// constructors take the full length), and Coal's cone has its origin at half height with the
// apex at +z; dcol's have axis x with full length L, and dcol's cone has its origin at the
// centroid with the apex at -3H/4 x. A dcol body point is b = M f + o for the Coal body point f,
// M = [[0,0,-1],[0,1,0],[1,0,0]] (Coal's +z, the cone's apex side, is dcol's -x), o = -H/4 x for
// the cone and 0 otherwise; Coal's pose is then (R M, r + R o). Coal's ellipsoid is axis-aligned
// with radii (a, b, c): dcol's is P = diag(1/a^2, 1/b^2, 1/c^2), both rotated by the pose.
// The 12-facet polytope is a coal::Convex<Triangle> on the vertices of its H-representation,
// each facet's counter-clockwise vertex loop split into a triangle fan (Coal's convex shapes
// store triangles; the fan keeps the facets' orientation, and Coal builds the vertex neighbour
// graph for its hill-climbing support from them). A padded polygon is a flat
// coal::Convex<Triangle> (its vertices at z = 0, a triangle fan) with Coal's swept-sphere radius
// set to the padding (Coal runs GJK on the flat core and subtracts the radius, as dcol's distance
// does); bench_compare still leaves polygon pairs out (FCL has no such shape), bench_posesets
// and bench_trajectory use it.
#ifndef DCOL_BENCH_COAL_BODY_HPP
#define DCOL_BENCH_COAL_BODY_HPP

#include <coal/collision_object.h>
#include <coal/shape/convex.h>
#include <coal/shape/geometric_shapes.h>

#include <cmath>
#include <memory>
#include <vector>

#include "compare_common.h"

/// A Coal geometry with its world transform.
struct CoalBody {
  std::shared_ptr<coal::CollisionGeometry> geom;
  coal::Transform3s tf;
};

/// The Coal world transform of a dcol comparison body (see the frames above): what to_coal
/// gives as `tf`, without building the geometry (bench_trajectory moves one geometry along).
inline coal::Transform3s coal_transform(const cmp_body& body) {
  const cmp_kind kind = body.shape->kind;
  coal::Matrix3s R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = body.R[3 * i + j];
  const coal::Vec3s r(body.pose.position[0], body.pose.position[1], body.pose.position[2]);
  coal::Matrix3s M;
  M << 0, 0, -1, 0, 1, 0, 1, 0, 0;
  const bool axial = kind == CMP_CAPSULE || kind == CMP_CYLINDER || kind == CMP_CONE;
  const coal::Vec3s o =
      kind == CMP_CONE ? coal::Vec3s(-0.25 * body.shape->height, 0, 0) : coal::Vec3s::Zero();
  coal::Transform3s tf;
  tf.setIdentity();
  tf.setRotation(axial ? coal::Matrix3s(R * M) : R);
  tf.setTranslation(r + R * o);
  return tf;
}

/// The Coal geometry and transform of a dcol comparison body (see the frames above).
inline CoalBody to_coal(const cmp_body& body) {
  const cmp_shape& s = *body.shape;
  CoalBody out;
  switch (s.kind) {
    case CMP_SPHERE:
      out.geom = std::make_shared<coal::Sphere>(s.radius);
      break;
    case CMP_ELLIPSOID:
      out.geom = std::make_shared<coal::Ellipsoid>(s.radii[0], s.radii[1], s.radii[2]);
      break;
    case CMP_BOX:
      out.geom = std::make_shared<coal::Box>(2 * s.half[0], 2 * s.half[1], 2 * s.half[2]);
      break;
    case CMP_POLYTOPE: {
      auto verts = std::make_shared<std::vector<coal::Vec3s>>();
      for (size_t u = 0; u < s.nv; ++u)
        verts->emplace_back(s.V[3 * u], s.V[3 * u + 1], s.V[3 * u + 2]);
      auto tris = std::make_shared<std::vector<coal::Triangle>>();
      for (size_t f = 0; f < s.nfaces; ++f) {
        const size_t a = s.face_start[f], e = s.face_start[f + 1];
        for (size_t k = a + 1; k + 1 < e; ++k)
          tris->emplace_back(static_cast<coal::Triangle::index_type>(s.face_index[a]),
                             static_cast<coal::Triangle::index_type>(s.face_index[k]),
                             static_cast<coal::Triangle::index_type>(s.face_index[k + 1]));
      }
      out.geom = std::make_shared<coal::Convex<coal::Triangle>>(
          verts, static_cast<unsigned int>(verts->size()), tris,
          static_cast<unsigned int>(tris->size()));
      break;
    }
    case CMP_CAPSULE:
      out.geom = std::make_shared<coal::Capsule>(s.radius, s.length);
      break;
    case CMP_CYLINDER:
      out.geom = std::make_shared<coal::Cylinder>(s.radius, s.length);
      break;
    case CMP_CONE:
      out.geom = std::make_shared<coal::Cone>(s.height * std::tan(s.half_angle), s.height);
      break;
    case CMP_POLYGON: {
      auto verts = std::make_shared<std::vector<coal::Vec3s>>();
      for (size_t u = 0; u < s.pnv; ++u) verts->emplace_back(s.PV[2 * u], s.PV[2 * u + 1], 0.0);
      auto tris = std::make_shared<std::vector<coal::Triangle>>();
      for (size_t k = 1; k + 1 < s.pnv; ++k)
        tris->emplace_back(0, static_cast<coal::Triangle::index_type>(k),
                           static_cast<coal::Triangle::index_type>(k + 1));
      out.geom = std::make_shared<coal::Convex<coal::Triangle>>(
          verts, static_cast<unsigned int>(verts->size()), tris,
          static_cast<unsigned int>(tris->size()));
      static_cast<coal::ShapeBase*>(out.geom.get())->setSweptSphereRadius(s.radius);
      break;
    }
    default:
      break;
  }
  if (out.geom) out.geom->computeLocalAABB();
  out.tf = coal_transform(body);
  return out;
}

#endif  // DCOL_BENCH_COAL_BODY_HPP
