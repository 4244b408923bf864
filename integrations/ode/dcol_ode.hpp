// dcol_ode.hpp: dcol as the narrow phase of ODE (the Open Dynamics Engine, 0.16, double precision).
//
// The one call: after dInitODE2, dcol answers every dCollide between ODE's own convex geoms.
//
//   dInitODE2(0);
//   dcol_ode::use_dcol();        // dSphere, dBox, dCapsule, dCylinder, dConvex (see below), dPlane
//   ... build and step the world as usual (dCreateBox, dSpaceCollide, dCollide, ...) ...
//
// use_dcol() installs one collider with dSetColliderOverride for every pair among dSphereClass,
// dBoxClass, dCapsuleClass, dCylinderClass and dConvexClass, and each of them against
// dPlaneClass. The collider reads each geom's own parameters (dGeomSphereGetRadius,
// dGeomBoxGetLengths, dGeomCapsuleGetParams, dGeomCylinderGetParams, dGeomPlaneGetParams) and its
// world pose (dGeomGetPosition, dGeomGetQuaternion: the body's pose composed with the geom's
// offset), maps ODE's capsules and cylinders (axis z) onto dcol's (axis x), and writes the
// contacts of dcol_contacts with margin 0: at most min(flags & 0xffff, DCOL_MAX_CONTACTS) of them,
// `skip` bytes apart. The overrides stay until dCloseODE (ODE keeps one collider table per
// process; dInitODE2 after dCloseODE restores ODE's own colliders, and use_dcol() may be called
// again).
//
// Convexes: ODE has no getter for a dConvex's points, so only convexes made by
// dcol_ode::create_convex (same arguments as dCreateConvex) go to dcol, as the convex hull of
// their points. Convexes made by a plain dCreateConvex keep ODE's own collider functions (found
// in libode by use_dcol(), see docs/ode.md).
//
// Conventions (ODE user guide, "Contact points"): dContactGeom.normal points *into* geom g1
// (moving g1 by depth along it separates the pair), depth > 0 means penetration, pos is dcol's
// contact position (midway between the two surfaces), side1 = side2 = -1.
//
// A pair dcol cannot take (a geom with non-finite or non-positive sizes, a non-finite pose from an
// exploding simulation, a failed query) gets no contacts; it is counted in stats().rejected and
// nothing is printed.
//
// Threads: the adapter's caches are not locked; collide from one thread at a time (as ODE's
// collider table is one per process).
//
// Also here, unchanged from the first adapter: a user geom class wrapping any dcol shape
// (init, create_geom), for dcol's shapes that ODE lacks (cones, ellipsoids, padded polygons,
// half-spaces). Its geoms collide with each other, with ODE's plane and, through the same
// collider, with ODE's sphere, box, capsule, cylinder and recorded convexes.
#ifndef DCOL_ODE_HPP
#define DCOL_ODE_HPP

#include <ode/ode.h>

#include "dcol.h"

namespace dcol_ode {

// ---------------------------------------------------------------------------------------------
// dcol as ODE's narrow phase for ODE's own geoms

/// Installs dcol as the collider of every pair among dSphereClass, dBoxClass, dCapsuleClass,
/// dCylinderClass and dConvexClass, and of each of them against dPlaneClass (call it after
/// dInitODE2; calling it again is harmless). Before overriding, it finds ODE's own collider for
/// each pair with a plain convex, so that those keep ODE's answers.
void use_dcol();

/// Whether use_dcol()'s colliders are installed in ODE's collider table now (false after
/// dCloseODE and a new dInitODE2, until use_dcol() is called again).
bool dcol_in_use();

/// dCreateConvex(space, planes, planecount, points, pointcount, polygons), and records the
/// points so that collisions of this geom go to dcol (as the convex hull of the points, which must
/// not all lie in a plane). As with dCreateConvex, the arrays must outlive the geom (ODE keeps the
/// pointers); the adapter keeps its own copy of the points.
///
/// The record belongs to the geom for as long as the geom lives. ODE tells nobody when a geom is
/// destroyed, so the collider checks a record against ODE's own bounding box of the geom (the box
/// of the recorded points at the geom's pose) whenever the geom has moved: a record whose geom
/// was destroyed (its address reused by another convex) or changed by dGeomSetConvex is dropped,
/// and that geom goes to ODE's own collider. Call forget(geom) when destroying such a geom to
/// free the record at once (release_all() frees every record).
///
/// Returns the geom (never 0). If the points cannot make a dcol hull (fewer than four points not
/// in a plane, non-finite values), the geom is still made but not recorded: it stays with ODE's
/// collider, and stats().unrecorded_convexes counts it.
dGeomID create_convex(dSpaceID space, const dReal *planes, unsigned planecount, const dReal *points,
                      unsigned pointcount, const unsigned *polygons);

/// Whether `geom` is a convex recorded by create_convex (its collisions go to dcol).
bool is_recorded_convex(dGeomID geom);

/// Drops what the adapter keeps for `geom` (a convex record); the geom itself is not touched and
/// may already be destroyed.
void forget(dGeomID geom);

/// Frees every cached dcol shape and every convex record (for instance before dCloseODE). Shapes
/// are made again on demand; convexes forgotten this way go to ODE's own collider.
void release_all();

/// The dcol shape and world pose that stand for an ODE geom (sphere, box, capsule, cylinder,
/// recorded convex, or a dcol geom): nullptr if the geom has none (another class, invalid sizes).
/// The shape belongs to the adapter and lives until release_all() (or the geom's parameters
/// change). Planes are not shapes (they are half-spaces, see docs/ode.md).
const dcol_shape *shape_of(dGeomID geom, dcol_pose *pose);

/// Counters since the start (or reset_stats()).
struct Stats {
  unsigned long calls;                ///< calls of the dcol collider (every pair it answered or rejected)
  unsigned long contacts;             ///< contacts it wrote
  unsigned long rejected;             ///< pairs dcol could not take: no contacts written
  unsigned long native_calls;         ///< pairs with a plain (unrecorded) convex handed to ODE's collider
  unsigned long native_missing;       ///< such pairs for which ODE's collider was not found: no contacts
  unsigned long unrecorded_convexes;  ///< create_convex calls whose points made no dcol hull
  unsigned long dropped_records;      ///< convex records dropped because their geom no longer matched
};
Stats stats();
void reset_stats();

/// Calls of the dcol collider so far (stats().calls).
unsigned long collider_calls();

// ---------------------------------------------------------------------------------------------
// The dcol geom class: any dcol shape as an ODE geom

/// Registers the geom class (idempotent; once per process, after dInitODE2) and returns its class
/// number.
int init();

/// The class number (init() must have been called).
int geom_class();

/// A new dcol geom in `space` (may be 0) wrapping `shape`, with bounding radius `radius` (the
/// radius of an origin-centred ball containing the shape: its AABB is the cube around it; pass
/// INFINITY for a half-space, which then overlaps every geom's AABB). The geom does not own the
/// shape: keep it alive as long as the geom.
dGeomID create_geom(dSpaceID space, const dcol_shape *shape, double radius);

/// The shape a dcol geom wraps.
const dcol_shape *geom_shape(dGeomID geom);

}  // namespace dcol_ode

#endif
