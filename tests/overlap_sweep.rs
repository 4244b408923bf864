//! Every overlapping contact query answers: `signed_distance` and `contact_manifold` on random
//! overlapping poses of all 55 unordered pairs of the 10 bounded kinds (the 8 primitives, the
//! convex hull and the rounded hull of 8 to 24 points; random sizes over two
//! decades, aspect ratios up to 10, random attitudes, depths from grazing to nearly coincident
//! origins) end `Converged`, never with the certificate open, and with the witness points on
//! their shapes.
//!
//! `DCOL_OVERLAP_CASES` poses are drawn (default 10⁶), `DCOL_OVERLAP_SEED` seeds them. A pose's
//! depth is set through its α* (from `proximity`): uniform in (0, 1), its cube (deep), or
//! 10^U(−4, −1) (origins almost together). Checked on every case, against the shapes written
//! out independently (`common::oracle`): each witness lies on its shape's support plane at the
//! normal and not outside the shape (within 1e-9·ℓ), and `closest2 − closest1 = sd·n`.
//! Checked against a brute-force maximum over normals: every case that needed more support
//! calls than EPA's polytope on the stack holds (250), and one case in 1 000.

mod common;

use common::oracle::{brute, lower, polygon_vertices, polytope_vertices, Oracle, Posed};
use common::random::Rng;
use dcol::{
    contact_manifold, proximity, signed_distance, Options, Pose, Shape, SignedDistance,
    SolveStatus, Vec3,
};
use nalgebra::Matrix3;
use std::collections::BTreeMap;

const NAMES: [&str; 10] = [
    "sphere",
    "ellipsoid",
    "box",
    "polytope",
    "capsule",
    "cylinder",
    "cone",
    "polygon",
    "hull",
    "rounded-hull",
];

/// Support calls EPA makes on its stack polytope; answers that needed more are all checked.
const STACK_SUPPORTS: u32 = 250;

/// 10^U(−e, e).
fn spread(rng: &mut Rng, e: f64) -> f64 {
    10f64.powf(rng.range(-e, e))
}

