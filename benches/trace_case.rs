// Development aid for solver work: `cargo bench --bench trace_case -- FILE INDEX` solves one
// reference case (`tests/data/*.jsonl` or `../shared/reference/*.jsonl`) and
// prints the result beside the reference α* (`DCOL_TOL` sets the tolerance); `trace_case time FILE...` (or `timejac`) prints the
// median time of proximity (or jacobian, `timegrad`: gradient) over reference files. Pair it with
// `valgrind --tool=callgrind` for instruction counts that do not depend on machine load.
use serde_json::Value;
#[path = "../tests/common/mod.rs"]
mod common;
fn main() {
    // `cargo bench` appends `--bench` to the arguments.
    let a: Vec<String> = std::env::args().filter(|s| s != "--bench").collect();
    // `cargo test --benches` runs every bench target without arguments: nothing to trace.
    if a.len() < 3 {
        eprintln!("usage: cargo bench --bench trace_case -- FILE INDEX | time FILE... | timejac FILE... | timegrad FILE...");
        return;
    }
    if a[1] == "time" || a[1] == "timejac" || a[1] == "timegrad" {
        let jac = a[1] == "timejac";
        let grad = a[1] == "timegrad";
        let mut all = Vec::new();
        for f in &a[2..] {
            for c in common::load(std::path::Path::new(f)) {
                all.push((
                    common::shape(&c["shape1"]),
                    common::pose(&c["pose1"]),
                    common::shape(&c["shape2"]),
                    common::pose(&c["pose2"]),
                ));
            }
        }
        let mut t = Vec::new();
        for _ in 0..5 {
            for (s1, p1, s2, p2) in &all {
                let st = std::time::Instant::now();
                for _ in 0..20 {
                    if grad {
                        std::hint::black_box(
                            dcol::gradient(s1, p1, s2, p2, &Default::default()).unwrap(),
                        );
                    } else if jac {
                        std::hint::black_box(
                            dcol::jacobian(s1, p1, s2, p2, &Default::default()).unwrap(),
                        );
                    } else {
                        std::hint::black_box(
                            dcol::proximity(s1, p1, s2, p2, &Default::default()).unwrap(),
                        );
                    }
                }
                t.push(st.elapsed().as_nanos() as f64 / 20.0);
            }
        }
        t.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!("median {:.0} ns over {} cases", t[t.len() / 2], all.len());
        return;
    }
    let cases = common::load(std::path::Path::new(&a[1]));
    let c: &Value = &cases[a[2].parse::<usize>().unwrap()];
    // `DCOL_TOL` overrides the solver tolerance (as in tests/reference.rs).
    let mut opts = dcol::Options::default();
    if let Some(t) = std::env::var("DCOL_TOL").ok().and_then(|v| v.parse().ok()) {
        opts.tolerance = t;
    }
    let p = dcol::proximity(
        &common::shape(&c["shape1"]),
        &common::pose(&c["pose1"]),
        &common::shape(&c["shape2"]),
        &common::pose(&c["pose2"]),
        &opts,
    )
    .unwrap();
    println!("{:?}\nref alpha {}", p, c["alpha"]);
}
