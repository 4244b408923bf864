//! Support maps: every primitive as the maximum of a few smooth *pieces*.
//!
//! A convex body `B` is described to the geometric solvers by its support function
//! `h(m) = max over b ∈ B of m·b` and a support point (a maximiser). For every primitive `h` is
//! the maximum of a few pieces of one form,
//!
//! ```text
//!     p(m) = a·m + ‖m‖_round        (a: a body point; ‖·‖_round: 0, r‖m‖, r‖m_yz‖ or √(mᵀQm))
//! ```
//!
//! whose gradient `a + ∇‖m‖_round` is the support point of that piece (a point of the shape) and
//! whose Hessian is what a Newton polish needs. A sphere or ellipsoid is one piece; a polytope
//! one linear piece per vertex; a capsule two (its end balls), a cylinder two (its rim circles),
//! a cone two (apex and base rim), a padded polygon one per polygon vertex. Where the round part
//! is not differentiable (a cylinder's or cone's flat disc, `m_yz = 0`) the shape has a flat
//! face, reported by `flat_face` instead.

use crate::math::{Mat3, Real, Vec3};

/// The curved part of a piece: `‖m‖_round`.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Round<'a> {
    /// Linear piece (a polytope vertex, a cone's apex).
    Flat,
    /// `r‖m‖`: a ball of radius `r` (sphere, capsule end, padded polygon corner).
    Ball(Real),
    /// `r‖(m_y, m_z)‖`: a circle of radius `r` in the body y-z plane (cylinder and cone rims).
    Circle(Real),
    /// `√(mᵀQm)` with `Q` symmetric positive definite (an ellipsoid, `Q = P⁻¹`).
    Quadric(&'a Mat3),
}

/// A piece evaluated at a direction: value, gradient (its support point) and Hessian.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PieceEval {
    /// `p(m)`.
    pub value: Real,
    /// `∇p(m)`: the piece's support point (body frame).
    pub grad: Vec3,
    /// `∇²p(m)`.
    pub hess: Mat3,
}

impl PieceEval {
    /// The value, the point and the Hessian reduced to the two directions `b`.
    #[inline(always)]
    pub(crate) fn reduced(&self, b: &[Vec3; 2]) -> Reduced {
        let (h0, h1) = (self.hess * b[0], self.hess * b[1]);
        Reduced {
            value: self.value,
            grad: self.grad,
            hess: [b[0].dot(&h0), b[0].dot(&h1), b[1].dot(&h1)],
        }
    }
}

/// Relative size below which the round part of a piece counts as not differentiable.
pub(crate) const ROUND_EPS: Real = 1e-300;

impl Round<'_> {
    /// The round part's support point at `m` (its gradient); at the one direction where it is
    /// not unique (`m = 0`, or `m_yz = 0` for a circle) any point of the round part.
    #[inline]
    pub(crate) fn point(&self, m: &Vec3) -> Vec3 {
        match *self {
            Round::Flat => Vec3::zeros(),
            Round::Ball(r) => {
                let n = m.norm();
                if n > ROUND_EPS {
                    m * (r / n)
                } else {
                    Vec3::new(r, 0.0, 0.0)
                }
            }
            Round::Circle(r) => {
                let n = (m.y * m.y + m.z * m.z).sqrt();
                if n > ROUND_EPS {
                    Vec3::new(0.0, m.y * (r / n), m.z * (r / n))
                } else {
                    Vec3::new(0.0, r, 0.0)
                }
            }
            Round::Quadric(q) => {
                let qm = q * m;
                let s = m.dot(&qm);
                if s > 0.0 {
                    qm / s.sqrt()
                } else {
                    Vec3::zeros()
                }
            }
        }
    }

    /// Value, gradient and Hessian of `a·m + ‖m‖_round`; `None` where the round part is not
    /// differentiable. Always inlined, so that a search taking only the value and the gradient
    /// ([`SupportMap::piece_point`]) does not form the Hessian.
    #[inline(always)]
    pub(crate) fn eval(&self, a: &Vec3, m: &Vec3) -> Option<PieceEval> {
        let (value, grad, hess) = match *self {
            Round::Flat => (0.0, Vec3::zeros(), Mat3::zeros()),
            Round::Ball(r) => {
                let n = m.norm();
                if !(n > ROUND_EPS) {
                    return None;
                }
                let u = m / n;
                (
                    r * n,
                    u * r,
                    (Mat3::identity() - u * u.transpose()) * (r / n),
                )
            }
            Round::Circle(r) => {
                let n = (m.y * m.y + m.z * m.z).sqrt();
                if !(n > ROUND_EPS * m.norm().max(ROUND_EPS)) {
                    return None;
                }
                let u = Vec3::new(0.0, m.y / n, m.z / n);
                let p = Mat3::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
                (r * n, u * r, (p - u * u.transpose()) * (r / n))
            }
            Round::Quadric(q) => {
                let qm = q * m;
                let s2 = m.dot(&qm);
                if !(s2 > 0.0) {
                    return None;
                }
                let s = s2.sqrt();
                let g = qm / s;
                (s, g, (q - g * g.transpose()) / s)
            }
        };
        Some(PieceEval {
            value: value + a.dot(m),
            grad: grad + a,
            hess,
        })
    }
}

