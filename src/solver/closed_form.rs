//! Closed forms: α* between two *rounded segments* (a sphere is a segment of length zero, a
//! capsule one of length L, each padded by its radius).
//!
//! With `Sᵢ = {rᵢ + s aᵢ : |s| ≤ hᵢ} ⊕ B(Rᵢ)`, the Minkowski difference is
//! `K = P ⊕ B(ρ)`, `P = {s a₁ − t a₂ : |s| ≤ h₁, |t| ≤ h₂}` (a point, a segment or a
//! parallelogram) and `ρ = R₁ + R₂`, and α* is the least α with `dist(d, αP) ≤ αρ`. For any
//! subset F of P the least α with `dist(d, αF) ≤ αρ` is at least α*, with equality for the
//! feature of P that holds the closest point at α*; so α* is the least of the features'
//! values, each in closed form:
//!
//! - a vertex `c`: `‖d − αc‖ = αρ`, a quadratic whose least positive root is
//!   `‖d‖² / (d·c + √D)`, `D = ρ²‖d‖² − ‖d × c‖²` (the cross product's form, see
//!   [`vertex_root`]);
//! - an edge `c + τe` (`|τ| ≤ h`): the same with `d` and `c` projected off `e`, valid when the
//!   closest τ lies in `[−h, h]`;
//! - the face: `α = |d·m̂|/ρ` (`m̂ ∥ a₁ × a₂`), valid when the projection of `d` lies in `αP`.
//!
//! A sphere against a box centred at its origin is one more: `K = B ⊕ B(ρ)` for either order
//! (the box is symmetric), and in the box's axes `dist(d, αB) = ‖max(|d| − αh, 0)‖`, so α* is
//! the root of `‖max(|d| − αh, 0)‖ = αρ`, a quadratic between consecutive breakpoints
//! `|dᵢ|/hᵢ` (`sphere_box`).
//!
//! A sphere against a cylinder or a cone is a plane problem in the meridian half-plane of the
//! offset, the same features' least value over the section's vertices and edges
//! (`sphere_revolution`).
//!
//! Everything is in the caller's normalised units (unit `d`, lengths over ℓ).

use super::ellipsoid_point;
use super::raycast::{Pair, Posed};
use crate::math::{Mat3, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// A rounded segment in the normalised world frame: unit axis, half-length, radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundedSegment {
    pub axis: Vec3,
    pub half: Real,
    pub radius: Real,
}

impl RoundedSegment {
    /// A sphere's or capsule's segment and radius in the normalised world frame (`None` for
    /// other kinds).
    pub fn of(posed: &Posed<'_, Shape>) -> Option<Self> {
        let (half, radius) = posed.shape.rounded_segment()?;
        Some(RoundedSegment {
            axis: posed.rot.column(0).into_owned(),
            half: half * posed.inv_scale,
            radius: radius * posed.inv_scale,
        })
    }
}

/// The closed-form answer: α' for the unit offset, the segment parameters of the closest
/// points (`s` on segment 1, `t` on segment 2) and the unit normal from shape 1 to shape 2.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SegmentHit {
    pub alpha: Real,
    pub s: Real,
    pub t: Real,
    pub normal: Vec3,
}

/// Least positive α with `‖d − αc‖ = αρ`, given `d2 = ‖d‖²`, `dc = d·c` and the cross term
/// `cross2 = ‖d × c‖²` (in the plane, `(d₁c₂ − d₂c₁)²`; in general `‖d‖²‖c‖² − (d·c)²`), or ∞.
///
/// The root is `‖d‖² / (d·c + √D)` with `D = ρ²‖d‖² − ‖d × c‖²`. Callers form `cross2` from
/// the cross product itself, never as `‖d‖²‖c‖² − (d·c)²`: near the root `‖d × c‖ ≈ ρ‖d‖`,
/// and the difference of products loses `ε‖c‖²/ρ²` of D to cancellation (a sphere of radius
/// 1e-8 on a unit cube's face was 1.2e-8 off), while the cross product's components are
/// accurate to `ε‖d‖‖c‖`: √D then carries a relative error `ε‖c‖/ρ`, which the sum
/// `d·c + √D` (`d·c ≈ ‖d‖‖c‖ ≫ √D`) damps by `ρ/‖c‖` to ε in α.
#[inline]
pub(crate) fn vertex_root(d2: Real, dc: Real, cross2: Real, rho: Real) -> Real {
    let disc = rho * rho * d2 - cross2;
    if !(disc >= 0.0) {
        return Real::INFINITY;
    }
    let den = dc + disc.sqrt();
    if den > 0.0 {
        d2 / den
    } else {
        Real::INFINITY
    }
}

