//! Merges: a move looks up every vertex's field inputs again and re-merges those that changed
//! (`rekey`, deferring the ones facing away: see the module docs of [`super`]); each cell's cuts
//! are prepared once per move and kept for the next; one [`Context::merge_vertex`] serves a
//! move's batch and a merge on the spot, whichever [`super::MergeAlgorithm`] prepared its
//! inputs (the seam is `vcut_merge::prepared`).

use super::drag::RestOf;
use super::kept::KeptCut;
use super::keys::{CellKey, Changed, FieldKey, SampleId, take_held};
use super::lists::ShadeList;
use super::object::{MergeState, placed};
use super::{Context, CutFailure, Frame, FrameError, MoveTiming};
use glam::Vec3;
use rayon::prelude::*;
use std::borrow::Cow;
use std::time::Instant;
use vcut_cut::Cut;
use vcut_merge::{MergedCut, Prepared, merge_prepared};

/// What [`Context::merge_vertex`] builds per vertex and a thread reuses for the next: the SVC
/// decoded when it is not kept decoded, each flat occluder's prepared cut, the SVC's zero
/// ranges, and the buffers a flat cut is walked into.
#[derive(Default)]
pub(super) struct MergeScratch {
    svc: Prepared,
    flats: Vec<Prepared>,
    /// The vertex's exact field factors ([`super::refine`]), prepared.
    exact: Vec<Prepared>,
    zeros: Vec<std::ops::Range<u32>>,
    nodes: (Vec<u8>, Vec<f32>),
}

/// One field factor of a product: a lookup's cell with its weights, or the `n`th exact factor
/// prepared in [`MergeScratch`] ([`super::refine`]).
enum Field {
    Cell(CellKey, [f32; 8]),
    Exact(usize),
}

impl Context {
    /// The field factors of vertex `v` of object `o` with inputs `keys`, in their order: each
    /// input's exact factor where it has one standing where it was cast (prepared into
    /// `exact`), else its lookup; `None` when an input without one hides every direction.
    /// Inputs of object `skip` always take their lookup (a drag's moved object).
    fn fields(
        &self,
        o: usize,
        v: usize,
        keys: &[FieldKey],
        exact: &mut Vec<Prepared>,
    ) -> Result<Option<Vec<Field>>, vcut_merge::MergeError> {
        let mut fields = Vec::with_capacity(keys.len());
        let mut n = 0;
        for k in keys {
            match self.exact_factor(o, v, k) {
                Some(cut) => {
                    if exact.len() == n {
                        exact.push(Prepared::default());
                    }
                    self.settings.merge_algorithm.prepare_into(&[cut], &mut exact[n])?;
                    fields.push(Field::Exact(n));
                    n += 1;
                }
                None if k.occludes_all() => return Ok(None),
                None => fields.extend(CellKey::of(k).map(|(c, w)| Field::Cell(c, w))),
            }
        }
        Ok(Some(fields))
    }
}

/// What the last merge of an object's vertices built, for the next move (a move along a path
/// needs mostly the same cells and samples again): the cells prepared for the merge (refined
/// for the counter merge), sorted by cell, and
/// the field cuts it decoded, by sample, sorted.
#[derive(Default)]
pub(super) struct FieldCache {
    pub(super) keys: Vec<SampleId>,
    pub(super) cuts: Vec<Cut>,
    pub(super) cells: Vec<CellKey>,
    pub(super) refined: Vec<Prepared>,
}

/// Merged vertices a range of [`Context::merge_all`] holds at most without the cell cache: the
/// cells decoded and refined at once for a range are what a lean frame's peak holds, and ranges
/// much smaller decode the cells two ranges share twice (`docs/benchmarks.md`, "The frame's
/// design, measured").
const MERGE_BATCH: usize = 1024;

/// Field inputs (lookups) a range of [`Context::merge_all`] holds at most without the cell cache:
/// a vertex that many fields reach (a ground among many objects) brings as many cells, so a
/// range ends at this many inputs too.
const MERGE_BATCH_INPUTS: usize = 1024;

