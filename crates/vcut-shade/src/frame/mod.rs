//! The frame loop of the paper, with caching: per vertex the SVC times the fields of the
//! objects that can move relative to it, interpolated from 8 samples each, merged once and kept;
//! a move re-merges only the vertices whose field inputs changed (those facing away from the
//! camera when it sees them: deferred merges, below); BRDF and lighting edits only re-shade,
//! and so do camera edits with nothing waiting. How it merges, caches and lights is one
//! [`FrameSettings`] value, given to [`Frame::open`] and changed with [`Frame::reconfigure`].
//! `docs/benchmarks.md` ("The frame's design, measured") has what each choice below cost and
//! gained.
//!
//! The frame is a shared [`Context`] — trees, light, objects with their stored cuts, settings —
//! and per object a `MergeState` (merged cuts, shading lists, field inputs, kept cells): a
//! merge borrows the context and the one state it writes.
//!
//! **Which fields a vertex uses.** Object j's field shadows a vertex of object o (o ≠ j) when
//! j has a field and o or j is movable (static–static shadows are baked into the SVCs), unless
//! j's bounding sphere lies wholly below the vertex's horizon ([`FrameSettings::horizon_culling`]):
//! then j hides none of the light the cut weighs by max(0, n·ω), and its field's sum over a node
//! straddling the horizon would only darken the node's upper part. Within 0.2r of j's centre
//! (0.05r–0.2r for a flat j: its layout's `inner`) the lookup clamps to the innermost sphere;
//! beyond [`FrameSettings::field_reach`] j casts no shadow (the paper stops at the outermost
//! sphere, 10r, where j's bounding cone covers under 0.25 % of the sphere); the sun's shadows
//! are cast by rays at any distance. Samples inside j blend in as fully occluded (or are dropped
//! and the rest renormalised: [`vcut_data::InsideSamples`]), and a vertex whose 8 samples are all inside j
//! is fully occluded.
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
//! cross the horizon keep `v_k f_r(Ê_k, ω_o) l_k`.
//!
//! **The SVC's share of a finer node.** A merged node k finer than the SVC node A around it
//! (a field splits A) gets the product's value v_A·F_k, with v_A A's mean of V·max(0, n·ω): A's
//! mean cosine, not k's. Where A lies wholly above the horizon the list takes k's visibility as
//! `v_k / (n·m_A)` instead of `v_k / (n·m_k)` — A's visibility fraction, times the fields — so
//! k's own cosine enters through n·E_k. The merged cuts stay the paper's product (bit for bit
//! with the counter merge); only the list reads the SVC's node ends.
//!
//! **The sun by rays** ([`FrameSettings::sun_rays`], [`crate::sun`]). The few leaves of the
//! light that hold a sun leave the cuts' light; each vertex adds their term with the visibility
//! cast at run time against the objects at their translations (a move casts only the object
//! pairs whose offset changed). The sun's shadow edges are then exact instead of blurred between
//! field samples. The merged cuts are the same either way.
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
//! the vertices facing a new eye.
//!
//! **Deferred merges** ([`FrameSettings::deferred_merges`]). For the same reason a move merges
//! only the changed vertices facing the last eye; the others keep their old cut and field
//! inputs and wait ([`Frame::pending_merges`]). The next move compares with those inputs (back
//! where it was, a vertex waits no more), [`Frame::set_eye`] merges and keeps the waiting
//! vertices facing the new eye, [`Frame::shade`] merges those it needs on the spot without
//! keeping them, and [`Frame::merge_pending`] merges all. Images are bit for bit the eager
//! frame's (tested). With deferral off a camera change never merges (with the merged cache on).
//!
//! **Turns** ([`Frame::turn`], `turn.rs`). Over a file precomputed with a direction set
//! symmetric about +Y (`turn_steps`), an object turns about the vertical through its
//! bounding-sphere centre: its geometry by the yaw asked for, its cuts (SVCs and field samples)
//! relabelled by the nearest whole wedge. A turn and back restores every cut bit for bit.
//!
//! **Drags** ([`Frame::drag`], `drag.rs`). While one object moves step after step, each vertex
//! its field reaches merges on the product of its other factors, prepared once, and the moved
//! field alone; [`Frame::settle`] gives back the full product bit for bit.
//!
//! **What a frame keeps** ([`Frame::memory`] by part). Per vertex its shading list, its field
//! inputs (keys) and — as caches, each a trade of memory for time ([`FrameCaches`]) — its SVC
//! decoded and its merged cut, per object the field cells its last merge refined, and the
//! file's stored cuts (off, they stay in the file and each cut a merge needs is read from it:
//! the operating system's file cache holds them, shared and evictable, not the frame). Moves
//! and BRDF edits need neither merged cuts nor lists rebuilt from them; a lighting change, a sun
//! toggle and a camera turn do, and without the merged cache they merge those vertices again at
//! their kept inputs in one batch (the same cuts, bit for bit). A kept merged cut is its heights
//! and values, 5 bytes a node (`kept.rs`: the level-order index follows from the heights).
//! [`FrameSettings::memory_budget`] drops caches, the one that saves least first, to fit.

