// The dcol geom class (dcol_ode::create_geom: dcol shapes as ODE geoms) in ODE scenes, and the same
// scenes with ODE's native colliders, run by ctest. (The scenes with ODE's own geoms and
// dcol_ode::use_dcol() are ode_engine_scenes.cpp.)
//
//   ode_adapter_tests normal          the adapter's normal/depth convention against ODE's own sphere-box
//   ode_adapter_tests drop GROUND     six primitives dropped on a ground; GROUND = halfspace (a dcol
//                              half-space geom), box (a large dcol box), plane (ODE's dCreatePlane
//                              through the dcol collider, itself a half-space) or native
//                              (ODE's own shapes and colliders, for the four it has)
//   ode_adapter_tests stack KIND      five boxes stacked for 10 s; KIND = dcol or native
//   ode_adapter_tests tumble          30 boxes, cylinders and capsules dropped with random attitudes and
//                              spins come to rest on a face
//   ode_adapter_tests compare         the drop with dcol and with ODE's colliders (the four shapes ODE
//                              has): same rest heights, and the time per step of each
//   ode_adapter_tests drop GROUND --csv FILE   also write the heights over time
//
// Exit status 0 when every check holds. Every check prints its numbers.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "engine_scenes.hpp"

namespace {

using engine_scenes::check;
using engine_scenes::kDt;
using engine_scenes::kFloorDepth;
using engine_scenes::kG;
using engine_scenes::kTol;
using engine_scenes::make;
using engine_scenes::make_floor;
using engine_scenes::now;

struct World {
  dWorldID world;
  dSpaceID space;
  dJointGroupID contacts;
  int max_contacts = 8;
  World() {
    world = dWorldCreate();
    space = dSimpleSpaceCreate(0);
    contacts = dJointGroupCreate(0);
    dWorldSetGravity(world, 0, 0, -kG);
    dWorldSetERP(world, 0.2);
    dWorldSetCFM(world, 1e-7);
    dWorldSetContactSurfaceLayer(world, 0.0);
  }
  ~World() {
    dJointGroupDestroy(contacts);
    dSpaceDestroy(space);
    dWorldDestroy(world);
  }
  static void near(void *self, dGeomID o1, dGeomID o2) {
    World *w = static_cast<World *>(self);
    dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
    if (!b1 && !b2) return;
    dContact c[16];
    const int n = dCollide(o1, o2, w->max_contacts, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      c[i].surface.mode = dContactApprox1;
      c[i].surface.mu = 0.6;
      dJointID j = dJointCreateContact(w->world, w->contacts, &c[i]);
      dJointAttach(j, b1, b2);
    }
  }
  void step() {
    dSpaceCollide(space, this, &near);
    dWorldStep(world, kDt);
    dJointGroupEmpty(contacts);
  }
};

double energy(dBodyID b) {
  dMass m;
  dBodyGetMass(b, &m);
  const dReal *v = dBodyGetLinearVel(b);
  const dReal *w = dBodyGetAngularVel(b);
  const dReal *R = dBodyGetRotation(b);  // 3x4 row-major
  // Body-frame angular velocity: R^T w.
  double wb[3];
  for (int i = 0; i < 3; ++i) wb[i] = R[0 * 4 + i] * w[0] + R[1 * 4 + i] * w[1] + R[2 * 4 + i] * w[2];
  double rot = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rot += wb[i] * m.I[i * 4 + j] * wb[j];
  const double lin = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  return 0.5 * m.mass * lin + 0.5 * rot + m.mass * kG * dBodyGetPosition(b)[2];
}

struct Spec {
  const char *name;
  double rest;    // analytic rest height of the centre
  double radius;  // bounding radius
  bool native;    // ODE has this shape
};

// q rotating body x to world -z (a cone standing on its base) and x to z.
const dQuaternion kXDown = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};

struct Body {
  Spec spec;
  dBodyID body;
  dGeomID geom;
  dcol_shape *shape;
};

const Spec kSpecs[] = {
    {"sphere", 0.2, 0.2, true},
    {"box", 0.1, std::sqrt(0.04 + 0.0225 + 0.01), true},
    {"capsule", 0.1, 0.3, true},
    {"cylinder", 0.15, std::sqrt(0.0225 + 0.04), true},
    {"cone", 0.1, std::max(0.3, std::hypot(0.1, 0.4 * std::tan(0.5))), false},
    {"ellipsoid", 0.12, 0.25, false},
};

