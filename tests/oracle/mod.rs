//! An independent oracle for the proximity and distance problems of `CONVENTIONS.md`, used by
//! `tests/generate_reference.rs` to make the committed reference data in `tests/data/`.
//!
//! Nothing here comes from dcol: the rotation matrix, each shape's conic constraints, the
//! normalisation and the solution checks are written from the conventions alone, and the cone
//! programs are solved by Clarabel (a general conic solver). Each Clarabel answer is then
//! *polished* and *certified*:
//!
//! 1. Clarabel solves at 1e-12 (gap and feasibility), with fallbacks if it stalls.
//! 2. The active set is read from its primal-dual point: an orthant row is active when its
//!    multiplier exceeds its slack; a second-order cone is inactive (λ ≈ 0), at its apex
//!    (s ≈ 0) or on its boundary with `λ = γ J s` (complementary boundary rays).
//! 3. Newton's method solves the KKT equations of that active set (stationarity, the active
//!    rows and apex cones at zero slack, boundary cones on their boundary) to rounding.
//! 4. The point is accepted only if every KKT condition of the *original* program holds at it,
//!    signs included (scaled residuals ≤ [`KKT_TOL`]): then it is an optimal solution of the
//!    convex program, whatever Clarabel did. A sign violation flips that row's classification
//!    and Newton runs again (at most [`MAX_FLIPS`] times).
//!
//! A certified point is *regular* when complementarity is strict (every active multiplier and
//! every inactive slack clear of zero) and the Newton matrix is well conditioned; the solution
//! is then locally unique, and since the optimal set of a convex program is convex, unique.
#![allow(dead_code)]

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};
use serde_json::{json, Value};

/// Largest scaled KKT residual a certified point may have.
pub const KKT_TOL: f64 = 1e-12;
/// Classification flips the polish may try.
pub const MAX_FLIPS: usize = 3;
/// Margin (relative) for strict complementarity.
const STRICT: f64 = 1e-8;

// ---------------------------------------------------------------------------------------------
// Small vector helpers.

pub type V3 = [f64; 3];

