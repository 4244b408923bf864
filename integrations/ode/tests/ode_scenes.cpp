// The scenes of ode_scenes.hpp.
#include "ode_scenes.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "dcol_ode.hpp"

namespace ode_scenes {
namespace {

const double kPi = 3.14159265358979323846;
const double kDensity = 500.0;

// Appends a face (vertex indices in any rotational order around it): its plane from Newell's
// normal, turned outward (away from the origin, which lies inside), and its polygon
// counter-clockwise seen from outside.
void add_face(Hull &h, std::vector<unsigned> idx) {
  double n[3] = {0, 0, 0}, c[3] = {0, 0, 0};
  for (std::size_t i = 0; i < idx.size(); ++i) {
    const dReal *a = &h.points[3 * idx[i]];
    const dReal *b = &h.points[3 * idx[(i + 1) % idx.size()]];
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    for (int k = 0; k < 3; ++k) c[k] += a[k] / idx.size();
  }
  const double l = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double &x : n) x /= l;
  if (n[0] * c[0] + n[1] * c[1] + n[2] * c[2] < 0) {
    std::reverse(idx.begin(), idx.end());
    for (double &x : n) x = -x;
  }
  h.planes.insert(h.planes.end(), {n[0], n[1], n[2], n[0] * c[0] + n[1] * c[1] + n[2] * c[2]});
  h.polygons.push_back(static_cast<unsigned>(idx.size()));
  h.polygons.insert(h.polygons.end(), idx.begin(), idx.end());
  ++h.plane_count;
}

void ring(Hull &h, int n, double r, double z) {
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n;
    h.points.insert(h.points.end(), {r * std::cos(a), r * std::sin(a), z});
  }
}

std::vector<unsigned> range(unsigned from, int n) {
  std::vector<unsigned> v;
  for (int i = 0; i < n; ++i) v.push_back(from + static_cast<unsigned>(i));
  return v;
}

double polygon_area(int n, double r) { return 0.5 * n * r * r * std::sin(2 * kPi / n); }

}  // namespace

Settings pyramid_settings() {
  Settings s;
  s.dt = 0.005;
  s.iterations = 100;
  s.erp = 0.2;
  s.cfm = 1e-5;
  s.mu = 0.6;
  return s;
}

Settings pile_settings() {
  Settings s;
  s.dt = 0.005;
  s.iterations = 50;
  s.erp = 0.2;
  s.cfm = 1e-5;
  s.mu = 0.6;
  s.max_contacts = 8;
  s.linear_damping = 0.001;
  s.angular_damping = 0.005;
  return s;
}

Settings slope_settings(double mu) {
  Settings s;
  s.dt = 0.002;
  s.iterations = 50;
  s.erp = 0.2;
  s.cfm = 1e-6;
  s.mu = mu;
  return s;
}

Hull prism(int n, double r, double h) {
  Hull p;
  p.name = std::to_string(n) + "-gon prism (" + std::to_string(2 * n) + " points)";
  ring(p, n, r, -h / 2);
  ring(p, n, r, h / 2);
  add_face(p, range(0, n));
  add_face(p, range(static_cast<unsigned>(n), n));
  for (int i = 0; i < n; ++i) {
    const unsigned j = static_cast<unsigned>((i + 1) % n), u = static_cast<unsigned>(i), m = static_cast<unsigned>(n);
    add_face(p, {u, j, m + j, m + u});
  }
  p.volume = polygon_area(n, r) * h;
  return p;
}

Hull pyramid(int n, double r, double h) {
  Hull p;
  p.name = std::to_string(n) + "-gon pyramid (" + std::to_string(n + 1) + " points)";
  ring(p, n, r, -h / 4);
  p.points.insert(p.points.end(), {0, 0, 0.75 * h});
  add_face(p, range(0, n));
  for (int i = 0; i < n; ++i)
    add_face(p, {static_cast<unsigned>(i), static_cast<unsigned>((i + 1) % n), static_cast<unsigned>(n)});
  p.volume = polygon_area(n, r) * h / 3;
  return p;
}

Hull bipyramid(int n, double r, double h) {
  Hull p;
  p.name = std::to_string(n) + "-gon bipyramid (" + std::to_string(n + 2) + " points)";
  ring(p, n, r, 0);
  p.points.insert(p.points.end(), {0, 0, h});
  p.points.insert(p.points.end(), {0, 0, -h});
  for (int i = 0; i < n; ++i) {
    const unsigned a = static_cast<unsigned>(i), b = static_cast<unsigned>((i + 1) % n);
    add_face(p, {a, b, static_cast<unsigned>(n)});
    add_face(p, {a, b, static_cast<unsigned>(n + 1)});
  }
  p.volume = 2 * polygon_area(n, r) * h / 3;
  return p;
}

