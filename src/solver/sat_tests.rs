//! Unit tests of `sat` (its private functions against the code they replaced).

use super::*;
use crate::math::lcg;
use crate::math::Pose;
use crate::shapes::Shape;

/// `two_boxes` as it was written before the edge axes were written out (the cross product,
/// its norm and Cᵀl in full): the reference for `two_boxes`.
fn two_boxes_full(
    ea: &Vec3,
    eb: &Vec3,
    c: &Mat3,
    t: &Vec3,
    beyond: Real,
) -> Result<(Real, Vec3, Axis), Real> {
    let abs = c.abs();
    let mut best = (Real::INFINITY, Vec3::zeros(), Axis::Face1(0));
    let mut keep = |v: Real, n: Vec3, axis: Axis| {
        if v < best.0 {
            best = (v, n, axis);
        }
        v < -beyond
    };
    for k in 0..3 {
        let rb = eb.x * abs[(k, 0)] + eb.y * abs[(k, 1)] + eb.z * abs[(k, 2)];
        let s = if t[k] < 0.0 { -1.0 } else { 1.0 };
        let v = ea[k] + rb - t[k].abs();
        let axis = Axis::Face1(k + if s < 0.0 { 3 } else { 0 });
        if keep(v, Vec3::ith(k, s), axis) {
            return Err(-v);
        }
    }
    for j in 0..3 {
        let col = c.column(j).into_owned();
        let ra = ea.x * abs[(0, j)] + ea.y * abs[(1, j)] + ea.z * abs[(2, j)];
        let tj = col.dot(t);
        let s = if tj < 0.0 { -1.0 } else { 1.0 };
        let v = ra + eb[j] - tj.abs();
        if keep(v, col * s, Axis::Face2(j + if s > 0.0 { 3 } else { 0 })) {
            return Err(-v);
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let l = Vec3::ith(i, 1.0).cross(&c.column(j));
            let len = l.norm();
            if !(len > PARALLEL) {
                continue;
            }
            let m = c.tr_mul(&l);
            let ra = ea.x * l.x.abs() + ea.y * l.y.abs() + ea.z * l.z.abs();
            let rb = eb.x * m.x.abs() + eb.y * m.y.abs() + eb.z * m.z.abs();
            let lt = l.dot(t);
            let s = if lt < 0.0 { -1.0 } else { 1.0 };
            let v = (ra + rb - lt.abs()) / len;
            if keep(v, l * (s / len), Axis::Edges(len)) {
                return Err(-v);
            }
        }
    }
    Ok(best)
}

/// `two_boxes` gives the full products' answers to the last bit (a zero's sign aside: the
/// normals compared with `==`): 60 000 box pairs at random attitudes, quarter turns (exact
/// zeros in C), tilts of 1e-3 to 1e-12 rad from a quarter turn (nearly parallel edges),
/// overlapping, touching and apart, margins 0 and 0.05; a few with a non-finite centre.
#[test]
fn edge_axes_are_the_full_products() {
    let mut r = lcg(0xb0b0);
    let (mut faces, mut edges, mut apart) = (0, 0, 0);
    for case in 0..60_000 {
        let e = |r: &mut dyn FnMut() -> Real| {
            Vec3::new(0.1 + r().abs(), 0.1 + r().abs(), 0.1 + r().abs())
        };
        let (ea, eb) = (e(&mut r), e(&mut r));
        let quarter = |r: &mut dyn FnMut() -> Real| {
            let h = 0.5_f64.sqrt();
            let q = [
                [1.0, 0.0, 0.0, 0.0],
                [h, h, 0.0, 0.0],
                [h, 0.0, h, 0.0],
                [0.5, 0.5, 0.5, 0.5],
            ];
            q[(r().abs() * 4.0) as usize % 4]
        };
        let q = match case % 4 {
            0 => [r(), r(), r(), r()],
            1 => quarter(&mut r),
            _ => {
                let [w, x, y, z] = quarter(&mut r);
                let tilt = [1e-3, 1e-6, 1e-9, 1e-12][case / 4 % 4] * r();
                let (a, b) = (tilt * r(), tilt * r());
                [w - a * x, x + a * w + b * z, y + b * w, z - b * x]
            }
        };
        let c = *Pose::new([0.0; 3], q).unwrap().rotation();
        let reach = (ea + eb).norm();
        let mut t = Vec3::new(r(), r(), r()) * reach * [0.5, 1.0, 1.5][case % 3];
        if case % 1000 == 7 {
            t[case % 3] = [Real::INFINITY, Real::NAN][case / 1000 % 2];
        }
        let beyond = [0.0, 0.05][case % 2];
        let (a, b) = (
            two_boxes(&ea, &eb, &c, &t, beyond),
            two_boxes_full(&ea, &eb, &c, &t, beyond),
        );
        match (a, b) {
            (Ok((va, na, xa)), Ok((vb, nb, xb))) => {
                assert_eq!(va.to_bits(), vb.to_bits(), "case {case}");
                assert_eq!(na, nb, "case {case}");
                match (xa, xb) {
                    (Axis::Face1(p), Axis::Face1(q)) | (Axis::Face2(p), Axis::Face2(q)) => {
                        assert_eq!(p, q, "case {case}");
                        faces += 1;
                    }
                    (Axis::Edges(p), Axis::Edges(q)) => {
                        assert_eq!(p.to_bits(), q.to_bits(), "case {case}");
                        edges += 1;
                    }
                    _ => panic!("case {case}: {xa:?} {xb:?}"),
                }
            }
            (Err(ga), Err(gb)) => {
                assert_eq!(ga.to_bits(), gb.to_bits(), "case {case}");
                apart += 1;
            }
            _ => panic!("case {case}"),
        }
    }
    assert!(
        faces > 5_000 && edges > 2_000 && apart > 5_000,
        "{faces} {edges} {apart}"
    );
}

