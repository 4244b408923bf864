//! The per-pair warm-start cache (`dcol::Cache`, `dcol_*_cached`): on trajectories (pairs
//! moving 1 mm and 1° per step) the cached queries give the cold queries' answers, and the
//! cache is used (between polytopes, most answers come from it); a cache of another pair, or
//! holding any bit pattern at all, gives the cold answer.

use dcol::ffi::cache::dcol_cache;
use dcol::ffi::early_exit::{dcol_intersect, dcol_intersect_cached};
use dcol::ffi::pose::dcol_pose;
use dcol::ffi::proximity::{dcol_proximity, dcol_proximity_cached, dcol_proximity_result};
use dcol::ffi::shape::{dcol_shape_free, dcol_shape_new_box, dcol_shape_new_convex_hull};
use dcol::ffi::status::dcol_status;
use dcol::{
    contact_manifold, contact_manifold_cached, derivatives, derivatives_cached, distance_gradient,
    distance_gradient_cached, gradient, gradient_cached, intersect, intersect_cached, jacobian,
    jacobian_cached, proximity, proximity_cached, signed_distance, signed_distance_cached, Cache,
    DecidedBy, DistancePath, Options, Pose, Proximity, Shape, Solver,
};

const OK: dcol_status = dcol_status::DCOL_OK;

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
    fn unit<const N: usize>(&mut self) -> [f64; N] {
        loop {
            let v = [0; N].map(|_| self.uniform(-1.0, 1.0));
            let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return v.map(|x| x / n);
            }
        }
    }
}

fn shapes(rng: &mut Rng) -> Vec<(&'static str, Shape)> {
    let hull: Vec<[f64; 3]> = (0..30)
        .map(|_| {
            let d: [f64; 3] = rng.unit();
            let r = rng.uniform(0.4, 0.6);
            [d[0] * r * 1.2, d[1] * r, d[2] * r * 0.8]
        })
        .collect();
    let normals: Vec<[f64; 3]> = (0..14).map(|_| rng.unit()).collect();
    let offsets: Vec<f64> = (0..14).map(|_| rng.uniform(0.4, 0.6)).collect();
    let poly_a = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.6, 0.8]];
    let poly_b = [0.5, 0.4, 0.45, 0.5, 0.55];
    vec![
        ("box", Shape::cuboid(0.5, 0.35, 0.25).unwrap()),
        ("polytope", Shape::polytope(&normals, &offsets).unwrap()),
        ("hull", Shape::convex_hull(&hull, 0.0).unwrap()),
        ("sphere", Shape::sphere(0.4).unwrap()),
        ("capsule", Shape::capsule(0.25, 0.8).unwrap()),
        ("cylinder", Shape::cylinder(0.3, 0.9).unwrap()),
        ("cone", Shape::cone(1.0, 0.5).unwrap()),
        ("polygon", Shape::polygon(&poly_a, &poly_b, 0.05).unwrap()),
        ("padded hull", Shape::convex_hull(&hull, 0.05).unwrap()),
    ]
}

fn qmul(p: [f64; 4], q: [f64; 4]) -> [f64; 4] {
    [
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    ]
}

/// A trajectory of `steps` poses of the pair: shape 2 starts where α* = `start` and moves
/// 1 mm per step (reversing every 150 steps), both turn 1° per step about their own axes.
fn trajectory(a: &Shape, b: &Shape, rng: &mut Rng, steps: usize, start: f64) -> Vec<(Pose, Pose)> {
    let turn = |axis: [f64; 3]| {
        let h = 1f64.to_radians() / 2.0;
        [
            h.cos(),
            axis[0] * h.sin(),
            axis[1] * h.sin(),
            axis[2] * h.sin(),
        ]
    };
    let (mut q1, mut q2): ([f64; 4], [f64; 4]) = (rng.unit(), rng.unit());
    let (w1, w2) = (turn(rng.unit()), turn(rng.unit()));
    let d: [f64; 3] = rng.unit();
    let trial = d.map(|x| x * (a.bounding_radius() + b.bounding_radius()));
    let alpha = proximity(
        a,
        &Pose::new([0.0; 3], q1).unwrap(),
        b,
        &Pose::new(trial, q2).unwrap(),
        &Options::default(),
    )
    .unwrap()
    .alpha;
    let mut r2 = trial.map(|x| x * start / alpha);
    let mut v = rng.unit::<3>().map(|x| x * 1e-3);
    let mut out = Vec::with_capacity(steps);
    for k in 0..steps {
        // Quaternions of any length (as a caller may pass them): the same rotations.
        let (s1, s2) = (0.7 + 0.6 * rng.next(), 0.7 + 0.6 * rng.next());
        out.push((
            Pose::new([0.0; 3], q1.map(|x| x * s1)).unwrap(),
            Pose::new(r2, q2.map(|x| x * s2)).unwrap(),
        ));
        if k % 150 == 149 {
            v = v.map(|x| -x);
        }
        r2 = [r2[0] + v[0], r2[1] + v[1], r2[2] + v[2]];
        q1 = qmul(w1, q1);
        q2 = qmul(w2, q2);
    }
    out
}

