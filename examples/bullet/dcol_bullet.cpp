// dcol shapes in Bullet: see dcol_bullet.hpp.
#include "dcol_bullet.hpp"

#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>

#include <cmath>
#include <cstdio>
#include <new>

namespace dcol_bullet {

namespace {
unsigned long g_calls = 0;
const std::size_t kMaxPoints = 4;  // Bullet's persistent manifold holds four

// Bullet's planes as a dcol half-space of depth 1, made on first use and kept for the process.
const dcol_shape *plane_halfspace() {
  static dcol_shape *const s = [] {
    dcol_shape *h = nullptr;
    return dcol_shape_new_halfspace(1.0, &h) == DCOL_OK ? h : nullptr;
  }();
  return s;
}

dcol_pose pose_of(const btTransform &t) {
  dcol_pose p;
  const btVector3 &o = t.getOrigin();
  const btQuaternion q = t.getRotation();
  p.position[0] = o.x();
  p.position[1] = o.y();
  p.position[2] = o.z();
  p.quaternion[0] = q.w();  // dcol: (w, x, y, z)
  p.quaternion[1] = q.x();
  p.quaternion[2] = q.y();
  p.quaternion[3] = q.z();
  return p;
}
}  // namespace

Shape::Shape(const dcol_shape *shape, double radius, const btVector3 &half_extents)
    : m_dcol(shape), m_radius(radius), m_half(half_extents) {
  m_shapeType = CUSTOM_CONVEX_SHAPE_TYPE;
  setMargin(0);
}

Shape::~Shape() {}

btVector3 Shape::localGetSupportingVertexWithoutMargin(const btVector3 &vec) const {
  const btScalar len = vec.length();
  return len > 0 ? vec * btScalar(m_radius / len) : btVector3(btScalar(m_radius), 0, 0);
}

void Shape::batchedUnitVectorGetSupportingVertexWithoutMargin(const btVector3 *vectors, btVector3 *out,
                                                              int n) const {
  for (int i = 0; i < n; ++i) out[i] = localGetSupportingVertexWithoutMargin(vectors[i]);
}

void Shape::getAabb(const btTransform &t, btVector3 &aabbMin, btVector3 &aabbMax) const {
  if (!std::isfinite(m_radius)) {  // a half-space: everywhere, as Bullet's planes
    aabbMin = btVector3(-BT_LARGE_FLOAT, -BT_LARGE_FLOAT, -BT_LARGE_FLOAT);
    aabbMax = btVector3(BT_LARGE_FLOAT, BT_LARGE_FLOAT, BT_LARGE_FLOAT);
    return;
  }
  const btScalar r = btScalar(m_radius);
  aabbMin = t.getOrigin() - btVector3(r, r, r);
  aabbMax = t.getOrigin() + btVector3(r, r, r);
}

void Shape::calculateLocalInertia(btScalar mass, btVector3 &inertia) const {
  const btVector3 l = 2 * m_half;
  inertia = mass / btScalar(12) *
            btVector3(l.y() * l.y() + l.z() * l.z(), l.x() * l.x() + l.z() * l.z(), l.x() * l.x() + l.y() * l.y());
}

namespace {

class Algorithm : public btActivatingCollisionAlgorithm {
 public:
  Algorithm(const btCollisionAlgorithmConstructionInfo &ci, const btCollisionObjectWrapper *b0,
            const btCollisionObjectWrapper *b1)
      : btActivatingCollisionAlgorithm(ci, b0, b1), m_manifold(nullptr) {
    m_manifold = m_dispatcher->getNewManifold(b0->getCollisionObject(), b1->getCollisionObject());
  }
  ~Algorithm() override {
    if (m_manifold) m_dispatcher->releaseManifold(m_manifold);
  }

