//! Tests of `super::closed_form` against independent truths (bisection, analytic cases).

use super::*;

fn seg(axis: [Real; 3], half: Real, radius: Real) -> RoundedSegment {
    RoundedSegment {
        axis: Vec3::from(axis).normalize(),
        half,
        radius,
    }
}

/// The cylinder's plane problem against bisection on `dist(p, αS) − αρ` (decreasing in α)
/// with the rectangle's distance written out: α to 1e-12 relative, the closest point of
/// αS to 1e-9, on points facing the side, the cap and the corner.
#[test]
fn rectangle_root_matches_bisection() {
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut unif = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as Real / (1u64 << 53) as Real
    };
    for _ in 0..20_000 {
        let (h, r, rho) = (0.05 + unif(), 0.05 + unif(), 0.01 + unif());
        let (pa, pr) = (6.0 * unif() - 3.0, 3.0 * unif());
        let closest = |a: Real| (pa.clamp(-a * h, a * h), pr.min(a * r));
        let f = |a: Real| {
            let (ca, cr) = closest(a);
            (pa - ca).hypot(pr - cr) - a * rho
        };
        let (mut lo, mut hi) = (0.0, 1e3);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (alpha, (xa, xr)) = rectangle_root(pa, pr, h, r, rho);
        assert!((alpha - hi).abs() <= 1e-12 * hi, "{alpha} vs {hi}");
        let (ca, cr) = closest(alpha);
        assert!((xa - ca).abs() <= 1e-9 && (xr - cr).abs() <= 1e-9);
    }
}

#[test]
fn sphere_against_a_box_face_edge_and_corner() {
    let id = Mat3::identity();
    let h = Vec3::new(1.0, 0.5, 0.25);
    // Face: along x, ‖d‖ = α(h_x + ρ).
    let hit = sphere_box(&Vec3::new(1.0, 0.0, 0.0), &id, &h, 0.5).unwrap();
    assert!((hit.alpha - 1.0 / 1.5).abs() < 1e-15 && (hit.normal.x - 1.0).abs() < 1e-15);
    // Edge (x, y): the corner of the scaled box's x-y face, α solves
    // (dx − αhx)² + (dy − αhy)² = α²ρ², checked by φ(α) = 0.
    let d = Vec3::new(3.0, 2.0, 0.0).normalize();
    let hit = sphere_box(&d, &id, &h, 0.2).unwrap();
    let a = hit.alpha;
    let r = ((d.x - a * h.x).powi(2) + (d.y - a * h.y).powi(2)).sqrt();
    assert!((r - a * 0.2).abs() < 1e-15 && d.x > a * h.x && d.y > a * h.y);
    // Corner: all three axes outside.
    let d = Vec3::new(1.0, 0.5, 0.25).normalize();
    let hit = sphere_box(&d, &id, &h, 0.3).unwrap();
    let a = hit.alpha;
    let e = Vec3::new(d.x - a * h.x, d.y - a * h.y, d.z - a * h.z);
    assert!(e.iter().all(|v| *v > 0.0) && (e.norm() - a * 0.3).abs() < 1e-15);
}

