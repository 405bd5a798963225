//! Setting a frame up under its [`FrameSettings`] ([`Frame::open`]: every vertex merged once,
//! under those settings from the start) and changing them ([`Frame::reconfigure`]: only what
//! the changed settings touch, each vertex merged at most once).

use super::kept::KeptCut;
use super::keys::{Changed, FieldKey};
use super::lists::{self, ShadeList};
use super::merge::{FieldCache, Rekey};
use super::object::{MergeState, ObjectData, ViewCone};
use super::{Context, Frame, FrameError, FrameSettings, LightChoice, MoveTiming, SettingError, Tally};
use crate::brdf;
use glam::Vec3;
use vcut_data::Precomputed;
use vcut_dirtree::DirectionTree;
use vcut_envmap::EnvMap;
use vcut_lighttree::LightTreeBuilder;

impl Frame {
    /// Reads everything from `data`, builds the light tree of `env`, and merges every vertex
    /// once under `settings`. With `eye`, the setup builds the shading lists of the vertices
    /// facing it only and marks the others' stale (built when a shading or an eye needs them):
    /// the same images bit for bit (tested). The caches the settings turn off (or a memory
    /// budget leaves out) are never built, so the setup's peak memory holds none of them.
    pub fn open(
        data: &mut Precomputed,
        env: &EnvMap,
        settings: &FrameSettings,
        eye: Option<Vec3>,
    ) -> Result<Frame, FrameError> {
        settings.validate()?;
        let tree = data.tree()?;
        if tree.node_count() > lists::MAX_NODES {
            return Err(FrameError::TooManyNodes { nodes: tree.node_count(), max: lists::MAX_NODES });
        }
        let flat_leaves = flat_leaves(settings, &tree)?;
        let caches = settings.caches_at_start();
        let mut objects = Vec::with_capacity(data.objects.len());
        for o in 0..data.objects.len() {
            objects.push(object_data(data, o, caches.stored, tree.turn_shape())?);
        }
        let mut builder = LightTreeBuilder::new(&tree);
        let light = builder.build(env);
        let states = objects
            .iter()
            .map(|s| MergeState { pending: vec![false; s.mesh.vertex_count()], ..MergeState::default() })
            .collect();
        let ctx = Context {
            tree,
            objects,
            settings: settings.clone(),
            flat_leaves,
            caches: super::FrameCaches { svc: false, ..caches },
            recorded_light_error: data.view.as_ref().and_then(|v| v.light_error),
            builder,
            light,
            sun: None,
            choice: LightChoice::default(),
            occluders: Vec::new(),
            turned_occluders: Vec::new(),
            origin_offset: data.svc_origin_offset(),
            // Built by `light_state` below, with the sun's leaves out when they are cast.
            nodes: Vec::new(),
            specular: Vec::new(),
            eye,
        };
        let mut frame = Frame { ctx, states, tally: Tally::default(), drag: None };
        frame.ctx.set_svc_cache(caches.svc)?;
        // The sun and the shading table before the merges build the lists.
        frame.ctx.light_state(&frame.states, false);
        for (o, state) in frame.states.iter_mut().enumerate() {
            let n = frame.ctx.objects[o].mesh.vertex_count();
            state.keys = (0..n).map(|v| frame.ctx.keys(o, v)).collect::<Vec<Vec<FieldKey>>>();
            state.merged = vec![KeptCut::default(); if caches.merged { n } else { 0 }];
            state.lists = vec![ShadeList::default(); n];
            let MergeState { keys, lists, decoded, merged, .. } = state;
            let kept = caches.merged.then_some(&mut merged[..]);
            let count =
                frame.ctx.merge_all(o, keys, &vec![true; n], kept, lists, decoded, None, &mut MoveTiming::default())?;
            frame.tally.setup_merges += count as u64;
        }
        if let Some(budget) = settings.memory_budget {
            frame.fit_memory(budget)?;
        }
        Ok(frame)
    }

    /// Changes the settings, doing only what the changed ones touch: lookups (inside samples,
    /// horizon culling, field reach) or flat cuts re-merge the vertices whose inputs or cuts
    /// change, once; the merge algorithm prepares the kept SVCs again; caches are dropped or
    /// filled (filling the merged cuts merges every vertex once, together with any other
    /// change); turning deferral off merges what waits; the sun's settings (and, with the sun by
    /// rays, changed cuts) choose and cast its leaves again and rebuild the lists of the
    /// vertices not merged; a memory budget drops caches to fit. A drag under way settles
    /// first. Returns how many vertices were merged. On an error the frame keeps the settings
    /// it had.
    pub fn reconfigure(&mut self, settings: &FrameSettings) -> Result<usize, FrameError> {
        settings.validate()?;
        let flat = flat_leaves(settings, &self.ctx.tree)?;
        // Rest products are the old settings' products.
        self.settle()?;
        let old = std::mem::replace(&mut self.ctx.settings, settings.clone());
        let old_flat = std::mem::replace(&mut self.ctx.flat_leaves, flat);
        let result = self.apply(&old, old_flat);
        if result.is_err() {
            (self.ctx.settings, self.ctx.flat_leaves) = (old, old_flat);
        }
        result
    }

