//! Many pairs on numpy arrays: poses as (N, 7) float64 arrays (or one (7,) pose for every
//! pair), shapes as a sequence of N shapes (or one shape for every pair). The pairs run without
//! the GIL on dcol's batch thread pool (`dcol::batch::for_each_parallel`, the pool of
//! `dcol_proximity_batch`), each pair exactly the single call's code (`Pose::new` then the
//! query), so every number equals the single call's bit for bit, on any number of threads.
//!
//! Like `dcol_proximity_batch`, every pair has its own status (0 ok, 2 invalid shape, 3 invalid
//! pose, 5 not converged with the last iterate written, 6 a caught panic); a pair that failed
//! with 2, 3 or 6 has NaN outputs. Wrong array shapes and invalid options raise for the whole
//! call.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use dcol::batch::{for_each_parallel, proximity_batch as rust_proximity_batch, Pair, CHUNK};
use dcol::ffi::boundary::status_of;
use dcol::ffi::dcol_status;
use dcol::{Options, Pose, Shape, SolveStatus, Vec3};
use numpy::ndarray::Array2;
use numpy::PyUntypedArrayMethods;
use numpy::{IntoPyArray, PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

use crate::convert::{f64_array, pose_from, shape_text, Kw};
use crate::errors::api_error;
use crate::queries::{answer_representable, distance_numbers, proximity_numbers};
use crate::shapes::PyShape;

/// One shape for every pair, or one per pair.
enum Shapes<'a> {
    One(&'a Shape),
    Many(Vec<&'a Shape>),
}

impl Shapes<'_> {
    fn get(&self, i: usize) -> &Shape {
        match self {
            Shapes::One(s) => s,
            Shapes::Many(v) => v[i],
        }
    }
}

/// The shape argument `name`: a `dcol.Shape` (broadcast: `None` as its count) or a sequence of
/// them (kept alive in the returned vector).
fn shape_arg<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<(Vec<Bound<'py, PyShape>>, bool)> {
    if let Ok(s) = obj.cast::<PyShape>() {
        return Ok((vec![s.clone()], false));
    }
    let shape = |i: usize, item: Bound<'py, PyAny>| {
        item.cast_into::<PyShape>().map_err(|e| {
            PyTypeError::new_err(format!(
                "{name}[{i}] must be a dcol.Shape, got {}",
                e.into_inner()
                    .get_type()
                    .name()
                    .map_or("?".into(), |n| n.to_string())
            ))
        })
    };
    // A list (the usual case) read by index, without the iterator protocol's call per item.
    if let Ok(list) = obj.cast::<PyList>() {
        let v = (list.iter().enumerate())
            .map(|(i, item)| shape(i, item))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok((v, true));
    }
    let mut v = Vec::new();
    let items = obj.try_iter().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} must be a dcol.Shape or a sequence of them, got {}",
            obj.get_type().name().map_or("?".into(), |n| n.to_string())
        ))
    })?;
    for (i, item) in items.enumerate() {
        v.push(shape(i, item?)?);
    }
    Ok((v, true))
}

fn shapes_of<'a>(kept: &'a [Bound<'_, PyShape>], batched: bool) -> Shapes<'a> {
    if batched {
        Shapes::Many(kept.iter().map(|b| &b.get().inner).collect())
    } else {
        Shapes::One(&kept[0].get().inner)
    }
}

/// The pose argument `name`: an (N, 7) array, or one pose (7,) for every pair.
fn pose_arg<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<(PyReadonlyArrayDyn<'py, f64>, Option<usize>)> {
    let a: Bound<'py, PyArrayDyn<f64>> = f64_array(obj)?;
    let shape = a.shape().to_vec();
    let count = match shape.as_slice() {
        [7] => None,
        [n, 7] => Some(*n),
        _ => {
            return Err(PyValueError::new_err(format!(
                "{name} must be an (N, 7) array of poses [x, y, z, qw, qx, qy, qz] (or one pose \
                 of shape (7,) for every pair), got an array of shape {}",
                shape_text(&shape)
            )))
        }
    };
    Ok((a.readonly(), count))
}

/// The pairs of a batch, read from the caller's arrays.
struct Pairs<'a> {
    shapes1: Shapes<'a>,
    poses1: &'a [f64],
    batched1: bool,
    shapes2: Shapes<'a>,
    poses2: &'a [f64],
    batched2: bool,
}

