//! The dispatch table against the dispatch it replaced, its symmetry, and its copy in the docs.

use super::*;

/// The conditions the queries tested in code before the table (each stage's gate as it was
/// written in `query/geometric.rs`, `query/shortcuts.rs`, `query/separated.rs`,
/// `query/signed.rs`, `query/cores.rs` and the solvers' own kind checks), for the solver kinds
/// `a`, `b` (proximity, distance, signed distance): the
/// table must give exactly these stages, so that every pair is answered as it was.
fn former(a: ShapeKind, b: ShapeKind) -> [Vec<Stage>; 3] {
    use ShapeKind::*;
    if a == Halfspace || b == Halfspace {
        return [0, 1, 2].map(|_| vec![Stage::Halfspace]);
    }
    let k = [a, b];
    let has = |x: ShapeKind| k.contains(&x);
    let all = |f: &dyn Fn(ShapeKind) -> bool| k.iter().all(|x| f(*x));
    let any = |f: &dyn Fn(ShapeKind) -> bool| k.iter().any(|x| f(*x));
    // One shape is `x`, the other in `ys`.
    let one =
        |x: ShapeKind, ys: &[ShapeKind]| (a == x && ys.contains(&b)) || (b == x && ys.contains(&a));
    let rounded = |x: ShapeKind| matches!(x, Sphere | Capsule);
    let padded = |x: ShapeKind| matches!(x, Sphere | Capsule | Polygon | ConvexHull);
    let cores_polyhedral = |x: ShapeKind| padded(x) || x == Polytope;
    let padded_cast = any(&padded) && all(&cores_polyhedral);
    let polytopes = all(&|x| x == Polytope);

    let mut p = Vec::new();
    // geometric::closed_form: a sphere with a centred box, cylinder or cone; two rounded
    // segments.
    if one(Sphere, &[Polytope, Cylinder, Cone]) || all(&rounded) {
        p.push(ClosedForm);
    }
    // Cache::polytopes: both have vertex pieces.
    if polytopes {
        p.push(Warm);
    }
    // segment_solid_alpha (a capsule and a box, cylinder or cone), rounded_facet_alpha (a
    // capsule and a polytope).
    if one(Capsule, &[Polytope, Cylinder, Cone]) {
        p.push(SegmentSolid);
    }
    if one(Sphere, &[Ellipsoid]) {
        p.push(SphereEllipsoid);
    }
    if all(&|x| x == Ellipsoid) {
        p.push(TwoEllipsoids);
    }
    if one(Ellipsoid, &[Capsule, Cylinder]) {
        p.push(EllipsoidRod);
    }
    if one(Ellipsoid, &[Polytope]) {
        p.push(EllipsoidPolytope);
    }
    // Cores::with_polygons(..).filter(Cores::polyhedral).
    if padded_cast {
        p.push(PaddedCast);
    }
    // flat_first: a cylinder or cone against a polytope, cylinder, cone or ellipsoid.
    let revolution = |x: ShapeKind| matches!(x, Cylinder | Cone);
    let against = |x: ShapeKind| matches!(x, Polytope | Cylinder | Cone | Ellipsoid);
    if (revolution(a) && against(b)) || (revolution(b) && against(a)) {
        p.push(FlatFaces);
    }
    // direct_first.
    let round = |x: ShapeKind| matches!(x, Sphere | Ellipsoid);
    let faceted = |x: ShapeKind| matches!(x, Polytope | Polygon);
    if any(&round) || has(Capsule) || !any(&faceted) {
        p.push(Newton);
    }
    p.push(if polytopes { ExactCast } else { Cast });
    p.push(InteriorPoint);

    let mut d = Vec::new();
    // warm_distance: both have vertex pieces.
    if polytopes {
        d.push(Warm);
    }
    // separated::closed_form: sphere_solid (a sphere and a polytope, ellipsoid, cylinder or
    // cone), segment_solid (a capsule and a box, cylinder or cone), two rounded segments.
    if one(Sphere, &[Polytope, Ellipsoid, Cylinder, Cone])
        || one(Capsule, &[Polytope, Cylinder, Cone])
        || all(&rounded)
    {
        d.push(ClosedForm);
    }
    // separated::newton_first; face_contact finds no face unless a shape has one.
    let cored = has(Polytope) && (has(Sphere) || has(Capsule));
    // A padded hull is routed as a padded polygon is (its core is a polytope: GJK on the cores
    // ends exactly); before 2026-11-27 it took flat faces and Newton first (3-4x the cost).
    let padded_flat = has(Polygon) || has(ConvexHull);
    let flat =
        padded_flat && all(&|x| matches!(x, Polytope | Polygon | Sphere | Capsule | ConvexHull));
    let newton_first = !polytopes && !cored && !flat;
    if newton_first && any(&|x| matches!(x, Polytope | Cylinder | Cone | Polygon)) {
        d.push(FlatFaces);
    }
    if newton_first {
        d.push(Newton);
    }
    // separated::cored: the polyhedral cores with polygons, else Cores::of (a sphere, capsule
    // or padded hull).
    if padded_cast || any(&|x| matches!(x, Sphere | Capsule | ConvexHull)) {
        d.push(CoredGjk);
    }
    d.push(if polytopes { ExactGjk } else { Gjk });
    d.push(InteriorPoint);

    let mut s = Vec::new();
    // signed::separating_axes: polytopes, or padded hulls by their hulls.
    if all(&|x| matches!(x, Polytope | ConvexHull)) {
        s.push(SeparatingAxes);
    }
    // signed's `rounded` probe.
    if any(&|x| matches!(x, Ellipsoid | Cylinder | Cone)) {
        s.push(Probe);
    }
    // signed::closed_forms (two rounded segments; sphere_solid: a sphere and a polytope,
    // ellipsoid, cylinder or cone) and signed::capsule_and_solid (segment_solid: a capsule and
    // a box, cylinder or cone); the early try ran on any pair with a sphere or capsule, and found
    // nothing on the others.
    if one(
        Sphere,
        &[Sphere, Capsule, Polytope, Ellipsoid, Cylinder, Cone],
    ) || one(Capsule, &[Capsule, Polytope, Cylinder, Cone])
    {
        s.push(ClosedForm);
    }
    s.push(Distance);
    // signed::cored: Cores::rolling (padded shapes' cores, ellipsoids shrunk).
    if any(&padded) || has(Ellipsoid) {
        s.push(CoredEpa);
    }
    s.push(if polytopes { ExactEpa } else { Epa });
    [p, d, s]
}