/// The merged cut of a vertex inside an object (a cut of one zero node).
pub(super) fn full_zero(h: u32) -> MergedCut {
    MergedCut { root_height: h, heights: vec![h as u8], values: vec![0.0], indices: vec![0] }
}

impl Frame {
    /// Moves object `o` to `translation` (from its rest position) and re-merges the vertices
    /// whose field inputs changed: its own, and other objects' vertices near it. Returns how
    /// many vertices were merged. A translation its mesh cannot take in f32 (non-finite, or so
    /// far out that f32 no longer keeps its shape) is refused before anything changes
    /// ([`FrameError::Placement`]). A drag under way settles first ([`Frame::settle`]): every
    /// cut is then the full product.
    pub fn translate(&mut self, o: usize, translation: Vec3) -> Result<usize, FrameError> {
        self.check_placement(o, translation)?;
        self.settle()?;
        self.ctx.objects[o].translation = translation;
        Ok(super::deferral::count(&self.rekey(Rekey::moved(o))?))
    }

    /// Refuses a translation object `o`'s mesh cannot take in f32 ([`FrameError::Placement`]).
    pub(super) fn check_placement(&self, o: usize, translation: Vec3) -> Result<(), FrameError> {
        let object = &self.ctx.objects[o];
        object.mesh.placed(translation).map_err(|error| FrameError::Placement {
            object: o,
            name: object.name.clone(),
            translation: translation.to_array(),
            error,
        })
    }
}

impl Context {
    /// The stored field cut of sample `s`, decoded and turned by its steps.
    pub(super) fn sample_cut(&self, s: SampleId) -> Result<Cut, CutFailure> {
        let object = &self.objects[s.object as usize];
        super::object::turned(object.field[s.sphere as usize].cut(s.point as usize)?, object.shape, s.steps)
    }

    /// Decodes the field cuts of `wanted` (sorted samples), taking those `old` holds (sorted
    /// too) from it.
    fn decode_samples(
        &self,
        o: usize,
        vertex: usize,
        wanted: &[SampleId],
        old_keys: Vec<SampleId>,
        old_cuts: Vec<Cut>,
    ) -> Result<Vec<Cut>, FrameError> {
        let reused = take_held(old_keys, old_cuts, wanted);
        wanted
            .par_iter()
            .zip(reused.into_par_iter())
            .map(|(&s, hit)| match hit {
                Some(c) => Ok(c),
                None => self.sample_cut(s),
            })
            .collect::<Result<_, _>>()
            .map_err(|e| FrameError::cut(o, vertex, e))
    }

