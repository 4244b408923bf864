// bench_posesets: dcol against Coal 3 per pair type, split by subset, on one of two pose sets:
//   - DCOL_BENCH_POSES=second (default): a pose set drawn differently from bench_compare's (which
//     dcol's speed work was measured on): a seed of its own, uniformly random attitudes for every
//     case (no cube-aligned quarter), and offsets drawn so that alpha* is log-uniform in [0.3, 3]
//     (the offset along a random direction rescaled by target / alpha*, alpha* being homogeneous
//     of degree one in it);
//   - DCOL_BENCH_POSES=compare: bench_compare's own cases (cmp_case_make, its seed 20240501 and
//     per-pair seeding), to read its poses per pair type against Coal with polygons included.
// Each case is timed with every method back to back (DCOL_BENCH_REPEAT calls each, default 5,
// their mean), and the medians are reported per pair type and per subset: separated
// (alpha* > 1.02), near touching (0.98 to 1.02) and overlapping (< 0.98), comparing like with like:
//   - dcol_proximity against coal::distance (every subset; Coal runs EPA on overlaps);
//   - dcol_distance against coal::distance on separated and near-touching poses;
//   - dcol_signed_distance against coal::distance on overlapping poses (both give the depth).
// All 36 pair types: a padded polygon is, for Coal, a flat convex with its swept-sphere radius
// (coal_body.hpp); the all-pairs medians are given over the 28 pair types without a polygon (as
// before) and over all 36. Agreement: separated cases where |dcol_distance - Coal's distance| >
// 1e-5 max(1, d) are counted per pair type (Coal's default gjk_tolerance is 1e-6; a wrong peer would make its times meaningless).
// Printed as markdown (run.sh writes it to results/posesets.md). DCOL_BENCH_CASES (default 600
// per pair type), DCOL_BENCH_SEED (default 7; 20240501 for the compare set), DCOL_BENCH_SMOKE=1
// (12 cases), DCOL_BENCH_PAIR=name (only that pair type, e.g. capsule-polygon).
#include <coal/collision_object.h>
#include <coal/distance.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "coal_body.hpp"
#include "compare_common.h"
#include "timing.hpp"

namespace {

using cmp_timing::median;
using cmp_timing::now_ns;

enum Subset { kSeparated = 0, kNear, kOverlapping, kSubsets };
const char *const kSubsetNames[kSubsets] = {"separated", "near touching", "overlapping"};

// Per pair type and subset: samples (ns) of each method.
struct Samples {
  std::vector<double> prox, dist, signed_dist, coal;
};

struct Pair {
  std::string name;
  bool polygon;
  long disagree = 0, checked = 0;
  double worst = 0;
};

}  // namespace

