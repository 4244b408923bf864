//! Shapes written out independently of the library (`shared/CONVENTIONS.md`): each kind's
//! support function and how far a point lies outside it, in the body frame; posed, in the
//! world. The property tests build a [`dcol::Shape`] and its [`Oracle`] from the same numbers
//! and check the library's answers against these formulas (the support plane at a normal, a
//! witness point on its shape, a brute-force maximum over normals).

use dcol::math::rotation_from_quaternion;
use dcol::{Pose, Vec3};
use nalgebra::Matrix3;

/// One shape, by its parameters.
pub enum Oracle {
    Sphere(f64),
    /// `P` and `P⁻¹`.
    Ellipsoid(Matrix3<f64>, Matrix3<f64>),
    /// `A x ≤ b` (rows), and its vertices.
    Polytope(Vec<Vec3>, Vec<f64>, Vec<Vec3>),
    Capsule(f64, f64),
    Cylinder(f64, f64),
    /// Height and half angle.
    Cone(f64, f64),
    /// The plane polygon's vertices in order round it, and the radius.
    Polygon(Vec<[f64; 2]>, f64),
    /// A convex hull padded by a radius: its points, its facets' triangles (every triple of
    /// points on a facet's plane) with their outward unit normals, and the radius.
    Hull(Vec<Vec3>, Vec<([Vec3; 3], Vec3)>, f64),
}

impl Oracle {
    /// The hull of `points` (surrounding the origin) padded by `radius`, its facets found by
    /// brute force over triples.
    pub fn hull(points: Vec<Vec3>, radius: f64) -> Oracle {
        let scale = points.iter().map(|p| p.norm()).fold(0.0, f64::max);
        let eps = 1e-12 * scale;
        let n = points.len();
        let mut tris = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let (a, b, c) = (points[i], points[j], points[k]);
                    let Some(nrm) = (b - a).cross(&(c - a)).try_normalize(1e-300) else {
                        continue;
                    };
                    let side = |p: &Vec3| nrm.dot(&(p - a));
                    if points.iter().all(|p| side(p) <= eps) {
                        tris.push(([a, b, c], nrm));
                    } else if points.iter().all(|p| side(p) >= -eps) {
                        tris.push(([a, b, c], -nrm));
                    }
                }
            }
        }
        Oracle::Hull(points, tris, radius)
    }
}

/// The distance from `p` to the triangle `t` (Ericson, *Real-Time Collision Detection* 5.1.5).
fn triangle_distance(p: &Vec3, t: &[Vec3; 3]) -> f64 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.norm();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.norm();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).norm();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.norm();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).norm();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).norm();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).norm()
}

/// The vertices of `A x ≤ b` by brute force over triples of planes.
pub fn polytope_vertices(a: &[Vec3], b: &[f64]) -> Vec<Vec3> {
    let mut out: Vec<Vec3> = Vec::new();
    let scale = b.iter().cloned().fold(0.0, f64::max);
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            for k in j + 1..a.len() {
                let m = Matrix3::from_rows(&[a[i].transpose(), a[j].transpose(), a[k].transpose()]);
                let Some(inv) = m.try_inverse() else {
                    continue;
                };
                let x = inv * Vec3::new(b[i], b[j], b[k]);
                let inside = a
                    .iter()
                    .zip(b)
                    .all(|(r, bi)| r.dot(&x) <= bi + 1e-9 * r.norm() * scale);
                if inside && out.iter().all(|v| (v - x).norm() > 1e-12 * scale) {
                    out.push(x);
                }
            }
        }
    }
    out
}