/// α* between two rounded segments for the unit offset `d = (r₂ − r₁)/‖r₂ − r₁‖`.
pub(crate) fn rounded_segments(
    d: &Vec3,
    one: &RoundedSegment,
    two: &RoundedSegment,
) -> Option<SegmentHit> {
    let rho = one.radius + two.radius;
    let (a1, a2) = (one.axis, two.axis);
    let (h1, h2) = (one.half, two.half);
    let d2 = d.norm_squared();
    // Two spheres: K is the ball of radius ρ, α = ‖d‖/ρ along d.
    if h1 == 0.0 && h2 == 0.0 {
        let len = d2.sqrt();
        let alpha = len / rho;
        return (alpha.is_finite() && len > 0.0).then(|| SegmentHit {
            alpha,
            s: 0.0,
            t: 0.0,
            normal: d / len,
        });
    }
    // The face, when both are segments and not parallel: P is planar, so a ray whose foot on
    // the offset plane lies inside P leaves K there (K's boundary is met once), and no other
    // feature need be tried.
    if h1 > 0.0 && h2 > 0.0 {
        let m = a1.cross(&a2);
        let mn = m.norm();
        if mn > 1e-12 {
            let m = m / mn;
            let dm = d.dot(&m);
            let alpha = dm.abs() / rho;
            // Solve s a₁ − t a₂ = (d − (d·m)m)/α for (s, t) by the 2×2 normal equations.
            let q = (d - m * dm) / alpha;
            let g12 = a1.dot(&a2);
            let det = 1.0 - g12 * g12;
            let (b1, b2) = (q.dot(&a1), q.dot(&a2));
            let s = (b1 - g12 * b2) / det;
            let t = -(b2 - g12 * b1) / det;
            if s.abs() <= h1 && t.abs() <= h2 && alpha.is_finite() && alpha > 0.0 {
                return hit(d, alpha, a1 * s - a2 * t, s, t);
            }
        }
    }
    // Best so far: (α, s, t) with the point s a₁ − t a₂ of P (unscaled). Every feature's
    // value is written with the scalars g = a₁·a₂, p = d·a₁, q = d·a₂ and the cross products
    // u = d × a₁, v = d × a₂, w = det[d, a₁, a₂] = u·a₂ (see `Cross`).
    let mut best = (Real::INFINITY, 0.0, 0.0);
    let mut consider = |alpha: Real, s: Real, t: Real| {
        if alpha < best.0 {
            best = (alpha, s, t);
        }
    };
    let (g, p, q) = (a1.dot(&a2), d.dot(&a1), d.dot(&a2));
    if h1 > 0.0 && h2 > 0.0 {
        let x = Cross::new(d, &a1, &a2);
        two_segments(d2, (g, p, q), &x, (h1, h2), rho, &mut consider);
    } else {
        // A sphere against a segment: P is the segment {τ a : |τ| ≤ h} (a = a₁, τ = s when
        // shape 1 is the capsule; a = a₂, τ = −t when shape 2 is), through the origin. Every
        // root (their square roots are independent: 80 ns against 92 for the edge-capsule
        // form, whose vertex waits on its edge's root), with d·a and ‖d × a‖²:
        // the ends c = ±h a have d·c = ±h d·a and ‖d × c‖² = h²‖d × a‖²; the side's root (the
        // ball's exit with d projected off a, c⊥ = 0) is ‖d × a‖/ρ, valid when the closest
        // point τ = d·a/α lies on the segment.
        let (axis, h, da) = if h1 > 0.0 { (a1, h1, p) } else { (a2, h2, q) };
        let n2 = d.cross(&axis).norm_squared();
        let mut segment = |alpha: Real, tau: Real| {
            let (s, t) = if h1 > 0.0 { (tau, 0.0) } else { (0.0, -tau) };
            consider(alpha, s, t);
        };
        for tau in [h, -h] {
            segment(vertex_root(d2, tau * da, tau * tau * n2, rho), tau);
        }
        let alpha = vertex_root(n2, 0.0, 0.0, rho);
        if alpha.is_finite() {
            let tau = da / alpha;
            if tau.abs() <= h {
                segment(alpha, tau);
            }
        }
    }
    let (alpha, s, t) = best;
    if !(alpha.is_finite() && alpha > 0.0) {
        return None;
    }
    hit(d, alpha, a1 * s - a2 * t, s, t)
}

