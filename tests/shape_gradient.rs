//! Derivatives with respect to the shapes' own parameters (`dcol::shape_gradient`,
//! `distance_shape_gradient`, `signed_distance_shape_gradient`) against central finite
//! differences of the constructors' arguments, and the scale identity.
//!
//! ## Cases
//!
//! All 100 ordered pairs of the ten random kinds of `tests/common/random.rs` (sphere, ellipsoid,
//! box, 12-facet polytope, capsule, cylinder, cone, padded polygon, hull, padded hull) and the
//! half-space against each of them in both orders: 120 pair types. Random attitudes (raw
//! quaternions of length 0.7–1.4), regimes cycling separated (α* ∈ [1.1, 3]), near touching
//! ([0.95, 1.05]) and overlapping ([0.3, 0.9]), the offset scaled so that α* hits its target.
//! A case is reproducible from its id `<kind1>-<kind2>#<index>` and the seed (`DCOL_SEED`
//! measures a second one).
//!
//! ## Finite differences
//!
//! Parameters are made non-dimensional: a length (radius, half extent, height, `b`, `d`, a
//! hull's points, depth) is measured in its shape's bounding radius ρ (a half-space's: its
//! depth), an ellipsoid's `P` in `1/ρ²`, `A`, `C` and angles as they are. A direction `v` in
//! that space (a random unit vector, or one parameter: an ellipsoid's off-diagonal entries move
//! in symmetric pairs, as the constructor requires) gives `f(t) = α*(θ + t·v)` through the
//! constructors (`Shape::with_parameters`), and `D(h) = (f(h) − f(−h))/2h`, evaluated at solver
//! tolerance 1e-11 (dcol's derivatives at its default). As in `tests/derivatives.rs`, `D` is
//! compared only where it is well conditioned, at the first step `h ∈ {1, 10, 100, 1000}·1e-6`
//! where `D(h)` and `D(2h)` agree to 1e-7·max(1, |D|), the kink indicator
//! `|f(2h) + f(−2h) − 4f(h) − 4f(−h) + 6f(0)|/2h` is below that, and so is the evaluation
//! noise over `h`; otherwise the derivative does not exist there (the answer changes features
//! within the step: a kink) and the case is skipped and counted. Cases whose derivative dcol
//! itself reports as not exact (`Smoothed` where the contact is not unique, `Subgradient`) are
//! counted apart and compared too, reported but not held to the tolerance. The requirement is
//! `|dcol − fd| ≤ 1e-5·max(1, |fd|)`, never loosened.
//!
//! ## Scale identity
//!
//! Scaling every length of both shapes and the offset by `s` leaves α* unchanged, so
//! `Σ_k dim_k θ_k ∂α*/∂θ_k + (r₂ − r₁)·∂α*/∂r₂ = 0` (`dim_k` from `Shape::parameter_dimensions`:
//! 1 for a length, 0 for a dimensionless number, −2 for `P`), with `∂α*/∂r₂` from
//! `dcol::gradient`; the distance and signed distance are homogeneous of degree one instead:
//! `Σ_k dim_k θ_k ∂d/∂θ_k + (r₂ − r₁)·n = d`.
//!
//! Counts: `DCOL_SG_DIR` (directional FD cases per pair type, default 84: 10 080 cases),
//! `DCOL_SG_ENTRY` (entry-wise, default 4), `DCOL_SG_ID` (identity, default 84), `DCOL_SG_SMOOTH`
//! (smoothed, default 5), `DCOL_SG_DIST` (distance and signed distance, default 10),
//! `DCOL_SG_IPM` (`Method::InteriorPoint`, default 8).

#![allow(clippy::needless_range_loop)]
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod common;

use common::random::{Kind, Rng, KINDS};
use dcol::{
    distance, distance_shape_gradient, gradient, proximity, shape_gradient, signed_distance,
    signed_distance_shape_gradient, DerivativeKind, Options, Pose, Shape,
};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Required agreement with the finite difference (non-dimensional, relative to max(1, |fd|)).
const TOL: f64 = 1e-5;
/// Agreement of D(h) with D(2h), the kink indicator and the noise over h.
const FD_CONSISTENCY: f64 = 1e-7;
const H: f64 = 1e-6;
const RUNGS: [f64; 4] = [1.0, 10.0, 100.0, 1000.0];
/// The scale identity holds to the solvers' accuracy.
const IDENTITY_TOL: f64 = 1e-8;

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn seed() -> u64 {
    env_or("DCOL_SEED", 0x5EED_5A9E_0000_0034)
}

