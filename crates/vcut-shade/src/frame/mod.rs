//! The frame loop of the paper, with caching: per vertex the SVC times the fields of the
//! objects that can move relative to it, interpolated from 8 samples each, merged once and kept;
//! a move re-merges only the vertices whose field inputs changed (those facing away from the
//! camera when it sees them: deferred merges, below); BRDF and lighting edits only re-shade,
//! and so do camera edits with nothing waiting.
//!
//! **Which fields a vertex uses.** Object j's field shadows a vertex of object o (o ≠ j) when
//! j has a field and o or j is movable (static–static shadows are baked into the SVCs), unless
//! j's bounding sphere lies wholly below the vertex's horizon ([`Frame::set_horizon_culling`],
//! on by default): then j hides none of the light the cut weighs by max(0, n·ω), and its field's
//! sum over a node straddling the horizon would only darken the node's upper part. On the
//! teapot scene at `balanced` this leaves 1.59 instead of 1.98 fields per re-merged vertex, a
//! move 0.76× the time, and the error against the exact reference unchanged (0.337 %); on
//! `builtin:showroom:32` at `fast` 7.7 instead of 11.6 fields and 0.68× the move
//! (`vcuts render FILE --move NAME=DX,DY,DZ --eager-merges --compare exact`, with and without
//! `--no-horizon-culling`). Within
//! 0.2r of j's centre (0.05r–0.2r for a flat j: its layout's `inner`) the lookup clamps to the
//! innermost sphere; beyond 6r j casts no shadow ([`Frame::set_field_reach`]; the paper
//! stops at the outermost sphere, 10r, where j's bounding cone covers under 0.25 % of the
//! sphere). Cut at 6r, a field leaves out at most the sky j hides beyond — the sun's shadows
//! are cast by rays — and the error against the exact reference did not grow: on
//! `builtin:showroom:32` at `fast` (moving `torus-14` by (0.3, 0, 0.2), eager) 6.0 instead of
//! 11.9 fields per re-merged vertex, 3,427 instead of 9,057 vertices re-merged, the move 0.28×
//! the time, vertex error 5.75 % instead of 5.89 %; `showroom:8` 4.19 % instead of 4.23 %;
//! the teapot scene at `balanced` 0.350 % against 0.349 %, the bunny at `fast` 1.221 % both
//! (`vcuts render FILE --move NAME=0.3,0,0.2 --eager-merges --compare exact [--field-reach
//! 10]`). At 4r the showroom's error falls further (5.59 %, 3.0 fields, a quarter of 6r's move
//! time) but the teapot's rises to 0.373 %. Samples inside j blend in as
//! fully occluded (or are dropped and the rest renormalised: [`Frame::set_inside_samples`],
//! [`InsideSamples`] says why and by how much), and a vertex whose 8 samples are all inside j is
//! fully occluded.
//!
//! **Where in a node the light is.** A merged node k holds v_k, the mean of V·max(0, n·ω) over
//! its leaves, and the light tree the node's total radiance l_k. The paper evaluates
//! `v_k f_r(ω_k, ω_o) l_k` at the node's mean direction ω_k, which is exact only if the light
//! is spread evenly over the node: a sun covering one leaf of a 13° node gets the node's mean
//! cosine and the BRDF 6° off. Here every node also knows the light-weighted mean of its leaf
//! directions E_k = Σ ω_l y_l / Σ y_l (y the luminance) and the plain mean m_k = Σ ω_l / n_k;
//! for a node wholly above the horizon, Σ_l max(0, n·ω_l) L_l = (n·E_k) l_k exactly, so with the
//! node's visibility taken as constant (α = v_k / (n·m_k)) the estimate is
//! `α (n·E_k) f_r(Ê_k, ω_o) l_k`: exact for any light within a fully visible node. Nodes that
//! cross the horizon keep `v_k f_r(Ê_k, ω_o) l_k`. On the teapot scene under the sky (with exact
//! fields, so clustering is the only error) this took the error against the exact reference
//! from 3.1 % to 1.05 % (`cargo run --release -p vcut-benches --example error_sources`).
//!
//! **The SVC's share of a finer node.** A merged node k finer than the SVC node A around it
//! (a field splits A) gets the product's value v_A·F_k, with v_A A's mean of V·max(0, n·ω): A's
//! mean cosine, not k's. Where A lies wholly above the horizon the list takes k's visibility as
//! `v_k / (n·m_A)` instead of `v_k / (n·m_k)` — A's visibility fraction, times the fields — so
//! k's own cosine enters through n·E_k. The merged cuts stay the paper's product (bit for bit
//! with the counter merge); only the list reads the SVC's node ends. On the teapot scene at the
//! paper preset (the bench's frame) this took the error against the exact reference from
//! 2.09 % to 1.77 %, the ground's from 4.4 % to 3.7 %, and with exact field cuts at the
//! vertices from 1.12 % to 0.71 % (`error_sources --scene builtin:teapot`); moves cost ~4 %
//! more (the list walks the SVC's ends beside the cut).
//!
//! **The sun by rays** (the default; [`Frame::set_sun_rays`], [`crate::sun`]). The few leaves
//! of the light that hold a sun leave the cuts' light; each vertex adds their term with the
//! visibility cast at run time against the objects at their translations (a move casts only
//! the object pairs whose offset changed). The sun's shadow edges are then exact instead of
//! blurred between field samples: at the paper preset the teapot scene's error against the
//! exact reference fell from 1.77 % to 0.25 % and the bunny's from 0.92 % to 0.18 %, for
//! ~1 ms of rays a move (`cargo xtask bench`, `rel_l2_exact` against `rel_l2_exact_cuts_only`).
//! The merged cuts are the same either way.
//!
//! **Shading lists.** After a merge (and after a lighting change) each vertex keeps the nodes
//! that can reflect light toward a viewer — value non-zero, Ê_k above the horizon — with the
//! weight `α (n·E_k)` (or v_k) folded in, and the diffuse sum Σ weight·l_k. A BRDF or camera
//! edit then evaluates only the specular lobe over that list and adds `k_d/π` times the sum.
//!
//! A vertex facing away from the camera reflects nothing toward it, so a merge (or a lighting
//! change) builds the lists of the vertices facing the last eye shaded from ([`Frame::shade`]
//! records it; [`Frame::set_eye`] sets it) and marks the others' stale. Shading builds a stale
//! list it needs on the spot, without keeping it; [`Frame::set_eye`] builds and keeps those of
//! the vertices facing a new eye. A move then spends nothing on the back-facing half of an
//! object's lists (the teapot scene's moves 0.89×, the bunny's 0.80× by `move_path`), and a
//! camera turn after it pays for their lists once.
//!
//! **Deferred merges** (the default; [`Frame::set_deferred_merges`]). For the same reason a
//! move merges only the changed vertices facing the last eye; the others keep their old cut and
//! field inputs and wait ([`Frame::pending_merges`]). The next move compares with those inputs
//! (back where it was, a vertex waits no more), [`Frame::set_eye`] merges and keeps the waiting
//! vertices facing the new eye, [`Frame::shade`] merges those it needs on the spot without
//! keeping them, and [`Frame::merge_pending`] merges all. Images are bit for bit the eager
//! frame's (tested); a move on the teapot scene merges ~6,600 of its 11,564 changed vertices
//! and takes ~0.75× the eager time, and the camera turn after it merges what it now sees
//! (`cargo xtask bench`: `move_ms_eager`, `turn_ms`, `turn_ms_eager`). With deferral off a
//! camera change never merges (with the merged cache on: below).
//!
//! **What a frame keeps** ([`Frame::memory`] by part). Per vertex its shading list, its field
//! inputs (keys) and — as caches, each a trade of memory for time ([`FrameCaches`]) — its SVC
//! decoded and its merged cut, per object the field cells its last merge refined, and the
//! file's stored cuts (off, [`Frame::set_stored_cache`], they stay in the file and each cut a
//! merge needs is read from it: the operating system's file cache holds them, shared and
//! evictable, not the frame). Moves and BRDF edits need neither merged cuts nor lists rebuilt
//! from them; a lighting change, a sun toggle and a camera turn do, and without the merged
//! cache ([`Frame::set_merged_cache`]) they merge those vertices again at their kept inputs in
//! one batch (the same cuts, bit for bit). A kept merged cut is its heights and values, 5
//! bytes a node (`kept.rs`: the level-order index follows from the heights). On the teapot
//! scene at `balanced` (`move_path`, 2026-12-05) the frame holds 107 MB with every cache, 65 MB
//! without the merged cuts (`NO_MERGED_CACHE=1`: a lighting change 246–383 instead of 67–89 ms,
//! a camera turn after it 76–103 instead of 13–19 ms) and 36 MB without any cache
//! (`NO_CELL_CACHE=1 NO_SVC_CACHE=1` too: the SVCs decoded at each merge, no field cells kept
//! between moves). [`Frame::fit_memory`] drops caches to fit a budget (`vcuts render
//! --memory-budget`).

