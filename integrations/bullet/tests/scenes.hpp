// The physics scenes written with Bullet's own shapes only (a pyramid of boxes, a pile of mixed
// bodies in a walled bin, bodies on a slope), each built the same way for Bullet's narrow phase
// and for dcol's (use_dcol): the ctest scenes (physics.cpp) and the benchmark
// (benches/engines/bullet) share them.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <memory>
#include <vector>

#include "dcol_bullet.hpp"

namespace bullet_scenes {

const double kG = 9.81;

/// What a user tunes, the same for both narrow phases.
struct Params {
  double dt = 1.0 / 240;         // fixed time step (one substep per step)
  int iterations = 20;           // sequential-impulse solver iterations
  double friction = 0.6;         // per body; Bullet multiplies the two bodies'
  double restitution = 0;        // per body; Bullet multiplies the two bodies'
  double linear_damping = 0;     // per dynamic body
  double angular_damping = 0;    // per dynamic body
  double rolling_friction = 0;   // per dynamic body (Bullet: r0 f1 + r1 f0)
  double spinning_friction = 0;  // per dynamic body
};

/// A Bullet world with its own collision configuration and dispatcher; `dcol` calls use_dcol.
struct World {
  Params params;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> states;
  std::vector<std::unique_ptr<btRigidBody>> bodies;

  World(bool dcol, const Params &p) : params(p) {
    if (dcol) dcol_bullet::use_dcol(&dispatcher);
    world.setGravity(btVector3(0, 0, btScalar(-kG)));
    world.getSolverInfo().m_numIterations = p.iterations;
  }
  ~World() {
    for (auto &b : bodies) world.removeRigidBody(b.get());
  }
  World(const World &) = delete;
  World &operator=(const World &) = delete;

  /// Takes `shape` (owned by the world; may be shared by later bodies through `share`).
  btCollisionShape *own(btCollisionShape *shape) {
    shapes.emplace_back(shape);
    return shape;
  }

  /// A body of `shape` (not owned here: see own), static when mass is 0; never sleeps, so every
  /// step collides every pair.
  btRigidBody *add(btCollisionShape *shape, double mass, const btTransform &t) {
    states.emplace_back(new btDefaultMotionState(t));
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(btScalar(mass), inertia);
    btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), states.back().get(), shape, inertia);
    info.m_friction = btScalar(params.friction);
    info.m_restitution = btScalar(params.restitution);
    if (mass > 0) {
      info.m_linearDamping = btScalar(params.linear_damping);
      info.m_angularDamping = btScalar(params.angular_damping);
      info.m_rollingFriction = btScalar(params.rolling_friction);
      info.m_spinningFriction = btScalar(params.spinning_friction);
    }
    bodies.emplace_back(new btRigidBody(info));
    btRigidBody *b = bodies.back().get();
    b->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(b);
    return b;
  }

  void step() { world.stepSimulation(btScalar(params.dt), 1, btScalar(params.dt)); }
};

inline btTransform at(double x, double y, double z, const btQuaternion &q = btQuaternion::getIdentity()) {
  return btTransform(q, btVector3(btScalar(x), btScalar(y), btScalar(z)));
}

// ---------------------------------------------------------------------------------------------
// The pyramid: 55 cubes (edge 0.2 m, 1 kg) in 10 layers of 10, 9, ..., 1 on a btStaticPlaneShape,
// 2 mm apart within a layer.

const double kCube = 0.1;  // half edge

inline Params pyramid_params() { return Params(); }

