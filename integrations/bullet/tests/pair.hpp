// One pair of Bullet collision objects run through a dispatcher's algorithm directly (no world):
// what the mapping tests use to look at a single manifold.
#pragma once

#include <btBulletCollisionCommon.h>

#include <vector>

namespace pair_test {

/// A manifold point as Bullet stores it, its normal turned to point from A's side to B's.
struct Point {
  btVector3 normal_a_to_b;  // unit normal from A towards B
  btVector3 on_b;           // the point on B's surface
  double distance;          // < 0 penetrating
};

/// Runs `dispatcher`'s contact algorithm for (A, B) once and returns the manifold's points.
inline std::vector<Point> collide(btCollisionDispatcher &dispatcher, btCollisionShape *sa, const btTransform &ta,
                                  btCollisionShape *sb, const btTransform &tb, double *threshold = nullptr) {
  btCollisionObject oa, ob;
  oa.setCollisionShape(sa);
  oa.setWorldTransform(ta);
  ob.setCollisionShape(sb);
  ob.setWorldTransform(tb);
  btCollisionObjectWrapper wa(nullptr, sa, &oa, ta, -1, -1);
  btCollisionObjectWrapper wb(nullptr, sb, &ob, tb, -1, -1);
  btCollisionAlgorithm *alg = dispatcher.findAlgorithm(&wa, &wb, nullptr, BT_CONTACT_POINT_ALGORITHMS);
  std::vector<Point> out;
  if (!alg) return out;
  btManifoldResult result(&wa, &wb);
  btDispatcherInfo info;
  alg->processCollision(&wa, &wb, info, &result);
  btManifoldArray manifolds;
  alg->getAllContactManifolds(manifolds);
  for (int m = 0; m < manifolds.size(); ++m) {
    const btPersistentManifold *pm = manifolds[m];
    if (threshold) *threshold = pm->getContactBreakingThreshold();
    // Bullet's normal is on body 1 pointing towards body 0.
    const double sign = pm->getBody0() == &oa ? -1.0 : 1.0;
    for (int i = 0; i < pm->getNumContacts(); ++i) {
      const btManifoldPoint &p = pm->getContactPoint(i);
      Point q;
      q.normal_a_to_b = p.m_normalWorldOnB * btScalar(sign);
      q.on_b = pm->getBody0() == &oa ? p.m_positionWorldOnB : p.m_positionWorldOnA;
      q.distance = p.getDistance();
      out.push_back(q);
    }
  }
  alg->~btCollisionAlgorithm();
  dispatcher.freeCollisionAlgorithm(alg);
  return out;
}

/// The deepest of `points` (the first when empty is not allowed: check size first).
inline const Point &deepest(const std::vector<Point> &points) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].distance < points[k].distance) k = i;
  return points[k];
}

}  // namespace pair_test
