// Scenes written with ODE's own geoms only (dCreateBox, dCreateSphere, dCreateCapsule,
// dCreateCylinder, dCreateConvex, dCreatePlane), the same for ODE's narrow phase and for dcol's
// (dcol_ode::use_dcol() called before building them): a pyramid of boxes, a pile of mixed bodies in
// a walled bin, bodies on a 30 degree slope. Shared by the scene tests (ode_engine_scenes.cpp) and
// the benchmark (benches/engines/ode).
#ifndef DCOL_ODE_SCENES_HPP
#define DCOL_ODE_SCENES_HPP

#include <ode/ode.h>

#include <string>
#include <vector>

#include "dcol.h"

namespace ode_scenes {

/// The stepping parameters, the same for both narrow phases (see docs/ode.md for the values).
struct Settings {
  double dt = 0.005;           ///< time step (s)
  int iterations = 50;         ///< dWorldQuickStep iterations
  double erp = 0.2;            ///< dWorldSetERP
  double cfm = 1e-5;           ///< dWorldSetCFM
  int max_contacts = 4;        ///< contacts asked of each dCollide
  double mu = 0.6;             ///< Coulomb friction (dContactApprox1)
  double linear_damping = 0;   ///< dWorldSetLinearDamping
  double angular_damping = 0;  ///< dWorldSetAngularDamping
};

/// The parameters of each scene (identical for both narrow phases).
Settings pyramid_settings();
Settings pile_settings();
Settings slope_settings(double mu);

/// A convex hull as ODE's dCreateConvex wants it (planes a, b, c, d with the normal out; points;
/// polygons as counts followed by counter-clockwise indices), about the origin.
struct Hull {
  std::string name;
  std::vector<dReal> planes;
  std::vector<dReal> points;
  std::vector<unsigned> polygons;
  unsigned plane_count = 0;
  unsigned point_count() const { return static_cast<unsigned>(points.size() / 3); }
  double volume = 0;  ///< for the mass
};

/// An n-gon prism of radius r and height h along z (2n points).
Hull prism(int n, double r, double h);
/// An n-gon pyramid (a cone's hull): base radius r, height h along z, centroid at the origin (n + 1 points).
Hull pyramid(int n, double r, double h);
/// An n-gon bipyramid: equator radius r, tips at +-h on z (n + 2 points).
Hull bipyramid(int n, double r, double h);

enum Kind { kSphere, kBox, kCapsule, kCylinder, kHull };

/// A body and its geom, with the sizes the scene gave it (for checks made without the adapter).
struct Body {
  Kind kind;
  dBodyID body;
  dGeomID geom;
  double size[3];     ///< sphere: r; box: full lengths; capsule, cylinder: r, length (along z)
  const Hull *hull;   ///< kHull
  double start[3];    ///< initial position
};

/// Narrow-phase statistics of the near callback (calls and contacts always; the times and the
/// per-pair counts when World::time_narrow is set).
struct Narrow {
  unsigned long calls = 0;       ///< dCollide calls
  unsigned long contacts = 0;    ///< contacts they returned
  double seconds = 0;            ///< their total time
  std::vector<double> samples;   ///< each call's time (s), when keep_samples
  // Per pair of classes (the lower class number first), calls and seconds.
  unsigned long pair_calls[16][16] = {};
  unsigned long pair_empty[16][16] = {};  ///< calls that returned no contact
  double pair_seconds[16][16] = {};
};

/// An ODE world, a hash space and a contact group, stepped with dWorldQuickStep.
class World {
 public:
  explicit World(const Settings &s);
  ~World();
  World(const World &) = delete;
  World &operator=(const World &) = delete;

  /// One step: dSpaceCollide (the near callback calls dCollide, timed when time_narrow), contact
  /// joints with Coulomb friction mu (dContactApprox1), dWorldQuickStep.
  void step();

  /// A dynamic body of the given kind (hull: made with dcol_ode::create_convex when `recorded`,
  /// else dCreateConvex), density 500 kg/m^3.
  Body &add(Kind kind, const double size[3], const Hull *hull, const double pos[3], const dQuaternion q, bool recorded);

  Settings settings;
  dWorldID world;
  dSpaceID space;
  dJointGroupID group;
  std::vector<Body> bodies;
  bool time_narrow = false;
  bool keep_samples = false;
  Narrow narrow;

 private:
  static void near(void *self, dGeomID o1, dGeomID o2);
};

/// The pyramid: 55 boxes (0.2 m cubes) in 10 layers on ODE's plane z = 0, each box on two below.
void build_pyramid(World &w, bool recorded_hulls);
/// The pile: 48 bodies (spheres, boxes, capsules, cylinders and hulls of 12 to 200 points) with
/// random attitudes, dropped from up to 1 m into a bin (floor and walls: ODE's planes z = 0 and
/// x, y = +-kBinInner / 2).
void build_pile(World &w, unsigned seed, bool recorded_hulls);
const double kBinInner = 0.9;

/// The hulls of the pile (each with 12 to 200 points).
const std::vector<Hull> &pile_hulls();

/// The dcol shape and pose of a body, made by the scene from its own sizes (not through the
/// adapter), for the depth checks; the shape is the caller's to free.
dcol_shape *check_shape(const Body &b, dcol_pose *pose);

}  // namespace ode_scenes

#endif
