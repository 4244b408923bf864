//! Timing of the queries over all 36 unordered pairs of the eight kinds (sphere, ellipsoid,
//! box, 12-facet polytope, capsule, cylinder, cone, padded polygon), on fixed-seed random
//! poses: one third separated (α* ∈ [1.2, 3]), one third near touching (α* ∈ [0.98, 1.02]),
//! one third overlapping (α* ∈ [0.2, 0.8]).
//!
//! Poses hit their target α* exactly: attitudes and a direction are drawn at random, the pair
//! is solved once at a trial offset, and the offset `r₂ − r₁` is rescaled by `target/α*`
//! (α* is homogeneous of degree one in `r₂ − r₁` when the attitudes are fixed); a second solve
//! checks that the target was hit.
//!
//! Output, in this order:
//! 1. a table per query method: median ns per query for each pair (overall and per class),
//!    mean and max interior-point iterations, then the all-pairs median; the methods are
//!    interleaved pose by pose, and each timing is the mean of `DCOL_BENCH_REPS` back-to-back
//!    calls on one pose;
//! 2. criterion benchmarks `<method>/all-pairs` (cycling through every pair and pose), and,
//!    with `DCOL_BENCH_PAIRS=1`, `<method>/<pair>` for each pair.
//!
//! Usage:
//! - `cargo bench --bench proximity`: 2000 poses per pair;
//! - `cargo bench --bench proximity -- --quick`: 200 poses per pair, criterion's quick mode;
//! - `cargo bench --bench proximity -- --test` (and `cargo test --benches`): a smoke run
//!   (3 poses per pair, every benchmark once) that fails if any pose misses its target;
//! - environment: `DCOL_BENCH_POSES` (poses per pair), `DCOL_BENCH_REPS` (calls per timing,
//!   default 8), `DCOL_BENCH_METHODS` (comma list, e.g. `proximity,jacobian`),
//!   `DCOL_BENCH_CPU` (pin the process to that core), `DCOL_BENCH_TABLE=0` (criterion only).
//!
//! A query that returns an error on its first case (for example, one not built yet) is
//! reported as unavailable and skipped.

use criterion::Criterion;
use dcol::{distance, gradient, jacobian, proximity, Error, Options, Pose, Shape, Vec3};
use std::hint::black_box;
use std::time::Instant;

/// A timed query; returns the interior-point iterations it used.
type Method = fn(&Shape, &Pose, &Shape, &Pose, &Options) -> Result<u32, Error>;

/// The timed queries, one line each.
const METHODS: &[(&str, Method)] = &[
    ("proximity", |a, pa, b, pb, o| {
        proximity(a, pa, b, pb, o).map(|r| black_box(r).iterations)
    }),
    ("proximity_ipm", |a, pa, b, pb, o| {
        let o = Options {
            method: dcol::Method::InteriorPoint,
            ..*o
        };
        proximity(a, pa, b, pb, &o).map(|r| black_box(r).iterations)
    }),
    ("intersect", |a, pa, b, pb, o| {
        dcol::intersect(a, pa, b, pb, o).map(|r| black_box(r).iterations)
    }),
    ("gradient", |a, pa, b, pb, o| {
        gradient(a, pa, b, pb, o).map(|r| black_box(r).0.iterations)
    }),
    ("jacobian", |a, pa, b, pb, o| {
        jacobian(a, pa, b, pb, o).map(|r| black_box(r).0.iterations)
    }),
    ("derivatives", |a, pa, b, pb, o| {
        // The Jacobian with both contact points' (`dcol_derivatives`).
        dcol::derivatives(a, pa, b, pb, o).map(|r| black_box(r).proximity.iterations)
    }),
    ("shape_gradient", |a, pa, b, pb, o| {
        // Both shapes' derivatives, into buffers kept between calls (as a caller would).
        SHAPE_BUFFERS.with(|cell| {
            let mut bufs = cell.borrow_mut();
            let (g1, g2) = bufs.split_at_mut(SHAPE_BUFFER);
            let r = dcol::shape_gradient(a, pa, b, pb, o, Some(g1), Some(g2))?;
            black_box((&g1[0], &g2[0]));
            Ok(black_box(r).iterations)
        })
    }),
    ("distance", |a, pa, b, pb, o| {
        distance(a, pa, b, pb, o).map(|r| black_box(r).iterations)
    }),
    ("distance_ipm", |a, pa, b, pb, o| {
        let o = Options {
            method: dcol::Method::InteriorPoint,
            ..*o
        };
        distance(a, pa, b, pb, &o).map(|r| black_box(r).iterations)
    }),
    ("signed_distance", |a, pa, b, pb, o| {
        dcol::signed_distance(a, pa, b, pb, o).map(|r| black_box(r).iterations)
    }),
    ("contacts", |a, pa, b, pb, o| {
        dcol::contact_manifold(a, pa, b, pb, 0.0, 4, o).map(|m| black_box(m).iterations)
    }),
];

