//! What the frame reports about itself: merge counts, the last move's timing, the caches it
//! keeps, and its memory by part.

use super::kept::KeptCut;
use super::keys::FieldKey;
use super::lists::ShadeList;
use super::{Frame, MoveTiming};
use glam::Vec3;
use vcut_merge::Prepared;

/// What a frame holds in memory, by part (bytes, counted from the buffers' capacities).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameMemory {
    /// The stored cuts read from the file (SVCs and fields, still coded).
    pub stored: usize,
    /// Meshes (positions, normals, triangles).
    pub meshes: usize,
    /// Every vertex's merged cut.
    pub merged: usize,
    /// Every vertex's shading list.
    pub lists: usize,
    /// The decoded SVCs kept for merging ([`super::FrameCaches::svc`]).
    pub svc_cache: usize,
    /// Every vertex's field inputs (the keys a move compares).
    pub keys: usize,
    /// The field cuts and cells the last merges decoded, kept for the next move.
    pub field_cache: usize,
    /// The sun by rays: every object's hierarchy and the masks of the sun's leaves each
    /// occluder blocks at each vertex ([`super::FrameSettings::sun_rays`]).
    pub rays: usize,
    /// A drag's rest products ([`Frame::drag`]; 0 with none under way).
    pub drag: usize,
    /// The exact field factors refinement cast ([`Frame::refine`]).
    pub exact: usize,
}

impl FrameMemory {
    /// Every part with its name (the field's name: `render`'s `frame_memory_<name>_mb` keys and
    /// Python's `Frame.stats()["memory"]` read this one list).
    pub fn parts(&self) -> [(&'static str, usize); 10] {
        [
            ("stored", self.stored),
            ("meshes", self.meshes),
            ("merged", self.merged),
            ("lists", self.lists),
            ("svc_cache", self.svc_cache),
            ("keys", self.keys),
            ("field_cache", self.field_cache),
            ("rays", self.rays),
            ("drag", self.drag),
            ("exact", self.exact),
        ]
    }

    /// Every part together.
    pub fn total(&self) -> usize {
        self.parts().iter().map(|(_, b)| b).sum()
    }
}

/// What a frame has done and keeps ([`Frame::stats`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameStats {
    /// Vertices re-merged by moves so far, and by camera turns or [`Frame::merge_pending`]
    /// merging what moves left waiting, by settings changes, and (without the merged cache) by
    /// lighting changes and camera turns rebuilding lists; not the setup's merges nor
    /// [`Frame::shade`]'s on-the-spot ones. BRDF edits never merge.
    pub merges: u64,
    /// Vertices the setup merged ([`Frame::open`]): each vertex once.
    pub setup_merges: u64,
    /// Vertices [`Frame::shade`] merged on the spot without keeping them: waiting vertices
    /// facing an eye that no [`Frame::set_eye`] announced, and without the merged cache those
    /// whose list is stale.
    pub spot_merges: u64,
    /// Vertices whose merge waits for an eye that sees them.
    pub pending_merges: usize,
    /// Where the last [`Frame::translate`]'s (or drag step's) time went.
    pub last_move: MoveTiming,
    /// The drag under way, or the last one: its preparation and its settle.
    pub drag: super::DragStats,
    /// The caches kept now: the settings' own, less those a memory budget dropped.
    pub caches: super::FrameCaches,
    /// Leaves of the light cast by rays (0 with sun rays off, or none chosen):
    /// [`Frame::light_choice`] has which and why.
    pub sun_leaves: usize,
    /// Bytes a shading pass reads from the shading lists (node index and weight packed in 4
    /// bytes per entry, and the diffuse sum per vertex): with the machine's memory bandwidth, a
    /// floor under its time.
    pub shade_bytes: usize,
    /// Bytes of every vertex's kept merged cut (height u8 and value f32 per node; 0 without
    /// the merged cache): streaming them is a floor under a shading pass that reads them.
    pub merged_bytes: usize,
}

impl Frame {
    /// What the frame has done and keeps: merge counts, the last move's timing, the caches
    /// kept, the sun's leaves, the bytes a shading reads.
    pub fn stats(&self) -> FrameStats {
        FrameStats {
            merges: self.tally.merges,
            setup_merges: self.tally.setup_merges,
            spot_merges: self.tally.spot_merges,
            pending_merges: self.pending_merges(),
            last_move: self.tally.last_move,
            drag: super::DragStats { object: self.dragging(), ..self.tally.drag },
            caches: self.ctx.caches,
            sun_leaves: self.ctx.sun.as_ref().map_or(0, crate::sun::Sun::len),
            shade_bytes: self
                .states
                .iter()
                .flat_map(|s| &s.lists)
                .map(|l| l.entries.len() * size_of::<u32>() + size_of::<Vec3>())
                .sum(),
            merged_bytes: self
                .states
                .iter()
                .flat_map(|s| &s.merged)
                .map(|m| m.len() * (size_of::<u8>() + size_of::<f32>()))
                .sum(),
        }
    }

    /// What the frame holds in memory, by part.
    pub fn memory(&self) -> FrameMemory {
        let ctx = &self.ctx;
        let mut m = FrameMemory {
            rays: ctx
                .occluders
                .iter()
                .chain(ctx.turned_occluders.iter().flatten().map(|(_, o)| o))
                .map(vcut_rays::Occluder::bytes)
                .sum::<usize>()
                + ctx.sun.as_ref().map_or(0, crate::sun::Sun::bytes),
            drag: self.drag.as_ref().map_or(0, super::drag::Drag::bytes),
            exact: self.exact_bytes(),
            ..FrameMemory::default()
        };
        let vec = size_of::<Vec<u8>>();
        for (s, state) in ctx.objects.iter().zip(&self.states) {
            m.stored += s.svc.iter().chain(&s.field).map(|a| a.bytes()).sum::<usize>();
            m.meshes += s.mesh.vertex_count() * 2 * size_of::<Vec3>()
                + s.mesh.triangle_count() * 3 * size_of::<u32>()
                + s.cones.len() * size_of::<super::object::ViewCone>();
            m.merged += state.merged.iter().map(KeptCut::bytes).sum::<usize>();
            m.lists += state.lists.iter().map(|l| size_of::<ShadeList>() + 4 * l.entries.capacity()).sum::<usize>();
            m.svc_cache += s.svc_refined.iter().map(Prepared::bytes).sum::<usize>()
                + s.svc_refined.capacity() * size_of::<Prepared>();
            m.keys += state.keys.iter().map(|k| vec + k.capacity() * size_of::<FieldKey>()).sum::<usize>();
            let c = &state.decoded;
            m.field_cache += c.keys.capacity() * size_of::<super::keys::SampleId>()
                + c.cuts.iter().map(|x| x.len() * 5).sum::<usize>()
                + c.cells.capacity() * size_of::<super::keys::CellKey>()
                + c.refined.iter().map(Prepared::bytes).sum::<usize>();
        }
        m
    }
}
