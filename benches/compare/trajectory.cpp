// bench_trajectory: warm starts against cold queries on trajectories, dcol against Coal 3.
//
// The trajectory set is benches/warm.rs's: per trajectory two random shapes of the pair type
// (compare_common's cmp_shape_random, as bench_posesets), shape 1 at the origin, shape 2 along a
// random direction at the offset that gives alpha* = start; every step shape 2 translates 1 mm
// along a random direction that reverses every 250 steps and both turn 1 degree about their own
// fixed random axes; DCOL_BENCH_STEPS steps (default 1 000). warm.rs starts every trajectory at
// alpha* = 1.2; here trajectories alternate between start 1.2 (mostly separated steps) and 0.8
// (mostly overlapping steps), so that both subsets have steps. Every step is put in a subset by
// a cold dcol_proximity (untimed): separated alpha* > 1, overlapping alpha* < 1.
//
// Timing: the steps are cut into blocks of DCOL_BENCH_BLOCK (default 10) consecutive steps; each
// method runs a block's steps in a row under one std::chrono::steady_clock reading (this machine's
// clock ticks by 10 ns: one reading per call would quantise the cheapest pairs by 7 %), the methods
// one after the other in a random order drawn per block and round. Methods:
// dcol_proximity, dcol_distance, dcol_signed_distance and dcol_gradient cold and cached (one
// dcol_cache per query and trajectory, carried across all its steps and blocks), coal::distance
// cold (a fresh default DistanceRequest per call) and warm (one DistanceRequest per trajectory
// with gjk_initial_guess = CachedGuess and updateGuess(result) after every call: GJK starts from
// the last ray and the support functions from the last vertices); dcol_intersect cold and cached
// against libccd's ccdMPRIntersect (CCD_INIT defaults, compare_common's support functions, as
// bench_compare; MPR has no warm start). Every query runs on every step
// (the caches see the whole trajectory); the tables read each on its subset: proximity and
// distance against Coal on separated blocks, signed distance against Coal on overlapping blocks,
// the gradient and the boolean query on every block (a block belongs to a subset when all its steps do; the few mixed
// blocks where alpha* crosses 1 count only for "all"). DCOL_BENCH_ROUNDS rounds (default 5;
// caches and Coal's guess start cold each round); per block the median round, per pair type the
// median over its blocks, in ns per step (the timer's own cost, measured at start, subtracted).
//
// Agreement (a pass of its own before the timed rounds, untimed): cached against cold to 1e-12
// relative (alpha*; distance and signed distance relative to max(1, |d|); the gradient's
// largest entry difference relative to max(1, |g|_inf)); dcol against Coal cold and warm to
// 1e-5 max(1, |d|) (Coal's default gjk_tolerance is 1e-6, as bench_posesets): distance on
// separated steps, signed distance on overlapping steps; where the depths differ, both against
// the independent depth of depth_check.cpp (support functions only), to say who is off. Failed
// calls are counted. Booleans: cached against cold (equal), both dcol_intersect and MPR against
// alpha* < 1 outside |alpha* - 1| < 1e-6. The exit status is 3 when a cached alpha*, distance or
// signed distance is beyond 1e-12 of the cold one or a cached boolean differs (dcol_cache's
// contract in dcol.h; the gradient is only counted).
//
// Two seeds: DCOL_BENCH_SEEDS (default "3301,3302"; the first is the one the bench was developed
// on, the second is only measured). DCOL_BENCH_TRAJECTORIES per pair type (default 8),
// DCOL_BENCH_PAIR=name (one pair type), DCOL_BENCH_CPU=n (pin to core n), DCOL_BENCH_CSV=file
// (every median and ratio as CSV), DCOL_BENCH_SMOKE=1 (2 trajectories of 60 steps, 1 round),
// DCOL_BENCH_VERBOSE=1 (each overlapping disagreement's depths on stderr).
// Markdown on stdout (run.sh writes results/trajectory.md and results/trajectory.csv).
#include <coal/collision_object.h>
#include <ccd/ccd.h>
#include <coal/distance.h>
#include <sched.h>

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
#include "depth_check.hpp"
#include "timing.hpp"

