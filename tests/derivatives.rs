//! Derivatives of the proximity solution (and of the exact distance) against central finite
//! differences, plus the identities every derivative must satisfy.
//!
//! Conventions (`shared/CONVENTIONS.md`, `shared/reference/README.md`): the 14 configuration
//! parameters are `θ = (r₁, q₁, r₂, q₂)` with the quaternion columns taken with respect to the
//! raw (not normalised) components, so `J[:, q-block]·q = 0`; with MRPs, `(r₁, p₁, r₂, p₂)`.
//! Everything is compared in non-dimensional units: r-columns multiplied by ℓ (the larger
//! bounding radius), x-, contact-point and distance rows divided by ℓ, and an entry's error is
//! `|dcol − fd| / max(1, |fd|)`, required to be at most [`TOL`] = 1e-6.
//!
//! ## Finite differences
//!
//! `D(h) = (f(θ + h·v) − f(θ − h·v)) / 2h` along a direction `v`: a coordinate axis (scaled by
//! ℓ for a position) for the entry-wise tests, a random unit vector of the non-dimensional
//! parameter space for the directional tests. The base step is `h = 1e-6` (so `1e-6·ℓ` for a
//! position), and the solver runs at `tolerance = 1e-11` for these evaluations (dcol itself runs
//! at its default tolerance). An entry is compared only where it is well conditioned, at the
//! first step `h ∈ {1, 10, 100, 1000}·1e-6` for which
//! - `D(h)` and `D(2h)` agree to [`FD_CONSISTENCY`]·max(1, |D|) (this also bounds the truncation
//!   error of `D(h)` by a third of that),
//! - the kink indicator `|f(2h) + f(−2h) − 4f(h) − 4f(−h) + 6f(0)| / 2h` is below the same bound
//!   (a central difference straddling an active-set change averages two one-sided slopes), and
//! - the evaluation noise of that output, measured at θ (see [`noise_floor`]), divided by `h` is
//!   below the same bound.
//!
//! Entries failing at every step are skipped and counted, never loosened. The larger steps are
//! there because dcol's x* (unlike α*, which is exact to ~1e-15) carries rounding noise of
//! ~1e-12–1e-10·ℓ on curved contacts, so `D(1e-6)` of an x-row is noise-dominated there.
//!
//! Every random case is reproducible from its id `<kind1>-<kind2>#<index>` through
//! [`Case::new`]; failures print it. Case counts can be raised with `DCOL_FD_CASES`,
//! `DCOL_DIR_CASES`, `DCOL_ID_CASES`, `DCOL_MRP_CASES`, `DCOL_DIST_CASES`; `DCOL_FD_TOL` sets the
//! finite-difference solver tolerance. The defaults take about 23 s of CPU (two threads).

// Rows and columns are compared by index in lockstep.
#![allow(clippy::needless_range_loop)]
// `!(err <= tol)` on purpose: a NaN error must fail.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod common;

use common::random::{Kind, Rng, KINDS};
use dcol::math::quaternion_from_mrp;
use dcol::{
    derivatives, distance, distance_gradient, gradient, gradient_mrp, jacobian, jacobian_mrp,
    proximity, Options, Pose, Proximity, Shape,
};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

// ---------------------------------------------------------------------------------------------
// Tolerances (non-dimensional) and case counts.

/// Required agreement of an analytic derivative with the finite difference (and of the
/// identities that hold only to solver accuracy).
const TOL: f64 = 1e-6;
/// Largest |D(h) − D(2h)|, kink indicator and noise/h for an entry to count as well conditioned.
const FD_CONSISTENCY: f64 = 1e-7;
/// Base step, non-dimensional (`1e-6·ℓ` for positions, `1e-6` for quaternion or MRP components).
const H: f64 = 1e-6;
/// Step multipliers tried in turn until an entry is well conditioned.
const RUNGS: [f64; 4] = [1.0, 10.0, 100.0, 1000.0];
/// Identities that hold exactly in exact arithmetic for any multipliers (translation and
/// quaternion-scale invariance of the formulas): only rounding separates them from zero.
const ALGEBRAIC_TOL: f64 = 1e-9;

