//! Warm starts: a caller-owned per-pair [`Cache`] that keeps the last geometric answer of a
//! pair (its normal, its contact features, the poses it was found at), so that the next query
//! on nearby poses solves the features' system at once instead of searching again.
//!
//! A warm answer is Newton's method on the kept features (`crate::solver::sensitivity::solve_on`)
//! from the kept normal, certified by the same bracket as a cold answer: the support functions
//! at the new normal bound α' below, the new touching points' difference bounds it above
//! (`docs/maths.md` §3). Where the features have changed (the poses moved too far, another
//! vertex or face became the contact) the bracket does not close, or the system leaves its
//! features, and the cold path answers; the cache then keeps the cold answer. Nothing a cache
//! holds is trusted: any bit pattern in it (a cache of another pair, of other shapes, garbage)
//! gives a correct answer, only a slower one.
//!
//! A cold answer is kept as it is (normal, points, poses); its features are identified on the
//! first warm call, at the poses it was found at (ties of the support functions at that exact
//! optimum), so a cold query pays nothing for the cache beyond the copy.

use super::shortcuts::Answer;
use crate::math::{rotation_from_quaternion, Pose, Real, Vec3};
use crate::shapes::{Shape, SupportMap};
use crate::solver::features::{identify, Feature, MAX_SIDE};
use crate::solver::raycast::{upper_from_point, Pair};
use crate::solver::sensitivity::Solution;
use crate::solver::Solver;

/// The poses may have moved at most this far (in units of ℓ) ...
const GATE_MOVE: Real = 0.25;
/// ... and turned by at most this much (the cosine of half the angle between the quaternions,
/// 20°), for the kept answer to be tried: beyond that the features have almost surely changed
/// and trying would cost more than it saves.
const GATE_COS_HALF: Real = 0.984_807_753_012_208;

/// What a kind's state word holds (its low four bits under [`KIND_MAGIC`], the back-off's level
/// in bits 4–6 and the calls it still skips in bits 8–15; any other word, as all zeros, is
/// cold): nothing,
const COLD: u32 = 0;
/// a cold answer (normal, points, poses; features not identified yet),
const SOLUTION: u32 = 1;
/// or identified features (a warm answer, or a cold one identified since).
const FEATURES: u32 = 2;
const KIND_MAGIC: u32 = 0x6463_0000;

/// A feature of pieces, in the words.
const TAG_PIECES: u32 = 1;

/// Words: the two kinds' states, the shapes' piece counts, then per kind two sides of five
/// words (a tag, a count, three piece ids).
const WORDS: usize = 25;
/// The separating normal's word (below): [`SEP_MAGIC`] in its high half when it holds anything
/// (else, as all zeros, nothing), then whether the normal is kept ([`SEP_KEPT`]), the back-off's
/// level (bits 8–10) and the calls it still skips (bits 0–7).
const W_SEPARATING: usize = 24;
const SEP_MAGIC: u32 = 0x6473_0000;
const SEP_KEPT: u32 = 1 << 15;
/// The back-off: after the `k`-th try in a row that did not decide, the next `2^(k−1) − 1`
/// calls neither try the kept normal nor keep one (at most 31: a try in 32 calls where the
/// normal never decides, as on random jumps); a try that decides resets it.
const MAX_LEVEL: u32 = 6;
const W_COUNTS: usize = 2;
const W_FEATURES: usize = 4;
/// Numbers: per kind a block of [`BLOCK`] (the unit normal, world; `μ` or the distance's lower
/// bound; the ray; the points a and b, normalised, relative to their origins; the two poses,
/// position and quaternion; per side three feature weights), then ℓ.
const BLOCK: usize = 33;
const NUMBERS: usize = 2 * BLOCK + 4;
/// A unit normal (world) that separated the shapes at the last answer (any unit vector gives a
/// valid lower bound on their distance: nothing about it needs checking).
const N_SEPARATING: usize = 2 * BLOCK + 1;
const N_NORMAL: usize = 0;
const N_VALUE: usize = 3;
const N_RAY: usize = 4;
const N_A: usize = 7;
const N_B: usize = 10;
const N_POSE: usize = 13;
const N_FEATURE: usize = 27;
const N_ELL: usize = 2 * BLOCK;

