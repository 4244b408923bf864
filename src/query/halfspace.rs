//! Every query with one half-space, in closed form.
//!
//! With `n` the half-space's outward unit normal (world), `c` its depth, `r_H` its position, and
//! the other shape B at `r_B` with attitude `R_B` and support function `h_B`, everything reduces
//! to one support call of B in the direction `m = −R_Bᵀn` (body frame), support point `s`:
//!
//! - `g = n·(r_B − r_H)`, `h = h_B(m) = m·s > 0` (B's origin is strictly inside B).
//! - α*: `αH = { x : n·(x − r_H) ≤ αc }` and `r_B + αR_B B` touch when `g − αh = αc`, so
//!   `α* = g/(c + h)` when `g > 0`, and `α* = 0` when `g ≤ 0` (B's origin in the half-space: at
//!   α = 0 the scaled half-space is its recession cone `n·(x − r_H) ≤ 0`). `x* = r_B + α*R_B s`.
//! - Signed distance `g − c − h`; witness on B `r_B + R_B s`, on the half-space that point
//!   projected onto the plane; the normal from shape 1 to shape 2 is `±n`.
//! - Derivatives (`D = c + h`, `w = R_B s`, `ω` a rotation axis of `rotation_axes`):
//!   `∂α/∂r_B = n/D = −∂α/∂r_H`, `∂α/∂q_H = ω·(n × (x* − r_H))/D`, `∂α/∂q_B = α ω·(w × n)/D`;
//!   `∂x* = ∂r_B + w ∂α + α ∂w` with `∂w = ω_B × w + H_w(ω_B × n − ∂n)`, `∂n = ω_H × n` and
//!   `H_w = R_B ∇²h_B(m) R_Bᵀ` (the support piece's Hessian).
//!
//! Under `Method::InteriorPoint`, or with `Options::smoothing`, proximity and its derivatives
//! come from the cone program instead (the half-space's one orthant row `α·depth − u_z ≥ 0`),
//! whenever `g > 1e-6 ‖r_B − r_H‖`; distances and contacts are always the closed forms.
//!
//! Where the support point is not unique (a face, an edge, a disc or a side line facing the
//! plane), `s` is the centroid of the tied support points (a support point itself), α* is not
//! differentiable in B's attitude and the derivatives are reported as a subgradient (the
//! formulas at that point, with `H_w = 0`).

use super::context::{Distance, DistancePath, Full, Options, Proximity, SignedDistance, Want};
use super::derivatives::rotation_axes;
use super::separated::witness_gradient;
use crate::error::{Error, ErrorDetail};
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, SupportMap};
use crate::solver::{DerivativeKind, Method, SolveStatus, Solver};

/// Relative tolerance (of B's bounding radius, or of 1e3 inscribed radii if smaller) under
/// which two support points tie.
const TIE: Real = 1e-9;

/// A pair of a half-space and a bounded shape.
pub(crate) struct HalfspacePair<'a> {
    /// True when the half-space is shape 1.
    pub hs_first: bool,
    /// The half-space's depth `c`.
    pub depth: Real,
    /// Its outward unit normal (world).
    pub normal: Vec3,
    /// Its pose.
    pub pose_h: &'a Pose,
    /// The other shape and its pose.
    pub other: &'a Shape,
    /// The other shape's pose.
    pub pose_b: &'a Pose,
}

/// B's support in the direction `−n` and what the derivatives need.
struct Support {
    /// `g = n·(r_B − r_H)`.
    g: Real,
    /// `h_B(−R_Bᵀ n)`.
    h: Real,
    /// `R_B s` (world axes, relative to `r_B`).
    w: Vec3,
    /// Whether `s` is the only support point.
    unique: bool,
    /// `R_B ∇²h_B R_Bᵀ` (zero when not unique).
    hess: Mat3,
}

