//! Fixed-size math: the scalar type, vectors, rotation matrices and poses.
//!
//! Poses follow `CONVENTIONS.md`: a position `r` in world coordinates and an attitude given as a
//! quaternion `q = [w, x, y, z]` (scalar first, world-from-body), so a body point `b` sits at
//! `r + Q(q) b`. A quaternion that is not unit length is normalised before use; the raw value is
//! kept because derivatives are taken with respect to it. Modified Rodrigues parameters (MRPs)
//! `p` map to `q = [1 - p·p, 2p] / (1 + p·p)`.

use crate::error::{Error, ErrorDetail};

/// The scalar type used throughout.
pub type Real = f64;
/// A 3-vector.
pub type Vec3 = nalgebra::Vector3<Real>;
/// A 3×3 matrix (rotation matrices, ellipsoid matrices).
pub type Mat3 = nalgebra::Matrix3<Real>;

/// A rigid pose: position and attitude of a shape's body frame in the world.
///
/// ```
/// use dcol::math::Pose;
/// let pose = Pose::new([1.0, 2.0, 3.0], [2.0, 0.0, 0.0, 0.0]).unwrap(); // normalised internally
/// assert_eq!(pose.position().x, 1.0);
/// assert!((pose.rotation() - nalgebra::Matrix3::identity()).norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    position: Vec3,
    quaternion: [Real; 4],
    rotation: Mat3,
}

impl Pose {
    /// A pose from a position and a quaternion `[w, x, y, z]` (any non-zero length).
    ///
    /// Fails with [`Error::InvalidPose`] on a non-finite component or a zero quaternion.
    #[inline]
    pub fn new(position: [Real; 3], quaternion: [Real; 4]) -> Result<Pose, Error> {
        // The common case in one test: a finite sum of the position (a NaN or infinity makes it
        // NaN or infinite) and a normal squared norm of the quaternion (which needs every
        // component finite). Anything else takes `new_checked`, which names the culprit.
        if plain_pose(&position, &quaternion) {
            return Ok(Pose {
                position: Vec3::from(position),
                quaternion,
                rotation: rotation_from_quaternion(quaternion),
            });
        }
        Pose::new_checked(position, quaternion)
    }

    /// [`Pose::new`] past its common case: names the non-finite component or the zero
    /// quaternion, and rescales a quaternion whose squared norm underflows or overflows. Kept
    /// out of line so that the common case inlines into every caller (the C boundary reads two
    /// poses a call).
    #[cold]
    #[inline(never)]
    fn new_checked(position: [Real; 3], quaternion: [Real; 4]) -> Result<Pose, Error> {
        for (i, v) in position.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::InvalidPose(ErrorDetail::at(
                    "position",
                    i,
                    *v,
                    "must be finite",
                )));
            }
        }
        for (i, v) in quaternion.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::InvalidPose(ErrorDetail::at(
                    "quaternion",
                    i,
                    *v,
                    "must be finite",
                )));
            }
        }
        let n2: Real = quaternion.iter().map(|v| v * v).sum();
        // n2 can underflow to zero or overflow to infinity for extreme but finite components;
        // rescale by the largest magnitude first so that only the exact zero is rejected.
        let big = quaternion.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        if big == 0.0 {
            return Err(Error::InvalidPose(ErrorDetail::new(
                "quaternion",
                0.0,
                "must not be zero (its norm is 0)",
            )));
        }
        let q = if n2.is_finite() && n2 > Real::MIN_POSITIVE {
            quaternion
        } else {
            quaternion.map(|v| v / big)
        };
        Ok(Pose {
            position: Vec3::from(position),
            quaternion,
            rotation: rotation_from_quaternion(q),
        })
    }

    /// A pose from a position and modified Rodrigues parameters `p` (`q = [1 - p·p, 2p]/(1 + p·p)`).
    pub fn from_mrp(position: [Real; 3], mrp: [Real; 3]) -> Result<Pose, Error> {
        for (i, v) in mrp.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::InvalidPose(ErrorDetail::at(
                    "mrp",
                    i,
                    *v,
                    "must be finite",
                )));
            }
        }
        Pose::new(position, quaternion_from_mrp(mrp))
    }

    /// A pose with identity attitude.
    pub fn from_position(position: [Real; 3]) -> Result<Pose, Error> {
        Pose::new(position, [1.0, 0.0, 0.0, 0.0])
    }

    /// Position `r` of the body origin, world coordinates.
    pub fn position(&self) -> &Vec3 {
        &self.position
    }

    /// The quaternion `[w, x, y, z]` as given (not normalised).
    pub fn quaternion(&self) -> [Real; 4] {
        self.quaternion
    }

    /// The rotation matrix `Q` (world from body) of the normalised quaternion.
    pub fn rotation(&self) -> &Mat3 {
        &self.rotation
    }
}