mod caches;
mod choice;
mod deferral;
mod kept;
mod keys;
mod lighting;
mod lists;
mod merge;
mod object;
mod shading;
mod stats;
#[cfg(test)]
mod tests;

use crate::brdf;
use crate::sun::{Sun, SunRays};
pub use caches::FrameCaches;
pub use choice::LightChoice;
use glam::Vec3;
use kept::KeptCut;
use keys::FieldKey;
use lists::{ShadeList, ShadeNode, SpecularNode};
use merge::FieldCache;
pub use merge::FlatEdges;
use object::{ObjectState, ViewCone};
pub use shading::Parts;
pub use stats::FrameMemory;
use vcut_cut::Cut;
use vcut_data::{FileError, InsideSamples, Precomputed};
use vcut_dirtree::DirectionTree;
use vcut_envmap::EnvMap;
use vcut_lighttree::{LightTree, LightTreeBuilder};
use vcut_merge::MergedCut;
use vcut_scene::{Material, Mesh, Motion};

/// Why a frame could not be set up.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// The precomputed data is unreadable.
    #[error(transparent)]
    File(#[from] FileError),
    /// A cut in the data does not decode or merge.
    #[error("object {object}, vertex {vertex}: {error}")]
    Cut {
        /// Object index.
        object: usize,
        /// Vertex index.
        vertex: usize,
        /// What failed.
        error: CutFailure,
    },
    /// A setting out of its range.
    #[error("{setting} = {value}: {reason}")]
    Setting {
        /// The setting's name.
        setting: &'static str,
        /// The value given.
        value: f32,
        /// What it must be.
        reason: &'static str,
    },
    /// An object's stored cuts could not be read back from their file
    /// ([`Frame::set_stored_cache`]).
    #[error("object {object}, its stored cuts: {error}")]
    Stored {
        /// Object index.
        object: usize,
        /// What failed.
        error: vcut_data::sections::CutFault,
    },
    /// The direction tree has more nodes than a shading list entry can name.
    #[error("the direction tree has {nodes} nodes; a frame shades at most {max} (65,536 directions)")]
    TooManyNodes {
        /// The tree's nodes.
        nodes: usize,
        /// The most a frame takes.
        max: usize,
    },
}

