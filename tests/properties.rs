//! Property tests of `proximity` over random shapes of all eight kinds (sphere, ellipsoid, box,
//! polytope, capsule, cylinder, cone, padded polygon) and random poses, with quaternions of any
//! length:
//!
//! - (a) swapping the two shapes leaves α* (and, for strictly convex pairs, x*) unchanged;
//! - (b) one rigid motion applied to both poses leaves α* unchanged and carries x* along;
//! - (c) the contact points lie on the unscaled boundaries, checked with implicit functions
//!   written here independently of the library;
//! - (d) sphere–sphere: α* = ‖r₁ − r₂‖/(R₁ + R₂) and the contact points in closed form;
//! - (e) α* = 0 exactly when the origins coincide (and α* is homogeneous in r₂ − r₁ near it);
//! - (f) every solve converges with finite outputs, over offsets from 1e-4 ℓ to 1e4 ℓ.
//!
//! Tolerances: α* to 1e-8 relative (the solver stops on a relative duality gap of 1e-10 in α);
//! points to 1e-5 ℓ (ℓ the larger bounding radius), because an interior-point method's x*
//! converges like the square root of its tolerance on curved contacts.

use dcol::{proximity, Options, Pose, Proximity, Shape, SolveStatus};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::f64::consts::PI;

type V3 = Vector3<f64>;

/// Relative tolerance on α*.
const ALPHA_RTOL: f64 = 1e-8;
/// Tolerance on points (x*, contact points), in units of ℓ.
const POINT_TOL: f64 = 1e-5;

/// A shape's parameters, kept so that the test can evaluate its own implicit function.
#[derive(Clone, Debug)]
enum Spec {
    Sphere {
        r: f64,
    },
    Ellipsoid {
        p: [[f64; 3]; 3],
    },
    Cuboid {
        h: [f64; 3],
    },
    Polytope {
        a: Vec<[f64; 3]>,
        b: Vec<f64>,
    },
    Capsule {
        r: f64,
        l: f64,
    },
    Cylinder {
        r: f64,
        l: f64,
    },
    Cone {
        h: f64,
        beta: f64,
    },
    Polygon {
        c: Vec<[f64; 2]>,
        d: Vec<f64>,
        r: f64,
        /// Vertices of `{ y : C y ≤ d }` in counter-clockwise order (computed here).
        verts: Vec<[f64; 2]>,
    },
}

impl Spec {
    fn build(&self) -> Shape {
        let s = match self {
            Spec::Sphere { r } => Shape::sphere(*r),
            Spec::Ellipsoid { p } => Shape::ellipsoid(*p),
            Spec::Cuboid { h } => Shape::cuboid(h[0], h[1], h[2]),
            Spec::Polytope { a, b } => Shape::polytope(a, b),
            Spec::Capsule { r, l } => Shape::capsule(*r, *l),
            Spec::Cylinder { r, l } => Shape::cylinder(*r, *l),
            Spec::Cone { h, beta } => Shape::cone(*h, *beta),
            Spec::Polygon { c, d, r, .. } => Shape::polygon(c, d, *r),
        };
        s.unwrap_or_else(|e| panic!("constructor rejected a valid shape {self:?}: {e}"))
    }

