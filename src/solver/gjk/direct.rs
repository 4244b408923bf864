//! The distance by Newton's method on the support function, before (and mostly instead of)
//! GJK.
//!
//! `d* = max over unit n of g(n)`, `g(n) = n·d − h₁(n) − h₂(−n)` (`docs/maths.md`
//! §5). Where the witness points lie on one smooth piece of each shape, `g` is smooth near the
//! optimum, and Newton's method on the unit sphere (tangent coordinates at the iterate, the
//! Riemannian Hessian `tᵢᵀ∇²h_K tⱼ + g·δᵢⱼ`, positive definite for separated shapes near the
//! optimum) converges quadratically from `n = d/‖d‖`, with a backtracking line search on `g`.
//! A step costs one support call of K and the two pieces' Hessians. The answer is certified as
//! GJK's ([`super::certify_candidate`]): the lower bound `g(n)`, the upper bound the distance
//! of the pieces' points. Where the support's pieces change at the end, or the Hessian is not
//! positive definite, or the certificate does not close, `None`: GJK answers.

use super::{certify_candidate, Route, Separation};
use crate::math::{Real, Vec3};
use crate::shapes::SupportMap;
use crate::solver::direct::{plane_basis, tie_step};
use crate::solver::polish::{point, Active};
use crate::solver::raycast::Pair;

/// Newton steps before handing over to GJK.
const MAX_STEPS: usize = 12;
/// The smallest step (radians) taken as the last ([`converged_step`]).
const CONVERGED_STEP: Real = 1e-7;
/// Armijo's sufficient-increase fraction.
const ARMIJO: Real = 1e-4;
/// Changes of the support's pieces tolerated on the way: none, the first change of pieces goes
/// to the tie solve with the two pieces seen (a second change was measured to cost more steps
/// and line searches than the ties it saved: cylinder–polygon 13 473 → 12 370 instructions,
/// box–cylinder 15 749 → 14 528, `docs/performance-notes.md`).
const MAX_CHANGES: u32 = 0;
/// Halvings of a step before the line search gives up.
const MAX_HALVINGS: u32 = 8;
/// Tie solves on the way to an answer: the first, and two more on the pieces found at the
/// previous one's end (callgrind, 2 000 poses of the second pose set's generator on seed 11,
/// `dcol_distance` instructions: one round → two, box–cylinder 13.10 M → 12.38 M,
/// cylinder–cylinder 12.51 M → 11.82 M; three, 12.28 M and 11.76 M).
const TIE_ROUNDS: usize = 3;

/// The step (radians) below which Newton stops: the iterate it leads to is within about its
/// square, below `tol` (the certificate then decides), but not below [`CONVERGED_STEP`].
fn converged_step(tol: Real) -> Real {
    (0.5 * tol.sqrt()).clamp(CONVERGED_STEP, 1e-3)
}

