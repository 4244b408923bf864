//! Overlaps the random sweep (`tests/overlap_sweep.rs`) found that `signed_distance` did not
//! answer, or answered with witnesses off their shapes; each is checked against the shapes
//! written out independently (`common::oracle`: a brute-force maximum over normals, the
//! support planes, the shapes' extents).

mod common;

use common::oracle::{brute, lower, Oracle, Posed};
use dcol::{signed_distance, DistancePath, Options, Pose, Shape, SignedDistance, SolveStatus};

/// Asserts a converged answer within 1e-9·ℓ of the brute force, attained at its normal, with
/// each witness on its support plane and not outside its shape, and the witness identity.
fn check(sd: &SignedDistance, s1: (&Shape, &Oracle, &Pose), s2: (&Shape, &Oracle, &Pose)) {
    let ell = s1.0.bounding_radius().max(s2.0.bounding_radius());
    let (o1, o2) = (Posed::new(s1.1, s1.2), Posed::new(s2.1, s2.2));
    assert_eq!(sd.status, SolveStatus::Converged, "{sd:?}");
    let b = brute(&o1, &o2, &sd.normal, 4000);
    let at_n = lower(&o1, &o2, &sd.normal);
    assert!(
        (b - sd.distance).abs() <= 1e-9 * ell && (at_n - sd.distance).abs() <= 1e-9 * ell,
        "sd {} vs brute force {b}, L(n) {at_n}",
        sd.distance
    );
    let n = sd.normal;
    let errors = [
        n.dot(&sd.closest1) - o1.h(&n),
        (-n).dot(&sd.closest2) - o2.h(&-n),
        o1.excess(&sd.closest1).max(0.0),
        o2.excess(&sd.closest2).max(0.0),
        (sd.closest2 - sd.closest1 - n * sd.distance).norm(),
    ];
    assert!(
        errors.iter().all(|e| e.abs() <= 1e-9 * ell),
        "witness errors (planes, outside, identity) {errors:?}"
    );
}

/// Two thin cones nearly apex to apex: the support points in the directions of a regular
/// tetrahedron (and of the opposite one) repeat a point, so EPA found no starting
/// tetrahedron and the query failed with `Internal("signed_distance: degenerate polytope")`
/// (16 of 10⁶ random overlaps, cone–cone and polytope–polytope). EPA now builds its start
/// one dimension at a time when both tetrahedra are flat.
#[test]
fn thin_cones_get_a_starting_tetrahedron() {
    let (h1, b1) = (0.43002380235319504, 0.21202394285594303);
    let (h2, b2) = (0.357009213307632, 0.35689600040762093);
    let (c1, c2) = (Shape::cone(h1, b1).unwrap(), Shape::cone(h2, b2).unwrap());
    let p1 = Pose::new(
        [2.401275623440524, -1.6890178335876584, -0.8812014962080355],
        [
            0.7209376274238406,
            0.2256710493159925,
            -0.7902098423319049,
            0.09819928329744743,
        ],
    )
    .unwrap();
    let p2 = Pose::new(
        [2.4012589890965947, -1.6886577277880117, -0.8812747242226526],
        [
            -0.3236592563390922,
            -0.836993187195966,
            -0.5304504904650377,
            0.7539388879066565,
        ],
    )
    .unwrap();
    let sd = signed_distance(&c1, &p1, &c2, &p2, &Options::default()).unwrap();
    check(
        &sd,
        (&c1, &Oracle::Cone(h1, b1), &p1),
        (&c2, &Oracle::Cone(h2, b2), &p2),
    );
}

/// A sphere whose centre lies 1.1e-5 from an ellipsoid's centre: the closed form's nearest
/// point lost its digits in `t + e₃²` and did not certify, and EPA, which then answered, ran
/// out of support calls (the two ends of the short axis are almost equally deep): 35 of 27 778
/// random sphere–ellipsoid overlaps were not converged. The closed form now solves for
/// `t + e₃²` itself.
#[test]
fn sphere_near_an_ellipsoids_centre_is_a_closed_form() {
    let p = [
        [
            2.9691640848417418,
            -0.6211661649879141,
            -0.04662330462052955,
        ],
        [-0.6211661649879141, 1.3787740288065087, -0.3502429821290144],
        [
            -0.04662330462052955,
            -0.3502429821290144,
            2.9513777988988874,
        ],
    ];
    let ball = Shape::sphere(0.48877897223957195).unwrap();
    let ellipsoid = Shape::ellipsoid(p).unwrap();
    let pm = nalgebra::Matrix3::from_fn(|i, j| p[i][j]);
    let oracle = Oracle::Ellipsoid(pm, pm.try_inverse().unwrap());
    let p1 = Pose::new(
        [2.847028100640091, -2.1455112160095866, -1.4806281314004586],
        [
            -0.5227097453347135,
            0.5010447645259842,
            0.12842684469800253,
            -0.5539752057537519,
        ],
    )
    .unwrap();
    let p2 = Pose::new(
        [2.8470215850875777, -2.1455186018451866, -1.4806312553513459],
        [
            -0.5386321757369231,
            0.6583268006613948,
            -0.08414177874425288,
            0.5017581941802408,
        ],
    )
    .unwrap();
    let sd = signed_distance(&ball, &p1, &ellipsoid, &p2, &Options::default()).unwrap();
    assert_eq!(sd.path, DistancePath::ClosedForm);
    check(
        &sd,
        (&ball, &Oracle::Sphere(0.48877897223957195), &p1),
        (&ellipsoid, &oracle, &p2),
    );
}