#[cfg(feature = "clap")]
mod args;
mod background;
mod caches;
mod choice;
mod configure;
mod deferral;
mod drag;
mod kept;
mod keys;
mod lighting;
mod lists;
mod merge;
mod object;
mod refine;
pub mod settings;
mod shading;
mod stats;
#[cfg(test)]
mod tests;
mod turn;

use crate::sun::Sun;
#[cfg(feature = "clap")]
pub use args::FrameArgs;
pub use background::{BackgroundFrame, BackgroundShading, BackgroundStats, FinishedJob, FrameJob};
pub use choice::LightChoice;
pub use drag::DragStats;
use glam::Vec3;
use lists::{ShadeNode, SpecularNode};
pub use object::FrameObject;
use object::{MergeState, ObjectData};
pub use refine::{REFINE_REACH, RefineStats, Refinement};
pub use settings::{
    FIELD_REACH, FieldReach, FlatEdges, FrameCaches, FrameSettings, INTERACTIVE_EDGE_SHARE, SettingError,
    algorithm_name, algorithm_named,
};
pub use shading::Parts;
pub use stats::{FrameMemory, FrameStats};
pub use turn::{TurnRefusal, Turned};
use vcut_cut::Cut;
use vcut_data::FileError;
use vcut_dirtree::DirectionTree;
use vcut_lighttree::{LightTree, LightTreeBuilder};
use vcut_merge::MergedCut;

/// Why a frame could not be set up or reconfigured.
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
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// An object's stored cuts could not be read back from their file
    /// ([`FrameCaches::stored`] turned on again).
    #[error("object {object}, its stored cuts: {error}")]
    Stored {
        /// Object index.
        object: usize,
        /// What failed.
        error: vcut_data::sections::CutFault,
    },
    /// A translation the object's mesh cannot take in f32 (a position overflows, or a
    /// triangle's corners round onto one line): the frame is left as it was.
    #[error("object {object} ({name}) moved to {translation:?}: {error}")]
    Placement {
        /// Object index.
        object: usize,
        /// Its name.
        name: String,
        /// The translation refused.
        translation: [f32; 3],
        /// What the placed mesh would break.
        error: vcut_scene::MeshError,
    },
    /// The frame's worker ([`BackgroundFrame`]) panicked running a job or a shading: a bug in
    /// the frame, reported to the caller instead of ending its thread. The frame is as the
    /// job left it when it panicked.
    #[error("the frame's worker failed (a bug, please report it): {0}")]
    Panicked(String),
    /// A turn the object cannot take ([`Frame::turn`]): the frame is left as it was.
    #[error("object {object} ({name}) cannot turn: {reason}")]
    Turn {
        /// Object index.
        object: usize,
        /// Its name.
        name: String,
        /// Why not.
        reason: TurnRefusal,
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
    /// A stored cut has a node a turn cannot relabel (a file whose cuts do not match its
    /// symmetric direction set).
    #[error(transparent)]
    Turn(#[from] vcut_cut::CutError),
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
    /// Casting the sun's rays the move changed (with [`FrameSettings::sun_rays`]; 0 without).
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
    /// that reach a merged vertex, on average). A vertex merged on its rest product during a
    /// drag counts the moved object's only.
    pub fields: usize,
    /// Vertices merged on their rest products ([`Frame::drag`]): their product took the moved
    /// field alone.
    pub on_rest: usize,
    /// Vertices a drag's step left as they were: the moved object hidden from them (their rest
    /// product zero wherever its field is below 1) where it was and where it is.
    pub hidden: usize,
    /// Vertices whose field inputs changed but whose merge waits: they face away from the eye
    /// ([`FrameSettings::deferred_merges`]).
    pub deferred: usize,
}

/// What every merge, list and shading of a frame reads: the trees, the light, the objects with
/// their stored cuts, translations and turns, and the settings. Per-object merge results live beside
/// it ([`MergeState`]), so a merge borrows this and writes one state.
pub(crate) struct Context {
    tree: DirectionTree,
    objects: Vec<ObjectData>,
    settings: FrameSettings,
    /// [`FrameSettings::flat_edge_leaves`] for this tree.
    flat_leaves: u32,
    /// The caches kept now: the settings' own, less those a memory budget dropped.
    caches: FrameCaches,
    /// The file's recorded target error of the light left in the cuts.
    recorded_light_error: Option<f64>,
    builder: LightTreeBuilder,
    light: LightTree,
    /// The sun by rays, when asked for and the light has one ([`crate::sun`]).
    sun: Option<Sun>,
    /// Why the sun's leaves are those ([`Frame::light_choice`]).
    choice: LightChoice,
    /// Every object's hierarchy at rest, for the sun's rays (built at the first choice that
    /// has a candidate leaf).
    occluders: Vec<vcut_rays::Occluder>,
    /// Per object, its hierarchy as it stands turned and the yaw it was built at (`None`: not
    /// turned, or not built yet; [`Context::ensure_turned_occluders`]).
    turned_occluders: Vec<Option<(f32, vcut_rays::Occluder)>>,
    /// Where the SVCs' rays start: this fraction of an object's bounding radius along the normal.
    origin_offset: f32,
    /// Per tree node (level order): what shading needs (under the light less the sun's leaves
    /// when the sun is cast).
    nodes: Vec<ShadeNode>,
    /// Per tree node: what the specular loop reads ([`ShadeNode::dir`] and `light`), half a
    /// cache line each, so the nodes a frame's lists use stay in cache.
    specular: Vec<SpecularNode>,
    /// The last eye shaded from or set: merges build the lists of the vertices facing it only
    /// (all while `None`).
    eye: Option<Vec3>,
}

/// What a frame counts of its own work.
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    merges: u64,
    setup_merges: u64,
    spot_merges: u64,
    last_move: MoveTiming,
    drag: DragStats,
    refine: Option<RefineStats>,
}

