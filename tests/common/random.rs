//! Random numbers (SplitMix64) and random shapes of the ten kinds (the eight primitives and
//! convex hulls of points, unpadded and padded), for the property tests.

use dcol::Shape;

pub struct Rng(pub u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        let mut r = Rng(seed);
        r.next_u64();
        r
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn unif(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    pub fn gauss(&mut self) -> f64 {
        let u = self.unif().max(1e-300);
        let v = self.unif();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
    pub fn unit<const D: usize>(&mut self) -> [f64; D] {
        loop {
            let v = [0; D].map(|_| self.gauss());
            let n = v.iter().map(|c| c * c).sum::<f64>().sqrt();
            if n > 1e-3 {
                return v.map(|c| c / n);
            }
        }
    }
    /// A uniformly random attitude as a quaternion of length 0.7..1.4 (not unit on purpose:
    /// derivatives are taken with respect to the raw components).
    pub fn quat(&mut self) -> [f64; 4] {
        let u = self.unit::<4>();
        let s = self.range(0.7, 1.4);
        u.map(|v| v * s)
    }
    /// Modified Rodrigues parameters of a random attitude (|p| ≤ 1 covers every rotation).
    pub fn mrp(&mut self) -> [f64; 3] {
        let t = self.range(0.0, 0.95);
        self.unit::<3>().map(|c| c * t)
    }
}

/// The bounded kinds. The half-space is left out on purpose: the property tests built on this
/// list compare against bounding-sphere brackets (`‖Δr‖/(ρ₁ + ρ₂) ≤ α*`), swap and rigid-motion
/// symmetries through the general solvers, and pairs of the same kind, none of which apply to
/// an unbounded shape (two half-spaces are an error); `tests/halfspace.rs` covers it against
/// every kind here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Sphere,
    Ellipsoid,
    Box,
    Polytope,
    Capsule,
    Cylinder,
    Cone,
    Polygon,
    /// The convex hull of 8 to 40 points (some inside, some repeated).
    Hull,
    /// The same, padded by a radius.
    RoundedHull,
}

pub const KINDS: [Kind; 10] = [
    Kind::Sphere,
    Kind::Ellipsoid,
    Kind::Box,
    Kind::Polytope,
    Kind::Capsule,
    Kind::Cylinder,
    Kind::Cone,
    Kind::Polygon,
    Kind::Hull,
    Kind::RoundedHull,
];

/// The hull of `n` points on an ellipsoid of semi-axes `axes` (a quarter of them inside, some
/// repeated), shifted so that their mean is the origin (strictly inside), padded by `radius`.
pub fn hull_of(rng: &mut Rng, n: usize, axes: [f64; 3], radius: f64) -> Shape {
    let mut pts: Vec<[f64; 3]> = Vec::with_capacity(n);
    while pts.len() < n {
        let u = rng.unit::<3>();
        let p = [0, 1, 2].map(|k| u[k] * axes[k]);
        // The first four on the surface: affinely independent (with probability one).
        match if pts.len() < 4 { 7 } else { rng.next_u64() % 8 } {
            0 | 1 => {
                let t = rng.range(0.0, 0.9);
                pts.push(p.map(|c| c * t))
            }
            2 if !pts.is_empty() => pts.push(pts[rng.next_u64() as usize % pts.len()]),
            _ => pts.push(p),
        }
    }
    let mean = [0, 1, 2].map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / n as f64);
    for p in pts.iter_mut() {
        *p = [0, 1, 2].map(|k| p[k] - mean[k]);
    }
    Shape::convex_hull(&pts, radius).expect("a random hull")
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sphere => "sphere",
            Kind::Ellipsoid => "ellipsoid",
            Kind::Box => "box",
            Kind::Polytope => "polytope12",
            Kind::Capsule => "capsule",
            Kind::Cylinder => "cylinder",
            Kind::Cone => "cone",
            Kind::Polygon => "polygon",
            Kind::Hull => "hull",
            Kind::RoundedHull => "rounded-hull",
        }
    }

    pub fn index(self) -> u64 {
        KINDS.iter().position(|k| *k == self).unwrap() as u64
    }

    pub fn random(self, rng: &mut Rng) -> Shape {
        match self {
            Kind::Sphere => Shape::sphere(rng.range(0.3, 1.2)),
            Kind::Ellipsoid => {
                // P = R diag(1/d²) Rᵀ with a random rotation R and semi-axes d.
                let m = dcol::math::rotation_from_quaternion(rng.quat());
                let d = [
                    rng.range(0.3, 1.2),
                    rng.range(0.3, 1.2),
                    rng.range(0.3, 1.2),
                ];
                let mut p = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        for k in 0..3 {
                            p[i][j] += m[(i, k)] * m[(j, k)] / (d[k] * d[k]);
                        }
                    }
                }
                Shape::ellipsoid(p)
            }
            Kind::Box => Shape::cuboid(
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
            ),
            Kind::Polytope => {
                // A perturbed dodecahedron: 12 facets, normals near the icosahedron's vertices.
                let phi = (1.0 + 5f64.sqrt()) / 2.0;
                let mut a = Vec::with_capacity(12);
                for s1 in [1.0, -1.0] {
                    for s2 in [1.0, -1.0] {
                        for v in [
                            [0.0, s1, s2 * phi],
                            [s1, s2 * phi, 0.0],
                            [s2 * phi, 0.0, s1],
                        ] {
                            a.push(v.map(|c| c + rng.range(-0.15, 0.15)));
                        }
                    }
                }
                let b: Vec<f64> = (0..12).map(|_| rng.range(0.5, 1.2)).collect();
                Shape::polytope(&a, &b)
            }
            Kind::Capsule => Shape::capsule(rng.range(0.2, 0.7), rng.range(0.3, 1.5)),
            Kind::Cylinder => Shape::cylinder(rng.range(0.2, 0.7), rng.range(0.3, 1.5)),
            Kind::Cone => Shape::cone(rng.range(0.5, 1.8), rng.range(0.25, 1.1)),
            Kind::Polygon => {
                // 3 to 7 edges with jittered directions, padded.
                let m = 3 + (rng.next_u64() % 5) as usize;
                let off = rng.range(0.0, std::f64::consts::TAU);
                let c: Vec<[f64; 2]> = (0..m)
                    .map(|i| {
                        let t = off
                            + std::f64::consts::TAU * (i as f64 + rng.range(-0.2, 0.2)) / m as f64;
                        [t.cos(), t.sin()]
                    })
                    .collect();
                let d: Vec<f64> = (0..m).map(|_| rng.range(0.3, 0.9)).collect();
                Shape::polygon(&c, &d, rng.range(0.05, 0.3))
            }
            Kind::Hull | Kind::RoundedHull => {
                let n = 8 + (rng.next_u64() % 33) as usize;
                let axes = [0; 3].map(|_| rng.range(0.3, 1.0));
                let radius = if self == Kind::Hull {
                    0.0
                } else {
                    rng.range(0.05, 0.3)
                };
                return hull_of(rng, n, axes, radius);
            }
        }
        .expect("valid random shape")
    }
}

