// The cost of dcol inside ODE: the scene tests' pyramid (55 boxes, 10 s) and pile (48 mixed bodies
// in a bin, 5 s; seed 1, and seed 2 only measured), stepped with ODE's own colliders and with dcol
// (dcol_ode::use_dcol()), in one process, each scene's two runs back to back, alternating which
// goes first. Prints a table:
//   - whole-step time (dSpaceCollide + dWorldQuickStep): median per step and total per run;
//   - narrow-phase time per pair call: each dCollide of the near callback timed (steady_clock,
//     the same code for both), mean and median, and per pair of geom classes.
// Whole-step and narrow-phase times come from separate passes (the clock calls of the second
// would weigh on the first); both passes step the same deterministic trajectory.
//
//   bench_ode [--smoke] [--rounds N]
//   bench_ode --only pyramid|pile|pile2 native|dcol [STEPS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "dcol_ode.hpp"
#include "ode_scenes.hpp"

namespace {

using ode_scenes::World;

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Scene {
  const char *name;
  int steps;
  unsigned seed;  // the pile's
};

// Everything measured for one scene and one narrow phase, over all rounds.
struct Result {
  std::vector<double> step;        // every step's time (s)
  std::vector<double> run_total;   // each round's total (s)
  std::vector<double> call;        // every dCollide's time (s)
  double narrow_seconds = 0;
  unsigned long calls = 0, contacts = 0, steps = 0;
  unsigned long pair_calls[16][16] = {};
  unsigned long pair_empty[16][16] = {};
  double pair_seconds[16][16] = {};
};

void build(World &w, const Scene &s, bool dcol) {
  if (!std::strcmp(s.name, "pyramid"))
    ode_scenes::build_pyramid(w, dcol);
  else
    ode_scenes::build_pile(w, s.seed, dcol);
}

ode_scenes::Settings settings(const Scene &s) {
  return !std::strcmp(s.name, "pyramid") ? ode_scenes::pyramid_settings() : ode_scenes::pile_settings();
}

void run(const Scene &s, bool dcol, Result &r) {
  {  // whole steps
    World w(settings(s));
    build(w, s, dcol);
    double total = 0;
    for (int k = 0; k < s.steps; ++k) {
      const double t0 = now();
      w.step();
      const double dt = now() - t0;
      r.step.push_back(dt);
      total += dt;
    }
    r.run_total.push_back(total);
    r.steps += static_cast<unsigned long>(s.steps);
  }
  {  // each dCollide
    World w(settings(s));
    build(w, s, dcol);
    w.time_narrow = true;
    w.keep_samples = true;
    for (int k = 0; k < s.steps; ++k) w.step();
    r.call.insert(r.call.end(), w.narrow.samples.begin(), w.narrow.samples.end());
    r.narrow_seconds += w.narrow.seconds;
    r.calls += w.narrow.calls;
    r.contacts += w.narrow.contacts;
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) {
        r.pair_calls[i][j] += w.narrow.pair_calls[i][j];
        r.pair_empty[i][j] += w.narrow.pair_empty[i][j];
        r.pair_seconds[i][j] += w.narrow.pair_seconds[i][j];
      }
  }
}

const char *class_name(int c) {
  switch (c) {
    case dSphereClass: return "sphere";
    case dBoxClass: return "box";
    case dCapsuleClass: return "capsule";
    case dCylinderClass: return "cylinder";
    case dPlaneClass: return "plane";
    case dConvexClass: return "hull";
    default: return "?";
  }
}

}  // namespace