/// A shape of kind `k` (the order of `NAMES`), size about `s`, aspect ratios up to 10, and its
/// oracle.
fn shape(rng: &mut Rng, k: usize, s: f64) -> (Shape, Oracle) {
    let len = |rng: &mut Rng| s * spread(rng, 0.5);
    let out = match k {
        0 => {
            let r = len(rng);
            (Shape::sphere(r), Oracle::Sphere(r))
        }
        1 => {
            let m = dcol::math::rotation_from_quaternion(rng.quat());
            let d = Vec3::new(len(rng), len(rng), len(rng));
            let inv = Matrix3::from_diagonal(&d.map(|v| 1.0 / (v * v)));
            let mut p = m * inv * m.transpose();
            p = (p + p.transpose()) * 0.5;
            let q = m * Matrix3::from_diagonal(&d.component_mul(&d)) * m.transpose();
            let rows = [0, 1, 2].map(|i| [0, 1, 2].map(|j| p[(i, j)]));
            (Shape::ellipsoid(rows), Oracle::Ellipsoid(p, q))
        }
        2 => {
            let h = [len(rng), len(rng), len(rng)];
            let a: Vec<Vec3> = (0..6)
                .map(|i| {
                    let mut r = Vec3::zeros();
                    r[i % 3] = if i < 3 { 1.0 } else { -1.0 };
                    r
                })
                .collect();
            let b: Vec<f64> = (0..6).map(|i| h[i % 3]).collect();
            let v = polytope_vertices(&a, &b);
            (Shape::cuboid(h[0], h[1], h[2]), Oracle::Polytope(a, b, v))
        }
        3 => {
            // A perturbed dodecahedron, stretched along the body axes (x = S y: rows A S⁻¹).
            let phi = (1.0 + 5f64.sqrt()) / 2.0;
            let st = [len(rng), len(rng), len(rng)];
            let mut a = Vec::with_capacity(12);
            for s1 in [1.0, -1.0] {
                for s2 in [1.0, -1.0] {
                    for v in [
                        [0.0, s1, s2 * phi],
                        [s1, s2 * phi, 0.0],
                        [s2 * phi, 0.0, s1],
                    ] {
                        let r = v.map(|c| c + rng.range(-0.15, 0.15));
                        a.push(Vec3::new(r[0] / st[0], r[1] / st[1], r[2] / st[2]));
                    }
                }
            }
            let b: Vec<f64> = (0..12).map(|_| rng.range(0.5, 1.2)).collect();
            let rows: Vec<[f64; 3]> = a.iter().map(|r| [r.x, r.y, r.z]).collect();
            let v = polytope_vertices(&a, &b);
            (Shape::polytope(&rows, &b), Oracle::Polytope(a, b, v))
        }
        4 => {
            let (r, l) = (len(rng), len(rng));
            (Shape::capsule(r, l), Oracle::Capsule(r, l))
        }
        5 => {
            let (r, l) = (len(rng), len(rng));
            (Shape::cylinder(r, l), Oracle::Cylinder(r, l))
        }
        6 => {
            let (h, b) = (len(rng), rng.range(0.1, 1.45));
            (Shape::cone(h, b), Oracle::Cone(h, b))
        }
        8 | 9 => {
            // 8 to 24 points on a stretched sphere (a fifth inside, some repeated), centred.
            let n = 8 + (rng.next_u64() % 17) as usize;
            let axes = Vec3::new(len(rng), len(rng), len(rng));
            let mut pts: Vec<Vec3> = Vec::with_capacity(n);
            while pts.len() < n {
                let p = Vec3::from(rng.unit::<3>()).component_mul(&axes);
                match if pts.len() < 4 {
                    9
                } else {
                    rng.next_u64() % 10
                } {
                    0 | 1 => pts.push(p * rng.range(0.0, 0.9)),
                    2 => pts.push(pts[rng.next_u64() as usize % pts.len()]),
                    _ => pts.push(p),
                }
            }
            let mean = pts.iter().sum::<Vec3>() / n as f64;
            let pts: Vec<Vec3> = pts.iter().map(|p| p - mean).collect();
            let r = if k == 8 {
                0.0
            } else {
                s * rng.range(0.05, 0.3)
            };
            let raw: Vec<[f64; 3]> = pts.iter().map(|p| [p.x, p.y, p.z]).collect();
            (Shape::convex_hull(&raw, r), Oracle::hull(pts, r))
        }
        _ => {
            let m = 3 + (rng.next_u64() % 6) as usize;
            let off = rng.range(0.0, std::f64::consts::TAU);
            let c: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let t =
                        off + std::f64::consts::TAU * (i as f64 + rng.range(-0.2, 0.2)) / m as f64;
                    [t.cos(), t.sin()]
                })
                .collect();
            let d: Vec<f64> = (0..m).map(|_| len(rng)).collect();
            let r = len(rng) * rng.range(0.05, 0.5);
            let w = polygon_vertices(&c, &d);
            (Shape::polygon(&c, &d, r), Oracle::Polygon(w, r))
        }
    };
    (out.0.expect("valid random shape"), out.1)
}

/// The overlapping poses' α*: uniform, cubed (deep), or nearly coincident origins.
fn target_alpha(rng: &mut Rng) -> f64 {
    match rng.next_u64() % 3 {
        0 => rng.range(0.0, 1.0),
        1 => rng.range(0.0, 1.0).powi(3),
        _ => 10f64.powf(rng.range(-4.0, -1.0)),
    }
    .max(1e-6)
}

/// The largest of: each witness's distance from its support plane at the normal, how far it
/// lies outside its shape, and the witness identity's residual (world units).
fn witness_error(sd: &SignedDistance, o1: &Posed, o2: &Posed) -> f64 {
    let n = sd.normal;
    let plane1 = (n.dot(&sd.closest1) - o1.h(&n)).abs();
    let plane2 = ((-n).dot(&sd.closest2) - o2.h(&-n)).abs();
    let identity = (sd.closest2 - sd.closest1 - n * sd.distance).norm();
    plane1
        .max(plane2)
        .max(identity)
        .max(o1.excess(&sd.closest1))
        .max(o2.excess(&sd.closest2))
}

