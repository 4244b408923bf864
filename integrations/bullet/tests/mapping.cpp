// Tests of use_dcol's mapping of Bullet's shapes and of its algorithm, run by ctest:
//
//   bullet_mapping support    every Bullet shape (sphere, box, capsule, cylinder and cone along
//                             x, y, z, with default, zero and changed margins, local scaling)
//                             against Bullet's own support map with margin: the mapped dcol shape
//                             (padding included) has the same support value in 400 directions
//   bullet_mapping pairs      every ordered pair of the types (and a dcol ellipsoid, and the
//                             plane) stacked 1 cm into each other along z: one manifold, deepest
//                             distance -0.01, normal along z, answered by dcol (algorithm_calls)
//   bullet_mapping native     contacts of simple pairs with use_dcol and with Bullet's own
//                             algorithms: the same normal and depth as the analytic one
//   bullet_mapping cache      one dcol shape per Bullet shape, rebuilt when its margin, scaling
//                             or size changes, or after forget(); as_dcol from two threads
//   bullet_mapping fallback   shapes dcol cannot take (a flat box, a cylinder thinner than its
//                             margin) keep Bullet's algorithm: a sphere rests on them
//   bullet_mapping nan        a non-finite pose: no contacts, counted, no crash
//   bullet_mapping reuse      a body at rest: the pair's last answer reused, the same manifold
//   bullet_mapping near       4 000 random pairs of every type near contact: contacts exactly when
//                             the signed distance of the mapped shapes is within the breaking
//                             threshold (the early-outs drop none), deepest = signed distance
#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dcol_bullet.hpp"
#include "engine_scenes.hpp"
#include "pair.hpp"

