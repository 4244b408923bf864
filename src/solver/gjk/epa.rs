//! Penetration depth of overlapping shapes: the expanding polytope algorithm (EPA) on
//! `K = K₁ ⊕ (−K₂)` around `d`, a Newton polish of the normal on the pieces it identified, and
//! a two-sided certificate.
//!
//! The signed distance is `sd = max over unit n of L(n)`, `L(n) = n·d − h_K(n)`. For `d ∈ K` it
//! is minus the distance from `d` to K's boundary (the depth).
//!
//! - **Lower bound**: `L(n)` at any unit `n` (one support call): `sd ≥ L(n)`. The polish makes
//!   it exact (to rounding) at the optimal normal; it is the reported value.
//! - **Upper bound**: the polytope's vertices are support points, so they lie in K. Let S be
//!   its closed oriented surface (every edge shared by two faces, as EPA's horizon step keeps
//!   it) and, for each face with unit normal `n_f` (the normalised cross product of its edges),
//!   `ρ_f = min over its three vertices of n_f·(w_i − d)`. If every `ρ_f > 0` then every face
//!   has a positive solid angle seen from `d`, so S winds around `d` a positive number of
//!   times and every ray from `d` crosses S, at a point `x` of a face: `x ∈ conv(vertices) ⊂ K`
//!   and `‖x − d‖ ≥ n_f·(x − d) ≥ ρ_f`. K being convex, the ball of radius `ρ = min ρ_f` about
//!   `d` lies in K, so depth ≥ ρ and `sd ≤ −ρ`. This needs neither the polytope's convexity
//!   nor exact face normals (only the sign of each face's orientation, settled by `ρ_f` far
//!   above rounding). Otherwise (d not enclosed) `sd ≤ ‖d − q‖` for any point `q` of a face
//!   (`sd ≤ dist(d, K)`), used near touching.
//!
//! Polytope pairs end exactly: the closest face becomes a facet of K. On curved pieces the
//! polytope approaches K only quadratically in its face size, so the bracket closes by
//! inserting the support point at the polished normal and refining the faces around it.

use super::newton::newton;
use super::polytope::{start_from, Face, OnHeap, Poly, Refused, Store, MAX_V};
use super::simplex::triangle;
use crate::math::{Real, Vec3};
use crate::shapes::SupportMap;
use crate::solver::polish::{drop_piece, eval, normalise_multipliers, Active, MAX_PIECES};
use crate::solver::raycast::{Pair, Vertex};
use std::cell::RefCell;

/// Support calls made on the stack's polytope; a pair that needs more continues on a
/// per-thread heap polytope of 4 096 vertices (`super::polytope`; allocated the first time,
/// then reused).
const STACK_BUDGET: u32 = (MAX_V - 6) as u32;
/// The bracket width (relative to the depth, plus an absolute part) at which curved pairs hand
/// over to the polish.
const HANDOVER: Real = 1e-4;
const HANDOVER_ABS: Real = 1e-8;
/// The polish stops at a Newton step of 1e-6 when the witness identity `d + b − a = μ n` then
/// holds to this fraction of the bracket's tolerance, and goes on to rounding otherwise.
/// Measured on benches/proximity's overlapping poses (150 per pair, default tolerance): the
/// class median 4110 -> 3500 ns with the answers within 2e-14 of those polished to rounding.
const FINE: Real = 0.1;
/// The least volume of a start tetrahedron, relative to the product of its edges from one
/// vertex; [`THIN_VOLUME`] where K is known to be full-dimensional (a thinner one is the
/// rounding of a flat set: cores in one plane, which the caller answers otherwise). Shapes of
/// aspect ratio 1e11 (a box 1e-7 by 1e4) make K thinner than the first.
const START_VOLUME: Real = 1e-9;
const THIN_VOLUME: Real = 1e-14;
/// Barycentric weights down to this count as inside a face (rounding).
const BARY_SLACK: Real = 1e-12;