/// A random kind, or the half-space.
#[derive(Clone, Copy, Debug, PartialEq)]
enum K {
    B(Kind),
    Halfspace,
}

impl K {
    fn name(self) -> &'static str {
        match self {
            K::B(k) => k.name(),
            K::Halfspace => "halfspace",
        }
    }
    fn index(self) -> u64 {
        match self {
            K::B(k) => k.index(),
            K::Halfspace => 10,
        }
    }
    fn group(self) -> &'static str {
        match self {
            K::B(Kind::Sphere | Kind::Ellipsoid | Kind::Capsule) => "smooth",
            K::B(Kind::Cylinder | Kind::Cone) => "revolved",
            K::B(Kind::Box | Kind::Polytope | Kind::Polygon) => "faceted",
            K::B(Kind::Hull | Kind::RoundedHull) => "hull",
            K::Halfspace => "half-space",
        }
    }
}

/// The 120 pair types: every ordered pair of the ten bounded kinds, and the half-space with
/// each of them in both orders.
fn pairs() -> Vec<(K, K)> {
    let mut v = Vec::new();
    for a in KINDS {
        for b in KINDS {
            v.push((K::B(a), K::B(b)));
        }
    }
    for a in KINDS {
        v.push((K::Halfspace, K::B(a)));
        v.push((K::B(a), K::Halfspace));
    }
    v
}

/// The group of a pair type: its two kinds' groups, in a fixed order.
fn group_of(p: (K, K)) -> String {
    let (a, b) = (p.0.group(), p.1.group());
    let order = ["smooth", "revolved", "faceted", "hull", "half-space"];
    let (i, j) = (
        order.iter().position(|g| *g == a).unwrap(),
        order.iter().position(|g| *g == b).unwrap(),
    );
    if i <= j {
        format!("{a}–{b}")
    } else {
        format!("{b}–{a}")
    }
}

#[derive(Clone, Copy)]
enum Regime {
    Separated,
    Near,
    Overlapping,
}

struct Case {
    id: String,
    s: [Shape; 2],
    theta: [Vec<f64>; 2],
    /// Each parameter's unit (ρ, 1 or 1/ρ²).
    unit: [Vec<f64>; 2],
    poses: [Pose; 2],
}

fn mix(seed: u64, a: u64, b: u64, c: u64) -> u64 {
    let mut r = Rng::new(seed ^ a.wrapping_mul(0x100_0000_01B3));
    let x = r.next_u64() ^ b.wrapping_mul(0x9E37_79B9);
    let mut r = Rng::new(x);
    r.next_u64() ^ c.wrapping_mul(0xD6E8_FEB8_6659_FD93)
}

fn random_shape(k: K, rng: &mut Rng) -> Shape {
    match k {
        K::B(k) => k.random(rng),
        K::Halfspace => Shape::halfspace(rng.range(0.3, 1.5)).unwrap(),
    }
}

fn units(s: &Shape) -> Vec<f64> {
    let rho = if s.kind() == dcol::ShapeKind::Halfspace {
        s.inscribed_radius()
    } else {
        s.bounding_radius()
    };
    s.parameter_dimensions()
        .iter()
        .map(|d| rho.powf(*d))
        .collect()
}

fn rotate(q: &[f64; 4], v: [f64; 3]) -> [f64; 3] {
    let m = dcol::math::rotation_from_quaternion(*q);
    [0, 1, 2].map(|i| (0..3).map(|j| m[(i, j)] * v[j]).sum())
}

/// The same hull without its repeated points (a corner given twice has no derivative).
fn without_repeats(s: Shape) -> Shape {
    let Some((pts, radius)) = s.hull_points() else {
        return s;
    };
    let mut kept: Vec<[f64; 3]> = Vec::new();
    for p in pts {
        if !kept.contains(p) {
            kept.push(*p);
        }
    }
    Shape::convex_hull(&kept, radius).unwrap()
}

