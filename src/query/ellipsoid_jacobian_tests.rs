//! The two ellipsoids' closed-form Jacobian (`super::ellipsoid_jacobian`) against the general
//! feature solve and against central differences, on thousands of random ellipsoids and poses.

use super::ellipsoid_jacobian::ellipsoid_jacobian;
use super::geometric::pair_axes;
use super::test_support::{central_jacobian, gap, general_beside, geometric_answer, Rng};
use crate::math::rotation_from_quaternion;
use crate::{Pose, Real, Shape};

/// A random ellipsoid: semi-axes log-uniform in [`lo`, 1], a random attitude.
pub(super) fn ellipsoid(rng: &mut Rng, lo: Real) -> Shape {
    let q = loop {
        let q = rng.quaternion();
        if q.iter().map(|v| v * v).sum::<Real>() > 0.01 {
            break q;
        }
    };
    let rot = rotation_from_quaternion(q);
    let axes = [0; 3].map(|_| lo.powf(rng.unit()));
    let d = crate::math::Mat3::from_diagonal(&crate::Vec3::from(axes.map(|a| 1.0 / (a * a))));
    let p = rot * d * rot.transpose();
    let p = [0, 1, 2].map(|i| [0, 1, 2].map(|k| 0.5 * (p[(i, k)] + p[(k, i)])));
    Shape::ellipsoid(p).unwrap()
}

/// The closed form where it answers.
fn closed(s: [&Shape; 2], p: [&Pose; 2]) -> Option<[[Real; 14]; 4]> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    let mut j = [[0.0; 14]; 4];
    ellipsoid_jacobian(&prox, &g, &dad, s, p, &pair_axes(s, p), &mut j)?;
    Some(j)
}

/// 10 000 random pairs of ellipsoids (semi-axes 0.1–1, so up to 10:1 eccentric, radii of
/// curvature from 0.01 to 10; separated and overlapping): the closed form answers wherever the
/// geometric path does, the public `jacobian` returns its numbers with the same proximity
/// answer, and it agrees with the general feature solve to 1e-12 (non-dimensional; measured
/// 1.1e-13). Both are exact formulas of the same answer; what differs is rounding, which both
/// amplify by the support Hessians' spread (the reduced system's conditioning), here at most
/// ~1e3: 1e-12 is that times a few ulps.
#[test]
fn ellipsoid_closed_form_matches_the_feature_solve() {
    let mut rng = Rng(0x6a09_e667_f3bc_c908);
    let (mut worst, mut hits, mut answered): (Real, usize, usize) = (0.0, 0, 0);
    let total = 10_000;
    for _ in 0..total {
        let e1 = ellipsoid(&mut rng, 0.1);
        let e2 = ellipsoid(&mut rng, 0.1);
        let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
        let s = [&e1, &e2];
        if geometric_answer(s, [&p1, &p2]).is_none() {
            continue;
        }
        answered += 1;
        let Some(jc) = closed(s, [&p1, &p2]) else {
            continue;
        };
        hits += 1;
        let general = general_beside([&e1, &e2], [&p1, &p2], &jc);
        let ell = e1.bounding_radius().max(e2.bounding_radius());
        worst = worst.max(gap(&jc, &general, ell));
    }
    eprintln!("ellipsoid pair: {hits} of {answered} answered, worst {worst:e}");
    assert!(
        hits == answered && hits * 10 >= total * 9,
        "{hits} of {answered}"
    );
    assert!(worst < 1e-12, "{worst:e}");
}

/// Central differences of proximity (step 1e-6, the quaternion's four components moved one at
/// a time) against the closed form on 300 random pairs: within 1e-6 (non-dimensional), the
/// differences' own truncation error.
#[test]
fn ellipsoid_closed_form_matches_central_differences() {
    let mut rng = Rng(0xbb67_ae85_84ca_a73b);
    let mut checked = 0;
    for _ in 0..300 {
        let e1 = ellipsoid(&mut rng, 0.3);
        let e2 = ellipsoid(&mut rng, 0.3);
        let (p1, p2) = (rng.pose(1.0), rng.pose(1.0));
        let Some(jc) = closed([&e1, &e2], [&p1, &p2]) else {
            continue;
        };
        checked += 1;
        let ell = e1.bounding_radius().max(e2.bounding_radius());
        let fd = central_jacobian([&e1, &e2], [&p1, &p2], 1e-6);
        let e = gap(&jc, &fd, ell);
        assert!(e < 1e-6, "{e:e}");
    }
    assert!(checked >= 290, "{checked}");
}
