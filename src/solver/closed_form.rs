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
//!   `‖d‖² / (d·c + √D)`, `D = (d·c)² − (‖c‖² − ρ²)‖d‖²`;
//! - an edge `c + τe` (`|τ| ≤ h`): the same with `d` and `c` projected off `e`, valid when the
//!   closest τ lies in `[−h, h]`;
//! - the face: `α = |d·m̂|/ρ` (`m̂ ∥ a₁ × a₂`), valid when the projection of `d` lies in `αP`.
//!
//! Everything is in the caller's normalised units (unit `d`, lengths over ℓ).

use crate::math::{Real, Vec3};

/// A rounded segment in the normalised world frame: unit axis, half-length, radius.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RoundedSegment {
    pub axis: Vec3,
    pub half: Real,
    pub radius: Real,
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

/// Least positive α with `‖d − αc‖ = αρ` (`d2 = ‖d‖²`, `dc = d·c`, `c2 = ‖c‖²`), or ∞.
#[inline]
fn vertex_root(d2: Real, dc: Real, c2: Real, rho: Real) -> Real {
    let disc = dc * dc - (c2 - rho * rho) * d2;
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
    // Best so far: (α, s, t) with the point s a₁ − t a₂ of P (unscaled).
    let mut best = (Real::INFINITY, 0.0, 0.0);
    let mut consider = |alpha: Real, s: Real, t: Real| {
        if alpha < best.0 {
            best = (alpha, s, t);
        }
    };
    // Vertices (one point when both lengths are zero, two for a segment).
    let s_ends: &[Real] = if h1 > 0.0 { &[1.0, -1.0] } else { &[0.0] };
    let t_ends: &[Real] = if h2 > 0.0 { &[1.0, -1.0] } else { &[0.0] };
    for &si in s_ends {
        for &ti in t_ends {
            let (s, t) = (si * h1, ti * h2);
            let c = a1 * s - a2 * t;
            consider(vertex_root(d2, d.dot(&c), c.norm_squared(), rho), s, t);
        }
    }
    // Edges: s fixed at an end with t free (direction −a₂), and t fixed with s free (a₁).
    let mut edge = |c: Vec3, e: Vec3, half: Real, fixed_s: Option<Real>, fixed_t: Option<Real>| {
        if half <= 0.0 {
            return;
        }
        let dp = d - e * d.dot(&e);
        let cp = c - e * c.dot(&e);
        let alpha = vertex_root(dp.norm_squared(), dp.dot(&cp), cp.norm_squared(), rho);
        if !alpha.is_finite() {
            return;
        }
        // The closest point of the line α(c + τe) to d.
        let tau = d.dot(&e) / alpha - c.dot(&e);
        if tau.abs() <= half {
            match (fixed_s, fixed_t) {
                (Some(s), _) => consider(alpha, s, tau),
                (_, Some(t)) => consider(alpha, tau, t),
                _ => {}
            }
        }
    };
    for &si in s_ends {
        // Points s a₁ − t a₂ = c + τ e with c = s a₁, e = −a₂, τ = t.
        edge(a1 * (si * h1), -a2, h2, Some(si * h1), None);
    }
    for &ti in t_ends {
        // c = −t a₂, e = a₁, τ = s.
        edge(-a2 * (ti * h2), a1, h1, None, Some(ti * h2));
    }
    // The face, when both are segments and not parallel.
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
            if s.abs() <= h1 && t.abs() <= h2 {
                consider(alpha, s, t);
            }
        }
    }
    let (alpha, s, t) = best;
    if !(alpha.is_finite() && alpha > 0.0) {
        return None;
    }
    // The exit point d/α of K is p + ρ n̂ with p = s a₁ − t a₂.
    let p = a1 * s - a2 * t;
    let normal = (d / alpha - p).try_normalize(0.0)?;
    Some(SegmentHit {
        alpha,
        s,
        t,
        normal,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(axis: [Real; 3], half: Real, radius: Real) -> RoundedSegment {
        RoundedSegment {
            axis: Vec3::from(axis).normalize(),
            half,
            radius,
        }
    }

    #[test]
    fn spheres_and_a_capsule_side_and_end() {
        let d = Vec3::new(0.0, 0.6, 0.8);
        let h = rounded_segments(
            &d,
            &seg([1.0, 0.0, 0.0], 0.0, 0.3),
            &seg([1.0, 0.0, 0.0], 0.0, 0.2),
        )
        .unwrap();
        assert!((h.alpha - 2.0).abs() < 1e-15);
        // Sphere against a capsule along x, offset along y: the side (α = 1/ρ).
        let d = Vec3::new(0.0, 1.0, 0.0);
        let h = rounded_segments(
            &d,
            &seg([1.0, 0.0, 0.0], 0.0, 0.25),
            &seg([1.0, 0.0, 0.0], 2.0, 0.25),
        )
        .unwrap();
        assert!((h.alpha - 2.0).abs() < 1e-15);
        // Along the axis: the end cap, ‖d‖ = α(h + ρ).
        let d = Vec3::new(1.0, 0.0, 0.0);
        let h = rounded_segments(
            &d,
            &seg([1.0, 0.0, 0.0], 0.0, 0.25),
            &seg([1.0, 0.0, 0.0], 0.5, 0.25),
        )
        .unwrap();
        assert!((h.alpha - 1.0).abs() < 1e-15, "{h:?}");
        assert!((h.t - 0.5).abs() < 1e-15 || (h.t + 0.5).abs() < 1e-15);
        // Crossed capsules, offset along the common normal: the face (α = 1/ρ).
        let d = Vec3::new(0.0, 0.0, 1.0);
        let h = rounded_segments(
            &d,
            &seg([1.0, 0.0, 0.0], 1.0, 0.1),
            &seg([0.0, 1.0, 0.0], 1.0, 0.4),
        )
        .unwrap();
        assert!((h.alpha - 2.0).abs() < 1e-15 && h.s.abs() < 1e-15 && h.t.abs() < 1e-15);
        assert!((h.normal - d).norm() < 1e-15);
    }
}
