//! Which solver answers which pair: the one table the geometric queries dispatch on.
//!
//! [`route`] gives, for the solver kinds of two shapes ([`Shape::solver_kind`]: a box and an
//! unpadded hull are polytopes, `ConvexHull` is a padded hull), the [`Stage`]s that proximity
//! (`super::geometric`), the exact distance (`super::separated`, `super::distance`) and the
//! signed distance (`super::signed`) try, in the order they try them, with `Method::Auto`. A
//! stage listed for a pair runs; one not listed does not. A stage may still decline on the
//! shapes themselves (a closed form for "a sphere and a box" needs the polytope to be a box
//! centred at its origin; a bracket that does not close goes on to the next stage): the table
//! says what is tried, the stage whether it certifies. The contacts start from the signed
//! distance's answer; how their faces are built is decided in `super::contact`.
//!
//! The table is one `match` over unordered pairs ([`pair_route`]), read top to bottom; both
//! orders of a pair share a row, expanded once at compile time into a 9×9 array so that a
//! query's lookup is one index. `docs/geometric-solver.md` carries its rendering (`markdown`,
//! built for the tests); a test keeps the two in step (`DCOL_BLESS=1` rewrites the docs).

use crate::shapes::{Shape, ShapeKind};

/// One solver the queries try. A stage's meaning depends on the query it is listed for (the
/// docs' rendering names each query's files).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Stage {
    /// A half-space and any bounded shape: closed forms (`query/halfspace.rs`).
    Halfspace,
    /// Closed forms: proximity for sphere and capsule pairs and a sphere with a centred box, a
    /// cylinder or a cone; the distance and the signed distance for those, a sphere with any
    /// polytope (its centre inside), an ellipsoid or a cone, and a capsule with a centred box,
    /// cylinder or cone.
    ClosedForm,
    /// The pair's cache (when the query is given one): the features of the last answer, kept
    /// between polytopes only (Newton on other pairs' kept pieces was measured slower than the
    /// cold path, `docs/warm-starts.md`).
    Warm,
    /// A capsule and a centred box, cylinder or cone (the segment's closest points), or a
    /// polytope touching on a facet (the facets' slabs).
    SegmentSolid,
    /// A sphere and an ellipsoid: the secular equation of the sphere's centre.
    SphereEllipsoid,
    /// Two ellipsoids: the Perram–Wertheim contact function.
    TwoEllipsoids,
    /// An ellipsoid and a capsule or cylinder (a segment padded by a ball or a disc): Newton's
    /// method along its side, else on the end (ball or rim) the side's weight points to.
    EllipsoidRod,
    /// An ellipsoid and a polytope, seen through the map that makes the ellipsoid a ball.
    EllipsoidPolytope,
    /// The padded cast (MPR) on the cores: spheres, capsules, padded polygons and hulls against
    /// polytopes and each other.
    PaddedCast,
    /// A flat face as the contact: a polytope facet, a cylinder cap, a cone base (proximity;
    /// the distance adds a padded polygon's sides).
    FlatFaces,
    /// Newton's method on the support function (proximity) or on the sphere of normals
    /// (distance), before the general solver.
    ///
    /// Proximity tries it with a sphere or an ellipsoid (strictly convex, so the optimum is
    /// mostly on a smooth patch of K), with a capsule (its side is a single tie), and between
    /// cylinders, cones and padded hulls; a cylinder or cone against a polytope or padded
    /// polygon, or two of those, meets mostly on an edge or face of K where the support
    /// alternates between many pieces, or a vertex against a rim where the Hessian is singular:
    /// the ray cast identifies those faster (measured: Newton first costs 1.1–2.5× there).
    ///
    /// The distance tries it (without a cutoff) on every pair but two polytopes (GJK ends
    /// exactly) and a sphere, capsule or padded polygon against a polytope, and a padded polygon
    /// against a sphere, capsule or polygon (GJK on their cores ends exactly, in a few hundred
    /// nanoseconds). Measured on benches/proximity's separated poses, Newton first against GJK
    /// first: box–cylinder 1.67 → 1.14 µs, cylinder–cylinder 1.83 → 1.17 µs,
    /// ellipsoid–polytope 1.73 → 1.08 µs; box–capsule 0.27 → 1.13 µs (so not there).
    Newton,
    /// The ray cast (MPR) to a bracket of 1e-3, then Newton on the portal's features, the
    /// polish, and a longer cast as a rescue.
    Cast,
    /// The ray cast between two polytopes: it ends exactly in a facet of K.
    ExactCast,
    /// GJK on the cores (a sphere's centre, a capsule's segment, a padded polygon's plane
    /// polygon, a padded hull's hull), the radii added back.
    CoredGjk,
    /// GJK on the shapes, its polish on curved pieces.
    Gjk,
    /// GJK between two polytopes: it ends exactly.
    ExactGjk,
    /// The interior-point solver (the distance: where the proximity does not certify an
    /// overlap first).
    InteriorPoint,
    /// The signed distance of two polytopes of few facets, or padded hulls: the separating
    /// axes, exact on an overlap.
    SeparatingAxes,
    /// The signed distance of a pair with an ellipsoid, cylinder or cone: a slab along the
    /// offset that does not separate the shapes sends them to EPA without the distance's stages
    /// (a separated pair comes back to the distance).
    Probe,
    /// The signed distance: the distance's stages (this table's distance column,
    /// `query/separated.rs`) where no earlier stage settled the pair; a separated answer is
    /// theirs.
    Distance,
    /// The signed distance: GJK, then EPA, on the cores (a sphere's centre, a capsule's segment,
    /// a padded polygon's plane polygon, a padded hull's hull, an ellipsoid less the ball that
    /// rolls inside it), the radii taken off.
    CoredEpa,
    /// EPA on the shapes with its polish on curved pieces, a slab where K is too thin.
    Epa,
    /// EPA between two polytopes, from GJK's tetrahedron: it ends exactly.
    ExactEpa,
}