/// When EPA polishes its answer (Newton's method on the pieces it identified).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Polish {
    /// Never: polytopes, whose answer is exact.
    Never,
    /// At the hand-over (the bracket within [`HANDOVER`]) or where EPA stops: curved pieces.
    HandOver,
    /// Also when the bracket closes before the hand-over, and once more from the closing face
    /// where the first polish found a worse stationary point: smooth, strictly curved pieces
    /// (an ellipsoid), on which the polytope's witnesses and normal are about `√tol` off
    /// (1.2e-5 measured on an ellipsoid sunk into a box's face). Cylinders and cones keep
    /// [`Polish::HandOver`]: their brackets close early on flat pieces, where the polytope's
    /// answer is exact, and polishing there cost 4–5 % more instructions.
    Smooth,
}

/// A penetration answer (normalised units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Penetration {
    /// The best lower bound found, the signed distance reported: `L(n)` at the reported
    /// normal, or (after the polish) up to a tenth of the tolerance above it where a face's
    /// normal did that much better without replacing the polished answer.
    pub sd: Real,
    /// The certified upper bound.
    #[allow(dead_code)]
    pub upper: Real,
    pub normal: Vec3,
    /// Witnesses relative to each shape's origin: `d + b − a ≈ sd·n`.
    pub a: Vec3,
    pub b: Vec3,
    /// The polish's normal gave the lower bound.
    pub polished: bool,
    /// Support calls of K made.
    pub supports: u32,
}

/// How EPA ended.
#[derive(Clone, Copy, Debug)]
pub(crate) enum EpaEnd {
    /// The bracket closed to the tolerance.
    Closed(Penetration),
    /// The lower bound is positive: the shapes are separated (the distance query answers).
    Separated,
    /// No closed bracket within the budget: the best answer, with its bracket.
    Open(Penetration),
    /// No non-degenerate start.
    Failed,
}

/// The best lower bound and its witnesses.
struct Best {
    lower: Real,
    normal: Vec3,
    a: Vec3,
    b: Vec3,
    /// Where the witnesses come from.
    from: Source,
    polished: bool,
}

/// The source of the best lower bound's witnesses.
#[derive(Clone, Copy, Debug)]
enum Source {
    /// `a` and `b` hold them (the polish's, checked against the witness identity).
    Held,
    /// The face whose normal gave `lower`: taken from it once, at the end (its vertices stay
    /// in the polytope).
    Face(Face),
    /// The polish's normal, whose own witnesses missed the identity: taken at the end where
    /// the ray from `d` along the normal leaves the polytope.
    Ray,
}

/// The state of a run of EPA: the bounds, the support calls made, whether the polish ran.
struct Run {
    best: Best,
    upper: Real,
    supports: u32,
    polished_once: bool,
    /// Whether the polish has run a second time: once more when the bracket closes on a face's
    /// answer after the first polish found another stationary point (a worse one, from the
    /// hand-over's face: two ellipsoids of aspect ratio 9 measured), from the closing face.
    /// (Not after a polish that found none: measured, on cylinder and cone pairs, whose
    /// polish often fails on a rim, the second failed as well, at 12 % more instructions.)
    retried: bool,
    /// Whether the first polish found a stationary point worse than a face's answer.
    rejected: bool,
    /// The lower bound at the polished normal (while the best answer is the polish's).
    polished: Real,
    /// [`Polish::Smooth`]: polish a bracket that closes before the hand-over too.
    smooth: bool,
    /// The bracket's width to reach, the rounding of `L`, and the insertion slack.
    tol: Real,
    floor: Real,
    eps: Real,
}

/// How a stretch of refinement ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ended {
    Closed,
    Separated,
    /// The support calls allowed were made.
    Budget,
    /// The polytope's arrays are full.
    Full,
    /// An insertion was refused for its geometry (the polytope is at rounding level).
    Stuck,
}

thread_local! {
    /// The heap polytope of the overlaps that need more than [`STACK_BUDGET`] support calls.
    static HEAP: RefCell<Option<Poly<OnHeap>>> = const { RefCell::new(None) };
}