/// Builds the pyramid; returns its boxes (their start poses are their transforms now).
inline std::vector<btRigidBody *> build_pyramid(World &w) {
  w.add(w.own(new btStaticPlaneShape(btVector3(0, 0, 1), 0)), 0, at(0, 0, 0));
  btCollisionShape *cube = w.own(new btBoxShape(btVector3(btScalar(kCube), btScalar(kCube), btScalar(kCube))));
  std::vector<btRigidBody *> boxes;
  const double pitch = 2 * kCube + 0.002;
  for (int layer = 0; layer < 10; ++layer) {
    const int n = 10 - layer;
    for (int i = 0; i < n; ++i) {
      const double x = (i - 0.5 * (n - 1)) * pitch;
      boxes.push_back(w.add(cube, 1.0, at(x, 0, kCube + 2 * kCube * layer)));
    }
  }
  return boxes;
}

// ---------------------------------------------------------------------------------------------
// The pile: 49 mixed bodies (spheres, boxes, capsules, cylinders, cones, hulls of 12 to 200
// points; sizes 0.1 to 0.3 m) dropped from a 7 x 7 grid of pitch 0.2 m, 0.25 m
// above the floor, into a bin (a btStaticPlaneShape floor and four static box walls, inner
// 1.4 m x 1.4 m, 0.8 m high): they land on and against each other. (Dropped in two or three
// layers, the heap kept avalanching after 5 s with either narrow phase: docs/bullet.md.)

const double kBinHalf = 0.7;    // inner half width
const double kWallHalf = 0.05;  // wall half thickness
const double kWallHeight = 0.8;
const int kGrid = 7;
const double kPitch = 0.2, kDropHeight = 0.25;

inline Params pile_params() {
  Params p;
  p.linear_damping = 0.05;
  p.angular_damping = 0.2;
  p.rolling_friction = 0.03;
  p.spinning_friction = 0.03;
  return p;
}

struct Pile {
  std::vector<btRigidBody *> bodies;  // the dropped bodies
  std::vector<btRigidBody *> statics;  // the floor, then the four walls
};

