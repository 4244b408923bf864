//! Shared test helpers: the reference sets (the repository's own `tests/data`, and
//! `../shared/reference` when it is present), reading their records, and building shapes and
//! poses from them.
//!
//! Skips: a test that cannot check what it promises fails, unless the environment variable
//! `DCOL_ALLOW_SKIP=1` asks for a skip. The repository's own data is always there, so on a
//! plain clone every accuracy test runs in full; `../shared/reference` is an extra cross-check
//! (required when `CI` is set).
#![allow(dead_code)]

pub mod oracle;
pub mod random;
pub mod xorshift;

use dcol::{Pose, Shape};
use serde_json::Value;
use std::path::PathBuf;

/// One set of reference cases: its name (for the tables) and its folder of `cases-*.jsonl`.
pub struct RefSet {
    pub name: &'static str,
    pub dir: PathBuf,
}

/// Whether `DCOL_ALLOW_SKIP=1` allows a test to skip what it cannot run.
pub fn skip_allowed() -> bool {
    std::env::var("DCOL_ALLOW_SKIP").is_ok_and(|v| v == "1")
}

/// The repository's own reference cases (`tests/data`, made by `tests/generate_reference.rs`).
/// Missing data fails the test unless `DCOL_ALLOW_SKIP=1`, which gives `None`.
pub fn own_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    if dir.join("cases-stress.jsonl").is_file() {
        return Some(dir);
    }
    if skip_allowed() {
        eprintln!(
            "not run, as DCOL_ALLOW_SKIP=1 allows: {} is missing",
            dir.display()
        );
        return None;
    }
    panic!(
        "{} is missing: regenerate it with `cargo test --release --test generate_reference -- --ignored` (or set DCOL_ALLOW_SKIP=1 to skip)",
        dir.display()
    );
}

/// The sets an accuracy test asserts on: the repository's own, then `../shared/reference` when
/// present. Under CI (`CI` set) the shared set must be there. Never empty unless
/// `DCOL_ALLOW_SKIP=1` allowed skipping the missing own data.
pub fn reference_sets() -> Vec<RefSet> {
    let mut sets = Vec::new();
    if let Some(dir) = own_dir() {
        sets.push(RefSet { name: "own", dir });
    }
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/reference");
    if shared.is_dir() {
        sets.push(RefSet {
            name: "shared",
            dir: shared,
        });
    } else if std::env::var_os("CI").is_some() {
        panic!("../shared/reference is missing, and CI always has it");
    } else {
        println!("(../shared/reference is not here: the cross-check against it did not run; the repository's own cases did)");
    }
    sets
}

/// All records of one JSON Lines file.
pub fn load(path: &std::path::Path) -> Vec<Value> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).expect("valid JSON line"))
        .collect()
}

/// Every reference file of a set: the 49 ordered pair files then `cases-stress.jsonl`.
pub fn all_files(dir: &std::path::Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy().to_string();
            n.starts_with("cases-") && n.ends_with(".jsonl")
        })
        .collect();
    v.sort();
    v
}

pub fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

pub fn v3(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("array");
    [f(&a[0]), f(&a[1]), f(&a[2])]
}

pub fn shape(v: &Value) -> Shape {
    let kind = v["kind"].as_str().unwrap();
    match kind {
        "sphere" => Shape::sphere(f(&v["R"])).unwrap(),
        "ellipsoid" => {
            let p = v["P"].as_array().unwrap();
            let row = |i: usize| v3(&p[i]);
            Shape::ellipsoid([row(0), row(1), row(2)]).unwrap()
        }
        "polytope" => {
            let a: Vec<[f64; 3]> = v["A"].as_array().unwrap().iter().map(v3).collect();
            let b: Vec<f64> = v["b"].as_array().unwrap().iter().map(f).collect();
            Shape::polytope(&a, &b).unwrap()
        }
        "capsule" => Shape::capsule(f(&v["R"]), f(&v["L"])).unwrap(),
        "cylinder" => Shape::cylinder(f(&v["R"]), f(&v["L"])).unwrap(),
        "cone" => Shape::cone(f(&v["H"]), f(&v["beta"])).unwrap(),
        "padded_polygon" => {
            let c: Vec<[f64; 2]> = v["C"]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| {
                    let a = r.as_array().unwrap();
                    [f(&a[0]), f(&a[1])]
                })
                .collect();
            let d: Vec<f64> = v["d"].as_array().unwrap().iter().map(f).collect();
            Shape::polygon(&c, &d, f(&v["R"])).unwrap()
        }
        other => panic!("unknown kind {other}"),
    }
}

pub fn pose(v: &Value) -> Pose {
    let q = v["q"].as_array().unwrap();
    Pose::new(v3(&v["r"]), [f(&q[0]), f(&q[1]), f(&q[2]), f(&q[3])]).unwrap()
}

/// A case's length scale ℓ.
pub fn length_scale(case: &Value) -> f64 {
    f(&case["solver_notes"]["length_scale"])
}

pub fn dist3(a: &[f64; 3], b: &dcol::Vec3) -> f64 {
    ((a[0] - b.x).powi(2) + (a[1] - b.y).powi(2) + (a[2] - b.z).powi(2)).sqrt()
}