/// Room for one shape's parameters in the `shape_gradient` method (the 12-facet polytope has
/// 48, the padded polygons 3m + 1).
const SHAPE_BUFFER: usize = 256;

thread_local! {
    static SHAPE_BUFFERS: std::cell::RefCell<Vec<f64>> =
        std::cell::RefCell::new(vec![0.0; 2 * SHAPE_BUFFER]);
}

/// The pose classes: name and the range of the target α*.
const CLASSES: [(&str, f64, f64); 3] = [
    ("separated", 1.2, 3.0),
    ("near", 0.98, 1.02),
    ("overlapping", 0.2, 0.8),
];

const SEED: u64 = 0x0DC0_1BE9_C4A5_E5ED;

/// SplitMix64: a tiny deterministic generator.
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
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Standard normal (Box–Muller).
    fn normal(&mut self) -> f64 {
        let u = 1.0 - self.unit();
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
    /// Uniform on the unit sphere.
    fn direction(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.normal(), self.normal(), self.normal());
            let n = v.norm();
            if n > 1e-6 {
                return v / n;
            }
        }
    }
    /// A uniformly random attitude, as a unit quaternion `[w, x, y, z]`.
    fn quaternion(&mut self) -> [f64; 4] {
        loop {
            let q = [self.normal(), self.normal(), self.normal(), self.normal()];
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 1e-6 {
                return q.map(|v| v / n);
            }
        }
    }
}

/// The eight benchmark shapes, all with bounding radii between 0.5 and 0.9.
fn shapes() -> Vec<(&'static str, Shape)> {
    let mut rng = Rng::new(SEED ^ 0x5AA5);
    // Ellipsoid: semi-axes (0.8, 0.5, 0.3) in a random orientation.
    let q = rng.quaternion();
    let rot = dcol::math::rotation_from_quaternion(q);
    let d = nalgebra::Matrix3::from_diagonal(&Vec3::new(
        1.0 / (0.8f64 * 0.8),
        1.0 / (0.5f64 * 0.5),
        1.0 / (0.3f64 * 0.3),
    ));
    let pm = rot * d * rot.transpose();
    let mut p = [[0.0; 3]; 3];
    for (i, row) in p.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = 0.5 * (pm[(i, j)] + pm[(j, i)]);
        }
    }
    // 12 facets: the normals of a regular dodecahedron (icosahedron vertices), jittered, with
    // random offsets.
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut normals = Vec::new();
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            normals.push(Vec3::new(0.0, s1, s2 * phi));
            normals.push(Vec3::new(s1, s2 * phi, 0.0));
            normals.push(Vec3::new(s2 * phi, 0.0, s1));
        }
    }
    let a: Vec<[f64; 3]> = normals
        .iter()
        .map(|n| {
            let v = n.normalize() + rng.direction() * 0.1;
            v.normalize().into()
        })
        .collect();
    let b: Vec<f64> = (0..12).map(|_| rng.uniform(0.45, 0.6)).collect();
    // An irregular hexagon in the body x-y plane.
    let c: Vec<[f64; 2]> = (0..6)
        .map(|i| {
            let t = (i as f64 + rng.uniform(-0.15, 0.15)) * std::f64::consts::PI / 3.0;
            [t.cos(), t.sin()]
        })
        .collect();
    let dd: Vec<f64> = (0..6).map(|_| rng.uniform(0.4, 0.6)).collect();
    vec![
        ("sphere", Shape::sphere(0.5).unwrap()),
        ("ellipsoid", Shape::ellipsoid(p).unwrap()),
        ("box", Shape::cuboid(0.5, 0.35, 0.25).unwrap()),
        ("polytope", Shape::polytope(&a, &b).unwrap()),
        ("capsule", Shape::capsule(0.25, 0.8).unwrap()),
        ("cylinder", Shape::cylinder(0.3, 0.9).unwrap()),
        ("cone", Shape::cone(1.0, 0.5).unwrap()),
        ("polygon", Shape::polygon(&c, &dd, 0.08).unwrap()),
    ]
}