    /// An implicit function of the unscaled body-frame set: zero on the boundary, negative
    /// inside, positive outside, in length units, with |f| no larger than a few times the
    /// Euclidean distance to the boundary near the boundary.
    fn implicit(&self, b: &V3) -> f64 {
        match self {
            Spec::Sphere { r } => b.norm() - r,
            Spec::Ellipsoid { p } => {
                // Radial distance to the boundary: ‖b‖ (1 − 1/√(bᵀPb)).
                let pm = Matrix3::from_fn(|i, j| p[i][j]);
                let g = b.dot(&(pm * b)).sqrt();
                if g == 0.0 {
                    return f64::NEG_INFINITY; // the centre
                }
                b.norm() * (1.0 - 1.0 / g)
            }
            Spec::Cuboid { h } => (0..3)
                .map(|i| b[i].abs() - h[i])
                .fold(f64::NEG_INFINITY, f64::max),
            Spec::Polytope { a, b: off } => a
                .iter()
                .zip(off)
                .map(|(ai, bi)| {
                    let n = V3::from(*ai);
                    (n.dot(b) - bi) / n.norm()
                })
                .fold(f64::NEG_INFINITY, f64::max),
            Spec::Capsule { r, l } => {
                let t = b.x.clamp(-0.5 * l, 0.5 * l);
                (b - V3::new(t, 0.0, 0.0)).norm() - r
            }
            Spec::Cylinder { r, l } => {
                // Exact signed distance.
                let d1 = b.y.hypot(b.z) - r;
                let d2 = b.x.abs() - 0.5 * l;
                d1.max(d2).min(0.0) + d1.max(0.0).hypot(d2.max(0.0))
            }
            Spec::Cone { h, beta } => {
                // Lateral surface (distance to the plane of the generator through b's meridian)
                // and the base plane.
                let t = b.x + 0.75 * h;
                let rho = b.y.hypot(b.z);
                let lateral = rho * beta.cos() - t * beta.sin();
                lateral.max(b.x - 0.25 * h)
            }
            Spec::Polygon { c, d, r, verts } => {
                // Exact: distance to the flat polygon (in 3D) minus the padding.
                let y = [b.x, b.y];
                let inside = c
                    .iter()
                    .zip(d)
                    .all(|(ci, di)| ci[0] * y[0] + ci[1] * y[1] <= *di);
                let planar = if inside {
                    0.0
                } else {
                    (0..verts.len())
                        .map(|k| seg_dist(y, verts[k], verts[(k + 1) % verts.len()]))
                        .fold(f64::INFINITY, f64::min)
                };
                planar.hypot(b.z) - r
            }
        }
    }
}

/// Distance from `p` to the segment `[a, b]` in the plane.
fn seg_dist(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let (px, py) = (p[0] - a[0], p[1] - a[1]);
    let ee = ex * ex + ey * ey;
    let t = if ee > 0.0 {
        ((px * ex + py * ey) / ee).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (px - t * ex).hypot(py - t * ey)
}

/// Vertices of the bounded polygon `C y ≤ d`, counter-clockwise.
fn polygon_vertices(c: &[[f64; 2]], d: &[f64]) -> Vec<[f64; 2]> {
    let m = c.len();
    let mut v = Vec::new();
    for i in 0..m {
        for j in (i + 1)..m {
            let det = c[i][0] * c[j][1] - c[i][1] * c[j][0];
            if det.abs() < 1e-12 {
                continue;
            }
            let y = [
                (d[i] * c[j][1] - d[j] * c[i][1]) / det,
                (c[i][0] * d[j] - c[j][0] * d[i]) / det,
            ];
            if c.iter()
                .zip(d)
                .all(|(ck, dk)| ck[0] * y[0] + ck[1] * y[1] <= dk + 1e-12)
            {
                v.push(y);
            }
        }
    }
    assert!(v.len() >= 3, "polygon has fewer than three vertices");
    let n = v.len() as f64;
    let cx = v.iter().map(|p| p[0]).sum::<f64>() / n;
    let cy = v.iter().map(|p| p[1]).sum::<f64>() / n;
    v.sort_by(|p, q| {
        let a = (p[1] - cy).atan2(p[0] - cx);
        let b = (q[1] - cy).atan2(q[0] - cx);
        a.total_cmp(&b)
    });
    v
}

// ---------------------------------------------------------------------------------------------
// Strategies.

/// A quaternion of length 10^e, e ∈ [-1, 1] (rarely a unit one).
fn quaternion() -> impl Strategy<Value = [f64; 4]> {
    (prop::array::uniform4(-1.0f64..1.0), -1.0f64..1.0).prop_map(|(q, e)| {
        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
        let len = 10f64.powf(e);
        if n < 0.1 {
            [len, 0.0, 0.0, 0.0]
        } else {
            q.map(|v| v * len / n)
        }
    })
}

fn rotation(q: [f64; 4]) -> Matrix3<f64> {
    UnitQuaternion::from_quaternion(Quaternion::new(q[0], q[1], q[2], q[3]))
        .to_rotation_matrix()
        .into_inner()
}

fn sphere() -> impl Strategy<Value = Spec> {
    (0.1f64..2.0).prop_map(|r| Spec::Sphere { r })
}

fn ellipsoid() -> impl Strategy<Value = Spec> {
    (prop::array::uniform3(0.1f64..2.0), quaternion()).prop_map(|(s, q)| {
        let u = rotation(q);
        let d = Matrix3::from_diagonal(&V3::new(
            1.0 / (s[0] * s[0]),
            1.0 / (s[1] * s[1]),
            1.0 / (s[2] * s[2]),
        ));
        let m = u * d * u.transpose();
        let mut p = [[0.0; 3]; 3];
        for (i, row) in p.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                *v = 0.5 * (m[(i, j)] + m[(j, i)]);
            }
        }
        Spec::Ellipsoid { p }
    })
}

