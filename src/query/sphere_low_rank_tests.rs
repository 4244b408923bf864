//! The sphere closed form's columns from a feature's `M = βI + κ₁u₁u₁ᵀ + κ₂u₂u₂ᵀ` applied term
//! by term (`super::sphere_jacobian::fill_low`) against the same closed form from the full 3×3
//! (`sphere_jacobian_as(.., dense = true)`, the form it replaced) and against central
//! differences, on random poses and on poses placed next to the features' changes (a box's
//! edges and corners, a capsule's cap circles, a cylinder's rims, a cone's apex and rim).

use super::sphere_jacobian::{sphere_jacobian, sphere_jacobian_as};
use super::test_support::{
    central_jacobian, gap, geometric_answer, hull_points, pentagon, random_polytope, Rng,
};
use crate::{jacobian, Options, Pose, Real, Shape, Vec3};

/// Points of `shape` (body frame) where its feature changes, each with a normal of a feature
/// beside it: a box's corners and edges with a face's normal, a capsule's cap circle with the
/// side's normal, a cylinder's rim with the disc's and the side's, a cone's apex with its
/// axis' and its rim with the base's and a generator's. Empty for other shapes.
fn feature_changes(shape: &Shape, rng: &mut Rng) -> Vec<(Vec3, Vec3)> {
    let mut out = Vec::new();
    let phi = rng.uniform(0.0, std::f64::consts::TAU);
    let (cp, sp) = (phi.cos(), phi.sin());
    if let Some(e) = shape.centred_box() {
        let s = [0; 3].map(|_| if rng.unit() < 0.5 { -1.0 } else { 1.0 });
        let corner = Vec3::new(s[0] * e[0], s[1] * e[1], s[2] * e[2]);
        for i in 0..3 {
            let mut a = Vec3::zeros();
            a[i] = s[i];
            out.push((corner, a));
            // The middle of an edge along axis (i + 1) % 3, with the face normal i.
            let mut edge = corner;
            edge[(i + 1) % 3] *= rng.uniform(-0.9, 0.9);
            out.push((edge, a));
        }
    } else if let Some((h, rho)) = shape.rounded_segment() {
        out.push((Vec3::new(h, rho * cp, rho * sp), Vec3::new(0.0, cp, sp)));
    } else if let Some((rho, h)) = shape.cylinder_dims() {
        let rim = Vec3::new(h, rho * cp, rho * sp);
        out.push((rim, Vec3::x()));
        out.push((rim, Vec3::new(0.0, cp, sp)));
    } else if let Some((section, _)) = shape.revolution_section() {
        let (apex, (base, rho)) = (section[0].0, section[2]);
        out.push((Vec3::new(apex, 0.0, 0.0), -Vec3::x()));
        let rim = Vec3::new(base, rho * cp, rho * sp);
        out.push((rim, Vec3::x()));
        // The generator's outward normal at the rim.
        let t = Vec3::new(base - apex, rho * cp, rho * sp).normalize();
        let radial = Vec3::new(0.0, cp, sp);
        out.push((rim, (radial - t * t.dot(&radial)).normalize()));
    }
    out
}

/// The closed form term by term and from the full `M`, where it answers (both or neither).
fn both(s: [&Shape; 2], p: [&Pose; 2]) -> Option<([[Real; 14]; 4], [[Real; 14]; 4])> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    let (mut low, mut dense) = ([[0.0; 14]; 4], [[0.0; 14]; 4]);
    let a = sphere_jacobian(&prox, &g, &dad, s, p, &mut low);
    let b = sphere_jacobian_as(&prox, &g, &dad, s, p, &mut dense, true);
    assert_eq!(a.is_some(), b.is_some());
    a.map(|_| (low, dense))
}

/// Against a box, a capsule, a cylinder, a cone, a 14-facet polytope, a 30-point hull and a
/// padded pentagon, both orders: 3 000 random poses and sphere radii, and 3 000 poses whose
/// sphere sits next to a feature change (its centre off a corner, an edge, a cap circle, a
/// rim or the apex along a normal tilted by 1e-12 to 0.3 rad from a neighbouring feature's):
/// the two forms answer on the same poses and agree within 1e-13 (non-dimensional: rounding,
/// measured below 2e-15), the public `jacobian` returns the term-by-term numbers; on about 40
/// of the random poses of each, both within 1e-6 of central differences (step 1e-6).
#[test]
fn low_rank_columns_match_the_full_matrix() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let others = [
        Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
        Shape::capsule(0.25, 0.8).unwrap(),
        Shape::cylinder(0.3, 0.9).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
        random_polytope(&mut rng),
        Shape::convex_hull(&hull_points(&mut rng), 0.0).unwrap(),
        Shape::polygon(&pentagon(), &[0.4, 0.3, 0.5, 0.35, 0.45], 0.08).unwrap(),
    ];
    let o = Options::default();
    for other in &others {
        for order in 0..2 {
            let (mut worst, mut worst_fd, mut hits, mut near_hits) = (0.0 as Real, 0.0, 0, 0);
            for k in 0..6000 {
                let ball = Shape::sphere(rng.uniform(0.05, 1.5)).unwrap();
                let radius = ball.bounding_radius();
                let (mut p1, mut p2) = (rng.pose(1.0), rng.pose(1.0));
                let near = k % 2 == 1;
                if near {
                    let changes = feature_changes(other, &mut rng);
                    if changes.is_empty() {
                        continue;
                    }
                    let (c, d0) = changes[k / 2 % changes.len()];
                    let tilt = 10f64.powf(rng.uniform(-12.0, -0.5));
                    let d = (d0 + Vec3::from(rng.direction()) * tilt).normalize();
                    // Touching at α = 1 with the centre off c along d, then scaled to α*.
                    let pb = if order == 0 { &p2 } else { &p1 };
                    let offset = pb.rotation() * (c + d * radius) * rng.uniform(0.3, 2.5);
                    let centre: [Real; 3] = (pb.position() + offset).into();
                    let moved = Pose::new(centre, rng.quaternion()).unwrap();
                    if order == 0 {
                        p1 = moved;
                    } else {
                        p2 = moved;
                    }
                }
                let s = if order == 0 {
                    [&ball, other]
                } else {
                    [other, &ball]
                };
                let Some((low, dense)) = both(s, [&p1, &p2]) else {
                    continue;
                };
                hits += 1;
                near_hits += usize::from(near);
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                worst = worst.max(gap(&low, &dense, ell));
                let (_, public) = jacobian(s[0], &p1, s[1], &p2, &o).unwrap();
                assert_eq!(public, low, "{:?} {order}", other.kind());
                // Central differences where no feature change is within their step.
                if !near && hits % 37 == 0 {
                    let fd = central_jacobian(s, [&p1, &p2], 1e-6);
                    worst_fd = worst_fd.max(gap(&low, &fd, ell).max(gap(&dense, &fd, ell)));
                }
            }
            eprintln!(
                "{:?} {order}: {hits} answered ({near_hits} near a change), worst {worst:.1e}, \
                 central differences {worst_fd:.1e}",
                other.kind()
            );
            assert!(hits > 2000, "{:?} {order}: {hits}", other.kind());
            assert!(worst < 1e-13, "{:?} {order}: {worst:e}", other.kind());
            assert!(worst_fd < 1e-6, "{:?} {order}: {worst_fd:e}", other.kind());
        }
    }
}
