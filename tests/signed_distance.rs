//! The signed distance (`signed_distance`): analytic overlaps, separated pairs equal to
//! `distance`, random pairs of the 8×8 kinds against an independent brute force over unit
//! normals (support functions written out here from `docs/maths.md` §2), the witness
//! identity, and continuity across touching.

mod common;

use dcol::math::rotation_from_quaternion;
use dcol::{distance, signed_distance, Options, Pose, Shape, SolveStatus, Vec3};
use std::collections::BTreeMap;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unif(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unif()
    }
    fn dir(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
    fn quat(&mut self) -> [f64; 4] {
        let v = loop {
            let q = [0; 4].map(|_| self.range(-1.0, 1.0));
            let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                break q.map(|x| x / n);
            }
        };
        v
    }
}

/// A shape with its body support function written out independently.
enum Oracle {
    Sphere(f64),
    Ellipsoid(nalgebra::Matrix3<f64>), // P⁻¹
    Vertices(Vec<Vec3>),
    Capsule(f64, f64),
    Cylinder(f64, f64),
    Cone(f64, f64),
    Polygon(Vec<[f64; 2]>, f64),
}

impl Oracle {
    fn h(&self, m: &Vec3) -> f64 {
        let yz = (m.y * m.y + m.z * m.z).sqrt();
        match self {
            Oracle::Sphere(r) => r * m.norm(),
            Oracle::Ellipsoid(q) => m.dot(&(q * m)).sqrt(),
            Oracle::Vertices(v) => v.iter().map(|p| p.dot(m)).fold(f64::MIN, f64::max),
            Oracle::Capsule(r, l) => 0.5 * l * m.x.abs() + r * m.norm(),
            Oracle::Cylinder(r, l) => 0.5 * l * m.x.abs() + r * yz,
            Oracle::Cone(h, b) => (-0.75 * h * m.x).max(0.25 * h * m.x + h * b.tan() * yz),
            Oracle::Polygon(w, r) => {
                w.iter()
                    .map(|p| p[0] * m.x + p[1] * m.y)
                    .fold(f64::MIN, f64::max)
                    + r * m.norm()
            }
        }
    }
}

/// Vertices of `A x ≤ b` by brute force over triples of planes.
fn vertices(a: &[[f64; 3]], b: &[f64]) -> Vec<Vec3> {
    let mut out = Vec::new();
    let rows: Vec<Vec3> = a.iter().map(|r| Vec3::new(r[0], r[1], r[2])).collect();
    for i in 0..a.len() {
        for j in i + 1..a.len() {
            for k in j + 1..a.len() {
                let m = nalgebra::Matrix3::from_rows(&[
                    rows[i].transpose(),
                    rows[j].transpose(),
                    rows[k].transpose(),
                ]);
                if let Some(x) = m.try_inverse().map(|inv| inv * Vec3::new(b[i], b[j], b[k])) {
                    if rows.iter().zip(b).all(|(r, bi)| r.dot(&x) <= bi + 1e-9) {
                        out.push(x);
                    }
                }
            }
        }
    }
    out
}

fn polygon_vertices(c: &[[f64; 2]], d: &[f64]) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for i in 0..c.len() {
        for j in i + 1..c.len() {
            let det = c[i][0] * c[j][1] - c[i][1] * c[j][0];
            if det.abs() < 1e-12 {
                continue;
            }
            let x = (d[i] * c[j][1] - c[i][1] * d[j]) / det;
            let y = (c[i][0] * d[j] - d[i] * c[j][0]) / det;
            if c.iter()
                .zip(d)
                .all(|(r, di)| r[0] * x + r[1] * y <= di + 1e-9)
            {
                out.push([x, y]);
            }
        }
    }
    out
}

const KINDS: [&str; 8] = [
    "sphere",
    "ellipsoid",
    "box",
    "polytope",
    "capsule",
    "cylinder",
    "cone",
    "polygon",
];

