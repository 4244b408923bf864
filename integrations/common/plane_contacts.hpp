// A primitive against an engine's plane in closed form, for the ODE and Bullet adapters (not
// installed): the contacts straight from the solid's support map, without a dcol query. The
// engine's plane is the half-space n.x <= d (n its unit normal, pointing out of it, towards the
// solid); a point q of the solid is `depth = d - n.q` below the plane, and its contact is written midway
// between q and its projection onto the plane, q + n depth/2 (dcol's convention). With a margin
// m >= 0 (0: touching only), a pair has contacts when its deepest point is at depth >= -m; the
// points of the feature facing the plane that lie within m + 1e-9 max(bounding radius, 1) of it
// are its contacts (dcol's tolerance), and the deepest point is always one of them:
//   - sphere: its lowest point;
//   - box: the corners of the face whose normal is best aligned with -n (it holds the lowest
//     corner);
//   - capsule: the lower end ball's lowest point, and the other end of the surface line below
//     the axis (the line's two ends when level);
//   - cylinder: a cap within about 25 degrees of facing the plane (|axis.n| >= 0.9, dcol's
//     threshold): the regular 12-gon on its rim with a vertex at the rim's lowest point; else each
//     rim's lowest point;
//   - cone (apex at -3H/4 along the axis, base of radius r at +H/4): its base as the
//     cylinder's cap when within about 25 degrees; else the base rim's lowest point and the apex.
// More points than asked: the deepest, the one farthest from it, the one spanning the largest
// triangle with those two, then each time the one farthest from those chosen (dcol's choice).
// A non-finite input, or a written point or depth that is not finite (a frame that is not
// orthonormal), reports -1 with no points (the caller counts the pair as rejected).
#ifndef DCOL_PLANE_CONTACTS_HPP
#define DCOL_PLANE_CONTACTS_HPP

#include <algorithm>
#include <cmath>

namespace dcol_plane {

/// The most points a solid's feature facing the plane has (a disc's 12-gon).
const int kMaxPoints = 12;

/// The plane: unit normal `n` out of the solid region, offset `d` (the plane is n.x = d).
struct Plane {
  double n[3];
  double d;
};

/// A solid's pose: centre `c` and the world directions of its body axes (`axis[k]`, unit, orthogonal).
struct Frame {
  double c[3];
  double axis[3][3];
};

/// Contacts against the plane: `pos` midway between the solid's point and the plane, `depth`
/// below the plane (> 0 penetrating).
struct Points {
  double pos[kMaxPoints][3];
  double depth[kMaxPoints];
  int count = 0;
};

namespace detail {

inline double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Adds the solid's point q when within `tol` of the plane.
inline void push(const Plane &p, const double q[3], double tol, Points &out) {
  const double depth = p.d - dot(p.n, q);
  if (depth >= -tol && out.count < kMaxPoints) {
    for (int k = 0; k < 3; ++k) out.pos[out.count][k] = q[k] + 0.5 * depth * p.n[k];
    out.depth[out.count] = depth;
    ++out.count;
  }
}

/// How far above the plane a point may be and count: the margin and 1e-9 max(bounding radius, 1).
inline double tolerance(double bounding_radius, double margin) { return margin + 1e-9 * std::max(bounding_radius, 1.0); }

/// The solid's answer once its points are written: 1 with contacts, 0 without, -1 (and no
/// points) when a written position or depth is not finite (a frame that is not orthonormal,
/// e.g. one entry of it infinite, can make a depth finite and a point not).
inline int finish(Points &out) {
  for (int i = 0; i < out.count; ++i) {
    const double *q = out.pos[i];
    if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) && std::isfinite(out.depth[i]))) {
      out.count = 0;
      return -1;
    }
  }
  return out.count > 0 ? 1 : 0;
}

/// 1: the lowest point's depth is >= -margin (touching, or within the margin); 0: apart; -1: not finite.
inline int touching(double deepest, double margin) {
  if (!std::isfinite(deepest)) return -1;
  return deepest >= -margin ? 1 : 0;
}

/// The unit direction along which a disc (unit normal `axis`) goes lowest: -(n - (n.axis) axis),
/// made orthogonal to the axis again after the rounding; `fallback` (a unit vector orthogonal to
/// the axis) when the disc is level. False when level.
inline bool low_direction(const Plane &p, const double axis[3], const double fallback[3], double u[3]) {
  const double a = dot(p.n, axis);
  for (int k = 0; k < 3; ++k) u[k] = a * axis[k] - p.n[k];
  const double b = dot(u, axis);
  for (int k = 0; k < 3; ++k) u[k] -= b * axis[k];
  const double len = std::sqrt(dot(u, u));
  if (!(len > 1e-12)) {
    for (int k = 0; k < 3; ++k) u[k] = fallback[k];
    return false;
  }
  for (int k = 0; k < 3; ++k) u[k] /= len;
  return true;
}

