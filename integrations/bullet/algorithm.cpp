// The collision algorithm that answers Bullet's pairs with dcol_contacts, its create function and
// its registration: see dcol_bullet.hpp.
#include <BulletCollision/CollisionDispatch/btActivatingCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <LinearMath/btPoolAllocator.h>

#include <cmath>
#include <cstring>
#include <new>

#include "internal.hpp"
#include "plane_contacts.hpp"

namespace dcol_bullet {

using detail::Entry;

namespace {

const std::size_t kMaxPoints = 4;  // Bullet's persistent manifold holds four

// Bullet's planes as a dcol half-space of depth 1, made on first use and kept for the process.
const dcol_shape *plane_halfspace() {
  struct Holder {
    dcol_shape *s = nullptr;
    Holder() { dcol_shape_new_halfspace(1.0, &s); }
    ~Holder() { dcol_shape_free(s); }
  };
  static const Holder h;
  return h.s;
}

void count(std::atomic<unsigned long> &c) { c.fetch_add(1, std::memory_order_relaxed); }

// One side of a pair: the entry it uses and what it was looked up for.
struct Slot {
  std::shared_ptr<const Entry> entry;
  const btCollisionShape *shape = nullptr;
  unsigned epoch = 0;

  // The entry for `s` as it is now: re-looked up when the shape, its parameters or the cache
  // (forget) changed since the last call.
  const Entry &get(const btCollisionShape *s) {
    const unsigned ep = detail::g_epoch.load(std::memory_order_relaxed);
    if (!entry || shape != s || epoch != ep || !(entry->key == detail::key_of(s))) {
      entry = detail::lookup(s);
      shape = s;
      epoch = ep;
    }
    return *entry;
  }
};

bool is_plane(const btCollisionShape *s) { return s->getShapeType() == STATIC_PLANE_PROXYTYPE; }

// Bullet's own algorithm for a pair (the dispatcher's collision configuration's).
btCollisionAlgorithm *native_algorithm(const btCollisionAlgorithmConstructionInfo &ci, const btCollisionObjectWrapper *a,
                                       const btCollisionObjectWrapper *b) {
  btCollisionDispatcher *d = static_cast<btCollisionDispatcher *>(ci.m_dispatcher1);
  btCollisionAlgorithmCreateFunc *f = d->getCollisionConfiguration()->getCollisionAlgorithmCreateFunc(
      a->getCollisionShape()->getShapeType(), b->getCollisionShape()->getShapeType());
  btCollisionAlgorithmConstructionInfo info = ci;
  info.m_manifold = nullptr;
  return f ? f->CreateCollisionAlgorithm(info, a, b) : nullptr;
}

class Algorithm : public btActivatingCollisionAlgorithm {
 public:
  Algorithm(const btCollisionAlgorithmConstructionInfo &ci, const btCollisionObjectWrapper *b0,
            const btCollisionObjectWrapper *b1)
      : btActivatingCollisionAlgorithm(ci, b0, b1), m_ci(ci) {
    m_manifold = m_dispatcher->getNewManifold(b0->getCollisionObject(), b1->getCollisionObject());
  }
  ~Algorithm() override {
    drop_fallback();
    if (m_manifold) m_dispatcher->releaseManifold(m_manifold);
  }