pub fn norm(v: &V3) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
pub fn sub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn scale(a: &V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Rotation matrix (world from body) of `q/‖q‖`, `q = [w, x, y, z]`.
pub fn rot(q: &[f64; 4]) -> [[f64; 3]; 3] {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let [w, x, y, z] = q.map(|v| v / n);
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

// ---------------------------------------------------------------------------------------------
// Shapes, by the parameters of CONVENTIONS.md.

#[derive(Clone, Debug)]
pub enum Spec {
    Sphere {
        r: f64,
    },
    Ellipsoid {
        p: [[f64; 3]; 3],
    },
    Polytope {
        a: Vec<V3>,
        b: Vec<f64>,
    },
    Capsule {
        r: f64,
        l: f64,
    },
    Cylinder {
        r: f64,
        l: f64,
    },
    Cone {
        h: f64,
        beta: f64,
    },
    Polygon {
        c: Vec<[f64; 2]>,
        d: Vec<f64>,
        r: f64,
    },
}

pub const KINDS: [&str; 7] = [
    "capsule",
    "cone",
    "cylinder",
    "ellipsoid",
    "padded_polygon",
    "polytope",
    "sphere",
];

impl Spec {
    pub fn kind(&self) -> &'static str {
        match self {
            Spec::Sphere { .. } => "sphere",
            Spec::Ellipsoid { .. } => "ellipsoid",
            Spec::Polytope { .. } => "polytope",
            Spec::Capsule { .. } => "capsule",
            Spec::Cylinder { .. } => "cylinder",
            Spec::Cone { .. } => "cone",
            Spec::Polygon { .. } => "padded_polygon",
        }
    }

    /// The record's shape object (names of the shared reference schema).
    pub fn to_json(&self) -> Value {
        match self {
            Spec::Sphere { r } => json!({"kind": "sphere", "R": r}),
            Spec::Ellipsoid { p } => json!({"kind": "ellipsoid", "P": p}),
            Spec::Polytope { a, b } => json!({"kind": "polytope", "A": a, "b": b}),
            Spec::Capsule { r, l } => json!({"kind": "capsule", "R": r, "L": l}),
            Spec::Cylinder { r, l } => json!({"kind": "cylinder", "R": r, "L": l}),
            Spec::Cone { h, beta } => json!({"kind": "cone", "H": h, "beta": beta}),
            Spec::Polygon { c, d, r } => {
                json!({"kind": "padded_polygon", "C": c, "d": d, "R": r})
            }
        }
    }

    /// Every length multiplied by `s`.
    pub fn scaled(&self, s: f64) -> Spec {
        match self {
            Spec::Sphere { r } => Spec::Sphere { r: r * s },
            Spec::Ellipsoid { p } => Spec::Ellipsoid {
                p: p.map(|row| row.map(|v| v / (s * s))),
            },
            Spec::Polytope { a, b } => Spec::Polytope {
                a: a.clone(),
                b: b.iter().map(|v| v * s).collect(),
            },
            Spec::Capsule { r, l } => Spec::Capsule { r: r * s, l: l * s },
            Spec::Cylinder { r, l } => Spec::Cylinder { r: r * s, l: l * s },
            Spec::Cone { h, beta } => Spec::Cone {
                h: h * s,
                beta: *beta,
            },
            Spec::Polygon { c, d, r } => Spec::Polygon {
                c: c.clone(),
                d: d.iter().map(|v| v * s).collect(),
                r: r * s,
            },
        }
    }

    /// The bounding radius about the origin: the largest ‖b‖ over the body set.
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Spec::Sphere { r } => *r,
            Spec::Ellipsoid { p } => {
                let m = nalgebra::Matrix3::from_fn(|i, j| p[i][j]);
                let e = m.symmetric_eigenvalues();
                1.0 / e.min().sqrt()
            }
            Spec::Polytope { a, b } => polytope_vertices(a, b).iter().map(norm).fold(0.0, f64::max),
            Spec::Capsule { r, l } => r + 0.5 * l,
            Spec::Cylinder { r, l } => r.hypot(0.5 * l),
            Spec::Cone { h, beta } => (0.75 * h).max((0.25 * h).hypot(h * beta.tan())),
            Spec::Polygon { c, d, r } => {
                let mut best: f64 = 0.0;
                for i in 0..c.len() {
                    for j in i + 1..c.len() {
                        let det = c[i][0] * c[j][1] - c[i][1] * c[j][0];
                        if det.abs() < 1e-12 {
                            continue;
                        }
                        let y = [
                            (d[i] * c[j][1] - c[i][1] * d[j]) / det,
                            (c[i][0] * d[j] - d[i] * c[j][0]) / det,
                        ];
                        if c.iter()
                            .zip(d)
                            .all(|(ck, dk)| ck[0] * y[0] + ck[1] * y[1] <= dk * (1.0 + 1e-12))
                        {
                            best = best.max(y[0].hypot(y[1]));
                        }
                    }
                }
                best + r
            }
        }
    }
}

/// The vertices of `{b : A b ≤ b}` (every feasible intersection of three planes).
pub fn polytope_vertices(a: &[V3], b: &[f64]) -> Vec<V3> {
    let mut out = Vec::new();
    let m = a.len();
    for i in 0..m {
        for j in i + 1..m {
            for k in j + 1..m {
                let mat = nalgebra::Matrix3::from_rows(&[
                    nalgebra::RowVector3::from(a[i]),
                    nalgebra::RowVector3::from(a[j]),
                    nalgebra::RowVector3::from(a[k]),
                ]);
                if mat.determinant().abs() < 1e-9 {
                    continue;
                }
                let Some(v) = mat.lu().solve(&nalgebra::Vector3::new(b[i], b[j], b[k])) else {
                    continue;
                };
                let v = [v.x, v.y, v.z];
                if a.iter().zip(b).all(|(ar, br)| {
                    ar[0] * v[0] + ar[1] * v[1] + ar[2] * v[2] <= br + 1e-9 * br.abs().max(1.0)
                }) {
                    out.push(v);
                }
            }
        }
    }
    out
}