/// The vertices of `{y : C y ≤ d}` in counter-clockwise order.
pub fn polygon_vertices(c: &[[f64; 2]], d: &[f64]) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::new();
    for i in 0..c.len() {
        for j in i + 1..c.len() {
            let det = c[i][0] * c[j][1] - c[i][1] * c[j][0];
            if det.abs() < 1e-12 {
                continue;
            }
            let x = (d[i] * c[j][1] - c[i][1] * d[j]) / det;
            let y = (c[i][0] * d[j] - d[i] * c[j][0]) / det;
            let inside = c
                .iter()
                .zip(d)
                .all(|(r, di)| r[0] * x + r[1] * y <= di + 1e-9 * di.abs().max(1.0));
            if inside && out.iter().all(|p| (p[0] - x).hypot(p[1] - y) > 1e-12) {
                out.push([x, y]);
            }
        }
    }
    let n = out.len() as f64;
    let cx = out.iter().map(|p| p[0]).sum::<f64>() / n;
    let cy = out.iter().map(|p| p[1]).sum::<f64>() / n;
    out.sort_by(|p, q| {
        (p[1] - cy)
            .atan2(p[0] - cx)
            .total_cmp(&(q[1] - cy).atan2(q[0] - cx))
    });
    out
}

/// The distance from `p` to the segment `a`–`b` (plane).
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

impl Oracle {
    /// The support function in the body frame.
    pub fn h(&self, m: &Vec3) -> f64 {
        let yz = m.y.hypot(m.z);
        match self {
            Oracle::Sphere(r) => r * m.norm(),
            Oracle::Ellipsoid(_, q) => m.dot(&(q * m)).max(0.0).sqrt(),
            Oracle::Polytope(_, _, v) => v.iter().map(|p| p.dot(m)).fold(f64::MIN, f64::max),
            Oracle::Capsule(r, l) => 0.5 * l * m.x.abs() + r * m.norm(),
            Oracle::Cylinder(r, l) => 0.5 * l * m.x.abs() + r * yz,
            Oracle::Cone(h, b) => (-0.75 * h * m.x).max(0.25 * h * m.x + h * b.tan() * yz),
            Oracle::Polygon(w, r) => {
                w.iter()
                    .map(|p| p[0] * m.x + p[1] * m.y)
                    .fold(f64::MIN, f64::max)
                    + r * m.norm()
            }
            Oracle::Hull(p, _, r) => {
                p.iter().map(|v| v.dot(m)).fold(f64::MIN, f64::max) + r * m.norm()
            }
        }
    }

    /// How far the body point `x` lies outside the shape (about; ≤ 0 inside): the distance to
    /// the shape for spheres, capsules and padded polygons, the largest violation of a bounding
    /// plane (or of the cone's slant line) for the flat kinds, and for an ellipsoid the
    /// distance to its boundary point on the ray through `x`; for a hull the distance to it
    /// outside, its largest plane violation inside, less the radius.
    pub fn excess(&self, x: &Vec3) -> f64 {
        let yz = x.y.hypot(x.z);
        match self {
            Oracle::Sphere(r) => x.norm() - r,
            Oracle::Ellipsoid(p, _) => {
                let g = x.dot(&(p * x)).max(0.0).sqrt();
                if g > 0.0 {
                    x.norm() * (1.0 - 1.0 / g)
                } else {
                    -1.0
                }
            }
            Oracle::Polytope(a, b, _) => a
                .iter()
                .zip(b)
                .map(|(r, bi)| (r.dot(x) - bi) / r.norm())
                .fold(f64::MIN, f64::max),
            Oracle::Capsule(r, l) => {
                let t = x.x.clamp(-0.5 * l, 0.5 * l);
                (x - Vec3::new(t, 0.0, 0.0)).norm() - r
            }
            Oracle::Cylinder(r, l) => (x.x.abs() - 0.5 * l).max(yz - r),
            Oracle::Cone(h, b) => {
                let side = (yz - (x.x + 0.75 * h) * b.tan()) * b.cos();
                (x.x - 0.25 * h).max(side)
            }
            Oracle::Polygon(w, r) => {
                let p = [x.x, x.y];
                let n = w.len();
                let inside = (0..n).all(|i| {
                    let (a, b) = (w[i], w[(i + 1) % n]);
                    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0.0
                });
                let planar = if inside {
                    0.0
                } else {
                    (0..n)
                        .map(|i| segment_distance(p, w[i], w[(i + 1) % n]))
                        .fold(f64::INFINITY, f64::min)
                };
                planar.hypot(x.z) - r
            }
            Oracle::Hull(_, tris, r) => {
                let plane = tris
                    .iter()
                    .map(|(t, n)| n.dot(&(x - t[0])))
                    .fold(f64::MIN, f64::max);
                if plane <= 0.0 {
                    plane - r
                } else {
                    tris.iter()
                        .map(|(t, _)| triangle_distance(x, t))
                        .fold(f64::INFINITY, f64::min)
                        - r
                }
            }
        }
    }
}

