//! The scene and batch layers against single calls: on random scenes the reported pairs are
//! exactly the pairs whose single-call α* is ≤ t (outside a 1e-7 band), with identical
//! proximity results; batch results equal single calls, single-threaded or on 4 threads.

use dcol::batch::{proximity_batch, Pair};
use dcol::scene::Scene;
use dcol::{proximity, Options, Pose, Shape};

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

fn random_shape(rng: &mut Rng) -> Shape {
    let s = rng.range(0.2, 1.0);
    match (rng.next() * 8.0) as usize {
        0 => Shape::sphere(s).unwrap(),
        1 => Shape::ellipsoid([
            [1.0 / (s * s), 0.0, 0.0],
            [0.0, 4.0 / (s * s), 0.0],
            [0.0, 0.0, 2.0 / (s * s)],
        ])
        .unwrap(),
        2 => Shape::cuboid(s, 0.7 * s, 0.4 * s).unwrap(),
        3 => {
            let a = [
                [1.0, 1.0, 1.0],
                [-1.0, -1.0, 1.0],
                [-1.0, 1.0, -1.0],
                [1.0, -1.0, -1.0],
            ];
            Shape::polytope(&a, &[s; 4]).unwrap()
        }
        4 => Shape::capsule(0.3 * s, s).unwrap(),
        5 => Shape::cylinder(0.4 * s, s).unwrap(),
        6 => Shape::cone(s, 0.5).unwrap(),
        _ => Shape::polygon(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
            &[0.5 * s; 4],
            0.1 * s,
        )
        .unwrap(),
    }
}

fn random_pose(rng: &mut Rng, extent: f64) -> Pose {
    let r = [
        rng.range(0.0, extent),
        rng.range(0.0, extent),
        rng.range(0.0, extent),
    ];
    let q = [
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    ];
    Pose::new(r, q).unwrap()
}

#[test]
fn scene_equals_single_calls() {
    let opts = Options::default();
    for seed in 1..6u64 {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ seed);
        let n = 60;
        let mut scene = Scene::new();
        for _ in 0..n {
            let s = random_shape(&mut rng);
            let p = random_pose(&mut rng, 6.0);
            scene.add(s, p);
        }
        let mut out = Vec::new();
        for step in 0..3 {
            for id in 0..n {
                if step > 0 && rng.next() < 0.5 {
                    scene.set_pose(id, random_pose(&mut rng, 6.0)).unwrap();
                }
            }
            for t in [0.5, 1.0, 1.5] {
                let stats = scene.pairs_within(t, &opts, &mut out).unwrap();
                let mut expected = Vec::new();
                for i in 0..n {
                    for j in (i + 1)..n {
                        let (s1, p1) = (scene.shape(i).unwrap(), scene.pose(i).unwrap());
                        let (s2, p2) = (scene.shape(j).unwrap(), scene.pose(j).unwrap());
                        let p = proximity(s1, p1, s2, p2, &opts).unwrap();
                        if (p.alpha - t).abs() < 1e-7 * t {
                            continue; // inside the tolerance band: either answer is right
                        }
                        if p.alpha <= t {
                            expected.push((i, j, p));
                        }
                    }
                }
                let got: Vec<_> = out
                    .iter()
                    .filter(|sp| (sp.proximity.alpha - t).abs() >= 1e-7 * t)
                    .collect();
                assert_eq!(got.len(), expected.len(), "seed {seed} step {step} t {t}");
                for (g, e) in got.iter().zip(&expected) {
                    assert_eq!((g.body1, g.body2), (e.0, e.1));
                    assert_eq!(g.proximity, e.2, "identical results for ({}, {})", e.0, e.1);
                }
                assert_eq!(stats.reported, out.len());
                assert_eq!(stats.pairs_total, n * (n - 1) / 2);
                assert!(stats.sphere_candidates <= stats.sweep_candidates);
            }
        }
    }
}

#[test]
fn batch_equals_single_calls_on_any_thread_count() {
    let opts = Options::default();
    let mut rng = Rng(12345);
    let shapes: Vec<Shape> = (0..40).map(|_| random_shape(&mut rng)).collect();
    let poses: Vec<Pose> = (0..40).map(|_| random_pose(&mut rng, 3.0)).collect();
    let pairs: Vec<Pair> = (0..39)
        .flat_map(|i| [(i, i + 1), (i, 39 - i)])
        .filter(|(a, b)| a != b)
        .map(|(a, b)| Pair {
            shape1: &shapes[a],
            pose1: &poses[a],
            shape2: &shapes[b],
            pose2: &poses[b],
        })
        .collect();
    let single: Vec<_> = pairs
        .iter()
        .map(|p| proximity(p.shape1, p.pose1, p.shape2, p.pose2, &opts))
        .collect();
    for threads in [1, 4] {
        let mut out = vec![Err(dcol::Error::Internal("unset")); pairs.len()];
        proximity_batch(&pairs, &opts, threads, &mut out).unwrap();
        assert_eq!(out, single, "threads = {threads}");
    }
    let mut short = vec![Err(dcol::Error::Internal("unset")); 1];
    assert!(proximity_batch(&pairs, &opts, 1, &mut short).is_err());
}