impl Case {
    fn new(p: (K, K), index: usize, regime: Option<Regime>) -> Case {
        Case::build(p, index, regime, false)
    }

    /// Case `index` of pair type `p`; `distinct`: hulls without repeated points.
    fn build(p: (K, K), index: usize, regime: Option<Regime>, distinct: bool) -> Case {
        let mut rng = Rng::new(mix(seed(), p.0.index(), p.1.index(), index as u64));
        let regime =
            regime.unwrap_or([Regime::Separated, Regime::Near, Regime::Overlapping][index % 3]);
        let mut s = [random_shape(p.0, &mut rng), random_shape(p.1, &mut rng)];
        if distinct {
            s = s.map(without_repeats);
        }
        let (q1, q2) = (rng.quat(), rng.quat());
        let r1 = [0; 3].map(|_| rng.range(-2.0, 2.0));
        let mut u = rng.unit::<3>();
        // With a half-space, the other origin clearly outside it (α* > 0).
        for (i, q) in [(0, &q1), (1, &q2)] {
            if s[i].kind() == dcol::ShapeKind::Halfspace {
                let n = rotate(q, [0.0, 0.0, 1.0]);
                let sign = if i == 0 { 1.0 } else { -1.0 };
                let g = sign * (0..3).map(|j| n[j] * u[j]).sum::<f64>();
                if g < 0.3 {
                    let t = 0.3 - g + rng.range(0.0, 0.5);
                    u = [0, 1, 2].map(|j| u[j] + sign * t * n[j]);
                    let l = u.iter().map(|c| c * c).sum::<f64>().sqrt();
                    u = u.map(|c| c / l);
                }
            }
        }
        let target = match regime {
            Regime::Separated => rng.range(1.1, 3.0),
            Regime::Near => rng.range(0.95, 1.05),
            Regime::Overlapping => rng.range(0.3, 0.9),
        };
        let p1 = Pose::new(r1, q1).unwrap();
        let p2 = Pose::new([0, 1, 2].map(|j| r1[j] + u[j]), q2).unwrap();
        let a0 = proximity(&s[0], &p1, &s[1], &p2, &Options::default())
            .unwrap()
            .alpha;
        let p2 = Pose::new([0, 1, 2].map(|j| r1[j] + u[j] * target / a0), q2).unwrap();
        Case {
            id: format!("{}-{}#{index}", p.0.name(), p.1.name()),
            theta: [s[0].parameters(), s[1].parameters()],
            unit: [units(&s[0]), units(&s[1])],
            s,
            poses: [p1, p2],
        }
    }

    fn offset(&self) -> [f64; 3] {
        let (a, b) = (self.poses[0].position(), self.poses[1].position());
        [b.x - a.x, b.y - a.y, b.z - a.z]
    }

    /// The shapes with their parameters moved by `t·v` (`v` non-dimensional, per shape; an
    /// empty `v` leaves that shape as it is).
    fn moved(&self, v: &[Vec<f64>; 2], t: f64) -> Option<[Shape; 2]> {
        let one = |i: usize| {
            if v[i].is_empty() {
                return Some(self.s[i].clone());
            }
            let p: Vec<f64> = (0..self.theta[i].len())
                .map(|k| self.theta[i][k] + t * v[i][k] * self.unit[i][k])
                .collect();
            self.s[i].with_parameters(&p).ok()
        };
        Some([one(0)?, one(1)?])
    }
}

fn fd_options() -> Options {
    Options {
        tolerance: 1e-11,
        ..Options::default()
    }
}

/// The measured quantity: α*, the distance, the signed distance.
#[derive(Clone, Copy, PartialEq)]
enum Quantity {
    Alpha,
    Distance,
    Signed,
}

fn evaluate(q: Quantity, s: &[Shape; 2], poses: &[Pose; 2], opts: &Options) -> Option<f64> {
    match q {
        Quantity::Alpha => {
            let p = proximity(&s[0], &poses[0], &s[1], &poses[1], opts).ok()?;
            p.status.is_converged().then_some(p.alpha)
        }
        Quantity::Distance => {
            let d = distance(&s[0], &poses[0], &s[1], &poses[1], opts).ok()?;
            d.status.is_converged().then_some(d.distance)
        }
        Quantity::Signed => {
            let d = signed_distance(&s[0], &poses[0], &s[1], &poses[1], opts).ok()?;
            d.status.is_converged().then_some(d.distance)
        }
    }
}

