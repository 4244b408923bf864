//! How the queries scale with a polytope's facet count. Prints the markdown table quoted in the
//! README:
//!
//! ```text
//! cargo bench --bench faces
//! ```
//!
//! Polytopes of 6 to 5 000 facets with random unit normals and offsets 0.5 ± 0.025 (bounding radii
//! 0.5 to 1), and convex hulls of random points on an ellipsoid of semi-axes (0.6, 0.5, 0.4)
//! (as many points as make about the same number of facets: a hull of n such points has 2n − 4
//! triangles), against a sphere of radius 0.3 and against themselves, at 200 random poses each
//! (random attitudes, offsets 0.6 to 1.6 between the origins: separated, touching and
//! overlapping), timed one call at a time and interleaved (each pose's queries back to back),
//! medians in ns. `cargo bench --bench faces -- --test` runs a few poses only.

use dcol::math::Vec3;
use dcol::{distance, proximity, signed_distance, Options, Pose, Shape};
use std::time::Instant;

/// xorshift64: a tiny deterministic generator, uniform in [-1, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.next(), self.next(), self.next());
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    fn quaternion(&mut self) -> [f64; 4] {
        loop {
            let q = [self.next(), self.next(), self.next(), self.next()];
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return q.map(|v| v / n);
            }
        }
    }
}

/// A bounded polytope of `m` random facets (redrawn until bounded).
fn polytope(m: usize, rng: &mut Rng) -> Shape {
    loop {
        let a: Vec<[f64; 3]> = (0..m).map(|_| rng.unit().into()).collect();
        let b: Vec<f64> = (0..m).map(|_| 0.5 + 0.025 * rng.next()).collect();
        if let Ok(p) = Shape::polytope(&a, &b) {
            return p;
        }
    }
}

/// The hull of `n` random points on an ellipsoid of semi-axes (0.6, 0.5, 0.4).
fn hull(n: usize, rng: &mut Rng) -> Shape {
    let pts: Vec<[f64; 3]> = (0..n)
        .map(|_| {
            let u = rng.unit();
            [0.6 * u.x, 0.5 * u.y, 0.4 * u.z]
        })
        .collect();
    Shape::convex_hull(&pts, 0.0).unwrap()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let test = std::env::args().any(|a| a == "--test");
    let (poses, reps) = if test { (5, 1) } else { (200, 25) };
    let mut rng = Rng(0x5EED_FACE_0000_0001);
    let o = Options::default();
    let sphere = Shape::sphere(0.3).unwrap();
    println!(
        "| shape | facets | build µs | proximity vs sphere | proximity vs itself | distance vs \
         itself | signed distance vs itself |"
    );
    println!("|---|--:|--:|--:|--:|--:|--:|");
    let sizes: &[usize] = if test {
        &[6, 100, 2000]
    } else {
        &[6, 12, 20, 50, 100, 256, 1000, 2000, 5000]
    };
    for &m in sizes {
        for planes in [true, false] {
            if !planes && m < 8 {
                continue;
            }
            let start = Instant::now();
            let p = if planes {
                polytope(m, &mut rng)
            } else {
                hull(m / 2 + 2, &mut rng)
            };
            let build = start.elapsed().as_secs_f64() * 1e6;
            let cases: Vec<(Pose, Pose)> = (0..poses)
                .map(|_| {
                    let p1 = Pose::new([0.0; 3], rng.quaternion()).unwrap();
                    let d = rng.unit() * (1.1 + 0.5 * rng.next());
                    let p2 = Pose::new(d.into(), rng.quaternion()).unwrap();
                    (p1, p2)
                })
                .collect();
            let mut t = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
            for _ in 0..reps {
                for (p1, p2) in &cases {
                    let s = Instant::now();
                    std::hint::black_box(proximity(&p, p1, &sphere, p2, &o).unwrap());
                    t[0].push(s.elapsed().as_nanos() as f64);
                    let s = Instant::now();
                    std::hint::black_box(proximity(&p, p1, &p, p2, &o).unwrap());
                    t[1].push(s.elapsed().as_nanos() as f64);
                    let s = Instant::now();
                    std::hint::black_box(distance(&p, p1, &p, p2, &o).unwrap());
                    t[2].push(s.elapsed().as_nanos() as f64);
                    let s = Instant::now();
                    std::hint::black_box(signed_distance(&p, p1, &p, p2, &o).unwrap());
                    t[3].push(s.elapsed().as_nanos() as f64);
                }
            }
            let [a, b, c, d] = t.map(|mut v| median(&mut v));
            let kind = if planes { "planes" } else { "hull" };
            let facets = if planes { m } else { 2 * (m / 2 + 2) - 4 };
            println!("| {kind} | {facets} | {build:.0} | {a:.0} | {b:.0} | {c:.0} | {d:.0} |");
        }
    }
}