int main() {
  const bool smoke = std::getenv("DCOL_BENCH_SMOKE") != nullptr;
  const char *poses_env = std::getenv("DCOL_BENCH_POSES");
  const bool compare_set = poses_env != nullptr && std::strcmp(poses_env, "compare") == 0;
  const long cases = smoke ? 12 : cmp_env_long("DCOL_BENCH_CASES", 600);
  const long seed = cmp_env_long("DCOL_BENCH_SEED", compare_set ? 20240501 : 7);
  const int repeat = static_cast<int>(cmp_env_long("DCOL_BENCH_REPEAT", 5));
  const char *only = std::getenv("DCOL_BENCH_PAIR");
  if (compare_set)
    std::printf("bench_compare's pose set: seed %ld, cmp_case_make (a third each separated, near touching, "
                "overlapping by construction; a quarter cube-aligned), %ld cases per pair type; Coal %s, "
                "default requests; medians in ns\n\n",
                seed, cases, DCOL_BENCH_COAL_VERSION);
  else
    std::printf("Second pose set: seed %ld, uniform random attitudes, alpha* log-uniform in [0.3, 3], "
                "%ld cases per pair type; Coal %s, default requests; medians in ns\n\n",
                seed, cases, DCOL_BENCH_COAL_VERSION);
  std::vector<Pair> pairs;
  std::vector<std::vector<Samples>> table;  // [pair][subset]
  long made = 0, refused = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1) {
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2) {
      const std::string name = std::string(cmp_kind_name((cmp_kind)k1)) + "-" + cmp_kind_name((cmp_kind)k2);
      if (only != nullptr && name != only) continue;
      pairs.push_back(Pair{name, k1 == CMP_POLYGON || k2 == CMP_POLYGON});
      Pair &P = pairs.back();
      table.emplace_back(kSubsets);
      cmp_rng rng;
      if (compare_set)
        cmp_rng_seed(&rng, (uint64_t)seed * 1000003u + (uint64_t)(k1 * 16 + k2));
      else
        cmp_rng_seed(&rng, (uint64_t)seed * 7919u + (uint64_t)(k1 * 16 + k2));
      for (long i = 0; i < cases; ++i) {
        cmp_case c;
        cmp_shape &s1 = c.s1, &s2 = c.s2;
        cmp_body &b1 = c.b1, &b2 = c.b2;
        dcol_proximity_result pr;
        if (compare_set) {
          const int rc = cmp_case_make(&c, (cmp_kind)k1, (cmp_kind)k2, (int)i, &rng);
          if (rc < 0) continue;
          if (rc > 0 || dcol_proximity(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &pr) != DCOL_OK) {
            ++refused;
            cmp_case_release(&c);
            continue;
          }
        } else {
          if (cmp_shape_random(&s1, (cmp_kind)k1, &rng) != 0) continue;
          if (cmp_shape_random(&s2, (cmp_kind)k2, &rng) != 0) {
            cmp_shape_release(&s1);
            continue;
          }
          double q1[4], q2[4], dir[3], r0[3] = {0, 0, 0};
          cmp_rng_quaternion(&rng, q1);
          cmp_rng_quaternion(&rng, q2);
          cmp_rng_unit_vector(&rng, dir);
          const double target = std::exp(std::log(0.3) + (std::log(3.0) - std::log(0.3)) * cmp_rng_uniform(&rng, 0, 1));
          cmp_body_set(&b1, &s1, r0, q1);
          cmp_body_set(&b2, &s2, dir, q2);
          if (dcol_proximity(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &pr) != DCOL_OK || !(pr.alpha > 0)) {
            ++refused;
            cmp_shape_release(&s1);
            cmp_shape_release(&s2);
            continue;
          }
          const double r2[3] = {dir[0] * target / pr.alpha, dir[1] * target / pr.alpha, dir[2] * target / pr.alpha};
          cmp_body_set(&b2, &s2, r2, q2);
          if (dcol_proximity(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &pr) != DCOL_OK) {
            ++refused;
            cmp_shape_release(&s1);
            cmp_shape_release(&s2);
            continue;
          }
        }
        const Subset sub = pr.alpha > 1.02 ? kSeparated : pr.alpha >= 0.98 ? kNear : kOverlapping;
        const CoalBody c1 = to_coal(b1), c2 = to_coal(b2);
        Samples &S = table.back()[sub];
        double t0, acc;
        dcol_distance_result dr;
        dcol_signed_distance_result sr;
        acc = 0;
        for (int r = 0; r < repeat; ++r) {
          t0 = now_ns();
          dcol_proximity(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &pr);
          acc += now_ns() - t0;
        }
        S.prox.push_back(acc / repeat);
        if (sub != kOverlapping) {
          acc = 0;
          for (int r = 0; r < repeat; ++r) {
            t0 = now_ns();
            dcol_distance(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &dr);
            acc += now_ns() - t0;
          }
          S.dist.push_back(acc / repeat);
        } else {
          acc = 0;
          for (int r = 0; r < repeat; ++r) {
            t0 = now_ns();
            dcol_signed_distance(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &sr);
            acc += now_ns() - t0;
          }
          S.signed_dist.push_back(acc / repeat);
        }
        acc = 0;
        double coal_d = NAN;
        for (int r = 0; r < repeat; ++r) {
          coal::DistanceRequest req;
          coal::DistanceResult res;
          t0 = now_ns();
          coal::distance(c1.geom.get(), c1.tf, c2.geom.get(), c2.tf, req, res);
          acc += now_ns() - t0;
          coal_d = res.min_distance;
        }
        S.coal.push_back(acc / repeat);
        if (sub == kSeparated) {
          const double e = std::fabs(dr.distance - coal_d);
          ++P.checked;
          if (!(e <= 1e-5 * std::max(1.0, dr.distance))) ++P.disagree;
          if (!(e <= P.worst)) P.worst = e;
        }
        ++made;
        cmp_shape_release(&s1);
        cmp_shape_release(&s2);
      }
    }
  }
  // Per pair type: proximity / Coal per subset; distance / Coal on separated and near; signed
  // distance / Coal on overlapping; then the separated medians themselves and the agreement.
  std::printf("| pair | proximity / Coal: separated | near | overlapping | distance / Coal: separated | "
              "near | signed distance / Coal: overlapping | separated: dcol distance ns | Coal ns | "
              "disagreements (of separated) |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  // Per-pair ratios and medians, for the all-pairs medians: [0] without polygons, [1] all.
  std::vector<double> all[2][6];
  std::vector<double> abs_prox[2][kSubsets], abs_coal[2][kSubsets], abs_dist[2][2], abs_signed[2];
  long disagree = 0;
  for (size_t p = 0; p < pairs.size(); ++p) {
    double r[6];
    for (int s = 0; s < kSubsets; ++s) {
      const Samples &S = table[p][s];
      r[s] = median(S.prox) / median(S.coal);
    }
    r[3] = median(table[p][kSeparated].dist) / median(table[p][kSeparated].coal);
    r[4] = median(table[p][kNear].dist) / median(table[p][kNear].coal);
    r[5] = median(table[p][kOverlapping].signed_dist) / median(table[p][kOverlapping].coal);
    disagree += pairs[p].disagree;
    std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.0f | %ld of %ld (worst %.1e) |\n",
                pairs[p].name.c_str(), r[0], r[1], r[2], r[3], r[4], r[5], median(table[p][kSeparated].dist),
                median(table[p][kSeparated].coal), pairs[p].disagree, pairs[p].checked, pairs[p].worst);
    for (int g = 0; g < 2; ++g) {
      if (g == 0 && pairs[p].polygon) continue;
      for (int s = 0; s < kSubsets; ++s) {
        abs_prox[g][s].push_back(median(table[p][s].prox));
        abs_coal[g][s].push_back(median(table[p][s].coal));
      }
      abs_dist[g][0].push_back(median(table[p][kSeparated].dist));
      abs_dist[g][1].push_back(median(table[p][kNear].dist));
      abs_signed[g].push_back(median(table[p][kOverlapping].signed_dist));
      for (int k = 0; k < 6; ++k)
        if (std::isfinite(r[k])) all[g][k].push_back(r[k]);
    }
  }
  for (int g = 0; g < 2; ++g) {
    if (abs_prox[g][0].empty()) continue;
    std::printf("\nAll-pairs medians (the median over pair types of each pair type's median), ns, %s:\n\n",
                g == 0 ? "the 28 pair types without a padded polygon" : "all pair types (polygons included)");
    std::printf("| subset | dcol proximity | dcol distance or signed distance | Coal distance | proximity / Coal | "
                "distance / Coal | worst pair type, proximity / Coal | worst pair type, distance / Coal |\n");
    std::printf("|---|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int s = 0; s < kSubsets; ++s) {
      const double second = s == kOverlapping ? median(abs_signed[g]) : median(abs_dist[g][s]);
      const int dk = s == kOverlapping ? 5 : 3 + s;
      const double worst = all[g][s].empty() ? NAN : *std::max_element(all[g][s].begin(), all[g][s].end());
      const double worst_d = all[g][dk].empty() ? NAN : *std::max_element(all[g][dk].begin(), all[g][dk].end());
      std::printf("| %s | %.0f | %.0f | %.0f | %.2f | %.2f | %.2f | %.2f |\n", kSubsetNames[s],
                  median(abs_prox[g][s]), second, median(abs_coal[g][s]), median(all[g][s]), median(all[g][dk]),
                  worst, worst_d);
    }
  }
  std::printf("\n%ld cases (%ld refused); %ld separated cases where dcol_distance and Coal's distance differ by "
              "more than 1e-5 max(1, d)\n",
              made, refused, disagree);
  return made > 0 ? 0 : 1;
}