  void processCollision(const btCollisionObjectWrapper *a, const btCollisionObjectWrapper *b, const btDispatcherInfo &,
                        btManifoldResult *result) override {
    ++g_calls;
    result->setPersistentManifold(m_manifold);
    dcol_contact cs[kMaxPoints];
    std::size_t n = 0;
    const bool a_plane = a->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE;
    const bool b_plane = b->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE;
    dcol_status st = DCOL_OK;
    if (!a_plane && !b_plane) {
      const Shape *sa = static_cast<const Shape *>(a->getCollisionShape());
      const Shape *sb = static_cast<const Shape *>(b->getCollisionShape());
      const dcol_pose pa = pose_of(a->getWorldTransform());
      const dcol_pose pb = pose_of(b->getWorldTransform());
      st = dcol_contacts(sa->dcol(), &pa, sb->dcol(), &pb, 0.0, nullptr, cs, kMaxPoints, &n);
    } else if (a_plane != b_plane) {
      // The plane n.x = c (its object's frame) as the dcol half-space of depth 1 whose boundary
      // it is, origin under the shape's centre; shape 1 = A as given.
      const btCollisionObjectWrapper *pw = a_plane ? a : b;
      const btCollisionObjectWrapper *sw = a_plane ? b : a;
      const btStaticPlaneShape *plane = static_cast<const btStaticPlaneShape *>(pw->getCollisionShape());
      const Shape *s = static_cast<const Shape *>(sw->getCollisionShape());
      const btTransform &tp = pw->getWorldTransform();
      const btVector3 nrm = tp.getBasis() * plane->getPlaneNormal();
      const btScalar c = plane->getPlaneConstant() + nrm.dot(tp.getOrigin());
      const btVector3 centre = sw->getWorldTransform().getOrigin();
      const double h = nrm.dot(centre) - c;
      const dcol_shape *hs = plane_halfspace();
      if (h <= s->radius() && hs) {
        dcol_pose box;
        for (int k = 0; k < 3; ++k) box.position[k] = centre[k] - (h + 1.0) * nrm[k];
        // Rotation taking e_z to the plane normal.
        double w = 1.0 + nrm.z(), x = -nrm.y(), y = nrm.x();
        if (w < 1e-12) {
          w = 0;
          x = 1;
          y = 0;
        }
        const double len = std::sqrt(w * w + x * x + y * y);
        box.quaternion[0] = w / len;
        box.quaternion[1] = x / len;
        box.quaternion[2] = y / len;
        box.quaternion[3] = 0;
        const dcol_pose ps = pose_of(sw->getWorldTransform());
        if (a_plane) {
          st = dcol_contacts(hs, &box, s->dcol(), &ps, 0.0, nullptr, cs, kMaxPoints, &n);
        } else {
          st = dcol_contacts(s->dcol(), &ps, hs, &box, 0.0, nullptr, cs, kMaxPoints, &n);
        }
      }
    }
    if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) {
      std::fprintf(stderr, "dcol_bullet: %s\n", dcol_last_error_message());
      n = 0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const btVector3 normal(btScalar(cs[i].normal[0]), btScalar(cs[i].normal[1]), btScalar(cs[i].normal[2]));
      const btVector3 pos(btScalar(cs[i].position[0]), btScalar(cs[i].position[1]), btScalar(cs[i].position[2]));
      const btScalar depth = btScalar(cs[i].depth);
      // Bullet: normal on B towards A, point on B, distance (< 0 penetrating).
      result->addContactPoint(-normal, pos - normal * (depth / 2), -depth);
    }
    result->refreshContactPoints();
  }

  btScalar calculateTimeOfImpact(btCollisionObject *, btCollisionObject *, const btDispatcherInfo &,
                                 btManifoldResult *) override {
    return btScalar(1);
  }

  void getAllContactManifolds(btManifoldArray &manifolds) override {
    if (m_manifold) manifolds.push_back(m_manifold);
  }

 private:
  btPersistentManifold *m_manifold;
};

struct CreateFunc : public btCollisionAlgorithmCreateFunc {
  btCollisionAlgorithm *CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo &ci,
                                                 const btCollisionObjectWrapper *b0,
                                                 const btCollisionObjectWrapper *b1) override {
    void *mem = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(Algorithm));
    return new (mem) Algorithm(ci, b0, b1);
  }
};

CreateFunc g_create;

}  // namespace

void register_algorithms(btCollisionDispatcher *dispatcher) {
  dispatcher->registerCollisionCreateFunc(CUSTOM_CONVEX_SHAPE_TYPE, CUSTOM_CONVEX_SHAPE_TYPE, &g_create);
  dispatcher->registerCollisionCreateFunc(CUSTOM_CONVEX_SHAPE_TYPE, STATIC_PLANE_PROXYTYPE, &g_create);
  dispatcher->registerCollisionCreateFunc(STATIC_PLANE_PROXYTYPE, CUSTOM_CONVEX_SHAPE_TYPE, &g_create);
}

unsigned long algorithm_calls() { return g_calls; }

}  // namespace dcol_bullet