/// The scene at run time: translations, materials, lighting, and the merged cuts.
pub struct Frame {
    ctx: Context,
    states: Vec<MergeState>,
    tally: Tally,
    /// The drag under way ([`Frame::drag`]), if one is.
    drag: Option<drag::Drag>,
}

impl Frame {
    /// The direction tree.
    pub fn tree(&self) -> &DirectionTree {
        &self.ctx.tree
    }

    /// The light tree of the environment (the sun's leaves included, also with sun rays on).
    pub fn light(&self) -> &LightTree {
        &self.ctx.light
    }

    /// The settings the frame was opened or last reconfigured with.
    pub fn settings(&self) -> &FrameSettings {
        &self.ctx.settings
    }

    /// Number of objects.
    pub fn object_count(&self) -> usize {
        self.ctx.objects.len()
    }

    /// Index of the object called `name`.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.ctx.objects.iter().position(|o| o.name == name)
    }

    /// Object `o`: its name, mesh at rest, material, motion and translation, and its vertices'
    /// materials, albedos and visibility from an eye.
    pub fn object(&self, o: usize) -> FrameObject<'_> {
        FrameObject::of(&self.ctx.objects[o])
    }

    /// Whether any object's material varies over it (textures with coordinates): then images
    /// take the albedo per pixel.
    pub fn has_textures(&self) -> bool {
        self.ctx.objects.iter().any(|s| !s.vertex_materials.is_empty())
    }

    /// The merged cut of vertex `v` of object `o`, as of its last merge: a vertex whose merge
    /// waits ([`Frame::pending_merges`]) still has the cut of its field inputs before the move.
    /// Without the merged cache it is merged again here at those inputs (the same cut, bit for
    /// bit). The frame keeps heights and values only: the level-order indices are derived here.
    pub fn merged(&self, o: usize, v: usize) -> Result<std::borrow::Cow<'_, MergedCut>, FrameError> {
        let s = &self.states[o];
        if let Some(cut) = s.merged.get(v) {
            return Ok(std::borrow::Cow::Owned(cut.to_merged()));
        }
        let mut cut = MergedCut::default();
        self.ctx.merge_one(o, v, &s.keys[v], &mut cut)?;
        Ok(std::borrow::Cow::Owned(cut))
    }

    /// The SVC of vertex `v` of object `o`, turned as the object stands ([`Frame::turn`]).
    pub fn svc(&self, o: usize, v: usize) -> Result<Cut, CutFailure> {
        self.ctx.objects[o].svc_cut(v)
    }
}
