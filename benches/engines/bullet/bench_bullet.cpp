// Cost of dcol inside Bullet: the pile and the pyramid of the ctest scenes
// (integrations/bullet/tests/scenes.hpp), each stepped with Bullet's narrow phase (native) and
// with dcol's (use_dcol), in one process, alternating, and printed as a table:
//
//   whole step: the median time of one stepSimulation after the first second (bodies settled),
//               and the total over the run;
//   narrow phase: the time per pair call, from a near callback that times Bullet's default near
//               callback (btCollisionDispatcher::defaultNearCallback: the algorithm's
//               processCollision, plus its creation on a pair's first call), the same callback
//               for both narrow phases; also per pair type.
//
//   bench_bullet [--repeat R] [--seconds S] [--seed N] [--smoke]
//
// R runs of each scene and narrow phase (default 3), interleaved (native, dcol, native, ...);
// medians over all steps of all runs. --smoke: one short run of each (for the test suite).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scenes.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct PairTimes {
  std::vector<double> ns;  // every timed call
};

struct Timing {
  std::map<std::pair<int, int>, PairTimes> by_type;
  std::vector<double> all;
};

Timing *g_timing = nullptr;

void timed_near_callback(btBroadphasePair &pair, btCollisionDispatcher &dispatcher, const btDispatcherInfo &info) {
  const Clock::time_point t0 = Clock::now();
  btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
  const Clock::time_point t1 = Clock::now();
  if (!g_timing) return;
  const btCollisionObject *a = static_cast<const btCollisionObject *>(pair.m_pProxy0->m_clientObject);
  const btCollisionObject *b = static_cast<const btCollisionObject *>(pair.m_pProxy1->m_clientObject);
  if (!pair.m_algorithm) return;  // not collided (e.g. two static bodies)
  int ta = a->getCollisionShape()->getShapeType(), tb = b->getCollisionShape()->getShapeType();
  if (ta > tb) std::swap(ta, tb);
  const double ns = std::chrono::duration<double, std::nano>(t1 - t0).count();
  g_timing->by_type[std::make_pair(ta, tb)].ns.push_back(ns);
  g_timing->all.push_back(ns);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double> &v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / double(v.size());
}

const char *type_name(int t) {
  switch (t) {
    case BOX_SHAPE_PROXYTYPE:
      return "box";
    case SPHERE_SHAPE_PROXYTYPE:
      return "sphere";
    case CAPSULE_SHAPE_PROXYTYPE:
      return "capsule";
    case CYLINDER_SHAPE_PROXYTYPE:
      return "cylinder";
    case CONE_SHAPE_PROXYTYPE:
      return "cone";
    case CONVEX_HULL_SHAPE_PROXYTYPE:
      return "hull";
    case STATIC_PLANE_PROXYTYPE:
      return "plane";
    default:
      return "other";
  }
}

struct Result {
  std::vector<double> steps;  // seconds per step, after the first second
  double total = 0;           // seconds, all steps
  int n_steps = 0;
  Timing timing;
};

void run(const std::string &scene, bool dcol, double seconds, unsigned seed, Result &r) {
  const bullet_scenes::Params p = scene == "pile" ? bullet_scenes::pile_params() : bullet_scenes::pyramid_params();
  bullet_scenes::World w(dcol, p);
  w.dispatcher.setNearCallback(timed_near_callback);
  if (scene == "pile") {
    bullet_scenes::build_pile(w, seed);
  } else {
    bullet_scenes::build_pyramid(w);
  }
  const int steps = static_cast<int>(seconds / p.dt + 0.5), settle = static_cast<int>(1.0 / p.dt + 0.5);
  for (int k = 0; k < steps; ++k) {
    g_timing = k >= settle ? &r.timing : nullptr;
    const Clock::time_point t0 = Clock::now();
    w.step();
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    r.total += s;
    if (k >= settle) r.steps.push_back(s);
  }
  g_timing = nullptr;
  r.n_steps += steps;
}

}  // namespace