/// The queries a cache keeps an answer for, each in its own part of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// The proximity family (α*): the kept facet of K.
    Proximity = 0,
    /// The distance: the kept closest features.
    Distance = 1,
}

/// A per-pair warm-start cache for the proximity queries: all zeros ([`Cache::new`],
/// `Default`) is cold. Keep one per pair of shapes and pass it to every query on that pair
/// (`crate::proximity_cached` and its siblings); it is plain data (copy it, zero it, move it
/// between threads). A cache used for another pair, or after a shape changed, costs one cold
/// query and is then that pair's: it never makes an answer wrong. Where the kept answer keeps
/// failing (poses that jump), the cache backs off: up to 31 calls then neither try nor keep one.
///
/// Layout-compatible with the C `dcol_cache`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cache {
    pub(crate) words: [u32; WORDS],
    pub(crate) numbers: [Real; NUMBERS],
}

impl Default for Cache {
    fn default() -> Self {
        Cache::new()
    }
}

impl Cache {
    /// A cold cache.
    pub const fn new() -> Cache {
        Cache {
            words: [0; WORDS],
            numbers: [0.0; NUMBERS],
        }
    }

    /// Whether the cache holds an answer to start from (false: the next query is cold).
    pub fn is_warm(&self) -> bool {
        [Kind::Proximity, Kind::Distance]
            .iter()
            .any(|&k| self.state(k).0 != COLD)
            || self.separating_state().0
    }

    /// Forgets what the cache holds.
    pub fn clear(&mut self) {
        *self = Cache::new();
    }

    fn vec(&self, at: usize) -> Vec3 {
        Vec3::new(self.numbers[at], self.numbers[at + 1], self.numbers[at + 2])
    }

    fn put(&mut self, at: usize, v: &Vec3) {
        self.numbers[at..at + 3].copy_from_slice(v.as_slice());
    }

    fn pose(&self, kind: Kind, i: usize) -> (Vec3, [Real; 4]) {
        let at = base(kind) + N_POSE + 7 * i;
        let q = &self.numbers[at + 3..at + 7];
        (self.vec(at), [q[0], q[1], q[2], q[3]])
    }

    /// Whether the poses are near enough the kept ones for the kept answer to be tried.
    fn near(&self, kind: Kind, poses: [&Pose; 2], ell: Real) -> bool {
        (0..2).all(|i| {
            let (p, q) = self.pose(kind, i);
            let q2 = poses[i].quaternion();
            // Quaternions are kept as given (any length): the cosine of the half angle is
            // their normalised dot product.
            let dot = q.iter().zip(&q2).map(|(a, b)| a * b).sum::<Real>().abs();
            let norms =
                q.iter().map(|a| a * a).sum::<Real>() * q2.iter().map(|a| a * a).sum::<Real>();
            (poses[i].position() - p).norm() <= GATE_MOVE * ell
                && dot >= GATE_COS_HALF * norms.sqrt()
        })
    }

