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
        // component finite). Anything else takes the checks below, which name the culprit.
        let n2: Real = quaternion.iter().map(|v| v * v).sum();
        if (position[0] + position[1] + position[2]).is_finite()
            && n2.is_finite()
            && n2 > Real::MIN_POSITIVE
        {
            return Ok(Pose {
                position: Vec3::from(position),
                quaternion,
                rotation: rotation_from_quaternion(quaternion),
            });
        }
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

    /// A pose from a position and a rotation matrix `rotation` (world from body, by rows: a body
    /// point `b` sits at `r + R b`), used as given: no quaternion is normalised and no matrix
    /// rebuilt. `R` must be a rotation to [`ROTATION_TOLERANCE`]: every entry of `R Rᵀ − I`
    /// within it and `det R > 0` (a matrix computed from a unit quaternion, or a product of a
    /// few such, is one to about 1e-15). The quaternion kept for warm starts and derivatives is
    /// `R`'s, not normalised.
    ///
    /// Fails with [`Error::InvalidPose`] on a non-finite component or a matrix that is not a
    /// rotation to that tolerance.
    ///
    /// ```
    /// use dcol::math::Pose;
    /// let q = Pose::new([1.0, 2.0, 3.0], [0.9, 0.1, -0.3, 0.2]).unwrap();
    /// let r = q.rotation();
    /// let rows = [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]);
    /// let m = Pose::from_rotation([1.0, 2.0, 3.0], rows).unwrap();
    /// assert_eq!(m.rotation(), q.rotation());
    /// assert!(Pose::from_rotation([0.0; 3], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]).is_err());
    /// ```
    #[inline]
    pub fn from_rotation(position: [Real; 3], rotation: [[Real; 3]; 3]) -> Result<Pose, Error> {
        let [r0, r1, r2] = rotation;
        let dot = |u: &[Real; 3], v: &[Real; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        // One test for every entry of R Rᵀ − I (a NaN or infinity anywhere fails it).
        let t = ROTATION_TOLERANCE;
        let near = |v: Real, want: Real| (v - want).abs() <= t;
        // `&`, not `&&`: six comparisons without a branch each.
        let rotation_ok = near(dot(&r0, &r0), 1.0)
            & near(dot(&r1, &r1), 1.0)
            & near(dot(&r2, &r2), 1.0)
            & near(dot(&r0, &r1), 0.0)
            & near(dot(&r0, &r2), 0.0)
            & near(dot(&r1, &r2), 0.0);
        if !(position[0] + position[1] + position[2]).is_finite() {
            // Names the position's culprit (a sum of finite coordinates may overflow: then Ok).
            Pose::new(position, [1.0, 0.0, 0.0, 0.0])?;
        }
        if !rotation_ok {
            for (k, v) in rotation.iter().flatten().enumerate() {
                if !v.is_finite() {
                    return Err(Error::InvalidPose(ErrorDetail::at(
                        "rotation",
                        k,
                        *v,
                        "must be finite",
                    )));
                }
            }
            let dev = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]
                .iter()
                .map(|&(i, j)| {
                    let id = if i == j { 1.0 } else { 0.0 };
                    (dot(&rotation[i], &rotation[j]) - id).abs()
                })
                .fold(0.0, Real::max);
            return Err(Error::InvalidPose(ErrorDetail::new(
                "rotation",
                dev,
                "is not a rotation: the largest entry of R R^T - I must be at most 1e-12",
            )));
        }
        let cross = [
            r1[1] * r2[2] - r1[2] * r2[1],
            r1[2] * r2[0] - r1[0] * r2[2],
            r1[0] * r2[1] - r1[1] * r2[0],
        ];
        let det = dot(&r0, &cross);
        if !(det > 0.0) {
            return Err(Error::InvalidPose(ErrorDetail::new(
                "rotation",
                det,
                "is a reflection, not a rotation (its determinant must be positive)",
            )));
        }
        let m = Mat3::new(
            r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2],
        );
        Ok(Pose {
            position: Vec3::from(position),
            quaternion: quaternion_from_rotation(&m),
            rotation: m,
        })
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