namespace {

// libccd's support and centre from compare_common's support functions (as bench_compare's).
void ccd_support(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *vec) {
  const cmp_body *body = static_cast<const cmp_body *>(obj);
  double d[3] = {dir->v[0], dir->v[1], dir->v[2]}, p[3];
  cmp_support_world(body, d, p);
  ccdVec3Set(vec, p[0], p[1], p[2]);
}

void ccd_center(const void *obj, ccd_vec3_t *center) {
  const cmp_body *body = static_cast<const cmp_body *>(obj);
  ccdVec3Set(center, body->pose.position[0], body->pose.position[1], body->pose.position[2]);
}

using cmp_timing::median;
using cmp_timing::now_ns;

enum Method {
  kProxCold = 0,
  kProxCached,
  kDistCold,
  kDistCached,
  kSdCold,
  kSdCached,
  kGradCold,
  kGradCached,
  kCoalCold,
  kCoalWarm,
  kIsectCold,
  kIsectCached,
  kMpr,
  kMethods
};
const char *const kMethodNames[kMethods] = {
    "dcol_proximity",       "dcol_proximity_cached",       "dcol_distance", "dcol_distance_cached",
    "dcol_signed_distance", "dcol_signed_distance_cached", "dcol_gradient", "dcol_gradient_cached",
    "coal_distance_cold",   "coal_distance_warm",          "dcol_intersect", "dcol_intersect_cached",
    "ccdMPRIntersect"};

enum Subset { kSeparated = 0, kOverlapping, kAll, kSubsets };
const char *const kSubsetNames[kSubsets] = {"separated", "overlapping", "all"};

// Disagreement counters: cached vs cold per query, dcol vs Coal (cold, warm) per subset.
// On the overlapping steps where dcol and Coal disagree, both depths are compared with the
// independent depth of depth_check.cpp (kIndepDcol, kIndepCoal, kIndepCoalWarm: that one is
// off it).
enum Check {
  kCProx = 0,
  kCDist,
  kCSd,
  kCGrad,
  kCoalColdSep,
  kCoalWarmSep,
  kCoalColdOvl,
  kCoalWarmOvl,
  kIndepDcol,
  kIndepCoal,
  kIndepCoalWarm,
  kCIsect,
  kIsectWrong,
  kMprWrong,
  kChecks
};
const char *const kCheckNames[kChecks] = {"proximity cached vs cold",
                                          "distance cached vs cold",
                                          "signed distance cached vs cold",
                                          "gradient cached vs cold",
                                          "distance vs Coal cold (separated)",
                                          "distance vs Coal warm (separated)",
                                          "signed distance vs Coal cold (overlapping)",
                                          "signed distance vs Coal warm (overlapping)",
                                          "those overlaps: dcol vs the independent depth",
                                          "those overlaps: Coal cold vs the independent depth",
                                          "those overlaps: Coal warm vs the independent depth",
                                          "intersect cached vs cold",
                                          "dcol_intersect wrong (outside 1e-6 of touching)",
                                          "ccdMPRIntersect wrong (outside 1e-6 of touching)"};
// The bound column of the agreement table.
const char *check_bound(int c) {
  if (c < kCoalColdSep) return "1e-12 relative";
  if (c < kCIsect) return "1e-5 max(1, abs d)";
  return c == kCIsect ? "equal" : "alpha* < 1";
}

struct PairStats {
  std::string name;
  bool polygon = false;
  long steps[kSubsets] = {0, 0, 0};
  std::vector<double> t[kMethods][kSubsets];  // per block: the median round's ns per step
  long disagree[kChecks] = {}, checked[kChecks] = {};
  double worst[kChecks] = {};
  long failed[kMethods] = {};
  long trajectories = 0, refused = 0, mixed_blocks = 0;
  double med[kMethods][kSubsets];  // medians, the timer's cost subtracted
};

struct Config {
  long steps, trajectories, block;
  int rounds;
  const char *only;
};

void qmul(const double p[4], const double q[4], double out[4]) {
  out[0] = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3];
  out[1] = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2];
  out[2] = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1];
  out[3] = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0];
  const double n = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
  for (int i = 0; i < 4; ++i) out[i] /= n;
}

void turn(const double axis[3], double deg, double q[4]) {
  const double h = deg * M_PI / 360.0;
  q[0] = std::cos(h);
  for (int i = 0; i < 3; ++i) q[i + 1] = axis[i] * std::sin(h);
}

struct Step {
  cmp_body b1, b2;
  coal::Transform3s t1, t2;
  Subset subset;  // kAll: the cold proximity failed, the step is left out
  double alpha;   // the cold proximity's
};

// The trajectory (warm.rs's `poses`): false when dcol refused the start.
bool make_trajectory(const cmp_shape &s1, const cmp_shape &s2, double start, long steps, cmp_rng *rng,
                     std::vector<Step> *out) {
  double q1[4], q2[4], a1[3], a2[3], w1[4], w2[4], dir[3], v[3], tmp[4];
  cmp_rng_quaternion(rng, q1);
  cmp_rng_quaternion(rng, q2);
  cmp_rng_unit_vector(rng, a1);
  cmp_rng_unit_vector(rng, a2);
  turn(a1, 1.0, w1);
  turn(a2, 1.0, w2);
  cmp_rng_unit_vector(rng, dir);
  const double reach = s1.bound_radius + s2.bound_radius, r0[3] = {0, 0, 0};
  const double trial[3] = {dir[0] * reach, dir[1] * reach, dir[2] * reach};
  cmp_body b1, b2;
  cmp_body_set(&b1, &s1, r0, q1);
  cmp_body_set(&b2, &s2, trial, q2);
  dcol_proximity_result pr;
  if (dcol_proximity(s1.handle, &b1.pose, s2.handle, &b2.pose, nullptr, &pr) != DCOL_OK || !(pr.alpha > 0))
    return false;
  double r2[3] = {trial[0] * start / pr.alpha, trial[1] * start / pr.alpha, trial[2] * start / pr.alpha};
  cmp_rng_unit_vector(rng, v);
  for (double &x : v) x *= 1e-3;
  out->clear();
  for (long k = 0; k < steps; ++k) {
    Step st;
    cmp_body_set(&st.b1, &s1, r0, q1);
    cmp_body_set(&st.b2, &s2, r2, q2);
    st.t1 = coal_transform(st.b1);
    st.t2 = coal_transform(st.b2);
    const bool ok = dcol_proximity(s1.handle, &st.b1.pose, s2.handle, &st.b2.pose, nullptr, &pr) == DCOL_OK;
    st.subset = !ok ? kAll : pr.alpha > 1 ? kSeparated : kOverlapping;
    st.alpha = ok ? pr.alpha : NAN;
    out->push_back(st);
    if (k % 250 == 249)
      for (double &x : v) x = -x;
    for (int i = 0; i < 3; ++i) r2[i] += v[i];
    qmul(w1, q1, tmp);
    std::memcpy(q1, tmp, sizeof tmp);
    qmul(w2, q2, tmp);
    std::memcpy(q2, tmp, sizeof tmp);
  }
  return true;
}

