//! Fixed-seed stress suite (issue 6, robustness), beyond `shared/reference/cases-stress.jsonl`.
//!
//! Classes (each counted separately in the printed table):
//!
//! | class | what | reference |
//! |---|---|---|
//! | `random` | well-scaled random pairs of all kinds | Clarabel |
//! | `sphere_sphere` | random radii and offsets, 1e-3..1e3 | `‖Δr‖/(R₁+R₂)` |
//! | `box_box` | boxes sharing one random attitude | `maxᵢ |(QᵀΔ)ᵢ|/(aᵢ+bᵢ)` |
//! | `sphere_box`, `sphere_capsule` | random attitudes | 1-D root of the Minkowski sum |
//! | `scale` | the same pairs scaled by 1e-4..1e4 m | Clarabel, and dcol at scale 1 |
//! | `aspect` | needles, disks, slabs, thin polygons: aspect 1e3 | Clarabel |
//! | `far_small` | sizes ~1e-2 m, positions ~1e4 m | Clarabel |
//! | `coincident` | `r₁ = r₂` exactly | `α* = 0` exactly |
//! | `near_coincident` | `‖Δr‖` from 1e-6 ℓ to 1e-14 ℓ | Clarabel on the stretched offset |
//! | `homogeneity` | `α(tΔ) = t α(Δ)`, t = 1e-12..1e3 | dcol itself |
//! | `touching` | exactly touching spheres, boxes, sphere–box, sphere–capsule | analytic (α = 1) |
//! | `parallel` | face–face, edge–face, side–face, cap–face, polygon–face, capsule–capsule | analytic / Clarabel |
//! | `cone_1deg`, `cone_89deg` | cones of half angle 1° and 89° | Clarabel |
//! | `flat` | ellipsoids and polytopes with thickness 1e-3..1e-4 of their width | Clarabel |
//! | `quat_norm` | quaternions of norm 1e-6, 1e6 (and 1e±30) | dcol with unit quaternions, Clarabel |
//! | `many_facets` | polytopes with 100–256 facets | Clarabel |
//! | `mixed_scale` | a small shape near one 1e2..1e5 times larger | Clarabel |
//!
//! For every case: no panic; `proximity`, `gradient`, `jacobian` and `distance` all return `Ok`;
//! every output is finite (also for a non-converged status, which must then carry a finite last
//! iterate); α* agrees with the reference; x* is an optimal point (the larger of the two
//! shapes' gauges at dcol's x*, each solved by Clarabel, gives back α*); the gradient satisfies
//! the identities every subgradient of the gauge α*(Δ) satisfies: `∂α/∂r₁ = −∂α/∂r₂`,
//! `∂α/∂r₂ · Δ = α` (Euler, degree one), and `∂α/∂qᵢ · qᵢ = 0` (the attitude depends on
//! `q/‖q‖` only); `distance` converges (outside `extreme`), is 0 exactly when α* < 1 (away
//! from touching), and matches
//! the closed form for two spheres and for two boxes sharing one attitude (1e-9 ℓ).
//!
//! Every proximity solve must converge except in the `extreme` class, which goes past double
//! precision on purpose and asserts robustness only. `STRESS_VERBOSE=1` prints each
//! non-converged case.
//!
//! The Clarabel oracle below is written from `CONVENTIONS.md` and the constraint list of
//! `shared/reference/README.md`, not from dcol's code: the rotation matrix, the conic rows of
//! every shape and the normalisation are computed here.
//!
//! Tolerances (relative error of α*, see `CLASS_TOL`):
//! - 1e-8 for every class. dcol stops on a relative duality gap of 1e-10 in α and then polishes;
//!   Clarabel here is run at 1e-12 (gap and feasibility), so the two agree to ~1e-10 whenever
//!   the problem is solvable in double precision, and 1e-8 leaves a 100× margin for Clarabel's
//!   own error on the worst-conditioned (aspect 1e3, flat 1e-4) problems.
//! - The analytic classes would allow 1e-12, but dcol's stopping rule only promises 1e-10, so
//!   they are held to 1e-9 (measured errors are printed).
//! - `homogeneity` and `quat_norm` compare dcol with dcol on mathematically identical problems
//!   whose inputs differ only by rounding: 1e-9 (twice the solver's 1e-10 promise, with margin).
//! - x*: `α(x fixed at x*) − α*` ≤ 1e-7 α*: x* from a refined solution is within ~1e-9 ℓ, and
//!   the gauge moves by at most (ℓ/inscribed radius) × that; the aspect and flat classes scale
//!   this by their aspect ratio (1e3, 1e4).
//! - gradient identities: 1e-6 relative (multipliers from the polished solution; the reference
//!   README reports finite-difference derivatives good to 1e-6 in the same units).

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use dcol::{distance, gradient, jacobian, proximity, Options, Pose, Shape, SolveStatus, Vec3};
use std::collections::BTreeMap;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------------
// Random numbers (SplitMix64; fixed seeds, no dependency).

struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unif(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    fn log_range(&mut self, a: f64, b: f64) -> f64 {
        (self.range(a.ln(), b.ln())).exp()
    }
    fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    fn normal(&mut self) -> f64 {
        let u1 = self.unif().max(1e-300);
        let u2 = self.unif();
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
    fn point(&mut self) -> [f64; 3] {
        [self.normal(), self.normal(), self.normal()]
    }
    fn unit_vec(&mut self) -> [f64; 3] {
        loop {
            let v = [self.normal(), self.normal(), self.normal()];
            let n = norm(&v);
            if n > 1e-3 {
                return v.map(|x| x / n);
            }
        }
    }
    fn unit_quat(&mut self) -> [f64; 4] {
        loop {
            let q = [self.normal(), self.normal(), self.normal(), self.normal()];
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 1e-3 {
                return q.map(|x| x / n);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Small vector helpers (independent of dcol).

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn scale(a: &[f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn v3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// Rotation matrix (world from body) of `q/‖q‖`, `q = [w, x, y, z]`.
fn rot(q: &[f64; 4]) -> [[f64; 3]; 3] {
    let big = q.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let q = q.map(|v| v / big);
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
/// `Qᵀ v`.
fn rot_t(q: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    [
        q[0][0] * v[0] + q[1][0] * v[1] + q[2][0] * v[2],
        q[0][1] * v[0] + q[1][1] * v[1] + q[2][1] * v[2],
        q[0][2] * v[0] + q[1][2] * v[1] + q[2][2] * v[2],
    ]
}

// ---------------------------------------------------------------------------------------------
// Shape descriptions, kept so that the oracle can write its own cone program.

#[derive(Clone, Debug)]
enum Spec {
    Sphere {
        r: f64,
    },
    /// `P = E diag(1/a²) Eᵀ` with `E = rot(e)`.
    Ellipsoid {
        axes: [f64; 3],
        e: [f64; 4],
    },
    Cuboid {
        h: [f64; 3],
    },
    Polytope {
        a: Vec<[f64; 3]>,
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

impl Spec {
    fn build(&self) -> Shape {
        self.try_build()
            .unwrap_or_else(|e| panic!("constructor rejected a valid shape {self:?}: {e}"))
    }

    fn try_build(&self) -> Result<Shape, dcol::Error> {
        match self {
            Spec::Sphere { r } => Shape::sphere(*r),
            Spec::Ellipsoid { axes, e } => {
                let m = rot(e);
                let mut p = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in i..3 {
                        let v: f64 = (0..3)
                            .map(|k| m[i][k] * m[j][k] / (axes[k] * axes[k]))
                            .sum();
                        p[i][j] = v;
                        p[j][i] = v;
                    }
                }
                Shape::ellipsoid(p)
            }
            Spec::Cuboid { h } => Shape::cuboid(h[0], h[1], h[2]),
            Spec::Polytope { a, b } => Shape::polytope(a, b),
            Spec::Capsule { r, l } => Shape::capsule(*r, *l),
            Spec::Cylinder { r, l } => Shape::cylinder(*r, *l),
            Spec::Cone { h, beta } => Shape::cone(*h, *beta),
            Spec::Polygon { c, d, r } => Shape::polygon(c, d, *r),
        }
    }

    /// Every length multiplied by `s`.
    fn scaled(&self, s: f64) -> Spec {
        match self {
            Spec::Sphere { r } => Spec::Sphere { r: r * s },
            Spec::Ellipsoid { axes, e } => Spec::Ellipsoid {
                axes: axes.map(|v| v * s),
                e: *e,
            },
            Spec::Cuboid { h } => Spec::Cuboid {
                h: h.map(|v| v * s),
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

    /// A rough size (the oracle's unit of length; any positive number would do).
    fn size(&self) -> f64 {
        match self {
            Spec::Sphere { r } => *r,
            Spec::Ellipsoid { axes, .. } => axes.iter().cloned().fold(0.0, f64::max),
            Spec::Cuboid { h } => norm(h),
            Spec::Polytope { a, b } => a
                .iter()
                .zip(b)
                .map(|(a, b)| b / norm(a))
                .fold(0.0, f64::max),
            Spec::Capsule { r, l } | Spec::Cylinder { r, l } => r + 0.5 * l,
            Spec::Cone { h, beta } => h * (1.0 + beta.tan()),
            Spec::Polygon { c, d, r } => {
                r + c
                    .iter()
                    .zip(d)
                    .map(|(c, d)| d / c[0].hypot(c[1]))
                    .fold(0.0, f64::max)
            }
        }
    }

    fn name(&self) -> &'static str {
        match self {
            Spec::Sphere { .. } => "sphere",
            Spec::Ellipsoid { .. } => "ellipsoid",
            Spec::Cuboid { .. } => "box",
            Spec::Polytope { .. } => "polytope",
            Spec::Capsule { .. } => "capsule",
            Spec::Cylinder { .. } => "cylinder",
            Spec::Cone { .. } => "cone",
            Spec::Polygon { .. } => "polygon",
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The oracle: the cone program of CONVENTIONS.md, solved by Clarabel.

/// Variables: x (0..3, normalised), α (3), then per-shape slacks (capsule γ, polygon y).
const NV: usize = 10;

/// An affine function `k·z + c` of the variables.
#[derive(Clone, Copy, Debug)]
struct Aff {
    k: [f64; NV],
    c: f64,
}

impl Aff {
    fn var(i: usize, s: f64) -> Aff {
        let mut k = [0.0; NV];
        k[i] = s;
        Aff { k, c: 0.0 }
    }
    fn plus(self, o: Aff) -> Aff {
        let mut k = self.k;
        for (a, b) in k.iter_mut().zip(o.k.iter()) {
            *a += b;
        }
        Aff { k, c: self.c + o.c }
    }
    fn times(self, s: f64) -> Aff {
        Aff {
            k: self.k.map(|v| v * s),
            c: self.c * s,
        }
    }
}

#[derive(Default)]
struct Socp {
    n: usize,
    zero: Vec<Aff>,
    nonneg: Vec<Aff>,
    soc: Vec<Vec<Aff>>,
}

impl Socp {
    fn new() -> Socp {
        let mut p = Socp {
            n: 4,
            ..Socp::default()
        };
        p.nonneg.push(Aff::var(3, 1.0)); // α ≥ 0
        p
    }

    fn slack(&mut self) -> Aff {
        self.n += 1;
        assert!(self.n <= NV);
        Aff::var(self.n - 1, 1.0)
    }

    /// Adds `x ∈ c + α Q S_body` in normalised lengths (`inv` = 1/unit).
    fn add_shape(&mut self, spec: &Spec, center: [f64; 3], q: &[[f64; 3]; 3], inv: f64) {
        // u = Qᵀ(x − c)
        let u: [Aff; 3] = std::array::from_fn(|i| {
            let mut k = [0.0; NV];
            let mut c = 0.0;
            for j in 0..3 {
                k[j] = q[j][i];
                c -= q[j][i] * center[j];
            }
            Aff { k, c }
        });
        let al = |s: f64| Aff::var(3, s);
        match spec {
            Spec::Sphere { r } => self.soc.push(vec![al(r * inv), u[0], u[1], u[2]]),
            Spec::Ellipsoid { axes, e } => {
                // ‖U u_phys‖ ≤ α with U = diag(1/a) Eᵀ and u_phys = u/inv.
                let m = rot(e);
                let mut cone = vec![al(1.0)];
                for i in 0..3 {
                    let mut row = u[0].times(m[0][i]);
                    row = row.plus(u[1].times(m[1][i]));
                    row = row.plus(u[2].times(m[2][i]));
                    cone.push(row.times(1.0 / (axes[i] * inv)));
                }
                self.soc.push(cone);
            }
            Spec::Cuboid { h } => {
                for i in 0..3 {
                    self.nonneg.push(al(h[i] * inv).plus(u[i].times(-1.0)));
                    self.nonneg.push(al(h[i] * inv).plus(u[i]));
                }
            }
            Spec::Polytope { a, b } => {
                for (a, b) in a.iter().zip(b) {
                    let au = u[0]
                        .times(a[0])
                        .plus(u[1].times(a[1]))
                        .plus(u[2].times(a[2]));
                    self.nonneg.push(al(b * inv).plus(au.times(-1.0)));
                }
            }
            Spec::Capsule { r, l } => {
                let g = self.slack();
                self.soc
                    .push(vec![al(r * inv), u[0].plus(g.times(-1.0)), u[1], u[2]]);
                self.nonneg.push(al(0.5 * l * inv).plus(g.times(-1.0)));
                self.nonneg.push(al(0.5 * l * inv).plus(g));
            }
            Spec::Cylinder { r, l } => {
                self.soc.push(vec![al(r * inv), u[1], u[2]]);
                self.nonneg.push(al(0.5 * l * inv).plus(u[0].times(-1.0)));
                self.nonneg.push(al(0.5 * l * inv).plus(u[0]));
            }
            Spec::Cone { h, beta } => {
                let t = beta.tan();
                let xt = u[0].plus(al(0.75 * h * inv));
                self.soc.push(vec![xt.times(t), u[1], u[2]]);
                self.nonneg.push(al(0.25 * h * inv).plus(u[0].times(-1.0)));
            }
            Spec::Polygon { c, d, r } => {
                let y0 = self.slack();
                let y1 = self.slack();
                self.soc.push(vec![
                    al(r * inv),
                    u[0].plus(y0.times(-1.0)),
                    u[1].plus(y1.times(-1.0)),
                    u[2],
                ]);
                for (c, d) in c.iter().zip(d) {
                    let cy = y0.times(c[0]).plus(y1.times(c[1]));
                    self.nonneg.push(al(d * inv).plus(cy.times(-1.0)));
                }
            }
        }
    }

    /// Minimises α; returns the optimal variables.
    fn solve(&self) -> Result<Vec<f64>, String> {
        let n = self.n;
        let mut rows: Vec<Vec<f64>> = Vec::new();
        let mut b = Vec::new();
        let mut cones = Vec::new();
        let mut push = |a: &Aff, rows: &mut Vec<Vec<f64>>| {
            rows.push(a.k[..n].iter().map(|v| -v).collect());
            b.push(a.c);
        };
        for a in &self.zero {
            push(a, &mut rows);
        }
        if !self.zero.is_empty() {
            cones.push(SupportedConeT::ZeroConeT(self.zero.len()));
        }
        for a in &self.nonneg {
            push(a, &mut rows);
        }
        cones.push(SupportedConeT::NonnegativeConeT(self.nonneg.len()));
        for s in &self.soc {
            for a in s {
                push(a, &mut rows);
            }
            cones.push(SupportedConeT::SecondOrderConeT(s.len()));
        }
        let a = CscMatrix::from(&rows);
        let p = CscMatrix::<f64>::zeros((n, n));
        let mut q = vec![0.0; n];
        q[3] = 1.0;
        let mut last = String::new();
        // Tight first; then without equilibration, then with a smaller static regularisation;
        // looser only if Clarabel still stalls. "AlmostSolved" means within the reduced
        // tolerances set here (1e-9), still 10× tighter than the 1e-8 comparison, and is taken
        // only on the last attempt.
        let attempts = [
            (1e-12, true, 1e-8),
            (1e-12, false, 1e-8),
            (1e-12, true, 1e-11),
            (1e-11, false, 1e-11),
            (1e-10, true, 1e-8),
        ];
        for (i, &(tol, equilibrate, reg)) in attempts.iter().enumerate() {
            let settings = DefaultSettingsBuilder::default()
                .verbose(false)
                .tol_gap_abs(tol)
                .tol_gap_rel(tol)
                .tol_feas(tol)
                .reduced_tol_gap_abs(1e-9)
                .reduced_tol_gap_rel(1e-9)
                .reduced_tol_feas(1e-9)
                .equilibrate_enable(equilibrate)
                .static_regularization_constant(reg)
                .max_iter(400)
                .build()
                .unwrap();
            let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
                .map_err(|e| format!("{e:?}"))?;
            solver.solve();
            match solver.solution.status {
                SolverStatus::Solved => return Ok(solver.solution.x.clone()),
                SolverStatus::AlmostSolved if i + 1 == attempts.len() => {
                    return Ok(solver.solution.x.clone())
                }
                s => last = format!("{last} {s:?}"),
            }
        }
        Err(format!("clarabel: {last}"))
    }
}

/// The posed inputs of one case.
#[derive(Clone, Debug)]
struct Posed {
    spec: Spec,
    r: [f64; 3],
    q: [f64; 4],
}

/// (α*, x*) by Clarabel. The program is solved in a normalised frame (origin r₁, unit = larger
/// size) with the offset stretched to unit length (α* and x* − r₁ are homogeneous of degree one
/// in r₂ − r₁).
fn oracle(a: &Posed, b: &Posed) -> Result<(f64, [f64; 3]), String> {
    let delta = sub(&b.r, &a.r);
    let unit = a.spec.size().max(b.spec.size());
    let inv = 1.0 / unit;
    let dn = norm(&scale(&delta, inv));
    if dn == 0.0 {
        return Ok((0.0, a.r));
    }
    let t = 1.0 / dn;
    let mut p = Socp::new();
    p.add_shape(&a.spec, [0.0; 3], &rot(&a.q), inv);
    p.add_shape(&b.spec, scale(&delta, inv * t), &rot(&b.q), inv);
    let z = p.solve()?;
    let alpha = z[3] / t;
    let x = add(&a.r, &scale(&[z[0], z[1], z[2]], unit / t));
    Ok((alpha, x))
}

/// The gauge of a posed shape at world point `x`: the smallest α with `x ∈ r + α Q S`. Solved
/// in the body frame with the body point normalised to unit length (the gauge is homogeneous).
fn gauge(s: &Posed, x: &[f64; 3]) -> Result<f64, String> {
    let u = rot_t(&rot(&s.q), &sub(x, &s.r));
    let un = norm(&u);
    if un == 0.0 {
        return Ok(0.0);
    }
    let ident = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut p = Socp::new();
    p.add_shape(&s.spec, [0.0; 3], &ident, 1.0 / s.spec.size());
    for (j, uj) in u.iter().enumerate() {
        let mut e = Aff::var(j, 1.0);
        e.c = -uj / un;
        p.zero.push(e);
    }
    let z = p.solve()?;
    Ok(z[3] * un / s.spec.size())
}

// ---------------------------------------------------------------------------------------------
// One-dimensional "analytic" references: the gauge of a Minkowski sum with a ball, found by
// bisection of a strictly decreasing function (exact to the last bits).

fn bisect(f: impl Fn(f64) -> f64, mut hi: f64) -> f64 {
    let mut lo = 0.0;
    while f(hi) > 0.0 {
        hi *= 2.0;
    }
    for _ in 0..2000 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// α* of a sphere (radius `rs`) and a box (half extents `h`), `d` = box-frame offset.
fn sphere_box_alpha(rs: f64, h: &[f64; 3], d: &[f64; 3]) -> f64 {
    let f = |al: f64| {
        let e: [f64; 3] = std::array::from_fn(|i| (d[i].abs() - al * h[i]).max(0.0));
        norm(&e) - al * rs
    };
    bisect(f, norm(d) / rs)
}

/// α* of a sphere (radius `rs`) and a capsule (`r`, `l`), `d` = capsule-frame offset.
fn sphere_capsule_alpha(rs: f64, r: f64, l: f64, d: &[f64; 3]) -> f64 {
    let f = |al: f64| {
        let e = [(d[0].abs() - 0.5 * al * l).max(0.0), d[1], d[2]];
        norm(&e) - al * (r + rs)
    };
    bisect(f, norm(d) / (r + rs))
}

// ---------------------------------------------------------------------------------------------
// Random shapes.

fn random_polytope(rng: &mut Rng, m: usize) -> Spec {
    // Six box rows keep it bounded; the rest are random tangent planes of a sphere-ish body,
    // every row scaled by a random positive factor (dcol must normalise).
    let mut a = Vec::with_capacity(m);
    let mut b = Vec::with_capacity(m);
    for i in 0..m.min(6) {
        let mut row = [0.0; 3];
        row[i % 3] = if i < 3 { 1.0 } else { -1.0 };
        a.push(row);
        b.push(rng.range(0.8, 1.2));
    }
    while a.len() < m {
        let n = rng.unit_vec();
        let k = rng.log_range(0.5, 2.0);
        a.push(scale(&n, k));
        b.push(k * rng.range(0.7, 1.0));
    }
    Spec::Polytope { a, b }
}

fn regular_polygon(rng: &mut Rng, m: usize, r: f64) -> Spec {
    let mut c = Vec::with_capacity(m);
    let mut d = Vec::with_capacity(m);
    let phase = rng.range(0.0, 2.0 * PI);
    for k in 0..m {
        let th = phase + 2.0 * PI * (k as f64 + rng.range(-0.2, 0.2)) / m as f64;
        c.push([th.cos(), th.sin()]);
        d.push(rng.range(0.6, 1.0));
    }
    Spec::Polygon { c, d, r }
}

fn random_spec(rng: &mut Rng) -> Spec {
    match rng.index(8) {
        0 => Spec::Sphere {
            r: rng.range(0.3, 1.0),
        },
        1 => Spec::Ellipsoid {
            axes: [
                rng.range(0.3, 1.0),
                rng.range(0.3, 1.0),
                rng.range(0.3, 1.0),
            ],
            e: rng.unit_quat(),
        },
        2 => Spec::Cuboid {
            h: [
                rng.range(0.2, 0.8),
                rng.range(0.2, 0.8),
                rng.range(0.2, 0.8),
            ],
        },
        3 => {
            let m = 6 + rng.index(14);
            random_polytope(rng, m)
        }
        4 => Spec::Capsule {
            r: rng.range(0.2, 0.5),
            l: rng.range(0.3, 1.2),
        },
        5 => Spec::Cylinder {
            r: rng.range(0.2, 0.6),
            l: rng.range(0.3, 1.2),
        },
        6 => Spec::Cone {
            h: rng.range(0.6, 1.5),
            beta: rng.range(0.2, 1.2),
        },
        _ => {
            let m = 3 + rng.index(6);
            let r = rng.range(0.05, 0.3);
            regular_polygon(rng, m, r)
        }
    }
}

/// A random pose pair with the second origin at `dist_factor × (size₁ + size₂)` from the first.
fn place(rng: &mut Rng, s1: Spec, s2: Spec, dist_factor: f64, origin: [f64; 3]) -> (Posed, Posed) {
    let d = (s1.size() + s2.size()) * dist_factor;
    let r1 = origin;
    let r2 = add(&origin, &scale(&rng.unit_vec(), d));
    (
        Posed {
            spec: s1,
            r: r1,
            q: rng.unit_quat(),
        },
        Posed {
            spec: s2,
            r: r2,
            q: rng.unit_quat(),
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Running one case.

#[derive(Clone, Copy, Debug, PartialEq)]
enum Reference {
    /// Compare with Clarabel.
    Oracle,
    /// A closed-form (or 1-D root) value.
    Exact(f64),
    /// Compare only with other dcol runs (done by the class code); no α reference here.
    None,
}

#[derive(Default, Debug)]
struct Stats {
    cases: usize,
    converged: usize,
    not_converged: usize,
    /// Shapes rejected by a constructor (allowed only in the `extreme` class).
    rejected: usize,
    /// `distance` solves that did not converge.
    dist_not_converged: usize,
    /// Largest distance error against a closed form, in units of ℓ.
    dist_err: f64,
    alpha_err: f64,
    x_excess: f64,
    grad_err: f64,
    max_iter: u32,
    failures: Vec<String>,
}

/// What one case gave (for class-level comparisons between dcol runs).
#[derive(Clone, Copy, Debug)]
struct Outcome {
    alpha: f64,
    converged: bool,
    gradient: [f64; 14],
}

struct Tol {
    alpha: f64,
    x: f64,
    grad: f64,
}

fn tol_for(class: &str) -> Tol {
    match class {
        // Aspect ratio 1e3 and thickness 1e-4: the gauge of the thin direction magnifies an
        // x* error of δ·ℓ into (1/aspect)·δ in α; see the module comment.
        "aspect" | "flat" => Tol {
            alpha: 1e-8,
            x: 1e-5,
            grad: 1e-6,
        },
        "homogeneity" | "quat_norm" => Tol {
            alpha: 1e-9,
            x: 1e-7,
            grad: 1e-6,
        },
        "sphere_sphere" | "box_box" | "sphere_box" | "sphere_capsule" | "touching" => Tol {
            alpha: 1e-9,
            x: 1e-7,
            grad: 1e-6,
        },
        _ => Tol {
            alpha: 1e-8,
            x: 1e-7,
            grad: 1e-6,
        },
    }
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn run_case(
    class: &str,
    id: usize,
    a: &Posed,
    b: &Posed,
    reference: Reference,
    st: &mut Stats,
) -> Outcome {
    let tol = tol_for(class);
    // `extreme*` classes go past what double precision can resolve: only robustness is
    // asserted there (Ok, finite, no panic); accuracy is measured and printed.
    let strict = !class.starts_with("extreme");
    let tag = format!(
        "{class}#{id} ({}-{}, r1={:?} q1={:?} r2={:?} q2={:?})",
        a.spec.name(),
        b.spec.name(),
        a.r,
        a.q,
        b.r,
        b.q
    );
    let fail = |st: &mut Stats, msg: String| st.failures.push(format!("{tag}: {msg}"));
    st.cases += 1;
    let (s1, s2) = if strict {
        (a.spec.build(), b.spec.build())
    } else {
        // Beyond double precision a constructor may reject the shape (e.g. an ellipsoid whose
        // P has condition 1e16 is not numerically positive definite); that must be an
        // InvalidShape error, never a panic.
        match (a.spec.try_build(), b.spec.try_build()) {
            (Ok(s1), Ok(s2)) => (s1, s2),
            (r1, r2) => {
                for e in [r1.err(), r2.err()].into_iter().flatten() {
                    if !matches!(e, dcol::Error::InvalidShape(_)) {
                        fail(st, format!("constructor failed with {e:?}"));
                    }
                }
                st.cases -= 1;
                st.rejected += 1;
                return Outcome {
                    alpha: f64::NAN,
                    converged: false,
                    gradient: [f64::NAN; 14],
                };
            }
        }
    };
    let p1 = Pose::new(a.r, a.q).expect("valid pose");
    let p2 = Pose::new(b.r, b.q).expect("valid pose");
    let opts = Options::default();

    let prox = match proximity(&s1, &p1, &s2, &p2, &opts) {
        Ok(p) => p,
        Err(e) => {
            fail(st, format!("proximity returned Err({e})"));
            return Outcome {
                alpha: f64::NAN,
                converged: false,
                gradient: [f64::NAN; 14],
            };
        }
    };
    st.max_iter = st.max_iter.max(prox.iterations);
    let outputs = [
        prox.alpha,
        prox.point.x,
        prox.point.y,
        prox.point.z,
        prox.contact1.x,
        prox.contact1.y,
        prox.contact1.z,
        prox.contact2.x,
        prox.contact2.y,
        prox.contact2.z,
    ];
    if !all_finite(&outputs) {
        fail(
            st,
            format!(
                "non-finite proximity output {outputs:?} ({:?})",
                prox.status
            ),
        );
    }
    let converged = prox.status == SolveStatus::Converged;
    if converged {
        st.converged += 1;
    } else {
        st.not_converged += 1;
        if std::env::var_os("STRESS_VERBOSE").is_some() {
            println!(
                "{tag}: {:?} after {} iterations, α = {:e}",
                prox.status, prox.iterations, prox.alpha
            );
        }
    }

    // Derivatives and distance: Ok, finite.
    let mut grad = [f64::NAN; 14];
    match gradient(&s1, &p1, &s2, &p2, &opts) {
        Ok((gp, g)) => {
            grad = g;
            if gp.status != prox.status || gp.alpha.to_bits() != prox.alpha.to_bits() {
                fail(
                    st,
                    format!(
                        "gradient's proximity differs: {:?} {} vs {:?} {}",
                        gp.status, gp.alpha, prox.status, prox.alpha
                    ),
                );
            }
            if !all_finite(&g) {
                fail(st, format!("non-finite gradient {g:?} ({:?})", gp.status));
            }
        }
        Err(e) => fail(st, format!("gradient returned Err({e})")),
    }
    match jacobian(&s1, &p1, &s2, &p2, &opts) {
        Ok((_, j)) => {
            if !all_finite(j.as_flattened()) {
                fail(st, format!("non-finite jacobian {j:?}"));
            }
        }
        Err(e) => fail(st, format!("jacobian returned Err({e})")),
    }
    match distance(&s1, &p1, &s2, &p2, &opts) {
        Ok(d) => {
            let o = [
                d.distance,
                d.closest1.x,
                d.closest1.y,
                d.closest1.z,
                d.closest2.x,
                d.closest2.y,
                d.closest2.z,
                d.normal.x,
                d.normal.y,
                d.normal.z,
            ];
            if !all_finite(&o) {
                fail(st, format!("non-finite distance output {o:?}"));
            }
            if !d.status.is_converged() {
                st.dist_not_converged += 1;
                if std::env::var_os("STRESS_VERBOSE").is_some() {
                    println!("{tag}: distance {:?}", d.status);
                }
            }
            // Closed forms: spheres, and boxes sharing one attitude (the distance is the norm
            // of the positive parts of |QᵀΔ| − (a + b)).
            let exact = match (&a.spec, &b.spec) {
                (Spec::Sphere { r: ra }, Spec::Sphere { r: rb }) => {
                    Some((norm(&sub(&b.r, &a.r)) - ra - rb).max(0.0))
                }
                (Spec::Cuboid { h: ha }, Spec::Cuboid { h: hb }) if a.q == b.q => {
                    let dd = rot_t(&rot(&a.q), &sub(&b.r, &a.r));
                    let e: [f64; 3] =
                        std::array::from_fn(|i| (dd[i].abs() - ha[i] - hb[i]).max(0.0));
                    Some(norm(&e))
                }
                _ => None,
            };
            if let (Some(ex), true) = (exact, d.status.is_converged()) {
                let ell = a.spec.size().max(b.spec.size());
                let err = (d.distance - ex).abs() / ell;
                st.dist_err = st.dist_err.max(err);
                if strict && err > 1e-9 {
                    fail(
                        st,
                        format!(
                            "distance {:.17e}, exact {ex:.17e} (error {err:.2e} ℓ)",
                            d.distance
                        ),
                    );
                }
            }
            if d.status.is_converged() && converged && d.distance < 0.0 {
                fail(st, format!("negative distance {}", d.distance));
            }
            // α* < 1 ⇔ overlap ⇔ d* = 0 (away from touching, where both are at round-off).
            if d.status.is_converged() && converged {
                let ell = a.spec.size().max(b.spec.size());
                if prox.alpha < 1.0 - 1e-6 && d.distance > 1e-8 * ell {
                    fail(
                        st,
                        format!("α* = {} < 1 but distance {}", prox.alpha, d.distance),
                    );
                }
                if prox.alpha > 1.0 + 1e-6 && d.distance == 0.0 {
                    fail(st, format!("α* = {} > 1 but distance 0", prox.alpha));
                }
            }
        }
        Err(e) => fail(st, format!("distance returned Err({e})")),
    }

    if !converged {
        return Outcome {
            alpha: prox.alpha,
            converged,
            gradient: grad,
        };
    }

    // α* against the reference.
    let delta = sub(&b.r, &a.r);
    let alpha_ref = match reference {
        Reference::Exact(v) => Some(v),
        Reference::Oracle => match oracle(a, b) {
            Ok((al, _)) => Some(al),
            Err(e) => {
                if strict {
                    fail(st, format!("oracle failed: {e}"));
                }
                None
            }
        },
        Reference::None => None,
    };
    if let Some(ar) = alpha_ref {
        let err = if ar == 0.0 {
            if prox.alpha == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        } else {
            (prox.alpha - ar).abs() / ar
        };
        st.alpha_err = st.alpha_err.max(err);
        if !strict && err > 1e-6 && std::env::var_os("STRESS_VERBOSE").is_some() {
            println!(
                "{tag}: α* = {:.17e}, oracle {ar:.17e}, error {err:.2e}",
                prox.alpha
            );
        }
        if strict && err > tol.alpha {
            fail(
                st,
                format!(
                    "α* = {:.17e}, reference {:.17e}: relative error {err:.2e} > {:.0e}",
                    prox.alpha, ar, tol.alpha
                ),
            );
        }
    }

    // x* optimal: the larger of the two shapes' gauges at dcol's x* is α* again.
    if reference != Reference::None && prox.alpha > 0.0 {
        let x = v3(&prox.point);
        match gauge(a, &x).and_then(|g1| gauge(b, &x).map(|g2| g1.max(g2))) {
            Ok(ax) => {
                // x* is returned in world coordinates, rounded to ~ε|x*|; the gauge of a shape
                // moves by at most (that)/(inscribed radius), which matters when α* is tiny
                // (nearly coincident origins): allow that floor on top of the relative bound.
                let iota = s1.inscribed_radius().min(s2.inscribed_radius());
                let floor = 8.0 * f64::EPSILON * norm(&v3(&prox.point)) / iota;
                let excess = (ax - prox.alpha - floor).max(0.0) / prox.alpha;
                st.x_excess = st.x_excess.max(excess);
                if strict && excess > tol.x {
                    fail(
                        st,
                        format!(
                            "x* = {:?} is not optimal: the smallest α containing it is {ax:.17e} \
                             vs α* = {:.17e} (excess {excess:.2e})",
                            v3(&prox.point),
                            prox.alpha
                        ),
                    );
                }
            }
            Err(e) => {
                if strict {
                    fail(st, format!("gauge oracle failed: {e}"))
                }
            }
        }
    }

    // Gradient identities (any subgradient of the gauge satisfies them).
    if prox.alpha > 0.0 && all_finite(&grad) {
        let g1 = [grad[0], grad[1], grad[2]];
        let g2 = [grad[7], grad[8], grad[9]];
        let gn = norm(&g2);
        let euler = (dot(&g2, &delta) - prox.alpha).abs() / prox.alpha;
        let transl = norm(&add(&g1, &g2)) / gn.max(f64::MIN_POSITIVE);
        let qa = [grad[3], grad[4], grad[5], grad[6]];
        let qb = [grad[10], grad[11], grad[12], grad[13]];
        // ∂α/∂qᵢ · qᵢ = 0, relative to the natural size of a rotation derivative,
        // |∂α/∂r|·(lever arm), which is invariant under scaling q.
        let x = v3(&prox.point);
        let qdot = |g: &[f64; 4], q: &[f64; 4], r: &[f64; 3]| {
            let d: f64 = (0..4).map(|i| g[i] * q[i]).sum();
            let lever = norm(&sub(&x, r)) + norm(&delta);
            d.abs() / (gn * lever + f64::MIN_POSITIVE)
        };
        let qerr = qdot(&qa, &a.q, &a.r).max(qdot(&qb, &b.q, &b.r));
        let e = euler.max(transl);
        st.grad_err = st.grad_err.max(e).max(qerr);
        if strict && (e > tol.grad || qerr > 1e-8) {
            fail(
                st,
                format!(
                    "gradient identities: |∂α/∂r₂·Δ − α|/α = {euler:.2e}, \
                     |∂α/∂r₁ + ∂α/∂r₂|/|∂α/∂r₂| = {transl:.2e}, |∂α/∂q·q| rel = {qerr:.2e}; \
                     gradient {grad:?}"
                ),
            );
        }
    }
    Outcome {
        alpha: prox.alpha,
        converged,
        gradient: grad,
    }
}

// ---------------------------------------------------------------------------------------------
// The classes.

type Table = BTreeMap<&'static str, Stats>;

fn class_random(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("random").or_default();
    for id in 0..96 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let f = rng.log_range(0.15, 3.0);
        let o = rng.point();
        let (a, b) = place(rng, s1, s2, f, o);
        run_case("random", id, &a, &b, Reference::Oracle, st);
    }
}

fn class_sphere_sphere(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("sphere_sphere").or_default();
    for id in 0..60 {
        let s = rng.log_range(1e-3, 1e3);
        let (r1, r2) = (s * rng.log_range(0.1, 10.0), s * rng.log_range(0.1, 10.0));
        let f = rng.log_range(0.05, 20.0);
        let origin = scale(&rng.unit_vec(), s * rng.range(0.0, 10.0));
        let (a, b) = place(
            rng,
            Spec::Sphere { r: r1 },
            Spec::Sphere { r: r2 },
            f,
            origin,
        );
        let exact = norm(&sub(&b.r, &a.r)) / (r1 + r2);
        run_case("sphere_sphere", id, &a, &b, Reference::Exact(exact), st);
    }
}

fn box_box_alpha(h1: &[f64; 3], h2: &[f64; 3], q: &[f64; 4], delta: &[f64; 3]) -> f64 {
    let d = rot_t(&rot(q), delta);
    (0..3)
        .map(|i| d[i].abs() / (h1[i] + h2[i]))
        .fold(0.0, f64::max)
}

fn class_box_box(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("box_box").or_default();
    for id in 0..60 {
        let s = rng.log_range(1e-2, 1e2);
        let h1 = [0.0; 3].map(|_: f64| s * rng.log_range(0.1, 3.0));
        let h2 = [0.0; 3].map(|_: f64| s * rng.log_range(0.1, 3.0));
        // Half the cases axis-aligned, half with one shared random attitude (rotating both
        // boxes together keeps the closed form in the common frame).
        let q = if id % 2 == 0 {
            [1.0, 0.0, 0.0, 0.0]
        } else {
            rng.unit_quat()
        };
        let r1 = rng.point().map(|v| v * s);
        let delta = scale(&rng.unit_vec(), s * rng.log_range(0.05, 20.0));
        let a = Posed {
            spec: Spec::Cuboid { h: h1 },
            r: r1,
            q,
        };
        let b = Posed {
            spec: Spec::Cuboid { h: h2 },
            r: add(&r1, &delta),
            q,
        };
        let exact = box_box_alpha(&h1, &h2, &q, &sub(&b.r, &a.r));
        run_case("box_box", id, &a, &b, Reference::Exact(exact), st);
    }
}

fn class_sphere_box_capsule(t: &mut Table, rng: &mut Rng) {
    for id in 0..40 {
        let s = rng.log_range(1e-2, 1e2);
        let rs = s * rng.log_range(0.1, 3.0);
        let h = [0.0; 3].map(|_: f64| s * rng.log_range(0.1, 3.0));
        let q = rng.unit_quat();
        let r1 = scale(&rng.unit_vec(), s);
        let delta = scale(&rng.unit_vec(), s * rng.log_range(0.05, 20.0));
        let bx = Posed {
            spec: Spec::Cuboid { h },
            r: r1,
            q,
        };
        let sp = Posed {
            spec: Spec::Sphere { r: rs },
            r: add(&r1, &delta),
            q: rng.unit_quat(),
        };
        let exact = sphere_box_alpha(rs, &h, &rot_t(&rot(&q), &delta));
        let st = t.entry("sphere_box").or_default();
        // Both orders.
        if id % 2 == 0 {
            run_case("sphere_box", id, &bx, &sp, Reference::Exact(exact), st);
        } else {
            run_case("sphere_box", id, &sp, &bx, Reference::Exact(exact), st);
        }

        let (r, l) = (s * rng.log_range(0.05, 2.0), s * rng.log_range(0.1, 10.0));
        let cap = Posed {
            spec: Spec::Capsule { r, l },
            r: r1,
            q,
        };
        let exact = sphere_capsule_alpha(rs, r, l, &rot_t(&rot(&q), &delta));
        let st = t.entry("sphere_capsule").or_default();
        if id % 2 == 0 {
            run_case("sphere_capsule", id, &cap, &sp, Reference::Exact(exact), st);
        } else {
            run_case("sphere_capsule", id, &sp, &cap, Reference::Exact(exact), st);
        }
    }
}

fn class_scale(t: &mut Table, rng: &mut Rng) {
    let mut base = Vec::new();
    for _ in 0..12 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let f = rng.log_range(0.2, 3.0);
        let o = rng.point();
        base.push(place(rng, s1, s2, f, o));
    }
    let mut id = 0;
    let mut at_one = Vec::new();
    {
        let st = t.entry("scale").or_default();
        for (a, b) in &base {
            at_one.push(run_case("scale", id, a, b, Reference::Oracle, st));
            id += 1;
        }
    }
    for k in [-4, -3, -2, -1, 1, 2, 3, 4] {
        let s = 10f64.powi(k);
        for (i, (a, b)) in base.iter().enumerate() {
            let sa = Posed {
                spec: a.spec.scaled(s),
                r: scale(&a.r, s),
                q: a.q,
            };
            let sb = Posed {
                spec: b.spec.scaled(s),
                r: scale(&b.r, s),
                q: b.q,
            };
            let st = t.entry("scale").or_default();
            let o = run_case("scale", id, &sa, &sb, Reference::Oracle, st);
            // Scale invariance of α* against dcol's own answer at scale 1.
            if o.converged && at_one[i].converged {
                let err = (o.alpha - at_one[i].alpha).abs() / at_one[i].alpha;
                st.alpha_err = st.alpha_err.max(err);
                if err > 1e-8 {
                    st.failures.push(format!(
                        "scale#{id}: α* at scale {s:e} = {:.17e} vs {:.17e} at scale 1",
                        o.alpha, at_one[i].alpha
                    ));
                }
            }
            id += 1;
        }
    }
}

fn class_aspect(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("aspect").or_default();
    let k = 1e3;
    for id in 0..80 {
        let long = rng.range(0.5, 2.0);
        let thin = long / k;
        let s1 = match id % 10 {
            0 => Spec::Capsule { r: thin, l: long },
            1 => Spec::Cylinder { r: thin, l: long }, // needle
            2 => Spec::Cylinder { r: long, l: thin }, // disk
            3 => Spec::Ellipsoid {
                axes: [long, long, thin],
                e: rng.unit_quat(),
            },
            4 => Spec::Ellipsoid {
                axes: [long, thin, thin],
                e: rng.unit_quat(),
            },
            5 => Spec::Cuboid {
                h: [long, thin, thin],
            },
            6 => Spec::Cuboid {
                h: [long, long, thin],
            },
            7 => regular_polygon(rng, 5, thin).scaled(long), // tiny padding
            8 => Spec::Polygon {
                c: vec![[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
                d: vec![long, thin, long, thin],
                r: 0.1 * thin,
            },
            _ => Spec::Cone { h: long, beta: 0.3 },
        };
        let s2 = if id % 3 == 0 {
            s1.clone()
        } else {
            random_spec(rng)
        };
        let f = rng.log_range(0.05, 2.0);
        let o = rng.point();
        let (a, b) = place(rng, s1, s2, f, o);
        run_case("aspect", id, &a, &b, Reference::Oracle, st);
    }
}

fn class_far_small(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("far_small").or_default();
    for id in 0..50 {
        let s1 = random_spec(rng).scaled(1e-2);
        let s2 = random_spec(rng).scaled(1e-2);
        let origin = [0.0; 3]
            .map(|_: f64| rng.range(0.5e4, 1.5e4) * if rng.unif() < 0.5 { -1.0 } else { 1.0 });
        let f = rng.log_range(0.15, 3.0);
        let (a, b) = place(rng, s1, s2, f, origin);
        run_case("far_small", id, &a, &b, Reference::Oracle, st);
    }
}

fn class_coincident(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("coincident").or_default();
    for id in 0..30 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let r = rng.point().map(|v| v * 10f64.powi(rng.index(9) as i32 - 4));
        let a = Posed {
            spec: s1,
            r,
            q: rng.unit_quat(),
        };
        let b = Posed {
            spec: s2,
            r,
            q: rng.unit_quat(),
        };
        run_case("coincident", id, &a, &b, Reference::Exact(0.0), st);
    }
}

fn class_near_coincident(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("near_coincident").or_default();
    for id in 0..50 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let f = 10f64.powi(-6 - (id as i32 % 9));
        let o = rng.point();
        let (a, b) = place(rng, s1, s2, f, o);
        run_case("near_coincident", id, &a, &b, Reference::Oracle, st);
    }
}

fn class_homogeneity(t: &mut Table, rng: &mut Rng) {
    // r₁ = 0 and t a power of two, so that r₂ = tΔ is exact: the two problems are then the
    // same up to the exact factor t (with r₁ ≠ 0 the rounding of r₁ + tΔ would change the
    // offset's direction by ~1e-16·|r₁|/|tΔ|, a different problem).
    let st = t.entry("homogeneity").or_default();
    let mut id = 0;
    for _ in 0..8 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let f = rng.log_range(0.3, 3.0);
        let (a, b) = place(rng, s1, s2, f, [0.0; 3]);
        let base = run_case("homogeneity", id, &a, &b, Reference::Oracle, st);
        id += 1;
        for k in [-40, -30, -20, -10, -3, 3, 10] {
            let tk = 2f64.powi(k);
            let bt = Posed {
                r: scale(&b.r, tk),
                ..b.clone()
            };
            let o = run_case("homogeneity", id, &a, &bt, Reference::None, st);
            if o.converged && base.converged {
                let expect = tk * base.alpha;
                let err = (o.alpha - expect).abs() / expect;
                st.alpha_err = st.alpha_err.max(err);
                if err > tol_for("homogeneity").alpha {
                    st.failures.push(format!(
                        "homogeneity#{id}: α(tΔ) = {:.17e}, t·α(Δ) = {expect:.17e} (t = 2^{k}, \
                         error {err:.2e}); {a:?} {bt:?}",
                        o.alpha
                    ));
                }
            }
            id += 1;
        }
    }
}

fn class_touching(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("touching").or_default();
    for id in 0..60 {
        let s = rng.log_range(1e-2, 1e2);
        let r1 = rng.point().map(|v| v * s);
        let (a, b, exact) = match id % 4 {
            0 => {
                // Spheres at exactly R₁ + R₂ (up to the rounding of the offset).
                let (ra, rb) = (s * rng.log_range(0.1, 3.0), s * rng.log_range(0.1, 3.0));
                let b_r = add(&r1, &scale(&rng.unit_vec(), ra + rb));
                let exact = norm(&sub(&b_r, &r1)) / (ra + rb);
                (
                    Posed {
                        spec: Spec::Sphere { r: ra },
                        r: r1,
                        q: rng.unit_quat(),
                    },
                    Posed {
                        spec: Spec::Sphere { r: rb },
                        r: b_r,
                        q: rng.unit_quat(),
                    },
                    exact,
                )
            }
            1 => {
                // Boxes face to face (shared attitude), lateral offset inside the face.
                let h1 = [0.0; 3].map(|_: f64| s * rng.log_range(0.2, 2.0));
                let h2 = [0.0; 3].map(|_: f64| s * rng.log_range(0.2, 2.0));
                let q = if id % 8 == 1 {
                    [1.0, 0.0, 0.0, 0.0]
                } else {
                    rng.unit_quat()
                };
                let axis = rng.index(3);
                let mut d = [0.0; 3];
                for i in 0..3 {
                    d[i] = if i == axis {
                        h1[i] + h2[i]
                    } else {
                        rng.range(-0.9, 0.9) * (h1[i] + h2[i])
                    };
                }
                let delta = {
                    let m = rot(&q);
                    [0, 1, 2].map(|i| m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2])
                };
                let b_r = add(&r1, &delta);
                let exact = box_box_alpha(&h1, &h2, &q, &sub(&b_r, &r1));
                (
                    Posed {
                        spec: Spec::Cuboid { h: h1 },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cuboid { h: h2 },
                        r: b_r,
                        q,
                    },
                    exact,
                )
            }
            2 => {
                // Sphere touching a box face or corner.
                let h = [0.0; 3].map(|_: f64| s * rng.log_range(0.2, 2.0));
                let rs = s * rng.log_range(0.1, 2.0);
                let q = rng.unit_quat();
                let d = if id % 8 == 2 {
                    [h[0] + rs, 0.3 * h[1], -0.5 * h[2]]
                } else {
                    let n = [1.0, 1.0, 1.0].map(|v: f64| v / 3f64.sqrt());
                    add(&h, &scale(&n, rs))
                };
                let m = rot(&q);
                let delta = [0, 1, 2].map(|i| m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2]);
                let b_r = add(&r1, &delta);
                let exact = sphere_box_alpha(rs, &h, &rot_t(&m, &sub(&b_r, &r1)));
                (
                    Posed {
                        spec: Spec::Cuboid { h },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Sphere { r: rs },
                        r: b_r,
                        q: rng.unit_quat(),
                    },
                    exact,
                )
            }
            _ => {
                // Sphere touching a capsule's side.
                let (r, l) = (s * rng.log_range(0.1, 1.0), s * rng.log_range(0.2, 4.0));
                let rs = s * rng.log_range(0.1, 2.0);
                let q = rng.unit_quat();
                let th = rng.range(0.0, 2.0 * PI);
                let d = [
                    rng.range(-0.5, 0.5) * l,
                    (r + rs) * th.cos(),
                    (r + rs) * th.sin(),
                ];
                let m = rot(&q);
                let delta = [0, 1, 2].map(|i| m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2]);
                let b_r = add(&r1, &delta);
                let exact = sphere_capsule_alpha(rs, r, l, &rot_t(&m, &sub(&b_r, &r1)));
                (
                    Posed {
                        spec: Spec::Capsule { r, l },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Sphere { r: rs },
                        r: b_r,
                        q: rng.unit_quat(),
                    },
                    exact,
                )
            }
        };
        assert!((exact - 1.0).abs() < 1e-12, "construction: {exact}");
        run_case("touching", id, &a, &b, Reference::Exact(exact), st);
    }
}

/// `q` followed by a turn of `th` about body axis `axis` (0 = x, 1 = y, 2 = z).
fn with_turn(q: &[f64; 4], axis: usize, th: f64) -> [f64; 4] {
    // q ⊗ [cos(th/2), sin(th/2) e_axis]
    let mut r = [(0.5 * th).cos(), 0.0, 0.0, 0.0];
    r[1 + axis] = (0.5 * th).sin();
    let [a0, a1, a2, a3] = *q;
    let [b0, b1, b2, b3] = r;
    [
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    ]
}

fn class_parallel(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("parallel").or_default();
    for id in 0..70 {
        let q = rng.unit_quat();
        let m = rot(&q);
        let to_world =
            |d: [f64; 3]| [0, 1, 2].map(|i| m[i][0] * d[0] + m[i][1] * d[1] + m[i][2] * d[2]);
        let r1 = rng.point();
        let gap = rng.range(0.6, 1.6); // α* in roughly that range
        let (a, b, reference) = match id % 7 {
            0 => {
                // Box face on box face, offset along the shared body x axis only.
                let h1 = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let h2 = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let d = [
                    gap * (h1[0] + h2[0]),
                    0.2 * gap * (h1[1] + h2[1]) * rng.range(-1.0, 1.0),
                    0.2 * gap * (h1[2] + h2[2]) * rng.range(-1.0, 1.0),
                ];
                let rb = add(&r1, &to_world(d));
                let exact = box_box_alpha(&h1, &h2, &q, &sub(&rb, &r1));
                (
                    Posed {
                        spec: Spec::Cuboid { h: h1 },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cuboid { h: h2 },
                        r: rb,
                        q,
                    },
                    Reference::Exact(exact),
                )
            }
            1 => {
                // Box edge on box face: the second box turned 45° about the body z axis.
                let h1 = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let h2 = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let d = [gap * 2.0, 0.0, 0.1 * rng.range(-1.0, 1.0)];
                (
                    Posed {
                        spec: Spec::Cuboid { h: h1 },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cuboid { h: h2 },
                        r: add(&r1, &to_world(d)),
                        q: with_turn(&q, 2, PI / 4.0),
                    },
                    Reference::Oracle,
                )
            }
            2 => {
                // Cylinder lying on a box face (line contact along the cylinder axis = body x).
                let h = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let (r, l) = (rng.range(0.2, 0.6), rng.range(0.5, 1.5));
                let d = [0.1 * rng.range(-1.0, 1.0), 0.0, gap * (h[2] + r)];
                (
                    Posed {
                        spec: Spec::Cuboid { h },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cylinder { r, l },
                        r: add(&r1, &to_world(d)),
                        q,
                    },
                    Reference::Oracle,
                )
            }
            3 => {
                // Cylinder cap flat on a box face (cylinder axis = body x).
                let h = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let (r, l) = (rng.range(0.2, 0.6), rng.range(0.5, 1.5));
                let d = [gap * (h[0] + 0.5 * l), 0.05 * rng.range(-1.0, 1.0), 0.0];
                (
                    Posed {
                        spec: Spec::Cuboid { h },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cylinder { r, l },
                        r: add(&r1, &to_world(d)),
                        q,
                    },
                    Reference::Oracle,
                )
            }
            4 => {
                // Padded polygon (in the body x-y plane) parallel to a box's z face.
                let h = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let pr = rng.range(0.05, 0.2);
                let m = 4 + rng.index(4);
                let poly = regular_polygon(rng, m, pr);
                let d = [0.1 * rng.range(-1.0, 1.0), 0.1, gap * (h[2] + pr)];
                (
                    Posed {
                        spec: Spec::Cuboid { h },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: poly,
                        r: add(&r1, &to_world(d)),
                        q,
                    },
                    Reference::Oracle,
                )
            }
            5 => {
                // Parallel capsules side by side (segment contact).
                let (ra, la) = (rng.range(0.1, 0.5), rng.range(0.5, 2.0));
                let (rb, lb) = (rng.range(0.1, 0.5), rng.range(0.5, 2.0));
                let d = [0.2 * rng.range(-1.0, 1.0), gap * (ra + rb), 0.0];
                (
                    Posed {
                        spec: Spec::Capsule { r: ra, l: la },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Capsule { r: rb, l: lb },
                        r: add(&r1, &to_world(d)),
                        q,
                    },
                    Reference::Oracle,
                )
            }
            _ => {
                // Cone side (a generator) flat on a box face: the cone turned so that one
                // generator is parallel to the body x axis, lying on the box's +z face.
                let h = [
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                    rng.range(0.3, 1.0),
                ];
                let (ch, beta) = (rng.range(0.6, 1.5), rng.range(0.2, 0.8));
                let qc = with_turn(&q, 1, -beta); // one generator along x, axis tilted up by β
                let d = [0.0, 0.0, gap * (h[2] + 0.75 * ch * beta.sin())];
                (
                    Posed {
                        spec: Spec::Cuboid { h },
                        r: r1,
                        q,
                    },
                    Posed {
                        spec: Spec::Cone { h: ch, beta },
                        r: add(&r1, &to_world(d)),
                        q: qc,
                    },
                    Reference::Oracle,
                )
            }
        };
        if id % 2 == 1 {
            run_case("parallel", id, &b, &a, reference, st);
        } else {
            run_case("parallel", id, &a, &b, reference, st);
        }
    }
}

fn class_cone(t: &mut Table, rng: &mut Rng, class: &'static str, beta: f64) {
    let st = t.entry(class).or_default();
    for id in 0..40 {
        let cone = Spec::Cone {
            h: rng.range(0.5, 2.0),
            beta,
        };
        let other = if id % 4 == 0 {
            Spec::Cone {
                h: rng.range(0.5, 2.0),
                beta,
            }
        } else {
            random_spec(rng)
        };
        let (f, o) = (rng.log_range(0.05, 2.0), rng.point());
        let (a, b) = place(rng, cone, other, f, o);
        if id % 2 == 0 {
            run_case(class, id, &a, &b, Reference::Oracle, st);
        } else {
            run_case(class, id, &b, &a, Reference::Oracle, st);
        }
    }
}

fn class_flat(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("flat").or_default();
    for id in 0..60 {
        let eps = 10f64.powf(-rng.range(3.0, 4.0));
        let w = rng.range(0.5, 2.0);
        let s1 = match id % 4 {
            0 => Spec::Ellipsoid {
                axes: [w, w * rng.range(0.5, 1.0), w * eps],
                e: rng.unit_quat(),
            },
            1 => Spec::Cuboid {
                h: [w, w * rng.range(0.5, 1.0), w * eps],
            },
            2 => {
                // A random polytope squashed in z: rows (nx, ny, nz/ε) keep b, so the body is
                // ε thin in z.
                let m = 8 + rng.index(12);
                match random_polytope(rng, m) {
                    Spec::Polytope { a, b } => Spec::Polytope {
                        a: a.iter().map(|r| [r[0], r[1], r[2] / eps]).collect(),
                        b: b.iter().map(|v| v * w).collect(),
                    },
                    _ => unreachable!(),
                }
            }
            _ => Spec::Ellipsoid {
                axes: [w * eps, w, w * eps.sqrt()],
                e: rng.unit_quat(),
            },
        };
        let s2 = if id % 3 == 0 {
            s1.clone()
        } else {
            random_spec(rng)
        };
        let f = rng.log_range(0.05, 2.0);
        let o = rng.point();
        let (a, b) = place(rng, s1, s2, f, o);
        run_case("flat", id, &a, &b, Reference::Oracle, st);
    }
}

fn class_quat_norm(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("quat_norm").or_default();
    let mut id = 0;
    for _ in 0..10 {
        let (s1, s2) = (random_spec(rng), random_spec(rng));
        let (f, o) = (rng.log_range(0.2, 3.0), rng.point());
        let (a, b) = place(rng, s1, s2, f, o);
        let base = run_case("quat_norm", id, &a, &b, Reference::Oracle, st);
        id += 1;
        for (k1, k2) in [(1e-6, 1e-6), (1e6, 1e6), (1e-6, 1e6), (1e-30, 1e30)] {
            let a2 = Posed {
                q: a.q.map(|v| v * k1),
                ..a.clone()
            };
            let b2 = Posed {
                q: b.q.map(|v| v * k2),
                ..b.clone()
            };
            let o = run_case("quat_norm", id, &a2, &b2, Reference::Oracle, st);
            if o.converged && base.converged {
                let err = (o.alpha - base.alpha).abs() / base.alpha;
                st.alpha_err = st.alpha_err.max(err);
                // ∂α/∂q scales like 1/‖q‖ (α depends on q/‖q‖).
                let mut gerr: f64 = 0.0;
                let gscale = base.gradient.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                for i in 0..14 {
                    let k = if (3..7).contains(&i) {
                        1.0 / k1
                    } else if i >= 10 {
                        1.0 / k2
                    } else {
                        1.0
                    };
                    let e = (o.gradient[i] / k - base.gradient[i]).abs() / gscale;
                    gerr = gerr.max(e);
                }
                st.grad_err = st.grad_err.max(gerr);
                if err > tol_for("quat_norm").alpha || gerr > 1e-6 {
                    st.failures.push(format!(
                        "quat_norm#{id}: norms ({k1:e}, {k2:e}): α* {:.17e} vs unit {:.17e} \
                         ({err:.2e}); scaled gradient error {gerr:.2e}",
                        o.alpha, base.alpha
                    ));
                }
            }
            id += 1;
        }
    }
}

fn class_many_facets(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("many_facets").or_default();
    let counts = [100, 128, 160, 200, 256];
    for id in 0..30 {
        let m = counts[id % counts.len()];
        let s1 = random_polytope(rng, m);
        let s2 = match id % 3 {
            0 => random_polytope(rng, counts[(id / 3) % counts.len()]),
            _ => random_spec(rng),
        };
        let f = rng.log_range(0.1, 2.0);
        let o = rng.point();
        let (a, b) = place(rng, s1, s2, f, o);
        run_case("many_facets", id, &a, &b, Reference::Oracle, st);
    }
}

/// Two shapes of very different sizes (a small object near a large one, e.g. a ball on a
/// ground slab): size ratios 1e2..1e5, the small shape within a few of its own sizes of the
/// large one's surface (α* of order 1).
fn class_mixed_scale(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("mixed_scale").or_default();
    for id in 0..48 {
        let k = 10f64.powi(2 + (id % 4) as i32);
        let big = random_spec(rng).scaled(k);
        let small = random_spec(rng);
        // Place the small shape's origin at (1 + f)·(big's extent along a random direction):
        // the gauge of the big shape at that point is about 1 + f.
        let qb = rng.unit_quat();
        let dir = rng.unit_vec();
        let probe = Posed {
            spec: big.clone(),
            r: [0.0; 3],
            q: qb,
        };
        let g = gauge(&probe, &dir).expect("gauge");
        let f = rng.range(-0.3, 0.6);
        let r2 = scale(&dir, (1.0 + f) / g);
        let a = Posed {
            spec: big,
            r: [0.0; 3],
            q: qb,
        };
        let b = Posed {
            spec: small,
            r: r2,
            q: rng.unit_quat(),
        };
        if id % 2 == 0 {
            run_case("mixed_scale", id, &a, &b, Reference::Oracle, st);
        } else {
            run_case("mixed_scale", id, &b, &a, Reference::Oracle, st);
        }
    }
}

/// Beyond double precision: positions 1e8 m with sizes 1e-6 m (the offset keeps ~2 digits),
/// aspect ratios 1e6, thickness 1e-8, cones of 0.01° and 89.99°, overall scales 1e±12.
/// Asserted: every query returns `Ok`, no panic, every output finite (converged or not).
fn class_extreme(t: &mut Table, rng: &mut Rng) {
    let st = t.entry("extreme").or_default();
    for id in 0..60 {
        let (s1, origin, f) = match id % 6 {
            0 => (
                random_spec(rng).scaled(1e-6),
                rng.point().map(|v| v * 1e8),
                1.0,
            ),
            1 => (
                Spec::Capsule {
                    r: 1e-6,
                    l: rng.range(0.5, 2.0),
                },
                rng.point(),
                0.3,
            ),
            2 => (
                Spec::Ellipsoid {
                    axes: [1.0, rng.range(0.5, 1.0), 1e-8],
                    e: rng.unit_quat(),
                },
                rng.point(),
                0.3,
            ),
            3 => (
                Spec::Cone {
                    h: 1.0,
                    beta: 0.01f64.to_radians(),
                },
                rng.point(),
                0.5,
            ),
            4 => (
                Spec::Cone {
                    h: 1.0,
                    beta: 89.99f64.to_radians(),
                },
                rng.point(),
                0.5,
            ),
            _ => {
                let k = if rng.unif() < 0.5 { 1e-12 } else { 1e12 };
                (random_spec(rng).scaled(k), rng.point().map(|v| v * k), 1.0)
            }
        };
        let s2 = match id % 6 {
            0 => random_spec(rng).scaled(1e-6),
            5 => match &s1 {
                Spec::Sphere { r } => Spec::Cuboid { h: [*r; 3] },
                other => other.clone(),
            },
            _ => random_spec(rng),
        };
        let f = f * rng.log_range(0.2, 3.0);
        let (a, b) = place(rng, s1, s2, f, origin);
        run_case("extreme", id, &a, &b, Reference::Oracle, st);
    }
}

#[test]
fn stress_suite() {
    let start = std::time::Instant::now();
    let mut t = Table::new();
    let mut rng = Rng::new(0x5EED_0006);
    class_random(&mut t, &mut rng);
    class_sphere_sphere(&mut t, &mut rng);
    class_box_box(&mut t, &mut rng);
    class_sphere_box_capsule(&mut t, &mut rng);
    class_scale(&mut t, &mut rng);
    class_aspect(&mut t, &mut rng);
    class_far_small(&mut t, &mut rng);
    class_coincident(&mut t, &mut rng);
    class_near_coincident(&mut t, &mut rng);
    class_homogeneity(&mut t, &mut rng);
    class_touching(&mut t, &mut rng);
    class_parallel(&mut t, &mut rng);
    class_cone(&mut t, &mut rng, "cone_1deg", 1f64.to_radians());
    class_cone(&mut t, &mut rng, "cone_89deg", 89f64.to_radians());
    class_flat(&mut t, &mut rng);
    class_quat_norm(&mut t, &mut rng);
    class_many_facets(&mut t, &mut rng);
    class_mixed_scale(&mut t, &mut rng);
    class_extreme(&mut t, &mut rng);

    println!(
        "\n{:<16} {:>6} {:>11} {:>14} {:>14} {:>14} {:>9} {:>8} {:>9} {:>10} {:>12}",
        "class",
        "cases",
        "converged%",
        "max α relerr",
        "max x* excess",
        "max grad err",
        "not conv",
        "max it",
        "rejected",
        "dist nc",
        "dist err/ℓ"
    );
    let mut failures = Vec::new();
    let (mut total, mut total_nc) = (0, 0);
    for (name, s) in &t {
        println!(
            "{:<16} {:>6} {:>10.1}% {:>14.2e} {:>14.2e} {:>14.2e} {:>9} {:>8} {:>9} {:>10} {:>12.2e}",
            name,
            s.cases,
            100.0 * s.converged as f64 / s.cases as f64,
            s.alpha_err,
            s.x_excess,
            s.grad_err,
            s.not_converged,
            s.max_iter,
            s.rejected,
            s.dist_not_converged,
            s.dist_err
        );
        total += s.cases;
        total_nc += s.not_converged;
        failures.extend(s.failures.iter().cloned());
        // Every class here is solvable in double precision: a non-converged status is a
        // failure (its outputs were still checked to be finite above).
        // `distance` must converge too (thin polytopes used not to:
        // `regression_distance_thin_polytopes`).
        if s.dist_not_converged > 0 && !name.starts_with("extreme") {
            failures.push(format!(
                "{name}: {} distance solves did not converge",
                s.dist_not_converged
            ));
        }
        if s.not_converged > 0 && !name.starts_with("extreme") {
            failures.push(format!(
                "{name}: {} cases did not converge",
                s.not_converged
            ));
        }
    }
    println!(
        "total {total} cases, {total_nc} not converged, {:.1} s",
        start.elapsed().as_secs_f64()
    );
    if !failures.is_empty() {
        for (name, s) in &t {
            for f in s.failures.iter().take(4) {
                println!("FAIL {f}");
            }
            if s.failures.len() > 4 {
                println!("FAIL {name}: ... {} failures in all", s.failures.len());
            }
        }
        panic!(
            "{} stress failures (printed above, at most 4 per class)",
            failures.len()
        );
    }
}

/// dcol bug found by this suite (issue 6), fixed in 70c3a92: `Pose::new` accepts any finite,
/// non-zero quaternion (and `proximity` is exact for all of them), but the quaternion columns
/// of `gradient` and `jacobian` are NaN for ‖q‖ below ~3e-103 or above ~1.3e154, and wrong
/// (the normalisation term is lost) for ‖q‖ above ~1e102. `math::rotation_derivatives` works on
/// the raw q: its term `2·s·q_k/n2 = 4 q_k/‖q‖⁴` overflows to inf for tiny q (then `K·inf` with
/// K = 0 gives NaN) and underflows to 0 for huge q, and `n2 = ‖q‖²` itself overflows above
/// 1.3e154. Minimal reproduction: a unit box at the origin with q₁ = [1e-150, 0, 0, 0], a
/// sphere at (3, 0.4, 0.2): `gradient(...)` returns status Converged, α* = 1.9775 (correct),
/// and gradient[3] = NaN. Expected: ∂α/∂q(λq) = ∂α/∂q(q)/λ for every λ > 0.
#[test]
fn regression_gradient_extreme_quaternion_norm() {
    let opts = Options::default();
    let bx = Shape::cuboid(1.0, 0.5, 0.25).unwrap();
    let ball = Shape::sphere(0.5).unwrap();
    let p2 = Pose::new([3.0, 0.4, 0.2], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let q = [0.9f64, 0.3, -0.2, 0.1];
    let qn = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let q = q.map(|v| v / qn);
    let unit = Pose::new([0.0; 3], q).unwrap();
    let (_, g0) = gradient(&bx, &unit, &ball, &p2, &opts).unwrap();
    let (_, j0) = jacobian(&bx, &unit, &ball, &p2, &opts).unwrap();
    for k in [1e-300, 1e-150, 1e-110, 1e110, 1e150, 1e160, 1e300] {
        let p1 = Pose::new([0.0; 3], q.map(|v| v * k)).unwrap();
        let (prox, g) = gradient(&bx, &p1, &ball, &p2, &opts).unwrap();
        let (_, j) = jacobian(&bx, &p1, &ball, &p2, &opts).unwrap();
        assert!(prox.status.is_converged());
        for c in 3..7 {
            assert!(
                (g[c] * k - g0[c]).abs() <= 1e-9 * (1.0 + g0[c].abs()),
                "‖q‖ = {k:e}: ∂α/∂q{} = {:e}, expected {:e}",
                c - 3,
                g[c],
                g0[c] / k
            );
            for r in 0..4 {
                assert!(
                    (j[r][c] * k - j0[r][c]).abs() <= 1e-9 * (1.0 + j0[r][c].abs()),
                    "‖q‖ = {k:e}: J[{r}][{c}] = {:e}, expected {:e}",
                    j[r][c],
                    j0[r][c] / k
                );
            }
        }
    }
    // The simplest case: a pure-w quaternion of norm 1e-150.
    let p1 = Pose::new([0.0; 3], [1e-150, 0.0, 0.0, 0.0]).unwrap();
    let (_, g) = gradient(&bx, &p1, &ball, &p2, &opts).unwrap();
    assert!(g.iter().all(|v| v.is_finite()), "gradient {g:?}");
}

/// dcol bug found by this suite (issue 6), fixed in feee3ae: a unit sphere resting in a large thin
/// slab — a box of half extents (1e6, 1e6, 1), as used for a ground plane — at (0.3, 0.2, 1.5):
/// α* = 0.75 exactly, and dcol's iterate is right to 5e-15, but the status is
/// NumericalFailure (so the C ABI returns DCOL_ERROR_NOT_CONVERGED), in both argument orders.
/// The same happens from half extents ~3e5 on, and for every height from 1e7 on; at 1e5 and
/// below it converges. Random pairs with size ratios up to 1e7 (`mixed_scale`, measured) and
/// aspect ratios up to 1e3 (`aspect`) converge, so it is the combination of a 1e6 aspect ratio
/// and the small partner that stalls the stopping test.
#[test]
fn regression_ground_slab_converges() {
    let opts = Options::default();
    let slab = Shape::cuboid(1e6, 1e6, 1.0).unwrap();
    let ball = Shape::sphere(1.0).unwrap();
    let p1 = Pose::from_position([0.0; 3]).unwrap();
    for z in [1.5, 3.0] {
        let p2 = Pose::from_position([0.3, 0.2, z]).unwrap();
        let a = proximity(&slab, &p1, &ball, &p2, &opts).unwrap();
        let b = proximity(&ball, &p2, &slab, &p1, &opts).unwrap();
        for p in [a, b] {
            assert!(
                (p.alpha - z / 2.0).abs() < 1e-12,
                "z = {z}: α* = {}",
                p.alpha
            );
            assert!(p.status.is_converged(), "z = {z}: {:?}", p.status);
        }
    }
}

/// dcol bug found by this suite (reported with issue 6), fixed: `distance` did not converge
/// for thin polytopes although `proximity` always did. Over 100 random pairs of two copies of a
/// polytope squashed to 1e-3 (1e-4) of its width, `distance` ended with NumericalFailure in 6
/// (14) cases. Minimal reproduction: the 16-facet polytope below (the box rows with z scaled
/// to ±1e-3, plus 10 random tangent planes), twice, at the poses below: α* = 1.898
/// (converged), `distance` → NumericalFailure after 19 iterations. Cause: with the points in
/// world axes the rows' 1000·n_z coefficients reached every column, and near the optimum the
/// Cholesky pivot floor (1e-14 × the largest diagonal, which grows like 1/μ) swamped the
/// genuine pivots of the distance's tangent directions; the dual residual then grew instead
/// of converging. See `regression_distance_thin_polytopes_random` for the random pairs.
#[test]
fn regression_distance_thin_polytopes() {
    let a = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1000.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1000.0],
        [1.6057732337732142, 0.3780453289026357, 454.43888935277073],
        [-0.8870285566839878, 0.42976478031911414, 779.4914789135906],
        [-0.3514151647194886, -0.2991514156946727, 206.25098628703853],
        [0.4213732220646186, -0.14899419232647398, 1137.1063107569619],
        [-1.4461776143602552, -0.2150882414303612, 473.5040783829848],
        [
            -0.4912753782532907,
            -0.18997697473742478,
            448.17642121155427,
        ],
        [0.1519296779236992, 0.7384767207779186, 639.9175587782976],
        [
            -0.3859018046735899,
            0.33730694316553766,
            -429.63035606664334,
        ],
        [0.615441001049038, 0.5636633660695896, 868.5873271242426],
        [
            0.47841161675429583,
            -0.12725807004816464,
            -289.8316817129222,
        ],
    ];
    let b = [
        0.9785254882857115,
        0.8225371602408503,
        0.8422155397878,
        1.020296878632628,
        1.1294752090089206,
        0.8770481046111892,
        1.4079286456224613,
        1.132640470442033,
        0.4372788539624632,
        1.196598033916937,
        1.5312783952651439,
        0.6350615245010223,
        0.7649055523562637,
        0.5420190012024355,
        1.119375098837384,
        0.5319164297408985,
    ];
    let s = Shape::polytope(&a, &b).unwrap();
    let p1 = Pose::new(
        [-0.8825309869914606, 1.030476015779372, -0.5348242414279838],
        [
            -0.6344320017210819,
            -0.41923826158802846,
            -0.6493752292612589,
            -0.006864898740440352,
        ],
    )
    .unwrap();
    let p2 = Pose::new(
        [0.13322015394826758, 2.3352946220839232, -1.9129749461237293],
        [
            -0.41852367174267036,
            0.8764927051246018,
            -0.15699572432606032,
            -0.1787479135478991,
        ],
    )
    .unwrap();
    let opts = Options::default();
    let prox = proximity(&s, &p1, &s, &p2, &opts).unwrap();
    assert!(prox.status.is_converged());
    let d = distance(&s, &p1, &s, &p2, &opts).unwrap();
    assert!(
        d.status.is_converged(),
        "distance: {d:?} (α* = {})",
        prox.alpha
    );
}

/// dcol bug found by this suite (issue 6), fixed in 1cd3bc7: `distance` between a 256-facet
/// polytope and a partner that overlaps it deeply (α* ≈ 0.2) hits the iteration limit (50) in
/// about 1 of 20 random cases, and the last iterate it returns is far off: distance 1.65e14
/// for shapes that overlap (exact answer 0). Reproduction: the generator of this file with
/// seed 79 (a 256-facet `random_polytope` and a cone, origins 0.18·(size₁ + size₂) apart).
#[test]
fn regression_distance_many_facets_overlap() {
    let mut rng = Rng::new(79);
    let s1 = random_polytope(&mut rng, 256);
    let s2 = random_spec(&mut rng);
    let (f, o) = (rng.log_range(0.1, 2.0), rng.point());
    let (a, b) = place(&mut rng, s1, s2, f, o);
    assert_eq!(b.spec.name(), "cone");
    let (sa, sb) = (a.spec.build(), b.spec.build());
    let (pa, pb) = (Pose::new(a.r, a.q).unwrap(), Pose::new(b.r, b.q).unwrap());
    let opts = Options::default();
    let prox = proximity(&sa, &pa, &sb, &pb, &opts).unwrap();
    assert!(prox.status.is_converged() && prox.alpha < 1.0);
    let d = distance(&sa, &pa, &sb, &pb, &opts).unwrap();
    assert!(
        d.status.is_converged(),
        "distance: {d:?} (α* = {})",
        prox.alpha
    );
    assert_eq!(d.distance, 0.0);
}

/// The random pairs of `regression_distance_thin_polytopes`: two copies of a random polytope
/// squashed to 1e-2, 1e-3 and 1e-4 of its width, 200 random poses each (origins 0.3 to 2 sizes
/// apart). Before the fix `distance` ended with NumericalFailure in 12 (1e-3) and 47 (1e-4) of
/// the 200; now every solve converges, and the distance is 0 exactly when α* < 1.
#[test]
fn regression_distance_thin_polytopes_random() {
    for eps in [1e-2, 1e-3, 1e-4] {
        let mut failed = Vec::new();
        let (mut iters, mut max_iters) = (0u32, 0u32);
        let mut rng = Rng::new(1234);
        for case in 0..200 {
            let m = 8 + rng.index(12);
            let s = match random_polytope(&mut rng, m) {
                Spec::Polytope { a, b } => Spec::Polytope {
                    a: a.iter().map(|r| [r[0], r[1], r[2] / eps]).collect(),
                    b,
                },
                _ => unreachable!(),
            };
            let s2 = s.scaled(1.0);
            let f = rng.log_range(0.3, 2.0);
            let o = rng.point();
            let (a, b) = place(&mut rng, s, s2, f, o);
            let (sa, sb) = (a.spec.build(), b.spec.build());
            let (pa, pb) = (Pose::new(a.r, a.q).unwrap(), Pose::new(b.r, b.q).unwrap());
            let opts = Options::default();
            let p = proximity(&sa, &pa, &sb, &pb, &opts).unwrap();
            let d = distance(&sa, &pa, &sb, &pb, &opts).unwrap();
            iters += d.iterations;
            max_iters = max_iters.max(d.iterations);
            let consistent = if p.alpha < 1.0 - 1e-9 {
                d.distance == 0.0
            } else if p.alpha > 1.0 + 1e-9 {
                d.distance > 0.0
            } else {
                true
            };
            if !p.status.is_converged() || !d.status.is_converged() || !consistent {
                failed.push(format!(
                    "case {case}: distance {:?} {} after {}, α* = {} ({:?})",
                    d.status, d.distance, d.iterations, p.alpha, p.status
                ));
            }
        }
        println!(
            "thickness {eps:e}: {} of 200 failed, distance iterations mean {:.1}, max {max_iters}",
            failed.len(),
            iters as f64 / 200.0
        );
        assert!(failed.is_empty(), "thickness {eps:e}: {failed:#?}");
    }
}