#[test]
fn table_gives_the_stages_the_code_tested_before() {
    for a in KINDS {
        for b in KINDS {
            let r = TABLE[a as usize][b as usize];
            let [p, d, s] = former(a, b);
            let got_p: Vec<_> = r.proximity.ordered(&PROXIMITY_ORDER).collect();
            let got_d: Vec<_> = r.distance.ordered(&DISTANCE_ORDER).collect();
            let got_s: Vec<_> = r.signed.ordered(&SIGNED_ORDER).collect();
            assert_eq!(got_p, p, "proximity {a:?}–{b:?}");
            assert_eq!(got_d, d, "distance {a:?}–{b:?}");
            assert_eq!(got_s, s, "signed distance {a:?}–{b:?}");
        }
    }
}

#[test]
fn both_orders_share_a_row_and_every_row_ends_in_a_fallback() {
    for a in KINDS {
        for b in KINDS {
            let r = TABLE[a as usize][b as usize];
            assert_eq!(r, TABLE[b as usize][a as usize], "{a:?}–{b:?}");
            if a == ShapeKind::Halfspace || b == ShapeKind::Halfspace {
                continue;
            }
            // Exactly one general solver, then the interior point, for each query.
            assert!(
                r.proximity.has(Cast) != r.proximity.has(ExactCast),
                "{a:?}–{b:?}"
            );
            assert!(
                r.distance.has(Gjk) != r.distance.has(ExactGjk),
                "{a:?}–{b:?}"
            );
            assert!(r.signed.has(Epa) != r.signed.has(ExactEpa), "{a:?}–{b:?}");
            assert!(r.signed.has(Distance), "{a:?}–{b:?}");
            assert!(r.proximity.has(InteriorPoint) && r.distance.has(InteriorPoint));
            assert_eq!(
                r.proximity.ordered(&PROXIMITY_ORDER).last(),
                Some(InteriorPoint)
            );
        }
    }
}

/// The shapes route by their solver kind: a box and an unpadded hull are polytopes, a padded
/// hull is not.
#[test]
fn shapes_route_by_their_solver_kind() {
    use crate::shapes::Shape;
    let cube = Shape::cuboid(1.0, 2.0, 3.0).unwrap();
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f64 - 0.5,
                ((i >> 1) & 1) as f64 - 0.5,
                ((i >> 2) & 1) as f64 - 0.5,
            ]
        })
        .collect();
    let hull = Shape::convex_hull(&corners, 0.0).unwrap();
    let padded = Shape::convex_hull(&corners, 0.1).unwrap();
    let ball = Shape::sphere(1.0).unwrap();
    let poly = pair_route(ShapeKind::Polytope, ShapeKind::Sphere);
    assert_eq!(route(&cube, &ball), poly);
    assert_eq!(route(&ball, &hull), poly);
    assert_eq!(
        route(&padded, &ball),
        pair_route(ShapeKind::ConvexHull, ShapeKind::Sphere)
    );
    assert_ne!(poly, pair_route(ShapeKind::ConvexHull, ShapeKind::Sphere));
}

const BEGIN: &str = "<!-- dispatch table: generated from src/query/dispatch.rs (DCOL_BLESS=1 cargo test --lib dispatch) -->\n";
const END: &str = "<!-- end of the dispatch table -->";

/// `docs/geometric-solver.md` holds [`markdown`] between its markers; with `DCOL_BLESS=1` the
/// test writes it there instead.
#[test]
fn docs_hold_the_table() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/docs/geometric-solver.md");
    let text = std::fs::read_to_string(path).unwrap();
    let start = text.find(BEGIN).expect("the table's opening marker") + BEGIN.len();
    let end = start + text[start..].find(END).expect("the table's closing marker");
    let table = markdown();
    if std::env::var("DCOL_BLESS").as_deref() == Ok("1") {
        let new = format!("{}{}{}", &text[..start], table, &text[end..]);
        std::fs::write(path, new).unwrap();
        return;
    }
    assert!(
        text[start..end] == table,
        "docs/geometric-solver.md's dispatch table is stale: run DCOL_BLESS=1 cargo test --lib dispatch"
    );
}