/// The evaluation noise at the case: the change under a common translation and re-scaled
/// quaternions (which leave the exact answer unchanged).
fn noise(case: &Case, q: Quantity, f0: f64, opts: &Options) -> f64 {
    let mut worst: f64 = 0.0;
    for (k1, k2, t) in [(1.1, 0.9, 1.0), (0.93, 1.07, -2.0)] {
        let shift = [0.31 * t, -0.17 * t, 0.23 * t];
        let moved = |p: &Pose, k: f64| {
            let r = p.position();
            Pose::new(
                [r.x + shift[0], r.y + shift[1], r.z + shift[2]],
                p.quaternion().map(|c| c * k),
            )
            .unwrap()
        };
        let poses = [moved(&case.poses[0], k1), moved(&case.poses[1], k2)];
        match evaluate(q, &case.s, &poses, opts) {
            Some(v) => worst = worst.max((v - f0).abs()),
            None => return f64::INFINITY,
        }
    }
    worst
}

/// Why a finite difference was not compared.
#[derive(Clone, Copy, Debug)]
enum Skip {
    /// A constructor rejected a perturbed shape, or a solve did not converge.
    Failed,
    /// No step passed the consistency, kink and noise tests: α* is not differentiable there
    /// (it changes features within the step).
    IllConditioned,
}

/// The central difference of `f` (a function of the non-dimensional step) at 0, at the first
/// well-conditioned step.
fn central(f0: f64, noise: f64, f: impl Fn(f64) -> Option<f64>) -> Result<f64, Skip> {
    let mut failed = true;
    for mult in RUNGS {
        let h = H * mult;
        let (Some(p1), Some(m1), Some(p2), Some(m2)) = (f(h), f(-h), f(2.0 * h), f(-2.0 * h))
        else {
            continue;
        };
        failed = false;
        let d1 = (p1 - m1) / (2.0 * h);
        let d2 = (p2 - m2) / (4.0 * h);
        let kink = (p2 + m2 - 4.0 * p1 - 4.0 * m1 + 6.0 * f0) / (2.0 * h);
        let bound = FD_CONSISTENCY * d1.abs().max(1.0);
        if noise / h <= bound && (d1 - d2).abs() <= bound && kink.abs() <= bound {
            return Ok(d1);
        }
    }
    Err(if failed {
        Skip::Failed
    } else {
        Skip::IllConditioned
    })
}

/// Per pair type.
#[derive(Clone, Debug, Default)]
struct Stats {
    cases: usize,
    compared: usize,
    /// Compared where dcol reported the derivative not exact (not held to the tolerance).
    compared_other: usize,
    skipped_failed: usize,
    skipped_kink: usize,
    /// Of the skipped, those dcol reported not exact (expected: no derivative there).
    skipped_other: usize,
    not_exact: usize,
    max_err: f64,
    max_err_other: f64,
    worst: String,
    failures: Vec<String>,
}

impl Stats {
    fn merge(&mut self, o: Stats) {
        self.cases += o.cases;
        self.compared += o.compared;
        self.compared_other += o.compared_other;
        self.skipped_failed += o.skipped_failed;
        self.skipped_kink += o.skipped_kink;
        self.skipped_other += o.skipped_other;
        self.not_exact += o.not_exact;
        if o.max_err > self.max_err {
            self.max_err = o.max_err;
            self.worst = o.worst;
        }
        self.max_err_other = self.max_err_other.max(o.max_err_other);
        self.failures.extend(o.failures);
    }

    fn record(&mut self, exact: bool, err: f64, tol: f64, what: impl Fn() -> String) {
        if exact {
            self.compared += 1;
            if !(err <= self.max_err) {
                self.max_err = err;
                self.worst = what();
            }
            if !(err <= tol) {
                self.failures.push(format!("{} err {err:.2e}", what()));
            }
        } else {
            self.compared_other += 1;
            self.max_err_other = self.max_err_other.max(err);
        }
    }