/// [`Pose::new`]'s common case: every component finite and a quaternion whose squared norm is
/// normal (neither underflows nor overflows), so that its rotation is
/// [`rotation_from_quaternion`] of the numbers as given. One test: a finite sum of the position
/// (a NaN or infinity makes it NaN or infinite) and a finite, normal squared norm of the
/// quaternion (which needs every component finite). Anything else takes the checked
/// constructor, which names the culprit or rescales. Shared with the C ABI's closed-form lane
/// (`crate::query::closed_lane`), which takes the same poses without forming `Pose`.
#[inline(always)]
pub(crate) fn plain_pose(position: &[Real; 3], quaternion: &[Real; 4]) -> bool {
    let n2: Real = quaternion.iter().map(|v| v * v).sum();
    (position[0] + position[1] + position[2]).is_finite()
        && n2.is_finite()
        && n2 > Real::MIN_POSITIVE
}

/// `q = [1 - p·p, 2p] / (1 + p·p)` for modified Rodrigues parameters `p`.
pub fn quaternion_from_mrp(p: [Real; 3]) -> [Real; 4] {
    let pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let k = 1.0 / (1.0 + pp);
    [
        (1.0 - pp) * k,
        2.0 * p[0] * k,
        2.0 * p[1] * k,
        2.0 * p[2] * k,
    ]
}

/// Rotation matrix of the normalised quaternion `q / |q|` (`q` non-zero, `[w, x, y, z]`).
#[inline]
pub fn rotation_from_quaternion(q: [Real; 4]) -> Mat3 {
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let s = 2.0 / n2;
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    Mat3::new(
        1.0 - s * (y * y + z * z),
        s * (x * y - w * z),
        s * (x * z + w * y),
        s * (x * y + w * z),
        1.0 - s * (x * x + z * z),
        s * (y * z - w * x),
        s * (x * z - w * y),
        s * (y * z + w * x),
        1.0 - s * (x * x + y * y),
    )
}

/// Derivatives `∂Q/∂q_k` (k = 0..3) of the rotation matrix of `q/|q|` with respect to the raw
/// (not necessarily unit) quaternion components, taken through the normalisation.
pub fn rotation_derivatives(q: [Real; 4]) -> [Mat3; 4] {
    // Q is homogeneous of degree 0 in q, so ∂Q/∂q at q is (1/c)·∂Q/∂q at q/c: evaluate at
    // q/c with c the largest |q_k|, so that no square overflows or underflows.
    let c = q.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    if c != 1.0 && c > 0.0 && c.is_finite() {
        let mut d = rotation_derivatives_scaled(q.map(|v| v / c));
        for m in d.iter_mut() {
            *m /= c;
        }
        return d;
    }
    rotation_derivatives_scaled(q)
}