/// [`rounded_segments`]' vertices and edges for two segments (the face missed): each edge with
/// its end balls (a capsule about the edge; K is the union of the face's slab and the four).
/// The vertex root with d and c projected off the edge's direction e is the entry into the
/// edge's infinite cylinder, where its foot τ lies on the edge; else the ray enters the capsule
/// through the end ball on τ's side or not at all (the balls lie in the cylinder), and where it
/// never enters the cylinder from afar (it runs parallel to the edge) both end balls decide.
/// With s fixed at an end (c = s a₁, e = −a₂): ‖d⊥‖² = ‖v‖², d⊥·c⊥ = s(p − g q),
/// ‖d⊥ × c⊥‖² = s²w², τ = t = −q/α + s g. With t fixed (c = −t a₂, e = a₁): ‖d⊥‖² = ‖u‖²,
/// d⊥·c⊥ = t(g p − q), ‖d⊥ × c⊥‖² = t²w², τ = s = p/α + t g. A vertex c = s a₁ − t a₂ has
/// d·c = s p − t q, d × c = s u − t v (`Cross`). Half the square roots of all eight features'
/// roots when the feet fall on the edges: capsule–capsule 106 → 96 ns.
///
/// Only the edges facing `d` can hold the exit point's closest point y: an edge E with in-plane
/// outward normal u (`a₁ − g a₂` for s = h₁, `g a₁ − a₂` for t = h₂, the opposite for the
/// other end) holding y has `x·u = y·u + λ‖u‖² ≥ h_P(u) > 0` at the exit point `x = d/α*`
/// (`x − y = λu + μm`, λ ≥ 0; at a vertex, were both edges' `x·u ≤ 0`, `‖x̄ − y‖² < 0` for the
/// in-plane part x̄), so `d·u > 0`. Where `|d·u| ≤ 1e-12` (far above its rounding) both ends
/// are tried; nearly parallel segments (`‖u‖ = sin θ` tiny) always land there.
#[inline(always)]
fn two_segments(
    d2: Real,
    (g, p, q): (Real, Real, Real),
    x: &Cross,
    (h1, h2): (Real, Real),
    rho: Real,
    consider: &mut impl FnMut(Real, Real, Real),
) {
    let vertex = |s: Real, t: Real| vertex_root(d2, s * p - t * q, x.vertex(s, t), rho);
    let facing = |du: Real, h: Real| match du {
        du if du > 1e-12 => ([h, h], 1),
        du if du < -1e-12 => ([-h, -h], 1),
        _ => ([h, -h], 2),
    };
    let (ends, n) = facing(p - g * q, h1);
    for &s in &ends[..n] {
        let alpha = vertex_root(x.v2, s * (p - g * q), s * s * x.w2, rho);
        if alpha.is_finite() {
            let t = -q / alpha + s * g;
            if t.abs() <= h2 {
                consider(alpha, s, t);
            } else {
                let t = h2.copysign(t);
                consider(vertex(s, t), s, t);
            }
        } else {
            consider(vertex(s, h2), s, h2);
            consider(vertex(s, -h2), s, -h2);
        }
    }
    let (ends, n) = facing(g * p - q, h2);
    for &t in &ends[..n] {
        let alpha = vertex_root(x.u2, t * (g * p - q), t * t * x.w2, rho);
        if alpha.is_finite() {
            let s = p / alpha + t * g;
            if s.abs() <= h1 {
                consider(alpha, s, t);
            } else {
                let s = h1.copysign(s);
                consider(vertex(s, t), s, t);
            }
        } else {
            consider(vertex(h1, t), h1, t);
            consider(vertex(-h1, t), -h1, t);
        }
    }
}