use Stage::*;

/// The order proximity tries its stages in (`super::geometric::solve`).
const PROXIMITY_ORDER: [Stage; 14] = [
    Halfspace,
    ClosedForm,
    Warm,
    SegmentSolid,
    SphereEllipsoid,
    TwoEllipsoids,
    EllipsoidRod,
    EllipsoidPolytope,
    PaddedCast,
    FlatFaces,
    Newton,
    Cast,
    ExactCast,
    InteriorPoint,
];

/// The order the signed distance tries its stages in (`super::signed`): its closed forms run
/// before the distance's stages unless the inscribed balls or the probe show an overlap, and
/// after them otherwise.
const SIGNED_ORDER: [Stage; 8] = [
    Halfspace,
    SeparatingAxes,
    Probe,
    ClosedForm,
    Distance,
    CoredEpa,
    Epa,
    ExactEpa,
];

/// The order the distance tries its stages in (`super::distance`, `super::separated`).
const DISTANCE_ORDER: [Stage; 9] = [
    Halfspace,
    Warm,
    ClosedForm,
    FlatFaces,
    Newton,
    CoredGjk,
    Gjk,
    ExactGjk,
    InteriorPoint,
];

impl Stage {
    #[cfg(test)]
    /// Where proximity's stage lives (`None`: not a proximity stage).
    pub(crate) const fn proximity_file(self) -> Option<&'static str> {
        Some(match self {
            Halfspace => "query/halfspace.rs",
            ClosedForm => "solver/closed_form.rs",
            Warm => "query/warm.rs",
            SegmentSolid => "solver/segment_solid.rs",
            SphereEllipsoid => "solver/ellipsoid_point.rs",
            TwoEllipsoids => "solver/ellipsoid_pair.rs",
            EllipsoidRod => "solver/ellipsoid_rod.rs",
            EllipsoidPolytope => "query/shortcuts.rs",
            PaddedCast => "solver/gjk/padded.rs",
            FlatFaces => "query/shortcuts.rs",
            Newton => "solver/direct.rs",
            Cast => "solver/raycast.rs, solver/direct.rs, solver/polish.rs",
            ExactCast => "solver/raycast.rs",
            InteriorPoint => "solver/ipm/",
            CoredGjk | Gjk | ExactGjk | SeparatingAxes | Probe | Distance | CoredEpa | Epa
            | ExactEpa => return None,
        })
    }

    #[cfg(test)]
    /// Where the distance's stage lives (`None`: not a distance stage).
    pub(crate) const fn distance_file(self) -> Option<&'static str> {
        Some(match self {
            Halfspace => "query/halfspace.rs",
            Warm => "query/warm_distance.rs",
            ClosedForm => "solver/closed_form.rs, solver/segment_solid.rs",
            FlatFaces => "query/separated.rs",
            Newton => "solver/gjk/direct.rs",
            CoredGjk => "query/cores.rs, solver/gjk/",
            Gjk | ExactGjk => "solver/gjk/",
            InteriorPoint => "query/distance.rs, solver/ipm/",
            SegmentSolid | SphereEllipsoid | TwoEllipsoids | EllipsoidRod | EllipsoidPolytope
            | PaddedCast | Cast | ExactCast | SeparatingAxes | Probe | Distance | CoredEpa
            | Epa | ExactEpa => return None,
        })
    }

    #[cfg(test)]
    /// Where the signed distance's stage lives (`None`: not a signed-distance stage).
    pub(crate) const fn signed_file(self) -> Option<&'static str> {
        Some(match self {
            Halfspace => "query/halfspace.rs",
            SeparatingAxes => "solver/sat.rs",
            Probe => "query/signed.rs",
            ClosedForm => "solver/closed_form.rs, solver/segment_solid.rs",
            Distance => "query/separated.rs",
            CoredEpa => "query/cores.rs, solver/gjk/",
            Epa | ExactEpa => "solver/gjk/",
            _ => return None,
        })
    }

    #[cfg(test)]
    /// The stage's name in the docs.
    pub(crate) const fn label(self) -> &'static str {
        match self {
            Halfspace => "half-space",
            ClosedForm => "closed form",
            Warm => "warm",
            SegmentSolid => "segment–solid",
            SphereEllipsoid => "sphere–ellipsoid",
            TwoEllipsoids => "two ellipsoids",
            EllipsoidRod => "ellipsoid–rod",
            EllipsoidPolytope => "ellipsoid–polytope",
            PaddedCast => "padded cast",
            FlatFaces => "flat faces",
            Newton => "Newton",
            Cast => "cast + polish",
            ExactCast => "exact cast",
            CoredGjk => "cored GJK",
            Gjk => "GJK + polish",
            ExactGjk => "exact GJK",
            InteriorPoint => "interior point",
            SeparatingAxes => "separating axes",
            Probe => "probe",
            Distance => "distance",
            CoredEpa => "cored EPA",
            Epa => "EPA + polish",
            ExactEpa => "exact EPA",
        }
    }

    const fn bit(self) -> u32 {
        1 << self as u32
    }
}