namespace {

using engine_scenes::check;

struct Rng {
  unsigned long long s;
  double unif() {
    s = s * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(s >> 11) / double(1ULL << 53);
  }
  btVector3 direction() {
    for (;;) {
      const btVector3 v(btScalar(2 * unif() - 1), btScalar(2 * unif() - 1), btScalar(2 * unif() - 1));
      if (v.length2() > 0.01 && v.length2() <= 1) return v.normalized();
    }
  }
  btTransform pose() {
    btTransform t;
    t.setOrigin(btVector3(btScalar(unif() - 0.5), btScalar(unif() - 0.5), btScalar(unif() - 0.5)));
    t.setRotation(btQuaternion(btScalar(unif() - 0.5), btScalar(unif() - 0.5), btScalar(unif() - 0.5),
                               btScalar(unif() - 0.5))
                      .normalized());
    return t;
  }
};

// A hull of n points on an ellipsoid of semi-axes a, b, c around `centre` (Bullet keeps every
// point; most are corners of the hull).
btConvexHullShape *random_hull(Rng &rng, int n, double a, double b, double c, const btVector3 &centre) {
  btConvexHullShape *h = new btConvexHullShape();
  for (int i = 0; i < n; ++i) {
    const btVector3 d = rng.direction();
    h->addPoint(centre + btVector3(btScalar(a * d.x()), btScalar(b * d.y()), btScalar(c * d.z())), false);
  }
  h->recalcLocalAabb();
  return h;
}

// The support value of the dcol shape (grown by `pad`) in world direction d: from its signed
// distance to the half-space {x : d.x >= c} (a closed form in dcol), c beyond the shape.
double dcol_support(const dcol_shape *s, const dcol_pose &p, double pad, const btVector3 &dir) {
  struct Holder {
    dcol_shape *s = nullptr;
    Holder() { dcol_shape_new_halfspace(1.0, &s); }
    ~Holder() { dcol_shape_free(s); }
  };
  static const Holder holder;
  const dcol_shape *hs = holder.s;
  // In double and of unit length: a float direction is off unit by ~6e-8, which the plane's
  // offset of 10 would turn into 1e-6.
  double d[3] = {dir.x(), dir.y(), dir.z()};
  const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (double &v : d) v /= dl;
  const double c = d[0] * p.position[0] + d[1] * p.position[1] + d[2] * p.position[2] + 10.0;
  dcol_pose h;
  for (int k = 0; k < 3; ++k) h.position[k] = (c + 1.0) * d[k];
  // The rotation taking e_z to -d.
  double w = 1.0 - d[2], x = d[1], y = -d[0];
  if (w < 1e-12) {
    w = 0;
    x = 1;
    y = 0;
  }
  const double l = std::sqrt(w * w + x * x + y * y);
  h.quaternion[0] = w / l;
  h.quaternion[1] = x / l;
  h.quaternion[2] = y / l;
  h.quaternion[3] = 0;
  dcol_signed_distance_result r;
  if (dcol_signed_distance(s, &p, hs, &h, nullptr, &r) != DCOL_OK) return NAN;
  return c - r.distance + pad;
}

// Bullet's support value of `shape` at `t` in world direction d (its margin included).
double bullet_support(const btConvexShape *shape, const btTransform &t, const btVector3 &d) {
  const btVector3 local = t.getBasis().transpose() * d;
  return d.dot(t(shape->localGetSupportingVertex(local)));
}

struct Named {
  std::string name;
  std::unique_ptr<btConvexShape> shape;
};

std::vector<Named> support_shapes() {
  std::vector<Named> v;
  auto add = [&v](const std::string &n, btConvexShape *s) { v.push_back(Named{n, std::unique_ptr<btConvexShape>(s)}); };
  add("sphere", new btSphereShape(0.3f));
  add("box", new btBoxShape(btVector3(0.4f, 0.25f, 0.3f)));
  btBoxShape *b0 = new btBoxShape(btVector3(0.4f, 0.25f, 0.1f));
  b0->setMargin(0);
  add("box margin 0", b0);
  btBoxShape *bs = new btBoxShape(btVector3(0.4f, 0.25f, 0.3f));
  bs->setLocalScaling(btVector3(1.5f, 0.5f, 2.0f));
  add("box scaled", bs);
  add("capsule X", new btCapsuleShapeX(0.15f, 0.5f));
  add("capsule Y", new btCapsuleShape(0.15f, 0.5f));
  add("capsule Z", new btCapsuleShapeZ(0.15f, 0.5f));
  btCapsuleShape *cs = new btCapsuleShapeZ(0.15f, 0.5f);
  cs->setLocalScaling(btVector3(2, 2, 2));
  add("capsule Z scaled", cs);
  add("cylinder X", new btCylinderShapeX(btVector3(0.5f, 0.3f, 0.3f)));
  add("cylinder Y", new btCylinderShape(btVector3(0.3f, 0.5f, 0.3f)));
  add("cylinder Z", new btCylinderShapeZ(btVector3(0.3f, 0.3f, 0.5f)));
  btCylinderShape *c0 = new btCylinderShapeZ(btVector3(0.3f, 0.3f, 0.5f));
  c0->setMargin(0);
  add("cylinder Z margin 0", c0);
  btCylinderShape *c1 = new btCylinderShape(btVector3(0.3f, 0.5f, 0.3f));
  c1->setMargin(0.1f);
  add("cylinder Y margin 0.1", c1);
  add("cone X", new btConeShapeX(0.2f, 0.5f));
  add("cone Y", new btConeShape(0.2f, 0.5f));
  add("cone Z", new btConeShapeZ(0.2f, 0.5f));
  btConeShape *k0 = new btConeShapeZ(0.3f, 0.2f);
  k0->setMargin(0);
  add("cone Z margin 0", k0);
  btConeShape *ks = new btConeShape(0.2f, 0.5f);
  ks->setLocalScaling(btVector3(1.5f, 2.0f, 1.5f));
  add("cone Y scaled", ks);
  Rng rng{3};
  add("hull 30 points", random_hull(rng, 30, 0.3, 0.2, 0.15, btVector3(0.02f, -0.01f, 0.03f)));
  btConvexHullShape *h1 = random_hull(rng, 200, 0.3, 0.3, 0.3, btVector3(0, 0, 0));
  h1->setMargin(0.01f);
  add("hull 200 points", h1);
  btConvexHullShape *h2 = random_hull(rng, 12, 0.2, 0.1, 0.25, btVector3(1.0f, 0.8f, -0.6f));
  add("hull off its origin", h2);
  btConvexHullShape *h3 = random_hull(rng, 40, 0.2, 0.2, 0.2, btVector3(0, 0, 0));
  h3->setLocalScaling(btVector3(1, 2, 0.5f));
  h3->setMargin(0);
  add("hull scaled, margin 0", h3);
  return v;
}

int support() {
  Rng rng{7};
  for (const Named &n : support_shapes()) {
    double worst = 0;
    int bad = 0;
    for (int k = 0; k < 400; ++k) {
      const btTransform t = rng.pose();
      const btVector3 d = rng.direction();
      const dcol_shape *s = nullptr;
      dcol_pose p;
      double pad = -1;
      if (!dcol_bullet::as_dcol(n.shape.get(), t, &s, &p, &pad)) {
        ++bad;
        continue;
      }
      const double err = std::fabs(dcol_support(s, p, pad, d) - bullet_support(n.shape.get(), t, d));
      if (!(err <= worst)) worst = err;
      if (!(err <= 5e-7)) ++bad;
    }
    std::printf("  %-22s support value, dcol - Bullet, worst |difference| over 400 directions: %.2e\n",
                n.name.c_str(), worst);
    char what[96];
    std::snprintf(what, sizeof what, "%s: the support of the mapped shape is Bullet's", n.name.c_str());
    check(bad == 0, what);
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Every ordered pair stacked along z.

struct Stackable {
  const char *name;
  std::unique_ptr<btCollisionShape> shape;
  double top, bottom;  // z extent of the shape's geometry in its own frame
};

struct Ellipsoid {
  dcol_shape *s = nullptr;
  Ellipsoid() {
    const double P[9] = {1 / 0.04, 0, 0, 0, 1 / 0.0625, 0, 0, 0, 1 / 0.09};  // semi-axes 0.2, 0.25, 0.3
    dcol_shape_new_ellipsoid(P, &s);
  }
  ~Ellipsoid() { dcol_shape_free(s); }
};

int pairs() {
  Ellipsoid ell;
  std::vector<Stackable> kinds;
  kinds.push_back({"sphere", std::unique_ptr<btCollisionShape>(new btSphereShape(0.3f)), 0.3, -0.3});
  kinds.push_back({"box", std::unique_ptr<btCollisionShape>(new btBoxShape(btVector3(0.4f, 0.3f, 0.2f))), 0.2, -0.2});
  kinds.push_back({"capsule", std::unique_ptr<btCollisionShape>(new btCapsuleShapeZ(0.15f, 0.4f)), 0.35, -0.35});
  kinds.push_back(
      {"cylinder", std::unique_ptr<btCollisionShape>(new btCylinderShapeZ(btVector3(0.3f, 0.3f, 0.25f))), 0.25, -0.25});
  btConeShapeZ *cone = new btConeShapeZ(0.3f, 0.5f);
  const double m = cone->getMargin();
  kinds.push_back({"cone", std::unique_ptr<btCollisionShape>(cone), 0.25 + m, -0.25 - m});
  kinds.push_back({"ellipsoid", std::unique_ptr<btCollisionShape>(new dcol_bullet::Shape(ell.s, 0.3, btVector3(0.2f, 0.25f, 0.3f))),
                   0.3, -0.3});
  btConvexHullShape *octa = new btConvexHullShape();
  for (int k = 0; k < 3; ++k) {
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      btVector3 p(0, 0, 0);
      p[k] = btScalar(0.25 * sgn);
      octa->addPoint(p, false);
    }
  }
  octa->recalcLocalAabb();
  const double om = octa->getMargin();
  kinds.push_back({"hull", std::unique_ptr<btCollisionShape>(octa), 0.25 + om, -0.25 - om});
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0);
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  dcol_bullet::use_dcol(&dispatcher);
  const double overlap = 0.01;
  int n_pairs = 0;
  for (int ia = -1; ia < int(kinds.size()); ++ia) {
    for (const Stackable &b : kinds) {
      // A below (the plane when ia = -1), B above, overlapping by 1 cm along z.
      btCollisionShape *sa = ia < 0 ? static_cast<btCollisionShape *>(&plane) : kinds[ia].shape.get();
      const double top_a = ia < 0 ? 0.0 : kinds[ia].top;
      btTransform ta, tb;
      ta.setIdentity();
      tb.setIdentity();
      ta.setOrigin(btVector3(0.01f, -0.02f, 0.5f));  // off the origin, so poses matter
      tb.setOrigin(btVector3(0.01f, -0.02f, btScalar(0.5 + top_a - b.bottom - overlap)));
      for (int order = 0; order < 2; ++order) {
        const unsigned long before = dcol_bullet::algorithm_calls();
        const std::vector<pair_test::Point> pts =
            order == 0 ? pair_test::collide(dispatcher, sa, ta, b.shape.get(), tb)
                       : pair_test::collide(dispatcher, b.shape.get(), tb, sa, ta);
        const unsigned long calls = dcol_bullet::algorithm_calls() - before;
        ++n_pairs;
        const char *na = ia < 0 ? "plane" : kinds[ia].name;
        bool ok = calls == 1 && !pts.empty();
        double dist = NAN, nz = NAN;
        if (!pts.empty()) {
          const pair_test::Point &p = pair_test::deepest(pts);
          dist = p.distance;
          nz = p.normal_a_to_b.z() * (order == 0 ? 1.0 : -1.0);  // from the lower to the upper shape
          ok = ok && std::fabs(dist + overlap) <= 2e-6 && std::fabs(nz - 1) <= 1e-6;
        }
        if (!ok) {
          std::printf("  %s under %s (order %d): %zu points, dcol calls %lu, deepest distance %.7f, normal z %.7f\n",
                      na, b.name, order, pts.size(), calls, dist, nz);
        }
        char what[96];
        std::snprintf(what, sizeof what, "%s under %s: dcol answers, depth 0.01 along z", na, b.name);
        check(ok, what);
      }
    }
  }
  std::printf("pairs: %d ordered pairs stacked 1 cm deep, every one answered by dcol; stats: %lu calls, %lu fallbacks\n",
              n_pairs, dcol_bullet::stats().calls, dcol_bullet::stats().fallback_calls);
  check(dcol_bullet::stats().fallback_calls == 0, "no pair handed to Bullet's algorithm");
  return 0;
}

// ---------------------------------------------------------------------------------------------
// use_dcol against Bullet's own algorithms, on pairs where both are exact: the same depth and
// normal, and that of the set-up.

struct NativeCase {
  const char *name;
  btCollisionShape *a, *b;
  btTransform ta, tb;
  double depth;  // the analytic penetration
};

btTransform at(double x, double y, double z, const btQuaternion &q = btQuaternion::getIdentity()) {
  btTransform t(q, btVector3(btScalar(x), btScalar(y), btScalar(z)));
  return t;
}

int native() {
  btBoxShape ground(btVector3(2, 2, 0.5f));
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0);
  btSphereShape ball(0.5f);
  btBoxShape box(btVector3(0.3f, 0.2f, 0.1f));
  btCapsuleShapeZ capsule(0.1f, 0.4f);
  btCapsuleShapeX lying_capsule(0.1f, 0.4f);
  btCylinderShapeZ standing_cylinder(btVector3(0.2f, 0.2f, 0.3f));
  btCylinderShapeX lying_cylinder(btVector3(0.3f, 0.2f, 0.2f));
  btConeShapeZ cone(0.2f, 0.4f);
  const double cm = cone.getMargin();
  btConvexHullShape cube;  // the corners of a 0.2 m cube, grown by a margin of 0.01
  for (int i = 0; i < 8; ++i) {
    cube.addPoint(btVector3(i & 1 ? 0.1f : -0.1f, i & 2 ? 0.1f : -0.1f, i & 4 ? 0.1f : -0.1f), i == 7);
  }
  cube.setMargin(0.01f);
  const btQuaternion tilt(btVector3(1, 0, 0), 0.02f);
  const double d = 0.01;
  const NativeCase cases[] = {
      {"sphere on box", &ground, &ball, at(0, 0, -0.5), at(0.1, 0.2, 0.5 - d), d},
      {"box on box", &ground, &box, at(0, 0, -0.5), at(0.1, 0.2, 0.1 - d), d},
      {"box on plane", &plane, &box, at(0, 0, 0), at(0.1, 0.2, 0.1 - d), d},
      {"tilted box on plane", &plane, &box, at(0, 0, 0), at(0, 0, 0.1 - d, tilt),
       d + 0.2 * std::sin(0.02) + 0.1 * (std::cos(0.02) - 1)},
      {"capsule on box", &ground, &capsule, at(0, 0, -0.5), at(0.1, 0.2, 0.3 - d), d},
      {"lying capsule on plane", &plane, &lying_capsule, at(0, 0, 0), at(0.1, 0.2, 0.1 - d), d},
      {"cylinder on plane", &plane, &standing_cylinder, at(0, 0, 0), at(0.1, 0.2, 0.3 - d), d},
      {"lying cylinder on box", &ground, &lying_cylinder, at(0, 0, -0.5), at(0.1, 0.2, 0.2 - d), d},
      {"cone on plane", &plane, &cone, at(0, 0, 0), at(0.1, 0.2, 0.2 + cm - d), d},
      {"hull on box", &ground, &cube, at(0, 0, -0.5), at(0.1, 0.2, 0.11 - d), d},
      {"hull on plane", &plane, &cube, at(0, 0, 0), at(0.1, 0.2, 0.11 - d), d},
  };
  for (const NativeCase &c : cases) {
    double dist[2] = {NAN, NAN}, nz[2] = {NAN, NAN};
    std::size_t count[2] = {0, 0};
    for (int use = 0; use < 2; ++use) {
      btDefaultCollisionConfiguration config;
      btCollisionDispatcher dispatcher(&config);
      if (use) dcol_bullet::use_dcol(&dispatcher);
      const std::vector<pair_test::Point> pts = pair_test::collide(dispatcher, c.a, c.ta, c.b, c.tb);
      count[use] = pts.size();
      if (!pts.empty()) {
        dist[use] = pair_test::deepest(pts).distance;
        nz[use] = pair_test::deepest(pts).normal_a_to_b.z();
      }
    }
    std::printf("  %-24s analytic %.6f; native: %zu points, deepest %.6f, normal z %.6f; dcol: %zu points, deepest %.6f, normal z %.6f\n",
                c.name, -c.depth, count[0], dist[0], nz[0], count[1], dist[1], nz[1]);
    char what[96];
    std::snprintf(what, sizeof what, "%s: dcol's depth is the analytic one", c.name);
    check(std::fabs(dist[1] + c.depth) <= 2e-6, what);
    std::snprintf(what, sizeof what, "%s: dcol's normal is Bullet's, from A to B", c.name);
    check(std::fabs(nz[1] - nz[0]) <= 1e-3 && nz[1] > 0.999, what);
    std::snprintf(what, sizeof what, "%s: Bullet's own depth agrees (1e-4)", c.name);
    check(std::fabs(dist[0] - dist[1]) <= 1e-4, what);
  }
  return 0;
}