impl Round<'_> {
    /// [`Round::eval`] with the gradient kept and the Hessian reduced to the two directions
    /// `b` (`[b₀ᵀ∇²b₀, b₀ᵀ∇²b₁, b₁ᵀ∇²b₁]`), without forming it: a circle's Hessian is
    /// `(r/n) w wᵀ` with `w = (0, −u_z, u_y)`, a ball's `(r/n)(I − u uᵀ)`. The same numbers as
    /// reducing `eval`'s Hessian, up to rounding.
    #[inline(always)]
    pub(crate) fn eval_reduced(&self, a: &Vec3, m: &Vec3, b: &[Vec3; 2]) -> Option<Reduced> {
        let (value, grad, hess) = match *self {
            Round::Flat => (0.0, Vec3::zeros(), [0.0; 3]),
            Round::Ball(r) => {
                let n = m.norm();
                if !(n > ROUND_EPS) {
                    return None;
                }
                let u = m / n;
                let s = r / n;
                let (u0, u1) = (b[0].dot(&u), b[1].dot(&u));
                (
                    r * n,
                    u * r,
                    [
                        (b[0].dot(&b[0]) - u0 * u0) * s,
                        (b[0].dot(&b[1]) - u0 * u1) * s,
                        (b[1].dot(&b[1]) - u1 * u1) * s,
                    ],
                )
            }
            Round::Circle(r) => {
                let n = (m.y * m.y + m.z * m.z).sqrt();
                if !(n > ROUND_EPS * m.norm().max(ROUND_EPS)) {
                    return None;
                }
                let (uy, uz) = (m.y / n, m.z / n);
                let s = r / n;
                let (w0, w1) = (b[0].z * uy - b[0].y * uz, b[1].z * uy - b[1].y * uz);
                (
                    r * n,
                    Vec3::new(0.0, uy * r, uz * r),
                    [w0 * w0 * s, w0 * w1 * s, w1 * w1 * s],
                )
            }
            Round::Quadric(_) => {
                let e = self.eval(&Vec3::zeros(), m)?;
                let (h0, h1) = (e.hess * b[0], e.hess * b[1]);
                (
                    e.value,
                    e.grad,
                    [b[0].dot(&h0), b[0].dot(&h1), b[1].dot(&h1)],
                )
            }
        };
        Some(Reduced {
            value: value + a.dot(m),
            grad: grad + a,
            hess,
        })
    }
}

/// A piece's value and support point at `m` and its Hessian reduced to two directions
/// ([`SupportMap::piece_reduced`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reduced {
    /// `p(m)`.
    pub value: Real,
    /// `∇p(m)`: the piece's support point (body frame).
    pub grad: Vec3,
    /// `[b₀ᵀ∇²p b₀, b₀ᵀ∇²p b₁, b₁ᵀ∇²p b₁]`.
    pub hess: [Real; 3],
}

/// What the geometric solvers need of a shape: its support map, its pieces, its flat faces.
/// Everything is in the body frame and in the shape's own units.
/// `rot · support(rotᵀn)`: the support point of a shape turned by `rot`, in world axes.
#[inline(always)]
pub(crate) fn turned<S: SupportMap + ?Sized>(shape: &S, rot: &Mat3, n: &Vec3) -> (Vec3, u32) {
    let (p, id) = shape.support(&rot.tr_mul(n));
    (rot * p, id)
}