fn random_shape(kind: usize, rng: &mut Rng) -> (Shape, Oracle) {
    match kind {
        0 => {
            let r = rng.range(0.3, 1.2);
            (Shape::sphere(r).unwrap(), Oracle::Sphere(r))
        }
        1 => {
            let m = rotation_from_quaternion(rng.quat());
            let ax = [0; 3].map(|_| rng.range(0.3, 1.2));
            let dd = nalgebra::Matrix3::from_diagonal(&Vec3::new(ax[0], ax[1], ax[2]));
            let p = m * dd.map(|x| if x > 0.0 { 1.0 / (x * x) } else { 0.0 }) * m.transpose();
            let q = m * dd * dd * m.transpose();
            let pa = [0, 1, 2].map(|i| [0, 1, 2].map(|j| p[(i, j)]));
            (Shape::ellipsoid(pa).unwrap(), Oracle::Ellipsoid(q))
        }
        2 => {
            let h = [0; 3].map(|_| rng.range(0.2, 1.0));
            let a = [
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [-1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, -1.0],
            ];
            let b = [h[0], h[1], h[2], h[0], h[1], h[2]];
            (
                Shape::cuboid(h[0], h[1], h[2]).unwrap(),
                Oracle::Vertices(vertices(&a, &b)),
            )
        }
        3 => {
            let phi = (1.0 + 5f64.sqrt()) / 2.0;
            let mut a = Vec::new();
            for s1 in [1.0, -1.0] {
                for s2 in [1.0, -1.0] {
                    for v in [
                        [0.0, s1, s2 * phi],
                        [s1, s2 * phi, 0.0],
                        [s2 * phi, 0.0, s1],
                    ] {
                        a.push(v.map(|c: f64| c + rng.range(-0.15, 0.15)));
                    }
                }
            }
            let b: Vec<f64> = (0..12).map(|_| rng.range(0.5, 1.2)).collect();
            let s = Shape::polytope(&a, &b).unwrap();
            (s, Oracle::Vertices(vertices(&a, &b)))
        }
        4 => {
            let (r, l) = (rng.range(0.2, 0.7), rng.range(0.3, 1.5));
            (Shape::capsule(r, l).unwrap(), Oracle::Capsule(r, l))
        }
        5 => {
            let (r, l) = (rng.range(0.2, 0.7), rng.range(0.3, 1.5));
            (Shape::cylinder(r, l).unwrap(), Oracle::Cylinder(r, l))
        }
        6 => {
            let (h, b) = (rng.range(0.5, 1.8), rng.range(0.25, 1.1));
            (Shape::cone(h, b).unwrap(), Oracle::Cone(h, b))
        }
        _ => {
            let m = 3 + (rng.next() % 5) as usize;
            let off = rng.range(0.0, std::f64::consts::TAU);
            let c: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let t =
                        off + std::f64::consts::TAU * (i as f64 + rng.range(-0.2, 0.2)) / m as f64;
                    [t.cos(), t.sin()]
                })
                .collect();
            let d: Vec<f64> = (0..m).map(|_| rng.range(0.3, 0.9)).collect();
            let r = rng.range(0.05, 0.3);
            let w = polygon_vertices(&c, &d);
            (Shape::polygon(&c, &d, r).unwrap(), Oracle::Polygon(w, r))
        }
    }
}

/// `L(n) = n·d − h₁(n) − h₂(−n)` from the oracles.
fn lower(o: [&Oracle; 2], rot: [&nalgebra::Matrix3<f64>; 2], d: &Vec3, n: &Vec3) -> f64 {
    n.dot(d) - o[0].h(&(rot[0].transpose() * n)) - o[1].h(&(rot[1].transpose() * -n))
}

