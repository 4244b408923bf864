//! `query::contact`'s unit tests: a box's fast feature and its closed form on a half-space
//! against the general path.

use super::*;
use crate::query::test_support::lcg;

/// A box's facet from its fast path is the general search's to the last bit (points, order,
/// normal): random attitudes and directions, the axes, the ties between facets (45
/// degrees, where both pick the last best facet).
#[test]
fn box_feature_is_the_general_one() {
    let b = Shape::cuboid(0.3, 0.2, 0.1).unwrap();
    assert!(box_polytope(&b).is_some());
    let mut rnd = lcg(7);
    let mut dirs = vec![];
    for v in [
        [1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, -1.0, 1.0],
        [0.0, 1.0, -1.0],
    ] {
        dirs.push(Vec3::from(v).normalize());
    }
    for _ in 0..400 {
        dirs.push(Vec3::new(rnd(), rnd(), rnd()).normalize());
    }
    for (i, d) in dirs.iter().enumerate() {
        let q = if i % 2 == 0 {
            [1.0, 0.0, 0.0, 0.0]
        } else {
            [rnd(), rnd(), rnd(), rnd()]
        };
        let pose = Pose::new([rnd(), rnd(), rnd()], q).unwrap();
        let (mut fast, mut general) = (Feature::empty(), Feature::empty());
        feature(&b, &pose, d, 1e-9, &mut fast);
        feature_general(&b, &pose, d, 1e-9, &mut general);
        assert_eq!(
            fast.pts.as_slice(),
            general.pts.as_slice(),
            "direction {d:?}"
        );
        assert_eq!(fast.face, general.face);
        // Every direction is within 55 degrees of a facet's normal: always a facet.
        assert_eq!(fast.k(), 4);
    }
}

