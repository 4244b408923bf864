/*
 * compare_common.h: what the FCL (C++) and libccd (C) comparison tests share.
 *
 * - a deterministic random number generator (splitmix64, the same stream on every platform);
 * - random shapes of the eight dcol kinds, kept both as dcol handles and as plain parameters
 *   (with the vertices and faces of each polytope, computed here from its H-representation);
 * - posed bodies and the random case generator (separated / near touching / overlapping, made
 *   by rescaling the offset r2 - r1 after one proximity solve: alpha* is homogeneous in it);
 * - independent geometry used to decide who is wrong when the libraries disagree: support
 *   functions, gauge functions (the smallest scaling of a shape that holds a point), an upper
 *   bound on the distance from a point to a shape, and certificates built from them:
 *     * a common point: max(gauge1(x), gauge2(x)) <= 1 proves the shapes intersect;
 *     * a separating direction n: n.(r2 - r1) - h1(n) - h2(-n) is a lower bound on the distance
 *       (h_i the support function of body i about its origin), > 0 proves separation;
 *     * a witness pair (w1, w2): |w1 - w2| + excess1(w1) + excess2(w2) is an upper bound on it.
 *
 * None of this code calls dcol for the certificates: dcol only supplies candidate points and
 * directions, whose worth is then checked with the functions here.
 */
#ifndef DCOL_COMPARE_COMMON_H
#define DCOL_COMPARE_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <dcol.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- random numbers ------------------------------------------------------------------ */
typedef struct cmp_rng {
  uint64_t state;
} cmp_rng;

void cmp_rng_seed(cmp_rng *rng, uint64_t seed);
uint64_t cmp_rng_next(cmp_rng *rng);
double cmp_rng_uniform(cmp_rng *rng, double lo, double hi); /* [lo, hi) */
int cmp_rng_int(cmp_rng *rng, int lo, int hi);              /* lo..hi inclusive */
void cmp_rng_unit_vector(cmp_rng *rng, double v[3]);
void cmp_rng_quaternion(cmp_rng *rng, double q[4]); /* uniform unit quaternion [w, x, y, z] */

/* ---- shapes -------------------------------------------------------------------------- */
typedef enum cmp_kind {
  CMP_SPHERE = 0,
  CMP_ELLIPSOID,
  CMP_POLYTOPE,
  CMP_BOX,
  CMP_CAPSULE,
  CMP_CYLINDER,
  CMP_CONE,
  CMP_POLYGON,
  CMP_KIND_COUNT
} cmp_kind;

const char *cmp_kind_name(cmp_kind kind);

#define CMP_MAX_FACETS 16
#define CMP_MAX_VERTICES 64
#define CMP_MAX_FACE_INDICES (3 * CMP_MAX_VERTICES + CMP_MAX_FACETS)

typedef struct cmp_shape {
  cmp_kind kind;
  double radius;     /* sphere, capsule, cylinder, padded polygon */
  double length;     /* capsule, cylinder */
  double height;     /* cone */
  double half_angle; /* cone */
  double half[3];    /* box half-extents */
  double radii[3];   /* ellipsoid semi-axes: P = diag(1 / radii^2) */
  /* polytope: A x <= b, its vertices and, per facet with an area, a counter-clockwise loop
     (seen from outside) of vertex indices */
  size_t m;
  double A[3 * CMP_MAX_FACETS];
  double b[CMP_MAX_FACETS];
  size_t nv;
  double V[3 * CMP_MAX_VERTICES];
  size_t nfaces;
  size_t face_start[CMP_MAX_FACETS + 1];
  int face_index[CMP_MAX_FACE_INDICES];
  /* padded polygon: C y <= d and its vertices in counter-clockwise order */
  size_t pm;
  double C[2 * CMP_MAX_FACETS];
  double d[CMP_MAX_FACETS];
  size_t pnv;
  double PV[2 * CMP_MAX_FACETS];
  double bound_radius; /* max |b| over the body-frame set */
  dcol_shape *handle;  /* the same shape in dcol */
} cmp_shape;

/* A random shape of the given kind (sizes about 0.2 .. 1.5); returns 0 on success. */
int cmp_shape_random(cmp_shape *shape, cmp_kind kind, cmp_rng *rng);
void cmp_shape_release(cmp_shape *shape);

/* ---- posed bodies -------------------------------------------------------------------- */
typedef struct cmp_body {
  const cmp_shape *shape;
  dcol_pose pose; /* unit quaternion */
  double R[9];    /* world-from-body rotation, row-major */
} cmp_body;

void cmp_body_set(cmp_body *body, const cmp_shape *shape, const double r[3], const double q[4]);
void cmp_quat_to_matrix(const double q[4], double R[9]);

/* Support point of the body-frame set in body direction dir (any length > 0, zero allowed);
   returns dir . point. */