const std::vector<Hull> &pile_hulls() {
  static const std::vector<Hull> hulls = {prism(6, 0.07, 0.1), bipyramid(10, 0.07, 0.09), pyramid(24, 0.07, 0.14),
                                          bipyramid(48, 0.06, 0.08), prism(100, 0.06, 0.1)};
  return hulls;
}

World::World(const Settings &s) : settings(s) {
  world = dWorldCreate();
  space = dHashSpaceCreate(0);
  group = dJointGroupCreate(0);
  dWorldSetGravity(world, 0, 0, -9.81);
  dWorldSetERP(world, s.erp);
  dWorldSetCFM(world, s.cfm);
  dWorldSetQuickStepNumIterations(world, s.iterations);
  dWorldSetContactSurfaceLayer(world, 0.0);
  dWorldSetLinearDamping(world, s.linear_damping);
  dWorldSetAngularDamping(world, s.angular_damping);
}

World::~World() {
  for (const Body &b : bodies) dcol_ode::forget(b.geom);
  dJointGroupDestroy(group);
  dSpaceDestroy(space);  // destroys the geoms it holds (cleanup mode on)
  dWorldDestroy(world);
}

void World::near(void *self, dGeomID o1, dGeomID o2) {
  World *w = static_cast<World *>(self);
  dBodyID b1 = dGeomGetBody(o1), b2 = dGeomGetBody(o2);
  if (!b1 && !b2) return;
  dContact c[16];
  const int max = std::min(w->settings.max_contacts, 16);
  int n;
  Narrow &s = w->narrow;
  if (w->time_narrow) {
    const auto t0 = std::chrono::steady_clock::now();
    n = dCollide(o1, o2, max, &c[0].geom, sizeof(dContact));
    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    s.seconds += dt;
    if (w->keep_samples) s.samples.push_back(dt);
    int c1 = dGeomGetClass(o1), c2 = dGeomGetClass(o2);
    if (c1 > c2) std::swap(c1, c2);
    if (c1 < 16 && c2 < 16) {
      ++s.pair_calls[c1][c2];
      s.pair_empty[c1][c2] += n == 0;
      s.pair_seconds[c1][c2] += dt;
    }
  } else {
    n = dCollide(o1, o2, max, &c[0].geom, sizeof(dContact));
  }
  ++s.calls;
  s.contacts += static_cast<unsigned long>(n);
  for (int i = 0; i < n; ++i) {
    c[i].surface.mode = dContactApprox1;
    c[i].surface.mu = w->settings.mu;
    dJointID j = dJointCreateContact(w->world, w->group, &c[i]);
    dJointAttach(j, b1, b2);
  }
}

void World::step() {
  dSpaceCollide(space, this, &near);
  dWorldQuickStep(world, settings.dt);
  dJointGroupEmpty(group);
}

Body &World::add(Kind kind, const double size[3], const Hull *hull, const double pos[3], const dQuaternion q,
                 bool recorded) {
  Body b;
  b.kind = kind;
  b.hull = hull;
  for (int k = 0; k < 3; ++k) {
    b.size[k] = size ? size[k] : 0;
    b.start[k] = pos[k];
  }
  b.body = dBodyCreate(world);
  dMass m;
  switch (kind) {
    case kSphere:
      b.geom = dCreateSphere(space, size[0]);
      dMassSetSphere(&m, kDensity, size[0]);
      break;
    case kBox:
      b.geom = dCreateBox(space, size[0], size[1], size[2]);
      dMassSetBox(&m, kDensity, size[0], size[1], size[2]);
      break;
    case kCapsule:
      b.geom = dCreateCapsule(space, size[0], size[1]);
      dMassSetCapsule(&m, kDensity, 3, size[0], size[1]);
      break;
    case kCylinder:
      b.geom = dCreateCylinder(space, size[0], size[1]);
      dMassSetCylinder(&m, kDensity, 3, size[0], size[1]);
      break;
    default: {
      const Hull &h = *hull;
      b.geom = recorded ? dcol_ode::create_convex(space, h.planes.data(), h.plane_count, h.points.data(), h.point_count(),
                                                  h.polygons.data())
                        : dCreateConvex(space, h.planes.data(), h.plane_count, h.points.data(), h.point_count(),
                                        h.polygons.data());
      // Mass from the hull's volume, inertia of its bounding box (the same in both runs).
      double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
      for (unsigned i = 0; i < h.point_count(); ++i)
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], h.points[3 * i + k]);
          hi[k] = std::max(hi[k], h.points[3 * i + k]);
        }
      dMassSetBoxTotal(&m, kDensity * h.volume, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
      break;
    }
  }
  dBodySetMass(b.body, &m);
  dGeomSetBody(b.geom, b.body);
  dBodySetPosition(b.body, pos[0], pos[1], pos[2]);
  dBodySetQuaternion(b.body, q);
  bodies.push_back(b);
  return bodies.back();
}

