//! The closed-form Jacobian of a capsule touching by a cap, or a box by a vertex
//! (`super::ball_jacobian`), against the general feature solve and central differences, on
//! thousands of random poses and dimensions per pair, both orders.

use super::ball_jacobian::ball_jacobian;
use super::geometric::pair_axes;
use super::test_support::{central_jacobian, gap, general_beside, geometric_answer, Rng};
use crate::{Pose, Real, Shape};

/// The closed form where it answers.
fn closed(s: [&Shape; 2], p: [&Pose; 2]) -> Option<[[Real; 14]; 4]> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    let mut j = [[0.0; 14]; 4];
    ball_jacobian(&prox, &g, &dad, s, p, &pair_axes(s, p), &mut j)?;
    Some(j)
}

/// A random capsule (radius 0.05–0.6, length 0.05–2) or box (half extents 0.05–0.8).
fn ball_shape(rng: &mut Rng, capsule: bool) -> Shape {
    if capsule {
        Shape::capsule(rng.uniform(0.05, 0.6), rng.uniform(0.05, 2.0)).unwrap()
    } else {
        let e = [0; 3].map(|_| rng.uniform(0.05, 0.8));
        Shape::cuboid(e[0], e[1], e[2]).unwrap()
    }
}

/// The sphere tests' mildly eccentric ellipsoid.
fn ellipsoid() -> Shape {
    Shape::ellipsoid([[1.5, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap()
}

/// The pairs the closed form takes: a capsule against a box, a cylinder, a cone and an
/// and a box against a box, a cylinder and a cone (the other shape fixed, the
/// capsule or box random).
fn pairs() -> Vec<(bool, Shape)> {
    vec![
        (true, Shape::cuboid(0.5, 0.35, 0.25).unwrap()),
        (true, Shape::cylinder(0.3, 0.9).unwrap()),
        (true, Shape::cone(1.0, 0.5).unwrap()),
        (true, ellipsoid()),
        (false, Shape::cuboid(0.5, 0.35, 0.25).unwrap()),
        (false, Shape::cylinder(0.3, 0.9).unwrap()),
        (false, Shape::cone(1.0, 0.5).unwrap()),
        (false, ellipsoid()),
    ]
}

/// On each pair in both orders, 3 000 random poses and dimensions (separated and
/// overlapping): wherever the closed form answers the general feature solve answers too, the
/// two agree to 1e-12 (non-dimensional), and the public `jacobian` returns the closed form's
/// numbers with the same proximity answer; the closed form answers on at least 300 poses of
/// each (a tenth: a box's vertex touches a cylinder on ~14 % of them, a cap or a vertex
/// touches on about half of the other pairs' poses).
#[test]
fn ball_closed_form_matches_the_feature_solve() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for (capsule, other) in &pairs() {
        for order in 0..2 {
            let (mut worst, mut hits, mut answered): (Real, usize, usize) = (0.0, 0, 0);
            for _ in 0..3000 {
                let ball = ball_shape(&mut rng, *capsule);
                let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                let s = if order == 0 {
                    [&ball, other]
                } else {
                    [other, &ball]
                };
                if geometric_answer(s, [&p1, &p2]).is_none() {
                    continue;
                }
                answered += 1;
                let Some(jc) = closed(s, [&p1, &p2]) else {
                    continue;
                };
                hits += 1;
                let general = general_beside([s[0], s[1]], [&p1, &p2], &jc);
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                // Relative to the Jacobian's size, as the capsules' test.
                let size = jc.iter().flatten().fold(1.0, |m: Real, v| m.max(v.abs()));
                worst = worst.max(gap(&jc, &general, ell) / size);
            }
            let kind = other.kind();
            eprintln!("{capsule} {kind:?} {order}: {hits} of {answered}, worst {worst:.1e}");
            assert!(hits >= 300 && answered > 2500, "{kind:?} {order}");
            assert!(worst < 1e-12, "{capsule} {kind:?} {order}: {worst:e}");
        }
    }
}

/// Against central differences of the public proximity (step 1e-6) on 100 poses of each pair
/// and order where the closed form answers: within 1e-6 (non-dimensional).
#[test]
fn ball_closed_form_matches_central_differences() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for (capsule, other) in &pairs() {
        for order in 0..2 {
            let mut checked = 0;
            for _ in 0..2000 {
                let ball = ball_shape(&mut rng, *capsule);
                let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
                let s = if order == 0 {
                    [&ball, other]
                } else {
                    [other, &ball]
                };
                let Some(jc) = closed(s, [&p1, &p2]) else {
                    continue;
                };
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                let fd = central_jacobian(s, [&p1, &p2], 1e-6);
                let e = gap(&jc, &fd, ell);
                assert!(e < 1e-6, "{capsule} {:?} {order}: {e:e}", other.kind());
                checked += 1;
                if checked == 100 {
                    break;
                }
            }
            assert!(
                checked == 100,
                "{capsule} {:?} {order}: {checked}",
                other.kind()
            );
        }
    }
}