/// The stages of one query, as a set (their order is the query's, [`PROXIMITY_ORDER`] or
/// [`DISTANCE_ORDER`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Stages(u32);

impl Stages {
    /// Whether `stage` is tried.
    #[inline(always)]
    pub(crate) const fn has(self, stage: Stage) -> bool {
        self.0 & stage.bit() != 0
    }

    /// `list` as a set; a compile-time error unless `list` follows `order`.
    const fn of(list: &[Stage], order: &[Stage]) -> Self {
        let (mut bits, mut i, mut at) = (0, 0, 0);
        while i < list.len() {
            while at < order.len() && order[at] as u8 != list[i] as u8 {
                at += 1;
            }
            assert!(
                at < order.len(),
                "a stage out of order, or not this query's"
            );
            bits |= list[i].bit();
            at += 1;
            i += 1;
        }
        Stages(bits)
    }

    #[cfg(test)]
    /// The stages in the order they run.
    fn ordered(self, order: &'static [Stage]) -> impl Iterator<Item = Stage> {
        order.iter().copied().filter(move |s| self.has(*s))
    }
}

/// What answers one pair: proximity's stages, the distance's and the signed distance's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Route {
    /// Proximity's stages (`super::geometric`, with the interior-point fallback).
    pub proximity: Stages,
    /// The exact distance's stages (`super::distance`, `super::separated`).
    pub distance: Stages,
    /// The signed distance's stages (`super::signed`).
    pub signed: Stages,
}

/// A row of the table: proximity's stages, the distance's, the signed distance's, each in its
/// query's order.
const fn row(proximity: &[Stage], distance: &[Stage], signed: &[Stage]) -> Route {
    Route {
        proximity: Stages::of(proximity, &PROXIMITY_ORDER),
        distance: Stages::of(distance, &DISTANCE_ORDER),
        signed: Stages::of(signed, &SIGNED_ORDER),
    }
}

