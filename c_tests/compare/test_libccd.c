/*
 * test_libccd.c: dcol's alpha* < 1 against libccd 2.1's ccdGJKIntersect and ccdMPRIntersect,
 * for every unordered pair of the eight dcol shapes (36 pair types), with support functions
 * written here for each shape (the padded polygon as polygon (+) ball).
 *
 * Cases per pair type: DCOL_COMPARE_CASES (default 3000), a third each separated, near touching
 * and overlapping; DCOL_COMPARE_SEED changes the seed. Cases with |alpha* - 1| < band are not
 * compared. Every disagreement is resolved independently of both libraries (compare_common.h):
 * - dcol says "intersecting": x* must be a common point by the gauge functions here;
 * - dcol says "separated": a direction must separate the shapes by the support functions here.
 * A disagreement is put down to libccd only with that evidence; otherwise to dcol, and the test
 * fails. Also checked on every case, (c): |p1 - p2| >= distance - 1e-9 l, distance = 0 iff
 * alpha* <= 1 (outside the band), x* inside both shapes scaled by alpha* (gauges, 1e-6
 * relative), alpha* not below the bound from the distance normal (cmp_check_dcol_self).
 * DCOL_COMPARE_PAIR=box-cone restricts a run to one pair type.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ccd/ccd.h>

#include "compare_common.h"

static const double kBand = 1e-6;
static double kDefaultMprTolerance; /* what CCD_INIT sets (1e-4 in libccd 2.1) */

static void support_fn(const void *obj, const ccd_vec3_t *dir, ccd_vec3_t *vec) {
  const cmp_body *body = (const cmp_body *)obj;
  double d[3] = {dir->v[0], dir->v[1], dir->v[2]}, p[3];
  cmp_support_world(body, d, p);
  ccdVec3Set(vec, p[0], p[1], p[2]);
}

static void center_fn(const void *obj, ccd_vec3_t *center) {
  const cmp_body *body = (const cmp_body *)obj;
  /* the body origin is an interior point of every shape */
  ccdVec3Set(center, body->pose.position[0], body->pose.position[1], body->pose.position[2]);
}

typedef struct tally {
  long cases, in_band, dcol_failures, self_violations, witness_violations;
  long gjk_dis, gjk_other, gjk_dcol;
  long mpr_dis, mpr_other, mpr_dcol;
  long mprd_dis, mprd_other, mprd_dcol; /* MPR with libccd's default tolerance */
  /* evidence */
  long ev_common_point, ev_separating_plane;
  double worst_common_gauge; /* largest max-gauge of x* among certified common points */
  double least_separation;   /* smallest certified separation bound */
  double missed_alpha_min[3]; /* deepest overlap (smallest alpha*) each of GJK, MPR, MPR% missed */
} tally;

static void resolve(const cmp_case *c, int dcol_overlap, const char *who, int claimed,
                    long *other, long *dcol, double *missed_alpha_min, tally *t) {
  if (dcol_overlap) {
    double g;
    if (cmp_certify_overlap(c, &g)) {
      (*other)++;
      t->ev_common_point++;
      if (c->prox.alpha < *missed_alpha_min) *missed_alpha_min = c->prox.alpha;
      if (g > t->worst_common_gauge) t->worst_common_gauge = g;
      return;
    }
    fprintf(stderr, "  %s-%s: %s says %s, dcol alpha %.17g, x* not verified (max gauge %.17g)\n",
            cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), who,
            claimed ? "intersecting" : "separated", c->prox.alpha, g);
  } else {
    double bound;
    if (cmp_certify_separation(c, NULL, &bound)) {
      (*other)++;
      t->ev_separating_plane++;
      if (bound < t->least_separation) t->least_separation = bound;
      return;
    }
    fprintf(stderr, "  %s-%s: %s says %s, dcol alpha %.17g, no separating plane (bound %.3g)\n",
            cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), who,
            claimed ? "intersecting" : "separated", c->prox.alpha, bound);
  }
  cmp_case_print(stderr, c);
  (*dcol)++;
}

/* The referee on known answers: for a few cases of every pair type (away from contact), x*
   must prove an overlap exactly when alpha* < 1 and a separating plane must be found exactly
   when alpha* > 1 (with this file's support and gauge functions, the padded polygon's too).
   Returns the number of wrong verdicts. */
