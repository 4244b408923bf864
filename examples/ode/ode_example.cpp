// A plain ODE program (ODE's own geoms: a plane, boxes, spheres, capsules, cylinders) with dcol as
// its narrow phase: the three lines marked "dcol" are all it takes. It runs the scene twice, with
// ODE's colliders and with dcol's, and checks that every body comes to rest at the same height
// both times (within 1 mm) and that dcol answered the pairs.
#include <dcol_ode.hpp>  // dcol

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

dWorldID world;
dJointGroupID contacts;

void near(void *, dGeomID o1, dGeomID o2) {
  dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
  dContact c[4];
  const int n = dCollide(o1, o2, 4, &c[0].geom, sizeof(dContact));
  for (int i = 0; i < n; ++i) {
    c[i].surface.mode = dContactApprox1;
    c[i].surface.mu = 0.6;
    dJointAttach(dJointCreateContact(world, contacts, &c[i]), b1, b2);
  }
}

// Drops a box, a sphere, a capsule and a cylinder (the last two lying on their side) on a plane
// and returns their heights after 3 s.
std::vector<double> run() {
  world = dWorldCreate();
  dSpaceID space = dHashSpaceCreate(0);
  contacts = dJointGroupCreate(0);
  dWorldSetGravity(world, 0, 0, -9.81);
  dCreatePlane(space, 0, 0, 1, 0);
  std::vector<dBodyID> bodies;
  for (int i = 0; i < 4; ++i) {
    dBodyID b = dBodyCreate(world);
    dMass m;
    dGeomID g;
    if (i == 0) {
      g = dCreateBox(space, 0.4, 0.3, 0.2);
      dMassSetBox(&m, 500, 0.4, 0.3, 0.2);
    } else if (i == 1) {
      g = dCreateSphere(space, 0.15);
      dMassSetSphere(&m, 500, 0.15);
    } else if (i == 2) {
      g = dCreateCapsule(space, 0.1, 0.4);
      dMassSetCapsule(&m, 500, 3, 0.1, 0.4);
    } else {
      g = dCreateCylinder(space, 0.12, 0.3);
      dMassSetCylinder(&m, 500, 3, 0.12, 0.3);
    }
    dBodySetMass(b, &m);
    dGeomSetBody(g, b);
    dBodySetPosition(b, i * 0.8, 0, 0.5);
    dMatrix3 R;
    dRFromAxisAndAngle(R, 1, 0, 0, i >= 2 ? 1.5708 : 0.05);  // capsule, cylinder: on their side
    dBodySetRotation(b, R);
    bodies.push_back(b);
  }
  for (int k = 0; k < 600; ++k) {
    dSpaceCollide(space, nullptr, &near);
    dWorldQuickStep(world, 0.005);
    dJointGroupEmpty(contacts);
  }
  std::vector<double> z;
  for (dBodyID b : bodies) z.push_back(dBodyGetPosition(b)[2]);
  dJointGroupDestroy(contacts);
  dSpaceDestroy(space);
  dWorldDestroy(world);
  return z;
}

}  // namespace

int main() {
  dInitODE2(0);
  const std::vector<double> native = run();  // ODE's own colliders
  dCloseODE();

  dInitODE2(0);
  dcol_ode::use_dcol();  // dcol: from here on dCollide asks dcol
  const std::vector<double> with_dcol = run();
  const unsigned long calls = dcol_ode::collider_calls();  // dcol
  dCloseODE();

  const double want[4] = {0.1, 0.15, 0.1, 0.12};  // half height, radius, radius, radius
  int bad = calls == 0;
  for (int i = 0; i < 4; ++i) {
    std::printf("body %d: rest height native %.6f m, dcol %.6f m (analytic %.3f)\n", i, native[i], with_dcol[i], want[i]);
    bad += std::fabs(native[i] - with_dcol[i]) > 1e-3 || std::fabs(with_dcol[i] - want[i]) > 1e-3;
  }
  std::printf("dcol collider calls: %lu\n%s\n", calls, bad ? "FAILED" : "ok");
  return bad ? 1 : 0;
}
