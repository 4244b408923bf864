//! An ellipsoid against an edge in closed form (`super::edge_jacobian`, reached through
//! `super::face_jacobian`) against the general feature solve and central differences: random
//! ellipsoids against a box, a 14-facet polytope and a 30-point hull, both orders.

use super::ellipsoid_jacobian_tests::ellipsoid;
use super::face_jacobian::{face_jacobian, touching_feature, Touch};
use super::geometric::pair_axes;
use super::test_support::{
    central_jacobian, gap, general_beside, geometric_answer, hull_points, random_polytope, Rng,
};
use super::vertex_feature::TIE;
use crate::{Pose, Real, Shape, Vec3};

/// Whether the shape other than the ellipsoid (`shapes[b]`) touches by an edge, as the closed
/// form decides it.
fn touches_by_edge(dad: &Vec3, s: [&Shape; 2], p: [&Pose; 2], b: usize) -> bool {
    let nu = dad.normalize();
    let out = if b == 0 { nu } else { -nu };
    let ell = s[0].bounding_radius().max(s[1].bounding_radius());
    matches!(
        touching_feature(s[b], p[b], &out, TIE * ell),
        Some(Touch::Edge(_))
    )
}

/// The edge closed form's answer, where the pose is an edge contact and it answers.
fn edge(s: [&Shape; 2], p: [&Pose; 2], b: usize) -> Option<[[Real; 14]; 4]> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    if !touches_by_edge(&dad, s, p, b) {
        return None;
    }
    let mut j = [[0.0; 14]; 4];
    face_jacobian(&prox, &g, &dad, s, p, &pair_axes(s, p), &mut j)?;
    Some(j)
}

/// The box, polytope and hull the ellipsoids are paired with.
fn flats(rng: &mut Rng) -> Vec<Shape> {
    vec![
        Shape::cuboid(0.45, 0.3, 0.2).unwrap(),
        random_polytope(rng),
        Shape::convex_hull(&hull_points(rng), 0.0).unwrap(),
    ]
}

/// 3 000 random poses of a random ellipsoid (semi-axes 0.15–1, a new one per pose) against a
/// box, a 14-facet polytope and a 30-point hull, both orders: wherever the contact is an edge,
/// the closed form answers (every such pose), the public `jacobian` returns its numbers with
/// the same proximity answer, and it agrees with the general feature solve within 1e-12
/// relative to the Jacobian's size (non-dimensional); the edge is the contact on at least a
/// fifth of the answered poses.
#[test]
fn edge_closed_form_matches_the_feature_solve() {
    let mut rng = Rng(0x3c6e_f372_fe94_f82b);
    let flat = flats(&mut rng);
    let mut worst_all: Real = 0.0;
    for (fi, f) in flat.iter().enumerate() {
        for b in 0..2 {
            let (mut worst, mut edges, mut answered): (Real, usize, usize) = (0.0, 0, 0);
            for _ in 0..3000 {
                let e = ellipsoid(&mut rng, 0.15);
                let s = if b == 0 { [f, &e] } else { [&e, f] };
                let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                let Some((_, dad, _)) = geometric_answer(s, [&p1, &p2]) else {
                    continue;
                };
                answered += 1;
                if !touches_by_edge(&dad, s, [&p1, &p2], b) {
                    continue;
                }
                let jc = edge(s, [&p1, &p2], b).expect("an edge contact the closed form takes");
                edges += 1;
                let general = general_beside(s, [&p1, &p2], &jc);
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                let size = jc.iter().flatten().fold(1.0, |m: Real, v| m.max(v.abs()));
                worst = worst.max(gap(&jc, &general, ell) / size);
            }
            eprintln!("{fi} flat as shape {b}: {edges} edges of {answered}, worst {worst:.1e}");
            assert!(edges * 5 >= answered && answered > 2000, "{fi} {b}");
            worst_all = worst_all.max(worst);
        }
    }
    eprintln!("worst {worst_all:.1e}");
    assert!(worst_all < 1e-12, "{worst_all:e}");
}

/// Against central differences of the public proximity (step 1e-6) on 60 edge contacts of each
/// shape and order of the test above (semi-axes 0.3–1): within 1e-6 (non-dimensional).
#[test]
fn edge_closed_form_matches_central_differences() {
    let mut rng = Rng(0xa54f_f53a_5f1d_36f1);
    let flat = flats(&mut rng);
    for (fi, f) in flat.iter().enumerate() {
        for b in 0..2 {
            let mut checked = 0;
            for _ in 0..2000 {
                let e = ellipsoid(&mut rng, 0.3);
                let s = if b == 0 { [f, &e] } else { [&e, f] };
                let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                let Some(jc) = edge(s, [&p1, &p2], b) else {
                    continue;
                };
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                let err = gap(&jc, &central_jacobian(s, [&p1, &p2], 1e-6), ell);
                assert!(err < 1e-6, "{fi} {b}: {err:e}");
                checked += 1;
                if checked == 60 {
                    break;
                }
            }
            assert!(checked == 60, "{fi} {b}: {checked}");
        }
    }
}
