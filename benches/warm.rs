//! Warm starts against cold queries on trajectories: every unordered pair of eight kinds
//! (sphere, ellipsoid, box, 12-facet polytope, 40-point hull, capsule, cylinder, cone, padded
//! polygon: 45 pairs), each moving 1 mm and 1° per step for `DCOL_WARM_STEPS` steps (default
//! 1 000): shape 2 translates along a direction that reverses every 250 steps, both turn about
//! their own fixed axes. The pair starts at α* = `start` (1.2; `DCOL_WARM_START`), so a
//! trajectory passes through separated, touching and (for some) overlapping poses, and the
//! contact features change as the shapes turn.
//!
//! For each query (proximity, gradient, Jacobian, distance, signed distance, contacts with a
//! 0.02 margin, derivatives, intersect) the whole trajectory is timed
//! cold (the plain query) and cached (one `dcol::Cache` carried through it), interleaved,
//! `DCOL_WARM_ROUNDS` times (default 5); per pair the median round, per step. Then the same
//! on random jumps (every step a new random pose of the pair, the cache carried along), where
//! a cache can only cost. The answers are compared: the largest relative difference in α*
//! between cached and cold, and for `intersect` the number of decisions that differ (none
//! expected). `DCOL_WARM_QUERIES=intersect,proximity` times only those queries;
//! `DCOL_WARM_STAT=min` takes the fastest round instead of the median one (the least disturbed
//! on a machine shared with other work).
//!
//! `cargo bench --bench warm` (`-- --test`: a smoke run of 20 steps, 1 round).

use dcol::{
    contact_manifold, contact_manifold_cached, derivatives, derivatives_cached, distance,
    distance_cached, gradient, gradient_cached, intersect, intersect_cached, jacobian,
    jacobian_cached, proximity, proximity_cached, signed_distance, signed_distance_cached, Cache,
    Options, Pose, Shape,
};
use std::hint::black_box;
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [0, 1, 2].map(|_| self.uniform(-1.0, 1.0));
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
    fn quaternion(&mut self) -> [f64; 4] {
        loop {
            let q = [0, 1, 2, 3].map(|_| self.uniform(-1.0, 1.0));
            let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return q.map(|x| x / n);
            }
        }
    }
}

fn shapes(rng: &mut Rng) -> Vec<(&'static str, Shape)> {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut a = Vec::new();
    for s1 in [-1.0, 1.0] {
        for s2 in [-1.0, 1.0] {
            for n in [
                [0.0, s1, s2 * phi],
                [s1, s2 * phi, 0.0],
                [s2 * phi, 0.0, s1],
            ] {
                let j = rng.direction();
                let v: Vec<f64> = (0..3).map(|k| n[k] / 1.902 + 0.1 * j[k]).collect();
                let m = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                a.push([v[0] / m, v[1] / m, v[2] / m]);
            }
        }
    }
    let b: Vec<f64> = (0..12).map(|_| rng.uniform(0.45, 0.6)).collect();
    let pts: Vec<[f64; 3]> = (0..40)
        .map(|_| {
            let d = rng.direction();
            let r = rng.uniform(0.4, 0.6);
            [d[0] * r * 1.2, d[1] * r, d[2] * r * 0.8]
        })
        .collect();
    let c: Vec<[f64; 2]> = (0..6)
        .map(|i| {
            let t = (i as f64 + rng.uniform(-0.15, 0.15)) * std::f64::consts::PI / 3.0;
            [t.cos(), t.sin()]
        })
        .collect();
    let d: Vec<f64> = (0..6).map(|_| rng.uniform(0.4, 0.6)).collect();
    let e = [
        [1.0 / 0.64, 0.0, 0.0],
        [0.0, 4.0, 0.0],
        [0.0, 0.0, 1.0 / 0.09],
    ];
    vec![
        ("sphere", Shape::sphere(0.5).unwrap()),
        ("ellipsoid", Shape::ellipsoid(e).unwrap()),
        ("box", Shape::cuboid(0.5, 0.35, 0.25).unwrap()),
        ("polytope", Shape::polytope(&a, &b).unwrap()),
        ("hull", Shape::convex_hull(&pts, 0.0).unwrap()),
        ("capsule", Shape::capsule(0.25, 0.8).unwrap()),
        ("cylinder", Shape::cylinder(0.3, 0.9).unwrap()),
        ("cone", Shape::cone(1.0, 0.5).unwrap()),
        ("polygon", Shape::polygon(&c, &d, 0.08).unwrap()),
    ]
}

/// Quaternion product `p q`.
fn qmul(p: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    [
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    ]
}

