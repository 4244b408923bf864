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
                    // The scene starts pairs of polytopes from their last answer (a per-pair
                    // `dcol::Cache`): the answer of a single call, certified the same way, to
                    // the cache's agreement (tests/warm_start.rs): α* within 1e-12 relative,
                    // the points within 1e-11 ℓ.
                    let (x, y) = (&g.proximity, &e.2);
                    let ell = scene
                        .shape(e.0)
                        .unwrap()
                        .bounding_radius()
                        .max(scene.shape(e.1).unwrap().bounding_radius());
                    let far = [
                        (x.point, y.point),
                        (x.contact1, y.contact1),
                        (x.contact2, y.contact2),
                    ]
                    .iter()
                    .map(|(a, b)| (a - b).norm() / ell)
                    .fold(0.0, f64::max);
                    assert!(
                        (x.alpha - y.alpha).abs() <= 1e-12 * y.alpha && far <= 1e-11,
                        "results for ({}, {}): {x:?} vs {y:?}",
                        e.0,
                        e.1
                    );
                    assert_eq!((x.status, x.derivatives), (y.status, y.derivatives));
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

/// A scene of boxes and hulls drifting 1 mm and about a degree per step: the pairs it reports
/// are those of single calls (α* within 1e-12 relative), and the per-pair caches answer most
/// of the reported pairs after the first step (`Solver::Polish`, where a single cold call's
/// ray cast answers).
#[test]
fn scene_starts_pairs_of_polytopes_from_their_last_answer() {
    let mut rng = Rng(0x5eed_cafe);
    let pts: Vec<[f64; 3]> = (0..24)
        .map(|_| {
            [
                rng.range(-0.5, 0.5),
                rng.range(-0.4, 0.4),
                rng.range(-0.3, 0.3),
            ]
        })
        .collect();
    let hull = Shape::convex_hull(&pts, 0.0).unwrap();
    let boxed = Shape::cuboid(0.4, 0.3, 0.2).unwrap();
    let n = 12;
    let mut scene = Scene::new();
    let mut state = Vec::new();
    for i in 0..n {
        let r = [
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
            rng.range(-1.2, 1.2),
        ];
        let q = [
            1.0,
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let v = [
            rng.range(-1e-3, 1e-3),
            rng.range(-1e-3, 1e-3),
            rng.range(-1e-3, 1e-3),
        ];
        let shape = if i % 2 == 0 {
            hull.clone()
        } else {
            boxed.clone()
        };
        scene.add(shape, Pose::new(r, q).unwrap());
        state.push((r, q, v));
    }
    let opts = Options::default();
    let mut out = Vec::new();
    let (mut reported, mut warm) = (0usize, 0usize);
    for step in 0..60 {
        for (id, (r, q, v)) in state.iter_mut().enumerate() {
            *r = [r[0] + v[0], r[1] + v[1], r[2] + v[2]];
            q[1] += 0.01;
            scene.set_pose(id, Pose::new(*r, *q).unwrap()).unwrap();
        }
        scene.pairs_within(1.3, &opts, &mut out).unwrap();
        for sp in &out {
            let (s1, p1) = (
                scene.shape(sp.body1).unwrap(),
                scene.pose(sp.body1).unwrap(),
            );
            let (s2, p2) = (
                scene.shape(sp.body2).unwrap(),
                scene.pose(sp.body2).unwrap(),
            );
            let cold = proximity(s1, p1, s2, p2, &opts).unwrap();
            let a = sp.proximity.alpha;
            assert!(
                (a - cold.alpha).abs() <= 1e-12 * cold.alpha,
                "step {step}: {a} vs {}",
                cold.alpha
            );
            if step > 0 {
                reported += 1;
                warm += usize::from(
                    sp.proximity.solver == dcol::Solver::Polish
                        && cold.solver != dcol::Solver::Polish,
                );
            }
        }
    }
    assert!(reported > 100, "only {reported} pairs reported");
    assert!(
        warm * 2 > reported,
        "{warm} of {reported} reported pairs warm"
    );
}
