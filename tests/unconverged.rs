//! Derivatives of a solve stopped by its iteration limit are those of its last iterate (with
//! that iterate's multipliers): finite, and close to the converged ones when the limit is one
//! iteration short. They used to be exactly zero there (the multipliers of the final polish,
//! which an unconverged solve never runs, were left unset).

use dcol::{gradient, jacobian, Method, Options, Pose, Shape, SolveStatus};

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[test]
fn iteration_limit_gives_the_last_iterates_derivatives() {
    let shapes = [
        Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 2.0, 0.1], [0.0, 0.1, 0.5]]).unwrap(),
        Shape::capsule(0.3, 1.2).unwrap(),
        Shape::cuboid(0.4, 0.3, 0.6).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
    ];
    let pa = Pose::new([0.0, 0.0, 0.0], [1.0, 0.1, 0.2, 0.3]).unwrap();
    let pb = Pose::new([1.5, 0.5, 0.1], [0.9, 0.0, 0.3, 0.1]).unwrap();
    for a in &shapes {
        for b in &shapes {
            let what = format!("{:?}-{:?}", a.kind(), b.kind());
            // The interior-point path (the geometric one has no iterates to stop at).
            let ipm = Options {
                method: Method::InteriorPoint,
                ..Options::default()
            };
            let (p, g) = gradient(a, &pa, b, &pb, &ipm).unwrap();
            assert!(p.status.is_converged(), "{what}: {:?}", p.status);
            assert!(p.iterations >= 2, "{what}: {} iterations", p.iterations);
            let short = Options {
                max_iterations: p.iterations - 1,
                ..ipm
            };
            let (q, gq) = gradient(a, &pa, b, &pb, &short).unwrap();
            let (_, jq) = jacobian(a, &pa, b, &pb, &short).unwrap();
            assert_eq!(q.status, SolveStatus::MaxIterations, "{what}");
            assert!(gq.iter().chain(jq.iter().flatten()).all(|v| v.is_finite()));
            let diff: Vec<f64> = gq.iter().zip(&g).map(|(x, y)| x - y).collect();
            let err = norm(&diff) / norm(&g);
            assert!(
                err <= 1e-3,
                "{what}: gradient one iteration short off by {err:e}"
            );
            let diff: Vec<f64> = jq[3].iter().zip(&gq).map(|(x, y)| x - y).collect();
            let err = norm(&diff) / norm(&g);
            assert!(
                err <= 1e-3,
                "{what}: J[3, :] and ∇α one iteration short differ by {err:e}"
            );
        }
    }
}