  void processCollision(const btCollisionObjectWrapper *a, const btCollisionObjectWrapper *b, const btDispatcherInfo &info,
                        btManifoldResult *result) override {
    const btCollisionShape *sa = a->getCollisionShape(), *sb = b->getCollisionShape();
    const bool pa = is_plane(sa), pb = is_plane(sb);
    const Entry *ea = pa ? nullptr : &m_slots[0].get(sa);
    const Entry *eb = pb ? nullptr : &m_slots[1].get(sb);
    if ((ea && !ea->shape) || (eb && !eb->shape) || (pa && pb)) {
      fallback(a, b, info, result);
      return;
    }
    drop_fallback();
    count(detail::counters().calls);
    result->setPersistentManifold(m_manifold);
    // Contacts within the manifold's breaking threshold, as Bullet's convex algorithms report
    // them; but two boxes only where they touch or overlap, as Bullet's own box-box algorithm
    // (btBoxBoxDetector, ODE's dBoxBox) does: the speculative points of boxes side by side (a
    // wall, a pyramid) cost the solver more than they give it (docs/bullet.md).
    const bool boxes = ea && eb && ea->kind == BOX_SHAPE_PROXYTYPE && eb->kind == BOX_SHAPE_PROXYTYPE;
    const double margin = boxes ? 0.0 : m_manifold->getContactBreakingThreshold();
    dcol_contact cs[kMaxPoints];
    std::size_t n = 0;
    dcol_status st = DCOL_OK;
    bool queried = false;
    // Cylinders and cones are dcol shapes grown by a ball: their contacts are those of the dcol
    // shapes within the margin plus the pads, the depths deeper by the pads and B's points moved
    // out by its pad (signed distances of grown convex shapes shift by the radii exactly).
    const double pad_a = ea ? ea->pad : 0, pad_b = eb ? eb->pad : 0;
    const btTransform &ta = a->getWorldTransform(), &tb = b->getWorldTransform();
    const bool same = m_last.valid && m_last.ea == ea && m_last.eb == eb && m_last.margin == margin &&
                      std::memcmp(&m_last.ta, &ta, sizeof ta) == 0 && std::memcmp(&m_last.tb, &tb, sizeof tb) == 0;
    if (same) {
      // The same shapes at bit-identical poses: dcol's answer would be the same (its cache
      // only decides faster), so the last one is used again.
      count(detail::counters().reused);
      n = m_last.n;
      st = m_last.st;
      queried = m_last.queried;
      for (std::size_t i = 0; i < n; ++i) cs[i] = m_last.cs[i];
    } else if (ea && eb) {
      // Apart by more than the margin along the line between the origins, or at least their
      // bounding spheres: no contact (a NaN distance falls through to dcol, which rejects it).
      if (!apart(*ea, a->getWorldTransform(), *eb, b->getWorldTransform(), margin)) {
        const dcol_pose p1 = detail::world_pose(*ea, a->getWorldTransform());
        const dcol_pose p2 = detail::world_pose(*eb, b->getWorldTransform());
        st = dcol_contacts_cached(ea->shape, &p1, eb->shape, &p2, margin + pad_a + pad_b, nullptr, &m_cache, cs,
                                  kMaxPoints, &n);
        queried = true;
      }
    } else {
      queried = plane_contacts(pa ? a : b, pa ? b : a, pa ? eb : ea, pa, margin, cs, &n, &st);
    }
    m_last.valid = true;
    m_last.ea = ea;
    m_last.eb = eb;
    m_last.margin = margin;
    m_last.ta = ta;
    m_last.tb = tb;
    m_last.n = n;
    m_last.st = st;
    m_last.queried = queried;
    for (std::size_t i = 0; i < n; ++i) m_last.cs[i] = cs[i];
    if (!same && !queried) count(detail::counters().early_outs);
    if (!same && queried && st == DCOL_OK && n == 0) count(detail::counters().apart);
    if (st == DCOL_ERROR_INVALID_POSE) {
      count(detail::counters().invalid_poses);
      m_manifold->clearManifold();
      return;
    }
    if (st == DCOL_ERROR_NOT_CONVERGED) count(detail::counters().not_converged);
    if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) {
      count(detail::counters().errors);
      n = 0;
    }
    // Bullet: normal on B towards A, point on B, distance (< 0 penetrating).
    btVector3 normal_b[kMaxPoints], on_b[kMaxPoints];
    btScalar dist[kMaxPoints];
    for (std::size_t i = 0; i < n; ++i) {
      const dcol_contact &c = cs[i];
      normal_b[i] = -btVector3(btScalar(c.normal[0]), btScalar(c.normal[1]), btScalar(c.normal[2]));
      const double h = 0.5 * c.depth + pad_b;
      on_b[i] = btVector3(btScalar(c.position[0] - h * c.normal[0]), btScalar(c.position[1] - h * c.normal[1]),
                          btScalar(c.position[2] - h * c.normal[2]));
      dist[i] = btScalar(-(c.depth + pad_a + pad_b));
    }
    if (n >= 2) drop_stale(a, n, normal_b, on_b, dist);
    // Shallowest first: Bullet merges a point into a cached one closer than the breaking
    // threshold, the later one replacing it, so the deepest is added last and always kept.
    std::size_t order[kMaxPoints];
    for (std::size_t i = 0; i < n; ++i) {  // insertion sort, by distance descending
      std::size_t j = i;
      for (; j > 0 && dist[order[j - 1]] < dist[i]; --j) order[j] = order[j - 1];
      order[j] = i;
    }
    for (std::size_t k = 0; k < n; ++k) result->addContactPoint(normal_b[order[k]], on_b[order[k]], dist[order[k]]);
    result->refreshContactPoints();
  }

