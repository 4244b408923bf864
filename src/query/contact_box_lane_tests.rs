//! `box_contacts` against the path it short-cuts: `manifold` with `exact_distance` false (the C
//! function's), and `manifold_cached` with the same cache.

use super::*;
use crate::math::lcg;
use crate::query::{manifold, manifold_cached, Manifold, Options};

/// A random pair of box sizes and poses: resting (stacked along an axis within 2 % of touching,
/// quarter turns tilted by 0 to 1e-3 rad), random attitudes (edge-edge and corner contacts),
/// deep overlaps, and apart by up to a tenth of the size; `case` picks the kind.
fn pair(r: &mut impl FnMut() -> Real, case: usize) -> (Shape, Pose, Shape, Pose) {
    let size =
        |r: &mut dyn FnMut() -> Real| Vec3::new(0.1 + r().abs(), 0.1 + r().abs(), 0.1 + r().abs());
    let (h1, h2) = if case % 3 == 0 {
        (Vec3::new(0.5, 0.25, 0.25), Vec3::new(0.5, 0.25, 0.25))
    } else {
        (size(r), size(r))
    };
    let quarter = |r: &mut dyn FnMut() -> Real| {
        let h = 0.5_f64.sqrt();
        let q = [
            [1.0, 0.0, 0.0, 0.0],
            [h, h, 0.0, 0.0],
            [h, 0.0, h, 0.0],
            [0.5, 0.5, 0.5, 0.5],
            [0.9238795325112867, 0.0, 0.0, 0.3826834323650898],
        ];
        q[(r().abs() * 5.0) as usize % 5]
    };
    let tilt = |r: &mut dyn FnMut() -> Real, q: [Real; 4], case: usize| {
        let [w, x, y, z] = q;
        let t = [0.0, 1e-6, 1e-3, 1e-9, 1e-12, 1e-6][case / 7 % 6] * r();
        let (a, b) = (t * r(), t * r());
        [w - a * x, x + a * w + b * z, y + b * w, z - b * x]
    };
    let q = quarter(r);
    let q1 = tilt(r, q, case);
    let (q2, centre) = match case % 4 {
        // Resting: shape 2 on one of shape 1's facets, within 2 % of touching.
        0 | 1 => {
            let q = quarter(r);
            let q2 = tilt(r, q, case + 3);
            let p1 = Pose::new([0.0; 3], q1).unwrap();
            let p2 = Pose::new([0.0; 3], q2).unwrap();
            let k = (r().abs() * 3.0) as usize % 3;
            let dir = p1.rotation().column(k).into_owned() * r().signum();
            let reach = |p: &Pose, h: &Vec3| {
                let m = p.rotation().tr_mul(&dir);
                h.x * m.x.abs() + h.y * m.y.abs() + h.z * m.z.abs()
            };
            let gap = (reach(&p1, &h1) + reach(&p2, &h2)) * (1.0 + 0.02 * r());
            let slide = Vec3::new(r(), r(), r()) * 0.3 * h1.min();
            (q2, dir * gap + slide - dir * dir.dot(&slide))
        }
        // Random attitudes and centres, from deep overlap to apart.
        _ => {
            let reach = (h1 + h2).norm();
            let c = Vec3::new(r(), r(), r()) * reach * [0.3, 0.7, 1.0][case % 3];
            ([r(), r(), r(), r()], c)
        }
    };
    let origin = Vec3::new(r(), r(), r()) * 10.0;
    let p1 = Pose::new(origin.into(), q1).unwrap();
    let p2 = Pose::new((origin + centre).into(), q2).unwrap();
    let s1 = Shape::cuboid(h1.x, h1.y, h1.z).unwrap();
    let s2 = Shape::cuboid(h2.x, h2.y, h2.z).unwrap();
    (s1, p1, s2, p2)
}

type Written = Vec<(Vec3, Vec3, Real)>;

