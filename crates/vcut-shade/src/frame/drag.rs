//! Drags: while one object moves step after step, each vertex of the others that its field
//! reaches keeps the product of every other factor — its SVC and the other fields, its *rest
//! product*, prepared when the drag begins — and a step merges that product with the moved
//! field alone: two factors where a full merge multiplies every field that reaches the vertex
//! (Sun & Mukherjee 2006 multiply the fixed factors once the same way).
//!
//! The product's order is not the full merge's (rest × moved field, against SVC × fields in
//! object order), so a dragged cut may differ from the full one in its last bits.
//! [`Frame::settle`] merges the dragged vertices again in full; after it every cut is, bit for
//! bit, the one [`Frame::translate`] to the same place gives. A translation, a settings change
//! and a drag of another object settle first, so the rest products only ever stand for objects
//! that have not moved since they were prepared.
//!
//! Rest products are prepared for the vertices the moved field reaches when the drag begins
//! and a step would merge (with deferred merges, those facing the eye), within what
//! [`super::FrameSettings::memory_budget`] leaves beside the frame; any other vertex a step
//! changes merges in full.

use super::deferral::count;
use super::keys::{CellKey, FieldKey, Input, SampleId};
use super::merge::{FieldCache, MergeScratch, Rekey};
use super::{Context, Frame, FrameError, MoveTiming};
use glam::Vec3;
use rayon::prelude::*;
use std::collections::HashMap;
use std::ops::Range;
use std::time::Instant;
use vcut_merge::{MergedCut, Prepared};

/// Vertices whose rest products are prepared at once: a chunk's cells are refined together,
/// and the memory budget is checked between chunks.
const PREPARE_CHUNK: usize = 4096;

/// A drag under way: the object moved, and per object and vertex its rest product (`None`:
/// merged in full) and whether its kept cut came from a step on it.
pub(super) struct Drag {
    object: usize,
    rest: Vec<Vec<Option<Prepared>>>,
    /// Per object and vertex with a rest product: the leaf ranges where it is zero, and
    /// whether the moved object was hidden there (`Drag::hides`) where the vertex's cut has it.
    zeros: Vec<Vec<Vec<Range<u32>>>>,
    hidden: Vec<Vec<bool>>,
    /// Per field sample of the moved object: the leaf ranges where its visibility is below 1.
    shadows: HashMap<SampleId, Vec<Range<u32>>>,
    dragged: Vec<Vec<bool>>,
    /// Bytes of the rest products and their zero ranges.
    rest_bytes: usize,
    /// What the memory budget left beside the frame and the rest products when the drag began
    /// (`None`: no budget); the shadow ranges are kept within it, and a sample without them
    /// hides nothing.
    room: Option<usize>,
}

/// One object's rest products during a drag of object `object` (vertex-indexed).
#[derive(Clone, Copy)]
pub(super) struct RestOf<'a> {
    pub(super) object: u32,
    pub(super) products: &'a [Option<Prepared>],
}

