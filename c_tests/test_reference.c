/* The C ABI against the reference cases: the first few cases of every pair file and of the
 * stress file, with the tolerances of the shared reference README, on the repository's own set
 * (tests/data, always) and on ../shared/reference as a cross-check when it is present.
 *
 * Usage: test_reference DATA_DIR [CASES_PER_FILE [SHARED_DIR]]
 * A missing DATA_DIR fails the test, unless the environment variable DCOL_ALLOW_SKIP=1 asks for
 * a skip (exit 77). A missing SHARED_DIR is noted and not checked, unless CI is set, in which
 * case its absence is a failure. */
#include "dcol.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"

#define SKIP_CODE 77

/* ---- A minimal reader for the reference records (one JSON object per line). ------------- */

/* Returns the start of the value of `key` among the members of the object that starts at
 * `obj` (which points at '{'), or NULL. Only direct members are considered. */
static const char *member(const char *obj, const char *key) {
  size_t klen = strlen(key);
  int depth = 0;
  const char *p = obj;
  for (; *p; p++) {
    char ch = *p;
    if (ch == '"') {
      const char *start = p + 1;
      p++;
      while (*p && *p != '"') {
        if (*p == '\\' && p[1]) p++;
        p++;
      }
      if (!*p) return NULL;
      if (depth == 1 && (size_t)(p - start) == klen && strncmp(start, key, klen) == 0) {
        const char *v = p + 1;
        while (*v == ' ' || *v == ':') v++;
        return v;
      }
    } else if (ch == '{' || ch == '[') {
      depth++;
    } else if (ch == '}' || ch == ']') {
      depth--;
      if (depth == 0) return NULL;
    }
  }
  return NULL;
}

/* Reads the numbers of the value at `v` (a number or nested arrays of numbers), flattened.
 * Returns how many, or -1 on `null` or a malformed value. */
static int numbers(const char *v, double *out, int max) {
  int n = 0, depth = 0;
  if (v == NULL || strncmp(v, "null", 4) == 0) return -1;
  do {
    if (*v == '[') {
      depth++;
      v++;
    } else if (*v == ']') {
      depth--;
      v++;
    } else if (*v == ',' || *v == ' ') {
      v++;
    } else {
      char *end;
      double x = strtod(v, &end);
      if (end == v || n >= max) return -1;
      out[n++] = x;
      v = end;
    }
  } while (depth > 0);
  return n;
}

static double number(const char *obj, const char *key) {
  double x = NAN;
  if (numbers(member(obj, key), &x, 1) != 1) return NAN;
  return x;
}

static int is_true(const char *obj, const char *key) {
  const char *v = member(obj, key);
  return v != NULL && strncmp(v, "true", 4) == 0;
}

static int string_is(const char *obj, const char *key, const char *want) {
  const char *v = member(obj, key);
  size_t n = strlen(want);
  return v != NULL && v[0] == '"' && strncmp(v + 1, want, n) == 0 && v[1 + n] == '"';
}

/* Builds the shape described by the object at `obj` through the C constructors. */
static dcol_status make_shape(const char *obj, dcol_shape **out) {
  static double a[3 * 300], b[300];
  int n, m;
  *out = NULL;
  if (string_is(obj, "kind", "sphere")) return dcol_shape_new_sphere(number(obj, "R"), out);
  if (string_is(obj, "kind", "capsule"))
    return dcol_shape_new_capsule(number(obj, "R"), number(obj, "L"), out);
  if (string_is(obj, "kind", "cylinder"))
    return dcol_shape_new_cylinder(number(obj, "R"), number(obj, "L"), out);
  if (string_is(obj, "kind", "cone"))
    return dcol_shape_new_cone(number(obj, "H"), number(obj, "beta"), out);
  if (string_is(obj, "kind", "ellipsoid")) {
    if (numbers(member(obj, "P"), a, 9) != 9) return DCOL_ERROR_INTERNAL;
    return dcol_shape_new_ellipsoid(a, out);
  }
  if (string_is(obj, "kind", "polytope")) {
    n = numbers(member(obj, "A"), a, 3 * 300);
    m = numbers(member(obj, "b"), b, 300);
    if (n < 0 || m < 0 || n != 3 * m) return DCOL_ERROR_INTERNAL;
    return dcol_shape_new_polytope(a, b, (size_t)m, out);
  }
  if (string_is(obj, "kind", "padded_polygon")) {
    n = numbers(member(obj, "C"), a, 2 * 300);
    m = numbers(member(obj, "d"), b, 300);
    if (n < 0 || m < 0 || n != 2 * m) return DCOL_ERROR_INTERNAL;
    return dcol_shape_new_polygon(a, b, (size_t)m, number(obj, "R"), out);
  }
  return DCOL_ERROR_INTERNAL;
}

