//! The distance's warm start (`super::warm::Cache`): between two polytopes, the closest
//! features of the pair's last answer (a vertex, an edge or a face triangle of each, their
//! dimensions adding up to at most two) give the closest points again in closed form, and the
//! answer is certified as GJK's is: the witnesses' distance bounds the distance above, the
//! support functions at their direction bound it below, and the bracket must close to the
//! tolerance. Anything else (the features changed, a pair with a curved shape) answers cold.

use super::context::{Distance, DistancePath};
use super::warm::{Cache, Kind};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, SupportMap};
use crate::solver::features::{Feature, MAX_SIDE};
use crate::solver::raycast::Pair;
use crate::solver::SolveStatus;

/// Weights this far outside `[0, 1]` (rounding) are clamped; beyond, the closest point has left
/// the feature.
const SLACK: Real = 1e-12;
/// As `super::separated`: the bracket is closed to this fraction of the tolerance, not below a
/// few roundings.
const MARGIN: Real = 1e-3;
const TOL_FLOOR: Real = 1e-14;

impl Cache {
    /// The distance of two separated polytopes from the kept features (see [`Cache::distance`]),
    /// with `tolerance` the options' (the bracket is closed to the fraction of it the cold path
    /// closes, in units of ℓ, the larger bounding radius).
    pub(super) fn warm_distance(
        &mut self,
        shapes: [&Shape; 2],
        poses: [&Pose; 2],
        ell: Real,
        tolerance: Real,
    ) -> Option<Distance> {
        if !shapes.iter().all(|s| s.vertex_pieces().is_some()) {
            return None;
        }
        let inv = 1.0 / ell;
        let pair = Pair::new(shapes, [poses[0].rotation(), poses[1].rotation()], inv);
        let d = (poses[1].position() - poses[0].position()) * inv;
        let tol = (tolerance * MARGIN).max(TOL_FLOOR);
        let answer = self.distance(&pair, poses, &d, tol);
        if answer.is_some() {
            self.keep_poses(Kind::Distance, shapes, ell, poses);
        }
        answer
    }

    /// Keeps a cold distance answer (a separated pair's, from GJK), or forgets the kept one.
    pub(super) fn keep_distance(
        &mut self,
        shapes: [&Shape; 2],
        poses: [&Pose; 2],
        ell: Real,
        answer: Option<&Distance>,
    ) {
        let polytopes = shapes.iter().all(|s| s.vertex_pieces().is_some());
        match answer.filter(|_| polytopes) {
            Some(d) => {
                let (r1, r2) = (poses[0].position(), poses[1].position());
                let (a, b) = ((d.closest1 - r1) / ell, (d.closest2 - r2) / ell);
                self.keep_answer(
                    Kind::Distance,
                    &d.normal,
                    d.distance / ell,
                    &d.normal,
                    &a,
                    &b,
                );
                self.keep_poses(Kind::Distance, shapes, ell, poses);
            }
            None => self.forget(Kind::Distance),
        }
    }

    /// The distance of two separated polytopes from the kept closest features, certified to
    /// `tol` (units of ℓ), or `None` (the cold path answers). `d = (r₂ − r₁)/ℓ`.
    fn distance(
        &mut self,
        pair: &Pair<'_, Shape>,
        poses: [&Pose; 2],
        d: &Vec3,
        tol: Real,
    ) -> Option<Distance> {
        let (verts1, verts2) = (
            pair.one.shape.vertex_pieces()?,
            pair.two.shape.vertex_pieces()?,
        );
        let feats = self.kept_features(Kind::Distance, pair, poses)?;
        let (
            Feature::Pieces {
                ids: i1, count: c1, ..
            },
            Feature::Pieces {
                ids: i2, count: c2, ..
            },
        ) = (feats[0], feats[1])
        else {
            return None;
        };
        // The features' vertices, normalised, relative to r₁.
        let mut p = [Vec3::zeros(); MAX_SIDE];
        let mut q = [Vec3::zeros(); MAX_SIDE];
        for k in 0..c1 {
            p[k] = pair.one.rot * verts1.get(i1[k] as usize)? * pair.one.inv_scale;
        }
        for k in 0..c2 {
            q[k] = pair.two.rot * verts2.get(i2[k] as usize)? * pair.two.inv_scale + d;
        }
        let (a, b, lam) = closest(&p[..c1], &q[..c2])?;
        let gap = b - a;
        let up = gap.norm();
        if !(up > 0.0 && up.is_finite()) {
            return None;
        }
        let n = gap / up;
        let lo = n.dot(d) - pair.support(&n).w.dot(&n);
        if !(lo > 0.0 && up - lo <= tol) {
            return None;
        }
        self.keep_features(Kind::Distance, &n, lo, &lam);
        let ell = 1.0 / pair.one.inv_scale;
        let r1 = *poses[0].position();
        Some(Distance {
            distance: up * ell,
            closest1: r1 + a * ell,
            closest2: r1 + b * ell,
            normal: n,
            iterations: 0,
            status: SolveStatus::Converged,
            path: DistancePath::GjkPolish,
        })
    }
}

