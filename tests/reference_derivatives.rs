//! Gradient and Jacobian against `dalpha_dconfig` and `jacobian` in every reference case that has
//! them (the repository's own set, and `../shared/reference` when present). Per the reference README: skip null entries; scale r-columns by ℓ and divide x-rows by
//! ℓ; require |J − J_ref| ≤ 1e-5·max(1, |J_ref|) (the finite-difference error of every kept entry
//! is ≤ 1e-6 in those units).

#![allow(clippy::needless_range_loop)] // entries are compared by index in lockstep

mod common;

use common::*;
use dcol::{gradient, jacobian, Options};
use std::collections::BTreeMap;

const TOL: f64 = 1e-5;

#[test]
fn derivatives_match_reference() {
    let sets = reference_sets();
    if sets.is_empty() {
        return; // DCOL_ALLOW_SKIP=1 and no data (see `common::own_dir`)
    }
    let opts = Options::default();
    let mut table: BTreeMap<String, (usize, f64, f64)> = BTreeMap::new();
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
                let entry = table.entry(key).or_insert((0, 0.0, 0.0));
                entry.0 += 1;
                let colscale = |c: usize| if c % 7 < 3 { ell } else { 1.0 };
                if let Some(g_ref) = case["dalpha_dconfig"].as_array() {
                    let (prox, g) = gradient(&s1, &p1, &s2, &p2, &opts).unwrap();
                    assert!(prox.status.is_converged(), "{id}");
                    for c in 0..14 {
                        let Some(r) = g_ref[c].as_f64() else { continue };
                        let err =
                            ((g[c] - r) * colscale(c)).abs() / (r * colscale(c)).abs().max(1.0);
                        entry.1 = entry.1.max(err);
                        if err > TOL {
                            failures
                                .push(format!("{id}: dalpha[{c}] {} vs {r} (err {err:e})", g[c]));
                        }
                    }
                }
                if let Some(j_ref) = case["jacobian"].as_array() {
                    let (_, j) = jacobian(&s1, &p1, &s2, &p2, &opts).unwrap();
                    for row in 0..4 {
                        let rs = if row < 3 { 1.0 / ell } else { 1.0 };
                        let jr = j_ref[row].as_array().unwrap();
                        for c in 0..14 {
                            let Some(r) = jr[c].as_f64() else { continue };
                            let k = rs * colscale(c);
                            let err = ((j[row][c] - r) * k).abs() / (r * k).abs().max(1.0);
                            entry.2 = entry.2.max(err);
                            if err > TOL {
                                failures.push(format!(
                                    "{id}: J[{row}][{c}] {} vs {r} (err {err:e})",
                                    j[row][c]
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    println!(
        "{:<40} {:>5} {:>12} {:>12}",
        "pair", "cases", "max dα err", "max J err"
    );
    for (k, (n, g, j)) in &table {
        println!("{k:<40} {n:>5} {g:>12.2e} {j:>12.2e}");
    }
    for f in failures.iter().take(30) {
        println!("FAIL {f}");
    }
    assert!(
        failures.is_empty(),
        "{} derivative entries failed",
        failures.len()
    );
}
