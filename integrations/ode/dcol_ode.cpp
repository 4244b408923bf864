// dcol as ODE's narrow phase: see dcol_ode.hpp (the contract) and docs/ode.md (the mapping).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dcol_ode_internal.hpp"
#include "plane_contacts.hpp"

namespace dcol_ode {
namespace {

// ---------------------------------------------------------------------------------------------
// The adapter's state (one per process; see "Threads" in dcol_ode.hpp).

using detail::Key;
using detail::KeyHash;
using detail::PairHash;
using detail::kBox;
using detail::kCapsule;
using detail::kCylinder;
using detail::kSphere;

// A convex made by create_convex: its hull (about `shift`, a point strictly inside it, when the
// geom's origin is not), its points (to check the record against ODE's bounding box of the geom)
// and the last bounding box found to match.
struct ConvexRecord {
  dcol_shape *shape = nullptr;
  double shift[3] = {0, 0, 0};
  double radius = 0;  // the largest distance of a point from `shift`
  std::vector<double> points;
  dReal aabb[6] = {0, 0, 0, 0, 0, 0};
  bool checked = false;
  // The points at the box's six sides (x min, x max, y min, ...) at the last full check: a body
  // moving a little keeps them, so a new box is first checked against those six alone.
  std::size_t extreme[6] = {0, 0, 0, 0, 0, 0};
};

// What the collider remembers of a pair of geoms between calls: whether its last call found
// contacts (a pair that had none is tested with dcol_alpha_below first, a far cheaper query when
// the shapes are apart), and when it was last seen (to forget pairs no longer colliding).
struct PairHint {
  bool had_contacts = false;
  // The last dcol_contacts_cached call found no contact: the pair's cache holds a normal that
  // separated the shapes, which decides the next call with two support calls while it still
  // separates them (cheaper than the dcol_alpha_below pre-check).
  bool apart_known = false;
  unsigned long seen = 0;
  // The pair's warm-start cache (docs/warm-starts.md): a geom id reused by another geom only
  // makes one call cold.
  dcol_cache cache = DCOL_CACHE_INIT;
};

// The last ODE plane's parameters (a, b, c, d) and what collide_plane derives from them.
struct PlaneFrame {
  dReal params[4] = {0, 0, 0, 0};
  bool set = false;
  bool ok = false;
  double n[3] = {0, 0, 0};
  double d = 0;
  double q[4] = {1, 0, 0, 0};
};

struct State {
  std::unordered_map<Key, dcol_shape *, KeyHash> shapes;  // nullptr: sizes dcol rejects
  // The shape each geom found last, in a table indexed by a Fibonacci hash of the geom's address
  // (a geom keeps its sizes from call to call): looked at before the map, whose hash and probe
  // cost 80 instructions a call (the address's bits 4-11 let a few of the pyramid's 56 geoms
  // share an entry and miss it on every call: 14 instructions a call on average). An entry
  // answers only for its geom and the same key, so a geom whose sizes changed, or a new geom at a
  // freed address, finds the shape of its own key.
  struct Recent {
    dGeomID geom = nullptr;
    Key key = {};
    const dcol_shape *shape = nullptr;
    // The geom's bounding radius as resolve() computed it for this key (a box's or cylinder's
    // square root, kept), when has_radius.
    bool has_radius = false;
    double radius = 0;
  };
  static constexpr std::size_t kRecent = 1024;
  Recent recent[kRecent];
  std::unordered_map<std::pair<dGeomID, dGeomID>, PairHint, PairHash> pairs;
  // The hint each pair found last, in a table indexed by a hash of the two addresses and checked
  // against them: looked at before the map, whose hash, bucket division and probe cost about 60
  // instructions a call. An entry points into `pairs` (whose elements do not move when it
  // grows); the table is emptied whenever pairs leave the map.
  struct RecentPair {
    dGeomID a = nullptr, b = nullptr;
    PairHint *hint = nullptr;
  };
  static constexpr std::size_t kRecentPairs = 1024;
  RecentPair recent_pairs[kRecentPairs];
  unsigned long pair_clock = 0;  // collider calls, for PairHint::seen
  std::unordered_map<dGeomID, ConvexRecord> convexes;
  dcol_shape *halfspace = nullptr;  // ODE's planes: a half-space of depth 1
  bool halfspace_tried = false;
  PlaneFrame plane_frame;
  Stats stats = Stats();
  int geom_class = -1;