/// A shape placed in the world.
#[derive(Clone, Debug)]
pub struct Posed {
    pub spec: Spec,
    pub r: V3,
    pub q: [f64; 4],
}

// ---------------------------------------------------------------------------------------------
// Cone programs: minimise cᵀz subject to affine expressions in the nonnegative orthant and in
// second-order cones.

/// Most variables of any program here: (ξ, α) or (y₁, y₂, t) plus two shapes' slack variables.
pub const NV: usize = 12;

/// An affine function `k·z + c` of the variables.
#[derive(Clone, Copy, Debug)]
pub struct Aff {
    pub k: [f64; NV],
    pub c: f64,
}

impl Aff {
    pub fn constant(c: f64) -> Aff {
        Aff { k: [0.0; NV], c }
    }
    pub fn var(i: usize, s: f64) -> Aff {
        let mut k = [0.0; NV];
        k[i] = s;
        Aff { k, c: 0.0 }
    }
    pub fn plus(self, o: Aff) -> Aff {
        let mut k = self.k;
        for (a, b) in k.iter_mut().zip(o.k.iter()) {
            *a += b;
        }
        Aff { k, c: self.c + o.c }
    }
    pub fn times(self, s: f64) -> Aff {
        Aff {
            k: self.k.map(|v| v * s),
            c: self.c * s,
        }
    }
    fn eval(&self, z: &[f64]) -> f64 {
        self.k.iter().zip(z).map(|(a, b)| a * b).sum::<f64>() + self.c
    }
}

#[derive(Clone, Debug, Default)]
pub struct Program {
    pub n: usize,
    pub cost: Vec<f64>,
    /// `expr ≥ 0`.
    pub nonneg: Vec<Aff>,
    /// `expr₀ ≥ ‖expr₁..‖`.
    pub soc: Vec<Vec<Aff>>,
}

impl Program {
    pub fn new(n: usize) -> Program {
        Program {
            n,
            cost: vec![0.0; n],
            ..Program::default()
        }
    }

    pub fn slack(&mut self) -> Aff {
        self.n += 1;
        self.cost.push(0.0);
        assert!(self.n <= NV);
        Aff::var(self.n - 1, 1.0)
    }

    /// Adds `point ∈ center + scale · Q S_body` in lengths divided by `unit`: `point` and
    /// `center` are affine 3-vectors in those units, `scale` an affine scalar (α, or 1).
    pub fn add_shape(
        &mut self,
        spec: &Spec,
        point: [Aff; 3],
        center: V3,
        q: &[[f64; 3]; 3],
        sc: Aff,
        unit: f64,
    ) {
        let inv = 1.0 / unit;
        // u = Qᵀ(point − center), in units.
        let u: [Aff; 3] = std::array::from_fn(|i| {
            let mut e = Aff::constant(0.0);
            for j in 0..3 {
                e = e.plus(point[j].plus(Aff::constant(-center[j])).times(q[j][i]));
            }
            e
        });
        match spec {
            Spec::Sphere { r } => self.soc.push(vec![sc.times(r * inv), u[0], u[1], u[2]]),
            Spec::Ellipsoid { p } => {
                // bᵀPb ≤ α² with P = UᵀU (Cholesky, U upper): ‖U u‖ ≤ α/unit… in units:
                // b = unit·u, so ‖U u‖ ≤ α/unit.
                let m = nalgebra::Matrix3::from_fn(|i, j| p[i][j]);
                let l = m.cholesky().expect("P is positive definite").l();
                let ut = l.transpose();
                let mut cone = vec![sc.times(inv)];
                for i in 0..3 {
                    let mut row = Aff::constant(0.0);
                    for j in 0..3 {
                        row = row.plus(u[j].times(ut[(i, j)]));
                    }
                    cone.push(row);
                }
                self.soc.push(cone);
            }
            Spec::Polytope { a, b } => {
                for (a, b) in a.iter().zip(b) {
                    let au = u[0]
                        .times(a[0])
                        .plus(u[1].times(a[1]))
                        .plus(u[2].times(a[2]));
                    self.nonneg.push(sc.times(b * inv).plus(au.times(-1.0)));
                }
            }
            Spec::Capsule { r, l } => {
                let g = self.slack();
                self.soc.push(vec![
                    sc.times(r * inv),
                    u[0].plus(g.times(-1.0)),
                    u[1],
                    u[2],
                ]);
                self.nonneg
                    .push(sc.times(0.5 * l * inv).plus(g.times(-1.0)));
                self.nonneg.push(sc.times(0.5 * l * inv).plus(g));
            }
            Spec::Cylinder { r, l } => {
                self.soc.push(vec![sc.times(r * inv), u[1], u[2]]);
                self.nonneg
                    .push(sc.times(0.5 * l * inv).plus(u[0].times(-1.0)));
                self.nonneg.push(sc.times(0.5 * l * inv).plus(u[0]));
            }
            Spec::Cone { h, beta } => {
                let xt = u[0].plus(sc.times(0.75 * h * inv));
                self.soc.push(vec![xt.times(beta.tan()), u[1], u[2]]);
                self.nonneg
                    .push(sc.times(0.25 * h * inv).plus(u[0].times(-1.0)));
            }
            Spec::Polygon { c, d, r } => {
                let y0 = self.slack();
                let y1 = self.slack();
                self.soc.push(vec![
                    sc.times(r * inv),
                    u[0].plus(y0.times(-1.0)),
                    u[1].plus(y1.times(-1.0)),
                    u[2],
                ]);
                for (c, d) in c.iter().zip(d) {
                    let cy = y0.times(c[0]).plus(y1.times(c[1]));
                    self.nonneg.push(sc.times(d * inv).plus(cy.times(-1.0)));
                }
            }
        }
    }