/// `Ok(Some(pair))` when exactly one shape is a half-space, `Ok(None)` when neither is, and an
/// `InvalidShape` error for two half-spaces.
pub(crate) fn split<'a>(
    shape1: &'a Shape,
    pose1: &'a Pose,
    shape2: &'a Shape,
    pose2: &'a Pose,
) -> Result<Option<HalfspacePair<'a>>, Error> {
    let make = |hs_first, depth, pose_h: &'a Pose, other, pose_b| {
        Some(HalfspacePair {
            hs_first,
            depth,
            normal: pose_h.rotation().column(2).into_owned(),
            pose_h,
            other,
            pose_b,
        })
    };
    match (shape1.halfspace_depth(), shape2.halfspace_depth()) {
        (Some(_), Some(d2)) => Err(two_halfspaces(d2)),
        (Some(d), None) => Ok(make(true, d, pose1, shape2, pose2)),
        (None, Some(d)) => Ok(make(false, d, pose2, shape1, pose1)),
        (None, None) => Ok(None),
    }
}

/// The error for a pair of half-spaces (`d2`: the second one's depth).
fn two_halfspaces(d2: Real) -> Error {
    Error::InvalidShape(ErrorDetail::new(
        "shape2",
        d2,
        "is a half-space and so is shape1 (two half-spaces: pair not supported)",
    ))
}

/// Fails with `InvalidShape` for two half-spaces.
pub(crate) fn check(shape1: &Shape, shape2: &Shape) -> Result<(), Error> {
    match (shape1.halfspace_depth(), shape2.halfspace_depth()) {
        (Some(_), Some(d2)) => Err(two_halfspaces(d2)),
        _ => Ok(()),
    }
}

