// dcol_ode.hpp: dcol shapes as ODE geoms (a user geom class made with dCreateGeomClass).
//
//   dcol_ode::init();                                  // once, after dInitODE2
//   dGeomID g = dcol_ode::create_geom(space, shape, bounding_radius);
//   dGeomSetBody(g, body);                             // then use it like any ODE geom
//
// The class's collider answers dCollide for a dcol geom against another dcol geom and against
// ODE's own plane (dCreatePlane, as a dcol half-space: dcol_shape_new_halfspace). A floor may also
// be a dcol geom wrapping a half-space itself (radius INFINITY: its AABB is all of space). Contacts
// come from dcol_contacts with margin 0 (the points where the shapes overlap or touch), at most
// min(flags & 0xffff, DCOL_MAX_CONTACTS) of them.
//
// Conventions (ODE user guide, "Contact points"): ODE's dContactGeom.normal points *into* geom o1
// (moving o1 by depth along the normal separates the pair) and depth > 0 means penetration.
// dcol's normal points from shape 1 to shape 2, so with shape 1 = o1 the collider writes
// normal = -dcol normal and depth = dcol depth (> 0 penetrating). pos is dcol's contact position,
// midway between the two surfaces.
//
// The geom holds a pointer to the dcol shape and does not own it (the shape must outlive the
// geom); shapes are immutable, so one shape may back many geoms.
#ifndef DCOL_ODE_HPP
#define DCOL_ODE_HPP

#include <ode/ode.h>

#include "dcol.h"

namespace dcol_ode {

/// Registers the geom class (idempotent) and returns its class number.
int init();

/// The class number (init() must have been called).
int geom_class();

/// A new dcol geom in `space` (may be 0) wrapping `shape`, with bounding radius `radius` (the
/// radius of an origin-centred ball containing the shape: its AABB is the cube around it; pass
/// INFINITY for a half-space, which then overlaps every geom's AABB).
dGeomID create_geom(dSpaceID space, const dcol_shape *shape, double radius);

/// The shape a dcol geom wraps.
const dcol_shape *geom_shape(dGeomID geom);

/// Calls to the collider so far and the contacts they wrote (for statistics).
unsigned long collider_calls();

}  // namespace dcol_ode

#endif