fn turn(axis: [f64; 3], deg: f64) -> [f64; 4] {
    let h = deg.to_radians() / 2.0;
    [
        h.cos(),
        axis[0] * h.sin(),
        axis[1] * h.sin(),
        axis[2] * h.sin(),
    ]
}

/// A trajectory of a pair, or random jumps when `jumps`.
fn poses(
    a: &Shape,
    b: &Shape,
    rng: &mut Rng,
    steps: usize,
    start: f64,
    jumps: bool,
) -> Vec<(Pose, Pose)> {
    let o = Options::default();
    let (mut q1, mut q2) = (rng.quaternion(), rng.quaternion());
    let (w1, w2) = (turn(rng.direction(), 1.0), turn(rng.direction(), 1.0));
    let dir = rng.direction();
    let p1 = Pose::new([0.0; 3], q1).unwrap();
    let trial = dir.map(|x| x * (a.bounding_radius() + b.bounding_radius()));
    let p2 = Pose::new(trial, q2).unwrap();
    let alpha = proximity(a, &p1, b, &p2, &o).unwrap().alpha;
    let mut r2 = trial.map(|x| x * start / alpha);
    let mut v = rng.direction().map(|x| x * 1e-3);
    let mut out = Vec::with_capacity(steps);
    for k in 0..steps {
        if jumps {
            let d = rng.direction();
            let s = rng.uniform(0.4, 1.4) * (a.bounding_radius() + b.bounding_radius());
            out.push((
                Pose::new([0.0; 3], rng.quaternion()).unwrap(),
                Pose::new(d.map(|x| x * s), rng.quaternion()).unwrap(),
            ));
            continue;
        }
        out.push((Pose::new([0.0; 3], q1).unwrap(), Pose::new(r2, q2).unwrap()));
        if k % 250 == 249 {
            v = v.map(|x| -x);
        }
        r2 = [r2[0] + v[0], r2[1] + v[1], r2[2] + v[2]];
        q1 = qmul(w1, q1);
        q2 = qmul(w2, q2);
    }
    out
}

/// The contact manifold's margin (the shapes are about 1 across).
const MARGIN: f64 = 0.02;

type Cold = fn(&Shape, &Pose, &Shape, &Pose, &Options) -> f64;
type Warm = fn(&Shape, &Pose, &Shape, &Pose, &Options, &mut Cache) -> f64;

