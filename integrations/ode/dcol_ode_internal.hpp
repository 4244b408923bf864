// What dcol_ode.cpp and dcol_ode_native.cpp share (not installed).
#ifndef DCOL_ODE_INTERNAL_HPP
#define DCOL_ODE_INTERNAL_HPP

#include "dcol_ode.hpp"

namespace dcol_ode {
namespace detail {

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
