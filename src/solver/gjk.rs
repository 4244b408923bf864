//! Exact distance between separated shapes by GJK on their support maps, with a certificate
//! (`../shared/ALGORITHMS.md` §5), then a Newton polish on the features GJK identified.
//!
//! The frame is the normalised one of the ray cast (`super::raycast`): origin at shape 1's
//! origin, lengths over ℓ, `d = (r₂ − r₁)/ℓ`. GJK finds the point of
//! `C = d + K₂ ⊕ (−K₁)` (the points `y₂ − y₁`) nearest the origin; its norm is the distance.
//! Every step certifies a bracket:
//!
//! - for any unit `n`, `d* ≥ n·d − h₁(n) − h₂(−n)` (the gap of the two slabs along `n`, one
//!   support call of each shape), the *lower* bound;
//! - for any points `a ∈ K₁`, `b ∈ K₂`, `d* ≤ ‖d + b − a‖` (the current convex combinations of
//!   support points), the *upper* bound.
//!
//! An answer is returned only when the lower bound is positive (the shapes are proven
//! separated, so a gap however small is never reported as 0) and the bracket is closed to the
//! requested width. Polytope pairs end exactly within a few steps. On curved pieces GJK
//! converges only linearly, and on a tiny gap the direction of `d + b − a` (a difference of
//! O(1) numbers) carries rounding far above the gap; so once GJK has identified the pieces in
//! contact, the normal is found from their smooth optimality conditions instead (Newton),
//! along with a simplex triangle's own normal and any flat face nearby, and the bracket is
//! certified again.

use super::polish::{
    drop_piece, eval, normalise_multipliers, solve_dense, Active, MAX_DIM, MAX_PIECES,
};
use super::raycast::{Pair, Vertex};
use crate::math::{Mat3, Real, Vec3};
use crate::shapes::SupportMap;

/// Within this relative width (or [`HANDOVER_ABS`]) of the bracket a curved pair's GJK hands
/// over to the polish: the pieces in contact are identified.
const HANDOVER: Real = 1e-6;
const HANDOVER_ABS: Real = 1e-9;
/// GJK stops on its own only when the bracket is this narrow relative to the distance (as well
/// as within the tolerance), so that tiny gaps come out with a few correct digits.
const REL_STRICT: Real = 1e-3;
/// Newton steps per active set.
const MAX_NEWTON: usize = 12;
/// A full Newton step this small (normalised units) ends the iteration.
const CONVERGED_STEP: Real = 1e-9;
/// A flat face within this cosine of the current normal is tried as the normal.
const FACE_COS: Real = 1.0 - 1e-3;

/// Which route certified the answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Route {
    /// GJK's own bracket (with a simplex or face normal).
    Gjk,
    /// The Newton polish on the features GJK identified.
    Polish,
}

/// A certified distance, normalised units.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Separation {
    /// `‖d + b − a‖`, the upper bound: the distance between the witness points.
    pub distance: Real,
    /// The certified lower bound (positive).
    pub lower: Real,
    /// The unit normal from shape 1 to shape 2 that gave `lower`.
    pub normal: Vec3,
    /// Witness of shape 1 (relative to its origin) and of shape 2 (relative to its origin).
    pub a: Vec3,
    pub b: Vec3,
    /// GJK iterations (support calls of the pair, about).
    pub iterations: u32,
    pub route: Route,
}

/// How GJK ended.
#[derive(Clone, Copy, Debug)]
pub(crate) enum GjkEnd {
    Separated(Separation),
    /// The origin lies in (or on) the simplex, or the bracket pins the distance at 0: touching
    /// or overlapping.
    Overlap,
    /// No certificate within the budget.
    Uncertified,
}

/// A point of `C` with the support points it came from.
#[derive(Clone, Copy, Debug, Default)]
struct Pt {
    c: Vec3,
    v: Vertex,
}

/// The best bounds seen.
struct Cert {
    lower: Real,
    normal: Vec3,
    upper: Real,
    a: Vec3,
    b: Vec3,
    d: Vec3,
}

impl Cert {
    /// Evaluates the lower bound at the direction of `n` (any length); returns the support
    /// vertex there.
    fn try_normal<S: SupportMap>(&mut self, pair: &Pair<'_, S>, n: &Vec3) -> Option<Vertex> {
        let len = n.norm();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let n = n / len;
        let v = pair.support(&n);
        let lo = n.dot(&self.d) - n.dot(&v.w);
        if lo > self.lower {
            self.lower = lo;
            self.normal = n;
        }
        Some(v)
    }