/// Why a vertex's cuts could not be merged.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CutFailure {
    /// A stored cut (its SVC or a field sample's) does not decode.
    #[error(transparent)]
    Decode(#[from] vcut_data::sections::CutDecodeError),
    /// The merge refused its inputs.
    #[error(transparent)]
    Merge(#[from] vcut_merge::MergeError),
}

impl FrameError {
    /// A failure of object `object`'s vertex `vertex`.
    pub(crate) fn cut(object: usize, vertex: usize, error: impl Into<CutFailure>) -> FrameError {
        FrameError::Cut { object, vertex, error: error.into() }
    }
}

/// Which merge a move uses: [`vcut_merge::Algorithm`]. Both give the same merged cuts bit for
/// bit (tested), so they can be timed on the same frames; the counter merge refines each field
/// cell's cuts (the 8 samples of a lookup, shared by the vertices around them) once into their
/// common refinement, then merges every vertex's SVC with its cells' refinements.
pub use vcut_merge::Algorithm as MergeAlgorithm;

/// Where the last move's time went (seconds, wall clock over both cores).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MoveTiming {
    /// Field lookups of every vertex (the keys).
    pub keys_s: f64,
    /// Decoding the field samples the changed vertices need (once each).
    pub decode_s: f64,
    /// Refining the field cells the changed vertices use (once each).
    pub refine_s: f64,
    /// Merging the changed vertices and building their shading lists (SVC decode included).
    pub merge_s: f64,
    /// Casting the sun's rays the move changed (with [`Frame::set_sun_rays`]; 0 without).
    pub sun_s: f64,
    /// Sun rays cast.
    pub sun_rays: u64,
    /// Vertices re-merged.
    pub vertices: usize,
    /// Nodes of the re-merged vertices' cuts, summed: the walk emits each once and builds the
    /// shading list from it, so a merge's time grows with them (over `vertices`: how fine the
    /// product of a vertex's SVC and fields is).
    pub nodes: usize,
    /// Field factors of the re-merged vertices' products, summed (over `vertices`: the fields
    /// that reach a merged vertex, on average).
    pub fields: usize,
    /// Vertices whose field inputs changed but whose merge waits: they face away from the eye
    /// ([`Frame::set_deferred_merges`]).
    pub deferred: usize,
}