// ---------------------------------------------------------------------------------------------

int cache() {
  btTransform id;
  id.setIdentity();
  const dcol_shape *s1 = nullptr, *s2 = nullptr;
  dcol_pose p;
  btBoxShape box(btVector3(0.3f, 0.2f, 0.1f));
  const unsigned long built0 = dcol_bullet::stats().shapes_built;
  check(dcol_bullet::as_dcol(&box, id, &s1, &p) && dcol_bullet::as_dcol(&box, id, &s2, &p) && s1 == s2,
        "the same dcol shape twice");
  check(dcol_bullet::stats().shapes_built == built0 + 1, "built once");
  const btVector3 up(0, 0, 1);
  double before = dcol_support(s1, p, 0, up);
  box.setLocalScaling(btVector3(1, 1, 2));
  check(dcol_bullet::as_dcol(&box, id, &s2, &p), "mapped after scaling");
  const double after = dcol_support(s2, p, 0, up);
  std::printf("  box: top %.6f, after scaling z by 2: %.6f (shapes built: %lu)\n", before, after,
              dcol_bullet::stats().shapes_built - built0);
  check(std::fabs(before - 0.1) < 1e-7 && std::fabs(after - 0.2) < 1e-7, "rebuilt with the scaling");
  box.setMargin(0.01f);
  const unsigned long built1 = dcol_bullet::stats().shapes_built;
  check(dcol_bullet::as_dcol(&box, id, &s2, &p) && dcol_bullet::stats().shapes_built == built1 + 1,
        "rebuilt when the margin changes");
  dcol_bullet::forget(&box);
  check(dcol_bullet::as_dcol(&box, id, &s2, &p) && dcol_bullet::stats().shapes_built == built1 + 2,
        "rebuilt after forget");
  btConeShape cone(0.2f, 0.5f);
  check(dcol_bullet::as_dcol(&cone, id, &s1, &p), "cone mapped");
  before = dcol_support(s1, p, cone.getMargin(), btVector3(0, 1, 0));
  cone.setHeight(1.0f);
  check(dcol_bullet::as_dcol(&cone, id, &s2, &p), "cone mapped after setHeight");
  const double cone_after = dcol_support(s2, p, cone.getMargin(), btVector3(0, 1, 0));
  check(std::fabs(before - (0.25 + 0.04)) < 1e-6 && std::fabs(cone_after - (0.5 + 0.04)) < 1e-6,
        "the cone's apex follows setHeight");

  // Two threads mapping the same 40 shapes (and one of them forgetting some) agree.
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  for (int i = 0; i < 40; ++i) {
    const btScalar r = btScalar(0.1 + 0.01 * i);
    if (i % 4 == 0) shapes.emplace_back(new btSphereShape(r));
    if (i % 4 == 1) shapes.emplace_back(new btBoxShape(btVector3(r, r, r)));
    if (i % 4 == 2) shapes.emplace_back(new btCylinderShapeZ(btVector3(r, r, 2 * r)));
    if (i % 4 == 3) shapes.emplace_back(new btConeShapeZ(r, 2 * r));
  }
  int wrong[2] = {0, 0};
  auto work = [&shapes, &id](int t, int *bad) {
    for (int round = 0; round < 200; ++round) {
      for (std::size_t i = 0; i < shapes.size(); ++i) {
        const dcol_shape *s = nullptr;
        dcol_pose q;
        double pad = 0;
        if (!dcol_bullet::as_dcol(shapes[i].get(), id, &s, &q, &pad)) {
          ++*bad;
          continue;
        }
        // The top of shape i: r (sphere, box), 2r (cylinder), r + margin (a cone of height 2r).
        const double r = 0.1 + 0.01 * double(i);
        const double want = i % 4 < 2 ? r : i % 4 == 2 ? 2 * r : r + 0.04;
        if (!(std::fabs(dcol_support(s, q, pad, btVector3(0, 0, 1)) - want) < 1e-6)) ++*bad;
        if (t == 1 && round % 10 == 0 && i % 7 == 0) dcol_bullet::forget(shapes[i].get());
      }
    }
  };
  std::thread a(work, 0, &wrong[0]), b(work, 1, &wrong[1]);
  a.join();
  b.join();
  std::printf("  two threads, 200 rounds over 40 shapes with forget(): %d and %d failures\n", wrong[0], wrong[1]);
  check(wrong[0] == 0 && wrong[1] == 0, "as_dcol from two threads");
  return 0;
}

