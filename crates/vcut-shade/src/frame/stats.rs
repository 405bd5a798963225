//! What the frame reports about itself: merge counts, the last move's timing, and the bytes
//! of its shading lists, merged cuts and kept SVCs.

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
    /// The decoded SVCs kept for merging ([`Frame::set_svc_cache`]).
    pub svc_cache: usize,
    /// Every vertex's field inputs (the keys a move compares).
    pub keys: usize,
    /// The field cuts and cells the last merges decoded, kept for the next move.
    pub field_cache: usize,
    /// The sun by rays: every object's hierarchy and the masks of the sun's leaves each
    /// occluder blocks at each vertex ([`Frame::set_sun_rays`]).
    pub rays: usize,
}

impl FrameMemory {
    /// Every part with its name (the field's name: `render`'s `frame_memory_<name>_mb` keys and
    /// Python's `Frame.stats()["memory"]` read this one list).
    pub fn parts(&self) -> [(&'static str, usize); 8] {
        [
            ("stored", self.stored),
            ("meshes", self.meshes),
            ("merged", self.merged),
            ("lists", self.lists),
            ("svc_cache", self.svc_cache),
            ("keys", self.keys),
            ("field_cache", self.field_cache),
            ("rays", self.rays),
        ]
    }

    /// Every part together.
    pub fn total(&self) -> usize {
        self.parts().iter().map(|(_, b)| b).sum()
    }
}

impl Frame {
    /// Vertices re-merged by moves so far, and by camera turns or [`Frame::merge_pending`]
    /// merging what moves left waiting ([`Frame::set_deferred_merges`]; the merges at setup are
    /// not counted, nor [`Frame::shade`]'s on-the-spot ones: [`Frame::spot_merges`]). BRDF
    /// edits never merge; lighting edits and camera turns merge what they relist only without
    /// the merged cache ([`Frame::set_merged_cache`]), and are counted then.
    pub fn merges(&self) -> u64 {
        self.merges
    }

    /// Vertices [`Frame::shade`] merged on the spot without keeping them: waiting vertices
    /// (deferred merges) facing an eye that no [`Frame::set_eye`] announced, and without the
    /// merged cache those whose list is stale.
    pub fn spot_merges(&self) -> u64 {
        self.spot_merges
    }

    /// Where the last [`Frame::translate`]'s time went.
    pub fn last_move(&self) -> MoveTiming {
        self.last_move
    }

    /// Bytes a shading pass reads from the shading lists (node index and weight packed in 4
    /// bytes per entry, and the diffuse sum per vertex): with the machine's memory bandwidth, a
    /// floor under its time.
    pub fn shade_bytes(&self) -> usize {
        self.objects.iter().flat_map(|s| &s.lists).map(|l| l.entries.len() * size_of::<u32>() + size_of::<Vec3>()).sum()
    }

    /// Bytes of every vertex's kept merged cut (height u8 and value f32 per node; 0 with the
    /// merged cache off): streaming them is the floor under a shading pass.
    pub fn merged_bytes(&self) -> usize {
        self.objects.iter().flat_map(|s| &s.merged).map(|m| m.len() * (size_of::<u8>() + size_of::<f32>())).sum()
    }

    /// What the frame holds in memory, by part.
    pub fn memory(&self) -> FrameMemory {
        let mut m = FrameMemory {
            rays: self.occluders.iter().map(vcut_rays::Occluder::bytes).sum::<usize>()
                + self.sun.as_ref().map_or(0, crate::sun::Sun::bytes),
            ..FrameMemory::default()
        };
        let vec = size_of::<Vec<u8>>();
        for s in &self.objects {
            m.stored += s.svc.iter().chain(&s.field).map(|a| a.bytes()).sum::<usize>();
            m.meshes += s.mesh.vertex_count() * 2 * size_of::<Vec3>()
                + s.mesh.triangle_count() * 3 * size_of::<u32>()
                + s.cones.len() * size_of::<super::object::ViewCone>();
            m.merged += s.merged.iter().map(KeptCut::bytes).sum::<usize>();
            m.lists += s.lists.iter().map(|l| size_of::<ShadeList>() + 4 * l.entries.capacity()).sum::<usize>();
            m.svc_cache += s.svc_refined.iter().map(Prepared::bytes).sum::<usize>()
                + s.svc_refined.capacity() * size_of::<Prepared>();
            m.keys += s.keys.iter().map(|k| vec + k.capacity() * size_of::<FieldKey>()).sum::<usize>();
            let c = &s.decoded;
            m.field_cache += c.keys.capacity() * 12
                + c.cuts.iter().map(|x| x.len() * 5).sum::<usize>()
                + c.cells.capacity() * size_of::<super::keys::CellKey>()
                + c.refined.iter().map(Prepared::bytes).sum::<usize>();
        }
        m
    }

    /// Bytes of the decoded SVCs kept for merging (0 with the cache off).
    pub fn svc_cache_bytes(&self) -> usize {
        self.objects.iter().flat_map(|s| &s.svc_refined).map(Prepared::bytes).sum()
    }
}