    fn skip(&mut self, exact: bool, why: Skip) {
        match why {
            Skip::Failed => self.skipped_failed += 1,
            Skip::IllConditioned => self.skipped_kink += 1,
        }
        if !exact {
            self.skipped_other += 1;
        }
    }
}

/// Runs `work(job, index, stats)` over every pair type and index on two threads.
fn sweep(per_pair: usize, work: impl Fn((K, K), usize, &mut Stats) + Sync) -> Vec<((K, K), Stats)> {
    let jobs = pairs();
    let total = jobs.len() * per_pair;
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Stats>> = Mutex::new(vec![Stats::default(); jobs.len()]);
    std::thread::scope(|scope| {
        for _ in 0..2 {
            scope.spawn(|| {
                let mut local = vec![Stats::default(); jobs.len()];
                loop {
                    let flat = next.fetch_add(1, Ordering::Relaxed);
                    if flat >= total {
                        break;
                    }
                    let (job, index) = (flat % jobs.len(), flat / jobs.len());
                    work(jobs[job], index, &mut local[job]);
                }
                let mut all = results.lock().unwrap();
                for (slot, v) in all.iter_mut().zip(local) {
                    slot.merge(v);
                }
            });
        }
    });
    jobs.into_iter()
        .zip(results.into_inner().unwrap())
        .collect()
}

/// Prints the per-group table and asserts that nothing failed and that most cases compared.
fn report(title: &str, results: &[((K, K), Stats)], max_skip: f64) {
    let mut groups: BTreeMap<String, Stats> = BTreeMap::new();
    let mut total = Stats::default();
    for (p, s) in results {
        groups.entry(group_of(*p)).or_default().merge(s.clone());
        total.merge(s.clone());
    }
    println!("\n### {title}\n");
    println!(
        "| group | cases | compared (exact) | max err | compared (not exact) | max err | skipped: kink | skipped: failed | of which not exact | not exact |"
    );
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    for (g, s) in groups.iter().chain([(&"all".to_string(), &total)]) {
        println!(
            "| {g} | {} | {} | {:.1e} | {} | {:.1e} | {} | {} | {} | {} |",
            s.cases,
            s.compared,
            s.max_err,
            s.compared_other,
            s.max_err_other,
            s.skipped_kink,
            s.skipped_failed,
            s.skipped_other,
            s.not_exact
        );
    }
    println!("worst: {}", total.worst);
    let shown: Vec<&String> = total.failures.iter().take(20).collect();
    assert!(
        total.failures.is_empty(),
        "{} of {} comparisons above the tolerance: {shown:#?}",
        total.failures.len(),
        total.compared
    );
    // Where dcol says the derivative exists, the finite difference must mostly confirm it.
    let skipped = total.skipped_kink + total.skipped_failed - total.skipped_other;
    let all = skipped + total.compared;
    assert!(
        (skipped as f64) <= max_skip * all as f64,
        "{skipped} of {all} cases dcol reports exact skipped"
    );
    for (p, s) in results {
        assert!(
            s.compared > 0,
            "pair {}-{}: nothing compared",
            p.0.name(),
            p.1.name()
        );
    }
}

/// Whether parameter `k` of shape `i` sits on the boundary of its domain, where only a
/// one-sided derivative exists: an unpadded hull's radius 0 (dcol returns the derivative for
/// growing it).
fn at_boundary(case: &Case, i: usize, k: usize) -> bool {
    case.s[i].kind() == dcol::ShapeKind::ConvexHull
        && k + 1 == case.theta[i].len()
        && case.theta[i][k] == 0.0
}

/// A random unit direction of both shapes' non-dimensional parameters (an ellipsoid's `P`
/// moved symmetrically).
fn random_direction(case: &Case, rng: &mut Rng) -> [Vec<f64>; 2] {
    let mut v = [0, 1].map(|i| {
        (0..case.theta[i].len())
            .map(|_| rng.gauss())
            .collect::<Vec<f64>>()
    });
    for i in 0..2 {
        if case.s[i].kind() == dcol::ShapeKind::Ellipsoid {
            for r in 0..3 {
                for c in 0..r {
                    v[i][3 * r + c] = v[i][3 * c + r];
                }
            }
        }
        if at_boundary(case, i, case.theta[i].len() - 1) {
            *v[i].last_mut().unwrap() = 0.0;
        }
    }
    let n = v.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for x in v.iter_mut().flatten() {
        *x /= n;
    }
    v
}