/// How far from a rotation a matrix given to [`Pose::from_rotation`] may be: the largest entry
/// of `R Rᵀ − I`.
pub const ROTATION_TOLERANCE: Real = 1e-12;

/// A quaternion `[w, x, y, z]` of the rotation `m` (not normalised: `4 q_k q` for its largest
/// component `q_k`, Shepperd's choice, without the square root).
pub fn quaternion_from_rotation(m: &Mat3) -> [Real; 4] {
    let (m00, m11, m22) = (m[(0, 0)], m[(1, 1)], m[(2, 2)]);
    let t = m00 + m11 + m22;
    if t >= m00 && t >= m11 && t >= m22 {
        [
            1.0 + t,
            m[(2, 1)] - m[(1, 2)],
            m[(0, 2)] - m[(2, 0)],
            m[(1, 0)] - m[(0, 1)],
        ]
    } else if m00 >= m11 && m00 >= m22 {
        [
            m[(2, 1)] - m[(1, 2)],
            1.0 + m00 - m11 - m22,
            m[(0, 1)] + m[(1, 0)],
            m[(0, 2)] + m[(2, 0)],
        ]
    } else if m11 >= m22 {
        [
            m[(0, 2)] - m[(2, 0)],
            m[(0, 1)] + m[(1, 0)],
            1.0 - m00 + m11 - m22,
            m[(1, 2)] + m[(2, 1)],
        ]
    } else {
        [
            m[(1, 0)] - m[(0, 1)],
            m[(0, 2)] + m[(2, 0)],
            m[(1, 2)] + m[(2, 1)],
            1.0 - m00 - m11 + m22,
        ]
    }
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

    /// A pose from a rotation matrix: the matrix kept as given, its quaternion the same rotation
    /// (each of Shepperd's four branches: attitudes near the identity and near half turns about
    /// each axis); bad matrices rejected with the culprit named.
    #[test]
    fn pose_from_rotation() {
        let mut seed = 3u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
        };
        let mut qs = vec![
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [1e-9, 1.0, 1e-3, 0.0],
            [0.0, 1e-3, 1.0, 1e-9],
        ];
        for _ in 0..2000 {
            qs.push([rnd(), rnd(), rnd(), rnd()]);
        }
        for q in qs {
            let p = Pose::new([rnd(), rnd(), rnd()], q).unwrap();
            let r = p.rotation();
            let rows = [0, 1, 2].map(|i| [r[(i, 0)], r[(i, 1)], r[(i, 2)]]);
            let m = Pose::from_rotation([p.position.x, p.position.y, p.position.z], rows).unwrap();
            assert_eq!(m.rotation(), p.rotation());
            assert_eq!(m.position(), p.position());
            // Its quaternion is the rotation's, up to scale and sign.
            let q2 = m.quaternion();
            let n1: Real = q.iter().map(|v| v * v).sum::<Real>().sqrt();
            let n2: Real = q2.iter().map(|v| v * v).sum::<Real>().sqrt();
            let dot: Real = q.iter().zip(&q2).map(|(a, b)| a * b).sum();
            assert!((dot.abs() / (n1 * n2) - 1.0).abs() < 1e-14, "{q:?} {q2:?}");
            assert!((rotation_from_quaternion(q2) - r).norm() < 1e-14);
        }
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(Pose::from_rotation([1e308, 1e308, 0.0], id).is_ok());
        let bad = |pos: [Real; 3], m: [[Real; 3]; 3], what: &str| {
            let e = Pose::from_rotation(pos, m).unwrap_err();
            assert!(matches!(e, Error::InvalidPose(_)));
            assert!(e.to_string().contains(what), "{e}");
        };
        bad([0.0, Real::NAN, 0.0], id, "position");
        let mut m = id;
        m[1][2] = Real::INFINITY;
        bad([0.0; 3], m, "rotation");
        m[1][2] = 2e-12;
        bad([0.0; 3], m, "not a rotation");
        m[1][2] = 5e-13; // within the tolerance
        assert!(Pose::from_rotation([0.0; 3], m).is_ok());
        bad(
            [0.0; 3],
            [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]],
            "reflection",
        );
        bad(
            [0.0; 3],
            [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "not a rotation",
        );
    }
}