  void clear() {
    for (auto &s : shapes) dcol_shape_free(s.second);
    shapes.clear();
    for (Recent &r : recent) r = Recent();
    for (auto &c : convexes) dcol_shape_free(c.second.shape);
    convexes.clear();
    pairs.clear();
    for (RecentPair &r : recent_pairs) r = RecentPair();
  }
  ~State() {
    clear();
    dcol_shape_free(halfspace);
  }
};
State g;

// ---------------------------------------------------------------------------------------------
// Geoms as dcol shapes and poses.

// The dcol geom class's per-geom data.
struct GeomData {
  const dcol_shape *shape;
  double radius;
};

GeomData *geom_data(dGeomID geom) { return static_cast<GeomData *>(dGeomGetClassData(geom)); }

struct Resolved {
  const dcol_shape *shape;
  dcol_pose pose;
  double radius;  // bounding radius about pose.position
};

enum class Res { kOk, kRejected, kPlainConvex, kUnsupported };

dcol_shape *make_shape(const Key &k) {
  dcol_shape *s = nullptr;
  switch (k.kind) {
    case kSphere: dcol_shape_new_sphere(k.a, &s); break;
    case kBox: dcol_shape_new_box(k.a, k.b, k.c, &s); break;
    case kCapsule: dcol_shape_new_capsule(k.a, k.b, &s); break;
    default: dcol_shape_new_cylinder(k.a, k.b, &s); break;
  }
  return s;  // nullptr when dcol rejects the sizes (its status and message are not needed)
}

// cached_shape() when the geom's entry of the recent table does not answer: the shape of `k` from
// the map (made when new), written to the entry `r`.
__attribute__((noinline)) const dcol_shape *cached_shape_miss(dGeomID geom, const Key &k, State::Recent &r) {
  // A NaN size never equals itself: it would miss the cache and add an entry on every call.
  // Sizes that are not finite are no shape (the pair is rejected), and are not kept (so an entry
  // of the recent table, whose key was finite, answers only finite sizes: the test comes after it).
  if (!(std::isfinite(k.a) && std::isfinite(k.b) && std::isfinite(k.c))) return nullptr;
  auto it = g.shapes.find(k);
  const dcol_shape *s = nullptr;
  if (it != g.shapes.end()) {
    s = it->second;
  } else {
    dcol_shape *made = make_shape(k);
    g.shapes.emplace(k, made);
    s = made;
  }
  r.geom = geom;
  r.key = k;
  r.shape = s;
  r.has_radius = false;
  return s;
}

State::Recent &recent_entry(dGeomID geom) {
  static_assert(State::kRecent == 1024, "the index takes the hash's top 10 bits");
  return g.recent[(static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(geom)) * 0x9E3779B97F4A7C15ull) >> 54];
}

// The dcol shape of the primitive `geom` with key `k` (nullptr: sizes dcol rejects): its entry in
// the recent table when that entry is for this geom and key, else the map's.
inline const dcol_shape *cached_shape(dGeomID geom, const Key &k) {
  State::Recent &r = recent_entry(geom);
  if (r.geom == geom && r.key == k) return r.shape;
  return cached_shape_miss(geom, k, r);
}

// cached_shape(), with the bounding radius `radius()` (of the same sizes) computed only the first
// time the entry answers for this geom and key, then kept in it.
template <class F>
inline const dcol_shape *cached_shape(dGeomID geom, const Key &k, double *radius, F compute) {
  State::Recent &r = recent_entry(geom);
  if (!(r.geom == geom && r.key == k)) {
    const dcol_shape *s = cached_shape_miss(geom, k, r);
    *radius = compute();
    if (r.geom == geom && r.key == k) {  // the entry was written (not for sizes not finite)
      r.radius = *radius;
      r.has_radius = true;
    }
    return s;
  }
  if (!r.has_radius) {  // written by the other cached_shape()
    r.radius = compute();
    r.has_radius = true;
  }
  *radius = r.radius;
  return r.shape;
}

void geom_pose(dGeomID geom, dcol_pose *pose) {
  const dReal *p = dGeomGetPosition(geom);  // the geom's own frame: body pose and offset composed
  dQuaternion q;
  dGeomGetQuaternion(geom, q);  // (w, x, y, z), as dcol's
  for (int i = 0; i < 3; ++i) pose->position[i] = p[i];
  for (int i = 0; i < 4; ++i) pose->quaternion[i] = q[i];
}

// ODE's capsules and cylinders lie along their geom's z axis, dcol's along body x: the dcol body
// frame is the geom's turned by -90 degrees about y (x to z), q' = q * (c, 0, -c, 0), c = sqrt(1/2).
void x_axis_to_z(dcol_pose *pose) {
  const double c = std::sqrt(0.5);
  const double w = pose->quaternion[0], x = pose->quaternion[1], y = pose->quaternion[2], z = pose->quaternion[3];
  pose->quaternion[0] = c * (w + y);
  pose->quaternion[1] = c * (x + z);
  pose->quaternion[2] = c * (y - w);
  pose->quaternion[3] = c * (z - x);
}

bool check_record(dGeomID geom, ConvexRecord &rec);

Res resolve(dGeomID geom, int cls, Resolved *r) {
  switch (cls) {
    case dSphereClass: {
      const double radius = dGeomSphereGetRadius(geom);
      r->shape = cached_shape(geom, Key{kSphere, radius, 0, 0});
      r->radius = radius;
      geom_pose(geom, &r->pose);
      break;
    }
    case dBoxClass: {
      dVector3 l;
      dGeomBoxGetLengths(geom, l);  // full side lengths
      r->shape = cached_shape(geom, Key{kBox, 0.5 * l[0], 0.5 * l[1], 0.5 * l[2]}, &r->radius,
                              [&l] { return 0.5 * std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]); });
      geom_pose(geom, &r->pose);
      break;
    }
    case dCapsuleClass:
    case dCylinderClass: {
      dReal radius = 0, length = 0;
      if (cls == dCapsuleClass) {
        dGeomCapsuleGetParams(geom, &radius, &length);  // length of the cylindrical part
        r->radius = radius + 0.5 * length;
      } else {
        dGeomCylinderGetParams(geom, &radius, &length);
        r->radius = std::sqrt(radius * radius + 0.25 * length * length);
      }
      // A capsule of length 0 is ODE's way to write a sphere (dcol's capsules need length > 0).
      if (cls == dCapsuleClass && length == 0)
        r->shape = cached_shape(geom, Key{kSphere, radius, 0, 0});
      else
        r->shape = cached_shape(geom, Key{cls == dCapsuleClass ? kCapsule : kCylinder, radius, length, 0});
      geom_pose(geom, &r->pose);
      x_axis_to_z(&r->pose);
      break;
    }
    case dConvexClass: {
      auto it = g.convexes.find(geom);
      if (it == g.convexes.end() || !check_record(geom, it->second)) return Res::kPlainConvex;
      const ConvexRecord &rec = it->second;
      r->shape = rec.shape;
      r->radius = rec.radius;
      geom_pose(geom, &r->pose);
      if (rec.shift[0] != 0 || rec.shift[1] != 0 || rec.shift[2] != 0) {
        const dReal *R = dGeomGetRotation(geom);  // 3x4 row-major
        for (int i = 0; i < 3; ++i)
          r->pose.position[i] += R[4 * i] * rec.shift[0] + R[4 * i + 1] * rec.shift[1] + R[4 * i + 2] * rec.shift[2];
      }
      break;
    }
    default:
      if (g.geom_class >= 0 && cls == g.geom_class) {
        const GeomData *d = geom_data(geom);
        r->shape = d->shape;
        r->radius = d->radius;
        geom_pose(geom, &r->pose);
        break;
      }
      return Res::kUnsupported;
  }
  return r->shape ? Res::kOk : Res::kRejected;
}