/// `Σ g_k v_k unit_k`: dcol's derivative along the non-dimensional direction `v`.
fn along(case: &Case, g: &[Vec<f64>; 2], v: &[Vec<f64>; 2]) -> f64 {
    (0..2)
        .map(|i| {
            (0..v[i].len())
                .map(|k| g[i][k] * v[i][k] * case.unit[i][k])
                .sum::<f64>()
        })
        .sum()
}

/// dcol's shape gradient of `q` at the case, and whether it is exact (for α*: labelled `Exact`,
/// or `Smoothed` when smoothing was asked for; the distances carry no label).
fn dcol_gradient(case: &Case, q: Quantity, opts: &Options) -> Option<([Vec<f64>; 2], bool)> {
    dcol_gradient_kind(case, q, opts).map(|(g, k)| {
        let exact =
            k == DerivativeKind::Exact || (opts.smoothing > 0.0 && k == DerivativeKind::Smoothed);
        (g, exact)
    })
}

/// dcol's shape gradient of `q` at the case and its kind (`Exact` for the distances).
fn dcol_gradient_kind(
    case: &Case,
    q: Quantity,
    opts: &Options,
) -> Option<([Vec<f64>; 2], DerivativeKind)> {
    let mut g = [
        vec![0.0; case.theta[0].len()],
        vec![0.0; case.theta[1].len()],
    ];
    let [p1, p2] = &case.poses;
    let [s1, s2] = &case.s;
    let [g1, g2] = &mut g;
    let converged = match q {
        Quantity::Alpha => {
            let p = shape_gradient(s1, p1, s2, p2, opts, Some(g1), Some(g2)).ok()?;
            return p.status.is_converged().then_some((g, p.derivatives));
        }
        Quantity::Distance => distance_shape_gradient(s1, p1, s2, p2, opts, Some(g1), Some(g2))
            .ok()?
            .status
            .is_converged(),
        Quantity::Signed => {
            signed_distance_shape_gradient(s1, p1, s2, p2, opts, Some(g1), Some(g2))
                .ok()?
                .status
                .is_converged()
        }
    };
    converged.then_some((g, DerivativeKind::Exact))
}

/// One directional comparison of quantity `q` (`opts` for both dcol and the differences, at
/// tolerance 1e-11 for the latter).
fn check_direction(case: &Case, q: Quantity, opts: &Options, rng: &mut Rng, stats: &mut Stats) {
    let fd_opts = Options {
        tolerance: fd_options().tolerance,
        ..*opts
    };
    let Some((g, exact)) = dcol_gradient(case, q, opts) else {
        stats.skip(true, Skip::Failed);
        return;
    };
    if !exact {
        stats.not_exact += 1;
    }
    let Some(f0) = evaluate(q, &case.s, &case.poses, &fd_opts) else {
        stats.skip(exact, Skip::Failed);
        return;
    };
    let v = random_direction(case, rng);
    let noise = noise(case, q, f0, &fd_opts);
    let f = |t: f64| evaluate(q, &case.moved(&v, t)?, &case.poses, &fd_opts);
    match central(f0, noise, f) {
        Ok(fd) => {
            let mine = along(case, &g, &v);
            let err = (mine - fd).abs() / fd.abs().max(1.0);
            stats.record(exact, err, TOL, || {
                format!("{} dcol {mine:.10e} fd {fd:.10e}", case.id)
            });
        }
        Err(why) => stats.skip(exact, why),
    }
}

#[test]
fn alpha_matches_finite_differences_along_random_directions() {
    let per = env_or("DCOL_SG_DIR", 84usize);
    let results = sweep(per, |p, index, stats| {
        let case = Case::new(p, index, None);
        stats.cases += 1;
        let mut rng = Rng::new(mix(
            seed(),
            77,
            p.0.index() * 11 + p.1.index(),
            index as u64,
        ));
        check_direction(&case, Quantity::Alpha, &Options::default(), &mut rng, stats);
    });
    report(
        "α*: directional central differences of the constructors' arguments",
        &results,
        0.2,
    );
}

