//! Batch throughput on 10 000 mixed pairs: the single-query loop against
//! `batch::proximity_batch` and `dcol_proximity_batch` (the C ABI) on 1 and 2 threads. Each
//! method runs `ROUNDS` times, interleaved with the others so that load on the machine falls on
//! all alike; the table gives the best and the median round per pair, and the speed-up of the
//! best rounds against one thread (on a shared machine the best round is the one least
//! disturbed by other work).
//!
//!     cargo bench --bench batch            # the table
//!     cargo bench --bench batch -- --test  # a smoke run on 200 pairs

use std::hint::black_box;
use std::time::Instant;

use dcol::batch::{proximity_batch, Pair};
use dcol::ffi::{
    dcol_pose, dcol_proximity_batch, dcol_proximity_result, dcol_shape, dcol_shape_free,
    dcol_shape_new_box, dcol_shape_new_capsule, dcol_shape_new_cone, dcol_shape_new_cylinder,
    dcol_shape_new_ellipsoid, dcol_shape_new_polygon, dcol_shape_new_sphere, dcol_status,
};
use dcol::{proximity, Options, Pose, Shape};

const ROUNDS: usize = 11;

/// SplitMix64, fixed seed.
struct Rng(u64);

impl Rng {
    fn unif(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    fn quat(&mut self) -> [f64; 4] {
        loop {
            let q = [0; 4].map(|_| self.range(-1.0, 1.0));
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return q.map(|v| v / n);
            }
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let smoke = std::env::args().any(|a| a == "--test");
    let n = if smoke { 200 } else { 10_000 };
    let rounds = if smoke { 1 } else { ROUNDS };
    let opts = Options::default();
    let mut rng = Rng(7);

    // The seven primitives (a box for the polytope), through both APIs.
    let kinds: Vec<Shape> = vec![
        Shape::sphere(0.5).unwrap(),
        Shape::ellipsoid([[4.0, 0.0, 0.0], [0.0, 2.0, 0.3], [0.0, 0.3, 1.0]]).unwrap(),
        Shape::cuboid(0.5, 0.3, 0.4).unwrap(),
        Shape::capsule(0.3, 0.8).unwrap(),
        Shape::cylinder(0.35, 0.9).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
        Shape::polygon(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
            &[0.5, 0.4, 0.5, 0.4],
            0.1,
        )
        .unwrap(),
    ];
    let mut c_kinds: Vec<*mut dcol_shape> = vec![std::ptr::null_mut(); 7];
    let p = [4.0, 0.0, 0.0, 0.0, 2.0, 0.3, 0.0, 0.3, 1.0];
    let (c, d) = (
        [1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, -1.0],
        [0.5, 0.4, 0.5, 0.4],
    );
    // SAFETY: every pointer is a valid local; the shapes are freed at the end.
    let built = unsafe {
        [
            dcol_shape_new_sphere(0.5, &mut c_kinds[0]),
            dcol_shape_new_ellipsoid(p.as_ptr(), &mut c_kinds[1]),
            dcol_shape_new_box(0.5, 0.3, 0.4, &mut c_kinds[2]),
            dcol_shape_new_capsule(0.3, 0.8, &mut c_kinds[3]),
            dcol_shape_new_cylinder(0.35, 0.9, &mut c_kinds[4]),
            dcol_shape_new_cone(1.0, 0.5, &mut c_kinds[5]),
            dcol_shape_new_polygon(c.as_ptr(), d.as_ptr(), 4, 0.1, &mut c_kinds[6]),
        ]
    };
    assert!(built.iter().all(|s| *s == dcol_status::DCOL_OK));

    // 10 000 pairs: every ordered kind pair in turn, random attitudes, offsets from deep
    // overlap to well apart (α* about 0.3 to 3).
    let mut poses = Vec::with_capacity(2 * n);
    let mut which = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (i % 7, (i / 7) % 7);
        let dir = loop {
            let v = [0; 3].map(|_| rng.range(-1.0, 1.0));
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.1 && l <= 1.0 {
                break v.map(|x| x / l);
            }
        };
        let dist = rng.range(0.3, 3.0);
        poses.push(Pose::new([0.0; 3], rng.quat()).unwrap());
        poses.push(Pose::new(dir.map(|x| x * dist), rng.quat()).unwrap());
        which.push((a, b));
    }
    let pairs: Vec<Pair> = (0..n)
        .map(|i| Pair {
            shape1: &kinds[which[i].0],
            pose1: &poses[2 * i],
            shape2: &kinds[which[i].1],
            pose2: &poses[2 * i + 1],
        })
        .collect();
    let c_pose = |p: &Pose| {
        let r = p.position();
        dcol_pose {
            position: [r.x, r.y, r.z],
            quaternion: p.quaternion(),
        }
    };
    let s1: Vec<*const dcol_shape> = which.iter().map(|w| c_kinds[w.0] as *const _).collect();
    let s2: Vec<*const dcol_shape> = which.iter().map(|w| c_kinds[w.1] as *const _).collect();
    let p1: Vec<dcol_pose> = (0..n).map(|i| c_pose(&poses[2 * i])).collect();
    let p2: Vec<dcol_pose> = (0..n).map(|i| c_pose(&poses[2 * i + 1])).collect();
    let mut c_out = vec![dcol_proximity_result::default(); n];
    let mut c_status = vec![dcol_status::DCOL_ERROR_INTERNAL; n];
    let mut out = vec![Err(dcol::Error::Internal("unset")); n];

    // Warm-up: creates the pool and every thread's scratch state before any timing.
    proximity_batch(&pairs, &opts, 2, &mut out).unwrap();
    let reference: Vec<_> = pairs
        .iter()
        .map(|p| proximity(p.shape1, p.pose1, p.shape2, p.pose2, &opts))
        .collect();
    assert_eq!(out, reference, "the batch differs from single calls");

    let names = [
        "single-query loop (Rust)",
        "proximity_batch, 1 thread",
        "proximity_batch, 2 threads",
        "dcol_proximity_batch, 1 thread",
        "dcol_proximity_batch, 2 threads",
    ];
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for _ in 0..rounds {
        for (m, t) in times.iter_mut().enumerate() {
            let t0 = Instant::now();
            match m {
                0 => {
                    for p in &pairs {
                        black_box(proximity(p.shape1, p.pose1, p.shape2, p.pose2, &opts).ok());
                    }
                }
                1 | 2 => proximity_batch(&pairs, &opts, m, &mut out).unwrap(),
                _ => {
                    // SAFETY: every array holds `n` elements; the shapes are live.
                    let st = unsafe {
                        dcol_proximity_batch(
                            s1.as_ptr(),
                            p1.as_ptr(),
                            s2.as_ptr(),
                            p2.as_ptr(),
                            n,
                            std::ptr::null(),
                            (m - 2) as u32,
                            c_out.as_mut_ptr(),
                            c_status.as_mut_ptr(),
                        )
                    };
                    assert_eq!(st, dcol_status::DCOL_OK);
                }
            }
            black_box(&out);
            t.push(t0.elapsed().as_secs_f64() / n as f64 * 1e9);
        }
    }
    let best: Vec<f64> = times
        .iter()
        .map(|t| t.iter().cloned().fold(f64::INFINITY, f64::min))
        .collect();
    let med: Vec<f64> = times.into_iter().map(median).collect();
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    println!("\n## batch throughput: {n} mixed pairs (all 49 ordered kind pairs), {cores} cores, {rounds} rounds\n");
    println!("| method | ns per pair, best | ns per pair, median | pairs per second, best | speed-up vs 1 thread (best) |");
    println!("|---|--:|--:|--:|--:|");
    for (i, name) in names.iter().enumerate() {
        let one = match i {
            0..=2 => best[1],
            _ => best[3],
        };
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} | {:.2} |",
            best[i],
            med[i],
            1e9 / best[i],
            one / best[i]
        );
    }
    for s in c_kinds {
        // SAFETY: built above, freed once.
        unsafe { dcol_shape_free(s) };
    }
}