  btScalar calculateTimeOfImpact(btCollisionObject *, btCollisionObject *, const btDispatcherInfo &,
                                 btManifoldResult *) override {
    return btScalar(1);
  }

  void getAllContactManifolds(btManifoldArray &manifolds) override {
    if (m_fallback) {
      m_fallback->getAllContactManifolds(manifolds);
    } else if (m_manifold) {
      manifolds.push_back(m_manifold);
    }
  }

 private:
  // Whether the two shapes are farther apart than `margin`: their bounding spheres, then their
  // extents along the line between their origins (support functions: a separating plane).
  static bool apart(const Entry &ea, const btTransform &ta, const Entry &eb, const btTransform &tb, double margin) {
    const btVector3 &oa = ta.getOrigin(), &ob = tb.getOrigin();
    double d[3] = {double(ob.x()) - oa.x(), double(ob.y()) - oa.y(), double(ob.z()) - oa.z()};
    const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double slack = 1e-6 * (ea.radius + eb.radius);  // float poses, double geometry
    if (dist - ea.radius - eb.radius > margin + slack) return true;
    if (!(dist > 0) || !std::isfinite(slack)) return false;
    for (double &v : d) v /= dist;
    double ua[3], ub[3];  // d in A's frame, -d in B's
    const btMatrix3x3 &ra = ta.getBasis(), &rb = tb.getBasis();
    for (int i = 0; i < 3; ++i) {
      ua[i] = ra[0][i] * d[0] + ra[1][i] * d[1] + ra[2][i] * d[2];
      ub[i] = -(rb[0][i] * d[0] + rb[1][i] * d[1] + rb[2][i] * d[2]);
    }
    return dist - detail::support(ea, ua) - detail::support(eb, ub) > margin + slack;
  }

