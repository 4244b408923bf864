//! The threshold fast paths against the full answer: on every reference case (the repository's
//! own set, and `../shared/reference` when present), `alpha_below(t)`
//! equals `α_ref < t` for thresholds on both sides of α_ref outside a 1e-6 relative band, and
//! the closed-form bracket contains α_ref. Prints the iterations each regime needs with and
//! without the early exit.

mod common;

use common::*;
use dcol::{alpha_below, alpha_bounds, intersect, proximity, DecidedBy, Options};
use std::collections::BTreeMap;

#[test]
fn threshold_answers_match_reference() {
    let sets = reference_sets();
    if sets.is_empty() {
        return; // DCOL_ALLOW_SKIP=1 and no data (see `common::own_dir`)
    }
    let opts = Options::default();
    // regime -> (cases, full iterations, early iterations at t = 1, decided by bounds)
    let mut stats: BTreeMap<String, (usize, u64, u64, usize)> = BTreeMap::new();
    let mut failures = Vec::new();
    for file in sets.iter().flat_map(|s| all_files(&s.dir)) {
        for case in load(&file) {
            let id = case["id"].as_str().unwrap().to_string();
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            // `coincident` cases are α* = 0 up to the oracle's 1e-28 noise (reference README).
            let a_ref = if case["category"] == "coincident" {
                0.0
            } else {
                f(&case["alpha"])
            };
            let (lo, hi) = alpha_bounds(&s1, &p1, &s2, &p2);
            if !(lo <= a_ref * (1.0 + 1e-12) + 1e-300 && a_ref <= hi * (1.0 + 1e-12)) {
                failures.push(format!("{id}: bracket [{lo}, {hi}] misses {a_ref}"));
            }
            for t in [a_ref * (1.0 - 1e-6), a_ref * (1.0 + 1e-6), 0.5, 1.0, 2.0] {
                if t <= 0.0 || ((t - a_ref) / a_ref.max(1e-300)).abs() < 1e-6 * 0.99 {
                    continue;
                }
                let d = alpha_below(&s1, &p1, &s2, &p2, t, &opts).unwrap();
                if d.below != (a_ref < t) {
                    failures.push(format!(
                        "{id}: t = {t}: below = {} but α_ref = {a_ref}",
                        d.below
                    ));
                }
            }
            let category = case["category"].as_str().unwrap().to_string();
            let e = stats.entry(category).or_insert((0, 0, 0, 0));
            let full = proximity(&s1, &p1, &s2, &p2, &opts).unwrap();
            let quick = intersect(&s1, &p1, &s2, &p2, &opts).unwrap();
            e.0 += 1;
            e.1 += full.iterations as u64;
            e.2 += quick.iterations as u64;
            e.3 += (quick.decided_by == DecidedBy::Bounds) as usize;
        }
    }
    println!(
        "{:<18} {:>6} {:>12} {:>16} {:>12}",
        "regime", "cases", "full iters", "intersect iters", "by bounds"
    );
    for (k, (n, a, b, c)) in &stats {
        println!(
            "{k:<18} {n:>6} {:>12.2} {:>16.2} {:>11.1}%",
            *a as f64 / *n as f64,
            *b as f64 / *n as f64,
            100.0 * *c as f64 / *n as f64
        );
    }
    for f in failures.iter().take(20) {
        println!("FAIL {f}");
    }
    assert!(
        failures.is_empty(),
        "{} threshold answers wrong",
        failures.len()
    );
}

#[test]
fn threshold_rejects_bad_values() {
    let s = dcol::Shape::sphere(1.0).unwrap();
    let p = dcol::Pose::from_position([0.0; 3]).unwrap();
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            alpha_below(&s, &p, &s, &p, t, &Options::default()),
            Err(dcol::Error::InvalidOptions(_))
        ));
    }
}

#[test]
fn distance_cutoff_matches_reference() {
    let sets = reference_sets();
    if sets.is_empty() {
        return; // DCOL_ALLOW_SKIP=1 and no data (see `common::own_dir`)
    }
    let opts = Options::default();
    let mut failures = Vec::new();
    let mut checked = 0usize;
    for file in sets.iter().flat_map(|s| all_files(&s.dir)) {
        for case in load(&file) {
            let id = case["id"].as_str().unwrap().to_string();
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            let ell = length_scale(&case);
            let d_ref = f(&case["distance"]);
            for cut in [
                0.5 * d_ref,
                d_ref - 1e-6 * ell,
                d_ref + 1e-6 * ell,
                2.0 * d_ref + ell,
            ] {
                if cut < 0.0 {
                    continue;
                }
                match dcol::distance_within(&s1, &p1, &s2, &p2, cut, &opts).unwrap() {
                    None if d_ref > cut => {}
                    Some(d) if d_ref <= cut && (d.distance - d_ref).abs() <= 1e-8 * ell => {}
                    other => failures.push(format!("{id}: cutoff {cut}: {other:?} vs {d_ref}")),
                }
            }
            checked += 1;
        }
    }
    println!("distance_within checked on {checked} cases, 4 cut-offs each");
    for f in failures.iter().take(20) {
        println!("FAIL {f}");
    }
    assert!(
        failures.is_empty(),
        "{} cut-off answers wrong",
        failures.len()
    );
}

