// bench_common.hpp: what the parts of bench_compare share: the constants and library status
// strings, the method table's types (Method, Sample), the statistics helpers, the current case
// seen by the method closures (CaseCtx) and everything one run accumulates (BenchRun).
#ifndef DCOL_BENCH_COMMON_HPP
#define DCOL_BENCH_COMMON_HPP

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <ccd/ccd.h>

#ifdef DCOL_BENCH_HAVE_COAL
#include <coal/collision.h>
#include <coal/distance.h>

#include "coal_body.hpp"
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "compare_common.h"
#include "engine_body.hpp"
#include "fcl_body.hpp"
#include "penetration.hpp"


constexpr double kBand = 1e-6;
constexpr double kTight = 1e-12;
const double kTols[] = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
const double kFclTols[] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-12};
constexpr double kRefAgree = 1e-9;  // the independent distance reference: agreement needed
constexpr double kFclRefTol = 1e-6;  // FCL's default distance_tolerance: the ratio reference
// Coal: gjk_tolerance sweep (EPA left at its default); 1e-6 is Coal's default request
// (GJK_DEFAULT_TOLERANCE), the ratio reference. Agreement with dcol_distance on separated cases
// is checked against tol * max(1, d_ref) at each gjk_tolerance (kCoalAgree for the functor at
// the default request).
const double kCoalTols[] = {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
constexpr double kCoalRefTol = 1e-6;
constexpr double kCoalAgree = 1e-6;
#ifdef DCOL_BENCH_HAVE_COAL
constexpr bool kHaveCoal = true;
const char* const kCoalStatus = "Coal " DCOL_BENCH_COAL_VERSION;
#else
constexpr bool kHaveCoal = false;
const char* const kCoalStatus = "Coal: not available (" DCOL_BENCH_COAL_MISSING ")";
#endif
// ODE and Bullet: the contact-query comparison (dcol_contacts vs dCollide vs GJK/EPA)
#ifdef DCOL_BENCH_HAVE_ODE
const char* const kOdeStatus = "ODE " DCOL_BENCH_ODE_VERSION " (dCollide, double precision)";
#else
const char* const kOdeStatus = "ODE: not available (" DCOL_BENCH_ODE_MISSING ")";
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
const char* const kBulletStatus =
    "Bullet " DCOL_BENCH_BULLET_VERSION " (btGjkPairDetector + btGjkEpaPenetrationDepthSolver, "
    "btScalar float)";
#else
const char* const kBulletStatus = "Bullet: not available (" DCOL_BENCH_BULLET_MISSING ")";
#endif
constexpr double kDepthAgree = 1e-4;  // deepest-point depth agreement with dcol_contacts
constexpr double kNoContact = -1e300;  // the value of a contact query that found none


inline void support_fn(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* vec) {
  const cmp_body* body = static_cast<const cmp_body*>(obj);
  double d[3] = {dir->v[0], dir->v[1], dir->v[2]}, p[3];
  cmp_support_world(body, d, p);
  ccdVec3Set(vec, p[0], p[1], p[2]);
}

inline void center_fn(const void* obj, ccd_vec3_t* center) {
  const cmp_body* body = static_cast<const cmp_body*>(obj);
  ccdVec3Set(center, body->pose.position[0], body->pose.position[1], body->pose.position[2]);
}

// FCL's (GST_LIBCCD) unsigned distance at a distance_tolerance, clamped at 0.
inline double fcl_distance_at(const FclBody& a, const FclBody& b, double tol) {
  fcl::DistanceRequestd req;
  req.gjk_solver_type = fcl::GST_LIBCCD;
  req.distance_tolerance = tol;
  fcl::DistanceResultd res;
  fcl::distance(a.geom.get(), a.tf, b.geom.get(), b.tf, req, res);
  return std::max(0.0, res.min_distance);
}

// One sample of one method on one case.
struct Sample {
  double ns;
  double err;   // NaN for boolean methods and where there is no reference
  double dcol_diff = NAN;  // distances: |max(0, d) - dcol@1e-12| (the Coal agreement table)
  int wrong;    // -1: not compared (in band or not boolean); 0/1 otherwise
  int pair;     // pair type index
  int cat;      // cmp_category
  double alpha_ref;
  bool fcl_pair;
};

struct Method {
  std::string name;
  double tol;        // 0: default / not applicable
  bool fcl_only;     // not run on polygon pairs
  bool boolean;
  // runs once; writes the value (alpha, distance, or 0/1) to *value; returns false on failure
  std::function<bool(double*)> run;
  std::vector<Sample> samples;
  long failures = 0;  // calls that returned an error (no sample kept)
  // signed distances checked against dcol (Coal): separated cases off by more than
  // agree_tol * max(1, d_ref), and overlapping cases (alpha_ref < 1 - 1e-6) reported separated
  // (distance > agree_tol); 0: not checked
  double agree_tol = 0;
  long sep_checked = 0, sep_disagree = 0, sep_disagree10 = 0, ovl_checked = 0, ovl_disagree = 0;
  long wrong_shown = 0;
  double worst_err = -1;   // the worst separated case
  std::string worst_case = "";
  // contact queries (dcol_contacts, ODE, Bullet): value = the deepest depth, kNoContact when
  // there is none; `only`: 0 all pairs, 1 ODE's pair types, 2 Bullet's; last value per case
  bool contact = false;
  int only = 0;
  double last = NAN;
  bool last_ok = false;
};

inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Stats {
  long n = 0;
  double med_ns = NAN, med_err = NAN, max_err = NAN;
  long wrong = 0, compared = 0;
};

template <class Pred>
inline Stats stats(const Method& m, Pred pred) {
  std::vector<double> ns, err;
  Stats s;
  for (const Sample& x : m.samples) {
    if (!pred(x)) continue;
    s.n++;
    ns.push_back(x.ns);
    if (!std::isnan(x.err)) err.push_back(x.err);
    if (x.wrong >= 0) s.compared++, s.wrong += x.wrong;
  }
  s.med_ns = median(ns);
  if (!err.empty()) {
    s.med_err = median(err);
    s.max_err = *std::max_element(err.begin(), err.end());
  }
  return s;
}

inline std::string label(const Method& m) {
  if (m.tol <= 0) return m.name;
  char b[64];
  snprintf(b, sizeof b, "%s @%.0e", m.name.c_str(), m.tol);
  return b;
}

inline std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "–";
  char b[64];
  snprintf(b, sizeof b, f, v);
  return b;
}