#[test]
fn alpha_matches_finite_differences_entry_by_entry() {
    let per = env_or("DCOL_SG_ENTRY", 4usize);
    let results = sweep(per, |p, index, stats| {
        let case = Case::new(p, 1_000_000 + index, None);
        stats.cases += 1;
        let opts = Options::default();
        let Some((g, exact)) = dcol_gradient(&case, Quantity::Alpha, &opts) else {
            stats.skip(true, Skip::Failed);
            return;
        };
        if !exact {
            stats.not_exact += 1;
        }
        let fd_opts = fd_options();
        let Some(f0) = evaluate(Quantity::Alpha, &case.s, &case.poses, &fd_opts) else {
            stats.skip(exact, Skip::Failed);
            return;
        };
        let noise = noise(&case, Quantity::Alpha, f0, &fd_opts);
        for i in 0..2 {
            let ellipsoid = case.s[i].kind() == dcol::ShapeKind::Ellipsoid;
            for k in 0..case.theta[i].len() {
                let (r, c) = (k / 3, k % 3);
                if (ellipsoid && c < r) || at_boundary(&case, i, k) {
                    continue; // moved with its mirror; one-sided
                }
                let mut v = [vec![], vec![]];
                v[i] = vec![0.0; case.theta[i].len()];
                v[i][k] = 1.0;
                if ellipsoid {
                    v[i][3 * c + r] = 1.0;
                }
                let f =
                    |t: f64| evaluate(Quantity::Alpha, &case.moved(&v, t)?, &case.poses, &fd_opts);
                match central(f0, noise, f) {
                    Ok(fd) => {
                        let mut full = [vec![0.0; g[0].len()], vec![0.0; g[1].len()]];
                        full[i].clone_from(&v[i]);
                        let mine = along(&case, &g, &full);
                        let err = (mine - fd).abs() / fd.abs().max(1.0);
                        stats.record(exact, err, TOL, || {
                            format!(
                                "{} shape {} parameter {k}: dcol {mine:.10e} fd {fd:.10e}",
                                case.id,
                                i + 1
                            )
                        });
                    }
                    Err(why) => stats.skip(exact, why),
                }
            }
        }
    });
    report(
        "α*: entry-wise central differences of the constructors' arguments",
        &results,
        0.25,
    );
}

#[test]
fn interior_point_alpha_matches_finite_differences() {
    // The interior-point path's multipliers (what answers flat against flat), everywhere.
    let per = env_or("DCOL_SG_IPM", 8usize);
    let results = sweep(per, |p, index, stats| {
        let case = Case::new(p, 5_000_000 + index, None);
        stats.cases += 1;
        let opts = Options {
            method: dcol::Method::InteriorPoint,
            ..Options::default()
        };
        let mut rng = Rng::new(mix(
            seed(),
            80,
            p.0.index() * 11 + p.1.index(),
            index as u64,
        ));
        check_direction(&case, Quantity::Alpha, &opts, &mut rng, stats);
    });
    report(
        "α*, Method::InteriorPoint: directional central differences",
        &results,
        0.2,
    );
}

#[test]
fn smoothed_alpha_matches_finite_differences() {
    let per = env_or("DCOL_SG_SMOOTH", 5usize);
    let results = sweep(per, |p, index, stats| {
        // Hulls without repeated points: on the central path every facet carries weight, and
        // a corner given twice makes the smoothed α* jump (its copies part and add facets).
        let case = Case::build(p, 2_000_000 + index, None, true);
        stats.cases += 1;
        let mu = [1e-2, 1e-3][index % 2];
        let opts = Options {
            smoothing: mu,
            ..Options::default()
        };
        let mut rng = Rng::new(mix(
            seed(),
            78,
            p.0.index() * 11 + p.1.index(),
            index as u64,
        ));
        check_direction(&case, Quantity::Alpha, &opts, &mut rng, stats);
    });
    report(
        "α* smoothed (μ = 1e-2, 1e-3): directional central differences",
        &results,
        0.2,
    );
}

