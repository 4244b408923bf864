// dcol_ode::use_dcol(): dcol answering dCollide for ODE's own geoms. Checks, each against an
// independent answer (closed forms, ODE's own colliders computed before the override, or the same
// pair asked in the other order):
//   - before use_dcol() no call reaches dcol; after it, every pair among sphere, box, capsule,
//     cylinder, recorded convex and plane does, in both argument orders;
//   - depth and normal: analytic for every class against ODE's plane (tilted, both sides) and for
//     sphere-sphere and sphere-box, and against ODE's own exact colliders (sphere-box,
//     sphere-capsule, box-box, capsule-capsule, box-plane) on random overlapping poses;
//   - the argument order: dCollide(b, a) is dCollide(a, b) with the normal turned and g1, g2 swapped;
//   - ODE's axis convention (capsules and cylinders along z) and geom offsets (dGeomSetOffset*);
//   - the contact count (flags & 0xffff, down to 1) and the `skip` stride;
//   - dGeomBoxSetLengths after the shape was cached; a capsule of length 0;
//   - pairs dcol cannot take (NaN pose, zero size): no contacts, counted, nothing on stderr;
//   - convexes: ode_convex_tests.cpp;
//   - many box pairs (more than the collider's tables hold, past the hint map's pruning; lengths
//     changing): every call's contacts dcol_contacts' (to 1e-12, most bit for bit);
//   - the dcol geom class against ODE's box.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "engine_scenes.hpp"
#include "override_test_util.hpp"

namespace {

using namespace override_test;

// Every class against a tilted plane, the plane on either side: one contact at least, the
// deepest depth the analytic one, every normal the plane's (into the geom given first).
void plane_analytic() {
  const double n0[3] = {0.2, -0.3, 1.0};
  const double len = std::sqrt(0.04 + 0.09 + 1.0);
  const double n[3] = {n0[0] / len, n0[1] / len, n0[2] / len};
  const double d = 0.1;
  const int classes[5] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass};
  double worst = 0;
  int cases = 0;
  for (int cls : classes) {
    for (int k = 0; k < 50; ++k) {
      dGeomID plane = dCreatePlane(0, n0[0], n0[1], n0[2], d * len);
      dGeomID g = make_geom(cls);
      dMatrix3 R;
      random_rotation(R);
      dGeomSetRotation(g, R);
      dGeomSetPosition(g, unif(-1, 1), unif(-1, 1), 0);
      // Put the lowest point a random depth in [0.001, 0.05] below the plane.
      const double depth = unif(0.001, 0.05);
      const double h = lowest(g, n, d);
      const dReal *p = dGeomGetPosition(g);
      dGeomSetPosition(g, p[0] - (h + depth) * n[0], p[1] - (h + depth) * n[1], p[2] - (h + depth) * n[2]);
      for (int order = 0; order < 2; ++order) {
        dContactGeom c[8];
        const int m = order == 0 ? dCollide(g, plane, 8, c, sizeof(dContactGeom)) : dCollide(plane, g, 8, c, sizeof(dContactGeom));
        bool ok = m >= 1;
        double ndev = 0;
        for (int i = 0; i < m; ++i) {
          const double s = order == 0 ? 1.0 : -1.0;  // into the first geom
          for (int j = 0; j < 3; ++j) ndev = std::max(ndev, std::fabs(c[i].normal[j] - s * n[j]));
          ok = ok && c[i].g1 == (order == 0 ? g : plane) && c[i].g2 == (order == 0 ? plane : g);
        }
        const double err = m >= 1 ? std::fabs(max_depth(c, m) - depth) : 1;
        worst = std::max(worst, std::max(err, ndev));
        ++cases;
        if (!ok || err > 1e-9 || ndev > 1e-12)
          std::printf("  %s vs plane (order %d): %d contacts, depth %.12f want %.12f, normal off by %.2e\n",
                      class_name(cls), order, m, m ? max_depth(c, m) : 0.0, depth, ndev);
        expect(ok && err <= 1e-9 && ndev <= 1e-12, std::string(class_name(cls)) + " against a tilted plane: analytic depth and normal");
      }
      destroy(g);
      destroy(plane);
    }
  }
  std::printf("plane: %d cases (5 classes, both orders), worst depth/normal error %.2e\n", cases, worst);
}

// ODE's own answers before the override, then dcol's on the same poses: the deepest depth and the
// normal agree where ODE's collider gives the penetration depth exactly (sphere-sphere,
// sphere-box, sphere-capsule, capsule-capsule; box-box is checked against the separating axes).
struct Saved {
  int c1, c2;
  dReal p1[3], p2[3];
  dMatrix3 R1, R2;
  Answer native;
};
std::vector<Saved> g_saved;

