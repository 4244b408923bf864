// Bullet scenes with dcol shapes (dcol_bullet::Shape, register_algorithms) and the same scenes with
// Bullet's native shapes and colliders, run by ctest (the adapter's tests from before use_dcol).
//
//   bullet_scenes normal          the algorithm's normal/depth convention against Bullet's own
//                                 sphere-box algorithm
//   bullet_scenes drop GROUND     six primitives dropped on a ground; GROUND = halfspace (a dcol
//                                 half-space), box (a large dcol box), plane (Bullet's
//                                 btStaticPlaneShape through the dcol algorithm, itself a
//                                 half-space) or
//                                 native (Bullet's own shapes, for the four it has centred as dcol's)
//   bullet_scenes tumble          30 boxes, cylinders and capsules dropped with random attitudes
//                                 and spins come to rest on a face
//   bullet_scenes compare         the drop with dcol and with Bullet's shapes: same rest heights,
//                                 and the time per step of each
//   bullet_scenes stack KIND      five boxes stacked for 10 s; KIND = dcol or native
//   bullet_scenes drop GROUND --csv FILE   also write the heights over time
//
// Bodies never sleep (deactivation disabled), so the checks see the contacts at every step.
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "dcol_bullet.hpp"
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
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> states;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  World() {
    dcol_bullet::register_algorithms(&dispatcher);
    world.setGravity(btVector3(0, 0, btScalar(-kG)));
  }
  ~World() {
    for (auto &b : bodies) world.removeRigidBody(b.get());
  }
  btRigidBody *add(btCollisionShape *shape, double mass, const btTransform &t) {
    shapes.emplace_back(shape);
    states.emplace_back(new btDefaultMotionState(t));
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), states.back().get(), shape, inertia);
    info.m_friction = 0.6;
    bodies.emplace_back(new btRigidBody(info));
    btRigidBody *b = bodies.back().get();
    b->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(b);
    return b;
  }
  void step() { world.stepSimulation(btScalar(kDt), 1, btScalar(kDt)); }
};

double energy(const btRigidBody *b) {
  const double m = 1.0 / b->getInvMass();
  const btVector3 v = b->getLinearVelocity();
  const btVector3 wb = b->getWorldTransform().getBasis().transpose() * b->getAngularVelocity();
  const btVector3 inv = b->getInvInertiaDiagLocal();
  double rot = 0;
  for (int i = 0; i < 3; ++i)
    if (inv[i] > 0) rot += wb[i] * wb[i] / inv[i];
  return 0.5 * m * v.length2() + 0.5 * rot + m * kG * b->getWorldTransform().getOrigin().z();
}

struct Spec {
  const char *name;
  double rest;
  double radius;
  btVector3 half;  // body-frame bounding box half extents (inertia)
  bool native;
};

const Spec kSpecs[] = {
    {"sphere", 0.2, 0.2, btVector3(0.2f, 0.2f, 0.2f), true},
    {"box", 0.1, std::sqrt(0.04 + 0.0225 + 0.01), btVector3(0.2f, 0.15f, 0.1f), true},
    {"capsule", 0.1, 0.3, btVector3(0.3f, 0.1f, 0.1f), true},
    {"cylinder", 0.15, std::sqrt(0.0225 + 0.04), btVector3(0.2f, 0.15f, 0.15f), true},
    {"cone", 0.1, std::max(0.3, std::hypot(0.1, 0.4 * std::tan(0.5))), btVector3(0.2f, 0.22f, 0.22f), false},
    {"ellipsoid", 0.12, 0.25, btVector3(0.25f, 0.2f, 0.12f), false},
};

// Bullet's own shapes with dcol's frames (capsule and cylinder along x).
btCollisionShape *native_shape(const char *name) {
  if (!std::strcmp(name, "sphere")) return new btSphereShape(0.2f);
  if (!std::strcmp(name, "box")) return new btBoxShape(btVector3(0.2f, 0.15f, 0.1f));
  if (!std::strcmp(name, "capsule")) return new btCapsuleShapeX(0.1f, 0.4f);
  if (!std::strcmp(name, "cylinder")) return new btCylinderShapeX(btVector3(0.2f, 0.15f, 0.15f));
  return nullptr;
}

struct Owned {
  std::vector<dcol_shape *> shapes;
  ~Owned() {
    for (dcol_shape *s : shapes) dcol_shape_free(s);
  }
  dcol_shape *keep(dcol_shape *s) {
    shapes.push_back(s);
    return s;
  }
};

