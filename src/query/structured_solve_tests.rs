//! The general feature solve's reduced system (`crate::solver::sensitivity`) against the full
//! system it replaced (kept for the tests), through `geometric::jacobian` with the closed forms
//! switched off, on random and near-degenerate poses of every ordered pair of kinds.

use super::geometric::{self, GENERAL_ONLY};
use super::test_support::{geometric_answer, hull_points, pentagon, random_polytope, Rng};
use crate::solver::sensitivity::dense_reference::{DENSE, LARGEST_HESSIAN};
use crate::{Pose, Real, Shape};

fn shapes(rng: &mut Rng) -> Vec<Shape> {
    let polytope = random_polytope(rng);
    let pts = hull_points(rng);
    let c = pentagon();
    vec![
        Shape::sphere(0.5).unwrap(),
        Shape::ellipsoid([[1.5, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap(),
        Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
        polytope,
        Shape::capsule(0.25, 0.8).unwrap(),
        Shape::cylinder(0.3, 0.9).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
        Shape::polygon(&c, &[0.5; 5], 0.08).unwrap(),
        Shape::convex_hull(&pts, 0.05).unwrap(),
    ]
}

/// A quaternion near one of the 24 axis-aligned attitudes (or their half-way turns), tilted by
/// an angle between 1e-9 and 1e-2: faces and edges nearly parallel to the other shape's.
fn near_aligned(rng: &mut Rng) -> [Real; 4] {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let base = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
        [h, h, 0.0, 0.0],
        [h, 0.0, h, 0.0],
        [h, 0.0, 0.0, h],
        [0.5, 0.5, 0.5, 0.5],
    ][(rng.unit() * 8.0) as usize];
    let tilt = 10.0_f64.powf(rng.uniform(-9.0, -2.0));
    base.map(|x| x + tilt * rng.uniform(-1.0, 1.0))
}

/// The Jacobian of the general feature solve at the geometric answer of `s` at `p`, by the
/// reduced system or (`dense`) the full one; `None` where it does not answer.
fn general(s: [&Shape; 2], p: [&Pose; 2], dense: bool) -> Option<[[Real; 14]; 4]> {
    let (prox, dad, g) = geometric_answer(s, p)?;
    GENERAL_ONLY.with(|f| f.set(true));
    DENSE.with(|f| f.set(dense));
    let j = geometric::jacobian(&prox, &dad, &g, s, p);
    DENSE.with(|f| f.set(false));
    GENERAL_ONLY.with(|f| f.set(false));
    j
}

/// On 200 poses of every ordered pair of nine kinds (half of them random, half with both
/// attitudes near axis-aligned ones and the offset along an axis: near ties of faces and edges),
/// the reduced system answers where the full one does and its Jacobian is the full one's to
/// 1e-12 relative to the Jacobian's largest entry (non-dimensional: r columns times ℓ, x rows
/// over ℓ), times the largest entry of the features' weighted Hessian where that exceeds one
/// (both solves' rounding is amplified by it: 30 of 16 166 poses, near-aligned rims with
/// Hessians 5e3 to 1.4e6, differ by 1e-12 to 4.6e-10, at most 4e-16 of their Hessian).
#[test]
fn reduced_system_matches_the_full_one() {
    let mut rng = Rng(0x005e_ed0f_2ed0_ced5);
    let kinds = shapes(&mut rng);
    let (mut compared, mut degenerate, mut amplified, mut worst) = (0, 0, 0, 0.0 as Real);
    for a in &kinds {
        for b in &kinds {
            let ell = a.bounding_radius().max(b.bounding_radius());
            for k in 0..200 {
                let near = k % 2 == 1;
                let (q1, q2) = if near {
                    (near_aligned(&mut rng), near_aligned(&mut rng))
                } else {
                    (rng.quaternion(), rng.quaternion())
                };
                let d = if near {
                    let mut d = [0.0; 3];
                    d[(rng.unit() * 3.0) as usize] = if rng.unit() < 0.5 { -1.0 } else { 1.0 };
                    d.map(|x| x + 1e-3 * rng.uniform(-1.0, 1.0))
                } else {
                    rng.direction()
                };
                let dist = rng.uniform(0.3, 2.5) * (a.bounding_radius() + b.bounding_radius());
                let p1 = Pose::new([0.1, -0.2, 0.3], q1).unwrap();
                let p2 = Pose::new(
                    [0.1 + d[0] * dist, -0.2 + d[1] * dist, 0.3 + d[2] * dist],
                    q2,
                )
                .unwrap();
                let full = general([a, b], [&p1, &p2], true);
                LARGEST_HESSIAN.with(|c| c.set(0.0));
                let reduced = general([a, b], [&p1, &p2], false);
                let amplification = LARGEST_HESSIAN.with(|c| c.get()).max(1.0);
                let (Some(f), Some(r)) = (full, reduced) else {
                    assert_eq!(
                        full.is_some(),
                        reduced.is_some(),
                        "{a:?} {b:?} {p1:?} {p2:?}"
                    );
                    continue;
                };
                let mut size: Real = 1.0;
                let mut diff: Real = 0.0;
                for row in 0..4 {
                    for col in 0..14 {
                        let s =
                            if col % 7 < 3 { ell } else { 1.0 } / if row < 3 { ell } else { 1.0 };
                        size = size.max(f[row][col].abs() * s);
                        diff = diff.max((f[row][col] - r[row][col]).abs() * s);
                    }
                }
                let rel = diff / size;
                // Within 1e-12, times the rounding's amplification where the features' Hessian is
                // large (a rim seen nearly along its axis: up to ~1e6 here, both solves then
                // differ by ~1e-16 of it).
                assert!(
                    rel <= 1e-12 * amplification,
                    "{rel:e} (size {size:e}, Hessian {amplification:e}): {a:?} {b:?} {p1:?} {p2:?}"
                );
                amplified += usize::from(rel > 1e-12);
                worst = worst.max(rel);
                compared += 1;
                degenerate += usize::from(near);
            }
        }
    }
    eprintln!(
        "reduced against full: {compared} compared ({degenerate} near-aligned), worst {worst:.1e}, \
         {amplified} beyond 1e-12 (all with a Hessian above 1e3)"
    );
    assert!(compared > 81 * 200 / 2, "{compared}");
    assert!(degenerate > 81 * 100 / 4, "{degenerate}");
}