void record_native(int c1, int c2, double reach, int count) {
  for (int k = 0; k < count; ++k) {
    dGeomID a = make_geom(c1), b = make_geom(c2);
    random_pose_pair(a, b, reach);
    Saved s;
    s.c1 = c1;
    s.c2 = c2;
    std::memcpy(s.p1, dGeomGetPosition(a), sizeof s.p1);
    std::memcpy(s.p2, dGeomGetPosition(b), sizeof s.p2);
    std::memcpy(s.R1, dGeomGetRotation(a), sizeof(dMatrix3));
    std::memcpy(s.R2, dGeomGetRotation(b), sizeof(dMatrix3));
    s.native.n = dCollide(a, b, 8, s.native.c, sizeof(dContactGeom));
    g_saved.push_back(s);
    destroy(a);
    destroy(b);
  }
}

// Two boxes: the penetration depth is the least overlap over the 15 separating axes (the faces'
// normals and the edges' cross products), the normal that axis (brute force, independent of dcol
// and of ODE's dBoxBox, which prefers a face axis unless an edge axis is 5 % shallower).
double sat_depth(const dReal *p1, const dReal *R1, const dReal *p2, const dReal *R2, const double h1[3],
                 const double h2[3], double normal[3]) {
  double axes[15][3];
  int n = 0;
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 3; ++k) axes[n][k] = R1[4 * k + j];
    ++n;
    for (int k = 0; k < 3; ++k) axes[n][k] = R2[4 * k + j];
    ++n;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double a[3] = {R1[i], R1[4 + i], R1[8 + i]}, b[3] = {R2[j], R2[4 + j], R2[8 + j]};
      axes[n][0] = a[1] * b[2] - a[2] * b[1];
      axes[n][1] = a[2] * b[0] - a[0] * b[2];
      axes[n][2] = a[0] * b[1] - a[1] * b[0];
      ++n;
    }
  double best = 1e300;
  for (int i = 0; i < n; ++i) {
    double *u = axes[i];
    const double l = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    if (l < 1e-9) continue;
    for (int k = 0; k < 3; ++k) u[k] /= l;
    double r = 0;
    for (int j = 0; j < 3; ++j) {
      r += h1[j] * std::fabs(u[0] * R1[j] + u[1] * R1[4 + j] + u[2] * R1[8 + j]);
      r += h2[j] * std::fabs(u[0] * R2[j] + u[1] * R2[4 + j] + u[2] * R2[8 + j]);
    }
    const double c = u[0] * (p2[0] - p1[0]) + u[1] * (p2[1] - p1[1]) + u[2] * (p2[2] - p1[2]);
    const double overlap = r - std::fabs(c);
    if (overlap < best) {
      best = overlap;
      const double s = c >= 0 ? -1.0 : 1.0;  // into box 1: from box 2 towards box 1
      for (int k = 0; k < 3; ++k) normal[k] = s * u[k];
    }
  }
  return best;
}

// Box-box on random overlapping poses: dcol's deepest depth and normal are the separating-axis
// brute force's (ODE's dBoxBox is reported alongside: it picks a face axis unless an edge axis is
// 5 % shallower, so it overestimates edge-edge depths by up to 5 %).
void box_box_sat() {
  const double h[3] = {0.25, 0.2, 0.15};
  double worst_depth = 0, worst_normal = 0, ode_worst = 0;
  int cases = 0;
  for (const Saved &s : g_saved) {
    if (s.c1 != dBoxClass || s.c2 != dBoxClass) continue;
    dGeomID a = make_geom(dBoxClass), b = make_geom(dBoxClass);
    dGeomSetPosition(a, s.p1[0], s.p1[1], s.p1[2]);
    dGeomSetRotation(a, s.R1);
    dGeomSetPosition(b, s.p2[0], s.p2[1], s.p2[2]);
    dGeomSetRotation(b, s.R2);
    double normal[3];
    const double want = sat_depth(s.p1, s.R1, s.p2, s.R2, h, h, normal);
    Answer ours;
    ours.n = dCollide(a, b, 8, ours.c, sizeof(dContactGeom));
    if (want > 0) {
      ++cases;
      const double dd = ours.n ? std::fabs(max_depth(ours.c, ours.n) - want) : 1;
      double nd = ours.n ? 0 : 1;
      for (int k = 0; ours.n && k < 3; ++k) nd = std::max(nd, std::fabs(ours.c[0].normal[k] - normal[k]));
      worst_depth = std::max(worst_depth, dd);
      worst_normal = std::max(worst_normal, nd);
      if (s.native.n) ode_worst = std::max(ode_worst, (max_depth(s.native.c, s.native.n) - want) / want);
    }
    destroy(a);
    destroy(b);
  }
  std::printf("box-box against the separating-axis brute force: %d overlapping cases, worst depth difference %.2e, "
              "normal %.2e (ODE's dBoxBox: depth up to %.1f %% deeper)\n",
              cases, worst_depth, worst_normal, 100 * ode_worst);
  expect(cases >= 120 && worst_depth <= 1e-9 && worst_normal <= 1e-6, "box-box: dcol's depth and normal are the exact ones");
}