/// The support feature of an eight-vertex polytope (`support_eight`) is the listed path's,
/// to the last bit: random boxes (and random hulls of eight points) at random attitudes, along
/// random directions and along the body axes and face diagonals (where 2 and 4 vertices
/// tie), tolerances 0 to 1e-3, outputs of 3 and 48 slots.
#[test]
fn eight_vertices_are_the_listed_path() {
    let mut r = lcg(0x5a7e1);
    let (mut cases, mut sizes) = (0, [0usize; 9]);
    for i in 0..6000 {
        let shape = if i % 4 == 3 {
            let pts: Vec<[Real; 3]> = (0..8)
                .map(|k| {
                    let s = |b: usize| if k >> b & 1 == 1 { 1.0 } else { -1.0 };
                    [s(0) + 0.3 * r(), s(1) + 0.3 * r(), s(2) + 0.3 * r()]
                })
                .collect();
            Shape::convex_hull(&pts, 0.0).unwrap()
        } else {
            Shape::cuboid(0.6 + 0.5 * r(), 0.6 + 0.5 * r(), 0.6 + 0.5 * r()).unwrap()
        };
        let poly = shape.as_polytope().unwrap();
        if poly.vertices().len() != 8 {
            continue;
        }
        let pose = Pose::new([r(), r(), r()], [r(), r(), r(), r()]).unwrap();
        let rot = pose.rotation();
        let body = match i % 3 {
            0 => Vec3::new(r(), r(), r()),
            1 => Vec3::ith(i % 7 % 3, if r() < 0.0 { -1.0 } else { 1.0 }),
            _ => {
                let (a, b) = (i % 3, (i + 1) % 3);
                (Vec3::ith(a, 1.0) + Vec3::ith(b, r().signum())) * 0.5_f64.sqrt()
            }
        };
        let m = rot * body;
        let tol = [0.0, 1e-12, 1e-9, 1e-3][i % 4];
        let placed = Placed {
            poly,
            rot,
            pos: *pose.position(),
        };
        for slots in [3, 48] {
            let (mut a, mut b) = ([Vec3::zeros(); 48], [Vec3::zeros(); 48]);
            let ka = support_feature(&placed, &m, tol, &mut a[..slots]);
            let kb = support_listed(&placed, &rot.tr_mul(&m), tol, &mut b[..slots]);
            assert_eq!(ka, kb, "case {i}");
            for (p, q) in a[..ka].iter().zip(&b[..kb]) {
                let bits = |v: &Vec3| v.map(Real::to_bits);
                assert_eq!(bits(p), bits(q), "case {i}");
            }
            sizes[ka] += 1;
        }
        cases += 1;
    }
    assert!(cases > 5000, "{cases}");
    // Vertices, edges and faces all met.
    assert!(
        sizes[1] > 1000 && sizes[2] > 1000 && sizes[3] > 500,
        "{sizes:?}"
    );
}

