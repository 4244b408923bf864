//! A centred box against a half-space in closed form: the contact manifold's candidate points
//! (`query::contact`'s half-space path for a box, the same numbers to the last bit) without the
//! general path's dispatch, support search and point buffers.
//!
//! With `n` the half-space's outward unit normal, `c` its depth, `r_H` its position and the box
//! of half extents `a` at `r_B`, `R_B`: `m = −R_Bᵀn`, the support point `s = (a_i sign m_i)`,
//! `h = s·m`, the signed distance `n·(r_B − r_H) − c − h` with normal `±n`; the facet facing the
//! plane is the one whose normal is best aligned with `m` (the last on a tie, as
//! `Polytope::facet_index`), used when within about 72 degrees of it (else the corner `s`), and
//! each of its corners `q` within the margin of the plane is a candidate at `q + n·depth/2`,
//! `depth = c − n·(q − r_H)`.

use super::context::SignedDistance;
use super::halfspace::HalfspacePair;
use crate::math::{Real, Vec3};
use crate::shapes::Polytope;

/// A polytope's facet is used when its normal is within about 72 degrees of the normal (as
/// `query::contact`'s `COS_FACET`).
const COS_FACET: Real = 0.3;
/// Relative tolerance (of the length scale) on the separation test (`query::contact`'s).
const SEP_TOL: Real = 1e-9;

/// The candidate points of a box on a half-space: at most a facet's four corners.
pub(crate) struct BoxOnPlane {
    /// The signed distance (value and normal as the half-space's closed form; witnesses its
    /// support point and that point's projection onto the plane).
    pub sd: SignedDistance,
    /// Candidate points, midway between the box's corner and the plane.
    pub pos: [Vec3; 4],
    /// Their depths below the plane.
    pub depth: [Real; 4],
    /// How many there are.
    pub count: usize,
}

/// The candidates of `pair`, whose other shape is the centred box `poly` of half extents
/// `half`, within `margin`; `None` where the general path must answer (a distance between the
/// origins beyond a double, or a facet that misses the deepest point).
pub(crate) fn box_on_halfspace(
    pair: &HalfspacePair<'_>,
    poly: &Polytope,
    half: &Vec3,
    margin: Real,
) -> Option<BoxOnPlane> {
    let n = pair.normal;
    let rot = pair.pose_b.rotation();
    let (rb, rh) = (pair.pose_b.position(), pair.pose_h.position());
    let g = n.dot(&(rb - rh));
    if !g.is_finite() {
        return None;
    }
    let m = -(rot.tr_mul(&n));
    let s = Vec3::new(
        half.x.copysign(m.x),
        half.y.copysign(m.y),
        half.z.copysign(m.z),
    );
    let h = s.dot(&m);
    // The witness on the box is `on_b` (the half-space's closed form computes `r_B + w` alike).
    let w = rot * s;
    let on_b = rb + w;
    let sd = pair.signed(g, h, &w);
    let distance = sd.distance;
    let mut out = BoxOnPlane {
        sd,
        pos: [Vec3::zeros(); 4],
        depth: [0.0; 4],
        count: 0,
    };
    if !(distance <= margin) {
        return Some(out);
    }
    let ell = pair.ell();
    let reach = margin + SEP_TOL * ell;
    let mut push = |q: Vec3| {
        // Below the plane `n·x = n·r + depth`, from its origin (`n·q` alone can overflow).
        let depth = pair.depth - n.dot(&(q - rh));
        if -depth <= reach && out.count < 4 {
            out.pos[out.count] = q + n * (0.5 * depth);
            out.depth[out.count] = depth;
            out.count += 1;
        }
    };
    // The facet best aligned with m (the last on a tie), as `query::contact::feature`.
    let (k, best) = poly.scan_facet(&m);
    let corners = poly.facet_loop(k).filter(|c| c.len() >= 3);
    match corners {
        Some(corners) if best >= COS_FACET * m.norm() => {
            let verts = poly.vertices();
            for &c in corners.iter().take(4) {
                push(rb + rot * verts[c as usize]);
            }
        }
        _ => push(on_b),
    }
    let deepest = out.depth[..out.count]
        .iter()
        .fold(Real::NEG_INFINITY, |a, d| a.max(*d));
    (deepest >= -distance - SEP_TOL * ell).then_some(out)
}
