// test_fcl.cpp: dcol against FCL 0.7 (GJK libccd solver) for every unordered pair of sphere,
// ellipsoid, convex polytope, box, capsule, cylinder and cone (28 pair types).
//
// Per case (DCOL_COMPARE_CASES per pair type, default 3000; a third each separated, near
// touching and overlapping, a quarter of them with cube-aligned attitudes; DCOL_COMPARE_SEED
// changes the seed; DCOL_COMPARE_PAIR=box-cone runs one pair type; DCOL_COMPARE_VERBOSE=1
// prints the cases behind the information columns):
//  (a) separated (alpha* > 1 + band): dcol_distance against fcl::distance (GST_LIBCCD,
//      distance_tolerance 1e-12, nearest points): |dd| <= kDistTol l, l the larger bounding
//      radius of the two shapes;
//  (b) outside the band: fcl::collide (GST_LIBCCD) against alpha* < 1, with gjk_tolerance
//      1e-12 ("coll") and with FCL's default 1e-6 ("coll%");
//  (c) |p1 - p2| from dcol_proximity >= dcol's distance - 1e-9 l, distance = 0 iff
//      alpha* <= 1 (outside the band), x* inside both shapes scaled by alpha* and alpha* not
//      below the bound from the distance normal (cmp_check_dcol_self);
//  (d) dcol's distance inside an independent bracket [L, U] (below), to kDistTol l.
//
// Every disagreement is resolved by recomputing the truth independently of both libraries
// (support and gauge functions of compare_common.c):
//  - distance: a bracket [L, U] on the true distance: U from witness pairs (dcol's and FCL's)
//    plus how far each witness lies outside its shape (gauge functions), L from separating
//    directions (dcol's normal and witness directions, FCL's witness direction) via support
//    functions, tightened when needed by an independent GJK-like iteration (Frank-Wolfe with
//    an exact min-norm step over up to four support points of the Minkowski difference).
//    FCL is wrong when its distance is outside [L - eps, U + eps] and dcol's is inside; anything
//    else (dcol outside, or a bracket too wide to decide) is put down to dcol.
//  - collide: dcol "intersecting" needs x* verified as a common point (both gauges <= 1); dcol
//    "separated" needs a verified separating plane. Without it the disagreement goes to dcol.
// The test fails (exit 1) when anything is put down to dcol.
//
// Frames and the conversion of each shape to FCL: c_tests/compare/fcl_body.hpp (shared with
// benches/compare/bench_compare.cpp).

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "compare_common.h"
#include "fcl_body.hpp"

namespace {

constexpr double kBand = 1e-6;           // |alpha* - 1| < band: collide not compared
constexpr double kDistTol = 1e-6;        // |d_dcol - d_fcl| <= kDistTol * l
constexpr double kCertEps = 1e-9;        // slack on the independent bracket, times l
constexpr double kWitnessOffTol = 1e-6;  // FCL witness "off its shape" beyond this, times l
constexpr double kTightTol = 1e-12;      // FCL's distance_tolerance and gjk_tolerance

const cmp_kind kKinds[] = {CMP_SPHERE,  CMP_ELLIPSOID, CMP_POLYTOPE, CMP_BOX,
                           CMP_CAPSULE, CMP_CYLINDER,  CMP_CONE};


struct Tally {
  long cases = 0, in_band = 0, separated = 0, dcol_failures = 0, self_violations = 0;
  long witness_violations = 0;  // (w): dcol's distance witnesses off their shapes
  double max_dd = 0;  // max |d_dcol - d_fcl| / l over separated cases
  long dist_dis = 0, dist_fcl = 0, dist_dcol = 0;
  long coll_dis = 0, coll_fcl = 0, coll_dcol = 0;     // gjk_tolerance 1e-12
  long colld_dis = 0, colld_fcl = 0, colld_dcol = 0;  // FCL's default gjk_tolerance
  // evidence against FCL
  long ev_fcl_above_feasible = 0;  // FCL's distance > U: a verified pair is closer
  long ev_fcl_below_plane = 0;     // FCL's distance < L: a verified plane separates more
  double fcl_err_max = 0;          // largest certified FCL distance error / l
  long ev_common_point = 0, ev_separating_plane = 0;
  double overlap_alpha_min = 1;    // deepest overlap FCL's collide missed (smallest alpha*)
  double separated_alpha_max = 1;  // most separated case FCL's collide called a collision
  long fcl_witness_off = 0;        // FCL witness off its shape by > kWitnessOffTol l
  double fcl_witness_off_max = 0;  // / l
  // dcol's own distance, checked independently (d)
  double dcol_bracket_max = 0;  // max (U - L) / l from dcol's witnesses and normal alone
  long dcol_refined = 0;        // cases where that was wider than kCertEps l and was tightened
  double dcol_refined_max = 0;  // max (U - L) / l after tightening
  double dcol_err = 0;          // largest certified error of dcol's distance / l
  long dcol_dist_wrong = 0;     // ... beyond kDistTol
  double normal_err = 0;        // largest angle between dcol's normal and the true one (rad)
  double dflt_dd = 0;           // max |dd| / l with FCL's default distance tolerance