impl Pairs<'_> {
    /// Pair `i`: its shapes and its poses (`Pose::new` of the 7 numbers, as the single call).
    fn get(&self, i: usize) -> Result<(&Shape, Pose, &Shape, Pose), dcol::Error> {
        let row = |batched: bool| if batched { 7 * i } else { 0 };
        let (a, b) = (row(self.batched1), row(self.batched2));
        let p1 = pose_from(&self.poses1[a..a + 7])?;
        let p2 = pose_from(&self.poses2[b..b + 7])?;
        Ok((self.shapes1.get(i), p1, self.shapes2.get(i), p2))
    }
}

/// The number of pairs the arguments agree on (1 when none is batched).
fn count(args: &[(&str, Option<usize>)]) -> PyResult<usize> {
    let mut n: Option<(usize, &str)> = None;
    for &(name, c) in args {
        if let Some(c) = c {
            match n {
                None => n = Some((c, name)),
                Some((m, first)) if m != c => {
                    return Err(PyValueError::new_err(format!(
                        "the batch's arguments disagree on the number of pairs: {first} has {m}, \
                         {name} has {c}"
                    )))
                }
                _ => {}
            }
        }
    }
    Ok(n.map_or(1, |(c, _)| c))
}

/// Output columns per batch: numbers per pair in each (0 for an unused column).
const COLS: usize = 5;

/// Runs `kernel(i, rows)` for every pair `i` on up to `threads` threads of dcol's batch pool,
/// `rows[k]` pair `i`'s row of column `k` (`widths[k]` numbers). Returns the columns and the
/// statuses (a panic in a pair is that pair's status 6); the rows of a pair that failed (any
/// status but 0 and 5) are NaN. The columns start as zeroed allocations (pages the system
/// hands over zeroed, not a pass over the memory): the kernel writes every row it succeeds on.
fn run_batch(
    n: usize,
    threads: usize,
    widths: [usize; COLS],
    kernel: impl Fn(usize, &mut [&mut [f64]; COLS]) -> dcol_status + Sync,
) -> ([Vec<f64>; COLS], Vec<i32>) {
    let mut cols: [Vec<f64>; COLS] = widths.map(|w| vec![0.0; n * w]);
    let mut status = vec![0_i32; n];
    let mut chunks = Vec::with_capacity(n.div_ceil(CHUNK));
    let mut rest: [&mut [f64]; COLS] = cols.each_mut().map(|v| v.as_mut_slice());
    let mut rest_status = status.as_mut_slice();
    let mut start = 0;
    while start < n {
        let len = CHUNK.min(n - start);
        let mut heads: [&mut [f64]; COLS] = Default::default();
        for k in 0..COLS {
            let (h, t) = std::mem::take(&mut rest[k]).split_at_mut(len * widths[k]);
            heads[k] = h;
            rest[k] = t;
        }
        let (h, t) = std::mem::take(&mut rest_status).split_at_mut(len);
        rest_status = t;
        chunks.push((start, heads, h));
        start += len;
    }
    for_each_parallel(chunks.into_iter(), threads, |(start, mut heads, st)| {
        for (j, s) in st.iter_mut().enumerate() {
            let mut rows: [&mut [f64]; COLS] = Default::default();
            for (k, (h, r)) in heads.iter_mut().zip(rows.iter_mut()).enumerate() {
                *r = &mut h[j * widths[k]..(j + 1) * widths[k]];
            }
            let outcome = catch_unwind(AssertUnwindSafe(|| kernel(start + j, &mut rows)));
            let st = outcome.unwrap_or(dcol_status::DCOL_ERROR_INTERNAL);
            if !matches!(
                st,
                dcol_status::DCOL_OK | dcol_status::DCOL_ERROR_NOT_CONVERGED
            ) {
                for r in rows.iter_mut() {
                    r.fill(f64::NAN);
                }
            }
            *s = st as i32;
        }
    });
    (cols, status)
}

fn put(row: &mut [f64], v: &Vec3) {
    row.copy_from_slice(&[v.x, v.y, v.z]);
}

fn solved(status: SolveStatus) -> dcol_status {
    if status.is_converged() {
        dcol_status::DCOL_OK
    } else {
        dcol_status::DCOL_ERROR_NOT_CONVERGED
    }
}

/// What each batch function computes per pair.
#[derive(Clone, Copy)]
enum Query {
    Proximity,
    Gradient,
    Distance,
}

