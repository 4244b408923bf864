//! Queries do not touch the heap.
//!
//! This test binary installs a counting global allocator (every `alloc`, `alloc_zeroed`,
//! `realloc` and `dealloc` is counted per thread). Shapes are built first (constructors may
//! allocate), every query is warmed up once (a polytope or polygon with more than 32 orthant
//! rows in a problem uses a per-thread scratch buffer that the first such call allocates), and
//! then every query of every pair of kinds, on several poses, must make zero heap operations:
//! `proximity`, `gradient`, `jacobian`, `distance` (its GJK path on the separated poses and,
//! with `Method::InteriorPoint`, its interior-point path), `distance_gradient`,
//! `distance_within`, `signed_distance` (GJK, EPA and its polish), `contact_manifold` and the
//! shape gradients (`shape_gradient`, `distance_shape_gradient`,
//! `signed_distance_shape_gradient`), whether they return `Ok` or `Err` (invalid options, and functions not
//! built yet, must not allocate on the error path either). The half-space's closed forms (and
//! the two-half-space error) are checked the same way against every shape.

use dcol::{
    distance, distance_gradient, distance_within, gradient, jacobian, proximity, Error, Options,
    Pose, Shape,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;

struct Counting;

thread_local! {
    static HEAP_OPS: Cell<u64> = const { Cell::new(0) };
}

fn bump() {
    // `try_with`: the allocator may be called while this thread's locals are being destroyed.
    let _ = HEAP_OPS.try_with(|c| c.set(c.get() + 1));
}

fn heap_ops() -> u64 {
    HEAP_OPS.with(|c| c.get())
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        bump();
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

thread_local! {
    /// The warm-start cache of the cached queries (const-initialised: no allocation).
    static CACHE: std::cell::RefCell<dcol::Cache> = const { std::cell::RefCell::new(dcol::Cache::new()) };
}

type Query = fn(&Shape, &Pose, &Shape, &Pose, &Options) -> Result<(), Error>;

/// Every query, reduced to `Result<(), Error>` without touching the heap.
const QUERIES: [(&str, Query); 16] = [
    ("proximity_cached", |a, pa, b, pb, o| {
        // One cache carried through every call: warm where the pair and poses allow it.
        CACHE
            .with(|c| dcol::proximity_cached(a, pa, b, pb, o, &mut c.borrow_mut()))
            .map(|r| {
                black_box(r);
            })
    }),
    ("derivatives_cached", |a, pa, b, pb, o| {
        CACHE
            .with(|c| dcol::derivatives_cached(a, pa, b, pb, o, &mut c.borrow_mut()))
            .map(|r| {
                black_box(r);
            })
    }),
    ("intersect_cached", |a, pa, b, pb, o| {
        CACHE
            .with(|c| dcol::intersect_cached(a, pa, b, pb, o, &mut c.borrow_mut()))
            .map(|r| {
                black_box(r);
            })
    }),
    ("proximity", |a, pa, b, pb, o| {
        proximity(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    ("gradient", |a, pa, b, pb, o| {
        gradient(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    ("jacobian", |a, pa, b, pb, o| {
        jacobian(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    ("distance", |a, pa, b, pb, o| {
        distance(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    // The GJK path (separated poses) with its gradient, and the interior-point path alone.
    ("distance_gradient", |a, pa, b, pb, o| {
        distance_gradient(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    ("distance_ipm", |a, pa, b, pb, o| {
        let o = Options {
            method: dcol::Method::InteriorPoint,
            ..*o
        };
        distance(a, pa, b, pb, &o).map(|r| {
            black_box(r);
        })
    }),
    ("signed_distance", |a, pa, b, pb, o| {
        dcol::signed_distance(a, pa, b, pb, o).map(|r| {
            black_box(r);
        })
    }),
    ("distance_within", |a, pa, b, pb, o| {
        distance_within(a, pa, b, pb, 1.0, o).map(|r| {
            black_box(r);
        })
    }),
    // Contact manifolds: faces clipped, segments, single points, and beyond the margin.
    ("contact_manifold", |a, pa, b, pb, o| {
        dcol::contact_manifold(a, pa, b, pb, 0.05, 8, o).map(|r| {
            black_box(r);
        })
    }),
    ("contact_manifold_far", |a, pa, b, pb, o| {
        dcol::contact_manifold(a, pa, b, pb, 10.0, 4, o).map(|r| {
            black_box(r);
        })
    }),
    // Shape gradients into buffers kept between calls (allocated once, at the warm-up).
    ("shape_gradient", |a, pa, b, pb, o| {
        with_buffers(|g1, g2| {
            dcol::shape_gradient(a, pa, b, pb, o, Some(g1), Some(g2)).map(|r| {
                black_box(r);
            })
        })
    }),
    ("distance_shape_gradient", |a, pa, b, pb, o| {
        with_buffers(|g1, g2| {
            dcol::distance_shape_gradient(a, pa, b, pb, o, Some(g1), Some(g2)).map(|r| {
                black_box(r);
            })
        })
    }),
    ("signed_distance_shape_gradient", |a, pa, b, pb, o| {
        with_buffers(|g1, g2| {
            dcol::signed_distance_shape_gradient(a, pa, b, pb, o, Some(g1), Some(g2)).map(|r| {
                black_box(r);
            })
        })
    }),
];

/// Room for the parameters of the largest shape below (the 300-plane polytope: 1 200).
const PARAMETERS: usize = 1200;

thread_local! {
    static BUFFERS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Runs `f` on this thread's two shape-gradient buffers.
fn with_buffers<R>(f: impl FnOnce(&mut [f64], &mut [f64]) -> R) -> R {
    BUFFERS.with(|cell| {
        let mut v = cell.borrow_mut();
        if v.is_empty() {
            v.resize(2 * PARAMETERS, 0.0);
        }
        let (g1, g2) = v.split_at_mut(PARAMETERS);
        f(g1, g2)
    })
}

/// Unit normals of a polytope with `k` roughly evenly spread facets (a Fibonacci sphere).
fn fibonacci_normals(k: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..k)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / k as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            [r * t.cos(), r * t.sin(), z]
        })
        .collect()
}

/// `k` points on a sphere of radius `r` (a Fibonacci sphere, jittered in radius).
fn sphere_points(k: usize, r: f64) -> Vec<[f64; 3]> {
    fibonacci_normals(k)
        .into_iter()
        .enumerate()
        .map(|(i, n)| n.map(|c| c * r * (1.0 + 0.01 * (i % 7) as f64)))
        .collect()
}

/// The eight kinds, plus a 40-facet polytope and a 36-edge padded polygon (each more than
/// the 32 orthant rows that fit on the stack), and hulls.
fn shapes() -> Vec<(&'static str, Shape)> {
    let twelve = fibonacci_normals(12);
    let b12: Vec<f64> = (0..12).map(|i| 0.6 + 0.05 * i as f64).collect();
    let forty = fibonacci_normals(40);
    let b40: Vec<f64> = (0..40).map(|i| 0.7 + 0.01 * i as f64).collect();
    let hexagon: Vec<[f64; 2]> = (0..6)
        .map(|i| {
            let t = i as f64 * std::f64::consts::PI / 3.0;
            [t.cos(), t.sin()]
        })
        .collect();
    let many: Vec<[f64; 2]> = (0..36)
        .map(|i| {
            let t = i as f64 * std::f64::consts::PI / 18.0;
            [t.cos(), t.sin()]
        })
        .collect();
    vec![
        ("sphere", Shape::sphere(0.7).unwrap()),
        (
            "ellipsoid",
            Shape::ellipsoid([[2.0, 0.3, 0.0], [0.3, 1.0, 0.1], [0.0, 0.1, 4.0]]).unwrap(),
        ),
        ("box", Shape::cuboid(0.5, 0.8, 0.3).unwrap()),
        ("polytope12", Shape::polytope(&twelve, &b12).unwrap()),
        ("capsule", Shape::capsule(0.3, 1.2).unwrap()),
        ("cylinder", Shape::cylinder(0.4, 1.0).unwrap()),
        ("cone", Shape::cone(1.5, 0.5).unwrap()),
        (
            "polygon",
            Shape::polygon(&hexagon, &[0.6, 0.7, 0.8, 0.6, 0.7, 0.8], 0.1).unwrap(),
        ),
        ("polytope40", Shape::polytope(&forty, &b40).unwrap()),
        ("polygon36", Shape::polygon(&many, &[0.9; 36], 0.2).unwrap()),
        // Hulls: of 300 points (596 facets, past the shortcuts' scan limit, climbing for the
        // support and the gauge), and padded; a polytope of 300 planes (from the polar hull).
        (
            "hull300",
            Shape::convex_hull(&sphere_points(300, 0.8), 0.0).unwrap(),
        ),
        (
            "rounded-hull40",
            Shape::convex_hull(&sphere_points(40, 0.6), 0.15).unwrap(),
        ),
        (
            "polytope300",
            Shape::polytope(&fibonacci_normals(300), &[0.75; 300]).unwrap(),
        ),
    ]
}

/// Pose pairs: separated, near touching, overlapping, deeply overlapping, coincident origins.
fn poses() -> Vec<(Pose, Pose)> {
    let q1 = [0.9, 0.1, -0.3, 0.2];
    let q2 = [1.3, -0.4, 0.5, 0.7]; // not unit length
    let p1 = Pose::new([0.1, -0.2, 0.3], q1).unwrap();
    [
        [3.0, 1.0, -0.5],
        [1.2, 0.4, 0.3],
        [0.6, 0.2, 0.1],
        [0.1, 0.05, -0.02],
        [0.1, -0.2, 0.3],
    ]
    .iter()
    .map(|r| (p1, Pose::new(*r, q2).unwrap()))
    .collect()
}

fn option_sets() -> Vec<Options> {
    vec![
        Options::default(),
        // Stops on the iteration limit: an outcome, not an error.
        Options {
            max_iterations: 2,
            ..Options::default()
        },
        // The smoothed answer: the interior-point method's centring steps.
        Options {
            smoothing: 1e-3,
            ..Options::default()
        },
        // Rejected: the error path.
        Options {
            tolerance: -1.0,
            ..Options::default()
        },
    ]
}

/// Runs every query on every ordered pair, pose and option set; returns the calls that made
/// heap operations after the warm-up, as (query, shape1, shape2, pose index, options index, ops).
fn offenders() -> Vec<(&'static str, &'static str, &'static str, usize, usize, u64)> {
    let shapes = shapes();
    let poses = poses();
    let options = option_sets();
    // Warm-up: every call once (this thread's scratch buffer grows to its final size).
    for (_, q) in QUERIES {
        for (_, s1) in &shapes {
            for (_, s2) in &shapes {
                for (p1, p2) in &poses {
                    for o in &options {
                        let _ = black_box(q(s1, p1, s2, p2, o));
                    }
                }
            }
        }
    }
    // Reserve the report up front so that recording an offender does not count as one.
    let mut bad =
        Vec::with_capacity(3 * QUERIES.len() * shapes.len().pow(2) * poses.len() * options.len());
    let mut calls = 0u64;
    for _round in 0..3 {
        for (qn, q) in QUERIES {
            for (n1, s1) in &shapes {
                for (n2, s2) in &shapes {
                    for (pi, (p1, p2)) in poses.iter().enumerate() {
                        for (oi, o) in options.iter().enumerate() {
                            let before = heap_ops();
                            let r = q(s1, p1, s2, p2, o);
                            let _ = black_box(r);
                            let ops = heap_ops() - before;
                            calls += 1;
                            if ops != 0 && bad.len() < bad.capacity() {
                                bad.push((qn, *n1, *n2, pi, oi, ops));
                            }
                        }
                    }
                }
            }
        }
    }
    assert_eq!(
        calls as usize,
        3 * QUERIES.len() * shapes.len().pow(2) * poses.len() * options.len()
    );
    bad
}

fn report(bad: &[(&str, &str, &str, usize, usize, u64)]) {
    assert!(
        bad.is_empty(),
        "{} calls made heap operations after warm-up, e.g. (query, shape1, shape2, pose, \
         options, ops): {:?}",
        bad.len(),
        &bad[..bad.len().min(20)]
    );
}

#[test]
fn counter_sees_allocations() {
    let before = heap_ops();
    let v: Vec<u8> = black_box(Vec::with_capacity(64));
    drop(v);
    assert_eq!(heap_ops() - before, 2, "one alloc and one dealloc");
}

#[test]
fn queries_do_not_allocate() {
    report(&offenders());
}

/// The scratch buffer is per thread: a fresh thread warms up its own and then stays quiet.
#[test]
fn queries_do_not_allocate_on_another_thread() {
    let bad = std::thread::spawn(offenders).join().unwrap();
    report(&bad);
}

/// The queries that are built answer correctly here too (the counting allocator is only a
/// wrapper): a plain sanity check that proximity ran, so the zero counts mean something.
#[test]
fn proximity_runs_under_the_counting_allocator() {
    let s = Shape::sphere(1.0).unwrap();
    let p1 = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
    let p2 = Pose::from_position([4.0, 0.0, 0.0]).unwrap();
    let before = heap_ops();
    let r = proximity(&s, &p1, &s, &p2, &Options::default()).unwrap();
    assert_eq!(heap_ops(), before);
    assert!((r.alpha - 2.0).abs() < 1e-9);
}

/// The separated poses do take the GJK path (so the zero counts above cover it).
#[test]
fn separated_distance_takes_the_gjk_path() {
    let poses = poses();
    let mut gjk = 0;
    for (_, s1) in &shapes() {
        for (_, s2) in &shapes() {
            let (p1, p2) = &poses[0];
            let before = heap_ops();
            let d = distance(s1, p1, s2, p2, &Options::default()).unwrap();
            assert_eq!(heap_ops(), before);
            if d.distance > 0.0 && d.path != dcol::DistancePath::InteriorPoint {
                gjk += 1;
            }
        }
    }
    assert!(
        gjk >= 90,
        "only {gjk} of 100 separated pairs took the GJK path"
    );
}

/// A half-space against every shape above (both orders, on a level and a tilted floor, the
/// origin above and below the plane), and two half-spaces (the error path): every query,
/// plus `intersect`, `alpha_below` and `signed_distance_gradient`, makes no heap operation.
#[test]
fn halfspace_queries_do_not_allocate() {
    let floor = Shape::halfspace(0.5).unwrap();
    let floors = [
        Pose::from_position([0.0, 0.0, -0.5]).unwrap(),
        Pose::new([0.2, -0.1, 0.3], [0.9, 0.3, -0.2, 0.1]).unwrap(),
    ];
    let shapes = shapes();
    let poses = poses();
    let options = option_sets();
    let run = |s1: &Shape, p1: &Pose, s2: &Shape, p2: &Pose, o: &Options| {
        for (_, q) in QUERIES {
            let _ = black_box(q(s1, p1, s2, p2, o));
        }
        let _ = black_box(dcol::intersect(s1, p1, s2, p2, o));
        let _ = black_box(dcol::alpha_below(s1, p1, s2, p2, 0.5, o));
        let _ = black_box(dcol::signed_distance_gradient(s1, p1, s2, p2, o));
    };
    let mut cases: Vec<(&Shape, &Pose, &Shape, &Pose)> = Vec::new();
    for pf in &floors {
        for (_, s) in &shapes {
            for (_, pb) in &poses {
                cases.push((&floor, pf, s, pb));
                cases.push((s, pb, &floor, pf));
            }
        }
        cases.push((&floor, pf, &floor, &floors[0]));
    }
    for &(s1, p1, s2, p2) in &cases {
        for o in &options {
            run(s1, p1, s2, p2, o);
        }
    }
    let mut bad = 0;
    for &(s1, p1, s2, p2) in &cases {
        for o in &options {
            let before = heap_ops();
            run(s1, p1, s2, p2, o);
            if heap_ops() != before {
                bad += 1;
            }
        }
    }
    assert_eq!(bad, 0, "{bad} half-space calls made heap operations");
    // The queries did run: a ball resting on the floor.
    let ball = Shape::sphere(0.5).unwrap();
    let on = Pose::from_position([0.0, 0.0, 0.49]).unwrap();
    let before = heap_ops();
    let m = dcol::contact_manifold(&floor, &floors[0], &ball, &on, 0.0, 4, &Options::default())
        .unwrap();
    assert_eq!(heap_ops(), before);
    assert_eq!(m.len(), 1);
}