/// The distance of the pair at offset `d` (normalised) by Newton's method on the sphere,
/// certified to `tol` (normalised); `None` where it does not certify.
pub(crate) fn distance<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
) -> Option<Separation> {
    let len = d.norm();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let converged = converged_step(tol);
    let mut n = d / len;
    let mut v = pair.support(&n);
    let mut g = n.dot(d) - v.w.dot(&n);
    let mut changes = 0;
    // Each shape's pieces seen (at most two: the first and the latest other one).
    let mut seen = v.id.map(|id| [id, id]);
    for _ in 0..MAX_STEPS {
        let ids = v.id;
        let (t1, t2) = plane_basis(&n);
        // Gradient and Hessian of h_K in the tangent coordinates, from each shape's piece.
        let mut grad = [0.0; 2];
        let mut hess = [0.0; 3];
        for shape in 0..2 {
            let (posed, sign) = pair.side(shape);
            let m = posed.rot.tr_mul(&n) * sign;
            let (b1, b2) = (posed.rot.tr_mul(&t1) * sign, posed.rot.tr_mul(&t2) * sign);
            let e = posed.shape.piece_reduced(v.id[shape], &m, &[b1, b2])?;
            let s = posed.inv_scale;
            grad[0] += b1.dot(&e.grad) * s;
            grad[1] += b2.dot(&e.grad) * s;
            for (h, e) in hess.iter_mut().zip(e.hess) {
                *h += e * s;
            }
        }
        // Maximise g = n·d − h_K: ascent direction from −(∇h_K − d) projected, Hessian
        // ∇²h_K + g·I (the sphere's curvature) for the minimisation of −g.
        let gy = [grad[0] - t1.dot(d), grad[1] - t2.dot(d)];
        let (a, b, c) = (hess[0] + g, hess[1], hess[2] + g);
        let det = a * c - b * b;
        if !(a > 0.0 && c > 0.0 && det > 1e-12 * a * c) {
            break;
        }
        let y1 = -(c * gy[0] - b * gy[1]) / det;
        let y2 = -(a * gy[1] - b * gy[0]) / det;
        let step = y1.hypot(y2);
        if !step.is_finite() {
            break;
        }
        if step <= converged {
            let nt = (n + t1 * y1 + t2 * y2).normalize();
            let vt = pair.support(&nt);
            if vt.id != v.id {
                // A kink right at the optimum: its pieces go to the tie solve.
                for (shape, pieces) in seen.iter_mut().enumerate() {
                    if vt.id[shape] != pieces[0] {
                        pieces[1] = vt.id[shape];
                    }
                }
                break;
            }
            let out = certify_candidate(pair, d, tol, &nt, vt.a, vt.b).map(|s| Separation {
                route: Route::Polish,
                ..s
            });
            if out.is_some() || step <= CONVERGED_STEP {
                return out;
            }
        }
        // Line search: g must rise by a fraction of its first-order increase −gy·y.
        let rise = -(gy[0] * y1 + gy[1] * y2);
        if !(rise > 0.0) {
            break;
        }
        let mut t = 1.0;
        let mut accepted = false;
        let mut trial = v.id;
        for _ in 0..=MAX_HALVINGS {
            let nt = (n + (t1 * y1 + t2 * y2) * t).normalize();
            let vt = pair.support(&nt);
            let gt = nt.dot(d) - vt.w.dot(&nt);
            if gt >= g + ARMIJO * t * rise {
                n = nt;
                v = vt;
                g = gt;
                accepted = true;
                break;
            }
            trial = vt.id;
            t *= 0.5;
        }
        if !accepted {
            // Every trial step met other pieces: a kink at the iterate. The pieces across it
            // (of the shortest trial) go to the tie solve, which otherwise had none to tie and
            // left the pair to GJK.
            for (shape, pieces) in seen.iter_mut().enumerate() {
                if trial[shape] != v.id[shape] {
                    *pieces = [v.id[shape], trial[shape]];
                }
            }
            break;
        }
        // The support moved to other pieces: a kink (an edge, a face, a capsule's side) lies
        // in the way or at the optimum, where these two-piece steps do not converge.
        for (shape, pieces) in seen.iter_mut().enumerate() {
            if v.id[shape] != pieces[0] {
                pieces[1] = v.id[shape];
            }
        }
        if v.id != ids {
            changes += 1;
            if changes > MAX_CHANGES {
                break;
            }
        }
    }
    // The tie solve. Where it ends on pieces that are not all the support's at its normal (a
    // multiplier outside [0, 1], or a bracket that does not close), it runs again from there
    // with the support's new piece tied to the one the multiplier favoured, up to
    // `TIE_ROUNDS` times, instead of leaving the pair to GJK.
    for _ in 0..TIE_ROUNDS {
        match tied(pair, d, tol, n, seen) {
            Ok(s) => return Some(s),
            Err(None) => return None,
            Err(Some((m, nu))) => {
                let ids = pair.support(&m).id;
                let mut again = seen;
                for shape in 0..2 {
                    let [f, k] = seen[shape];
                    if ids[shape] != f && ids[shape] != k {
                        // Keep the piece the multiplier favours.
                        let keep = if f != k && nu[shape] > 0.5 { k } else { f };
                        again[shape] = [keep, ids[shape]];
                    }
                }
                if again == seen {
                    return None;
                }
                seen = again;
                n = m;
            }
        }
    }
    None
}