void compare_native() {
  struct Worst {
    double depth = 0, normal = 0;
    int cases = 0, apart = 0, apart_agree = 0;
  } w[5][5];
  for (const Saved &s : g_saved) {
    if (s.c1 == dBoxClass && s.c2 == dBoxClass) continue;  // box_box_sat()
    dGeomID a = make_geom(s.c1), b = make_geom(s.c2);
    dGeomSetPosition(a, s.p1[0], s.p1[1], s.p1[2]);
    dGeomSetRotation(a, s.R1);
    dGeomSetPosition(b, s.p2[0], s.p2[1], s.p2[2]);
    dGeomSetRotation(b, s.R2);
    Answer ours;
    ours.n = dCollide(a, b, 8, ours.c, sizeof(dContactGeom));
    Worst &wc = w[s.c1][s.c2];
    if (s.native.n == 0) {
      // Apart by ODE's exact collider: no contact from dcol either.
      ++wc.apart;
      wc.apart_agree += ours.n == 0;
    } else {
      ++wc.cases;
      const double dd = ours.n > 0 ? std::fabs(max_depth(ours.c, ours.n) - max_depth(s.native.c, s.native.n)) : 1;
      double nd = 1;
      if (ours.n > 0) {
        nd = 0;
        for (int j = 0; j < 3; ++j) nd = std::max(nd, std::fabs(ours.c[0].normal[j] - s.native.c[0].normal[j]));
      }
      wc.depth = std::max(wc.depth, dd);
      wc.normal = std::max(wc.normal, nd);
      if (dd > 1e-7 || nd > 1e-6)
        std::printf("  %s-%s: dcol %d contacts depth %.9f normal (%.6f %.6f %.6f); ODE %d depth %.9f normal (%.6f %.6f %.6f)\n",
                    class_name(s.c1), class_name(s.c2), ours.n, ours.n ? max_depth(ours.c, ours.n) : 0.0, ours.c[0].normal[0],
                    ours.c[0].normal[1], ours.c[0].normal[2], s.native.n, max_depth(s.native.c, s.native.n),
                    s.native.c[0].normal[0], s.native.c[0].normal[1], s.native.c[0].normal[2]);
    }
    destroy(a);
    destroy(b);
  }
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const Worst &wc = w[i][j];
      if (wc.cases + wc.apart == 0) continue;
      std::printf("against ODE's own %s-%s collider: %d overlapping poses, worst depth difference %.2e, normal %.2e; "
                  "%d apart, %d of them apart for dcol too\n",
                  class_name(i), class_name(j), wc.cases, wc.depth, wc.normal, wc.apart, wc.apart_agree);
      expect(wc.cases >= 20, std::string("enough overlapping ") + class_name(i) + "-" + class_name(j) + " poses");
      expect(wc.apart_agree == wc.apart, std::string("apart for ODE, apart for dcol: ") + class_name(i) + "-" + class_name(j));
      expect(wc.depth <= 1e-7 && wc.normal <= 1e-6,
             std::string("dcol's depth and normal are ODE's for ") + class_name(i) + "-" + class_name(j));
    }
}