// Whether a convex record still describes its geom: ODE's bounding box of the geom must be the box
// of the recorded points at the geom's pose (checked again only when ODE's box has changed). A box
// that changed is first compared with the six points found at its sides by the last full check
// (a moving body mostly keeps them: six points instead of all, 340 instructions a pile's call on
// average); when those do not reach ODE's box within the tolerance, every point is looked at.
bool check_record(dGeomID geom, ConvexRecord &rec) {
  dReal box[6];
  dGeomGetAABB(geom, box);
  if (rec.checked && std::memcmp(box, rec.aabb, sizeof box) == 0) return true;
  const dReal *p = dGeomGetPosition(geom);
  const dReal *R = dGeomGetRotation(geom);
  double scale = 1.0;
  for (int i = 0; i < 6; ++i) scale = std::max(scale, std::fabs(box[i]));
  auto world = [&](std::size_t j, int i) {
    const double *b = &rec.points[3 * j];
    return R[4 * i] * b[0] + R[4 * i + 1] * b[1] + R[4 * i + 2] * b[2] + p[i];
  };
  if (rec.checked) {
    bool same = true;
    for (int k = 0; k < 6; ++k) same = same && std::fabs(world(rec.extreme[k], k / 2) - box[k]) <= 1e-9 * scale;
    if (same) {
      std::memcpy(rec.aabb, box, sizeof box);
      return true;
    }
  }
  double ours[6] = {INFINITY, -INFINITY, INFINITY, -INFINITY, INFINITY, -INFINITY};
  std::size_t at[6] = {0, 0, 0, 0, 0, 0};
  const std::size_t n = rec.points.size() / 3;
  for (std::size_t j = 0; j < n; ++j) {
    for (int i = 0; i < 3; ++i) {
      const double w = world(j, i);
      if (w < ours[2 * i]) {
        ours[2 * i] = w;
        at[2 * i] = j;
      }
      if (w > ours[2 * i + 1]) {
        ours[2 * i + 1] = w;
        at[2 * i + 1] = j;
      }
    }
  }
  bool same = true;
  for (int i = 0; i < 6; ++i) same = same && std::fabs(ours[i] - box[i]) <= 1e-9 * scale;
  if (same) {
    std::memcpy(rec.aabb, box, sizeof box);
    std::memcpy(rec.extreme, at, sizeof at);
    rec.checked = true;
    return true;
  }
  // Not the geom it was recorded for (destroyed and its address reused, or dGeomSetConvex): a
  // plain convex from now on.
  dcol_shape_free(rec.shape);
  g.convexes.erase(geom);
  ++g.stats.dropped_records;
  return false;
}

