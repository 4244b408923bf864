// dcol_bullet::Shape, a dcol shape as a Bullet convex shape: see dcol_bullet.hpp.
#include "dcol_bullet.hpp"

#include <cmath>

namespace dcol_bullet {

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

}  // namespace dcol_bullet
