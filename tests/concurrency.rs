//! Concurrency (issue 6): 8 threads query the same shared shapes at once, for thousands of
//! pairs, with `proximity`, `gradient`, `jacobian`, `distance` and `distance_gradient`; every
//! result must be bit-identical to the single-threaded run.
//!
//! The shape set includes polytopes and a padded polygon with more than 32 facets, so the
//! per-thread scratch buffer (used when the two shapes have more than 32 orthant rows) runs in
//! every thread, interleaved with stack-only queries of small shapes, and each thread walks the
//! pairs in its own order so that different threads solve different problems at the same time.

use dcol::{
    distance, distance_gradient, gradient, jacobian, proximity, Options, Pose, Shape, SolveStatus,
};
use std::sync::Arc;

const THREADS: usize = 8;

/// SplitMix64, fixed seed.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unif(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// A polytope with `m` facets tangent to the unit sphere (plus the six box rows).
fn many_facets(rng: &mut Rng, m: usize) -> Shape {
    let mut a: Vec<[f64; 3]> = vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    while a.len() < m {
        let v = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if (0.1..=1.0).contains(&n) {
            a.push(v.map(|x| x / n));
        }
    }
    let b: Vec<f64> = (0..m).map(|_| rng.range(0.8, 1.0)).collect();
    Shape::polytope(&a, &b).unwrap()
}

fn shapes(rng: &mut Rng) -> Vec<Shape> {
    let polygon = {
        let m = 40;
        let c: Vec<[f64; 2]> = (0..m)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
                [t.cos(), t.sin()]
            })
            .collect();
        let d: Vec<f64> = (0..m).map(|_| rng.range(0.7, 1.0)).collect();
        Shape::polygon(&c, &d, 0.1).unwrap()
    };
    vec![
        Shape::sphere(0.7).unwrap(),
        Shape::ellipsoid([[2.0, 0.3, 0.0], [0.3, 1.0, 0.1], [0.0, 0.1, 4.0]]).unwrap(),
        Shape::cuboid(0.5, 0.3, 0.8).unwrap(),
        Shape::capsule(0.3, 1.2).unwrap(),
        Shape::cylinder(0.4, 0.9).unwrap(),
        Shape::cone(1.2, 0.5).unwrap(),
        polygon,
        many_facets(rng, 20), // two of these: 40 rows, scratch path
        many_facets(rng, 48), // scratch path with any partner
        many_facets(rng, 64),
        many_facets(rng, 256), // the largest allowed (only in the scoped test: slow)
    ]
}

/// One query: shape indices and poses.
#[derive(Clone, Copy)]
struct Pair {
    i: usize,
    j: usize,
    p1: Pose,
    p2: Pose,
}

fn pairs(rng: &mut Rng, n_shapes: usize, n: usize) -> Vec<Pair> {
    let quat = |rng: &mut Rng| {
        // Any non-zero length: the library normalises.
        let q = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        if q.iter().all(|v| v.abs() < 1e-3) {
            [1.0, 0.0, 0.0, 0.0]
        } else {
            q
        }
    };
    (0..n)
        .map(|k| {
            let r = |rng: &mut Rng, s: f64| [rng.range(-s, s), rng.range(-s, s), rng.range(-s, s)];
            let p1 = Pose::new(r(rng, 1.0), quat(rng)).unwrap();
            // Every 50th pair has coincident origins (α* = 0).
            let r2 = if k % 50 == 0 {
                let r1 = p1.position();
                [r1.x, r1.y, r1.z]
            } else {
                r(rng, 3.0)
            };
            let p2 = Pose::new(r2, quat(rng)).unwrap();
            Pair {
                i: rng.index(n_shapes),
                j: rng.index(n_shapes),
                p1,
                p2,
            }
        })
        .collect()
}

