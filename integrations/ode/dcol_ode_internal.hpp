// What dcol_ode.cpp and dcol_ode_native.cpp share (not installed).
#ifndef DCOL_ODE_INTERNAL_HPP
#define DCOL_ODE_INTERNAL_HPP

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "dcol_ode.hpp"

namespace dcol_ode {
namespace detail {

// The keys and hashes of dcol_ode.cpp's shape and pair tables.

enum Kind { kSphere, kBox, kCapsule, kCylinder };

// A primitive's dcol shape is keyed by its kind and parameters (as ODE reports them), so geoms of
// the same size share one shape, a geom whose sizes change (dGeomBoxSetLengths) finds the shape of
// its new sizes, and no record has to follow a geom's lifetime.
struct Key {
  int kind;
  double a, b;
  double c;
  bool operator==(const Key &o) const { return kind == o.kind && a == o.a && b == o.b && c == o.c; }
};

struct KeyHash {
  std::size_t operator()(const Key &k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.kind) * 0x9E3779B97F4A7C15ull;
    const double v[3] = {k.a, k.b, k.c};
    for (double x : v) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h ^= bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

struct PairHash {
  std::size_t operator()(const std::pair<dGeomID, dGeomID> &p) const {
    const std::uint64_t a = reinterpret_cast<std::uintptr_t>(p.first), b = reinterpret_cast<std::uintptr_t>(p.second);
    return static_cast<std::size_t>((a * 0x9E3779B97F4A7C15ull) ^ (b + 0x632BE59BD9B4E019ull + (a << 6) + (a >> 2)));
  }
};

/// The counters behind stats() (one set per process).
Stats &counters();

/// Finds ODE's own collider function for a plain convex against each of the five other classes
/// and the plane. Must run while ODE's own colliders are still in its table (before the
/// overrides); calling it again replaces what was found.
void find_native_colliders();

/// Collides a pair of which at least one geom is a plain dConvex (not recorded by create_convex)
/// with ODE's own collider found by find_native_colliders(): the contacts as dCollide(o1, o2)
/// would have written them before use_dcol(). Returns 0 and counts the pair in native_missing
/// when no such collider was found.
int collide_native(dGeomID o1, dGeomID o2, int flags, dContactGeom *contact, int skip);

}  // namespace detail
}  // namespace dcol_ode

#endif