// ---------------------------------------------------------------------------------------------
// The collider.

// The hint of a pair (either order). Every 2^16 calls the pairs not seen in the last 2^16 calls are
// forgotten, so the table holds about the pairs of the last few steps (a destroyed geom's pairs
// go with them; a hint is only a hint: a stale one costs one extra query, never a contact).
PairHint &pair_hint(dGeomID a, dGeomID b) {
  const unsigned long now = ++g.pair_clock;
  const unsigned long kWindow = 1ul << 16;
  if (now % kWindow == 0) {
    for (State::RecentPair &r : g.recent_pairs) r = State::RecentPair();
    for (auto it = g.pairs.begin(); it != g.pairs.end();) {
      if (now - it->second.seen > kWindow)
        it = g.pairs.erase(it);
      else
        ++it;
    }
  }
  if (b < a) std::swap(a, b);
  const std::uint64_t ua = reinterpret_cast<std::uintptr_t>(a), ub = reinterpret_cast<std::uintptr_t>(b);
  State::RecentPair &r = g.recent_pairs[((ua ^ (ub >> 3)) * 0x9E3779B97F4A7C15ull) >> 54];
  static_assert(State::kRecentPairs == 1024, "the index takes the hash's top 10 bits");
  if (r.a != a || r.b != b) {
    r.a = a;
    r.b = b;
    r.hint = &g.pairs[std::make_pair(a, b)];
  }
  r.hint->seen = now;
  return *r.hint;
}

std::size_t capacity(int flags) {
  const std::size_t n = static_cast<std::size_t>(flags & 0xffff);
  return std::max<std::size_t>(1, std::min<std::size_t>(n, DCOL_MAX_CONTACTS));
}

dContactGeom *slot(dContactGeom *contact, int skip, std::size_t i) {
  return reinterpret_cast<dContactGeom *>(reinterpret_cast<char *>(contact) + i * static_cast<std::size_t>(skip));
}