/// The cross products of the offset with the segments' axes, from which [`vertex_root`]'s
/// cross terms are formed without cancellation: `u = d × a₁`, `v = d × a₂`, and
/// `w² = det[d, a₁, a₂]²`. For an edge along `a₂` (unit) the parts of `d` and `c = s a₁`
/// off it have `‖d⊥‖² = ‖d × a₂‖²` and `‖d⊥ × c⊥‖ = |s det[d, a₁, a₂]|` (both perpendicular to
/// `a₂`), and likewise along `a₁`; a vertex `c = s a₁ − t a₂` has `d × c = s u − t v`.
/// (Forming a vertex's cross product from `c` only when it is needed costs more: capsule–capsule
/// +8 instructions a call.)
struct Cross {
    u: Vec3,
    v: Vec3,
    u2: Real,
    v2: Real,
    w2: Real,
}

impl Cross {
    #[inline(always)]
    fn new(d: &Vec3, a1: &Vec3, a2: &Vec3) -> Self {
        let (u, v) = (d.cross(a1), d.cross(a2));
        let w = u.dot(a2);
        Cross {
            u,
            v,
            u2: u.norm_squared(),
            v2: v.norm_squared(),
            w2: w * w,
        }
    }

    /// `‖d × c‖²` for the vertex `c = s a₁ − t a₂`.
    #[inline(always)]
    fn vertex(&self, s: Real, t: Real) -> Real {
        (self.u * s - self.v * t).norm_squared()
    }
}

/// The answer at `α` with the point `p = s a₁ − t a₂` of P: the exit point `d/α` of K is
/// `p + ρ n̂`.
fn hit(d: &Vec3, alpha: Real, p: Vec3, s: Real, t: Real) -> Option<SegmentHit> {
    let normal = (d / alpha - p).try_normalize(0.0)?;
    Some(SegmentHit {
        alpha,
        s,
        t,
        normal,
    })
}

/// The sphere–box answer: α' for the unit offset, the box's point (normalised world frame,
/// relative to the box's centre, unscaled) and the unit normal along the offset's side of K.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxHit {
    pub alpha: Real,
    pub box_point: Vec3,
    pub normal: Vec3,
}

/// α* of a sphere of radius `rho` and a box (`rot`: world from box, half extents `half`) for
/// the unit offset `d` between their centres, from the box to the sphere.
pub(crate) fn sphere_box(d: &Vec3, rot: &Mat3, half: &Vec3, rho: Real) -> Option<BoxHit> {
    let db = rot.tr_mul(d);
    let a = db.abs();
    let t = [a.x / half.x, a.y / half.y, a.z / half.z];
    // φ(α) = ‖max(a − αh, 0)‖ − αρ decreases strictly; it is ≤ 0 once α ≥ max tᵢ.
    let phi = |alpha: Real| {
        let mut s = 0.0;
        for j in 0..3 {
            let e = (a[j] - alpha * half[j]).max(0.0);
            s += e * e;
        }
        s.sqrt() - alpha * rho
    };
    let mut bps = t;
    bps.sort_by(|x, y| x.total_cmp(y));
    let mut lo = 0.0;
    let mut alpha = Real::NAN;
    for &hi in &bps {
        if hi > lo && phi(hi) <= 0.0 {
            // On (lo, hi) the axes with tᵢ ≥ hi are outside the scaled box: a quadratic.
            // The cross term of a and h restricted to those axes J, by Lagrange's identity
            // Σ_{i<j ∈ J} (aᵢhⱼ − aⱼhᵢ)² (see `vertex_root`: not Σa² Σh² − (Σah)²).
            let (mut ah, mut aa, mut cross2) = (0.0, 0.0, 0.0);
            for j in 0..3 {
                if t[j] >= hi {
                    ah += a[j] * half[j];
                    aa += a[j] * a[j];
                    for i in 0..j {
                        if t[i] >= hi {
                            let m = a[i] * half[j] - a[j] * half[i];
                            cross2 += m * m;
                        }
                    }
                }
            }
            alpha = vertex_root(aa, ah, cross2, rho).clamp(lo, hi);
            break;
        }
        lo = lo.max(hi);
    }
    if !(alpha.is_finite() && alpha > 0.0) {
        return None;
    }
    let p = Vec3::from_fn(|j, _| db[j].signum() * a[j].min(alpha * half[j]));
    let nb = (db - p).try_normalize(0.0)?;
    Some(BoxHit {
        alpha,
        box_point: rot * (p / alpha),
        normal: rot * nb,
    })
}

