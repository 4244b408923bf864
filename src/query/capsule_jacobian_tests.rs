//! The two capsules' closed-form Jacobian (`super::capsule_jacobian`) against the general
//! feature solve and against central differences, on thousands of random poses, radii and
//! lengths.

use super::capsule_jacobian::capsule_jacobian;
use super::geometric::pair_axes;
use super::test_support::{central_jacobian, gap, general_beside, geometric_answer, Rng};
use crate::{Pose, Real, Shape};

/// Which part of each capsule its contact point (world) lies on: its side (true) or a cap.
fn sides(s: [&Shape; 2], p: [&Pose; 2], c: [&crate::Vec3; 2]) -> [bool; 2] {
    [0, 1].map(|i| {
        let (h, _) = s[i].rounded_segment().unwrap();
        let b = p[i].rotation().tr_mul(&(c[i] - p[i].position()));
        b.x.abs() < h - 1e-9
    })
}

/// The closed form where it answers, with the touching parts (sides or caps).
fn closed(s: [&Shape; 2], p: [&Pose; 2]) -> Option<([[Real; 14]; 4], [bool; 2])> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    let mut j = [[0.0; 14]; 4];
    capsule_jacobian(&prox, &g, &dad, s, p, &pair_axes(s, p), &mut j)?;
    Some((j, sides(s, p, [&prox.contact1, &prox.contact2])))
}

/// 10 000 random pairs of capsules (radii 0.05–0.6, lengths 0.05–2, separated and overlapping;
/// a tenth of them with axes within 1e-3 rad of parallel): wherever the closed form answers (at
/// least 97 % of the pairs) the general feature solve answers too, the two agree to 1e-12
/// (non-dimensional, relative to the largest entry or 1), and the public `jacobian` returns the
/// closed form's numbers with the same proximity answer; each combination of side and cap
/// contacts is met at least 100 times.
///
/// Relative, because two sides at an angle θ have entries up to ~1/(α* sin²θ) (the closest
/// points of nearly parallel lines move fast), and so does the rounding of the contact point
/// the closed form starts from: on the worst pair of this test (sin θ = 0.06, α* = 4.1, entries
/// up to 439), against central differences of step 1e-25 in 60-digit arithmetic of the two
/// lines' closed form, the closed form is 1.9e-11 off (4e-14 relative: the contact
/// parameter t carries 2.6e-14 relative, the conditioning 1/sin²θ = 264 times the rounding),
/// the feature solve, which refines the point by Newton first, 1.9e-12.
#[test]
fn capsule_closed_form_matches_the_feature_solve() {
    let mut rng = Rng(0x41c6_4e6d_a3bc_0074);
    let (mut worst, mut hits, total): (Real, usize, usize) = (0.0, 0, 10_000);
    let mut seen = [[0usize; 2]; 2];
    for k in 0..total {
        let c1 = Shape::capsule(rng.uniform(0.05, 0.6), rng.uniform(0.05, 2.0)).unwrap();
        let c2 = Shape::capsule(rng.uniform(0.05, 0.6), rng.uniform(0.05, 2.0)).unwrap();
        let p1 = rng.pose(1.0);
        let p2 = if k % 10 == 0 {
            // Nearly parallel axes: shape 1's attitude turned by up to 1e-3 rad.
            let q = p1.quaternion();
            let tilt = [0; 3].map(|_| rng.uniform(-5e-4, 5e-4));
            let qq = [
                q[0] - tilt[0] * q[1] - tilt[1] * q[2] - tilt[2] * q[3],
                q[1] + tilt[0] * q[0],
                q[2] + tilt[1] * q[0],
                q[3] + tilt[2] * q[0],
            ];
            let r = [0; 3].map(|_| rng.uniform(-1.0, 1.0));
            Pose::new(r, qq).unwrap()
        } else {
            rng.pose(1.0)
        };
        let s = [&c1, &c2];
        let Some((jc, part)) = closed(s, [&p1, &p2]) else {
            continue;
        };
        hits += 1;
        seen[usize::from(part[0])][usize::from(part[1])] += 1;
        let general = general_beside([&c1, &c2], [&p1, &p2], &jc);
        let ell = c1.bounding_radius().max(c2.bounding_radius());
        // Relative to the Jacobian's size: nearly parallel sides have entries ~1/(α sin²θ).
        let size = jc.iter().flatten().fold(1.0, |m: Real, v| m.max(v.abs()));
        let e = gap(&jc, &general, ell) / size;
        worst = worst.max(e);
    }
    assert!(hits * 100 >= total * 97, "{hits}");
    for row in seen {
        for n in row {
            assert!(n >= 100, "{seen:?}");
        }
    }
    eprintln!("capsule closed form against the feature solve: worst {worst:e} ({hits} of {total})");
    assert!(worst < 1e-12, "{worst:e}");
}

/// Central differences of proximity (step 1e-6, the quaternion's four components moved one at
/// a time) against the closed form on 400 random pairs where it answers: within 1e-6
/// (non-dimensional), the differences' own truncation error.
#[test]
fn capsule_closed_form_matches_central_differences() {
    let mut rng = Rng(0x9d2c_5680_1b87_3f11);
    let mut checked = 0;
    for _ in 0..400 {
        let c1 = Shape::capsule(rng.uniform(0.05, 0.6), rng.uniform(0.05, 2.0)).unwrap();
        let c2 = Shape::capsule(rng.uniform(0.05, 0.6), rng.uniform(0.05, 2.0)).unwrap();
        let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
        let Some((jc, _)) = closed([&c1, &c2], [&p1, &p2]) else {
            continue;
        };
        checked += 1;
        let ell = c1.bounding_radius().max(c2.bounding_radius());
        let fd = central_jacobian([&c1, &c2], [&p1, &p2], 1e-6);
        let e = gap(&jc, &fd, ell);
        assert!(e < 1e-6, "{e:e}");
    }
    assert!(checked >= 380, "{checked}");
}