int drop(const std::string &ground, const char *csv, bool only_native = false, std::vector<double> *heights = nullptr,
         double *step_time = nullptr) {
  Owned owned;  // declared before the world: freed after it
  World w;
  btTransform tg;
  tg.setIdentity();
  tg.setOrigin(btVector3(0, 0, btScalar(-kFloorDepth)));
  if (ground == "halfspace") {
    w.add(new dcol_bullet::Shape(owned.keep(make_floor()), INFINITY, btVector3(5, 5, 0.5f)), 0, tg);
  } else if (ground == "box") {
    dcol_shape *g = nullptr;
    dcol_shape_new_box(5, 5, 0.5, &g);
    w.add(new dcol_bullet::Shape(owned.keep(g), std::sqrt(50.25), btVector3(5, 5, 0.5f)), 0, tg);
  } else if (ground == "plane") {
    btTransform t;
    t.setIdentity();
    w.add(new btStaticPlaneShape(btVector3(0, 0, 1), 0), 0, t);
  } else if (ground == "native") {
    w.add(new btBoxShape(btVector3(5, 5, 0.5f)), 0, tg);
  } else {
    std::printf("unknown ground %s\n", ground.c_str());
    return 2;
  }
  const bool native = ground == "native";
  struct Item {
    const Spec *spec;
    btRigidBody *body;
  };
  std::vector<Item> items;
  double x = -5 * 0.9;
  for (const Spec &s : kSpecs) {
    x += 0.9;
    if ((native || only_native) && !s.native) continue;
    btCollisionShape *shape = native ? native_shape(s.name) : new dcol_bullet::Shape(owned.keep(make(s.name)), s.radius, s.half);
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(btScalar(x), 0, btScalar(s.rest + 0.3)));
    // Flat-bottomed bodies land tilted by 0.05 rad and must settle flat; round ones straight.
    const btScalar tilt = 0.05f;
    if (!std::strcmp(s.name, "cone")) {
      t.setRotation(btQuaternion(btVector3(1, 0, 0), tilt) * btQuaternion(btVector3(0, 1, 0), btScalar(M_PI / 2)));
    } else if (!std::strcmp(s.name, "box")) {
      t.setRotation(btQuaternion(btVector3(1, 0, 0), tilt));
    } else if (!std::strcmp(s.name, "cylinder") || !std::strcmp(s.name, "capsule")) {
      t.setRotation(btQuaternion(btVector3(0, 1, 0), tilt));
    }
    items.push_back({&s, w.add(shape, 1.0, t)});
  }
  FILE *out = csv ? std::fopen(csv, "w") : nullptr;
  if (out) {
    std::fprintf(out, "t");
    for (const Item &it : items) std::fprintf(out, ",%s", it.spec->name);
    std::fprintf(out, "\n");
  }
  const int steps = 800, settle = 400;
  std::vector<double> e0(items.size()), emax(items.size(), -1e300), zmin(items.size(), 1e300);
  const double t0 = now();
  for (int k = 1; k <= steps; ++k) {
    w.step();
    if (out && k % 2 == 0) {
      std::fprintf(out, "%.4f", k * kDt);
      for (const Item &it : items) std::fprintf(out, ",%.6f", double(it.body->getWorldTransform().getOrigin().z()));
      std::fprintf(out, "\n");
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (k == settle) e0[i] = energy(items[i].body);
      if (k > settle) {
        emax[i] = std::max(emax[i], energy(items[i].body));
        zmin[i] = std::min(zmin[i], double(items[i].body->getWorldTransform().getOrigin().z()));
      }
    }
  }
  const double per_step = (now() - t0) / steps;
  if (out) std::fclose(out);
  std::printf("drop on %s ground (%s): %.1f us per step (%zu bodies, dt %.3f s)\n", ground.c_str(),
              native ? "Bullet's shapes" : "dcol", per_step * 1e6, items.size(), kDt);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Spec &s = *items[i].spec;
    const double z = items[i].body->getWorldTransform().getOrigin().z();
    const double sink = s.rest - zmin[i];
    const double gain = emax[i] - e0[i];
    std::printf("  %-9s rest %.6f m (analytic %.4f, error %+.2e m), sink after 2 s %+.2e m, energy gain %+.2e J\n",
                s.name, z, s.rest, z - s.rest, sink, gain);
    char what[128];
    std::snprintf(what, sizeof what, "%s rest height within 1 mm", s.name);
    check(std::fabs(z - s.rest) <= kTol, what);
    // The sink and energy checks are the adapter's; for the engine's own colliders they are
    // reported only (the comparison is on rest heights).
    std::snprintf(what, sizeof what, "%s sinks less than 1 mm", s.name);
    if (!native) check(sink <= kTol, what);
    std::snprintf(what, sizeof what, "%s gains no energy after settling", s.name);
    if (!native) check(gain <= 1e-4 * kG, what);  // at most the energy of a 0.1 mm rise of 1 kg
    if (heights) heights->push_back(z);
  }
  if (step_time) *step_time = per_step;
  return 0;
}

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