/// The signed distance of an overlapping (or touching) pair at offset `d` (normalised),
/// closing the bracket to `tol` within `budget` support calls, polishing as `polish` says.
/// `tet`: support vertices of the pair to start from (GJK's last simplex), when they span a
/// tetrahedron; otherwise EPA starts from four support calls of its own. `thin`: K is known to
/// be full-dimensional (two shapes, not cores that may be flat), so a start tetrahedron as
/// thin as [`THIN_VOLUME`] is taken.
///
/// The first [`STACK_BUDGET`] calls refine a polytope on the stack. A pair that needs more
/// (deep overlaps of curved shapes whose boundary nearly follows the sphere about `d` of the
/// depth's radius, where every face near the optimum must come within the tolerance of K:
/// 2.6e-4 of random overlapping pairs) goes on with a copy of it in this thread's heap
/// polytope, allocated at the first such call and reused.
pub(crate) fn penetration<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
    budget: u32,
    polish: Polish,
    tet: Option<&[Vertex; 4]>,
    thin: bool,
) -> EpaEnd {
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let mut run = Run {
        best: Best {
            lower: Real::NEG_INFINITY,
            normal: Vec3::x(),
            a: Vec3::zeros(),
            b: Vec3::zeros(),
            from: Source::Held,
            polished: false,
        },
        upper: Real::INFINITY,
        supports: 0,
        polished_once: polish == Polish::Never,
        retried: polish != Polish::Smooth,
        smooth: polish == Polish::Smooth,
        rejected: false,
        polished: Real::NEG_INFINITY,
        tol: tol.max(4.0 * floor),
        floor,
        eps: floor,
    };
    let mut poly = Poly::new(d);
    if !tet.is_some_and(|t| start_from(&mut poly, t, START_VOLUME))
        && !start(pair, &mut poly, &mut run.supports, thin)
    {
        return EpaEnd::Failed;
    }
    let ended = refine(pair, &mut poly, &mut run, budget.min(STACK_BUDGET));
    let more = (ended == Ended::Budget && run.supports < budget) || ended == Ended::Full;
    if !more {
        return finish(&poly, &run, ended);
    }
    HEAP.with(|cell| match cell.try_borrow_mut() {
        Ok(mut slot) => {
            let big = slot.get_or_insert_with(Poly::heap);
            big.copy_from(&poly);
            let ended = refine(pair, big, &mut run, budget);
            finish(big, &run, ended)
        }
        // Re-entered (this crate never does): a heap polytope of its own.
        Err(_) => {
            let mut big = Poly::heap();
            big.copy_from(&poly);
            let ended = refine(pair, &mut big, &mut run, budget);
            finish(&big, &run, ended)
        }
    })
}