    /// Clarabel's primal-dual point `(z, λ)` (λ ordered as the rows: orthant, then cones).
    pub fn clarabel(&self) -> Result<(Vec<f64>, Vec<f64>), String> {
        let n = self.n;
        let mut rows: Vec<Vec<f64>> = Vec::new();
        let mut b = Vec::new();
        let mut cones = Vec::new();
        for a in self.nonneg.iter().chain(self.soc.iter().flatten()) {
            rows.push(a.k[..n].iter().map(|v| -v).collect());
            b.push(a.c);
        }
        if !self.nonneg.is_empty() {
            cones.push(SupportedConeT::NonnegativeConeT(self.nonneg.len()));
        }
        for s in &self.soc {
            cones.push(SupportedConeT::SecondOrderConeT(s.len()));
        }
        let a = CscMatrix::from(&rows);
        let p = CscMatrix::<f64>::zeros((n, n));
        let mut last = String::new();
        for (tol, equilibrate) in [(1e-12, true), (1e-12, false), (1e-11, true), (1e-10, true)] {
            let settings = DefaultSettingsBuilder::default()
                .verbose(false)
                .tol_gap_abs(tol)
                .tol_gap_rel(tol)
                .tol_feas(tol)
                .equilibrate_enable(equilibrate)
                .max_iter(400)
                .build()
                .unwrap();
            let mut solver = DefaultSolver::new(&p, &self.cost, &a, &b, &cones, settings)
                .map_err(|e| format!("{e:?}"))?;
            solver.solve();
            match solver.solution.status {
                SolverStatus::Solved | SolverStatus::AlmostSolved => {
                    return Ok((solver.solution.x.clone(), solver.solution.z.clone()))
                }
                s => last = format!("{last} {s:?}"),
            }
        }
        Err(format!("clarabel:{last}"))
    }

    /// Clarabel, then the polish and certificate of the module docs.
    pub fn solve(&self) -> Result<Certified, String> {
        let (z, lam) = self.clarabel()?;
        self.polish(&z, &lam)
    }
}

/// How a constraint block is treated by the polish.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// Orthant row active (s = 0, λ ≥ 0) or inactive (λ = 0).
    Row(bool),
    /// Cone inactive (λ = 0).
    SocOff,
    /// Cone at its apex (s = 0, λ free in the cone).
    SocApex,
    /// Cone on its boundary, λ = γ J s.
    SocBound,
}