// A body at rest (no gravity, no velocity) on a box: every step after the first has the same
// shapes at bit-identical poses, so the pair's last answer is reused, with the same manifold.
int reuse() {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  dcol_bullet::use_dcol(&dispatcher);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, 0));
  // A ball (two boxes get no speculative points: only where they touch, as Bullet's box-box).
  btBoxShape slab(btVector3(1, 1, 0.1f));
  btSphereShape cube(0.1f);
  btRigidBody ground(0, nullptr, &slab);
  btVector3 inertia;
  cube.calculateLocalInertia(1, inertia);
  btDefaultMotionState state(at(0.3, 0.1, 0.2 + 0.001));  // 1 mm above: a speculative point, no impulse
  btRigidBody body(1, &state, &cube, inertia);
  body.setActivationState(DISABLE_DEACTIVATION);
  world.addRigidBody(&ground);
  world.addRigidBody(&body);
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  std::vector<double> deepest;
  for (int k = 0; k < 10; ++k) {
    world.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240));
    btPersistentManifold *m = dispatcher.getNumManifolds() ? dispatcher.getManifoldByIndexInternal(0) : nullptr;
    double d = NAN;
    for (int i = 0; m && i < m->getNumContacts(); ++i) {
      const double di = m->getContactPoint(i).getDistance();
      d = std::isnan(d) ? di : std::min(d, di);
    }
    deepest.push_back(d);
  }
  const dcol_bullet::Stats s1 = dcol_bullet::stats();
  bool same = true;
  for (double d : deepest) same = same && d == deepest[0];
  std::printf("reuse: 10 steps at rest, %lu dcol calls, %lu answers reused, manifold distance %.6f every step: %s\n",
              s1.calls - s0.calls, s1.reused - s0.reused, deepest[0], same ? "yes" : "no");
  check(s1.calls - s0.calls == 10 && s1.reused - s0.reused == 9, "the nine calls after the first reuse its answer");
  check(same && std::fabs(deepest[0] - 0.001) < 1e-6, "the same manifold, 1 mm apart");
  world.removeRigidBody(&body);
  world.removeRigidBody(&ground);
  return 0;
}

