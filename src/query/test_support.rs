//! What the derivatives' closed-form tests share: a seeded random source, their test shapes'
//! data, the geometric answer with its gradient, and the non-dimensional difference of two
//! Jacobians.

use super::context::{Options, Proximity};
use super::geometric::{self, Outcome};
use crate::math::robust_norm;
use crate::{Pose, Real, Shape, Vec3};

/// A xorshift64 source: the same numbers on every machine.
pub(crate) struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> Real {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as Real / (1u64 << 53) as Real
    }
    /// Uniform in [lo, hi).
    pub(crate) fn uniform(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * self.unit()
    }
    /// Four components in [−1, 1): a quaternion of any length (the columns are taken through
    /// the normalisation).
    pub(crate) fn quaternion(&mut self) -> [Real; 4] {
        [0; 4].map(|_| self.uniform(-1.0, 1.0))
    }
    /// A position in [−spread, spread)³ and a random quaternion.
    pub(crate) fn pose(&mut self, spread: Real) -> Pose {
        let p = [0; 3].map(|_| self.uniform(-spread, spread));
        Pose::new(p, self.quaternion()).unwrap()
    }
    /// A unit direction, uniform on the sphere (rejection from the ball, norms in (0.1, 1]).
    pub(crate) fn direction(&mut self) -> [Real; 3] {
        loop {
            let v = [0; 3].map(|_| self.uniform(-1.0, 1.0));
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

pub(crate) use crate::math::lcg;

/// A polytope of 14 random facets at distances 0.4–0.6 (normals drawn first, then offsets).
pub(crate) fn random_polytope(rng: &mut Rng) -> Shape {
    let normals: Vec<[Real; 3]> = (0..14).map(|_| rng.direction()).collect();
    let offsets: Vec<Real> = (0..14).map(|_| rng.uniform(0.4, 0.6)).collect();
    Shape::polytope(&normals, &offsets).unwrap()
}

/// 30 random points 0.4–0.6 from the origin, stretched 1.2 : 1 : 0.8 (the tests' hulls).
pub(crate) fn hull_points(rng: &mut Rng) -> Vec<[Real; 3]> {
    (0..30)
        .map(|_| {
            let d = rng.direction();
            let r = rng.uniform(0.4, 0.6);
            [d[0] * r * 1.2, d[1] * r, d[2] * r * 0.8]
        })
        .collect()
}

/// The edge normals of a regular pentagon (the tests' padded polygon, offsets 0.5).
pub(crate) fn pentagon() -> Vec<[Real; 2]> {
    (0..5)
        .map(|i| {
            let t = i as Real * std::f64::consts::TAU / 5.0;
            [t.cos(), t.sin()]
        })
        .collect()
}

/// Non-dimensional largest difference of two Jacobians (r columns times ℓ, x rows over ℓ).
pub(crate) fn gap(a: &[[Real; 14]; 4], b: &[[Real; 14]; 4], ell: Real) -> Real {
    let mut worst: Real = 0.0;
    for r in 0..4 {
        for c in 0..14 {
            let k = if c % 7 < 3 { ell } else { 1.0 } / if r < 3 { ell } else { 1.0 };
            worst = worst.max((a[r][c] - b[r][c]).abs() * k);
        }
    }
    worst
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` by central differences of step `h` on the public proximity
/// query (default options): the closed-form Jacobians' independent reference.
pub(crate) fn central_jacobian(s: [&Shape; 2], p: [&Pose; 2], h: Real) -> [[Real; 14]; 4] {
    let o = Options::default();
    let row = |p1: &Pose, p2: &Pose| {
        let r = crate::proximity(s[0], p1, s[1], p2, &o).unwrap();
        [r.point.x, r.point.y, r.point.z, r.alpha]
    };
    let mut fd = [[0.0; 14]; 4];
    for col in 0..14 {
        let (i, k) = (col / 7, col % 7);
        let moved = |sign: Real| {
            let (mut r, mut q) = (*p[i].position(), p[i].quaternion());
            if k < 3 {
                r[k] += sign * h;
            } else {
                q[k - 3] += sign * h;
            }
            let moved = Pose::new(r.into(), q).unwrap();
            if i == 0 {
                row(&moved, p[1])
            } else {
                row(p[0], &moved)
            }
        };
        let (up, down) = (moved(1.0), moved(-1.0));
        for r in 0..4 {
            fd[r][col] = (up[r] - down[r]) / (2.0 * h);
        }
    }
    fd
}

/// The public Jacobian with the closed forms switched off (the general feature solve) and on,
/// against a closed form's `jc`: both give the same proximity answer with exact derivatives,
/// and the public one is `jc` to the last bit. Returns the general solve's Jacobian.
pub(crate) fn general_beside(
    s: [&Shape; 2],
    p: [&Pose; 2],
    jc: &[[Real; 14]; 4],
) -> [[Real; 14]; 4] {
    let o = Options::default();
    geometric::GENERAL_ONLY.with(|g| g.set(true));
    let general = crate::jacobian(s[0], p[0], s[1], p[1], &o).unwrap();
    geometric::GENERAL_ONLY.with(|g| g.set(false));
    let fast = crate::jacobian(s[0], p[0], s[1], p[1], &o).unwrap();
    assert_eq!(general.0, fast.0);
    assert_eq!(fast.0.derivatives, crate::DerivativeKind::Exact);
    assert_eq!(&fast.1, jc);
    general.1
}

/// The geometric answer of a pair (default options), `∂α*/∂d` and the gradient: what the
/// closed-form Jacobians start from; `None` where the geometric path does not answer.
pub(crate) fn geometric_answer(
    s: [&Shape; 2],
    p: [&Pose; 2],
) -> Option<(Proximity, Vec3, [Real; 14])> {
    let o = Options::default();
    let dist = robust_norm(&(p[1].position() - p[0].position()));
    let Outcome::Answer(prox, dad) =
        geometric::proximity(s[0], p[0], s[1], p[1], &o, dist, None, None)
    else {
        return None;
    };
    let g = geometric::gradient(&prox, &dad, s, p[0], p[1]);
    Some((prox, dad, g))
}