double cmp_support_body(const cmp_shape *shape, const double dir[3], double point[3]);
/* The same in the world frame: point is a world point of the posed body. */
double cmp_support_world(const cmp_body *body, const double dir[3], double point[3]);
/* Gauge of a body-frame point: the smallest t >= 0 with b in t * S. */
double cmp_gauge_body(const cmp_shape *shape, const double b[3]);
/* Gauge of a world point with respect to the posed body (scaled about its origin r). */
double cmp_gauge_world(const cmp_body *body, const double y[3]);
/* An upper bound on the Euclidean distance from world point y to the posed body (0 inside). */
double cmp_excess_world(const cmp_body *body, const double y[3]);

/* Lower bound on the distance between the bodies from direction n (from 1 to 2, any length):
   n.(r2 - r1) - h1(n) - h2(-n) over |n|; > 0 proves them separated. */
double cmp_separation_bound(const cmp_body *b1, const cmp_body *b2, const double n[3]);
/* Lower bound on alpha* from direction n: n.(r2 - r1) / (h1(n) + h2(-n)). */
double cmp_alpha_lower_bound(const cmp_body *b1, const cmp_body *b2, const double n[3]);
/* Upper bound on the distance from a witness pair: |w1 - w2| + excess1(w1) + excess2(w2). */
double cmp_witness_bound(const cmp_body *b1, const cmp_body *b2, const double w1[3],
                         const double w2[3]);
/* Refines a separating direction by an independent method (subgradient ascent of the concave
   function n -> n.(r2 - r1) - h1(n) - h2(-n) on the unit sphere, plus a Frank-Wolfe / GJK-like
   iteration on the Minkowski difference using only the support functions here). Returns the
   best lower bound found and stores its direction in n (in/out: the starting direction). Also
   returns in *upper the best upper bound found from support points (a feasible pair). */
double cmp_independent_distance(const cmp_body *b1, const cmp_body *b2, double n[3],
                                double *upper, int iterations);

/* ---- cases --------------------------------------------------------------------------- */
typedef enum cmp_category { CMP_SEPARATED = 0, CMP_NEAR, CMP_OVERLAPPING } cmp_category;

typedef struct cmp_case {
  cmp_shape s1, s2;
  cmp_body b1, b2;
  cmp_category category;
  int aligned; /* attitudes from the 24 rotations of the cube (a quarter of the cases) */
  double alpha_target;
  dcol_proximity_result prox; /* at the final pose */
  dcol_distance_result dist;  /* at the final pose */
  dcol_status prox_status, dist_status;
  double scale; /* length scale l: max(bound radius 1, bound radius 2) */
} cmp_case;

/* Makes case number `index` of the pair (k1, k2): random shapes and attitudes (for a quarter
   of the cases, (index / 3) % 4 == 3, attitudes from the 24 rotations of the cube, so that
   faces and axes line up), the category index % 3, then the offset rescaled to hit the category's target alpha, then proximity and
   distance at the final pose. Returns 0 on success, non-zero when dcol refused (reported). */
int cmp_case_make(cmp_case *c, cmp_kind k1, cmp_kind k2, int index, cmp_rng *rng);
void cmp_case_release(cmp_case *c);
/* Prints the two shapes (parameters) and poses to 17 digits. */
void cmp_shape_describe(FILE *out, const cmp_shape *shape);
void cmp_case_print(FILE *out, const cmp_case *c);
/* Pair filter: DCOL_COMPARE_PAIR="box-capsule" (either order) restricts a run to that pair type. */
int cmp_pair_selected(cmp_kind k1, cmp_kind k2);

/* ---- checks on dcol alone ------------------------------------------------------------ */
/* (c): |p1 - p2| from proximity is not below the exact distance (minus 1e-9 l); the distance
   is 0 exactly when alpha* <= 1 (outside the band); max(gauge1(x*), gauge2(x*)) = alpha* to
   1e-6 relative (x* in both scaled shapes, and no smaller scaling holds it); alpha* is not
   below the lower bound from the distance normal (1e-6 relative). Returns the number of
   violations and prints them. (w), counted apart in *witness_bad (0 or 1): the distance's
   witness points lie within 1e-6 l of their shapes and |c2 - c1| = distance to 1e-6 l. */
int cmp_check_dcol_self(const cmp_case *c, double band, int *witness_bad);
/* DCOL_COMPARE_WITNESS=warn: (w) violations are printed and counted but do not fail a test. */
int cmp_witness_warn_only(void);

/* ---- certificates for collision disagreements ---------------------------------------- */
typedef enum cmp_verdict {
  CMP_VERDICT_OTHER = 0, /* the other library is wrong: evidence found */
  CMP_VERDICT_DCOL = 1   /* no evidence for dcol's answer: counted against dcol */
} cmp_verdict;

/* dcol says the bodies intersect (alpha* < 1): is x* a verified common point? */
int cmp_certify_overlap(const cmp_case *c, double *gauge_max);
/* dcol says they are separated (alpha* > 1): is there a verified separating direction (from
   dcol's distance normal, dcol's contact points, an extra candidate, or the independent
   refinement)? Returns 1 with the bound found in *bound. */
int cmp_certify_separation(const cmp_case *c, const double *extra_dir, double *bound);

/* Environment: integer from a variable, or the default. */
long cmp_env_long(const char *name, long fallback);

#ifdef __cplusplus
}
#endif

#endif