// What round 1 keeps of each call for the checks.
struct Answers {
  double prox[2], dist[2], sd[2], grad[2][14], coal[2], sd_normal[3], coal_normal[2][3];
  int isect[3];  // dcol_intersect cold, cached, ccdMPRIntersect
  bool ok[kMethods];
};

void check(PairStats &P, Check c, double diff, double bound) {
  ++P.checked[c];
  if (!(diff <= bound)) ++P.disagree[c];
  if (!(diff <= P.worst[c])) P.worst[c] = diff;
}

void check_step(PairStats &P, const Answers &a, const Step &st) {
  const Subset sub = st.subset;
  if (a.ok[kProxCold] && a.ok[kProxCached])
    check(P, kCProx, std::fabs(a.prox[1] - a.prox[0]) / std::fabs(a.prox[0]), 1e-12);
  if (a.ok[kDistCold] && a.ok[kDistCached])
    check(P, kCDist, std::fabs(a.dist[1] - a.dist[0]) / std::max(1.0, a.dist[0]), 1e-12);
  if (a.ok[kSdCold] && a.ok[kSdCached])
    check(P, kCSd, std::fabs(a.sd[1] - a.sd[0]) / std::max(1.0, std::fabs(a.sd[0])), 1e-12);
  if (a.ok[kGradCold] && a.ok[kGradCached]) {
    double diff = 0, scale = 1;
    for (int i = 0; i < 14; ++i) {
      diff = std::max(diff, std::fabs(a.grad[1][i] - a.grad[0][i]));
      scale = std::max(scale, std::fabs(a.grad[0][i]));
    }
    check(P, kCGrad, diff / scale, 1e-12);
  }
  if (a.ok[kIsectCold] && a.ok[kIsectCached]) check(P, kCIsect, a.isect[1] == a.isect[0] ? 0 : 1, 0);
  if (std::fabs(st.alpha - 1) >= 1e-6) {
    const int truth = st.alpha < 1;
    if (a.ok[kIsectCold]) check(P, kIsectWrong, a.isect[0] == truth ? 0 : 1, 0);
    check(P, kMprWrong, a.isect[2] == truth ? 0 : 1, 0);
  }
  bool ovl_disagree = false;
  for (int w = 0; w < 2; ++w) {
    if (!a.ok[kCoalCold + w]) continue;
    if (sub == kSeparated && a.ok[kDistCold])
      check(P, w == 0 ? kCoalColdSep : kCoalWarmSep, std::fabs(a.dist[0] - a.coal[w]),
            1e-5 * std::max(1.0, a.dist[0]));
    if (sub == kOverlapping && a.ok[kSdCold]) {
      const double bound = 1e-5 * std::max(1.0, std::fabs(a.sd[0]));
      check(P, w == 0 ? kCoalColdOvl : kCoalWarmOvl, std::fabs(a.sd[0] - a.coal[w]), bound);
      ovl_disagree = ovl_disagree || !(std::fabs(a.sd[0] - a.coal[w]) <= bound);
    }
  }
  if (ovl_disagree && a.ok[kCoalCold]) {
    // Who is right: both against the independent depth (its normals as candidates only).
    std::vector<Dir> cand;
    for (const double *n : {a.sd_normal, a.coal_normal[0], a.coal_normal[1]})
      for (double sgn : {1.0, -1.0}) cand.push_back(Dir{sgn * n[0], sgn * n[1], sgn * n[2]});
    const IndependentDepth ind = independent_depth(st.b1, st.b2, cand);
    const double bound = 1e-5 * std::max(1.0, ind.depth);
    check(P, kIndepDcol, std::fabs(-a.sd[0] - ind.depth), bound);
    check(P, kIndepCoal, std::fabs(-a.coal[0] - ind.depth), bound);
    if (a.ok[kCoalWarm]) check(P, kIndepCoalWarm, std::fabs(-a.coal[1] - ind.depth), bound);
    if (std::getenv("DCOL_BENCH_VERBOSE") != nullptr)
      std::fprintf(stderr, "%s: dcol signed distance %.9f, Coal cold %.9f, warm %.9f, independent -%.9f\n",
                   P.name.c_str(), a.sd[0], a.coal[0], a.coal[1], ind.depth);
  }
}

struct TrajectoryState {
  dcol_cache cache[5];  // proximity, distance, signed distance, gradient, intersect
  coal::DistanceRequest warm;
  void reset() {
    for (dcol_cache &c : cache) c = DCOL_CACHE_INIT;
    warm = coal::DistanceRequest();
    warm.gjk_initial_guess = coal::GJKInitialGuess::CachedGuess;
  }
};