impl Drag {
    /// Object `k`'s rest products.
    pub(super) fn rest_of(&self, k: usize) -> RestOf<'_> {
        RestOf { object: self.object as u32, products: &self.rest[k] }
    }

    /// Bytes the drag holds: the rest products with their zero ranges, and the shadow ranges
    /// of the samples its steps looked at.
    pub(super) fn bytes(&self) -> usize {
        self.rest_bytes + self.shadows.values().map(|runs| shadow_bytes(runs)).sum::<usize>()
    }

    /// Takes out of `merge` the vertices of object `k` (with new field inputs `keys`) from which
    /// the moved object is hidden where their cut has it and where it is now: their rest
    /// product is zero wherever any of its field samples there is below 1, so the product is
    /// the rest product times the lookup's weights' sum, now as before — their cut stays (a
    /// settle merges it at the new inputs). Returns how many were taken out.
    pub(super) fn skip_hidden(
        &mut self,
        ctx: &Context,
        k: usize,
        keys: &[Vec<FieldKey>],
        merge: &mut [bool],
    ) -> Result<usize, FrameError> {
        if self.rest[k].is_empty() {
            return Ok(0);
        }
        let m = self.object as u32;
        let candidates: Vec<usize> = (0..merge.len()).filter(|&v| merge[v] && self.rest[k][v].is_some()).collect();
        self.shadows_of(ctx, candidates.iter().flat_map(|&v| &keys[v]).filter(|key| key.object == m))?;
        let hides: Vec<bool> = candidates.par_iter().map(|&v| self.hides(&keys[v], &self.zeros[k][v])).collect();
        let mut skipped = 0;
        for (&v, now) in candidates.iter().zip(hides) {
            if now && self.hidden[k][v] {
                merge[v] = false;
                self.dragged[k][v] = true;
                skipped += 1;
            }
            self.hidden[k][v] = now;
        }
        Ok(skipped)
    }

    /// Whether the moved object's inputs among `keys` shadow nothing where `zeros` (a rest
    /// product's zero ranges) lets light through.
    fn hides(&self, keys: &[FieldKey], zeros: &[Range<u32>]) -> bool {
        let covered = |r: &Range<u32>| {
            let i = zeros.partition_point(|z| z.end <= r.start);
            zeros.get(i).is_some_and(|z| z.start <= r.start && r.end <= z.end)
        };
        keys.iter().filter(|key| key.object == self.object as u32).all(|key| match key.input {
            Input::Samples(samples) => samples.iter().filter(|x| x.weight > 0.0).all(|x| {
                let id = SampleId::of(key, x);
                self.shadows.get(&id).is_some_and(|runs| runs.iter().all(covered))
            }),
            _ => false,
        })
    }

    /// Finds the shadow ranges of the samples `keys` use that it has not yet.
    fn shadows_of<'k>(&mut self, ctx: &Context, keys: impl Iterator<Item = &'k FieldKey>) -> Result<(), FrameError> {
        let mut missing: Vec<SampleId> = keys
            .filter_map(|key| match key.input {
                Input::Samples(samples) => Some(samples.map(|x| SampleId::of(key, &x))),
                _ => None,
            })
            .flatten()
            .filter(|id| !self.shadows.contains_key(id))
            .collect();
        missing.sort_unstable();
        missing.dedup();
        let found: Vec<(SampleId, Vec<Range<u32>>)> = missing
            .into_par_iter()
            .map(|id| {
                let cut = ctx.sample_cut(id).map_err(|e| FrameError::cut(self.object, 0, e))?;
                Ok((id, below_one(&cut)))
            })
            .collect::<Result<_, FrameError>>()?;
        for (id, runs) in found {
            let b = shadow_bytes(&runs);
            if self.room.is_some_and(|r| b > r) {
                break;
            }
            self.room = self.room.map(|r| r - b);
            self.shadows.insert(id, runs);
        }
        Ok(())
    }
}

/// What one sample's shadow ranges hold in [`Drag::shadows`].
fn shadow_bytes(runs: &[Range<u32>]) -> usize {
    size_of::<(SampleId, Vec<Range<u32>>)>() + size_of_val(runs)
}

/// The leaf ranges where `cut` is below 1, joined.
fn below_one(cut: &vcut_cut::Cut) -> Vec<Range<u32>> {
    let mut runs: Vec<Range<u32>> = Vec::new();
    let mut start = 0u32;
    for (&h, &v) in cut.heights().iter().zip(cut.values()) {
        let end = start + (1u32 << h);
        if v < 1.0 {
            match runs.last_mut() {
                Some(last) if last.end == start => last.end = end,
                _ => runs.push(start..end),
            }
        }
        start = end;
    }
    runs.shrink_to_fit();
    runs
}

/// What the drags did ([`super::FrameStats::drag`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DragStats {
    /// The object being dragged, if one is.
    pub object: Option<usize>,
    /// Preparing the current (or last) drag's rest products (seconds).
    pub prepare_s: f64,
    /// Vertices given a rest product.
    pub prepared: usize,
    /// Vertices the moved field reached that were left to full merges: the memory budget had
    /// no room for their rest products.
    pub unprepared: usize,
    /// Bytes the drag holds: its rest products, and the shadow ranges of the moved object's
    /// samples its steps looked at (0 once settled).
    pub bytes: usize,
    /// The last settle's time (seconds).
    pub settle_s: f64,
    /// Vertices the last settle merged again in full.
    pub settled: usize,
}