/// A box on a half-space in closed form (`box_on_plane`) gives the general half-space path's
/// manifold to the last bit (`on_halfspace_alone`: the signed distance of one support point and
/// the box's feature facing the plane): random attitudes and positions, resting exactly aligned
/// and tilted by 1e-12 to 0.3 rad, standing on an edge (45 degrees), both argument orders,
/// margins 0 to 0.2, 1 to 16 points; and analytic cases.
#[test]
fn box_on_a_halfspace_is_the_general_path() {
    let mut rnd = lcg(11);
    let floor = Shape::halfspace(0.7).unwrap();
    let (mut points, mut closed, mut cases) = (0, 0, 0);
    for i in 0..6000 {
        let b = Shape::cuboid(0.3 + 0.2 * rnd(), 0.2 + 0.1 * rnd(), 0.1 + 0.05 * rnd()).unwrap();
        let qh = [rnd(), rnd(), rnd(), rnd()];
        let ph = Pose::new([rnd(), rnd(), rnd()], qh).unwrap();
        let n = ph.rotation().column(2).into_owned();
        // The box's attitude: random, or a body axis along -n turned by a small angle.
        let qb = match i % 4 {
            0 => [rnd(), rnd(), rnd(), rnd()],
            k => {
                let tilt = [0.0, 1e-12, 1e-6, 0.3, std::f64::consts::FRAC_PI_4][(i / 4) % 5];
                let axis = Vec3::new(rnd(), rnd(), rnd()).normalize() * (0.5 * tilt).sin();
                let turn = [(0.5 * tilt).cos(), axis.x, axis.y, axis.z];
                // The box's body axis k - 1 onto the plane's -n: the plane's attitude, then a
                // quarter turn about another axis, then the tilt.
                let quarter = match k {
                    1 => [0.0, 1.0, 0.0, 0.0],
                    2 => [0.5f64.sqrt(), 0.5f64.sqrt(), 0.0, 0.0],
                    _ => [0.5f64.sqrt(), 0.0, 0.5f64.sqrt(), 0.0],
                };
                mul(turn, mul(ph.quaternion(), quarter))
            }
        };
        // The box's centre about its size above or below the plane's boundary.
        let up = 0.7 + 0.1 + 0.3 * rnd();
        let offset = Vec3::new(rnd(), rnd(), rnd()) * 2.0;
        let c = ph.position() + n * up + (offset - n * n.dot(&offset));
        let pb = Pose::new([c.x, c.y, c.z], qb).unwrap();
        let margin = if i % 3 == 0 { 0.0 } else { 0.2 * rnd().abs() };
        let cap = 1 + i % 16;
        for hs_first in [true, false] {
            let (s1, p1, s2, p2) = if hs_first {
                (&floor, &ph, &b, &pb)
            } else {
                (&b, &pb, &floor, &ph)
            };
            let pair = super::super::halfspace::split(s1, p1, s2, p2)
                .unwrap()
                .unwrap();
            let mut general = Manifold::empty();
            let done = on_halfspace_alone(&pair, false, margin, cap, &mut general).unwrap();
            let Some(fast) = box_on_plane(&pair, margin) else {
                continue;
            };
            cases += 1;
            assert!(
                done.is_some(),
                "the closed form answers where the general path passes"
            );
            let mut pts = Points::new();
            for (p, d) in fast.pos.iter().zip(&fast.depth).take(fast.count) {
                pts.push(*p, *d);
            }
            let mut m = Manifold::empty();
            finish(&fast.sd, pts.slices(), cap, &mut m, (p1, p2)).unwrap();
            assert_eq!(m.normal, general.normal);
            assert_eq!(m.signed_distance, general.signed_distance);
            assert_eq!(m.contacts(), general.contacts(), "case {i}");
            points += m.len();
            closed += usize::from(m.len() >= 2);
        }
    }
    // Not vacuous: most cases are answered in closed form, most with points.
    assert!(
        cases > 11_000 && points > 15_000 && closed > 3_000,
        "{cases} {points} {closed}"
    );
    // Analytic: a 0.6 x 0.4 x 0.2 box resting 0.01 deep on the plane z = 0; then turned about x
    // by 0.1 rad with its lower edge 0.01 deep: the bottom face's other two corners are
    // 0.4 sin 0.1 higher, 0.4 sin 0.1 - 0.01 above the plane (within a margin of 0.05).
    let b = Shape::cuboid(0.3, 0.2, 0.1).unwrap();
    let ph = Pose::from_position([0.0, 0.0, -0.7]).unwrap();
    let pb = Pose::from_position([0.0, 0.0, 0.09]).unwrap();
    let pair = super::super::halfspace::split(&floor, &ph, &b, &pb)
        .unwrap()
        .unwrap();
    let f = box_on_plane(&pair, 0.0).unwrap();
    assert_eq!(f.count, 4);
    assert!((f.sd.distance + 0.01).abs() < 1e-15);
    for k in 0..4 {
        assert!((f.depth[k] - 0.01).abs() < 1e-15);
        assert!((f.pos[k].z + 0.005).abs() < 1e-15);
        assert!((f.pos[k].x.abs() - 0.3).abs() < 1e-15 && (f.pos[k].y.abs() - 0.2).abs() < 1e-15);
    }
    let t: Real = 0.1;
    let z = 0.2 * t.sin() + 0.1 * t.cos() - 0.01; // the lower edge 0.01 deep
    let pb = Pose::new([0.0, 0.0, z], [(0.5 * t).cos(), (0.5 * t).sin(), 0.0, 0.0]).unwrap();
    let pair = super::super::halfspace::split(&floor, &ph, &b, &pb)
        .unwrap()
        .unwrap();
    let f = box_on_plane(&pair, 0.05).unwrap();
    assert_eq!(f.count, 4);
    let high = 0.4 * t.sin() - 0.01;
    for k in 0..4 {
        let d = f.depth[k];
        assert!((d - 0.01).abs() < 1e-15 || (d + high).abs() < 1e-15, "{d}");
    }
    // With margin 0 only the lower edge's two corners.
    let f = box_on_plane(&pair, 0.0).unwrap();
    assert_eq!(f.count, 2);
}

/// `a ⊗ b` (scalar first).
fn mul(a: [Real; 4], b: [Real; 4]) -> [Real; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}
