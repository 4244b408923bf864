//! The Jacobian of `(x*, α*)` is the same problem at every size: scaling both shapes and both
//! positions by `s` leaves ∂x*/∂r and ∂α*/∂q unchanged, multiplies ∂x*/∂q by `s` and ∂α*/∂r by
//! `1/s`. Checked for the pairs with an ellipsoid, whose closed forms (two ellipsoids; an
//! ellipsoid on a face or an edge) once lost precision away from unit size: the tangent block of
//! `(Y + nnᵀ)⁻¹` mixed a length with a pure number (wrong columns at 1e-20 and 1e20), and an
//! ellipsoid's support Hessian formed `ggᵀ ∝ size⁴`, which underflows below ~1e-77.

mod common;

use common::xorshift::Rng;
use dcol::{jacobian, Options, Pose, Real, Shape};

/// An ellipsoid of semi-axes `axes · s` (body axes).
fn ellipsoid(axes: [Real; 3], s: Real) -> Shape {
    let d = |k: usize| 1.0 / (axes[k] * s * axes[k] * s);
    Shape::ellipsoid([[d(0), 0.0, 0.0], [0.0, d(1), 0.0], [0.0, 0.0, d(2)]]).unwrap()
}

/// A six-plane polytope (a box with one corner cut) of size `s`.
fn polytope(s: Real) -> Shape {
    let a = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-0.3, -0.3, -1.0],
    ];
    let b = [0.5, 0.4, 0.6, 0.3, 0.5, 0.4].map(|v| v * s);
    Shape::polytope(&a, &b).unwrap()
}

/// The Jacobian at size `s`, brought back to unit size (`None` when the query does not answer).
fn unit_jacobian(
    shapes: [&Shape; 2],
    at: [([Real; 3], [Real; 4]); 2],
    s: Real,
) -> Option<[[Real; 14]; 4]> {
    let pose = |(r, q): ([Real; 3], [Real; 4])| Pose::new(r.map(|v| v * s), q).unwrap();
    let (p1, p2) = (pose(at[0]), pose(at[1]));
    let (_, mut j) = jacobian(shapes[0], &p1, shapes[1], &p2, &Options::default()).ok()?;
    for (i, row) in j.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            let rotation = (3..7).contains(&c) || c >= 10;
            match (i < 3, rotation) {
                (true, true) => *v /= s,
                (false, false) => *v *= s,
                _ => {}
            }
        }
    }
    Some(j)
}

/// Random poses of an ellipsoid against another ellipsoid, a box and a cut box, both orders,
/// at sizes from 1e-100 to 1e100: the Jacobian brought back to unit size equals the unit
/// size's within 1e-8 of its largest entry (the closed forms measure ~1e-12; where one
/// declines, the general feature solve ~5e-10).
#[test]
fn ellipsoid_jacobians_are_the_same_at_every_size() {
    let mut rng = Rng(0x3c6e_f372_fe94_f82b);
    let mut compared = 0;
    for case in 0..240 {
        let axes = [
            0.2 + 0.8 * rng.next(),
            0.2 + 0.8 * rng.next(),
            0.2 + 0.8 * rng.next(),
        ];
        let other = |s: Real| match case % 3 {
            0 => ellipsoid([0.9, 0.4, 0.6], s),
            1 => Shape::cuboid(0.5 * s, 0.3 * s, 0.4 * s).unwrap(),
            _ => polytope(s),
        };
        let quaternion = |rng: &mut Rng| [0; 4].map(|_| rng.next() - 0.5);
        let direction = rng.unit();
        let direction = [direction.x, direction.y, direction.z];
        let reach = 0.6 + 1.2 * rng.next();
        let at = [
            ([0.1, -0.2, 0.3], quaternion(&mut rng)),
            (direction.map(|d| d * reach), quaternion(&mut rng)),
        ];
        let flip = case % 2 == 1;
        let pair = |s: Real| {
            let (e, o) = (ellipsoid(axes, s), other(s));
            if flip {
                unit_jacobian([&o, &e], at, s)
            } else {
                unit_jacobian([&e, &o], at, s)
            }
        };
        let Some(unit) = pair(1.0) else { continue };
        let big = unit.iter().flatten().fold(0.0, |m: Real, v| m.max(v.abs()));
        for s in [1e-100, 1e-80, 1e-40, 1e-20, 1e20, 1e40, 1e100] {
            let j = pair(s).unwrap_or_else(|| panic!("case {case}: no answer at {s:e}"));
            for (i, (a, b)) in j.iter().flatten().zip(unit.iter().flatten()).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-8 * big,
                    "case {case} at {s:e}: entry ({}, {}) {a} against {b} at unit size",
                    i / 14,
                    i % 14
                );
            }
            compared += 1;
        }
    }
    assert!(compared >= 1500, "{compared} comparisons");
}