/// Solver options for the finite-difference evaluations.
fn fd_options() -> Options {
    Options {
        tolerance: env_or("DCOL_FD_TOL", 1e-11),
        ..Options::default()
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

const SEED: u64 = 0x5EED_DE12_1A7E_0001;

/// Cases where dcol is known to miss the 1e-6 requirement (each with an ignored `known_issue_*`
/// test until fixed, and a report in `docs/derivatives.md`). They are still run and printed,
/// but excluded from the assertions; every other case must pass. Empty: the three near-kink
/// cases listed here before (cone-polytope12#1112, polytope12-capsule#24, sphere-capsule#720)
/// were fixed by the active-set refinement in `src/query/derivatives.rs`, and their
/// `known_issue_*` tests now run as regression tests.
const KNOWN_ISSUES: &[(&str, &str)] = &[];

fn known_issue(id: &str) -> Option<&'static str> {
    KNOWN_ISSUES.iter().find(|k| k.0 == id).map(|k| k.1)
}

// ---------------------------------------------------------------------------------------------
// Random numbers (SplitMix64), shapes and pair types.

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The 55 unordered pair types (the eight primitives and the two hulls), then seven of them in
/// the other order.
fn pair_jobs() -> Vec<(Kind, Kind)> {
    let mut v = Vec::new();
    for i in 0..KINDS.len() {
        for j in i..KINDS.len() {
            v.push((KINDS[i], KINDS[j]));
        }
    }
    v.extend([
        (Kind::Box, Kind::Sphere),
        (Kind::Cone, Kind::Polytope),
        (Kind::Polygon, Kind::Capsule),
        (Kind::Cylinder, Kind::Ellipsoid),
        (Kind::Cone, Kind::Box),
        (Kind::RoundedHull, Kind::Capsule),
        (Kind::Cone, Kind::Hull),
    ]);
    v
}

fn pair_name(p: (Kind, Kind)) -> String {
    format!("{}-{}", p.0.name(), p.1.name())
}

// ---------------------------------------------------------------------------------------------
// Cases.

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Regime {
    /// α* ∈ [1.1, 3]
    Separated,
    /// α* ∈ [0.95, 1.05]
    Near,
    /// α* ∈ [0.3, 0.9]
    Overlapping,
}

/// One random configuration: `theta = (r₁, q₁, r₂, q₂)`; `mrp` holds the attitudes as MRPs
/// when the case was drawn for the MRP test (then `q = q(p)`).
struct Case {
    id: String,
    s: [Shape; 2],
    theta: [f64; 14],
    mrp: [[f64; 3]; 2],
    ell: f64,
}

fn poses(theta: &[f64; 14]) -> (Pose, Pose) {
    let p = |o: usize| {
        Pose::new(
            [theta[o], theta[o + 1], theta[o + 2]],
            [theta[o + 3], theta[o + 4], theta[o + 5], theta[o + 6]],
        )
        .expect("valid pose")
    };
    (p(0), p(7))
}

fn mix(seed: u64, a: u64, b: u64, c: u64) -> u64 {
    let mut r = Rng::new(seed ^ a.wrapping_mul(0x100_0000_01B3));
    let x = r.next_u64() ^ b.wrapping_mul(0x9E37_79B9);
    let mut r = Rng::new(x);
    r.next_u64() ^ c.wrapping_mul(0xD6E8_FEB8_6659_FD93)
}

impl Case {
    /// Case `index` of the pair `(k1, k2)` (regimes cycle separated, near, overlapping).
    fn new(k1: Kind, k2: Kind, index: usize, seed: u64) -> Case {
        let regime = [Regime::Separated, Regime::Near, Regime::Overlapping][index % 3];
        Case::build(k1, k2, index, seed, regime, false)
    }

    /// Random shapes and attitudes, then the offset r₂ − r₁ is scaled so that α* hits the
    /// regime's target (α* is homogeneous of degree one in r₂ − r₁).
    fn build(k1: Kind, k2: Kind, index: usize, seed: u64, regime: Regime, mrp: bool) -> Case {
        let mut rng = Rng::new(mix(seed, k1.index(), k2.index(), index as u64));
        let s = [k1.random(&mut rng), k2.random(&mut rng)];
        let ell = s[0].bounding_radius().max(s[1].bounding_radius());
        let (mut q1, mut q2) = (rng.quat(), rng.quat());
        let mut m = [[0.0; 3]; 2];
        if mrp {
            m = [rng.mrp(), rng.mrp()];
            q1 = quaternion_from_mrp(m[0]);
            q2 = quaternion_from_mrp(m[1]);
        }
        let r1 = [0; 3].map(|_| rng.range(-2.0, 2.0));
        let u = rng.unit::<3>();
        let target = match regime {
            Regime::Separated => rng.range(1.1, 3.0),
            Regime::Near => rng.range(0.95, 1.05),
            Regime::Overlapping => rng.range(0.3, 0.9),
        };
        let mut theta = [0.0; 14];
        theta[..3].copy_from_slice(&r1);
        theta[3..7].copy_from_slice(&q1);
        theta[10..14].copy_from_slice(&q2);
        for j in 0..3 {
            theta[7 + j] = r1[j] + u[j];
        }
        let (p1, p2) = poses(&theta);
        // The cases are placed with the interior-point solver's α (the placement is arbitrary;
        // this keeps the case set the one the suite was tuned on: a different rounding of α
        // moves the distance sweep's base points, two of which then stall its 1e-11 solves).
        let ipm = Options {
            method: dcol::Method::InteriorPoint,
            ..Options::default()
        };
        let a0 = proximity(&s[0], &p1, &s[1], &p2, &ipm)
            .expect("proximity")
            .alpha;
        for j in 0..3 {
            theta[7 + j] = r1[j] + u[j] * target / a0;
        }
        Case {
            id: format!("{}-{}#{index}", k1.name(), k2.name()),
            s,
            theta,
            mrp: m,
            ell,
        }
    }

    fn poses(&self) -> (Pose, Pose) {
        poses(&self.theta)
    }

    /// `(r₁, p₁, r₂, p₂)`.
    fn theta_mrp(&self) -> [f64; 12] {
        let mut t = [0.0; 12];
        for i in 0..2 {
            t[6 * i..6 * i + 3].copy_from_slice(&self.theta[7 * i..7 * i + 3]);
            t[6 * i + 3..6 * i + 6].copy_from_slice(&self.mrp[i]);
        }
        t
    }
}

/// `(x*, α*, p₁, p₂)` at `theta`, or `None` when the solve did not converge.
fn outputs(s: &[Shape; 2], theta: &[f64; 14], opts: &Options) -> Option<[f64; 10]> {
    let (p1, p2) = poses(theta);
    let p = proximity(&s[0], &p1, &s[1], &p2, opts).ok()?;
    p.status.is_converged().then(|| flatten(&p))
}

fn flatten(p: &Proximity) -> [f64; 10] {
    [
        p.point.x,
        p.point.y,
        p.point.z,
        p.alpha,
        p.contact1.x,
        p.contact1.y,
        p.contact1.z,
        p.contact2.x,
        p.contact2.y,
        p.contact2.z,
    ]
}

/// Row scales of `(x, α, p₁, p₂)`: lengths over ℓ.
fn prox_row_scale(ell: f64) -> [f64; 10] {
    let mut s = [1.0 / ell; 10];
    s[3] = 1.0;
    s
}

/// The world axis along which output row `r` moves under a common translation (x, p₁, p₂).
fn prox_moves(r: usize) -> Option<usize> {
    match r {
        3 => None,
        _ => Some((r - usize::from(r > 3)) % 3),
    }
}

/// Coordinate directions in parameter space, scaled to non-dimensional units (ℓ for a
/// position; `per` parameters per pose, the first three a position).
fn axes<const P: usize>(per: usize, ell: f64) -> Vec<[f64; P]> {
    (0..P)
        .map(|c| {
            let mut v = [0.0; P];
            v[c] = if c % per < 3 { ell } else { 1.0 };
            v
        })
        .collect()
}

/// Random unit directions in the non-dimensional 14-parameter space, in raw units.
fn random_directions(n: usize, ell: f64, rng: &mut Rng) -> Vec<[f64; 14]> {
    (0..n)
        .map(|_| {
            let mut v = rng.unit::<14>();
            for c in 0..14 {
                if c % 7 < 3 {
                    v[c] *= ell;
                }
            }
            v
        })
        .collect()
}

fn dot<const P: usize>(a: &[f64; P], b: &[f64; P]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

// ---------------------------------------------------------------------------------------------
// Central finite differences with the well-conditioning tests.

/// Finite differences of `R` outputs along a list of directions.
struct Fd<const R: usize> {
    /// Derivative along each direction, in output units (multiply by the row scale).
    d: Vec<[f64; R]>,
    /// Index into [`RUNGS`] of the step that passed, or `None` (the entry is skipped).
    rung: Vec<[Option<usize>; R]>,
    /// |D(h) − D(2h)| and the kink indicator at the last step tried, non-dimensional.
    spread: Vec<[f64; R]>,
    kink: Vec<[f64; R]>,
}

/// Central differences of `f` at `theta` along each of `dirs` (see the module doc for the
/// acceptance tests). `noise[r]` is the evaluation noise of output r (from [`noise_floor`]);
/// a step is not evaluated at all when no pending entry could pass its noise test there, and
/// a step where an evaluation fails to converge is passed over.
fn finite_differences<const P: usize, const R: usize>(
    theta: &[f64; P],
    f0: &[f64; R],
    noise: &[f64; R],
    row_scale: &[f64; R],
    dirs: &[[f64; P]],
    f: impl Fn(&[f64; P]) -> Option<[f64; R]>,
) -> Fd<R> {
    let n = dirs.len();
    let mut out = Fd {
        d: vec![[0.0; R]; n],
        rung: vec![[None; R]; n],
        spread: vec![[f64::INFINITY; R]; n],
        kink: vec![[f64::INFINITY; R]; n],
    };
    for (c, v) in dirs.iter().enumerate() {
        for (k, mult) in RUNGS.iter().enumerate() {
            let h = H * mult;
            let quiet = |r: usize| noise[r] * row_scale[r] / h <= FD_CONSISTENCY;
            if !(0..R).any(|r| out.rung[c][r].is_none() && quiet(r)) {
                continue;
            }
            let at = |m: f64| {
                let mut t = *theta;
                for j in 0..P {
                    t[j] += m * h * v[j];
                }
                f(&t)
            };
            let (Some(fp1), Some(fm1), Some(fp2), Some(fm2)) =
                (at(1.0), at(-1.0), at(2.0), at(-2.0))
            else {
                continue;
            };
            for r in 0..R {
                if out.rung[c][r].is_some() {
                    continue;
                }
                let sc = row_scale[r];
                let d1 = (fp1[r] - fm1[r]) / (2.0 * h);
                let d2 = (fp2[r] - fm2[r]) / (4.0 * h);
                let kink =
                    (fp2[r] + fm2[r] - 4.0 * fp1[r] - 4.0 * fm1[r] + 6.0 * f0[r]) / (2.0 * h);
                let bound = FD_CONSISTENCY * (d1 * sc).abs().max(1.0);
                out.d[c][r] = d1;
                out.spread[c][r] = ((d1 - d2) * sc).abs();
                out.kink[c][r] = (kink * sc).abs();
                if noise[r] * sc / h <= bound
                    && out.spread[c][r] <= bound
                    && out.kink[c][r] <= bound
                {
                    out.rung[c][r] = Some(k);
                }
            }
        }
    }
    out
}

/// The evaluation noise of each output at `theta` (quaternion parameters): the largest change
/// under transformations that leave the exact answer unchanged or move it in a known way —
/// both quaternions re-scaled (by factors that are not powers of two) and a common
/// translation. It measures how far the solver's rounding alone moves an output.
fn noise_floor<const R: usize>(
    theta: &[f64; 14],
    f0: &[f64; R],
    moves: impl Fn(usize) -> Option<usize>,
    f: impl Fn(&[f64; 14]) -> Option<[f64; R]>,
) -> [f64; R] {
    let mut noise = [0.0f64; R];
    let shift = [0.31, -0.17, 0.23];
    for (k1, k2, t) in [(1.1, 0.9, 1.0), (0.93, 1.07, -2.0)] {
        let mut p = *theta;
        for j in 0..4 {
            p[3 + j] *= k1;
            p[10 + j] *= k2;
        }
        for j in 0..3 {
            p[j] += t * shift[j];
            p[7 + j] += t * shift[j];
        }
        let Some(v) = f(&p) else {
            return [f64::INFINITY; R];
        };
        for r in 0..R {
            let moved = moves(r).map_or(0.0, |axis| t * shift[axis]);
            noise[r] = noise[r].max((v[r] - moved - f0[r]).abs());
        }
    }
    noise
}

/// `|a − fd| / max(1, |fd|)`, both already non-dimensional.
fn rel_error(a: f64, fd: f64) -> f64 {
    (a - fd).abs() / fd.abs().max(1.0)
}

// ---------------------------------------------------------------------------------------------
// Bookkeeping shared by the sweeps.

/// Per-pair results. Groups: 0 gradient (dα), 1 Jacobian (x, α rows), 2 contact points.
#[derive(Clone, Default)]
struct Stats {
    cases: usize,
    compared: [usize; 3],
    skipped: [usize; 3],
    max_err: [f64; 3],
    /// Compared entries by the step that passed (1, 10, 100, 1000 × 1e-6).
    rungs: [usize; 4],
    /// Largest evaluation noise: x/ℓ, α, contact/ℓ.
    noise: [f64; 3],
    /// Cases whose finite-difference base point did not converge at the FD tolerance.
    fd_unconverged: usize,
}

impl Stats {
    fn merge(&mut self, o: &Stats) {
        self.cases += o.cases;
        self.fd_unconverged += o.fd_unconverged;
        for i in 0..3 {
            self.compared[i] += o.compared[i];
            self.skipped[i] += o.skipped[i];
            self.max_err[i] = self.max_err[i].max(o.max_err[i]);
            self.noise[i] = self.noise[i].max(o.noise[i]);
        }
        for i in 0..4 {
            self.rungs[i] += o.rungs[i];
        }
    }
}

struct Failure {
    case: String,
    what: String,
    err: f64,
}

#[derive(Default)]
struct JobResult {
    stats: Stats,
    failures: Vec<Failure>,
    /// Failures of cases listed in [`KNOWN_ISSUES`] (reported, not asserted).
    known: Vec<Failure>,
}

impl JobResult {
    fn fail(&mut self, case: &str, what: String, err: f64) {
        let f = Failure {
            case: case.to_string(),
            what,
            err,
        };
        if known_issue(case).is_some() {
            self.known.push(f);
        } else {
            self.failures.push(f);
        }
    }

    /// Compares one analytic entry (non-dimensional) with `fd` entry (dir, row).
    #[allow(clippy::too_many_arguments)]
    fn compare<const R: usize>(
        &mut self,
        case: &str,
        group: usize,
        fd: &Fd<R>,
        dir: usize,
        row: usize,
        row_scale: f64,
        value: f64,
        label: impl FnOnce() -> String,
    ) {
        let Some(rung) = fd.rung[dir][row] else {
            self.stats.skipped[group] += 1;
            return;
        };
        self.stats.compared[group] += 1;
        self.stats.rungs[rung] += 1;
        let fdv = fd.d[dir][row] * row_scale;
        let err = rel_error(value, fdv);
        if known_issue(case).is_none() {
            self.stats.max_err[group] = self.stats.max_err[group].max(err);
        }
        if !(err <= TOL) {
            let what = format!(
                "{}: dcol {value:.9e}, fd {fdv:.9e} (step {}e-6, spread {:.1e}, kink {:.1e})",
                label(),
                RUNGS[rung],
                fd.spread[dir][row],
                fd.kink[dir][row]
            );
            self.fail(case, what, err);
        }
    }

    fn merge(&mut self, o: JobResult) {
        self.stats.merge(&o.stats);
        self.failures.extend(o.failures);
        self.known.extend(o.known);
    }
}

/// Per-job results that can be merged across threads.
trait Merge: Default + Send {
    fn merge(&mut self, other: Self);
}

impl Merge for JobResult {
    fn merge(&mut self, o: JobResult) {
        JobResult::merge(self, o);
    }
}

/// Runs `work(job, index, out)` for every job and index on all cores, merging per-job results.
fn parallel<T: Merge>(
    jobs: usize,
    per_job: usize,
    work: impl Fn(usize, usize, &mut T) + Sync,
) -> Vec<T> {
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(2)
        .min(8);
    let next = AtomicUsize::new(0);
    let total = jobs * per_job;
    const CHUNK: usize = 8;
    let results: Mutex<Vec<T>> = Mutex::new((0..jobs).map(|_| T::default()).collect());
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| {
                let mut local: Vec<T> = (0..jobs).map(|_| T::default()).collect();
                loop {
                    let start = next.fetch_add(CHUNK, Ordering::Relaxed);
                    if start >= total {
                        break;
                    }
                    for flat in start..(start + CHUNK).min(total) {
                        // Interleave jobs so that every thread sees every pair type.
                        let (job, index) = (flat % jobs, flat / jobs);
                        work(job, index, &mut local[job]);
                    }
                }
                let mut all = results.lock().unwrap();
                for (slot, value) in all.iter_mut().zip(local) {
                    slot.merge(value);
                }
            });
        }
    });
    results.into_inner().unwrap()
}