#[test]
fn distances_match_finite_differences() {
    let per = env_or("DCOL_SG_DIST", 10usize);
    for q in [Quantity::Distance, Quantity::Signed] {
        let results = sweep(per, |p, index, stats| {
            // The distance is differentiable where the shapes are apart.
            let regime = (q == Quantity::Distance).then_some(Regime::Separated);
            let case = Case::new(p, 3_000_000 + index, regime);
            stats.cases += 1;
            let mut rng = Rng::new(mix(
                seed(),
                79,
                p.0.index() * 11 + p.1.index(),
                index as u64,
            ));
            check_direction(&case, q, &Options::default(), &mut rng, stats);
        });
        let title = if q == Quantity::Distance {
            "distance (separated): directional central differences"
        } else {
            "signed distance: directional central differences"
        };
        report(title, &results, 0.3);
    }
}

#[test]
fn scale_identity() {
    let per = env_or("DCOL_SG_ID", 84usize);
    let worst: Mutex<[(f64, String); 3]> = Mutex::new(Default::default());
    let results = sweep(per, |p, index, stats| {
        let case = Case::new(p, 4_000_000 + index, None);
        stats.cases += 1;
        let opts = Options::default();
        let d = case.offset();
        let [s1, s2] = &case.s;
        let [p1, p2] = &case.poses;
        let weighted = |g: &[Vec<f64>; 2]| -> f64 {
            (0..2)
                .map(|i| {
                    let dims = case.s[i].parameter_dimensions();
                    (0..g[i].len())
                        .map(|k| dims[k] * case.theta[i][k] * g[i][k])
                        .sum::<f64>()
                })
                .sum()
        };
        let mut failed = false;
        let mut check = |which: usize, residual: f64, scale: f64, kind: DerivativeKind| {
            let err = residual.abs() / scale.max(1.0);
            let exact = kind != DerivativeKind::Smoothed;
            if kind != DerivativeKind::Exact {
                stats.not_exact += 1;
            }
            stats.record(exact, err, IDENTITY_TOL, || {
                format!("{} identity {which}: residual {residual:.3e}", case.id)
            });
            let mut w = worst.lock().unwrap();
            if err > w[which].0 {
                w[which] = (err, case.id.clone());
            }
        };
        // α*: Σ dim θ ∂α/∂θ + d·∂α/∂r₂ = 0.
        let (Some((g, kind)), Ok((prox, pose))) = (
            dcol_gradient_kind(&case, Quantity::Alpha, &opts),
            gradient(s1, p1, s2, p2, &opts),
        ) else {
            stats.skip(true, Skip::Failed);
            return;
        };
        let dd = (0..3).map(|j| d[j] * pose[7 + j]).sum::<f64>();
        check(0, weighted(&g) + dd, prox.alpha.abs(), kind);
        // The distance and the signed distance: Σ dim θ ∂d/∂θ + d·n = d*.
        for (which, q) in [(1, Quantity::Distance), (2, Quantity::Signed)] {
            // (A deep curved overlap can leave the signed distance's certificate open.)
            let Some((g, _)) = dcol_gradient_kind(&case, q, &opts) else {
                failed = true;
                continue;
            };
            let (value, n) = if q == Quantity::Distance {
                let r = distance(s1, p1, s2, p2, &opts).unwrap();
                (r.distance, r.normal)
            } else {
                let r = signed_distance(s1, p1, s2, p2, &opts).unwrap();
                (r.distance, r.normal)
            };
            let dn = d[0] * n.x + d[1] * n.y + d[2] * n.z;
            let finite = |s: &Shape| {
                let r = s.bounding_radius();
                if r.is_finite() {
                    r
                } else {
                    0.0
                }
            };
            let ell = finite(s1).max(finite(s2));
            let scale = if value == 0.0 { 1.0 } else { ell };
            check(
                which,
                (weighted(&g) + dn - value) / scale,
                1.0,
                DerivativeKind::Exact,
            );
        }
        if failed {
            stats.skip(true, Skip::Failed);
        }
    });
    let w = worst.into_inner().unwrap();
    println!(
        "\nscale identity, worst residuals: α* {:.1e} ({}), distance {:.1e} ({}), signed {:.1e} ({})",
        w[0].0, w[0].1, w[1].0, w[1].1, w[2].0, w[2].1
    );
    report(
        "scale identity (residual relative to max(1, α*), and to ℓ for the distances)",
        &results,
        0.01,
    );
}