/// α* of a sphere of radius `rho` and a solid of revolution about body x (a cylinder or a
/// cone; `rot`: world from body) whose meridian section has the counter-clockwise vertices
/// `section` (`(axial, radial)`, symmetric in the radial coordinate), for the unit offset `q`
/// from the solid's origin to the sphere's centre. The box's hit: the solid's point
/// (normalised world frame, relative to its origin, unscaled) and the unit normal from the
/// solid to the sphere.
///
/// The closest point of a solid of revolution to a point lies in the point's meridian
/// half-plane, so with `p = (q_x, ‖(q_y, q_z)‖)` the problem is the plane one
/// `dist(p, αS) = αρ` for the section S, and α* is the least of its features' values (as for
/// the rounded segments above): each vertex's root, and each edge's `p·n̂/(b + ρ)` (outward unit
/// normal `n̂`, offset `b`) where the closest point stays on the edge.
pub(crate) fn sphere_revolution(
    q: &Vec3,
    rot: &Mat3,
    section: &[(Real, Real)],
    rho: Real,
) -> Option<BoxHit> {
    let qb = rot.tr_mul(q);
    // Plain square roots (hypot is several times slower): normalised units, no overflow.
    let radial = (qb.y * qb.y + qb.z * qb.z).sqrt();
    let (pa, pr) = (qb.x, radial);
    let p2 = pa * pa + pr * pr;
    // (α, closest point of αS in the plane).
    let mut best = (Real::INFINITY, (0.0, 0.0));
    let m = section.len();
    if m == 4 {
        // A cylinder's rectangle: only the side, the cap and the corner facing p.
        let (h, r) = section[2];
        best = rectangle_root(pa, pr, h, r, rho);
    } else {
        for i in 0..m {
            let (ca, cr) = section[i];
            let cross = pa * cr - pr * ca;
            let alpha = vertex_root(p2, pa * ca + pr * cr, cross * cross, rho);
            if alpha < best.0 {
                best = (alpha, (alpha * ca, alpha * cr));
            }
            let (na, nr) = section[(i + 1) % m];
            let (ea, er) = (na - ca, nr - cr);
            let len = (ea * ea + er * er).sqrt();
            if !(len > 0.0) {
                continue;
            }
            let (ea, er) = (ea / len, er / len);
            // Outward normal of a counter-clockwise edge, and the edge's offset.
            let (ua, ur) = (er, -ea);
            let b = ua * ca + ur * cr;
            let pn = ua * pa + ur * pr;
            if !(pn > 0.0 && b > 0.0) {
                continue;
            }
            let alpha = pn / (b + rho);
            let s = (pa - alpha * ca) * ea + (pr - alpha * cr) * er;
            if alpha < best.0 && (0.0..=alpha * len).contains(&s) {
                best = (alpha, (alpha * ca + s * ea, alpha * cr + s * er));
            }
        }
    }
    let (alpha, (xa, xr)) = best;
    if !(alpha.is_finite() && alpha > 0.0) {
        return None;
    }
    let (ma, mr) = (pa - xa, pr - xr);
    let len = (ma * ma + mr * mr).sqrt();
    if !(len > 0.0) {
        return None;
    }
    // The meridian half-plane's radial unit vector (any, on the axis).
    let u = if radial > 0.0 {
        Vec3::new(0.0, qb.y / radial, qb.z / radial)
    } else {
        Vec3::y()
    };
    let point = Vec3::new(xa / alpha, 0.0, 0.0) + u * (xr / alpha);
    let normal = Vec3::new(ma / len, 0.0, 0.0) + u * (mr / len);
    Some(BoxHit {
        alpha,
        box_point: rot * point,
        normal: rot * normal,
    })
}