fn cuboid() -> impl Strategy<Value = Spec> {
    prop::array::uniform3(0.1f64..2.0).prop_map(|h| Spec::Cuboid { h })
}

/// Twelve random normals plus the six of a box (so the set is bounded), each row scaled by a
/// random factor (A need not have unit rows), and random positive offsets.
fn polytope() -> impl Strategy<Value = Spec> {
    (
        prop::array::uniform12(prop::array::uniform3(-1.0f64..1.0)),
        prop::array::uniform18(0.2f64..1.5),
        prop::array::uniform18(0.5f64..2.0),
    )
        .prop_map(|(normals, off, k)| {
            let mut a: Vec<[f64; 3]> = normals
                .iter()
                .map(|n| {
                    let v = V3::from(*n);
                    let len = v.norm();
                    if len < 1e-3 {
                        [1.0, 0.0, 0.0]
                    } else {
                        (v / len).into()
                    }
                })
                .collect();
            for i in 0..3 {
                let mut e = [0.0; 3];
                e[i] = 1.0;
                a.push(e);
                e[i] = -1.0;
                a.push(e);
            }
            let b: Vec<f64> = off.iter().zip(&k).map(|(o, s)| o * s).collect();
            let a = a
                .iter()
                .zip(&k)
                .map(|(row, s)| row.map(|v| v * s))
                .collect();
            Spec::Polytope { a, b }
        })
}

fn capsule() -> impl Strategy<Value = Spec> {
    (0.1f64..1.5, 0.1f64..3.0).prop_map(|(r, l)| Spec::Capsule { r, l })
}

fn cylinder() -> impl Strategy<Value = Spec> {
    (0.1f64..1.5, 0.1f64..3.0).prop_map(|(r, l)| Spec::Cylinder { r, l })
}

fn cone() -> impl Strategy<Value = Spec> {
    (0.2f64..3.0, 0.1f64..1.4).prop_map(|(h, beta)| Spec::Cone { h, beta })
}

/// m ∈ 3..=8 edge normals at jittered, roughly even angles (so consecutive normals are less
/// than π apart and the polygon is bounded), each scaled, with random offsets and padding.
fn polygon() -> impl Strategy<Value = Spec> {
    (
        3usize..=8,
        0.0f64..(2.0 * PI),
        prop::array::uniform8(-0.2f64..0.2),
        prop::array::uniform8(0.2f64..1.5),
        prop::array::uniform8(0.5f64..2.0),
        0.02f64..0.5,
    )
        .prop_map(|(m, phase, jitter, off, k, r)| {
            let step = 2.0 * PI / m as f64;
            let c: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let th = phase + step * (i as f64 + jitter[i]);
                    [k[i] * th.cos(), k[i] * th.sin()]
                })
                .collect();
            let d: Vec<f64> = (0..m).map(|i| off[i] * k[i]).collect();
            let verts = polygon_vertices(&c, &d);
            Spec::Polygon { c, d, r, verts }
        })
}

fn any_shape() -> impl Strategy<Value = Spec> {
    prop_oneof![
        sphere(),
        ellipsoid(),
        cuboid(),
        polytope(),
        capsule(),
        cylinder(),
        cone(),
        polygon(),
    ]
}

fn strictly_convex_shape() -> impl Strategy<Value = Spec> {
    prop_oneof![sphere(), ellipsoid()]
}