// dCollide(b, a) is dCollide(a, b) with normals turned and g1, g2 swapped, for every pair.
void argument_order() {
  const int classes[6] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass, dPlaneClass};
  int pairs = 0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      if (classes[i] == dPlaneClass && classes[j] == dPlaneClass) continue;
      int agree = 0, tried = 0;
      for (int k = 0; k < 20; ++k) {
        dGeomID a = make_geom(classes[i]), b = make_geom(classes[j]);
        if (classes[i] == dPlaneClass) {
          random_attitude(b);
          dGeomSetPosition(b, unif(-1, 1), unif(-1, 1), unif(0.05, 0.2));
        } else if (classes[j] == dPlaneClass) {
          random_attitude(a);
          dGeomSetPosition(a, unif(-1, 1), unif(-1, 1), unif(0.05, 0.2));
        } else {
          random_pose_pair(a, b, 0.7);
        }
        const unsigned long before = dcol_ode::collider_calls();
        dContactGeom x[8], y[8];
        const int nx = dCollide(a, b, 8, x, sizeof(dContactGeom));
        const int ny = dCollide(b, a, 8, y, sizeof(dContactGeom));
        expect(dcol_ode::collider_calls() == before + 2,
               std::string("dcol answers ") + class_name(classes[i]) + "-" + class_name(classes[j]) + " in both orders");
        ++tried;
        // The same count, the normal turned, g1 and g2 swapped and the same deepest depth. (The
        // points themselves may differ: the manifold's reference face may change with the order.)
        bool ok = nx == ny && (nx == 0 || std::fabs(max_depth(x, nx) - max_depth(y, ny)) < 1e-9);
        for (int c = 0; ok && c < nx; ++c) {
          ok = x[c].g1 == a && x[c].g2 == b && y[c].g1 == b && y[c].g2 == a;
          for (int m = 0; m < 3; ++m) ok = ok && std::fabs(x[c].normal[m] + y[c].normal[m]) < 1e-9;
        }
        if (ok) ++agree;
        else {
          std::printf("  order %s-%s: %d vs %d contacts\n", class_name(classes[i]), class_name(classes[j]), nx, ny);
          for (int c = 0; c < std::max(nx, ny); ++c)
            std::printf("    x depth %.9f n (%.6f %.6f %.6f) p (%.6f %.6f %.6f) | y depth %.9f n (%.6f %.6f %.6f) p (%.6f %.6f %.6f)\n",
                        x[c].depth, x[c].normal[0], x[c].normal[1], x[c].normal[2], x[c].pos[0], x[c].pos[1], x[c].pos[2],
                        y[c].depth, y[c].normal[0], y[c].normal[1], y[c].normal[2], y[c].pos[0], y[c].pos[1], y[c].pos[2]);
        }
        destroy(a);
        destroy(b);
      }
      ++pairs;
      expect(agree == tried, std::string("argument order ") + class_name(classes[i]) + "-" + class_name(classes[j]));
    }
  std::printf("argument order: %d ordered class pairs, 20 poses each, dCollide(b, a) = dCollide(a, b) turned\n", pairs);
}

// ODE's axis convention and offsets: a capsule and a cylinder lying along the world x axis on the
// plane z = 0 (geom along z turned by an offset rotation of the body), their offset moving them.
void axes_and_offsets() {
  dWorldID world = dWorldCreate();
  for (int cls : {dCapsuleClass, dCylinderClass, dBoxClass}) {
    dBodyID body = dBodyCreate(world);
    dBodySetPosition(body, 1.0, 2.0, 3.0);
    dQuaternion qb = {std::cos(0.35), 0, 0, std::sin(0.35)};  // body turned 40 degrees about z
    dBodySetQuaternion(body, qb);
    dGeomID g = make_geom(cls);
    dGeomSetBody(g, body);
    // The offset lays the geom's z axis along the body's x axis and moves it 0.3 along body y.
    dQuaternion qo = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};
    dGeomSetOffsetQuaternion(g, qo);
    dGeomSetOffsetPosition(g, 0.0, 0.3, 0.0);
    const dReal *p = dGeomGetPosition(g);
    // The geom's centre: body position + Rz(40 deg) (0, 0.3, 0).
    const double cx = 1.0 - 0.3 * std::sin(0.7), cy = 2.0 + 0.3 * std::cos(0.7);
    expect(std::fabs(p[0] - cx) < 1e-12 && std::fabs(p[1] - cy) < 1e-12 && std::fabs(p[2] - 3.0) < 1e-12,
           "dGeomGetPosition is the body's position with the offset turned by the body");
    // Lying on its side: its lowest point is its radius (box: half of its z length, now along
    // world -x... the box's z side of 0.3 lies horizontal, its x side 0.5 vertical).
    double half_height = 0;
    if (cls == dCapsuleClass) half_height = 0.15;
    if (cls == dCylinderClass) half_height = 0.2;
    if (cls == dBoxClass) half_height = 0.25;
    const double depth = 0.004;
    dBodySetPosition(body, 1.0, 2.0, half_height - depth);
    dGeomID plane = dCreatePlane(0, 0, 0, 1, 0);
    dContactGeom c[8];
    const int n = dCollide(g, plane, 8, c, sizeof(dContactGeom));
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (int i = 0; i < n; ++i) {
      xmin = std::min(xmin, c[i].pos[0]);
      xmax = std::max(xmax, c[i].pos[0]);
      ymin = std::min(ymin, c[i].pos[1]);
      ymax = std::max(ymax, c[i].pos[1]);
    }
    std::printf("offset %s on its side: %d contacts, depth %.6f (want %.6f), contact x in [%.4f, %.4f], y in [%.4f, %.4f]\n",
                class_name(cls), n, n ? max_depth(c, n) : 0.0, depth, xmin, xmax, ymin, ymax);
    expect(n >= 2 && std::fabs(max_depth(c, n) - depth) < 1e-9, std::string("offset ") + class_name(cls) + ": depth");
    // The contacts spread along the geom's axis, i.e. along the body's x axis turned 40 degrees:
    // their span in x and y is the axis length times (cos 40, sin 40) (capsule: the segment
    // between its end balls; cylinder: its length; box: its z side).
    double along = 0.5;
    if (cls == dBoxClass) along = 0.3;
    const double cxp = 1.0 - 0.3 * std::sin(0.7), cyp = 2.0 + 0.3 * std::cos(0.7);
    expect(std::fabs((xmax - xmin) - along * std::cos(0.7) - (cls == dBoxClass ? 0.4 * std::sin(0.7) : 0)) < 1e-6 &&
               std::fabs(0.5 * (xmin + xmax) - cxp) < 1e-6 && std::fabs(0.5 * (ymin + ymax) - cyp) < 1e-6,
           std::string("offset ") + class_name(cls) + ": contacts along the turned axis, around the offset centre");
    destroy(plane);
    destroy(g);
  }
  dWorldDestroy(world);
}

