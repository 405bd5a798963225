//! What a frame has done and holds, as report keys: the part of `render`'s outcome that
//! describes the frame, and Python's `Frame.stats()` (the same keys from the same
//! serialisation).

use serde::Serialize;
use vcut_shade::{Frame, MoveTiming};

/// A frame's figures: its caches, the light it casts by rays, its merges, its last move and its
/// memory.
#[derive(Debug, Clone, Serialize)]
pub struct FrameReport {
    /// The caches it keeps, comma-separated (`none`).
    pub frame_caches: String,
    /// The scene's vertices.
    pub vertices: usize,
    /// Leaves of the light cast by rays.
    pub sun_leaves: usize,
    /// How those leaves were chosen (with sun rays on).
    #[serde(flatten)]
    pub light: Option<LightReport>,
    /// Vertices merged since the setup (moves, camera turns after them, settings changes).
    pub merges: u64,
    /// Vertices the setup merged.
    pub setup_merges: u64,
    /// Vertices shading merged on the spot without keeping them.
    pub spot_merges: u64,
    /// Vertices whose merge waits for an eye that sees them.
    pub pending_merges: usize,
    /// Where the last move's time went (after a move).
    #[serde(flatten)]
    pub last_move: Option<MoveReport>,
    /// The drag under way or the last one (after a drag: `Frame::drag`).
    #[serde(flatten)]
    pub drag: Option<DragReport>,
    /// The last refinement (after `--refine` or `Frame.refine`).
    #[serde(flatten)]
    pub refine: Option<RefineReport>,
    /// Its memory by part.
    #[serde(flatten)]
    pub memory: MemoryReport,
}

/// The last refinement ([`vcut_shade::RefineStats`]).
#[derive(Debug, Clone, Serialize)]
pub struct RefineReport {
    /// Its time.
    pub refine_ms: f64,
    /// Exact field factors it cast.
    pub refine_factors_cast: usize,
    /// Rays they took.
    pub refine_rays: u64,
    /// Vertices it merged again.
    pub refine_merged_vertices: usize,
    /// Pairs within reach that are exact now.
    pub refine_exact_pairs: usize,
    /// Pairs within reach still looked up.
    pub refine_remaining_pairs: usize,
    /// Of those, pairs the memory budget had no room for.
    pub refine_over_budget_pairs: usize,
    /// Whether every pair within reach is exact.
    pub refine_complete: bool,
}

impl RefineReport {
    /// The report of `r`.
    pub fn of(r: &vcut_shade::RefineStats) -> RefineReport {
        RefineReport {
            refine_ms: r.seconds * 1e3,
            refine_factors_cast: r.cast,
            refine_rays: r.rays,
            refine_merged_vertices: r.merged,
            refine_exact_pairs: r.exact,
            refine_remaining_pairs: r.remaining,
            refine_over_budget_pairs: r.over_budget,
            refine_complete: r.complete(),
        }
    }
}

/// How the leaves cast by rays were chosen ([`vcut_shade::LightChoice`]).
#[derive(Debug, Clone, Serialize)]
pub struct LightReport {
    /// The target error.
    pub light_error_target: f64,
    /// At most this many leaves.
    pub light_max_leaves: usize,
    /// The estimated error with every candidate left in the cuts.
    pub light_error_estimate_cuts: f64,
    /// The estimated error with the chosen leaves cast.
    pub light_error_estimate: f64,
    /// The estimate's time.
    pub light_choice_ms: f64,
    /// Rays per vertex of a full cast.
    pub sun_rays_per_vertex: f64,
    /// Microseconds per vertex of a full cast.
    pub sun_cast_us_per_vertex: f64,
}

/// Where the last move's time went ([`MoveTiming`]).
#[derive(Debug, Clone, Serialize)]
pub struct MoveReport {
    /// Field lookups.
    pub move_keys_ms: f64,
    /// Decoding field samples.
    pub move_decode_ms: f64,
    /// Refining field cells.
    pub move_refine_ms: f64,
    /// The merges proper, shading lists built as the nodes are emitted.
    pub move_merge_only_ms: f64,
    /// Casting the sun's rays.
    pub move_sun_ms: f64,
    /// Sun rays cast.
    pub move_sun_rays: u64,
    /// Vertices whose merge waits (facing away from the eye).
    pub move_deferred_vertices: usize,
    /// Field factors per merged vertex.
    pub move_fields_per_vertex: f64,
    /// Nodes of the merged cuts per merged vertex.
    pub move_nodes_per_vertex: f64,
    /// Vertices merged on their rest products (a drag's step).
    pub move_on_rest_vertices: usize,
    /// Vertices a drag's step left as they were: the moved object hidden from them.
    pub move_hidden_vertices: usize,
}

/// A drag's preparation and settle ([`vcut_shade::DragStats`]).
#[derive(Debug, Clone, Serialize)]
pub struct DragReport {
    /// Preparing the rest products.
    pub drag_prepare_ms: f64,
    /// Vertices given a rest product.
    pub drag_prepared_vertices: usize,
    /// Vertices the memory budget left to full merges.
    pub drag_unprepared_vertices: usize,
    /// The rest products' memory (0 once settled).
    pub drag_memory_mb: f64,
    /// The last settle.
    pub drag_settle_ms: f64,
    /// Vertices the last settle merged again in full.
    pub drag_settled_vertices: usize,
}