/// A certified optimal point.
#[derive(Clone, Debug)]
pub struct Certified {
    pub z: Vec<f64>,
    /// Largest scaled KKT residual.
    pub kkt: f64,
    /// Strictly complementary with a well-conditioned Newton matrix (the solution is unique).
    pub regular: bool,
}

impl Program {
    fn slacks(&self, z: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
        (
            self.nonneg.iter().map(|a| a.eval(z)).collect(),
            self.soc
                .iter()
                .map(|b| b.iter().map(|a| a.eval(z)).collect())
                .collect(),
        )
    }

    fn polish(&self, z0: &[f64], lam0: &[f64]) -> Result<Certified, String> {
        let m = self.nonneg.len();
        let (s_lp, s_soc) = self.slacks(z0);
        let mut roles: Vec<Role> = (0..m).map(|i| Role::Row(lam0[i] > s_lp[i])).collect();
        let mut off = m;
        let mut soc_lam: Vec<Vec<f64>> = Vec::new();
        for (k, b) in self.soc.iter().enumerate() {
            let l = &lam0[off..off + b.len()];
            off += b.len();
            let s = &s_soc[k];
            roles.push(if l[0] < 1e-6 * s[0] {
                Role::SocOff
            } else if s[0] < 1e-6 * l[0] {
                Role::SocApex
            } else {
                Role::SocBound
            });
            soc_lam.push(l.to_vec());
        }
        let mut last = String::from("no attempt");
        for _ in 0..=MAX_FLIPS {
            match self.newton(z0, lam0, &soc_lam, &roles) {
                Ok((z, lam_lp, lam_soc, cond)) => match self.certify(&z, &lam_lp, &lam_soc) {
                    Ok((kkt, flip, strict)) => {
                        if let Some(i) = flip {
                            roles[i] = match roles[i] {
                                Role::Row(a) => Role::Row(!a),
                                Role::SocOff => Role::SocBound,
                                Role::SocBound => Role::SocOff,
                                Role::SocApex => Role::SocBound,
                            };
                            last = format!("sign of block {i}");
                            continue;
                        }
                        return Ok(Certified {
                            z,
                            kkt,
                            regular: strict && cond < 1e10,
                        });
                    }
                    Err(e) => return Err(e),
                },
                Err(e) => return Err(e),
            }
        }
        Err(format!("polish: {last}"))
    }