/// [`sphere_revolution`]'s plane problem for the rectangle `[−h, h] × [−r, r]` (a cylinder's
/// section) and a point `(pa, pr)` with `pr ≥ 0`: the least α of the features facing the point,
/// the side `pr/(r + ρ)` where `|pa| ≤ αh`, the cap `|pa|/(h + ρ)` where `pr ≤ αr`, and the
/// corner's root; with the closest point of αS. The other features lie farther from the point
/// (their roots are larger), so this is the loop's minimum.
fn rectangle_root(pa: Real, pr: Real, h: Real, r: Real, rho: Real) -> (Real, (Real, Real)) {
    let (sa, qa) = (if pa < 0.0 { -1.0 } else { 1.0 }, pa.abs());
    let side = pr / (r + rho);
    if pr > 0.0 && qa <= side * h {
        return (side, (pa, side * r));
    }
    let cap = qa / (h + rho);
    if qa > 0.0 && pr <= cap * r {
        return (cap, (sa * cap * h, pr));
    }
    let cross = qa * r - pr * h;
    let corner = vertex_root(qa * qa + pr * pr, qa * h + pr * r, cross * cross, rho);
    (corner, (sa * corner * h, corner * r))
}

/// The closest points `x₁`, `x₂` of two segments, shape 1's centred at the origin and shape 2's
/// at `c₂` (Ericson, *Real-Time Collision Detection* §5.1.9; parallel segments get one of their
/// closest pairs). The exact distance of two
/// rounded segments is then `‖x₂ − x₁‖ − ρ₁ − ρ₂` when positive.
pub(crate) fn closest_segment_points(
    one: &RoundedSegment,
    c2: &Vec3,
    two: &RoundedSegment,
) -> (Vec3, Vec3) {
    // Two spheres: their centres (the same points as below, without the ~150 instructions of
    // vector arithmetic that a sphere–sphere `dcol_distance` spent here).
    if one.half == 0.0 && two.half == 0.0 {
        return (Vec3::zeros(), *c2);
    }
    let p1 = -one.axis * one.half;
    let p2 = c2 - two.axis * two.half;
    let d1 = one.axis * (2.0 * one.half);
    let d2 = two.axis * (2.0 * two.half);
    let r = p1 - p2;
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let clamp = |x: Real| x.clamp(0.0, 1.0);
    let (s, t) = if a <= 0.0 && e <= 0.0 {
        (0.0, 0.0)
    } else if a <= 0.0 {
        (0.0, clamp(f / e))
    } else {
        let c = d1.dot(&r);
        if e <= 0.0 {
            (clamp(-c / a), 0.0)
        } else {
            let b = d1.dot(&d2);
            // `a·e − b²` and `b·f − c·e` as `‖m‖²` and `−r·(d₂ × m)`, `m = d₁ × d₂` (the same
            // numbers in exact arithmetic): the differences of products lose everything to
            // cancellation for nearly parallel segments (relative error ε/θ², θ their angle:
            // capsules tilted by 1e-8 rad got a distance 7e-9 too large), the cross product
            // only ε/θ.
            let m = d1.cross(&d2);
            let denom = m.norm_squared();
            let mut s = if denom > 0.0 {
                clamp(-r.dot(&d2.cross(&m)) / denom)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = clamp(-c / a);
            } else if t > 1.0 {
                t = 1.0;
                s = clamp((b - c) / a);
            }
            (s, t)
        }
    };
    (p1 + d1 * s, p2 + d2 * t)
}

/// The point of the box `|uᵢ| ≤ hᵢ` closest to `c` (body frame): `c` clamped.
pub(crate) fn closest_on_box(c: &Vec3, half: &Vec3) -> Vec3 {
    Vec3::new(
        c.x.clamp(-half.x, half.x),
        c.y.clamp(-half.y, half.y),
        c.z.clamp(-half.z, half.z),
    )
}

/// The point of the cylinder of radius `radius` about body x, `|u_x| ≤ half_length`, closest
/// to `c` (body frame): the axial coordinate clamped, the radial part shortened to the radius.
pub(crate) fn closest_on_cylinder(c: &Vec3, radius: Real, half_length: Real) -> Vec3 {
    let rho = (c.y * c.y + c.z * c.z).sqrt();
    let k = if rho > radius { radius / rho } else { 1.0 };
    Vec3::new(c.x.clamp(-half_length, half_length), c.y * k, c.z * k)
}