/// Every output of every query for one pair, as bit patterns.
fn evaluate(shapes: &[Shape], p: &Pair, opts: &Options) -> Vec<u64> {
    let (s1, s2) = (&shapes[p.i], &shapes[p.j]);
    let mut out = Vec::with_capacity(128);
    let status = |s: SolveStatus| match s {
        SolveStatus::Converged => 0u64,
        SolveStatus::MaxIterations => 1,
        SolveStatus::NumericalFailure => 2,
    };
    let prox = |pr: &dcol::Proximity, out: &mut Vec<u64>| {
        out.push(pr.alpha.to_bits());
        for v in [pr.point, pr.contact1, pr.contact2] {
            out.extend(v.iter().map(|x| x.to_bits()));
        }
        out.push(pr.iterations as u64);
        out.push(status(pr.status));
    };
    let pr = proximity(s1, &p.p1, s2, &p.p2, opts).unwrap();
    prox(&pr, &mut out);
    let (pr, g) = gradient(s1, &p.p1, s2, &p.p2, opts).unwrap();
    prox(&pr, &mut out);
    out.extend(g.iter().map(|x| x.to_bits()));
    let (pr, j) = jacobian(s1, &p.p1, s2, &p.p2, opts).unwrap();
    prox(&pr, &mut out);
    out.extend(j.iter().flatten().map(|x| x.to_bits()));
    let d = distance(s1, &p.p1, s2, &p.p2, opts).unwrap();
    let (d2, dg) = distance_gradient(s1, &p.p1, s2, &p.p2, opts).unwrap();
    for d in [d, d2] {
        out.push(d.distance.to_bits());
        for v in [d.closest1, d.closest2, d.normal] {
            out.extend(v.iter().map(|x| x.to_bits()));
        }
        out.push(d.iterations as u64);
        out.push(status(d.status));
    }
    out.extend(dg.iter().map(|x| x.to_bits()));
    out
}

#[test]
fn eight_threads_bit_identical_to_single_thread() {
    let mut rng = Rng(0xC0C0_0006);
    let shapes = Arc::new(shapes(&mut rng));
    // Thousands of pairs in release mode (CI); fewer in an unoptimised build.
    let n = if cfg!(debug_assertions) { 200 } else { 1500 };
    let n_shapes = shapes.len() - 1; // all but the 256-facet polytope
    let pairs = Arc::new(pairs(&mut rng, n_shapes, n));
    let opts = Options::default();
    // Make sure the scratch path is really exercised: some pair has > 32 orthant rows.
    assert!(pairs.iter().any(|p| p.i >= 8 || p.j >= 8));

    let expected: Vec<Vec<u64>> = pairs.iter().map(|p| evaluate(&shapes, p, &opts)).collect();

    let handles: Vec<_> = (0..THREADS)
        .map(|t| {
            let shapes = Arc::clone(&shapes);
            let pairs = Arc::clone(&pairs);
            std::thread::spawn(move || {
                // Thread t visits every pair once, from its own starting point, forwards (even
                // t) or backwards (odd t).
                let n = pairs.len();
                let start = t * n / THREADS;
                let mut got = vec![Vec::new(); n];
                for k in 0..n {
                    let idx = if t % 2 == 0 {
                        (start + k) % n
                    } else {
                        (start + n - k) % n
                    };
                    got[idx] = evaluate(&shapes, &pairs[idx], &opts);
                }
                got
            })
        })
        .collect();

    for (t, h) in handles.into_iter().enumerate() {
        let got = h.join().expect("a query thread panicked");
        for (k, (g, e)) in got.iter().zip(&expected).enumerate() {
            assert!(!g.is_empty(), "thread {t} did not evaluate pair {k}");
            assert_eq!(
                g, e,
                "thread {t}, pair {k} (shapes {} and {}): result differs from the \
                 single-threaded run",
                pairs[k].i, pairs[k].j
            );
        }
    }
}

/// Scoped threads sharing plain references (no Arc), all querying the 256-facet polytope so
/// that every thread's scratch buffer is in use at the same time.
#[test]
fn scoped_threads_share_large_polytope() {
    let mut rng = Rng(0x5C09_ED00);
    let shapes = shapes(&mut rng);
    let n = if cfg!(debug_assertions) { 16 } else { 120 };
    let mut pairs = pairs(&mut rng, shapes.len(), n);
    for (k, p) in pairs.iter_mut().enumerate() {
        p.i = 10;
        p.j = [7, 8, 9, 10, 0, 6][k % 6];
    }
    let opts = Options::default();
    let expected: Vec<Vec<u64>> = pairs.iter().map(|p| evaluate(&shapes, p, &opts)).collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..THREADS)
            .map(|t| {
                let (shapes, pairs, expected) = (&shapes, &pairs, &expected);
                scope.spawn(move || {
                    for k in 0..pairs.len() {
                        let idx = (k * 7 + t * 13) % pairs.len();
                        let got = evaluate(shapes, &pairs[idx], &opts);
                        assert_eq!(got, expected[idx], "thread {t}, pair {idx}");
                    }
                })
            })
            .collect();
        for h in handles {
            h.join().expect("a query thread panicked");
        }
    });
}