impl DragReport {
    /// The report of `d`; `None` when no drag has begun.
    pub fn of(d: &vcut_shade::DragStats) -> Option<DragReport> {
        (d.object.is_some() || d.prepared + d.unprepared + d.settled > 0).then(|| DragReport {
            drag_prepare_ms: d.prepare_s * 1e3,
            drag_prepared_vertices: d.prepared,
            drag_unprepared_vertices: d.unprepared,
            drag_memory_mb: d.bytes as f64 / 1e6,
            drag_settle_ms: d.settle_s * 1e3,
            drag_settled_vertices: d.settled,
        })
    }
}

impl MoveReport {
    /// The report of `t`.
    pub fn of(t: &MoveTiming) -> MoveReport {
        let per = |x: usize| x as f64 / t.vertices.max(1) as f64;
        MoveReport {
            move_keys_ms: t.keys_s * 1e3,
            move_decode_ms: t.decode_s * 1e3,
            move_refine_ms: t.refine_s * 1e3,
            move_merge_only_ms: t.merge_s * 1e3,
            move_sun_ms: t.sun_s * 1e3,
            move_sun_rays: t.sun_rays,
            move_deferred_vertices: t.deferred,
            move_fields_per_vertex: per(t.fields),
            move_nodes_per_vertex: per(t.nodes),
            move_on_rest_vertices: t.on_rest,
            move_hidden_vertices: t.hidden,
        }
    }
}

/// A frame's memory by part (MB), per vertex, and the process's peak.
#[derive(Debug, Clone, Serialize)]
pub struct MemoryReport {
    /// Every part together.
    pub frame_memory_mb: f64,
    /// Every part over the scene's vertices (bytes).
    pub frame_bytes_per_vertex: usize,
    /// The file's stored cuts held in memory.
    pub frame_memory_stored_mb: f64,
    /// Meshes.
    pub frame_memory_meshes_mb: f64,
    /// Merged cuts.
    pub frame_memory_merged_mb: f64,
    /// Shading lists.
    pub frame_memory_lists_mb: f64,
    /// Decoded SVCs.
    pub frame_memory_svc_cache_mb: f64,
    /// Field inputs (keys).
    pub frame_memory_keys_mb: f64,
    /// Field cells and decoded samples kept for the next move.
    pub frame_memory_field_cache_mb: f64,
    /// The sun by rays: hierarchies and masks.
    pub frame_memory_rays_mb: f64,
    /// A drag's rest products.
    pub frame_memory_drag_mb: f64,
    /// The exact field factors refinement cast.
    pub frame_memory_exact_mb: f64,
    /// The process's peak resident memory, where the system says it.
    pub peak_rss_mb: Option<f64>,
}

impl FrameReport {
    /// The figures of `frame` now; `moved`: whether the last move's timing is to be reported.
    pub fn of(frame: &Frame, moved: bool) -> FrameReport {
        let stats = frame.stats();
        let light = frame.settings().sun_rays.then(|| {
            let c = frame.light_choice();
            LightReport {
                light_error_target: c.target,
                light_max_leaves: frame.settings().light_max_leaves,
                light_error_estimate_cuts: c.estimate_cuts,
                light_error_estimate: c.estimate,
                light_choice_ms: c.estimate_s * 1e3,
                sun_rays_per_vertex: c.rays_per_vertex(),
                sun_cast_us_per_vertex: c.cast_us_per_vertex(),
            }
        });
        FrameReport {
            frame_caches: stats.caches.names(),
            vertices: (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum(),
            sun_leaves: stats.sun_leaves,
            light,
            merges: stats.merges,
            setup_merges: stats.setup_merges,
            spot_merges: stats.spot_merges,
            pending_merges: stats.pending_merges,
            last_move: moved.then(|| MoveReport::of(&stats.last_move)),
            drag: DragReport::of(&stats.drag),
            refine: frame.last_refine().as_ref().map(RefineReport::of),
            memory: MemoryReport::of(frame),
        }
    }
}

impl MemoryReport {
    /// The memory of `frame` now.
    pub fn of(frame: &Frame) -> MemoryReport {
        let m = frame.memory();
        let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();
        let mb = |b: usize| b as f64 / 1e6;
        MemoryReport {
            frame_memory_mb: mb(m.total()),
            frame_bytes_per_vertex: m.total() / vertices.max(1),
            frame_memory_stored_mb: mb(m.stored),
            frame_memory_meshes_mb: mb(m.meshes),
            frame_memory_merged_mb: mb(m.merged),
            frame_memory_lists_mb: mb(m.lists),
            frame_memory_svc_cache_mb: mb(m.svc_cache),
            frame_memory_keys_mb: mb(m.keys),
            frame_memory_field_cache_mb: mb(m.field_cache),
            frame_memory_drag_mb: mb(m.drag),
            frame_memory_exact_mb: mb(m.exact),
            frame_memory_rays_mb: mb(m.rays),
            peak_rss_mb: vcut_scene::budget::peak_memory().map(|p| p as f64 / 1e6),
        }
    }
}