    /// [`Frame::reconfigure`] from `old` (and its flat leaves), the new settings in place.
    fn apply(&mut self, old: &FrameSettings, old_flat: u32) -> Result<usize, FrameError> {
        let new = self.ctx.settings.clone();
        if new.merge_algorithm != old.merge_algorithm {
            // The kept SVCs and cells are in the old merge's form.
            self.ctx.objects.iter_mut().for_each(|s| s.svc_refined = Vec::new());
            self.states.iter_mut().for_each(|s| s.decoded = FieldCache::default());
            let svc = self.ctx.caches.svc;
            self.ctx.set_svc_cache(svc)?;
        }
        // Under the same budget and asked caches, the caches the budget left stay as they are.
        let want = if (new.caches, new.memory_budget) == (old.caches, old.memory_budget) {
            self.ctx.caches
        } else {
            new.caches_at_start()
        };
        let fill = self.apply_caches(want)?;
        let lookups = (new.inside_samples, new.horizon_culling, new.field_reach)
            != (old.inside_samples, old.horizon_culling, old.field_reach);
        let flat = self.ctx.flat_leaves != old_flat;
        let undefer = old.deferred_merges && !new.deferred_merges && self.pending_merges() > 0;
        let recorded = self.ctx.recorded_light_error;
        // The sun's leaves are chosen by their error through the cuts: chosen again when the
        // sun's settings or the cuts change, as a frame set up under these settings chose them.
        let relight = new.sun(recorded) != old.sun(recorded) || (new.sun_rays && (lookups || flat));
        if relight {
            // Before the merges, so that they build their lists under the new light; the
            // choice merges its samples anew when the cuts change.
            self.ctx.light_state(&self.states, lookups || flat);
        }
        let mut merged = Vec::new();
        if lookups || flat || fill || undefer {
            let changed = Changed::Settings { keys: lookups, flat };
            // A flat cut changes the cut, not the keys a waiting vertex is compared by: those
            // it shadows merge now, whichever way they face.
            merged = self.rekey(Rekey { changed, eager: flat, all: fill, record: false, on_rest: false })?;
        }
        if relight {
            self.relist_all(Some(&merged));
        }
        if let Some(budget) = new.memory_budget {
            self.fit_memory(budget)?;
        }
        Ok(super::deferral::count(&merged))
    }
}

/// The settings' flat edge leaves for `tree`, refused above its directions.
fn flat_leaves(settings: &FrameSettings, tree: &DirectionTree) -> Result<u32, SettingError> {
    let leaves = settings.flat_edge_leaves.leaves(tree.leaf_count());
    if leaves as usize > tree.leaf_count() {
        return Err(SettingError {
            key: "flat_edge_leaves",
            value: leaves.to_string(),
            reason: format!("must be at most the number of directions, {}", tree.leaf_count()),
        });
    }
    Ok(leaves)
}

/// Object `o` of `data` as a frame reads it, at rest; its stored cuts left in the file unless
/// `stored` (one object's arrays at a time, so that the setup never holds the whole file);
/// `shape`, the file's turn shape.
fn object_data(
    data: &mut Precomputed,
    o: usize,
    stored: bool,
    shape: Option<vcut_cut::turn::TurnShape>,
) -> Result<ObjectData, FrameError> {
    let mut svc = data.svc_arrays(o)?;
    let mut field = data.field_arrays(o)?;
    if !stored {
        svc.iter_mut().chain(&mut field).for_each(|a| _ = a.evict());
    }
    let mut svc_starts = vec![0];
    for a in &svc {
        svc_starts.push(svc_starts.last().copied().unwrap_or(0) + a.len());
    }
    let s = &data.objects[o];
    let mut object = ObjectData {
        name: s.name.clone(),
        mesh: s.mesh.clone(),
        material: s.material,
        textures: s.textures.clone(),
        vertex_materials: Vec::new(),
        loaded_material: s.material,
        pow: brdf::PowTable::new(s.material.exponent),
        motion: s.motion,
        translation: Vec3::ZERO,
        turn: Default::default(),
        centre: data.layouts[o].map_or(s.mesh.bounds().center, |l| l.center),
        rest_mesh: None,
        shape,
        svc,
        svc_starts,
        layout: data.layouts[o],
        field,
        flat: vcut_scene::flat::FlatOutline::of(&s.mesh),
        ray_offset: vcut_rays::origin_offset(data.svc_origin_offset(), &s.mesh),
        svc_refined: Vec::new(),
        cones: ViewCone::of(&s.mesh),
        exact: Vec::new(),
    };
    object.vertex_materials = object.vertex_materials();
    Ok(object)
}