/// Prints the markdown table of a sweep and the failures; returns (total, failures).
fn report(
    title: &str,
    jobs: &[String],
    results: Vec<JobResult>,
    groups: &[&str],
) -> (Stats, usize) {
    println!("\n### {title}\n");
    let mut head = String::from("| pair | cases |");
    let mut rule = String::from("|---|--:|");
    for g in groups {
        head += &format!(" {g} compared | {g} skipped | max {g} err |");
        rule += "--:|--:|--:|";
    }
    println!("{head}\n{rule}");
    let mut total = Stats::default();
    let mut failures = Vec::new();
    let mut known = Vec::new();
    let line = |name: &str, s: &Stats| {
        let mut l = format!("| {name} | {} |", s.cases);
        for g in 0..groups.len() {
            l += &format!(
                " {} | {} | {:.1e} |",
                s.compared[g], s.skipped[g], s.max_err[g]
            );
        }
        println!("{l}");
    };
    for (name, r) in jobs.iter().zip(results) {
        line(name, &r.stats);
        total.merge(&r.stats);
        failures.extend(r.failures);
        known.extend(r.known);
    }
    line("**all**", &total);
    println!(
        "\nentries compared at step 1/10/100/1000 × 1e-6: {:?}; largest evaluation noise \
         (x/ℓ, α, p/ℓ): {:.1e} {:.1e} {:.1e}; cases whose FD base point did not converge: {}",
        total.rungs, total.noise[0], total.noise[1], total.noise[2], total.fd_unconverged
    );
    let show = |list: &mut Vec<Failure>, tag: &str| {
        list.sort_by(|a, b| b.err.total_cmp(&a.err));
        for f in list.iter().take(25) {
            println!("{tag} {} {} (err {:.2e})", f.case, f.what, f.err);
        }
    };
    show(&mut known, "KNOWN ISSUE");
    show(&mut failures, "FAIL");
    (total, failures.len())
}