/// Refines the polytope until the bracket closes, the shapes prove separated, `budget`
/// support calls are made in all, or the polytope can take no more.
fn refine<P: SupportMap, S: Store>(
    pair: &Pair<'_, P>,
    poly: &mut Poly<S>,
    run: &mut Run,
    budget: u32,
) -> Ended {
    let d = poly.d;
    let stopped = |r: Result<(), Refused>| match r {
        Ok(()) => None,
        Err(Refused::Full) => Some(Ended::Full),
        Err(Refused::Degenerate) => Some(Ended::Stuck),
    };
    loop {
        let k = poly.closest();
        let f = poly.faces[k];
        run.upper = bound(poly, &f, run.floor);
        let vtx = pair.support(&f.n);
        run.supports += 1;
        let lo = f.n.dot(&(d - vtx.w));
        // After the polish a face's normal replaces its answer only where it does better by
        // more than a tenth of the tolerance: otherwise it is the same optimum found less
        // exactly (its witnesses the polytope's, 1e-7 off on an ellipsoid), and only its
        // bound is taken (the polish stops within about 1e-12 of the optimum, and the bracket
        // may need that to close).
        // (Measured from the polished value itself, so that raises of the bound cannot add up
        // to more than the margin between the answer's normal and its value.)
        let beats = if run.best.polished {
            lo > run.polished + FINE * run.tol
        } else {
            lo > run.best.lower
        };
        if beats {
            run.best = Best {
                lower: lo,
                normal: f.n,
                a: Vec3::zeros(),
                b: Vec3::zeros(),
                from: Source::Face(f),
                polished: false,
            };
        } else if lo > run.best.lower {
            run.best.lower = lo;
        }
        if run.best.lower > run.floor {
            return Ended::Separated;
        }
        // Closed: the answer, once the polish has run on curved pieces (a bracket that closes
        // before the hand-over, as on the cores of an ellipsoid, bounds the depth but leaves
        // the polytope's witnesses and normal only to about the square root of the
        // tolerance: 1.5e-7 measured).
        let closed = run.upper - run.best.lower <= run.tol;
        let retry = closed && run.rejected && !run.retried && !run.best.polished;
        if closed && (run.polished_once || !run.smooth) && !retry {
            return Ended::Closed;
        }
        // Hand over once the pieces are identified, or when EPA stops (the polish then still
        // makes the lower bound, the answer, exact where the bracket stays open).
        let (lower, upper) = (run.best.lower, run.upper);
        let narrow =
            closed || upper - lower <= HANDOVER * lower.abs().max(upper.abs()) + HANDOVER_ABS;
        let mut stop = (run.supports >= budget).then_some(Ended::Budget);
        if stop.is_none() && !narrow {
            stop = stopped(poly.insert(vtx, run.eps, k));
        }
        if retry || (!run.polished_once && (narrow || stop.is_some())) {
            run.retried |= retry;
            run.polished_once = true;
            if let Some((n, a, b)) = polish(pair, poly, &f, run.best.lower, FINE * run.tol) {
                let v = pair.support(&n);
                run.supports += 1;
                let lo = n.dot(&(d - v.w));
                run.rejected = lo < run.best.lower;
                if lo >= run.best.lower {
                    run.polished = lo;
                    run.best = Best {
                        lower: lo,
                        normal: n,
                        a,
                        b,
                        // The polish's witnesses where they meet the identity
                        // `d + b − a = L·n` (its last Newton run may stall short of it: 6e-6
                        // seen on a box–cylinder pair, the box's witness that far inside its
                        // support plane); otherwise the polytope's, at the end.
                        from: if (d + b - a - n * lo).norm() <= run.tol {
                            Source::Held
                        } else {
                            Source::Ray
                        },
                        polished: true,
                    };
                }
                // A bracket closed already needs no more points: its answer is now the
                // polish's (inserting its support point, within the tolerance of the closest
                // face's plane, would only cut slivers whose bound is worse: measured, an
                // ellipsoid–hull pair left open at 2e-9).
                if closed {
                    return Ended::Closed;
                }
                if stop.is_none() && poly.insert(v, run.eps, k).is_ok() {
                    continue;
                }
            }
        }
        if closed {
            return Ended::Closed;
        }
        if stop.is_none() && narrow {
            stop = stopped(poly.insert(vtx, run.eps, k));
        }
        if let Some(why) = stop {
            if run.upper - run.best.lower > run.tol {
                let k = poly.closest();
                run.upper = bound(poly, &poly.faces[k], run.floor);
            }
            return if run.upper - run.best.lower <= run.tol {
                Ended::Closed
            } else {
                why
            };
        }
    }
}