impl Frame {
    /// Moves object `o` to `translation` as one step of a drag: the first step (or the first
    /// after another object's drag, which settles) prepares the rest products of the vertices
    /// its field reaches; every step re-merges the changed vertices, those with a rest product
    /// on it alone. Returns how many vertices were merged. Refused as [`Frame::translate`]
    /// refuses a translation, before anything changes. The cuts it leaves may differ from a
    /// full merge's in their last bits until [`Frame::settle`].
    pub fn drag(&mut self, o: usize, translation: Vec3) -> Result<usize, FrameError> {
        self.check_placement(o, translation)?;
        if self.drag.as_ref().is_none_or(|d| d.object != o) {
            self.settle()?;
            self.begin_drag(o)?;
        }
        self.ctx.objects[o].translation = translation;
        let merged = self.rekey(Rekey { on_rest: true, ..Rekey::moved(o) })?;
        if let Some(d) = self.drag.as_mut() {
            for (k, which) in merged.iter().enumerate() {
                for (v, _) in which.iter().enumerate().filter(|(v, m)| **m && d.rest[k][*v].is_some()) {
                    d.dragged[k][v] = true;
                }
            }
            self.tally.drag.bytes = d.bytes();
        }
        Ok(count(&merged))
    }

    /// The object being dragged ([`Frame::drag`]), if one is.
    pub fn dragging(&self) -> Option<usize> {
        self.drag.as_ref().map(|d| d.object)
    }

    /// Ends a drag: merges every vertex a drag step merged on its rest product again in full
    /// (at its kept field inputs) and drops the rest products. Every cut is then the full
    /// product, bit for bit. Returns how many vertices were merged (0 with no drag).
    pub fn settle(&mut self) -> Result<usize, FrameError> {
        let Some(drag) = self.drag.take() else { return Ok(0) };
        let start = Instant::now();
        let ctx = &self.ctx;
        let mut total = 0;
        for (k, state) in self.states.iter_mut().enumerate() {
            let which = &drag.dragged[k];
            if !which.contains(&true) {
                continue;
            }
            let super::object::MergeState { keys, lists, decoded, merged, pending, .. } = state;
            let kept = ctx.caches.merged.then_some(&mut merged[..]);
            match ctx.merge_all(k, keys, which, kept, lists, decoded, None, &mut MoveTiming::default()) {
                Ok(n) => total += n,
                Err(e) => {
                    // Some may hold a new cut, some a dragged one: any later move merges them.
                    for (v, _) in which.iter().enumerate().filter(|(_, d)| **d) {
                        keys[v] = vec![FieldKey::failed()];
                    }
                    return Err(e);
                }
            }
            // A waiting vertex keeps its cut for its kept inputs but no list.
            for (v, list) in lists.iter_mut().enumerate() {
                if pending[v] && which[v] {
                    list.mark_stale();
                }
            }
        }
        self.tally.merges += total as u64;
        self.tally.drag.settle_s = start.elapsed().as_secs_f64();
        self.tally.drag.settled = total;
        self.tally.drag.bytes = 0;
        Ok(total)
    }