fn lane(
    (s1, p1, s2, p2): (&Shape, &Pose, &Shape, &Pose),
    margin: Real,
    cap: usize,
    cache: Option<&mut Cache>,
) -> Option<Written> {
    let mut out = Written::new();
    let k = box_contacts(s1, p1, s2, p2, margin, cap, cache, |i, p, n, d| {
        assert_eq!(i, out.len());
        out.push((*p, *n, d));
    })?;
    assert_eq!(k, out.len());
    Some(out)
}

fn assert_same(m: &Manifold, w: &Written, case: usize) {
    assert_eq!(m.len(), w.len(), "case {case}");
    let bits = |v: &Vec3| v.map(Real::to_bits);
    for (c, (p, n, d)) in m.contacts().iter().zip(w) {
        assert_eq!(bits(&c.position), bits(p), "case {case}");
        assert_eq!(bits(&c.normal), bits(n), "case {case}");
        assert_eq!(c.depth.to_bits(), d.to_bits(), "case {case}");
    }
}

/// The lane's points are the C function's general path's, bit for bit (count, order, positions,
/// normals, depths), wherever it answers: 60 000 random box pairs (`pair`), margins 0 and 0.05,
/// capacities 0, 1, 2, 4, 8 and 16; it answers most of them (see the counts below), and
/// declines a NaN, negative or infinite margin.
#[test]
fn lane_is_the_manifold() {
    let mut r = lcg(0xb0c5);
    let o = Options::default();
    let (mut answered, mut declined, mut touching, mut points) = (0, 0, 0, [0usize; 17]);
    let (mut declined_apart, mut declined_resting) = (0, 0);
    for case in 0..60_000 {
        let (s1, p1, s2, p2) = pair(&mut r, case);
        let margin = [0.0, 0.05][case % 2];
        let cap = [0, 1, 2, 4, 8, 16][case / 2 % 6];
        let mut m = Manifold::empty();
        let reference = manifold(&s1, &p1, &s2, &p2, margin, cap, &o, false, &mut m);
        match lane((&s1, &p1, &s2, &p2), margin, cap, None) {
            Some(w) => {
                assert!(reference.is_ok(), "case {case}");
                assert_same(&m, &w, case);
                answered += 1;
                points[w.len()] += 1;
            }
            None => {
                declined += 1;
                if m.signed_distance > 0.0 {
                    declined_apart += 1;
                } else if case % 4 < 2 {
                    declined_resting += 1;
                }
            }
        }
        if m.signed_distance <= margin && reference.is_ok() {
            touching += 1;
        }
        if case % 100 == 0 {
            for bad in [Real::NAN, -1e-3, Real::INFINITY] {
                assert!(lane((&s1, &p1, &s2, &p2), bad, cap, None).is_none());
            }
        }
    }
    assert!(touching > 30_000, "{touching}");
    // Declined (this seed: 5 215 of 60 000): pairs apart by less than the margin whose nearest
    // points are not across a facet (3 717), and overlaps the closed form leaves to the general
    // path (1 498 of the resting ones: edge pairs whose points it does not find, clippings that
    // miss the depth).
    let dr = declined_resting;
    assert!(
        declined * 8 < answered && dr * 20 < answered,
        "{answered} {declined} {declined_apart} {dr}"
    );
    assert!(
        points[4] > 5_000 && points[1] > 1_000 && points[8] > 30,
        "{points:?}"
    );
}