// agreement of ODE (0) and Bullet (1) with dcol_contacts, per pair type, outside the band
// |alpha* - 1| < 1e-6: contact / no contact, and the deepest depth when both report contact
struct Agree {
  long contact_checked = 0, contact_disagree = 0, contact_disagree4 = 0, depth_checked = 0,
       depth_disagree = 0, sd_checked = 0, sd_disagree = 0;
  double depth_max = 0;
  std::string worst = "";
};

// The current case and its shapes in the other libraries, seen by the method closures.
struct CaseCtx {
  cmp_case c{};
  FclBody f1, f2;
#ifdef DCOL_BENCH_HAVE_COAL
  CoalBody g1, g2;
  std::unique_ptr<coal::ComputeDistance> coal_dist_functor;
#endif
  dcol_options defaults = dcol_options_default();
#ifdef DCOL_BENCH_HAVE_ODE
  std::unique_ptr<OdeBody> o1, o2;
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
  std::unique_ptr<BulletBody> u1, u2;
#endif
  ccd_t ccd;  // set up by add_methods (compare_common.c's support functions)
};

// Local references to every member of a CaseCtx under its member's name, for the code that
// runs per case (bench_compare.cpp) and the method closures (methods.cpp), which capture them.
#ifdef DCOL_BENCH_HAVE_COAL
#define DCOL_BENCH_COAL_REFS(ctx)                                                         \
  CoalBody& g1 = (ctx).g1;                                                                \
  CoalBody& g2 = (ctx).g2;                                                                \
  std::unique_ptr<coal::ComputeDistance>& coal_dist_functor = (ctx).coal_dist_functor;