/// A pose as raw numbers: position in [-2, 2]³ and a quaternion of any length.
#[derive(Clone, Copy, Debug)]
struct RawPose {
    r: [f64; 3],
    q: [f64; 4],
}

impl RawPose {
    fn pose(&self) -> Pose {
        Pose::new(self.r, self.q).expect("valid pose")
    }
}

fn raw_pose() -> impl Strategy<Value = RawPose> {
    (prop::array::uniform3(-2.0f64..2.0), quaternion()).prop_map(|(r, q)| RawPose { r, q })
}

// ---------------------------------------------------------------------------------------------
// Helpers.

/// `cases` per property, or `PROPTEST_CASES` when set (for long runs).
fn config(cases: u32) -> Config {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(cases);
    Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    }
}

fn solve(s1: &Shape, p1: &Pose, s2: &Shape, p2: &Pose) -> Result<Proximity, TestCaseError> {
    let prox = proximity(s1, p1, s2, p2, &Options::default())
        .map_err(|e| TestCaseError::fail(format!("proximity returned an error: {e}")))?;
    check_outcome(&prox)?;
    Ok(prox)
}

/// (f): converged, and every output finite.
fn check_outcome(p: &Proximity) -> Result<(), TestCaseError> {
    prop_assert_eq!(p.status, SolveStatus::Converged, "{:?}", p);
    let finite = p.alpha.is_finite()
        && p.alpha >= 0.0
        && p.point.iter().all(|v| v.is_finite())
        && p.contact1.iter().all(|v| v.is_finite())
        && p.contact2.iter().all(|v| v.is_finite());
    prop_assert!(finite, "non-finite or negative output: {:?}", p);
    Ok(())
}

fn ell(s1: &Shape, s2: &Shape) -> f64 {
    s1.bounding_radius().max(s2.bounding_radius())
}

fn rel_err(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs())
}

/// Hamilton product `g ⊗ q` of `[w, x, y, z]` quaternions (not normalised).
fn qmul(g: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    let p = Quaternion::new(g[0], g[1], g[2], g[3]) * Quaternion::new(q[0], q[1], q[2], q[3]);
    [p.w, p.i, p.j, p.k]
}

// ---------------------------------------------------------------------------------------------
// Properties.