// Writes dcol's contacts as ODE's for (o1, o2): `flip` when dcol's normal (from its shape 1 to its
// shape 2) points out of o1, i.e. when dcol's shape 1 was o1 (ODE's normal points into o1).
int write_contacts(dGeomID o1, dGeomID o2, const dcol_contact *cs, std::size_t n, bool flip, dContactGeom *contact,
                   int skip) {
  const double s = flip ? -1.0 : 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    dContactGeom *c = slot(contact, skip, i);
    for (int k = 0; k < 3; ++k) {
      c->pos[k] = cs[i].position[k];
      c->normal[k] = s * cs[i].normal[k];
    }
    c->pos[3] = 0;
    c->normal[3] = 0;
    c->depth = cs[i].depth;
    c->g1 = o1;
    c->g2 = o2;
    c->side1 = -1;
    c->side2 = -1;
  }
  g.stats.contacts += n;
  return static_cast<int>(n);
}

// ODE's plane n.x = d (the solid region below, n out of it): its unit normal, offset and attitude,
// computed again only when its parameters change (a scene has one floor or a few walls; the same
// numbers either way). nullptr when the parameters make no plane.
const PlaneFrame *plane_frame(dGeomID plane) {
  dVector4 p;
  dGeomPlaneGetParams(plane, p);
  PlaneFrame &f = g.plane_frame;
  if (!f.set || std::memcmp(f.params, p, sizeof f.params) != 0) {
    std::memcpy(f.params, p, sizeof f.params);
    f.set = true;
    const double len = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    f.ok = len > 0 && std::isfinite(len);
    if (f.ok) {
      for (int k = 0; k < 3; ++k) f.n[k] = p[k] / len;
      f.d = p[3] / len;
      // The attitude turning e_z to n: (1 + n_z, -n_y, n_x, 0) normalised (e_x's half turn if n = -e_z).
      double q[4] = {1.0 + f.n[2], -f.n[1], f.n[0], 0.0};
      if (q[0] < 1e-12) {
        q[0] = 0;
        q[1] = 1;
        q[2] = 0;
      }
      const double ql = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
      for (int k = 0; k < 4; ++k) f.q[k] = q[k] / ql;
    }
  }
  return f.ok ? &f : nullptr;
}

// A solid against ODE's plane: the dcol half-space of depth 1 whose boundary is the plane, posed
// at the foot of the solid's centre on the plane.
int collide_plane(dGeomID o1, dGeomID o2, const Resolved &solid, dGeomID plane, int flags, dContactGeom *contact,
                  int skip) {
  const PlaneFrame *f = plane_frame(plane);
  if (!f) {
    ++g.stats.rejected;
    return 0;
  }
  const double *n = f->n;
  const double *c = solid.pose.position;
  const double h = n[0] * c[0] + n[1] * c[1] + n[2] * c[2] - f->d;
  if (h > solid.radius) return 0;  // the solid's bounding ball is above the plane
  if (!g.halfspace_tried) {
    g.halfspace_tried = true;
    dcol_shape_new_halfspace(1.0, &g.halfspace);
  }
  if (!g.halfspace) {
    ++g.stats.rejected;
    return 0;
  }
  dcol_pose hp;
  for (int k = 0; k < 3; ++k) hp.position[k] = c[k] - (h + 1.0) * n[k];
  for (int k = 0; k < 4; ++k) hp.quaternion[k] = f->q[k];
  dcol_contact cs[DCOL_MAX_CONTACTS];
  std::size_t count = 0;
  const dcol_status st = dcol_contacts(g.halfspace, &hp, solid.shape, &solid.pose, 0.0, nullptr, cs, capacity(flags), &count);
  if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) {
    ++g.stats.rejected;
    return 0;
  }
  // dcol's normal points out of the plane into the solid: ODE's normal when o1 is the solid.
  return write_contacts(o1, o2, cs, count, o1 == plane, contact, skip);
}