/// A box deep in a long cylinder: EPA's polish stalled short of its witness identity, and its
/// normal (the best lower bound) was kept with its witnesses, the box's 6.1e-6·ℓ inside its
/// support plane. The polish's witnesses are now kept only where they meet the identity;
/// otherwise they are taken where the ray from the offset along the normal leaves EPA's
/// polytope.
#[test]
fn box_in_a_cylinder_keeps_witnesses_on_both() {
    let h = [4.588713682981641, 3.8364337278293656, 1.1840044001142966];
    let (r, l) = (0.9470037232336211, 6.925031258312985);
    let boxed = Shape::cuboid(h[0], h[1], h[2]).unwrap();
    let cylinder = Shape::cylinder(r, l).unwrap();
    let rows: Vec<dcol::Vec3> = (0..6)
        .map(|i| {
            let mut v = dcol::Vec3::zeros();
            v[i % 3] = if i < 3 { 1.0 } else { -1.0 };
            v
        })
        .collect();
    let b: Vec<f64> = (0..6).map(|i| h[i % 3]).collect();
    let verts = common::oracle::polytope_vertices(&rows, &b);
    let p1 = Pose::new(
        [-1.6923386158535816, 0.6452458805792016, 0.5074436985970503],
        [
            -0.870305376969656,
            0.12647604473460383,
            0.1078231420742115,
            0.3422541907477569,
        ],
    )
    .unwrap();
    let p2 = Pose::new(
        [-0.7534001083762863, 1.7445762850803792, 0.26687429505402926],
        [
            -0.3272303896795557,
            -0.7370211853770605,
            0.28663508914266433,
            -0.5054065644639706,
        ],
    )
    .unwrap();
    let sd = signed_distance(&boxed, &p1, &cylinder, &p2, &Options::default()).unwrap();
    check(
        &sd,
        (&boxed, &Oracle::Polytope(rows, b, verts), &p1),
        (&cylinder, &Oracle::Cylinder(r, l), &p2),
    );
}

/// Shapes of aspect ratio 1e11 (from the fuzzer: a box 1e-7 × 1e4 × 7e-6 and a cylinder of
/// radius 5e-7 and length 3.4e-6, overlapping): K is thinner than EPA's start tolerance, no
/// tetrahedron was found and the query ended `Internal("signed_distance: degenerate
/// polytope")`. A start as thin as 1e-14 (relative) is now taken for two shapes (K is
/// full-dimensional), and a K flatter than that gets the best slab (its normal from three far
/// apart support points) with `NumericalFailure`. The answer is finite; converged, it lies
/// between the thin slab's bound and 0; not converged (EPA stopped at rounding on the
/// needle-like K, 2e4 long and 1e-5 wide: 193 of these 200 poses), a lower bound within K's
/// width.
#[test]
fn shapes_of_aspect_1e11_answer() {
    let h = [
        1.0133516441596102e-7,
        10246.433203631645,
        7.205767910276951e-6,
    ];
    let boxed = Shape::cuboid(h[0], h[1], h[2]).unwrap();
    let cylinder = Shape::cylinder(4.97306782635233e-7, 3.396505683985656e-6).unwrap();
    let mut rng = common::random::Rng::new(0x7417);
    let (mut converged, mut cases) = (0, 0);
    for _ in 0..200 {
        let q1 = rng.quat();
        let p1 = Pose::new([-5047.8, 7.98, 0.002], q1).unwrap();
        let off = rng.unit::<3>().map(|v| v * rng.range(0.0, 1e-7));
        let p2 = Pose::new(
            [-5047.8 + off[0], 7.98 + off[1], 0.002 + off[2]],
            rng.quat(),
        )
        .unwrap();
        let sd = signed_distance(&boxed, &p1, &cylinder, &p2, &Options::default()).unwrap();
        cases += 1;
        converged += usize::from(sd.status == SolveStatus::Converged);
        // The box's thin axis bounds the depth: h_x + the cylinder's extent along it.
        let thin = dcol::math::rotation_from_quaternion(q1) * dcol::Vec3::x();
        let bound = h[0] + 4.97306782635233e-7 + 0.5 * 3.396505683985656e-6 + 1e-7;
        // Converged, the answer is within the thin slab; otherwise it is a lower bound (EPA's
        // best normal when it stopped, or the slab's): K is a needle 2e4 long and 1e-5 wide,
        // and the bound is only within its width of the depth.
        let floor = if sd.status == SolveStatus::Converged {
            -bound
        } else {
            -1e-4
        };
        assert!(
            sd.distance.is_finite() && sd.distance <= 1e-15 && sd.distance >= floor,
            "{sd:?} (thin axis {thin:?})"
        );
    }
    // Measured: 7 of 200 converge (docs/failure-modes.md: thin shapes).
    println!("{converged} of {cases} converged");
}

