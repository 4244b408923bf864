//! Two boxes nearly face to face and turned a little (a settling stack or pyramid), whose least
//! separating axis is often an edge pair: the boxes' closed-form manifold
//! (`query::contact_boxes`, which clips the faces in the reference box's frame) against the
//! general path on the same geometry (each box as the convex hull of its corners turned by a
//! fixed rotation, posed back by its inverse: not recognised as a box, so its manifold is the
//! general signed distance, then the general face clipping in the plane orthogonal to the
//! normal).

mod common;

use common::random::Rng;
use dcol::{contact_manifold, Options, Pose, Shape};

type Q = [f64; 4];

fn mul(a: Q, b: Q) -> Q {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn axis_angle(axis: [f64; 3], angle: f64) -> Q {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

fn rotate(q: Q, v: [f64; 3]) -> [f64; 3] {
    let p = mul(mul(q, [0.0, v[0], v[1], v[2]]), [q[0], -q[1], -q[2], -q[3]]);
    [p[1], p[2], p[3]]
}

/// The box of half extents `h` as a hull of its corners turned by `fixed` (posed with
/// `q ⊗ fixed⁻¹`, the same solid).
fn hull_of_box(h: [f64; 3], fixed: Q) -> Shape {
    let mut pts = vec![];
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            for sz in [-1.0, 1.0] {
                pts.push(rotate(fixed, [sx * h[0], sy * h[1], sz * h[2]]));
            }
        }
    }
    Shape::convex_hull(&pts, 0.0).unwrap()
}

#[test]
fn edge_pair_boxes_match_the_general_path() {
    let mut rng = Rng::new(32);
    let opts = Options::default();
    let fixed = axis_angle(
        {
            let a: [f64; 3] = [0.3, -0.5, 0.8];
            let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            [a[0] / n, a[1] / n, a[2] / n]
        },
        0.9,
    );
    let inv = [fixed[0], -fixed[1], -fixed[2], -fixed[3]];
    let (mut cases, mut edge_axes, mut multi) = (0, 0, 0);
    let (mut worst_point, mut worst_normal) = (0.0f64, 0.0f64);
    for trial in 0..2000 {
        let ha = [0.0; 3].map(|_| rng.range(0.05, 0.3));
        let hb = [0.0; 3].map(|_| rng.range(0.05, 0.3));
        let tilt = [1e-7, 1e-6, 1e-4, 1e-2][trial % 4] * rng.range(0.5, 1.0);
        // The whole pair turned anywhere; box b on a's top face, turned by `tilt` about a
        // random axis and shifted sideways, `pen` deep.
        let world = axis_angle(rng.unit::<3>(), rng.range(0.0, 3.0));
        let qa = mul(world, axis_angle(rng.unit::<3>(), tilt));
        let qb = mul(world, axis_angle(rng.unit::<3>(), tilt));
        let pen = rng.range(1e-6, 1e-2);
        let off = [
            rng.range(-ha[0], ha[0]),
            rng.range(-ha[1], ha[1]),
            ha[2] + hb[2] - pen,
        ];
        let ra = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        let d = rotate(world, off);
        let rb = [ra[0] + d[0], ra[1] + d[1], ra[2] + d[2]];
        let (a, b) = (
            Shape::cuboid(ha[0], ha[1], ha[2]).unwrap(),
            Shape::cuboid(hb[0], hb[1], hb[2]).unwrap(),
        );
        let (ga, gb) = (hull_of_box(ha, fixed), hull_of_box(hb, fixed));
        let (pa, pb) = (Pose::new(ra, qa).unwrap(), Pose::new(rb, qb).unwrap());
        let (pga, pgb) = (
            Pose::new(ra, mul(qa, inv)).unwrap(),
            Pose::new(rb, mul(qb, inv)).unwrap(),
        );
        let m = contact_manifold(&a, &pa, &b, &pb, 0.0, 8, &opts).unwrap();
        let g = contact_manifold(&ga, &pga, &gb, &pgb, 0.0, 8, &opts).unwrap();
        assert!(
            (m.signed_distance - g.signed_distance).abs() <= 1e-12,
            "trial {trial}: {} against {}",
            m.signed_distance,
            g.signed_distance
        );
        if m.signed_distance > 0.0 {
            continue;
        }
        cases += 1;
        worst_normal = worst_normal.max((m.normal - g.normal).norm());
        assert!((m.normal - g.normal).norm() <= 1e-12, "trial {trial}");
        // An edge pair's normal is along no face normal of either box.
        let (fa, fb) = (pa.rotation(), pb.rotation());
        let off_faces = (0..3).all(|i| {
            fa.column(i).dot(&m.normal).abs() < 1.0 - 1e-15
                && fb.column(i).dot(&m.normal).abs() < 1.0 - 1e-15
        });
        edge_axes += usize::from(off_faces);
        assert_eq!(m.len(), g.len(), "trial {trial}: {m:?} against {g:?}");
        assert!(!m.is_empty(), "trial {trial}");
        multi += usize::from(m.len() >= 3);
        for c in m.contacts() {
            let (near, depth) = g
                .contacts()
                .iter()
                .map(|o| ((o.position - c.position).norm(), o.depth))
                .fold((f64::INFINITY, 0.0), |x, y| if y.0 < x.0 { y } else { x });
            worst_point = worst_point.max(near);
            assert!(
                near <= 1e-12,
                "trial {trial}: point {c:?} is {near} from the general path's"
            );
            assert!((depth - c.depth).abs() <= 1e-12, "trial {trial}");
        }
        // The deepest point is the overlap's depth.
        let deepest = m
            .contacts()
            .iter()
            .map(|c| c.depth)
            .fold(f64::MIN, f64::max);
        assert!(
            (deepest + m.signed_distance).abs() <= 1e-12,
            "trial {trial}"
        );
    }
    println!(
        "{cases} overlapping pairs, {edge_axes} with an edge pair's normal, {multi} with three \
         points or more; worst point {worst_point:.1e}, normal {worst_normal:.1e}"
    );
    assert!(multi >= 1000, "{multi}");
    assert!(cases >= 1900, "{cases}");
    assert!(edge_axes >= 300, "{edge_axes}");
}