/// The table: the stages of each unordered pair of solver kinds. Rows are written once, with
/// the kinds in [`KINDS`] order; the last arm turns the other order round.
pub(crate) const fn pair_route(a: ShapeKind, b: ShapeKind) -> Route {
    use ShapeKind::*;
    match (a, b) {
        (Halfspace, _) | (_, Halfspace) => row(
            &[Stage::Halfspace],
            &[Stage::Halfspace],
            &[Stage::Halfspace],
        ),
        (Sphere, Sphere) => row(
            &[ClosedForm, PaddedCast, Newton, Cast, InteriorPoint],
            &[ClosedForm, Newton, CoredGjk, Gjk, InteriorPoint],
            &[ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Ellipsoid) => row(
            &[SphereEllipsoid, Newton, Cast, InteriorPoint],
            &[ClosedForm, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Polytope) => row(
            &[ClosedForm, PaddedCast, Newton, Cast, InteriorPoint],
            &[ClosedForm, CoredGjk, Gjk, InteriorPoint],
            &[ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Capsule) => row(
            &[ClosedForm, PaddedCast, Newton, Cast, InteriorPoint],
            &[ClosedForm, Newton, CoredGjk, Gjk, InteriorPoint],
            &[ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Cylinder) => row(
            &[ClosedForm, Newton, Cast, InteriorPoint],
            &[ClosedForm, FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Cone) => row(
            &[ClosedForm, Newton, Cast, InteriorPoint],
            &[ClosedForm, FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Sphere, Polygon) => row(
            &[PaddedCast, Newton, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Sphere, ConvexHull) => row(
            &[PaddedCast, Newton, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Ellipsoid) => row(
            &[TwoEllipsoids, Newton, Cast, InteriorPoint],
            &[Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Polytope) => row(
            &[EllipsoidPolytope, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Capsule) => row(
            &[EllipsoidRod, Newton, Cast, InteriorPoint],
            &[Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Cylinder) => row(
            &[EllipsoidRod, FlatFaces, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Cone) => row(
            &[FlatFaces, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, Polygon) => row(
            &[Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Ellipsoid, ConvexHull) => row(
            &[Newton, Cast, InteriorPoint],
            &[Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Polytope, Polytope) => row(
            &[Warm, ExactCast, InteriorPoint],
            &[Warm, ExactGjk, InteriorPoint],
            &[SeparatingAxes, Distance, ExactEpa],
        ),
        (Polytope, Capsule) => row(
            &[SegmentSolid, PaddedCast, Newton, Cast, InteriorPoint],
            &[ClosedForm, CoredGjk, Gjk, InteriorPoint],
            &[ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Polytope, Cylinder) => row(
            &[FlatFaces, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, Epa],
        ),
        (Polytope, Cone) => row(
            &[FlatFaces, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, Epa],
        ),
        (Polytope, Polygon) => row(
            &[PaddedCast, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Polytope, ConvexHull) => row(
            &[PaddedCast, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[SeparatingAxes, Distance, CoredEpa, Epa],
        ),
        (Capsule, Capsule) => row(
            &[ClosedForm, PaddedCast, Newton, Cast, InteriorPoint],
            &[ClosedForm, Newton, CoredGjk, Gjk, InteriorPoint],
            &[ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Capsule, Cylinder) => row(
            &[SegmentSolid, Newton, Cast, InteriorPoint],
            &[ClosedForm, FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Capsule, Cone) => row(
            &[SegmentSolid, Newton, Cast, InteriorPoint],
            &[ClosedForm, FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, ClosedForm, Distance, CoredEpa, Epa],
        ),
        (Capsule, Polygon) => row(
            &[PaddedCast, Newton, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Capsule, ConvexHull) => row(
            &[PaddedCast, Newton, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Cylinder, Cylinder) => row(
            &[FlatFaces, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, Epa],
        ),
        (Cylinder, Cone) => row(
            &[FlatFaces, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, Epa],
        ),
        (Cylinder, Polygon) => row(
            &[Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Cylinder, ConvexHull) => row(
            &[Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Cone, Cone) => row(
            &[FlatFaces, Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, Epa],
        ),
        (Cone, Polygon) => row(
            &[Cast, InteriorPoint],
            &[FlatFaces, Newton, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Cone, ConvexHull) => row(
            &[Newton, Cast, InteriorPoint],
            &[FlatFaces, Newton, CoredGjk, Gjk, InteriorPoint],
            &[Probe, Distance, CoredEpa, Epa],
        ),
        (Polygon, Polygon) => row(
            &[PaddedCast, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (Polygon, ConvexHull) => row(
            &[PaddedCast, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[Distance, CoredEpa, Epa],
        ),
        (ConvexHull, ConvexHull) => row(
            &[PaddedCast, Newton, Cast, InteriorPoint],
            &[CoredGjk, Gjk, InteriorPoint],
            &[SeparatingAxes, Distance, CoredEpa, Epa],
        ),
        (a, b) => pair_route(b, a),
    }
}

/// Every solver kind, in the order of [`ShapeKind`]'s declaration (its `as usize` index).
pub(crate) const KINDS: [ShapeKind; 9] = [
    ShapeKind::Sphere,
    ShapeKind::Ellipsoid,
    ShapeKind::Polytope,
    ShapeKind::Capsule,
    ShapeKind::Cylinder,
    ShapeKind::Cone,
    ShapeKind::Polygon,
    ShapeKind::Halfspace,
    ShapeKind::ConvexHull,
];

/// [`pair_route`] for every ordered pair, indexed by the kinds' `as usize`.
const TABLE: [[Route; 9]; 9] = {
    let mut t = [[row(&[], &[], &[]); 9]; 9];
    let mut i = 0;
    while i < 9 {
        assert!(
            KINDS[i] as usize == i,
            "KINDS follows ShapeKind's declaration"
        );
        let mut j = 0;
        while j < 9 {
            t[i][j] = pair_route(KINDS[i], KINDS[j]);
            j += 1;
        }
        i += 1;
    }
    t
};

/// The route of a pair of shapes (either order): one table index.
#[inline(always)]
pub(crate) fn route(one: &Shape, two: &Shape) -> Route {
    TABLE[one.solver_kind() as usize][two.solver_kind() as usize]
}

#[cfg(test)]
/// A kind's name in the docs.
fn kind_name(k: ShapeKind) -> &'static str {
    match k {
        ShapeKind::Sphere => "sphere",
        ShapeKind::Ellipsoid => "ellipsoid",
        ShapeKind::Polytope => "polytope",
        ShapeKind::Capsule => "capsule",
        ShapeKind::Cylinder => "cylinder",
        ShapeKind::Cone => "cone",
        ShapeKind::Polygon => "padded polygon",
        ShapeKind::Halfspace => "half-space",
        ShapeKind::ConvexHull => "padded hull",
    }
}

#[cfg(test)]
/// The table as markdown: every unordered pair with its stages for each query, in order, then
/// each stage's files. `docs/geometric-solver.md` holds exactly this text.
pub(crate) fn markdown() -> String {
    let mut s =
        String::from("| pair | proximity | distance | signed distance |\n|---|---|---|---|\n");
    let cell = |st: Stages, order: &'static [Stage]| {
        st.ordered(order)
            .map(Stage::label)
            .collect::<Vec<_>>()
            .join(" → ")
    };
    for (i, &a) in KINDS.iter().enumerate() {
        for &b in &KINDS[i..] {
            let r = pair_route(a, b);
            s += &format!(
                "| {} – {} | {} | {} | {} |\n",
                kind_name(a),
                kind_name(b),
                cell(r.proximity, &PROXIMITY_ORDER),
                cell(r.distance, &DISTANCE_ORDER),
                cell(r.signed, &SIGNED_ORDER)
            );
        }
    }
    s += "\n| stage | proximity (`src/`) | distance (`src/`) | signed distance (`src/`) |\n";
    s += "|---|---|---|---|\n";
    let mut seen = 0;
    for &st in PROXIMITY_ORDER
        .iter()
        .chain(&DISTANCE_ORDER)
        .chain(&SIGNED_ORDER)
    {
        if seen & st.bit() != 0 {
            continue;
        }
        seen |= st.bit();
        let f = |x: Option<&str>| x.map_or("—".to_string(), |x| format!("`{x}`"));
        s += &format!(
            "| {} | {} | {} | {} |\n",
            st.label(),
            f(st.proximity_file()),
            f(st.distance_file()),
            f(st.signed_file())
        );
    }
    s
}

#[cfg(test)]
#[path = "dispatch_tests.rs"]
mod tests;