proptest! {
    #![proptest_config(config(256))]

    /// (a) α*(a, b) = α*(b, a), for every pair of kinds.
    #[test]
    fn swap_symmetry_alpha(s1 in any_shape(), s2 in any_shape(), a in raw_pose(), b in raw_pose()) {
        let (sh1, sh2, p1, p2) = (s1.build(), s2.build(), a.pose(), b.pose());
        let ab = solve(&sh1, &p1, &sh2, &p2)?;
        let ba = solve(&sh2, &p2, &sh1, &p1)?;
        let e = rel_err(ab.alpha, ba.alpha);
        prop_assert!(e <= ALPHA_RTOL, "alpha(a,b) = {:e}, alpha(b,a) = {:e}, rel err {:e}", ab.alpha, ba.alpha, e);
    }

    /// (a) For strictly convex pairs x* is unique: swapping gives the same x* and contacts.
    #[test]
    fn swap_symmetry_point(s1 in strictly_convex_shape(), s2 in strictly_convex_shape(), a in raw_pose(), b in raw_pose()) {
        let (sh1, sh2, p1, p2) = (s1.build(), s2.build(), a.pose(), b.pose());
        let ab = solve(&sh1, &p1, &sh2, &p2)?;
        let ba = solve(&sh2, &p2, &sh1, &p1)?;
        let l = ell(&sh1, &sh2);
        prop_assert!(rel_err(ab.alpha, ba.alpha) <= ALPHA_RTOL, "alpha {:e} vs {:e}", ab.alpha, ba.alpha);
        let dx = (ab.point - ba.point).norm();
        prop_assert!(dx <= POINT_TOL * l * ab.alpha.max(1.0), "x*: {} vs {}, |dx| = {:e} ℓ", ab.point, ba.point, dx / l);
        let dc1 = (ab.contact1 - ba.contact2).norm();
        let dc2 = (ab.contact2 - ba.contact1).norm();
        prop_assert!(dc1.max(dc2) <= POINT_TOL * l, "contacts differ by {:e} ℓ, {:e} ℓ", dc1 / l, dc2 / l);
    }

    /// (b) A rigid motion applied to both poses leaves α* unchanged.
    #[test]
    fn rigid_motion_invariance_alpha(
        s1 in any_shape(), s2 in any_shape(), a in raw_pose(), b in raw_pose(),
        t in prop::array::uniform3(-5.0f64..5.0), g in quaternion(),
    ) {
        let (sh1, sh2) = (s1.build(), s2.build());
        let before = solve(&sh1, &a.pose(), &sh2, &b.pose())?;
        let gm = rotation(g);
        let tv = V3::from(t);
        let move_pose = |p: &RawPose| Pose::new((gm * V3::from(p.r) + tv).into(), qmul(g, p.q)).unwrap();
        let after = solve(&sh1, &move_pose(&a), &sh2, &move_pose(&b))?;
        let e = rel_err(before.alpha, after.alpha);
        prop_assert!(e <= ALPHA_RTOL, "alpha before {:e}, after {:e}, rel err {:e}", before.alpha, after.alpha, e);
    }

    /// (b) ... and, for strictly convex pairs, carries x* and the contact points with it.
    #[test]
    fn rigid_motion_invariance_point(
        s1 in strictly_convex_shape(), s2 in strictly_convex_shape(), a in raw_pose(), b in raw_pose(),
        t in prop::array::uniform3(-5.0f64..5.0), g in quaternion(),
    ) {
        let (sh1, sh2) = (s1.build(), s2.build());
        let before = solve(&sh1, &a.pose(), &sh2, &b.pose())?;
        let gm = rotation(g);
        let tv = V3::from(t);
        let move_pose = |p: &RawPose| Pose::new((gm * V3::from(p.r) + tv).into(), qmul(g, p.q)).unwrap();
        let after = solve(&sh1, &move_pose(&a), &sh2, &move_pose(&b))?;
        let l = ell(&sh1, &sh2);
        prop_assert!(rel_err(before.alpha, after.alpha) <= ALPHA_RTOL, "alpha {:e} vs {:e}", before.alpha, after.alpha);
        let dx = (gm * before.point + tv - after.point).norm();
        prop_assert!(dx <= POINT_TOL * l * before.alpha.max(1.0), "moved x* off by {:e} ℓ", dx / l);
        let dc1 = (gm * before.contact1 + tv - after.contact1).norm();
        let dc2 = (gm * before.contact2 + tv - after.contact2).norm();
        prop_assert!(dc1.max(dc2) <= POINT_TOL * l, "moved contacts off by {:e} ℓ, {:e} ℓ", dc1 / l, dc2 / l);
    }

    /// (d) Sphere–sphere in closed form: α* = ‖r₁ − r₂‖/(R₁ + R₂), p₁ = r₁ + R₁ u, p₂ = r₂ − R₂ u.
    #[test]
    fn sphere_sphere_closed_form(r1 in 0.01f64..3.0, r2 in 0.01f64..3.0, a in raw_pose(), b in raw_pose()) {
        let (sh1, sh2) = (Shape::sphere(r1).unwrap(), Shape::sphere(r2).unwrap());
        let prox = solve(&sh1, &a.pose(), &sh2, &b.pose())?;
        let delta = V3::from(b.r) - V3::from(a.r);
        let dist = delta.norm();
        prop_assume!(dist > 0.0);
        let alpha = dist / (r1 + r2);
        let e = rel_err(prox.alpha, alpha);
        prop_assert!(e <= 1e-9, "alpha {:e}, exact {:e}, rel err {:e}", prox.alpha, alpha, e);
        let u = delta / dist;
        let l = r1.max(r2);
        let e1 = (prox.contact1 - (V3::from(a.r) + u * r1)).norm();
        let e2 = (prox.contact2 - (V3::from(b.r) - u * r2)).norm();
        prop_assert!(e1.max(e2) <= POINT_TOL * l, "contacts off by {:e} ℓ, {:e} ℓ", e1 / l, e2 / l);
        // x* = r₁ + α* R₁ u, the point dividing the offset in the ratio of the radii.
        let ex = (prox.point - (V3::from(a.r) + u * (alpha * r1))).norm();
        prop_assert!(ex <= POINT_TOL * l * alpha.max(1.0), "x* off by {:e} ℓ", ex / l);
    }

    /// (e) Coincident origins give α* = 0 exactly (and x* = r); a tiny non-zero offset gives
    /// α* > 0, homogeneous of degree one in r₂ − r₁.
    #[test]
    fn zero_alpha_iff_coincident(
        s1 in any_shape(), s2 in any_shape(), a in raw_pose(), q2 in quaternion(),
        dir in prop::array::uniform3(-1.0f64..1.0), k in 4i32..14,
    ) {
        let (sh1, sh2) = (s1.build(), s2.build());
        let p1 = a.pose();
        let same = Pose::new(a.r, q2).unwrap();
        let prox = solve(&sh1, &p1, &sh2, &same)?;
        prop_assert_eq!(prox.alpha, 0.0);
        prop_assert_eq!(prox.point, V3::from(a.r));

        let d = V3::from(dir);
        prop_assume!(d.norm() > 0.1);
        let r1 = V3::from(a.r);
        let r2 = r1 + d * 10f64.powi(-k);
        let offset = r2 - r1; // the offset the library sees, as rounded
        prop_assume!(offset != V3::zeros());
        let tiny = solve(&sh1, &p1, &sh2, &Pose::new(r2.into(), q2).unwrap())?;
        prop_assert!(tiny.alpha > 0.0, "alpha {:e} at offset {:e}", tiny.alpha, offset.norm());
        // Same attitudes, offset scaled up by s and placed at the origin: α scales by s.
        let s = 1.0 / offset.norm();
        let unit = solve(
            &sh1,
            &Pose::new([0.0; 3], a.q).unwrap(),
            &sh2,
            &Pose::new((offset * s).into(), q2).unwrap(),
        )?;
        let e = rel_err(tiny.alpha * s, unit.alpha);
        prop_assert!(e <= ALPHA_RTOL, "alpha/|offset| = {:e} at |offset| = {:e}, {:e} at 1; rel err {:e}", tiny.alpha * s, offset.norm(), unit.alpha, e);
    }
}