// ODE's sphere, box, capsule or cylinder against ODE's plane in closed form (plane_contacts.hpp:
// the contacts from the solid's support map, no dcol query; docs/ode.md). The solid's sizes are
// checked as dcol checks them (the shape made for them, or the rejection, is cached). Returns -2
// for the other classes (recorded convexes and dcol geoms go to collide_plane).
int collide_plane_closed(dGeomID o1, dGeomID o2, dGeomID solid, int cls, dGeomID plane, int flags,
                         dContactGeom *contact, int skip) {
  double dims[3] = {0, 0, 0};
  Key key;
  switch (cls) {
    case dSphereClass:
      dims[0] = dGeomSphereGetRadius(solid);
      key = Key{kSphere, dims[0], 0, 0};
      break;
    case dBoxClass: {
      dVector3 l;
      dGeomBoxGetLengths(solid, l);  // full side lengths
      for (int k = 0; k < 3; ++k) dims[k] = 0.5 * l[k];
      key = Key{kBox, dims[0], dims[1], dims[2]};
      break;
    }
    case dCapsuleClass:
    case dCylinderClass: {
      dReal radius = 0, length = 0;
      if (cls == dCapsuleClass)
        dGeomCapsuleGetParams(solid, &radius, &length);
      else
        dGeomCylinderGetParams(solid, &radius, &length);
      dims[0] = radius;
      dims[1] = length;
      if (cls == dCapsuleClass && length == 0) {
        cls = dSphereClass;  // ODE's way to write a sphere
        key = Key{kSphere, radius, 0, 0};
      } else {
        key = Key{cls == dCapsuleClass ? kCapsule : kCylinder, radius, length, 0};
      }
      break;
    }
    default:
      return -2;
  }
  if (!cached_shape(solid, key)) {
    ++g.stats.rejected;
    return 0;
  }
  const PlaneFrame *f = plane_frame(plane);
  if (!f) {
    ++g.stats.rejected;
    return 0;
  }
  dcol_plane::Plane pl;
  for (int k = 0; k < 3; ++k) pl.n[k] = f->n[k];
  pl.d = f->d;
  const dReal *p = dGeomGetPosition(solid);
  dcol_plane::Points pts;
  int t;
  if (cls == dSphereClass) {
    const double c[3] = {p[0], p[1], p[2]};
    t = dcol_plane::sphere(pl, c, dims[0], pts);
  } else {
    const dReal *R = dGeomGetRotation(solid);  // 3x4 row-major: column k is the body's axis k
    dcol_plane::Frame fr;
    for (int i = 0; i < 3; ++i) {
      fr.c[i] = p[i];
      for (int k = 0; k < 3; ++k) fr.axis[k][i] = R[4 * i + k];
    }
    if (cls == dBoxClass)
      t = dcol_plane::box(pl, fr, dims, pts);
    else if (cls == dCapsuleClass)
      t = dcol_plane::capsule(pl, fr, 2, dims[0], dims[1], pts);
    else
      t = dcol_plane::cylinder(pl, fr, 2, dims[0], dims[1], pts);
  }
  if (t < 0) {
    ++g.stats.rejected;  // a non-finite pose
    return 0;
  }
  if (t == 0) return 0;
  int order[dcol_plane::kMaxPoints];
  const int n = dcol_plane::reduce(pts, static_cast<int>(capacity(flags)), order);
  // The plane's normal points out of it into the solid: ODE's normal when o1 is the solid.
  const double s = o1 == plane ? -1.0 : 1.0;
  for (int i = 0; i < n; ++i) {
    dContactGeom *c = slot(contact, skip, static_cast<std::size_t>(i));
    for (int k = 0; k < 3; ++k) {
      c->pos[k] = pts.pos[order[i]][k];
      c->normal[k] = s * pl.n[k];
    }
    c->pos[3] = 0;
    c->normal[3] = 0;
    c->depth = pts.depth[order[i]];
    c->g1 = o1;
    c->g2 = o2;
    c->side1 = -1;
    c->side2 = -1;
  }
  g.stats.contacts += static_cast<unsigned long>(n);
  return n;
}

