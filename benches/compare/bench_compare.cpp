// bench_compare.cpp: time and accuracy of dcol against Coal 3 (when built with it), FCL 0.7 and
// libccd 2.1 on the same fixed-seed cases (36 unordered pair types of the eight dcol shapes; Coal
// and FCL have no padded polygon, so the 8 polygon pairs are skipped for both). Cases come from c_tests/compare/compare_common.c,
// shared with the agreement suite: a third separated, a third near touching, a third overlapping.
//
// Per case, every method is run `repeat` times in a row and timed with std::chrono::steady_clock
// (ns per call = total / repeat); methods are interleaved per case, starting at a rotating
// offset, so machine noise hits them all alike. Reported: medians over cases.
// Errors are against a dcol solve at tolerance 1e-12 (alpha for proximity, distance for the
// distance methods); boolean methods count wrong answers against alpha* < 1 outside the band
// |alpha* - 1| < 1e-6.
//
// Environment: DCOL_BENCH_CASES (per pair type, default 1500), DCOL_BENCH_REPEAT (default 5),
// DCOL_BENCH_SEED (default 20240501), DCOL_BENCH_OUT (results directory, default "results").

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
#include <chrono>
#include <exception>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "compare_common.h"
#include "depth_check.hpp"
#include "engine_body.hpp"
#include "fcl_body.hpp"
#include "penetration.hpp"