pub(crate) trait SupportMap {
    /// A support point for direction `m` (any `m ≠ 0`; not necessarily unit) and the index of the
    /// piece it belongs to. `h(m) = m·point`.
    fn support(&self, m: &Vec3) -> (Vec3, u32);
    /// [`SupportMap::support`] for a world direction `n` of the shape turned by `rot` (world
    /// from body), the point in world axes: `rot · support(rotᵀn)`. A shape whose support
    /// needs less than the two turns may say so.
    #[inline(always)]
    fn support_world(&self, rot: &Mat3, n: &Vec3) -> (Vec3, u32) {
        turned(self, rot, n)
    }
    /// Piece `id` evaluated at `m` (`None` where it is not differentiable or `id` is unknown).
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval>;
    /// [`SupportMap::piece`] with its Hessian reduced to the two body directions `b`
    /// (Newton's method in a plane of normals needs no more). Shapes whose pieces are
    /// [`Round`]s may skip forming the Hessian ([`Round::eval_reduced`]).
    #[inline(always)]
    fn piece_reduced(&self, id: u32, m: &Vec3, b: &[Vec3; 2]) -> Option<Reduced> {
        self.piece(id, m).map(|e| e.reduced(b))
    }
    /// [`SupportMap::piece`]'s value and support point only (the same numbers), for searches
    /// that never use the Hessian: inlined, the Hessian is not formed.
    #[inline(always)]
    fn piece_point(&self, id: u32, m: &Vec3) -> Option<(Real, Vec3)> {
        self.piece(id, m).map(|e| (e.value, e.grad))
    }
    /// The outward unit normal of a flat face (a polytope facet, a disc, a padded polygon's
    /// top or bottom) whose normal makes an angle with `m` of cosine at least `cos_min`,
    /// the closest such one; `None` if there is none.
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3>;
    /// An upper bound `g` on the gauge of body point `p` (the least `t ≥ 0` with `p ∈ tB`), so
    /// that `p/g` lies in the shape: exact for the sphere, ellipsoid, polytope, cylinder and
    /// cone; for the capsule and padded polygon the gauge of an inscribed cylinder or prism.
    fn gauge(&self, p: &Vec3) -> Real;
    /// The outward unit normal at point `p` of piece `id` when the piece is strictly convex
    /// there (a ball or ellipsoid patch: its support point determines its direction); `None`
    /// for flat pieces and rims.
    fn normal_at(&self, _id: u32, _p: &Vec3) -> Option<Vec3> {
        None
    }
    /// The number of pieces: their ids are `0..piece_count()`.
    fn piece_count(&self) -> u32;
    /// A flat disc of the shape (a cylinder's cap, a cone's base) whose outward normal makes an
    /// angle with `m` of cosine at least `cos_min`: its centre (body frame) and radius. Every
    /// disc's normal is `±e_x`, so its points are `centre + (0, y, z)` with `y² + z² ≤ radius²`.
    fn disc(&self, _m: &Vec3, _cos_min: Real) -> Option<(Vec3, Real)> {
        None
    }
    /// The pieces' points (body frame) when every piece is a plain vertex, `p(m) = v·m` with
    /// piece `id` the `id`-th point (a polytope): a search over all pieces can then take the
    /// dot products instead of evaluating each piece with its Hessian.
    fn vertex_pieces(&self) -> Option<&[Vec3]> {
        None
    }
    /// The pieces' points (body frame) and radius when every piece is a vertex padded by the
    /// same ball, `p(m) = v·m + r‖m‖` (a padded hull, a padded polygon): a search over all
    /// pieces can then take the norm of `m` once.
    fn ball_pieces(&self) -> Option<(&[Vec3], Real)> {
        None
    }
    /// The support set at `m` in closed form, where the shape's pieces differ along its axes
    /// only (a centred box, a capsule's or cylinder's two ends): its affine dimension and, when
    /// that is one, its direction (body), as a search of the pieces decides it: pieces within
    /// `tie` of the support value tie, tied points closer than `point` are one. `None`: no
    /// closed form here (or a piece not differentiable at `m`); search the pieces.
    fn support_set(&self, _m: &Vec3, _tie: Real, _point: Real) -> Option<(usize, Vec3)> {
        None
    }
}

/// [`SupportMap::support_set`] of two pieces `length` apart along body x that differ at `m` by
/// `length·|m_x|` (a capsule's or cylinder's ends).
#[inline]
pub(crate) fn two_ends_set(length: Real, m: &Vec3, tie: Real, point: Real) -> (usize, Vec3) {
    if length * m.x.abs() <= tie && length > point {
        (1, Vec3::x())
    } else {
        (0, Vec3::zeros())
    }
}