int collide(dGeomID o1, dGeomID o2, int flags, dContactGeom *contact, int skip) {
  ++g.stats.calls;
  const int c1 = dGeomGetClass(o1), c2 = dGeomGetClass(o2);
  Resolved r1, r2;
  if (c1 == dPlaneClass || c2 == dPlaneClass) {
    const bool plane_first = c1 == dPlaneClass;
    dGeomID solid = plane_first ? o2 : o1;
    const int closed = collide_plane_closed(o1, o2, solid, plane_first ? c2 : c1, plane_first ? o1 : o2, flags, contact, skip);
    if (closed != -2) return closed;
    const Res res = resolve(solid, plane_first ? c2 : c1, &r1);
    if (res == Res::kPlainConvex) {
      --g.stats.calls;  // ODE's answer, not dcol's
      return detail::collide_native(o1, o2, flags, contact, skip);
    }
    if (res != Res::kOk) {
      ++g.stats.rejected;
      return 0;
    }
    return collide_plane(o1, o2, r1, plane_first ? o1 : o2, flags, contact, skip);
  }
  const Res a = resolve(o1, c1, &r1);
  const Res b = a == Res::kPlainConvex ? Res::kPlainConvex : resolve(o2, c2, &r2);
  if (a == Res::kPlainConvex || b == Res::kPlainConvex) {
    --g.stats.calls;
    return detail::collide_native(o1, o2, flags, contact, skip);
  }
  if (a != Res::kOk || b != Res::kOk) {
    ++g.stats.rejected;
    return 0;
  }
  // Bounding balls apart: no contact (margin 0). A NaN centre fails this test and is left to dcol,
  // which rejects its pose.
  const double dx = r1.pose.position[0] - r2.pose.position[0];
  const double dy = r1.pose.position[1] - r2.pose.position[1];
  const double dz = r1.pose.position[2] - r2.pose.position[2];
  const double reach = r1.radius + r2.radius;
  if (dx * dx + dy * dy + dz * dz > reach * reach) return 0;
  // A pair that had no contacts at its last call (or is new) is first asked whether its shapes
  // overlap, scaled by 1 + 1e-6 (so that touching pairs, and the solver's tolerance band of 1e-9
  // around the threshold, still go to dcol_contacts): about 0.5 us where dcol_contacts takes
  // several (see docs/ode.md). A pair with contacts, or whose cache holds a separating normal,
  // goes straight to dcol_contacts_cached.
  PairHint &hint = pair_hint(o1, o2);
  if (!hint.had_contacts && !hint.apart_known) {
    std::int32_t below = 1;
    const dcol_status st = dcol_alpha_below(r1.shape, &r1.pose, r2.shape, &r2.pose, 1.0 + 1e-6, nullptr, &below);
    if (st == DCOL_OK && !below) return 0;
  }
  dcol_contact cs[DCOL_MAX_CONTACTS];
  std::size_t n = 0;
  const dcol_status st = dcol_contacts_cached(r1.shape, &r1.pose, r2.shape, &r2.pose, 0.0, nullptr, &hint.cache, cs,
                                              capacity(flags), &n);
  if (st != DCOL_OK && st != DCOL_ERROR_NOT_CONVERGED) {
    ++g.stats.rejected;
    return 0;
  }
  hint.had_contacts = n > 0;
  hint.apart_known = n == 0;
  return write_contacts(o1, o2, cs, n, true, contact, skip);
}

const int kClasses[5] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass};

// The dcol geom class: its collider for every class it meets (the others: none).
dColliderFn *user_class_collider(int num) {
  if (num == g.geom_class || num == dPlaneClass) return &collide;
  for (int c : kClasses)
    if (num == c) return &collide;
  return nullptr;
}

void user_class_aabb(dGeomID geom, dReal box[6]) {
  const dReal *p = dGeomGetPosition(geom);
  const double r = geom_data(geom)->radius;
  for (int i = 0; i < 3; ++i) {
    box[2 * i] = p[i] - r;
    box[2 * i + 1] = p[i] + r;
  }
}

void user_class_dtor(dGeomID) {}

}  // namespace

namespace detail {
Stats &counters() { return g.stats; }
}  // namespace detail

// ---------------------------------------------------------------------------------------------
// The public functions.

bool dcol_in_use() {
  // Whether dCollide of two overlapping spheres reaches the dcol collider (ODE has no getter for
  // its collider table); the probe leaves the counters as they were.
  const Stats saved = g.stats;
  dGeomID a = dCreateSphere(0, 1.0), b = dCreateSphere(0, 1.0);
  dGeomSetPosition(b, 0.5, 0, 0);
  dContactGeom c;
  dCollide(a, b, 1, &c, sizeof c);
  const bool used = g.stats.calls != saved.calls;
  dGeomDestroy(a);
  dGeomDestroy(b);
  g.stats = saved;
  return used;
}