    /// Evaluates the upper bound from points `a ∈ K₁`, `b ∈ K₂`.
    fn try_points(&mut self, a: Vec3, b: Vec3) {
        let up = (self.d + b - a).norm();
        if up < self.upper {
            self.upper = up;
            self.a = a;
            self.b = b;
        }
    }

    fn width(&self) -> Real {
        self.upper - self.lower
    }
}

/// GJK distance of the pair at offset `d` (normalised), closing the bracket to `tol`
/// (normalised; widened to the rounding of the bounds at large offsets) within `budget`
/// iterations.
pub(crate) fn distance<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
    budget: u32,
    polyhedral: bool,
) -> GjkEnd {
    // Rounding of `n·d − n·w` (|w| ≤ 2 in these units).
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let tol = tol.max(floor);
    let strict =
        |c: &Cert| c.lower > 0.0 && c.width() <= tol.min(REL_STRICT * c.upper).max(0.5 * floor);
    let mut cert = Cert {
        lower: Real::NEG_INFINITY,
        normal: Vec3::zeros(),
        upper: Real::INFINITY,
        a: Vec3::zeros(),
        b: Vec3::zeros(),
        d: *d,
    };
    let start = if d.norm_squared() > 0.0 {
        *d
    } else {
        Vec3::x()
    };
    let Some(first) = cert.try_normal(pair, &start) else {
        return GjkEnd::Uncertified;
    };
    let mut simplex = [Pt::default(); 4];
    let mut w = [0.0; 4];
    simplex[0] = Pt {
        c: d - first.w,
        v: first,
    };
    w[0] = 1.0;
    let mut k = 1;
    let mut v = simplex[0].c;
    cert.try_points(first.a, first.b);
    let mut iterations = 0;
    let mut done = false;
    for _ in 0..budget {
        iterations += 1;
        let vv = v.norm_squared();
        if !(vv > 0.0) {
            return GjkEnd::Overlap;
        }
        let Some(vtx) = cert.try_normal(pair, &v) else {
            return GjkEnd::Uncertified;
        };
        if strict(&cert) {
            done = true;
            break;
        }
        if !polyhedral && (cert.width() <= HANDOVER * cert.upper || cert.width() <= HANDOVER_ABS) {
            break;
        }
        let c = d - vtx.w;
        // The new point adds nothing beyond v's plane (to rounding): GJK has stalled.
        if vv - v.dot(&c) <= 1e-14 * vv {
            break;
        }
        let (old, old_w, old_k) = (simplex, w, k);
        simplex[k] = Pt { c, v: vtx };
        k += 1;
        let Some(nk) = reduce(&mut simplex, &mut w, k) else {
            return GjkEnd::Overlap;
        };
        k = nk;
        let (nv, a, b) = combine(&simplex[..k], &w[..k]);
        if !(nv.norm_squared() < vv) {
            // No progress (rounding): keep the previous simplex.
            simplex = old;
            w = old_w;
            k = old_k;
            break;
        }
        v = nv;
        cert.try_points(a, b);
    }
    let mut route = Route::Gjk;
    if !done {
        extra_normals(pair, &simplex[..k], &v, &mut cert);
        if !strict(&cert) {
            let before = (cert.lower, cert.upper);
            polish(pair, &simplex[..k], &w[..k], &mut cert);
            if (cert.lower, cert.upper) != before {
                route = Route::Polish;
            }
        }
    }
    if cert.lower > 0.0 && cert.width() <= tol {
        return GjkEnd::Separated(Separation {
            distance: cert.upper,
            lower: cert.lower,
            normal: cert.normal,
            a: cert.a,
            b: cert.b,
            iterations,
            route,
        });
    }
    if cert.lower <= 0.0 && cert.upper <= tol {
        return GjkEnd::Overlap;
    }
    GjkEnd::Uncertified
}

