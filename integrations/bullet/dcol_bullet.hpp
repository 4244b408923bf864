// dcol_bullet.hpp: dcol as the narrow phase of a Bullet program (the dcol::bullet component).
//
//   find_package(dcol REQUIRED COMPONENTS bullet)          # CMake
//   target_link_libraries(app PRIVATE dcol::bullet)
//
//   #include <dcol_bullet.hpp>
//   btCollisionDispatcher dispatcher(&config);
//   dcol_bullet::use_dcol(&dispatcher);                     // once, before stepping
//
// use_dcol registers one collision algorithm for every pair among btSphereShape, btBoxShape,
// btCapsuleShape (X, Y, Z), btCylinderShape (X, Y, Z), btConeShape (X, Y, Z), btConvexHullShape
// and dcol_bullet::Shape, and each of them against btStaticPlaneShape. The program keeps its
// shapes, AABBs, inertia, ray tests and closest-point queries (contactTest, contactPairTest):
// only the contacts of the simulation change. Compound shapes are collided child by child, so
// their convex children go through dcol too.
//
// Each Bullet shape maps to the dcol shape of the geometry Bullet collides, margins included
// (docs/bullet.md has the table): a sphere and a capsule are themselves; a box is the sharp dcol
// box of its half extents with margin (what Bullet's box-box and plane algorithms collide; its
// GJK pairs round the edges by the margin); a cylinder is its core (the half extents without
// margin) grown by the margin, and a cone (apex at +height/2 on the up axis) grown by its margin:
// the dcol cylinder or cone of the core, with the margin added to the contacts (signed distances
// of grown shapes shift by the radius exactly); a convex hull is the padded hull of its scaled
// points, radius = margin, built about the points' mean when they do not surround the shape's
// origin. The dcol shape is built once per Bullet shape and reused while the parameters that
// define its geometry (type, dimensions, margin, local scaling, up axis, number of points) are
// unchanged; forget() drops it (call it after editing a hull's points in place). A shape dcol
// cannot take (a zero-size box, a degenerate hull, non-finite sizes, a margin larger than a
// cylinder's half extents) keeps Bullet's own algorithm for its pairs.
//
// Contacts: dcol_contacts with margin = the persistent manifold's contact breaking threshold,
// at most 4 points, written through btManifoldResult::addContactPoint(normalOnBInWorld,
// pointInWorld, depth): the normal on body B (body 1) pointing towards body A (body 0), the
// point on B's surface, depth = the signed distance (< 0 penetrating). dcol's normal points from
// shape 1 (= A) to shape 2 (= B), so the algorithm passes normal = -n, point = position -
// depth/2 n and depth = -dcol depth. Bullet's persistent manifold then merges and refreshes the
// points as it does for its own algorithms. A body with a non-finite pose gets no contacts (the
// manifold is cleared and the call counted in Stats::invalid_poses); nothing is printed.
//
// dcol_bullet::Shape wraps any dcol shape (ellipsoids, padded polygons, dcol's own half-space)
// as a Bullet shape of type CUSTOM_CONVEX_SHAPE_TYPE: its AABB is the cube around a bounding
// sphere, its inertia that of a box with the given half extents, and its support map (used only
// by Bullet code other than the dcol algorithm, e.g. ray tests) the bounding sphere. A floor may
// be a static Shape wrapping a dcol half-space with radius INFINITY (AABB +-BT_LARGE_FLOAT, as
// btStaticPlaneShape). The dcol shape is not owned and must outlive the Shape.
//
// Thread safety: the shape cache is guarded by a mutex (only taken when a pair meets a shape it
// has not seen, or a shape changed) and the counters are atomic, so a dispatcher that runs pairs
// in parallel (btCollisionDispatcherMt) may call the algorithm from several threads.
//
// Bullet's btScalar must be the one this component was built with (Debian's `bullet`
// pkg-config module: float).
#ifndef DCOL_BULLET_HPP
#define DCOL_BULLET_HPP

#include <btBulletCollisionCommon.h>

#include "dcol.h"

namespace dcol_bullet {

/// A dcol shape as a Bullet convex shape (CUSTOM_CONVEX_SHAPE_TYPE): see the header comment.
class Shape : public btConvexInternalShape {
 public:
  /// `shape` (not owned, must outlive this), `radius` a bounding radius about the body origin
  /// (INFINITY for a half-space), `half_extents` of the box whose inertia the body gets.
  Shape(const dcol_shape *shape, double radius, const btVector3 &half_extents);
  ~Shape() override;
  /// The wrapped dcol shape.
  const dcol_shape *dcol() const { return m_dcol; }
  /// The bounding radius given to the constructor.
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

/// Registers dcol's algorithm with `dispatcher` for every pair among Bullet's sphere, box,
/// capsule, cylinder, cone, convex hull and dcol_bullet::Shape, and each of them against
/// btStaticPlaneShape. Call it once after constructing the dispatcher (calling it again is
/// harmless). `dispatcher` NULL is a no-op.
void use_dcol(btCollisionDispatcher *dispatcher);

/// Registers dcol's algorithm only for the pairs that involve a dcol_bullet::Shape (against
/// each other, btStaticPlaneShape and Bullet's convex shapes above): Bullet's own shapes keep
/// Bullet's algorithms against each other.
void register_algorithms(btCollisionDispatcher *dispatcher);

/// Pair calls answered by dcol so far (all dispatchers and threads).
unsigned long algorithm_calls();

/// What the algorithm has done so far (all dispatchers and threads).
struct Stats {
  unsigned long calls;           ///< pair calls answered by dcol (= algorithm_calls())
  unsigned long early_outs;      ///< of those, decided apart without a query (bounding spheres, or the support functions along the line between the origins or the plane normal)
  unsigned long apart;           ///< of those, queried and found farther apart than the margin
  unsigned long reused;          ///< of those, the same shapes at bit-identical poses as the pair's last call: its answer reused
  unsigned long fallback_pairs;  ///< pairs given Bullet's own algorithm when created (a shape dcol cannot take)
  unsigned long fallback_calls;  ///< calls of dcol's algorithm handed to Bullet's (a shape changed into one dcol cannot take)
  unsigned long invalid_poses;   ///< calls with a non-finite pose: no contacts
  unsigned long not_converged;   ///< dcol_contacts answered DCOL_ERROR_NOT_CONVERGED (best answer used)
  unsigned long errors;          ///< other dcol errors: no contacts
  unsigned long shapes_built;    ///< dcol shapes built for Bullet shapes (cache misses)
};

/// The counters above.
Stats stats();

/// The dcol shape and world pose the algorithm uses for `shape` placed at `world` (the collision
/// object's world transform), and the radius of the ball Bullet's shape adds to it (a cylinder's
/// or cone's margin, else 0: Bullet's shape is the dcol shape grown by it, so its signed distance
/// to another is dcol's minus both paddings). Returns true and writes *out, *pose and, when not
/// NULL, *padding; false when dcol cannot take the shape, or it is a btStaticPlaneShape or not a
/// convex shape of the list. *out belongs to the adapter's cache (valid until the shape changes
/// or forget(shape)).
bool as_dcol(const btCollisionShape *shape, const btTransform &world, const dcol_shape **out, dcol_pose *pose,
             double *padding = nullptr);

/// Drops the cached dcol shape of `shape` (after editing a btConvexHullShape's points in place,
/// or before deleting a shape when many shapes come and go). Pairs still using it keep their
/// copy until they next see the shape change.
void forget(const btCollisionShape *shape);

}  // namespace dcol_bullet

#endif