/// Asserts no failures and that the sweep really compared: at most `max_skip` of each group's
/// entries skipped.
fn assert_sweep(total: &Stats, failures: usize, groups: usize, max_skip: f64) {
    assert_eq!(
        failures, 0,
        "{failures} entries disagree with finite differences"
    );
    assert!(
        total.fd_unconverged * 200 <= total.cases,
        "{} of {} FD base points did not converge",
        total.fd_unconverged,
        total.cases
    );
    for g in 0..groups {
        let (c, s) = (total.compared[g], total.skipped[g]);
        assert!(c > 0, "group {g}: nothing compared");
        assert!(
            s as f64 <= max_skip * (c + s) as f64,
            "group {g}: {s} of {} entries skipped",
            c + s
        );
    }
}

// ---------------------------------------------------------------------------------------------
// (a) + (d): gradient, Jacobian and contact-point Jacobians against finite differences.

/// Checks one case along `dirs` (entry-wise when `dirs` are the coordinate axes).
fn check_proximity_case(case: &Case, dirs: &[[f64; 14]], entrywise: bool, out: &mut JobResult) {
    let opts = Options::default();
    let fd_opts = fd_options();
    let (p1, p2) = case.poses();
    let [s1, s2] = &case.s;
    let ell = case.ell;
    out.stats.cases += 1;
    let d = derivatives(s1, &p1, s2, &p2, &opts).expect("derivatives");
    if !d.proximity.status.is_converged() {
        out.fail(
            &case.id,
            format!("dcol: {:?}", d.proximity.status),
            f64::INFINITY,
        );
        return;
    }
    let Some(f0) = outputs(&case.s, &case.theta, &fd_opts) else {
        out.stats.fd_unconverged += 1;
        return;
    };
    let f = |t: &[f64; 14]| outputs(&case.s, t, &fd_opts);
    let noise = noise_floor(&case.theta, &f0, prox_moves, f);
    let rs = prox_row_scale(ell);
    for r in 0..10 {
        let g = [0, 0, 0, 1, 2, 2, 2, 2, 2, 2][r];
        out.stats.noise[g] = out.stats.noise[g].max(noise[r] * rs[r]);
    }
    let fd = finite_differences(&case.theta, &f0, &noise, &rs, dirs, f);
    for (k, v) in dirs.iter().enumerate() {
        // Entry label: `m[r][c]` entry-wise, `m[r]·v` along a direction; r = None for ∇α.
        let name = |m: &str, r: Option<usize>| {
            let row = r.map_or(String::new(), |r| format!("[{r}]"));
            if entrywise {
                let c = v.iter().position(|x| *x != 0.0).unwrap();
                format!("{m}{row}[{c}]")
            } else {
                format!("{m}{row}·v")
            }
        };
        out.compare(&case.id, 0, &fd, k, 3, 1.0, dot(&d.dalpha, v), || {
            name("dalpha", None)
        });
        for r in 0..4 {
            out.compare(
                &case.id,
                1,
                &fd,
                k,
                r,
                rs[r],
                dot(&d.jacobian[r], v) * rs[r],
                || name("J", Some(r)),
            );
        }
        for r in 0..3 {
            let (a, b) = (dot(&d.dcontact1[r], v), dot(&d.dcontact2[r], v));
            out.compare(&case.id, 2, &fd, k, 4 + r, rs[4 + r], a * rs[4 + r], || {
                name("dp1", Some(r))
            });
            out.compare(&case.id, 2, &fd, k, 7 + r, rs[7 + r], b * rs[7 + r], || {
                name("dp2", Some(r))
            });
        }
    }
}

/// Entry-wise: every one of the 14 columns, all rows (α, x, contact points).
#[test]
fn fd_entrywise_all_pairs() {
    let start = Instant::now();
    let jobs = pair_jobs();
    let n = env_or("DCOL_FD_CASES", 80);
    let results = parallel(jobs.len(), n, |job, index, out: &mut JobResult| {
        let (k1, k2) = jobs[job];
        let case = Case::new(k1, k2, index, SEED);
        check_proximity_case(&case, &axes::<14>(7, case.ell), true, out);
    });
    let names: Vec<String> = jobs.iter().map(|p| pair_name(*p)).collect();
    let (total, failures) = report(
        &format!(
            "Entry-wise finite differences ({n} cases per pair, FD solver tolerance {:e})",
            fd_options().tolerance
        ),
        &names,
        results,
        &["dα", "J", "dp"],
    );
    println!("{:.1} s", start.elapsed().as_secs_f64());
    // x rows on curved contacts are noisier (see the module doc): allow up to a third skipped.
    assert_sweep(&total, failures, 3, 0.35);
    assert!(
        total.skipped[0] * 100 <= total.compared[0],
        "dα: more than 1% skipped"
    );
}

/// Directional: J·v along one random unit direction per case, on many more cases.
#[test]
fn fd_directional_all_pairs() {
    let start = Instant::now();
    let jobs = pair_jobs();
    let n = env_or("DCOL_DIR_CASES", 2500);
    let results = parallel(jobs.len(), n, |job, index, out: &mut JobResult| {
        let (k1, k2) = jobs[job];
        let case = Case::new(k1, k2, index, SEED);
        let mut rng = Rng::new(mix(SEED ^ 0xD1, k1.index(), k2.index(), index as u64));
        let dirs = random_directions(1, case.ell, &mut rng);
        check_proximity_case(&case, &dirs, false, out);
    });
    let names: Vec<String> = jobs.iter().map(|p| pair_name(*p)).collect();
    let (total, failures) = report(
        &format!("Directional finite differences ({n} cases per pair, one random direction each)"),
        &names,
        results,
        &["dα·v", "J·v", "dp·v"],
    );
    println!("{:.1} s", start.elapsed().as_secs_f64());
    assert_sweep(&total, failures, 3, 0.35);
    assert!(
        total.skipped[0] * 100 <= total.compared[0],
        "dα: more than 1% skipped"
    );
}

// ---------------------------------------------------------------------------------------------
// (b): identities.

/// The identities that compare J with the returned x* and contact points: both are taken at
/// the same point (refined on its active set next to an active-set change), so they hold to
/// about 1e-9. While x* was the polished point and J the refined one they differed by up to
/// 5e-7 there.
const POINT_CONSISTENCY_TOL: f64 = 1e-7;