int main(int argc, char **argv) {
  int repeat = 3;
  double seconds = 5;
  unsigned seed = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--smoke")) {
      repeat = 1;
      seconds = 1.5;
    } else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seconds") && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = static_cast<unsigned>(std::atoi(argv[++i]));
    } else {
      std::printf("usage: %s [--repeat R] [--seconds S] [--seed N] [--smoke]\n", argv[0]);
      return 2;
    }
  }
  if (repeat < 1 || !(seconds > 1)) {
    std::printf("--repeat must be >= 1 and --seconds > 1\n");
    return 2;
  }
  const char *scenes[] = {"pile", "pyramid"};
  std::printf("Bullet %d (btScalar %zu bytes), dcol %s: %d run(s) of %.1f s per scene and narrow phase, interleaved; "
              "medians after the first second\n\n",
              btGetVersion(), sizeof(btScalar), dcol_version(), repeat, seconds);
  std::printf("| scene | narrow phase | step median (us) | step total (s) | pair calls | per call median (ns) | per call mean (ns) |\n");
  std::printf("|---|---|--:|--:|--:|--:|--:|\n");
  int failures = 0;
  for (const char *scene : scenes) {
    Result res[2];
    const dcol_bullet::Stats s0 = dcol_bullet::stats();
    for (int r = 0; r < repeat; ++r) {
      for (int mode = 0; mode < 2; ++mode) run(scene, mode == 1, seconds, seed, res[mode]);
    }
    const dcol_bullet::Stats s1 = dcol_bullet::stats();
    for (int mode = 0; mode < 2; ++mode) {
      const Result &x = res[mode];
      std::printf("| %s | %s | %.1f | %.3f | %zu | %.0f | %.0f |\n", scene, mode ? "dcol" : "native", median(x.steps) * 1e6,
                  x.total, x.timing.all.size(), median(x.timing.all), mean(x.timing.all));
    }
    std::printf("| %s | dcol / native | %.2f | %.2f | | %.2f | %.2f |\n", scene,
                median(res[1].steps) / median(res[0].steps), res[1].total / res[0].total,
                median(res[1].timing.all) / median(res[0].timing.all), mean(res[1].timing.all) / mean(res[0].timing.all));
    if (s1.calls == s0.calls || s1.fallback_pairs != s0.fallback_pairs) {
      std::printf("FAILED: dcol did not answer every pair of the %s\n", scene);
      ++failures;
    }
    std::printf("|   | (dcol: %lu calls, %lu decided apart without a query, %lu not converged, %lu errors) | | | | | |\n",
                s1.calls - s0.calls, s1.early_outs - s0.early_outs, s1.not_converged - s0.not_converged,
                s1.errors - s0.errors);
    // Per pair type.
    std::vector<std::pair<int, int>> types;
    for (const auto &kv : res[0].timing.by_type) types.push_back(kv.first);
    for (const auto &kv : res[1].timing.by_type) {
      if (!res[0].timing.by_type.count(kv.first)) types.push_back(kv.first);
    }
    std::printf("\n%s, per pair type: calls per run (dcol), time per call (ns): median and mean, native / dcol\n\n",
                scene);
    std::printf("| pair | calls | median native | median dcol | ratio | mean native | mean dcol | ratio |\n");
    std::printf("|---|--:|--:|--:|--:|--:|--:|--:|\n");
    for (const auto &t : types) {
      const std::vector<double> &a = res[0].timing.by_type[t].ns, &b = res[1].timing.by_type[t].ns;
      std::printf("| %s-%s | %zu | %.0f | %.0f | %.2f | %.0f | %.0f | %.2f |\n", type_name(t.first), type_name(t.second),
                  b.size() / repeat, median(a), median(b), median(a) > 0 ? median(b) / median(a) : 0.0, mean(a), mean(b),
                  mean(a) > 0 ? mean(b) / mean(a) : 0.0);
    }
    std::printf("\n");
  }
  return failures ? 1 : 0;
}