/// One object of a [`Frame`], as [`Frame::object`] shows it.
#[derive(Debug, Clone, Copy)]
pub struct FrameObject<'a> {
    /// Its name (unique in the scene).
    pub name: &'a str,
    /// Its mesh at rest.
    pub mesh: &'a Mesh,
    /// Its BRDF parameters now.
    pub material: &'a Material,
    /// Its glTF material's textures.
    pub textures: &'a vcut_scene::loaders::MaterialTextures,
    /// Whether it may move.
    pub motion: Motion,
    /// Its translation from rest now.
    pub translation: Vec3,
}

/// The scene at run time: translations, materials, lighting, and the merged cuts.
pub struct Frame {
    tree: DirectionTree,
    objects: Vec<ObjectState>,
    builder: LightTreeBuilder,
    light: LightTree,
    /// The sun by rays, when asked for and the light has one ([`crate::sun`]).
    sun_rays: Option<SunRays>,
    sun: Option<Sun>,
    /// Why the sun's leaves are those ([`Frame::light_choice`]).
    choice: LightChoice,
    /// Every object's hierarchy at rest, for the sun's rays (built at the first choice that
    /// has a candidate leaf).
    occluders: Vec<vcut_rays::Occluder>,
    /// Where the SVCs' rays start: this fraction of an object's bounding radius along the normal.
    origin_offset: f32,
    /// Per tree node (level order): what shading needs (under the light less the sun's leaves
    /// when the sun is cast).
    nodes: Vec<ShadeNode>,
    /// Per tree node: what the specular loop reads ([`ShadeNode::dir`] and `light`), half a
    /// cache line each, so the nodes a frame's lists use stay in cache.
    specular: Vec<SpecularNode>,
    merges: u64,
    algorithm: MergeAlgorithm,
    inside: InsideSamples,
    last_move: MoveTiming,
    /// The last eye shaded from or set: merges build the lists of the vertices facing it only
    /// (all while `None`).
    eye: Option<Vec3>,
    /// Whether a move leaves the vertices facing away from the eye for later.
    defer: bool,
    /// Merges [`Frame::shade`] did on the spot.
    spot_merges: u64,
    /// Whether a field whose object lies wholly below a vertex's horizon is left out of its
    /// product ([`Frame::set_horizon_culling`]).
    horizon_culling: bool,
    /// Whether every vertex's merged cut is kept ([`Frame::set_merged_cache`]).
    merged_cache: bool,
    /// Whether the last merge's field cells are kept ([`Frame::set_cell_cache`]).
    cell_cache: bool,
    /// How far a field reaches, in its object's bounding radii ([`Frame::set_field_reach`];
    /// `None`: to its outermost sphere).
    field_reach: Option<f32>,
    /// The largest node across a flat occluder's edge whose visible share is estimated
    /// ([`Frame::set_flat_edge_leaves`]; 1: exact).
    flat_edge_leaves: u32,
}

/// A field's default reach, in its object's bounding radii ([`Frame::set_field_reach`]).
pub const FIELD_REACH: f32 = 6.0;

/// The share of the sphere of directions (1/256) whose nodes
/// [`Frame::interactive_flat_edge_leaves`] estimates across a ground's edges.
pub const INTERACTIVE_EDGE_SHARE: u32 = 256;

impl Frame {
    /// Reads everything from `data`, builds the light tree of `env`, and merges every vertex;
    /// keeps both caches ([`FrameCaches::default`]).
    pub fn new(data: &mut Precomputed, env: &EnvMap) -> Result<Frame, FrameError> {
        Frame::with_caches(data, env, FrameCaches::default())
    }

    /// [`Frame::new`] keeping only the caches `caches` asks for (from the start, so that the
    /// setup's peak memory holds none of the others either).
    pub fn with_caches(data: &mut Precomputed, env: &EnvMap, caches: FrameCaches) -> Result<Frame, FrameError> {
        Frame::setup(data, env, caches, None)
    }