/// Names of the identities checked by [`identities_all_pairs`], with their tolerance.
const IDENTITIES: [(&str, f64); 11] = [
    ("∂α/∂r₁ + ∂α/∂r₂ = 0", TOL),
    ("J[:,r₁] + J[:,r₂] = [I; 0]", ALGEBRAIC_TOL),
    ("dpᵢ[:,r₁] + dpᵢ[:,r₂] = I", ALGEBRAIC_TOL),
    ("J·q = 0, ∇α·q = 0, dpᵢ·q = 0 per block", ALGEBRAIC_TOL),
    ("∇α·m = 0 (common rotation m)", TOL),
    (
        "J·m = [ω×(x−c); 0], dpᵢ·m = ω×(pᵢ−c)",
        POINT_CONSISTENCY_TOL,
    ),
    ("∂α/∂r₂·(r₂−r₁) = α", TOL),
    ("∂x/∂r₂·(r₂−r₁) = x − r₁", POINT_CONSISTENCY_TOL),
    ("∇α (Lagrangian) = J[3,:] (implicit function)", TOL),
    ("swap: ∇α(b,a) = ∇α(a,b) permuted", TOL),
    ("swap: J(b,a) = J(a,b) permuted", TOL),
];

#[derive(Default)]
struct IdResult {
    cases: usize,
    max: [f64; IDENTITIES.len()],
    api_mismatch: usize,
    failures: Vec<Failure>,
    known: Vec<Failure>,
}

impl Merge for IdResult {
    fn merge(&mut self, o: IdResult) {
        self.cases += o.cases;
        self.api_mismatch += o.api_mismatch;
        for i in 0..self.max.len() {
            self.max[i] = self.max[i].max(o.max[i]);
        }
        self.failures.extend(o.failures);
        self.known.extend(o.known);
    }
}

impl IdResult {
    fn record(&mut self, case: &str, which: usize, err: f64, detail: impl FnOnce() -> String) {
        let known = known_issue(case).is_some();
        if !known {
            self.max[which] = self.max[which].max(err);
        }
        if !(err <= IDENTITIES[which].1) {
            let f = Failure {
                case: case.to_string(),
                what: format!("{}: {}", IDENTITIES[which].0, detail()),
                err,
            };
            if known {
                self.known.push(f);
            } else {
                self.failures.push(f);
            }
        }
    }
}

/// `½ (0, ω) ⊗ q`: the rate of a quaternion under a world-frame angular velocity ω.
fn quaternion_rate(omega: &[f64; 3], q: &[f64]) -> [f64; 4] {
    let v = [q[1], q[2], q[3]];
    let c = cross(omega, &v);
    [
        -0.5 * (omega[0] * v[0] + omega[1] * v[1] + omega[2] * v[2]),
        0.5 * (q[0] * omega[0] + c[0]),
        0.5 * (q[0] * omega[1] + c[1]),
        0.5 * (q[0] * omega[2] + c[2]),
    ]
}

/// Swaps the two pose blocks of a 14-vector.
fn swap_blocks(v: &[f64; 14]) -> [f64; 14] {
    let mut o = [0.0; 14];
    o[..7].copy_from_slice(&v[7..]);
    o[7..].copy_from_slice(&v[..7]);
    o
}

fn check_identities(case: &Case, index: usize, out: &mut IdResult) {
    let opts = Options::default();
    let (p1, p2) = case.poses();
    let [s1, s2] = &case.s;
    let ell = case.ell;
    let id = case.id.as_str();
    out.cases += 1;
    let d = derivatives(s1, &p1, s2, &p2, &opts).expect("derivatives");
    assert!(
        d.proximity.status.is_converged(),
        "{id}: {:?}",
        d.proximity.status
    );
    let (g, j, alpha) = (&d.dalpha, &d.jacobian, d.proximity.alpha);
    let x = [
        d.proximity.point.x,
        d.proximity.point.y,
        d.proximity.point.z,
    ];
    let t = &case.theta;
    let cs = |c: usize| if c % 7 < 3 { ell } else { 1.0 };
    let dps = [&d.dcontact1, &d.dcontact2];
    let pts = [d.proximity.contact1, d.proximity.contact2];

    // Common translation.
    let mut e: f64 = 0.0;
    for a in 0..3 {
        e = e.max((g[a] + g[7 + a]).abs() * ell);
    }
    out.record(id, 0, e, || format!("{:?}", g));
    let mut e: f64 = 0.0;
    for r in 0..4 {
        for a in 0..3 {
            let want = if r == a { 1.0 } else { 0.0 };
            let k = if r < 3 { 1.0 } else { ell };
            e = e.max((j[r][a] + j[r][7 + a] - want).abs() * k);
        }
    }
    out.record(id, 1, e, || format!("{:?}", j));
    let mut e: f64 = 0.0;
    for dp in dps {
        for r in 0..3 {
            for a in 0..3 {
                let want = if r == a { 1.0 } else { 0.0 };
                e = e.max((dp[r][a] + dp[r][7 + a] - want).abs());
            }
        }
    }
    out.record(id, 2, e, String::new);

    // Quaternion normalisation: every row's q-block is orthogonal to q.
    let mut e: f64 = 0.0;
    for b in 0..2 {
        let q = &t[7 * b + 3..7 * b + 7];
        let qdot = |row: &[f64; 14]| (0..4).map(|k| row[7 * b + 3 + k] * q[k]).sum::<f64>();
        let mag = |row: &[f64; 14]| {
            (0..4)
                .map(|k| (row[7 * b + 3 + k] * q[k]).abs())
                .sum::<f64>()
        };
        let mut rel =
            |row: &[f64; 14], k: f64| e = e.max((qdot(row) * k).abs() / (mag(row) * k).max(1.0));
        rel(g, 1.0);
        for r in 0..4 {
            rel(&j[r], if r < 3 { 1.0 / ell } else { 1.0 });
        }
        for dp in dps {
            for r in 0..3 {
                rel(&dp[r], 1.0 / ell);
            }
        }
    }
    out.record(id, 3, e, String::new);

    // A common infinitesimal rotation ω about a point c: α is unchanged, x and the contact
    // points rotate with the bodies.
    let mut rng = Rng::new(mix(SEED ^ 0x1D, 0, 0, index as u64));
    let omega = rng.unit::<3>();
    let off = rng.unit::<3>();
    let rad = rng.range(0.0, 2.0) * ell;
    let c = [0, 1, 2].map(|a| t[a] + rad * off[a]);
    let mut m = [0.0; 14];
    for b in 0..2 {
        let rel = [0, 1, 2].map(|a| t[7 * b + a] - c[a]);
        m[7 * b..7 * b + 3].copy_from_slice(&cross(&omega, &rel));
        m[7 * b + 3..7 * b + 7].copy_from_slice(&quaternion_rate(&omega, &t[7 * b + 3..7 * b + 7]));
    }
    let mag = |row: &[f64; 14]| (0..14).map(|k| (row[k] * m[k]).abs()).sum::<f64>();
    out.record(id, 4, dot(g, &m).abs() / mag(g).max(1.0), || {
        format!("∇α·m = {:e}", dot(g, &m))
    });
    let mut e: f64 = 0.0;
    let xr = cross(&omega, &[0, 1, 2].map(|a| x[a] - c[a]));
    for r in 0..3 {
        e = e.max((dot(&j[r], &m) - xr[r]).abs() / ell / (mag(&j[r]) / ell).max(1.0));
    }
    e = e.max(dot(&j[3], &m).abs() / mag(&j[3]).max(1.0));
    for (dp, p) in dps.iter().zip(pts) {
        let pr = cross(&omega, &[p.x - c[0], p.y - c[1], p.z - c[2]]);
        for r in 0..3 {
            e = e.max((dot(&dp[r], &m) - pr[r]).abs() / ell / (mag(&dp[r]) / ell).max(1.0));
        }
    }
    out.record(id, 5, e, String::new);

    // Homogeneity: α and x − r₁ are of degree one in r₂ − r₁ (r₁ and the attitudes fixed).
    let delta = [0, 1, 2].map(|a| t[7 + a] - t[a]);
    let lin = |row: &[f64; 14]| (0..3).map(|a| row[7 + a] * delta[a]).sum::<f64>();
    let linmag = |row: &[f64; 14]| (0..3).map(|a| (row[7 + a] * delta[a]).abs()).sum::<f64>();
    out.record(id, 6, (lin(g) - alpha).abs() / linmag(g).max(1.0), || {
        format!("{} vs α {alpha}", lin(g))
    });
    let mut e: f64 = 0.0;
    for r in 0..3 {
        e = e.max((lin(&j[r]) - (x[r] - t[r])).abs() / ell / (linmag(&j[r]) / ell).max(1.0));
    }
    out.record(id, 7, e, String::new);

    // The two routes to ∂α: Lagrangian with polished multipliers, and the Jacobian's α row.
    let mut e: f64 = 0.0;
    let mut worst = 0;
    for c in 0..14 {
        let err = rel_error(g[c] * cs(c), j[3][c] * cs(c));
        if err > e {
            e = err;
            worst = c;
        }
    }
    out.record(id, 8, e, || {
        format!(
            "column {worst}: ∇α {:.9e}, J[3] {:.9e}",
            g[worst], j[3][worst]
        )
    });

    // Swapping the shapes permutes the columns.
    let ds = derivatives(s2, &p2, s1, &p1, &opts).expect("derivatives");
    let gs = swap_blocks(&ds.dalpha);
    let mut e: f64 = 0.0;
    for c in 0..14 {
        e = e.max(rel_error(gs[c] * cs(c), g[c] * cs(c)));
    }
    out.record(id, 9, e, String::new);
    let mut e: f64 = 0.0;
    for r in 0..4 {
        let js = swap_blocks(&ds.jacobian[r]);
        let k = if r < 3 { 1.0 / ell } else { 1.0 };
        for c in 0..14 {
            e = e.max(rel_error(js[c] * cs(c) * k, j[r][c] * cs(c) * k));
        }
    }
    out.record(id, 10, e, String::new);

    // jacobian() returns exactly what derivatives() does (one interior-point solve); gradient()
    // runs the geometric path (the envelope theorem at the polished normal) and agrees with
    // derivatives().dalpha to the two solvers' accuracy.
    if index % 8 == 0 {
        let (_, g1) = gradient(s1, &p1, s2, &p2, &opts).expect("gradient");
        let (_, j1) = jacobian(s1, &p1, s2, &p2, &opts).expect("jacobian");
        let scale = d.dalpha.iter().fold(1.0, |m: f64, v| m.max(v.abs()));
        let gerr = g1
            .iter()
            .zip(&d.dalpha)
            .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()))
            / scale;
        if j1 != d.jacobian || gerr > 1e-6 {
            out.api_mismatch += 1;
        }
    }
}