/// The normal of a ball piece about `center` at `p`.
#[inline]
pub(crate) fn ball_normal(center: &Vec3, p: &Vec3) -> Option<Vec3> {
    (p - center).try_normalize(0.0)
}

/// The best of a set of points in direction `m`: `(index, m·point)`.
#[inline]
pub(crate) fn argmax_dot(points: &[Vec3], m: &Vec3) -> (usize, Real) {
    let mut best = 0;
    let mut best_h = Real::NEG_INFINITY;
    for (k, p) in points.iter().enumerate() {
        let h = p.dot(m);
        if h > best_h {
            best_h = h;
            best = k;
        }
    }
    (best, best_h)
}

/// The closest of a set of unit normals to `m` if its cosine is at least `cos_min`.
pub(crate) fn nearest_normal(normals: &[Vec3], m: &Vec3, cos_min: Real) -> Option<Vec3> {
    let n = m.norm();
    if !(n > 0.0) {
        return None;
    }
    let (k, c) = argmax_dot(normals, m);
    (c >= cos_min * n).then(|| normals[k])
}

/// At most this many active rows enter [`multipliers`] (more meet at one corner only in
/// contrived polytopes; the rest are left out, and the answer is marked not unique).
pub(crate) const MAX_ACTIVE_ROWS: usize = 8;

/// The rows active at a support point: their indices and unit normals, and whether all of
/// them fitted.
pub(crate) struct Active {
    pub ids: [usize; MAX_ACTIVE_ROWS],
    pub rows: [Vec3; MAX_ACTIVE_ROWS],
    pub n: usize,
    pub all: bool,
}

impl Active {
    pub(crate) fn new() -> Self {
        Active {
            ids: [0; MAX_ACTIVE_ROWS],
            rows: [Vec3::zeros(); MAX_ACTIVE_ROWS],
            n: 0,
            all: true,
        }
    }

    /// Adds row `i` with unit normal `row` (or notes that it did not fit).
    #[inline]
    pub(crate) fn push(&mut self, i: usize, row: Vec3) {
        if self.n == MAX_ACTIVE_ROWS {
            self.all = false;
        } else {
            self.ids[self.n] = i;
            self.rows[self.n] = row;
            self.n += 1;
        }
    }
}

/// The multipliers `λ ≥ 0` with `Σ λ_k rows_k = m` of the rows active at a support point (the
/// dual of the support function's linear program `max m·x s.t. a_k·x ≤ b_k`: `∂h/∂b_k = λ_k`,
/// `∂h/∂a_k = −λ_k x`), in a space of dimension `dim` (2: rows with a zero z, a polygon's
/// edges; 3: a polytope's facets). Up to `dim` independent rows have one solution (the
/// normal equations); more, as at a corner where four facets meet, have many: the first subset
/// of `dim` rows with a solution `λ ≥ 0` is taken, and the flag says whether every such subset
/// gives the same `λ` (then it is unique). The flag is also false when no exact solution exists
/// (the rows given do not span `m`: the least-squares one is returned).
pub(crate) fn multipliers(rows: &[Vec3], m: &Vec3, dim: usize) -> ([Real; MAX_ACTIVE_ROWS], bool) {
    let mut lam = [0.0; MAX_ACTIVE_ROWS];
    let n = rows.len().min(MAX_ACTIVE_ROWS);
    let scale = m.norm();
    if n == 0 || !(scale > 0.0) {
        return (lam, n == rows.len() && !(scale > 0.0));
    }
    let tol = 1e-9 * scale;
    // The common case: at most `dim` independent rows.
    if n <= dim {
        if let Some((x, residual)) = gram_solve(&rows[..n], m) {
            if residual <= 1e-9 * scale && x[..n].iter().all(|v| *v >= -tol) {
                lam[..n].copy_from_slice(&x[..n]);
                return (lam, n == rows.len());
            }
        }
    }
    // Dependent rows, or more rows than the dimension: every subset of at most `dim` of them
    // with an exact solution λ ≥ 0.
    let mut found = false;
    let mut unique = n == rows.len();
    let mut subset = |ids: &[usize]| {
        let sub: [Vec3; 3] = [0, 1, 2].map(|k| ids.get(k).map_or(Vec3::zeros(), |&i| rows[i]));
        let Some((x, residual)) = gram_solve(&sub[..ids.len()], m) else {
            return;
        };
        if residual > 1e-9 * scale || x[..ids.len()].iter().any(|v| *v < -tol) {
            return;
        }
        let mut full = [0.0; MAX_ACTIVE_ROWS];
        for (k, &i) in ids.iter().enumerate() {
            full[i] = x[k];
        }
        if !found {
            lam = full;
            found = true;
        } else if (0..n).any(|i| (full[i] - lam[i]).abs() > 1e-9 * (1.0 + lam[i].abs())) {
            unique = false;
        }
    };
    for i in 0..n {
        subset(&[i]);
        for j in (i + 1)..n {
            subset(&[i, j]);
            if dim == 3 {
                for k in (j + 1)..n {
                    subset(&[i, j, k]);
                }
            }
        }
    }
    if !found {
        // No subset solves it exactly (the rows do not span m: a missed active row, or
        // rounding at a nearly degenerate corner): the least-squares solution of the first rows.
        let k = dim.min(n);
        if let Some((x, _)) = gram_solve(&rows[..k], m) {
            lam[..k].copy_from_slice(&x[..k]);
        }
        unique = false;
    }
    (lam, unique)
}

