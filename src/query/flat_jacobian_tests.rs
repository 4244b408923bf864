//! The closed-form Jacobians on shapes made of vertices (a box, a 14-facet polytope, a 30-point
//! hull, a padded pentagon: `super::vertex_feature`), through the public dispatch, against the
//! general feature solve and central differences: a sphere against each
//! (`super::sphere_jacobian`), a vertex as a ball (`super::ball_jacobian`), an edge as a
//! segment (`super::segment_jacobian`), a face against an ellipsoid (`super::face_jacobian`).

use super::geometric::{jacobian_into, Formed};
use super::test_support::{
    central_jacobian, gap, general_beside, geometric_answer, hull_points, pentagon,
    random_polytope, Rng,
};
use crate::{Pose, Real, Shape};

/// The dispatch's answer where a closed form gave it.
fn closed(s: [&Shape; 2], p: [&Pose; 2]) -> Option<[[Real; 14]; 4]> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    let mut j = [[0.0; 14]; 4];
    let formed = jacobian_into(&prox, &dad, &g, s, p, &mut j)?;
    (formed == Formed::Closed).then_some(j)
}

/// The shapes made of vertices, then the others they are paired with.
fn shapes(rng: &mut Rng) -> (Vec<Shape>, Vec<Shape>) {
    let flat = vec![
        Shape::cuboid(0.45, 0.3, 0.2).unwrap(),
        random_polytope(rng),
        Shape::convex_hull(&hull_points(rng), 0.0).unwrap(),
        Shape::polygon(&pentagon(), &[0.5; 5], 0.08).unwrap(),
    ];
    let others = vec![
        Shape::sphere(0.4).unwrap(),
        Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
        Shape::capsule(0.25, 0.8).unwrap(),
        Shape::cylinder(0.3, 0.9).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
        Shape::ellipsoid([[1.5, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap(),
    ];
    (flat, others)
}

/// Every shape made of vertices (and a box) against itself, the others made of vertices, and a
/// sphere, a box, a capsule, a cylinder, a cone and an ellipsoid, both orders, 1 500 random
/// poses each: wherever a closed form answers the general feature solve answers too, the two
/// agree to 1e-12 (non-dimensional, relative to the Jacobian's largest entry or 1; measured
/// 6.2e-13), and the public `jacobian` returns the closed form's numbers with the same
/// proximity answer; a closed form answers on at least a tenth of each pair's poses (a cone or
/// a cylinder touches by its rim or side on most, which only the general solve takes).
#[test]
fn flat_closed_forms_match_the_feature_solve() {
    let mut rng = Rng(0x6a09_e667_f3bc_c908);
    let (flat, others) = shapes(&mut rng);
    let mut worst_all: Real = 0.0;
    for (fi, f) in flat.iter().enumerate() {
        for o in flat[fi..].iter().chain(others.iter()) {
            for order in 0..2 {
                let s = if order == 0 { [f, o] } else { [o, f] };
                let (mut worst, mut hits, mut answered): (Real, usize, usize) = (0.0, 0, 0);
                for _ in 0..1500 {
                    let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                    if geometric_answer(s, [&p1, &p2]).is_none() {
                        continue;
                    }
                    answered += 1;
                    let Some(jc) = closed(s, [&p1, &p2]) else {
                        continue;
                    };
                    hits += 1;
                    let general = general_beside(s, [&p1, &p2], &jc);
                    let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                    // Relative to the Jacobian's size: nearly parallel edges have entries up
                    // to ~100.
                    let size = jc.iter().flatten().fold(1.0, |m: Real, v| m.max(v.abs()));
                    worst = worst.max(gap(&jc, &general, ell) / size);
                }
                let k = [s[0].kind(), s[1].kind()];
                eprintln!("{fi} {k:?}: {hits} of {answered}, worst {worst:.1e}");
                assert!(hits * 10 >= answered && answered > 1000, "{fi} {k:?}");
                worst_all = worst_all.max(worst);
            }
        }
    }
    eprintln!("worst {worst_all:.1e}");
    assert!(worst_all < 1e-12, "{worst_all:e}");
    // A padded hull is not taken (`super::vertex_feature`).
    let padded = Shape::convex_hull(&hull_points(&mut rng), 0.1).unwrap();
    let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
    let s = [&padded, &others[0]];
    assert!(geometric_answer(s, [&p1, &p2]).is_some() && closed(s, [&p1, &p2]).is_none());
}

/// Against central differences of the public proximity (step 1e-6) on 20 poses of each pair
/// and order of the test above where a closed form answers: within 1e-6 (non-dimensional).
#[test]
fn flat_closed_forms_match_central_differences() {
    let mut rng = Rng(0xbb67_ae85_84ca_a73b);
    let (flat, others) = shapes(&mut rng);
    for (fi, f) in flat.iter().enumerate() {
        for o in flat[fi..].iter().chain(others.iter()) {
            for order in 0..2 {
                let s = if order == 0 { [f, o] } else { [o, f] };
                let mut checked = 0;
                for _ in 0..1000 {
                    let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                    let Some(jc) = closed(s, [&p1, &p2]) else {
                        continue;
                    };
                    let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                    let e = gap(&jc, &central_jacobian(s, [&p1, &p2], 1e-6), ell);
                    assert!(e < 1e-6, "{fi} {:?} {:?}: {e:e}", s[0].kind(), s[1].kind());
                    checked += 1;
                    if checked == 20 {
                        break;
                    }
                }
                assert!(checked == 20, "{fi} {:?} {:?}", s[0].kind(), s[1].kind());
            }
        }
    }
}