void set_mass(dBodyID b, const char *name) {
  dMass m;
  if (!std::strcmp(name, "sphere")) dMassSetSphereTotal(&m, 1.0, 0.2);
  else if (!std::strcmp(name, "box")) dMassSetBoxTotal(&m, 1.0, 0.4, 0.3, 0.2);
  else if (!std::strcmp(name, "capsule")) dMassSetCapsuleTotal(&m, 1.0, 1, 0.1, 0.4);
  else if (!std::strcmp(name, "cylinder")) dMassSetCylinderTotal(&m, 1.0, 1, 0.15, 0.4);
  else if (!std::strcmp(name, "cone")) dMassSetCylinderTotal(&m, 1.0, 1, 0.15, 0.4);
  else dMassSetBoxTotal(&m, 1.0, 0.5, 0.4, 0.24);
  dBodySetMass(b, &m);
}

// A native ODE geom for the shape (capsule and cylinder axes moved from ODE's z to body x).
dGeomID native_geom(dSpaceID space, const char *name) {
  const dQuaternion z_to_x = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};
  if (!std::strcmp(name, "sphere")) return dCreateSphere(space, 0.2);
  if (!std::strcmp(name, "box")) return dCreateBox(space, 0.4, 0.3, 0.2);
  if (!std::strcmp(name, "capsule")) {
    dGeomID g = dCreateCapsule(space, 0.1, 0.4);
    return g;
  }
  if (!std::strcmp(name, "cylinder")) return dCreateCylinder(space, 0.15, 0.4);
  (void)z_to_x;
  return nullptr;
}

int drop(const std::string &ground, const char *csv, bool only_native = false, std::vector<double> *heights = nullptr,
         double *step_time = nullptr) {
  World w;
  dcol_shape *ground_shape = nullptr;
  if (ground == "halfspace") {
    ground_shape = make_floor();
    dGeomID g = dcol_ode::create_geom(w.space, ground_shape, dInfinity);
    dGeomSetPosition(g, 0, 0, -kFloorDepth);
  } else if (ground == "box") {
    dcol_shape_new_box(5, 5, 0.5, &ground_shape);
    dGeomID g = dcol_ode::create_geom(w.space, ground_shape, std::sqrt(50.25));
    dGeomSetPosition(g, 0, 0, -0.5);
  } else if (ground == "plane") {
    dCreatePlane(w.space, 0, 0, 1, 0);
  } else if (ground == "native") {
    dGeomID g = dCreateBox(w.space, 10, 10, 1);
    dGeomSetPosition(g, 0, 0, -0.5);
  } else {
    std::printf("unknown ground %s\n", ground.c_str());
    return 2;
  }
  const bool native = ground == "native";
  std::vector<Body> bodies;
  double x = -5 * 0.9;
  for (const Spec &s : kSpecs) {
    x += 0.9 * 1.0;
    if ((native || only_native) && !s.native) continue;
    Body b{s, dBodyCreate(w.world), nullptr, nullptr};
    set_mass(b.body, s.name);
    if (native) {
      b.geom = native_geom(w.space, s.name);
      dGeomSetBody(b.geom, b.body);
      if (!std::strcmp(s.name, "capsule") || !std::strcmp(s.name, "cylinder")) {
        const dQuaternion z_to_x = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};
        dGeomSetOffsetQuaternion(b.geom, z_to_x);
      }
    } else {
      b.shape = make(s.name);
      b.geom = dcol_ode::create_geom(w.space, b.shape, s.radius);
      dGeomSetBody(b.geom, b.body);
    }
    dBodySetPosition(b.body, x, 0, s.rest + 0.3);
    // Flat-bottomed bodies land tilted by 0.05 rad (on an edge or a rim first) and must
    // settle flat; round ones land straight.
    const double tilt = 0.025;  // half angle
    const dQuaternion tilted = {std::cos(tilt), std::sin(tilt), 0, 0};  // about world x
    if (!std::strcmp(s.name, "cone")) {
      dQuaternion q;
      dQMultiply0(q, tilted, kXDown);
      dBodySetQuaternion(b.body, q);
    } else if (!std::strcmp(s.name, "box") || !std::strcmp(s.name, "cylinder") || !std::strcmp(s.name, "capsule")) {
      const dQuaternion about_y = {std::cos(tilt), 0, std::sin(tilt), 0};
      dBodySetQuaternion(b.body, !std::strcmp(s.name, "box") ? tilted : about_y);
    }
    bodies.push_back(b);
  }
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) {
    std::fprintf(out, "t");
    for (const Body &b : bodies) std::fprintf(out, ",%s", b.spec.name);
    std::fprintf(out, "\n");
  }
  const int steps = 800;  // 4 s
  const int settle = 400;  // 2 s
  std::vector<double> e0(bodies.size()), emax(bodies.size(), -1e300), zmin(bodies.size(), 1e300);
  double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    if (out && k % 2 == 0) {
      std::fprintf(out, "%.4f", k * kDt);
      for (const Body &b : bodies) std::fprintf(out, ",%.6f", dBodyGetPosition(b.body)[2]);
      std::fprintf(out, "\n");
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      if (k == settle) e0[i] = energy(bodies[i].body);
      if (k > settle) {
        emax[i] = std::max(emax[i], energy(bodies[i].body));
        zmin[i] = std::min(zmin[i], dBodyGetPosition(bodies[i].body)[2]);
      }
    }
  }
  const double per_step = (now() - t0) / steps;
  if (out) std::fclose(out);
  std::printf("drop on %s ground (%s colliders): %.1f us per step (%zu bodies, dt %.3f s)\n", ground.c_str(),
              native ? "native ODE" : "dcol", per_step * 1e6, bodies.size(), kDt);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body &b = bodies[i];
    const double z = dBodyGetPosition(b.body)[2];
    const double sink = b.spec.rest - zmin[i];
    const double gain = emax[i] - e0[i];
    std::printf("  %-9s rest %.6f m (analytic %.4f, error %+.2e m), sink after 2 s %+.2e m, energy gain %+.2e J\n",
                b.spec.name, z, b.spec.rest, z - b.spec.rest, sink, gain);
    char what[128];
    std::snprintf(what, sizeof what, "%s rest height within 1 mm", b.spec.name);
    check(std::fabs(z - b.spec.rest) <= kTol, what);
    // The sink and energy checks are the adapter's; for the engine's own colliders they are
    // reported only (the comparison is on rest heights).
    std::snprintf(what, sizeof what, "%s sinks less than 1 mm", b.spec.name);
    if (!native) check(sink <= kTol, what);
    std::snprintf(what, sizeof what, "%s gains no energy after settling", b.spec.name);
    if (!native) check(gain <= 1e-4 * kG, what);  // at most the energy of a 0.1 mm rise of 1 kg
    if (heights) heights->push_back(z);
  }
  if (step_time) *step_time = per_step;
  for (Body &b : bodies) {
    dGeomDestroy(b.geom);
    dBodyDestroy(b.body);
    dcol_shape_free(b.shape);
  }
  dcol_shape_free(ground_shape);
  return 0;
}