  // A shape against Bullet's plane n.x = c (plane object frame): the plane is the dcol half-space
  // of depth 1 whose boundary it is, its origin under the shape's dcol origin. Returns whether
  // dcol was asked (false: the bounding sphere is above the plane by more than the margin).
  static bool plane_contacts(const btCollisionObjectWrapper *pw, const btCollisionObjectWrapper *sw, const Entry *e,
                             bool plane_first, double margin, dcol_contact *cs, std::size_t *n, dcol_status *st) {
    const btStaticPlaneShape *plane = static_cast<const btStaticPlaneShape *>(pw->getCollisionShape());
    const btTransform &tp = pw->getWorldTransform();
    const btVector3 nb = tp.getBasis() * plane->getPlaneNormal();
    double nrm[3] = {nb.x(), nb.y(), nb.z()};
    const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    if (!(len > 0)) {
      *st = DCOL_ERROR_INVALID_POSE;
      return true;
    }
    for (double &v : nrm) v /= len;
    const btVector3 &o = tp.getOrigin();
    const double c = plane->getPlaneConstant() / len + nrm[0] * o.x() + nrm[1] * o.y() + nrm[2] * o.z();
    const btVector3 &so = sw->getWorldTransform().getOrigin();
    const double above = nrm[0] * so.x() + nrm[1] * so.y() + nrm[2] * so.z() - c;
    // The shape's lowest point (its support at -n) above the plane by more than the margin.
    const btMatrix3x3 &r = sw->getWorldTransform().getBasis();
    double down[3];
    for (int i = 0; i < 3; ++i) down[i] = -(r[0][i] * nrm[0] + r[1][i] * nrm[1] + r[2][i] * nrm[2]);
    if (above - detail::support(*e, down) > margin + 1e-6 * e->radius) return false;
    margin += e->pad;
    if (closed_form(*e, sw->getWorldTransform(), nrm, c, plane_first, margin, cs, n, st)) return true;
    const dcol_pose ps = detail::world_pose(*e, sw->getWorldTransform());
    const double h = nrm[0] * ps.position[0] + nrm[1] * ps.position[1] + nrm[2] * ps.position[2] - c;
    dcol_pose box;
    for (int k = 0; k < 3; ++k) box.position[k] = ps.position[k] - (h + 1.0) * nrm[k];
    // The rotation taking e_z to the plane normal.
    double w = 1.0 + nrm[2], x = -nrm[1], y = nrm[0];
    if (w < 1e-12) {
      w = 0;
      x = 1;
      y = 0;
    }
    const double ql = std::sqrt(w * w + x * x + y * y);
    box.quaternion[0] = w / ql;
    box.quaternion[1] = x / ql;
    box.quaternion[2] = y / ql;
    box.quaternion[3] = 0;
    const dcol_shape *hs = plane_halfspace();
    *st = plane_first ? dcol_contacts(hs, &box, e->shape, &ps, margin, nullptr, cs, kMaxPoints, n)
                      : dcol_contacts(e->shape, &ps, hs, &box, margin, nullptr, cs, kMaxPoints, n);
    return true;
  }

  // Bullet's sphere, box, capsule, cylinder or cone (their dcol shapes: for cylinders and cones
  // the core, `margin` holding the pad) against the plane n.x = c in closed form
  // (plane_contacts.hpp: the contacts from the support map, no dcol query; docs/bullet.md), as
  // dcol_contacts writes them (normal from the first shape to the second). False for the other
  // shapes (hulls, dcol_bullet::Shape): dcol answers.
  static bool closed_form(const Entry &e, const btTransform &t, const double nrm[3], double c, bool plane_first,
                          double margin, dcol_contact *cs, std::size_t *n, dcol_status *st) {
    const int kind = e.kind;
    if (kind != SPHERE_SHAPE_PROXYTYPE && kind != BOX_SHAPE_PROXYTYPE && kind != CAPSULE_SHAPE_PROXYTYPE &&
        kind != CYLINDER_SHAPE_PROXYTYPE && kind != CONE_SHAPE_PROXYTYPE)
      return false;
    dcol_plane::Plane pl;
    for (int k = 0; k < 3; ++k) pl.n[k] = nrm[k];
    pl.d = c;
    const btMatrix3x3 &r = t.getBasis();
    const btVector3 &o = t.getOrigin();
    dcol_plane::Frame f;
    for (int i = 0; i < 3; ++i) {
      f.c[i] = o[i];
      for (int k = 0; k < 3; ++k) f.axis[k][i] = r[i][k];  // column k: the shape's axis k in world
    }
    dcol_plane::Points pts;
    int res;
    const int up = e.axis;
    switch (kind) {
      case SPHERE_SHAPE_PROXYTYPE: res = dcol_plane::sphere(pl, f.c, e.dims[0], pts, margin); break;
      case BOX_SHAPE_PROXYTYPE: res = dcol_plane::box(pl, f, e.dims, pts, margin); break;
      case CAPSULE_SHAPE_PROXYTYPE:
        res = e.dims[0] > 0 ? dcol_plane::capsule(pl, f, up, e.dims[1], 2 * e.dims[0], pts, margin)
                            : dcol_plane::sphere(pl, f.c, e.dims[1], pts, margin);
        break;
      case CYLINDER_SHAPE_PROXYTYPE: res = dcol_plane::cylinder(pl, f, up, e.dims[1], 2 * e.dims[0], pts, margin); break;
      default: {
        // Bullet's cone: apex at +h/2 on the up axis, base at -h/2; dcol's: apex at -3h/4 on its
        // axis, base at +h/4: the axis is -up, the centre h/4 below the shape's origin.
        const double h = 2 * e.dims[0];
        for (int i = 0; i < 3; ++i) {
          f.c[i] -= 0.25 * h * f.axis[up][i];
          f.axis[up][i] = -f.axis[up][i];
        }
        res = dcol_plane::cone(pl, f, up, h, e.dims[1], pts, margin);
        break;
      }
    }
    *n = 0;
    if (res < 0) {
      *st = DCOL_ERROR_INVALID_POSE;
      return true;
    }
    *st = DCOL_OK;
    int order[dcol_plane::kMaxPoints];
    const int k = res == 0 ? 0 : dcol_plane::reduce(pts, static_cast<int>(kMaxPoints), order);
    const double s = plane_first ? 1.0 : -1.0;
    for (int i = 0; i < k; ++i) {
      for (int j = 0; j < 3; ++j) {
        cs[i].position[j] = pts.pos[order[i]][j];
        cs[i].normal[j] = s * nrm[j];
      }
      cs[i].depth = pts.depth[order[i]];
    }
    *n = static_cast<std::size_t>(k);
    return true;
  }