/// x* and the contact points of a cached answer agree with the cold one's to this (units of ℓ):
/// both are certified by a bracket on α* of 1e-12 relative, which pins the points of a curved
/// contact to about 1e-11 ℓ (the cross-check against `../shared/reference` finds x* within
/// 1.2e-11 ℓ of the oracle), not to the bracket's width.
const POINTS: f64 = 1e-11;

fn ell(a: &Shape, b: &Shape) -> f64 {
    a.bounding_radius().max(b.bounding_radius())
}

/// The largest difference between two answers: α* relative, the points in units of ℓ.
fn difference(x: &Proximity, y: &Proximity, ell: f64) -> (f64, f64) {
    let da = (x.alpha - y.alpha).abs() / y.alpha.abs().max(1e-300);
    let dp = [
        (x.point, y.point),
        (x.contact1, y.contact1),
        (x.contact2, y.contact2),
    ]
    .iter()
    .map(|(p, q)| (p - q).norm() / ell)
    .fold(0.0, f64::max);
    (da, dp)
}

/// ≥ 100 000 trajectory steps over every ordered pair of nine kinds: the cached proximity
/// agrees with the cold one to 1e-12 in α* (relative) and to [`POINTS`] in x* and the
/// contact points; between polytopes most answers are warm (`Solver::Polish` where the cold
/// path's ray cast answers).
#[test]
fn cached_proximity_agrees_with_cold_on_trajectories() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let (mut steps, mut worst_a, mut worst_p) = (0usize, 0.0f64, 0.0f64);
    let (mut polytope_steps, mut warm) = (0usize, 0usize);
    for (na, a) in &kinds {
        for (nb, b) in &kinds {
            for start in [0.7, 1.0, 1.4] {
                let mut cache = Cache::new();
                for (p, q) in trajectory(a, b, &mut rng, 450, start) {
                    let cold = proximity(a, &p, b, &q, &o).unwrap();
                    let hot = proximity_cached(a, &p, b, &q, &o, &mut cache).unwrap();
                    let (da, dp) = difference(&hot, &cold, ell(a, b));
                    assert!(
                        da <= 1e-12 && dp <= POINTS,
                        "{na}-{nb} step {steps}: alpha {da:e}, points {dp:e} ({:?} vs {:?})",
                        hot.solver,
                        cold.solver
                    );
                    assert_eq!(hot.status, cold.status);
                    worst_a = worst_a.max(da);
                    worst_p = worst_p.max(dp);
                    steps += 1;
                    let polytopes = ["box", "polytope", "hull"];
                    if polytopes.contains(na) && polytopes.contains(nb) {
                        polytope_steps += 1;
                        warm += usize::from(
                            hot.solver == Solver::Polish && cold.solver != Solver::Polish,
                        );
                    }
                }
            }
        }
    }
    assert!(steps >= 100_000, "{steps} steps");
    let share = warm as f64 / polytope_steps as f64;
    assert!(
        share > 0.5,
        "only {warm} of {polytope_steps} polytope steps were warm"
    );
    eprintln!(
        "{steps} steps: alpha within {worst_a:.1e}, points within {worst_p:.1e} l; \
         {warm} of {polytope_steps} polytope steps warm"
    );
}