// ---------------------------------------------------------------------------------------------

int fallback() {
  struct Case {
    const char *name;
    btCollisionShape *floor;
  };
  btBoxShape flat(btVector3(1, 1, 0));
  btCylinderShapeZ thin(btVector3(1, 1, 0.02f));
  thin.setMargin(0.04f);  // larger than its half height: no core
  btTransform id;
  id.setIdentity();
  const dcol_shape *s = nullptr;
  dcol_pose p;
  check(!dcol_bullet::as_dcol(&flat, id, &s, &p), "a flat box is not mapped");
  check(!dcol_bullet::as_dcol(&thin, id, &s, &p), "a cylinder thinner than its margin is not mapped");
  btConvexHullShape square;  // four points in a plane: no volume
  square.addPoint(btVector3(-1, -1, 0), false);
  square.addPoint(btVector3(1, -1, 0), false);
  square.addPoint(btVector3(1, 1, 0), false);
  square.addPoint(btVector3(-1, 1, 0), true);
  square.setMargin(0);
  check(!dcol_bullet::as_dcol(&square, id, &s, &p), "a flat hull is not mapped");
  const Case cases[] = {{"flat box", &flat}, {"cylinder thinner than its margin", &thin}, {"flat hull", &square}};
  for (const Case &c : cases) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    dcol_bullet::use_dcol(&dispatcher);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    world.setGravity(btVector3(0, 0, btScalar(-engine_scenes::kG)));
    btSphereShape ball(0.2f);
    btRigidBody ground(0, nullptr, c.floor);
    const double top = c.floor == &thin ? 0.02 : 0.0;  // the thin cylinder: its half height with margin
    btVector3 inertia;
    ball.calculateLocalInertia(1, inertia);
    btDefaultMotionState state(at(0.3, 0.1, top + 0.3));
    btRigidBody body(1, &state, &ball, inertia);
    body.setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(&ground);
    world.addRigidBody(&body);
    const dcol_bullet::Stats s0 = dcol_bullet::stats();
    for (int k = 0; k < 240; ++k) world.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240));
    const dcol_bullet::Stats s1 = dcol_bullet::stats();
    const double z = body.getWorldTransform().getOrigin().z();
    std::printf("  sphere on a %s: rests at %.5f (floor top %.2f + radius 0.2), %lu pair given Bullet's algorithm, %lu dcol calls\n",
                c.name, z, top, s1.fallback_pairs - s0.fallback_pairs, s1.calls - s0.calls);
    check(s1.fallback_pairs == s0.fallback_pairs + 1 && s1.calls == s0.calls, "the pair went to Bullet's algorithm");
    check(std::fabs(z - (top + 0.2)) < 2e-3, "the sphere rests on it");
    world.removeRigidBody(&body);
    world.removeRigidBody(&ground);
  }

  // A box floor that dcol takes, flattened (local scaling 0 along z) while a sphere rests on it:
  // the pair's dcol algorithm hands its calls to Bullet's from then on.
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  dcol_bullet::use_dcol(&dispatcher);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
  world.setGravity(btVector3(0, 0, btScalar(-engine_scenes::kG)));
  btBoxShape slab(btVector3(1, 1, 0.1f));
  slab.setMargin(0);
  btSphereShape ball(0.2f);
  btRigidBody ground(0, nullptr, &slab);
  btVector3 inertia;
  ball.calculateLocalInertia(1, inertia);
  btDefaultMotionState state(at(0.3, 0.1, 0.35));
  btRigidBody body(1, &state, &ball, inertia);
  body.setActivationState(DISABLE_DEACTIVATION);
  world.addRigidBody(&ground);
  world.addRigidBody(&body);
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  for (int k = 0; k < 240; ++k) world.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240));
  const double z0 = body.getWorldTransform().getOrigin().z();
  const dcol_bullet::Stats s1 = dcol_bullet::stats();
  slab.setLocalScaling(btVector3(1, 1, 0));
  world.updateSingleAabb(&ground);
  for (int k = 0; k < 240; ++k) world.stepSimulation(btScalar(1.0 / 240), 1, btScalar(1.0 / 240));
  const double z1 = body.getWorldTransform().getOrigin().z();
  const dcol_bullet::Stats s2 = dcol_bullet::stats();
  std::printf("  sphere on a slab: rests at %.5f (dcol calls %lu); slab flattened: rests at %.5f (%lu calls handed to Bullet's algorithm, %lu dcol calls)\n",
              z0, s1.calls - s0.calls, z1, s2.fallback_calls - s1.fallback_calls, s2.calls - s1.calls);
  check(s1.calls > s0.calls && std::fabs(z0 - 0.3) < 1e-3, "on the slab, dcol's contacts hold the sphere");
  check(s2.fallback_calls > s1.fallback_calls && s2.calls == s1.calls, "flattened, the calls go to Bullet's algorithm");
  check(std::fabs(z1 - 0.2) < 2e-3, "and the sphere rests on the flat box");
  world.removeRigidBody(&body);
  world.removeRigidBody(&ground);
  return 0;
}