/// Reads the arguments, runs the batch without the GIL, and returns the columns as numpy
/// arrays (`(N,)` for width 1, `(N, w)` otherwise) followed by the statuses `(N,)` int32.
#[allow(clippy::too_many_arguments)]
fn batch<'py>(
    py: Python<'py>,
    func: &str,
    query: Query,
    args: [&Bound<'py, PyAny>; 4],
    threads: Option<usize>,
    kw: Kw<'_, 'py>,
) -> PyResult<Bound<'py, PyTuple>> {
    let [shapes1, poses1, shapes2, poses2] = args;
    let (kept1, b1) = shape_arg(shapes1, "shapes1")?;
    let (ro1, c1) = pose_arg(poses1, "poses1")?;
    let (kept2, b2) = shape_arg(shapes2, "shapes2")?;
    let (ro2, c2) = pose_arg(poses2, "poses2")?;
    let n = count(&[
        ("shapes1", b1.then_some(kept1.len())),
        ("poses1", c1),
        ("shapes2", b2.then_some(kept2.len())),
        ("poses2", c2),
    ])?;
    // An empty shape sequence is the only batched argument: no pose array says the batch is
    // empty, so it is more likely a list left unfilled than a wish for no pairs. (A single
    // shape always comes as one kept shape, so neither side is ever without a shape.)
    if n == 0 && c1.is_none() && c2.is_none() {
        let empty = match (b1, b2) {
            (true, true) => "shapes1 and shapes2 are empty sequences",
            (true, false) => "shapes1 is an empty sequence",
            _ => "shapes2 is an empty sequence",
        };
        return Err(PyValueError::new_err(format!(
            "{empty} and both poses are single poses of shape (7,): no pair to compute; for an \
             empty batch pass the poses as arrays of shape (0, 7)"
        )));
    }
    let opts: Options = kw.options(py, func)?;
    let threads = match threads {
        None => std::thread::available_parallelism().map_or(1, |t| t.get()),
        Some(0) => return Err(PyValueError::new_err("threads must be at least 1")),
        Some(t) => t,
    };
    let pairs = Pairs {
        shapes1: shapes_of(&kept1, b1),
        poses1: ro1.as_slice()?,
        batched1: c1.is_some(),
        shapes2: shapes_of(&kept2, b2),
        poses2: ro2.as_slice()?,
        batched2: c2.is_some(),
    };
    let widths = match query {
        Query::Proximity => [1, 3, 3, 3, 0],
        Query::Gradient => [1, 3, 3, 3, 14],
        Query::Distance => [1, 3, 3, 3, 0],
    };
    let kernel = |i: usize, rows: &mut [&mut [f64]; COLS]| -> dcol_status {
        let (s1, p1, s2, p2) = match pairs.get(i) {
            Ok(p) => p,
            Err(e) => return status_of(&e),
        };
        let outcome = match query {
            Query::Proximity => dcol::proximity(s1, &p1, s2, &p2, &opts).map(|p| (p, None)),
            Query::Gradient => dcol::gradient(s1, &p1, s2, &p2, &opts).map(|(p, g)| (p, Some(g))),
            Query::Distance => {
                let checked = dcol::distance(s1, &p1, s2, &p2, &opts).and_then(|d| {
                    answer_representable(&[&distance_numbers(&d)], &p1, &p2).map(|()| d)
                });
                return match checked {
                    Ok(d) => {
                        rows[0][0] = d.distance;
                        put(rows[1], &d.closest1);
                        put(rows[2], &d.closest2);
                        put(rows[3], &d.normal);
                        solved(d.status)
                    }
                    Err(e) => status_of(&e),
                };
            }
        };
        // An answer a double cannot hold is the single call's (and the C function's) status 3.
        let outcome = outcome.and_then(|(p, g)| {
            let grad = match &g {
                Some(g) if p.status.is_converged() => &g[..],
                _ => &[],
            };
            answer_representable(&[&proximity_numbers(&p), grad], &p1, &p2).map(|()| (p, g))
        });
        match outcome {
            Ok((p, g)) => {
                rows[0][0] = p.alpha;
                put(rows[1], &p.point);
                put(rows[2], &p.contact1);
                put(rows[3], &p.contact2);
                if let Some(g) = g {
                    rows[4].copy_from_slice(&g);
                }
                solved(p.status)
            }
            Err(e) => status_of(&e),
        }
    };
    let (cols, status) = py.detach(|| run_batch(n, threads, widths, kernel));
    let mut out: Vec<Bound<'py, PyAny>> = Vec::new();
    for (col, w) in cols.into_iter().zip(widths) {
        match w {
            0 => {}
            1 => out.push(PyArray1::from_vec(py, col).into_any()),
            w => out.push(
                Array2::from_shape_vec((n, w), col)
                    .expect("n rows of w numbers")
                    .into_pyarray(py)
                    .into_any(),
            ),
        }
    }
    out.push(PyArray1::from_vec(py, status).into_any());
    PyTuple::new(py, out)
}

