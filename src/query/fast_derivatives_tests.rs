//! The derivatives' short cuts against the general paths they stand in for, on thousands of
//! random poses: the plain geometric answer of `gradient`, `jacobian` and `derivatives`
//! against the full query (bit for bit, every kind pair), the two spheres' closed-form
//! Jacobian against the feature solve, and the two capsules' uniqueness test against the
//! general one.

use super::context::Want;
use super::geometric::GENERAL_ONLY;
use super::proximity::query;
use super::test_support::{gap, pentagon, Rng};
use crate::{derivatives, gradient, jacobian, DerivativeKind, Options, Pose, Real, Shape};

fn shapes() -> Vec<Shape> {
    let c = pentagon();
    vec![
        Shape::sphere(0.5).unwrap(),
        Shape::ellipsoid([[1.5, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap(),
        Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
        Shape::capsule(0.25, 0.8).unwrap(),
        Shape::cylinder(0.3, 0.9).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
        Shape::polygon(&c, &[0.5; 5], 0.08).unwrap(),
    ]
}

fn general<T>(f: impl FnOnce() -> T) -> T {
    GENERAL_ONLY.with(|g| g.set(true));
    let out = f();
    GENERAL_ONLY.with(|g| g.set(false));
    out
}

/// `gradient`, `jacobian` and `derivatives` answer exactly what the full query answers, for
/// every ordered pair of kinds (fallbacks included: they are the full query's).
#[test]
fn plain_path_is_the_full_query_bit_for_bit() {
    let shapes = shapes();
    let o = Options::default();
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut exact = 0;
    for s1 in &shapes {
        for s2 in &shapes {
            for _ in 0..80 {
                let (p1, p2) = (rng.pose(1.0), rng.pose(2.0));
                let fg = query(s1, &p1, s2, &p2, &o, Want::Gradient).unwrap();
                let fj = query(s1, &p1, s2, &p2, &o, Want::Jacobian).unwrap();
                let (pg, g) = gradient(s1, &p1, s2, &p2, &o).unwrap();
                let (pj, j) = jacobian(s1, &p1, s2, &p2, &o).unwrap();
                let d = derivatives(s1, &p1, s2, &p2, &o).unwrap();
                assert_eq!((pg, g), (fg.prox, fg.gradient));
                assert_eq!((pj, j), (fj.prox, fj.jacobian));
                assert_eq!(
                    (d.proximity, d.dalpha, d.jacobian),
                    (fj.prox, fj.gradient, fj.jacobian)
                );
                exact += usize::from(pj.derivatives == DerivativeKind::Exact);
            }
        }
    }
    // Most answers took the plain path (exact derivatives); the rest were compared too.
    assert!(exact > 49 * 80 / 2, "{exact}");
}

/// Two spheres' closed-form Jacobian against the feature solve's, on 4 000 random poses and
/// radii (separated and overlapping).
#[test]
fn two_spheres_closed_form_matches_the_feature_solve() {
    let o = Options::default();
    let mut rng = Rng(0x0dd5_eed5_0f5a_1e55);
    let mut worst: Real = 0.0;
    for _ in 0..4000 {
        let (ra, rb) = (rng.uniform(0.05, 2.0), rng.uniform(0.05, 2.0));
        let (s1, s2) = (Shape::sphere(ra).unwrap(), Shape::sphere(rb).unwrap());
        let (p1, p2) = (rng.pose(1.5), rng.pose(1.5));
        let (pa, ja) = jacobian(&s1, &p1, &s2, &p2, &o).unwrap();
        let (pb, jb) = general(|| jacobian(&s1, &p1, &s2, &p2, &o).unwrap());
        assert_eq!(pa, pb);
        assert_eq!(pa.derivatives, DerivativeKind::Exact);
        worst = worst.max(gap(&ja, &jb, ra.max(rb)));
    }
    assert!(worst < 1e-12, "{worst:e}");
}

/// The two capsules' uniqueness short cut decides as the general feature test does, on 4 000
/// random poses of which a quarter have nearly parallel axes (sines from 1e-8 to 1e-4 either
/// side of the test's 1e-6).
#[test]
fn two_capsules_uniqueness_matches_the_general_test() {
    let o = Options::default();
    let mut rng = Rng(0xc4b5_1e5c_4b51_e5c4);
    let (s1, s2) = (
        Shape::capsule(0.25, 0.8).unwrap(),
        Shape::capsule(0.3, 0.5).unwrap(),
    );
    let mut smoothed = 0;
    for k in 0..4000 {
        let p1 = rng.pose(1.0);
        let p2 = if k % 4 == 0 {
            // The same attitude turned by a tiny angle about a random axis, side by side.
            let q = p1.quaternion();
            let eps = 10f64.powf(rng.uniform(-8.0, -4.0));
            let w = [0; 3].map(|_| rng.uniform(-1.0, 1.0));
            let q2 = [
                q[0] - 0.5 * eps * (w[0] * q[1] + w[1] * q[2] + w[2] * q[3]),
                q[1] + 0.5 * eps * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2]),
                q[2] + 0.5 * eps * (w[1] * q[0] + w[2] * q[1] - w[0] * q[3]),
                q[3] + 0.5 * eps * (w[2] * q[0] + w[0] * q[2] - w[1] * q[1]),
            ];
            // Beside it: an offset across the axis, so that the sides face each other.
            let axis = p1.rotation().column(0).into_owned();
            let v = crate::Vec3::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), 0.3);
            let across = (v - axis * v.dot(&axis)).normalize() * rng.uniform(0.3, 1.2);
            let r = p1.position() + across + axis * rng.uniform(-0.1, 0.1);
            Pose::new([r.x, r.y, r.z], q2).unwrap()
        } else {
            rng.pose(2.0)
        };
        let a = gradient(&s1, &p1, &s2, &p2, &o).unwrap();
        let b = general(|| gradient(&s1, &p1, &s2, &p2, &o).unwrap());
        assert_eq!(a, b, "pose {k}");
        smoothed += usize::from(a.0.derivatives != DerivativeKind::Exact);
    }
    // The parallel side-by-side poses reach the non-unique case the short cut leaves alone.
    assert!(smoothed > 0);
}