int stack(const std::string &kind) {
  Owned owned;
  World w;
  const bool native = kind == "native";
  const double h = 0.25;
  btTransform tg;
  tg.setIdentity();
  tg.setOrigin(btVector3(0, 0, btScalar(-kFloorDepth)));
  dcol_shape *cube = nullptr;
  if (native) {
    w.add(new btBoxShape(btVector3(5, 5, 0.5f)), 0, tg);
  } else {
    w.add(new dcol_bullet::Shape(owned.keep(make_floor()), INFINITY, btVector3(5, 5, 0.5f)), 0, tg);
    dcol_shape_new_box(h, h, h, &cube);
    owned.keep(cube);
  }
  std::vector<btRigidBody *> boxes;
  for (int i = 0; i < 5; ++i) {
    btCollisionShape *s = native ? static_cast<btCollisionShape *>(new btBoxShape(btVector3(btScalar(h), btScalar(h), btScalar(h))))
                                 : new dcol_bullet::Shape(cube, h * std::sqrt(3.0), btVector3(btScalar(h), btScalar(h), btScalar(h)));
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(btScalar(0.002 * i), 0, btScalar(h + i * (2 * h + 0.001))));
    boxes.push_back(w.add(s, 1.0, t));
  }
  const int steps = static_cast<int>(10.0 / kDt);
  const double t0 = now();
  for (int k = 0; k < steps; ++k) w.step();
  const double per_step = (now() - t0) / steps;
  std::printf("stack of five boxes (%s), 10 s: %.1f us per step\n", native ? "Bullet's shapes" : "dcol", per_step * 1e6);
  for (int i = 0; i < 5; ++i) {
    const btVector3 p = boxes[i]->getWorldTransform().getOrigin();
    const double want = h + i * 2 * h;
    std::printf("  box %d: z %.6f (analytic %.4f, error %+.2e), x %+.2e, y %+.2e\n", i, double(p.z()), want,
                p.z() - want, p.x() - 0.002 * i, double(p.y()));
    char what[96];
    std::snprintf(what, sizeof what, "box %d of the stack within 1 mm of its height", i);
    check(std::fabs(p.z() - want) <= kTol, what);
    std::snprintf(what, sizeof what, "box %d of the stack did not slide more than 1 cm", i);
    check(std::hypot(p.x() - 0.002 * i, p.y()) <= 0.01, what);
  }
  return 0;
}

// One step of a sphere resting 5 cm deep in a box, with dcol and with Bullet's shapes: the
// manifolds' normals (on B) and distances agree.
int normal_convention() {
  for (int order = 0; order < 2; ++order) {
    double normals[2][3], dist[2];
    int counts[2];
    for (int native = 0; native < 2; ++native) {
      Owned owned;
      World w;
      w.world.setGravity(btVector3(0, 0, 0));
      btTransform tb, ts;
      tb.setIdentity();
      ts.setIdentity();
      ts.setOrigin(btVector3(0.1f, 0.2f, 1.45f));
      btCollisionShape *box, *ball;
      if (native) {
        box = new btBoxShape(btVector3(1, 1, 1));
        ball = new btSphereShape(0.5f);
      } else {
        dcol_shape *b = nullptr, *s = nullptr;
        dcol_shape_new_box(1, 1, 1, &b);
        dcol_shape_new_sphere(0.5, &s);
        box = new dcol_bullet::Shape(owned.keep(b), std::sqrt(3.0), btVector3(1, 1, 1));
        ball = new dcol_bullet::Shape(owned.keep(s), 0.5, btVector3(0.5f, 0.5f, 0.5f));
      }
      if (order == 0) {
        w.add(box, 0, tb);
        w.add(ball, 1, ts);
      } else {
        w.add(ball, 1, ts);
        w.add(box, 0, tb);
      }
      w.world.performDiscreteCollisionDetection();
      counts[native] = w.dispatcher.getNumManifolds();
      dist[native] = 0;
      for (int k = 0; k < 3; ++k) normals[native][k] = 0;
      if (counts[native] >= 1) {
        btPersistentManifold *m = w.dispatcher.getManifoldByIndexInternal(0);
        // Express the normal as pointing from the box to the ball.
        const double sign = m->getBody0() == w.bodies[order == 0 ? 0 : 1].get() ? -1.0 : 1.0;
        if (m->getNumContacts() >= 1) {
          const btManifoldPoint &p = m->getContactPoint(0);
          for (int k = 0; k < 3; ++k) normals[native][k] = sign * p.m_normalWorldOnB[k];
          dist[native] = p.getDistance();
        }
      }
    }
    std::printf("order %d: dcol normal box->ball (%.5f %.5f %.5f) distance %.5f; Bullet (%.5f %.5f %.5f) distance %.5f\n",
                order, normals[0][0], normals[0][1], normals[0][2], dist[0], normals[1][0], normals[1][1], normals[1][2],
                dist[1]);
    check(counts[0] == 1 && counts[1] == 1, "one manifold each");
    check(std::fabs(normals[0][2] - 1) < 1e-5 && std::fabs(normals[1][2] - 1) < 1e-5, "normals from the box to the ball");
    check(std::fabs(dist[0] + 0.05) < 1e-5 && std::fabs(dist[1] + 0.05) < 1e-5, "distance -0.05 (penetration)");
  }
  return 0;
}

