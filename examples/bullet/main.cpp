// A plain Bullet program (Bullet's own shapes dropped on a plane) with dcol as its narrow phase:
// the lines marked "dcol" are all it takes. It runs the scene with Bullet's narrow phase and with
// dcol's, and checks that every body comes to rest at the same height in both (within 1 mm), the
// analytic one, and that dcol answered the pairs.
#include <btBulletDynamicsCommon.h>
#include <dcol_bullet.hpp>  // dcol

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace {

struct Body {
  const char *name;
  btCollisionShape *shape;
  double rest;  // height of the centre at rest on the plane
};

std::vector<double> simulate(bool use_dcol) {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  if (use_dcol) dcol_bullet::use_dcol(&dispatcher);  // dcol
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, -9.81f));

  btStaticPlaneShape ground_shape(btVector3(0, 0, 1), 0);
  btRigidBody ground(0, nullptr, &ground_shape);
  world.addRigidBody(&ground);

  btSphereShape sphere(0.2f);
  btBoxShape box(btVector3(0.3f, 0.2f, 0.1f));
  btCapsuleShapeX capsule(0.1f, 0.4f);     // lying on its side
  btCylinderShapeZ cylinder(btVector3(0.15f, 0.15f, 0.25f));  // standing on its cap
  btConeShapeZ cone(0.2f, 0.4f);           // on its base
  const Body bodies[] = {{"sphere", &sphere, 0.2},
                         {"box", &box, 0.1},
                         {"capsule", &capsule, 0.1},
                         {"cylinder", &cylinder, 0.25},
                         {"cone", &cone, 0.2 + cone.getMargin()}};
  std::vector<std::unique_ptr<btDefaultMotionState>> states;
  std::vector<std::unique_ptr<btRigidBody>> rigid;
  double x = -1.2;
  for (const Body &b : bodies) {
    btVector3 inertia;
    b.shape->calculateLocalInertia(1, inertia);
    states.emplace_back(new btDefaultMotionState(btTransform(btQuaternion::getIdentity(),
                                                             btVector3(btScalar(x += 0.6), 0, btScalar(b.rest + 0.2)))));
    rigid.emplace_back(new btRigidBody(1, states.back().get(), b.shape, inertia));
    world.addRigidBody(rigid.back().get());
  }
  for (int k = 0; k < 240 * 3; ++k) world.stepSimulation(1.0f / 240, 1, 1.0f / 240);

  std::vector<double> heights;
  for (std::size_t i = 0; i < rigid.size(); ++i) {
    heights.push_back(rigid[i]->getWorldTransform().getOrigin().z());
    world.removeRigidBody(rigid[i].get());
  }
  world.removeRigidBody(&ground);
  return heights;
}

}  // namespace

int main() {
  const char *names[] = {"sphere", "box", "capsule", "cylinder", "cone"};
  const double rest[] = {0.2, 0.1, 0.1, 0.25, 0.2 + 0.04};  // the cone's margin (0.04) is outside it
  const std::vector<double> native = simulate(false), with_dcol = simulate(true);
  bool ok = dcol_bullet::algorithm_calls() > 0;
  for (std::size_t i = 0; i < native.size(); ++i) {
    std::printf("%-8s rests at %.5f m with Bullet's narrow phase, %.5f m with dcol (analytic %.2f)\n", names[i],
                native[i], with_dcol[i], rest[i]);
    ok = ok && std::fabs(native[i] - with_dcol[i]) < 1e-3 && std::fabs(with_dcol[i] - rest[i]) < 1e-3;
  }
  std::printf("pair calls answered by dcol: %lu\n%s\n", dcol_bullet::algorithm_calls(), ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
