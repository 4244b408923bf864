// bench_posesets: dcol against Coal 3 on a second pose set, drawn differently from bench_compare's
// (which dcol's speed work was measured on): a seed of its own, uniformly random attitudes for
// every case (no cube-aligned quarter), and offsets drawn so that alpha* is log-uniform in
// [0.3, 3] (the offset along a random direction rescaled by target / alpha*, alpha* being
// homogeneous of degree one in it). Each case is timed with every method back to back
// (DCOL_BENCH_REPEAT calls each, default 5, their mean), and the medians are reported per pair
// type and per subset: separated (alpha* > 1.02), near touching (0.98 to 1.02) and overlapping
// (< 0.98), comparing like with like:
//   - dcol_proximity against coal::distance (every subset; Coal runs EPA on overlaps);
//   - dcol_distance against coal::distance on separated and near-touching poses;
//   - dcol_signed_distance against coal::distance on overlapping poses (both give the depth).
// The 28 pair types of the seven kinds Coal has (padded polygons left out). Printed as markdown
// (run.sh writes it to results/posesets.md). DCOL_BENCH_CASES (default 600 per pair type),
// DCOL_BENCH_SEED (default 7), DCOL_BENCH_SMOKE=1 (12 cases).
#include <coal/collision_object.h>
#include <coal/distance.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "coal_body.hpp"
#include "compare_common.h"

namespace {

double now_ns() {
  return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now().time_since_epoch())
                                 .count());
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

enum Subset { kSeparated = 0, kNear, kOverlapping, kSubsets };
const char *const kSubsetNames[kSubsets] = {"separated", "near touching", "overlapping"};

// Per pair type and subset: samples (ns) of each method.
struct Samples {
  std::vector<double> prox, dist, signed_dist, coal;
};

}  // namespace

int main() {
  const bool smoke = std::getenv("DCOL_BENCH_SMOKE") != nullptr;
  const long cases = smoke ? 12 : cmp_env_long("DCOL_BENCH_CASES", 600);
  const long seed = cmp_env_long("DCOL_BENCH_SEED", 7);
  const int repeat = static_cast<int>(cmp_env_long("DCOL_BENCH_REPEAT", 5));
  std::printf("Second pose set: seed %ld, uniform random attitudes, alpha* log-uniform in [0.3, 3], "
              "%ld cases per pair type; Coal %s, default requests; medians in ns\n\n",
              seed, cases, DCOL_BENCH_COAL_VERSION);
  std::vector<std::string> names;
  std::vector<std::vector<Samples>> table;  // [pair][subset]
  long made = 0, refused = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1) {
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2) {
      if (k1 == CMP_POLYGON || k2 == CMP_POLYGON) continue;
      names.push_back(std::string(cmp_kind_name((cmp_kind)k1)) + "-" + cmp_kind_name((cmp_kind)k2));
      table.emplace_back(kSubsets);
      cmp_rng rng;
      cmp_rng_seed(&rng, (uint64_t)seed * 7919u + (uint64_t)(k1 * 16 + k2));
      for (long i = 0; i < cases; ++i) {
        cmp_shape s1, s2;
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
        cmp_body b1, b2;
        cmp_body_set(&b1, &s1, r0, q1);
        cmp_body_set(&b2, &s2, dir, q2);
        dcol_proximity_result pr;
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
        for (int r = 0; r < repeat; ++r) {
          coal::DistanceRequest req;
          coal::DistanceResult res;
          t0 = now_ns();
          coal::distance(c1.geom.get(), c1.tf, c2.geom.get(), c2.tf, req, res);
          acc += now_ns() - t0;
        }
        S.coal.push_back(acc / repeat);
        ++made;
        cmp_shape_release(&s1);
        cmp_shape_release(&s2);
      }
    }
  }
  // Per pair type: proximity / Coal per subset; distance / Coal on separated and near; signed
  // distance / Coal on overlapping.
  std::printf("| pair | proximity / Coal: separated | near | overlapping | distance / Coal: separated | "
              "near | signed distance / Coal: overlapping |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|\n");
  std::vector<double> all[6];  // per-pair ratios, for the all-pairs medians
  std::vector<double> abs_prox[kSubsets], abs_coal[kSubsets], abs_dist[2], abs_signed;
  for (size_t p = 0; p < names.size(); ++p) {
    double r[6];
    for (int s = 0; s < kSubsets; ++s) {
      const Samples &S = table[p][s];
      r[s] = median(S.prox) / median(S.coal);
      abs_prox[s].push_back(median(S.prox));
      abs_coal[s].push_back(median(S.coal));
    }
    r[3] = median(table[p][kSeparated].dist) / median(table[p][kSeparated].coal);
    r[4] = median(table[p][kNear].dist) / median(table[p][kNear].coal);
    r[5] = median(table[p][kOverlapping].signed_dist) / median(table[p][kOverlapping].coal);
    abs_dist[0].push_back(median(table[p][kSeparated].dist));
    abs_dist[1].push_back(median(table[p][kNear].dist));
    abs_signed.push_back(median(table[p][kOverlapping].signed_dist));
    std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f |\n", names[p].c_str(), r[0], r[1], r[2], r[3],
                r[4], r[5]);
    for (int k = 0; k < 6; ++k)
      if (std::isfinite(r[k])) all[k].push_back(r[k]);
  }
  std::printf("\nAll-pairs medians (the median over pair types of each pair type's median), ns:\n\n");
  std::printf("| subset | dcol proximity | dcol distance or signed distance | Coal distance | proximity / Coal | "
              "distance / Coal | worst pair type, proximity / Coal |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|\n");
  for (int s = 0; s < kSubsets; ++s) {
    const double second = s == kOverlapping ? median(abs_signed) : median(abs_dist[s]);
    const double worst = all[s].empty() ? NAN : *std::max_element(all[s].begin(), all[s].end());
    std::printf("| %s | %.0f | %.0f | %.0f | %.2f | %.2f | %.2f |\n", kSubsetNames[s], median(abs_prox[s]),
                second, median(abs_coal[s]), median(all[s]), median(all[s == kOverlapping ? 5 : 3 + s]), worst);
  }
  std::printf("\n%ld cases (%ld refused)\n", made, refused);
  return made > 0 ? 0 : 1;
}