#[test]
fn distance_cutoff_rejects_bad_values() {
    let s = dcol::Shape::sphere(1.0).unwrap();
    let p = dcol::Pose::from_position([0.0; 3]).unwrap();
    for c in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            dcol::distance_within(&s, &p, &s, &p, c, &Options::default()),
            Err(dcol::Error::InvalidOptions(_))
        ));
    }
}

/// A sphere against a box, a capsule, a cylinder (and a rounded box, which takes the general
/// path), both orders, on random poses about the touching scale and random thresholds: the
/// threshold answer (decided without α* for the first three) equals `proximity(..).alpha < t`
/// outside a 1e-9 relative band around the tie.
#[test]
fn sphere_decisions_match_proximity() {
    use common::random::{hull_of, Rng};
    use dcol::{Pose, Shape};
    let mut rng = Rng::new(0xDEC1DE);
    let ball = Shape::sphere(0.35).unwrap();
    let rounded = {
        let mut r = Rng::new(7);
        hull_of(&mut r, 40, [0.5, 0.4, 0.3], 0.05)
    };
    let solids = [
        Shape::cuboid(0.6, 0.4, 0.3).unwrap(),
        Shape::capsule(0.25, 0.9).unwrap(),
        Shape::cylinder(0.4, 0.8).unwrap(),
        rounded,
    ];
    let opts = Options::default();
    let (mut checked, mut below) = (0usize, 0usize);
    for solid in &solids {
        for k in 0..8_000 {
            let dir = rng.unit::<3>();
            let reach = rng.range(0.3, 1.6);
            let p1 = Pose::new([rng.range(-1.0, 1.0), 0.2, -0.3], rng.quat()).unwrap();
            let r1 = p1.position();
            let p2 = Pose::new(
                [
                    r1.x + dir[0] * reach,
                    r1.y + dir[1] * reach,
                    r1.z + dir[2] * reach,
                ],
                rng.quat(),
            )
            .unwrap();
            let (s1, s2, q1, q2) = if k % 2 == 0 {
                (&ball, solid, &p1, &p2)
            } else {
                (solid, &ball, &p2, &p1)
            };
            let alpha = proximity(s1, q1, s2, q2, &opts).unwrap().alpha;
            for t in [1.0, rng.range(0.3, 2.5)] {
                if ((alpha - t) / t).abs() < 1e-9 {
                    continue;
                }
                let d = alpha_below(s1, q1, s2, q2, t, &opts).unwrap();
                assert_eq!(d.below, alpha < t, "{k}: alpha {alpha}, t {t}");
                if t == 1.0 {
                    assert_eq!(intersect(s1, q1, s2, q2, &opts).unwrap().below, alpha < 1.0);
                }
                checked += 1;
                below += usize::from(d.below);
            }
        }
    }
    assert!(
        checked > 60_000 && below > 15_000 && checked - below > 15_000,
        "{checked} {below}"
    );
}

/// Two boxes (decided by their 15 separating axes without α*), on random poses about the
/// touching scale, a third of them with equal or axis-swapped attitudes (parallel edges, left
/// to the general path): the threshold answer equals `proximity(..).alpha < t` outside a 1e-9
/// relative band.
#[test]
fn box_decisions_match_proximity() {
    use common::random::Rng;
    use dcol::Pose;
    let mut rng = Rng::new(0xB0B0);
    let (a, b) = (
        dcol::Shape::cuboid(0.6, 0.4, 0.3).unwrap(),
        dcol::Shape::cuboid(0.25, 0.5, 0.2).unwrap(),
    );
    let opts = Options::default();
    let (mut checked, mut below) = (0usize, 0usize);
    for k in 0..20_000 {
        let q1 = rng.quat();
        let q2 = match k % 3 {
            0 => q1,
            1 => {
                // q1 times a quarter turn about body x: every edge parallel to one of box 1's.
                let (c, s) = (0.5f64.sqrt(), 0.5f64.sqrt());
                let [w, x, y, z] = q1;
                [w * c - x * s, w * s + x * c, y * c + z * s, z * c - y * s]
            }
            _ => rng.quat(),
        };
        let dir = rng.unit::<3>();
        let reach = rng.range(0.3, 2.0);
        let p1 = Pose::new([0.1, -0.2, 0.3], q1).unwrap();
        let p2 = Pose::new(
            [
                0.1 + dir[0] * reach,
                -0.2 + dir[1] * reach,
                0.3 + dir[2] * reach,
            ],
            q2,
        )
        .unwrap();
        let alpha = proximity(&a, &p1, &b, &p2, &opts).unwrap().alpha;
        for t in [1.0, rng.range(0.3, 2.5)] {
            if ((alpha - t) / t).abs() < 1e-9 {
                continue;
            }
            let d = alpha_below(&a, &p1, &b, &p2, t, &opts).unwrap();
            assert_eq!(d.below, alpha < t, "{k}: alpha {alpha}, t {t}");
            checked += 1;
            below += usize::from(d.below);
        }
    }
    assert!(
        checked > 35_000 && below > 8_000 && checked - below > 8_000,
        "{checked} {below}"
    );
}