    /// [`Frame::with_caches`] for a renderer that knows its eye: the eye is set first
    /// ([`Frame::set_eye`]), so the setup builds the shading lists of the vertices facing it
    /// only and marks the others' stale (built when a shading or an eye needs them), instead of
    /// every list, then those facing the eye. The same images bit for bit (tested); on
    /// `builtin:showroom:32` at `balanced` with no cache the lists are ~37 MB of a ~57 MB frame.
    pub fn with_caches_facing(
        data: &mut Precomputed,
        env: &EnvMap,
        caches: FrameCaches,
        eye: Vec3,
    ) -> Result<Frame, FrameError> {
        Frame::setup(data, env, caches, Some(eye))
    }

    fn setup(
        data: &mut Precomputed,
        env: &EnvMap,
        caches: FrameCaches,
        eye: Option<Vec3>,
    ) -> Result<Frame, FrameError> {
        let tree = data.tree()?;
        if tree.node_count() > lists::MAX_NODES {
            return Err(FrameError::TooManyNodes { nodes: tree.node_count(), max: lists::MAX_NODES });
        }
        let mut objects = Vec::new();
        for o in 0..data.objects.len() {
            let mut svc = data.svc_arrays(o)?;
            let mut field = data.field_arrays(o)?;
            if !caches.stored {
                // One object's arrays at a time, so that the setup never holds the whole file.
                svc.iter_mut().chain(&mut field).for_each(|a| _ = a.evict());
            }
            let mut svc_starts = vec![0];
            for a in &svc {
                svc_starts.push(svc_starts.last().copied().unwrap_or(0) + a.len());
            }
            let stored = &data.objects[o];
            objects.push(ObjectState {
                name: stored.name.clone(),
                mesh: stored.mesh.clone(),
                material: stored.material,
                textures: stored.textures.clone(),
                vertex_materials: Vec::new(),
                loaded_material: stored.material,
                pow: brdf::PowTable::new(stored.material.exponent),
                motion: stored.motion,
                translation: Vec3::ZERO,
                svc,
                svc_starts,
                layout: data.layouts[o],
                field,
                flat: vcut_scene::flat::FlatOutline::of(&stored.mesh),
                ray_offset: vcut_rays::origin_offset(data.svc_origin_offset(), &stored.mesh),
                merged: Vec::new(),
                lists: Vec::new(),
                keys: Vec::new(),
                decoded: FieldCache::default(),
                svc_refined: Vec::new(),
                pending: Vec::new(),
                cones: ViewCone::of(&stored.mesh),
            });
            let last = objects.last_mut().expect("just pushed");
            last.vertex_materials = last.vertex_materials();
        }
        let mut builder = LightTreeBuilder::new(&tree);
        let light = builder.build(env);
        let mut frame = Frame {
            tree,
            objects,
            builder,
            light,
            sun_rays: Some(SunRays::default()),
            sun: None,
            choice: LightChoice::default(),
            occluders: Vec::new(),
            origin_offset: data.svc_origin_offset(),
            // Built by `light_state` below, with the sun's leaves out when they are cast.
            specular: Vec::new(),
            nodes: Vec::new(),
            merges: 0,
            algorithm: MergeAlgorithm::Counter,
            inside: InsideSamples::default(),
            last_move: MoveTiming::default(),
            eye,
            defer: true,
            spot_merges: 0,
            horizon_culling: true,
            merged_cache: caches.merged,
            cell_cache: caches.cells,
            field_reach: Some(FIELD_REACH),
            flat_edge_leaves: 1,
        };
        frame.set_svc_cache(caches.svc)?;
        // The sun and the shading table before the merges build the lists.
        frame.light_state();
        for o in 0..frame.objects.len() {
            let n = frame.objects[o].mesh.vertex_count();
            let keys: Vec<Vec<FieldKey>> = (0..n).map(|v| frame.keys(o, v)).collect();
            let mut merged = vec![KeptCut::default(); if caches.merged { n } else { 0 }];
            let mut lists = vec![ShadeList::default(); n];
            let mut cache = FieldCache::default();
            let kept = caches.merged.then_some(&mut merged[..]);
            frame.merge_all(o, &keys, &vec![true; n], kept, &mut lists, &mut cache, &mut MoveTiming::default())?;
            frame.objects[o].decoded = cache;
            frame.objects[o].pending = vec![false; n];
            frame.objects[o].keys = keys;
            frame.objects[o].merged = merged;
            frame.objects[o].lists = lists;
        }
        Ok(frame)
    }