    /// Newton's method on the KKT equations of `roles`. Returns the point, the orthant and cone
    /// multipliers, and the condition estimate of the final matrix.
    #[allow(clippy::type_complexity)]
    fn newton(
        &self,
        z0: &[f64],
        lam0: &[f64],
        soc_lam0: &[Vec<f64>],
        roles: &[Role],
    ) -> Result<(Vec<f64>, Vec<f64>, Vec<Vec<f64>>, f64), String> {
        let n = self.n;
        let m = self.nonneg.len();
        // Unknown layout: z, then per block its multiplier unknowns.
        let mut idx = Vec::with_capacity(roles.len());
        let mut nu = n;
        for (i, r) in roles.iter().enumerate() {
            idx.push(nu);
            nu += match r {
                Role::Row(true) => 1,
                Role::Row(false) | Role::SocOff => 0,
                Role::SocApex => self.soc[i - m].len(),
                Role::SocBound => 1,
            };
        }
        let mut u = DVector::<f64>::zeros(nu);
        for i in 0..n {
            u[i] = z0[i];
        }
        let (_, s_soc0) = self.slacks(z0);
        for (i, r) in roles.iter().enumerate() {
            match r {
                Role::Row(true) => u[idx[i]] = lam0[i].max(0.0),
                Role::SocApex => {
                    for (j, v) in soc_lam0[i - m].iter().enumerate() {
                        u[idx[i] + j] = *v;
                    }
                }
                Role::SocBound => u[idx[i]] = soc_lam0[i - m][0] / s_soc0[i - m][0],
                _ => {}
            }
        }
        let mut cond = f64::INFINITY;
        let mut best = f64::INFINITY;
        for _ in 0..30 {
            let z: Vec<f64> = (0..n).map(|i| u[i]).collect();
            let (s_lp, s_soc) = self.slacks(&z);
            let mut f = DVector::<f64>::zeros(nu);
            let mut jac = DMatrix::<f64>::zeros(nu, nu);
            for i in 0..n {
                f[i] = self.cost[i];
            }
            let mut eq = n;
            for (bi, r) in roles.iter().enumerate() {
                match r {
                    Role::Row(true) => {
                        let a = &self.nonneg[bi];
                        let l = u[idx[bi]];
                        for i in 0..n {
                            f[i] -= l * a.k[i];
                            jac[(i, idx[bi])] = -a.k[i];
                            jac[(eq, i)] = a.k[i];
                        }
                        f[eq] = s_lp[bi];
                        eq += 1;
                    }
                    Role::SocApex => {
                        let b = &self.soc[bi - m];
                        for (j, a) in b.iter().enumerate() {
                            let l = u[idx[bi] + j];
                            for i in 0..n {
                                f[i] -= l * a.k[i];
                                jac[(i, idx[bi] + j)] = -a.k[i];
                                jac[(eq, i)] = a.k[i];
                            }
                            f[eq] = s_soc[bi - m][j];
                            eq += 1;
                        }
                    }
                    Role::SocBound => {
                        let b = &self.soc[bi - m];
                        let s = &s_soc[bi - m];
                        let g = u[idx[bi]];
                        // λ = γ J s; stationarity term −Σ_j λ_j k_j.
                        let js: Vec<f64> = s
                            .iter()
                            .enumerate()
                            .map(|(j, v)| if j == 0 { *v } else { -*v })
                            .collect();
                        for (j, a) in b.iter().enumerate() {
                            let sign = if j == 0 { 1.0 } else { -1.0 };
                            for i in 0..n {
                                f[i] -= g * js[j] * a.k[i];
                                jac[(i, idx[bi])] -= js[j] * a.k[i];
                                for c in 0..n {
                                    jac[(i, c)] -= g * sign * a.k[c] * a.k[i];
                                }
                            }
                        }
                        // ½ sᵀJs = 0, gradient (Js)ᵀK.
                        f[eq] = 0.5 * s.iter().zip(&js).map(|(a, b)| a * b).sum::<f64>();
                        for (j, a) in b.iter().enumerate() {
                            for c in 0..n {
                                jac[(eq, c)] += js[j] * a.k[c];
                            }
                        }
                        eq += 1;
                    }
                    _ => {}
                }
            }
            assert_eq!(eq, nu);
            let fmax = f.amax();
            let svd = jac.clone().svd(false, false);
            let smax = svd.singular_values.max();
            let smin = svd.singular_values.min();
            cond = if smin > 0.0 {
                smax / smin
            } else {
                f64::INFINITY
            };
            if fmax <= 1e-16 * (1.0 + u.amax()) || (fmax >= best && fmax < 1e-13) {
                break;
            }
            best = best.min(fmax);
            let Some(step) = jac.lu().solve(&(-f)) else {
                return Err("polish: singular KKT system".into());
            };
            if !step.iter().all(|v| v.is_finite()) {
                return Err("polish: non-finite step".into());
            }
            u += step;
        }
        let z: Vec<f64> = (0..n).map(|i| u[i]).collect();
        let (_, s_soc) = self.slacks(&z);
        let mut lam_lp = vec![0.0; m];
        let mut lam_soc: Vec<Vec<f64>> = self.soc.iter().map(|b| vec![0.0; b.len()]).collect();
        for (bi, r) in roles.iter().enumerate() {
            match r {
                Role::Row(true) => lam_lp[bi] = u[idx[bi]],
                Role::SocApex => {
                    for j in 0..self.soc[bi - m].len() {
                        lam_soc[bi - m][j] = u[idx[bi] + j];
                    }
                }
                Role::SocBound => {
                    let g = u[idx[bi]];
                    for (j, v) in s_soc[bi - m].iter().enumerate() {
                        lam_soc[bi - m][j] = if j == 0 { g * v } else { -g * v };
                    }
                }
                _ => {}
            }
        }
        Ok((z, lam_lp, lam_soc, cond))
    }