/// The least-squares solution `x` of `Σ x_k rows_k = m` for at most three independent rows (the
/// normal equations), and its residual; `None` when the rows are dependent.
fn gram_solve(rows: &[Vec3], m: &Vec3) -> Option<([Real; 3], Real)> {
    let k = rows.len();
    match k {
        // Closed forms for the common cases: a facet, and a simple corner (Cramer's rule on
        // `Σ x_k rows_k = m`, exact, so no residual).
        1 => {
            let rr = rows[0].norm_squared();
            if !(rr > 0.0) {
                return None;
            }
            let x = rows[0].dot(m) / rr;
            return Some(([x, 0.0, 0.0], (rows[0] * x - m).norm()));
        }
        2 => {
            let (g00, g01, g11) = (
                rows[0].norm_squared(),
                rows[0].dot(&rows[1]),
                rows[1].norm_squared(),
            );
            let det = g00 * g11 - g01 * g01;
            if !(det > 1e-20 * g00 * g11) {
                return None;
            }
            let (b0, b1) = (rows[0].dot(m), rows[1].dot(m));
            let (x0, x1) = ((g11 * b0 - g01 * b1) / det, (g00 * b1 - g01 * b0) / det);
            return Some(([x0, x1, 0.0], (rows[0] * x0 + rows[1] * x1 - m).norm()));
        }
        3 => {
            let (c0, c1, c2) = (
                rows[1].cross(&rows[2]),
                rows[2].cross(&rows[0]),
                rows[0].cross(&rows[1]),
            );
            let det = rows[0].dot(&c0);
            let scale = rows[0].norm_squared() * rows[1].norm_squared() * rows[2].norm_squared();
            if !(det * det > 1e-20 * scale) {
                return None;
            }
            return Some(([m.dot(&c0) / det, m.dot(&c1) / det, m.dot(&c2) / det], 0.0));
        }
        _ => {}
    }
    let mut g = Mat3::identity();
    let mut rhs = Vec3::zeros();
    let mut big: Real = 0.0;
    for a in 0..k {
        rhs[a] = rows[a].dot(m);
        for b in 0..k {
            g[(a, b)] = rows[a].dot(&rows[b]);
        }
        big = big.max(g[(a, a)]);
    }
    let det = g.determinant();
    if !(det.abs() > 1e-20 * big.powi(k as i32)) {
        return None;
    }
    let x = g.try_inverse()? * rhs;
    let mut fit = Vec3::zeros();
    for a in 0..k {
        fit += rows[a] * x[a];
    }
    Some(([x[0], x[1], x[2]], (fit - m).norm()))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::shapes::Shape;

    /// Checks a shape's support map against brute force over sampled directions: the support
    /// point's value `m·s` is at least that of every other support point seen (so `h` is the
    /// maximum over the shape's points), the piece reproduces the point, and the piece's
    /// gradient and Hessian match finite differences.
    pub(crate) fn check_support(shape: &Shape) {
        let dirs: Vec<Vec3> = (0..400)
            .map(|i| {
                let t = i as Real * 0.618_033_988_75;
                let z = 1.0 - 2.0 * ((i as Real + 0.5) / 400.0);
                let r = (1.0 - z * z).sqrt();
                let phi = t * std::f64::consts::TAU;
                Vec3::new(r * phi.cos(), r * phi.sin(), z)
            })
            .collect();
        let pts: Vec<Vec3> = dirs.iter().map(|m| shape.support(m).0).collect();
        for m in &dirs {
            let (s, id) = shape.support(m);
            let h = s.dot(m);
            for p in &pts {
                assert!(
                    p.dot(m) <= h + 1e-12,
                    "{:?}: support not maximal",
                    shape.kind()
                );
            }
            if let Some(e) = shape.piece(id, m) {
                assert!((e.grad - s).norm() < 1e-12, "piece point differs");
                assert!((e.value - h).abs() < 1e-12, "piece value differs");
                let step = 1e-6;
                for j in 0..3 {
                    let mut mp = *m;
                    let mut mm = *m;
                    mp[j] += step;
                    mm[j] -= step;
                    let (ep, em) = (shape.piece(id, &mp).unwrap(), shape.piece(id, &mm).unwrap());
                    let fd_g = (ep.value - em.value) / (2.0 * step);
                    assert!((fd_g - e.grad[j]).abs() < 1e-6, "gradient vs FD");
                    let fd_h = (ep.grad - em.grad) / (2.0 * step);
                    for i in 0..3 {
                        assert!((fd_h[i] - e.hess[(i, j)]).abs() < 1e-5, "Hessian vs FD");
                    }
                }
            }
        }
    }

    /// One of each primitive, the padded polygon last.
    fn primitives() -> [Shape; 7] {
        [
            Shape::sphere(0.7).unwrap(),
            Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap(),
            Shape::cuboid(1.0, 0.5, 0.25).unwrap(),
            Shape::capsule(0.3, 1.2).unwrap(),
            Shape::cylinder(0.4, 1.0).unwrap(),
            Shape::cone(1.5, 0.4).unwrap(),
            Shape::polygon(
                &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
                &[0.5; 4],
                0.1,
            )
            .unwrap(),
        ]
    }

    #[test]
    fn every_primitive_support_map_is_maximal_and_pieces_match() {
        for s in &primitives() {
            check_support(s);
        }
    }

    /// `piece_reduced` against `piece`'s Hessian reduced by hand, on every primitive's pieces
    /// (the default for polytopes and ellipsoids; `Round::eval_reduced` for cylinders' and
    /// cones' rims and apexes): the same value and point to rounding, the reduced Hessian to
    /// 1e-12 of its scale, over 400 directions and two arbitrary (not orthonormal) directions.
    #[test]
    fn reduced_pieces_equal_the_reduced_hessians() {
        let all = primitives();
        let shapes = &all[..6];
        let b = [Vec3::new(0.3, -1.2, 0.5), Vec3::new(-0.7, 0.2, 1.1)];
        let mut checked = 0;
        for shape in shapes {
            for i in 0..400 {
                let t = i as Real * 0.618_033_988_75 * std::f64::consts::TAU;
                let z = 1.0 - 2.0 * ((i as Real + 0.5) / 400.0);
                let m = Vec3::new(
                    (1.0 - z * z).sqrt() * t.cos(),
                    (1.0 - z * z).sqrt() * t.sin(),
                    z,
                ) * 2.5;
                for id in 0..shape.piece_count() {
                    let (Some(e), Some(r)) = (shape.piece(id, &m), shape.piece_reduced(id, &m, &b))
                    else {
                        assert!(
                            shape.piece(id, &m).is_none()
                                == shape.piece_reduced(id, &m, &b).is_none()
                        );
                        continue;
                    };
                    assert!((e.value - r.value).abs() <= 1e-14 * e.value.abs().max(1.0));
                    assert!((e.grad - r.grad).norm() <= 1e-14 * e.grad.norm().max(1.0));
                    let want = [
                        b[0].dot(&(e.hess * b[0])),
                        b[0].dot(&(e.hess * b[1])),
                        b[1].dot(&(e.hess * b[1])),
                    ];
                    let scale = e.hess.norm() * b[0].norm() * b[1].norm() + 1e-300;
                    for k in 0..3 {
                        assert!(
                            (want[k] - r.hess[k]).abs() <= 1e-12 * scale,
                            "{:?} piece {id} at {m:?}: {want:?} vs {:?}",
                            shape.kind(),
                            r.hess
                        );
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 2000, "{checked}");
    }
}