namespace {

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


void support_fn(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* vec) {
  const cmp_body* body = static_cast<const cmp_body*>(obj);
  double d[3] = {dir->v[0], dir->v[1], dir->v[2]}, p[3];
  cmp_support_world(body, d, p);
  ccdVec3Set(vec, p[0], p[1], p[2]);
}

void center_fn(const void* obj, ccd_vec3_t* center) {
  const cmp_body* body = static_cast<const cmp_body*>(obj);
  ccdVec3Set(center, body->pose.position[0], body->pose.position[1], body->pose.position[2]);
}

// FCL's (GST_LIBCCD) unsigned distance at a distance_tolerance, clamped at 0.
double fcl_distance_at(const FclBody& a, const FclBody& b, double tol) {
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

double median(std::vector<double> v) {
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
Stats stats(const Method& m, Pred pred) {
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

std::string label(const Method& m) {
  if (m.tol <= 0) return m.name;
  char b[64];
  snprintf(b, sizeof b, "%s @%.0e", m.name.c_str(), m.tol);
  return b;
}

std::string fmt(double v, const char* f) {
  if (std::isnan(v)) return "–";
  char b[64];
  snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int run() {
  const long cases = cmp_env_long("DCOL_BENCH_CASES", 1500);
  const long repeat = std::max(1L, cmp_env_long("DCOL_BENCH_REPEAT", 5));
  const long seed = cmp_env_long("DCOL_BENCH_SEED", 20240501);
  const char* outdir_env = std::getenv("DCOL_BENCH_OUT");
  const std::string outdir = outdir_env && *outdir_env ? outdir_env : "results";

  // The current case, seen by the method closures.
  cmp_case c{};
  FclBody f1, f2;
#ifdef DCOL_BENCH_HAVE_COAL
  CoalBody g1, g2;
  std::unique_ptr<coal::ComputeDistance> coal_dist_functor;
#endif
  const dcol_options defaults = dcol_options_default();
#ifdef DCOL_BENCH_HAVE_ODE
  dInitODE2(0);
  std::unique_ptr<OdeBody> o1, o2;
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
  std::unique_ptr<BulletBody> u1, u2;
#endif

  std::vector<Method> methods;
  auto prox_with = [&](double tol) {
    return [&, tol](double* v) {
      dcol_options o = dcol_options_default();
      o.tolerance = tol;
      dcol_proximity_result r;
      bool ok = dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
                DCOL_OK;
      *v = r.alpha;
      return ok;
    };
  };
  auto dist_with = [&](double tol) {
    return [&, tol](double* v) {
      dcol_options o = dcol_options_default();
      o.tolerance = tol;
      dcol_distance_result r;
      bool ok = dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
                DCOL_OK;
      *v = r.distance;
      return ok;
    };
  };
  for (double t : kTols) methods.push_back({"dcol_proximity", t, false, false, prox_with(t), {}, 0});
  methods.push_back({"dcol_proximity (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       bool ok = dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                &c.b2.pose, &defaults, &r) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_gradient (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       double g[14];
                       bool ok = dcol_gradient(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r, g) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_jacobian (default tol)", 0, false, false, [&](double* v) {
                       dcol_proximity_result r;
                       double j[56];
                       bool ok = dcol_jacobian(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r, j) == DCOL_OK;
                       *v = r.alpha;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_distance (default tol)", 0, false, false, [&](double* v) {
                       dcol_distance_result r;
                       bool ok = dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                               &defaults, &r) == DCOL_OK;
                       *v = r.distance;
                       return ok;
                     }, {}, 0});
  for (double t : kTols) methods.push_back({"dcol_distance", t, false, false, dist_with(t), {}, 0});
  // signed distance: timed on every case; its time on the overlapping cases is compared with
  // coal::distance's (default request: EPA) in the penetration-depth section
  methods.push_back({"dcol_signed_distance (default tol)", 0, false, false, [&](double* v) {
                       dcol_signed_distance_result r;
                       bool ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                      &c.b2.pose, &defaults, &r) == DCOL_OK;
                       *v = r.distance;
                       return ok;
                     }, {}, 0});
  methods.push_back({"dcol_intersect (default tol)", 0, false, true, [&](double* v) {
                       int32_t hit = 0;
                       bool ok = dcol_intersect(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                                &defaults, &hit) == DCOL_OK;
                       *v = hit ? 1 : 0;
                       return ok;
                     }, {}, 0});
  for (double t : kFclTols)
    methods.push_back({"fcl::distance", t, true, false, [&, t](double* v) {
                         fcl::DistanceRequestd req;
                         req.gjk_solver_type = fcl::GST_LIBCCD;
                         req.distance_tolerance = t;
                         fcl::DistanceResultd res;
                         fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                         *v = std::max(0.0, res.min_distance);
                         return true;
                       }, {}, 0});
  methods.push_back({"fcl::collide (default)", 0, true, true, [&](double* v) {
                       fcl::CollisionRequestd req;
                       req.gjk_solver_type = fcl::GST_LIBCCD;
                       fcl::CollisionResultd res;
                       fcl::collide(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
#ifdef DCOL_BENCH_HAVE_COAL
  // Coal: default requests (signed distance, EPA on overlap; collide with contact = EPA), the
  // distance at gjk_tolerance 1e-2 ... 1e-12; the values are the raw signed distances (errors
  // are taken on max(0, d) on separated cases, as for FCL).
  for (double t : kCoalTols) {
    methods.push_back({"coal::distance", t, true, false, [&, t](double* v) {
                         coal::DistanceRequest req;
                         req.gjk_tolerance = t;
                         coal::DistanceResult res;
                         *v = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                         return true;
                       }, {}, 0});
    methods.back().agree_tol = t;
  }
  methods.push_back({"coal::ComputeDistance (default)", 0, true, false, [&](double* v) {
                       coal::DistanceRequest req;
                       coal::DistanceResult res;
                       *v = (*coal_dist_functor)(g1.tf, g2.tf, req, res);
                       return true;
                     }, {}, 0});
  methods.back().agree_tol = kCoalAgree;
  methods.push_back({"coal::collide (default)", 0, true, true, [&](double* v) {
                       coal::CollisionRequest req;
                       coal::CollisionResult res;
                       coal::collide(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"coal::collide (no contact)", 0, true, true, [&](double* v) {
                       coal::CollisionRequest req(coal::NO_REQUEST, 1);
                       coal::CollisionResult res;
                       coal::collide(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                       *v = res.isCollision() ? 1 : 0;
                       return true;
                     }, {}, 0});
#endif
  // contact queries: dcol_contacts (margin 0, capacity 4) on every pair type; ODE's dCollide
  // (4 contacts) and Bullet's GJK/EPA (one point) on the pair types of sphere, box, polytope,
  // capsule, cylinder. Value: the deepest depth (> 0 penetrating), kNoContact when none.
  methods.push_back({"dcol_contacts (margin 0, capacity 4)", 0, false, false, [&](double* v) {
                       dcol_contact cs[4];
                       size_t n = 0;
                       const dcol_status st = dcol_contacts(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                            &c.b2.pose, 0.0, &defaults, cs, 4, &n);
                       *v = kNoContact;
                       for (size_t k = 0; k < n; ++k) *v = std::max(*v, cs[k].depth);
                       return st == DCOL_OK;
                     }, {}, 0});
  methods.back().contact = true;
#ifdef DCOL_BENCH_HAVE_ODE
  methods.push_back({"ODE dCollide (4 contacts)", 0, false, false, [&](double* v) {
                       dContactGeom cg[4];
                       const int n = dCollide(o1->geom, o2->geom, 4, cg, sizeof(dContactGeom));
                       *v = kNoContact;
                       for (int k = 0; k < n; ++k) *v = std::max(*v, static_cast<double>(cg[k].depth));
                       return true;
                     }, {}, 0});
  methods.back().contact = true;
  methods.back().only = 1;
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
  methods.push_back({"Bullet GJK/EPA (1 point)", 0, false, false, [&](double* v) {
                       BulletContact res;
                       bullet_contact(*u1, *u2, res);
                       *v = res.hit ? -static_cast<double>(res.depth) : kNoContact;
                       return true;
                     }, {}, 0});
  methods.back().contact = true;
  methods.back().only = 2;
#endif
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = support_fn;
  ccd.support2 = support_fn;
  ccd.center1 = center_fn;
  ccd.center2 = center_fn;
  methods.push_back({"ccdGJKIntersect", 0, false, true, [&](double* v) {
                       *v = ccdGJKIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"ccdMPRIntersect", 0, false, true, [&](double* v) {
                       *v = ccdMPRIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
                       return true;
                     }, {}, 0});
  methods.push_back({"ccdMPRPenetration", 0, false, true, [&](double* v) {
                       ccd_real_t depth;
                       ccd_vec3_t dir, pos;
                       *v = ccdMPRPenetration(&c.b1, &c.b2, &ccd, &depth, &dir, &pos) == 0 ? 1
                                                                                           : 0;
                       return true;
                     }, {}, 0});

  // which solver answered dcol_proximity (the result's `solver`: DCOL_SOLVER_*), per tolerance
  // (kTols, then the default) and regime, and the interior-point iterations of the calls the
  // interior-point solver answered (untimed extra solve; `iterations` counts only those)
  const size_t n_tol_rows = std::size(kTols) + 1;
  std::vector<std::vector<std::array<long, 4>>> solver_count(
      n_tol_rows, std::vector<std::array<long, 4>>(3, std::array<long, 4>{0, 0, 0, 0}));
  std::vector<std::vector<std::vector<double>>> ip_iters(
      n_tol_rows, std::vector<std::vector<double>>(3));

  std::vector<std::string> pair_names;
  std::vector<bool> engine_pair_of;
  std::vector<int> ode_pair_of;  // 1: ODE has a collider for the pair type
  // agreement of ODE (0) and Bullet (1) with dcol_contacts, per pair type, outside the band
  // |alpha* - 1| < 1e-6: contact / no contact, and the deepest depth when both report contact
  struct Agree {
    long contact_checked = 0, contact_disagree = 0, contact_disagree4 = 0, depth_checked = 0,
         depth_disagree = 0, sd_checked = 0, sd_disagree = 0;
    double depth_max = 0;
    std::string worst = "";
  };
  std::vector<std::vector<Agree>> agree(2, std::vector<Agree>(CMP_KIND_COUNT * (CMP_KIND_COUNT + 1) / 2));
  // dcol_contacts' deepest depth against dcol_signed_distance (untimed, same case): [2] = the
  // worst case over all pairs
  std::vector<Agree> self_agree(CMP_KIND_COUNT * (CMP_KIND_COUNT + 1) / 2 + 1);
  long made = 0, failures = 0, ref_fallbacks = 0;
  // the independent distance reference (separated cases): from FCL (FCL and Coal agree), from
  // dcol (it agrees with one of them), none, and no peer (padded polygon pairs); the spread
  // |FCL - Coal| on the cases where FCL is the reference
  long dref_fcl = 0, dref_dcol = 0, dref_none = 0, dref_nopeer = 0;
  // penetration depth per pair type, and FCL signed distances that threw (libccd, indep)
  std::vector<DepthRow> depth_rows(CMP_KIND_COUNT * (CMP_KIND_COUNT + 1) / 2);
  long fcl_signed_threw[2] = {0, 0};
  std::vector<double> dref_spread;
  const auto t_start = std::chrono::steady_clock::now();
  int pair = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1)
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2, ++pair) {
      pair_names.push_back(std::string(cmp_kind_name((cmp_kind)k1)) + "-" +
                           cmp_kind_name((cmp_kind)k2));
      const bool fcl_pair = k1 != CMP_POLYGON && k2 != CMP_POLYGON;
      const bool engine_pair = engine_kind(k1) && engine_kind(k2);
      engine_pair_of.push_back(engine_pair);
      // does ODE have a collider for this pair type? (dCollide on two concentric shapes)
      int ode_pair = -1;  // -1: not yet checked
#ifndef DCOL_BENCH_HAVE_ODE
      ode_pair = 0;
#endif
      if (!engine_pair) ode_pair = 0;
      cmp_rng rng;
      cmp_rng_seed(&rng, (uint64_t)seed * 1000003u + (uint64_t)(k1 * 16 + k2));
      for (long i = 0; i < cases; ++i) {
        const int rc = cmp_case_make(&c, (cmp_kind)k1, (cmp_kind)k2, (int)i, &rng);
        if (rc < 0) continue;
        if (rc > 0) {
          failures++;
          fprintf(stderr, "%s: case %ld: dcol refused while making it: %s\n",
                  pair_names.back().c_str(), i, dcol_last_error_message());
          cmp_case_release(&c);
          continue;
        }
        // the reference: a tight dcol solve (alpha and distance) at 1e-12; when the solver stalls
        // short of that (it reports an error), 1e-11 then 1e-10 (counted as fallbacks)
        dcol_proximity_result pr;
        dcol_distance_result dr;
        bool ref_ok = false;
        for (double rt : {1e-12, 1e-11, 1e-10}) {
          dcol_options o = dcol_options_default();
          o.tolerance = rt;
          if (dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &pr) ==
                  DCOL_OK &&
              dcol_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &dr) ==
                  DCOL_OK) {
            ref_ok = true;
            if (rt > kTight) ref_fallbacks++;
            break;
          }
        }
        if (!ref_ok) {
          failures++;
          fprintf(stderr, "%s: case %ld: reference solve failed: %s\n",
                  pair_names.back().c_str(), i, dcol_last_error_message());
          cmp_case_release(&c);
          continue;
        }
        made++;
        const double alpha_ref = pr.alpha, dist_ref = dr.distance;
        const bool in_band = std::fabs(alpha_ref - 1) < kBand;
        const int truth = alpha_ref < 1;
        if (fcl_pair) f1 = to_fcl(c.b1), f2 = to_fcl(c.b2);
#ifdef DCOL_BENCH_HAVE_ODE
        if (engine_pair) {
          o1 = to_ode(c.b1), o2 = to_ode(c.b2);
          if (ode_pair < 0) {
            // two concentric copies: any collider reports a contact
            auto q1 = to_ode(c.b1), q2 = to_ode(c.b2);
            dGeomSetPosition(q1->geom, 0, 0, 0);
            dGeomSetPosition(q2->geom, 0, 0, 0);
            dContactGeom cg[4];
            ode_pair = dCollide(q1->geom, q2->geom, 4, cg, sizeof(dContactGeom)) > 0;
            if (!ode_pair)
              printf("ODE: no collider for %s (dCollide reports no contact for concentric "
                     "shapes): left out\n", pair_names.back().c_str());
          }
        }
#endif
#ifdef DCOL_BENCH_HAVE_BULLET
        if (engine_pair) u1 = to_bullet(c.b1), u2 = to_bullet(c.b2);
#endif
#ifdef DCOL_BENCH_HAVE_COAL
        if (fcl_pair) {
          g1 = to_coal(c.b1), g2 = to_coal(c.b2);
          coal_dist_functor = std::make_unique<coal::ComputeDistance>(g1.geom.get(), g2.geom.get());
        }
#endif
        // the independent distance reference on separated cases: FCL at distance_tolerance
        // 1e-12 where it agrees with Coal at gjk_tolerance 1e-12 to kRefAgree max(1, d), else
        // dcol at 1e-12 where it agrees with one of them; else none (left out of the errors)
        double dist_ind = NAN;
        if (alpha_ref > 1 + kBand) {
          if (!fcl_pair) {
            dref_nopeer++;
          } else {
            const double df = fcl_distance_at(f1, f2, kTight);
            double dc = NAN;
#ifdef DCOL_BENCH_HAVE_COAL
            {
              coal::DistanceRequest req;
              req.gjk_tolerance = kTight;
              coal::DistanceResult res;
              dc = std::max(0.0, coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res));
            }
#endif
            auto close = [](double a, double b) {
              return std::fabs(a - b) <= kRefAgree * std::max(1.0, std::fabs(b));
            };
            if (close(df, dc)) {
              dist_ind = df, dref_fcl++;
              dref_spread.push_back(std::fabs(df - dc));
            } else if (close(dist_ref, df) || close(dist_ref, dc)) {
              dist_ind = dist_ref, dref_dcol++;
            } else if (dref_none++ < 5) {
              fprintf(stderr, "%s case %ld: no distance reference: FCL@1e-12 %.17g, Coal@1e-12 "
                      "%.17g, dcol@1e-12 %.17g\n", pair_names.back().c_str(), i, df, dc, dist_ref);
            }
          }
        }
        for (size_t t = 0; t < n_tol_rows; ++t) {
          dcol_options o = dcol_options_default();
          if (t < std::size(kTols)) o.tolerance = kTols[t];
          dcol_proximity_result r;
          if (dcol_proximity(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &o, &r) ==
              DCOL_OK) {
            if (r.solver < 4) solver_count[t][c.category][r.solver]++;
            if (r.solver == DCOL_SOLVER_INTERIOR_POINT)
              ip_iters[t][c.category].push_back(r.iterations);
          }
        }
        const size_t nm = methods.size();
        const size_t start = static_cast<size_t>(made) % nm;
        for (size_t j = 0; j < nm; ++j) {
          Method& m = methods[(start + j) % nm];
          if (m.fcl_only && !fcl_pair) continue;
          if ((m.only == 1 && ode_pair != 1) || (m.only == 2 && !engine_pair)) continue;
          m.last_ok = false;
          double v = NAN;
          bool ok = true;
          const auto t0 = std::chrono::steady_clock::now();
          for (long r = 0; r < repeat; ++r) ok = m.run(&v) && ok;
          const auto t1 = std::chrono::steady_clock::now();
          Sample s;
          s.ns = std::chrono::duration<double, std::nano>(t1 - t0).count() / repeat;
          s.pair = pair;
          s.cat = c.category;
          s.alpha_ref = alpha_ref;
          s.fcl_pair = fcl_pair;
          s.err = NAN;
          s.wrong = -1;
          if (!ok) {
            m.failures++;
            fprintf(stderr, "%s: %s failed on case %ld: %s\n", pair_names.back().c_str(),
                    label(m).c_str(), i, dcol_last_error_message());
            continue;
          }
          if (m.contact) {
            if (!in_band) s.wrong = ((v > kNoContact) != (truth != 0));
            m.last = v, m.last_ok = true;
          } else if (m.boolean) {
            if (!in_band) s.wrong = (static_cast<int>(v) != truth);
            if (s.wrong == 1 && m.name.rfind("coal::", 0) == 0 && ++m.wrong_shown <= 8)
              fprintf(stderr, "%s: %s case %ld: says %s, alpha* %.17g\n",
                      pair_names.back().c_str(), label(m).c_str(), i, v ? "collision" : "free",
                      alpha_ref);
          } else if (m.name.rfind("dcol_proximity", 0) == 0 || m.name.rfind("dcol_gradient", 0) == 0 ||
                     m.name.rfind("dcol_jacobian", 0) == 0) {
            s.err = std::fabs(v - alpha_ref);
          } else if (alpha_ref > 1 + kBand) {
            s.err = std::fabs(std::max(0.0, v) - dist_ind);  // distance errors: separated only
            s.dcol_diff = std::fabs(std::max(0.0, v) - dist_ref);
          }
          if (m.agree_tol > 0) {
            if (alpha_ref > 1 + kBand) {
              m.sep_checked++;
              if (s.dcol_diff > m.worst_err) {
                // a third opinion for the worst case: FCL at distance_tolerance 1e-12 (untimed)
                fcl::DistanceRequestd req;
                req.gjk_solver_type = fcl::GST_LIBCCD;
                req.distance_tolerance = 1e-12;
                fcl::DistanceResultd res;
                fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
                char b[256];
                snprintf(b, sizeof b, "%s case %ld: %.17g vs dcol %.17g, FCL@1e-12 %.17g",
                         pair_names.back().c_str(), i, v, dist_ref, res.min_distance);
                m.worst_err = s.dcol_diff, m.worst_case = b;
              }
              if (s.dcol_diff > 10 * m.agree_tol * std::max(1.0, dist_ref)) m.sep_disagree10++;
              if (s.dcol_diff > m.agree_tol * std::max(1.0, dist_ref)) {
                if (m.sep_disagree++ < 5)
                  fprintf(stderr, "%s: %s case %ld: distance %.17g, dcol %.17g (alpha* %.17g)\n",
                          pair_names.back().c_str(), label(m).c_str(), i, v, dist_ref, alpha_ref);
              }
            } else if (alpha_ref < 1 - kBand) {
              m.ovl_checked++;
              if (v > m.agree_tol) {
                if (m.ovl_disagree++ < 5)
                  fprintf(stderr, "%s: %s case %ld: distance %.17g on an overlapping pair "
                          "(alpha* %.17g)\n", pair_names.back().c_str(), label(m).c_str(), i, v,
                          alpha_ref);
              }
            }
          }
          m.samples.push_back(s);
        }
        // penetration depth on the overlapping cases (untimed): dcol_signed_distance against
        // Coal, FCL (libccd and indep solvers), libccd MPR and the independent check
        if (alpha_ref < 1 - kBand) {
          PeerDepths pdp;
          if (fcl_pair) {
#ifdef DCOL_BENCH_HAVE_COAL
            {
              coal::DistanceRequest req;
              coal::DistanceResult res;
              const double d = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
              pdp.raw[kPeerCoal] = d;
              if (d < 0) pdp.depth[kPeerCoal] = -d;
              pdp.normal[kPeerCoal] = {res.normal[0], res.normal[1], res.normal[2]};
            }
#endif
            for (int k : {kPeerFclCcd, kPeerFclIndep}) {
              // fcl::distance(..., request, result) as FCL 0.7 does it (the solver set up from
              // the request), but through the solver-templated overload compiled here: the
              // instantiation inside the Debian libfcl keeps its assert()s, and GST_INDEP
              // aborts on `index != -1` when its collide fallback finds no contact; with
              // NDEBUG, as in a release build of FCL, it returns -DBL_MIN instead
              fcl::DistanceRequestd req;
              req.enable_signed_distance = true;
              req.gjk_solver_type = k == kPeerFclCcd ? fcl::GST_LIBCCD : fcl::GST_INDEP;
              fcl::DistanceResultd res;
              try {
                if (k == kPeerFclCcd) {
                  fcl::detail::GJKSolver_libccd<double> solver;
                  solver.distance_tolerance = req.distance_tolerance;
                  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, &solver, req, res);
                } else {
                  fcl::detail::GJKSolver_indep<double> solver;
                  solver.gjk_tolerance = req.distance_tolerance;
                  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, &solver, req, res);
                }
              } catch (const std::exception& e) {
                if (fcl_signed_threw[k - kPeerFclCcd]++ < 3)
                  fprintf(stderr, "%s case %ld: FCL signed distance threw: %s\n",
                          pair_names.back().c_str(), i, e.what());
                continue;
              }
              const double d = res.min_distance;
              pdp.raw[k] = d;
              // -1: libccd's EPA failed; > -1e-300: FCL's collide fallback found no contact
              if (d < -1e-300 && d != -1.0) pdp.depth[k] = -d;
            }
          }
          {
            ccd_real_t depth;
            ccd_vec3_t dir, pos;
            const int rc = ccdMPRPenetration(&c.b1, &c.b2, &ccd, &depth, &dir, &pos);
            pdp.raw[kPeerMpr] = rc == 0 ? depth : -1;
            if (rc == 0) {
              pdp.depth[kPeerMpr] = depth;
              pdp.normal[kPeerMpr] = {dir.v[0], dir.v[1], dir.v[2]};
            }
          }
          dcol_signed_distance_result osd{};
          const bool osd_ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle,
                                                   &c.b2.pose, &defaults, &osd) == DCOL_OK;
          record_depth(depth_rows[pair], c, osd_ok, osd, pdp, defaults.tolerance,
                       pair_names.back() + " case " + std::to_string(i));
        }
        // contact agreement with dcol_contacts (this case's values)
        dcol_signed_distance_result sd{};
        bool sd_ok = false;
        if (!in_band) {
          const Method* dm = nullptr;
          for (const Method& m : methods)
            if (m.contact && m.only == 0) dm = &m;
          sd_ok = dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose,
                                       &defaults, &sd) == DCOL_OK;
          if (dm->last_ok && dm->last > kNoContact && sd_ok) {
            Agree& a = self_agree[pair];
            a.depth_checked++;
            const double e = std::fabs(dm->last + sd.distance);
            if (e > kDepthAgree) a.depth_disagree++;
            if (e > a.depth_max) {
              char b[200];
              snprintf(b, sizeof b, "%s case %ld: %.9g vs %.9g, alpha* %.6g",
                       pair_names.back().c_str(), i, dm->last, -sd.distance, alpha_ref);
              a.depth_max = e, a.worst = b;
            }
          }
        }
        if (engine_pair && !in_band) {
          const Method* dm = nullptr;
          for (const Method& m : methods)
            if (m.contact && m.only == 0) dm = &m;
          for (const Method& m : methods) {
            if (!m.contact || m.only == 0 || !dm->last_ok || !m.last_ok) continue;
            Agree& a = agree[m.only - 1][pair];
            const bool hd = dm->last > kNoContact, he = m.last > kNoContact;
            a.contact_checked++;
            if (hd != he) {
              if (std::fabs(alpha_ref - 1) >= 1e-4) a.contact_disagree4++;
              if (a.contact_disagree++ < 3)
                fprintf(stderr, "%s: %s case %ld: %s, dcol_contacts %s (alpha* %.17g)\n",
                        pair_names.back().c_str(), m.name.c_str(), i, he ? "contact" : "none",
                        hd ? "contact" : "none", alpha_ref);
            } else if (hd) {
              // the engine's depth against dcol_signed_distance (-distance), when it certified
              if (sd_ok && sd.distance < 0) {
                a.sd_checked++;
                if (std::fabs(m.last + sd.distance) > kDepthAgree) a.sd_disagree++;
              }
              a.depth_checked++;
              const double e = std::fabs(m.last - dm->last);
              if (e > kDepthAgree) a.depth_disagree++;
              if (e > a.depth_max) {
                char b[320];
                dcol_signed_distance_result sd{};
                dcol_signed_distance(c.s1.handle, &c.b1.pose, c.s2.handle, &c.b2.pose, &defaults,
                                     &sd);
                snprintf(b, sizeof b, "case %ld: %.9g vs dcol_contacts %.9g (dcol_signed_distance "
                         "%.9g), alpha* %.6g", i, m.last, dm->last, -sd.distance, alpha_ref);
#ifdef DCOL_BENCH_HAVE_COAL
                {
                  // a third opinion: Coal's signed distance (default request, EPA), untimed
                  coal::DistanceRequest req;
                  coal::DistanceResult res;
                  const double d = coal::distance(g1.geom.get(), g1.tf, g2.geom.get(), g2.tf, req, res);
                  snprintf(b + strlen(b), sizeof b - strlen(b), ", Coal %.9g", -d);
                }
#endif
                a.depth_max = e, a.worst = b;
              }
            }
          }
        }
        cmp_case_release(&c);
      }
      ode_pair_of.push_back(ode_pair == 1);
      fprintf(stderr, "%s done (%ld cases so far)\n", pair_names.back().c_str(), made);
    }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

  // ---- output ----------------------------------------------------------------------------
  const std::string md_path = outdir + "/benchmark.md", csv_path = outdir + "/time_vs_error.csv";
  FILE* md = fopen(md_path.c_str(), "w");
  FILE* csv = fopen(csv_path.c_str(), "w");
  if (!md || !csv) {
    fprintf(stderr, "cannot write %s or %s\n", md_path.c_str(), csv_path.c_str());
    return 1;
  }
  const Method* fcl_ref = nullptr;
  for (const Method& m : methods)
    if (m.name == "fcl::distance" && m.tol == kFclRefTol) fcl_ref = &m;
  const Stats ref_all = stats(*fcl_ref, [](const Sample&) { return true; });
  auto find = [&](const std::string& name, double tol) -> const Method* {
    for (const Method& m : methods)
      if (m.name == name && m.tol == tol) return &m;
    return nullptr;
  };
  const Method* coal_ref = find("coal::distance", kCoalRefTol);  // null without Coal
  const Stats coal_all =
      coal_ref ? stats(*coal_ref, [](const Sample&) { return true; }) : Stats{};

  fprintf(md, "# dcol vs Coal 3, FCL 0.7 and libccd 2.1: time and error\n\n");
  fprintf(md, "%s.%s\n\n", kCoalStatus,
          kHaveCoal ? " Coal comes from the libcoal wheel on PyPI (cmeel build, Release); "
                      "`coal::distance` and `coal::collide` with default requests (GJK + EPA; "
                      "the distance is signed, collide computes the contact), the distance also "
                      "at gjk_tolerance 1e-2 … 1e-12 (EPA at its default), "
                      "`coal::ComputeDistance` the functor that caches the shape pair's "
                      "function, `coal::collide (no contact)` a boolean request "
                      "(CollisionRequest(NO_REQUEST, 1)). Coal, like FCL, runs on the 28 pair "
                      "types without the padded polygon."
                    : " The tables below have no Coal columns.");
  fprintf(md,
          "dcol %s; %ld cases per pair type (seed %ld; a third separated, near touching, "
          "overlapping), %ld calls timed together per case (steady_clock), methods interleaved "
          "per case; %ld cases in all, %ld failures; %.1f s. Times are medians over cases in ns "
          "per call. Reference solves that fell back from 1e-12 to 1e-11 or 1e-10 (solver stalled): %ld; failed calls (dcol returned an error, e.g. a stall at 1e-12) are left out of a method's statistics and counted in the table. Errors: |alpha - alpha_ref| for proximity/gradient/jacobian against "
          "the dcol solve at tolerance 1e-12 (self-referenced: only dcol computes alpha, so "
          "these errors say how far a looser tolerance is from dcol's own tight answer, not "
          "from the truth); |max(0, d) - d_ind| for distances on separated cases only "
          "(alpha_ref > 1 + 1e-6) against an independent reference d_ind (see \"Distance error "
          "reference\" below; cases without one are left out of the distance errors). Wrong: boolean answers that disagree with alpha_ref < 1, "
          "cases with |alpha_ref - 1| < 1e-6 not counted. FCL runs on the 28 pair types without "
          "the padded polygon; libccd uses CCD_INIT defaults (mpr_tolerance 1e-4) with support "
          "functions from compare_common.c.\n\n",
          dcol_version(), cases, seed, repeat, made, failures, seconds, ref_fallbacks);

  {
    // headline ratios on the 28 FCL pair types, same cases, same run
    auto fcl_med = [&](const Method* m) {
      return stats(*m, [](const Sample& x) { return x.fcl_pair; }).med_ns;
    };
    const double fd = fcl_med(fcl_ref);
    const double fc = fcl_med(find("fcl::collide (default)", 0));
    fprintf(md, "## Headline (28 FCL pair types, medians in the same run)\n\n");
    fprintf(md, "| comparison | dcol ns | FCL ns | ratio dcol / FCL |\n|---|--:|--:|--:|\n");
    const Method* pd = find("dcol_proximity (default tol)", 0);
    fprintf(md, "| dcol_proximity (default tol) / fcl::distance @1e-06 | %.0f | %.0f | %.2f |\n",
            fcl_med(pd), fd, fcl_med(pd) / fd);
    for (double t : {1e-4, 1e-6}) {
      const Method* p = find("dcol_proximity", t);
      fprintf(md, "| dcol_proximity @%.0e / fcl::distance @1e-06 | %.0f | %.0f | %.2f |\n", t,
              fcl_med(p), fd, fcl_med(p) / fd);
    }
    const Method* di = find("dcol_intersect (default tol)", 0);
    fprintf(md, "| dcol_intersect / fcl::collide | %.0f | %.0f | %.2f |\n\n", fcl_med(di), fc,
            fcl_med(di) / fc);
    if (coal_ref) {
      const double cd = fcl_med(coal_ref);
      fprintf(md, "| comparison | dcol ns | Coal ns | ratio dcol / Coal |\n|---|--:|--:|--:|\n");
      const Method* dd = find("dcol_distance (default tol)", 0);
      for (const Method* m : {pd, dd})
        fprintf(md, "| %s / coal::distance (default) | %.0f | %.0f | %.2f |\n", m->name.c_str(),
                fcl_med(m), cd, fcl_med(m) / cd);
      for (const char* cn : {"coal::collide (default)", "coal::collide (no contact)"}) {
        const double cc = fcl_med(find(cn, 0));
        fprintf(md, "| dcol_intersect / %s | %.0f | %.0f | %.2f |\n", cn, fcl_med(di), cc,
                fcl_med(di) / cc);
      }
      fprintf(md, "\n");
    }
  }
  {
    const long sep = dref_fcl + dref_dcol + dref_none;
    const double spread_med = median(dref_spread);
    const double spread_max =
        dref_spread.empty() ? NAN : *std::max_element(dref_spread.begin(), dref_spread.end());
    fprintf(md, "## Distance error reference\n\n"
                "On the separated cases (alpha_ref > 1 + 1e-6) of the 28 pair types with an FCL "
                "shape: d_ind = FCL's distance (GST_LIBCCD) at distance_tolerance 1e-12 where it "
                "agrees with Coal's at gjk_tolerance 1e-12 to %.0e max(1, d) (%ld cases; there "
                "|FCL - Coal| has median %s and max %s); else dcol's at tolerance 1e-12 where it "
                "agrees with FCL's or Coal's to the same bound (%ld cases); else no reference "
                "(%ld cases, left out of the distance errors). %ld separated cases of the 8 "
                "padded-polygon pair types have no peer and no reference: the distance errors "
                "are over the 28 pair types. By construction FCL @1e-12 has error 0 on the "
                "cases where it is the reference (%.1f %% of them) and dcol @1e-12 on the "
                "others: the 1e-12 points of those two sweeps are not measurements.%s\n\n",
            kRefAgree, dref_fcl, fmt(spread_med, "%.1e").c_str(), fmt(spread_max, "%.1e").c_str(),
            dref_dcol, dref_none, dref_nopeer, sep ? 100.0 * dref_fcl / sep : NAN,
            kHaveCoal ? "" : " Without Coal no two peers can agree: the reference is dcol at "
                             "1e-12 where FCL at 1e-12 agrees with it.");
    printf("distance reference on %ld separated cases: FCL=Coal %ld, dcol (agrees with one) %ld, "
           "none %ld; |FCL - Coal| median %s max %s; %ld polygon cases without a peer\n", sep,
           dref_fcl, dref_dcol, dref_none, fmt(spread_med, "%.1e").c_str(),
           fmt(spread_max, "%.1e").c_str(), dref_nopeer);
  }
  fprintf(md, "## All pairs\n\n");
  fprintf(md,
          "`all 36`: every case the method ran on; `28 FCL pairs`: the pair types FCL supports, "
          "with the ratio to `fcl::distance @1e-06` (FCL's default tolerance) on the same cases.\n\n");
  fprintf(md, "| method | all 36: median ns | 28 FCL pairs: median ns | ratio to FCL distance | "
              "%smedian error | max error | wrong / compared | failed calls |\n|---|--:|--:|--:|%s--:|--:|--:|--:|\n",
          coal_ref ? "ratio to Coal distance | " : "", coal_ref ? "--:|" : "");
  for (const Method& m : methods) {
    if (m.contact) continue;  // their own table below
    const Stats a = stats(m, [](const Sample&) { return true; });
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    const Stats e = m.fcl_only ? f : a;
    fprintf(md, "| %s | %s | %s | %s | %s%s | %s | %s | %ld |\n", label(m).c_str(),
            m.fcl_only ? "–" : fmt(a.med_ns, "%.0f").c_str(), fmt(f.med_ns, "%.0f").c_str(),
            fmt(f.med_ns / ref_all.med_ns, "%.2f").c_str(),
            coal_ref ? (fmt(f.med_ns / coal_all.med_ns, "%.2f") + " | ").c_str() : "",
            fmt(e.med_err, "%.1e").c_str(),
            fmt(e.max_err, "%.1e").c_str(),
            m.boolean ? (std::to_string(e.wrong) + " / " + std::to_string(e.compared)).c_str()
                      : "–",
            m.failures);
  }

  // CSV over the 28 FCL pair types (the same cases for every method)
  // quantity: alpha (self-referenced, dcol at 1e-12) or distance (the independent reference);
  // zero_error_share: the share of the errors that are exactly 0
  fprintf(csv, "method,tolerance,quantity,reference,median_ns,median_error,max_error,"
               "error_cases,zero_error_share\n");
  for (const Method& m : methods) {
    if (m.boolean || m.contact) continue;
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    long n_err = 0, n_zero = 0;
    for (const Sample& x : m.samples)
      if (x.fcl_pair && !std::isnan(x.err)) n_err++, n_zero += x.err == 0;
    const bool alpha = m.name.rfind("dcol_proximity", 0) == 0 ||
                       m.name.rfind("dcol_gradient", 0) == 0 || m.name.rfind("dcol_jacobian", 0) == 0;
    fprintf(csv, "%s,%s,%s,%s,%.1f,%.6e,%.6e,%ld,%.4f\n", m.name.c_str(),
            m.tol > 0 ? fmt(m.tol, "%.0e").c_str() : "default", alpha ? "alpha" : "distance",
            alpha ? "dcol@1e-12 (self)" : "independent", f.med_ns, f.med_err, f.max_err, n_err,
            n_err ? static_cast<double>(n_zero) / n_err : NAN);
  }

  // dcol distance vs FCL (and Coal) distance at equal (median) error, on the 28 FCL pairs
  struct Pt { double err, ns; };
  auto curve_of = [&](const std::string& name) {
    std::vector<Pt> curve;
    for (const Method& m : methods)
      if (m.name == name) {
        const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
        curve.push_back({f.med_err, f.med_ns});
      }
    std::sort(curve.begin(), curve.end(), [](const Pt& a, const Pt& b) { return a.err < b.err; });
    return curve;
  };
  auto ns_at = [](const std::vector<Pt>& curve, double err) {
    double ns = NAN;
    for (size_t k = 0; k + 1 < curve.size(); ++k) {
      const Pt a = curve[k], b = curve[k + 1];
      if (a.err > 0 && b.err > a.err && err >= a.err && err <= b.err) {
        const double w = std::log(err / a.err) / std::log(b.err / a.err);
        ns = std::exp((1 - w) * std::log(a.ns) + w * std::log(b.ns));
      }
    }
    return ns;
  };
  const std::vector<Pt> fcl_curve = curve_of("fcl::distance"), coal_curve = curve_of("coal::distance");
  fprintf(md, "\n## dcol_distance vs fcl::distance%s at equal median error (28 FCL pairs)\n\n",
          coal_ref ? " and coal::distance" : "");
  fprintf(md, "The other library's time at dcol's median error, interpolated log-log along its "
              "tolerance sweep (– when dcol's error lies outside its range).\n\n");
  fprintf(md, "| dcol tolerance | dcol median error | dcol median ns | FCL ns at that error | "
              "ratio dcol / FCL |%s\n|---|--:|--:|--:|--:|%s\n",
          coal_ref ? " Coal ns at that error | ratio dcol / Coal |" : "", coal_ref ? "--:|--:|" : "");
  for (const Method& m : methods) {
    if (m.name != "dcol_distance" && m.name != "dcol_distance (default tol)") continue;
    const Stats f = stats(m, [](const Sample& x) { return x.fcl_pair; });
    const double fcl_ns = ns_at(fcl_curve, f.med_err), coal_ns = ns_at(coal_curve, f.med_err);
    fprintf(md, "| %s | %s | %.0f | %s | %s |", m.tol > 0 ? fmt(m.tol, "%.0e").c_str() : "default",
            fmt(f.med_err, "%.1e").c_str(), f.med_ns, fmt(fcl_ns, "%.0f").c_str(),
            fmt(f.med_ns / fcl_ns, "%.2f").c_str());
    if (coal_ref)
      fprintf(md, " %s | %s |", fmt(coal_ns, "%.0f").c_str(), fmt(f.med_ns / coal_ns, "%.2f").c_str());
    fprintf(md, "\n");
  }

  // dcol vs Coal (and FCL collide) per pair type: medians per pair type, then the median over
  // the 28 pair types (the project's "all-pairs median") and the worst pair type
  if (coal_ref) {
    const Method* pd = find("dcol_proximity (default tol)", 0);
    const Method* dd = find("dcol_distance (default tol)", 0);
    const Method* di = find("dcol_intersect (default tol)", 0);
    const Method* cc = find("coal::collide (default)", 0);
    const Method* cb = find("coal::collide (no contact)", 0);
    const Method* fc = find("fcl::collide (default)", 0);
    const Method* cols[] = {pd, dd, di, coal_ref, cc, cb, fc};
    fprintf(md, "\n## dcol vs Coal per pair type (28 pair types)\n\n"
                "Median ns per pair type; ratios of those medians. `all-pairs median`: the median "
                "over the 28 pair types of each column (ratios: the median of the per-pair "
                "ratios); `ratio of the all-pairs medians`: the all-pairs median times divided; "
                "`worst`: the largest per-pair ratio.\n\n");
    fprintf(md, "| pair | dcol proximity | dcol distance | dcol intersect | Coal distance | Coal "
                "collide | Coal collide (no contact) | FCL collide | proximity / Coal distance | "
                "distance / Coal distance | intersect / Coal collide | intersect / Coal collide "
                "(no contact) | intersect / FCL collide |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    std::vector<std::vector<double>> colv(7), ratv(5);
    std::vector<std::string> worst_pair(5);
    std::vector<double> worst(5, -1);
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      double v[7];
      bool any = true;
      for (int k = 0; k < 7; ++k) {
        const Stats st = stats(*cols[k], [p](const Sample& x) { return x.pair == p; });
        v[k] = st.med_ns;
        if (st.n == 0) any = false;
      }
      if (!any) continue;
      const double r[5] = {v[0] / v[3], v[1] / v[3], v[2] / v[4], v[2] / v[5], v[2] / v[6]};
      fprintf(md, "| %s |", pair_names[p].c_str());
      for (int k = 0; k < 7; ++k) fprintf(md, " %.0f |", v[k]), colv[k].push_back(v[k]);
      for (int k = 0; k < 5; ++k) {
        fprintf(md, " %.2f |", r[k]);
        ratv[k].push_back(r[k]);
        if (r[k] > worst[k]) worst[k] = r[k], worst_pair[k] = pair_names[p];
      }
      fprintf(md, "\n");
    }
    fprintf(md, "| **all-pairs median** |");
    for (int k = 0; k < 7; ++k) fprintf(md, " **%.0f** |", median(colv[k]));
    for (int k = 0; k < 5; ++k) fprintf(md, " **%.2f** |", median(ratv[k]));
    {
      const double m[7] = {median(colv[0]), median(colv[1]), median(colv[2]), median(colv[3]),
                           median(colv[4]), median(colv[5]), median(colv[6])};
      fprintf(md, "\n| ratio of the all-pairs medians | | | | | | | | %.2f | %.2f | %.2f | %.2f | %.2f |",
              m[0] / m[3], m[1] / m[3], m[2] / m[4], m[2] / m[5], m[2] / m[6]);
    }
    fprintf(md, "\n| worst pair type | | | | | | | |");
    for (int k = 0; k < 5; ++k) fprintf(md, " %.2f (%s) |", worst[k], worst_pair[k].c_str());
    fprintf(md, "\n");
    const char* rname[5] = {"dcol proximity / Coal distance", "dcol distance / Coal distance",
                            "dcol intersect / Coal collide (default)",
                            "dcol intersect / Coal collide (no contact)",
                            "dcol intersect / FCL collide"};
    printf("all-pairs medians over the 28 pair types (ns): proximity %.0f, distance %.0f, "
           "intersect %.0f, Coal distance %.0f, Coal collide %.0f / no contact %.0f, FCL collide %.0f\n",
           median(colv[0]), median(colv[1]), median(colv[2]), median(colv[3]), median(colv[4]),
           median(colv[5]), median(colv[6]));
    for (int k = 0; k < 5; ++k)
      printf("  %s: median of per-pair ratios %.2f, worst %.2f (%s)\n", rname[k],
             median(ratv[k]), worst[k], worst_pair[k].c_str());
    // agreement with dcol
    fprintf(md, "\n## Coal agreement with dcol\n\n"
                "Distance: separated cases (alpha_ref > 1 + 1e-6) where |max(0, d) - d_ref| > "
                "tol max(1, d_ref), and overlapping cases (alpha_ref < 1 - 1e-6) where Coal's "
                "signed distance is > tol, tol = the request's gjk_tolerance (default %.0e). Collide: answers against alpha_ref < 1, "
                "|alpha_ref - 1| < 1e-6 not counted (dcol_intersect on the same cases for "
                "comparison).\n\n| method | separated: disagree / checked | beyond 10 tol | "
                "max \\|max(0, d) - d_dcol\\| (worst case) | overlapping: disagree / checked |\n|---|--:|--:|--:|--:|\n",
            kCoalAgree);
    printf("%s: agreement with dcol\n", kCoalStatus);
    for (const Method& m : methods) {
      if (m.agree_tol > 0) {
        fprintf(md, "| %s | %ld / %ld | %ld | %s (%s) | %ld / %ld |\n", label(m).c_str(),
                m.sep_disagree, m.sep_checked, m.sep_disagree10, fmt(m.worst_err, "%.1e").c_str(),
                m.worst_case.c_str(), m.ovl_disagree, m.ovl_checked);
        printf("  %s: separated %ld / %ld disagree, %ld beyond 10x tol (max error %s: %s), "
               "overlapping %ld / %ld\n", label(m).c_str(), m.sep_disagree, m.sep_checked,
               m.sep_disagree10, fmt(m.worst_err, "%.1e").c_str(), m.worst_case.c_str(),
               m.ovl_disagree, m.ovl_checked);
      }
    }
    fprintf(md, "\n| boolean method (28 pair types) | wrong / compared (band 1e-6) | wrong / "
                "compared outside \\|alpha_ref - 1\\| < 1e-4 | wrong with alpha_ref < 0.99 or > 1.01 |\n|---|--:|--:|--:|\n");
    for (const Method* m : {di, cc, cb, fc}) {
      const Stats st = stats(*m, [](const Sample& x) { return x.fcl_pair; });
      const Stats wide = stats(*m, [](const Sample& x) {
        return x.fcl_pair && std::fabs(x.alpha_ref - 1) >= 1e-4;
      });
      const Stats far = stats(*m, [](const Sample& x) {
        return x.fcl_pair && std::fabs(x.alpha_ref - 1) > 1e-2;
      });
      fprintf(md, "| %s | %ld / %ld | %ld / %ld | %ld |\n", m->name.c_str(), st.wrong, st.compared,
              wide.wrong, wide.compared, far.wrong);
      printf("  %s: %ld / %ld wrong (band 1e-6), %ld / %ld outside 1e-4, %ld with |alpha*-1| > 1e-2\n",
             m->name.c_str(), st.wrong, st.compared, wide.wrong, wide.compared, far.wrong);
    }
  } else {
    fprintf(md, "\n## dcol vs Coal\n\n%s\n", kCoalStatus);
  }
  printf("%s\n", kCoalStatus);

  // penetration depth, and the signed-distance timing on the overlapping cases
  {
    std::string timing;
    const Method* sdm = find("dcol_signed_distance (default tol)", 0);
    if (coal_ref && sdm) {
      auto ovl = [](const Sample& x) { return x.fcl_pair && x.alpha_ref < 1 - kBand; };
      const double all_d = stats(*sdm, ovl).med_ns, all_c = stats(*coal_ref, ovl).med_ns;
      std::vector<double> md_d, md_c, rat;
      double worst = -1;
      std::string worst_pair;
      char b[512];
      timing += "### Time on the overlapping poses: dcol_signed_distance vs coal::distance\n\n"
                "The same interleaved timing as the other tables (the methods `dcol_signed_distance "
                "(default tol)` and `coal::distance @1e-06`, Coal's default request), on the "
                "overlapping cases of the 28 pair types only. The project's target: dcol's signed "
                "distance <= 1.0x Coal's on overlapping poses.\n\n"
                "| pair | dcol_signed_distance ns | coal::distance ns | ratio |\n|---|--:|--:|--:|\n";
      for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
        auto pp = [p](const Sample& x) { return x.pair == p && x.fcl_pair && x.alpha_ref < 1 - kBand; };
        const Stats a = stats(*sdm, pp), g = stats(*coal_ref, pp);
        if (a.n == 0 || g.n == 0) continue;
        const double r = a.med_ns / g.med_ns;
        md_d.push_back(a.med_ns), md_c.push_back(g.med_ns), rat.push_back(r);
        if (r > worst) worst = r, worst_pair = pair_names[p];
        snprintf(b, sizeof b, "| %s | %.0f | %.0f | %.2f |\n", pair_names[p].c_str(), a.med_ns,
                 g.med_ns, r);
        timing += b;
      }
      snprintf(b, sizeof b, "| **all-pairs median** | **%.0f** | **%.0f** | **%.2f** |\n"
               "| median over all overlapping cases | %.0f | %.0f | %.2f |\n"
               "| worst pair type | | | %.2f (%s) |\n",
               median(md_d), median(md_c), median(rat), all_d, all_c, all_d / all_c, worst,
               worst_pair.c_str());
      timing += b;
      printf("signed distance on overlapping poses: dcol %.0f ns, Coal %.0f ns (all-pairs "
             "medians), median of per-pair ratios %.2f (target <= 1.0), over all cases %.2f, "
             "worst %.2f (%s)\n", median(md_d), median(md_c), median(rat), all_d / all_c, worst,
             worst_pair.c_str());
    } else {
      timing = std::string("No signed-distance timing against Coal: ") + kCoalStatus + ".\n";
    }
    if (fcl_signed_threw[0] || fcl_signed_threw[1])
      timing += "\nFCL signed distance threw (left out): libccd " +
                std::to_string(fcl_signed_threw[0]) + ", indep " +
                std::to_string(fcl_signed_threw[1]) + " cases.\n";
    write_depth_section(md, depth_rows, pair_names, kHaveCoal, defaults.tolerance, timing);
  }