fn rotation_derivatives_scaled(q: [Real; 4]) -> [Mat3; 4] {
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    // Unnormalised M(q) = 2·(outer terms) with Q = I + M(q)/n2 where M is quadratic in q:
    // Q = I + (2/n2) * K(q), K = [[-(y²+z²), xy-wz, xz+wy], [xy+wz, -(x²+z²), yz-wx],
    //                             [xz-wy, yz+wx, -(x²+y²)]].
    let k = Mat3::new(
        -(y * y + z * z),
        x * y - w * z,
        x * z + w * y,
        x * y + w * z,
        -(x * x + z * z),
        y * z - w * x,
        x * z - w * y,
        y * z + w * x,
        -(x * x + y * y),
    );
    // ∂K/∂w, ∂K/∂x, ∂K/∂y, ∂K/∂z
    let dk = [
        Mat3::new(0.0, -z, y, z, 0.0, -x, -y, x, 0.0),
        Mat3::new(0.0, y, z, y, -2.0 * x, -w, z, w, -2.0 * x),
        Mat3::new(-2.0 * y, x, w, x, 0.0, z, -w, z, -2.0 * y),
        Mat3::new(-2.0 * z, -w, x, w, -2.0 * z, y, x, y, 0.0),
    ];
    let s = 2.0 / n2;
    let mut out = [Mat3::zeros(); 4];
    for i in 0..4 {
        // d(2K/n2)/dq_i = 2 dK/n2 - 2K * 2 q_i / n2²
        out[i] = dk[i] * s - k * (2.0 * s * q[i] / n2);
    }
    out
}

/// `∂q/∂p` (4×3) of the MRP-to-quaternion map, row-major `[q_k][p_j]`.
pub fn mrp_quaternion_jacobian(p: [Real; 3]) -> [[Real; 3]; 4] {
    let pp = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let d = 1.0 + pp;
    let d2 = d * d;
    let mut j = [[0.0; 3]; 4];
    for c in 0..3 {
        // q0 = (1 - pp)/d → dq0/dp_c = (-2p_c d - (1-pp) 2 p_c)/d² = -4 p_c / d²
        j[0][c] = -4.0 * p[c] / d2;
        for r in 0..3 {
            // q_{r+1} = 2 p_r / d
            let delta = if r == c { 1.0 } else { 0.0 };
            j[r + 1][c] = 2.0 * delta / d - 4.0 * p[r] * p[c] / d2;
        }
    }
    j
}

/// Whether every entry of a Jacobian is finite: `v·0` is zero for a finite `v` and NaN for an
/// infinite or NaN one, so the sum is zero exactly when all are finite (no overflow, and a
/// loop the compiler vectorises: the iterator over rows and entries cost ~900 instructions
/// for 4×14).
#[inline]
pub(crate) fn all_finite<const R: usize, const C: usize>(m: &[[Real; C]; R]) -> bool {
    m.iter().all(finite_array)
}

/// Whether every number of `a` is finite, as [`all_finite`]: about three instructions a
/// number, unrolled (the iterator chains it replaced at the C boundary cost ~275 instructions
/// for a proximity answer's ten numbers; a fold of `is_finite` over a slice ~8 a number).
#[inline]
pub(crate) fn finite_array<const N: usize>(a: &[Real; N]) -> bool {
    a.iter().map(|v| v * 0.0).sum::<Real>() == 0.0
}

/// Whether every number of `a` is finite, for long slices: [`finite_array`]'s test in four
/// independent lanes, which the compiler keeps in vector registers (a Jacobian's 56 numbers and
/// more; the one-lane sum is a chain of dependent additions).
#[inline]
pub(crate) fn finite_lanes(a: &[Real]) -> bool {
    let mut acc = [0.0; 4];
    let chunks = a.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for k in 0..4 {
            acc[k] += c[k] * 0.0;
        }
    }
    for (k, v) in rest.iter().enumerate() {
        acc[k] += v * 0.0;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) == 0.0
}

/// Uniform in [−1, 1) from a 64-bit linear congruential generator seeded with `seed` (the
/// contact and separating-axis tests' source: the same numbers on every machine). Here, below
/// both `solver` and `query`, so that either's tests take it without the two modules using
/// each other.
#[cfg(test)]
pub(crate) fn lcg(mut seed: u64) -> impl FnMut() -> Real {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
    }
}