/// The optimum on a kink: each shape whose support alternated between two pieces has them
/// tied, `p_k(n) = p_f(n)`, as an equality constraint of `max g(n)` on the sphere. Newton on the
/// Lagrangian `n·d − Σ_shapes [(1 − ν) p_f + ν p_k]` in the tangent coordinates (its Hessian
/// with the sphere's curvature term) and the multipliers (solved for afresh each step); the
/// witnesses are the pieces' points weighted `(1 − ν, ν)`, which must lie in [0, 1]. Certified
/// as GJK's candidates are. Where it converges but a multiplier lies outside [0, 1] or the
/// bracket does not close, `Err` with its final normal and multipliers (a start for another
/// round on other pieces); `Err(None)` where it fails otherwise.
fn tied<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
    mut n: Vec3,
    pieces: [[u32; 2]; 2],
) -> Result<Separation, Option<(Vec3, [Real; 2])>> {
    let ties: Vec2Ties = pieces.map(|p| (p[0] != p[1]).then_some(p));
    let count = ties.iter().flatten().count();
    if count == 0 {
        return Err(None);
    }
    let converged = converged_step(tol);
    let mut nu = [0.5; 2];
    for _ in 0..MAX_STEPS {
        let (t1, t2) = plane_basis(&n);
        // The Lagrangian's value and reduced Hessian (of Σ weighted pieces), the objective's
        // reduced gradient (the first pieces), and the ties' values and reduced gradients: each
        // piece reduced to the tangent plane in its own body frame (no world Hessian formed).
        let (mut value, mut hy, mut go) = (0.0, [0.0; 3], [0.0; 2]);
        let (mut cval, mut cy) = ([0.0; 2], [[0.0; 2]; 2]);
        let mut m = 0;
        for shape in 0..2 {
            let f = tangent(pair, shape, pieces[shape][0], &n, &t1, &t2).ok_or(None)?;
            go[0] += f.grad[0];
            go[1] += f.grad[1];
            match ties[shape] {
                None => {
                    value += f.value;
                    for (h, e) in hy.iter_mut().zip(f.hess) {
                        *h += e;
                    }
                }
                Some(p) => {
                    let k = tangent(pair, shape, p[1], &n, &t1, &t2).ok_or(None)?;
                    let w = nu[shape];
                    value += f.value * (1.0 - w) + k.value * w;
                    for ((h, a), b) in hy.iter_mut().zip(f.hess).zip(k.hess) {
                        *h += a * (1.0 - w) + b * w;
                    }
                    cval[m] = k.value - f.value;
                    cy[m] = [k.grad[0] - f.grad[0], k.grad[1] - f.grad[1]];
                    m += 1;
                }
            }
        }
        // Minimise Φ = h(n) − n·d on the sphere: Riemannian Hessian P∇²L P − (n·∇L)·I.
        let curv = value - n.dot(d);
        let (a11, a12, a22) = (hy[0] - curv, hy[1], hy[2] - curv);
        let gy = [go[0] - t1.dot(d), go[1] - t2.dot(d)];
        let (dy, new_nu) = tie_step([a11, a12, a22], gy, cval, cy, count).ok_or(None)?;
        let step = dy[0].hypot(dy[1]);
        if !step.is_finite() {
            return Err(None);
        }
        let mut j = 0;
        for shape in 0..2 {
            if ties[shape].is_some() {
                nu[shape] = new_nu[j];
                j += 1;
            }
        }
        n = (n + t1 * dy[0] + t2 * dy[1]).normalize();
        if step <= converged {
            if nu
                .iter()
                .zip(&ties)
                .any(|(w, t)| t.is_some() && !(-1e-9..=1.0 + 1e-9).contains(w))
            {
                return Err(Some((n, nu)));
            }
            // The witnesses at the final normal, weighted by the multipliers.
            let mut wit = [Vec3::zeros(); 2];
            for shape in 0..2 {
                let (f, k) = shape_pieces(pair, shape, pieces, &ties, &n).ok_or(None)?;
                let w = nu[shape].clamp(0.0, 1.0);
                wit[shape] = k.map_or(f, |k| f * (1.0 - w) + k * w);
            }
            // Shape 1's point is its gradient; shape 2's gradient is minus its point.
            return certify_candidate(pair, d, tol, &n, wit[0], -wit[1])
                .map(|s| Separation {
                    route: Route::Polish,
                    ..s
                })
                .ok_or(Some((n, nu)));
        }
    }
    Err(None)
}

/// A piece at the unit normal `n` in the tangent coordinates `(t1, t2)` (normalised units).
struct Tangent {
    value: Real,
    grad: [Real; 2],
    hess: [Real; 3],
}