/// (b) Identities on many cases per pair type (one derivatives() call each, plus the swapped
/// pair).
#[test]
fn identities_all_pairs() {
    let start = Instant::now();
    let jobs = pair_jobs();
    let n = env_or("DCOL_ID_CASES", 2000);
    let results: Vec<IdResult> = parallel(jobs.len(), n, |job, index, out: &mut IdResult| {
        let (k1, k2) = jobs[job];
        check_identities(&Case::new(k1, k2, index, SEED), index, out);
    });
    println!("\n### Identities ({n} cases per pair; largest violation, non-dimensional)\n");
    let mut head = String::from("| pair | cases |");
    let mut rule = String::from("|---|--:|");
    for (i, _) in IDENTITIES.iter().enumerate() {
        head += &format!(" ({}) |", i + 1);
        rule += "--:|";
    }
    println!("{head}\n{rule}");
    let mut total = IdResult::default();
    for (p, r) in jobs.iter().zip(results) {
        let mut l = format!("| {} | {} |", pair_name(*p), r.cases);
        for v in r.max {
            l += &format!(" {v:.0e} |");
        }
        println!("{l}");
        total.merge(r);
    }
    let mut l = format!("| **all** | {} |", total.cases);
    for v in total.max {
        l += &format!(" {v:.0e} |");
    }
    println!("{l}\n");
    for (i, (name, tol)) in IDENTITIES.iter().enumerate() {
        println!("({}) {name}: tolerance {tol:e}", i + 1);
    }
    for f in total.known.iter().take(20) {
        println!("KNOWN ISSUE {} {} (err {:.2e})", f.case, f.what, f.err);
    }
    total.failures.sort_by(|a, b| b.err.total_cmp(&a.err));
    for f in total.failures.iter().take(25) {
        println!("FAIL {} {} (err {:.2e})", f.case, f.what, f.err);
    }
    println!("{:.1} s", start.elapsed().as_secs_f64());
    assert_eq!(
        total.api_mismatch, 0,
        "gradient()/jacobian() differ from derivatives()"
    );
    assert!(
        total.failures.is_empty(),
        "{} identity violations",
        total.failures.len()
    );
}

// ---------------------------------------------------------------------------------------------
// (c): MRP derivatives.

/// `(x*, α*)` at MRP parameters `(r₁, p₁, r₂, p₂)`.
fn outputs_mrp(s: &[Shape; 2], t: &[f64; 12], opts: &Options) -> Option<[f64; 4]> {
    let p1 = Pose::from_mrp([t[0], t[1], t[2]], [t[3], t[4], t[5]]).ok()?;
    let p2 = Pose::from_mrp([t[6], t[7], t[8]], [t[9], t[10], t[11]]).ok()?;
    let p = proximity(&s[0], &p1, &s[1], &p2, opts).ok()?;
    p.status
        .is_converged()
        .then_some([p.point.x, p.point.y, p.point.z, p.alpha])
}

fn first4(v: Option<[f64; 10]>) -> Option<[f64; 4]> {
    v.map(|o| [o[0], o[1], o[2], o[3]])
}

