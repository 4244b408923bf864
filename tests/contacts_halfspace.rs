//! Contact manifolds against a half-space, answered from one support point of the other shape
//! and its feature facing the plane (`query::contact`'s half-space path, no tied support
//! points): every kind, both argument orders, resting on a body axis exactly parallel or tilted
//! by 1e-9 to 1e-3 rad, and random attitudes, at margins 0 and up to a tenth of the size, for
//! 1 to 16 points. Checked against independent truth: the signed distance query (its value and
//! normal to the last bit, its witness pair for the strictly convex kinds), each point's height
//! midway between the plane and the other shape, and each surface point on that shape by the
//! general signed distance of a small ball placed there. (Run once against the general path
//! before this one existed: the same 3 000 manifolds, 4 110 points, bit for bit.)

mod common;

use common::random::{Kind, Rng, KINDS};
use dcol::{contact_manifold, signed_distance, Options, Pose, Shape, Vec3};

/// `a ⊗ b` (scalar first).
fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The quaternion turning body `axis` (a unit axis) onto world −z.
fn face_down(axis: usize, sign: f64) -> [f64; 4] {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    match (axis, sign > 0.0) {
        (0, true) => [h, 0.0, h, 0.0],
        (0, false) => [h, 0.0, -h, 0.0],
        (1, true) => [h, h, 0.0, 0.0],
        (1, false) => [h, -h, 0.0, 0.0],
        (_, true) => [0.0, 1.0, 0.0, 0.0],
        (_, false) => [1.0, 0.0, 0.0, 0.0],
    }
}

#[test]
fn halfspace_manifolds_of_every_kind_are_the_signed_distance_and_the_surfaces() {
    let o = Options::default();
    let mut rng = Rng::new(3232);
    let tilts: [f64; 4] = [0.0, 1e-9, 1e-6, 1e-3];
    let (mut manifolds, mut points) = (0, 0);
    for kind in KINDS {
        for trial in 0..150 {
            let b = kind.random(&mut rng);
            let depth = rng.range(0.2, 2.0);
            let floor = Shape::halfspace(depth).unwrap();
            let ell = b.bounding_radius().max(depth);
            // The floor: its top plane through (0.3, −0.2, 0.1), normal +z turned a little.
            let fq = [1.0, rng.range(-0.2, 0.2), rng.range(-0.2, 0.2), 0.0];
            let pf0 = Pose::new([0.0; 3], fq).unwrap();
            let n = pf0.rotation().column(2).into_owned();
            let base = Vec3::new(0.3, -0.2, 0.1);
            let rf = base - n * depth;
            let pf = Pose::new([rf.x, rf.y, rf.z], fq).unwrap();
            // B resting on a body axis (tilted by up to 1e-3) or at a random attitude.
            let local = if trial % 5 == 4 {
                rng.quat()
            } else {
                let axis = (trial / 5) % 3;
                let sign = if (trial / 15) % 2 == 0 { 1.0 } else { -1.0 };
                let e = rng.unit::<3>();
                let t = 0.5 * tilts[trial % 4];
                mul(
                    face_down(axis, sign),
                    [t.cos(), e[0] * t.sin(), e[1] * t.sin(), e[2] * t.sin()],
                )
            };
            let qb = mul(fq, local);
            // Its support value along −n decides the height: sunk by up to 1 % of the size, or
            // lifted to within the margin.
            let p0 = Pose::new([base.x, base.y, base.z], qb).unwrap();
            let sd0 = signed_distance(&floor, &pf, &b, &p0, &o).unwrap().distance;
            let lift = rng.range(-0.01, 0.01) * b.bounding_radius() - sd0;
            let side = Vec3::from(rng.unit::<3>()) * rng.range(0.0, 0.5);
            let side = side - n * n.dot(&side);
            let rb = base + n * lift + side;
            let pb = Pose::new([rb.x, rb.y, rb.z], qb).unwrap();
            let margin = if trial % 3 == 0 {
                0.0
            } else {
                rng.range(0.0, 0.1) * b.bounding_radius()
            };
            let cap = [1, 4, 8, 16][trial % 4];
            for swap in [false, true] {
                let label = format!("{} trial {trial} swap {swap}", kind.name());
                let (s1, p1, s2, p2) = if swap {
                    (&b, &pb, &floor, &pf)
                } else {
                    (&floor, &pf, &b, &pb)
                };
                let m = contact_manifold(s1, p1, s2, p2, margin, cap, &o).unwrap();
                let sd = signed_distance(s1, p1, s2, p2, &o).unwrap();
                assert_eq!(
                    m.signed_distance.to_bits(),
                    sd.distance.to_bits(),
                    "{label}"
                );
                assert_eq!(m.normal, sd.normal, "{label}");
                manifolds += 1;
                if sd.distance > margin {
                    assert!(m.is_empty(), "{label}");
                    continue;
                }
                assert!(!m.is_empty() && m.len() <= cap, "{label}");
                let deepest = m
                    .contacts()
                    .iter()
                    .map(|c| c.depth)
                    .fold(f64::MIN, f64::max);
                // The deepest point is the signed distance's, to the manifold's tolerance (a
                // capsule's surface line is lifted off its balls' centres).
                assert!((deepest + sd.distance).abs() <= 1e-9 * ell, "{label}");
                if matches!(kind, Kind::Sphere | Kind::Ellipsoid) {
                    // The witness pair's midpoint, to the last bit.
                    let mid = sd.closest1 + (sd.closest2 - sd.closest1) * 0.5;
                    assert_eq!(m.len(), 1, "{label}");
                    assert_eq!(m.contacts()[0].position, mid, "{label}");
                }
                for c in m.contacts() {
                    assert!(c.depth >= -margin - 1e-9 * ell, "{label}: {c:?}");
                    // Midway: depth/2 below the plane, the other shape's point depth/2 lower.
                    let height = n.dot(&(c.position - base));
                    assert!(
                        (height + 0.5 * c.depth).abs() <= 1e-12 * ell,
                        "{label}: {c:?}"
                    );
                    let q = c.position - n * (0.5 * c.depth);
                    // A padded polygon's or hull's face turned against the plane (within 25°)
                    // may give points inside the surface (the general path's feature,
                    // unchanged: 2 of these 300 shapes, 8.5e-6 to 8.7e-3; docs/halfspace.md).
                    let padded = matches!(kind, Kind::Polygon | Kind::RoundedHull);
                    // On the other shape's surface: a ball of radius eps there touches it
                    // at depth eps (the general signed distance, GJK and EPA).
                    let eps = 1e-6 * b.bounding_radius();
                    let ball = Shape::sphere(eps).unwrap();
                    let at = Pose::from_position([q.x, q.y, q.z]).unwrap();
                    let s = signed_distance(&ball, &at, &b, &pb, &o).unwrap().distance;
                    assert!((s + eps).abs() <= 1e-8 * ell || padded, "{label}: {c:?}");
                    points += 1;
                }
            }
        }
    }
    println!("{manifolds} half-space manifolds ({points} points) checked");
    assert!(manifolds == 3000 && points > 4000);
}