/// Builds the bin and drops `count` bodies (a fixed mix by index, sizes and attitudes from
/// `seed`) from the grid (7 x 7 per layer) above it.
inline Pile build_pile(World &w, unsigned seed, int count = kGrid * kGrid) {
  Pile pile;
  pile.statics.push_back(w.add(w.own(new btStaticPlaneShape(btVector3(0, 0, 1), 0)), 0, at(0, 0, 0)));
  const double wz = 0.5 * kWallHeight, off = kBinHalf + kWallHalf, len = kBinHalf + 2 * kWallHalf;
  btCollisionShape *wall_x = w.own(new btBoxShape(btVector3(btScalar(kWallHalf), btScalar(len), btScalar(wz))));
  btCollisionShape *wall_y = w.own(new btBoxShape(btVector3(btScalar(len), btScalar(kWallHalf), btScalar(wz))));
  pile.statics.push_back(w.add(wall_x, 0, at(off, 0, wz)));
  pile.statics.push_back(w.add(wall_x, 0, at(-off, 0, wz)));
  pile.statics.push_back(w.add(wall_y, 0, at(0, off, wz)));
  pile.statics.push_back(w.add(wall_y, 0, at(0, -off, wz)));
  unsigned long long state = 0x9E3779B97F4A7C15ULL * (seed + 1);
  auto unif = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  for (int i = 0; i < count; ++i) {
    const double s = 0.05 + 0.03 * unif();  // size scale
    btCollisionShape *shape = nullptr;
    switch (i % 6) {
      case 0:
        shape = new btSphereShape(btScalar(s * 1.3));
        break;
      case 1:
        shape = new btBoxShape(btVector3(btScalar(1.6 * s), btScalar(1.2 * s), btScalar(0.8 * s)));
        break;
      case 2: {
        const int axis = int(unif() * 3);
        shape = axis == 0 ? static_cast<btCollisionShape *>(new btCapsuleShapeX(btScalar(0.8 * s), btScalar(2 * s)))
                : axis == 1 ? static_cast<btCollisionShape *>(new btCapsuleShape(btScalar(0.8 * s), btScalar(2 * s)))
                            : new btCapsuleShapeZ(btScalar(0.8 * s), btScalar(2 * s));
        break;
      }
      case 3: {
        const btScalar r = btScalar(1.1 * s), h = btScalar(1.2 * s);
        const int axis = int(unif() * 3);
        shape = axis == 0 ? static_cast<btCollisionShape *>(new btCylinderShapeX(btVector3(h, r, r)))
                : axis == 1 ? static_cast<btCollisionShape *>(new btCylinderShape(btVector3(r, h, r)))
                            : new btCylinderShapeZ(btVector3(r, r, h));
        break;
      }
      case 4: {
        const btScalar r = btScalar(1.2 * s), h = btScalar(2.4 * s);
        const int axis = int(unif() * 3);
        shape = axis == 0 ? static_cast<btCollisionShape *>(new btConeShapeX(r, h))
                : axis == 1 ? static_cast<btCollisionShape *>(new btConeShape(r, h))
                            : new btConeShapeZ(r, h);
        break;
      }
      default: {
        // A hull of 12 to 200 points on an ellipsoid, with a margin of 4 mm (Bullet's default,
        // 4 cm, would grow these 0.1 m bodies by almost half).
        static const int kPoints[] = {12, 24, 50, 100, 200, 16, 36, 150};
        btConvexHullShape *hull = new btConvexHullShape();
        const int n = kPoints[(i / 6) % 8];
        for (int k = 0; k < n; ++k) {
          double d[3];
          double len = 0;
          do {
            for (double &v : d) v = 2 * unif() - 1;
            len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          } while (len < 0.1 || len > 1);
          hull->addPoint(btVector3(btScalar(1.4 * s * d[0] / len), btScalar(1.1 * s * d[1] / len),
                                   btScalar(0.9 * s * d[2] / len)),
                         false);
        }
        hull->recalcLocalAabb();
        hull->setMargin(0.004f);
        shape = hull;
        break;
      }
    }
    const int layer = i / (kGrid * kGrid), cell = i % (kGrid * kGrid);
    const double x = (cell % kGrid - 0.5 * (kGrid - 1)) * kPitch + 0.02 * (unif() - 0.5);
    const double y = (cell / kGrid - 0.5 * (kGrid - 1)) * kPitch + 0.02 * (unif() - 0.5);
    const double z = kDropHeight + 0.3 * layer;
    const btQuaternion q = btQuaternion(btScalar(unif() - 0.5), btScalar(unif() - 0.5), btScalar(unif() - 0.5),
                                        btScalar(unif() - 0.5))
                               .normalized();
    btRigidBody *b = w.add(w.own(shape), 0.5 + unif(), at(x, y, z, q));
    pile.bodies.push_back(b);
  }
  return pile;
}

// ---------------------------------------------------------------------------------------------
// The slope: a static box (half 3 x 1 x 0.1 m, friction 1) tilted by 30 degrees about y; its top
// face descends along +x.

const double kSlope = M_PI / 6;

inline Params slope_params() {
  Params p;
  p.friction = 1.0;  // the slope's; each body sets its own
  return p;
}

/// Builds the slope; returns the unit vector down the slope and its top face's normal.
inline void build_slope(World &w, btVector3 *down, btVector3 *normal) {
  const btQuaternion q(btVector3(0, 1, 0), btScalar(kSlope));
  w.add(w.own(new btBoxShape(btVector3(3, 1, 0.1f))), 0, at(0, 0, 0, q));
  *down = btMatrix3x3(q) * btVector3(1, 0, 0);
  *normal = btMatrix3x3(q) * btVector3(0, 0, 1);
}

/// A point on the slope's top face at distance `s` from its centre along the slope (down > 0),
/// lifted by `lift` along the normal.
inline btVector3 on_slope(const btVector3 &down, const btVector3 &normal, double s, double lift) {
  return normal * btScalar(0.1 + lift) + down * btScalar(s);
}

}  // namespace bullet_scenes
