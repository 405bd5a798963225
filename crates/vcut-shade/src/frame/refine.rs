//! Refinement at rest: the frame replaces interpolated field factors by exact ones while nothing
//! moves. Next to its source a field's trilinear lookup is most of a frame's error
//! (`docs/benchmarks.md`, "Where a dense arrangement's error is"); the exact factor of source j
//! at a vertex is j's cut cast by rays from the vertex's ray origin over j's bounding cone
//! ([`vcut_precompute::field::exact_point_cut`], the cut the field's samples are made of, at the
//! vertex itself).
//!
//! **Which pairs.** A vertex's field input from j (its samples, or all of them inside j) whose
//! ray origin lies within [`Refinement::reach`] of j's bounding radii from j's centre. Flat
//! occluders are exact already.
//!
//! **Kept per pair.** Each exact factor is kept with the ray origin relative to j's translation
//! it was cast at ([`ExactFactor::at`]) and j's yaw (cast against j's hierarchy as it stands
//! turned): every merge (a move's, a drag's rest products, a merge on
//! the spot) uses it while the pair stands where it was cast and the lookup otherwise, so a
//! pair that has not moved is never cast twice, and a move and back finds it again. A vertex
//! keeps at most one factor per source (a cast at a new place replaces the old one).
//!
//! **Order and interruption.** Visible vertices first (facing the last eye), then the rest;
//! within each, the vertices nearest a source (in its radii) first. A pass casts a batch of
//! vertices' factors, merges those vertices again, and checks its deadline and its cancel flag
//! between batches (and the flag between casts), so a move waits at most one batch's casts.
//!
//! **Determinism.** A factor is a function of the pair's geometry; a merge of the factors
//! present. Once a refinement completes, every pair within reach holds the exact factor, so
//! the frame's cuts depend on the scene's state only, not on thread timing or on where earlier
//! passes stopped.

use super::keys::{FieldKey, Input};
use super::merge::Rekey;
use super::{Context, Frame, FrameError, MoveTiming};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;
use vcut_cut::Cut;

/// How far from a source its factors are refined by default, in its bounding radii: every pair
/// a field reaches. Far pairs cost few rays (their bounding cone is narrow), and they still
/// carry part of the lookups' error (what each reach costs and leaves: `docs/benchmarks.md`,
/// "Refinement at rest").
pub const REFINE_REACH: f32 = f32::INFINITY;

/// Vertices whose factors a pass casts before it merges them and checks its deadline.
const BATCH_VERTICES: usize = 64;

/// What a refinement pass does ([`Frame::refine`]).
#[derive(Debug, Clone, Copy)]
pub struct Refinement<'a> {
    /// Refine the pairs whose ray origin lies within this many of the source's bounding radii
    /// of its centre (above 0; `f32::INFINITY`: every pair a field reaches).
    pub reach: f32,
    /// Stop after the batch running at this instant (`None`: run to completion).
    pub deadline: Option<Instant>,
    /// Stop as soon as this is set (a move or an edit is waiting).
    pub cancel: Option<&'a AtomicBool>,
}

impl Default for Refinement<'_> {
    fn default() -> Self {
        Refinement { reach: REFINE_REACH, deadline: None, cancel: None }
    }
}

/// What a refinement pass did, and how far the frame's refinement is.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RefineStats {
    /// Exact factors cast by this pass.
    pub cast: usize,
    /// Rays they took.
    pub rays: u64,
    /// Vertices merged again with their new factors.
    pub merged: usize,
    /// Pairs within reach whose exact factor the frame now uses.
    pub exact: usize,
    /// Pairs within reach still looked up (the pass stopped, or the memory budget is spent).
    pub remaining: usize,
    /// Of the pairs remaining, those left looked up because the memory budget had no room for
    /// more factors (the pass stopped there).
    pub over_budget: usize,
    /// Bytes of the exact factors the frame keeps.
    pub bytes: usize,
    /// The pass's time (seconds).
    pub seconds: f64,
    /// Stopped by its cancel flag.
    pub cancelled: bool,
}

impl RefineStats {
    /// Whether every pair within reach is exact.
    pub fn complete(&self) -> bool {
        self.remaining == 0
    }
}