/// The SplitMix64 generator of the scale-spanning sweeps (`tests/geometric.rs`,
/// `tests/gjk_distance.rs`): uniform numbers, log-uniform sizes, raw quaternions.
pub struct Scaled(pub u64);
impl Scaled {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    /// 10^U(lo, hi).
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(self.range(lo, hi))
    }
    pub fn quat(&mut self) -> [f64; 4] {
        [0; 4].map(|_| self.range(-1.0, 1.0))
    }
}

/// A random shape of kind `k` (0..10: sphere, ellipsoid, polytope, capsule, cylinder, cone,
/// padded polygon, box, hull, padded hull) with size `size`.
pub fn random_shape(rng: &mut Scaled, k: usize, size: f64) -> dcol::Shape {
    use dcol::Shape;
    let u = |rng: &mut Scaled| size * rng.range(0.3, 1.0);
    match k {
        0 => Shape::sphere(u(rng)).unwrap(),
        1 => {
            let (a, b, c) = (u(rng), u(rng), u(rng));
            Shape::ellipsoid([
                [1.0 / (a * a), 0.0, 0.0],
                [0.0, 1.0 / (b * b), 0.0],
                [0.0, 0.0, 1.0 / (c * c)],
            ])
            .unwrap()
        }
        2 => {
            // A random 12-facet polytope around a ball: unit normals, offsets in [0.5, 1]·size.
            let a: Vec<[f64; 3]> = (0..12)
                .map(|i| {
                    let z = 1.0 - 2.0 * (i as f64 + 0.5) / 12.0;
                    let t = i as f64 * 2.399963 + rng.range(-0.2, 0.2);
                    let r = (1.0 - z * z).sqrt();
                    [r * t.cos(), r * t.sin(), z]
                })
                .collect();
            let b: Vec<f64> = (0..12).map(|_| u(rng)).collect();
            Shape::polytope(&a, &b).unwrap()
        }
        3 => Shape::capsule(u(rng), u(rng)).unwrap(),
        4 => Shape::cylinder(u(rng), u(rng)).unwrap(),
        5 => Shape::cone(u(rng) * 2.0, rng.range(0.2, 1.2)).unwrap(),
        7 => Shape::cuboid(u(rng), u(rng), u(rng)).unwrap(),
        8 | 9 => {
            // 8 to 40 points on an ellipsoid (some inside, some repeated), padded for kind 9.
            let mut r = Rng::new(rng.0);
            rng.next();
            let n = 8 + (r.next_u64() % 33) as usize;
            let axes = [0; 3].map(|_| u(rng));
            let radius = if k == 9 { 0.3 * u(rng) } else { 0.0 };
            hull_of(&mut r, n, axes, radius)
        }
        _ => {
            let c = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.7, 0.7]];
            let d: Vec<f64> = (0..5).map(|_| u(rng)).collect();
            Shape::polygon(&c, &d, u(rng) * 0.3).unwrap()
        }
    }
}

/// The shapes of random pair `i` (the kinds cycle over the 100 ordered pairs of the ten kinds,
/// the box and the hulls included), sizes within a factor 3 of `scale`.
pub fn random_shapes(rng: &mut Scaled, i: usize, scale: f64) -> (dcol::Shape, dcol::Shape) {
    let (z1, z2) = (scale * rng.log(-0.5, 0.5), scale * rng.log(-0.5, 0.5));
    let s1 = random_shape(rng, (i / 10) % 10, z1);
    let s2 = random_shape(rng, i % 10, z2);
    (s1, s2)
}

/// Random attitudes, shape 1 somewhere within 10·`scale` of the origin, and the two origins
/// `len` apart in a random direction.
pub fn random_poses(rng: &mut Scaled, scale: f64, len: f64) -> (dcol::Pose, dcol::Pose) {
    let dir = [0; 3].map(|_| rng.range(-1.0, 1.0));
    let dn = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
    let r1 = [0; 3].map(|_| scale * rng.range(-10.0, 10.0));
    let r2 = [0, 1, 2].map(|j| r1[j] + dir[j] * len / dn);
    (
        dcol::Pose::new(r1, rng.quat()).unwrap(),
        dcol::Pose::new(r2, rng.quat()).unwrap(),
    )
}
