// bench_hulls: dcol against Coal 3 on convex hulls of random points, by facet count. Prints the
// markdown table the README quotes (run.sh writes it to results/hulls.md).
//
// For each size, n random points on an ellipsoid of semi-axes (0.6, 0.5, 0.4) (their hull has
// 2n - 4 triangular facets: none are coplanar) make one dcol hull (dcol_shape_new_convex_hull)
// and one Coal convex (coal::ConvexBase::convexHull: qhull, triangles kept, so that Coal builds
// its vertex neighbour graph and climbs it for the support). Both are queried at the same 200
// poses (random attitudes, the second body 0.5 to 1.6 from the first in a random direction,
// the sphere 0.35 to 0.95: about half separated), against a sphere of radius 0.3 and against the hull itself:
// dcol_proximity and dcol_distance against coal::distance (default request: GJK tolerance 1e-6,
// EPA on overlaps). Each pose's calls run back to back, DCOL_BENCH_REPEAT (default 15) rounds;
// medians in ns over all calls, and over the separated poses alone (where Coal runs GJK only).
// Build times are medians of 5 builds; the last row's hull is that of 10 000 points. DCOL_BENCH_SMOKE=1: two sizes, 5 poses.
#include <dcol.h>

#ifdef DCOL_BENCH_HAVE_COAL
#include <coal/collision_object.h>
#include <coal/distance.h>
#include <coal/shape/convex.h>
#include <coal/shape/geometric_shapes.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <vector>

#include "timing.hpp"

namespace {

struct Rng {
  uint64_t s;
  double next() {  // uniform in [-1, 1)
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    return static_cast<double>(s >> 11) / static_cast<double>(1ull << 53) * 2.0 - 1.0;
  }
  void unit(double u[3]) {
    for (;;) {
      double v[3] = {next(), next(), next()};
      double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (n > 0.1 && n <= 1.0) {
        for (int k = 0; k < 3; ++k) u[k] = v[k] / n;
        return;
      }
    }
  }
};

using cmp_timing::median;
using cmp_timing::now_ns;

void die(const char *what) {
  std::fprintf(stderr, "bench_hulls: %s: %s\n", what, dcol_last_error_message());
  std::exit(1);
}

#ifdef DCOL_BENCH_HAVE_COAL
coal::Transform3s to_coal(const dcol_pose &p) {
  const double *q = p.quaternion;
  coal::Quatf quat(q[0], q[1], q[2], q[3]);
  return coal::Transform3s(quat.normalized().toRotationMatrix(),
                           coal::Vec3s(p.position[0], p.position[1], p.position[2]));
}
#endif

}  // namespace