/// The same question at every scale from 1e-200 to 1e200 (a sphere against a box, capsule and
/// cylinder, and two boxes, posed at α* = 0.75 and 1.5 along a rotated offset): the decision
/// does not depend on the scale (the closed decisions compare squares of lengths, which
/// underflow below ~1e-154, and leave such scales to the general path, which must then be
/// right too: a box's vertices were once merged into one below ~1e-162, where a norm's squares
/// underflow, and its early exit said "not below" for α* = 0.75).
#[test]
fn decisions_hold_at_every_scale() {
    use dcol::{Pose, Shape};
    let q = [0.9, 0.1, -0.3, 0.2];
    let opts = Options::default();
    for e in (-200..=200).step_by(10) {
        let s = 10f64.powi(e);
        let ball = Shape::sphere(s).unwrap();
        let solids = [
            Shape::cuboid(s, 0.1 * s, 0.1 * s).unwrap(),
            Shape::capsule(0.1 * s, 1.8 * s).unwrap(),
            Shape::cylinder(0.1 * s, 2.0 * s).unwrap(),
        ];
        let boxes = (
            Shape::cuboid(s, 0.5 * s, 0.3 * s).unwrap(),
            Shape::cuboid(s, 0.1 * s, 0.1 * s).unwrap(),
        );
        let pairs = [
            (&ball, &solids[0]),
            (&ball, &solids[1]),
            (&ball, &solids[2]),
            (&boxes.0, &boxes.1),
        ];
        for (n, (a, b)) in pairs.into_iter().enumerate() {
            let p1 = Pose::new([0.0; 3], [1.0, 0.0, 0.0, 0.0]).unwrap();
            // α* at unit offset along the direction, then offsets that give 0.75 and 1.5.
            let dir = [0.8 * s, 0.5 * s, 0.3 * s];
            let unit = Pose::new(dir, q).unwrap();
            let a0 = proximity(a, &p1, b, &unit, &opts).unwrap().alpha;
            for target in [0.75, 1.5] {
                let k = target / a0;
                let p2 = Pose::new(dir.map(|v| v * k), q).unwrap();
                for (x, y, px, py) in [(a, b, &p1, &p2), (b, a, &p2, &p1)] {
                    let d = alpha_below(x, px, y, py, 1.0, &opts).unwrap();
                    assert_eq!(
                        d.below,
                        target < 1.0,
                        "pair {n}, scale 1e{e}, alpha* {target}"
                    );
                }
            }
        }
    }
}

/// Two boxes of size 1e-170, α* = 0.75: the general path answers "below" and proximity answers
/// by the ray cast (every vertex of such a box was merged into one, the norm's squares
/// underflowing, so the cast's first support point was wrong, the early exit said "not below"
/// and proximity fell back to the interior-point method).
#[test]
fn tiny_boxes_threshold() {
    use dcol::{Pose, Shape};
    let s = 1e-170;
    let a = Shape::cuboid(s, 0.5 * s, 0.3 * s).unwrap();
    let b = Shape::cuboid(s, 0.1 * s, 0.1 * s).unwrap();
    let p1 = Pose::new([0.0; 3], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let p2 = Pose::new([1.5 * s, 0.3 * s, 0.1 * s], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let opts = Options::default();
    let p = proximity(&a, &p1, &b, &p2, &opts).unwrap();
    assert!((p.alpha - 0.75).abs() < 1e-12, "{}", p.alpha);
    assert_eq!(p.solver, dcol::Solver::RayCast);
    assert!(alpha_below(&a, &p1, &b, &p2, 1.0, &opts).unwrap().below);
}