/// `order` is the sort it replaced (both angles computed in the comparator), bit for bit:
/// 20 000 faces of 3 to 48 points (random in a plane, on a circle, regular polygons with
/// repeated points and exact ties in angle, about random and axis-aligned axes).
#[test]
fn order_is_the_comparator_sort() {
    fn old(pts: &mut [Vec3], axis: &Vec3) {
        let c = pts.iter().sum::<Vec3>() / pts.len() as Real;
        let u = (pts[0] - c).try_normalize(0.0).unwrap_or_else(Vec3::x);
        let v = axis.cross(&u);
        pts.sort_by(|x, y| {
            let (dx, dy) = (x - c, y - c);
            dx.dot(&v)
                .atan2(dx.dot(&u))
                .total_cmp(&dy.dot(&v).atan2(dy.dot(&u)))
        });
    }
    let mut r = lcg(0x0dde);
    let mut moved = 0;
    for case in 0..20_000 {
        let k = 3 + (case % 46);
        let axis = match case % 3 {
            0 => Vec3::z(),
            _ => Vec3::new(r(), r(), r()).normalize(),
        };
        let e1 = axis.cross(&Vec3::new(r(), r(), r())).normalize();
        let e2 = axis.cross(&e1);
        let centre = Vec3::new(r(), r(), r()) * 10.0;
        let mut pts = [Vec3::zeros(); MAX_POINTS];
        for (i, p) in pts[..k].iter_mut().enumerate() {
            let (a, b) = match case % 4 {
                0 => (r(), r()),
                1 => {
                    let t = std::f64::consts::PI * r();
                    (t.cos(), t.sin())
                }
                // A regular polygon, each corner twice: ties in angle.
                2 => {
                    let t = std::f64::consts::TAU * (i / 2) as Real / k as Real;
                    (t.cos(), t.sin())
                }
                _ => ((i % 3) as Real, (i % 2) as Real),
            };
            *p = centre + e1 * a + e2 * b;
        }
        let mut want = pts;
        old(&mut want[..k], &axis);
        let before = pts;
        order(&mut pts[..k], &axis);
        let bits = |v: &Vec3| v.map(Real::to_bits);
        for (p, q) in pts[..k].iter().zip(&want[..k]) {
            assert_eq!(bits(p), bits(q), "case {case}");
        }
        moved += usize::from(pts[..k] != before[..k]);
    }
    assert!(moved > 10_000, "{moved}");
}

/// `Body::h` and `Body::h_both` are the polytope's support value at `m` and `−m`, bit for bit:
/// 4 000 polytopes (hulls of 4 to 40 random points, boxes, hulls of eight box corners) at
/// random directions, the axes and the face diagonals (ties of two and four vertices), and NaN.
#[test]
fn both_signs_are_two_supports() {
    let mut r = lcg(0xb0d1);
    let mut scanned = 0;
    for case in 0..4_000 {
        let shape = match case % 3 {
            0 => Shape::cuboid(0.2 + r().abs(), 0.2 + r().abs(), 0.2 + r().abs()).unwrap(),
            1 => {
                let (x, y, z) = (0.2 + r().abs(), 0.2 + r().abs(), 0.2 + r().abs());
                let pts: Vec<[Real; 3]> = (0..8)
                    .map(|i| {
                        let s = |b: usize| if i & b == 0 { -1.0 } else { 1.0 };
                        [s(1) * x + 0.1 * x, s(2) * y, s(4) * z]
                    })
                    .collect();
                Shape::convex_hull(&pts, 0.0).unwrap()
            }
            _ => {
                let n = 4 + case % 37;
                let pts: Vec<[Real; 3]> = (0..n).map(|_| [r(), r(), r()]).collect();
                match Shape::convex_hull(&pts, 0.0) {
                    Ok(s) => s,
                    Err(_) => continue,
                }
            }
        };
        let Some(poly) = shape.as_polytope() else {
            continue;
        };
        let body = Body::of(poly);
        scanned += usize::from(matches!(body, Body::Poly(p) if p.vertices().len() < SCAN_BOTH));
        for j in 0..12 {
            let m = match j {
                0..=2 => Vec3::ith(j, 1.0),
                3..=5 => Vec3::new(1.0, 1.0, 0.0).component_mul(&Vec3::new(1.0, r(), 1.0)),
                6 => Vec3::new(Real::NAN, 0.0, 1.0),
                _ => Vec3::new(r(), r(), r()),
            };
            let (p, n) = body.h_both(&m);
            // The polytope's own support value (a box's: the closed form); a NaN's sign bit
            // is the instruction's operand order's, so NaN only as NaN.
            let want = |m: &Vec3| match body {
                Body::Box(_) => body.h(m),
                Body::Poly(q) => q.support_value(m),
            };
            let same = |x: Real, y: Real| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
            assert!(same(p, want(&m)), "case {case} {j}");
            assert!(same(n, want(&-m)), "case {case} {j}");
            assert!(same(body.h(&m), want(&m)), "case {case} {j}");
            assert!(same(body.h(&-m), want(&-m)), "case {case} {j}");
        }
    }
    assert!(scanned > 1_500, "{scanned}");
}