// The contact count (flags & 0xffff) and the stride: a box resting flat on a larger box gives 4
// corners; asking for k writes min(k, 4), each `skip` bytes apart, and nothing in between.
void count_and_skip() {
  dGeomID top = dCreateBox(0, 0.4, 0.4, 0.4);
  dGeomID base = dCreateBox(0, 2, 2, 1);
  dGeomSetPosition(base, 0, 0, -0.5);
  dGeomSetPosition(top, 0.1, 0.05, 0.2 - 0.003);
  struct Padded {
    dContactGeom geom;
    unsigned char pad[40];
  };
  for (int k : {1, 2, 3, 4, 8, 16}) {
    Padded buf[16];
    std::memset(buf, 0xAB, sizeof buf);
    const int n = dCollide(top, base, k, &buf[0].geom, sizeof(Padded));
    bool pads = true;
    for (int i = 0; i < 16; ++i)
      for (unsigned char b : buf[i].pad) pads = pads && b == 0xAB;
    bool untouched = true;
    for (int i = n; i < 16; ++i) {
      const unsigned char *raw = reinterpret_cast<const unsigned char *>(&buf[i].geom);
      for (std::size_t j = 0; j < sizeof(dContactGeom); ++j) untouched = untouched && raw[j] == 0xAB;
    }
    bool depths = true;
    for (int i = 0; i < n; ++i) depths = depths && std::fabs(buf[i].geom.depth - 0.003) < 1e-9 && buf[i].geom.normal[2] > 0.999999;
    std::printf("count %2d: %d contacts written, padding intact %d, slots past the count untouched %d\n", k, n, pads, untouched);
    expect(n == std::min(k, 4) && pads && untouched && depths, "contact count and stride");
  }
  destroy(top);
  destroy(base);
}

// dGeomBoxSetLengths after the box's shape was cached; a capsule of length 0 (a sphere).
void parameters_change() {
  dGeomID box = dCreateBox(0, 0.4, 0.4, 0.4);
  dGeomID plane = dCreatePlane(0, 0, 0, 1, 0);
  dGeomSetPosition(box, 0, 0, 0.19);
  dContactGeom c[4];
  int n = dCollide(box, plane, 4, c, sizeof(dContactGeom));
  expect(n == 4 && std::fabs(c[0].depth - 0.01) < 1e-12, "box on the plane: depth 0.01");
  dGeomBoxSetLengths(box, 0.4, 0.4, 0.6);
  n = dCollide(box, plane, 4, c, sizeof(dContactGeom));
  std::printf("box lengths changed: %d contacts, depth %.6f (want 0.11)\n", n, n ? c[0].depth : 0.0);
  expect(n == 4 && std::fabs(c[0].depth - 0.11) < 1e-12, "dGeomBoxSetLengths: the new size answers");
  dGeomID cap = dCreateCapsule(0, 0.2, 0.0);
  dGeomSetPosition(cap, 0, 0, 0.15);
  n = dCollide(cap, plane, 4, c, sizeof(dContactGeom));
  expect(n == 1 && std::fabs(c[0].depth - 0.05) < 1e-12, "a capsule of length 0 is a sphere");
  destroy(cap);
  destroy(box);
  destroy(plane);
}