/// A disc (centre `c`, unit normal `axis`, `radius`) facing the plane: the regular 12-gon on its
/// rim with a vertex at the rim's lowest point (`fallback`'s when the disc is level).
inline void disc(const Plane &p, const double c[3], const double axis[3], const double fallback[3], double radius,
                 double tol, Points &out) {
  double u[3];
  low_direction(p, axis, fallback, u);
  const double v[3] = {axis[1] * u[2] - axis[2] * u[1], axis[2] * u[0] - axis[0] * u[2], axis[0] * u[1] - axis[1] * u[0]};
  // cos and sin of 30 i degrees (sqrt(3)/2 rounded to the nearest double).
  const double h = 0.8660254037844386;
  const double cs[12] = {1, h, 0.5, 0, -0.5, -h, -1, -h, -0.5, 0, 0.5, h};
  const double sn[12] = {0, 0.5, h, 1, h, 0.5, 0, -0.5, -h, -1, -h, -0.5};
  for (int i = 0; i < 12; ++i) {
    double q[3];
    for (int k = 0; k < 3; ++k) q[k] = c[k] + radius * (cs[i] * u[k] + sn[i] * v[k]);
    detail::push(p, q, tol, out);
  }
}

/// A disc's lowest rim point (centre `c`, unit normal `axis`; its centre when level).
inline void rim_low(const Plane &p, const double c[3], const double axis[3], double radius, double q[3]) {
  double u[3];
  const double zero[3] = {0, 0, 0};
  low_direction(p, axis, zero, u);
  for (int k = 0; k < 3; ++k) q[k] = c[k] + radius * u[k];
}

}  // namespace detail

/// A sphere of `radius`: 1 when it touches, 0 when apart, -1 when a number is not finite.
inline int sphere(const Plane &p, const double c[3], double radius, Points &out, double margin = 0) {
  out.count = 0;
  const double h = detail::dot(p.n, c) - p.d;
  const int t = detail::touching(radius - h, margin);
  if (t <= 0) return t;
  double q[3];
  for (int k = 0; k < 3; ++k) q[k] = c[k] - radius * p.n[k];
  detail::push(p, q, detail::tolerance(radius, margin), out);
  return detail::finish(out);
}

/// A box of half extents `half` (along the frame's axes).
inline int box(const Plane &p, const Frame &f, const double half[3], Points &out, double margin = 0) {
  out.count = 0;
  double a[3], s[3];
  double deepest = p.d - detail::dot(p.n, f.c);
  int best = 0;
  for (int k = 0; k < 3; ++k) {
    a[k] = detail::dot(p.n, f.axis[k]);
    s[k] = a[k] > 0 ? -1.0 : 1.0;  // the lowest corner's side along axis k
    deepest += half[k] * std::fabs(a[k]);
    if (std::fabs(a[k]) >= std::fabs(a[best])) best = k;  // the last on a tie
  }
  const int t = detail::touching(deepest, margin);
  if (t <= 0) return t;
  const double tol = detail::tolerance(std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]), margin);
  // The face best aligned with -n: its corners in a loop (the lowest corner first).
  const int i = (best + 1) % 3, j = (best + 2) % 3;
  const double signs[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
  for (int m = 0; m < 4; ++m) {
    double q[3];
    for (int k = 0; k < 3; ++k)
      q[k] = f.c[k] + s[best] * half[best] * f.axis[best][k] + signs[m][0] * s[i] * half[i] * f.axis[i][k] +
             signs[m][1] * s[j] * half[j] * f.axis[j][k];
    detail::push(p, q, tol, out);
  }
  return detail::finish(out);
}

/// A capsule of `radius` around the segment of `length` along the frame's axis `along`.
inline int capsule(const Plane &p, const Frame &f, int along, double radius, double length, Points &out,
                   double margin = 0) {
  out.count = 0;
  const double *e = f.axis[along];
  const double a = detail::dot(p.n, e);
  const int t = detail::touching(p.d - detail::dot(p.n, f.c) + 0.5 * length * std::fabs(a) + radius, margin);
  if (t <= 0) return t;
  const double tol = detail::tolerance(radius + 0.5 * length, margin);
  // The lower end ball's lowest point (the deepest), and the other end of the surface line
  // below the axis (the same point when level; none when upright).
  const double low = a > 0 ? -1.0 : 1.0;
  double q[3];
  for (int k = 0; k < 3; ++k) q[k] = f.c[k] + low * 0.5 * length * e[k] - radius * p.n[k];
  detail::push(p, q, tol, out);
  double w[3];
  const double zero[3] = {0, 0, 0};
  if (detail::low_direction(p, e, zero, w)) {
    for (int k = 0; k < 3; ++k) q[k] = f.c[k] - low * 0.5 * length * e[k] + radius * w[k];
    detail::push(p, q, tol, out);
  }
  return detail::finish(out);
}