#[test]
fn sphere_against_a_cylinder_side_cap_and_rim_and_a_cone() {
    let id = Mat3::identity();
    // Cylinder of radius 0.5 and half-length 1 about x, sphere of radius 0.25.
    let cyl = [(-1.0, -0.5), (1.0, -0.5), (1.0, 0.5), (-1.0, 0.5)];
    let side = sphere_revolution(&Vec3::new(0.0, 0.6, 0.8), &id, &cyl, 0.25).unwrap();
    assert!((side.alpha - 1.0 / 0.75).abs() < 1e-15);
    assert!((side.normal - Vec3::new(0.0, 0.6, 0.8)).norm() < 1e-15);
    assert!((side.box_point - Vec3::new(0.0, 0.3, 0.4)).norm() < 1e-15);
    let cap = sphere_revolution(&Vec3::new(-1.0, 0.0, 0.0), &id, &cyl, 0.25).unwrap();
    assert!((cap.alpha - 0.8).abs() < 1e-15 && (cap.normal.x + 1.0).abs() < 1e-15);
    // The rim: (q_a − αh)² + (q_r − αR)² = α²ρ² with both parts outside.
    let q = Vec3::new(3.0, 0.0, 2.0).normalize();
    let rim = sphere_revolution(&q, &id, &cyl, 0.25).unwrap();
    let a = rim.alpha;
    let (ea, er) = (q.x - a, q.z - a * 0.5);
    assert!(ea > 0.0 && er > 0.0 && (ea.hypot(er) - a * 0.25).abs() < 1e-15);
    assert!((rim.box_point - Vec3::new(1.0, 0.0, 0.5)).norm() < 1e-15);
    // Cone of height 1, half angle 45°: apex at −3/4, base of radius 1 at +1/4.
    let cone = [(-0.75, 0.0), (0.25, -1.0), (0.25, 1.0)];
    let apex = sphere_revolution(&Vec3::new(-1.0, 0.0, 0.0), &id, &cone, 0.25).unwrap();
    assert!((apex.alpha - 1.0).abs() < 1e-15);
    assert!((apex.box_point - Vec3::new(-0.75, 0.0, 0.0)).norm() < 1e-15);
    let base = sphere_revolution(&Vec3::new(1.0, 0.0, 0.0), &id, &cone, 0.25).unwrap();
    assert!((base.alpha - 2.0).abs() < 1e-15);
    // The slant side, offset along its outward normal (−1, 1)/√2: α = 1/(b + ρ).
    let n = Vec3::new(-1.0, 1.0, 0.0).normalize();
    let slant = sphere_revolution(&n, &id, &cone, 0.25).unwrap();
    let b = 0.75 / (2.0 as Real).sqrt();
    assert!((slant.alpha - 1.0 / (b + 0.25)).abs() < 1e-15);
    assert!((slant.normal - n).norm() < 1e-15);
    // Turned: the answer turns with the solid.
    let rot = Mat3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let turned = sphere_revolution(&(rot * n), &rot, &cone, 0.25).unwrap();
    assert!((turned.alpha - slant.alpha).abs() < 1e-15);
    assert!((turned.box_point - rot * slant.box_point).norm() < 1e-15);
}

#[test]
fn spheres_and_a_capsule_side_and_end() {
    let d = Vec3::new(0.0, 0.6, 0.8);
    let h = rounded_segments(
        &d,
        &seg([1.0, 0.0, 0.0], 0.0, 0.3),
        &seg([1.0, 0.0, 0.0], 0.0, 0.2),
    )
    .unwrap();
    assert!((h.alpha - 2.0).abs() < 1e-15);
    // Sphere against a capsule along x, offset along y: the side (α = 1/ρ).
    let d = Vec3::new(0.0, 1.0, 0.0);
    let h = rounded_segments(
        &d,
        &seg([1.0, 0.0, 0.0], 0.0, 0.25),
        &seg([1.0, 0.0, 0.0], 2.0, 0.25),
    )
    .unwrap();
    assert!((h.alpha - 2.0).abs() < 1e-15);
    // Along the axis: the end cap, ‖d‖ = α(h + ρ).
    let d = Vec3::new(1.0, 0.0, 0.0);
    let h = rounded_segments(
        &d,
        &seg([1.0, 0.0, 0.0], 0.0, 0.25),
        &seg([1.0, 0.0, 0.0], 0.5, 0.25),
    )
    .unwrap();
    assert!((h.alpha - 1.0).abs() < 1e-15, "{h:?}");
    assert!((h.t - 0.5).abs() < 1e-15 || (h.t + 0.5).abs() < 1e-15);
    // Crossed capsules, offset along the common normal: the face (α = 1/ρ).
    let d = Vec3::new(0.0, 0.0, 1.0);
    let h = rounded_segments(
        &d,
        &seg([1.0, 0.0, 0.0], 1.0, 0.1),
        &seg([0.0, 1.0, 0.0], 1.0, 0.4),
    )
    .unwrap();
    assert!((h.alpha - 2.0).abs() < 1e-15 && h.s.abs() < 1e-15 && h.t.abs() < 1e-15);
    assert!((h.normal - d).norm() < 1e-15);
}