/// The brute-force maximum of `L` over unit normals: a Fibonacci sphere, then a local search.
fn brute(
    o: [&Oracle; 2],
    rot: [&nalgebra::Matrix3<f64>; 2],
    d: &Vec3,
    hint: &Vec3,
    rng: &mut Rng,
) -> f64 {
    let k = 4000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut best = (f64::MIN, Vec3::x());
    if hint.norm() > 0.5 {
        best = (lower(o, rot, d, hint), *hint);
    }
    for i in 0..k {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / k as f64;
        let r = (1.0 - z * z).sqrt();
        let t = golden * i as f64;
        let n = Vec3::new(r * t.cos(), r * t.sin(), z);
        let l = lower(o, rot, d, &n);
        if l > best.0 {
            best = (l, n);
        }
    }
    let mut step = 0.05;
    while step > 1e-9 {
        let mut improved = false;
        for _ in 0..40 {
            let n = (best.1 + rng.dir() * step).normalize();
            let l = lower(o, rot, d, &n);
            if l > best.0 {
                best = (l, n);
                improved = true;
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    best.0
}

fn pose(p: Vec3, q: [f64; 4]) -> Pose {
    Pose::new([p.x, p.y, p.z], q).unwrap()
}

#[test]
fn analytic_overlaps() {
    let o = Options::default();
    let at = |x: f64, y: f64, z: f64| Pose::from_position([x, y, z]).unwrap();
    // Sphere–sphere: depth R1 + R2 − |d|.
    let (a, b) = (Shape::sphere(1.0).unwrap(), Shape::sphere(0.5).unwrap());
    let s = signed_distance(&a, &at(0.0, 0.0, 0.0), &b, &at(0.3, 0.4, 1.0), &o).unwrap();
    let len = (0.09f64 + 0.16 + 1.0).sqrt();
    assert!((s.distance - (len - 1.5)).abs() < 1e-10, "{s:?}");
    assert!((s.normal - Vec3::new(0.3, 0.4, 1.0) / len).norm() < 1e-8);
    // Box–box, axis aligned: depth is the least overlap over the axes.
    let (a, b) = (
        Shape::cuboid(1.0, 0.5, 0.7).unwrap(),
        Shape::cuboid(0.4, 0.6, 0.3).unwrap(),
    );
    let s = signed_distance(&a, &at(0.0, 0.0, 0.0), &b, &at(1.2, 0.3, -0.2), &o).unwrap();
    let over = [1.4 - 1.2, 1.1 - 0.3, 1.0 - 0.2];
    let depth = over.iter().cloned().fold(f64::MAX, f64::min);
    assert!((s.distance + depth).abs() < 1e-10, "{s:?} vs {depth}");
    assert!((s.normal - Vec3::x()).norm() < 1e-10);
    // A sphere over a box face: depth R + h − |d_z|.
    let (a, b) = (
        Shape::cuboid(2.0, 2.0, 0.5).unwrap(),
        Shape::sphere(0.4).unwrap(),
    );
    let s = signed_distance(&a, &at(0.0, 0.0, 0.0), &b, &at(0.3, -0.2, 0.7), &o).unwrap();
    assert!((s.distance - (0.7 - 0.9)).abs() < 1e-10, "{s:?}");
    assert!((s.normal - Vec3::z()).norm() < 1e-8);
    // Crossing capsules (axes along x and y, offset along z): depth R1 + R2 − |dz|.
    let (a, b) = (
        Shape::capsule(0.3, 2.0).unwrap(),
        Shape::capsule(0.2, 2.0).unwrap(),
    );
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let pb = Pose::new([0.1, 0.05, 0.35], [h, 0.0, 0.0, h]).unwrap();
    let s = signed_distance(&a, &at(0.0, 0.0, 0.0), &b, &pb, &o).unwrap();
    assert!((s.distance - (0.35 - 0.5)).abs() < 1e-10, "{s:?}");
    assert!((s.normal - Vec3::z()).norm() < 1e-8);
    let e = (s.closest2 - s.closest1 - s.normal * s.distance).norm();
    assert!(e < 1e-9, "witness identity {e:e}");
    // A sphere whose centre is inside a rotated box, and inside a cylinder near its cap, both
    // argument orders: depth R + the centre's distance to the nearest face, that face's normal.
    let q = [0.9, 0.2, -0.3, 0.1];
    let rot = *pose(Vec3::zeros(), q).rotation();
    let ball = Shape::sphere(0.2).unwrap();
    let cases = [
        // (solid, centre in the solid's frame, depth of the centre, face normal in its frame)
        (
            Shape::cuboid(1.0, 0.5, 0.3).unwrap(),
            Vec3::new(0.1, 0.05, -0.02),
            0.28,
            -Vec3::z(),
        ),
        (
            Shape::cylinder(0.5, 2.0).unwrap(),
            Vec3::new(0.8, 0.1, 0.0),
            0.2,
            Vec3::x(),
        ),
        (
            Shape::cylinder(0.5, 2.0).unwrap(),
            Vec3::new(0.1, 0.0, -0.35),
            0.15,
            -Vec3::z(),
        ),
    ];
    for (solid, c, depth, face) in cases {
        let ps = pose(Vec3::new(0.3, -0.1, 0.2), q);
        let pc = pose(ps.position() + rot * c, [1.0, 0.0, 0.0, 0.0]);
        for flip in [false, true] {
            let s = if flip {
                signed_distance(&ball, &pc, &solid, &ps, &o).unwrap()
            } else {
                signed_distance(&solid, &ps, &ball, &pc, &o).unwrap()
            };
            let n = if flip { -(rot * face) } else { rot * face };
            assert!((s.distance + depth + 0.2).abs() < 1e-12, "{s:?}");
            assert!((s.normal - n).norm() < 1e-12, "{s:?}");
            let e = (s.closest2 - s.closest1 - s.normal * s.distance).norm();
            assert!(e < 1e-12, "witness identity {e:e}");
        }
    }
}

#[test]
#[allow(clippy::needless_range_loop)]
fn random_pairs_against_brute_force() {
    let o = Options::default();
    let mut rng = Rng(0x5D15_7A4C_E000_0001);
    let per_pair: usize = std::env::var("DCOL_SD_PAIRS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100);
    let mut failures = Vec::new();
    let mut stats: BTreeMap<String, (usize, usize, u32)> = BTreeMap::new();
    let (mut worst_hi, mut worst_lo, mut worst_w) = (0.0f64, 0.0f64, 0.0f64);
    let mut overl = 0;
    let mut open_worst = 0.0f64;
    for k1 in 0..8 {
        for k2 in 0..8 {
            for i in 0..per_pair {
                let (s1, o1) = random_shape(k1, &mut rng);
                let (s2, o2) = random_shape(k2, &mut rng);
                let (q1, q2) = (rng.quat(), rng.quat());
                let reach = s1.bounding_radius() + s2.bounding_radius();
                let d = rng.dir() * rng.range(0.0, 0.9) * reach;
                let r1 = Vec3::new(0.1, -0.2, 0.3);
                let (p1, p2) = (pose(r1, q1), pose(r1 + d, q2));
                let ell = s1.bounding_radius().max(s2.bounding_radius());
                let s = signed_distance(&s1, &p1, &s2, &p2, &o).unwrap();
                let (m1, m2) = (rotation_from_quaternion(q1), rotation_from_quaternion(q2));
                let b = brute([&o1, &o2], [&m1, &m2], &d, &s.normal, &mut rng);
                // The reported value is attained at the reported normal (independent support
                // functions), so it is a lower bound on the true maximum.
                let at_n = lower([&o1, &o2], [&m1, &m2], &d, &s.normal);
                let name = format!("{}-{}", KINDS[k1], KINDS[k2]);
                if s.distance < 0.0 {
                    overl += 1;
                    let e = stats.entry(format!("{:?}", s.path)).or_default();
                    e.0 += 1;
                    e.1 += usize::from(s.status != SolveStatus::Converged);
                    e.2 = e.2.max(s.iterations);
                }
                let hi = (b - s.distance) / ell;
                let lo = (s.distance - b) / ell;
                if s.status == SolveStatus::Converged {
                    worst_hi = worst_hi.max(hi);
                    worst_lo = worst_lo.max(lo);
                } else {
                    open_worst = open_worst.max(hi);
                }
                let attained = (s.distance - at_n) / ell;
                worst_lo = worst_lo.max(attained);
                // A bracket that did not close (status not converged) gives the best answer only.
                let strict = s.status == SolveStatus::Converged;
                if (strict && (hi > 1e-9 || lo > 1e-6))
                    || attained > 1e-9
                    || !s.distance.is_finite()
                {
                    failures.push(format!(
                        "{name} #{i}: sd {} vs brute {b}, L(n) {at_n} ({:?}, {:?})",
                        s.distance, s.path, s.status
                    ));
                }
                let w = (s.closest2 - s.closest1 - s.normal * s.distance).norm() / ell;
                if s.distance != 0.0 && strict {
                    worst_w = worst_w.max(w);
                    if w > 1e-8 {
                        failures.push(format!(
                            "{name} #{i}: witness identity off by {w:e} ℓ ({:?})",
                            s.path
                        ));
                    }
                }
                if s.distance > 0.0 {
                    let dd = distance(&s1, &p1, &s2, &p2, &o).unwrap();
                    if dd.distance != s.distance {
                        failures.push(format!("{name} #{i}: separated sd != distance"));
                    }
                }
            }
        }
    }
    println!("overlapping {overl}; paths (count, not converged, max supports) {stats:?}");
    println!("not converged: brute above sd by ≤ {open_worst:e} ℓ");
    println!("brute above sd by ≤ {worst_hi:e} ℓ; sd above brute by ≤ {worst_lo:e} ℓ; witness identity ≤ {worst_w:e} ℓ");
    for f in failures.iter().take(40) {
        println!("{f}");
    }
    assert!(failures.is_empty(), "{} failures", failures.len());
}

#[test]
fn continuous_across_touching() {
    let o = Options::default();
    let (a, b) = (
        Shape::cylinder(0.5, 1.0).unwrap(),
        Shape::ellipsoid([[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]).unwrap(),
    );
    let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
    // Ellipsoid semi-axis along y is 1: touching at y = 1.5 (cylinder radius 0.5 along y).
    let mut prev: Option<f64> = None;
    for k in -20..=20 {
        let eps = k as f64 * 1e-11;
        let pb = Pose::from_position([0.0, 1.5 + eps, 0.0]).unwrap();
        let s = signed_distance(&a, &pa, &b, &pb, &o).unwrap();
        assert!(
            (s.distance - eps).abs() < 1e-12,
            "eps {eps:e}: sd {:e} ({:?})",
            s.distance,
            s.path
        );
        if let Some(p) = prev {
            assert!(s.distance >= p - 1e-13);
        }
        prev = Some(s.distance);
    }
}

/// The gradient of the signed distance against central differences of the query itself, on
/// random poses of a strictly convex shape (sphere, ellipsoid: the witness points are unique)
/// against every kind, separated and overlapping; and equal to `distance_gradient` on the
/// separated ones.
#[test]
fn gradient_matches_finite_differences() {
    use common::random::{Kind, Rng as Random, KINDS};
    use dcol::{distance_gradient, proximity, signed_distance_gradient};
    // The default tolerance (deep curved overlaps at 1e-12 leave the certificate open more
    // often); its answers are good to 1e-10·ℓ, so the step 1e-4 keeps that noise at 1e-6.
    let opts = Options::default();
    let sd_at = |s: &[Shape; 2], t: &[f64; 14]| {
        let p1 = Pose::new([t[0], t[1], t[2]], [t[3], t[4], t[5], t[6]]).unwrap();
        let p2 = Pose::new([t[7], t[8], t[9]], [t[10], t[11], t[12], t[13]]).unwrap();
        let d = signed_distance(&s[0], &p1, &s[1], &p2, &opts).unwrap();
        d.status.is_converged().then_some(d.distance)
    };
    let (mut worst, mut cases, mut open) = (0.0f64, 0, 0);
    for k1 in [Kind::Sphere, Kind::Ellipsoid] {
        for k2 in KINDS {
            for index in 0..12u64 {
                let mut rng =
                    Random::new(0x5D9A_0000 ^ (k1.index() << 8) ^ (k2.index() << 4) ^ index);
                let s = [k1.random(&mut rng), k2.random(&mut rng)];
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                let mut t = [0.0; 14];
                t[3..7].copy_from_slice(&rng.quat());
                t[10..14].copy_from_slice(&rng.quat());
                let u = rng.unit::<3>();
                t[7..10].copy_from_slice(&u);
                let (p1, p2) = (
                    Pose::new([0.0; 3], [t[3], t[4], t[5], t[6]]).unwrap(),
                    Pose::new(u, [t[10], t[11], t[12], t[13]]).unwrap(),
                );
                let a = proximity(&s[0], &p1, &s[1], &p2, &Options::default())
                    .unwrap()
                    .alpha;
                let target = [1.4, 0.7][index as usize % 2];
                for j in 0..3 {
                    t[7 + j] = u[j] * target / a;
                }
                let p2 = Pose::new([t[7], t[8], t[9]], [t[10], t[11], t[12], t[13]]).unwrap();
                let (d, g) = signed_distance_gradient(&s[0], &p1, &s[1], &p2, &opts).unwrap();
                if !d.status.is_converged() {
                    open += 1;
                    continue;
                }
                if d.distance > 0.0 {
                    let (_, gd) = distance_gradient(&s[0], &p1, &s[1], &p2, &opts).unwrap();
                    for c in 0..14 {
                        let scale = if c % 7 < 3 { 1.0 } else { 1.0 / ell };
                        assert!(
                            (g[c] - gd[c]).abs() * scale <= 1e-9,
                            "{k1:?}-{k2:?}#{index}"
                        );
                    }
                }
                for c in 0..14 {
                    let h = if c % 7 < 3 { 1e-4 * ell } else { 1e-4 };
                    let (mut tp, mut tm) = (t, t);
                    tp[c] += h;
                    tm[c] -= h;
                    let (Some(fp), Some(fm)) = (sd_at(&s, &tp), sd_at(&s, &tm)) else {
                        continue;
                    };
                    let fd = (fp - fm) / (2.0 * h);
                    // Non-dimensional: rotation columns over ℓ.
                    let scale = if c % 7 < 3 { 1.0 } else { 1.0 / ell };
                    let e = (g[c] - fd).abs() * scale / (g[c].abs() * scale).max(1.0);
                    assert!(
                        e <= 1e-5,
                        "{k1:?}-{k2:?}#{index} column {c}: {} vs {fd}",
                        g[c]
                    );
                    worst = worst.max(e);
                }
                cases += 1;
            }
        }
    }
    println!("{cases} cases ({open} left open by the certificate), worst relative error {worst:e}");
    assert!(
        cases >= 150 && open * 10 <= cases,
        "{cases} cases, {open} open"
    );
}

/// A sphere whose centre lies inside a polytope that is not a box (an octahedron
/// |x| + |y| + |z| ≤ 1, turned): the depth is the centre's distance to the nearest facet plane
/// plus the radius, the normal that facet's, in either order; and with the centre outside,
/// the polytope's closest point (a vertex) minus the radius.
#[test]
fn sphere_in_an_octahedron() {
    let s3 = 3f64.sqrt();
    let mut a = Vec::new();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                a.push([sx, sy, sz]);
            }
        }
    }
    let octa = Shape::polytope(&a, &[1.0; 8]).unwrap();
    let ball = Shape::sphere(0.2).unwrap();
    let q = [0.9, 0.1, -0.3, 0.2];
    let rot = rotation_from_quaternion(q);
    let opts = Options::default();
    // Inside, nearest the facet (1, 1, ±1)/√3: depth (1 − 0.15)/√3 + 0.2.
    let c = Vec3::new(0.1, 0.05, 0.0);
    let (po, pb) = (
        pose(Vec3::new(0.3, -0.2, 0.5), q),
        pose(Vec3::new(0.3, -0.2, 0.5) + rot * c, q),
    );
    let want = -(0.85 / s3 + 0.2);
    for (sd, sign) in [
        (signed_distance(&octa, &po, &ball, &pb, &opts).unwrap(), 1.0),
        (
            signed_distance(&ball, &pb, &octa, &po, &opts).unwrap(),
            -1.0,
        ),
    ] {
        assert!(
            (sd.distance - want).abs() < 1e-14,
            "{} vs {want}",
            sd.distance
        );
        let n = rot.transpose() * sd.normal * sign;
        assert!(
            (n.x - 1.0 / s3).abs() < 1e-14 && (n.y - 1.0 / s3).abs() < 1e-14,
            "{n:?}"
        );
        assert!((sd.closest2 - sd.closest1 - sd.normal * sd.distance).norm() < 1e-14);
        assert_eq!(sd.path, dcol::DistancePath::ClosedForm);
    }
    // Outside, beyond the vertex (1, 0, 0): ‖c − e_x‖ − ρ.
    let c = Vec3::new(1.1, 0.05, 0.0);
    let pb = pose(Vec3::new(0.3, -0.2, 0.5) + rot * c, q);
    let sd = signed_distance(&octa, &po, &ball, &pb, &opts).unwrap();
    let want = (c - Vec3::x()).norm() - 0.2;
    assert!(
        (sd.distance - want).abs() < 1e-13,
        "{} vs {want}",
        sd.distance
    );
}

/// A sphere against a cone (height 1, half angle 45°: apex at x = −3/4, base of radius 1 at
/// x = 1/4), in closed form in the offset's meridian plane: centre inside near the base and
/// near the side, and outside beyond the base; both orders, turned.
#[test]
fn sphere_and_a_cone() {
    let cone = Shape::cone(1.0, std::f64::consts::FRAC_PI_4).unwrap();
    let ball = Shape::sphere(0.1).unwrap();
    let q = [0.8, -0.3, 0.4, 0.1];
    let rot = rotation_from_quaternion(q);
    let origin = Vec3::new(0.2, 0.1, -0.4);
    let opts = Options::default();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // (centre in the cone's frame, signed distance, unit normal from the cone in its frame)
    let cases = [
        (Vec3::new(0.0, 0.1, 0.0), -(0.25 + 0.1), Vec3::x()),
        (
            Vec3::new(-0.3, 0.0, 0.4),
            -((0.75 - 0.7) * h + 0.1),
            Vec3::new(-h, 0.0, h),
        ),
        (Vec3::new(0.5, 0.2, 0.0), 0.25 - 0.1, Vec3::x()),
    ];
    let pc = pose(origin, q);
    for (c, want, n) in cases {
        let pb = pose(origin + rot * c, q);
        for (sd, sign) in [
            (signed_distance(&cone, &pc, &ball, &pb, &opts).unwrap(), 1.0),
            (
                signed_distance(&ball, &pb, &cone, &pc, &opts).unwrap(),
                -1.0,
            ),
        ] {
            assert!(
                (sd.distance - want).abs() < 1e-14,
                "{c:?}: {} vs {want}",
                sd.distance
            );
            assert!(
                (rot.transpose() * sd.normal * sign - n).norm() < 1e-14,
                "{c:?}"
            );
            assert_eq!(sd.path, dcol::DistancePath::ClosedForm);
        }
    }
}

/// A sphere centred inside an ellipsoid (semi-axes 2, 1, 0.5, turned): on the short axis the
/// depth is that semi-axis; off the axes the nearest boundary point solves Eberly's secular
/// equation, checked against a dense search over the boundary; both orders.
#[test]
fn sphere_inside_an_ellipsoid() {
    let semi = [2.0, 1.0, 0.5];
    let p = [[1.0 / 4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 4.0]];
    let ell = Shape::ellipsoid(p).unwrap();
    let ball = Shape::sphere(0.05).unwrap();
    let q = [0.7, 0.2, -0.5, 0.4];
    let rot = rotation_from_quaternion(q);
    let origin = Vec3::new(-0.3, 0.2, 0.1);
    let pe = pose(origin, q);
    let opts = Options::default();
    // The nearest boundary point to c by a dense search over the surface (then a local one).
    let search = |c: &Vec3| {
        let point = |th: f64, ph: f64| {
            Vec3::new(
                semi[0] * th.sin() * ph.cos(),
                semi[1] * th.sin() * ph.sin(),
                semi[2] * th.cos(),
            )
        };
        let (mut best, mut at) = (f64::INFINITY, (0.0, 0.0));
        for i in 0..=400 {
            for j in 0..800 {
                let (th, ph) = (
                    std::f64::consts::PI * i as f64 / 400.0,
                    std::f64::consts::TAU * j as f64 / 800.0,
                );
                let d = (point(th, ph) - c).norm();
                if d < best {
                    (best, at) = (d, (th, ph));
                }
            }
        }
        let mut step = 0.01;
        while step > 1e-12 {
            let mut moved = false;
            for (dt, dp) in [(step, 0.0), (-step, 0.0), (0.0, step), (0.0, -step)] {
                let d = (point(at.0 + dt, at.1 + dp) - c).norm();
                if d < best {
                    (best, at, moved) = (d, (at.0 + dt, at.1 + dp), true);
                }
            }
            if !moved {
                step *= 0.5;
            }
        }
        best
    };
    for c in [
        Vec3::new(0.0, 0.0, 0.1),
        Vec3::new(0.7, -0.3, 0.2),
        Vec3::new(-1.2, 0.4, -0.15),
    ] {
        let want = -(search(&c) + 0.05);
        let pb = pose(origin + rot * c, q);
        for sd in [
            signed_distance(&ell, &pe, &ball, &pb, &opts).unwrap(),
            signed_distance(&ball, &pb, &ell, &pe, &opts).unwrap(),
        ] {
            assert!(
                (sd.distance - want).abs() < 1e-10,
                "{c:?}: {} vs {want}",
                sd.distance
            );
            assert_eq!(sd.path, dcol::DistancePath::ClosedForm);
            assert!((sd.closest2 - sd.closest1 - sd.normal * sd.distance).norm() < 1e-13);
        }
    }
    // On the short axis: the depth is that semi-axis less the offset.
    let pb = pose(origin + rot * Vec3::new(0.0, 0.0, 0.1), q);
    let sd = signed_distance(&ell, &pe, &ball, &pb, &opts).unwrap();
    assert!(
        (sd.distance + (0.4 + 0.05)).abs() < 1e-14,
        "{}",
        sd.distance
    );
}

/// A polytope overlapping a padded polygon (from the random sweep at 400 pairs per kind) whose
/// EPA bracket closed with its best lower bound from an older face lying 6.7e-3 ℓ inside its
/// support plane: the witnesses from that face's barycentric point missed the identity
/// `closest2 − closest1 = distance·normal` by as much. They are now where the ray from d along
/// the normal leaves the polytope, within the bracket of the identity.
#[test]
fn epa_witnesses_meet_the_identity_when_an_older_face_gave_the_bound() {
    let a = [
        [-0.1455341206910462, 0.8936268776126459, 1.6025422966492153],
        [1.083463439934545, 1.6603905896699547, 0.09651045807186262],
        [1.639877046166702, -0.07754888493954261, 1.0991183622585692],
        [0.02527925469338055, 1.0459560118000732, -1.6180274939179071],
        [0.8717003997470388, -1.736339881588577, -0.12948644254695893],
        [-1.550301152579949, 0.06959770969205842, 0.892743490178842],
        [
            -0.14456376296298432,
            -0.8635249004015462,
            1.5457728293778776,
        ],
        [-1.006565000392277, 1.5501504388082925, 0.04430214651798514],
        [1.7195938364752963, 0.09891895132913106, -1.080060849783396],
        [
            0.09623368710271837,
            -0.8999375399571641,
            -1.7575095862615404,
        ],
        [
            -0.9082515253217835,
            -1.4979717028023094,
            -0.06714343207704936,
        ],
        [
            -1.7656446059214796,
            0.028761676786554558,
            -0.9176946244809342,
        ],
    ];
    let b = [
        0.5955661170399245,
        0.9143985749095058,
        0.7330318030929298,
        0.7775002065085859,
        0.853698639557438,
        0.9709034664521372,
        0.8096348464203615,
        1.0013709250368001,
        0.6980411920173032,
        0.7902730103568978,
        1.1440358491425653,
        0.5186551758286096,
    ];
    let polytope = Shape::polytope(&a, &b).unwrap();
    let c = [
        [-0.3358984724318488, 0.9418981984365139],
        [-0.9889509248688338, 0.14824327371276616],
        [-0.5521659150014533, -0.8337342516117519],
        [0.4996878375364766, -0.8662055558688825],
        [0.8020452697200035, 0.597263246248894],
    ];
    let d = [
        0.8000006829085651,
        0.47543535490763744,
        0.7069649906983697,
        0.5082250512809117,
        0.43951078181427095,
    ];
    let polygon = Shape::polygon(&c, &d, 0.15224779354588275).unwrap();
    let p1 = Pose::new(
        [0.1, -0.2, 0.3],
        [
            0.40532400943524255,
            -0.877412244479881,
            -0.1548541233394683,
            0.20464701585139689,
        ],
    )
    .unwrap();
    let p2 = Pose::new(
        [
            -0.009252469680020123,
            -0.035290635794977904,
            0.29237885907053335,
        ],
        [
            0.7289205422092533,
            -0.4530595308999354,
            0.5057272845526125,
            -0.08747467213507874,
        ],
    )
    .unwrap();
    let s = signed_distance(&polytope, &p1, &polygon, &p2, &Options::default()).unwrap();
    assert_eq!(s.status, SolveStatus::Converged);
    assert!((s.distance + 0.6251044976099122).abs() < 1e-9, "{s:?}");
    let ell = polygon.bounding_radius();
    let w = (s.closest2 - s.closest1 - s.normal * s.distance).norm() / ell;
    assert!(w <= 1e-9, "witness identity off by {w:e} ℓ ({:?})", s.path);
}
