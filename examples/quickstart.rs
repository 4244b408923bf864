//! The Rust quickstart: a box and a ball, how far apart they are (α*, the exact distance) and
//! how α* changes when either moves.
//!
//!     cargo run --release --example quickstart

use dcol::{distance, gradient, proximity, Options, Pose, Shape};

fn main() -> Result<(), dcol::Error> {
    let boxed = Shape::cuboid(0.5, 0.5, 0.5)?;
    let ball = Shape::sphere(0.5)?;
    let p1 = Pose::new([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0])?; // quaternion [w, x, y, z]
    let p2 = Pose::from_position([2.0, 0.0, 0.0])?;
    let options = Options::default();

    let prox = proximity(&boxed, &p1, &ball, &p2, &options)?;
    println!(
        "alpha* = {:.6} (> 1: separated), touching point {:?}, {} iterations",
        prox.alpha,
        prox.point.as_slice(),
        prox.iterations
    );

    let d = distance(&boxed, &p1, &ball, &p2, &options)?;
    println!("distance = {:.6}", d.distance);

    let (_, g) = gradient(&boxed, &p1, &ball, &p2, &options)?; // d alpha / d(r1, q1, r2, q2)
    println!("d alpha / d r2 = {:?}", &g[7..10]);
    Ok(())
}