// One call of method m at step st; its answer into a (when a is not null).
inline void call_method(int m, const cmp_shape &s1, const cmp_shape &s2, const Step &st, const CoalBody &c1,
                  const CoalBody &c2, TrajectoryState &S, Answers *a) {
  const dcol_pose *p1 = &st.b1.pose, *p2 = &st.b2.pose;
  dcol_proximity_result pr;
  dcol_distance_result dr;
  dcol_signed_distance_result sr;
  double g[14];
  dcol_status rc = DCOL_OK;
  switch (m) {
    case kProxCold:
    case kProxCached:
      rc = m == kProxCold ? dcol_proximity(s1.handle, p1, s2.handle, p2, nullptr, &pr)
                          : dcol_proximity_cached(s1.handle, p1, s2.handle, p2, nullptr, &S.cache[0], &pr);
      if (a) a->prox[m - kProxCold] = pr.alpha;
      break;
    case kDistCold:
    case kDistCached:
      rc = m == kDistCold ? dcol_distance(s1.handle, p1, s2.handle, p2, nullptr, &dr)
                          : dcol_distance_cached(s1.handle, p1, s2.handle, p2, nullptr, &S.cache[1], &dr);
      if (a) a->dist[m - kDistCold] = dr.distance;
      break;
    case kSdCold:
    case kSdCached:
      rc = m == kSdCold ? dcol_signed_distance(s1.handle, p1, s2.handle, p2, nullptr, &sr)
                        : dcol_signed_distance_cached(s1.handle, p1, s2.handle, p2, nullptr, &S.cache[2], &sr);
      if (a) a->sd[m - kSdCold] = sr.distance;
      if (a && m == kSdCold) std::memcpy(a->sd_normal, sr.normal, sizeof sr.normal);
      break;
    case kGradCold:
    case kGradCached:
      rc = m == kGradCold ? dcol_gradient(s1.handle, p1, s2.handle, p2, nullptr, &pr, g)
                          : dcol_gradient_cached(s1.handle, p1, s2.handle, p2, nullptr, &S.cache[3], &pr, g);
      if (a) std::memcpy(a->grad[m - kGradCold], g, sizeof g);
      break;
    case kCoalCold: {
      coal::DistanceRequest req;
      coal::DistanceResult res;
      coal::distance(c1.geom.get(), st.t1, c2.geom.get(), st.t2, req, res);
      if (a) a->coal[0] = res.min_distance;
      if (a)
        for (int i = 0; i < 3; ++i) a->coal_normal[0][i] = res.normal[i];
      break;
    }
    case kIsectCold:
    case kIsectCached: {
      int32_t hit = 0;
      rc = m == kIsectCold ? dcol_intersect(s1.handle, p1, s2.handle, p2, nullptr, &hit)
                           : dcol_intersect_cached(s1.handle, p1, s2.handle, p2, nullptr, &S.cache[4], &hit);
      if (a) a->isect[m - kIsectCold] = hit != 0;
      break;
    }
    case kMpr: {
      ccd_t ccd;
      CCD_INIT(&ccd);
      ccd.support1 = ccd_support;
      ccd.support2 = ccd_support;
      ccd.center1 = ccd_center;
      ccd.center2 = ccd_center;
      const int hit = ccdMPRIntersect(&st.b1, &st.b2, &ccd);
      if (a) a->isect[2] = hit != 0;
      break;
    }
    case kCoalWarm: {
      coal::DistanceResult res;
      coal::distance(c1.geom.get(), st.t1, c2.geom.get(), st.t2, S.warm, res);
      S.warm.updateGuess(res);
      if (a) a->coal[1] = res.min_distance;
      if (a)
        for (int i = 0; i < 3; ++i) a->coal_normal[1][i] = res.normal[i];
      break;
    }
    default:
      break;
  }
  if (a) a->ok[m] = rc == DCOL_OK;
}

