// One resting pair, dCollide'd COUNT times with ODE's collider or dcol's, for instruction counts
// under callgrind (run.sh --instructions runs it with COUNT 0 and 1000 and prints the difference
// per call): the pairs of the pyramid and the pile at rest, face on face exactly aligned (as every
// stack starts) and tilted by TILT radians.
//
//   pair_instructions PAIR native|dcol COUNT [TILT]     prints the contacts of the last call
//   pair_instructions --list                             the pairs' names, one a line
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "ode_scenes.hpp"

namespace {

const char *kPairs[] = {"box-box (pyramid)", "box-plane",      "sphere-plane",     "sphere-box",
                        "capsule-plane",     "cylinder-plane", "hull200-plane",    "hull12-hull12",
                        "cylinder-cylinder"};
const int kCount = sizeof kPairs / sizeof kPairs[0];

dGeomID hull(const ode_scenes::Hull &h) {
  return dcol_ode::create_convex(0, h.planes.data(), h.plane_count, h.points.data(), h.point_count(), h.polygons.data());
}

}  // namespace

int main(int argc, char **argv) {
  if (argc > 1 && !std::strcmp(argv[1], "--list")) {
    for (const char *p : kPairs) std::printf("%s\n", p);
    return 0;
  }
  if (argc < 4) {
    std::printf("usage: %s PAIR native|dcol COUNT [TILT] | --list\n", argv[0]);
    return 2;
  }
  const int pair = std::atoi(argv[1]), count = std::atoi(argv[3]);
  const bool dcol = !std::strcmp(argv[2], "dcol");
  const double tilt = argc > 4 ? std::atof(argv[4]) : 0.0;
  if (pair < 0 || pair >= kCount) return 2;
  dInitODE2(0);
  if (dcol) dcol_ode::use_dcol();
  static const ode_scenes::Hull prism200 = ode_scenes::prism(100, 0.06, 0.1), prism12 = ode_scenes::prism(6, 0.07, 0.1);
  dGeomID plane = dCreatePlane(0, 0, 0, 1, 0), a = 0, b = plane;
  switch (pair) {
    case 0:  // the pyramid's: a 0.2 m cube on two, half over each
      a = dCreateBox(0, 0.2, 0.2, 0.2);
      b = dCreateBox(0, 0.2, 0.2, 0.2);
      dGeomSetPosition(a, 0.105, 0, 0.2999);
      dGeomSetPosition(b, 0, 0, 0.1);
      break;
    case 1:
      a = dCreateBox(0, 0.2, 0.2, 0.2);
      dGeomSetPosition(a, 0, 0, 0.0999);
      break;
    case 2:
      a = dCreateSphere(0, 0.1);
      dGeomSetPosition(a, 0, 0, 0.0999);
      break;
    case 3:
      a = dCreateSphere(0, 0.1);
      b = dCreateBox(0, 0.2, 0.2, 0.2);
      dGeomSetPosition(a, 0.02, 0, 0.1999);
      break;
    case 4: {  // on its side
      a = dCreateCapsule(0, 0.04, 0.12);
      dMatrix3 R;
      dRFromAxisAndAngle(R, 1, 0, 0, M_PI / 2);
      dGeomSetRotation(a, R);
      dGeomSetPosition(a, 0, 0, 0.0399);
      break;
    }
    case 5:  // on its cap
      a = dCreateCylinder(0, 0.06, 0.1);
      dGeomSetPosition(a, 0, 0, 0.0499);
      break;
    case 6:
      a = hull(prism200);
      dGeomSetPosition(a, 0, 0, 0.0499);
      break;
    case 7:
      a = hull(prism12);
      b = hull(prism12);
      dGeomSetPosition(a, 0.01, 0, 0.0999);
      break;
    default:
      a = dCreateCylinder(0, 0.06, 0.1);
      b = dCreateCylinder(0, 0.06, 0.1);
      dGeomSetPosition(a, 0.01, 0, 0.0999);
      break;
  }
  if (tilt != 0) {
    dMatrix3 R;
    dRFromAxisAndAngle(R, 0.3, 1, 0.2, tilt);
    dGeomSetRotation(a, R);
  }
  dContactGeom c[8];
  int n = 0;
  for (int i = 0; i < count; ++i) n = dCollide(a, b, 8, c, sizeof(dContactGeom));
  std::printf("%d\n", n);
  dcol_ode::release_all();
  dCloseODE();
  return 0;
}
