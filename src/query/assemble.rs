//! One generic routine that stacks the scaled conic constraints of any two shapes into one
//! cone program (no code per pair of shape kinds), and the workspace that holds its orthant
//! rows without allocating per query.

use std::cell::RefCell;

use crate::math::{Mat3, Real, Vec3};
use crate::shapes::{BodyRow, ConicShape, RowSink, Shape};
use crate::solver::{LpRow, Problem, MAX_VARS};

/// Orthant rows up to which the workspace lives on the stack.
const STACK_ROWS_SMALL: usize = 8;
const STACK_ROWS: usize = 32;

thread_local! {
    static SCRATCH: RefCell<Vec<LpRow>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with `m` zeroed orthant rows: on the stack for small problems, otherwise in a
/// per-thread buffer that is allocated once and reused.
pub(crate) fn with_rows<R>(m: usize, f: impl FnOnce(&mut [LpRow]) -> R) -> R {
    if m <= STACK_ROWS_SMALL {
        let mut buf = [LpRow::ZERO; STACK_ROWS_SMALL];
        f(&mut buf[..m])
    } else if m <= STACK_ROWS {
        let mut buf = [LpRow::ZERO; STACK_ROWS];
        f(&mut buf[..m])
    } else {
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut v) => {
                if v.len() < m {
                    v.resize(m, LpRow::ZERO);
                }
                let rows = &mut v[..m];
                rows.fill(LpRow::ZERO);
                f(rows)
            }
            // Re-entered from inside `f` (not done by this crate): fall back to the heap.
            Err(_) => f(&mut vec![LpRow::ZERO; m]),
        })
    }
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

/// Writes a shape's rows into a problem.
struct Builder<'p, 'a> {
    problem: &'p mut Problem<'a>,
    place: Placement,
    lp_next: usize,
}

impl Builder<'_, '_> {
    fn fill(&self, row: &BodyRow, g: &mut [Real; MAX_VARS], h: &mut Real) {
        let pl = &self.place;
        // s = f_u·Qᵀ(x − c) + f_α α + f_w·w  ⇒  G = [−Q f_u, −f_α, −f_w], h = −(Q f_u)·c
        let qf = pl.rotation * Vec3::from(row.fu);
        g.fill(0.0);
        g[pl.point_col] = -qf.x;
        g[pl.point_col + 1] = -qf.y;
        g[pl.point_col + 2] = -qf.z;
        *h = -qf.dot(&pl.center);
        match pl.alpha_col {
            Some(c) => g[c] = -row.fa,
            None => *h += row.fa,
        }
        for k in 0..pl.slacks {
            g[pl.slack_col + k] = -row.fw[k];
        }
    }
}

impl RowSink for Builder<'_, '_> {
    fn lp(&mut self, row: BodyRow) {
        let mut g = [0.0; MAX_VARS];
        let mut h = 0.0;
        self.fill(&row, &mut g, &mut h);
        let r = &mut self.problem.lp[self.lp_next];
        r.g = g;
        r.h = h;
        self.lp_next += 1;
    }

    fn soc(&mut self, rows: &[BodyRow]) {
        let k = self.problem.n_soc;
        let mut block = self.problem.soc[k];
        block.dim = rows.len();
        for (i, row) in rows.iter().enumerate() {
            let mut h = 0.0;
            self.fill(row, &mut block.g[i], &mut h);
            block.h[i] = h;
        }
        self.problem.soc[k] = block;
        self.problem.n_soc += 1;
    }
}

/// Appends `shape`'s scaled rows (lengths times `inv_scale`) to `problem`, starting at orthant
/// row `lp_start`; returns the next free orthant row.
pub(crate) fn add_shape(
    problem: &mut Problem<'_>,
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