    /// The answer on the kept facet of K (two polytopes, the only pairs a proximity answer is
    /// kept for: `super::dispatch` lists `Stage::Warm` for no other proximity), certified to `tol`, or
    /// `None` (the cold path answers). On success the cache holds the new answer's features.
    pub(super) fn solve(
        &mut self,
        pair: &Pair<'_, Shape>,
        poses: [&Pose; 2],
        ray: &Vec3,
        iota: Real,
        tol: Real,
    ) -> Option<Answer> {
        let (verts1, verts2) = (
            pair.one.shape.vertex_pieces()?,
            pair.two.shape.vertex_pieces()?,
        );
        let feats = self.kept_features(Kind::Proximity, pair, poses)?;
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
        // The features' vertices, world orientation, normalised lengths (shape 2's as they are:
        // K's points are p − q).
        let world = |posed: &crate::solver::raycast::Posed<'_, Shape>, v: &[Vec3], id: u32| {
            v.get(id as usize).map(|v| posed.rot * v * posed.inv_scale)
        };
        let mut p = [Vec3::zeros(); MAX_SIDE];
        let mut q = [Vec3::zeros(); MAX_SIDE];
        for k in 0..c1 {
            p[k] = world(&pair.one, verts1, i1[k])?;
        }
        for k in 0..c2 {
            q[k] = world(&pair.two, verts2, i2[k])?;
        }
        let facet = facet_point(&p[..c1], &q[..c2], ray)?;
        let n = facet.normal;
        let lo = n.dot(ray) / pair.support(&n).w.dot(&n);
        let hi = upper_from_point(&(facet.a - facet.b), ray, iota);
        if !(lo.is_finite() && lo > 0.0 && hi - lo <= tol * lo) {
            return None;
        }
        self.keep_features(Kind::Proximity, &n, 1.0 / lo, &facet.lam);
        Some(Answer {
            alpha: lo,
            normal: n,
            a: facet.a,
            b: facet.b,
            solver: Solver::Polish,
        })
    }

    /// `kind`'s state ([`COLD`], [`SOLUTION`] or [`FEATURES`]), the back-off's level and the
    /// calls it still skips.
    fn state(&self, kind: Kind) -> (u32, u32, u32) {
        let w = self.words[kind as usize];
        if w & 0xffff_0000 != KIND_MAGIC || w & 0xf > FEATURES {
            return (COLD, 0, 0);
        }
        let level = ((w >> 4) & 7).min(MAX_LEVEL);
        (w & 0xf, level, ((w >> 8) & 0xff).min(skips(MAX_LEVEL)))
    }

    fn set_state(&mut self, kind: Kind, (state, level, skip): (u32, u32, u32)) {
        self.words[kind as usize] = if state == COLD && level == 0 && skip == 0 {
            COLD
        } else {
            KIND_MAGIC | skip << 8 | level << 4 | state
        };
    }

    /// Sets `kind`'s state, the back-off as it is.
    fn set_kind(&mut self, kind: Kind, state: u32) {
        let (_, level, skip) = self.state(kind);
        self.set_state(kind, (state, level, skip));
    }

    /// Whether `kind`'s kept answer may be tried: it is one, of these shapes, and the poses
    /// moved little since. A call the back-off skips is counted; poses that moved too far raise
    /// the back-off (the next calls neither try nor keep an answer), near ones reset it.
    fn usable(&mut self, kind: Kind, pair: &Pair<'_, Shape>, poses: [&Pose; 2]) -> bool {
        let (state, level, skip) = self.state(kind);
        if skip > 0 {
            self.set_state(kind, (COLD, level, skip - 1));
            return false;
        }
        let ell = 1.0 / pair.one.inv_scale;
        let mine = (state == SOLUTION || state == FEATURES)
            && self.words[W_COUNTS] == pair.one.shape.piece_count()
            && self.words[W_COUNTS + 1] == pair.two.shape.piece_count()
            && self.numbers[N_ELL] == ell;
        if !mine {
            return false;
        }
        let near = self.near(kind, poses, ell);
        let level = if near { 0 } else { (level + 1).min(MAX_LEVEL) };
        self.set_state(kind, (state, level, if near { 0 } else { skips(level) }));
        near
    }

    /// Whether the back-off skips `kind`'s keeping on this call.
    fn skipping(&self, kind: Kind) -> bool {
        self.state(kind).2 > 0
    }

    /// The kept features of `kind`'s last answer, when the cache holds one for these shapes
    /// and the poses moved little since: identified now (at the poses it was found at) if
    /// the answer was a cold one.
    pub(super) fn kept_features(
        &mut self,
        kind: Kind,
        pair: &Pair<'_, Shape>,
        poses: [&Pose; 2],
    ) -> Option<[Feature; 2]> {
        if !self.usable(kind, pair, poses) {
            return None;
        }
        if self.state(kind).0 == FEATURES {
            return Some([self.feature(kind, pair, 0)?, self.feature(kind, pair, 1)?]);
        }
        let feats = self.identify_kept(kind, pair);
        match &feats {
            // Kept, so that a query that fails after does not identify them again.
            Some(f) => self.keep_ids(kind, f),
            None => self.set_kind(kind, COLD),
        }
        feats
    }

    /// Keeps a cold answer of `kind` (features identified lazily, on the next warm call):
    /// `normal` (any length), `value` (`μ`, or the distance), the ray (proximity), the points.
    pub(super) fn keep_answer(
        &mut self,
        kind: Kind,
        normal: &Vec3,
        value: Real,
        ray: &Vec3,
        a: &Vec3,
        b: &Vec3,
    ) {
        let unit = normal.try_normalize(0.0);
        let Some(unit) = unit.filter(|_| !self.skipping(kind)) else {
            self.set_kind(kind, COLD);
            return;
        };
        let at = base(kind);
        self.set_kind(kind, SOLUTION);
        self.put(at + N_NORMAL, &unit);
        self.numbers[at + N_VALUE] = value;
        self.put(at + N_RAY, ray);
        self.put(at + N_A, a);
        self.put(at + N_B, b);
    }

    /// Records the poses and the shapes `kind`'s kept answer belongs to (after every answer).
    pub(super) fn keep_poses(
        &mut self,
        kind: Kind,
        shapes: [&Shape; 2],
        ell: Real,
        poses: [&Pose; 2],
    ) {
        if self.skipping(kind) {
            // Nothing is kept while the back-off skips calls.
            return;
        }
        let (n1, n2) = (shapes[0].piece_count(), shapes[1].piece_count());
        let same = self.words[W_COUNTS] == n1
            && self.words[W_COUNTS + 1] == n2
            && self.numbers[N_ELL] == ell;
        if !same {
            // Other shapes: the other kind's answer is not theirs.
            let other = [Kind::Proximity, Kind::Distance][1 - kind as usize];
            self.set_kind(other, COLD);
            self.words[W_COUNTS] = n1;
            self.words[W_COUNTS + 1] = n2;
            self.numbers[N_ELL] = ell;
        }
        for (i, pose) in poses.iter().enumerate() {
            let at = base(kind) + N_POSE + 7 * i;
            self.put(at, pose.position());
            self.numbers[at + 3..at + 7].copy_from_slice(&pose.quaternion());
        }
    }

    /// The separating word: whether a normal is kept, the back-off's level and the calls it
    /// still skips (any other word: nothing).
    fn separating_state(&self) -> (bool, u32, u32) {
        let w = self.words[W_SEPARATING];
        if w & 0xffff_0000 != SEP_MAGIC {
            return (false, 0, 0);
        }
        let level = ((w >> 8) & 7).min(MAX_LEVEL);
        (w & SEP_KEPT != 0, level, (w & 0xff).min(skips(MAX_LEVEL)))
    }

    fn set_separating_state(&mut self, kept: bool, level: u32, skip: u32) {
        self.words[W_SEPARATING] = if kept || level > 0 || skip > 0 {
            SEP_MAGIC | if kept { SEP_KEPT } else { 0 } | level << 8 | skip
        } else {
            COLD
        };
    }

    /// The separating normal to try on this call (unit, world, from shape 1 to shape 2): the
    /// kept one, or `None` when none is kept or the back-off skips this call (counted).
    pub(super) fn separating(&mut self) -> Option<Vec3> {
        let (kept, level, skip) = self.separating_state();
        if skip > 0 {
            self.set_separating_state(false, level, skip - 1);
            return None;
        }
        let n = self.vec(N_SEPARATING);
        (kept && (n.norm_squared() - 1.0).abs() < 1e-9).then_some(n)
    }

    /// Records how the normal [`Cache::separating`] gave fared: `decided` resets the back-off,
    /// a try that did not decide raises it (the next calls skip the kept normal).
    pub(super) fn separating_tried(&mut self, decided: bool) {
        let (kept, level, _) = self.separating_state();
        if decided {
            self.set_separating_state(kept, 0, 0);
        } else {
            let level = (level + 1).min(MAX_LEVEL);
            self.set_separating_state(kept, level, skips(level));
        }
    }

    /// Keeps `normal` (unit, from shape 1 to shape 2) as the separating normal to try next, or
    /// forgets it (`None`); while the back-off skips calls, nothing is kept (nor copied).
    pub(super) fn keep_separating(&mut self, normal: Option<&Vec3>) {
        let (_, level, skip) = self.separating_state();
        let unit = normal
            .filter(|_| skip == 0)
            .and_then(|n| n.try_normalize(0.0));
        if let Some(n) = &unit {
            self.put(N_SEPARATING, n);
        }
        self.set_separating_state(unit.is_some(), level, skip);
    }

    /// Marks `kind`'s part cold (the answer was not one the cache can start from).
    pub(super) fn forget(&mut self, kind: Kind) {
        self.set_kind(kind, COLD);
    }

    /// Keeps a warm answer's normal, value and feature weights (the ids are kept already).
    pub(super) fn keep_features(
        &mut self,
        kind: Kind,
        normal: &Vec3,
        value: Real,
        lam: &[[Real; MAX_SIDE]; 2],
    ) {
        let Some(unit) = normal.try_normalize(0.0) else {
            self.set_kind(kind, COLD);
            return;
        };
        let at = base(kind);
        self.set_kind(kind, FEATURES);
        self.put(at + N_NORMAL, &unit);
        self.numbers[at + N_VALUE] = value;
        for (i, l) in lam.iter().enumerate() {
            let n = at + N_FEATURE + 3 * i;
            self.numbers[n..n + 3].copy_from_slice(l);
        }
    }

    /// Keeps identified features' piece ids (the state becomes [`FEATURES`]).
    fn keep_ids(&mut self, kind: Kind, feats: &[Feature; 2]) {
        self.set_kind(kind, FEATURES);
        for (i, f) in feats.iter().enumerate() {
            let w = W_FEATURES + 10 * kind as usize + 5 * i;
            match f {
                Feature::Pieces { ids, count, .. } => {
                    self.words[w] = TAG_PIECES;
                    self.words[w + 1] = *count as u32;
                    self.words[w + 2..w + 5].copy_from_slice(ids);
                }
                Feature::Disc { .. } => self.words[w] = COLD,
            }
        }
    }

    /// Side `i`'s kept feature of `kind`, checked against the shape (piece ids in range).
    fn feature(&self, kind: Kind, pair: &Pair<'_, Shape>, i: usize) -> Option<Feature> {
        let w = W_FEATURES + 10 * kind as usize + 5 * i;
        if self.words[w] != TAG_PIECES {
            return None;
        }
        let count = self.words[w + 1] as usize;
        if !(1..=MAX_SIDE).contains(&count) {
            return None;
        }
        let mut ids = [0; MAX_SIDE];
        ids.copy_from_slice(&self.words[w + 2..w + 5]);
        let (posed, _) = pair.side(i);
        if ids[..count]
            .iter()
            .any(|&id| id >= posed.shape.piece_count())
        {
            return None;
        }
        Some(Feature::Pieces {
            ids,
            lam: [0.0; MAX_SIDE],
            count,
        })
    }

    /// The features of `kind`'s kept cold answer, identified at the poses it was found at.
    fn identify_kept(&self, kind: Kind, pair: &Pair<'_, Shape>) -> Option<[Feature; 2]> {
        let at = base(kind);
        let rots = [0, 1].map(|i| rotation_from_quaternion(self.pose(kind, i).1));
        let then = Pair::new(
            [pair.one.shape, pair.two.shape],
            [&rots[0], &rots[1]],
            pair.one.inv_scale,
        );
        let unit = self.vec(at + N_NORMAL);
        let ray = match kind {
            Kind::Proximity => self.vec(at + N_RAY),
            // The ties do not depend on the ray.
            Kind::Distance => unit,
        };
        let along = unit.dot(&ray);
        if !(along > 0.0) {
            return None;
        }
        let sol = Solution {
            r: ray,
            normal: unit / along,
            mu: self.numbers[at + N_VALUE],
            a: self.vec(at + N_A),
            b: self.vec(at + N_B),
        };
        identify(&then, &sol)
    }
}

