//! The scene layer for "N bodies: which pairs have α* ≤ t?": shapes registered once, poses
//! updated per step, a broad phase that skips every pair it can, and the narrow phase only where
//! needed.
//!
//! Levels, cheapest first (each counted in [`StepStats`]):
//! 1. Sweep-and-prune on the x extent of each body's bounding sphere scaled by t (α* ≤ t needs
//!    the scaled bounding spheres to overlap, so pairs whose intervals are disjoint are skipped).
//! 2. The exact sphere test `‖Δr‖ ≤ t (ρ₁ + ρ₂)` on the pairs the sweep reports.
//! 3. The inscribed-sphere bound: `‖Δr‖/(ι₁ + ι₂) ≤ t` proves α* ≤ t without deciding anything
//!    else, so such a pair goes straight to the full solve.
//! 4. A solve that stops as soon as α* is proven above t; pairs proven below run to convergence
//!    and are reported with their full proximity.
//!
//! A half-space's interval is the whole line, so it is a candidate against every other body
//! (its narrow phase is a closed form); pairs of two half-spaces are skipped.
//!
//! Cost: the sweep is O(N log N) per step (a sort of N intervals) plus O(K) for the K pairs whose
//! intervals overlap; the narrow phase is one (often truncated) solve per pair surviving level 2.

use crate::error::{Error, ErrorDetail};
use crate::math::{Pose, Real};
use crate::query::{query_until, query_until_warm, Cache, Options, Proximity, Want};
use crate::shapes::{Shape, SupportMap};
use std::collections::HashMap;

/// A body's index in its scene.
pub type BodyId = usize;

/// One reported pair: `body1 < body2` and α* ≤ threshold.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScenePair {
    /// The lower body index.
    pub body1: BodyId,
    /// The higher body index.
    pub body2: BodyId,
    /// The full proximity result for (body1, body2).
    pub proximity: Proximity,
}

/// How many pairs each level of a step handled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// N (N − 1)/2.
    pub pairs_total: usize,
    /// Pairs whose sweep intervals overlap.
    pub sweep_candidates: usize,
    /// Pairs whose scaled bounding spheres overlap.
    pub sphere_candidates: usize,
    /// Pairs proven below t by the inscribed-sphere bound (then solved fully).
    pub proven_by_bounds: usize,
    /// Pairs whose solve stopped early once α* > t was proven.
    pub early_exits: usize,
    /// Pairs solved to convergence.
    pub full_solves: usize,
    /// Pairs reported (α* ≤ t).
    pub reported: usize,
}

/// A set of bodies for repeated all-pairs threshold queries.
#[derive(Debug, Default)]
pub struct Scene {
    shapes: Vec<Shape>,
    poses: Vec<Pose>,
    /// Scratch reused across steps: (interval min, body) sorted by min.
    order: Vec<(Real, BodyId)>,
    /// The warm-start caches of the pairs of polytopes that reached the narrow phase in the
    /// last step, and that step's number (older ones are dropped).
    caches: HashMap<(BodyId, BodyId), (u64, Cache)>,
    /// Steps taken.
    steps: u64,
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Scene {
        Scene::default()
    }

    /// Adds a body and returns its id (ids are consecutive from 0).
    pub fn add(&mut self, shape: Shape, pose: Pose) -> BodyId {
        self.shapes.push(shape);
        self.poses.push(pose);
        self.shapes.len() - 1
    }

    /// Number of bodies.
    pub fn len(&self) -> usize {
        self.shapes.len()
    }

    /// True when the scene has no bodies.
    pub fn is_empty(&self) -> bool {
        self.shapes.is_empty()
    }

    /// Moves body `id`.
    pub fn set_pose(&mut self, id: BodyId, pose: Pose) -> Result<(), Error> {
        match self.poses.get_mut(id) {
            Some(p) => {
                *p = pose;
                Ok(())
            }
            None => Err(Error::InvalidOptions(ErrorDetail::new(
                "id",
                id as Real,
                "is not a body of this scene",
            ))),
        }
    }

    /// Shape of body `id`.
    pub fn shape(&self, id: BodyId) -> Option<&Shape> {
        self.shapes.get(id)
    }

    /// Pose of body `id`.
    pub fn pose(&self, id: BodyId) -> Option<&Pose> {
        self.poses.get(id)
    }

    /// All pairs with α* ≤ `threshold`, written to `out` (cleared first) in increasing
    /// (body1, body2) order. A pair whose solve did not converge is reported with its status
    /// when its last iterate is ≤ threshold. A half-space (bounding radius `+∞`) is a
    /// candidate against every body; a pair of two half-spaces is skipped, never reported.
    pub fn pairs_within(
        &mut self,
        threshold: Real,
        options: &Options,
        out: &mut Vec<ScenePair>,
    ) -> Result<StepStats, Error> {
        crate::query::check_threshold(threshold)?;
        options.validate()?;
        out.clear();
        self.steps += 1;
        let step = self.steps;
        let n = self.shapes.len();
        let mut stats = StepStats {
            pairs_total: n * n.saturating_sub(1) / 2,
            ..StepStats::default()
        };
        let t = threshold;
        self.order.clear();
        for (i, (s, p)) in self.shapes.iter().zip(&self.poses).enumerate() {
            self.order
                .push((p.position().x - t * s.bounding_radius(), i));
        }
        self.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for a in 0..self.order.len() {
            let i = self.order[a].1;
            let (si, pi) = (&self.shapes[i], &self.poses[i]);
            let max_i = pi.position().x + t * si.bounding_radius();
            for b in (a + 1)..self.order.len() {
                if self.order[b].0 > max_i {
                    break;
                }
                stats.sweep_candidates += 1;
                let j = self.order[b].1;
                let (b1, b2) = if i < j { (i, j) } else { (j, i) };
                let (s1, p1, s2, p2) = (
                    &self.shapes[b1],
                    &self.poses[b1],
                    &self.shapes[b2],
                    &self.poses[b2],
                );
                let d = (p2.position() - p1.position()).norm();
                if d > t * (s1.bounding_radius() + s2.bounding_radius()) {
                    continue;
                }
                // Two half-spaces have no α* (a query on them is an error): never reported.
                if crate::query::check_halfspace_pair(s1, s2).is_err() {
                    continue;
                }
                stats.sphere_candidates += 1;
                let proven = d <= t * (s1.inscribed_radius() + s2.inscribed_radius());
                let thresh = if proven {
                    stats.proven_by_bounds += 1;
                    None
                } else {
                    Some((t, false))
                };
                // Pairs of polytopes start from their last answer (`crate::Cache`); the
                // others answer cold.
                let f = if s1.vertex_pieces().is_some() && s2.vertex_pieces().is_some() {
                    let (seen, cache) = self.caches.entry((b1, b2)).or_default();
                    *seen = step;
                    query_until_warm(s1, p1, s2, p2, options, Want::Proximity, thresh, cache)?
                } else {
                    query_until(s1, p1, s2, p2, options, Want::Proximity, thresh)?
                };
                if f.decided == Some(false) {
                    stats.early_exits += 1;
                    continue;
                }
                stats.full_solves += 1;
                if f.prox.alpha <= t {
                    out.push(ScenePair {
                        body1: b1,
                        body2: b2,
                        proximity: f.prox,
                    });
                }
            }
        }
        // Pairs that left the narrow phase lose their caches (no allocation: it only shrinks).
        self.caches.retain(|_, (seen, _)| *seen == step);
        out.sort_unstable_by_key(|a| (a.body1, a.body2));
        stats.reported = out.len();
        Ok(stats)
    }
}
