//! One generic routine that stacks the scaled conic constraints of any two shapes into one
//! cone program (no code per pair of shape kinds), the workspace that holds its orthant rows
//! without allocating per query, and the dispatch from a runtime variable count to the
//! solver's compile-time `N`.

use std::cell::RefCell;

use crate::math::{Mat3, Real, Vec3};
use crate::shapes::{BodyRow, ConicShape, RowSink, Shape};
use crate::solver::{LpRow, Problem};

/// Orthant rows up to which the workspace lives on the stack.
pub(crate) const STACK_ROWS_SMALL: usize = 8;
/// Orthant rows up to which the workspace lives on the stack (middle buffer: two boxes, or a
/// box and a 12-facet polytope; a smaller buffer is less to zero per query).
pub(crate) const STACK_ROWS_MEDIUM: usize = 18;
/// Orthant rows up to which the workspace lives on the stack (larger buffer).
pub(crate) const STACK_ROWS: usize = 32;

/// Marker type carrying a variable count.
pub(crate) struct Dim<const N: usize>;

/// A per-thread buffer of orthant rows for problems too large for the stack, allocated on
/// first use and reused (API.md allows this for polytopes and polygons with many facets).
pub(crate) trait Scratch<const N: usize> {
    /// Runs `f` with `m` zeroed rows from this thread's buffer.
    fn with_scratch<R>(m: usize, f: impl FnOnce(&mut [LpRow<N>]) -> R) -> R;
}

macro_rules! scratch_for {
    ($($n:literal),*) => {$(
        impl Scratch<$n> for Dim<$n> {
            fn with_scratch<R>(m: usize, f: impl FnOnce(&mut [LpRow<$n>]) -> R) -> R {
                thread_local! {
                    static SCRATCH: RefCell<Vec<LpRow<$n>>> = const { RefCell::new(Vec::new()) };
                }
                SCRATCH.with(|cell| match cell.try_borrow_mut() {
                    Ok(mut v) => {
                        if v.len() < m {
                            v.resize(m, LpRow::ZERO);
                        }
                        let rows = &mut v[..m];
                        rows.fill(LpRow::ZERO);
                        f(rows)
                    }
                    // Re-entered from inside `f` (this crate never does): use the heap.
                    Err(_) => f(&mut vec![LpRow::ZERO; m]),
                })
            }
        }
    )*};
}
scratch_for!(4, 5, 6, 7, 8, 9, 10, 11, 12, 13);

/// Runs `f` with `m` zeroed orthant rows: on the stack for small problems, otherwise in a
/// per-thread buffer that is allocated once and reused.
pub(crate) fn with_rows<const N: usize, R>(m: usize, f: impl FnOnce(&mut [LpRow<N>]) -> R) -> R
where
    Dim<N>: Scratch<N>,
{
    if m == 0 {
        f(&mut [])
    } else if m <= STACK_ROWS_SMALL {
        let mut buf = [LpRow::ZERO; STACK_ROWS_SMALL];
        f(&mut buf[..m])
    } else if m <= STACK_ROWS_MEDIUM {
        let mut buf = [LpRow::ZERO; STACK_ROWS_MEDIUM];
        f(&mut buf[..m])
    } else if m <= STACK_ROWS {
        let mut buf = [LpRow::ZERO; STACK_ROWS];
        f(&mut buf[..m])
    } else {
        <Dim<N> as Scratch<N>>::with_scratch(m, f)
    }
}

/// Something to run on a problem with a compile-time variable count.
pub(crate) trait Task {
    type Output;
    fn run<const N: usize>(self, rows: &mut [LpRow<N>]) -> Self::Output;
}

/// Calls `task.run::<N>` with `N = n` and `m` orthant rows. `n` must be in 4..=13 (the
/// distance program of two padded hulls has 7 + 3 + 3 variables).
pub(crate) fn dispatch<T: Task>(n: usize, m: usize, task: T) -> Option<T::Output> {
    Some(match n {
        4 => with_rows::<4, _>(m, |r| task.run(r)),
        5 => with_rows::<5, _>(m, |r| task.run(r)),
        6 => with_rows::<6, _>(m, |r| task.run(r)),
        7 => with_rows::<7, _>(m, |r| task.run(r)),
        8 => with_rows::<8, _>(m, |r| task.run(r)),
        9 => with_rows::<9, _>(m, |r| task.run(r)),
        10 => with_rows::<10, _>(m, |r| task.run(r)),
        11 => with_rows::<11, _>(m, |r| task.run(r)),
        12 => with_rows::<12, _>(m, |r| task.run(r)),
        13 => with_rows::<13, _>(m, |r| task.run(r)),
        _ => return None,
    })
}

/// Where a shape's variables sit among the problem's columns, and where it is.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Placement {
    /// Body rotation `Q`.
    pub rotation: Mat3,
    /// Body origin in the problem's (non-dimensional) coordinates.
    pub center: Vec3,
    /// Column of the point's first coordinate (three columns).
    pub point_col: usize,
    /// Column of the scale α, or `None` for the fixed scale 1.
    pub alpha_col: Option<usize>,
    /// First column of the shape's own slack variables.
    pub slack_col: usize,
    /// Number of slack variables.
    pub slacks: usize,
}

impl Placement {
    /// Fills one row of `G` and its `h` from a body row:
    /// `s = f_u·Qᵀ(x − c) + f_α α + f_w·w` ⇒ `G = [−Q f_u, −f_α, −f_w]`, `h = −(Q f_u)·c`.
    pub(crate) fn fill<const N: usize>(&self, row: &BodyRow, g: &mut [Real; N], h: &mut Real) {
        let qf = self.rotation * Vec3::from(row.fu);
        *g = [0.0; N];
        g[self.point_col] = -qf.x;
        g[self.point_col + 1] = -qf.y;
        g[self.point_col + 2] = -qf.z;
        *h = -qf.dot(&self.center);
        match self.alpha_col {
            Some(c) => g[c] = -row.fa,
            None => *h += row.fa,
        }
        for k in 0..self.slacks {
            g[self.slack_col + k] = -row.fw[k];
        }
    }
}

/// Writes a shape's rows into a problem.
struct Builder<'p, 'a, const N: usize> {
    problem: &'p mut Problem<'a, N>,
    place: Placement,
    lp_next: usize,
}

impl<const N: usize> RowSink for Builder<'_, '_, N> {
    fn lp(&mut self, row: BodyRow) {
        let r = &mut self.problem.lp[self.lp_next];
        self.place.fill(&row, &mut r.g, &mut r.h);
        self.lp_next += 1;
    }

    fn soc(&mut self, rows: &[BodyRow]) {
        let k = self.problem.n_soc;
        let block = &mut self.problem.soc[k];
        for (i, row) in rows.iter().enumerate() {
            self.place.fill(row, &mut block.g[i], &mut block.h[i]);
        }
        // A 3-dimensional cone keeps a zero fourth row (see `solver::cones`).
        for i in rows.len()..block.g.len() {
            block.g[i] = [0.0; N];
            block.h[i] = 0.0;
        }
        self.problem.n_soc += 1;
    }
}

/// Appends `shape`'s scaled rows (lengths times `inv_scale`) to `problem`, starting at orthant
/// row `lp_start`; returns the next free orthant row.
pub(crate) fn add_shape<const N: usize>(
    problem: &mut Problem<'_, N>,
    shape: &Shape,
    place: Placement,
    inv_scale: Real,
    lp_start: usize,
) -> usize {
    let mut b = Builder {
        problem,
        place,
        lp_next: lp_start,
    };
    shape.rows(inv_scale, &mut b);
    b.lp_next
}