/// `(alpha (N,), point (N, 3), contact1 (N, 3), contact2 (N, 3), status (N,))`: proximity of
/// every pair; `dcol.proximity_batch` wraps it in a named tuple.
#[pyfunction]
#[pyo3(signature = (shapes1, poses1, shapes2, poses2, *, threads=None, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
fn proximity_batch<'py>(
    py: Python<'py>,
    shapes1: &Bound<'py, PyAny>,
    poses1: &Bound<'py, PyAny>,
    shapes2: &Bound<'py, PyAny>,
    poses2: &Bound<'py, PyAny>,
    threads: Option<usize>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let args = [shapes1, poses1, shapes2, poses2];
    batch(
        py,
        "dcol_proximity_batch",
        Query::Proximity,
        args,
        threads,
        kw,
    )
}

/// As `proximity_batch`, with the gradients `(N, 14)` before the statuses.
#[pyfunction]
#[pyo3(signature = (shapes1, poses1, shapes2, poses2, *, threads=None, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
fn gradient_batch<'py>(
    py: Python<'py>,
    shapes1: &Bound<'py, PyAny>,
    poses1: &Bound<'py, PyAny>,
    shapes2: &Bound<'py, PyAny>,
    poses2: &Bound<'py, PyAny>,
    threads: Option<usize>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let args = [shapes1, poses1, shapes2, poses2];
    batch(
        py,
        "dcol.gradient_batch",
        Query::Gradient,
        args,
        threads,
        kw,
    )
}

/// `(distance (N,), closest1 (N, 3), closest2 (N, 3), normal (N, 3), status (N,))`.
#[pyfunction]
#[pyo3(signature = (shapes1, poses1, shapes2, poses2, *, threads=None, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
fn distance_batch<'py>(
    py: Python<'py>,
    shapes1: &Bound<'py, PyAny>,
    poses1: &Bound<'py, PyAny>,
    shapes2: &Bound<'py, PyAny>,
    poses2: &Bound<'py, PyAny>,
    threads: Option<usize>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyTuple>> {
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let args = [shapes1, poses1, shapes2, poses2];
    batch(
        py,
        "dcol.distance_batch",
        Query::Distance,
        args,
        threads,
        kw,
    )
}

/// Benchmark support (python/bench): seconds per round of `dcol::batch::proximity_batch`, the
/// Rust batch, on the same pairs (poses and pairs built before the clock starts, as a Rust
/// caller holds them), `rounds` rounds on `threads` threads. Not part of the API.
#[pyfunction]
fn _bench_rust_proximity_batch<'py>(
    py: Python<'py>,
    shapes1: &Bound<'py, PyAny>,
    poses1: &Bound<'py, PyAny>,
    shapes2: &Bound<'py, PyAny>,
    poses2: &Bound<'py, PyAny>,
    threads: usize,
    rounds: usize,
) -> PyResult<Vec<f64>> {
    let (kept1, b1) = shape_arg(shapes1, "shapes1")?;
    let (ro1, c1) = pose_arg(poses1, "poses1")?;
    let (kept2, b2) = shape_arg(shapes2, "shapes2")?;
    let (ro2, c2) = pose_arg(poses2, "poses2")?;
    if !(b1 && b2 && c1.is_some() && c2.is_some()) {
        return Err(PyValueError::new_err("every argument must be batched"));
    }
    let n = count(&[
        ("shapes1", Some(kept1.len())),
        ("poses1", c1),
        ("shapes2", Some(kept2.len())),
        ("poses2", c2),
    ])?;
    let func = "dcol::batch::proximity_batch";
    let poses = |s: &[f64]| -> PyResult<Vec<Pose>> {
        s.chunks_exact(7)
            .map(|p| pose_from(p).map_err(|e| api_error(py, func, "", e)))
            .collect()
    };
    let (p1, p2) = (poses(ro1.as_slice()?)?, poses(ro2.as_slice()?)?);
    let pairs: Vec<Pair<'_>> = (0..n)
        .map(|i| Pair {
            shape1: &kept1[i].get().inner,
            pose1: &p1[i],
            shape2: &kept2[i].get().inner,
            pose2: &p2[i],
        })
        .collect();
    let opts = Options::default();
    let mut out = vec![Err(dcol::Error::Internal("unset")); n];
    py.detach(|| {
        (0..rounds)
            .map(|_| {
                let t = Instant::now();
                rust_proximity_batch(&pairs, &opts, threads, &mut out)
                    .map(|()| t.elapsed().as_secs_f64())
            })
            .collect::<Result<Vec<f64>, dcol::Error>>()
    })
    .map_err(|e| api_error(py, func, "", e))
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(proximity_batch, m)?)?;
    m.add_function(wrap_pyfunction!(gradient_batch, m)?)?;
    m.add_function(wrap_pyfunction!(distance_batch, m)?)?;
    m.add_function(wrap_pyfunction!(_bench_rust_proximity_batch, m)?)?;
    Ok(())
}