proptest! {
    #![proptest_config(config(512))]

    /// (c) Contact points lie on the unscaled boundaries (own implicit functions), and
    /// p_i = r_i + (x* − r_i)/α* holds.
    #[test]
    fn contacts_on_boundaries(s1 in any_shape(), s2 in any_shape(), a in raw_pose(), b in raw_pose()) {
        let (sh1, sh2, p1, p2) = (s1.build(), s2.build(), a.pose(), b.pose());
        let prox = solve(&sh1, &p1, &sh2, &p2)?;
        let l = ell(&sh1, &sh2);
        let body = |raw: &RawPose, p: &V3| rotation(raw.q).transpose() * (p - V3::from(raw.r));
        let f1 = s1.implicit(&body(&a, &prox.contact1));
        let f2 = s2.implicit(&body(&b, &prox.contact2));
        prop_assert!(
            f1.abs() <= POINT_TOL * l && f2.abs() <= POINT_TOL * l,
            "alpha = {:e}: implicit at contact1 = {:e} ℓ, at contact2 = {:e} ℓ", prox.alpha, f1 / l, f2 / l
        );
        // Consistency with x*: r_i + α*(p_i − r_i) = x*.
        for (raw, c) in [(&a, &prox.contact1), (&b, &prox.contact2)] {
            let r = V3::from(raw.r);
            let e = (r + (c - r) * prox.alpha - prox.point).norm();
            prop_assert!(e <= POINT_TOL * l * prox.alpha.max(1.0), "r + α(p − r) is {:e} ℓ from x*", e / l);
        }
    }

    /// (f) Every solve converges with finite outputs, for offsets from 1e-4 ℓ to 1e4 ℓ in any
    /// direction; the contact points are still on the boundaries.
    #[test]
    fn converges_over_offset_scales(
        s1 in any_shape(), s2 in any_shape(), a in raw_pose(), q2 in quaternion(),
        dir in prop::array::uniform3(-1.0f64..1.0), e in -4.0f64..4.0,
    ) {
        let (sh1, sh2) = (s1.build(), s2.build());
        let d = V3::from(dir);
        prop_assume!(d.norm() > 0.1);
        let l = ell(&sh1, &sh2);
        let r2 = V3::from(a.r) + d.normalize() * (l * 10f64.powf(e));
        let b = RawPose { r: r2.into(), q: q2 };
        let prox = solve(&sh1, &a.pose(), &sh2, &b.pose())?;
        let body = |raw: &RawPose, p: &V3| rotation(raw.q).transpose() * (p - V3::from(raw.r));
        let f1 = s1.implicit(&body(&a, &prox.contact1));
        let f2 = s2.implicit(&body(&b, &prox.contact2));
        prop_assert!(
            f1.abs() <= POINT_TOL * l && f2.abs() <= POINT_TOL * l,
            "alpha = {:e}: implicit at contact1 = {:e} ℓ, at contact2 = {:e} ℓ", prox.alpha, f1 / l, f2 / l
        );
    }
}