/// The calls the separating normal's back-off skips at `level` (0 at levels 0 and 1).
const fn skips(level: u32) -> u32 {
    if level == 0 {
        0
    } else {
        (1 << (level - 1)) - 1
    }
}

/// Where `kind`'s block of numbers starts.
fn base(kind: Kind) -> usize {
    BLOCK * kind as usize
}

/// A point of a facet of K on the ray: its normal (`n·r = 1`), the points of shape 1 and 2
/// whose difference it is, and their weights on the features' vertices.
struct Facet {
    normal: Vec3,
    a: Vec3,
    b: Vec3,
    lam: [[Real; MAX_SIDE]; 2],
}

/// The facet of K spanned by a vertex of one polytope and a face triangle of the other, or by
/// an edge of each (the vertices `p` of shape 1 and `q` of shape 2, world orientation,
/// normalised): where the ray `r` meets its plane, as a point `a − b` with `a` in the hull of
/// `p` and `b` in the hull of `q`. `None` for other features (a vertex against a vertex or
/// an edge does not span a facet), a degenerate facet, or a ray that leaves the facet by more
/// than rounding (the contact moved to another feature); weights a rounding below 0 are
/// clamped, so that `a` and `b` are always points of the shapes.
fn facet_point(p: &[Vec3], q: &[Vec3], r: &Vec3) -> Option<Facet> {
    let normal_dir = match (p.len(), q.len()) {
        (1, 3) => (q[1] - q[0]).cross(&(q[2] - q[0])),
        (3, 1) => (p[1] - p[0]).cross(&(p[2] - p[0])),
        (2, 2) => (p[1] - p[0]).cross(&(q[1] - q[0])),
        _ => return None,
    };
    let along = normal_dir.dot(r);
    if !(along.abs() > 1e-9 * normal_dir.norm()) {
        return None;
    }
    let n = normal_dir / along;
    // The plane n·x = h (n·r = 1): the ray meets it at h·r.
    let h = n.dot(&(p[0] - q[0]));
    if !(h > 0.0) {
        return None;
    }
    let w = r * h;
    let mut lam = [[0.0; MAX_SIDE]; 2];
    match (p.len(), q.len()) {
        (1, 3) => {
            // w = p₀ − Σ μ_j q_j.
            let mu = barycentric(&q[0], &q[1], &q[2], &(p[0] - w))?;
            lam[0][0] = 1.0;
            lam[1] = mu;
        }
        (3, 1) => {
            let l = barycentric(&p[0], &p[1], &p[2], &(w + q[0]))?;
            lam[0] = l;
            lam[1][0] = 1.0;
        }
        _ => {
            // w = p₀ + s e₁ − q₀ − u e₂: least squares in the facet's plane.
            let (e1, e2) = (p[1] - p[0], q[1] - q[0]);
            let d = w - p[0] + q[0];
            let (a11, a12, a22) = (e1.dot(&e1), -e1.dot(&e2), e2.dot(&e2));
            let (b1, b2) = (e1.dot(&d), -e2.dot(&d));
            let det = a11 * a22 - a12 * a12;
            if !(det > 1e-12 * a11 * a22) {
                return None;
            }
            let s = (b1 * a22 - b2 * a12) / det;
            let u = (a11 * b2 - a12 * b1) / det;
            lam[0] = [1.0 - s, s, 0.0];
            lam[1] = [1.0 - u, u, 0.0];
        }
    }
    for side in lam.iter_mut() {
        if side.iter().any(|l| !(*l >= -1e-12)) {
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
        .fold(Vec3::zeros(), |acc, (v, l)| acc + v * *l);
    let b = q
        .iter()
        .zip(&lam[1])
        .fold(Vec3::zeros(), |acc, (v, l)| acc + v * *l);
    Some(Facet {
        normal: n,
        a,
        b,
        lam,
    })
}

/// Barycentric coordinates of `x` projected onto the plane of the triangle `(a, b, c)`.
fn barycentric(a: &Vec3, b: &Vec3, c: &Vec3, x: &Vec3) -> Option<[Real; 3]> {
    let (u, v, w) = (b - a, c - a, x - a);
    let (uu, uv, vv) = (u.dot(&u), u.dot(&v), v.dot(&v));
    let (wu, wv) = (w.dot(&u), w.dot(&v));
    let det = uu * vv - uv * uv;
    if !(det > 1e-12 * uu * vv) {
        return None;
    }
    let y = (wu * vv - wv * uv) / det;
    let z = (wv * uu - wu * uv) / det;
    Some([1.0 - y - z, y, z])
}