// Boxes, cylinders and capsules dropped with random attitudes and spins, apart from each other:
// after 6 s each rests on a face (box: one of its half extents; cylinder: its radius or half
// length; capsule: its radius), within 1 mm.
int tumble() {
  Owned owned;
  World w;
  btTransform tg;
  tg.setIdentity();
  tg.setOrigin(btVector3(0, 0, btScalar(-kFloorDepth)));
  dcol_shape *g = make_floor(), *box = nullptr, *cyl = nullptr, *cap = nullptr;
  dcol_shape_new_box(0.2, 0.15, 0.1, &box);
  dcol_shape_new_cylinder(0.15, 0.4, &cyl);
  dcol_shape_new_capsule(0.1, 0.4, &cap);
  owned.keep(g);
  owned.keep(box);
  owned.keep(cyl);
  owned.keep(cap);
  w.add(new dcol_bullet::Shape(g, INFINITY, btVector3(20, 20, 0.5f)), 0, tg);
  unsigned long long state = 12345;
  auto unif = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  std::vector<std::pair<int, btRigidBody *>> items;
  for (int i = 0; i < 30; ++i) {
    const int kind = i % 3;
    const Spec &s = kSpecs[kind == 0 ? 1 : kind == 1 ? 3 : 2];
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(btScalar(-12 + 1.5 * (i % 10) + 0.3 * unif()), btScalar(-3 + 2.0 * (i / 10)),
                          btScalar(0.5 + unif())));
    btQuaternion q(btScalar(unif() - 0.5), btScalar(unif() - 0.5), btScalar(unif() - 0.5), btScalar(unif() - 0.5));
    t.setRotation(q.normalized());
    btRigidBody *b = w.add(new dcol_bullet::Shape(kind == 0 ? box : kind == 1 ? cyl : cap, s.radius, s.half), 1.0, t);
    b->setAngularVelocity(btVector3(btScalar(4 * (unif() - 0.5)), btScalar(4 * (unif() - 0.5)), btScalar(4 * (unif() - 0.5))));
    items.push_back({kind, b});
  }
  for (int k = 0; k < static_cast<int>(6.0 / kDt); ++k) w.step();
  int bad = 0;
  double worst = 0;
  static const double rests[3][3] = {{0.2, 0.15, 0.1}, {0.15, 0.2, 0.15}, {0.1, 0.1, 0.1}};
  for (const auto &it : items) {
    const double z = it.second->getWorldTransform().getOrigin().z();
    const double speed = it.second->getLinearVelocity().length();
    double err = 1e300;
    for (double r : rests[it.first]) err = std::min(err, std::fabs(z - r));
    worst = std::max(worst, err);
    if (err > kTol || (it.first == 0 && speed > 1e-3)) {
      ++bad;
      std::printf("  body of kind %d: z %.6f (error %.2e), speed %.2e\n", it.first, z, err, speed);
    }
  }
  std::printf("tumble: 30 bodies (boxes, cylinders, capsules) at rest on a face, worst height error %.2e m\n",
              worst);
  check(bad == 0, "every tumbled body rests on a face within 1 mm");
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::printf("usage: %s normal | drop halfspace|box|plane|native [--csv FILE] | compare | stack dcol|native\n", argv[0]);
    return 2;
  }
  const std::string what = argv[1];
  const char *csv = nullptr;
  if (argc >= 5 && !std::strcmp(argv[3], "--csv")) csv = argv[4];
  int rc = 2;
  if (what == "normal") rc = normal_convention();
  if (what == "drop" && argc >= 3) rc = drop(argv[2], csv);
  if (what == "compare") rc = compare();
  if (what == "tumble") rc = tumble();
  if (what == "stack" && argc >= 3) rc = stack(argv[2]);
  if (rc != 0) return rc;
  std::printf("%s\n", engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