static int make_pose(const char *obj, dcol_pose *p) {
  return numbers(member(obj, "r"), p->position, 3) == 3 &&
         numbers(member(obj, "q"), p->quaternion, 4) == 4;
}

static double dist3(const double *a, const double *b) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
              (a[2] - b[2]) * (a[2] - b[2]));
}

/* Reads one line of any length into *buf (grown as needed). Returns 0 at end of file. */
static int read_line(FILE *f, char **buf, size_t *cap) {
  size_t len = 0;
  if (*buf == NULL) {
    *cap = 1 << 16;
    *buf = (char *)malloc(*cap);
    if (*buf == NULL) return 0;
  }
  for (;;) {
    if (fgets(*buf + len, (int)(*cap - len), f) == NULL) return len > 0;
    len += strlen(*buf + len);
    if (len > 0 && (*buf)[len - 1] == '\n') return 1;
    if (*cap - len < 2) {
      char *grown = (char *)realloc(*buf, *cap * 2);
      if (grown == NULL) return 0;
      *buf = grown;
      *cap *= 2;
    }
  }
}

/* ---- The comparison ------------------------------------------------------------------------ */

static int cases_checked = 0, gradients_checked = 0, distances_checked = 0;

static void check_case(const char *line) {
  const char *id = member(line, "id");
  const char *o1 = member(line, "shape1"), *o2 = member(line, "shape2");
  const char *notes = member(line, "solver_notes");
  dcol_shape *s1 = NULL, *s2 = NULL;
  dcol_pose p1, p2;
  dcol_proximity_result r;
  dcol_distance_result dr;
  double alpha_ref = number(line, "alpha");
  double ell = notes ? number(notes, "length_scale") : NAN;
  double ref[56], g[14];
  int coincident = string_is(line, "category", "coincident");
  int k;
  char name[64];
  dcol_status st;

  name[0] = '\0';
  if (id) sscanf(id, "\"%63[^\"]", name);
  CHECK_MSG(o1 && o2 && isfinite(alpha_ref) && isfinite(ell), "%s: unreadable record", name);
  if (!(o1 && o2 && isfinite(alpha_ref) && isfinite(ell))) return;
  CHECK_MSG(make_shape(o1, &s1) == DCOL_OK, "%s: shape1: %s", name, dcol_last_error_message());
  CHECK_MSG(make_shape(o2, &s2) == DCOL_OK, "%s: shape2: %s", name, dcol_last_error_message());
  CHECK_MSG(make_pose(member(line, "pose1"), &p1) && make_pose(member(line, "pose2"), &p2),
            "%s: unreadable pose", name);
  if (s1 == NULL || s2 == NULL) goto done;

  st = dcol_proximity(s1, &p1, s2, &p2, NULL, &r);
  CHECK_MSG(st == DCOL_OK, "%s: %s", name, dcol_last_error_message());
  if (st != DCOL_OK) goto done;
  cases_checked++;
  {
    double err = coincident ? fabs(r.alpha - alpha_ref)
                            : fabs(r.alpha - alpha_ref) / (alpha_ref > 1.0 ? alpha_ref : 1.0);
    CHECK_MSG(err <= 1e-8, "%s: alpha %.17g, reference %.17g", name, r.alpha, alpha_ref);
  }
  if (is_true(line, "x_unique") && numbers(member(line, "x"), ref, 3) == 3) {
    CHECK_MSG(dist3(r.point, ref) <= 1e-5 * ell, "%s: x off by %g l", name,
              dist3(r.point, ref) / ell);
    if (!coincident && numbers(member(line, "p1"), ref, 3) == 3) {
      double tol = 1e-5 * ell / (alpha_ref < 1.0 ? alpha_ref : 1.0);
      CHECK_MSG(dist3(r.contact1, ref) <= tol, "%s: p1 off by %g", name, dist3(r.contact1, ref));
      if (numbers(member(line, "p2"), ref, 3) == 3)
        CHECK_MSG(dist3(r.contact2, ref) <= tol, "%s: p2 off by %g", name,
                  dist3(r.contact2, ref));
    }
  }

  /* d alpha / d(r1, q1, r2, q2), in non-dimensional units (r columns times l); null entries of
   * the reference are skipped. Only once the core implements it. */
  st = dcol_gradient(s1, &p1, s2, &p2, NULL, &r, g);
  if (!(st == DCOL_ERROR_INTERNAL && strstr(dcol_last_error_message(), "not yet built"))) {
    const char *v = member(line, "dalpha_dconfig");
    CHECK_MSG(st == DCOL_OK, "%s: gradient: %s", name, dcol_last_error_message());
    if (st == DCOL_OK && v != NULL && strncmp(v, "null", 4) != 0) {
      /* Read entry by entry: some may be null. */
      const char *p = v + 1;
      gradients_checked++;
      for (k = 0; k < 14 && p; k++) {
        while (*p == ' ' || *p == ',') p++;
        if (strncmp(p, "null", 4) != 0) {
          double want = strtod(p, NULL);
          double scale = (k < 3 || (k >= 7 && k < 10)) ? ell : 1.0;
          double tol = 1e-5 * (fabs(want * scale) > 1.0 ? fabs(want * scale) : 1.0);
          CHECK_MSG(fabs((g[k] - want) * scale) <= tol, "%s: dalpha[%d] %.12g, reference %.12g",
                    name, k, g[k], want);
        }
        p = strchr(p, k < 13 ? ',' : ']');
      }
    }
  }

  st = dcol_distance(s1, &p1, s2, &p2, NULL, &dr);
  if (!(st == DCOL_ERROR_INTERNAL && strstr(dcol_last_error_message(), "not yet built"))) {
    double d_ref = number(line, "distance");
    CHECK_MSG(st == DCOL_OK, "%s: distance: %s", name, dcol_last_error_message());
    if (st == DCOL_OK && isfinite(d_ref)) {
      distances_checked++;
      CHECK_MSG(fabs(dr.distance - d_ref) <= 1e-6 * ell, "%s: distance %.12g, reference %.12g",
                name, dr.distance, d_ref);
    }
  }

done:
  dcol_shape_free(s1);
  dcol_shape_free(s2);
}