  void add(const Tally& t) {
    cases += t.cases, in_band += t.in_band, separated += t.separated;
    dcol_failures += t.dcol_failures, self_violations += t.self_violations;
    witness_violations += t.witness_violations;
    max_dd = std::max(max_dd, t.max_dd);
    dist_dis += t.dist_dis, dist_fcl += t.dist_fcl, dist_dcol += t.dist_dcol;
    coll_dis += t.coll_dis, coll_fcl += t.coll_fcl, coll_dcol += t.coll_dcol;
    colld_dis += t.colld_dis, colld_fcl += t.colld_fcl, colld_dcol += t.colld_dcol;
    ev_fcl_above_feasible += t.ev_fcl_above_feasible;
    ev_fcl_below_plane += t.ev_fcl_below_plane;
    fcl_err_max = std::max(fcl_err_max, t.fcl_err_max);
    ev_common_point += t.ev_common_point, ev_separating_plane += t.ev_separating_plane;
    overlap_alpha_min = std::min(overlap_alpha_min, t.overlap_alpha_min);
    separated_alpha_max = std::max(separated_alpha_max, t.separated_alpha_max);
    fcl_witness_off += t.fcl_witness_off;
    fcl_witness_off_max = std::max(fcl_witness_off_max, t.fcl_witness_off_max);
    dcol_bracket_max = std::max(dcol_bracket_max, t.dcol_bracket_max);
    dcol_refined += t.dcol_refined;
    dcol_refined_max = std::max(dcol_refined_max, t.dcol_refined_max);
    dcol_err = std::max(dcol_err, t.dcol_err);
    dcol_dist_wrong += t.dcol_dist_wrong;
    normal_err = std::max(normal_err, t.normal_err);
    dflt_dd = std::max(dflt_dd, t.dflt_dd);
  }
  long against_dcol() const {
    return dist_dcol + coll_dcol + colld_dcol + dcol_failures + self_violations + dcol_dist_wrong +
           (cmp_witness_warn_only() ? 0 : witness_violations);
  }
};

void print_pose(FILE* out, const cmp_case& c) { cmp_case_print(out, &c); }

void print_header() {
  std::printf("%-19s %6s %5s %5s | %7s %4s %5s %6s | %4s %5s %6s | %5s %5s %6s | %3s %3s | %8s "
              "%7s | %8s\n",
              "pair", "cases", "band", "sep", "max|dd|", "dist", "->fcl", "->dcol", "coll",
              "->fcl", "->dcol", "coll%", "->fcl", "->dcol", "(c)", "(w)", "dcol err", "n err",
              "dflt|dd|");
}

void print_row(const char* name, const Tally& t) {
  std::printf("%-19s %6ld %5ld %5ld | %7.1e %4ld %5ld %6ld | %4ld %5ld %6ld | %5ld %5ld %6ld | "
              "%3ld %3ld | %8.1e %7.1e | %8.1e%s\n",
              name, t.cases, t.in_band, t.separated, t.max_dd, t.dist_dis, t.dist_fcl,
              t.dist_dcol, t.coll_dis, t.coll_fcl, t.coll_dcol, t.colld_dis, t.colld_fcl,
              t.colld_dcol, t.self_violations, t.witness_violations, t.dcol_err, t.normal_err,
              t.dflt_dd,
              t.against_dcol() ? "  <- DCOL" : "");
}

std::string pair_name(const cmp_case& c) {
  return std::string(cmp_kind_name(c.s1.kind)) + "-" + cmp_kind_name(c.s2.kind) +
         (c.aligned ? " (aligned)" : "");
}

void sub(const double a[3], const double b[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = a[i] - b[i];
}

double norm(const double a[3]) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

// (a): resolve a distance disagreement. Returns true when put down to FCL.
bool resolve_distance(const cmp_case& c, double d_fcl, const double f1[3], const double f2[3],
                      Tally& t, bool quiet = false) {
  const double l = c.scale, eps = kCertEps * l, d_dcol = c.dist.distance;
  double dirs[4][3];
  std::copy(c.dist.normal, c.dist.normal + 3, dirs[0]);
  sub(c.dist.closest2, c.dist.closest1, dirs[1]);
  sub(f2, f1, dirs[2]);
  sub(c.prox.contact2, c.prox.contact1, dirs[3]);
  double L = -INFINITY, best[3] = {1, 0, 0};
  for (auto& d : dirs) {
    const double v = cmp_separation_bound(&c.b1, &c.b2, d);
    if (v > L) L = v, std::copy(d, d + 3, best);
  }
  double U = std::min(cmp_witness_bound(&c.b1, &c.b2, c.dist.closest1, c.dist.closest2),
                      cmp_witness_bound(&c.b1, &c.b2, f1, f2));
  auto outside = [&](double d) { return d < L - eps || d > U + eps; };
  if (!(outside(d_fcl) && !outside(d_dcol))) {  // tighten independently before deciding
    double up = INFINITY;
    L = std::max(L, cmp_independent_distance(&c.b1, &c.b2, best, &up, 20000));
    U = std::min(U, up);
  }
  double e[3];
  sub(f2, f1, e);
  if (outside(d_fcl) && !outside(d_dcol)) {
    static int shown = 0;
    if (!quiet && shown++ < 20)
      std::printf("  FCL distance error, %s: dcol %.12g, FCL %.12g (|p1-p2| %.12g, witnesses "
                  "off their shapes by %.2g, %.2g); independent bracket [%.12g, %.12g]\n",
                  pair_name(c).c_str(), d_dcol, d_fcl, norm(e), cmp_excess_world(&c.b1, f1),
                  cmp_excess_world(&c.b2, f2), L, U);
    if (d_fcl > U + eps) {
      t.ev_fcl_above_feasible++;
      t.fcl_err_max = std::max(t.fcl_err_max, (d_fcl - U) / l);
    } else {
      t.ev_fcl_below_plane++;
      t.fcl_err_max = std::max(t.fcl_err_max, (L - d_fcl) / l);
    }
    return true;
  }
  if (quiet) return false;
  std::fprintf(stderr,
               "  %s: distance dcol %.17g, FCL %.17g; independent bracket [%.17g, %.17g]: %s\n",
               pair_name(c).c_str(), d_dcol, d_fcl, L, U,
               outside(d_dcol) ? "dcol outside it" : "cannot decide");
  print_pose(stderr, c);
  return false;
}

// (b): resolve a collide disagreement. Returns true when put down to FCL.
bool resolve_collide(const cmp_case& c, bool fcl_hit, const char* what, Tally& t) {
  const double a = c.prox.alpha;
  double g = 0, bound = 0;
  if (a < 1) {
    if (cmp_certify_overlap(&c, &g)) {
      t.ev_common_point++;
      t.overlap_alpha_min = std::min(t.overlap_alpha_min, a);
      return true;
    }
  } else if (cmp_certify_separation(&c, nullptr, &bound)) {
    t.ev_separating_plane++;
    t.separated_alpha_max = std::max(t.separated_alpha_max, a);
    return true;
  }
  std::fprintf(stderr,
               "  %s: %s says %d, dcol alpha %.17g: no evidence for dcol (max gauge of x* %.17g, "
               "separation bound %.3g)\n",
               pair_name(c).c_str(), what, fcl_hit ? 1 : 0, a, g, bound);
  print_pose(stderr, c);
  return false;
}

bool fcl_collide(const FclBody& f1, const FclBody& f2, double tolerance) {
  fcl::CollisionRequestd req;
  req.gjk_solver_type = fcl::GST_LIBCCD;
  req.gjk_tolerance = tolerance;
  fcl::CollisionResultd res;
  fcl::collide(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
  return res.isCollision();
}

// (a) and (d) on a separated case.
void check_separated(const cmp_case& c, const FclBody& f1, const FclBody& f2, bool verbose,
                     long index, Tally& t) {
  const double l = c.scale;
  t.separated++;
  fcl::DistanceRequestd req;
  req.enable_nearest_points = true;
  req.gjk_solver_type = fcl::GST_LIBCCD;
  req.distance_tolerance = kTightTol;
  fcl::DistanceResultd res;
  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req, res);
  const double d_fcl = res.min_distance;
  double w1[3], w2[3];
  for (int q = 0; q < 3; ++q) w1[q] = res.nearest_points[0][q], w2[q] = res.nearest_points[1][q];
  const double off = std::max(cmp_excess_world(&c.b1, w1), cmp_excess_world(&c.b2, w2)) / l;
  if (off > kWitnessOffTol) {
    t.fcl_witness_off++;
    if (t.fcl_witness_off <= 3) {
      double e[3];
      sub(w2, w1, e);
      std::printf("  FCL witness off its shape by %.3g l, %s: dcol %.12g, FCL %.12g, FCL "
                  "witnesses (%.9g, %.9g, %.9g), (%.9g, %.9g, %.9g), |p1-p2| %.12g\n",
                  off, pair_name(c).c_str(), c.dist.distance, d_fcl, w1[0], w1[1], w1[2], w2[0],
                  w2[1], w2[2], norm(e));
    }
  }
  t.fcl_witness_off_max = std::max(t.fcl_witness_off_max, off);
  const double dd = std::fabs(d_fcl - c.dist.distance) / l;
  t.max_dd = std::max(t.max_dd, dd);
  if (dd > kDistTol) {
    t.dist_dis++;
    (resolve_distance(c, d_fcl, w1, w2, t) ? t.dist_fcl : t.dist_dcol)++;
  }

  // (d) dcol's distance on its own: the bracket from its witnesses (upper) and its normal
  // (lower), tightened independently when wider than kCertEps l.
  double U = cmp_witness_bound(&c.b1, &c.b2, c.dist.closest1, c.dist.closest2);
  double L = cmp_separation_bound(&c.b1, &c.b2, c.dist.normal);
  t.dcol_bracket_max = std::max(t.dcol_bracket_max, (U - L) / l);
  if (verbose && U - L > 1e-3 * l) {
    static int shown = 0;
    if (shown++ < 5 || U - L > 0.1 * l) {
      double e[3];
      sub(c.dist.closest2, c.dist.closest1, e);
      std::printf("  dcol normal/witnesses weak, %s case %ld: distance %.12g, |c2-c1| %.12g, "
                  "witnesses off their shapes by %.3g, %.3g, separation bound of the normal "
                  "%.12g\n",
                  pair_name(c).c_str(), index, c.dist.distance, norm(e),
                  cmp_excess_world(&c.b1, c.dist.closest1),
                  cmp_excess_world(&c.b2, c.dist.closest2), L);
      print_pose(stdout, c);
    }
  }
  if (U - L > kCertEps * l) {
    double n[3] = {c.dist.normal[0], c.dist.normal[1], c.dist.normal[2]}, up = INFINITY;
    const double L0 = L;
    L = std::max(L, cmp_independent_distance(&c.b1, &c.b2, n, &up, 2000));
    U = std::min(U, up);
    t.dcol_refined++;
    t.dcol_refined_max = std::max(t.dcol_refined_max, (U - L) / l);
    // the independent direction n is the true normal to within the bracket: report the angle
    const double cosang = std::clamp(
        (n[0] * c.dist.normal[0] + n[1] * c.dist.normal[1] + n[2] * c.dist.normal[2]) / norm(n),
        -1.0, 1.0);
    const double ang = std::acos(cosang);
    t.normal_err = std::max(t.normal_err, ang);
    if (verbose && ang > 1e-6)
      std::printf("  [verbose] %s case %ld: dcol distance %.12g, normal %.3g rad off the "
                  "independent one (separation bound of dcol's normal %.6g)\n",
                  pair_name(c).c_str(), index, c.dist.distance, ang, L0),
          print_pose(stdout, c);
  }
  const double err = std::max({0.0, L - c.dist.distance, c.dist.distance - U}) / l;
  t.dcol_err = std::max(t.dcol_err, err);
  if (err > kDistTol) {
    t.dcol_dist_wrong++;
    std::fprintf(stderr, "  %s: dcol distance %.17g outside the independent bracket [%.17g, %.17g]\n",
                 pair_name(c).c_str(), c.dist.distance, L, U);
    print_pose(stderr, c);
  }

  // information: FCL at its default distance tolerance (1e-6)
  fcl::DistanceRequestd req_default(true);
  fcl::DistanceResultd res_default;
  fcl::distance(f1.geom.get(), f1.tf, f2.geom.get(), f2.tf, req_default, res_default);
  const double ddd = std::fabs(res_default.min_distance - c.dist.distance) / l;
  if (verbose && ddd > 1e-4)
    std::printf("  [verbose] %s case %ld: FCL at default tolerance %.12g, dcol %.12g\n",
                pair_name(c).c_str(), index, res_default.min_distance, c.dist.distance);
  t.dflt_dd = std::max(t.dflt_dd, ddd);
}

// The referee on known answers: for one case per category of every pair type, fabricated
// disagreements must be resolved the right way. A distance 1e-3 l too long or too short is
// FCL's error; dcol's distance moved by 1e-3 l (FCL exact) is dcol's; x* must prove an overlap
// exactly when alpha* < 1, and a separating plane must be found exactly when alpha* > 1.
// Returns the number of wrong verdicts.
long referee_selftest(long seed) {
  long wrong = 0, checks = 0;
  const int nk = static_cast<int>(sizeof kKinds / sizeof kKinds[0]);
  for (int i1 = 0; i1 < nk; ++i1)
    for (int i2 = i1; i2 < nk; ++i2) {
      cmp_rng rng;
      cmp_rng_seed(&rng, static_cast<uint64_t>(seed) * 104729u + static_cast<uint64_t>(i1 * 16 + i2));
      for (int i = 0; i < 6; ++i) {
        cmp_case c;
        if (cmp_case_make(&c, kKinds[i1], kKinds[i2], i, &rng) != 0) continue;
        const double a = c.prox.alpha, l = c.scale;
        if (std::fabs(a - 1) < 1e-3) {
          cmp_case_release(&c);
          continue;
        }
        Tally t;
        double g, bound;
        const bool overlap_proved = cmp_certify_overlap(&c, &g) != 0;
        const bool separation_proved = cmp_certify_separation(&c, nullptr, &bound) != 0;
        checks += 2;
        wrong += overlap_proved != (a < 1);
        wrong += separation_proved != (a > 1);
        if (a > 1) {
          const double d = c.dist.distance;
          checks += 3;
          wrong += !resolve_distance(c, d + 1e-3 * l, c.dist.closest1, c.dist.closest2, t, true);
          wrong += !resolve_distance(c, d - 1e-3 * l, c.dist.closest1, c.dist.closest2, t, true);
          cmp_case bad = c;
          bad.dist.distance = d + 1e-3 * l;
          wrong += resolve_distance(bad, d, c.dist.closest1, c.dist.closest2, t, true);
        }
        cmp_case_release(&c);
      }
    }
  std::printf("referee self-test: %ld fabricated verdicts, %ld wrong\n", checks, wrong);
  return wrong;
}

}  // namespace

int main() {
  const long n = cmp_env_long("DCOL_COMPARE_CASES", 3000);
  const long seed = cmp_env_long("DCOL_COMPARE_SEED", 20240501);
  const bool verbose = cmp_env_long("DCOL_COMPARE_VERBOSE", 0) > 0;
  double default_gjk_tolerance;
  {
    fcl::CollisionRequestd r;
    default_gjk_tolerance = r.gjk_tolerance;
  }
  std::printf("dcol %s vs FCL 0.7 (GST_LIBCCD): %ld cases per pair type, seed %ld, band "
              "|alpha*-1| < %g, distance tolerance %g l (l = larger bounding radius)\n",
              dcol_version(), n, seed, kBand, kDistTol);
  std::printf("sep = separated cases (distance compared); max|dd| = max |d_dcol - d_fcl| / l; "
              "dist, coll (gjk_tolerance %g), coll%% (FCL's default %g) = disagreements; ->fcl = "
              "put down to FCL with evidence; ->dcol = put down to dcol; (c) = dcol self-check "
              "violations; (w) = dcol distance witness points off their shapes; dcol err = largest certified error of dcol's distance / l; n err = "
              "largest angle (rad) of dcol's normal off the true one (information); dflt|dd| = "
              "max|dd| with FCL's default distance_tolerance (information)\n",
              kTightTol, default_gjk_tolerance);
  const long referee_wrong = referee_selftest(seed);
  print_header();
  Tally total;
  long gen_failures = 0;
  const int nk = static_cast<int>(sizeof kKinds / sizeof kKinds[0]);
  for (int i1 = 0; i1 < nk; ++i1)
    for (int i2 = i1; i2 < nk; ++i2) {
      const cmp_kind k1 = kKinds[i1], k2 = kKinds[i2];
      if (!cmp_pair_selected(k1, k2)) continue;
      Tally t;
      cmp_rng rng;
      cmp_rng_seed(&rng, static_cast<uint64_t>(seed) * 7919u + static_cast<uint64_t>(k1 * 16 + k2));
      for (long i = 0; i < n; ++i) {
        cmp_case c;
        const int rc = cmp_case_make(&c, k1, k2, static_cast<int>(i), &rng);
        if (rc < 0) {
          gen_failures++;
          continue;
        }
        t.cases++;
        if (rc > 0) {
          t.dcol_failures++;
          cmp_case_release(&c);
          continue;
        }
        int wbad = 0;
        t.self_violations += cmp_check_dcol_self(&c, kBand, &wbad);
        t.witness_violations += wbad;
        const double a = c.prox.alpha;
        const FclBody f1 = to_fcl(c.b1), f2 = to_fcl(c.b2);
        if (a > 1 + kBand) check_separated(c, f1, f2, verbose, i, t);
        if (std::fabs(a - 1) < kBand) {
          t.in_band++;
        } else {
          const bool dcol_hit = a < 1;
          const bool hit = fcl_collide(f1, f2, kTightTol);
          if (hit != dcol_hit) {
            t.coll_dis++;
            (resolve_collide(c, hit, "fcl::collide", t) ? t.coll_fcl : t.coll_dcol)++;
          }
          const bool hitd = fcl_collide(f1, f2, default_gjk_tolerance);
          if (hitd != dcol_hit) {
            t.colld_dis++;
            (resolve_collide(c, hitd, "fcl::collide (default tolerance)", t) ? t.colld_fcl
                                                                             : t.colld_dcol)++;
          }
        }
        cmp_case_release(&c);
      }
      print_row((std::string(cmp_kind_name(k1)) + "-" + cmp_kind_name(k2)).c_str(), t);
      std::fflush(stdout);
      total.add(t);
    }
  print_row("total", total);
  std::printf("evidence against FCL, distance: %ld x above a verified feasible pair, %ld x below "
              "a verified separating-plane bound (largest certified FCL error %.3g l)\n",
              total.ev_fcl_above_feasible, total.ev_fcl_below_plane, total.fcl_err_max);
  std::printf("evidence against FCL, collide: %ld x 'x* is a common point' (deepest missed "
              "overlap alpha* = %.9g), %ld x 'verified separating plane' (largest alpha* called "
              "a collision: %.9g)\n",
              total.ev_common_point, total.overlap_alpha_min, total.ev_separating_plane,
              total.separated_alpha_max);
  std::printf("FCL witness points off their shape by > %g l: %ld (max %.3g l)\n", kWitnessOffTol,
              total.fcl_witness_off, total.fcl_witness_off_max);
  std::printf("dcol's distance, checked independently on all %ld separated cases: bracket from "
              "its own witnesses and normal at most %.3g l wide; %ld cases wider than %g l "
              "tightened to at most %.3g l; largest certified error %.3g l\n",
              total.separated, total.dcol_bracket_max, total.dcol_refined, kCertEps,
              total.dcol_refined_max, total.dcol_err);
  if (gen_failures) std::printf("case generation failures: %ld\n", gen_failures);
  const long dcol_errors = total.against_dcol();
  std::printf("put down to dcol: %ld (distance %ld, collide %ld + %ld, solver failures %ld, "
              "(c) %ld, distance outside the independent bracket %ld, (w) witness points %ld%s)\n",
              dcol_errors, total.dist_dcol, total.coll_dcol, total.colld_dcol,
              total.dcol_failures, total.self_violations, total.dcol_dist_wrong,
              total.witness_violations,
              cmp_witness_warn_only() ? ", not failing: DCOL_COMPARE_WITNESS=warn" : "");
  return dcol_errors || gen_failures || referee_wrong ? 1 : 0;
}
