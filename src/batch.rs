//! Many pair queries in one call: results written into caller-provided slices (no allocation
//! per pair), optionally spread over several threads of a pool that is created once, on the
//! first parallel call, and reused by every later one. Each result is exactly what the single
//! call returns (the same code runs; the solver keeps no state between calls).

use std::sync::{Mutex, OnceLock};

use crate::error::Error;
use crate::math::Pose;
use crate::query::{proximity, Options, Proximity};
use crate::shapes::Shape;

/// Pairs handed to a thread at a time: small enough that the threads finish together when
/// pairs differ in cost, large enough that taking the next chunk costs nothing measurable.
/// Callers of [`for_each_parallel`] use it to cut their own arrays into items.
pub const CHUNK: usize = 16;

/// One pair of posed shapes.
#[derive(Clone, Copy, Debug)]
pub struct Pair<'a> {
    /// First shape.
    pub shape1: &'a Shape,
    /// Its pose.
    pub pose1: &'a Pose,
    /// Second shape.
    pub shape2: &'a Shape,
    /// Its pose.
    pub pose2: &'a Pose,
}

/// The worker pool every parallel batch runs on: one thread per available core (at least one),
/// created on first use and kept for the life of the process. `None` when its threads could
/// not be started; batches then run on the calling thread.
fn pool() -> Option<&'static rayon::ThreadPool> {
    static POOL: OnceLock<Option<rayon::ThreadPool>> = OnceLock::new();
    POOL.get_or_init(|| {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("dcol-batch-{i}"))
            .build()
            .ok()
    })
    .as_ref()
}

/// Runs `work` on every item of `items`, on at most `threads` threads at once: the calling
/// thread and up to `threads − 1` tasks on the pool (never more tasks than the pool has
/// threads). Each thread takes the next item from the shared iterator until none is left, so
/// the threads finish together however the items differ in cost. The items are processed in no
/// particular order and on no particular thread; `work` must not depend on either.
///
/// `threads ≤ 1` runs everything on the calling thread without touching the pool (and without
/// allocating). Otherwise the call allocates one pool job per task (the pool itself is created
/// once, on the first such call), nothing per item. A panic in `work` propagates to the caller
/// once every task has stopped.
///
/// Public so that bindings (the Python package's batches of gradients and distances) run their
/// own per-pair queries on the same pool as [`proximity_batch`] and `dcol_proximity_batch`:
/// cut the outputs into chunks of [`CHUNK`] pairs and hand the chunks over as the items.
///
/// ```
/// use dcol::batch::{for_each_parallel, CHUNK};
/// let x: Vec<f64> = (0..100).map(f64::from).collect();
/// let mut y = vec![0.0; x.len()];
/// let items = x.chunks(CHUNK).zip(y.chunks_mut(CHUNK));
/// for_each_parallel(items, 2, |(x, y)| {
///     for (xi, yi) in x.iter().zip(y) {
///         *yi = 2.0 * xi;
///     }
/// });
/// assert_eq!(y[99], 198.0);
/// ```
pub fn for_each_parallel<I>(items: I, threads: usize, work: impl Fn(I::Item) + Sync)
where
    I: Iterator + Send,
{
    let pool = if threads > 1 { pool() } else { None };
    let Some(pool) = pool else {
        items.for_each(work);
        return;
    };
    let helpers = (threads - 1).min(pool.current_num_threads());
    let items = Mutex::new(items);
    let drain = || loop {
        // A poisoned lock means another thread's `work` panicked: stop taking items (the panic
        // reaches the caller through the scope).
        let Some(item) = items.lock().ok().and_then(|mut it| it.next()) else {
            return;
        };
        work(item);
    };
    pool.in_place_scope(|scope| {
        for _ in 0..helpers {
            scope.spawn(|_| drain());
        }
        drain();
    });
}

/// Proximity for every pair, written to `out[i]` (`out.len()` must equal `pairs.len()`).
/// `threads` ≤ 1 runs on the calling thread; otherwise up to `threads` threads share the pairs:
/// the calling thread and the threads of a pool created once (one thread per core) and reused
/// by every call, taking chunks of 16 pairs in turn. The results do not depend on `threads`.
///
/// ```
/// use dcol::batch::{proximity_batch, Pair};
/// use dcol::{Options, Pose, Shape};
/// let s = Shape::sphere(1.0).unwrap();
/// let poses: Vec<Pose> = (0..4).map(|i| Pose::from_position([3.0 * i as f64, 0.0, 0.0]).unwrap()).collect();
/// let pairs: Vec<Pair> = (0..3).map(|i| Pair { shape1: &s, pose1: &poses[i], shape2: &s, pose2: &poses[i + 1] }).collect();
/// let mut out = vec![Err(dcol::Error::Internal("unset")); pairs.len()];
/// proximity_batch(&pairs, &Options::default(), 2, &mut out).unwrap();
/// assert!((out[0].as_ref().unwrap().alpha - 1.5).abs() < 1e-9);
/// ```
pub fn proximity_batch(
    pairs: &[Pair<'_>],
    options: &Options,
    threads: usize,
    out: &mut [Result<Proximity, Error>],
) -> Result<(), Error> {
    if out.len() != pairs.len() {
        return Err(Error::InvalidOptions(crate::error::ErrorDetail::new(
            "out",
            out.len() as f64,
            "must have one slot per pair",
        )));
    }
    options.validate()?;
    let threads = if pairs.len() < 2 { 1 } else { threads };
    let chunks = pairs.chunks(CHUNK).zip(out.chunks_mut(CHUNK));
    for_each_parallel(chunks, threads, |(pairs, out)| {
        for (p, o) in pairs.iter().zip(out.iter_mut()) {
            *o = proximity(p.shape1, p.pose1, p.shape2, p.pose2, options);
        }
    });
    Ok(())
}
