//! What the solver tolerance does to α* and its derivatives at box corners, edges and faces.
//!
//! Prints the markdown tables quoted in `docs/derivatives.md`:
//!
//! ```text
//! cargo bench --bench tolerance_table
//! ```
//!
//! Geometry (everything has a closed form, so errors are measured against exact values):
//! box 1 with half-extents a = (1, 0.8, 0.5) at the origin, axis-aligned; box 2 with
//! half-extents b = (0.6, 0.4, 0.3) at r₂ = (0.1, −0.05, 1.2), attitude R = R_y(φ)·R_x(θ₀).
//! Box 2's lowest vertex touches box 1's top face, so
//! `α* = d / (a₃ + Σⱼ |R₃ⱼ| bⱼ)` with d = 1.2, and for θ₀ ≠ 0
//! `dα*/dφ → ∓(α*²/d)·b₁` as φ → 0±: at φ = 0 the lowest feature switches from the corner at
//! x = −b₁ to the one at x = +b₁ (at φ = 0 itself the bottom edge lies flat on the face).

use dcol::{derivatives, Derivatives, Options, Pose, Shape};

const A: [f64; 3] = [1.0, 0.8, 0.5];
const B: [f64; 3] = [0.6, 0.4, 0.3];
const R2: [f64; 3] = [0.1, -0.05, 1.2];
const TOLERANCES: [f64; 5] = [1e-2, 1e-4, 1e-6, 1e-8, 1e-10];

/// Hamilton product of `[w, x, y, z]` quaternions.
fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// `q = q_y(φ) ⊗ q_x(θ₀)`, i.e. `R = R_y(φ) R_x(θ₀)`.
fn attitude(theta0: f64, phi: f64) -> [f64; 4] {
    let qx = [(theta0 / 2.0).cos(), (theta0 / 2.0).sin(), 0.0, 0.0];
    let qy = [(phi / 2.0).cos(), 0.0, (phi / 2.0).sin(), 0.0];
    qmul(qy, qx)
}

/// Exact α* and, where the touching vertex is unique, dα*/dφ and x₁*.
struct Exact {
    alpha: f64,
    dalpha_dphi: Option<f64>,
    x1: Option<f64>,
}

fn exact(theta0: f64, phi: f64) -> Exact {
    let (s, c) = theta0.sin_cos();
    let (sp, cp) = phi.sin_cos();
    // Third row of R_y(φ) R_x(θ₀) and its φ-derivative.
    let row3 = [-sp, cp * s, cp * c];
    let drow3 = [-cp, -sp * s, -sp * c];
    let d = R2[2];
    let den = A[2] + (0..3).map(|j| row3[j].abs() * B[j]).sum::<f64>();
    let alpha = d / den;
    let unique = row3.iter().all(|v| *v != 0.0);
    let dalpha_dphi = unique.then(|| {
        let dden: f64 = (0..3).map(|j| row3[j].signum() * B[j] * drow3[j]).sum();
        -d * dden / (den * den)
    });
    // The touching vertex v = −sign(R₃ⱼ) bⱼ; x₁* = r₂,₁ + α (R v)₁ with R's first row.
    let row1 = [cp, sp * s, sp * c];
    let x1 = unique.then(|| {
        R2[0]
            + alpha
                * (0..3)
                    .map(|j| -row3[j].signum() * B[j] * row1[j])
                    .sum::<f64>()
    });
    Exact {
        alpha,
        dalpha_dphi,
        x1,
    }
}

fn solve(theta0: f64, phi: f64, tolerance: f64) -> Derivatives {
    let box1 = Shape::cuboid(A[0], A[1], A[2]).unwrap();
    let box2 = Shape::cuboid(B[0], B[1], B[2]).unwrap();
    let p1 = Pose::from_position([0.0; 3]).unwrap();
    let p2 = Pose::new(R2, attitude(theta0, phi)).unwrap();
    let opts = Options {
        tolerance,
        ..Options::default()
    };
    derivatives(&box1, &p1, &box2, &p2, &opts).unwrap()
}

/// dα/dφ by the chain rule through `dq₂/dφ = ½ (0, e_y) ⊗ q₂`, from a row of 14 derivatives.
fn along_phi(row: &[f64; 14], theta0: f64, phi: f64) -> f64 {
    let q = attitude(theta0, phi);
    let dq = qmul([0.0, 0.0, 0.5, 0.0], q);
    (0..4).map(|k| row[10 + k] * dq[k]).sum()
}

/// Length scale ℓ: the larger bounding radius.
fn ell() -> f64 {
    let n = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    n(A).max(n(B))
}

/// Largest non-dimensional difference of two 14-vectors (r columns × ℓ).
fn diff14(a: &[f64; 14], b: &[f64; 14], row_scale: f64) -> f64 {
    (0..14)
        .map(|c| {
            let k = if c % 7 < 3 { ell() } else { 1.0 };
            (a[c] - b[c]).abs() * k * row_scale
        })
        .fold(0.0, f64::max)
}

fn fmt(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v:.1e}")
    }
}