#[derive(Default)]
struct Tally {
    cases: usize,
    sd_open: usize,
    contacts_open: usize,
    errors: usize,
    off_shape: usize,
    checked: usize,
    wrong: usize,
    /// Most support calls, worst witness error and worst brute-force difference (over ℓ).
    supports: u32,
    worst_witness: f64,
    worst_depth: f64,
}

/// Runs `n` overlapping cases of pair `(k1, k2)` from `seed`; failures are written to `notes`
/// (at most 20).
fn sweep(k1: usize, k2: usize, n: usize, seed: u64, notes: &mut Vec<String>) -> Tally {
    let opts = Options::default();
    let mut rng = Rng::new(seed);
    let mut t = Tally::default();
    // `DCOL_OVERLAP_VERBOSE=1` adds the shapes and poses to the notes.
    let verbose = std::env::var_os("DCOL_OVERLAP_VERBOSE").is_some();
    let mut note = |s: String, what: &dyn Fn() -> String| {
        if notes.len() < 20 {
            let more = if verbose { what() } else { String::new() };
            notes.push(format!(
                "{}-{} seed {seed:#x}: {s}{more}",
                NAMES[k1], NAMES[k2]
            ));
        }
    };
    // A pair of shapes serves 16 poses (constructing a polytope costs more than a query).
    let mut shapes = None;
    while t.cases < n {
        if t.cases % 16 == 0 || shapes.is_none() {
            let s = spread(&mut rng, 1.0);
            shapes = Some((shape(&mut rng, k1, s), shape(&mut rng, k2, s)));
        }
        let ((s1, or1), (s2, or2)) = shapes.as_ref().unwrap();
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        let r1 = [0; 3].map(|_| rng.range(-3.0, 3.0));
        let (q1, q2) = (rng.quat(), rng.quat());
        let u = rng.unit::<3>();
        let p1 = Pose::new(r1, q1).unwrap();
        let unit = Pose::new([r1[0] + u[0], r1[1] + u[1], r1[2] + u[2]], q2).unwrap();
        let a = proximity(s1, &p1, s2, &unit, &opts).unwrap();
        assert!(a.status.is_converged());
        let scale = target_alpha(&mut rng) / a.alpha;
        let p2 = Pose::new([0, 1, 2].map(|j| r1[j] + u[j] * scale), q2).unwrap();
        t.cases += 1;
        let case = t.cases;
        let what = || format!("; {s1:?} {p1:?} / {s2:?} {p2:?}");
        let sd = match signed_distance(s1, &p1, s2, &p2, &opts) {
            Ok(sd) => sd,
            Err(e) => {
                t.errors += 1;
                note(format!("case {case}: {e:?}"), &what);
                continue;
            }
        };
        t.supports = t.supports.max(sd.iterations);
        if sd.status != SolveStatus::Converged {
            t.sd_open += 1;
            note(
                format!(
                    "case {case}: sd {:e} ({:?}, {} supports) not converged, ℓ {ell:.3e}",
                    sd.distance, sd.path, sd.iterations
                ),
                &what,
            );
        }
        let (o1, o2) = (Posed::new(or1, &p1), Posed::new(or2, &p2));
        let w = witness_error(&sd, &o1, &o2) / ell;
        t.worst_witness = t.worst_witness.max(w);
        if w > 1e-9 {
            t.off_shape += 1;
            let n = sd.normal;
            note(
                format!(
                    "case {case}: witness off its shape by {w:.2e} ℓ ({:?}, {} supports): planes \
                 {:.1e} {:.1e}, outside {:.1e} {:.1e}, sd {:e}",
                    sd.path,
                    sd.iterations,
                    (n.dot(&sd.closest1) - o1.h(&n)) / ell,
                    ((-n).dot(&sd.closest2) - o2.h(&-n)) / ell,
                    o1.excess(&sd.closest1) / ell,
                    o2.excess(&sd.closest2) / ell,
                    sd.distance / ell
                ),
                &what,
            );
        }
        if sd.iterations > STACK_SUPPORTS || case % 1000 == 0 {
            t.checked += 1;
            let b = brute(&o1, &o2, &sd.normal, 4000);
            let at_n = lower(&o1, &o2, &sd.normal);
            let e = ((b - sd.distance).abs().max((at_n - sd.distance).abs())) / ell;
            t.worst_depth = t.worst_depth.max(e);
            if e > 1e-9 {
                t.wrong += 1;
                note(
                    format!(
                        "case {case}: sd {} vs brute force {b}, L(n) {at_n} ({:?}, {} supports)",
                        sd.distance, sd.path, sd.iterations
                    ),
                    &what,
                );
            }
        }
        let m = contact_manifold(s1, &p1, s2, &p2, 0.0, 4, &opts).unwrap();
        if m.status != SolveStatus::Converged {
            t.contacts_open += 1;
        }
    }
    t
}