  // contact queries: dcol_contacts vs ODE dCollide vs Bullet GJK/EPA, per pair type
  {
    const Method* dc = nullptr;
    const Method* eng[2] = {nullptr, nullptr};
    for (const Method& m : methods)
      if (m.contact) (m.only == 0 ? dc : eng[m.only - 1]) = &m;
    const char* ename[2] = {"ODE", "Bullet"};
    const char* estat[2] = {kOdeStatus, kBulletStatus};
    fprintf(md, "\n## Contact queries: dcol_contacts vs ODE dCollide vs Bullet GJK/EPA\n\n");
    fprintf(md, "%s. %s.\n\n", kOdeStatus, kBulletStatus);
    fprintf(md,
            "On the same cases (the pair types of sphere, box, 12-facet polytope, capsule, "
            "cylinder: the kinds both engines have; ODE only where it has a collider), the same "
            "interleaved timing: `dcol_contacts` with margin 0 and capacity 4 (the manifold, "
            "default tolerance); ODE `dCollide(g1, g2, 4, ...)` with ODE's own geoms (capsule "
            "and cylinder along z, rotated as for FCL; polytope: dCreateConvex from its faces "
            "and planes); Bullet: one `btGjkPairDetector::getClosestPoints` (btVoronoiSimplexSolver, "
            "btGjkEpaPenetrationDepthSolver, maximum distance the sum of the margins as in "
            "btConvexConvexAlgorithm, reported distances > 0 dropped) on btSphereShape, btBoxShape, "
            "btCapsuleShapeX, btCylinderShapeX, btConvexHullShape (margins 0 on box, cylinder, "
            "hull), what btConvexConvexAlgorithm does for one contact point, with btScalar = "
            "float. Shapes are built outside the timed calls. Median ns per pair type; "
            "`all-pairs median`: the median over the pair types of each column (ratios: the "
            "median of the per-pair ratios); min / max: the per-pair extremes.\n\n"
            "Agreement with dcol_contacts, cases with |alpha* - 1| >= 1e-6: contact / no "
            "contact disagreements, and, when both report contact, the deepest point's depth "
            "differing by more than %.0e (max difference in the last columns; the worst case "
            "overall is printed with Coal's signed distance, default request, as a third opinion "
            "when Coal is there). `wrong`: contact against alpha* < 1 (same band). dcol_contacts "
            "calls that returned an error (not converged) are left out of its times and of the "
            "agreement counts (failed calls below).\n\n", kDepthAgree);
    fprintf(md, "| pair | dcol_contacts ns | ODE ns | Bullet ns | dcol / ODE | dcol / Bullet | "
                "ODE contact disagree / checked | ODE depth > 1e-4 / checked | Bullet contact "
                "disagree / checked | Bullet depth > 1e-4 / checked | max depth diff ODE | max "
                "depth diff Bullet | dcol_contacts depth vs dcol_signed_distance > 1e-4 / checked |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    std::vector<double> col[3], rat[2];
    double rmin[2] = {INFINITY, INFINITY}, rmax[2] = {-1, -1};
    std::string pmin[2], pmax[2];
    Agree tot[2];
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      if (!engine_pair_of[p]) continue;
      double v[3];
      for (int k = 0; k < 3; ++k) {
        const Method* m = k == 0 ? dc : eng[k - 1];
        v[k] = m ? stats(*m, [p](const Sample& x) { return x.pair == p; }).med_ns : NAN;
        if (!std::isnan(v[k])) col[k].push_back(v[k]);
      }
      fprintf(md, "| %s | %s | %s | %s |", pair_names[p].c_str(), fmt(v[0], "%.0f").c_str(),
              fmt(v[1], "%.0f").c_str(), fmt(v[2], "%.0f").c_str());
      for (int e = 0; e < 2; ++e) {
        const double r = v[0] / v[e + 1];
        fprintf(md, " %s |", fmt(r, "%.2f").c_str());
        if (std::isnan(r)) continue;
        rat[e].push_back(r);
        if (r < rmin[e]) rmin[e] = r, pmin[e] = pair_names[p];
        if (r > rmax[e]) rmax[e] = r, pmax[e] = pair_names[p];
      }
      for (int e = 0; e < 2; ++e) {
        const Agree& a = agree[e][p];
        if (!eng[e] || a.contact_checked == 0)
          fprintf(md, " – | – |");
        else
          fprintf(md, " %ld / %ld | %ld / %ld |", a.contact_disagree, a.contact_checked,
                  a.depth_disagree, a.depth_checked);
        tot[e].contact_checked += a.contact_checked, tot[e].contact_disagree += a.contact_disagree;
        tot[e].contact_disagree4 += a.contact_disagree4;
        tot[e].sd_checked += a.sd_checked, tot[e].sd_disagree += a.sd_disagree;
        tot[e].depth_checked += a.depth_checked, tot[e].depth_disagree += a.depth_disagree;
        if (a.depth_max > tot[e].depth_max)
          tot[e].depth_max = a.depth_max, tot[e].worst = pair_names[p] + " " + a.worst;
      }
      for (int e = 0; e < 2; ++e)
        fprintf(md, " %s |", eng[e] && agree[e][p].depth_checked
                                 ? fmt(agree[e][p].depth_max, "%.1e").c_str() : "–");
      fprintf(md, " %ld / %ld |\n", self_agree[p].depth_disagree, self_agree[p].depth_checked);
    }
    const double m0 = median(col[0]), m1 = median(col[1]), m2 = median(col[2]);
    fprintf(md, "| **all-pairs median** | **%s** | **%s** | **%s** | **%s** | **%s** |",
            fmt(m0, "%.0f").c_str(), fmt(m1, "%.0f").c_str(), fmt(m2, "%.0f").c_str(),
            fmt(median(rat[0]), "%.2f").c_str(), fmt(median(rat[1]), "%.2f").c_str());
    for (int e = 0; e < 2; ++e)
      fprintf(md, " %ld / %ld | %ld / %ld |", tot[e].contact_disagree, tot[e].contact_checked,
              tot[e].depth_disagree, tot[e].depth_checked);
    Agree self_eng, self_all;
    for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
      for (Agree* t : {&self_all, &self_eng}) {
        if (t == &self_eng && !engine_pair_of[p]) continue;
        t->depth_checked += self_agree[p].depth_checked;
        t->depth_disagree += self_agree[p].depth_disagree;
        if (self_agree[p].depth_max > t->depth_max)
          t->depth_max = self_agree[p].depth_max, t->worst = self_agree[p].worst;
      }
    }
    fprintf(md, " %s | %s | %ld / %ld |\n", fmt(tot[0].depth_max, "%.1e").c_str(),
            fmt(tot[1].depth_max, "%.1e").c_str(), self_eng.depth_disagree, self_eng.depth_checked);
    fprintf(md, "| ratio of the all-pairs medians | | | | %s | %s |\n",
            fmt(m0 / m1, "%.2f").c_str(), fmt(m0 / m2, "%.2f").c_str());
    fprintf(md, "| min / max per-pair ratio | | | | %s (%s) / %s (%s) | %s (%s) / %s (%s) |\n\n",
            fmt(rat[0].empty() ? NAN : rmin[0], "%.2f").c_str(), pmin[0].c_str(),
            fmt(rat[0].empty() ? NAN : rmax[0], "%.2f").c_str(), pmax[0].c_str(),
            fmt(rat[1].empty() ? NAN : rmin[1], "%.2f").c_str(), pmin[1].c_str(),
            fmt(rat[1].empty() ? NAN : rmax[1], "%.2f").c_str(), pmax[1].c_str());
    printf("contact queries (all-pairs medians over the engine pair types, ns): dcol_contacts %s, "
           "ODE %s, Bullet %s\n", fmt(m0, "%.0f").c_str(), fmt(m1, "%.0f").c_str(),
           fmt(m2, "%.0f").c_str());
    printf("  dcol_contacts' deepest depth vs dcol_signed_distance: %ld / %ld differ by more than "
           "%.0e on the engine pair types, %ld / %ld on all 36 (largest %.2e: %s)\n",
           self_eng.depth_disagree, self_eng.depth_checked, kDepthAgree, self_all.depth_disagree,
           self_all.depth_checked, self_all.depth_max, self_all.worst.c_str());
    fprintf(md, "dcol_contacts' deepest depth against dcol_signed_distance on the same case "
                "(untimed): %ld / %ld differ by more than %.0e on these pair types, %ld / %ld on "
                "all 36 (largest %.2e: %s).\n\n", self_eng.depth_disagree,
            self_eng.depth_checked, kDepthAgree, self_all.depth_disagree, self_all.depth_checked,
            self_all.depth_max, self_all.worst.c_str());
    for (int e = 0; e < 2; ++e) {
      if (!eng[e]) {
        printf("  %s\n", estat[e]);
        fprintf(md, "%s: no %s columns.\n\n", estat[e], ename[e]);
        continue;
      }
      printf("  dcol_contacts / %s: median of per-pair ratios %.2f, ratio of medians %.2f, "
             "min %.2f (%s), max %.2f (%s)\n", ename[e], median(rat[e]),
             m0 / (e ? m2 : m1), rmin[e], pmin[e].c_str(), rmax[e], pmax[e].c_str());
      printf("  %s vs dcol_contacts: contact disagreements %ld / %ld (%ld with |alpha*-1| >= 1e-4), "
             "depth > %.0e: %ld / %ld (max %.2e, %s)\n", ename[e], tot[e].contact_disagree,
             tot[e].contact_checked, tot[e].contact_disagree4,
             kDepthAgree, tot[e].depth_disagree, tot[e].depth_checked, tot[e].depth_max,
             tot[e].worst.c_str());
      printf("  %s depth vs dcol_signed_distance: %ld / %ld off by more than %.0e\n", ename[e],
             tot[e].sd_disagree, tot[e].sd_checked, kDepthAgree);
      fprintf(md, "%s depth against dcol_signed_distance (where both dcol_contacts and %s report "
                  "contact and the signed distance converged): %ld / %ld off by more than %.0e.\n\n",
              ename[e], ename[e], tot[e].sd_disagree, tot[e].sd_checked, kDepthAgree);
      fprintf(md, "%s vs dcol_contacts: %ld / %ld contact disagreements (%ld of them with "
                  "|alpha* - 1| >= 1e-4), %ld / %ld depths off by "
                  "more than %.0e (largest %.2e: %s).\n\n", ename[e], tot[e].contact_disagree,
              tot[e].contact_checked, tot[e].contact_disagree4, tot[e].depth_disagree, tot[e].depth_checked, kDepthAgree,
              tot[e].depth_max, tot[e].worst.c_str());
    }
    fprintf(md, "| method | pair types | median ns (all its cases) | wrong / compared | failed "
                "calls |\n|---|--:|--:|--:|--:|\n");
    for (const Method* m : {dc, eng[0], eng[1]}) {
      if (!m) continue;
      const Stats all = stats(*m, [](const Sample&) { return true; });
      const Stats ep = stats(*m, [&](const Sample& x) { return engine_pair_of[x.pair]; });
      fprintf(md, "| %s (engine pair types) | %d | %.0f | %ld / %ld | %ld |\n", m->name.c_str(),
              static_cast<int>(m == eng[0] ? std::count(ode_pair_of.begin(), ode_pair_of.end(), true)
                                           : std::count(engine_pair_of.begin(), engine_pair_of.end(), true)),
              ep.med_ns, ep.wrong, ep.compared, m->failures);
      printf("  %s: %ld / %ld wrong against alpha* < 1\n", m->name.c_str(), ep.wrong, ep.compared);
      if (m == dc)
        fprintf(md, "| %s (all 36 pair types) | 36 | %.0f | %ld / %ld | |\n", m->name.c_str(),
                all.med_ns, all.wrong, all.compared);
    }
    if (eng[0])
      for (int p = 0; p < static_cast<int>(pair_names.size()); ++p)
        if (engine_pair_of[p] && !ode_pair_of[p])
          fprintf(md, "\nODE has no collider for %s: left out of its columns.\n",
                  pair_names[p].c_str());
  }
  printf("%s\n%s\n", kOdeStatus, kBulletStatus);

  // which solver answered dcol_proximity, per regime
  const char* cat_names[] = {"separated", "near touching", "overlapping"};
  fprintf(md, "\n## Which solver answered dcol_proximity, per regime\n\n"
              "The result's `solver` field on an untimed extra dcol_proximity call per case and "
              "tolerance (all 36 pair types): the share of calls answered by a closed form, the "
              "certified ray cast, the ray cast with a Newton polish, and the interior-point "
              "solver, with the interior-point iterations of the calls that solver answered "
              "(median / max; `iterations` counts interior-point iterations only, so it is 0 for "
              "the other solvers).\n\n"
              "| tolerance | regime | calls | closed form | ray cast | polish | interior point | "
              "interior-point iterations (its calls) |\n|---|---|--:|--:|--:|--:|--:|--:|\n");
  printf("dcol_proximity: which solver answered (closed form / ray cast / polish / interior "
         "point, %% of calls):\n");
  for (size_t t = 0; t < n_tol_rows; ++t) {
    const std::string tl = t < std::size(kTols) ? fmt(kTols[t], "%.0e")
                                                : "default (" + fmt(defaults.tolerance, "%.0e") + ")";
    printf("  tol %s:", tl.c_str());
    for (int k = 0; k < 3; ++k) {
      const std::array<long, 4>& n = solver_count[t][k];
      const long tot = n[0] + n[1] + n[2] + n[3];
      auto pct = [&](long x) { return fmt(tot ? 100.0 * x / tot : NAN, "%.1f %%"); };
      const auto& v = ip_iters[t][k];
      const double mx = v.empty() ? NAN : *std::max_element(v.begin(), v.end());
      fprintf(md, "| %s | %s | %ld | %s | %s | %s | %s | %s / %s |\n", tl.c_str(), cat_names[k],
              tot, pct(n[DCOL_SOLVER_CLOSED_FORM]).c_str(), pct(n[DCOL_SOLVER_RAY_CAST]).c_str(),
              pct(n[DCOL_SOLVER_POLISH]).c_str(), pct(n[DCOL_SOLVER_INTERIOR_POINT]).c_str(),
              fmt(median(v), "%.0f").c_str(), fmt(mx, "%.0f").c_str());
      printf("  %s %s/%s/%s/%s", cat_names[k], pct(n[DCOL_SOLVER_CLOSED_FORM]).c_str(),
             pct(n[DCOL_SOLVER_RAY_CAST]).c_str(), pct(n[DCOL_SOLVER_POLISH]).c_str(),
             pct(n[DCOL_SOLVER_INTERIOR_POINT]).c_str());
    }
    printf("\n");
  }

  // per pair type
  fprintf(md, "\n## Per pair type\n");
  for (int p = 0; p < static_cast<int>(pair_names.size()); ++p) {
    const Stats ref = stats(*fcl_ref, [p](const Sample& x) { return x.pair == p; });
    const Stats cref =
        coal_ref ? stats(*coal_ref, [p](const Sample& x) { return x.pair == p; }) : Stats{};
    fprintf(md, "\n### %s\n\n| method | median ns | ratio to FCL distance @1e-06 | %smedian error "
                "| max error | wrong / compared |\n|---|--:|--:|%s--:|--:|--:|\n",
            pair_names[p].c_str(), coal_ref ? "ratio to Coal distance (default) | " : "",
            coal_ref ? "--:|" : "");
    for (const Method& m : methods) {
      const Stats s = stats(m, [p](const Sample& x) { return x.pair == p; });
      if (s.n == 0) continue;
      fprintf(md, "| %s | %.0f | %s | %s%s | %s | %s |\n", label(m).c_str(), s.med_ns,
              fmt(s.med_ns / ref.med_ns, "%.2f").c_str(),
              coal_ref ? (fmt(s.med_ns / cref.med_ns, "%.2f") + " | ").c_str() : "",
              fmt(s.med_err, "%.1e").c_str(),
              fmt(s.max_err, "%.1e").c_str(),
              m.boolean ? (std::to_string(s.wrong) + " / " + std::to_string(s.compared)).c_str()
                        : "–");
    }
  }
  fclose(md);
  fclose(csv);
  for (const Method& m : methods)
    if (m.failures) printf("%s: %ld failed calls\n", label(m).c_str(), m.failures);
  printf("reference fallbacks: %ld\n", ref_fallbacks);
  printf("%ld cases, %ld failures, %.1f s; wrote %s and %s\n", made, failures, seconds,
         md_path.c_str(), csv_path.c_str());
  return made > 0 ? 0 : 1;
}

int main() {
  const int rc = run();
  fflush(stdout);
  fflush(stderr);
  // With Coal, the process holds two octomap builds: the system's 1.9 (through libfcl) and the
  // wheel's 1.10 (through libcoal). Their static objects share symbols, so both libraries
  // construct and destroy the same ones and the exit-time destructors end in a double free.
  // Nothing here uses octomap: skip the static destructors (the outputs are closed and flushed).
  // Done with or without Coal (a build directory configured before may still link both).
  std::_Exit(rc);
}