int stack(const std::string &kind) {
  World w;
  const bool native = kind == "native";
  dcol_shape *ground = nullptr, *cube = nullptr;
  const double h = 0.25;
  if (native) {
    dGeomID g = dCreateBox(w.space, 10, 10, 1);
    dGeomSetPosition(g, 0, 0, -0.5);
  } else {
    ground = make_floor();
    dcol_shape_new_box(h, h, h, &cube);
    dGeomID g = dcol_ode::create_geom(w.space, ground, dInfinity);
    dGeomSetPosition(g, 0, 0, -kFloorDepth);
  }
  std::vector<dBodyID> boxes;
  for (int i = 0; i < 5; ++i) {
    dBodyID b = dBodyCreate(w.world);
    dMass m;
    dMassSetBoxTotal(&m, 1.0, 2 * h, 2 * h, 2 * h);
    dBodySetMass(b, &m);
    dGeomID g = native ? dCreateBox(w.space, 2 * h, 2 * h, 2 * h) : dcol_ode::create_geom(w.space, cube, h * std::sqrt(3.0));
    dGeomSetBody(g, b);
    dBodySetPosition(b, 0.002 * i, 0, h + i * (2 * h + 0.001));
    boxes.push_back(b);
  }
  const int steps = static_cast<int>(10.0 / kDt);
  const double t0 = now();
  for (int k = 0; k < steps; ++k) w.step();
  const double per_step = (now() - t0) / steps;
  std::printf("stack of five boxes (%s colliders), 10 s: %.1f us per step\n", native ? "native ODE" : "dcol",
              per_step * 1e6);
  for (int i = 0; i < 5; ++i) {
    const dReal *p = dBodyGetPosition(boxes[i]);
    const double want = h + i * 2 * h;
    std::printf("  box %d: z %.6f (analytic %.4f, error %+.2e), x %+.2e, y %+.2e\n", i, p[2], want, p[2] - want,
                p[0] - 0.002 * i, p[1]);
    char what[96];
    std::snprintf(what, sizeof what, "box %d of the stack within 1 mm of its height", i);
    check(std::fabs(p[2] - want) <= kTol, what);
    std::snprintf(what, sizeof what, "box %d of the stack did not slide more than 1 cm", i);
    check(std::hypot(p[0] - 0.002 * i, p[1]) <= 0.01, what);
  }
  dcol_shape_free(ground);
  dcol_shape_free(cube);
  return 0;
}