int main(int argc, char **argv) {
  bool smoke = false;
  int rounds = 5;
  // --only SCENE MODE [STEPS]: one run of one scene (pyramid, pile, pile2) with one narrow phase
  // (native, dcol), printing only its number of dCollide calls and of steps: for instruction
  // counts under callgrind (run.sh --instructions), which are the same on a loaded machine.
  for (int i = 1; i + 2 < argc; ++i) {
    if (std::strcmp(argv[i], "--only")) continue;
    const std::string scene = argv[i + 1], mode = argv[i + 2];
    Scene s = scene == "pyramid" ? Scene{"pyramid", 2000, 1} : Scene{"pile", 1000, scene == "pile2" ? 2u : 1u};
    if (i + 3 < argc) s.steps = std::atoi(argv[i + 3]);
    dInitODE2(0);
    if (mode == "dcol") dcol_ode::use_dcol();
    {
      World w(settings(s));
      build(w, s, mode == "dcol");
      for (int k = 0; k < s.steps; ++k) w.step();
      std::printf("%lu %d\n", w.narrow.calls, s.steps);  // dCollide calls, steps
    }
    dcol_ode::release_all();
    dCloseODE();
    return 0;
  }
  if (const char *e = std::getenv("DCOL_BENCH_ROUNDS")) rounds = std::max(1, std::atoi(e));
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--smoke")) smoke = true;
    if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc) rounds = std::max(1, std::atoi(argv[++i]));
  }
  std::vector<Scene> scenes = {{"pyramid", 2000, 1}, {"pile", 1000, 1}, {"pile", 1000, 2}};
  if (smoke) {
    rounds = 1;
    for (Scene &s : scenes) s.steps = 20;
  }
  const int n = static_cast<int>(scenes.size());
  std::vector<Result> native(n), dcol(n);
  // Each scene runs with both narrow phases back to back (ODE closed and initialised again in
  // between: dInitODE2 restores ODE's own colliders), the first of the two alternating, so that
  // both see the same machine load.
  for (int round = 0; round < rounds; ++round) {
    for (int i = 0; i < n; ++i) {
      for (int order = 0; order < 2; ++order) {
        const bool use = (order + round + i) % 2 == 1;
        dInitODE2(0);
        if (use) dcol_ode::use_dcol();
        run(scenes[i], use, use ? dcol[i] : native[i]);
        if (use && (dcol_ode::stats().rejected || dcol_ode::stats().native_calls)) {
          std::printf("dcol rejected %lu pairs and left %lu to ODE's colliders\n", dcol_ode::stats().rejected,
                      dcol_ode::stats().native_calls);
          return 1;
        }
        if (!use && dcol_ode::collider_calls()) {
          std::printf("a native run reached dcol\n");
          return 1;
        }
        dcol_ode::release_all();
        dcol_ode::reset_stats();
        dCloseODE();
      }
    }
  }
  const ode_scenes::Settings py = ode_scenes::pyramid_settings(), pi = ode_scenes::pile_settings();
  std::printf("ODE (%s), narrow phase: native colliders against dcol (dcol_ode::use_dcol()), %d round%s, %s\n",
              dGetConfiguration(), rounds, rounds > 1 ? "s" : "", smoke ? "SMOKE RUN (20 steps)" : "full runs");
  std::printf("pyramid: 55 boxes, %d steps of %.3f s, QuickStep %d iterations, %d contacts per pair; pile: 48 bodies, "
              "%d steps of %.3f s, QuickStep %d iterations, %d contacts per pair\n\n",
              scenes[0].steps, py.dt, py.iterations, py.max_contacts, scenes[1].steps, pi.dt, pi.iterations, pi.max_contacts);
  std::printf("| scene | narrow phase | step median (us) | run total (s) | dCollide calls per step | contacts per step | "
              "per call mean (ns) | per call median (ns) |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (int i = 0; i < n; ++i) {
    for (int m = 0; m < 2; ++m) {
      const Result &r = m ? dcol[i] : native[i];
      const double steps = static_cast<double>(r.steps);
      std::printf("| %s%s | %s | %.1f | %.3f | %.1f | %.1f | %.0f | %.0f |\n", scenes[i].name,
                  scenes[i].seed == 2 ? " (seed 2)" : "", m ? "dcol" : "ODE", median(r.step) * 1e6, median(r.run_total),
                  r.calls / steps, r.contacts / steps, r.calls ? r.narrow_seconds / r.calls * 1e9 : 0.0,
                  median(r.call) * 1e9);
    }
  }
  std::printf("\nsame-run ratios dcol / ODE:\n\n| scene | step median | run total | per call mean | per call median |\n"
              "|---|---|---|---|---|\n");
  for (int i = 0; i < n; ++i) {
    const Result &a = dcol[i], &b = native[i];
    std::printf("| %s%s | %.2f | %.2f | %.2f | %.2f |\n", scenes[i].name, scenes[i].seed == 2 ? " (seed 2)" : "",
                median(a.step) / median(b.step), median(a.run_total) / median(b.run_total),
                (a.narrow_seconds / a.calls) / (b.narrow_seconds / b.calls), median(a.call) / median(b.call));
  }
  std::printf("\nper pair of geom classes (mean ns per dCollide; calls per step; share of calls with no contact):\n\n"
              "| scene | pair | ODE | dcol | ratio |\n|---|---|---|---|---|\n");
  for (int i = 0; i < n; ++i)
    for (int c1 = 0; c1 < 16; ++c1)
      for (int c2 = c1; c2 < 16; ++c2) {
        const Result &a = dcol[i], &b = native[i];
        if (!a.pair_calls[c1][c2] && !b.pair_calls[c1][c2]) continue;
        const double ta = a.pair_calls[c1][c2] ? a.pair_seconds[c1][c2] / a.pair_calls[c1][c2] * 1e9 : 0;
        const double tb = b.pair_calls[c1][c2] ? b.pair_seconds[c1][c2] / b.pair_calls[c1][c2] * 1e9 : 0;
        auto empty = [&](const Result &r) {
          return r.pair_calls[c1][c2] ? 100.0 * r.pair_empty[c1][c2] / r.pair_calls[c1][c2] : 0.0;
        };
        std::printf("| %s%s | %s-%s | %.0f (%.1f; %.0f %%) | %.0f (%.1f; %.0f %%) | %.2f |\n", scenes[i].name,
                    scenes[i].seed == 2 ? " (seed 2)" : "", class_name(c1), class_name(c2), tb,
                    b.pair_calls[c1][c2] / static_cast<double>(b.steps), empty(b), ta,
                    a.pair_calls[c1][c2] / static_cast<double>(a.steps), empty(a), tb > 0 ? ta / tb : 0.0);
      }
  return 0;
}