/// gradient_mrp and jacobian_mrp against central differences in the MRP parameters.
#[test]
fn mrp_matches_finite_differences() {
    let start = Instant::now();
    let jobs = pair_jobs();
    let n = env_or("DCOL_MRP_CASES", 24);
    let fd_opts = fd_options();
    let results: Vec<JobResult> = parallel(jobs.len(), n, |job, index, out: &mut JobResult| {
        let (k1, k2) = jobs[job];
        let regime = [Regime::Separated, Regime::Near, Regime::Overlapping][index % 3];
        let case = Case::build(k1, k2, index, SEED ^ 0x3A9, regime, true);
        let ell = case.ell;
        let tm = case.theta_mrp();
        let (r1, r2) = ([tm[0], tm[1], tm[2]], [tm[6], tm[7], tm[8]]);
        let (m1, m2) = (case.mrp[0], case.mrp[1]);
        let [s1, s2] = &case.s;
        let opts = Options::default();
        out.stats.cases += 1;
        let (pg, g) = gradient_mrp(s1, r1, m1, s2, r2, m2, &opts).expect("gradient_mrp");
        let (pj, j) = jacobian_mrp(s1, r1, m1, s2, r2, m2, &opts).expect("jacobian_mrp");
        let (p1, p2) = case.poses();
        // The quaternion query with the same options: the MRP variants must give its α exactly.
        let direct = gradient(s1, &p1, s2, &p2, &opts).expect("gradient").0;
        // gradient_mrp is gradient() on the converted pose (the geometric path), jacobian_mrp
        // the interior-point path: the same α to the solvers' accuracy.
        let close = |a: f64| (a - direct.alpha).abs() <= 1e-10 * direct.alpha.max(1.0);
        if !(pg.status.is_converged() && pg.alpha == direct.alpha && close(pj.alpha)) {
            out.fail(
                &case.id,
                "MRP query differs from the quaternion one".into(),
                f64::INFINITY,
            );
            return;
        }
        let Some(f0) = outputs_mrp(&case.s, &tm, &fd_opts) else {
            out.stats.fd_unconverged += 1;
            return;
        };
        let noise = noise_floor(&case.theta, &f0, prox_moves, |t| {
            first4(outputs(&case.s, t, &fd_opts))
        });
        let rs = [1.0 / ell, 1.0 / ell, 1.0 / ell, 1.0];
        for r in 0..4 {
            let g = usize::from(r == 3);
            out.stats.noise[g] = out.stats.noise[g].max(noise[r] * rs[r]);
        }
        let dirs = axes::<12>(6, ell);
        let fd = finite_differences(&tm, &f0, &noise, &rs, &dirs, |t| {
            outputs_mrp(&case.s, t, &fd_opts)
        });
        for (c, v) in dirs.iter().enumerate() {
            out.compare(&case.id, 0, &fd, c, 3, 1.0, dot(&g, v), || {
                format!("dalpha_mrp[{c}]")
            });
            for r in 0..4 {
                out.compare(&case.id, 1, &fd, c, r, rs[r], dot(&j[r], v) * rs[r], || {
                    format!("J_mrp[{r}][{c}]")
                });
            }
        }
    });
    let names: Vec<String> = jobs.iter().map(|p| pair_name(*p)).collect();
    let (total, failures) = report(
        &format!("MRP: gradient_mrp and jacobian_mrp ({n} cases per pair, entry-wise)"),
        &names,
        results,
        &["dα", "J"],
    );
    println!("{:.1} s", start.elapsed().as_secs_f64());
    assert_sweep(&total, failures, 2, 0.35);
}

// ---------------------------------------------------------------------------------------------
// (e): distance gradient.

fn outputs_distance(s: &[Shape; 2], t: &[f64; 14], opts: &Options) -> Option<[f64; 1]> {
    let (p1, p2) = poses(t);
    let d = distance(&s[0], &p1, &s[1], &p2, opts).ok()?;
    d.status.is_converged().then_some([d.distance])
}

/// distance_gradient against central differences of the distance on separated cases.
#[test]
fn distance_gradient_matches_finite_differences() {
    let start = Instant::now();
    let jobs: Vec<(Kind, Kind)> = pair_jobs().into_iter().take(55).collect();
    let n = env_or("DCOL_DIST_CASES", 8);
    let fd_opts = fd_options();
    let results: Vec<JobResult> = parallel(jobs.len(), n, |job, index, out: &mut JobResult| {
        let (k1, k2) = jobs[job];
        let case = Case::build(k1, k2, index, SEED ^ 0xD15, Regime::Separated, false);
        let ell = case.ell;
        let (p1, p2) = case.poses();
        let [s1, s2] = &case.s;
        let opts = Options::default();
        out.stats.cases += 1;
        let (dist, g) = distance_gradient(s1, &p1, s2, &p2, &opts).expect("distance_gradient");
        let plain = distance(s1, &p1, s2, &p2, &opts).expect("distance");
        if !(dist.status.is_converged() && dist.distance > 0.0 && dist.distance == plain.distance) {
            out.fail(
                &case.id,
                format!("distance {:?} vs {:?}", dist, plain),
                f64::INFINITY,
            );
            return;
        }
        let Some(f0) = outputs_distance(&case.s, &case.theta, &fd_opts) else {
            out.stats.fd_unconverged += 1;
            return;
        };
        let f = |t: &[f64; 14]| outputs_distance(&case.s, t, &fd_opts);
        let noise = noise_floor(&case.theta, &f0, |_| None, f);
        out.stats.noise[0] = out.stats.noise[0].max(noise[0] / ell);
        let rs = [1.0 / ell];
        let dirs = axes::<14>(7, ell);
        let fd = finite_differences(&case.theta, &f0, &noise, &rs, &dirs, f);
        for (c, v) in dirs.iter().enumerate() {
            out.compare(&case.id, 0, &fd, c, 0, rs[0], dot(&g, v) * rs[0], || {
                format!("dd[{c}]")
            });
        }
    });
    let names: Vec<String> = jobs.iter().map(|p| pair_name(*p)).collect();
    let (total, failures) = report(
        &format!("distance_gradient ({n} separated cases per pair, entry-wise; noise column: d/ℓ)"),
        &names,
        results,
        &["∂d"],
    );
    println!("{:.1} s", start.elapsed().as_secs_f64());
    assert_sweep(&total, failures, 1, 0.05);
}

// ---------------------------------------------------------------------------------------------
// Former known issues (near-kink cases), now regression tests: minimal reproductions.

/// ∂α*/∂θ_c by a central difference at a tight solver tolerance (step 1e-6, ×ℓ for a
/// position); well conditioned at the points below (it agrees with steps 1e-7..1e-5 and with
/// solver tolerances 1e-10..1e-12 to 1e-8 or better).
fn fd_alpha(s: &[Shape; 2], theta: &[f64; 14], c: usize, ell: f64) -> f64 {
    let h = if c % 7 < 3 { 1e-6 * ell } else { 1e-6 };
    let opts = fd_options();
    let (mut tp, mut tm) = (*theta, *theta);
    tp[c] += h;
    tm[c] -= h;
    let a = |t: &[f64; 14]| outputs(s, t, &opts).expect("converged")[3];
    (a(&tp) - a(&tm)) / (tp[c] - tm[c])
}

/// Checks ∇α and J[3,:] of dcol at the default tolerance against [`fd_alpha`].
fn assert_alpha_derivatives(s: [Shape; 2], theta: [f64; 14]) {
    let ell = s[0].bounding_radius().max(s[1].bounding_radius());
    let (p1, p2) = poses(&theta);
    let d = derivatives(&s[0], &p1, &s[1], &p2, &Options::default()).unwrap();
    assert!(d.proximity.status.is_converged());
    let mut worst = (0.0f64, String::new());
    for c in 0..14 {
        let k = if c % 7 < 3 { ell } else { 1.0 };
        let fd = fd_alpha(&s, &theta, c, ell) * k;
        for (what, v) in [("dalpha", d.dalpha[c]), ("J[3]", d.jacobian[3][c])] {
            let err = rel_error(v * k, fd);
            if err > worst.0 {
                worst = (
                    err,
                    format!("{what}[{c}]: dcol {:.9e}, fd {:.9e}", v * k, fd),
                );
            }
        }
    }
    assert!(worst.0 <= TOL, "{} (err {:.2e})", worst.1, worst.0);
}