/// The answer of a run that ended as `ended`, its witnesses from the polytope.
fn finish<S: Store>(poly: &Poly<S>, run: &Run, ended: Ended) -> EpaEnd {
    if ended == Ended::Separated {
        return EpaEnd::Separated;
    }
    let mut best = Best { ..run.best };
    if let Source::Ray = best.from {
        (best.a, best.b) = ray_witnesses(poly, &best.normal).unwrap_or_else(|| {
            let k = poly.closest();
            witnesses(poly, &poly.faces[k])
        });
    }
    if let Source::Face(f) = best.from {
        // The face's barycentric point lies `−(lower + ρ_f)` inside the support plane at its
        // normal: within the tolerance when the face closed the bracket, but an older face that
        // gave a better lower bound may lie deeper (7e-9 seen on a capsule–ellipsoid pair, a
        // witness identity off by as much). Then the witnesses are where the ray from `d` along
        // the normal leaves the polytope: a point of K at a distance between the bracket's
        // ends, exactly on the ray. The same where `d`'s projection falls outside the face:
        // K's facet is split into coplanar triangles whose `ρ_f` tie to rounding, and the
        // closest by index need not hold the projection; its barycentric combination of the
        // shapes' points then lies outside both shapes, on their support planes (two boxes of
        // one attitude face to face: 21 of 20 000 random offsets, by up to 0.09 of the size).
        let gap = -(best.lower + f.rho);
        let outside = bary(poly, &f).iter().any(|t| *t < -BARY_SLACK);
        (best.a, best.b) = if gap > run.tol || outside {
            ray_witnesses(poly, &best.normal).unwrap_or_else(|| witnesses(poly, &f))
        } else {
            witnesses(poly, &f)
        };
    }
    let out = Penetration {
        sd: best.lower,
        upper: run.upper,
        normal: best.normal,
        a: best.a,
        b: best.b,
        polished: best.polished,
        supports: run.supports,
    };
    if run.upper - best.lower <= run.tol {
        EpaEnd::Closed(out)
    } else {
        EpaEnd::Open(out)
    }
}

/// A tetrahedron of support points in the directions of a regular tetrahedron (or of the
/// opposite one), its faces oriented outward.
fn start<S: SupportMap, T: Store>(
    pair: &Pair<'_, S>,
    poly: &mut Poly<T>,
    supports: &mut u32,
    thin: bool,
) -> bool {
    let s = 1.0 / (3.0 as Real).sqrt();
    let dirs = [
        Vec3::new(s, s, s),
        Vec3::new(s, -s, -s),
        Vec3::new(-s, s, -s),
        Vec3::new(-s, -s, s),
    ];
    for sign in [1.0, -1.0] {
        let tet = dirs.map(|dir| pair.support(&(dir * sign)));
        *supports += 4;
        if start_from(poly, &tet, START_VOLUME) {
            return true;
        }
    }
    let least = if thin { THIN_VOLUME } else { START_VOLUME };
    spanning(pair, poly, supports, least)
}

/// A tetrahedron of support points chosen one dimension at a time: the two ends of K along a
/// direction, then the support point farthest from their line (of the two opposite directions
/// orthogonal to it), then the one farthest from their plane. For K with a vertex that is the
/// support point of most directions (two cones' apexes, needle-like polytopes) the regular
/// tetrahedron's directions can give a repeated point; this cannot, unless K is flat.
fn spanning<S: SupportMap, T: Store>(
    pair: &Pair<'_, S>,
    poly: &mut Poly<T>,
    supports: &mut u32,
    least: Real,
) -> bool {
    let mut call = |n: &Vec3| {
        *supports += 1;
        pair.support(n)
    };
    let u = Vec3::new(1.0, 1.0, 1.0) / (3.0 as Real).sqrt();
    let (v0, v1) = (call(&u), call(&-u));
    let Some(e) = (v1.w - v0.w).try_normalize(0.0) else {
        return false;
    };
    // The other end of the line, and a direction orthogonal to it.
    let o = if e.x.abs() < 0.6 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let m = (o - e * e.dot(&o)).normalize();
    let off_line = |v: &Vertex| {
        let r = v.w - v0.w;
        (r - e * e.dot(&r)).norm()
    };
    let (p, q) = (call(&m), call(&-m));
    let v2 = if off_line(&p) >= off_line(&q) { p } else { q };
    let Some(n) = (v1.w - v0.w).cross(&(v2.w - v0.w)).try_normalize(0.0) else {
        return false;
    };
    let (p, q) = (call(&n), call(&-n));
    let v3 = if n.dot(&(p.w - v0.w)).abs() >= n.dot(&(q.w - v0.w)).abs() {
        p
    } else {
        q
    };
    start_from(poly, &[v0, v1, v2, v3], least)
}

