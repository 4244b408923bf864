// What the adapter's files share (not installed): the mapping of a Bullet shape to a dcol shape
// and the cache of those mappings (shapes.cpp), used by the algorithm (algorithm.cpp).
#ifndef DCOL_BULLET_INTERNAL_HPP
#define DCOL_BULLET_INTERNAL_HPP

#include <atomic>
#include <memory>

#include "dcol_bullet.hpp"

namespace dcol_bullet {
namespace detail {

/// The parameters that define a Bullet shape's geometry: equal keys, equal dcol shapes.
struct Key {
  const btCollisionShape *shape = nullptr;
  int type = -1;
  int ints[2] = {0, 0};  // up axis; number of hull points
  const void *ptr = nullptr;  // a hull's point array, a dcol_bullet::Shape's dcol shape
  btScalar f[8] = {0, 0, 0, 0, 0, 0, 0, 0};  // dimensions, local scaling, margin
  bool operator==(const Key &o) const;
};

/// The key of `shape` as it is now.
Key key_of(const btCollisionShape *shape);

/// A Bullet shape mapped to dcol: the dcol shape and where its body frame sits in the Bullet
/// shape's frame (a rotation for capsules, cylinders and cones along y or z, an offset for cones
/// and hulls built about their points' mean), and the margin Bullet grows it by (cylinders and
/// cones: the dcol shape is Bullet's core, and the adapter adds the margin to the contacts).
struct Entry {
  Key key;
  const dcol_shape *shape = nullptr;  // nullptr: dcol cannot take this shape
  dcol_shape *owned = nullptr;        // freed with the entry (a dcol_bullet::Shape's is borrowed)
  bool has_offset = false;            // false: the dcol frame is the Bullet shape's frame
  double pos[3] = {0, 0, 0};          // dcol origin in the Bullet shape frame
  double quat[4] = {1, 0, 0, 0};      // dcol frame in the Bullet shape frame (w, x, y, z)
  // The Bullet shape's geometry in its own frame, for the support function (support()): kind is
  // its type; dims: sphere (R), box (hx, hy, hz), capsule (half length, R), cylinder and cone
  // (half length or height, R, pad), hull (the half extents of the box around its points, whose
  // centre is `centre`, and `margin`); axis: a capsule's, cylinder's or cone's up axis.
  int kind = -1;
  int axis = 0;
  double dims[3] = {0, 0, 0};
  double centre[3] = {0, 0, 0};
  double margin = 0;
  double pad = 0;                     // the Bullet shape is the dcol shape grown by this ball
  double radius = 0;                  // bounding radius about the Bullet shape's origin (pad included)
  Entry() = default;
  Entry(const Entry &) = delete;
  Entry &operator=(const Entry &) = delete;
  ~Entry();
};

/// The cached entry for `shape` (built on a miss or when the shape changed); never null (the
/// entry's `shape` is null when dcol cannot take the Bullet shape). Thread-safe.
std::shared_ptr<const Entry> lookup(const btCollisionShape *shape);

/// Bumped by forget(): an algorithm re-looks its shapes up when it changes.
extern std::atomic<unsigned> g_epoch;

/// Counters (Stats).
struct Counters {
  std::atomic<unsigned long> calls{0}, early_outs{0}, apart{0}, reused{0}, fallback_pairs{0}, fallback_calls{0}, invalid_poses{0}, not_converged{0},
      errors{0}, shapes_built{0};
};
Counters &counters();

/// The support value max { u . x } of the entry's Bullet shape (padding included) over its points x
/// in its own frame, for a unit direction u of that frame (a bound from above for shapes it does
/// not know: the bounding radius).
double support(const Entry &e, const double u[3]);

/// World pose of an entry's dcol frame for a Bullet shape at `t`.
dcol_pose world_pose(const Entry &e, const btTransform &t);

/// Whether a shape type is one the algorithm maps (the convex types of use_dcol).
bool mapped_type(int type);

}  // namespace detail
}  // namespace dcol_bullet

#endif
