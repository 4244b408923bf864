//! Exact distance against `distance`, `closest1`, `closest2` in every reference case (the
//! repository's own set, and `../shared/reference` when present): within
//! 1e-8·ℓ of the reference on every separated case, exactly 0 for touching and overlapping
//! ones (d_ref = 0.0), witness points (only where `closest_unique`) within 1e-6·ℓ, and the
//! distance gradient against central finite differences of `distance` on separated cases.

#![allow(clippy::needless_range_loop)] // entries are compared by index in lockstep

mod common;

use common::*;
use dcol::{distance, distance_gradient, Options, Pose};
use std::collections::BTreeMap;

#[test]
fn distance_matches_reference() {
    let sets = reference_sets();
    if sets.is_empty() {
        return; // DCOL_ALLOW_SKIP=1 and no data (see `common::own_dir`)
    }
    let opts = Options::default();
    let mut table: BTreeMap<String, (usize, f64, f64, u32)> = BTreeMap::new();
    let mut failures = Vec::new();
    for set in &sets {
        for file in all_files(&set.dir) {
            for case in load(&file) {
                let key = if case["group"] == "stress" {
                    format!(
                        "{}: stress/{}",
                        set.name,
                        case["category"].as_str().unwrap()
                    )
                } else {
                    format!(
                        "{}: {}-{}",
                        set.name,
                        case["shape1"]["kind"].as_str().unwrap(),
                        case["shape2"]["kind"].as_str().unwrap()
                    )
                };
                let id = case["id"].as_str().unwrap().to_string();
                let ell = length_scale(&case);
                let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
                let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
                let d = distance(&s1, &p1, &s2, &p2, &opts).unwrap();
                let e = table.entry(key).or_insert((0, 0.0, 0.0, 0));
                e.0 += 1;
                e.3 = e.3.max(d.iterations);
                if !d.status.is_converged() {
                    failures.push(format!("{id}: status {:?}", d.status));
                    continue;
                }
                let d_ref = f(&case["distance"]);
                let err = (d.distance - d_ref).abs() / ell;
                e.1 = e.1.max(err);
                if d_ref == 0.0 {
                    if d.distance != 0.0 && err > 1e-8 {
                        failures.push(format!(
                            "{id}: distance {} for touching/overlap",
                            d.distance
                        ));
                    }
                    continue;
                }
                if err > 1e-8 {
                    failures.push(format!(
                        "{id}: distance {} vs {d_ref} (err {err:e} ℓ)",
                        d.distance
                    ));
                }
                if case["closest_unique"].as_bool() == Some(true) {
                    let ew = dist3(&v3(&case["closest1"]), &d.closest1)
                        .max(dist3(&v3(&case["closest2"]), &d.closest2))
                        / ell;
                    e.2 = e.2.max(ew);
                    if ew > 1e-6 {
                        failures.push(format!("{id}: witness off by {ew:e} ℓ"));
                    }
                }
            }
        }
    }
    println!(
        "{:<40} {:>5} {:>12} {:>12} {:>5}",
        "pair", "cases", "max|Δd|/ℓ", "max|Δw|/ℓ", "iters"
    );
    for (k, (n, d, w, it)) in &table {
        println!("{k:<40} {n:>5} {d:>12.2e} {w:>12.2e} {it:>5}");
    }
    for f in failures.iter().take(30) {
        println!("FAIL {f}");
    }
    assert!(
        failures.is_empty(),
        "{} distance checks failed",
        failures.len()
    );
}

#[test]
fn distance_gradient_matches_finite_differences() {
    let sets = reference_sets();
    if sets.is_empty() {
        return; // DCOL_ALLOW_SKIP=1 and no data (see `common::own_dir`)
    }
    let opts = Options::default();
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for set in &sets {
        // Every case of the repository's small set, every fifth of the shared one.
        let step = if set.name == "own" { 1 } else { 5 };
        for file in all_files(&set.dir) {
            for case in load(&file).into_iter().step_by(step) {
                if f(&case["distance"]) == 0.0 || case["closest_unique"].as_bool() != Some(true) {
                    continue;
                }
                let ell = length_scale(&case);
                let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
                let base = [pose(&case["pose1"]), pose(&case["pose2"])];
                let (_, g) = distance_gradient(&s1, &base[0], &s2, &base[1], &opts).unwrap();
                for c in 0..14 {
                    let (i, p) = (c / 7, c % 7);
                    let h = if p < 3 { 1e-6 * ell } else { 1e-6 };
                    let eval = |sign: f64| {
                        let mut r = [
                            base[i].position().x,
                            base[i].position().y,
                            base[i].position().z,
                        ];
                        let mut q = base[i].quaternion();
                        if p < 3 {
                            r[p] += sign * h;
                        } else {
                            q[p - 3] += sign * h;
                        }
                        let moved = Pose::new(r, q).unwrap();
                        let (a, b) = if i == 0 {
                            (&moved, &base[1])
                        } else {
                            (&base[0], &moved)
                        };
                        distance(&s1, a, &s2, b, &opts).unwrap().distance
                    };
                    let fd = (eval(1.0) - eval(-1.0)) / (2.0 * h);
                    let scale = if p < 3 { 1.0 } else { 1.0 / ell };
                    let err = ((g[c] - fd) * scale).abs() / (fd * scale).abs().max(1.0);
                    worst = worst.max(err);
                    assert!(
                        err < 1e-5,
                        "{}: column {c}: {} vs fd {fd}",
                        case["id"],
                        g[c]
                    );
                    checked += 1;
                }
            }
        }
    }
    println!("distance gradient: {checked} entries, max error {worst:e}");
    assert!(checked > 1000);
}
