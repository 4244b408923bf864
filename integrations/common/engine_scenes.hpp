// What the Bullet and ODE adapters' scene tests share (integrations/bullet/tests,
// integrations/ode/tests): the scene constants, the check counter, a clock, the six dcol
// primitives of the drop scenes and the floor (a dcol half-space).
#pragma once

#include <dcol.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace engine_scenes {

const double kG = 9.81;
const double kDt = 0.005;
const double kTol = 1e-3;  // 1 mm

/// Failed checks so far (the program's exit status is nonzero when any failed).
inline int &failures() {
  static int n = 0;
  return n;
}

inline void check(bool ok, const char *what) {
  if (!ok) {
    ++failures();
    std::printf("FAILED: %s\n", what);
  }
}

inline double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The drop scenes' dcol shape of kind `name` (sphere R 0.2; box half 0.2 x 0.15 x 0.1; capsule
/// R 0.1, L 0.4; cylinder R 0.15, L 0.4; cone H 0.4, beta 0.5; ellipsoid semi-axes 0.25, 0.2,
/// 0.12); exits with status 2 if it cannot be built.
inline dcol_shape *make(const char *name) {
  dcol_shape *s = nullptr;
  dcol_status st = DCOL_ERROR_INVALID_SHAPE;
  if (!std::strcmp(name, "sphere")) st = dcol_shape_new_sphere(0.2, &s);
  if (!std::strcmp(name, "box")) st = dcol_shape_new_box(0.2, 0.15, 0.1, &s);
  if (!std::strcmp(name, "capsule")) st = dcol_shape_new_capsule(0.1, 0.4, &s);
  if (!std::strcmp(name, "cylinder")) st = dcol_shape_new_cylinder(0.15, 0.4, &s);
  if (!std::strcmp(name, "cone")) st = dcol_shape_new_cone(0.4, 0.5, &s);
  if (!std::strcmp(name, "ellipsoid")) {
    const double P[9] = {1 / 0.0625, 0, 0, 0, 1 / 0.04, 0, 0, 0, 1 / 0.0144};
    st = dcol_shape_new_ellipsoid(P, &s);
  }
  if (st != DCOL_OK) {
    std::printf("shape %s: %s\n", name, dcol_last_error_message());
    std::exit(2);
  }
  return s;
}

/// The floor's depth: the half-space {u_z <= kFloorDepth} posed at (0, 0, -kFloorDepth) (identity
/// attitude) has its top surface at z = 0.
const double kFloorDepth = 0.5;

/// The floor of every dcol scene: a dcol half-space (dcol_shape_new_halfspace), to be posed at
/// (0, 0, -kFloorDepth); exits with status 2 if it cannot be built.
inline dcol_shape *make_floor() {
  dcol_shape *s = nullptr;
  if (dcol_shape_new_halfspace(kFloorDepth, &s) != DCOL_OK) {
    std::printf("floor: %s\n", dcol_last_error_message());
    std::exit(2);
  }
  return s;
}

}  // namespace engine_scenes