/// Robust Euclidean norm (no underflow or overflow for finite input).
pub(crate) fn robust_norm(v: &Vec3) -> Real {
    let m = v.x.abs().max(v.y.abs()).max(v.z.abs());
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * (v / m).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `finite_lanes` finds one infinity or NaN at any place of slices of every length up to
    /// 60 (every lane and the remainder), and passes all-finite ones (huge values included).
    #[test]
    fn finite_lanes_finds_every_place() {
        for n in 0..60 {
            let ok: Vec<f64> = (0..n).map(|k| (k as f64 - 7.0) * 1e300).collect();
            assert!(super::finite_lanes(&ok), "{n}");
            for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
                for k in 0..n {
                    let mut v = ok.clone();
                    v[k] = bad;
                    assert!(!super::finite_lanes(&v), "{n}, {k}, {bad}");
                }
            }
        }
    }
    #[test]
    fn rotation_is_orthonormal_and_matches_axis_angle() {
        let t: Real = 0.7;
        let q = [(t / 2.0).cos(), 0.0, 0.0, (t / 2.0).sin()];
        let r = rotation_from_quaternion(q);
        let expect = Mat3::new(t.cos(), -t.sin(), 0.0, t.sin(), t.cos(), 0.0, 0.0, 0.0, 1.0);
        assert!((r - expect).norm() < 1e-15);
        let q2 = q.map(|v| 3.0 * v);
        assert!((rotation_from_quaternion(q2) - expect).norm() < 1e-15);
    }

    #[test]
    fn rotation_derivatives_match_finite_differences() {
        let q = [0.3, -0.4, 0.5, 0.9];
        let d = rotation_derivatives(q);
        for k in 0..4 {
            let h = 1e-6;
            let mut qp = q;
            qp[k] += h;
            let mut qm = q;
            qm[k] -= h;
            let fd = (rotation_from_quaternion(qp) - rotation_from_quaternion(qm)) / (2.0 * h);
            assert!(
                (fd - d[k]).norm() < 1e-8,
                "column {k}: {}",
                (fd - d[k]).norm()
            );
        }
    }

    #[test]
    fn mrp_jacobian_matches_finite_differences() {
        let p = [0.2, -0.3, 0.45];
        let j = mrp_quaternion_jacobian(p);
        for c in 0..3 {
            let h = 1e-6;
            let mut pp = p;
            pp[c] += h;
            let mut pm = p;
            pm[c] -= h;
            let (a, b) = (quaternion_from_mrp(pp), quaternion_from_mrp(pm));
            for r in 0..4 {
                assert!(((a[r] - b[r]) / (2.0 * h) - j[r][c]).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn pose_rejects_bad_input() {
        assert!(matches!(
            Pose::new([0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0, 0.0]),
            Err(Error::InvalidPose(_))
        ));
        assert!(matches!(
            Pose::new([0.0; 3], [0.0; 4]),
            Err(Error::InvalidPose(_))
        ));
        assert!(matches!(
            Pose::new([0.0; 3], [f64::INFINITY, 0.0, 0.0, 0.0]),
            Err(Error::InvalidPose(_))
        ));
        // Tiny and huge but finite quaternions are fine.
        let p = Pose::new([0.0; 3], [1e-200, 0.0, 0.0, 1e-200]).unwrap();
        assert!((p.rotation().determinant() - 1.0).abs() < 1e-14);
        let p = Pose::new([0.0; 3], [1e200, 0.0, 1e200, 0.0]).unwrap();
        assert!((p.rotation().determinant() - 1.0).abs() < 1e-14);
    }

    /// `all_finite` is `is_finite` of every entry: true for entries near the largest double
    /// (whose plain sum overflows), false for one infinity of either sign or one NaN anywhere.
    #[test]
    fn all_finite_is_every_entry_finite() {
        let mut m = [[Real::MAX; 14]; 4];
        m[1][3] = -Real::MAX;
        assert!(all_finite(&m));
        for (r, c) in [(0, 0), (2, 7), (3, 13)] {
            for bad in [Real::INFINITY, Real::NEG_INFINITY, Real::NAN] {
                let mut b = m;
                b[r][c] = bad;
                assert!(!all_finite(&b), "{bad} at {r},{c}");
                assert_eq!(all_finite(&b), b.iter().flatten().all(|v| v.is_finite()));
            }
        }
    }
}