// Pairs dcol cannot take: no contacts, counted, nothing printed on stderr.
void rejected_pairs() {
  std::fflush(stderr);
  char path[] = "/tmp/dcol_ode_stderr_XXXXXX";
  const int fd = mkstemp(path);
  const int saved = dup(2);
  dup2(fd, 2);
  const dcol_ode::Stats before = dcol_ode::stats();
  dGeomID a = dCreateSphere(0, 0.3), b = dCreateBox(0, 0.5, 0.5, 0.5);
  dGeomID plane = dCreatePlane(0, 0, 0, 1, 0);
  dGeomSetPosition(a, NAN, 0, 0);
  dContactGeom c[4];
  int total = 0;
  for (int k = 0; k < 100; ++k) {
    total += dCollide(a, b, 4, c, sizeof(dContactGeom));
    total += dCollide(b, a, 4, c, sizeof(dContactGeom));
    total += dCollide(a, plane, 4, c, sizeof(dContactGeom));
  }
  dGeomID flat = dCreateBox(0, 0.5, 0.0, 0.5);  // zero width
  dGeomSetPosition(flat, 0.1, 0, 0);
  dGeomSetPosition(a, 0, 0, 0);
  for (int k = 0; k < 100; ++k) total += dCollide(flat, a, 4, c, sizeof(dContactGeom));
  // The plane pairs' closed forms: a box, capsule and cylinder with a NaN position, and with a
  // NaN quaternion, each in both orders against the plane. (A NaN radius cannot be set here:
  // this libode's dGeomCapsuleSetParams asserts; the adapter refuses non-finite sizes anyway.)
  dGeomID cap = dCreateCapsule(0, 0.2, 0.6), cyl = dCreateCylinder(0, 0.3, 0.8);
  dGeomID solids[3] = {b, cap, cyl};
  const dReal nan_q[4] = {NAN, 0, 0, 1};
  for (dGeomID s : solids) {
    dGeomSetPosition(s, NAN, 0, 0.1);
    total += dCollide(s, plane, 4, c, sizeof(dContactGeom)) + dCollide(plane, s, 4, c, sizeof(dContactGeom));
    dGeomSetPosition(s, 0, 0, 0.1);
    dGeomSetQuaternion(s, nan_q);
    total += dCollide(s, plane, 4, c, sizeof(dContactGeom)) + dCollide(plane, s, 4, c, sizeof(dContactGeom));
  }

  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  const long size = lseek(fd, 0, SEEK_END);
  close(fd);
  std::remove(path);
  const dcol_ode::Stats after = dcol_ode::stats();
  std::printf("rejected pairs: %d contacts written, %lu counted rejected, %ld bytes on stderr\n", total,
              after.rejected - before.rejected, size);
  expect(total == 0 && after.rejected - before.rejected == 400 + 12 && size == 0,
         "NaN pose and zero size: no contacts, every pair counted, nothing printed");
  destroy(cap);
  destroy(cyl);
  destroy(a);
  destroy(b);
  destroy(flat);
  destroy(plane);
}

// The collider's shortcut: a pair without contacts at its last call is first asked
// dcol_alpha_below(1 + 1e-6). Near touching, in and out of contact again and again (the same geom
// pair, so its hint flips), dCollide must report contacts exactly when dcol_contacts on the same
// shapes and poses does, with the same deepest depth.
void near_touching() {
  const int classes[5] = {dSphereClass, dBoxClass, dCapsuleClass, dCylinderClass, dConvexClass};
  const double gaps[6] = {-1e-4, -1e-7, -1e-10, 1e-10, 1e-7, 1e-4};
  int cases = 0, agree = 0, touching = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = i; j < 5; ++j) {
      dGeomID a = make_geom(classes[i]), b = make_geom(classes[j]);
      for (int k = 0; k < 12; ++k) {
        random_pose_pair(a, b, 0.7);
        dcol_pose pa, pb;
        const dcol_shape *sa = dcol_ode::shape_of(a, &pa), *sb = dcol_ode::shape_of(b, &pb);
        dcol_signed_distance_result r;
        if (!sa || !sb || dcol_signed_distance(sa, &pa, sb, &pb, nullptr, &r) != DCOL_OK) continue;
        const dReal *p = dGeomGetPosition(b);
        const double base[3] = {p[0], p[1], p[2]};
        for (double gap : gaps) {
          // Move b along the normal so that the signed distance becomes about `gap`.
          const double t = gap - r.distance;
          dGeomSetPosition(b, base[0] + t * r.normal[0], base[1] + t * r.normal[1], base[2] + t * r.normal[2]);
          dcol_ode::shape_of(b, &pb);
          // dcol_contacts in both argument orders: ODE hands an override of a class against itself
          // the geoms reversed, and between orders dcol's depth may differ in the last bits (by up
          // to 7e-12 m for two cylinders) and its manifold in the number of points.
          dcol_contact cs[8];
          std::size_t n = 0, n2 = 0;
          dcol_contacts(sa, &pa, sb, &pb, 0.0, nullptr, cs, 8, &n);
          double want = -1e300, want2 = -1e300;
          for (std::size_t q = 0; q < n; ++q) want = std::max(want, cs[q].depth);
          dcol_contacts(sb, &pb, sa, &pa, 0.0, nullptr, cs, 8, &n2);
          for (std::size_t q = 0; q < n2; ++q) want2 = std::max(want2, cs[q].depth);
          dContactGeom c[8];
          const int m = dCollide(a, b, 8, c, sizeof(dContactGeom));
          ++cases;
          touching += n > 0;
          const bool depth_ok = std::fabs(max_depth(c, m) - want) < 1e-12 || std::fabs(max_depth(c, m) - want2) < 1e-12;
          const std::size_t mm = static_cast<std::size_t>(m);
          if ((m > 0) == (n > 0) && (n > 0) == (n2 > 0) && (mm == n || mm == n2) && (n == 0 || depth_ok)) {
            ++agree;
          } else {
            std::printf("  %s-%s gap %.0e: dCollide %d contacts (deepest %.15f), dcol_contacts %zu (%.15f)\n",
                        class_name(classes[i]), class_name(classes[j]), gap, m, m ? max_depth(c, m) : 0.0, n, want);
          }
        }
      }
      destroy(a);
      destroy(b);
    }
  std::printf("near touching: %d poses (signed distance -1e-4 to 1e-4, the same pairs in and out of contact), %d with "
              "contacts, %d as dcol_contacts\n",
              cases, touching, agree);
  expect(cases > 800 && agree == cases, "the alpha_below shortcut never changes dcol_contacts' answer");
}