    /// Merges the vertices of object `o` marked in `changed` with their keys into `merged`
    /// (`None` with the merged cache off: each cut lives until its list is built) and builds
    /// their shading `lists` (in place, reusing each buffer), in parallel. Returns how many
    /// were merged. Without the cell cache ([`super::FrameCaches::cells`]) it goes in ranges of
    /// at most [`MERGE_BATCH`] merged vertices and [`MERGE_BATCH_INPUTS`] field inputs, so that
    /// the cells decoded and refined at once stay few (a range reuses those it shares with the
    /// one before, and none is kept after). A vertex `rest` holds a product for is merged on it
    /// ([`Context::merge_on_rest`]; a drag's step), every other one in full.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn merge_all(
        &self,
        o: usize,
        keys: &[Vec<FieldKey>],
        changed: &[bool],
        mut merged: Option<&mut [KeptCut]>,
        lists: &mut [ShadeList],
        cache: &mut FieldCache,
        rest: Option<RestOf<'_>>,
        timing: &mut MoveTiming,
    ) -> Result<usize, FrameError> {
        let (n, batch) = (changed.len(), if self.caches.cells { usize::MAX } else { MERGE_BATCH });
        let inputs_max = if self.caches.cells { usize::MAX } else { MERGE_BATCH_INPUTS };
        let (mut total, mut start) = (0, 0);
        while start < n {
            let (mut end, mut count, mut inputs) = (start, 0, 0);
            while end < n && count < batch && inputs < inputs_max {
                if changed[end] {
                    count += 1;
                    inputs += keys[end].len();
                }
                end += 1;
            }
            let range = start..end;
            let slots = merged.as_deref_mut().map(|m| &mut m[range.clone()]);
            total += self.merge_range(
                o,
                start,
                &keys[range.clone()],
                &changed[range.clone()],
                slots,
                &mut lists[range],
                cache,
                rest,
                timing,
            )?;
            start = end;
        }
        if !self.caches.cells {
            *cache = FieldCache::default();
        }
        Ok(total)
    }

    /// [`Context::merge_all`] over the vertices `offset..offset + changed.len()` (every slice
    /// starts at vertex `offset`); leaves in `cache` the cells and samples it used.
    #[allow(clippy::too_many_arguments)]
    fn merge_range(
        &self,
        o: usize,
        offset: usize,
        keys: &[Vec<FieldKey>],
        changed: &[bool],
        merged: Option<&mut [KeptCut]>,
        lists: &mut [ShadeList],
        cache: &mut FieldCache,
        rest: Option<RestOf<'_>>,
        timing: &mut MoveTiming,
    ) -> Result<usize, FrameError> {
        let vertices: Vec<usize> = (0..changed.len()).filter(|&v| changed[v]).collect();
        let on_rest = |v: usize| rest.and_then(|r| r.products.get(offset + v)?.as_ref().map(|p| (r.object, p)));
        // A vertex merged on its rest product uses the moved object's inputs only.
        let used = |v: usize| keys[v].iter().filter(move |k| on_rest(v).is_none_or(|(m, _)| k.object == m));
        timing.fields += vertices.iter().map(|&v| used(v).count()).sum::<usize>();
        timing.on_rest += vertices.iter().filter(|&&v| on_rest(v).is_some()).count();
        let first = offset + vertices.first().copied().unwrap_or(0);
        let me = &self.objects[o];
        let normals = &me.mesh.normals()[offset..];
        let eye = self.eye;
        let facing = |v: usize| eye.is_none_or(|e| me.seen(offset + v, e));
        let table = &self.nodes;
        let (cells, refined) = self.refine_cells(o, first, vertices.iter().flat_map(|&v| used(v)), cache, timing)?;
        let start = Instant::now();
        let nodes = std::sync::atomic::AtomicUsize::new(0);
        let slots: Vec<Option<&mut KeptCut>> = match merged {
            Some(m) => m.iter_mut().map(Some).collect(),
            None => (0..changed.len()).map(|_| None).collect(),
        };
        let result =
            slots.into_par_iter().zip(lists.par_iter_mut()).enumerate().filter(|(v, _)| changed[*v]).try_for_each_init(
                || (MergeScratch::default(), Vec::new(), MergedCut::default()),
                |(scratch, below, spare), (v, (slot, list))| {
                    let cell = |c: &CellKey| {
                        &refined[cells.binary_search(c).unwrap_or_else(|_| unreachable!("collected above"))]
                    };
                    let svc = match on_rest(v) {
                        Some((m, product)) => {
                            self.merge_on_rest(o, offset + v, &keys[v], m, product, &cell, scratch, spare)?
                        }
                        None => self.merge_vertex(o, offset + v, &keys[v], &cell, scratch, spare)?,
                    };
                    nodes.fetch_add(spare.heights.len(), std::sync::atomic::Ordering::Relaxed);
                    // The list while the cut is still in cache.
                    match svc {
                        None => list.clear(),
                        Some(_) if !facing(v) => list.mark_stale(),
                        Some(ends) => list.rebuild((&*spare).into(), normals[v], table, Some(&ends), below),
                    }
                    if let Some(slot) = slot {
                        slot.keep(spare);
                    }
                    Ok(())
                },
            );
        timing.merge_s += start.elapsed().as_secs_f64();
        timing.nodes += nodes.into_inner();
        cache.cells = cells;
        cache.refined = refined;
        result.map(|()| vertices.len())
    }

    /// The field cells of the inputs `used` (object `o`'s, from vertex `first` on), each
    /// prepared once (refined for the counter merge), sorted by cell, with their prepared
    /// groups beside them. Cells and decoded samples `cache` holds are taken from it; it is
    /// left holding the samples decoded (the caller puts the cells back).
    pub(super) fn refine_cells<'k>(
        &self,
        o: usize,
        first: usize,
        used: impl Iterator<Item = &'k FieldKey>,
        cache: &mut FieldCache,
        timing: &mut MoveTiming,
    ) -> Result<(Vec<CellKey>, Vec<Prepared>), FrameError> {
        let old = std::mem::take(cache);
        let start = Instant::now();
        // The cells the vertices use; those the last move prepared are kept.
        let mut cells: Vec<CellKey> = used.filter_map(|k| CellKey::of(k).map(|c| c.0)).collect();
        cells.sort_unstable();
        cells.dedup();
        let reused = take_held(old.cells, old.refined, &cells);
        // The new cells' samples, each decoded once.
        let mut wanted: Vec<SampleId> = cells
            .iter()
            .zip(&reused)
            .filter(|(_, r)| r.is_none())
            .flat_map(|(c, _)| c.samples().iter().copied())
            .collect();
        wanted.sort_unstable();
        wanted.dedup();
        timing.refine_s += start.elapsed().as_secs_f64();
        let start = Instant::now();
        let decoded = self.decode_samples(o, first, &wanted, old.keys, old.cuts)?;
        timing.decode_s += start.elapsed().as_secs_f64();
        let start = Instant::now();
        let algorithm = self.settings.merge_algorithm;
        let refined: Vec<Prepared> = cells
            .par_iter()
            .zip(reused.into_par_iter())
            .map(|(c, hit)| match hit {
                Some(r) => Ok(r),
                None => {
                    let cuts: Vec<&Cut> = c
                        .samples()
                        .iter()
                        .map(|x| &decoded[wanted.binary_search(x).unwrap_or_else(|_| unreachable!("collected above"))])
                        .collect();
                    algorithm.prepare(&cuts)
                }
            })
            .collect::<Result<_, _>>()
            .map_err(|e| FrameError::cut(o, first, e))?;
        timing.refine_s += start.elapsed().as_secs_f64();
        *cache = FieldCache { keys: wanted, cuts: decoded, cells: Vec::new(), refined: Vec::new() };
        Ok((cells, refined))
    }

    /// The one merge of vertex `v` of object `o` with field inputs `keys` (the counter merge
    /// through refinements, for a move's batch and for a merge on the spot alike): a cut of
    /// one zero node when a field's samples are all inside its object, else the vertex's SVC
    /// (kept decoded, or decoded into `scratch`) times each field cell's refinement (`cell`
    /// gives it) and each flat occluder's exact cut (prepared in `scratch`) into `out`.
    /// Returns the SVC's node ends (for its shading list), `None` for the occluded vertex.
    pub(super) fn merge_vertex<'r>(
        &'r self,
        o: usize,
        v: usize,
        keys: &[FieldKey],
        cell: &dyn Fn(&CellKey) -> &'r Prepared,
        scratch: &'r mut MergeScratch,
        out: &mut MergedCut,
    ) -> Result<Option<Cow<'r, [u32]>>, FrameError> {
        let err = |e: CutFailure| FrameError::cut(o, v, e);
        let MergeScratch { svc: decoded, flats, exact, zeros, nodes } = scratch;
        let Some(fields) = self.fields(o, v, keys, exact).map_err(|e| err(e.into()))? else {
            *out = full_zero(self.tree.height());
            return Ok(None);
        };
        let me = &self.objects[o];
        let svc = match me.svc_refined.get(v) {
            Some(cached) => cached,
            None => {
                me.prepare_svc(v, self.settings.merge_algorithm, decoded).map_err(err)?;
                &*decoded
            }
        };
        let planes: Vec<(usize, Vec3)> = keys.iter().filter_map(|k| Some((k.object as usize, k.flat()?))).collect();
        // An SVC times one flat occluder and nothing else (an object on a ground): one walk
        // of the tree, the ground classified only where the SVC lets light through.
        if let ([], [(j, at)], Prepared::Refined(r)) = (&fields[..], &planes[..], svc)
            && r.members() == 1
        {
            let outline =
                self.objects[*j].flat.as_ref().unwrap_or_else(|| unreachable!("a flat key is a flat object's"));
            crate::flat::flat_product(&self.tree, outline.corners(), *at, self.flat_leaves, r, out)
                .map_err(|e| err(e.into()))?;
            return Ok(Some(svc.ends()));
        }
        // Where the SVC is zero (below the horizon, where the object hides itself) the product
        // is zero whatever a flat occluder hides: its cut is not walked there.
        self.prepare_flats(&planes, svc, flats, zeros, nodes).map_err(|e| err(e.into()))?;
        let weights = me.turn.svc_weights();
        product((svc, weights.as_slice()), &fields, exact, &flats[..planes.len()], cell, out)
            .map_err(|e| err(e.into()))?;
        Ok(Some(svc.ends()))
    }

    /// Prepares into `flats` the exact cut of each flat occluder `(object, ray origin)` of
    /// `planes`, walked only where `first` (a factor of the same product) is not zero.
    fn prepare_flats(
        &self,
        planes: &[(usize, Vec3)],
        first: &Prepared,
        flats: &mut Vec<Prepared>,
        zeros: &mut Vec<std::ops::Range<u32>>,
        nodes: &mut (Vec<u8>, Vec<f32>),
    ) -> Result<(), vcut_merge::MergeError> {
        flats.resize_with(planes.len(), Prepared::default);
        zeros.clear();
        if !planes.is_empty() {
            first.zero_runs(zeros);
        }
        for (&(j, at), prepared) in planes.iter().zip(flats.iter_mut()) {
            let cut = self
                .flat_cut_at_rest(j, at, zeros, std::mem::take(nodes))
                .unwrap_or_else(|| unreachable!("a flat key is a flat object's"));
            self.settings.merge_algorithm.prepare_into(&[&cut], prepared)?;
            *nodes = cut.into_parts();
        }
        Ok(())
    }

    /// Vertex `v` of object `o` merged on its rest product `rest` (every factor but moved
    /// object `m`'s, prepared when the drag began): `rest` times m's inputs among `keys`, two
    /// factors where a full merge multiplies every field. The cut equals the full merge's up to
    /// the rounding of the product's order (a settle merges it again in full). Returns the
    /// SVC's node ends, `None` for the occluded vertex, as [`Context::merge_vertex`] does.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn merge_on_rest<'r>(
        &'r self,
        o: usize,
        v: usize,
        keys: &[FieldKey],
        m: u32,
        rest: &'r Prepared,
        cell: &dyn Fn(&CellKey) -> &'r Prepared,
        scratch: &'r mut MergeScratch,
        out: &mut MergedCut,
    ) -> Result<Option<Cow<'r, [u32]>>, FrameError> {
        let err = |e: CutFailure| FrameError::cut(o, v, e);
        let MergeScratch { flats, exact, zeros, nodes, .. } = scratch;
        // Every input decides whether the vertex is occluded, as in the full merge; the moved
        // object's by its lookup (its exact factor stands where it was cast, not where it
        // moves), so its lookups are its factors here.
        if keys.iter().any(|k| k.occludes_all() && (k.object == m || self.exact_factor(o, v, k).is_none())) {
            *out = full_zero(self.tree.height());
            return Ok(None);
        }
        let mine = || keys.iter().filter(|k| k.object == m);
        let lookups: Vec<Field> = mine().filter_map(CellKey::of).map(|(c, w)| Field::Cell(c, w)).collect();
        let planes: Vec<(usize, Vec3)> = mine().filter_map(|k| Some((m as usize, k.flat()?))).collect();
        self.prepare_flats(&planes, rest, flats, zeros, nodes).map_err(|e| err(e.into()))?;
        product((rest, &[1.0]), &lookups, exact, &flats[..planes.len()], cell, out).map_err(|e| err(e.into()))?;
        Ok(self.objects[o].svc_ends(v))
    }

    /// Vertex `v`'s cut with field inputs `keys`, merged on the spot and not kept (a vertex
    /// whose merge waits, at its current inputs; with the merged cache off, any vertex at its
    /// kept ones): [`Context::merge_vertex`] with its cells refined here, so the cut a merge
    /// would keep, bit for bit.
    pub(super) fn merge_one(
        &self,
        o: usize,
        v: usize,
        keys: &[FieldKey],
        out: &mut MergedCut,
    ) -> Result<(), FrameError> {
        let err = |e: CutFailure| FrameError::cut(o, v, e);
        let mut local: Vec<(CellKey, Prepared)> = Vec::new();
        for (cell, _) in keys.iter().filter_map(CellKey::of) {
            let cuts =
                cell.samples().iter().map(|&s| self.sample_cut(s)).collect::<Result<Vec<Cut>, _>>().map_err(err)?;
            local.push((
                cell,
                self.settings.merge_algorithm.prepare(&cuts.iter().collect::<Vec<_>>()).map_err(|e| err(e.into()))?,
            ));
        }
        let cell = |c: &CellKey| &local.iter().find(|(k, _)| k == c).unwrap_or_else(|| unreachable!("refined above")).1;
        self.merge_vertex(o, v, keys, &cell, &mut MergeScratch::default(), out)?;
        Ok(())
    }

    /// Builds the shading lists of object `o`'s vertices marked in `which` (none waiting for
    /// a merge) for the current light, from their kept merged cuts — or, without the merged
    /// cache, by merging them again at their kept field inputs in one batch (the cuts they had,
    /// bit for bit). Those facing away from the eye are marked stale instead. Returns how many
    /// vertices were merged again.
    pub(super) fn relist(&self, o: usize, state: &mut MergeState, which: &[bool]) -> Result<usize, FrameError> {
        let eye = self.eye;
        if self.caches.merged {
            let (me, nodes, merged) = (&self.objects[o], &self.nodes, &state.merged);
            state.lists.par_iter_mut().enumerate().filter(|(v, _)| which[*v]).for_each_init(
                Vec::new,
                |below, (v, list)| {
                    if eye.is_none_or(|e| me.seen(v, e)) {
                        me.relist(v, &merged[v], nodes, list, below);
                    } else {
                        list.mark_stale();
                    }
                },
            );
            return Ok(0);
        }
        let MergeState { keys, lists, decoded, .. } = state;
        let result = self.merge_all(o, keys, which, None, lists, decoded, None, &mut MoveTiming::default());
        if result.is_err() {
            // Built on the spot by a shading instead (which shades black what fails there).
            for (list, _) in lists.iter_mut().zip(which).filter(|(_, w)| **w) {
                list.mark_stale();
            }
        }
        result
    }
}