/// The certified upper bound on `sd` with closest face `f`: `−(min ρ_f − rounding)` when every
/// face has `d` strictly on its inner side, else the distance from `d` to that face.
fn bound<T: Store>(poly: &Poly<T>, f: &Face, floor: Real) -> Real {
    if f.rho > floor {
        return -(f.rho - floor);
    }
    let w = f.v.map(|i| poly.verts[i as usize].w - poly.d);
    let (_, t) = triangle(&w[0], &w[1], &w[2]);
    (w[0] * t[0] + w[1] * t[1] + w[2] * t[2]).norm() + floor
}

/// The witnesses of face `f`: the barycentric combination of its vertices' shape points at
/// the projection of `d` onto its plane (the nearest point of the face, weights clamped to be
/// nonnegative, where the projection falls outside it).
fn witnesses<T: Store>(poly: &Poly<T>, f: &Face) -> (Vec3, Vec3) {
    let mut t = bary(poly, f);
    if t.iter().any(|v| *v < 0.0) {
        let sum: Real = t.iter().map(|v| v.max(0.0)).sum();
        t = t.map(|v| v.max(0.0) / sum);
    }
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    for (i, ti) in f.v.iter().zip(t) {
        let v = &poly.verts[*i as usize];
        a += v.a * ti;
        b += v.b * ti;
    }
    (a, b)
}

/// The witnesses where the ray from `d` along the unit `n` leaves the polytope: the nearest
/// crossing of a live face (its barycentric combination of shape points); `None` when no face
/// is crossed (to rounding).
fn ray_witnesses<T: Store>(poly: &Poly<T>, n: &Vec3) -> Option<(Vec3, Vec3)> {
    let mut best: Option<(Real, usize, [Real; 3])> = None;
    for (k, f) in poly.faces.iter().enumerate() {
        let c = f.n.dot(n);
        if !f.alive || !(c > 0.0) {
            continue;
        }
        let w = f.v.map(|i| poly.verts[i as usize].w);
        let s = f.n.dot(&(w[0] - poly.d)) / c;
        if best.is_some_and(|b| b.0 <= s) || !(s >= 0.0) {
            continue;
        }
        let x = poly.d + n * s;
        let area = |p: &Vec3, q: &Vec3, r: &Vec3| (q - p).cross(&(r - p)).dot(&f.n);
        let total = area(&w[0], &w[1], &w[2]);
        let t = [
            area(&x, &w[1], &w[2]) / total,
            area(&w[0], &x, &w[2]) / total,
            area(&w[0], &w[1], &x) / total,
        ];
        if total > 0.0 && t.iter().all(|v| *v >= -BARY_SLACK) {
            best = Some((s, k, t));
        }
    }
    let (_, k, t) = best?;
    let f = &poly.faces[k];
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    for (i, ti) in f.v.iter().zip(t) {
        let v = &poly.verts[*i as usize];
        a += v.a * ti;
        b += v.b * ti;
    }
    Some((a, b))
}

/// Barycentric coordinates of the projection of `d` onto face `f`'s plane.
fn bary<T: Store>(poly: &Poly<T>, f: &Face) -> [Real; 3] {
    let w = f.v.map(|i| poly.verts[i as usize].w);
    let p = poly.d + f.n * f.n.dot(&(w[0] - poly.d));
    let area = |x: &Vec3, y: &Vec3, z: &Vec3| (y - x).cross(&(z - x)).dot(&f.n);
    let total = area(&w[0], &w[1], &w[2]);
    if !(total.abs() > 0.0) {
        return [1.0 / 3.0; 3];
    }
    [
        area(&p, &w[1], &w[2]) / total,
        area(&w[0], &p, &w[2]) / total,
        area(&w[0], &w[1], &p) / total,
    ]
}