  // Several points are a whole contact feature (a face, an edge): the manifold's points that none
  // of them continues (matched as btPersistentManifold::getCacheEntry matches, on body 0's local
  // point within the contact breaking threshold) are stale and removed, so that the manifold is
  // dcol's answer, its matched points keeping their impulses for warm starting. (Left in, they
  // crowd out the new points when a body moves more than the threshold per step.)
  void drop_stale(const btCollisionObjectWrapper *a, std::size_t n, const btVector3 *normal_b, const btVector3 *on_b,
                  const btScalar *dist) {
    const int old = m_manifold->getNumContacts();
    if (old == 0) return;
    const bool a_is_body0 = m_manifold->getBody0() == a->getCollisionObject();
    const btScalar limit = m_manifold->getContactBreakingThreshold() * m_manifold->getContactBreakingThreshold();
    // Body 0's local points of the new contacts (A's surface points when A is body 0, else B's).
    btVector3 local0[kMaxPoints];
    const btTransform &t0 = m_manifold->getBody0()->getWorldTransform();
    for (std::size_t i = 0; i < n; ++i) {
      local0[i] = t0.invXform(a_is_body0 ? on_b[i] + normal_b[i] * dist[i] : on_b[i]);
    }
    for (int k = old - 1; k >= 0; --k) {
      const btVector3 &p = m_manifold->getContactPoint(k).m_localPointA;
      bool continued = false;
      for (std::size_t i = 0; i < n && !continued; ++i) continued = (p - local0[i]).length2() < limit;
      if (!continued) m_manifold->removeContactPoint(k);
    }
  }

  void fallback(const btCollisionObjectWrapper *a, const btCollisionObjectWrapper *b, const btDispatcherInfo &info,
                btManifoldResult *result) {
    count(detail::counters().fallback_calls);
    if (m_manifold->getNumContacts()) m_manifold->clearManifold();
    if (!m_fallback) m_fallback = native_algorithm(m_ci, a, b);
    if (m_fallback) m_fallback->processCollision(a, b, info, result);
  }

  void drop_fallback() {
    if (!m_fallback) return;
    m_fallback->~btCollisionAlgorithm();
    m_dispatcher->freeCollisionAlgorithm(m_fallback);
    m_fallback = nullptr;
  }

