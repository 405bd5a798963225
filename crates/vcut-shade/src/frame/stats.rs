//! What the frame reports about itself: merge counts, the last move's timing, and the bytes
//! of its shading lists, merged cuts and kept SVCs.

use super::{Frame, MoveTiming};
use glam::Vec3;
use vcut_merge::Prepared;

impl Frame {
    /// Vertices re-merged by moves so far, and by camera turns or [`Frame::merge_pending`]
    /// merging what moves left waiting ([`Frame::set_deferred_merges`]; the merges at setup are
    /// not counted, nor [`Frame::shade`]'s on-the-spot ones: [`Frame::spot_merges`]). BRDF and
    /// lighting edits never merge.
    pub fn merges(&self) -> u64 {
        self.merges
    }

    /// Vertices [`Frame::shade`] merged on the spot without keeping them: waiting vertices
    /// (deferred merges) facing an eye that no [`Frame::set_eye`] announced.
    pub fn spot_merges(&self) -> u64 {
        self.spot_merges
    }

    /// Where the last [`Frame::translate`]'s time went.
    pub fn last_move(&self) -> MoveTiming {
        self.last_move
    }

    /// Bytes a shading pass reads from the shading lists (node index and weight per entry, and
    /// the diffuse sum per vertex): with the machine's memory bandwidth, a floor under its time.
    pub fn shade_bytes(&self) -> usize {
        self.objects
            .iter()
            .flat_map(|s| &s.lists)
            .map(|l| l.nodes.len() * (size_of::<u32>() + size_of::<f32>()) + size_of::<Vec3>())
            .sum()
    }

    /// Bytes of every vertex's merged cut (height u8, value f32 and level-order index u32 per
    /// node): streaming them is the floor under a shading pass.
    pub fn merged_bytes(&self) -> usize {
        self.objects
            .iter()
            .flat_map(|s| &s.merged)
            .map(|m| m.heights.len() * (size_of::<u8>() + size_of::<f32>() + size_of::<u32>()))
            .sum()
    }

    /// Bytes of the decoded SVCs kept for merging (0 with the cache off).
    pub fn svc_cache_bytes(&self) -> usize {
        self.objects.iter().flat_map(|s| &s.svc_refined).map(Prepared::bytes).sum()
    }
}