    /// The direction tree.
    pub fn tree(&self) -> &DirectionTree {
        &self.tree
    }

    /// The light tree of the environment (the sun's leaves included, also with sun rays on).
    pub fn light(&self) -> &LightTree {
        &self.light
    }

    /// Number of objects.
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    /// Index of the object called `name`.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.name == name)
    }

    /// Object `o`: its name, mesh at rest, material, motion and translation.
    pub fn object(&self, o: usize) -> FrameObject<'_> {
        let s = &self.objects[o];
        FrameObject {
            name: &s.name,
            mesh: &s.mesh,
            material: &s.material,
            textures: &s.textures,
            motion: s.motion,
            translation: s.translation,
        }
    }

    /// The diffuse albedo of object `o` at texture coordinates `uv`: the `kd` of its material
    /// there ([`vcut_scene::texture::MaterialTextures::material_at`]), else its own `kd`.
    pub fn albedo_at(&self, o: usize, uv: Option<glam::Vec2>) -> Vec3 {
        let s = &self.objects[o];
        match uv {
            Some(uv) if s.textures.vary() => Vec3::from(s.material_at(uv).kd),
            _ => Vec3::from(s.material.kd),
        }
    }

    /// Object `o`'s diffuse albedo averaged over its vertices (its `kd` when textures do not
    /// vary it): for renderers that take one per object.
    pub fn mean_albedo(&self, o: usize) -> Vec3 {
        let s = &self.objects[o];
        match s.vertex_materials.len() {
            0 => Vec3::from(s.material.kd),
            n => s.vertex_materials.iter().map(|m| Vec3::from(m.kd)).sum::<Vec3>() / n as f32,
        }
    }

    /// Vertex `v`'s diffuse albedo (its material's `kd`).
    pub fn albedo(&self, o: usize, v: usize) -> Vec3 {
        Vec3::from(self.objects[o].material(v).kd)
    }

    /// Vertex `v`'s material: the object's, varied by its textures at the vertex's coordinates
    /// (the BRDF every shading of the vertex evaluates).
    pub fn material(&self, o: usize, v: usize) -> &Material {
        self.objects[o].material(v)
    }

    /// Whether any object's material varies over it (textures with coordinates): then images
    /// take the albedo per pixel.
    pub fn has_textures(&self) -> bool {
        self.objects.iter().any(|s| !s.vertex_materials.is_empty())
    }

    /// The merged cut of vertex `v` of object `o`, as of its last merge: a vertex whose merge
    /// waits ([`Frame::set_deferred_merges`], [`Frame::pending_merges`]) still has the cut of
    /// its field inputs before the move. With the merged cache off ([`Frame::set_merged_cache`])
    /// it is merged again here at those inputs (the same cut, bit for bit). The frame keeps
    /// heights and values only: the level-order indices are derived here.
    pub fn merged(&self, o: usize, v: usize) -> Result<std::borrow::Cow<'_, MergedCut>, FrameError> {
        let s = &self.objects[o];
        if let Some(cut) = s.merged.get(v) {
            return Ok(std::borrow::Cow::Owned(cut.to_merged()));
        }
        let mut cut = MergedCut::default();
        self.merge_one(o, v, &s.keys[v], &mut cut)?;
        Ok(std::borrow::Cow::Owned(cut))
    }

    /// The SVC of vertex `v` of object `o`.
    pub fn svc(&self, o: usize, v: usize) -> Result<Cut, vcut_data::sections::CutDecodeError> {
        self.objects[o].svc_cut(v)
    }

    /// World positions of object `o`'s vertices at its current translation.
    pub fn positions(&self, o: usize) -> Vec<Vec3> {
        let s = &self.objects[o];
        s.mesh.positions().iter().map(|&p| p + s.translation).collect()
    }

    /// Whether vertex `v` of object `o` may be seen from `eye`, and so is shaded toward it: its
    /// normal faces the eye, or one of its triangles may (a silhouette vertex of a visible
    /// triangle, shaded toward [`brdf::view_direction`]). What is not seen shades black in
    /// [`Frame::shade`] and its merges may wait.
    pub fn seen(&self, o: usize, v: usize, eye: Vec3) -> bool {
        self.objects[o].seen(v, eye)
    }

    /// The eye that merges build shading lists for.
    fn eye(&self) -> Option<Vec3> {
        self.eye
    }
}