/// cone–polytope12#1112 (α* = 0.365): the cone's lateral surface touches a polytope edge whose
/// second facet is only weakly active (multiplier 6.4e-6). At the default tolerance that
/// facet's interior-iterate slack is still 1.3e-5 > its multiplier, so the active set used to
/// be read off the interior iterate with that facet inactive; the remaining system (a facet
/// plane tangent to the cone along a generator) is singular, its Jacobian (~1e9) was rejected
/// by the identity checks and the barrier-smoothed fallback was 6.4e-6 off. Fixed: the active
/// set is read off the polished point, where the facet's slack is 3e-10.
#[test]
fn known_issue_jacobian_weakly_active_facet() {
    let s = [
        Shape::cone(1.040323879081226, 0.7656787297155261).unwrap(),
        Shape::polytope(
            &[
                [0.05114643034675914, 1.0544784376399123, 1.5216769030925577],
                [0.941528764295183, 1.548271476707662, -0.05192118792614729],
                [1.6689790398523465, 0.06714399995309184, 0.8946848120121652],
                [
                    -0.048884117497756396,
                    1.0033031416724536,
                    -1.6139265870484483,
                ],
                [1.1220722049680407, -1.6154289085526312, 0.10371259942429809],
                [-1.486151826689736, 0.08564867058844988, 1.0372501019804685],
                [
                    -0.11389787797920346,
                    -0.9940910529621709,
                    1.7112329705258937,
                ],
                [-1.1193735337010253, 1.6389509682735914, 0.0366527951818052],
                [
                    1.7620175334749506,
                    -0.021507477635812206,
                    -1.1009260445777191,
                ],
                [
                    -0.0817679226784936,
                    -0.9021916489793486,
                    -1.7305673903868901,
                ],
                [-1.1165287447304795, -1.4808016263258252, -0.086015092518804],
                [
                    -1.703854946203231,
                    -0.046474421174660344,
                    -0.8651937955226049,
                ],
            ],
            &[
                0.8603975126186685,
                0.9493476116733475,
                0.7682315655028205,
                0.6557787790714749,
                0.635185171870744,
                0.9986027470921168,
                0.847420243694833,
                0.6283664557481445,
                1.0510193530716845,
                0.5403599089700495,
                0.5523140126149638,
                0.6273807318514141,
            ],
        )
        .unwrap(),
    ];
    assert_alpha_derivatives(
        s,
        [
            1.4805286853822848,
            0.05542538436240818,
            -0.33896837584557993,
            -0.017905337595789012,
            0.3005930751563378,
            -0.8946926956137246,
            -0.3652670611884478,
            1.591229391488909,
            0.20742483860497798,
            -0.6256090580766847,
            0.625593654503965,
            -0.13565816566238414,
            0.9887251826080246,
            -0.08618325897161284,
        ],
    );
}

/// polytope12–capsule#24 (α* = 2.73): a polytope edge against the capsule's side, with a third
/// facet 1.5e-4 from active (an active-set change ~1e-5 away in q₂). At the default tolerance
/// the polish left that inactive facet a multiplier of 8e-8, which pulled the polished point
/// and the cone's multiplier ~1e-6 off, so ∇α from the Lagrangian was off by 1.3e-6
/// (∂α/∂q₂,w: 0.97352624 vs 0.97352752). Fixed by refining the point on the active set.
#[test]
fn known_issue_gradient_near_kink() {
    let s = [
        Shape::polytope(
            &[
                [0.03656035658469162, 1.1387621619394948, 1.7025431626534615],
                [1.0110006061305332, 1.7529268759129362, 0.11527811267802376],
                [
                    1.5003496085854389,
                    -0.008404590634075088,
                    1.0636544127283618,
                ],
                [
                    0.022627262139310877,
                    1.1008938402256538,
                    -1.7384161682749881,
                ],
                [
                    1.1182847080476608,
                    -1.5068949587414961,
                    -0.13580687102316952,
                ],
                [
                    -1.745510371224497,
                    -0.040796271977076734,
                    0.8687966094678095,
                ],
                [-0.1388625644831699, -1.1297952577076917, 1.5150491398574073],
                [-1.0207301614310933, 1.645224894845636, -0.09501757423892371],
                [
                    1.5353843344651237,
                    -0.032752436957456624,
                    -0.8773663176606288,
                ],
                [
                    -0.017182543439596215,
                    -1.0628405688779154,
                    -1.7658875302128345,
                ],
                [
                    -0.9361158370967197,
                    -1.6066482411881602,
                    -0.014699097400406508,
                ],
                [
                    -1.5267180013081652,
                    0.07996263608200202,
                    -0.9592962951204093,
                ],
            ],
            &[
                0.5322419295309859,
                0.6642553046784534,
                0.5800671800121404,
                0.8708414453268268,
                0.7335092988657154,
                1.0698173269027342,
                0.6120880618183245,
                0.9548681303636437,
                0.9400457986869318,
                1.185831425891513,
                0.7058945296285084,
                0.6642652272521337,
            ],
        )
        .unwrap(),
        Shape::capsule(0.47896345861415784, 1.2455591867091194).unwrap(),
    ];
    assert_alpha_derivatives(
        s,
        [
            0.46497656881463767,
            -1.270536819934919,
            -0.48969777745476284,
            -0.5048441791390742,
            0.06901064577014995,
            -0.5446581018041267,
            0.014836762293761015,
            0.7791703273942094,
            -2.656567297047112,
            -2.5423065325854344,
            0.37994016044513074,
            0.4171268818120216,
            1.0644013238635819,
            0.006693125105118782,
        ],
    );
}

/// sphere–capsule#720 (α* = 2.97): the contact sits on the capsule's end cap next to the
/// cylinder junction; the segment-end row is active with a tiny multiplier (2.3e-5). At the
/// default tolerance its slack is 1e-5 at the last iterate and still 6e-7 after the polish, so
/// the point was off along the surface and ∇α and J[3,:] were both off by up to 5e-7 per entry
/// (1.6e-6 along a random direction, where the directional sweep found it). Fixed by refining
/// the point on the active set.
#[test]
fn known_issue_derivatives_weakly_active_row() {
    let s = [
        Shape::sphere(0.4138696767731502).unwrap(),
        Shape::capsule(0.5519281066631796, 1.3364692088875985).unwrap(),
    ];
    let theta = [
        0.9064141850716894,
        0.004322838983236821,
        0.28035302872296786,
        -0.1696027467513728,
        -1.0225907925180207,
        -0.2764781437715965,
        -0.08282338402389625,
        -0.8038516454990003,
        -1.9826084956547076,
        -2.027062831094123,
        -0.7029704748804794,
        -0.6584295666652271,
        -0.8288716340464038,
        0.5457115053407556,
    ];
    // The entry-wise errors are 4e-7..6e-7; the directional sweep's failing combination:
    let v = [
        -0.21622948097419034,
        -0.28940209399235367,
        -0.7352967728943162,
        0.043555345136705975,
        -0.24971968627351324,
        0.30890272923564277,
        -0.12574878093737013,
        -0.01860495034776041,
        0.12377306504269756,
        0.2484608955720733,
        -0.0002876726332974132,
        -0.06196244959064814,
        0.2783017784505618,
        -0.4903232799217505,
    ];
    let (p1, p2) = poses(&theta);
    let d = derivatives(&s[0], &p1, &s[1], &p2, &Options::default()).unwrap();
    let opts = fd_options();
    let at = |m: f64| {
        let t: [f64; 14] = std::array::from_fn(|j| theta[j] + m * 1e-6 * v[j]);
        outputs(&s, &t, &opts).expect("converged")[3]
    };
    let fd = (at(1.0) - at(-1.0)) / 2e-6;
    for (what, row) in [("dalpha", &d.dalpha), ("J[3]", &d.jacobian[3])] {
        let err = rel_error(dot(row, &v), fd);
        assert!(
            err <= TOL,
            "{what}·v: dcol {:.9e}, fd {fd:.9e} (err {err:.2e})",
            dot(row, &v)
        );
    }
    assert_alpha_derivatives(s, theta);
}