// The adapter's contacts against ODE's native sphere-box collider: same normal (into o1), same
// depth, in both orders.
int normal_convention() {
  dcol_shape *ball = nullptr, *box = nullptr;
  dcol_shape_new_sphere(0.5, &ball);
  dcol_shape_new_box(1, 1, 1, &box);
  dGeomID s = dcol_ode::create_geom(0, ball, 0.5);
  dGeomID b = dcol_ode::create_geom(0, box, std::sqrt(3.0));
  dGeomID ns = dCreateSphere(0, 0.5);
  dGeomID nb = dCreateBox(0, 2, 2, 2);
  dGeomSetPosition(s, 0.1, 0.2, 1.45);
  dGeomSetPosition(ns, 0.1, 0.2, 1.45);
  dGeomSetPosition(b, 0, 0, 0);
  dGeomSetPosition(nb, 0, 0, 0);
  dContactGeom ours[4], theirs[4];
  const dGeomID pairs[2][4] = {{s, b, ns, nb}, {b, s, nb, ns}};
  for (const auto &p : pairs) {
    const int n1 = dCollide(p[0], p[1], 4, ours, sizeof(dContactGeom));
    const int n2 = dCollide(p[2], p[3], 4, theirs, sizeof(dContactGeom));
    std::printf("normal convention: dcol n %d normal (%.6f %.6f %.6f) depth %.6f; ODE n %d normal (%.6f %.6f %.6f) depth %.6f\n",
                n1, ours[0].normal[0], ours[0].normal[1], ours[0].normal[2], ours[0].depth, n2,
                theirs[0].normal[0], theirs[0].normal[1], theirs[0].normal[2], theirs[0].depth);
    check(n1 == 1 && n2 >= 1, "one contact each");
    double dn = 0;
    for (int k = 0; k < 3; ++k) dn += std::fabs(ours[0].normal[k] - theirs[0].normal[k]);
    check(dn < 1e-9, "same normal as ODE's collider");
    check(std::fabs(ours[0].depth - theirs[0].depth) < 1e-9, "same depth as ODE's collider");
    check(ours[0].g1 == p[0] && ours[0].g2 == p[1], "g1, g2 in the order asked");
  }
  // Against ODE's plane through the dcol collider.
  dGeomID plane = dCreatePlane(0, 0, 0, 1, 1.0);
  dGeomID nplane_ball = dCreateSphere(0, 0.5);
  dGeomSetPosition(nplane_ball, 0.1, 0.2, 1.45);
  const int n1 = dCollide(s, plane, 4, ours, sizeof(dContactGeom));
  const int n2 = dCollide(nplane_ball, plane, 4, theirs, sizeof(dContactGeom));
  std::printf("plane: dcol n %d normal (%.6f %.6f %.6f) depth %.6f; ODE n %d normal (%.6f %.6f %.6f) depth %.6f\n", n1,
              ours[0].normal[0], ours[0].normal[1], ours[0].normal[2], ours[0].depth, n2, theirs[0].normal[0],
              theirs[0].normal[1], theirs[0].normal[2], theirs[0].depth);
  check(n1 == 1 && n2 == 1 && std::fabs(ours[0].normal[2] - theirs[0].normal[2]) < 1e-9 &&
            std::fabs(ours[0].depth - theirs[0].depth) < 1e-9,
        "plane contact as ODE's");
  dGeomDestroy(plane);
  dGeomDestroy(nplane_ball);
  dGeomDestroy(s);
  dGeomDestroy(b);
  dGeomDestroy(ns);
  dGeomDestroy(nb);
  dcol_shape_free(ball);
  dcol_shape_free(box);
  return 0;
}

// The drop on the floor (a dcol half-space; ODE's: a box) with dcol and with ODE's own colliders, for the four shapes ODE has:
// the same rest heights (within 1 mm), and the time per step of each.
int compare() {
  std::vector<double> ours, theirs;
  double t_ours = 0, t_theirs = 0;
  drop("halfspace", nullptr, true, &ours, &t_ours);
  drop("native", nullptr, true, &theirs, &t_theirs);
  check(ours.size() == theirs.size(), "same bodies");
  for (std::size_t i = 0; i < ours.size() && i < theirs.size(); ++i) {
    std::printf("  rest height dcol %.6f, native %.6f, difference %+.2e m\n", ours[i], theirs[i], ours[i] - theirs[i]);
    check(std::fabs(ours[i] - theirs[i]) <= kTol, "dcol and native rest heights within 1 mm");
  }
  std::printf("time per step (4 bodies on the floor): dcol %.1f us, native %.1f us (ratio %.1f)\n", t_ours * 1e6,
              t_theirs * 1e6, t_ours / t_theirs);
  return 0;
}

