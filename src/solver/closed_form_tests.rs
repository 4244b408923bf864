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
    let mut unif = stream(0x9E37_79B9_7F4A_7C15);
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

/// A small xorshift stream in [0, 1) for the tests below.
fn stream(seed: u64) -> impl FnMut() -> Real {
    let mut x = seed;
    move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as Real / (1u64 << 53) as Real
    }
}

/// The least α with `dist(d, αS) ≤ αρ` by bisection on the decreasing `dist(d, αS) − αρ`,
/// with the distance written out directly (it has no cancelling square), to the last bits.
fn bisect(mut f: impl FnMut(Real) -> Real) -> Real {
    let (mut lo, mut hi) = (0.0, 1e6);
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// A unit direction through a point `y` of a feature, moved off it by about `rho` at a random
/// angle: the rays that leave K through the small ball about the feature.
fn near(y: Vec3, rho: Real, unif: &mut impl FnMut() -> Real) -> Vec3 {
    let w = Vec3::new(unif() - 0.5, unif() - 0.5, unif() - 0.5);
    (y + w * (3.0 * rho)).normalize()
}

/// Radii far below the other shape's size (the closed forms' ball-exit root cancelled there
/// when its discriminant was formed as `(d·c)² − (‖c‖² − ρ²)‖d‖²`: a sphere of radius 1e-8
/// on a unit cube's face 1.2e-8 off): sphere–box over faces, edges and corners, against
/// bisection, to 1e-13 relative, for ρ from 1e-3 to 1e-10.
#[test]
fn thin_radius_sphere_box_matches_bisection() {
    let mut unif = stream(0x2545_F491_4F6C_DD1D);
    let id = Mat3::identity();
    for k in 0..6000 {
        let rho = [1e-3, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10][k % 6];
        let h = Vec3::new(0.2 + unif(), 0.2 + unif(), 0.2 + unif());
        // A point on a face (one coordinate at ±h), an edge (two) or a corner (three).
        let mut y = Vec3::from_fn(|j, _| (2.0 * unif() - 1.0) * h[j]);
        for j in 0..=(k / 6) % 3 {
            let j = (j + k / 18) % 3;
            y[j] = h[j].copysign(y[j]);
        }
        let d = near(y, rho, &mut unif);
        let hit = sphere_box(&d, &id, &h, rho).unwrap();
        let truth = bisect(|a| {
            let e = Vec3::from_fn(|j, _| (d[j].abs() - a * h[j]).max(0.0));
            e.norm() - a * rho
        });
        let err = (hit.alpha - truth).abs() / truth;
        assert!(
            err <= 1e-13,
            "rho {rho}, h {h:?}, d {d:?}: {} vs {truth} ({err:e})",
            hit.alpha
        );
    }
}

/// The same for a sphere against a solid of revolution: a cylinder's rim and a cone's apex and
/// base rim, through `sphere_revolution`'s plane problem.
#[test]
fn thin_radius_sphere_revolution_matches_bisection() {
    let mut unif = stream(0x9E37_79B9_7F4A_7C15 ^ 77);
    let id = Mat3::identity();
    for k in 0..6000 {
        let rho = [1e-3, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10][k % 6];
        let (h, r) = (0.2 + unif(), 0.2 + unif());
        let cone = k % 2 == 1;
        let section: Vec<(Real, Real)> = if cone {
            vec![(-0.75 * h, 0.0), (0.25 * h, -r), (0.25 * h, r)]
        } else {
            vec![(-h, -r), (h, -r), (h, r), (-h, r)]
        };
        // A vertex of the section, turned about the axis.
        let (ya, yr) = section[(k / 2) % section.len()];
        let phi = std::f64::consts::TAU * unif();
        let y = Vec3::new(ya, yr * phi.cos(), yr * phi.sin());
        let d = near(y, rho, &mut unif);
        let hit = sphere_revolution(&d, &id, &section, rho).unwrap();
        let (pa, pr) = (d.x, d.y.hypot(d.z));
        let truth = bisect(|a| {
            let dist = if cone {
                // Distance to the scaled triangle: zero inside, else the nearest edge.
                let v: Vec<(Real, Real)> = section.iter().map(|&(x, y)| (a * x, a * y)).collect();
                let mut best = Real::INFINITY;
                let mut inside = true;
                for i in 0..3 {
                    let (p0, p1) = (v[i], v[(i + 1) % 3]);
                    let (ex, ey) = (p1.0 - p0.0, p1.1 - p0.1);
                    let (wx, wy) = (pa - p0.0, pr - p0.1);
                    if ex * wy - ey * wx < 0.0 {
                        inside = false;
                    }
                    let s = ((ex * wx + ey * wy) / (ex * ex + ey * ey)).clamp(0.0, 1.0);
                    best = best.min((wx - s * ex).hypot(wy - s * ey));
                }
                if inside {
                    0.0
                } else {
                    best
                }
            } else {
                (pa.abs() - a * h).max(0.0).hypot((pr - a * r).max(0.0))
            };
            dist - a * rho
        });
        let err = (hit.alpha - truth).abs() / truth;
        assert!(
            err <= 1e-13,
            "rho {rho}, cone {cone}, d {d:?}: {} vs {truth} ({err:e})",
            hit.alpha
        );
    }
}

/// The same for spheres and capsules: a sphere against a capsule's end, and two capsules at
/// the parallelogram P's corners and edges. Only answers from a vertex or an edge of P are
/// compared: the others are ill-conditioned in the offset itself (a ray near a point of P runs
/// nearly in P's plane, or along a sphere's segment, and the face's `|d·m̂|/ρ` or the side's
/// `‖d × a₂‖/ρ` divides a cross or dot product of nearly parallel or orthogonal vectors, its
/// rounding included, by ρ), and a fixed share of the cases must be compared.
#[test]
fn thin_radius_rounded_segments_match_bisection() {
    let mut unif = stream(0xD1B5_4A32_D192_ED03);
    let dist_segment = |x: Vec3, p0: Vec3, p1: Vec3| {
        let e = p1 - p0;
        let n2 = e.norm_squared();
        let s = if n2 > 0.0 {
            ((x - p0).dot(&e) / n2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (x - p0 - e * s).norm()
    };
    let mut compared = [0usize; 2];
    let mut worst: Real = 0.0;
    for k in 0..6000 {
        let rho = [1e-3, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10][k % 6];
        let unit =
            |u: &mut dyn FnMut() -> Real| Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize();
        let (a1, a2) = (unit(&mut unif), unit(&mut unif));
        let h1 = if k % 2 == 0 { 0.0 } else { 0.2 + unif() };
        let h2 = 0.2 + unif();
        // P's corner s a₁ − t a₂ at (±h₁, ±h₂), or a point on one of its edges.
        let (mut s, mut t) = (h1.copysign(unif() - 0.5), h2.copysign(unif() - 0.5));
        if h1 > 0.0 && (k / 2) % 3 == 1 {
            t *= 2.0 * unif() - 1.0;
        } else if h1 > 0.0 && (k / 2) % 3 == 2 {
            s *= 2.0 * unif() - 1.0;
        }
        let d = near(a1 * s - a2 * t, rho, &mut unif);
        let one = RoundedSegment {
            axis: a1,
            half: h1,
            radius: 0.5 * rho,
        };
        let two = RoundedSegment {
            axis: a2,
            half: h2,
            radius: 0.5 * rho,
        };
        let Some(hit) = rounded_segments(&d, &one, &two) else {
            panic!("no answer for rho {rho}, d {d:?}");
        };
        let conditioned = if h1 == 0.0 {
            hit.t.abs() == h2
        } else {
            hit.s.abs() == h1 || hit.t.abs() == h2
        };
        if !conditioned {
            continue;
        }
        compared[(h1 > 0.0) as usize] += 1;
        let c = [(1.0, 1.0), (1.0, -1.0), (-1.0, -1.0), (-1.0, 1.0)]
            .map(|(i, j)| a1 * (i * h1) - a2 * (j * h2));
        let truth = bisect(|a| {
            // The distance to αP: to its plane where the foot lies inside, else to its edges.
            let m = a1.cross(&a2);
            let (g, b1, b2) = (a1.dot(&a2), d.dot(&a1), d.dot(&a2));
            let det = 1.0 - g * g;
            let (fs, ft) = ((b1 - g * b2) / det, -(b2 - g * b1) / det);
            let dist = if h1 > 0.0 && fs.abs() <= a * h1 && ft.abs() <= a * h2 {
                d.dot(&m).abs() / m.norm()
            } else {
                (0..4)
                    .map(|i| dist_segment(d, c[i] * a, c[(i + 1) % 4] * a))
                    .fold(Real::INFINITY, Real::min)
            };
            dist - a * rho
        });
        // Both sides carry the axes' rounding amplified by 1/sin²θ (θ their angle) where the
        // segments are nearly parallel.
        let sin2 = a1.cross(&a2).norm_squared();
        let err = (hit.alpha - truth).abs() / truth;
        worst = worst.max(err * sin2);
        assert!(
            err * sin2 <= 1e-13,
            "rho {rho}, h {h1} {h2}, d {d:?}, a1 {a1:?}, a2 {a2:?}, hit {hit:?}: {} vs {truth} \
             ({err:e})",
            hit.alpha
        );
    }
    eprintln!("compared {compared:?}, worst error times sin²θ {worst:e}");
    assert!(
        compared[0] >= 1000 && compared[1] >= 1500,
        "{compared:?} compared"
    );
}