void build_pyramid(World &w, bool) {
  dCreatePlane(w.space, 0, 0, 1, 0);
  const double s = 0.2, pitch = 0.21;
  const double size[3] = {s, s, s};
  const dQuaternion q = {1, 0, 0, 0};
  for (int layer = 0; layer < 10; ++layer) {
    const int n = 10 - layer;
    for (int j = 0; j < n; ++j) {
      const double pos[3] = {(j - 0.5 * (n - 1)) * pitch, 0, 0.5 * s + layer * s};
      w.add(kBox, size, nullptr, pos, q, false);
    }
  }
}

void build_pile(World &w, unsigned seed, bool recorded_hulls) {
  // The floor and the four walls are ODE's planes (normals into the bin): against a plane ODE's
  // own convex collider gives a contact per vertex below it, where its libccd colliders against a
  // box give one (see docs/ode.md).
  dCreatePlane(w.space, 0, 0, 1, 0);
  const double half = 0.5 * kBinInner;
  dCreatePlane(w.space, 1, 0, 0, -half);
  dCreatePlane(w.space, -1, 0, 0, -half);
  dCreatePlane(w.space, 0, 1, 0, -half);
  dCreatePlane(w.space, 0, -1, 0, -half);
  unsigned long long state = 0x9E3779B97F4A7C15ULL * (seed + 1);
  auto unif = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  const std::vector<Hull> &hulls = pile_hulls();
  int hull_next = 0;
  // 4 layers of 4 x 3 cells, 0.225 x 0.3 m each: 48 bodies, bounding radius <= 0.1 m.
  for (int i = 0; i < 48; ++i) {
    const int layer = i / 12, cell = i % 12;
    const double pos[3] = {-0.3375 + 0.225 * (cell % 4) + 0.02 * (unif() - 0.5),
                           -0.3 + 0.3 * (cell / 4) + 0.02 * (unif() - 0.5), 0.2 + 0.25 * layer};
    dQuaternion q = {unif() - 0.5, unif() - 0.5, unif() - 0.5, unif() - 0.5};
    dNormalize4(q);
    const int kind = i % 6;
    Body *b = nullptr;
    if (kind == 0) {
      const double size[3] = {0.06 + 0.02 * unif(), 0, 0};
      b = &w.add(kSphere, size, nullptr, pos, q, false);
    } else if (kind == 1) {
      const double size[3] = {0.16, 0.12, 0.1};
      b = &w.add(kBox, size, nullptr, pos, q, false);
    } else if (kind == 2) {
      const double size[3] = {0.04, 0.12, 0};
      b = &w.add(kCapsule, size, nullptr, pos, q, false);
    } else if (kind == 3) {
      const double size[3] = {0.06, 0.1, 0};
      b = &w.add(kCylinder, size, nullptr, pos, q, false);
    } else {
      b = &w.add(kHull, nullptr, &hulls[hull_next++ % hulls.size()], pos, q, recorded_hulls);
    }
    dBodySetLinearVel(b->body, 0.5 * (unif() - 0.5), 0.5 * (unif() - 0.5), 0);
  }
}

dcol_shape *check_shape(const Body &b, dcol_pose *pose) {
  const dReal *p = dBodyGetPosition(b.body);
  const dReal *q = dBodyGetQuaternion(b.body);
  for (int k = 0; k < 3; ++k) pose->position[k] = p[k];
  for (int k = 0; k < 4; ++k) pose->quaternion[k] = q[k];
  dcol_shape *s = nullptr;
  switch (b.kind) {
    case kSphere: dcol_shape_new_sphere(b.size[0], &s); break;
    case kBox: dcol_shape_new_box(0.5 * b.size[0], 0.5 * b.size[1], 0.5 * b.size[2], &s); break;
    case kCapsule:
    case kCylinder: {
      if (b.kind == kCapsule)
        dcol_shape_new_capsule(b.size[0], b.size[1], &s);
      else
        dcol_shape_new_cylinder(b.size[0], b.size[1], &s);
      // dcol's axis is body x, ODE's z: turn x onto z (a quarter turn about y).
      const dQuaternion x_to_z = {std::sqrt(0.5), 0, -std::sqrt(0.5), 0};
      dQuaternion out;
      dQMultiply0(out, q, x_to_z);
      for (int k = 0; k < 4; ++k) pose->quaternion[k] = out[k];
      break;
    }
    default: {
      // The hull of the points (about the origin, inside every pile hull).
      const Hull &h = *b.hull;
      std::vector<double> pts(h.points.begin(), h.points.end());
      dcol_shape_new_convex_hull(pts.data(), h.point_count(), 0.0, &s);
      break;
    }
  }
  return s;
}

}  // namespace ode_scenes