    /// The KKT conditions of the original program at `(z, λ)`: the largest scaled residual,
    /// the first block whose sign condition fails (to flip), and whether complementarity is
    /// strict. Error when a residual other than a sign is too large.
    fn certify(
        &self,
        z: &[f64],
        lam_lp: &[f64],
        lam_soc: &[Vec<f64>],
    ) -> Result<(f64, Option<usize>, bool), String> {
        let n = self.n;
        let m = self.nonneg.len();
        let (s_lp, s_soc) = self.slacks(z);
        let zs = 1.0 + z.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let ls = lam_lp
            .iter()
            .chain(lam_soc.iter().flatten())
            .fold(1e-300_f64, |a, v| a.max(v.abs()));
        let mut stat = self.cost.clone();
        let mut kkt: f64 = 0.0;
        let mut flip = None;
        let mut strict = true;
        for (i, a) in self.nonneg.iter().enumerate() {
            for j in 0..n {
                stat[j] -= lam_lp[i] * a.k[j];
            }
            let (s, l) = (s_lp[i] / zs, lam_lp[i] / ls);
            let viol = (-s).max(-l).max(0.0);
            kkt = kkt.max((s * l).abs());
            if viol > KKT_TOL && flip.is_none() {
                flip = Some(i);
            }
            kkt = kkt.max(viol);
            if s.abs() < STRICT && l.abs() < STRICT {
                strict = false;
            }
        }
        for (k, b) in self.soc.iter().enumerate() {
            for (j, a) in b.iter().enumerate() {
                for c in 0..n {
                    stat[c] -= lam_soc[k][j] * a.k[c];
                }
            }
            let s: Vec<f64> = s_soc[k].iter().map(|v| v / zs).collect();
            let l: Vec<f64> = lam_soc[k].iter().map(|v| v / ls).collect();
            let outside = |u: &[f64]| u[1..].iter().map(|v| v * v).sum::<f64>().sqrt() - u[0];
            let (os, ol) = (outside(&s), outside(&l));
            let viol = os.max(ol).max(0.0);
            let comp: f64 = s.iter().zip(&l).map(|(a, b)| a * b).sum();
            kkt = kkt.max(comp.abs());
            if viol > KKT_TOL && flip.is_none() {
                flip = Some(m + k);
            }
            kkt = kkt.max(viol);
            // Strict: not both at the apex, and each either clearly inside or paired on the
            // boundary with the other clearly off zero.
            let (s0, l0) = (s[0], l[0]);
            if s0 < STRICT && l0 < STRICT {
                strict = false;
            }
            if s0 >= STRICT && l0 >= STRICT && (-os > STRICT || -ol > STRICT) {
                strict = false; // both nonzero but not complementary rays: not a KKT point
            }
            if s0 < STRICT && -ol < STRICT {
                strict = false; // apex with λ on the cone's boundary
            }
            if l0 < STRICT && -os < STRICT {
                strict = false; // inactive cone with s on its boundary
            }
        }
        let st = stat.iter().fold(0.0_f64, |a, v| a.max(v.abs())) / ls.max(1.0);
        kkt = kkt.max(st);
        if flip.is_none() && kkt > KKT_TOL {
            return Err(format!("certificate: KKT residual {kkt:e}"));
        }
        Ok((kkt, flip, strict))
    }
}

// ---------------------------------------------------------------------------------------------
// The two problems.

/// `ℓ`, the larger bounding radius.
pub fn length_scale(a: &Posed, b: &Posed) -> f64 {
    a.spec.bounding_radius().max(b.spec.bounding_radius())
}

/// The proximity answer: α*, x* (world), and how it was certified.
#[derive(Clone, Debug)]
pub struct Prox {
    pub alpha: f64,
    pub x: V3,
    /// `x* − r₁` (world), to full relative precision.
    pub x_rel: V3,
    pub kkt: f64,
    pub regular: bool,
}

