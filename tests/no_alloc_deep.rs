//! The deep overlaps whose signed distance needs more support points than EPA's polytope on
//! the stack holds (250) go on in a per-thread heap polytope: the first such query on a thread
//! allocates it, and every later one (signed distance, its gradient, contacts) makes no heap
//! operation. Counted with a global allocator that counts per thread.

mod common;

use common::random::Rng;
use dcol::{
    contact_manifold, proximity, signed_distance, signed_distance_gradient, Options, Pose, Shape,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::hint::black_box;

struct Counting;

thread_local! {
    static HEAP_OPS: Cell<u64> = const { Cell::new(0) };
}

fn bump() {
    let _ = HEAP_OPS.try_with(|c| c.set(c.get() + 1));
}

fn heap_ops() -> u64 {
    HEAP_OPS.with(|c| c.get())
}

// SAFETY: forwards every call to the system allocator unchanged; the count is a thread-local
// cell touched without allocating.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        bump();
        // SAFETY: the caller's contract, forwarded.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Deep overlaps of random ellipsoids whose signed distance needs more than 250 support calls
/// (about 1 in 2 000 of these poses).
fn hard_cases(want: usize) -> Vec<(Shape, Pose, Shape, Pose)> {
    let opts = Options::default();
    let mut rng = Rng::new(0xDEE9);
    let mut out = Vec::new();
    for _ in 0..200_000 {
        if out.len() == want {
            break;
        }
        let (a, b) = (
            common::random::Kind::Ellipsoid.random(&mut rng),
            common::random::Kind::Ellipsoid.random(&mut rng),
        );
        let p1 = Pose::new([0.1, -0.2, 0.3], rng.quat()).unwrap();
        let u = rng.unit::<3>();
        let q2 = rng.quat();
        let unit = Pose::new([0.1 + u[0], -0.2 + u[1], 0.3 + u[2]], q2).unwrap();
        let alpha = proximity(&a, &p1, &b, &unit, &opts).unwrap().alpha;
        let s = rng.range(0.0, 0.5) / alpha;
        let p2 = Pose::new([0.1 + u[0] * s, -0.2 + u[1] * s, 0.3 + u[2] * s], q2).unwrap();
        let sd = signed_distance(&a, &p1, &b, &p2, &opts).unwrap();
        if sd.iterations > 250 {
            assert!(sd.status.is_converged());
            out.push((a, p1, b, p2));
        }
    }
    out
}

/// Heap operations of the queries on `cases`.
fn ops(cases: &[(Shape, Pose, Shape, Pose)]) -> u64 {
    let opts = Options::default();
    let before = heap_ops();
    for (a, p1, b, p2) in cases {
        let _ = black_box(signed_distance(a, p1, b, p2, &opts));
        let _ = black_box(signed_distance_gradient(a, p1, b, p2, &opts));
        let _ = black_box(contact_manifold(a, p1, b, p2, 0.0, 8, &opts));
    }
    heap_ops() - before
}

#[test]
fn deep_overlaps_allocate_once_per_thread() {
    let cases = hard_cases(5);
    assert!(cases.len() >= 3, "{} hard cases found", cases.len());
    // This thread made its heap polytope while searching: none now.
    assert_eq!(ops(&cases), 0);
    // A new thread: its first hard query makes the polytope (a few operations), then none.
    std::thread::scope(|s| {
        s.spawn(|| {
            let first = ops(&cases[..1]);
            assert!(
                first > 0,
                "the first deep overlap on a thread reserves its polytope"
            );
            assert_eq!(ops(&cases), 0);
        });
    });
}