/// One benchmark pose of a pair.
struct Case {
    pose1: Pose,
    pose2: Pose,
    class: usize,
}

/// An unordered pair of kinds (i ≤ j) and its poses.
struct Pair {
    name: String,
    i: usize,
    j: usize,
    cases: Vec<Case>,
}

/// `n` poses for the pair (s1, s2): class `k % 3`, target α* uniform in the class's range.
fn make_cases(s1: &Shape, s2: &Shape, n: usize, seed: u64, name: &str) -> Vec<Case> {
    let mut rng = Rng::new(seed);
    let opts = Options::default();
    let reach = s1.bounding_radius() + s2.bounding_radius();
    (0..n)
        .map(|k| {
            let class = k % CLASSES.len();
            let (_, lo, hi) = CLASSES[class];
            let target = rng.uniform(lo, hi);
            let r1 = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            );
            let (q1, q2) = (rng.quaternion(), rng.quaternion());
            let dir = rng.direction();
            let pose1 = Pose::new(r1.into(), q1).unwrap();
            let trial = Pose::new((r1 + dir * reach).into(), q2).unwrap();
            let a0 = proximity(s1, &pose1, s2, &trial, &opts).unwrap();
            assert!(a0.status.is_converged() && a0.alpha > 0.0, "{name}: {a0:?}");
            let pose2 = Pose::new((r1 + dir * (reach * target / a0.alpha)).into(), q2).unwrap();
            let a1 = proximity(s1, &pose1, s2, &pose2, &opts).unwrap();
            assert!(
                a1.status.is_converged() && (a1.alpha - target).abs() <= 1e-6 * target,
                "{name}, pose {k}: target alpha {target}, got {a1:?}"
            );
            Case {
                pose1,
                pose2,
                class,
            }
        })
        .collect()
}

fn env_usize(key: &str) -> Option<usize> {
    std::env::var(key).ok().map(|v| {
        v.parse()
            .unwrap_or_else(|_| panic!("{key}={v} is not a number"))
    })
}

/// Pins the process to one core (Linux).
fn pin_to_cpu(cpu: usize) {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: a zeroed cpu_set_t is a valid empty set; the call only reads it.
        let ok = unsafe {
            let mut set: libc::cpu_set_t = std::mem::zeroed();
            libc::CPU_SET(cpu, &mut set);
            libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) == 0
        };
        if !ok {
            eprintln!("could not pin to CPU {cpu}; running unpinned");
        }
    }
    #[cfg(not(target_os = "linux"))]
    eprintln!("DCOL_BENCH_CPU={cpu} is only supported on Linux; running unpinned");
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Timings of one method on one pair.
#[derive(Default)]
struct Samples {
    /// (ns per query, class, iterations)
    rows: Vec<(f64, usize, u32)>,
    errors: usize,
}