/// The point of a solid of revolution about body x with the meridian section `section`
/// (counter-clockwise `(axial, radial)` vertices, symmetric in the radial coordinate) closest
/// to `c` (body frame), and the outward normal and distance of the boundary nearest `c` when
/// `c` lies inside (the least distance to an edge's line, as for any convex polygon). The
/// closest point lies in the meridian half-plane of `c`: a plane problem.
pub(crate) fn closest_on_section(c: &Vec3, section: &[(Real, Real)]) -> (Vec3, (Vec3, Real)) {
    let radial = (c.y * c.y + c.z * c.z).sqrt();
    let u = if radial > 0.0 {
        Vec3::new(0.0, c.y / radial, c.z / radial)
    } else {
        Vec3::y()
    };
    let (pa, pr) = (c.x, radial);
    let m = section.len();
    // Inside: the nearest edge line; outside: the nearest point of the edges.
    let (mut depth, mut normal) = (Real::INFINITY, (1.0, 0.0));
    let (mut best, mut closest) = (Real::INFINITY, (pa, pr));
    for i in 0..m {
        let (ca, cr) = section[i];
        let (ea, er) = (section[(i + 1) % m].0 - ca, section[(i + 1) % m].1 - cr);
        let len2 = ea * ea + er * er;
        if !(len2 > 0.0) {
            continue;
        }
        let len = len2.sqrt();
        let (na, nr) = (er / len, -ea / len);
        let gap = na * ca + nr * cr - (na * pa + nr * pr);
        if gap < depth {
            (depth, normal) = (gap, (na, nr));
        }
        let t = (((pa - ca) * ea + (pr - cr) * er) / len2).clamp(0.0, 1.0);
        let (qa, qr) = (ca + t * ea, cr + t * er);
        let dist2 = (pa - qa) * (pa - qa) + (pr - qr) * (pr - qr);
        if dist2 < best {
            (best, closest) = (dist2, (qa, qr));
        }
    }
    if depth >= 0.0 {
        let n = Vec3::new(normal.0, 0.0, 0.0) + u * normal.1;
        return (*c, (n, depth));
    }
    let p = Vec3::new(closest.0, 0.0, 0.0) + u * closest.1;
    (p, (Vec3::x(), 0.0))
}

/// The signed distance of a sphere and a centred box or a cylinder (either order), in the
/// pair's normalised frame: `sd`, the unit normal from shape 1 to shape 2, and the witnesses
/// relative to each shape's origin (`d + b − a = sd·normal`).
pub(crate) struct SphereSolid {
    pub sd: Real,
    pub normal: Vec3,
    pub a: Vec3,
    pub b: Vec3,
    /// Outside a box or cylinder, the certificate's lower bound `n·d − h₁(n) − h₂(−n)` at
    /// `normal` with the support functions in closed form (`s(u·c − h(u)) − ρ`, body frame).
    pub lower: Option<Real>,
}