// Many box pairs through the collider's per-pair and per-geom tables (1024 entries each, indexed
// by hashes: more pairs and geoms than entries, so entries are shared and replaced; past 2^16
// calls, when old pairs leave the hint map and the pair table is emptied): every call's contacts
// are dcol_contacts' (no cache) on shape_of's shapes and poses (normal turned into o1): the same
// count, every number within 1e-12 (the pair's warm cache may move the general path's answers by
// rounding; a shape, radius or hint of another geom or pair moves them by the sizes, 0.1 and
// more), most of them bit for bit (the boxes' closed form, the same with or without a cache).
// Every fourth geom changes its lengths between rounds (0.15 <-> 0.6 a side), so a bounding
// radius kept for its old sizes would drop contacts its new sizes make, or keep the small shape.
void many_pairs() {
  const int kGeoms = 1200, kPairs = 2400, kRounds = 30;  // 72 000 calls
  std::vector<dGeomID> geoms;
  for (int i = 0; i < kGeoms; ++i) {
    const double side = i % 4 == 0 ? 0.15 : unif(0.3, 0.8);
    dGeomID g = dCreateBox(0, side, unif(0.3, 0.8), unif(0.3, 0.8));
    random_attitude(g);
    geoms.push_back(g);
  }
  std::vector<std::pair<int, int>> pairs;
  for (int k = 0; k < kPairs; ++k) {
    const int a = static_cast<int>(unif() * kGeoms) % kGeoms;
    int b = static_cast<int>(unif() * kGeoms) % kGeoms;
    if (b == a) b = (a + 1) % kGeoms;
    pairs.emplace_back(a, b);
  }
  long calls = 0, with_contacts = 0, same = 0, bitwise = 0, grown = 0;
  for (int round = 0; round < kRounds; ++round) {
    for (int i = 0; i < kGeoms; i += 4) {  // the small side 0.15 in even rounds, 0.6 in odd ones
      dVector3 l;
      dGeomBoxGetLengths(geoms[i], l);
      dGeomBoxSetLengths(geoms[i], round % 2 ? 0.6 : 0.15, l[1], l[2]);
    }
    for (const auto &pr : pairs) {
      dGeomID a = geoms[pr.first], b = geoms[pr.second];
      // b placed about a within the reach of their sizes (some pairs apart, most overlapping).
      const dReal *pa = dGeomGetPosition(a);
      const double r = unif(0.1, 0.7);
      double d[3] = {unif(-1, 1), unif(-1, 1), unif(-1, 1)};
      const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + 1e-12;
      dGeomSetPosition(b, pa[0] + r * d[0] / dl, pa[1] + r * d[1] / dl, pa[2] + r * d[2] / dl);
      if (round % 3 == 0) random_attitude(b);
      dContactGeom c[8];
      const int n = dCollide(a, b, 8, c, sizeof(dContactGeom));
      ++calls;
      dcol_pose p1, p2;
      const dcol_shape *s1 = dcol_ode::shape_of(a, &p1), *s2 = dcol_ode::shape_of(b, &p2);
      dcol_contact cs[8];
      std::size_t m = 0;
      const dcol_status st = dcol_contacts(s1, &p1, s2, &p2, 0.0, nullptr, cs, 8, &m);
      bool ok = s1 && s2 && (st == DCOL_OK || st == DCOL_ERROR_NOT_CONVERGED) && static_cast<std::size_t>(n) == m;
      bool exact = ok;
      for (int i = 0; ok && i < n; ++i) {
        ok = ok && c[i].g1 == a && c[i].g2 == b;
        for (int k = 0; k < 3; ++k) {
          const double e[3] = {c[i].pos[k] - cs[i].position[k], c[i].normal[k] + cs[i].normal[k], c[i].depth - cs[i].depth};
          for (double x : e) {
            ok = ok && std::fabs(x) <= 1e-12;
            exact = exact && x == 0;
          }
        }
      }
      same += ok;
      bitwise += ok && exact;
      with_contacts += n > 0;
      grown += n > 0 && (pr.first % 4 == 0 || pr.second % 4 == 0) && round % 2 == 1;
    }
  }
  std::printf("many pairs: %ld calls (%d geoms, %d pairs), %ld with contacts (%ld of a grown box), %ld as "
              "dcol_contacts (%ld bit for bit)\n",
              calls, kGeoms, kPairs, with_contacts, grown, same, bitwise);
  expect(calls == static_cast<long>(kPairs) * kRounds && same == calls && with_contacts > calls / 2 && grown > 1000,
         "many pairs through the collider's tables: dcol_contacts' contacts");
  for (dGeomID g : geoms) destroy(g);
}