/// One configuration swept over the tolerances.
fn tolerance_sweep(name: &str, theta0: f64, phi: f64) {
    let ex = exact(theta0, phi);
    let reference = solve(theta0, phi, 1e-10);
    println!("\n#### {name}\n");
    println!(
        "α* = {:.12} (exact); dα*/dφ exact: {}\n",
        ex.alpha,
        ex.dalpha_dphi.map_or(
            "not defined (kink: one-sided slopes ∓(α*²/d)·b₁)".into(),
            |v| format!("{v:.9}")
        )
    );
    println!(
        "| tolerance | status | iterations | α* error | ∇α − ∇α(1e-10) | J[3,:] − J[3,:](1e-10) | J x-rows − (1e-10) | max J x-row, r cols | max J x-row, q cols | dα/dφ from ∇α | dα/dφ from J[3,:] |"
    );
    println!("|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    for tol in TOLERANCES {
        let d = solve(theta0, phi, tol);
        let jx = (0..3)
            .map(|r| diff14(&d.jacobian[r], &reference.jacobian[r], 1.0 / ell()))
            .fold(0.0, f64::max);
        // Largest x-row entry over the position columns and over the quaternion columns.
        let jmax = |q: bool| {
            let mut m: f64 = 0.0;
            for r in 0..3 {
                for c in (0..14).filter(|c| (c % 7 >= 3) == q) {
                    let k = if q { 1.0 } else { ell() };
                    m = m.max((d.jacobian[r][c] * k / ell()).abs());
                }
            }
            m
        };
        println!(
            "| {tol:.0e} | {:?} | {} | {} | {} | {} | {} | {} | {} | {:.6} | {:.6} |",
            d.proximity.status,
            d.proximity.iterations,
            fmt((d.proximity.alpha - ex.alpha).abs()),
            fmt(diff14(&d.dalpha, &reference.dalpha, 1.0)),
            fmt(diff14(&d.jacobian[3], &reference.jacobian[3], 1.0)),
            fmt(jx),
            fmt(jmax(false)),
            fmt(jmax(true)),
            along_phi(&d.dalpha, theta0, phi),
            along_phi(&d.jacobian[3], theta0, phi),
        );
    }
}

/// The kink sweep across the corner switch at φ = 0: dα/dφ by both routes, the error of α*,
/// and x₁*.
fn kink_sweep(theta0: f64) {
    let phis = [
        -1e-2, -1e-3, -1e-4, -1e-5, -1e-6, 0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2,
    ];
    let tables = [
        "dα*/dφ from `gradient` (Lagrangian, polished multipliers)",
        "dα*/dφ from `jacobian` row α (implicit function)",
        "α* error (returned α* − exact α*)",
        "x₁* (the touching point jumps between the two corners at φ = 0)",
    ];
    for (t, title) in tables.iter().enumerate() {
        println!("\n#### {title}\n");
        let mut head = String::from("| φ (rad) | exact |");
        let mut rule = String::from("|--:|--:|");
        for tol in TOLERANCES {
            head += &format!(" tol {tol:.0e} |");
            rule += "--:|";
        }
        println!("{head}\n{rule}");
        for phi in phis {
            let ex = exact(theta0, phi);
            let exact_text = match t {
                0 | 1 => ex.dalpha_dphi.map_or("kink".into(), |v| format!("{v:.6}")),
                2 => "0".into(),
                _ => ex.x1.map_or("not unique".into(), |v| format!("{v:.6}")),
            };
            let phi_text = if phi == 0.0 {
                "0".to_string()
            } else {
                format!("{phi:.0e}")
            };
            let mut line = format!("| {phi_text} | {exact_text} |");
            for tol in TOLERANCES {
                let d = solve(theta0, phi, tol);
                line += &match t {
                    0 => format!(" {:.6} |", along_phi(&d.dalpha, theta0, phi)),
                    1 => format!(" {:.6} |", along_phi(&d.jacobian[3], theta0, phi)),
                    2 => format!(" {:.1e} |", d.proximity.alpha - ex.alpha),
                    _ => format!(" {:.6} |", d.proximity.point.x),
                };
            }
            println!("{line}");
        }
    }
}

fn main() {
    let theta0 = 0.35;
    println!(
        "### Solver tolerance sweep, box–box (dcol {})",
        env!("CARGO_PKG_VERSION")
    );
    println!(
        "\nDifferences are the largest entry, non-dimensional (r columns × ℓ, x rows ÷ ℓ, \
         ℓ = {:.4}); the reference is dcol at tolerance 1e-10.",
        ell()
    );
    tolerance_sweep(
        "Corner on face (φ = 0.2, θ₀ = 0.35): unique touching point",
        theta0,
        0.2,
    );
    tolerance_sweep(
        "Edge on face (φ = 0, θ₀ = 0.35): the bottom edge lies flat on the face; x* not unique",
        theta0,
        0.0,
    );
    tolerance_sweep(
        "Face on face (φ = 0, θ₀ = 0): parallel faces; x* not unique",
        0.0,
        0.0,
    );
    println!("\n### Crossing the corner switch (θ₀ = 0.35, rotating box 2 about y by φ)");
    kink_sweep(theta0);
}