// Every trajectory of one pair type.
void run_pair(PairStats &P, int k1, int k2, long seed, const Config &cfg) {
  cmp_rng rng;
  cmp_rng_seed(&rng, (uint64_t)seed * 7919u + (uint64_t)(k1 * 16 + k2));
  cmp_rng shuffle;
  cmp_rng_seed(&shuffle, (uint64_t)seed * 104729u + (uint64_t)(k1 * 16 + k2));
  std::vector<Step> traj;
  std::vector<double> times[kMethods];
  for (long t = 0; t < cfg.trajectories; ++t) {
    cmp_shape s1, s2;
    if (cmp_shape_random(&s1, (cmp_kind)k1, &rng) != 0) continue;
    if (cmp_shape_random(&s2, (cmp_kind)k2, &rng) != 0) {
      cmp_shape_release(&s1);
      continue;
    }
    const double start = t % 2 == 0 ? 1.2 : 0.8;
    if (!make_trajectory(s1, s2, start, cfg.steps, &rng, &traj)) {
      ++P.refused;
      cmp_shape_release(&s1);
      cmp_shape_release(&s2);
      continue;
    }
    ++P.trajectories;
    const CoalBody c1 = to_coal(traj[0].b1), c2 = to_coal(traj[0].b2);
    const long n = static_cast<long>(traj.size());
    for (auto &v : times) v.assign(static_cast<size_t>(n * cfg.rounds), 0.0);
    TrajectoryState S;
    // The check pass (untimed): every method on every step, the answers compared.
    S.reset();
    for (long k = 0; k < n; ++k) {
      Answers ans;
      for (int m = 0; m < kMethods; ++m) call_method(m, s1, s2, traj[k], c1, c2, S, &ans);
      for (int m = 0; m < kMethods; ++m)
        if (!ans.ok[m]) ++P.failed[m];
      if (traj[k].subset != kAll) check_step(P, ans, traj[k]);
    }
    // The timed rounds: per block of cfg.block steps, each method runs the block's steps in a
    // row (its cache or guess carried on from the previous block), the methods one after the
    // other.
    const long blocks = (n + cfg.block - 1) / cfg.block;
    for (auto &v : times) v.assign(static_cast<size_t>(blocks * cfg.rounds), 0.0);
    for (int r = 0; r < cfg.rounds; ++r) {
      S.reset();
      for (long b = 0; b < blocks; ++b) {
        const long k0 = b * cfg.block, k1 = std::min(n, k0 + cfg.block);
        // A fresh random order per block: a method that runs right after its twin (cached after
        // cold) on the same steps finds the caches and branch predictors trained on them (a fixed
        // order made the cached signed distance of curved pairs, the very same computation as the
        // cold one, 0.88-0.95x cold); at random, each goes first half the time.
        int order[kMethods];
        for (int j = 0; j < kMethods; ++j) order[j] = j;
        for (int j = kMethods - 1; j > 0; --j) std::swap(order[j], order[cmp_rng_int(&shuffle, 0, j)]);
        for (int j = 0; j < kMethods; ++j) {
          const int m = order[j];
          const double t0 = now_ns();
          for (long k = k0; k < k1; ++k) call_method(m, s1, s2, traj[k], c1, c2, S, nullptr);
          times[m][static_cast<size_t>(b * cfg.rounds + r)] = (now_ns() - t0) / static_cast<double>(k1 - k0);
        }
      }
    }
    // A block counts for a subset when all its steps are in it (and for "all" when none failed).
    for (long b = 0; b < blocks; ++b) {
      const long k0 = b * cfg.block, k1 = std::min(n, k0 + cfg.block);
      Subset sub = traj[k0].subset;
      bool failed = false;
      for (long k = k0; k < k1; ++k) {
        failed = failed || traj[k].subset == kAll;
        if (traj[k].subset != sub) sub = kAll;
      }
      if (failed) continue;
      if (sub == kAll) ++P.mixed_blocks;
      for (int m = 0; m < kMethods; ++m) {
        std::vector<double> rounds(times[m].begin() + b * cfg.rounds, times[m].begin() + (b + 1) * cfg.rounds);
        const double t_block = median(rounds);
        if (sub != kAll) P.t[m][sub].push_back(t_block);
        P.t[m][kAll].push_back(t_block);
      }
      if (sub != kAll) P.steps[sub] += k1 - k0;
      P.steps[kAll] += k1 - k0;
    }
    cmp_shape_release(&s1);
    cmp_shape_release(&s2);
  }
}

double timer_cost() {
  std::vector<double> v(20001);
  for (double &x : v) {
    const double t0 = now_ns();
    x = now_ns() - t0;
  }
  return median(v);
}