/// Boxes the general path refuses or answers at the edge of the doubles (offsets up to
/// ±1.7e308, whose gap overflows; sizes up to 1e300; tiny boxes): the lane declines exactly
/// where `manifold` errs (its finiteness test is the only guard against an overflowing gap)
/// and otherwise answers with the same bits.
#[test]
fn lane_declines_what_the_manifold_refuses() {
    let o = Options::default();
    let (mut refused, mut answered) = (0, 0);
    let sizes = [1.0, 1e-300, 1e300, 0.5];
    let offsets = [
        ([-1.7e308, 0.0, 0.0], [1.7e308, 0.0, 0.0]),
        ([-1e308, 0.0, 0.0], [1e308, 0.0, 0.0]),
        ([1.79e308, 0.0, 0.0], [1e308, 0.0, 0.0]),
        ([0.0, -1.7e308, 0.0], [0.0, 1.7e308, 1.0]),
        ([1e308, 1e308, 0.0], [1e308, 1e308, 0.5]),
        ([0.0; 3], [0.0, 0.0, 1.5]),
        ([1e300, 0.0, 0.0], [1e300, 0.0, 1.0]),
    ];
    for (k, (a, b)) in offsets.iter().enumerate() {
        for (j, &h) in sizes.iter().enumerate() {
            let s = Shape::cuboid(h, h, h).unwrap();
            let q = [[1.0, 0.0, 0.0, 0.0], [0.9, 0.1, 0.2, 0.3]][(k + j) % 2];
            let (p1, p2) = (Pose::new(*a, q).unwrap(), Pose::new(*b, q).unwrap());
            for margin in [0.0, 1.0, 1e308] {
                let mut m = Manifold::empty();
                let reference = manifold(&s, &p1, &s, &p2, margin, 4, &o, false, &mut m);
                match (lane((&s, &p1, &s, &p2), margin, 4, None), reference) {
                    (Some(w), Ok(_)) => {
                        assert_same(&m, &w, k);
                        answered += 1;
                    }
                    (Some(w), Err(e)) => panic!("offsets {k}, size {h}: lane {w:?}, path {e:?}"),
                    (None, Err(_)) => refused += 1,
                    (None, Ok(_)) => {}
                }
            }
        }
    }
    // Measured: 27 refused by both (the gaps that overflow), 45 answered by both.
    // Measured: 42 refused by both (the gaps that overflow), 33 answered by both.
    assert!(refused >= 30 && answered >= 25, "{refused} {answered}");
}

/// With a cache: each pair through three poses (a small move, then apart by more than the
/// margin now and then, so that caches hold separating normals and back-off counts), the lane
/// (or, where it declines, `manifold_cached`) against `manifold_cached` alone: the same points
/// and, after every call, the same cache to the last bit.
#[test]
fn lane_keeps_the_cache_as_manifold_cached() {
    let mut r = lcg(0xcac4e);
    let o = Options::default();
    let (mut answered, mut declined) = (0, 0);
    for case in 0..20_000 {
        let (s1, p1, s2, p2) = pair(&mut r, case);
        let margin = [0.0, 0.05][case % 2];
        let cap = [1, 4, 8][case % 3];
        let (mut c_ref, mut c_lane) = (Cache::new(), Cache::new());
        for step in 0..4 {
            let away = if (case + step) % 5 == 0 {
                3.0
            } else {
                1e-3 * step as Real
            };
            let shift = Vec3::new(r(), r(), r()) * away;
            let p2 = Pose::new((p2.position() + shift).into(), p2.quaternion()).unwrap();
            let mut m = Manifold::empty();
            let reference =
                manifold_cached(&s1, &p1, &s2, &p2, margin, cap, &o, &mut m, &mut c_ref);
            match lane((&s1, &p1, &s2, &p2), margin, cap, Some(&mut c_lane)) {
                Some(w) => {
                    assert!(reference.is_ok(), "case {case}");
                    assert_same(&m, &w, case);
                    answered += 1;
                }
                None => {
                    let mut m2 = Manifold::empty();
                    let again =
                        manifold_cached(&s1, &p1, &s2, &p2, margin, cap, &o, &mut m2, &mut c_lane);
                    assert_eq!(reference.is_ok(), again.is_ok(), "case {case}");
                    assert_eq!(m.len(), m2.len(), "case {case}");
                    declined += 1;
                }
            }
            assert_eq!(c_ref.words, c_lane.words, "case {case} step {step}");
            let bits = |c: &Cache| c.numbers.map(Real::to_bits);
            assert_eq!(bits(&c_ref), bits(&c_lane), "case {case} step {step}");
        }
    }
    assert!(
        answered > 40_000 && declined > 5_000,
        "{answered} {declined}"
    );
}