  // The last call's inputs and dcol's answer.
  struct Last {
    bool valid = false;
    bool queried = false;
    const Entry *ea = nullptr, *eb = nullptr;
    double margin = 0;
    btTransform ta, tb;
    std::size_t n = 0;
    dcol_status st = DCOL_OK;
    dcol_contact cs[kMaxPoints];
  };
  Last m_last;
  // The pair's warm-start cache (docs/warm-starts.md): shapes replaced in a slot only make one
  // call cold.
  dcol_cache m_cache = DCOL_CACHE_INIT;
  btCollisionAlgorithmConstructionInfo m_ci;
  btPersistentManifold *m_manifold = nullptr;
  btCollisionAlgorithm *m_fallback = nullptr;
  Slot m_slots[2];
};

// Whether dcol can take the shape of `w` now (a plane always: it is dcol's half-space).
bool takes(const btCollisionObjectWrapper *w) {
  const btCollisionShape *s = w->getCollisionShape();
  return is_plane(s) || detail::lookup(s)->shape != nullptr;
}

struct CreateFunc : public btCollisionAlgorithmCreateFunc {
  btCollisionAlgorithm *CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo &ci,
                                                 const btCollisionObjectWrapper *b0,
                                                 const btCollisionObjectWrapper *b1) override {
    // A shape dcol cannot take (a zero-size box, a degenerate hull) keeps Bullet's algorithm.
    if (!takes(b0) || !takes(b1)) {
      count(detail::counters().fallback_pairs);
      return native_algorithm(ci, b0, b1);
    }
    btCollisionDispatcher *d = static_cast<btCollisionDispatcher *>(ci.m_dispatcher1);
    // The dispatcher's pool hands out blocks of the configuration's largest algorithm; a bigger
    // one is allocated apart (freeCollisionAlgorithm frees either).
    const int size = static_cast<int>(sizeof(Algorithm));
    const btPoolAllocator *pool = d->getCollisionConfiguration()->getCollisionAlgorithmPool();
    void *mem = pool && size <= pool->getElementSize() ? d->allocateCollisionAlgorithm(size) : btAlignedAlloc(size, 16);
    return new (mem) Algorithm(ci, b0, b1);
  }
};

CreateFunc &create_func() {
  static CreateFunc f;  // stateless: one for every dispatcher
  return f;
}

const int kBulletTypes[] = {SPHERE_SHAPE_PROXYTYPE,   BOX_SHAPE_PROXYTYPE,  CAPSULE_SHAPE_PROXYTYPE,
                            CYLINDER_SHAPE_PROXYTYPE, CONE_SHAPE_PROXYTYPE, CONVEX_HULL_SHAPE_PROXYTYPE};

void register_pair(btCollisionDispatcher *d, int t0, int t1) {
  d->registerCollisionCreateFunc(t0, t1, &create_func());
  d->registerCollisionCreateFunc(t1, t0, &create_func());
}

}  // namespace

void register_algorithms(btCollisionDispatcher *dispatcher) {
  if (!dispatcher) return;
  register_pair(dispatcher, CUSTOM_CONVEX_SHAPE_TYPE, CUSTOM_CONVEX_SHAPE_TYPE);
  register_pair(dispatcher, CUSTOM_CONVEX_SHAPE_TYPE, STATIC_PLANE_PROXYTYPE);
  for (int t : kBulletTypes) register_pair(dispatcher, CUSTOM_CONVEX_SHAPE_TYPE, t);
}

void use_dcol(btCollisionDispatcher *dispatcher) {
  if (!dispatcher) return;
  register_algorithms(dispatcher);
  for (int t0 : kBulletTypes) {
    register_pair(dispatcher, t0, STATIC_PLANE_PROXYTYPE);
    for (int t1 : kBulletTypes) register_pair(dispatcher, t0, t1);
  }
}

unsigned long algorithm_calls() { return detail::counters().calls.load(std::memory_order_relaxed); }

Stats stats() {
  const detail::Counters &c = detail::counters();
  Stats s;
  s.calls = c.calls.load(std::memory_order_relaxed);
  s.early_outs = c.early_outs.load(std::memory_order_relaxed);
  s.apart = c.apart.load(std::memory_order_relaxed);
  s.reused = c.reused.load(std::memory_order_relaxed);
  s.fallback_pairs = c.fallback_pairs.load(std::memory_order_relaxed);
  s.fallback_calls = c.fallback_calls.load(std::memory_order_relaxed);
  s.invalid_poses = c.invalid_poses.load(std::memory_order_relaxed);
  s.not_converged = c.not_converged.load(std::memory_order_relaxed);
  s.errors = c.errors.load(std::memory_order_relaxed);
  s.shapes_built = c.shapes_built.load(std::memory_order_relaxed);
  return s;
}

}  // namespace dcol_bullet