int nan_pose() {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  dcol_bullet::use_dcol(&dispatcher);
  btBoxShape a(btVector3(0.5f, 0.5f, 0.5f)), b(btVector3(0.3f, 0.3f, 0.3f));
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0);
  const btScalar nan = std::numeric_limits<btScalar>::quiet_NaN();
  const dcol_bullet::Stats s0 = dcol_bullet::stats();
  std::size_t points = 0;
  for (int k = 0; k < 100; ++k) {
    btTransform bad = at(0, 0, 0.7);
    bad.setOrigin(btVector3(nan, 0, nan));
    points += pair_test::collide(dispatcher, &a, at(0, 0, 0), &b, bad).size();
    btTransform rot = at(0, 0, 0.2);
    rot.setBasis(btMatrix3x3(nan, 0, 0, 0, 1, 0, 0, 0, 1));
    points += pair_test::collide(dispatcher, &plane, at(0, 0, 0), &b, rot).size();
  }
  const dcol_bullet::Stats s1 = dcol_bullet::stats();
  std::printf("nan: 200 calls with non-finite poses: %zu contact points, %lu counted as invalid poses, %lu errors\n", points,
              s1.invalid_poses - s0.invalid_poses, s1.errors - s0.errors);
  check(points == 0, "no contacts from a non-finite pose");
  check(s1.invalid_poses - s0.invalid_poses == 200, "every such call counted");
  return 0;
}

