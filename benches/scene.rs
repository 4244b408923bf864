//! Skip-what-you-don't-need benchmarks, printed as tables (medians, same run):
//! 1. `intersect` (early exit) vs full `proximity` per regime (separated / near / overlapping);
//! 2. batch throughput per pair vs single calls (1 and 2 threads);
//! 3. scene step time at N = 100, 1 000, 10 000 (constant density) and the share of pairs each
//!    level skips.
//!
//! `cargo bench --bench scene` (full) or `cargo bench --bench scene -- --test` (smoke, seconds).

use dcol::batch::{proximity_batch, Pair};
use dcol::scene::Scene;
use dcol::{intersect, proximity, Options, Pose, Shape};
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
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn shapes() -> Vec<Shape> {
    vec![
        Shape::sphere(0.5).unwrap(),
        Shape::ellipsoid([[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]).unwrap(),
        Shape::cuboid(0.5, 0.3, 0.2).unwrap(),
        Shape::capsule(0.2, 0.6).unwrap(),
        Shape::cylinder(0.25, 0.6).unwrap(),
        Shape::cone(0.8, 0.5).unwrap(),
        Shape::polygon(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
            &[0.4; 4],
            0.05,
        )
        .unwrap(),
    ]
}

fn quat(rng: &mut Rng) -> [f64; 4] {
    [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ]
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let smoke = std::env::args().any(|a| a == "--test");
    let opts = Options::default();
    let kinds = shapes();
    let mut rng = Rng(0xDC01);

    // 1. Boolean early exit vs full proximity, per regime.
    let per = if smoke { 20 } else { 2000 };
    println!("## intersect (early exit) vs proximity, median ns per query\n");
    println!("| regime | proximity | intersect | ratio | iterations full | iterations intersect |");
    println!("|---|--:|--:|--:|--:|--:|");
    for (name, lo, hi) in [
        ("separated", 1.1, 3.0),
        ("near", 0.9, 1.1),
        ("overlapping", 0.2, 0.9),
    ] {
        let mut cases = Vec::new();
        while cases.len() < per {
            let a = &kinds[(rng.next() * kinds.len() as f64) as usize];
            let b = &kinds[(rng.next() * kinds.len() as f64) as usize];
            let p1 = Pose::new([0.0; 3], quat(&mut rng)).unwrap();
            let dir = [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ];
            let p2 = Pose::new(dir, quat(&mut rng)).unwrap();
            let alpha = proximity(a, &p1, b, &p2, &opts).unwrap().alpha;
            let target = rng.range(lo, hi);
            let k = target / alpha;
            let p2 = Pose::new(dir.map(|v| v * k), p2.quaternion()).unwrap();
            cases.push((a, p1, b, p2));
        }
        let (mut tf, mut ti, mut itf, mut iti) = (Vec::new(), Vec::new(), 0u64, 0u64);
        for (a, p1, b, p2) in &cases {
            let t0 = Instant::now();
            let f = black_box(proximity(a, p1, b, p2, &opts).unwrap());
            let t1 = Instant::now();
            let d = black_box(intersect(a, p1, b, p2, &opts).unwrap());
            let t2 = Instant::now();
            tf.push((t1 - t0).as_nanos() as f64);
            ti.push((t2 - t1).as_nanos() as f64);
            itf += f.iterations as u64;
            iti += d.iterations as u64;
        }
        let (mf, mi) = (median(tf), median(ti));
        println!(
            "| {name} | {mf:.0} | {mi:.0} | {:.2} | {:.2} | {:.2} |",
            mi / mf,
            itf as f64 / per as f64,
            iti as f64 / per as f64
        );
    }

    // 2. Batch throughput.
    let n = if smoke { 50 } else { 20000 };
    let mut bodies = Vec::new();
    for _ in 0..n + 1 {
        let r = [
            rng.range(0.0, 2.0),
            rng.range(0.0, 2.0),
            rng.range(0.0, 2.0),
        ];
        bodies.push(Pose::new(r, quat(&mut rng)).unwrap());
    }
    let pairs: Vec<Pair> = (0..n)
        .map(|i| Pair {
            shape1: &kinds[i % kinds.len()],
            pose1: &bodies[i],
            shape2: &kinds[(i / 3) % kinds.len()],
            pose2: &bodies[i + 1],
        })
        .collect();
    let mut out = vec![Err(dcol::Error::Internal("unset")); n];
    let t0 = Instant::now();
    for p in &pairs {
        black_box(proximity(p.shape1, p.pose1, p.shape2, p.pose2, &opts).unwrap());
    }
    let single = t0.elapsed().as_nanos() as f64 / n as f64;
    // The first parallel batch creates the thread pool: keep that out of the timing.
    proximity_batch(&pairs, &opts, 2, &mut out).unwrap();
    println!("\n## batch throughput, ns per pair ({n} pairs)\n");
    println!("| method | ns/pair | speed-up |\n|---|--:|--:|");
    println!("| single calls | {single:.0} | 1.00 |");
    for threads in [1, 2] {
        let t0 = Instant::now();
        proximity_batch(&pairs, &opts, threads, &mut out).unwrap();
        let per_pair = t0.elapsed().as_nanos() as f64 / n as f64;
        println!(
            "| batch, {threads} thread(s) | {per_pair:.0} | {:.2} |",
            single / per_pair
        );
    }

    // 3. Scene steps.
    println!("\n## scene step (threshold α ≤ 1), constant density\n");
    println!("| N | ms/step | pairs | sweep cand. | sphere cand. | early exits | full solves | reported | skipped before any solve |");
    println!("|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    let sizes: &[usize] = if smoke { &[100] } else { &[100, 1000, 10000] };
    for &nb in sizes {
        let extent = 2.5 * (nb as f64).cbrt();
        let mut scene = Scene::new();
        for i in 0..nb {
            let r = [
                rng.range(0.0, extent),
                rng.range(0.0, extent),
                rng.range(0.0, extent),
            ];
            scene.add(
                kinds[i % kinds.len()].clone(),
                Pose::new(r, quat(&mut rng)).unwrap(),
            );
        }
        let mut found = Vec::new();
        let steps = if smoke { 2 } else { 5 };
        let mut times = Vec::new();
        let mut stats = Default::default();
        for _ in 0..steps {
            for id in 0..nb {
                let p = *scene.pose(id).unwrap().position();
                let r = [
                    p.x + rng.range(-0.05, 0.05),
                    p.y + rng.range(-0.05, 0.05),
                    p.z + rng.range(-0.05, 0.05),
                ];
                scene
                    .set_pose(id, Pose::new(r, quat(&mut rng)).unwrap())
                    .unwrap();
            }
            let t0 = Instant::now();
            stats = scene.pairs_within(1.0, &opts, &mut found).unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        let s: dcol::scene::StepStats = stats;
        let skipped = 1.0 - s.sphere_candidates as f64 / s.pairs_total.max(1) as f64;
        println!(
            "| {nb} | {:.2} | {} | {} | {} | {} | {} | {} | {:.4}% |",
            median(times),
            s.pairs_total,
            s.sweep_candidates,
            s.sphere_candidates,
            s.early_exits,
            s.full_solves,
            s.reported,
            100.0 * skipped
        );
    }
}
