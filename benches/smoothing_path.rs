//! α* and its derivative along a path that crosses face-against-face contact, exact and
//! smoothed (`Options::smoothing`), as CSV for `scripts/plot_smoothing.py`.
//!
//! A 0.5 m cube rests on a 1 m cube's top face (offset 1.5 m along z, 0.2 m along x) and tilts
//! by φ ∈ [−12°, 12°] about a horizontal axis 30° from x. At φ = 0 the faces are parallel and
//! x* is not unique; on either side one corner of the small cube touches, so α*(φ) has a kink
//! at 0 and its derivative jumps. The smoothed answer at barrier parameter μ is smooth through
//! it.
//!
//! `cargo bench --bench smoothing_path [-- OUT.csv]` (default `docs/data/smoothing_path.csv`).
//! Columns: `phi_deg, mu` (0 for exact), `alpha, dalpha_dphi, kind` (the derivative kind).

use dcol::{gradient, Options, Pose, Shape};
use std::fmt::Write as _;

fn main() {
    let out = std::env::args()
        .skip(1)
        .find(|a| a.ends_with(".csv"))
        .unwrap_or_else(|| "docs/data/smoothing_path.csv".to_string());
    let big = Shape::cuboid(1.0, 1.0, 1.0).expect("cube");
    let small = Shape::cuboid(0.5, 0.5, 0.5).expect("cube");
    let p1 = Pose::from_position([0.0, 0.0, 0.0]).expect("pose");
    let mut csv = String::from("phi_deg,mu,alpha,dalpha_dphi,kind\n");
    let steps = 481;
    for mu in [0.0, 1e-2, 1e-3, 1e-4] {
        let o = Options {
            smoothing: mu,
            ..Options::default()
        };
        for k in 0..steps {
            let deg = -12.0 + 24.0 * k as f64 / (steps - 1) as f64;
            let phi = deg.to_radians();
            let (s, c) = (0.5 * phi).sin_cos();
            let (ax, ay) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
            let q = [c, s * ax, s * ay, 0.0];
            let p2 = Pose::new([0.2, 0.0, 1.5], q).expect("pose");
            let (p, g) = gradient(&big, &p1, &small, &p2, &o).expect("gradient");
            // dq/dφ = ½(−sin(φ/2), cos(φ/2)·axis).
            let dphi = 0.5 * (-s * g[10] + c * (ax * g[11] + ay * g[12]));
            writeln!(csv, "{deg},{mu},{},{dphi},{:?}", p.alpha, p.derivatives).unwrap();
        }
    }
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir).expect("output folder");
    }
    std::fs::write(&out, csv).expect("write CSV");
    println!("wrote {out}");
}