/// A shape with its pose: world support function and world excess.
pub struct Posed<'a> {
    pub oracle: &'a Oracle,
    pub r: Vec3,
    pub rot: Matrix3<f64>,
}

impl<'a> Posed<'a> {
    pub fn new(oracle: &'a Oracle, pose: &Pose) -> Self {
        Posed {
            oracle,
            r: *pose.position(),
            rot: rotation_from_quaternion(pose.quaternion()),
        }
    }
    /// `h(n) = r·n + h_body(Rᵀn)`.
    pub fn h(&self, n: &Vec3) -> f64 {
        self.r.dot(n) + self.oracle.h(&(self.rot.transpose() * n))
    }
    pub fn excess(&self, x: &Vec3) -> f64 {
        self.oracle.excess(&(self.rot.transpose() * (x - self.r)))
    }
}

/// `L(n) = n·(r₂ − r₁) − h₁(n) − h₂(−n)` with the origins' offset taken exactly as the
/// difference of the posed support functions: `−h₁(n) − h₂(−n)` (world).
pub fn lower(s1: &Posed, s2: &Posed, n: &Vec3) -> f64 {
    let (o1, o2) = (
        Posed {
            oracle: s1.oracle,
            r: Vec3::zeros(),
            rot: s1.rot,
        },
        Posed {
            oracle: s2.oracle,
            r: Vec3::zeros(),
            rot: s2.rot,
        },
    );
    n.dot(&(s2.r - s1.r)) - o1.h(n) - o2.h(&-n)
}

/// A deterministic point sequence for the brute force's local search (SplitMix64).
struct Walk(u64);
impl Walk {
    fn unif(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn dir(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                2.0 * self.unif() - 1.0,
                2.0 * self.unif() - 1.0,
                2.0 * self.unif() - 1.0,
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

/// The brute-force maximum of `L` over unit normals (the signed distance): `k` normals of a
/// Fibonacci sphere, then a local random search from the best of them and from `hint`.
pub fn brute(s1: &Posed, s2: &Posed, hint: &Vec3, k: usize) -> f64 {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut starts = vec![(f64::MIN, Vec3::x())];
    if hint.norm() > 0.5 {
        starts.push((lower(s1, s2, hint), *hint));
    }
    for i in 0..k {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / k as f64;
        let r = (1.0 - z * z).sqrt();
        let t = golden * i as f64;
        let n = Vec3::new(r * t.cos(), r * t.sin(), z);
        let l = lower(s1, s2, &n);
        if l > starts[0].0 {
            starts[0] = (l, n);
        }
    }
    let mut walk = Walk(k as u64);
    let mut top = f64::MIN;
    for mut best in starts {
        let mut step = 0.05;
        while step > 1e-10 {
            let mut improved = false;
            for _ in 0..40 {
                let n = (best.1 + walk.dir() * step).normalize();
                let l = lower(s1, s2, &n);
                if l > best.0 {
                    best = (l, n);
                    improved = true;
                }
            }
            if !improved {
                step *= 0.5;
            }
        }
        top = top.max(best.0);
    }
    top
}