/// One exact field factor of a vertex: source `object`'s cut cast from ray origin `at`
/// (relative to the source's translation) against the source turned by `yaw`. Kept as a cut
/// (prepared by each merge that takes it, as flat occluders' cuts are), so it serves either
/// merge algorithm.
pub(super) struct ExactFactor {
    pub(super) object: u32,
    pub(super) at: Vec3,
    pub(super) yaw: f32,
    pub(super) cut: Cut,
}

impl ExactFactor {
    pub(super) fn bytes(&self) -> usize {
        size_of::<ExactFactor>() + self.cut.len() * (size_of::<u8>() + size_of::<f32>())
    }
}

/// A pair to refine: object `o`'s vertex `v` and source `j`, cast from `at` (relative to j).
#[derive(Clone, Copy)]
struct Pair {
    o: usize,
    v: usize,
    j: u32,
    at: Vec3,
}

impl Context {
    /// Vertex `v` of object `o`'s ray origin relative to object `j`'s placement: where its exact
    /// factor of j is cast from.
    fn exact_origin(&self, o: usize, v: usize, j: usize) -> Vec3 {
        let me = &self.objects[o];
        let p = me.mesh.positions()[v] + me.translation;
        vcut_rays::origin(p, me.mesh.normals()[v], me.ray_offset) - self.objects[j].translation
    }

    /// The exact factor vertex `v` of object `o` keeps for input `k` where the pair stands now
    /// (`None`: none cast there; a lookup, then).
    pub(super) fn exact_factor(&self, o: usize, v: usize, k: &FieldKey) -> Option<&Cut> {
        let kept = self.objects[o].exact.get(v).filter(|e| !e.is_empty())?;
        if !matches!(k.input, Input::Samples(_) | Input::Inside) {
            return None;
        }
        let at = self.exact_origin(o, v, k.object as usize);
        let yaw = self.objects[k.object as usize].turn.yaw;
        kept.iter().find(|f| f.object == k.object && f.at == at && f.yaw == yaw).map(|f| &f.cut)
    }

    /// The pair of vertex `v` of object `o` and the source of input `k`, with its distance from
    /// the source's centre in its radii, if `k` is a field input within `reach`.
    fn pair(&self, o: usize, v: usize, k: &FieldKey, reach: f32) -> Option<(Pair, f32)> {
        if !matches!(k.input, Input::Samples(_) | Input::Inside) {
            return None;
        }
        let j = k.object as usize;
        let layout = self.objects[j].layout?;
        let at = self.exact_origin(o, v, j);
        let d = at.distance(layout.center) / layout.radius;
        (d <= reach).then_some((Pair { o, v, j: k.object, at }, d))
    }
}

