//! Many pair queries in one call: results written into caller-provided slices (no allocation
//! per pair), optionally spread over a caller-chosen number of threads. Each result is exactly
//! what the single call returns (the same code runs; the solver keeps no state between calls).

use crate::error::Error;
use crate::math::Pose;
use crate::query::{proximity, Options, Proximity};
use crate::shapes::Shape;

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

/// Proximity for every pair, written to `out[i]` (`out.len()` must equal `pairs.len()`).
/// `threads` ≤ 1 runs on the calling thread; otherwise the pairs are split into that many
/// contiguous chunks run on scoped threads.
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
    let run = |pairs: &[Pair<'_>], out: &mut [Result<Proximity, Error>]| {
        for (p, o) in pairs.iter().zip(out.iter_mut()) {
            *o = proximity(p.shape1, p.pose1, p.shape2, p.pose2, options);
        }
    };
    if threads <= 1 || pairs.len() < 2 {
        run(pairs, out);
        return Ok(());
    }
    let chunk = pairs.len().div_ceil(threads);
    std::thread::scope(|scope| {
        for (p, o) in pairs.chunks(chunk).zip(out.chunks_mut(chunk)) {
            scope.spawn(move || run(p, o));
        }
    });
    Ok(())
}