/// Piece `id` of shape `shape` at `n`, reduced to the tangent plane in the shape's body frame.
fn tangent<S: SupportMap>(
    pair: &Pair<'_, S>,
    shape: usize,
    id: u32,
    n: &Vec3,
    t1: &Vec3,
    t2: &Vec3,
) -> Option<Tangent> {
    let (posed, sign) = pair.side(shape);
    let m = posed.rot.tr_mul(n) * sign;
    let b = [posed.rot.tr_mul(t1) * sign, posed.rot.tr_mul(t2) * sign];
    let e = posed.shape.piece_reduced(id, &m, &b)?;
    let s = posed.inv_scale;
    Some(Tangent {
        value: e.value * s,
        grad: [b[0].dot(&e.grad) * s, b[1].dot(&e.grad) * s],
        hess: e.hess.map(|h| h * s),
    })
}

/// Shape `shape`'s first piece's point (its world gradient) at `n` and, when it is tied, its
/// second's.
fn shape_pieces<S: SupportMap>(
    pair: &Pair<'_, S>,
    shape: usize,
    pieces: [[u32; 2]; 2],
    ties: &Vec2Ties,
    n: &Vec3,
) -> Option<(Vec3, Option<Vec3>)> {
    let first = point(
        pair,
        Active {
            shape,
            id: pieces[shape][0],
        },
        n,
    )?;
    let second = match ties[shape] {
        Some(p) => Some(point(pair, Active { shape, id: p[1] }, n)?),
        None => None,
    };
    Some((first, second))
}

/// Per shape, the two pieces tied (`None`: one piece).
type Vec2Ties = [Option<[u32; 2]>; 2];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Mat3, Pose};
    use crate::shapes::Shape;
    use crate::solver::gjk::{self, GjkEnd};

    fn rot(q: [Real; 4]) -> Mat3 {
        *Pose::new([0.0; 3], q).unwrap().rotation()
    }

    /// Newton's distance against GJK's on the same pair, both certified to 1e-13: the
    /// distances agree to 2e-13 and the witnesses realise the distance.
    fn check(a: &Shape, qa: [Real; 4], b: &Shape, qb: [Real; 4], d: Vec3) {
        let (ra, rb) = (rot(qa), rot(qb));
        let pair = Pair::new([a, b], [&ra, &rb], 1.0);
        let s = distance(&pair, &d, 1e-13).expect("Newton certifies");
        let GjkEnd::Separated(g) = gjk::distance(&pair, &d, 1e-13, 400, false, None, None) else {
            panic!("GJK did not certify");
        };
        assert!(
            (s.distance - g.distance).abs() <= 2e-13,
            "{} vs {}",
            s.distance,
            g.distance
        );
        assert!(((d + s.b - s.a).norm() - s.distance).abs() <= 1e-12);
        assert!(matches!(s.route, Route::Polish));
    }

    #[test]
    fn tied_pieces_match_gjk() {
        // A capsule's side against an ellipsoid (its two end balls tie), and a cylinder's
        // side against a crossed capsule's side (both shapes tie).
        let c = Shape::capsule(0.3, 2.0).unwrap();
        let e = Shape::ellipsoid([[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]).unwrap();
        let id = [1.0, 0.0, 0.0, 0.0];
        check(&c, id, &e, [0.95, 0.0, 0.3, 0.0], Vec3::new(0.1, 2.0, 0.2));
        let y = Shape::cylinder(0.4, 2.0).unwrap();
        let crossed = [0.5_f64.sqrt(), 0.0, 0.0, 0.5_f64.sqrt()];
        check(&y, id, &c, crossed, Vec3::new(0.05, -0.03, 1.5));
    }

    #[test]
    fn smooth_pairs_match_gjk() {
        let e = Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap();
        let q = [0.3, 0.5, -0.2, 0.7];
        check(&e, [1.0, 0.0, 0.0, 0.0], &e, q, Vec3::new(1.5, -2.0, 0.7));
        // A cone's rim against a cylinder's rim, and an ellipsoid against a cone's apex side.
        let k = Shape::cone(1.2, 0.5).unwrap();
        let y = Shape::cylinder(0.4, 1.0).unwrap();
        check(&k, [0.9, 0.3, 0.2, 0.1], &y, q, Vec3::new(0.4, 2.2, -1.1));
        check(&e, q, &k, [0.2, 0.9, -0.3, 0.1], Vec3::new(-2.5, 0.3, 0.9));
    }
}