/// Newton on the optimality conditions of `max L(n)` (`Σ λ ∇p + μ n = d`, `‖n‖ = 1`; μ is the
/// signed distance) on the pieces of face `f`'s vertices, dropping a piece whose multiplier
/// turns negative: the normal and the primal witnesses `Σ λ ∇p` of each shape.
fn polish<S: SupportMap, T: Store>(
    pair: &Pair<'_, S>,
    poly: &Poly<T>,
    f: &Face,
    mu0: Real,
    fine: Real,
) -> Option<(Vec3, Vec3, Vec3)> {
    let mut act = [Active { shape: 0, id: 0 }; 2 * MAX_PIECES];
    let mut lam = [0.0; 2 * MAX_PIECES];
    let mut p = 0;
    let t = bary(poly, f);
    for (i, wt) in f.v.iter().zip(t) {
        let v = &poly.verts[*i as usize];
        for shape in 0..2 {
            let id = v.id[shape];
            match act[..p].iter().position(|a| a.shape == shape && a.id == id) {
                Some(k) => lam[k] += wt.max(0.0),
                None => {
                    act[p] = Active { shape, id };
                    lam[p] = wt.max(0.0);
                    p += 1;
                }
            }
        }
    }
    // The normal and the witnesses `Σ λ ∇p` of each shape at a Newton solution, with the
    // residual of the witness identity `d + b − a = μ n` there.
    let answer = |act: &[Active], l: &[Real], n: &Vec3, mu: Real| {
        let n = n / n.norm();
        let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
        let mut sums = [0.0; 2];
        for (piece, lk) in act.iter().zip(l) {
            let lk = lk.max(0.0);
            let e = eval(pair, *piece, &n)?;
            sums[piece.shape] += lk;
            if piece.shape == 0 {
                a += e.grad * lk;
            } else {
                b -= e.grad * lk;
            }
        }
        if !(sums[0] > 0.0 && sums[1] > 0.0) {
            return None;
        }
        let (a, b) = (a / sums[0], b / sums[1]);
        let residual = (poly.d + b - a - n * mu).norm();
        Some(((n, a, b), residual))
    };
    for _attempt in 0..4 {
        let mut l = lam;
        normalise_multipliers(&act[..p], &mut l[..p]);
        let (mut n, mut mu) = (f.n, mu0);
        let ok = newton(pair, &poly.d, &act[..p], &mut n, &mut mu, &mut l[..p], 1e-6);
        if ok {
            let lmin = l[..p].iter().fold(Real::INFINITY, |m, v| m.min(*v));
            if lmin >= -1e-12 {
                // A step of 1e-6 leaves the iterate within about its square of the solution:
                // where the witness identity holds to `fine` that is the answer; otherwise
                // (sharply curved pieces) on to rounding (the state stays at the last
                // accepted step if it stalls).
                if let Some((out, residual)) = answer(&act[..p], &l[..p], &n, mu) {
                    if residual <= fine {
                        return Some(out);
                    }
                }
            }
            newton(
                pair,
                &poly.d,
                &act[..p],
                &mut n,
                &mut mu,
                &mut l[..p],
                1e-13,
            );
            let (kmin, lmin) = (0..p).fold((0, Real::INFINITY), |acc, k| {
                if l[k] < acc.1 {
                    (k, l[k])
                } else {
                    acc
                }
            });
            if lmin >= -1e-12 {
                return answer(&act[..p], &l[..p], &n, mu).map(|(out, _)| out);
            }
            if !drop_piece(&mut act, &mut lam, &mut p, kmin) {
                return None;
            }
        } else {
            let k = (0..p)
                .filter(|&k| act[..p].iter().filter(|a| a.shape == act[k].shape).count() > 1)
                .min_by(|&i, &j| lam[i].total_cmp(&lam[j]))?;
            if !drop_piece(&mut act, &mut lam, &mut p, k) {
                return None;
            }
        }
    }
    None
}