/// Sphere and capsule cores that meet: two spheres at the same centre, a sphere centred on a
/// capsule's segment, two capsules whose segments cross, two coaxial capsules; exactly and
/// within 1e-300 to 1e-13 of it. EPA found no start there and `signed_distance` (and so
/// `dcol_contacts`) returned `MaxIterations` after 4 000 iterations (from the review). The
/// depth is `R₁ + R₂` less the cores' distance, along any normal of their flat difference: now
/// answered in closed form, checked against the brute force as above and against that value.
#[test]
fn meeting_cores_answer() {
    let (r1, r2, half) = (0.5, 0.3, 0.4);
    let ball = Shape::sphere(r1).unwrap();
    let caps = Shape::capsule(r2, 2.0 * half).unwrap();
    let caps2 = Shape::capsule(r1, 1.2).unwrap();
    let (ob, oc, oc2) = (
        Oracle::Sphere(r1),
        Oracle::Capsule(r2, 2.0 * half),
        Oracle::Capsule(r1, 1.2),
    );
    let q1 = [0.9, 0.1, -0.3, 0.2];
    let q2 = [0.3, -0.7, 0.2, 0.5];
    let p1 = Pose::new([0.3, -1.2, 2.0], q1).unwrap();
    // A point `t` along a pose's capsule axis (body x), in the world.
    let on_axis = |p: &Pose, t: f64| p.position() + p.rotation() * dcol::Vec3::new(t, 0.0, 0.0);
    let mut checked = 0;
    for off in [0.0, 1e-300, 1e-100, 1e-20, 1e-13] {
        let shift = dcol::Vec3::new(off, -0.5 * off, 0.25 * off);
        let at = |c: dcol::Vec3, q: [f64; 4]| Pose::new((c + shift).into(), q).unwrap();
        // (shape 1 at p1, shape 2 at its pose, depth): the same centre; a ball centred on the
        // capsule's segment; a capsule crossing it (another attitude, its centre on the
        // segment); a coaxial capsule.
        let cases = [
            (&ball, &ob, &ball, &ob, at(*p1.position(), q2), 2.0 * r1),
            (&caps, &oc, &ball, &ob, at(on_axis(&p1, 0.17), q2), r1 + r2),
            (
                &caps,
                &oc,
                &caps2,
                &oc2,
                at(on_axis(&p1, -0.1), q2),
                r1 + r2,
            ),
            (&caps, &oc, &caps2, &oc2, at(*p1.position(), q1), r1 + r2),
        ];
        for (s1, o1, s2, o2, p2, depth) in cases {
            for (x, ox, px, y, oy, py) in [(s1, o1, &p1, s2, o2, &p2), (s2, o2, &p2, s1, o1, &p1)] {
                let sd = signed_distance(x, px, y, py, &Options::default()).unwrap();
                check(&sd, (x, ox, px), (y, oy, py));
                assert!(
                    (sd.distance + depth).abs() <= 1e-12,
                    "offset {off:e}: sd {} against -{depth}",
                    sd.distance
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 40);
}

/// Open defect (docs/failure-modes.md): coaxial solids of revolution overlapping deeply
/// (a capsule inside a cylinder, about the same centre) have a circle of optimal normals, and
/// EPA's bracket does not close: `MaxIterations` with the right value (−0.7 to 2e-16).
#[test]
#[ignore = "open defect: coaxial deep overlaps of cylinders, cones and capsules (docs/failure-modes.md)"]
fn coaxial_deep_overlaps_converge() {
    let (caps, cyl) = (
        Shape::capsule(0.3, 0.8).unwrap(),
        Shape::cylinder(0.4, 0.9).unwrap(),
    );
    let (p1, p2) = (
        Pose::from_position([0.0; 3]).unwrap(),
        Pose::from_position([0.3, 0.0, 0.0]).unwrap(),
    );
    let sd = signed_distance(&caps, &p1, &cyl, &p2, &Options::default()).unwrap();
    check(
        &sd,
        (&caps, &Oracle::Capsule(0.3, 0.8), &p1),
        (&cyl, &Oracle::Cylinder(0.4, 0.9), &p2),
    );
}
