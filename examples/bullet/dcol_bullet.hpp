// dcol_bullet.hpp: dcol shapes in Bullet (a custom convex shape and its collision algorithm).
//
//   btCollisionDispatcher dispatcher(&config);
//   dcol_bullet::register_algorithms(&dispatcher);   // once per dispatcher
//   dcol_bullet::Shape shape(dcol_shape_ptr, bounding_radius, half_extents);
//   btRigidBody body(mass, motion_state, &shape, inertia);  // then use it like any shape
//
// Pairs of dcol shapes, and a dcol shape against Bullet's btStaticPlaneShape (as a dcol
// half-space: dcol_shape_new_halfspace), are handled by an algorithm registered with
// btCollisionDispatcher::registerCollisionCreateFunc for CUSTOM_CONVEX_SHAPE_TYPE. It writes
// dcol_contacts (margin 0: the points where the shapes overlap or touch, at most 4, the size of
// Bullet's persistent manifold) through btManifoldResult::addContactPoint.
//
// Conventions (btManifoldResult::addContactPoint(normalOnBInWorld, pointInWorld, depth)): the
// normal is on body B (body 1) pointing towards body A (body 0), the point lies on B's surface and
// depth is the signed distance (< 0 penetrating). dcol's normal points from shape 1 to shape 2, so
// with shape 1 = A the algorithm passes normal = -n, point = position - depth/2 n (shape 2's
// surface point) and depth = -dcol depth.
//
// The Shape's support map (used only by Bullet code other than this algorithm, e.g. ray tests)
// is its bounding sphere; its AABB is the cube around that sphere and its inertia that of the
// box with the given half extents. A floor may be a static Shape wrapping a dcol half-space,
// with radius INFINITY: its AABB is then +-BT_LARGE_FLOAT, as for btStaticPlaneShape. The dcol
// shape is not owned and must outlive the Shape.
#ifndef DCOL_BULLET_HPP
#define DCOL_BULLET_HPP

#include <btBulletCollisionCommon.h>

#include "dcol.h"

namespace dcol_bullet {

class Shape : public btConvexInternalShape {
 public:
  Shape(const dcol_shape *shape, double radius, const btVector3 &half_extents);
  ~Shape() override;
  const dcol_shape *dcol() const { return m_dcol; }
  double radius() const { return m_radius; }

  btVector3 localGetSupportingVertexWithoutMargin(const btVector3 &vec) const override;
  void batchedUnitVectorGetSupportingVertexWithoutMargin(const btVector3 *vectors, btVector3 *out,
                                                         int n) const override;
  void getAabb(const btTransform &t, btVector3 &aabbMin, btVector3 &aabbMax) const override;
  void calculateLocalInertia(btScalar mass, btVector3 &inertia) const override;
  const char *getName() const override { return "dcol"; }
  int getNumPreferredPenetrationDirections() const override { return 0; }
  void getPreferredPenetrationDirection(int, btVector3 &) const override {}

 private:
  const dcol_shape *m_dcol;
  double m_radius;
  btVector3 m_half;
};

/// Registers the dcol algorithm for dcol-dcol and dcol-plane pairs with `dispatcher`.
void register_algorithms(btCollisionDispatcher *dispatcher);

/// Calls of the algorithm so far.
unsigned long algorithm_calls();

}  // namespace dcol_bullet

#endif
