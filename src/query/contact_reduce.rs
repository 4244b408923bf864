//! The choice of a manifold's points among its candidates (`super::contact`): at most the
//! number asked for, the deepest first, then the ones spanning the largest area.

use crate::math::{Real, Vec3};

/// The most candidates considered (the clipping buffers' size).
pub(crate) const MAX_CANDIDATES: usize = 64;
const BUF: usize = MAX_CANDIDATES;

/// Chooses at most `cap` of the points: the deepest, the farthest from it, the one spanning the
/// largest triangle with those two, then each time the one farthest from those chosen (each
/// candidate's distance to the chosen ones kept up to date, one pass per pick).
#[inline]
pub(crate) fn reduce(pos: &[Vec3], depth: &[Real], cap: usize, chosen: &mut [usize]) -> usize {
    let n = pos.len().min(depth.len()).min(BUF);
    let cap = cap.min(chosen.len());
    if n <= cap {
        for (i, c) in chosen.iter_mut().enumerate().take(n) {
            *c = i;
        }
        return n;
    }
    let mut used = [false; BUF];
    let deepest = pick(n, &used, |i| depth[i]).unwrap_or(0);
    chosen[0] = deepest;
    used[deepest] = true;
    let p0 = pos[deepest];
    // Each candidate's distance to the nearest chosen point.
    let mut near = [0.0; BUF];
    for i in 0..n {
        near[i] = (pos[i] - p0).norm();
    }
    let mut k = 1;
    while k < cap {
        let best = if k == 2 {
            let (a, e) = (pos[chosen[0]], pos[chosen[1]] - pos[chosen[0]]);
            pick(n, &used, |i| e.cross(&(pos[i] - a)).norm_squared())
        } else {
            pick(n, &used, |i| near[i])
        };
        let Some(b) = best else { break };
        chosen[k] = b;
        used[b] = true;
        let pb = pos[b];
        for i in 0..n {
            near[i] = near[i].min((pos[i] - pb).norm());
        }
        k += 1;
    }
    k
}

/// The first unused candidate of the best `score` (each scored once), `None` when all are used.
#[inline]
fn pick(n: usize, used: &[bool; BUF], score: impl Fn(usize) -> Real) -> Option<usize> {
    let mut best: Option<(usize, Real)> = None;
    for i in 0..n {
        if used[i] {
            continue;
        }
        let s = score(i);
        if best.map_or(true, |(_, b)| s > b) {
            best = Some((i, s));
        }
    }
    best.map(|(i, _)| i)
}