#else
#define DCOL_BENCH_COAL_REFS(ctx)
#endif
#ifdef DCOL_BENCH_HAVE_ODE
#define DCOL_BENCH_ODE_REFS(ctx)              \
  std::unique_ptr<OdeBody>& o1 = (ctx).o1; \
  std::unique_ptr<OdeBody>& o2 = (ctx).o2;
#else
#define DCOL_BENCH_ODE_REFS(ctx)
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
#define DCOL_BENCH_BULLET_REFS(ctx)              \
  std::unique_ptr<BulletBody>& u1 = (ctx).u1; \
  std::unique_ptr<BulletBody>& u2 = (ctx).u2;
#else
#define DCOL_BENCH_BULLET_REFS(ctx)
#endif
#define DCOL_BENCH_CASE_REFS(ctx)                 \
  cmp_case& c = (ctx).c;                          \
  FclBody& f1 = (ctx).f1;                         \
  FclBody& f2 = (ctx).f2;                         \
  DCOL_BENCH_COAL_REFS(ctx)                       \
  const dcol_options& defaults = (ctx).defaults;  \
  DCOL_BENCH_ODE_REFS(ctx)                        \
  DCOL_BENCH_BULLET_REFS(ctx)                     \
  ccd_t& ccd = (ctx).ccd

constexpr int kPairTypes = CMP_KIND_COUNT * (CMP_KIND_COUNT + 1) / 2;

// Everything one run accumulates, for the report.
struct BenchRun {
  long cases = 0, repeat = 0, seed = 0;
  std::string outdir;
  dcol_options defaults = dcol_options_default();
  std::vector<Method> methods;
  // which solver answered dcol_proximity (the result's `solver`: DCOL_SOLVER_*), per tolerance
  // (kTols, then the default) and regime, and the interior-point iterations of the calls the
  // interior-point solver answered (untimed extra solve; `iterations` counts only those)
  size_t n_tol_rows = std::size(kTols) + 1;
  std::vector<std::vector<std::array<long, 4>>> solver_count = std::vector<std::vector<std::array<long, 4>>>(
      std::size(kTols) + 1, std::vector<std::array<long, 4>>(3, std::array<long, 4>{0, 0, 0, 0}));
  std::vector<std::vector<std::vector<double>>> ip_iters = std::vector<std::vector<std::vector<double>>>(
      std::size(kTols) + 1, std::vector<std::vector<double>>(3));
  std::vector<std::string> pair_names;
  std::vector<bool> engine_pair_of;
  std::vector<int> ode_pair_of;  // 1: ODE has a collider for the pair type
  std::vector<std::vector<Agree>> agree = std::vector<std::vector<Agree>>(2, std::vector<Agree>(kPairTypes));
  // dcol_contacts' deepest depth against dcol_signed_distance (untimed, same case), per pair type
  std::vector<Agree> self_agree = std::vector<Agree>(kPairTypes + 1);
  long made = 0, failures = 0, ref_fallbacks = 0;
  // the independent distance reference (separated cases): from FCL (FCL and Coal agree), from
  // dcol (it agrees with one of them), none, and no peer (padded polygon pairs); the spread
  // |FCL - Coal| on the cases where FCL is the reference
  long dref_fcl = 0, dref_dcol = 0, dref_none = 0, dref_nopeer = 0;
  std::vector<double> dref_spread;
  // penetration depth per pair type, and FCL signed distances that threw (libccd, indep)
  std::vector<DepthRow> depth_rows = std::vector<DepthRow>(kPairTypes);
  long fcl_signed_threw[2] = {0, 0};
  double seconds = 0;
};

// methods.cpp: the method table (closures over ctx, which must outlive them); sets up ctx.ccd.
void add_methods(std::vector<Method>& methods, CaseCtx& ctx);
// report.cpp: benchmark.md and time_vs_error.csv; returns the exit status.
int write_report(const BenchRun& run);
// report_contacts.cpp: the section on dcol_contacts vs ODE and Bullet.
void write_contact_section(FILE* md, const BenchRun& run);

#endif  // DCOL_BENCH_COMMON_HPP
