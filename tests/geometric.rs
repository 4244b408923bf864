//! The geometric path (closed forms, ray cast, polish) on every reference case: which solver
//! answered, per pair type, and the interior-point fallback's share (none on the random pair
//! groups, under 5 % on the stress group). Accuracy against the oracle is `tests/reference.rs`.

mod common;

use common::*;
use dcol::{proximity, Method, Options, Solver};
use std::collections::BTreeMap;

#[test]
fn fallback_share_per_pair_type() {
    let Some(dir) = reference_dir() else { return };
    // [closed form, ray cast, polish, interior point]
    let mut table: BTreeMap<String, [usize; 4]> = BTreeMap::new();
    let mut ipm_disagree = Vec::new();
    let ipm = Options {
        method: Method::InteriorPoint,
        ..Options::default()
    };
    for file in all_files(&dir) {
        for case in load(&file) {
            let stress = case["group"] == "stress";
            let key = if stress {
                format!("stress/{}", case["category"].as_str().unwrap())
            } else {
                format!(
                    "{}-{}",
                    case["shape1"]["kind"].as_str().unwrap(),
                    case["shape2"]["kind"].as_str().unwrap()
                )
            };
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            let p = proximity(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
            let slot = match p.solver {
                Solver::ClosedForm => 0,
                Solver::RayCast => 1,
                Solver::Polish => 2,
                Solver::InteriorPoint => 3,
            };
            table.entry(key).or_default()[slot] += 1;
            let q = proximity(&s1, &p1, &s2, &p2, &ipm).unwrap();
            assert!(matches!(
                q.solver,
                Solver::InteriorPoint | Solver::ClosedForm
            ));
            if q.status.is_converged() && (p.alpha - q.alpha).abs() > 1e-10 * q.alpha.max(1.0) {
                ipm_disagree.push(format!(
                    "{}: {} vs interior point {}",
                    case["id"], p.alpha, q.alpha
                ));
            }
        }
    }
    println!("| pair | closed form | ray cast | polish | interior point |");
    println!("|---|--:|--:|--:|--:|");
    let (mut random, mut random_ipm, mut stress, mut stress_ipm) = (0, 0, 0, 0);
    for (k, c) in &table {
        println!("| {k} | {} | {} | {} | {} |", c[0], c[1], c[2], c[3]);
        let n: usize = c.iter().sum();
        if k.starts_with("stress/") {
            stress += n;
            stress_ipm += c[3];
        } else {
            random += n;
            random_ipm += c[3];
        }
    }
    println!("random groups: {random_ipm} of {random} by the interior-point fallback");
    println!("stress group: {stress_ipm} of {stress} by the interior-point fallback");
    assert!(ipm_disagree.is_empty(), "{ipm_disagree:#?}");
    assert_eq!(random_ipm, 0, "the fallback answered random-group cases");
    assert!(
        (stress_ipm as f64) < 0.05 * stress as f64,
        "fallback share on the stress group {stress_ipm}/{stress}"
    );
}

#[test]
fn debug_gradient_vs_ipm() {
    let Some(dir) = reference_dir() else { return };
    let ipm = Options {
        method: Method::InteriorPoint,
        ..Options::default()
    };
    let mut worst = Vec::new();
    for file in all_files(&dir) {
        for case in load(&file) {
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            let (p, g) = dcol::gradient(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
            let (_, gi) = dcol::gradient(&s1, &p1, &s2, &p2, &ipm).unwrap();
            let e = g
                .iter()
                .zip(&gi)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / gi.iter().map(|v| v.abs()).fold(1.0, f64::max);
            if case["x_unique"].as_bool() == Some(true) {
                worst.push((
                    e,
                    case["id"].to_string(),
                    p.solver,
                    case["x_unique"].clone(),
                ));
            }
        }
    }
    worst.sort_by(|a, b| b.0.total_cmp(&a.0));
    for w in worst.iter().take(25) {
        println!("{:.2e} {} {:?} {}", w.0, w.1, w.2, w.3);
    }
}