void use_dcol() {
  if (dcol_in_use()) return;
  detail::find_native_colliders();
  for (int i = 0; i < 5; ++i) {
    for (int j = i; j < 5; ++j) dSetColliderOverride(kClasses[i], kClasses[j], &collide);
    dSetColliderOverride(kClasses[i], dPlaneClass, &collide);
  }
}

namespace {

// The convex hull of a convex's points (dcol_shape_new_convex_hull), about the geom's origin when
// it lies strictly inside them, else about their mean (strictly inside any full-dimensional hull):
// *shift is that centre in the geom's frame. nullptr when the points make no dcol hull (fewer than
// four not in a plane, non-finite values).
dcol_shape *convex_shape(const dReal *points, unsigned pointcount, double shift[3]) {
  shift[0] = shift[1] = shift[2] = 0;
  if (!points || pointcount == 0) return nullptr;
  std::vector<double> p(points, points + 3 * static_cast<std::size_t>(pointcount));
  dcol_shape *s = nullptr;
  if (dcol_shape_new_convex_hull(p.data(), pointcount, 0.0, &s) == DCOL_OK) return s;
  for (unsigned j = 0; j < pointcount; ++j)
    for (int k = 0; k < 3; ++k) shift[k] += p[3 * j + k] / pointcount;
  for (unsigned j = 0; j < pointcount; ++j)
    for (int k = 0; k < 3; ++k) p[3 * j + k] -= shift[k];
  if (dcol_shape_new_convex_hull(p.data(), pointcount, 0.0, &s) == DCOL_OK) return s;
  shift[0] = shift[1] = shift[2] = 0;
  return nullptr;
}

}  // namespace

dGeomID create_convex(dSpaceID space, const dReal *planes, unsigned planecount, const dReal *points,
                      unsigned pointcount, const unsigned *polygons) {
  dGeomID geom = dCreateConvex(space, planes, planecount, points, pointcount, polygons);
  ConvexRecord rec;
  rec.shape = convex_shape(points, pointcount, rec.shift);
  if (!rec.shape) {
    ++g.stats.unrecorded_convexes;
    return geom;
  }
  rec.points.assign(points, points + 3 * static_cast<std::size_t>(pointcount));
  for (unsigned j = 0; j < pointcount; ++j) {
    const double dx = points[3 * j] - rec.shift[0], dy = points[3 * j + 1] - rec.shift[1], dz = points[3 * j + 2] - rec.shift[2];
    rec.radius = std::max(rec.radius, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  // A record left by a destroyed geom at the same address is replaced.
  forget(geom);
  g.convexes.emplace(geom, std::move(rec));
  return geom;
}

bool is_recorded_convex(dGeomID geom) {
  if (dGeomGetClass(geom) != dConvexClass) return false;
  auto it = g.convexes.find(geom);
  return it != g.convexes.end() && check_record(geom, it->second);
}

void forget(dGeomID geom) {
  auto it = g.convexes.find(geom);
  if (it == g.convexes.end()) return;
  dcol_shape_free(it->second.shape);
  g.convexes.erase(it);
}

void release_all() { g.clear(); }

const dcol_shape *shape_of(dGeomID geom, dcol_pose *pose) {
  Resolved r;
  if (resolve(geom, dGeomGetClass(geom), &r) != Res::kOk) return nullptr;
  if (pose) *pose = r.pose;
  return r.shape;
}

Stats stats() { return g.stats; }

void reset_stats() { g.stats = Stats(); }

unsigned long collider_calls() { return g.stats.calls; }

int init() {
  if (g.geom_class < 0) {
    dGeomClass c;
    c.bytes = sizeof(GeomData);
    c.collider = &user_class_collider;
    c.aabb = &user_class_aabb;
    c.aabb_test = nullptr;
    c.dtor = &user_class_dtor;
    g.geom_class = dCreateGeomClass(&c);
  }
  return g.geom_class;
}

int geom_class() { return g.geom_class; }

dGeomID create_geom(dSpaceID space, const dcol_shape *shape, double radius) {
  dGeomID geom = dCreateGeom(init());
  GeomData *d = geom_data(geom);
  d->shape = shape;
  d->radius = radius;
  if (space) dSpaceAdd(space, geom);
  return geom;
}

const dcol_shape *geom_shape(dGeomID geom) { return geom_data(geom)->shape; }

}  // namespace dcol_ode