std::string fmt(double x, const char *f) {
  if (!std::isfinite(x)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

const int kRatios = 11;  // kSummaryNames
struct SeedSummary {
  long seed;
  double ratio[kRatios];  // all 36: see kSummaryNames
  long disagree[kChecks], checked[kChecks], failed;
  long steps[kSubsets];
};
const char *const kSummaryNames[kRatios] = {
    "proximity cached / cold (separated)", "distance cached / cold (separated)",
    "signed distance cached / cold (overlapping)", "gradient cached / cold (all steps)",
    "Coal warm / cold (separated)", "Coal warm / cold (overlapping)",
    "proximity cached / Coal warm (separated)", "distance cached / Coal warm (separated)",
    "signed distance cached / Coal warm (overlapping)", "intersect cached / cold (all steps)",
    "intersect cached / ccdMPRIntersect (all steps)"};

// The ratios of one pair type, in kSummaryNames's order.
void ratios(const PairStats &P, double r[kRatios]) {
  auto q = [&](int a, int b, Subset s) { return P.med[a][s] / P.med[b][s]; };
  r[0] = q(kProxCached, kProxCold, kSeparated);
  r[1] = q(kDistCached, kDistCold, kSeparated);
  r[2] = q(kSdCached, kSdCold, kOverlapping);
  r[3] = q(kGradCached, kGradCold, kAll);
  r[4] = q(kCoalWarm, kCoalCold, kSeparated);
  r[5] = q(kCoalWarm, kCoalCold, kOverlapping);
  r[6] = q(kProxCached, kCoalWarm, kSeparated);
  r[7] = q(kDistCached, kCoalWarm, kSeparated);
  r[8] = q(kSdCached, kCoalWarm, kOverlapping);
  r[9] = q(kIsectCached, kIsectCold, kAll);
  r[10] = q(kIsectCached, kMpr, kAll);
}

SeedSummary report(std::vector<PairStats> &pairs, long seed, const Config &cfg, double overhead, FILE *csv) {
  SeedSummary sum{};
  sum.seed = seed;
  for (PairStats &P : pairs)
    for (int m = 0; m < kMethods; ++m)
      for (int s = 0; s < kSubsets; ++s)
        P.med[m][s] = std::max(0.0, median(P.t[m][s]) - overhead / static_cast<double>(cfg.block));
  std::printf("\n## Seed %ld\n\n", seed);
  std::printf("Separated blocks (alpha* > 1): median ns per step; ratios of the medians, same run.\n\n");
  std::printf("| pair | steps | proximity cold | cached | cached / cold | distance cold | cached | cached / cold | "
              "Coal cold | Coal warm | warm / cold | proximity cached / Coal warm | distance cached / Coal warm |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  for (const PairStats &P : pairs) {
    double r[kRatios];
    ratios(P, r);
    const int s = kSeparated;
    std::printf("| %s | %ld | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", P.name.c_str(), P.steps[s],
                fmt(P.med[kProxCold][s], "%.0f").c_str(), fmt(P.med[kProxCached][s], "%.0f").c_str(),
                fmt(r[0], "%.2f").c_str(), fmt(P.med[kDistCold][s], "%.0f").c_str(),
                fmt(P.med[kDistCached][s], "%.0f").c_str(), fmt(r[1], "%.2f").c_str(),
                fmt(P.med[kCoalCold][s], "%.0f").c_str(), fmt(P.med[kCoalWarm][s], "%.0f").c_str(),
                fmt(r[4], "%.2f").c_str(), fmt(r[6], "%.2f").c_str(), fmt(r[7], "%.2f").c_str());
  }
  std::printf("\nOverlapping blocks (alpha* < 1), and the gradient on every block.\n\n");
  std::printf("| pair | steps | signed distance cold | cached | cached / cold | Coal cold | Coal warm | warm / cold | "
              "signed distance cached / Coal warm | gradient cold (all) | cached | cached / cold |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  for (const PairStats &P : pairs) {
    double r[kRatios];
    ratios(P, r);
    const int s = kOverlapping;
    std::printf("| %s | %ld | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", P.name.c_str(), P.steps[s],
                fmt(P.med[kSdCold][s], "%.0f").c_str(), fmt(P.med[kSdCached][s], "%.0f").c_str(),
                fmt(r[2], "%.2f").c_str(), fmt(P.med[kCoalCold][s], "%.0f").c_str(),
                fmt(P.med[kCoalWarm][s], "%.0f").c_str(), fmt(r[5], "%.2f").c_str(), fmt(r[8], "%.2f").c_str(),
                fmt(P.med[kGradCold][kAll], "%.0f").c_str(), fmt(P.med[kGradCached][kAll], "%.0f").c_str(),
                fmt(r[3], "%.2f").c_str());
  }
  std::printf("\nThe boolean query on every block: dcol_intersect cold and cached against libccd's MPR "
              "(ccdMPRIntersect, CCD_INIT defaults, on compare_common's support functions; no warm start).\n\n");
  std::printf("| pair | steps | intersect cold | cached | cached / cold | ccdMPRIntersect | cached / MPR |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|\n");
  for (const PairStats &P : pairs) {
    double r[kRatios];
    ratios(P, r);
    std::printf("| %s | %ld | %s | %s | %s | %s | %s |\n", P.name.c_str(), P.steps[kAll],
                fmt(P.med[kIsectCold][kAll], "%.0f").c_str(), fmt(P.med[kIsectCached][kAll], "%.0f").c_str(),
                fmt(r[9], "%.2f").c_str(), fmt(P.med[kMpr][kAll], "%.0f").c_str(), fmt(r[10], "%.2f").c_str());
  }
  // All-pairs medians: the median over pair types of each pair type's median (or ratio).
  std::printf("\nAll-pairs medians (median over pair types of the per-pair medians and ratios):\n\n");
  std::printf("| pair types | proximity cold | cached | distance cold | cached | Coal cold (sep.) | Coal warm (sep.) | "
              "signed distance cold | cached | Coal cold (ovl.) | Coal warm (ovl.) | gradient cold | cached | "
              "intersect cold | cached | ccdMPRIntersect |\n");
  std::printf("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  const int kCols = 15;
  const int cols[kCols][2] = {{kProxCold, kSeparated},   {kProxCached, kSeparated}, {kDistCold, kSeparated},
                           {kDistCached, kSeparated}, {kCoalCold, kSeparated},   {kCoalWarm, kSeparated},
                           {kSdCold, kOverlapping},   {kSdCached, kOverlapping}, {kCoalCold, kOverlapping},
                           {kCoalWarm, kOverlapping}, {kGradCold, kAll},         {kGradCached, kAll},
                              {kIsectCold, kAll},        {kIsectCached, kAll},      {kMpr, kAll}};
  std::vector<double> rat[2][kRatios];
  for (int g = 0; g < 2; ++g) {
    std::vector<double> col[kCols];
    for (const PairStats &P : pairs) {
      if (g == 0 && P.polygon) continue;
      for (int c = 0; c < kCols; ++c)
        if (std::isfinite(P.med[cols[c][0]][cols[c][1]]) && P.steps[cols[c][1]] > 0)
          col[c].push_back(P.med[cols[c][0]][cols[c][1]]);
      double r[kRatios];
      ratios(P, r);
      for (int k = 0; k < kRatios; ++k)
        if (std::isfinite(r[k])) rat[g][k].push_back(r[k]);
    }
    if (col[0].empty()) continue;
    std::printf("| %s |", g == 0 ? "28 without a polygon" : "all");
    for (int c = 0; c < kCols; ++c) std::printf(" %s |", fmt(median(col[c]), "%.0f").c_str());
    std::printf("\n");
  }
  std::printf("\n| ratio (median over pair types) | 28 without a polygon | all | best pair type | worst pair type |\n");
  std::printf("|---|--:|--:|--:|--:|\n");
  for (int k = 0; k < kRatios; ++k) {
    std::string best = "–", worst = "–";
    double lo = INFINITY, hi = -INFINITY;
    for (const PairStats &P : pairs) {
      double r[kRatios];
      ratios(P, r);
      if (!std::isfinite(r[k])) continue;
      if (r[k] < lo) lo = r[k], best = P.name + " " + fmt(r[k], "%.2f");
      if (r[k] > hi) hi = r[k], worst = P.name + " " + fmt(r[k], "%.2f");
    }
    sum.ratio[k] = median(rat[1][k]);
    std::printf("| %s | %s | %s | %s | %s |\n", kSummaryNames[k], fmt(median(rat[0][k]), "%.2f").c_str(),
                fmt(sum.ratio[k], "%.2f").c_str(), best.c_str(), worst.c_str());
  }
  // Agreement.
  std::printf("\nAgreement (an untimed pass over every step): steps beyond the bound / steps checked (worst difference). On the "
              "overlapping steps where dcol and Coal differ, both depths are set against an independent depth "
              "(depth_check.cpp: the minimum over directions of the overlap of the support functions).\n\n");
  std::printf("| check | bound | disagreements | worst |\n|---|---|--:|--:|\n");
  for (int c = 0; c < kChecks; ++c) {
    double worst = 0;
    for (const PairStats &P : pairs) {
      sum.disagree[c] += P.disagree[c];
      sum.checked[c] += P.checked[c];
      worst = std::max(worst, P.worst[c]);
    }
    std::printf("| %s | %s | %ld of %ld | %.1e |\n", kCheckNames[c], check_bound(c),
                sum.disagree[c], sum.checked[c], worst);
  }
  std::string per_pair;
  for (const PairStats &P : pairs) {
    std::string row;
    for (int c = 0; c < kChecks; ++c)
      if (P.disagree[c] > 0) row += std::string(row.empty() ? "" : ", ") + kCheckNames[c] + " " + std::to_string(P.disagree[c]);
    if (!row.empty()) per_pair += "- " + P.name + ": " + row + "\n";
  }
  if (!per_pair.empty()) std::printf("\nPair types with disagreements:\n\n%s", per_pair.c_str());
  long trajectories = 0, refused = 0, mixed = 0;
  for (const PairStats &P : pairs) {
    mixed += P.mixed_blocks;
    for (int m = 0; m < kMethods; ++m) sum.failed += P.failed[m];
    for (int s = 0; s < kSubsets; ++s) sum.steps[s] += P.steps[s];
    trajectories += P.trajectories;
    refused += P.refused;
  }
  std::printf("\n%ld trajectories (%ld refused at the start), %ld steps timed: %ld in separated blocks, %ld in "
              "overlapping blocks, %ld blocks mixed; %ld failed calls; %d rounds\n",
              trajectories, refused, sum.steps[kAll], sum.steps[kSeparated], sum.steps[kOverlapping], mixed,
              sum.failed, cfg.rounds);
  if (csv) {
    for (const PairStats &P : pairs) {
      for (int m = 0; m < kMethods; ++m)
        for (int s = 0; s < kSubsets; ++s)
          if (P.steps[s] > 0)
            std::fprintf(csv, "%ld,%s,%s,%s,ns,%.1f,%ld\n", seed, P.name.c_str(), kSubsetNames[s], kMethodNames[m],
                         P.med[m][s], P.steps[s]);
      double r[kRatios];
      ratios(P, r);
      for (int k = 0; k < kRatios; ++k)
        if (std::isfinite(r[k])) std::fprintf(csv, "%ld,%s,,%s,ratio,%.4f,\n", seed, P.name.c_str(), kSummaryNames[k], r[k]);
    }
    for (int k = 0; k < kRatios; ++k) {
      std::fprintf(csv, "%ld,all-pairs,,%s,ratio,%.4f,\n", seed, kSummaryNames[k], median(rat[1][k]));
      std::fprintf(csv, "%ld,all-pairs-28,,%s,ratio,%.4f,\n", seed, kSummaryNames[k], median(rat[0][k]));
    }
    for (int c = 0; c < kChecks; ++c)
      std::fprintf(csv, "%ld,all-pairs,,%s,disagreements,%ld,%ld\n", seed, kCheckNames[c], sum.disagree[c],
                   sum.checked[c]);
  }
  return sum;
}

}  // namespace

int main() {
  const bool smoke = std::getenv("DCOL_BENCH_SMOKE") != nullptr;
  Config cfg;
  cfg.steps = smoke ? 60 : cmp_env_long("DCOL_BENCH_STEPS", 1000);
  cfg.trajectories = smoke ? 2 : cmp_env_long("DCOL_BENCH_TRAJECTORIES", 8);
  cfg.rounds = smoke ? 1 : static_cast<int>(cmp_env_long("DCOL_BENCH_ROUNDS", 5));
  cfg.block = cmp_env_long("DCOL_BENCH_BLOCK", 10);
  cfg.only = std::getenv("DCOL_BENCH_PAIR");
  if (cfg.steps < 1 || cfg.trajectories < 1 || cfg.rounds < 1 || cfg.block < 1) {
    std::fprintf(stderr, "bench_trajectory: DCOL_BENCH_STEPS, _TRAJECTORIES, _ROUNDS and _BLOCK must be >= 1\n");
    return 2;
  }
  std::vector<long> seeds;
  {
    const char *env = std::getenv("DCOL_BENCH_SEEDS");
    std::string s = env ? env : "3301,3302";
    size_t pos = 0;
    while (pos <= s.size()) {
      const size_t comma = std::min(s.find(',', pos), s.size());
      if (comma > pos) seeds.push_back(std::strtol(s.substr(pos, comma - pos).c_str(), nullptr, 10));
      pos = comma + 1;
    }
  }
  std::string pinned = "not pinned";
  if (const char *cpu = std::getenv("DCOL_BENCH_CPU")) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(std::atoi(cpu), &set);
    pinned = sched_setaffinity(0, sizeof set, &set) == 0 ? std::string("pinned to CPU ") + cpu
                                                         : std::string("could not pin to CPU ") + cpu;
  }
  FILE *csv = nullptr;
  if (const char *path = std::getenv("DCOL_BENCH_CSV")) {
    csv = std::fopen(path, "w");
    if (!csv) {
      std::fprintf(stderr, "bench_trajectory: cannot write %s\n", path);
      return 2;
    }
    std::fprintf(csv, "seed,pair,subset,quantity,unit,value,steps\n");
  }
  const double overhead = timer_cost();
  std::printf("# Trajectories: warm against cold, dcol against Coal %s\n\n", DCOL_BENCH_COAL_VERSION);
  std::printf("%ld trajectories per pair type (start alpha* 1.2 and 0.8 alternately), %ld steps of 1 mm and 1 "
              "degree, timed in blocks of %ld steps, %d rounds (per block the median round, per pair type the "
              "median block, ns per step); default tolerances and requests; %s; the timer's own cost, %.0f ns a "
              "reading, subtracted.\n",
              cfg.trajectories, cfg.steps, cfg.block, cfg.rounds, pinned.c_str(), overhead);
  std::vector<SeedSummary> sums;
  for (long seed : seeds) {
    std::vector<PairStats> pairs;
    for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1)
      for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2) {
        const std::string name = std::string(cmp_kind_name((cmp_kind)k1)) + "-" + cmp_kind_name((cmp_kind)k2);
        if (cfg.only != nullptr && name != cfg.only) continue;
        pairs.emplace_back();
        pairs.back().name = name;
        pairs.back().polygon = k1 == CMP_POLYGON || k2 == CMP_POLYGON;
        run_pair(pairs.back(), k1, k2, seed, cfg);
      }
    if (pairs.empty()) {
      std::fprintf(stderr, "bench_trajectory: no pair type named %s\n", cfg.only ? cfg.only : "");
      return 2;
    }
    sums.push_back(report(pairs, seed, cfg, overhead, csv));
  }
  std::printf("\n## Both seeds: all-pairs medians of the per-pair ratios (all pair types)\n\n| ratio |");
  for (const SeedSummary &s : sums) std::printf(" seed %ld |", s.seed);
  std::printf("\n|---|");
  for (size_t i = 0; i < sums.size(); ++i) std::printf("--:|");
  std::printf("\n");
  for (int k = 0; k < kRatios; ++k) {
    std::printf("| %s |", kSummaryNames[k]);
    for (const SeedSummary &s : sums) std::printf(" %s |", fmt(s.ratio[k], "%.2f").c_str());
    std::printf("\n");
  }
  long steps = 0, contract = 0;
  for (const SeedSummary &s : sums) {
    steps += s.steps[kAll];
    contract += s.disagree[kCProx] + s.disagree[kCDist] + s.disagree[kCSd] + s.disagree[kCIsect];
  }
  std::printf("| disagreements, cached vs cold |");
  for (const SeedSummary &s : sums)
    std::printf(" %ld |", s.disagree[kCProx] + s.disagree[kCDist] + s.disagree[kCSd] + s.disagree[kCGrad] +
                              s.disagree[kCIsect]);
  std::printf("\n| disagreements, dcol vs Coal (cold + warm) |");
  for (const SeedSummary &s : sums)
    std::printf(" %ld |", s.disagree[kCoalColdSep] + s.disagree[kCoalWarmSep] + s.disagree[kCoalColdOvl] + s.disagree[kCoalWarmOvl]);
  std::printf("\n| of those overlaps: dcol / Coal cold / Coal warm off the independent depth |");
  for (const SeedSummary &s : sums)
    std::printf(" %ld / %ld / %ld |", s.disagree[kIndepDcol], s.disagree[kIndepCoal], s.disagree[kIndepCoalWarm]);
  std::printf("\n| wrong booleans (outside 1e-6 of touching): dcol_intersect / ccdMPRIntersect |");
  for (const SeedSummary &s : sums) std::printf(" %ld / %ld |", s.disagree[kIsectWrong], s.disagree[kMprWrong]);
  std::printf("\n");
  if (csv) std::fclose(csv);
  std::fflush(stdout);
  if (contract > 0) {
    // dcol_cache's contract (dcol.h): warm alpha* and distances within 1e-12 relative of cold.
    std::fprintf(stderr, "bench_trajectory: %ld cached answers (alpha*, distance, signed distance beyond 1e-12 "
                 "relative; intersect at all) differ from the cold ones\n", contract);
    return 3;
  }
  return steps > 0 ? 0 : 1;
}
