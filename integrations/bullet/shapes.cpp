// Bullet shapes as dcol shapes, and the cache of those mappings: see dcol_bullet.hpp and
// docs/bullet.md (the mapping table and why each shape maps as it does).
#include <cmath>
#include <algorithm>
#include <cstring>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "internal.hpp"

namespace dcol_bullet {
namespace detail {

std::atomic<unsigned> g_epoch{0};

Counters &counters() {
  static Counters c;
  return c;
}

bool Key::operator==(const Key &o) const {
  return shape == o.shape && type == o.type && ints[0] == o.ints[0] && ints[1] == o.ints[1] && ptr == o.ptr &&
         std::memcmp(f, o.f, sizeof f) == 0;  // bytes: a NaN size still equals itself
}

bool mapped_type(int type) {
  switch (type) {
    case SPHERE_SHAPE_PROXYTYPE:
    case BOX_SHAPE_PROXYTYPE:
    case CAPSULE_SHAPE_PROXYTYPE:
    case CYLINDER_SHAPE_PROXYTYPE:
    case CONE_SHAPE_PROXYTYPE:
    case CONVEX_HULL_SHAPE_PROXYTYPE:
    case CUSTOM_CONVEX_SHAPE_TYPE:
      return true;
    default:
      return false;
  }
}

Key key_of(const btCollisionShape *shape) {
  Key k;
  k.shape = shape;
  k.type = shape->getShapeType();
  if (!mapped_type(k.type)) return k;
  if (k.type == CUSTOM_CONVEX_SHAPE_TYPE) {
    const Shape *s = static_cast<const Shape *>(shape);
    k.ptr = s->dcol();
    k.f[0] = btScalar(s->radius());
    return k;
  }
  // Every mapped Bullet type is a btConvexInternalShape: its implicit dimensions (scaling
  // included), local scaling and margin, read without virtual calls.
  const btConvexInternalShape *c = static_cast<const btConvexInternalShape *>(shape);
  const btVector3 &dims = c->getImplicitShapeDimensions();
  const btVector3 &scale = c->getLocalScalingNV();
  for (int i = 0; i < 3; ++i) {
    k.f[i] = dims[i];
    k.f[3 + i] = scale[i];
  }
  k.f[6] = c->getMarginNV();
  switch (k.type) {
    case CAPSULE_SHAPE_PROXYTYPE:
      k.ints[0] = static_cast<const btCapsuleShape *>(shape)->getUpAxis();
      break;
    case CYLINDER_SHAPE_PROXYTYPE:
      k.ints[0] = static_cast<const btCylinderShape *>(shape)->getUpAxis();
      break;
    case CONE_SHAPE_PROXYTYPE: {
      // setRadius/setHeight change the cone without touching its implicit dimensions.
      const btConeShape *cone = static_cast<const btConeShape *>(shape);
      k.ints[0] = cone->getConeUpIndex();
      k.f[0] = cone->getRadius();
      k.f[1] = cone->getHeight();
      break;
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE: {
      const btConvexHullShape *hull = static_cast<const btConvexHullShape *>(shape);
      k.ints[1] = hull->getNumPoints();
      k.ptr = hull->getNumPoints() > 0 ? static_cast<const void *>(hull->getUnscaledPoints()) : nullptr;
      break;
    }
    default:
      break;
  }
  return k;
}

Entry::~Entry() { dcol_shape_free(owned); }

namespace {

const double kH = 0.70710678118654752440;  // sqrt(1/2)

// The rotation taking dcol's body x axis to `sign` times Bullet's axis `axis` (w, x, y, z).
void axis_rotation(int axis, int sign, double q[4]) {
  static const double plus[3][4] = {{1, 0, 0, 0}, {kH, 0, 0, kH}, {kH, 0, -kH, 0}};
  static const double minus[3][4] = {{0, 0, 0, 1}, {kH, 0, 0, -kH}, {kH, 0, kH, 0}};
  const double(&r)[4] = sign > 0 ? plus[axis] : minus[axis];
  for (int i = 0; i < 4; ++i) q[i] = r[i];
}

bool finite_positive(double v) { return std::isfinite(v) && v > 0; }

// Fills `e` for a Bullet shape of a mapped type; leaves e.shape null when dcol cannot take it.
void build(const btCollisionShape *shape, Entry &e) {
  dcol_shape *s = nullptr;
  switch (e.key.type) {
    case CUSTOM_CONVEX_SHAPE_TYPE: {
      const Shape *c = static_cast<const Shape *>(shape);
      e.shape = c->dcol();
      e.radius = c->radius();
      return;
    }
    case SPHERE_SHAPE_PROXYTYPE: {
      const double r = static_cast<const btSphereShape *>(shape)->getRadius();
      if (finite_positive(r) && dcol_shape_new_sphere(r, &s) == DCOL_OK) {
        e.radius = r;
        e.dims[0] = r;
      }
      break;
    }
    case BOX_SHAPE_PROXYTYPE: {
      // The sharp box of the half extents with margin: what btBoxBoxDetector and the plane
      // algorithm collide (GJK rounds its edges and corners by the margin).
      const btVector3 h = static_cast<const btBoxShape *>(shape)->getHalfExtentsWithMargin();
      if (finite_positive(h.x()) && finite_positive(h.y()) && finite_positive(h.z()) &&
          dcol_shape_new_box(h.x(), h.y(), h.z(), &s) == DCOL_OK) {
        e.radius = std::sqrt(double(h.x()) * h.x() + double(h.y()) * h.y() + double(h.z()) * h.z());
        for (int i = 0; i < 3; ++i) e.dims[i] = h[i];
      }
      break;
    }
    case CAPSULE_SHAPE_PROXYTYPE: {
      const btCapsuleShape *c = static_cast<const btCapsuleShape *>(shape);
      const double r = c->getRadius(), hh = c->getHalfHeight();
      if (!finite_positive(r) || !std::isfinite(hh) || hh < 0) break;
      // A capsule of no length is its sphere.
      const dcol_status st = hh > 0 ? dcol_shape_new_capsule(r, 2 * hh, &s) : dcol_shape_new_sphere(r, &s);
      if (st != DCOL_OK) break;
      e.radius = hh + r;
      e.axis = c->getUpAxis();
      e.dims[0] = hh;
      e.dims[1] = r;
      if (c->getUpAxis() != 0) {
        e.has_offset = true;
        axis_rotation(c->getUpAxis(), 1, e.quat);
      }
      break;
    }
    case CYLINDER_SHAPE_PROXYTYPE: {
      // Bullet's cylinder is its core (the half extents without margin) grown by the margin, a
      // cylinder with rounded rims: the dcol cylinder of the core, padded by the margin.
      const btCylinderShape *c = static_cast<const btCylinderShape *>(shape);
      const int up = c->getUpAxis();
      const btVector3 &h = c->getHalfExtentsWithoutMargin();
      const double r = h[up == 0 ? 1 : 0], hh = h[up], m = c->getMarginNV();
      if (!finite_positive(r) || !finite_positive(hh) || !std::isfinite(m) || m < 0 ||
          dcol_shape_new_cylinder(r, 2 * hh, &s) != DCOL_OK) {
        break;
      }
      e.pad = m;
      e.radius = std::sqrt(r * r + hh * hh) + m;
      e.axis = up;
      e.dims[0] = hh;
      e.dims[1] = r;
      if (up != 0) {
        e.has_offset = true;
        axis_rotation(up, 1, e.quat);
      }
      break;
    }
    case CONE_SHAPE_PROXYTYPE: {
      // Bullet's cone: apex at +h/2 on the up axis, base disc of radius r at -h/2, grown by the
      // margin: the dcol cone of height h and half angle atan(r/h) (its centroid at -h/4 on the
      // up axis, its body x along -up), padded by the margin.
      const btConeShape *c = static_cast<const btConeShape *>(shape);
      const double r = c->getRadius(), h = c->getHeight(), m = c->getMarginNV();
      if (!finite_positive(r) || !finite_positive(h) || !std::isfinite(m) || m < 0 ||
          dcol_shape_new_cone(h, std::atan2(r, h), &s) != DCOL_OK) {
        break;
      }
      const int up = c->getConeUpIndex();
      e.has_offset = true;
      e.pos[up] = -0.25 * h;
      axis_rotation(up, -1, e.quat);  // dcol's apex is at -3H/4 on body x: body x is -up
      e.pad = m;
      e.radius = std::sqrt(0.25 * h * h + r * r) + m;
      e.axis = up;
      e.dims[0] = 0.5 * h;
      e.dims[1] = r;
      break;
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE: {
      // Bullet's hull is its scaled points' hull grown by the margin: dcol's hull padded by it,
      // built about the points' mean (strictly inside a full-dimensional hull) when the points do
      // not surround the shape's origin.
      const btConvexHullShape *h = static_cast<const btConvexHullShape *>(shape);
      const int n = h->getNumPoints();
      const double m = h->getMarginNV();
      if (n < 4 || !std::isfinite(m) || m < 0) break;
      std::vector<double> pts(3 * static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) {
        const btVector3 p = h->getScaledPoint(i);
        for (int k = 0; k < 3; ++k) pts[3 * i + k] = p[k];
      }
      dcol_status st = dcol_shape_new_convex_hull(pts.data(), pts.size() / 3, m, &s);
      double mean[3] = {0, 0, 0};
      if (st == DCOL_ERROR_INVALID_SHAPE) {
        for (int i = 0; i < n; ++i)
          for (int k = 0; k < 3; ++k) mean[k] += pts[3 * i + k] / n;
        for (int i = 0; i < n; ++i)
          for (int k = 0; k < 3; ++k) pts[3 * i + k] -= mean[k];
        st = dcol_shape_new_convex_hull(pts.data(), pts.size() / 3, m, &s);
        if (st == DCOL_OK) {
          e.has_offset = true;
          for (int k = 0; k < 3; ++k) e.pos[k] = mean[k];
        }
      }
      if (st != DCOL_OK) break;
      // The support function bounds the hull by the box around its points (Bullet's frame).
      double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, far = 0;
      for (int i = 0; i < n; ++i) {
        double r2 = 0;
        for (int k = 0; k < 3; ++k) {
          const double v = pts[3 * i + k] + mean[k];
          lo[k] = std::min(lo[k], v);
          hi[k] = std::max(hi[k], v);
          r2 += v * v;
        }
        far = std::max(far, r2);
      }
      for (int k = 0; k < 3; ++k) {
        e.dims[k] = 0.5 * (hi[k] - lo[k]);
        e.centre[k] = 0.5 * (hi[k] + lo[k]);
      }
      e.pad = 0;
      e.margin = m;
      e.radius = std::sqrt(far) + m;
      break;
    }
    default:
      break;
  }
  e.shape = s;
  e.owned = s;
  if (s) e.kind = e.key.type;
}

struct Cache {
  std::mutex mutex;
  std::unordered_map<const btCollisionShape *, std::shared_ptr<const Entry>> map;
};

Cache &cache() {
  static Cache c;  // destroyed at exit, freeing every dcol shape it built
  return c;
}

}  // namespace

std::shared_ptr<const Entry> lookup(const btCollisionShape *shape) {
  const Key key = key_of(shape);
  Cache &c = cache();
  std::lock_guard<std::mutex> lock(c.mutex);
  std::shared_ptr<const Entry> &slot = c.map[shape];
  if (slot && slot->key == key) return slot;
  std::shared_ptr<Entry> e = std::make_shared<Entry>();
  e->key = key;
  if (mapped_type(key.type)) {
    build(shape, *e);
    if (e->owned) counters().shapes_built.fetch_add(1, std::memory_order_relaxed);
  }
  slot = e;
  return slot;
}

double support(const Entry &e, const double u[3]) {
  switch (e.kind) {
    case SPHERE_SHAPE_PROXYTYPE:
      return e.dims[0];
    case BOX_SHAPE_PROXYTYPE:
      return e.dims[0] * std::fabs(u[0]) + e.dims[1] * std::fabs(u[1]) + e.dims[2] * std::fabs(u[2]);
    case CAPSULE_SHAPE_PROXYTYPE:
      return e.dims[0] * std::fabs(u[e.axis]) + e.dims[1];
    case CYLINDER_SHAPE_PROXYTYPE: {
      const double a = u[e.axis];
      return e.dims[0] * std::fabs(a) + e.dims[1] * std::sqrt(std::max(0.0, 1 - a * a)) + e.pad;
    }
    case CONE_SHAPE_PROXYTYPE: {
      // The apex at +h/2 on the up axis, the base rim at -h/2.
      const double a = u[e.axis];
      return std::max(e.dims[0] * a, -e.dims[0] * a + e.dims[1] * std::sqrt(std::max(0.0, 1 - a * a))) + e.pad;
    }
    case CONVEX_HULL_SHAPE_PROXYTYPE:  // the box around its points, grown by the margin
      return e.centre[0] * u[0] + e.centre[1] * u[1] + e.centre[2] * u[2] + e.dims[0] * std::fabs(u[0]) +
             e.dims[1] * std::fabs(u[1]) + e.dims[2] * std::fabs(u[2]) + e.margin;
    default:
      return e.radius;
  }
}

dcol_pose world_pose(const Entry &e, const btTransform &t) {
  dcol_pose p;
  const btVector3 &o = t.getOrigin();
  const btQuaternion q = t.getRotation();
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  if (!e.has_offset) {
    for (int i = 0; i < 3; ++i) p.position[i] = o[i];
    p.quaternion[0] = w;  // dcol: (w, x, y, z)
    p.quaternion[1] = x;
    p.quaternion[2] = y;
    p.quaternion[3] = z;
    return p;
  }
  const btMatrix3x3 &b = t.getBasis();
  for (int i = 0; i < 3; ++i) {
    p.position[i] = double(o[i]) + double(b[i][0]) * e.pos[0] + double(b[i][1]) * e.pos[1] + double(b[i][2]) * e.pos[2];
  }
  const double *r = e.quat;  // q (x) r
  p.quaternion[0] = w * r[0] - x * r[1] - y * r[2] - z * r[3];
  p.quaternion[1] = w * r[1] + x * r[0] + y * r[3] - z * r[2];
  p.quaternion[2] = w * r[2] - x * r[3] + y * r[0] + z * r[1];
  p.quaternion[3] = w * r[3] + x * r[2] - y * r[1] + z * r[0];
  return p;
}

}  // namespace detail

bool as_dcol(const btCollisionShape *shape, const btTransform &world, const dcol_shape **out, dcol_pose *pose,
             double *padding) {
  if (!shape || !out || !pose || !detail::mapped_type(shape->getShapeType())) return false;
  const std::shared_ptr<const detail::Entry> e = detail::lookup(shape);
  if (!e->shape) return false;
  *out = e->shape;
  *pose = detail::world_pose(*e, world);
  if (padding) *padding = e->pad;
  return true;
}

void forget(const btCollisionShape *shape) {
  detail::Cache &c = detail::cache();
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    c.map.erase(shape);
  }
  detail::g_epoch.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace dcol_bullet