/// The cached gradient, Jacobian and derivatives give the cold ones (1e-12 on α*, 1e-9
/// relative to the largest entry on the derivatives) on trajectories between polytopes, where
/// the cache answers.
#[test]
fn cached_derivatives_agree_with_cold() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let close = |x: &[f64], y: &[f64]| {
        let scale = y.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
        x.iter()
            .zip(y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max)
            / scale
    };
    for (na, a) in &kinds[..3] {
        for (nb, b) in &kinds[..3] {
            let (mut c1, mut c2, mut c3) = (Cache::new(), Cache::new(), Cache::new());
            for (k, (p, q)) in trajectory(a, b, &mut rng, 400, 1.1).into_iter().enumerate() {
                let (pc, gc) = gradient(a, &p, b, &q, &o).unwrap();
                let (pw, gw) = gradient_cached(a, &p, b, &q, &o, &mut c1).unwrap();
                assert!(difference(&pw, &pc, ell(a, b)).0 <= 1e-12, "{na}-{nb} {k}");
                assert!(
                    close(&gw, &gc) <= 1e-9,
                    "{na}-{nb} {k}: gradient {:e}",
                    close(&gw, &gc)
                );
                assert_eq!(pw.derivatives, pc.derivatives);
                let (_, jc) = jacobian(a, &p, b, &q, &o).unwrap();
                let (_, jw) = jacobian_cached(a, &p, b, &q, &o, &mut c2).unwrap();
                let (jc, jw) = (jc.concat(), jw.concat());
                assert!(
                    close(&jw, &jc) <= 1e-9,
                    "{na}-{nb} {k}: jacobian {:e}",
                    close(&jw, &jc)
                );
                let dc = derivatives(a, &p, b, &q, &o).unwrap();
                let dw = derivatives_cached(a, &p, b, &q, &o, &mut c3).unwrap();
                let (x, y) = (dw.dcontact1.concat(), dc.dcontact1.concat());
                assert!(close(&x, &y) <= 1e-9, "{na}-{nb} {k}: contact jacobian");
            }
        }
    }
}