/// The closest points of the hulls of `p` and of `q` (a point, a segment or a triangle each,
/// dimensions adding up to at most two), and the weights of `p`'s and `q`'s points that give
/// them; `None` for other features, degenerate ones, or closest points that leave the
/// features' interiors by more than rounding (weights within it are clamped, so that the
/// points are always points of the hulls).
#[allow(clippy::type_complexity)]
fn closest(p: &[Vec3], q: &[Vec3]) -> Option<(Vec3, Vec3, [[Real; MAX_SIDE]; 2])> {
    let mut lam = [[0.0; MAX_SIDE]; 2];
    match (p.len(), q.len()) {
        (1, 1) => {
            lam[0][0] = 1.0;
            lam[1][0] = 1.0;
        }
        (1, 2) | (1, 3) => {
            lam[0][0] = 1.0;
            lam[1] = on_simplex(q, &p[0])?;
        }
        (2, 1) | (3, 1) => {
            lam[0] = on_simplex(p, &q[0])?;
            lam[1][0] = 1.0;
        }
        (2, 2) => {
            let (e1, e2, w) = (p[1] - p[0], q[1] - q[0], p[0] - q[0]);
            let (a, b, c) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
            let (dd, e) = (e1.dot(&w), e2.dot(&w));
            let m = e1.cross(&e2).norm_squared();
            if !(m > 1e-18 * a * c) {
                return None;
            }
            let s = (b * e - c * dd) / m;
            let t = (a * e - b * dd) / m;
            lam[0] = [1.0 - s, s, 0.0];
            lam[1] = [1.0 - t, t, 0.0];
        }
        _ => return None,
    }
    for side in lam.iter_mut() {
        if side.iter().any(|l| !(*l >= -SLACK)) {
            return None;
        }
        for l in side.iter_mut() {
            *l = l.max(0.0);
        }
        let sum: Real = side.iter().sum();
        for l in side.iter_mut() {
            *l /= sum;
        }
    }
    let a = p
        .iter()
        .zip(&lam[0])
        .fold(Vec3::zeros(), |s, (v, l)| s + v * *l);
    let b = q
        .iter()
        .zip(&lam[1])
        .fold(Vec3::zeros(), |s, (v, l)| s + v * *l);
    Some((a, b, lam))
}

/// The weights of the projection of `x` onto the affine hull of the segment or triangle `s`.
fn on_simplex(s: &[Vec3], x: &Vec3) -> Option<[Real; MAX_SIDE]> {
    let u = s[1] - s[0];
    let w = x - s[0];
    if s.len() == 2 {
        let uu = u.dot(&u);
        if !(uu > 0.0) {
            return None;
        }
        let t = w.dot(&u) / uu;
        return Some([1.0 - t, t, 0.0]);
    }
    let v = s[2] - s[0];
    let (uu, uv, vv) = (u.dot(&u), u.dot(&v), v.dot(&v));
    let (wu, wv) = (w.dot(&u), w.dot(&v));
    let det = u.cross(&v).norm_squared();
    if !(det > 1e-18 * uu * vv) {
        return None;
    }
    let y = (wu * vv - wv * uv) / det;
    let z = (wv * uu - wu * uv) / det;
    Some([1.0 - y - z, y, z])
}