const QUERIES: &[(&str, Cold, Warm)] = &[
    (
        "proximity",
        |a, p, b, q, o| proximity(a, p, b, q, o).unwrap().alpha,
        |a, p, b, q, o, c| proximity_cached(a, p, b, q, o, c).unwrap().alpha,
    ),
    (
        "gradient",
        |a, p, b, q, o| gradient(a, p, b, q, o).unwrap().0.alpha,
        |a, p, b, q, o, c| gradient_cached(a, p, b, q, o, c).unwrap().0.alpha,
    ),
    (
        "jacobian",
        |a, p, b, q, o| jacobian(a, p, b, q, o).unwrap().0.alpha,
        |a, p, b, q, o, c| jacobian_cached(a, p, b, q, o, c).unwrap().0.alpha,
    ),
    (
        "distance",
        |a, p, b, q, o| distance(a, p, b, q, o).unwrap().distance,
        |a, p, b, q, o, c| distance_cached(a, p, b, q, o, c).unwrap().distance,
    ),
    (
        "signed_distance",
        |a, p, b, q, o| signed_distance(a, p, b, q, o).unwrap().distance,
        |a, p, b, q, o, c| signed_distance_cached(a, p, b, q, o, c).unwrap().distance,
    ),
    (
        "contacts",
        |a, p, b, q, o| {
            let m = contact_manifold(a, p, b, q, MARGIN, 4, o).unwrap();
            m.signed_distance + m.len() as f64
        },
        |a, p, b, q, o, c| {
            let m = contact_manifold_cached(a, p, b, q, MARGIN, 4, o, c).unwrap();
            m.signed_distance + m.len() as f64
        },
    ),
    (
        "derivatives",
        |a, p, b, q, o| derivatives(a, p, b, q, o).unwrap().proximity.alpha,
        |a, p, b, q, o, c| {
            derivatives_cached(a, p, b, q, o, c)
                .unwrap()
                .proximity
                .alpha
        },
    ),
    (
        "intersect",
        |a, p, b, q, o| f64::from(u8::from(intersect(a, p, b, q, o).unwrap().below)),
        |a, p, b, q, o, c| f64::from(u8::from(intersect_cached(a, p, b, q, o, c).unwrap().below)),
    ),
];

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let smoke = std::env::args().any(|a| a == "--test");
    let env = |k: &str, d: usize| {
        std::env::var(k)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(d)
    };
    let steps = if smoke {
        20
    } else {
        env("DCOL_WARM_STEPS", 1000)
    };
    let rounds = if smoke { 1 } else { env("DCOL_WARM_ROUNDS", 5) };
    let start: f64 = std::env::var("DCOL_WARM_START")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.2);
    let seed = env("DCOL_WARM_SEED", 0x5eed_3301) as u64;
    let fastest = std::env::var("DCOL_WARM_STAT").is_ok_and(|v| v == "min");
    let pick = |v: &mut [f64]| {
        if fastest {
            v.iter().cloned().fold(f64::INFINITY, f64::min)
        } else {
            median(v)
        }
    };
    let mut rng = Rng(seed | 1);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let wanted: Option<Vec<String>> = std::env::var("DCOL_WARM_QUERIES")
        .ok()
        .map(|v| v.split(',').map(str::to_string).collect());
    let queries: Vec<_> = QUERIES
        .iter()
        .filter(|q| wanted.as_ref().map_or(true, |w| w.iter().any(|n| n == q.0)))
        .collect();
    let mut mismatches = 0usize;
    for jumps in [false, true] {
        println!(
            "\n## {} ({} steps, {} rounds; ns per step, median round)\n",
            if jumps {
                "random jumps"
            } else {
                "trajectories: 1 mm and 1 degree per step"
            },
            steps,
            rounds
        );
        println!(
            "| pair | {} |",
            queries
                .iter()
                .map(|q| format!("{} cold | cached | ratio", q.0))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        println!("|---|{}", "--:|".repeat(3 * queries.len()));
        let mut ratios = vec![Vec::new(); queries.len()];
        let mut colds = vec![Vec::new(); queries.len()];
        let mut warms = vec![Vec::new(); queries.len()];
        let mut worst: f64 = 0.0;
        for i in 0..kinds.len() {
            for j in i..kinds.len() {
                let (a, b) = (&kinds[i].1, &kinds[j].1);
                let traj = poses(a, b, &mut rng, steps, start, jumps);
                let mut row = format!("| {}-{} |", kinds[i].0, kinds[j].0);
                for (qi, (name, cold, warm)) in queries.iter().enumerate() {
                    let (mut tc, mut tw) = (Vec::new(), Vec::new());
                    for _ in 0..rounds {
                        let t = Instant::now();
                        for (p, q) in &traj {
                            black_box(cold(a, p, b, q, &o));
                        }
                        tc.push(t.elapsed().as_nanos() as f64 / steps as f64);
                        let mut cache = Cache::new();
                        let t = Instant::now();
                        for (p, q) in &traj {
                            black_box(warm(a, p, b, q, &o, &mut cache));
                        }
                        tw.push(t.elapsed().as_nanos() as f64 / steps as f64);
                    }
                    if matches!(*name, "proximity" | "distance" | "signed_distance") {
                        let mut cache = Cache::new();
                        for (p, q) in &traj {
                            let (x, y) = (cold(a, p, b, q, &o), warm(a, p, b, q, &o, &mut cache));
                            let scale = if *name == "proximity" { x.abs() } else { 1.0 };
                            worst = worst.max((x - y).abs() / scale.max(1e-300));
                        }
                    }
                    if *name == "intersect" {
                        let mut cache = Cache::new();
                        for (p, q) in &traj {
                            let (x, y) = (cold(a, p, b, q, &o), warm(a, p, b, q, &o, &mut cache));
                            mismatches += usize::from(x != y);
                        }
                    }
                    let (c, w) = (pick(&mut tc), pick(&mut tw));
                    ratios[qi].push(w / c);
                    colds[qi].push(c);
                    warms[qi].push(w);
                    row += &format!(" {c:.0} | {w:.0} | {:.2} |", w / c);
                }
                println!("{row}");
            }
        }
        let mut all = "| all-pairs median |".to_string();
        for qi in 0..queries.len() {
            all += &format!(
                " {:.0} | {:.0} | {:.2} |",
                median(&mut colds[qi]),
                median(&mut warms[qi]),
                median(&mut ratios[qi])
            );
        }
        println!("{all}");
        let maxr: Vec<String> = ratios
            .iter()
            .map(|r| format!("{:.2}", r.iter().cloned().fold(0.0, f64::max)))
            .collect();
        println!("\nworst pair ratio per query: {}; largest difference cached vs cold (alpha relative, distance absolute): {worst:.1e}; intersect decisions that differ: {mismatches}", maxr.join(", "));
    }
}