/// `Σ wᵢ cᵢ` and the witnesses `Σ wᵢ aᵢ`, `Σ wᵢ bᵢ`.
fn combine(pts: &[Pt], w: &[Real]) -> (Vec3, Vec3, Vec3) {
    let (mut v, mut a, mut b) = (Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
    for (p, wi) in pts.iter().zip(w) {
        v += p.c * *wi;
        a += p.v.a * *wi;
        b += p.v.b * *wi;
    }
    (v, a, b)
}

/// Candidate normals beyond GJK's own: a triangle simplex's plane normal (accurate where the
/// closest point is tiny and its direction mostly rounding) and flat faces of either shape
/// near the best normal so far.
fn extra_normals<S: SupportMap>(pair: &Pair<'_, S>, pts: &[Pt], v: &Vec3, cert: &mut Cert) {
    if pts.len() == 3 {
        let n = (pts[1].c - pts[0].c).cross(&(pts[2].c - pts[0].c));
        let s = n.dot(v);
        let s = if s != 0.0 { s } else { n.dot(&cert.normal) };
        if s != 0.0 {
            cert.try_normal(pair, &(n * s.signum()));
        }
    }
    let best = cert.normal;
    for shape in 0..2 {
        let (posed, sign) = pair.side(shape);
        let m = posed.rot.tr_mul(&best) * sign;
        if let Some(f) = posed.shape.flat_face(&m, FACE_COS) {
            cert.try_normal(pair, &(posed.rot * f * sign));
        }
    }
}

/// Replaces the simplex (its first `k` points) by the smallest sub-simplex whose hull holds
/// the point nearest the origin, with that point's barycentric weights; `None` when the
/// origin lies inside the tetrahedron.
fn reduce(s: &mut [Pt; 4], w: &mut [Real; 4], k: usize) -> Option<usize> {
    let mut wk = [0.0; 4];
    let mask = match k {
        1 => {
            wk[0] = 1.0;
            1
        }
        2 => {
            let (m, t) = segment(&s[0].c, &s[1].c);
            wk[..2].copy_from_slice(&t);
            m
        }
        3 => {
            let (m, t) = triangle(&s[0].c, &s[1].c, &s[2].c);
            wk[..3].copy_from_slice(&t);
            m
        }
        _ => {
            let (m, t) = tetrahedron(&[s[0].c, s[1].c, s[2].c, s[3].c])?;
            wk = t;
            m
        }
    };
    let mut n = 0;
    for i in 0..k {
        if mask & (1 << i) != 0 {
            s[n] = s[i];
            w[n] = wk[i];
            n += 1;
        }
    }
    Some(n)
}

/// The point of segment `ab` nearest the origin: the vertices used (bit mask) and weights.
fn segment(a: &Vec3, b: &Vec3) -> (u8, [Real; 2]) {
    let ab = b - a;
    let t = -a.dot(&ab);
    if t <= 0.0 {
        return (0b01, [1.0, 0.0]);
    }
    let dd = ab.norm_squared();
    if t >= dd {
        return (0b10, [0.0, 1.0]);
    }
    let t = t / dd;
    (0b11, [1.0 - t, t])
}

/// The point of triangle `abc` nearest the origin (Ericson's Voronoi-region tests).
fn triangle(a: &Vec3, b: &Vec3, c: &Vec3) -> (u8, [Real; 3]) {
    let ab = b - a;
    let ac = c - a;
    let d1 = -ab.dot(a);
    let d2 = -ac.dot(a);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (0b001, [1.0, 0.0, 0.0]);
    }
    let d3 = -ab.dot(b);
    let d4 = -ac.dot(b);
    if d3 >= 0.0 && d4 <= d3 {
        return (0b010, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return (0b011, [1.0 - t, t, 0.0]);
    }
    let d5 = -ab.dot(c);
    let d6 = -ac.dot(c);
    if d6 >= 0.0 && d5 <= d6 {
        return (0b100, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return (0b101, [1.0 - t, 0.0, t]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (0b110, [0.0, 1.0 - t, t]);
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) {
        // Degenerate (collinear) triangle: the best of its edges.
        let cands = [(0usize, 1usize), (0, 2), (1, 2)];
        let p = [*a, *b, *c];
        let mut best = (0b001, [1.0, 0.0, 0.0]);
        let mut best_d = Real::INFINITY;
        for (i, j) in cands {
            let (m, t) = segment(&p[i], &p[j]);
            let q = p[i] * t[0] + p[j] * t[1];
            if q.norm_squared() < best_d {
                best_d = q.norm_squared();
                let mut wt = [0.0; 3];
                wt[i] = t[0];
                wt[j] = t[1];
                let mm =
                    (if m & 1 != 0 { 1 << i } else { 0 }) | (if m & 2 != 0 { 1 << j } else { 0 });
                best = (mm, wt);
            }
        }
        return best;
    }
    let v = vb / sum;
    let w = vc / sum;
    (0b111, [1.0 - v - w, v, w])
}

/// The point of tetrahedron `p` nearest the origin, `None` when the origin is inside it.
fn tetrahedron(p: &[Vec3; 4]) -> Option<(u8, [Real; 4])> {
    const FACES: [[usize; 4]; 4] = [[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 1, 2], [1, 3, 2, 0]];
    let mut best: Option<(u8, [Real; 4])> = None;
    let mut best_d = Real::INFINITY;
    for [i, j, l, o] in FACES {
        let n = (p[j] - p[i]).cross(&(p[l] - p[i]));
        let side_origin = -p[i].dot(&n);
        let side_other = (p[o] - p[i]).dot(&n);
        let flat = side_other.abs() <= 1e-12 * n.norm() * (p[o] - p[i]).norm();
        if side_origin * side_other < 0.0 || flat {
            let (m, t) = triangle(&p[i], &p[j], &p[l]);
            let q = p[i] * t[0] + p[j] * t[1] + p[l] * t[2];
            let dq = q.norm_squared();
            if dq < best_d {
                best_d = dq;
                let mut wt = [0.0; 4];
                let mut mm = 0u8;
                for (bit, idx) in [i, j, l].into_iter().enumerate() {
                    if m & (1 << bit) != 0 {
                        mm |= 1 << idx;
                        wt[idx] = t[bit];
                    }
                }
                best = Some((mm, wt));
            }
        }
    }
    best
}

/// Newton on the optimality conditions of `max n·d − h₁(n) − h₂(−n)` over unit `n` with the
/// pieces active in the simplex, then the certificate at the solution.
fn polish<S: SupportMap>(pair: &Pair<'_, S>, pts: &[Pt], w: &[Real], cert: &mut Cert) {
    let mut act = [Active { shape: 0, id: 0 }; 2 * MAX_PIECES];
    let mut lam = [0.0; 2 * MAX_PIECES];
    let mut p = 0;
    for (pt, wt) in pts.iter().zip(w) {
        for shape in 0..2 {
            let id = pt.v.id[shape];
            match act[..p].iter().position(|a| a.shape == shape && a.id == id) {
                Some(k) => lam[k] += wt.max(0.0),
                None if p < act.len() => {
                    act[p] = Active { shape, id };
                    lam[p] = wt.max(0.0);
                    p += 1;
                }
                None => return,
            }
        }
    }
    let n0 = cert.normal;
    let mu0 = cert.upper.max(0.0);
    for _attempt in 0..4 {
        normalise_multipliers(&act[..p], &mut lam[..p]);
        let mut n = n0;
        let mut mu = mu0;
        let mut l = lam;
        if newton(pair, &cert.d, &act[..p], &mut n, &mut mu, &mut l[..p]) {
            let (kmin, lmin) = (0..p).fold((0, Real::INFINITY), |acc, k| {
                if l[k] < acc.1 {
                    (k, l[k])
                } else {
                    acc
                }
            });
            if lmin >= -1e-12 {
                certify(pair, &act[..p], &n, &l[..p], cert);
                return;
            }
            if !drop_piece(&mut act, &mut lam, &mut p, kmin) {
                return;
            }
        } else {
            let Some(k) = (0..p)
                .filter(|&k| act[..p].iter().filter(|a| a.shape == act[k].shape).count() > 1)
                .min_by(|&i, &j| lam[i].total_cmp(&lam[j]))
            else {
                return;
            };
            if !drop_piece(&mut act, &mut lam, &mut p, k) {
                return;
            }
        }
    }
}

/// The bounds at a Newton solution: the full support maps at `n`, and the primal points
/// `Σ λ_k ∇p_k` of each shape.
fn certify<S: SupportMap>(
    pair: &Pair<'_, S>,
    act: &[Active],
    n: &Vec3,
    lam: &[Real],
    cert: &mut Cert,
) {
    cert.try_normal(pair, n);
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    let mut sums = [0.0; 2];
    for (piece, l) in act.iter().zip(lam) {
        let l = l.max(0.0);
        let Some(e) = eval(pair, *piece, n) else {
            return;
        };
        sums[piece.shape] += l;
        if piece.shape == 0 {
            a += e.grad * l;
        } else {
            b -= e.grad * l;
        }
    }
    if sums[0] > 0.0 && sums[1] > 0.0 {
        cert.try_points(a / sums[0], b / sums[1]);
    }
}

/// Damped Newton on `Σ λ_k ∇p_k(n) + μ n = d`, `‖n‖² = 1`, each shape's multipliers summing
/// to one and its active pieces tied; true when a full step converged to rounding.
fn newton<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    act: &[Active],
    n: &mut Vec3,
    mu: &mut Real,
    lam: &mut [Real],
) -> bool {
    let p = act.len();
    let dim = 4 + p;
    let mut jac = [[0.0; MAX_DIM]; MAX_DIM];
    let mut rhs = [0.0; MAX_DIM];
    let Some(mut scale) = system(pair, d, act, n, *mu, lam, &mut jac, &mut rhs) else {
        return false;
    };
    for _ in 0..MAX_NEWTON {
        if !solve_dense(&mut jac, &mut rhs, dim) {
            return false;
        }
        let dn = Vec3::new(rhs[0], rhs[1], rhs[2]);
        let dmu = rhs[3];
        let mut dl = [0.0; 2 * MAX_PIECES];
        dl[..p].copy_from_slice(&rhs[4..4 + p]);
        let step = dn.norm() + dmu.abs() + dl[..p].iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        if !step.is_finite() {
            return false;
        }
        let mut t = 1.0;
        let accepted = loop {
            let nt = *n + dn * t;
            let mt = *mu + dmu * t;
            let mut lt = [0.0; 2 * MAX_PIECES];
            for k in 0..p {
                lt[k] = lam[k] + dl[k] * t;
            }
            let st = system(pair, d, act, &nt, mt, &lt[..p], &mut jac, &mut rhs);
            if let Some(st) = st {
                if st < scale || (t == 1.0 && step <= CONVERGED_STEP) {
                    *n = nt;
                    *mu = mt;
                    lam.copy_from_slice(&lt[..p]);
                    scale = st;
                    break true;
                }
            }
            t *= 0.5;
            if t < 1.0 / 1024.0 {
                break false;
            }
        };
        if !accepted {
            return false;
        }
        if t == 1.0 && step <= CONVERGED_STEP {
            return true;
        }
    }
    false
}

/// The residual (negated, into `rhs`) and Jacobian of the polish's system; the residual's
/// 1-norm, or `None` where a piece is not differentiable.
#[allow(clippy::too_many_arguments)]
fn system<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    act: &[Active],
    n: &Vec3,
    mu: Real,
    lam: &[Real],
    jac: &mut [[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> Option<Real> {
    let p = act.len();
    let first = |shape: usize| act.iter().position(|a| a.shape == shape);
    let (f0, f1) = (first(0)?, first(1)?);
    let mut value = [0.0; 2 * MAX_PIECES];
    let mut grad = [Vec3::zeros(); 2 * MAX_PIECES];
    let mut hsum = Mat3::identity() * mu;
    let mut gsum = Vec3::zeros();
    for k in 0..p {
        let e = eval(pair, act[k], n)?;
        value[k] = e.value;
        grad[k] = e.grad;
        hsum += e.hess * lam[k];
        gsum += e.grad * lam[k];
    }
    let dim = 4 + p;
    for row in jac.iter_mut().take(dim) {
        row[..dim].fill(0.0);
    }
    // Rows 0..3: Σ λ_k g_k + μ n − d.
    let ra = gsum + n * mu - d;
    for i in 0..3 {
        for j in 0..3 {
            jac[i][j] = hsum[(i, j)];
        }
        jac[i][3] = n[i];
        for k in 0..p {
            jac[i][4 + k] = grad[k][i];
        }
        rhs[i] = -ra[i];
    }
    // Row 3: (‖n‖² − 1)/2.
    for j in 0..3 {
        jac[3][j] = n[j];
    }
    rhs[3] = -0.5 * (n.norm_squared() - 1.0);
    let mut scale = ra.norm() + rhs[3].abs();
    for k in 0..p {
        let row = 4 + k;
        let shape = act[k].shape;
        let f = if shape == 0 { f0 } else { f1 };
        if k == f {
            let mut sum = 0.0;
            for (i, a) in act.iter().enumerate() {
                if a.shape == shape {
                    jac[row][4 + i] = 1.0;
                    sum += lam[i];
                }
            }
            rhs[row] = -(sum - 1.0);
        } else {
            let g = grad[k] - grad[f];
            for j in 0..3 {
                jac[row][j] = g[j];
            }
            rhs[row] = -(value[k] - value[f]);
        }
        scale += rhs[row].abs();
    }
    scale.is_finite().then_some(scale)
}