// The dcol geom class against ODE's own box (through the same collider).
void user_class() {
  dcol_shape *ball = nullptr;
  dcol_shape_new_sphere(0.25, &ball);
  dGeomID g = dcol_ode::create_geom(0, ball, 0.25);
  dGeomID box = dCreateBox(0, 1, 1, 1);
  dGeomSetPosition(g, 0.1, -0.2, 0.5 + 0.25 - 0.01);
  dContactGeom c[4];
  const int n = dCollide(g, box, 4, c, sizeof(dContactGeom));
  const int m = dCollide(box, g, 4, c + 1, sizeof(dContactGeom));
  std::printf("dcol geom on ODE's box: %d and %d contacts, depth %.6f, normal z %.6f / %.6f\n", n, m, n ? c[0].depth : 0.0,
              c[0].normal[2], c[1].normal[2]);
  expect(n == 1 && m == 1 && std::fabs(c[0].depth - 0.01) < 1e-12 && c[0].normal[2] > 1 - 1e-12 &&
             c[1].normal[2] < -1 + 1e-12,
         "the dcol geom class collides with ODE's box");
  destroy(g);
  destroy(box);
  dcol_shape_free(ball);
}

}  // namespace

int main() {
  dInitODE2(0);
  // Before the override: ODE's own answers, and no call reaches dcol.
  expect(!dcol_ode::dcol_in_use(), "dcol is not in use before use_dcol()");
  record_native(dSphereClass, dSphereClass, 0.6, 40);
  record_native(dSphereClass, dBoxClass, 0.7, 40);
  record_native(dBoxClass, dSphereClass, 0.7, 40);
  record_native(dSphereClass, dCapsuleClass, 0.7, 40);
  record_native(dBoxClass, dBoxClass, 0.8, 200);
  record_native(dCapsuleClass, dCapsuleClass, 0.8, 40);
  expect(dcol_ode::collider_calls() == 0, "no dcol call before use_dcol()");

  dcol_ode::use_dcol();
  dcol_ode::use_dcol();  // harmless twice
  dcol_ode::init();
  expect(dcol_ode::dcol_in_use(), "dcol is in use after use_dcol()");
  plane_analytic();
  compare_native();
  box_box_sat();
  argument_order();
  axes_and_offsets();
  count_and_skip();
  parameters_change();
  rejected_pairs();
  near_touching();
  many_pairs();
  user_class();
  const dcol_ode::Stats s = dcol_ode::stats();
  std::printf("stats: %lu dcol calls, %lu contacts, %lu rejected, %lu handed to ODE (%lu without a collider), "
              "%lu records dropped\n",
              s.calls, s.contacts, s.rejected, s.native_calls, s.native_missing, s.dropped_records);
  dcol_ode::release_all();
  dCloseODE();
  // After dCloseODE and a new dInitODE2, ODE's own colliders are back.
  dInitODE2(0);
  expect(!dcol_ode::dcol_in_use(), "dInitODE2 after dCloseODE restores ODE's colliders");
  dcol_ode::use_dcol();
  expect(dcol_ode::dcol_in_use(), "use_dcol() again installs dcol");
  dcol_ode::release_all();
  dCloseODE();
  std::printf("%d checks, %s\n", checks(), engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