/// The implicit functions themselves: zero on known boundary points, negative at the origin.
#[test]
fn implicit_functions_are_sane() {
    let cases: Vec<(Spec, V3)> = vec![
        (Spec::Sphere { r: 2.0 }, V3::new(0.0, 2.0, 0.0)),
        (
            Spec::Ellipsoid {
                p: [[0.25, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 4.0]],
            },
            V3::new(0.0, 0.0, 0.5),
        ),
        (Spec::Cuboid { h: [1.0, 2.0, 3.0] }, V3::new(0.5, 2.0, -1.0)),
        (Spec::Capsule { r: 0.5, l: 2.0 }, V3::new(1.5, 0.0, 0.0)),
        (Spec::Capsule { r: 0.5, l: 2.0 }, V3::new(0.3, 0.0, 0.5)),
        (Spec::Cylinder { r: 0.5, l: 2.0 }, V3::new(1.0, 0.2, 0.1)),
        (Spec::Cylinder { r: 0.5, l: 2.0 }, V3::new(0.7, 0.3, 0.4)),
        (Spec::Cone { h: 2.0, beta: 0.5 }, V3::new(-1.5, 0.0, 0.0)),
        (
            Spec::Cone { h: 2.0, beta: 0.5 },
            V3::new(0.5, 2.0 * 0.5f64.tan(), 0.0),
        ),
        (Spec::Cone { h: 2.0, beta: 0.5 }, V3::new(0.5, 0.1, 0.2)),
    ];
    for (spec, p) in cases {
        assert!(spec.implicit(&p).abs() < 1e-12, "{spec:?} at {p}");
        assert!(spec.implicit(&V3::zeros()) < 0.0, "{spec:?}");
        spec.build();
    }
    // A unit square padded by 0.5: boundary above the middle, beside an edge, off a corner.
    let c = vec![[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];
    let d = vec![1.0; 4];
    let verts = polygon_vertices(&c, &d);
    let sq = Spec::Polygon {
        c,
        d,
        r: 0.5,
        verts,
    };
    let s = 0.5 / 3f64.sqrt();
    for p in [
        V3::new(0.2, 0.3, 0.5),
        V3::new(1.5, 0.3, 0.0),
        V3::new(1.0 + s, -1.0 - s, s),
    ] {
        assert!(sq.implicit(&p).abs() < 1e-12, "{p}");
    }
    assert!((sq.implicit(&V3::zeros()) + 0.5).abs() < 1e-15);
    // Polytope rows need not be unit: max_i (a_i·b − b_i)/‖a_i‖.
    let pt = Spec::Polytope {
        a: vec![
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [-1.0, -1.0, -1.0],
        ],
        b: vec![2.0, 1.0, 1.0, 1.0],
    };
    assert!(pt.implicit(&V3::new(1.0, 0.2, 0.3)).abs() < 1e-15);
    assert!((pt.implicit(&V3::new(2.0, 0.0, 0.0)) - 1.0).abs() < 1e-15);
}