/* Checks the first `per_file` cases of each of the 50 files in `dir`; returns the number of
 * files found, or -1 when the folder has no stress file. */
static int check_dir(const char *dir, int per_file) {
  static const char *kinds[7] = {"capsule",  "cone",     "cylinder", "ellipsoid",
                                 "padded_polygon", "polytope", "sphere"};
  char path[4096];
  char *line = NULL;
  size_t cap = 0;
  int i, files = 0;
  FILE *f;

  sprintf(path, "%.4000s/cases-stress.jsonl", dir);
  f = fopen(path, "r");
  if (f == NULL) return -1;
  fclose(f);
  for (i = 0; i <= 7 * 7; i++) {
    int n = 0;
    if (i < 49)
      sprintf(path, "%.4000s/cases-%s-%s.jsonl", dir, kinds[i / 7], kinds[i % 7]);
    else
      sprintf(path, "%.4000s/cases-stress.jsonl", dir);
    f = fopen(path, "r");
    CHECK_MSG(f != NULL, "cannot open %s", path);
    if (f == NULL) continue;
    files++;
    while (n < per_file && read_line(f, &line, &cap)) {
      if (line[0] != '{') continue;
      check_case(line);
      n++;
    }
    fclose(f);
  }
  free(line);
  return files;
}

int main(int argc, char **argv) {
  int per_file = argc > 2 ? atoi(argv[2]) : 3;
  int files, before;
  const char *allow = getenv("DCOL_ALLOW_SKIP");

  if (argc < 2) {
    fprintf(stderr, "usage: %s DATA_DIR [CASES_PER_FILE [SHARED_DIR]]\n", argv[0]);
    return 2;
  }
  files = check_dir(argv[1], per_file);
  if (files < 0) {
    if (allow != NULL && strcmp(allow, "1") == 0) {
      printf("SKIPPED (DCOL_ALLOW_SKIP=1): %s has no reference cases\n", argv[1]);
      return SKIP_CODE;
    }
    fprintf(stderr, "FAILED: %s has no reference cases (set DCOL_ALLOW_SKIP=1 to skip)\n",
            argv[1]);
    return 1;
  }
  printf("own set: %d files, %d cases, %d gradients, %d distances compared\n", files,
         cases_checked, gradients_checked, distances_checked);
  CHECK(files == 50);
  CHECK(cases_checked >= 50 * (per_file < 1 ? 1 : per_file) - 5);

  if (argc > 3) {
    before = cases_checked;
    files = check_dir(argv[3], per_file);
    if (files < 0) {
      if (getenv("CI") != NULL) {
        fprintf(stderr, "FAILED: %s is missing, and CI always has the shared reference\n",
                argv[3]);
        return 1;
      }
      printf("(%s is not here: the cross-check against it did not run)\n", argv[3]);
    } else {
      printf("shared set: %d files, %d cases compared\n", files, cases_checked - before);
      CHECK(files == 50);
    }
  }
  return check_summary("test_reference");
}