// ---------------------------------------------------------------------------------------------

int near_pairs() {
  std::vector<Named> shapes;
  auto add = [&shapes](const std::string &n, btConvexShape *s) {
    shapes.push_back(Named{n, std::unique_ptr<btConvexShape>(s)});
  };
  add("sphere", new btSphereShape(0.15f));
  add("box", new btBoxShape(btVector3(0.25f, 0.1f, 0.05f)));
  add("capsule", new btCapsuleShapeZ(0.06f, 0.3f));
  add("cylinder", new btCylinderShape(btVector3(0.1f, 0.2f, 0.1f)));
  add("cone", new btConeShapeX(0.12f, 0.3f));
  Rng hulls{5};
  add("hull", random_hull(hulls, 20, 0.15, 0.1, 0.12, btVector3(0, 0, 0)));
  add("offset hull", random_hull(hulls, 60, 0.1, 0.15, 0.1, btVector3(0.3f, 0, 0)));
  btStaticPlaneShape plane(btVector3(0, 0, 1), 0);
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  dcol_bullet::use_dcol(&dispatcher);
  Rng rng{99};
  int wrong = 0, with = 0, without = 0;
  double worst = 0;
  for (int k = 0; k < 4000; ++k) {
    const std::size_t ia = k % (shapes.size() + 1), ib = (k / (shapes.size() + 1)) % shapes.size();
    const bool on_plane = ia == shapes.size();
    btCollisionShape *sa = on_plane ? static_cast<btCollisionShape *>(&plane) : shapes[ia].shape.get();
    btCollisionShape *sb = shapes[ib].shape.get();
    btTransform ta = on_plane ? at(0, 0, 0) : rng.pose(), tb = rng.pose();
    // Place B at a random distance from A along a random direction, near contact.
    const btVector3 dir = on_plane ? btVector3(0, 0, 1) : rng.direction();
    tb.setOrigin(ta.getOrigin() + dir * btScalar(on_plane ? 0.3 * rng.unif() - 0.05 : 0.2 + 0.4 * rng.unif()));
    const dcol_shape *db = nullptr;
    dcol_pose pb;
    double padb = 0, sd = NAN;
    dcol_signed_distance_result r;
    dcol_bullet::as_dcol(sb, tb, &db, &pb, &padb);
    if (on_plane) {
      dcol_shape *floor = nullptr;
      dcol_shape_new_halfspace(1.0, &floor);
      const dcol_pose fp = {{0, 0, -1}, {1, 0, 0, 0}};
      if (dcol_signed_distance(floor, &fp, db, &pb, nullptr, &r) == DCOL_OK) sd = r.distance - padb;
      dcol_shape_free(floor);
    } else {
      const dcol_shape *da = nullptr;
      dcol_pose pa;
      double pada = 0;
      dcol_bullet::as_dcol(sa, ta, &da, &pa, &pada);
      if (dcol_signed_distance(da, &pa, db, &pb, nullptr, &r) == DCOL_OK) sd = r.distance - pada - padb;
    }
    double threshold = NAN;
    const std::vector<pair_test::Point> pts = pair_test::collide(dispatcher, sa, ta, sb, tb, &threshold);
    if (std::isnan(sd)) continue;
    // The threshold is known only when a manifold exists: Bullet's, from both shapes. Two boxes
    // get contacts only where they touch or overlap (as Bullet's own box-box algorithm).
    const bool boxes = !on_plane && shapes[ia].name == "box" && shapes[ib].name == "box";
    const double thr = boxes ? 0.0
                       : std::isnan(threshold) ? std::min(sa->getContactBreakingThreshold(gContactBreakingThreshold),
                                                          sb->getContactBreakingThreshold(gContactBreakingThreshold))
                                               : threshold;
    const double tol = 2e-6;
    if (sd < thr - tol) {
      ++with;
      if (pts.empty()) {
        ++wrong;
        std::printf("  %s-%s: signed distance %.6f within the threshold %.6f but no contact\n",
                    on_plane ? "plane" : shapes[ia].name.c_str(), shapes[ib].name.c_str(), sd, thr);
      } else {
        worst = std::max(worst, std::fabs(pair_test::deepest(pts).distance - sd));
        if (std::fabs(pair_test::deepest(pts).distance - sd) > 1e-5) {
          ++wrong;
          std::printf("  %s-%s: signed distance %.7f, deepest manifold point %.7f (%zu points)\n",
                      on_plane ? "plane" : shapes[ia].name.c_str(), shapes[ib].name.c_str(), sd,
                      pair_test::deepest(pts).distance, pts.size());
        }
      }
    } else if (sd > thr + tol) {
      ++without;
      if (!pts.empty()) ++wrong;
    }
  }
  std::printf("near: %d pairs within the threshold (deepest point = signed distance, worst %.2e m), %d beyond it, %d wrong\n",
              with, worst, without, wrong);
  check(wrong == 0, "contacts exactly within the threshold, at the signed distance");
  check(with > 500 && without > 500, "both kinds of case");
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  const std::string what = argc >= 2 ? argv[1] : "";
  int rc = 2;
  if (what == "support") rc = support();
  if (what == "pairs") rc = pairs();
  if (what == "native") rc = native();
  if (what == "cache") rc = cache();
  if (what == "fallback") rc = fallback();
  if (what == "nan") rc = nan_pose();
  if (what == "near") rc = near_pairs();
  if (what == "reuse") rc = reuse();
  if (rc == 2) {
    std::printf("usage: %s support | pairs | native | cache | fallback | nan | near | reuse\n", argv[0]);
    return 2;
  }
  std::printf("%s\n", engine_scenes::failures() ? "FAILED" : "ok");
  return engine_scenes::failures() ? 1 : 0;
}