/// A cylinder of `radius` and `length` along the frame's axis `along` (caps at +-length/2).
inline int cylinder(const Plane &p, const Frame &f, int along, double radius, double length, Points &out,
                    double margin = 0) {
  out.count = 0;
  const double *e = f.axis[along];
  const double a = detail::dot(p.n, e);
  const double lateral = std::sqrt(std::max(0.0, 1.0 - a * a));
  const int t = detail::touching(p.d - detail::dot(p.n, f.c) + 0.5 * length * std::fabs(a) + radius * lateral, margin);
  if (t <= 0) return t;
  const double tol = detail::tolerance(std::sqrt(radius * radius + 0.25 * length * length), margin);
  const double low = a > 0 ? -1.0 : 1.0;  // the lower cap's side
  double c0[3], c1[3];
  for (int k = 0; k < 3; ++k) {
    c0[k] = f.c[k] + low * 0.5 * length * e[k];
    c1[k] = f.c[k] - low * 0.5 * length * e[k];
  }
  if (std::fabs(a) >= 0.9) {
    detail::disc(p, c0, e, f.axis[(along + 1) % 3], radius, tol, out);
  } else {
    double q[3];
    detail::rim_low(p, c0, e, radius, q);
    detail::push(p, q, tol, out);
    detail::rim_low(p, c1, e, radius, q);
    detail::push(p, q, tol, out);
  }
  return detail::finish(out);
}

/// A cone of `height` and base `radius` along the frame's axis `along` (apex at -3H/4, base at
/// +H/4: dcol's cone of half angle atan(radius/height)).
inline int cone(const Plane &p, const Frame &f, int along, double height, double radius, Points &out,
                double margin = 0) {
  out.count = 0;
  const double *e = f.axis[along];
  const double a = detail::dot(p.n, e);
  const double h = detail::dot(p.n, f.c) - p.d;
  double apex[3], base[3];
  for (int k = 0; k < 3; ++k) {
    apex[k] = f.c[k] - 0.75 * height * e[k];
    base[k] = f.c[k] + 0.25 * height * e[k];
  }
  double rim[3];
  detail::rim_low(p, base, e, radius, rim);
  const double apex_depth = -h + 0.75 * height * a;
  const double rim_depth = p.d - detail::dot(p.n, rim);
  const int t = detail::touching(std::max(apex_depth, rim_depth), margin);
  if (t <= 0) return t;
  const double tol = detail::tolerance(std::max(0.75 * height, std::sqrt(radius * radius + height * height / 16)), margin);
  if (a <= -0.9) {
    detail::disc(p, base, e, f.axis[(along + 1) % 3], radius, tol, out);  // the base faces the plane
  } else {
    detail::push(p, rim, tol, out);
    detail::push(p, apex, tol, out);
  }
  return detail::finish(out);
}

/// Keeps at most `cap` (>= 1) of the points, dcol's choice; `order` receives their indices.
inline int reduce(const Points &pts, int cap, int order[kMaxPoints]) {
  const int n = pts.count;
  if (n <= cap) {
    for (int i = 0; i < n; ++i) order[i] = i;
    return n;
  }
  bool used[kMaxPoints] = {};
  double near[kMaxPoints];  // squared distances to the nearest chosen point (sqrt is monotone)
  auto dist = [&](int i, int j) {
    const double dx = pts.pos[i][0] - pts.pos[j][0], dy = pts.pos[i][1] - pts.pos[j][1], dz = pts.pos[i][2] - pts.pos[j][2];
    return dx * dx + dy * dy + dz * dz;
  };
  int first = 0;
  for (int i = 1; i < n; ++i)
    if (pts.depth[i] > pts.depth[first]) first = i;
  order[0] = first;
  used[first] = true;
  for (int i = 0; i < n; ++i) near[i] = dist(i, first);
  int k = 1;
  while (k < cap) {
    int best = -1;
    double score = 0;
    for (int i = 0; i < n; ++i) {
      if (used[i]) continue;
      double s = near[i];
      if (k == 2) {
        const double *p0 = pts.pos[order[0]], *p1 = pts.pos[order[1]], *q = pts.pos[i];
        const double e[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        const double w[3] = {q[0] - p0[0], q[1] - p0[1], q[2] - p0[2]};
        const double x[3] = {e[1] * w[2] - e[2] * w[1], e[2] * w[0] - e[0] * w[2], e[0] * w[1] - e[1] * w[0]};
        s = detail::dot(x, x);
      }
      if (best < 0 || s > score) {
        best = i;
        score = s;
      }
    }
    if (best < 0) break;
    order[k] = best;
    used[best] = true;
    for (int i = 0; i < n; ++i) near[i] = std::min(near[i], dist(i, best));
    ++k;
  }
  return k;
}

}  // namespace dcol_plane

#endif