impl Frame {
    /// Refines the frame toward the exact reference: casts the exact factor of every pair
    /// within `how.reach` that has none where it stands, and merges those vertices again, until
    /// done, past `how.deadline`, or cancelled. A drag under way settles first; the vertices
    /// whose merge waits are merged before the ones facing away are refined. Exact factors are
    /// kept within what [`super::FrameSettings::memory_budget`] leaves beside the frame as the
    /// pass begins (the vertices merged again may grow their shading lists a little beyond).
    pub fn refine(&mut self, how: &Refinement<'_>) -> Result<RefineStats, FrameError> {
        let start = Instant::now();
        if how.reach.is_nan() || how.reach <= 0.0 {
            return Err(FrameError::Setting(super::SettingError {
                key: "refine_reach",
                value: how.reach.to_string(),
                reason: "must be above 0 (radii; inf: every pair a field reaches)".into(),
            }));
        }
        self.settle()?;
        self.ctx.ensure_turned_occluders();
        let mut stats = RefineStats::default();
        // Cancelled at once; out of time only once a batch has run, so that every pass makes
        // progress.
        let cancelled = |s: &mut RefineStats| {
            s.cancelled = how.cancel.is_some_and(|c| c.load(Ordering::Relaxed));
            s.cancelled
        };
        let late = |s: &RefineStats| s.cast > 0 && how.deadline.is_some_and(|d| Instant::now() >= d);
        let stop = |s: &mut RefineStats| cancelled(s) || late(s);
        let budget = self.ctx.settings.memory_budget.map(|b| usize::try_from(b).unwrap_or(usize::MAX));
        let mut room = budget.map(|b| b.saturating_sub(self.memory().total()));
        let mut full = false;
        'phases: for visible in [true, false] {
            // The waiting vertices are merged first (those facing the eye, then the others), so
            // that every vertex refined has its inputs where the objects are.
            if self.pending_merges() > 0 {
                if stop(&mut stats) {
                    break;
                }
                self.rekey(Rekey::waiting(!visible))?;
            }
            let order = self.refine_order(visible, how.reach);
            for batch in order.chunks(BATCH_VERTICES) {
                if stop(&mut stats) {
                    break 'phases;
                }
                let pairs: Vec<Pair> = batch.iter().flat_map(|(_, pairs)| pairs.iter().copied()).collect();
                let cast = self.cast(&pairs, how.cancel);
                stats.rays += cast.iter().flatten().map(|(_, rays)| rays).sum::<u64>();
                let mut touched: Vec<(usize, usize)> = Vec::new();
                for (pair, factor) in pairs.iter().zip(cast) {
                    let Some((cut, _)) = factor else { continue };
                    let yaw = self.ctx.objects[pair.j as usize].turn.yaw;
                    let factor = ExactFactor { object: pair.j, at: pair.at, yaw, cut };
                    if room.is_some_and(|r| factor.bytes() > r) {
                        full = true;
                        continue;
                    }
                    room = room.map(|r| r - factor.bytes());
                    self.keep(pair, factor);
                    stats.cast += 1;
                    touched.push((pair.o, pair.v));
                }
                touched.dedup();
                stats.merged += self.merge_again(&touched)?;
                if full {
                    break 'phases;
                }
            }
        }
        self.count_refined(how.reach, &mut stats);
        if full {
            stats.over_budget = stats.remaining;
        }
        stats.seconds = start.elapsed().as_secs_f64();
        self.tally.refine = Some(stats);
        Ok(stats)
    }

    /// The vertices to refine (facing the eye, or the others), each with its pairs within
    /// `reach` that have no exact factor where they stand, nearest a source first.
    fn refine_order(&self, visible: bool, reach: f32) -> Vec<(f32, Vec<Pair>)> {
        let ctx = &self.ctx;
        let mut order: Vec<(f32, Vec<Pair>)> = Vec::new();
        for (o, state) in self.states.iter().enumerate() {
            let me = &ctx.objects[o];
            let rows: Vec<(f32, Vec<Pair>)> = (0..state.keys.len())
                .into_par_iter()
                .filter(|&v| !state.pending[v] && ctx.eye.is_none_or(|e| me.seen(v, e)) == visible)
                .filter_map(|v| {
                    let mut nearest = f32::INFINITY;
                    let pairs: Vec<Pair> = state.keys[v]
                        .iter()
                        .filter(|k| ctx.exact_factor(o, v, k).is_none())
                        .filter_map(|k| ctx.pair(o, v, k, reach))
                        .map(|(p, d)| {
                            nearest = nearest.min(d);
                            p
                        })
                        .collect();
                    (!pairs.is_empty()).then_some((nearest, pairs))
                })
                .collect();
            order.extend(rows);
        }
        // Stable, so ties keep object and vertex order: the same order at any thread count.
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        order
    }

    /// The exact factors of `pairs`, with their rays (`None` where cancelled first).
    fn cast(&self, pairs: &[Pair], cancel: Option<&AtomicBool>) -> Vec<Option<(Cut, u64)>> {
        let ctx = &self.ctx;
        pairs
            .par_iter()
            .map(|p| {
                if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return None;
                }
                let j = p.j as usize;
                let layout = ctx.objects[j].layout.unwrap_or_else(|| unreachable!("a pair's source has a field"));
                let (cut, rays) = vcut_precompute::field::exact_point_cut(
                    ctx.turned_occluder(j),
                    &ctx.tree,
                    p.at,
                    layout.center,
                    layout.radius,
                );
                Some((cut, rays.rays_cast))
            })
            .collect()
    }

    /// Keeps `factor` for `pair`'s vertex, in place of any it had for the same source.
    fn keep(&mut self, pair: &Pair, factor: ExactFactor) {
        let me = &mut self.ctx.objects[pair.o];
        if me.exact.is_empty() {
            me.exact = (0..me.mesh.vertex_count()).map(|_| Vec::new()).collect();
        }
        let kept = &mut me.exact[pair.v];
        match kept.iter_mut().find(|f| f.object == pair.j) {
            Some(old) => *old = factor,
            None => kept.push(factor),
        }
    }

    /// Merges again the vertices `touched` (object, vertex; grouped by object) at their kept
    /// inputs, now with their exact factors; returns how many.
    fn merge_again(&mut self, touched: &[(usize, usize)]) -> Result<usize, FrameError> {
        let mut total = 0;
        for o in 0..self.states.len() {
            let n = self.ctx.objects[o].mesh.vertex_count();
            let mut which = vec![false; n];
            for &(_, v) in touched.iter().filter(|t| t.0 == o) {
                which[v] = true;
            }
            if !which.contains(&true) {
                continue;
            }
            let ctx = &self.ctx;
            let state = &mut self.states[o];
            if ctx.caches.merged && state.merged.len() != n {
                state.merged = vec![super::kept::KeptCut::default(); n];
            }
            let super::object::MergeState { keys, lists, decoded, merged, .. } = state;
            let kept = ctx.caches.merged.then_some(&mut merged[..]);
            total += ctx.merge_all(o, keys, &which, kept, lists, decoded, None, &mut MoveTiming::default())?;
        }
        self.tally.merges += total as u64;
        Ok(total)
    }

    /// Counts into `stats` the pairs within `reach` that are exact and those still looked up,
    /// and the exact factors' bytes.
    fn count_refined(&self, reach: f32, stats: &mut RefineStats) {
        let ctx = &self.ctx;
        for (o, state) in self.states.iter().enumerate() {
            let (exact, remaining) = (0..state.keys.len())
                .into_par_iter()
                .map(|v| {
                    state.keys[v].iter().filter(|k| ctx.pair(o, v, k, reach).is_some()).fold((0, 0), |(e, r), k| {
                        if ctx.exact_factor(o, v, k).is_some() { (e + 1, r) } else { (e, r + 1) }
                    })
                })
                .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
            stats.exact += exact;
            stats.remaining += remaining;
        }
        stats.bytes = self.exact_bytes();
    }

    /// Bytes of the exact factors the frame keeps.
    pub(super) fn exact_bytes(&self) -> usize {
        self.ctx
            .objects
            .iter()
            .map(|s| {
                s.exact
                    .iter()
                    .map(|e| size_of::<Vec<ExactFactor>>() + e.iter().map(ExactFactor::bytes).sum::<usize>())
                    .sum::<usize>()
            })
            .sum()
    }

    /// The exact factor vertex `v` of object `o` keeps for source `j` where the pair stands
    /// now (`None`: its factor of j is looked up, or j does not shadow it).
    pub fn exact_factor(&self, o: usize, v: usize, j: usize) -> Option<&Cut> {
        let k = self.states.get(o)?.keys.get(v)?.iter().find(|k| k.object as usize == j)?;
        self.ctx.exact_factor(o, v, k)
    }

    /// Vertex `v` of object `o`'s ray origin in world space: where its exact factors are cast
    /// from (the SVC's ray origin, moved with the object).
    pub fn ray_origin(&self, o: usize, v: usize) -> Vec3 {
        self.ctx.exact_origin(o, v, o) + self.ctx.objects[o].translation
    }

    /// What the last [`Frame::refine`] did (`None`: none ran).
    pub fn last_refine(&self) -> Option<RefineStats> {
        self.tally.refine
    }

    /// Drops every exact factor (the frame merges again the vertices that used one): the
    /// frame as it was before any refinement, bit for bit.
    pub fn unrefine(&mut self) -> Result<usize, FrameError> {
        let touched: Vec<(usize, usize)> = self
            .ctx
            .objects
            .iter()
            .enumerate()
            .flat_map(|(o, s)| s.exact.iter().enumerate().filter(|(_, e)| !e.is_empty()).map(move |(v, _)| (o, v)))
            .collect();
        for s in &mut self.ctx.objects {
            s.exact = Vec::new();
        }
        self.settle()?;
        self.merge_again(&touched)
    }
}