/// α* and x* of two posed shapes, certified.
pub fn proximity(a: &Posed, b: &Posed) -> Result<Prox, String> {
    proximity_eps(a, b, None)
}

/// [`proximity`] with the objective `α + ε c·ξ` (`ξ = (x − r₁)/ℓ` in the stretched frame) when
/// `eps_dir = Some((ε, c))`: the program is solved in the normalised frame, origin r₁, lengths
/// over ℓ, and the offset stretched to unit length (α* and x* − r₁ are homogeneous of degree
/// one in r₂ − r₁), and rescaled exactly.
pub fn proximity_eps(a: &Posed, b: &Posed, eps_dir: Option<(f64, V3)>) -> Result<Prox, String> {
    let ell = length_scale(a, b);
    let delta = scale(&sub(&b.r, &a.r), 1.0 / ell);
    let dn = norm(&delta);
    if dn == 0.0 {
        return Ok(Prox {
            alpha: 0.0,
            x: a.r,
            x_rel: [0.0; 3],
            kkt: 0.0,
            regular: true,
        });
    }
    let t = 1.0 / dn;
    let mut p = Program::new(4);
    p.cost[3] = 1.0;
    if let Some((eps, c)) = eps_dir {
        for i in 0..3 {
            p.cost[i] = eps * c[i];
        }
    }
    p.nonneg.push(Aff::var(3, 1.0)); // α ≥ 0
    let xi = [Aff::var(0, 1.0), Aff::var(1, 1.0), Aff::var(2, 1.0)];
    let al = Aff::var(3, 1.0);
    p.add_shape(&a.spec, xi, [0.0; 3], &rot(&a.q), al, ell);
    p.add_shape(&b.spec, xi, scale(&delta, t), &rot(&b.q), al, ell);
    let c = p.solve()?;
    let alpha = c.z[3] / t;
    let x_rel = scale(&[c.z[0], c.z[1], c.z[2]], ell / t);
    Ok(Prox {
        alpha,
        x: add(&a.r, &x_rel),
        x_rel,
        kkt: c.kkt,
        regular: c.regular,
    })
}

/// The exact distance between the unscaled shapes (for separated shapes) and the closest
/// points; `None` distance parts when the program is degenerate.
#[derive(Clone, Debug)]
pub struct Dist {
    pub distance: f64,
    pub c1: V3,
    pub c2: V3,
    pub kkt: f64,
    pub regular: bool,
}

/// min t s.t. ‖y₁ − y₂‖ ≤ t, yᵢ ∈ Sᵢ(1): solved with origin r₁ and lengths over ℓ.
pub fn distance(a: &Posed, b: &Posed) -> Result<Dist, String> {
    let ell = length_scale(a, b);
    let delta = scale(&sub(&b.r, &a.r), 1.0 / ell);
    let mut p = Program::new(7);
    p.cost[6] = 1.0;
    let y1 = [Aff::var(0, 1.0), Aff::var(1, 1.0), Aff::var(2, 1.0)];
    let y2 = [Aff::var(3, 1.0), Aff::var(4, 1.0), Aff::var(5, 1.0)];
    let one = Aff::constant(1.0);
    p.add_shape(&a.spec, y1, [0.0; 3], &rot(&a.q), one, ell);
    p.add_shape(&b.spec, y2, delta, &rot(&b.q), one, ell);
    p.soc.push(vec![
        Aff::var(6, 1.0),
        y1[0].plus(y2[0].times(-1.0)),
        y1[1].plus(y2[1].times(-1.0)),
        y1[2].plus(y2[2].times(-1.0)),
    ]);
    let c = p.solve()?;
    let z = &c.z;
    let c1 = add(&a.r, &scale(&[z[0], z[1], z[2]], ell));
    let c2 = add(&a.r, &scale(&[z[3], z[4], z[5]], ell));
    let d = norm(&sub(&[z[0], z[1], z[2]], &[z[3], z[4], z[5]])) * ell;
    Ok(Dist {
        distance: d,
        c1,
        c2,
        kkt: c.kkt,
        regular: c.regular,
    })
}