/// Merges into `out` the product `first` (an SVC, with its members' weights, or a rest
/// product) × each field factor (a lookup's cell, `cell` gives it, weighted by the lookup's
/// weights, or an exact factor of `exact`) × each of `flats`, in that order (the order a
/// merged cut's rounding follows).
fn product<'a, 'r: 'a>(
    first: (&'a Prepared, &'a [f32]),
    fields: &'a [Field],
    exact: &'a [Prepared],
    flats: &'a [Prepared],
    cell: &dyn Fn(&CellKey) -> &'r Prepared,
    out: &mut MergedCut,
) -> Result<usize, vcut_merge::MergeError> {
    let mut factors: Vec<(&'a Prepared, &'a [f32])> = Vec::with_capacity(1 + fields.len() + flats.len());
    factors.push(first);
    for field in fields {
        factors.push(match field {
            Field::Cell(c, weights) => (cell(c), &weights[..usize::from(c.len)]),
            Field::Exact(n) => (&exact[*n], &[1.0][..]),
        });
    }
    factors.extend(flats.iter().map(|p| (p, &[1.0][..])));
    merge_prepared(&factors, out)
}

/// What [`Frame::rekey`] merges.
#[derive(Debug, Clone, Copy)]
pub(super) struct Rekey {
    /// What may have changed since the kept field inputs were looked up.
    pub(super) changed: Changed,
    /// Merge every changed vertex now, whichever way it faces (else, with deferred merges,
    /// those facing the eye; the others wait).
    pub(super) eager: bool,
    /// Merge every vertex, changed or not (to fill the merged cache): implies `eager`.
    pub(super) all: bool,
    /// Keep the timing as the last move's.
    pub(super) record: bool,
    /// Merge the vertices a drag prepared on their rest products ([`super::drag`]).
    pub(super) on_rest: bool,
}