    /// Prepares the rest products of a drag of object `m` and starts it.
    fn begin_drag(&mut self, m: usize) -> Result<(), FrameError> {
        let start = Instant::now();
        let ctx = &self.ctx;
        let budget = ctx.settings.memory_budget.map(|b| usize::try_from(b).unwrap_or(usize::MAX));
        let mut room = budget.map(|b| b.saturating_sub(self.memory().total()));
        let eye = ctx.eye.filter(|_| ctx.settings.deferred_merges);
        let (mut rest, mut dragged, mut zeros) = (Vec::new(), Vec::new(), Vec::new());
        let (mut prepared, mut unprepared, mut bytes) = (0, 0, 0);
        for (k, state) in self.states.iter_mut().enumerate() {
            let n = ctx.objects[k].mesh.vertex_count();
            dragged.push(vec![false; n]);
            let me = &ctx.objects[k];
            let reached: Vec<usize> = (0..n)
                .filter(|&v| {
                    k != m
                        && !state.pending[v]
                        && state.keys[v].iter().any(|key| key.object == m as u32 && !key.occludes_all())
                        && eye.is_none_or(|e| me.seen(v, e))
                })
                .collect();
            let mut products: Vec<Option<Prepared>> = (0..n).map(|_| None).collect();
            let mut zero_runs: Vec<Vec<Range<u32>>> = vec![Vec::new(); n];
            for chunk in reached.chunks(PREPARE_CHUNK) {
                if room == Some(0) {
                    unprepared += chunk.len();
                    continue;
                }
                for (v, p) in ctx.rest_products(k, &state.keys, chunk, m as u32, &mut state.decoded)? {
                    let mut zero = Vec::new();
                    p.zero_runs(&mut zero);
                    zero.shrink_to_fit();
                    let b = p.bytes() + zero.capacity() * size_of::<Range<u32>>();
                    if room.is_some_and(|r| b > r) {
                        room = Some(0);
                        unprepared += 1;
                        continue;
                    }
                    room = room.map(|r| r - b);
                    bytes += b;
                    prepared += 1;
                    zero_runs[v] = zero;
                    products[v] = Some(p);
                }
            }
            if !ctx.caches.cells {
                state.decoded = FieldCache::default();
            }
            rest.push(products);
            zeros.push(zero_runs);
        }
        let hidden = rest.iter().map(|r| vec![false; r.len()]).collect();
        let mut drag =
            Drag { object: m, rest, zeros, hidden, shadows: HashMap::new(), dragged, rest_bytes: bytes, room };
        // Where the object is hidden now: a step that finds it hidden too need not merge.
        for (k, state) in self.states.iter().enumerate() {
            let mut all: Vec<bool> = drag.rest[k].iter().map(Option::is_some).collect();
            drag.skip_hidden(ctx, k, &state.keys, &mut all)?;
        }
        self.tally.drag = super::DragStats {
            object: Some(m),
            prepare_s: start.elapsed().as_secs_f64(),
            prepared,
            unprepared,
            bytes: drag.bytes(),
            ..self.tally.drag
        };
        self.drag = Some(drag);
        Ok(())
    }
}

impl Context {
    /// The rest products of object `k`'s vertices `vertices` for a drag of object `m`: each
    /// merged from every field input of `keys` but m's, and prepared as one factor.
    fn rest_products(
        &self,
        k: usize,
        keys: &[Vec<FieldKey>],
        vertices: &[usize],
        m: u32,
        cache: &mut FieldCache,
    ) -> Result<Vec<(usize, Prepared)>, FrameError> {
        let others = |v: usize| keys[v].iter().filter(move |key| key.object != m);
        let first = vertices.first().copied().unwrap_or(0);
        let (cells, refined) =
            self.refine_cells(k, first, vertices.iter().flat_map(|&v| others(v)), cache, &mut MoveTiming::default())?;
        let algorithm = self.settings.merge_algorithm;
        let products = vertices
            .par_iter()
            .map_init(
                || (MergeScratch::default(), MergedCut::default()),
                |(scratch, out), &v| {
                    let cell = |c: &CellKey| {
                        &refined[cells.binary_search(c).unwrap_or_else(|_| unreachable!("collected above"))]
                    };
                    let inputs: Vec<FieldKey> = others(v).copied().collect();
                    self.merge_vertex(k, v, &inputs, &cell, scratch, out)?;
                    let cut = out.to_cut().unwrap_or_else(|e| unreachable!("a merge emits a valid cut: {e}"));
                    let product = algorithm.prepare(&[&cut]).map_err(|e| FrameError::cut(k, v, e))?;
                    Ok((v, product))
                },
            )
            .collect();
        cache.cells = cells;
        cache.refined = refined;
        products
    }
}