/// A sphere against a centred box or a cylinder, in closed form: with `c` the centre in the
/// solid's body frame, outside the solid `sd = ‖c − p‖ − ρ` at its closest point `p`; inside,
/// `sd = −(δ + ρ)` with `δ` the distance to the nearest face (a box's face, a cylinder's side
/// or cap, a cone's base or side, any polytope's facet, an ellipsoid's nearest point) and the
/// normal that face's. Against a polytope that is not a centred box only with the centre
/// inside; against an ellipsoid by its certified nearest point (`super::ellipsoid_point`).
/// `None` for other pairs.
pub(crate) fn sphere_solid(pair: &Pair<'_, Shape>, d: &Vec3) -> Option<SphereSolid> {
    let ball = |posed: &Posed<'_, Shape>| match posed.shape.rounded_segment() {
        Some((0.0, radius)) => Some(radius * posed.inv_scale),
        _ => None,
    };
    // The sphere's radius, the solid, the sphere's centre relative to the solid's origin
    // (world axes), and whether the solid is shape 1.
    let (rho, solid, centre, solid_first) = if let Some(rho) = ball(&pair.two) {
        (rho, &pair.one, *d, true)
    } else {
        (ball(&pair.one)?, &pair.two, -d, false)
    };
    let s = solid.inv_scale;
    let c = solid.rot.tr_mul(&centre) / s;
    // The closest point of the solid and, inside, the nearest face's outward normal and
    // distance (body frame, the solid's units).
    // The solid's support function in closed form, for the certificate: a box's half-extents,
    // or a cylinder's (half-length, radius, 0).
    let mut support: Option<(bool, Vec3)> = None;
    let (p, inside) = if let Some(h) = solid.shape.centred_box() {
        let p = closest_on_box(&c, &h);
        support = Some((true, h));
        if p != c {
            // Outside: the nearest face is not needed.
            (p, (Vec3::zeros(), 0.0))
        } else {
            let gaps = [h.x - c.x.abs(), h.y - c.y.abs(), h.z - c.z.abs()];
            let k = (0..3).min_by(|&i, &j| gaps[i].total_cmp(&gaps[j]))?;
            let mut u = Vec3::zeros();
            u[k] = if c[k] < 0.0 { -1.0 } else { 1.0 };
            (p, (u, gaps[k]))
        }
    } else if let Some((normals, offsets)) = solid.shape.facets() {
        // Any other polytope, the centre inside only (outside, its closest point is GJK's):
        // the distance from an interior point to the boundary is the least distance to a
        // facet's plane (a plane that bounds no facet lies farther).
        let (k, depth) = normals
            .iter()
            .zip(offsets)
            .map(|(n, o)| o - n.dot(&c))
            .enumerate()
            .min_by(|x, y| x.1.total_cmp(&y.1))?;
        if !(depth >= 0.0) {
            return None;
        }
        (c, (normals[k], depth))
    } else if let Some((axes, semi)) = solid.shape.ellipsoid_principal() {
        let y = axes.tr_mul(&c);
        let near = ellipsoid_point::nearest(&y, semi)?;
        let x = near.x;
        if !near.inside {
            if !(near.dist > 0.0) {
                return None;
            }
            (axes * x, (Vec3::x(), 0.0))
        } else {
            let u = if near.dist > 0.0 {
                (x - y) / near.dist
            } else {
                Vec3::from_fn(|i, _| x[i] / (semi[i] * semi[i])).try_normalize(0.0)?
            };
            (c, (axes * u, near.dist))
        }
    } else if solid.shape.solver_kind() == ShapeKind::Cone {
        let (v, m) = solid.shape.revolution_section()?;
        let (p, (u, depth)) = closest_on_section(&c, &v[..m]);
        (p, (u, depth))
    } else {
        let (radius, half) = solid.shape.cylinder_dims()?;
        support = Some((false, Vec3::new(half, radius, 0.0)));
        let r = (c.y * c.y + c.z * c.z).sqrt();
        let (side, cap) = (radius - r, half - c.x.abs());
        let u = if side < cap && r > 0.0 {
            Vec3::new(0.0, c.y / r, c.z / r)
        } else {
            Vec3::new(if c.x < 0.0 { -1.0 } else { 1.0 }, 0.0, 0.0)
        };
        (closest_on_cylinder(&c, radius, half), (u, side.min(cap)))
    };
    let gap = c - p;
    let len = gap.norm();
    // Outside: the closest point; inside: the centre pushed out through the nearest face.
    let mut lower = None;
    let (u, sd, p) = if len > 0.0 {
        let u = gap / len;
        lower = support.map(|(is_box, h)| {
            let hu = if is_box {
                h.dot(&u.abs())
            } else {
                h.x * u.x.abs() + h.y * (u.y * u.y + u.z * u.z).sqrt()
            };
            s * (u.dot(&c) - hu) - rho
        });
        (u, len * s - rho, p)
    } else {
        let (u, depth) = inside;
        (u, -(depth * s + rho), c + u * depth)
    };
    // u points from the solid to the sphere (world axes).
    let u = solid.rot * u;
    let on_solid = solid.rot * p * s;
    let on_sphere = u * (-rho);
    let (normal, a, b) = if solid_first {
        (u, on_solid, on_sphere)
    } else {
        (-u, on_sphere, on_solid)
    };
    (sd.is_finite() && normal.iter().all(|v| v.is_finite())).then_some(SphereSolid {
        sd,
        normal,
        a,
        b,
        lower,
    })
}

#[cfg(test)]
#[path = "closed_form_tests.rs"]
mod tests;