int main() {
  const bool smoke = std::getenv("DCOL_BENCH_SMOKE") != nullptr;
  const int reps = std::getenv("DCOL_BENCH_REPEAT") ? std::atoi(std::getenv("DCOL_BENCH_REPEAT")) : 15;
  const int poses = smoke ? 5 : 200;
  std::vector<int> sizes = smoke ? std::vector<int>{12, 2000}
                                 : std::vector<int>{12, 50, 100, 256, 1000, 2000, 5000, 19996};
  Rng rng{0x5EED0000C0A1ull};
  dcol_shape *sphere = nullptr;
  if (dcol_shape_new_sphere(0.3, &sphere) != DCOL_OK) die("sphere");
#ifdef DCOL_BENCH_HAVE_COAL
  std::printf("Coal %s: coal::distance against coal::ConvexBase::convexHull (qhull)\n\n",
              DCOL_BENCH_COAL_VERSION);
  auto coal_sphere = std::make_shared<coal::Sphere>(0.3);
#else
  std::printf("Coal: not available (%s): dcol only\n\n", DCOL_BENCH_COAL_MISSING);
#endif
  std::printf(
      "| facets | points | build dcol ms | build Coal ms | vs sphere: dcol proximity | dcol distance "
      "| Coal distance | vs itself: dcol proximity | dcol distance | Coal distance | proximity / Coal, "
      "all | proximity / Coal, separated |\n");
  std::printf("|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  for (int facets : sizes) {
    const int n = facets / 2 + 2;
    std::vector<double> pts(3 * static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      double u[3];
      rng.unit(u);
      pts[3 * i] = 0.6 * u[0];
      pts[3 * i + 1] = 0.5 * u[1];
      pts[3 * i + 2] = 0.4 * u[2];
    }
    std::vector<double> build_dcol, build_coal;
    dcol_shape *hull = nullptr;
    for (int b = 0; b < 5; ++b) {
      dcol_shape *h = nullptr;
      const double t0 = now_ns();
      if (dcol_shape_new_convex_hull(pts.data(), static_cast<size_t>(n), 0.0, &h) != DCOL_OK) die("hull");
      build_dcol.push_back((now_ns() - t0) * 1e-6);
      if (hull) dcol_shape_free(hull);
      hull = h;
    }
#ifdef DCOL_BENCH_HAVE_COAL
    std::shared_ptr<coal::ConvexBase> coal_hull;
    for (int b = 0; b < 5; ++b) {
      auto cp = std::make_shared<std::vector<coal::Vec3s>>();
      for (int i = 0; i < n; ++i) cp->emplace_back(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]);
      const double t0 = now_ns();
      coal::ConvexBase *c = coal::ConvexBase::convexHull(cp, static_cast<unsigned>(n), true, nullptr);
      build_coal.push_back((now_ns() - t0) * 1e-6);
      coal_hull.reset(c);
    }
#endif
    struct Case {
      dcol_pose p1, p2, ps;
      bool apart_self, apart_sphere;
    };
    std::vector<Case> cases;
    for (int k = 0; k < poses; ++k) {
      Case c;
      for (dcol_pose *p : {&c.p1, &c.p2, &c.ps}) {
        double q[3];
        rng.unit(q);
        const double w = rng.next();
        const double s = std::sqrt(1 - w * w);
        p->quaternion[0] = w;
        for (int j = 0; j < 3; ++j) p->quaternion[j + 1] = s * q[j];
      }
      double d[3];
      rng.unit(d);
      const double len = 1.05 + 0.55 * rng.next();
      const double lens = 0.65 + 0.3 * rng.next();
      for (int j = 0; j < 3; ++j) {
        c.p1.position[j] = 0;
        c.p2.position[j] = len * d[j];
        c.ps.position[j] = lens * d[j];
      }
      dcol_distance_result dr;
      if (dcol_distance(hull, &c.p1, hull, &c.p2, nullptr, &dr) != DCOL_OK) die("distance");
      c.apart_self = dr.distance > 0;
      if (dcol_distance(hull, &c.p1, sphere, &c.ps, nullptr, &dr) != DCOL_OK) die("distance");
      c.apart_sphere = dr.distance > 0;
      cases.push_back(c);
    }
    // [dcol prox sphere, dcol dist sphere, coal sphere, dcol prox self, dcol dist self, coal self]
    std::vector<double> t[6], apart[2][2];
    for (int r = 0; r < reps; ++r) {
      for (const Case &c : cases) {
        dcol_proximity_result pr;
        dcol_distance_result dr;
        double t0 = now_ns();
        if (dcol_proximity(hull, &c.p1, sphere, &c.ps, nullptr, &pr) != DCOL_OK) die("proximity");
        double t1 = now_ns();
        t[0].push_back(t1 - t0);
        t0 = now_ns();
        if (dcol_distance(hull, &c.p1, sphere, &c.ps, nullptr, &dr) != DCOL_OK) die("distance");
        t[1].push_back(now_ns() - t0);
        t0 = now_ns();
        if (dcol_proximity(hull, &c.p1, hull, &c.p2, nullptr, &pr) != DCOL_OK) die("proximity");
        t1 = now_ns();
        t[3].push_back(t1 - t0);
        if (c.apart_self) apart[1][0].push_back(t1 - t0);
        if (c.apart_sphere) apart[0][0].push_back(t[0].back());
        t0 = now_ns();
        if (dcol_distance(hull, &c.p1, hull, &c.p2, nullptr, &dr) != DCOL_OK) die("distance");
        t[4].push_back(now_ns() - t0);
#ifdef DCOL_BENCH_HAVE_COAL
        const coal::Transform3s tf1 = to_coal(c.p1), tf2 = to_coal(c.p2), tfs = to_coal(c.ps);
        coal::DistanceRequest req;
        coal::DistanceResult res;
        t0 = now_ns();
        coal::distance(coal_hull.get(), tf1, coal_sphere.get(), tfs, req, res);
        t1 = now_ns();
        t[2].push_back(t1 - t0);
        if (c.apart_sphere) apart[0][1].push_back(t1 - t0);
        res.clear();
        t0 = now_ns();
        coal::distance(coal_hull.get(), tf1, coal_hull.get(), tf2, req, res);
        t1 = now_ns();
        t[5].push_back(t1 - t0);
        if (c.apart_self) apart[1][1].push_back(t1 - t0);
#endif
      }
    }
    double m[6];
    for (int k = 0; k < 6; ++k) m[k] = median(t[k]);
    const double ratio_all = m[3] / m[5];
    const double ratio_apart = median(apart[1][0]) / median(apart[1][1]);
    std::printf("| %d | %d | %.2f | %.2f | %.0f | %.0f | %.0f | %.0f | %.0f | %.0f | %.2f | %.2f |\n",
                facets, n, median(build_dcol), median(build_coal), m[0], m[1], m[2], m[3], m[4], m[5],
                ratio_all, ratio_apart);
    std::fflush(stdout);
    dcol_shape_free(hull);
  }
  dcol_shape_free(sphere);
  return 0;
}