// Boxes, cylinders and capsules dropped with random attitudes and spins, apart from each other:
// after 6 s each is at rest on a face (box: one of its half extents; cylinder: its radius or
// half length; capsule: its radius), within 1 mm. Exercises corner, edge and rim contacts.
int tumble() {
  World w;
  dcol_shape *ground = make_floor();
  dGeomID g = dcol_ode::create_geom(w.space, ground, dInfinity);
  dGeomSetPosition(g, 0, 0, -kFloorDepth);
  dcol_shape *box = nullptr, *cyl = nullptr, *cap = nullptr;
  dcol_shape_new_box(0.2, 0.15, 0.1, &box);
  dcol_shape_new_cylinder(0.15, 0.4, &cyl);
  dcol_shape_new_capsule(0.1, 0.4, &cap);
  unsigned long long state = 12345;
  auto unif = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  struct Item {
    int kind;
    dBodyID body;
  };
  std::vector<Item> items;
  for (int i = 0; i < 30; ++i) {
    const int kind = i % 3;
    dBodyID b = dBodyCreate(w.world);
    set_mass(b, kind == 0 ? "box" : kind == 1 ? "cylinder" : "capsule");
    dGeomID geom = dcol_ode::create_geom(w.space, kind == 0 ? box : kind == 1 ? cyl : cap,
                                         kind == 0 ? std::sqrt(0.0725) : kind == 1 ? 0.25 : 0.3);
    dGeomSetBody(geom, b);
    dBodySetPosition(b, -12 + 1.5 * (i % 10) + 0.3 * unif(), -3 + 2.0 * (i / 10), 0.5 + unif());
    dQuaternion q = {unif() - 0.5, unif() - 0.5, unif() - 0.5, unif() - 0.5};
    dNormalize4(q);
    dBodySetQuaternion(b, q);
    dBodySetAngularVel(b, 4 * (unif() - 0.5), 4 * (unif() - 0.5), 4 * (unif() - 0.5));
    items.push_back({kind, b});
  }
  for (int k = 0; k < static_cast<int>(6.0 / kDt); ++k) w.step();
  int bad = 0;
  double worst = 0;
  for (const Item &it : items) {
    const double z = dBodyGetPosition(it.body)[2];
    const dReal *v = dBodyGetLinearVel(it.body);
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    static const double rests[3][3] = {{0.2, 0.15, 0.1}, {0.15, 0.2, 0.15}, {0.1, 0.1, 0.1}};
    double err = 1e300;
    for (double r : rests[it.kind]) err = std::min(err, std::fabs(z - r));
    worst = std::max(worst, err);
    // Round bodies may still roll: only their height is checked.
    if (err > kTol || (it.kind == 0 && speed > 1e-3)) {
      ++bad;
      std::printf("  body of kind %d: z %.6f (error %.2e), speed %.2e\n", it.kind, z, err, speed);
    }
  }
  std::printf("tumble: 30 bodies (boxes, cylinders, capsules) at rest on a face, worst height error %.2e m\n",
              worst);
  check(bad == 0, "every tumbled body rests on a face within 1 mm");
  dcol_shape_free(ground);
  dcol_shape_free(box);
  dcol_shape_free(cyl);
  dcol_shape_free(cap);
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::printf("usage: %s normal | drop halfspace|box|plane|native [--csv FILE] | stack dcol|native\n", argv[0]);
    return 2;
  }
  dInitODE2(0);
  dcol_ode::init();
  const std::string what = argv[1];
  const char *csv = nullptr;
  if (argc >= 5 && !std::strcmp(argv[3], "--csv")) csv = argv[4];
  int rc = 2;
  if (what == "normal") rc = normal_convention();
  if (what == "drop" && argc >= 3) rc = drop(argv[2], csv);
  if (what == "stack" && argc >= 3) rc = stack(argv[2]);
  if (what == "compare") rc = compare();
  if (what == "tumble") rc = tumble();
  dCloseODE();
  if (rc != 0) return rc;
  std::printf("%s\n", engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