impl Rekey {
    /// A move of object `o`.
    pub(super) fn moved(o: usize) -> Rekey {
        Rekey { changed: Changed::Object(o), eager: false, all: false, record: true, on_rest: false }
    }

    /// The waiting vertices (those an eye sees, or all when `eager`).
    pub(super) fn waiting(eager: bool) -> Rekey {
        Rekey { changed: Changed::Nothing, eager, all: false, record: false, on_rest: false }
    }
}

impl Frame {
    /// Looks up the vertices' field inputs again and re-merges those that changed (with
    /// deferred merges and not `eager`, those facing the eye; the others wait), or every vertex
    /// (`all`). Returns per object which vertices it merged.
    pub(super) fn rekey(&mut self, how: Rekey) -> Result<Vec<Vec<bool>>, FrameError> {
        let mut total = 0;
        let mut timing = MoveTiming::default();
        let ctx = &self.ctx;
        let eye = ctx.eye.filter(|_| ctx.settings.deferred_merges && !how.eager && !how.all);
        let mut done = Vec::with_capacity(self.states.len());
        let mut failure = None;
        for (k, state) in self.states.iter_mut().enumerate() {
            let n = ctx.objects[k].mesh.vertex_count();
            let start = Instant::now();
            let fresh: Vec<Option<Vec<FieldKey>>> =
                (0..n).into_par_iter().map(|v| ctx.changed_keys(k, v, state, how.changed)).collect();
            let me = &ctx.objects[k];
            let mut merge: Vec<bool> =
                (0..n).map(|v| how.all || (fresh[v].is_some() && eye.is_none_or(|e| me.seen(v, e)))).collect();
            let steps = me.turn.svc_stamp();
            timing.keys_s += start.elapsed().as_secs_f64();
            // A waiting vertex keeps the keys of its merged cut (the next move compares with
            // them) and no list; one whose inputs are back to its cut's waits no more.
            for (v, new) in fresh.into_iter().enumerate() {
                state.pending[v] = new.is_some() && !merge[v];
                if state.pending[v] {
                    state.lists[v].mark_stale();
                    timing.deferred += 1;
                } else if let Some(new) = new {
                    state.keys[v] = new;
                    state.set_svc_turn(v, steps);
                }
            }
            if let Some(drag) = self.drag.as_mut().filter(|_| how.on_rest) {
                match drag.skip_hidden(ctx, k, &state.keys, &mut merge) {
                    Ok(skipped) => timing.hidden += skipped,
                    Err(e) => {
                        failure = Some(e);
                        break;
                    }
                }
            }
            if !merge.contains(&true) {
                // Nothing to merge: the object keeps its cells for a later move.
                done.push(merge);
                continue;
            }
            if ctx.caches.merged && state.merged.len() != n {
                state.merged = vec![KeptCut::default(); n];
            }
            let MergeState { keys, lists, decoded, merged, .. } = state;
            let kept = ctx.caches.merged.then_some(&mut merged[..]);
            let rest = self.drag.as_ref().filter(|_| how.on_rest).map(|d| d.rest_of(k));
            match ctx.merge_all(k, keys, &merge, kept, lists, decoded, rest, &mut timing) {
                Ok(count) => total += count,
                Err(e) => {
                    // Some changed vertices may hold new cuts: key them as failed so that any
                    // later move merges them again.
                    for (v, m) in merge.iter().enumerate() {
                        if *m {
                            keys[v] = vec![FieldKey::failed()];
                        }
                    }
                    failure = Some(e);
                    break;
                }
            }
            done.push(merge);
        }
        if let Some(sun) = self.ctx.sun.as_mut() {
            let start = Instant::now();
            timing.sun_rays = sun.update(&placed(&self.ctx.objects), &self.ctx.occluders);
            timing.sun_s = start.elapsed().as_secs_f64();
        }
        self.tally.merges += total as u64;
        timing.vertices = total;
        if how.record {
            self.tally.last_move = timing;
        }
        match failure {
            Some(e) => Err(e),
            None => Ok(done),
        }
    }
}
