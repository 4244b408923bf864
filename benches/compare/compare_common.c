/* compare_common.c: see compare_common.h. */
#include "compare_common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CMP_PI 3.14159265358979323846

/* ---- small vector helpers ------------------------------------------------------------ */
static double dot3(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void sub3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[0] - b[0];
  out[1] = a[1] - b[1];
  out[2] = a[2] - b[2];
}
static void cross3(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
/* out = R v */
static void mat_vec(const double R[9], const double v[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = R[3 * i] * v[0] + R[3 * i + 1] * v[1] + R[3 * i + 2] * v[2];
}
/* out = R^T v */
static void mat_t_vec(const double R[9], const double v[3], double out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = R[i] * v[0] + R[3 + i] * v[1] + R[6 + i] * v[2];
}

/* ---- random numbers ------------------------------------------------------------------ */
void cmp_rng_seed(cmp_rng *rng, uint64_t seed) { rng->state = seed; }

uint64_t cmp_rng_next(cmp_rng *rng) {
  uint64_t z = (rng->state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double cmp_rng_uniform(cmp_rng *rng, double lo, double hi) {
  double u = (double)(cmp_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
  return lo + (hi - lo) * u;
}

int cmp_rng_int(cmp_rng *rng, int lo, int hi) {
  return lo + (int)(cmp_rng_next(rng) % (uint64_t)(hi - lo + 1));
}

void cmp_rng_unit_vector(cmp_rng *rng, double v[3]) {
  double z = cmp_rng_uniform(rng, -1.0, 1.0);
  double phi = cmp_rng_uniform(rng, 0.0, 2.0 * CMP_PI);
  double s = sqrt(fmax(0.0, 1.0 - z * z));
  v[0] = s * cos(phi);
  v[1] = s * sin(phi);
  v[2] = z;
}

void cmp_rng_quaternion(cmp_rng *rng, double q[4]) {
  double u1 = cmp_rng_uniform(rng, 0.0, 1.0);
  double u2 = cmp_rng_uniform(rng, 0.0, 2.0 * CMP_PI);
  double u3 = cmp_rng_uniform(rng, 0.0, 2.0 * CMP_PI);
  double a = sqrt(1.0 - u1), b = sqrt(u1);
  q[0] = b * cos(u3);
  q[1] = a * sin(u2);
  q[2] = a * cos(u2);
  q[3] = b * sin(u3);
}

long cmp_env_long(const char *name, long fallback) {
  const char *s = getenv(name);
  if (!s || !*s) return fallback;
  char *end = NULL;
  long v = strtol(s, &end, 10);
  if (end == s || *end != '\0' || v <= 0) {
    fprintf(stderr, "ignoring %s=%s (want a positive integer)\n", name, s);
    return fallback;
  }
  return v;
}

int cmp_witness_warn_only(void) {
  const char *v = getenv("DCOL_COMPARE_WITNESS");
  return v && strcmp(v, "warn") == 0;
}

int cmp_pair_selected(cmp_kind k1, cmp_kind k2) {
  const char *want = getenv("DCOL_COMPARE_PAIR");
  if (!want || !*want) return 1;
  char a[64], b[64];
  snprintf(a, sizeof a, "%s-%s", cmp_kind_name(k1), cmp_kind_name(k2));
  snprintf(b, sizeof b, "%s-%s", cmp_kind_name(k2), cmp_kind_name(k1));
  return strcmp(want, a) == 0 || strcmp(want, b) == 0;
}

/* ---- shapes -------------------------------------------------------------------------- */
const char *cmp_kind_name(cmp_kind kind) {
  static const char *names[CMP_KIND_COUNT] = {"sphere",  "ellipsoid", "polytope", "box",
                                              "capsule", "cylinder",  "cone",     "polygon"};
  return (kind >= 0 && kind < CMP_KIND_COUNT) ? names[kind] : "?";
}

void cmp_quat_to_matrix(const double q_in[4], double R[9]) {
  double n = sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
  double w = q_in[0] / n, x = q_in[1] / n, y = q_in[2] / n, z = q_in[3] / n;
  R[0] = 1 - 2 * (y * y + z * z);
  R[1] = 2 * (x * y - w * z);
  R[2] = 2 * (x * z + w * y);
  R[3] = 2 * (x * y + w * z);
  R[4] = 1 - 2 * (x * x + z * z);
  R[5] = 2 * (y * z - w * x);
  R[6] = 2 * (x * z - w * y);
  R[7] = 2 * (y * z + w * x);
  R[8] = 1 - 2 * (x * x + y * y);
}

/* Solves the 3x3 system M v = r (rows of M given); returns 0 when nearly singular. */
static int solve3(const double *r0, const double *r1, const double *r2, const double rhs[3],
                  double v[3]) {
  double c0[3], c1[3], c2[3];
  cross3(r1, r2, c0);
  cross3(r2, r0, c1);
  cross3(r0, r1, c2);
  double det = dot3(r0, c0);
  if (fabs(det) < 1e-9) return 0;
  for (int i = 0; i < 3; ++i) v[i] = (rhs[0] * c0[i] + rhs[1] * c1[i] + rhs[2] * c2[i]) / det;
  return 1;
}

/* Vertices of { A x <= b } by intersecting facet triples, and a vertex loop per facet. */
static int polytope_vertices(cmp_shape *s) {
  const double tol = 1e-10;
  s->nv = 0;
  for (size_t i = 0; i < s->m; ++i)
    for (size_t j = i + 1; j < s->m; ++j)
      for (size_t k = j + 1; k < s->m; ++k) {
        double rhs[3] = {s->b[i], s->b[j], s->b[k]}, v[3];
        if (!solve3(&s->A[3 * i], &s->A[3 * j], &s->A[3 * k], rhs, v)) continue;
        int feasible = 1;
        for (size_t l = 0; l < s->m && feasible; ++l)
          if (dot3(&s->A[3 * l], v) > s->b[l] + tol) feasible = 0;
        if (!feasible) continue;
        int dup = 0;
        for (size_t u = 0; u < s->nv && !dup; ++u) {
          double e[3];
          sub3(&s->V[3 * u], v, e);
          if (norm3(e) < 1e-9) dup = 1;
        }
        if (dup) continue;
        if (s->nv >= CMP_MAX_VERTICES) return -1;
        memcpy(&s->V[3 * s->nv], v, sizeof v);
        s->nv++;
      }
  /* faces: the vertices on each facet, sorted counter-clockwise about its outward normal */
  size_t used = 0;
  s->nfaces = 0;
  for (size_t i = 0; i < s->m; ++i) {
    const double *a = &s->A[3 * i];
    int idx[CMP_MAX_VERTICES];
    double ang[CMP_MAX_VERTICES];
    size_t n = 0;
    for (size_t u = 0; u < s->nv; ++u)
      if (fabs(dot3(a, &s->V[3 * u]) - s->b[i]) <= 1e-9) idx[n++] = (int)u;
    if (n < 3) continue;
    double c[3] = {0, 0, 0};
    for (size_t t = 0; t < n; ++t)
      for (int q = 0; q < 3; ++q) c[q] += s->V[3 * idx[t] + q] / (double)n;
    double nn[3] = {a[0], a[1], a[2]}, len = norm3(a);
    for (int q = 0; q < 3; ++q) nn[q] /= len;
    double helper[3] = {1, 0, 0};
    if (fabs(nn[0]) > 0.8) helper[0] = 0, helper[1] = 1;
    double e1[3], e2[3];
    cross3(helper, nn, e1);
    double l1 = norm3(e1);
    for (int q = 0; q < 3; ++q) e1[q] /= l1;
    cross3(nn, e1, e2); /* (e1, e2, nn) right-handed */
    for (size_t t = 0; t < n; ++t) {
      double w[3];
      sub3(&s->V[3 * idx[t]], c, w);
      ang[t] = atan2(dot3(w, e2), dot3(w, e1));
    }
    for (size_t t = 1; t < n; ++t) /* insertion sort by angle */
      for (size_t r = t; r > 0 && ang[r - 1] > ang[r]; --r) {
        double ta = ang[r];
        ang[r] = ang[r - 1];
        ang[r - 1] = ta;
        int ti = idx[r];
        idx[r] = idx[r - 1];
        idx[r - 1] = ti;
      }
    if (used + n > CMP_MAX_FACE_INDICES) return -1;
    s->face_start[s->nfaces] = used;
    for (size_t t = 0; t < n; ++t) s->face_index[used++] = idx[t];
    s->nfaces++;
  }
  s->face_start[s->nfaces] = used;
  s->bound_radius = 0;
  for (size_t u = 0; u < s->nv; ++u) s->bound_radius = fmax(s->bound_radius, norm3(&s->V[3 * u]));
  return (s->nv >= 4 && s->nfaces >= 4) ? 0 : -1;
}

/* Vertices of the plane polygon { C y <= d }, counter-clockwise. */
static int polygon_vertices(cmp_shape *s) {
  double P[2 * CMP_MAX_FACETS * CMP_MAX_FACETS];
  size_t n = 0;
  for (size_t i = 0; i < s->pm; ++i)
    for (size_t j = i + 1; j < s->pm; ++j) {
      const double *a = &s->C[2 * i], *c = &s->C[2 * j];
      double det = a[0] * c[1] - a[1] * c[0];
      if (fabs(det) < 1e-9) continue;
      double x = (s->d[i] * c[1] - a[1] * s->d[j]) / det;
      double y = (a[0] * s->d[j] - s->d[i] * c[0]) / det;
      int ok = 1;
      for (size_t l = 0; l < s->pm && ok; ++l)
        if (s->C[2 * l] * x + s->C[2 * l + 1] * y > s->d[l] + 1e-10) ok = 0;
      for (size_t u = 0; u < n && ok; ++u)
        if (hypot(P[2 * u] - x, P[2 * u + 1] - y) < 1e-9) ok = 0;
      if (!ok) continue;
      P[2 * n] = x;
      P[2 * n + 1] = y;
      n++;
    }
  if (n < 3 || n > CMP_MAX_FACETS) return -1;
  double cx = 0, cy = 0, ang[CMP_MAX_FACETS];
  for (size_t u = 0; u < n; ++u) cx += P[2 * u] / (double)n, cy += P[2 * u + 1] / (double)n;
  for (size_t u = 0; u < n; ++u) ang[u] = atan2(P[2 * u + 1] - cy, P[2 * u] - cx);
  for (size_t t = 1; t < n; ++t)
    for (size_t r = t; r > 0 && ang[r - 1] > ang[r]; --r) {
      double ta = ang[r];
      ang[r] = ang[r - 1];
      ang[r - 1] = ta;
      double tx = P[2 * r], ty = P[2 * r + 1];
      P[2 * r] = P[2 * r - 2];
      P[2 * r + 1] = P[2 * r - 1];
      P[2 * r - 2] = tx;
      P[2 * r - 1] = ty;
    }
  s->pnv = n;
  memcpy(s->PV, P, 2 * n * sizeof(double));
  double br = 0;
  for (size_t u = 0; u < n; ++u) br = fmax(br, hypot(P[2 * u], P[2 * u + 1]));
  s->bound_radius = br + s->radius;
  return 0;
}

static int report_dcol(const char *what, dcol_status st) {
  if (st == DCOL_OK) return 0;
  fprintf(stderr, "%s: %s (%s)\n", what, dcol_status_string(st), dcol_last_error_message());
  return 1;
}

int cmp_shape_random(cmp_shape *s, cmp_kind kind, cmp_rng *rng) {
  memset(s, 0, sizeof *s);
  s->kind = kind;
  dcol_status st = DCOL_ERROR_INTERNAL;
  switch (kind) {
    case CMP_SPHERE:
      s->radius = cmp_rng_uniform(rng, 0.2, 1.2);
      s->bound_radius = s->radius;
      st = dcol_shape_new_sphere(s->radius, &s->handle);
      break;
    case CMP_ELLIPSOID: {
      double P[9] = {0};
      for (int i = 0; i < 3; ++i) {
        s->radii[i] = cmp_rng_uniform(rng, 0.2, 1.2);
        P[4 * i] = 1.0 / (s->radii[i] * s->radii[i]);
        s->bound_radius = fmax(s->bound_radius, s->radii[i]);
      }
      st = dcol_shape_new_ellipsoid(P, &s->handle);
      break;
    }
    case CMP_POLYTOPE: {
      /* a randomly rotated tetrahedron's four normals (so the set is bounded) plus 2..10
         random ones; every offset in [0.4, 1) */
      static const double tet[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
      double q[4], R[9];
      cmp_rng_quaternion(rng, q);
      cmp_quat_to_matrix(q, R);
      s->m = (size_t)(4 + cmp_rng_int(rng, 2, 10));
      for (size_t i = 0; i < s->m; ++i) {
        double n[3];
        if (i < 4) {
          double t[3] = {tet[i][0] / sqrt(3.0), tet[i][1] / sqrt(3.0), tet[i][2] / sqrt(3.0)};
          mat_vec(R, t, n);
        } else {
          cmp_rng_unit_vector(rng, n);
        }
        memcpy(&s->A[3 * i], n, sizeof n);
        s->b[i] = cmp_rng_uniform(rng, 0.4, 1.0);
      }
      if (polytope_vertices(s) != 0) return -1;
      st = dcol_shape_new_polytope(s->A, s->b, s->m, &s->handle);
      break;
    }
    case CMP_BOX:
      for (int i = 0; i < 3; ++i) s->half[i] = cmp_rng_uniform(rng, 0.15, 1.0);
      s->bound_radius = norm3(s->half);
      /* the polytope view of the box, for the shared support and gauge code */
      s->m = 6;
      memset(s->A, 0, sizeof s->A);
      for (int i = 0; i < 3; ++i) {
        s->A[3 * i + i] = 1;
        s->A[3 * (i + 3) + i] = -1;
        s->b[i] = s->b[i + 3] = s->half[i];
      }
      if (polytope_vertices(s) != 0) return -1;
      st = dcol_shape_new_box(s->half[0], s->half[1], s->half[2], &s->handle);
      break;
    case CMP_CAPSULE:
      s->radius = cmp_rng_uniform(rng, 0.15, 0.7);
      s->length = cmp_rng_uniform(rng, 0.2, 1.8);
      s->bound_radius = s->radius + 0.5 * s->length;
      st = dcol_shape_new_capsule(s->radius, s->length, &s->handle);
      break;
    case CMP_CYLINDER:
      s->radius = cmp_rng_uniform(rng, 0.15, 0.8);
      s->length = cmp_rng_uniform(rng, 0.2, 1.8);
      s->bound_radius = hypot(s->radius, 0.5 * s->length);
      st = dcol_shape_new_cylinder(s->radius, s->length, &s->handle);
      break;
    case CMP_CONE:
      s->height = cmp_rng_uniform(rng, 0.4, 1.8);
      s->half_angle = cmp_rng_uniform(rng, 0.2, 1.0);
      s->bound_radius = fmax(0.75 * s->height, hypot(0.25 * s->height, s->height * tan(s->half_angle)));
      st = dcol_shape_new_cone(s->height, s->half_angle, &s->handle);
      break;
    case CMP_POLYGON: {
      /* three normals about 120 degrees apart (bounded), plus 0..5 more */
      double a0 = cmp_rng_uniform(rng, 0, 2 * CMP_PI);
      s->pm = (size_t)(3 + cmp_rng_int(rng, 0, 5));
      for (size_t i = 0; i < s->pm; ++i) {
        double a = i < 3 ? a0 + 2.0 * CMP_PI * (double)i / 3.0 + cmp_rng_uniform(rng, -0.3, 0.3)
                         : cmp_rng_uniform(rng, 0, 2 * CMP_PI);
        s->C[2 * i] = cos(a);
        s->C[2 * i + 1] = sin(a);
        s->d[i] = cmp_rng_uniform(rng, 0.3, 1.0);
      }
      s->radius = cmp_rng_uniform(rng, 0.05, 0.4);
      if (polygon_vertices(s) != 0) return -1;
      st = dcol_shape_new_polygon(s->C, s->d, s->pm, s->radius, &s->handle);
      break;
    }
    default:
      return -1;
  }
  return report_dcol("dcol_shape_new", st);
}

void cmp_shape_release(cmp_shape *s) {
  dcol_shape_free(s->handle);
  s->handle = NULL;
}

void cmp_body_set(cmp_body *body, const cmp_shape *shape, const double r[3], const double q[4]) {
  body->shape = shape;
  double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (int i = 0; i < 3; ++i) body->pose.position[i] = r[i];
  for (int i = 0; i < 4; ++i) body->pose.quaternion[i] = q[i] / n;
  cmp_quat_to_matrix(body->pose.quaternion, body->R);
}

/* ---- support functions --------------------------------------------------------------- */
double cmp_support_body(const cmp_shape *s, const double d[3], double p[3]) {
  double len = norm3(d);
  switch (s->kind) {
    case CMP_SPHERE:
      for (int i = 0; i < 3; ++i) p[i] = len > 0 ? s->radius * d[i] / len : 0;
      break;
    case CMP_ELLIPSOID: {
      /* P^-1 d / sqrt(d^T P^-1 d) with P^-1 = diag(radii^2) */
      double w[3], den = 0;
      for (int i = 0; i < 3; ++i) w[i] = s->radii[i] * s->radii[i] * d[i], den += d[i] * w[i];
      den = sqrt(den);
      for (int i = 0; i < 3; ++i) p[i] = den > 0 ? w[i] / den : 0;
      break;
    }
    case CMP_POLYTOPE:
    case CMP_BOX: {
      size_t best = 0;
      double bv = -INFINITY;
      for (size_t u = 0; u < s->nv; ++u) {
        double v = dot3(d, &s->V[3 * u]);
        if (v > bv) bv = v, best = u;
      }
      if (s->kind == CMP_BOX) {
        for (int i = 0; i < 3; ++i) p[i] = d[i] >= 0 ? s->half[i] : -s->half[i];
      } else {
        memcpy(p, &s->V[3 * best], 3 * sizeof(double));
      }
      break;
    }
    case CMP_CAPSULE:
      for (int i = 0; i < 3; ++i) p[i] = len > 0 ? s->radius * d[i] / len : 0;
      p[0] += d[0] >= 0 ? 0.5 * s->length : -0.5 * s->length;
      break;
    case CMP_CYLINDER: {
      double rho = hypot(d[1], d[2]);
      p[0] = d[0] >= 0 ? 0.5 * s->length : -0.5 * s->length;
      p[1] = rho > 0 ? s->radius * d[1] / rho : 0;
      p[2] = rho > 0 ? s->radius * d[2] / rho : 0;
      break;
    }
    case CMP_CONE: {
      double rho = hypot(d[1], d[2]), rb = s->height * tan(s->half_angle);
      double apex = -0.75 * s->height * d[0];
      double rim = 0.25 * s->height * d[0] + rb * rho;
      if (apex > rim) {
        p[0] = -0.75 * s->height, p[1] = 0, p[2] = 0;
      } else {
        p[0] = 0.25 * s->height;
        p[1] = rho > 0 ? rb * d[1] / rho : 0;
        p[2] = rho > 0 ? rb * d[2] / rho : 0;
      }
      break;
    }
    case CMP_POLYGON: {
      size_t best = 0;
      double bv = -INFINITY;
      for (size_t u = 0; u < s->pnv; ++u) {
        double v = d[0] * s->PV[2 * u] + d[1] * s->PV[2 * u + 1];
        if (v > bv) bv = v, best = u;
      }
      for (int i = 0; i < 3; ++i) p[i] = len > 0 ? s->radius * d[i] / len : 0;
      p[0] += s->PV[2 * best];
      p[1] += s->PV[2 * best + 1];
      break;
    }
    default:
      p[0] = p[1] = p[2] = 0;
  }
  return dot3(d, p);
}

double cmp_support_world(const cmp_body *body, const double dir[3], double point[3]) {
  double db[3], pb[3];
  mat_t_vec(body->R, dir, db);
  cmp_support_body(body->shape, db, pb);
  mat_vec(body->R, pb, point);
  for (int i = 0; i < 3; ++i) point[i] += body->pose.position[i];
  return dot3(dir, point);
}

/* ---- gauges -------------------------------------------------------------------------- */
/* distance from a 2-D point to the polygon (0 inside) */
static double polygon_distance(const cmp_shape *s, double x, double y) {
  int inside = 1;
  for (size_t i = 0; i < s->pm && inside; ++i)
    if (s->C[2 * i] * x + s->C[2 * i + 1] * y > s->d[i]) inside = 0;
  if (inside) return 0;
  double best = INFINITY;
  for (size_t u = 0; u < s->pnv; ++u) {
    const double *a = &s->PV[2 * u], *b = &s->PV[2 * ((u + 1) % s->pnv)];
    double ex = b[0] - a[0], ey = b[1] - a[1];
    double t = ((x - a[0]) * ex + (y - a[1]) * ey) / (ex * ex + ey * ey);
    t = fmin(1, fmax(0, t));
    best = fmin(best, hypot(x - a[0] - t * ex, y - a[1] - t * ey));
  }
  return best;
}

/* Is the body point inside t * S? For the shapes whose gauge is found by bisection. */
static int inside_scaled(const cmp_shape *s, const double b[3], double t) {
  if (s->kind == CMP_CAPSULE) {
    double h = 0.5 * s->length * t;
    double ex = fabs(b[0]) > h ? fabs(b[0]) - h : 0;
    return ex * ex + b[1] * b[1] + b[2] * b[2] <= t * t * s->radius * s->radius;
  }
  /* padded polygon: dist((x, y), t P)^2 + z^2 <= (t R)^2, dist((x, y), tP) = t dist(. / t, P) */
  double dp = t * polygon_distance(s, b[0] / t, b[1] / t);
  return dp * dp + b[2] * b[2] <= t * t * s->radius * s->radius;
}

double cmp_gauge_body(const cmp_shape *s, const double b[3]) {
  if (!isfinite(b[0]) || !isfinite(b[1]) || !isfinite(b[2])) return INFINITY;
  switch (s->kind) {
    case CMP_SPHERE:
      return norm3(b) / s->radius;
    case CMP_ELLIPSOID: {
      double g = 0;
      for (int i = 0; i < 3; ++i) g += b[i] * b[i] / (s->radii[i] * s->radii[i]);
      return sqrt(g);
    }
    case CMP_POLYTOPE:
    case CMP_BOX: {
      double g = 0;
      for (size_t i = 0; i < s->m; ++i) g = fmax(g, dot3(&s->A[3 * i], b) / s->b[i]);
      return g;
    }
    case CMP_CYLINDER:
      return fmax(fabs(b[0]) / (0.5 * s->length), hypot(b[1], b[2]) / s->radius);
    case CMP_CONE: {
      double rho = hypot(b[1], b[2]), H = s->height;
      double g = fmax(0.0, 4.0 * b[0] / H);
      return fmax(g, (rho / tan(s->half_angle) - b[0]) / (0.75 * H));
    }
    case CMP_CAPSULE:
    case CMP_POLYGON: {
      if (norm3(b) == 0) return 0;
      double hi = 1;
      while (!inside_scaled(s, b, hi))
        if ((hi *= 2) > 1e300) return INFINITY;
      double lo = hi / 2;
      if (inside_scaled(s, b, lo)) {
        while (lo > 1e-300 && inside_scaled(s, b, lo)) lo /= 2;
        hi = 2 * lo;
      }
      for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        double mid = 0.5 * (lo + hi);
        if (inside_scaled(s, b, mid))
          hi = mid;
        else
          lo = mid;
      }
      return hi;
    }
    default:
      return INFINITY;
  }
}

double cmp_gauge_world(const cmp_body *body, const double y[3]) {
  double e[3], b[3];
  sub3(y, body->pose.position, e);
  mat_t_vec(body->R, e, b);
  return cmp_gauge_body(body->shape, b);
}

double cmp_excess_world(const cmp_body *body, const double y[3]) {
  double e[3];
  sub3(y, body->pose.position, e);
  double g = cmp_gauge_world(body, y);
  if (g <= 1) return 0;
  return norm3(e) * (1 - 1 / g); /* |b - b/g|, and b/g is in the set */
}

/* ---- certificates -------------------------------------------------------------------- */
double cmp_separation_bound(const cmp_body *b1, const cmp_body *b2, const double n_in[3]) {
  double len = norm3(n_in);
  if (!(len > 0)) return -INFINITY;
  double n[3] = {n_in[0] / len, n_in[1] / len, n_in[2] / len}, mn[3] = {-n[0], -n[1], -n[2]};
  double p1[3], p2[3];
  double h1 = cmp_support_world(b1, n, p1);   /* max over S1 of n.y */
  double h2 = -cmp_support_world(b2, mn, p2); /* min over S2 of n.y */
  return h2 - h1;
}

double cmp_alpha_lower_bound(const cmp_body *b1, const cmp_body *b2, const double n[3]) {
  double db[3], pb[3], mn[3] = {-n[0], -n[1], -n[2]};
  mat_t_vec(b1->R, n, db);
  double h1 = cmp_support_body(b1->shape, db, pb);
  mat_t_vec(b2->R, mn, db);
  double h2 = cmp_support_body(b2->shape, db, pb);
  double off[3];
  sub3(b2->pose.position, b1->pose.position, off);
  return dot3(n, off) / (h1 + h2);
}

double cmp_witness_bound(const cmp_body *b1, const cmp_body *b2, const double w1[3],
                         const double w2[3]) {
  double e[3];
  sub3(w2, w1, e);
  return norm3(e) + cmp_excess_world(b1, w1) + cmp_excess_world(b2, w2);
}

/* Support point of the Minkowski difference S2 - S1 minimising dir . z. */
static void diff_support_min(const cmp_body *b1, const cmp_body *b2, const double dir[3],
                             double z[3]) {
  double md[3] = {-dir[0], -dir[1], -dir[2]}, p1[3], p2[3];
  cmp_support_world(b2, md, p2);
  cmp_support_world(b1, dir, p1);
  sub3(p2, p1, z);
}

/* Minimum-norm point of the convex hull of k <= 4 points: every subset's affine minimum-norm
   point (a Gram system of size <= 3) is tried, and the nearest one whose barycentric
   coordinates are all non-negative wins (the brute-force form of Johnson's sub-algorithm). */
static void min_norm_hull(double pts[][3], int k, double lam[], double out[3]) {
  double best = INFINITY;
  memcpy(out, pts[0], 3 * sizeof(double));
  for (int mask = 1; mask < (1 << k); ++mask) {
    int idx[4], n = 0;
    for (int i = 0; i < k; ++i)
      if (mask & (1 << i)) idx[n++] = i;
    /* z = p0 + sum_j mu_j (p_j - p0); minimise |z|: (E^T E) mu = -E^T p0 */
    double E[3][3], G[3][4];
    for (int j = 1; j < n; ++j) sub3(pts[idx[j]], pts[idx[0]], E[j - 1]);
    int m = n - 1, ok = 1;
    for (int a = 0; a < m; ++a) {
      for (int b = 0; b < m; ++b) G[a][b] = dot3(E[a], E[b]);
      G[a][m] = -dot3(E[a], pts[idx[0]]);
    }
    /* Gaussian elimination with partial pivoting */
    for (int c = 0; c < m && ok; ++c) {
      int piv = c;
      for (int r = c + 1; r < m; ++r)
        if (fabs(G[r][c]) > fabs(G[piv][c])) piv = r;
      if (fabs(G[piv][c]) < 1e-14 * (1 + fabs(G[0][0]))) {
        ok = 0;
        break;
      }
      for (int q = 0; q <= m; ++q) {
        double t = G[c][q];
        G[c][q] = G[piv][q];
        G[piv][q] = t;
      }
      for (int r = 0; r < m; ++r) {
        if (r == c) continue;
        double f = G[r][c] / G[c][c];
        for (int q = c; q <= m; ++q) G[r][q] -= f * G[c][q];
      }
    }
    if (!ok) continue;
    double w[4], sum = 0;
    for (int j = 0; j < m; ++j) w[j + 1] = G[j][m] / G[j][j], sum += w[j + 1];
    w[0] = 1 - sum;
    int feasible = 1;
    for (int j = 0; j < n; ++j)
      if (w[j] < -1e-12) feasible = 0;
    if (!feasible) continue;
    double z[3] = {0, 0, 0};
    for (int j = 0; j < n; ++j)
      for (int q = 0; q < 3; ++q) z[q] += w[j] * pts[idx[j]][q];
    double nz = norm3(z);
    if (nz < best) {
      best = nz;
      memcpy(out, z, sizeof z);
      for (int i = 0; i < k; ++i) lam[i] = 0;
      for (int j = 0; j < n; ++j) lam[idx[j]] = fmax(0, w[j]);
    }
  }
}

double cmp_independent_distance(const cmp_body *b1, const cmp_body *b2, double n[3],
                                double *upper, int iterations) {
  /* Frank-Wolfe with a small active set (fully corrective over the last four support points)
     on the Minkowski difference D = S2 - S1: z stays a convex combination of points of D, so
     |z| is an upper bound on the distance; each support point gives the lower bound
     n.z_s with n = z / |z|. Only the support functions of this file are used. */
  double pts[4][3], lam[4];
  int k = 1;
  double z[3];
  diff_support_min(b1, b2, n, pts[0]);
  lam[0] = 1;
  memcpy(z, pts[0], sizeof z);
  double best_lb = cmp_separation_bound(b1, b2, n), best_ub = norm3(z);
  double best_n[3] = {n[0], n[1], n[2]};
  for (int it = 0; it < iterations; ++it) {
    double zn = norm3(z);
    if (!(zn > 0)) break;
    double dir[3] = {z[0] / zn, z[1] / zn, z[2] / zn}, s[3];
    diff_support_min(b1, b2, dir, s);
    double lb = dot3(dir, s);
    if (lb > best_lb) best_lb = lb, memcpy(best_n, dir, sizeof best_n);
    if (zn < best_ub) best_ub = zn;
    if (best_ub - best_lb <= 1e-13 * (1 + best_ub)) break;
    /* add s to the active set (replacing the point of least weight when full) */
    if (k < 4) {
      memcpy(pts[k], s, sizeof s);
      lam[k] = 0;
      k++;
    } else {
      int w = 0;
      for (int i = 1; i < 4; ++i)
        if (lam[i] < lam[w]) w = i;
      memcpy(pts[w], s, sizeof s);
      double rest = 1 - lam[w];
      lam[w] = 0;
      for (int i = 0; i < 4; ++i) lam[i] = rest > 0 ? lam[i] / rest : 0.25;
    }
    double znew[3];
    min_norm_hull(pts, k, lam, znew);
    /* the hull step never increases |z|; guard against round-off anyway with a plain
       Frank-Wolfe line search */
    if (norm3(znew) >= zn) {
      double e[3];
      sub3(s, z, e);
      double ee = dot3(e, e);
      double g = ee > 0 ? fmin(1, fmax(0, -dot3(z, e) / ee)) : 0;
      for (int q = 0; q < 3; ++q) znew[q] = z[q] + g * e[q];
    }
    memcpy(z, znew, sizeof z);
  }
  if (norm3(z) < best_ub) best_ub = norm3(z);
  memcpy(n, best_n, sizeof best_n);
  if (upper) *upper = best_ub;
  return best_lb;
}

/* ---- cases --------------------------------------------------------------------------- */
static double target_alpha(cmp_category cat, cmp_rng *rng) {
  switch (cat) {
    case CMP_SEPARATED:
      return 1 + pow(10, cmp_rng_uniform(rng, -2, 0.3));
    case CMP_NEAR: {
      double e = pow(10, cmp_rng_uniform(rng, -7, -2));
      return cmp_rng_uniform(rng, 0, 1) < 0.5 ? 1 - e : 1 + e;
    }
    default:
      return cmp_rng_uniform(rng, 0.1, 0.98);
  }
}

/* One of the 24 rotations of the cube, uniformly: faces, edges and axes of the two shapes then
   line up (face-face, edge-parallel and rim-face contacts, the degenerate ones). */
static void aligned_quaternion(cmp_rng *rng, double q[4]) {
  int k = cmp_rng_int(rng, 0, 23);
  q[0] = q[1] = q[2] = q[3] = 0;
  if (k < 4) {
    q[k] = 1;
  } else if (k < 12) {
    int signs = k - 4;
    q[0] = 0.5;
    for (int i = 0; i < 3; ++i) q[i + 1] = (signs >> i) & 1 ? -0.5 : 0.5;
  } else {
    static const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    int p = (k - 12) / 2;
    q[pairs[p][0]] = sqrt(0.5);
    q[pairs[p][1]] = (k - 12) % 2 ? -sqrt(0.5) : sqrt(0.5);
  }
}

int cmp_case_make(cmp_case *c, cmp_kind k1, cmp_kind k2, int index, cmp_rng *rng) {
  memset(c, 0, sizeof *c);
  if (cmp_shape_random(&c->s1, k1, rng) != 0 || cmp_shape_random(&c->s2, k2, rng) != 0) {
    cmp_case_release(c);
    return -1;
  }
  c->scale = fmax(c->s1.bound_radius, c->s2.bound_radius);
  c->category = (cmp_category)(index % 3);
  double r1[3], q1[4], q2[4], dir[3];
  for (int i = 0; i < 3; ++i) r1[i] = cmp_rng_uniform(rng, -3, 3);
  c->aligned = (index / 3) % 4 == 3;
  if (c->aligned) {
    aligned_quaternion(rng, q1);
    aligned_quaternion(rng, q2);
  } else {
    cmp_rng_quaternion(rng, q1);
    cmp_rng_quaternion(rng, q2);
  }
  cmp_rng_unit_vector(rng, dir);
  double len = cmp_rng_uniform(rng, 1, 4);
  double r2[3] = {r1[0] + len * dir[0], r1[1] + len * dir[1], r1[2] + len * dir[2]};
  cmp_body_set(&c->b1, &c->s1, r1, q1);
  cmp_body_set(&c->b2, &c->s2, r2, q2);
  dcol_proximity_result p0;
  dcol_status st = dcol_proximity(c->s1.handle, &c->b1.pose, c->s2.handle, &c->b2.pose, NULL, &p0);
  if (report_dcol("dcol_proximity (initial)", st) || !(p0.alpha > 0)) {
    cmp_case_release(c);
    return -1;
  }
  /* alpha* is homogeneous of degree one in r2 - r1 (attitudes fixed) */
  c->alpha_target = target_alpha(c->category, rng);
  double f = c->alpha_target / p0.alpha;
  for (int i = 0; i < 3; ++i) r2[i] = r1[i] + f * len * dir[i];
  cmp_body_set(&c->b2, &c->s2, r2, q2);
  c->prox_status =
      dcol_proximity(c->s1.handle, &c->b1.pose, c->s2.handle, &c->b2.pose, NULL, &c->prox);
  c->dist_status =
      dcol_distance(c->s1.handle, &c->b1.pose, c->s2.handle, &c->b2.pose, NULL, &c->dist);
  if (c->prox_status != DCOL_OK || c->dist_status != DCOL_OK) {
    fprintf(stderr, "dcol failed on %s-%s case %d: proximity %s, distance %s (%s)\n",
            cmp_kind_name(k1), cmp_kind_name(k2), index, dcol_status_string(c->prox_status),
            dcol_status_string(c->dist_status), dcol_last_error_message());
    cmp_case_print(stderr, c);
    return 1; /* kept: counted as a dcol failure by the caller */
  }
  return 0;
}

void cmp_case_release(cmp_case *c) {
  cmp_shape_release(&c->s1);
  cmp_shape_release(&c->s2);
}

void cmp_shape_describe(FILE *out, const cmp_shape *s) {
  fprintf(out, "    %s:", cmp_kind_name(s->kind));
  switch (s->kind) {
    case CMP_SPHERE:
      fprintf(out, " radius %.17g\n", s->radius);
      break;
    case CMP_ELLIPSOID:
      fprintf(out, " radii %.17g %.17g %.17g (P = diag(1/radii^2))\n", s->radii[0], s->radii[1],
              s->radii[2]);
      break;
    case CMP_BOX:
      fprintf(out, " half extents %.17g %.17g %.17g\n", s->half[0], s->half[1], s->half[2]);
      break;
    case CMP_POLYTOPE:
      fprintf(out, " m %zu, rows a_i b_i:", s->m);
      for (size_t i = 0; i < s->m; ++i)
        fprintf(out, " [%.17g %.17g %.17g | %.17g]", s->A[3 * i], s->A[3 * i + 1], s->A[3 * i + 2],
                s->b[i]);
      fprintf(out, "\n");
      break;
    case CMP_CAPSULE:
    case CMP_CYLINDER:
      fprintf(out, " radius %.17g length %.17g\n", s->radius, s->length);
      break;
    case CMP_CONE:
      fprintf(out, " height %.17g half_angle %.17g\n", s->height, s->half_angle);
      break;
    case CMP_POLYGON:
      fprintf(out, " radius %.17g, m %zu, rows c_i d_i:", s->radius, s->pm);
      for (size_t i = 0; i < s->pm; ++i)
        fprintf(out, " [%.17g %.17g | %.17g]", s->C[2 * i], s->C[2 * i + 1], s->d[i]);
      fprintf(out, "\n");
      break;
    default:
      fprintf(out, "\n");
  }
}

void cmp_case_print(FILE *out, const cmp_case *c) {
  cmp_shape_describe(out, &c->s1);
  cmp_shape_describe(out, &c->s2);
  const dcol_pose *p1 = &c->b1.pose, *p2 = &c->b2.pose;
  fprintf(out, "    pose1 r=(%.17g, %.17g, %.17g) q=(%.17g, %.17g, %.17g, %.17g)\n",
          p1->position[0], p1->position[1], p1->position[2], p1->quaternion[0],
          p1->quaternion[1], p1->quaternion[2], p1->quaternion[3]);
  fprintf(out, "    pose2 r=(%.17g, %.17g, %.17g) q=(%.17g, %.17g, %.17g, %.17g)\n",
          p2->position[0], p2->position[1], p2->position[2], p2->quaternion[0],
          p2->quaternion[1], p2->quaternion[2], p2->quaternion[3]);
}


int cmp_check_dcol_self(const cmp_case *c, double band, int *witness_bad) {
  int bad = 0;
  double l = c->scale, e[3];
  sub3(c->prox.contact2, c->prox.contact1, e);
  double pd = norm3(e);
  if (pd < c->dist.distance - 1e-9 * l) {
    fprintf(stderr, "  (c) %s-%s: |p1 - p2| = %.17g below distance %.17g (alpha %.17g)\n",
            cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), pd, c->dist.distance,
            c->prox.alpha);
    cmp_case_print(stderr, c);
    bad++;
  }
  double a = c->prox.alpha;
  if ((a > 1 + band && !(c->dist.distance > 0)) || (a < 1 - band && c->dist.distance > 1e-9 * l)) {
    fprintf(stderr, "  (c) %s-%s: alpha %.17g but distance %.17g\n", cmp_kind_name(c->s1.kind),
            cmp_kind_name(c->s2.kind), a, c->dist.distance);
    cmp_case_print(stderr, c);
    bad++;
  }
  /* alpha* itself, bracketed independently: x* must lie in both shapes scaled by alpha*
     (gauges), and no direction may prove a larger alpha* (the distance normal, for separated
     shapes, gives the lower bound n.(r2 - r1) / (h1(n) + h2(-n)) <= alpha*). */
  double g = fmax(cmp_gauge_world(&c->b1, c->prox.point), cmp_gauge_world(&c->b2, c->prox.point));
  if (g > a * (1 + 1e-6) + 1e-12) {
    fprintf(stderr, "  (c) %s-%s: x* is not in the shapes scaled by alpha* = %.17g (gauge %.17g)\n",
            cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), a, g);
    cmp_case_print(stderr, c);
    bad++;
  } else if (g < a * (1 - 1e-6)) {
    /* x* is in both shapes scaled by g < alpha*: alpha* is not the minimum */
    fprintf(stderr, "  (c) %s-%s: alpha* = %.17g is not minimal: x* is in both shapes scaled by "
            "%.17g\n", cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), a, g);
    cmp_case_print(stderr, c);
    bad++;
  }
  /* the distance's witness points lie in their shapes, |c2 - c1| = distance */
  double x1 = cmp_excess_world(&c->b1, c->dist.closest1);
  double x2 = cmp_excess_world(&c->b2, c->dist.closest2);
  double cd[3];
  sub3(c->dist.closest2, c->dist.closest1, cd);
  *witness_bad = 0;
  if (x1 > 1e-6 * l || x2 > 1e-6 * l || fabs(norm3(cd) - c->dist.distance) > 1e-6 * l) {
    fprintf(stderr, "  (w) %s-%s: distance %.17g with witness points off their shapes by %.3g "
            "and %.3g, |c2 - c1| = %.17g: c1 = (%.17g, %.17g, %.17g), c2 = (%.17g, %.17g, %.17g)\n",
            cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), c->dist.distance, x1, x2,
            norm3(cd), c->dist.closest1[0], c->dist.closest1[1], c->dist.closest1[2],
            c->dist.closest2[0], c->dist.closest2[1], c->dist.closest2[2]);
    cmp_case_print(stderr, c);
    (*witness_bad)++;
  }
  if (c->dist.distance > 0) {
    double lb = cmp_alpha_lower_bound(&c->b1, &c->b2, c->dist.normal);
    if (lb > a * (1 + 1e-6)) {
      fprintf(stderr, "  (c) %s-%s: alpha* = %.17g below the lower bound %.17g from a direction\n",
              cmp_kind_name(c->s1.kind), cmp_kind_name(c->s2.kind), a, lb);
      cmp_case_print(stderr, c);
      bad++;
    }
  }
  return bad;
}

int cmp_certify_overlap(const cmp_case *c, double *gauge_max) {
  double g = fmax(cmp_gauge_world(&c->b1, c->prox.point), cmp_gauge_world(&c->b2, c->prox.point));
  if (gauge_max) *gauge_max = g;
  return g <= 1;
}

int cmp_certify_separation(const cmp_case *c, const double *extra_dir, double *bound) {
  double cands[4][3];
  int k = 0;
  memcpy(cands[k++], c->dist.normal, sizeof cands[0]);
  sub3(c->prox.contact2, c->prox.contact1, cands[k++]);
  sub3(c->dist.closest2, c->dist.closest1, cands[k++]);
  if (extra_dir) memcpy(cands[k++], extra_dir, sizeof cands[0]);
  double best = -INFINITY, best_n[3] = {1, 0, 0};
  for (int i = 0; i < k; ++i) {
    double v = cmp_separation_bound(&c->b1, &c->b2, cands[i]);
    if (v > best) best = v, memcpy(best_n, cands[i], sizeof best_n);
  }
  if (!(best > 0)) {
    double up;
    double v = cmp_independent_distance(&c->b1, &c->b2, best_n, &up, 2000);
    if (v > best) best = v;
  }
  if (bound) *bound = best;
  return best > 0;
}
