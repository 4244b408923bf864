//! The polytope closed-form Jacobian (`super::polytope_jacobian`) against the general feature
//! solve and against central differences, on random poses of boxes, polytopes and hulls.

use super::context::Options;
use super::geometric::GENERAL_ONLY;
use super::test_support::{gap, hull_points, random_polytope, Rng};
use crate::{jacobian, proximity, DerivativeKind, Pose, Real, Shape};

fn shapes(rng: &mut Rng) -> Vec<Shape> {
    let polytope = random_polytope(rng);
    let pts = hull_points(rng);
    vec![
        Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
        polytope,
        Shape::convex_hull(&pts, 0.0).unwrap(),
    ]
}

/// Random poses of a pair with α* in [0.5, 2].
fn poses(a: &Shape, b: &Shape, rng: &mut Rng) -> (Pose, Pose) {
    let (q1, q2) = (rng.quaternion(), rng.quaternion());
    let d = rng.direction();
    let p1 = Pose::new([0.1, -0.2, 0.3], q1).unwrap();
    let trial = d.map(|x| x * (a.bounding_radius() + b.bounding_radius()));
    let r2 = |t: [Real; 3]| [t[0] + 0.1, t[1] - 0.2, t[2] + 0.3];
    let alpha = proximity(
        a,
        &p1,
        b,
        &Pose::new(r2(trial), q2).unwrap(),
        &Options::default(),
    )
    .unwrap()
    .alpha;
    let target = rng.uniform(0.5, 2.0);
    (
        p1,
        Pose::new(r2(trial.map(|x| x * target / alpha)), q2).unwrap(),
    )
}

/// On 2 000 random poses of every ordered pair of a box, a polytope and a hull, wherever the
/// closed form answers (the contact a vertex against a face or an edge against an edge: at
/// least 90 % of the poses) it agrees with the general feature solve to 1e-9 (non-dimensional),
/// and the public `jacobian` returns it, labelled exact.
#[test]
fn polytope_closed_form_matches_the_feature_solve() {
    let mut rng = Rng(0x7a3c_55e1_0d9b_4f27);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let mut worst: Real = 0.0;
    for a in &kinds {
        for b in &kinds {
            let ell = a.bounding_radius().max(b.bounding_radius());
            let (mut answered, mut total) = (0, 0);
            for _ in 0..2000 {
                let (p1, p2) = poses(a, b, &mut rng);
                let closed = jacobian(a, &p1, b, &p2, &o).unwrap();
                GENERAL_ONLY.with(|f| f.set(true));
                let general = jacobian(a, &p1, b, &p2, &o);
                GENERAL_ONLY.with(|f| f.set(false));
                let general = general.unwrap();
                total += 1;
                if closed.0.derivatives != DerivativeKind::Exact
                    || general.0.derivatives != DerivativeKind::Exact
                {
                    continue;
                }
                answered += 1;
                let g = gap(&closed.1, &general.1, ell);
                assert!(g <= 1e-9, "gap {g:e} at {p1:?} {p2:?}");
                worst = worst.max(g);
            }
            assert!(answered * 10 >= total * 9, "{answered} of {total}");
        }
    }
    eprintln!("closed form against the feature solve: worst {worst:.1e}");
}

/// Central differences of α* and x* along every pose coordinate (raw quaternion components
/// included) on 300 random poses per ordered pair: within 1e-6 (non-dimensional, step 1e-6),
/// on at least 80 % of the poses (the others: an exact-derivative answer is not available, or
/// the solver changes inside the stencil).
#[test]
fn polytope_closed_form_matches_central_differences() {
    let mut rng = Rng(0x1d2e_3f40_5a6b_7c8d);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let coords = |p: &Pose| {
        let r = p.position();
        let q = p.quaternion();
        [r.x, r.y, r.z, q[0], q[1], q[2], q[3]]
    };
    let with = |c: [Real; 7]| Pose::new([c[0], c[1], c[2]], [c[3], c[4], c[5], c[6]]).unwrap();
    let mut worst: Real = 0.0;
    let (mut compared, mut cases) = (0, 0);
    for a in &kinds {
        for b in &kinds {
            let ell = a.bounding_radius().max(b.bounding_radius());
            for _ in 0..300 {
                cases += 1;
                let (p1, p2) = poses(a, b, &mut rng);
                let (prox, j) = jacobian(a, &p1, b, &p2, &o).unwrap();
                if prox.derivatives != DerivativeKind::Exact {
                    continue;
                }
                let h = 1e-6;
                let mut fd = [[0.0; 14]; 4];
                let mut smooth = true;
                for col in 0..14 {
                    let (i, k) = (col / 7, col % 7);
                    let mut plus = [coords(&p1), coords(&p2)];
                    let mut minus = plus;
                    let step = if k < 3 { h * ell } else { h };
                    plus[i][k] += step;
                    minus[i][k] -= step;
                    let f =
                        |c: [[Real; 7]; 2]| proximity(a, &with(c[0]), b, &with(c[1]), &o).unwrap();
                    let (up, down) = (f(plus), f(minus));
                    // A feature change inside the stencil (measure zero, but it happens).
                    if up.solver != prox.solver || down.solver != prox.solver {
                        smooth = false;
                    }
                    fd[3][col] = (up.alpha - down.alpha) / (2.0 * step);
                    for r in 0..3 {
                        fd[r][col] = (up.point[r] - down.point[r]) / (2.0 * step);
                    }
                }
                let g = gap(&j, &fd, ell);
                if smooth {
                    assert!(g <= 1e-6, "gap {g:e} at {p1:?} {p2:?}");
                    worst = worst.max(g);
                    compared += 1;
                }
            }
        }
    }
    assert!(
        compared * 10 >= cases * 8,
        "only {compared} of {cases} poses compared"
    );
    eprintln!("closed form against central differences: worst {worst:.1e}");
}