#[test]
fn every_overlap_certifies() {
    let var = |name: &str, default: u64| -> u64 {
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let total = var("DCOL_OVERLAP_CASES", 1_000_000) as usize;
    let seed = var("DCOL_OVERLAP_SEED", 0x0E7A_5EED);
    let mut pairs: Vec<(usize, usize)> = (0..NAMES.len())
        .flat_map(|i| (i..NAMES.len()).map(move |j| (i, j)))
        .collect();
    let per = total.div_ceil(pairs.len());
    // `DCOL_OVERLAP_PAIR=2,5` replays one pair type's cases (box-cylinder) alone.
    if let Ok(v) = std::env::var("DCOL_OVERLAP_PAIR") {
        let k: Vec<usize> = v.split(',').map(|x| x.trim().parse().unwrap()).collect();
        pairs = vec![(k[0], k[1])];
    }
    // Two threads over the pair types (each pair type's cases come from its own seed).
    let results: Vec<(usize, usize, Tally, Vec<String>)> = std::thread::scope(|sc| {
        let handles: Vec<_> = (0..2)
            .map(|t| {
                let chunk: Vec<(usize, usize)> = pairs.iter().copied().skip(t).step_by(2).collect();
                sc.spawn(move || {
                    chunk
                        .into_iter()
                        .map(|(i, j)| {
                            let mut notes = Vec::new();
                            let s = seed ^ ((i as u64) << 40) ^ ((j as u64) << 32);
                            let tally = sweep(i, j, per, s, &mut notes);
                            (i, j, tally, notes)
                        })
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    let mut sum = Tally::default();
    let mut by_pair = BTreeMap::new();
    for (i, j, t, notes) in &results {
        sum.cases += t.cases;
        sum.sd_open += t.sd_open;
        sum.contacts_open += t.contacts_open;
        sum.errors += t.errors;
        sum.off_shape += t.off_shape;
        sum.checked += t.checked;
        sum.wrong += t.wrong;
        sum.supports = sum.supports.max(t.supports);
        sum.worst_witness = sum.worst_witness.max(t.worst_witness);
        sum.worst_depth = sum.worst_depth.max(t.worst_depth);
        if t.sd_open + t.contacts_open + t.errors + t.off_shape + t.wrong > 0 {
            by_pair.insert(
                format!("{}-{}", NAMES[*i], NAMES[*j]),
                [t.sd_open, t.contacts_open, t.errors, t.off_shape, t.wrong],
            );
        }
        for s in notes {
            println!("{s}");
        }
    }
    println!(
        "{} overlapping cases: signed distance not converged {}, contacts not converged {}, \
         errors {}, witnesses off their shapes {} (worst {:.2e} ℓ); most support calls {}; \
         against brute force {} checked, {} off by more than 1e-9 ℓ (worst {:.2e} ℓ)",
        sum.cases,
        sum.sd_open,
        sum.contacts_open,
        sum.errors,
        sum.off_shape,
        sum.worst_witness,
        sum.supports,
        sum.checked,
        sum.wrong,
        sum.worst_depth
    );
    println!("by pair [sd open, contacts open, errors, off shape, wrong]: {by_pair:?}");
    assert!(sum.cases >= per * pairs.len());
    assert!(
        sum.sd_open + sum.contacts_open + sum.errors + sum.off_shape + sum.wrong == 0,
        "{by_pair:?}"
    );
}