static long referee_selftest(long seed) {
  long wrong = 0, checks = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1)
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2) {
      cmp_rng rng;
      cmp_rng_seed(&rng, (uint64_t)seed * 104729u + (uint64_t)(k1 * 16 + k2));
      for (int i = 0; i < 6; ++i) {
        cmp_case c;
        if (cmp_case_make(&c, (cmp_kind)k1, (cmp_kind)k2, i, &rng) != 0) continue;
        double a = c.prox.alpha, g, bound;
        if (fabs(a - 1) >= 1e-3) {
          checks += 2;
          wrong += (cmp_certify_overlap(&c, &g) != 0) != (a < 1);
          wrong += (cmp_certify_separation(&c, NULL, &bound) != 0) != (a > 1);
        }
        cmp_case_release(&c);
      }
    }
  printf("referee self-test: %ld fabricated verdicts, %ld wrong\n", checks, wrong);
  return wrong;
}

int main(void) {
  long n = cmp_env_long("DCOL_COMPARE_CASES", 3000);
  {
    ccd_t init;
    CCD_INIT(&init);
    kDefaultMprTolerance = init.mpr_tolerance;
  }
  long seed = cmp_env_long("DCOL_COMPARE_SEED", 20240501);
  printf("dcol %s vs libccd 2.1 (GJK and MPR intersection): %ld cases per pair type, seed %ld, "
         "band |alpha*-1| < %g\n",
         dcol_version(), n, seed, kBand);
  printf("GJK: ccdGJKIntersect; MPR: ccdMPRIntersect with mpr_tolerance 1e-12; MPR%%: the same "
         "with libccd's default mpr_tolerance %g. dis = disagreements with alpha* < 1, ->ccd = put "
         "down to libccd with evidence, ->dcol = put down to dcol; band = cases with "
         "|alpha*-1| < band (not compared); (c) = dcol self-check violations; (w) = dcol "
         "distance witness points off their shapes\n",
         kDefaultMprTolerance);
  long referee_wrong = referee_selftest(seed);
  printf("%-20s %6s %5s | %5s %5s %6s | %5s %5s %6s | %5s %5s %6s | %3s %3s\n", "pair", "cases",
         "band", "GJK", "->ccd", "->dcol", "MPR", "->ccd", "->dcol", "MPR%", "->ccd", "->dcol",
         "(c)", "(w)");
  tally total;
  memset(&total, 0, sizeof total);
  total.least_separation = INFINITY;
  total.missed_alpha_min[0] = total.missed_alpha_min[1] = total.missed_alpha_min[2] = 1;
  long gen_failures = 0;
  for (int k1 = 0; k1 < CMP_KIND_COUNT; ++k1)
    for (int k2 = k1; k2 < CMP_KIND_COUNT; ++k2) {
      if (!cmp_pair_selected((cmp_kind)k1, (cmp_kind)k2)) continue;
      tally t;
      memset(&t, 0, sizeof t);
      t.least_separation = INFINITY;
      t.missed_alpha_min[0] = t.missed_alpha_min[1] = t.missed_alpha_min[2] = 1;
      cmp_rng rng;
      cmp_rng_seed(&rng, (uint64_t)seed * 1000003u + (uint64_t)(k1 * 16 + k2));
      for (long i = 0; i < n; ++i) {
        cmp_case c;
        int rc = cmp_case_make(&c, (cmp_kind)k1, (cmp_kind)k2, (int)i, &rng);
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
        double a = c.prox.alpha;
        if (fabs(a - 1) < kBand) {
          t.in_band++;
          cmp_case_release(&c);
          continue;
        }
        int dcol_overlap = a < 1;
        ccd_t ccd;
        CCD_INIT(&ccd);
        ccd.support1 = support_fn;
        ccd.support2 = support_fn;
        ccd.center1 = center_fn;
        ccd.center2 = center_fn;
        ccd.max_iterations = 1000;
        ccd.mpr_tolerance = 1e-12;
        ccd.epa_tolerance = 1e-12;
        ccd.dist_tolerance = 1e-12;
        int gjk = ccdGJKIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
        int mpr = ccdMPRIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
        ccd.mpr_tolerance = kDefaultMprTolerance;
        int mprd = ccdMPRIntersect(&c.b1, &c.b2, &ccd) ? 1 : 0;
        if (gjk != dcol_overlap) {
          t.gjk_dis++;
          resolve(&c, dcol_overlap, "ccdGJKIntersect", gjk, &t.gjk_other, &t.gjk_dcol,
                  &t.missed_alpha_min[0], &t);
        }
        if (mpr != dcol_overlap) {
          t.mpr_dis++;
          resolve(&c, dcol_overlap, "ccdMPRIntersect", mpr, &t.mpr_other, &t.mpr_dcol,
                  &t.missed_alpha_min[1], &t);
        }
        if (mprd != dcol_overlap) {
          t.mprd_dis++;
          resolve(&c, dcol_overlap, "ccdMPRIntersect (default tolerance)", mprd, &t.mprd_other,
                  &t.mprd_dcol, &t.missed_alpha_min[2], &t);
        }
        cmp_case_release(&c);
      }
      char name[64];
      snprintf(name, sizeof name, "%s-%s", cmp_kind_name((cmp_kind)k1), cmp_kind_name((cmp_kind)k2));
      printf("%-20s %6ld %5ld | %5ld %5ld %6ld | %5ld %5ld %6ld | %5ld %5ld %6ld | %3ld %3ld%s\n",
             name, t.cases, t.in_band, t.gjk_dis, t.gjk_other, t.gjk_dcol, t.mpr_dis,
             t.mpr_other, t.mpr_dcol, t.mprd_dis, t.mprd_other, t.mprd_dcol, t.self_violations,
             t.witness_violations,
             t.dcol_failures || t.gjk_dcol || t.mpr_dcol || t.mprd_dcol || t.self_violations ||
                     (t.witness_violations && !cmp_witness_warn_only())
                 ? "  <- DCOL"
                 : "");
      total.cases += t.cases;
      total.in_band += t.in_band;
      total.dcol_failures += t.dcol_failures;
      total.self_violations += t.self_violations;
      total.witness_violations += t.witness_violations;
      total.gjk_dis += t.gjk_dis;
      total.gjk_other += t.gjk_other;
      total.gjk_dcol += t.gjk_dcol;
      total.mpr_dis += t.mpr_dis;
      total.mpr_other += t.mpr_other;
      total.mpr_dcol += t.mpr_dcol;
      total.mprd_dis += t.mprd_dis;
      total.mprd_other += t.mprd_other;
      total.mprd_dcol += t.mprd_dcol;
      total.ev_common_point += t.ev_common_point;
      total.ev_separating_plane += t.ev_separating_plane;
      if (t.worst_common_gauge > total.worst_common_gauge)
        total.worst_common_gauge = t.worst_common_gauge;
      if (t.least_separation < total.least_separation) total.least_separation = t.least_separation;
      for (int a = 0; a < 3; ++a)
        if (t.missed_alpha_min[a] < total.missed_alpha_min[a])
          total.missed_alpha_min[a] = t.missed_alpha_min[a];
    }
  printf("%-20s %6ld %5ld | %5ld %5ld %6ld | %5ld %5ld %6ld | %5ld %5ld %6ld | %3ld %3ld\n",
         "total", total.cases, total.in_band, total.gjk_dis, total.gjk_other, total.gjk_dcol,
         total.mpr_dis, total.mpr_other, total.mpr_dcol, total.mprd_dis, total.mprd_other,
         total.mprd_dcol, total.self_violations, total.witness_violations);
  printf("evidence for libccd's errors: %ld x 'x* is a common point' (max gauge %.12g <= 1), "
         "%ld x 'separating plane' (smallest certified gap %.3g)\n",
         total.ev_common_point, total.worst_common_gauge, total.ev_separating_plane,
         total.least_separation);
  printf("deepest overlap missed (smallest alpha*): GJK %.9g, MPR %.9g, MPR%% %.9g\n",
         total.missed_alpha_min[0], total.missed_alpha_min[1], total.missed_alpha_min[2]);
  long dcol_errors = total.gjk_dcol + total.mpr_dcol + total.mprd_dcol + total.dcol_failures +
                     total.self_violations +
                     (cmp_witness_warn_only() ? 0 : total.witness_violations);
  if (gen_failures) printf("case generation failures (not counted): %ld\n", gen_failures);
  printf("put down to dcol: %ld (GJK %ld, MPR %ld, MPR%% %ld, solver failures %ld, (c) %ld, "
         "(w) witness points %ld%s)\n",
         dcol_errors, total.gjk_dcol, total.mpr_dcol, total.mprd_dcol, total.dcol_failures,
         total.self_violations, total.witness_violations,
         cmp_witness_warn_only() ? ", not failing: DCOL_COMPARE_WITNESS=warn" : "");
  return dcol_errors || gen_failures || referee_wrong ? 1 : 0;
}