/// One cache carried across different pairs, and caches filled with random bits through the
/// C ABI: every answer is the cold one.
#[test]
fn any_cache_gives_the_cold_answer() {
    let mut rng = Rng(0xdead_beef_cafe_f00d);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let mut shared = Cache::new();
    let trajs: Vec<_> = (0..kinds.len())
        .map(|i| {
            trajectory(
                &kinds[i].1,
                &kinds[(i + 1) % kinds.len()].1,
                &mut rng,
                200,
                1.0,
            )
        })
        .collect();
    for k in 0..200 {
        for (i, t) in trajs.iter().enumerate() {
            let (a, b) = (&kinds[i].1, &kinds[(i + 1) % kinds.len()].1);
            let (p, q) = &t[k];
            let cold = proximity(a, p, b, q, &o).unwrap();
            let hot = proximity_cached(a, p, b, q, &o, &mut shared).unwrap();
            let (da, dp) = difference(&hot, &cold, ell(a, b));
            assert!(
                da <= 1e-12 && dp <= POINTS,
                "pair {i} step {k}: {da:e} {dp:e}"
            );
        }
    }
    // Random bits, and random bits in a cache that was warm for the pair.
    let pose = |p: &Pose| dcol_pose {
        position: [p.position().x, p.position().y, p.position().z],
        quaternion: p.quaternion(),
    };
    // The box and the hull of `shapes`, made through the C constructors.
    let (a, b) = (&kinds[0].1, &kinds[2].1);
    let hull: Vec<f64> = b.parameters()[..b.parameter_count() - 1].to_vec();
    let (mut ca, mut cb) = (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: valid out-pointers; `hull` holds n × 3 doubles.
    unsafe {
        assert_eq!(dcol_shape_new_box(0.5, 0.35, 0.25, &mut ca), OK);
        assert_eq!(
            dcol_shape_new_convex_hull(hull.as_ptr(), hull.len() / 3, 0.0, &mut cb),
            OK
        );
    }
    let t = trajectory(a, b, &mut rng, 300, 1.0);
    let mut warm = dcol_cache::default();
    for (k, (p, q)) in t.iter().enumerate() {
        let mut garbage = warm;
        let bits = (rng.next() * 14.0) as usize;
        if k % 2 == 0 {
            for w in garbage.words.iter_mut() {
                *w = (rng.next() * 4.3e9) as u32;
            }
            for x in garbage.numbers.iter_mut() {
                *x = f64::from_bits((rng.next() * 1.8e19) as u64);
            }
        } else {
            // A few words of a warm cache flipped (plausible ids, other features).
            garbage.words[bits] ^= 1 << (k % 5);
            garbage.numbers[bits * 2] *= -1.0;
        }
        let (pp, pq) = (pose(p), pose(q));
        let mut cold = dcol_proximity_result::default();
        let mut hot = dcol_proximity_result::default();
        let mut unused = dcol_proximity_result::default();
        // SAFETY: live shapes (`dcol_shape` is the C name of `Shape`), valid poses, results
        // and caches on the stack.
        unsafe {
            assert_eq!(
                dcol_proximity(ca, &pp, cb, &pq, std::ptr::null(), &mut cold),
                OK
            );
            assert_eq!(
                dcol_proximity_cached(ca, &pp, cb, &pq, std::ptr::null(), &mut garbage, &mut hot),
                OK
            );
            assert_eq!(
                dcol_proximity_cached(ca, &pp, cb, &pq, std::ptr::null(), &mut warm, &mut unused),
                OK
            );
        }
        assert!(
            (hot.alpha - cold.alpha).abs() <= 1e-12 * cold.alpha,
            "step {k}"
        );
        for i in 0..3 {
            assert!(
                (hot.point[i] - cold.point[i]).abs() <= 1e-12 * ell(a, b),
                "step {k}"
            );
        }
    }
    // A NULL cache is an error, and nothing is written.
    let (pp, pq) = (pose(&t[0].0), pose(&t[0].1));
    let mut r = dcol_proximity_result::default();
    // SAFETY: as above; the cache is NULL on purpose.
    let status = unsafe {
        dcol_proximity_cached(
            ca,
            &pp,
            cb,
            &pq,
            std::ptr::null(),
            std::ptr::null_mut(),
            &mut r,
        )
    };
    assert_eq!(status, dcol_status::DCOL_ERROR_NULL_POINTER);
    assert_eq!(r, dcol_proximity_result::default());
    // SAFETY: made above, freed once.
    unsafe {
        dcol_shape_free(ca);
        dcol_shape_free(cb);
    }
}

/// The cached distance and its gradient give the cold ones on trajectories over every ordered
/// pair of the nine kinds (distance and witnesses within 1e-12 ℓ, the gradient within 1e-9 of
/// its largest entry), and between polytopes most separated steps are warm (GJK's path is
/// `Gjk`, the cache's `GjkPolish`).
#[test]
fn cached_distance_agrees_with_cold_on_trajectories() {
    let mut rng = Rng(0x51f1_5eed_0bad_cafe);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let (mut steps, mut worst, mut worst_g) = (0usize, 0.0f64, 0.0f64);
    let (mut polytope_steps, mut warm) = (0usize, 0usize);
    for (na, a) in &kinds {
        for (nb, b) in &kinds {
            let l = ell(a, b);
            for start in [1.05, 1.5] {
                let mut cache = Cache::new();
                for (p, q) in trajectory(a, b, &mut rng, 300, start) {
                    let (cold, gc) = distance_gradient(a, &p, b, &q, &o).unwrap();
                    let (hot, gw) = distance_gradient_cached(a, &p, b, &q, &o, &mut cache).unwrap();
                    let dd = (hot.distance - cold.distance).abs() / l;
                    let dw = ((hot.closest1 - cold.closest1).norm() / l)
                        .max((hot.closest2 - cold.closest2).norm() / l);
                    let scale = gc.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
                    let dg = gw
                        .iter()
                        .zip(&gc)
                        .map(|(x, y)| (x - y).abs())
                        .fold(0.0, f64::max)
                        / scale;
                    assert!(
                        dd <= 1e-12 && dw <= 1e-12 && dg <= 1e-9,
                        "{na}-{nb} step {steps}: distance {dd:e}, witnesses {dw:e}, gradient {dg:e} \
                         ({:?} vs {:?})",
                        hot.path,
                        cold.path
                    );
                    worst = worst.max(dd.max(dw));
                    worst_g = worst_g.max(dg);
                    steps += 1;
                    let polytopes = ["box", "polytope", "hull"];
                    if polytopes.contains(na) && polytopes.contains(nb) && cold.distance > 0.0 {
                        polytope_steps += 1;
                        warm += usize::from(
                            hot.path == DistancePath::GjkPolish && cold.path == DistancePath::Gjk,
                        );
                    }
                }
            }
        }
    }
    let share = warm as f64 / polytope_steps as f64;
    assert!(
        share > 0.5,
        "only {warm} of {polytope_steps} separated polytope steps were warm"
    );
    eprintln!(
        "{steps} steps: distance and witnesses within {worst:.1e} l, gradient {worst_g:.1e}; \
         {warm} of {polytope_steps} separated polytope steps warm"
    );
}

/// The cached signed distance and contact manifold give the cold ones on trajectories over
/// every ordered pair of the nine kinds, separated and overlapping (signed distance within
/// 1e-12 ℓ, the same number of contact points, each within 1e-9 ℓ and its depth within 1e-9 ℓ
/// of the cold one's); between separated polytopes most signed distances come from the cache
/// (`DistancePath::GjkPolish` where the cold one is GJK's).
#[test]
fn cached_signed_distance_and_contacts_agree_with_cold() {
    let mut rng = Rng(0x0dd5_eed5_1234_5678);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let (mut steps, mut warm, mut polytope_apart) = (0usize, 0usize, 0usize);
    for (na, a) in &kinds {
        for (nb, b) in &kinds {
            let l = ell(a, b);
            for start in [0.8, 1.3] {
                let (mut c1, mut c2) = (Cache::new(), Cache::new());
                for (p, q) in trajectory(a, b, &mut rng, 200, start) {
                    let cold = signed_distance(a, &p, b, &q, &o).unwrap();
                    let hot = signed_distance_cached(a, &p, b, &q, &o, &mut c1).unwrap();
                    let dd = (hot.distance - cold.distance).abs() / l;
                    assert!(
                        dd <= 1e-12,
                        "{na}-{nb} step {steps}: {dd:e} ({:?} vs {:?})",
                        hot.path,
                        cold.path
                    );
                    let margin = 0.05 * l;
                    let mc = contact_manifold(a, &p, b, &q, margin, 8, &o).unwrap();
                    let mw = contact_manifold_cached(a, &p, b, &q, margin, 8, &o, &mut c2).unwrap();
                    assert_eq!(mw.len(), mc.len(), "{na}-{nb} step {steps}");
                    assert!((mw.signed_distance - mc.signed_distance).abs() <= 1e-12 * l);
                    for (x, y) in mw.contacts().iter().zip(mc.contacts()) {
                        assert!(
                            (x.position - y.position).norm() <= 1e-9 * l,
                            "{na}-{nb} step {steps}"
                        );
                        assert!((x.depth - y.depth).abs() <= 1e-9 * l);
                    }
                    steps += 1;
                    let polytopes = ["box", "polytope", "hull"];
                    if polytopes.contains(na) && polytopes.contains(nb) && cold.distance > 0.0 {
                        polytope_apart += 1;
                        warm += usize::from(
                            hot.path == DistancePath::GjkPolish && cold.path == DistancePath::Gjk,
                        );
                    }
                }
            }
        }
    }
    assert!(
        warm * 2 > polytope_apart,
        "{warm} of {polytope_apart} separated polytope steps warm"
    );
    eprintln!("{steps} steps; {warm} of {polytope_apart} separated polytope signed distances warm");
}

/// The cached intersection test gives the cold one's decision on every step of trajectories over
/// every ordered pair of the nine kinds, separated, crossing α* = 1 and overlapping (with the
/// default tolerance, and with 1e-5 on the touching start); both agree with α* < 1 from the full
/// proximity wherever α* is more than 1e-9 from 1; and most separated steps are decided by the
/// kept separating normal (`DecidedBy::Cache`).
#[test]
fn cached_intersect_agrees_with_cold_on_trajectories() {
    let mut rng = Rng(0x1a7e_25ec_7ca5_4ed1);
    let kinds = shapes(&mut rng);
    let loose = Options {
        tolerance: 1e-5,
        ..Options::default()
    };
    let (mut steps, mut apart, mut by_cache, mut crossings) = (0usize, 0usize, 0usize, 0usize);
    for (na, a) in &kinds {
        for (nb, b) in &kinds {
            for (start, o) in [
                (0.7, Options::default()),
                (1.0, Options::default()),
                (1.4, Options::default()),
                (1.0, loose),
            ] {
                let mut cache = Cache::new();
                let mut last = None;
                for (p, q) in trajectory(a, b, &mut rng, 300, start) {
                    let cold = intersect(a, &p, b, &q, &o).unwrap();
                    let hot = intersect_cached(a, &p, b, &q, &o, &mut cache).unwrap();
                    assert_eq!(
                        hot.below, cold.below,
                        "{na}-{nb} step {steps}: {hot:?} vs {cold:?}"
                    );
                    assert_eq!(hot.status, cold.status);
                    let alpha = proximity(a, &p, b, &q, &Options::default()).unwrap().alpha;
                    if (alpha - 1.0).abs() > 1e-9 {
                        assert_eq!(hot.below, alpha < 1.0, "{na}-{nb} step {steps}: {alpha}");
                    }
                    crossings += usize::from(last.is_some_and(|l| l != hot.below));
                    last = Some(hot.below);
                    steps += 1;
                    if !cold.below && cold.decided_by != DecidedBy::Bounds {
                        apart += 1;
                        by_cache += usize::from(hot.decided_by == DecidedBy::Cache);
                    }
                }
            }
        }
    }
    assert!(steps >= 90_000, "{steps} steps");
    assert!(crossings >= 50, "only {crossings} crossings of alpha* = 1");
    assert!(
        by_cache * 10 > apart * 8,
        "only {by_cache} of {apart} separated steps decided by the cache"
    );
    eprintln!(
        "{steps} steps, {crossings} crossings of alpha* = 1; {by_cache} of {apart} separated \
         steps (not decided by the bounds) decided by the cache"
    );
}

/// One cache carried across different pairs, caches of random bits and of flipped bits, through
/// Rust and the C ABI: the cold decision every time; a NULL cache is DCOL_ERROR_NULL_POINTER
/// with nothing written.
#[test]
fn any_cache_gives_the_cold_intersection() {
    let mut rng = Rng(0x7f4a_7c15_dead_0042);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let mut shared = Cache::new();
    let n = kinds.len();
    let trajs: Vec<_> = (0..n)
        .map(|i| trajectory(&kinds[i].1, &kinds[(i + 4) % n].1, &mut rng, 200, 1.0))
        .collect();
    for k in 0..200 {
        for (i, t) in trajs.iter().enumerate() {
            let (a, b) = (&kinds[i].1, &kinds[(i + 4) % n].1);
            let (p, q) = &t[k];
            let cold = intersect(a, p, b, q, &o).unwrap();
            let hot = intersect_cached(a, p, b, q, &o, &mut shared).unwrap();
            assert_eq!(hot.below, cold.below, "pair {i} step {k}");
        }
    }
    let pose = |p: &Pose| dcol_pose {
        position: [p.position().x, p.position().y, p.position().z],
        quaternion: p.quaternion(),
    };
    // The box and the hull of `shapes` through the C constructors, and in Rust every kind
    // against the hull.
    let hull_shape = &kinds[2].1;
    let hull: Vec<f64> = hull_shape.parameters()[..hull_shape.parameter_count() - 1].to_vec();
    let (mut ca, mut cb) = (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: valid out-pointers; `hull` holds n × 3 doubles.
    unsafe {
        assert_eq!(dcol_shape_new_box(0.5, 0.35, 0.25, &mut ca), OK);
        assert_eq!(
            dcol_shape_new_convex_hull(hull.as_ptr(), hull.len() / 3, 0.0, &mut cb),
            OK
        );
    }
    let mut garbage_rust = 0usize;
    for (na, a) in &kinds {
        let t = trajectory(a, hull_shape, &mut rng, 200, 1.0);
        let mut warm = Cache::new();
        for (k, (p, q)) in t.iter().enumerate() {
            let mut garbage = dcol_cache::default();
            // SAFETY: `Cache` and `dcol_cache` have one layout (asserted in the library), and
            // every bit pattern of their u32 and f64 fields is a value.
            let warm_c: dcol_cache = unsafe { std::mem::transmute(warm) };
            if k % 2 == 0 {
                for w in garbage.words.iter_mut() {
                    *w = (rng.next() * 4.3e9) as u32;
                }
                for x in garbage.numbers.iter_mut() {
                    *x = f64::from_bits((rng.next() * 1.8e19) as u64);
                }
            } else {
                garbage = warm_c;
                let bits = (rng.next() * 25.0) as usize;
                garbage.words[bits] ^= 1 << (k % 5);
                let at = (rng.next() * 70.0) as usize;
                garbage.numbers[at] = -garbage.numbers[at] * 1.5 + 0.25;
            }
            let cold = intersect(a, p, hull_shape, q, &o).unwrap();
            // SAFETY: as above.
            let mut g: Cache = unsafe { std::mem::transmute(garbage) };
            let hot = intersect_cached(a, p, hull_shape, q, &o, &mut g).unwrap();
            assert_eq!(hot.below, cold.below, "{na}-hull step {k}");
            intersect_cached(a, p, hull_shape, q, &o, &mut warm).unwrap();
            garbage_rust += 1;
            if *na == "box" {
                let (pp, pq) = (pose(p), pose(q));
                let (mut c, mut h) = (-1, -1);
                // SAFETY: live shapes, valid poses, outputs and cache on the stack.
                unsafe {
                    assert_eq!(
                        dcol_intersect(ca, &pp, cb, &pq, std::ptr::null(), &mut c),
                        OK
                    );
                    assert_eq!(
                        dcol_intersect_cached(
                            ca,
                            &pp,
                            cb,
                            &pq,
                            std::ptr::null(),
                            &mut garbage,
                            &mut h
                        ),
                        OK
                    );
                }
                assert_eq!((h, c), (i32::from(cold.below), i32::from(cold.below)));
            }
        }
    }
    assert_eq!(garbage_rust, 200 * kinds.len());
    let t = trajectory(&kinds[0].1, hull_shape, &mut rng, 1, 1.0);
    let (pp, pq) = (pose(&t[0].0), pose(&t[0].1));
    let mut out = 7;
    // SAFETY: as above; the cache is NULL on purpose.
    let status = unsafe {
        dcol_intersect_cached(
            ca,
            &pp,
            cb,
            &pq,
            std::ptr::null(),
            std::ptr::null_mut(),
            &mut out,
        )
    };
    assert_eq!(status, dcol_status::DCOL_ERROR_NULL_POINTER);
    assert_eq!(out, 7);
    // SAFETY: made above, freed once.
    unsafe {
        dcol_shape_free(ca);
        dcol_shape_free(cb);
    }
}

/// Random jumps (every step a new random pose of the pair, as far as 0.4–1.4 times the sum of
/// the bounding radii), then a trajectory, with one cache per query carried through both: every
/// answer is the cold one (α* within 1e-12 relative, the distance within 1e-12 ℓ, the same
/// decision); during the jumps the caches back off (most calls keep nothing: `is_warm` is
/// false after most of them), and on the trajectory after them the warm answers come back
/// within 33 steps (the back-off skips at most 31 calls) and answer most steps after that (of
/// the separated ones for the distance, of those the bounding spheres do not decide for the
/// intersection).
#[test]
fn caches_back_off_on_random_jumps_and_come_back() {
    let mut rng = Rng(0x0ba0_c0ff_1ee7_5eed);
    let kinds = shapes(&mut rng);
    let o = Options::default();
    let kind = |n: &str| kinds.iter().find(|k| k.0 == n).unwrap().1.clone();
    let (jumps, steps) = (300, 150);
    // Trajectories starting near enough touching that the bounding spheres do not decide most
    // intersections.
    for (na, nb, start) in [
        ("box", "hull", 1.1),
        ("polytope", "hull", 1.1),
        ("capsule", "cylinder", 1.02),
    ] {
        let (a, b) = (kind(na), kind(nb));
        let polytopes = nb == "hull";
        let (mut prox, mut dist, mut inter) = (Cache::new(), Cache::new(), Cache::new());
        let mut kept = [0usize; 3];
        let reach = a.bounding_radius() + b.bounding_radius();
        for _ in 0..jumps {
            let d: [f64; 3] = rng.unit();
            let s = rng.uniform(0.4, 1.4) * reach;
            let p = Pose::new([0.0; 3], rng.unit()).unwrap();
            let q = Pose::new(d.map(|x| x * s), rng.unit()).unwrap();
            let hot = proximity_cached(&a, &p, &b, &q, &o, &mut prox).unwrap();
            let cold = proximity(&a, &p, &b, &q, &o).unwrap();
            assert!(difference(&hot, &cold, ell(&a, &b)).0 <= 1e-12, "{na}-{nb}");
            let (hot, _) = distance_gradient_cached(&a, &p, &b, &q, &o, &mut dist).unwrap();
            let (cold, _) = distance_gradient(&a, &p, &b, &q, &o).unwrap();
            assert!((hot.distance - cold.distance).abs() <= 1e-12 * ell(&a, &b));
            let hot = intersect_cached(&a, &p, &b, &q, &o, &mut inter).unwrap();
            assert_eq!(hot.below, intersect(&a, &p, &b, &q, &o).unwrap().below);
            for (k, c) in [&prox, &dist, &inter].iter().enumerate() {
                kept[k] += usize::from(c.is_warm());
            }
        }
        // Without the back-off every separated jump's answer would be kept (the proximity's
        // and the distance's between polytopes, the intersection's normal of any pair).
        let caches = if polytopes { 0..3 } else { 2..3 };
        for k in caches {
            assert!(
                kept[k] * 5 < jumps,
                "{na}-{nb}: cache {k} kept {} of {jumps}",
                kept[k]
            );
        }
        // A trajectory from there: the caches answer again.
        let (mut first, mut warm, mut eligible) = ([usize::MAX; 3], [0usize; 3], [0usize; 3]);
        for (i, (p, q)) in trajectory(&a, &b, &mut rng, steps, start)
            .iter()
            .enumerate()
        {
            let hot = proximity_cached(&a, p, &b, q, &o, &mut prox).unwrap();
            let cold = proximity(&a, p, &b, q, &o).unwrap();
            assert!(
                difference(&hot, &cold, ell(&a, &b)).0 <= 1e-12,
                "{na}-{nb} step {i}"
            );
            let by_prox = hot.solver == Solver::Polish && cold.solver != Solver::Polish;
            let (hot, _) = distance_gradient_cached(&a, p, &b, q, &o, &mut dist).unwrap();
            let (cold, _) = distance_gradient(&a, p, &b, q, &o).unwrap();
            assert!((hot.distance - cold.distance).abs() <= 1e-12 * ell(&a, &b));
            let by_dist = hot.path == DistancePath::GjkPolish && cold.path == DistancePath::Gjk;
            let hot = intersect_cached(&a, p, &b, q, &o, &mut inter).unwrap();
            assert_eq!(hot.below, intersect(&a, p, &b, q, &o).unwrap().below);
            let counted = [
                true,
                cold.distance > 0.0,
                hot.decided_by != DecidedBy::Bounds,
            ];
            for (k, w) in [by_prox, by_dist, hot.decided_by == DecidedBy::Cache]
                .into_iter()
                .enumerate()
            {
                if w {
                    first[k] = first[k].min(i);
                }
                if i > 33 && counted[k] {
                    eligible[k] += 1;
                    warm[k] += usize::from(w);
                }
            }
        }
        let caches = if polytopes { 0..3 } else { 2..3 };
        for k in caches {
            assert!(
                first[k] <= 33 && warm[k] * 2 > eligible[k] && eligible[k] > 50,
                "{na}-{nb}: cache {k} warm from step {}, {} of {} steps",
                first[k],
                warm[k],
                eligible[k]
            );
        }
        eprintln!(
            "{na}-{nb}: kept after {jumps} jumps {kept:?}; warm from step {first:?}, then \
             {warm:?} of {eligible:?} steps"
        );
    }
}