/// Times every available method on every pose of every pair, methods interleaved pose by
/// pose, and prints one table per method.
fn run_table(shapes: &[(&str, Shape)], pairs: &[Pair], methods: &[(&str, Method)], reps: usize) {
    let opts = Options::default();
    let mut samples: Vec<Vec<Samples>> = methods
        .iter()
        .map(|_| pairs.iter().map(|_| Samples::default()).collect())
        .collect();
    let start = Instant::now();
    for (pi, pair) in pairs.iter().enumerate() {
        let (s1, s2) = (&shapes[pair.i].1, &shapes[pair.j].1);
        for case in &pair.cases {
            for (mi, (_, m)) in methods.iter().enumerate() {
                let its = m(s1, &case.pose1, s2, &case.pose2, &opts);
                let t0 = Instant::now();
                for _ in 0..reps {
                    let _ = black_box(m(
                        black_box(s1),
                        black_box(&case.pose1),
                        black_box(s2),
                        black_box(&case.pose2),
                        black_box(&opts),
                    ));
                }
                let ns = t0.elapsed().as_nanos() as f64 / reps as f64;
                match its {
                    Ok(its) => samples[mi][pi].rows.push((ns, case.class, its)),
                    Err(_) => samples[mi][pi].errors += 1,
                }
            }
        }
    }
    let n = pairs.first().map_or(0, |p| p.cases.len());
    println!(
        "\n{} poses per pair ({}), {} calls per timing, {:.1} s",
        n,
        CLASSES
            .iter()
            .map(|c| format!("{} α* ∈ [{}, {}]", c.0, c.1, c.2))
            .collect::<Vec<_>>()
            .join(", "),
        reps,
        start.elapsed().as_secs_f64()
    );
    for (mi, (mname, _)) in methods.iter().enumerate() {
        println!("\n{mname}: median ns per query");
        println!(
            "{:<20} {:>8} {:>10} {:>8} {:>12} {:>8} {:>7}",
            "pair", "median", "separated", "near", "overlapping", "mean it", "max it"
        );
        let mut all = Vec::new();
        let mut pair_medians = Vec::new();
        let (mut it_sum, mut it_n, mut errors) = (0u64, 0u64, 0usize);
        for (pi, pair) in pairs.iter().enumerate() {
            let s = &samples[mi][pi];
            errors += s.errors;
            let mut t: Vec<f64> = s.rows.iter().map(|r| r.0).collect();
            all.extend_from_slice(&t);
            let med = median(&mut t);
            pair_medians.push(med);
            let class_med = |c: usize| {
                let mut v: Vec<f64> = s.rows.iter().filter(|r| r.1 == c).map(|r| r.0).collect();
                median(&mut v)
            };
            let its: u64 = s.rows.iter().map(|r| r.2 as u64).sum();
            let max_it = s.rows.iter().map(|r| r.2).max().unwrap_or(0);
            it_sum += its;
            it_n += s.rows.len() as u64;
            let err = if s.errors > 0 {
                format!("  ({} errors)", s.errors)
            } else {
                String::new()
            };
            println!(
                "{:<20} {:>8.0} {:>10.0} {:>8.0} {:>12.0} {:>8.2} {:>7}{}",
                pair.name,
                med,
                class_med(0),
                class_med(1),
                class_med(2),
                its as f64 / s.rows.len().max(1) as f64,
                max_it,
                err
            );
        }
        let n_all = all.len();
        println!(
            "{:<20} {:>8.0}   (median of the pair medians {:.0}; {} queries, mean iterations {:.2}{})",
            "ALL PAIRS",
            median(&mut all),
            median(&mut pair_medians),
            n_all,
            it_sum as f64 / it_n.max(1) as f64,
            if errors > 0 {
                format!(", {errors} errors")
            } else {
                String::new()
            }
        );
        let by_class: Vec<String> = CLASSES
            .iter()
            .enumerate()
            .map(|(c, (cname, _, _))| {
                let mut v: Vec<f64> = samples[mi]
                    .iter()
                    .flat_map(|s| s.rows.iter().filter(|r| r.1 == c).map(|r| r.0))
                    .collect();
                format!("{cname} {:.0}", median(&mut v))
            })
            .collect();
        println!("{:<20} {}", "ALL PAIRS by class", by_class.join(", "));
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let flag = |f: &str| args.iter().any(|a| a == f);
    let list = flag("--list");
    // As criterion decides: a smoke run unless `--bench` is given without `--test`.
    let test_mode = flag("--test") || !flag("--bench");
    let quick = flag("--quick");

    if let Some(cpu) = env_usize("DCOL_BENCH_CPU") {
        pin_to_cpu(cpu);
    }
    let n = env_usize("DCOL_BENCH_POSES").unwrap_or(if test_mode {
        3
    } else if quick {
        200
    } else {
        2000
    });
    let reps = env_usize("DCOL_BENCH_REPS")
        .unwrap_or(if test_mode { 1 } else { 8 })
        .max(1);

    let shapes = shapes();
    let mut pairs = Vec::new();
    if !list {
        for i in 0..shapes.len() {
            for j in i..shapes.len() {
                let name = format!("{}-{}", shapes[i].0, shapes[j].0);
                let seed = SEED ^ ((i as u64) << 32 | j as u64).wrapping_mul(0x9E37_79B9);
                let cases = make_cases(&shapes[i].1, &shapes[j].1, n, seed, &name);
                pairs.push(Pair { name, i, j, cases });
            }
        }
        assert_eq!(pairs.len(), 36);
    }

    // The methods asked for that answer the first case.
    let wanted: Option<Vec<String>> = std::env::var("DCOL_BENCH_METHODS")
        .ok()
        .map(|v| v.split(',').map(|s| s.trim().to_string()).collect());
    let mut methods: Vec<(&str, Method)> = Vec::new();
    for &(name, m) in METHODS {
        if let Some(w) = &wanted {
            if !w.iter().any(|x| x == name) {
                continue;
            }
        }
        if let Some(c) = pairs.first().and_then(|p| p.cases.first()) {
            let (s1, s2) = (&shapes[pairs[0].i].1, &shapes[pairs[0].j].1);
            if let Err(e) = m(s1, &c.pose1, s2, &c.pose2, &Options::default()) {
                println!("{name}: unavailable ({e}); skipped");
                continue;
            }
        }
        methods.push((name, m));
    }

    if !list && std::env::var("DCOL_BENCH_TABLE").as_deref() != Ok("0") {
        run_table(&shapes, &pairs, &methods, reps);
    }

    // Criterion: each method cycling through every pose of every pair (pose-major, so that
    // consecutive calls are different pairs).
    let mut c = Criterion::default().configure_from_args();
    let opts = Options::default();
    let mut flat: Vec<(&Shape, &Pose, &Shape, &Pose)> = Vec::new();
    for k in 0..n {
        for p in &pairs {
            let case = &p.cases[k];
            flat.push((&shapes[p.i].1, &case.pose1, &shapes[p.j].1, &case.pose2));
        }
    }
    let per_pair = std::env::var("DCOL_BENCH_PAIRS").as_deref() == Ok("1");
    for &(name, m) in &methods {
        c.bench_function(&format!("{name}/all-pairs"), |b| {
            let mut k = 0;
            b.iter(|| {
                let (s1, p1, s2, p2) = flat[k];
                k = (k + 1) % flat.len();
                m(s1, p1, s2, p2, &opts)
            })
        });
        if per_pair {
            for p in &pairs {
                let (s1, s2) = (&shapes[p.i].1, &shapes[p.j].1);
                c.bench_function(&format!("{name}/{}", p.name), |b| {
                    let mut k = 0;
                    b.iter(|| {
                        let case = &p.cases[k];
                        k = (k + 1) % p.cases.len();
                        m(s1, &case.pose1, s2, &case.pose2, &opts)
                    })
                });
            }
        }
    }
    c.final_summary();
}