impl HalfspacePair<'_> {
    /// The pair's length scale: the other shape's bounding radius, or the depth if larger.
    pub(crate) fn ell(&self) -> Real {
        self.other.bounding_radius().max(self.depth)
    }

    /// Whether proximity goes to the interior-point method: when the options ask for it
    /// (`Method::InteriorPoint`, or smoothing without a threshold) and B's origin is clearly
    /// outside the half-space, `g > 1e-6 ‖r_B − r_H‖`. Otherwise the closed form answers: at
    /// α* = 0 it is exact and the cone program's optimum sits on its boundary α = 0, and for
    /// `g` that small relative to the offset the normalised α' is too (its polish could step
    /// to a negative α* of the rounding's size).
    pub(crate) fn by_interior_point(
        &self,
        options: &Options,
        threshold: Option<(Real, bool)>,
    ) -> bool {
        let asked = options.method == Method::InteriorPoint
            || (options.smoothing > 0.0 && threshold.is_none());
        let offset = self.pose_b.position() - self.pose_h.position();
        asked && self.normal.dot(&offset) > 1e-6 * crate::math::robust_norm(&offset)
    }

    /// Column offsets of the half-space's and the other shape's (r, q) in a 14-vector.
    fn cols(&self) -> (usize, usize) {
        if self.hs_first {
            (0, 7)
        } else {
            (7, 0)
        }
    }

    /// `g = n·(r_B − r_H)`, B's support point `s` in the direction `m = −R_Bᵀn`, its piece and
    /// `h = m·s`.
    fn support_point(&self) -> Result<(Real, Vec3, u32, Vec3, Real), Error> {
        let n = self.normal;
        let rot = self.pose_b.rotation();
        let g = n.dot(&(self.pose_b.position() - self.pose_h.position()));
        if !g.is_finite() {
            return Err(Error::InvalidPose(ErrorDetail::new(
                "position",
                g,
                "the distance between the two origins overflows a double",
            )));
        }
        let m = -(rot.tr_mul(&n));
        let (s, id) = self.other.support(&m);
        let h = s.dot(&m);
        Ok((g, m, id, s, h))
    }

    fn support(&self) -> Result<Support, Error> {
        let rot = self.pose_b.rotation();
        let b = self.other;
        let (g, m, id, s, h) = self.support_point()?;
        // Thin shapes (aspect above 1e3): relative to a thousand inscribed radii instead, so
        // that a box's two large faces never tie.
        let tol = TIE * b.bounding_radius().min(1e3 * b.inscribed_radius());
        let own = b.piece(id, &m);
        // A disc (normal ±e_x) facing the plane within rounding: every rim point ties.
        let disc = b
            .disc(&m, 0.9)
            .filter(|(_, radius)| radius * m.y.hypot(m.z) <= tol * m.norm());
        let mut unique = own.is_some() && disc.is_none();
        let (mut sum, mut count) = (Vec3::zeros(), 0.0);
        if let Some((tied, n)) = b.support_ties(id, &m, tol) {
            // A polytope's or hull's tied corners, found on its vertex graph.
            (sum, count) = (tied, n as Real);
            unique &= n == 1;
        } else {
            for k in 0..b.piece_count() {
                if let Some(e) = b.piece(k, &m) {
                    if e.value >= h - tol {
                        sum += e.grad;
                        count += 1.0;
                        unique &= (e.grad - s).norm() <= tol;
                    }
                }
            }
        }
        let point = if unique {
            s
        } else if let Some((centre, _)) = disc {
            centre
        } else if count > 0.0 {
            sum / count
        } else {
            s
        };
        let hess = match own {
            Some(e) if unique => rot * e.hess * rot.transpose(),
            _ => Mat3::zeros(),
        };
        Ok(Support {
            g,
            h,
            w: rot * point,
            unique,
            hess,
        })
    }

    /// α*, x*, the contact points and what `want` asks for.
    pub(crate) fn proximity(&self, want: Want) -> Result<Full, Error> {
        let sp = self.support()?;
        let (rh, rb) = (*self.pose_h.position(), *self.pose_b.position());
        let n = self.normal;
        let d = self.depth + sp.h;
        let alpha = if sp.g > 0.0 { sp.g / d } else { 0.0 };
        let point = rb + sp.w * alpha;
        let (contact_h, contact_b) = if alpha > 0.0 {
            // On the plane, `‖(r_B − r_H)_t‖·D/g` from r_H along it: unbounded as g → 0. Where
            // that overflows a double, B's contact point projected onto the plane stands in.
            let on_b = rb + sp.w;
            let p = rh + (point - rh) / alpha;
            let p = if p.iter().all(|v| v.is_finite()) {
                p
            } else {
                on_b - n * (n.dot(&(on_b - rh)) - self.depth)
            };
            (p, on_b)
        } else {
            (rh, rb)
        };
        let (contact1, contact2) = if self.hs_first {
            (contact_h, contact_b)
        } else {
            (contact_b, contact_h)
        };
        let mut full = Full {
            prox: Proximity {
                alpha,
                point,
                contact1,
                contact2,
                iterations: 0,
                status: SolveStatus::Converged,
                solver: Solver::ClosedForm,
                derivatives: DerivativeKind::None,
            },
            gradient: [0.0; 14],
            jacobian: [[0.0; 14]; 4],
            decided: None,
        };
        if want < Want::Gradient {
            return Ok(full);
        }
        let (ch, cb) = self.cols();
        if sp.g <= 0.0 {
            // α* ≡ 0 and x* = r_B nearby (exact), except on the kink g = 0.
            for i in 0..3 {
                full.jacobian[i][cb + i] = 1.0;
            }
            full.prox.derivatives = if sp.g < 0.0 {
                DerivativeKind::Exact
            } else {
                DerivativeKind::Subgradient
            };
            return Ok(full);
        }
        let (axes_h, axes_b) = (rotation_axes(self.pose_h), rotation_axes(self.pose_b));
        let round = self.other.solver_kind() == crate::ShapeKind::Sphere;
        let mut da = [0.0; 14];
        let nr = n.cross(&(point - rh)) / d;
        let wn = sp.w.cross(&n) * (alpha / d);
        for j in 0..3 {
            da[cb + j] = n[j] / d;
            da[ch + j] = -n[j] / d;
        }
        for k in 0..4 {
            da[ch + 3 + k] = axes_h[k].dot(&nr);
            if !round {
                da[cb + 3 + k] = axes_b[k].dot(&wn);
            }
        }
        full.gradient = da;
        full.jacobian[3] = da;
        for c in 0..14 {
            for i in 0..3 {
                full.jacobian[i][c] = sp.w[i] * da[c];
            }
        }
        for i in 0..3 {
            full.jacobian[i][cb + i] += 1.0;
        }
        for k in 0..4 {
            let dn = axes_h[k].cross(&n);
            let dwh = -(sp.hess * dn) * alpha;
            let dwb = if round {
                Vec3::zeros()
            } else {
                (axes_b[k].cross(&sp.w) + sp.hess * axes_b[k].cross(&n)) * alpha
            };
            for i in 0..3 {
                full.jacobian[i][ch + 3 + k] += dwh[i];
                if round {
                    full.jacobian[i][cb + 3 + k] = 0.0;
                } else {
                    full.jacobian[i][cb + 3 + k] += dwb[i];
                }
            }
        }
        full.prox.derivatives = if sp.unique {
            DerivativeKind::Exact
        } else {
            DerivativeKind::Subgradient
        };
        let finite = full.jacobian.iter().flatten().all(|v| v.is_finite());
        super::derivatives::check_representable(finite, self.pose_h, self.pose_b)?;
        if !finite {
            full.prox.status = SolveStatus::NumericalFailure;
            full.gradient = [0.0; 14];
            full.jacobian = [[0.0; 14]; 4];
        }
        Ok(full)
    }

    /// The signed distance, its normal (from shape 1 to shape 2) and witness points.
    pub(crate) fn signed_distance(&self) -> Result<SignedDistance, Error> {
        let sp = self.support()?;
        self.answer(sp.g, sp.h, &sp.w)
    }

    /// [`Self::signed_distance`]'s distance and normal (the same bits: they depend on the
    /// support value alone), its witnesses from one support point instead of the centroid of
    /// the tied ones: for the contact manifold, which needs the witnesses only where its points
    /// miss the deepest one (and then asks for [`Self::signed_distance`]).
    pub(crate) fn signed_distance_of_one_support(&self) -> Result<SignedDistance, Error> {
        let (g, _, _, s, h) = self.support_point()?;
        self.answer(g, h, &(self.pose_b.rotation() * s))
    }

    /// The signed distance `g − c − h` with the witness `r_B + w` on B.
    fn answer(&self, g: Real, h: Real, w: &Vec3) -> Result<SignedDistance, Error> {
        Ok(self.signed(g, h, w))
    }

    /// [`Self::answer`]'s signed distance (also the box-on-plane contacts').
    pub(crate) fn signed(&self, g: Real, h: Real, w: &Vec3) -> SignedDistance {
        let n = self.normal;
        let sd = g - self.depth - h;
        let on_b = self.pose_b.position() + w;
        let on_h = on_b - n * sd;
        let (normal, closest1, closest2) = if self.hs_first {
            (n, on_h, on_b)
        } else {
            (-n, on_b, on_h)
        };
        SignedDistance {
            distance: sd,
            normal,
            closest1,
            closest2,
            iterations: 0,
            status: SolveStatus::Converged,
            path: DistancePath::ClosedForm,
        }
    }

    /// The distance (0 when touching or overlapping, both witnesses then B's deepest point),
    /// its gradient when asked for, and whether it exceeds `cutoff`.
    pub(crate) fn distance(
        &self,
        shapes: [&Shape; 2],
        gradient: bool,
        cutoff: Option<Real>,
    ) -> Result<(Distance, [Real; 14], bool), Error> {
        let sd = self.signed_distance()?;
        let beyond = cutoff.is_some_and(|c| sd.distance > c);
        if sd.distance <= 0.0 {
            let w = if self.hs_first {
                sd.closest2
            } else {
                sd.closest1
            };
            let d = Distance {
                distance: 0.0,
                closest1: w,
                closest2: w,
                normal: Vec3::zeros(),
                iterations: 0,
                status: SolveStatus::Converged,
                path: DistancePath::ClosedForm,
            };
            return Ok((d, [0.0; 14], false));
        }
        let d = Distance {
            distance: sd.distance,
            closest1: sd.closest1,
            closest2: sd.closest2,
            normal: sd.normal,
            iterations: 0,
            status: SolveStatus::Converged,
            path: DistancePath::ClosedForm,
        };
        let mut g = [0.0; 14];
        if gradient {
            let poses = if self.hs_first {
                [self.pose_h, self.pose_b]
            } else {
                [self.pose_b, self.pose_h]
            };
            g = witness_gradient(&d.normal, &d.closest1, &d.closest2, shapes, poses);
            super::derivatives::check_representable(
                g.iter().all(|v| v.is_finite()),
                poses[0],
                poses[1],
            )?;
        }
        Ok((d, g, beyond))
    }
}
