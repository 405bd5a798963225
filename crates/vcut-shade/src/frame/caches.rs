//! What a frame keeps beyond its shading lists and field inputs, each a trade of memory for
//! time: the file's stored cuts, the SVCs decoded, the field cells of the last merges and the
//! merged cuts; turning each on and off, and dropping them to fit a memory budget.

use super::kept::KeptCut;
use super::merge::FieldCache;
use super::{Frame, FrameError, MergeAlgorithm, MoveTiming};
use rayon::prelude::*;

/// What a frame keeps beyond the shading lists and field inputs, each a trade of memory for
/// time ([`Frame::with_caches`], [`Frame::fit_memory`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameCaches {
    /// The file's stored cuts (SVCs and fields, coded) in memory ([`Frame::set_stored_cache`]):
    /// without, each cut a merge reads is read from the file (its block's bytes, one
    /// positional read: the operating system's file cache, not the frame, holds them).
    pub stored: bool,
    /// Every vertex's SVC decoded and prepared ([`Frame::set_svc_cache`]): spares each merge
    /// the SVC's decoding.
    pub svc: bool,
    /// The field cells the last merge of each object refined, and their decoded samples
    /// ([`Frame::set_cell_cache`]): the next move along a path needs most of them again.
    pub cells: bool,
    /// Every vertex's merged cut ([`Frame::set_merged_cache`]): a lighting change, a sun
    /// toggle or a camera turn rebuilds lists from it instead of merging again.
    pub merged: bool,
}

impl Default for FrameCaches {
    /// All kept.
    fn default() -> FrameCaches {
        FrameCaches { stored: true, svc: true, cells: true, merged: true }
    }
}

impl Frame {
    /// Chooses the merge that later moves use: the kept SVCs are prepared again in its form,
    /// and the field cells the last moves kept are dropped.
    pub fn set_merge_algorithm(&mut self, algorithm: MergeAlgorithm) -> Result<(), FrameError> {
        if algorithm == self.algorithm {
            return Ok(());
        }
        self.algorithm = algorithm;
        let cached = self.svc_cache_on();
        for s in &mut self.objects {
            s.decoded.cells.clear();
            s.decoded.refined.clear();
            s.svc_refined = Vec::new();
        }
        self.set_svc_cache(cached)
    }

    /// Whether the SVCs are kept prepared ([`Frame::set_svc_cache`]).
    fn svc_cache_on(&self) -> bool {
        self.objects.iter().any(|s| !s.svc_refined.is_empty())
    }

    /// Keeps every vertex's SVC decoded (`on`, the default) or decodes it at every merge.
    /// Keeping them spares a move the SVCs' decoding (split flags walked bit by bit) at
    /// [`Frame::svc_cache_bytes`] of memory (8 bytes a node); `cargo xtask bench` reports both.
    pub fn set_svc_cache(&mut self, on: bool) -> Result<(), FrameError> {
        let algorithm = self.algorithm;
        for o in 0..self.objects.len() {
            let s = &self.objects[o];
            if !on {
                self.objects[o].svc_refined = Vec::new();
            } else if s.svc_refined.is_empty() {
                let cached = (0..s.mesh.vertex_count())
                    .into_par_iter()
                    .map(|v| {
                        let svc = s.svc_cut(v).map_err(|e| FrameError::cut(o, v, e))?;
                        algorithm.prepare(&[&svc]).map_err(|e| FrameError::cut(o, v, e))
                    })
                    .collect::<Result<_, _>>()?;
                self.objects[o].svc_refined = cached;
            }
        }
        Ok(())
    }

    /// Keeps every vertex's merged cut (`on`, the default) or only its shading list. Without
    /// them the frame holds less memory (the merged cuts are its largest part: ~55 % of the
    /// teapot scene's at `balanced`), moves and BRDF edits cost the same, and what would build a
    /// list from a kept cut merges the vertex again at its kept field inputs: a lighting change
    /// or a sun toggle merges every vertex facing the eye, a camera turn those newly facing
    /// it, [`Frame::merged`] the one asked for. Images are the same bit for bit (tested).
    /// Turning it on merges every vertex once (at its kept inputs) to fill it.
    pub fn set_merged_cache(&mut self, on: bool) -> Result<(), FrameError> {
        if on == self.merged_cache {
            return Ok(());
        }
        self.merged_cache = on;
        for o in 0..self.objects.len() {
            let s = &mut self.objects[o];
            if !on {
                s.merged = Vec::new();
                continue;
            }
            let n = s.mesh.vertex_count();
            let (keys, mut lists, mut cache) =
                (std::mem::take(&mut s.keys), std::mem::take(&mut s.lists), std::mem::take(&mut s.decoded));
            let mut merged = vec![KeptCut::default(); n];
            let result = self.merge_all(
                o,
                &keys,
                &vec![true; n],
                Some(&mut merged),
                &mut lists,
                &mut cache,
                &mut MoveTiming::default(),
            );
            let s = &mut self.objects[o];
            // Waiting vertices keep their cut of the old inputs, and no list.
            for (list, _) in lists.iter_mut().zip(&s.pending).filter(|(_, p)| **p) {
                list.mark_stale();
            }
            (s.keys, s.lists, s.decoded, s.merged) = (keys, lists, cache, merged);
            if let Err(e) = result {
                self.set_merged_cache(false)?;
                return Err(e);
            }
        }
        Ok(())
    }

    /// Keeps the field cells each object's last merge refined, with their decoded samples
    /// (`on`, the default), for the next move, which reuses those it needs again; off, every
    /// merge decodes and refines the cells it uses and drops them after. The images are the
    /// same either way.
    pub fn set_cell_cache(&mut self, on: bool) {
        self.cell_cache = on;
        if !on {
            for s in &mut self.objects {
                s.decoded = FieldCache::default();
            }
        }
    }

    /// Which caches the frame keeps now.
    pub fn caches(&self) -> FrameCaches {
        FrameCaches {
            stored: self.stored_cache_on(),
            svc: self.svc_cache_on(),
            cells: self.cell_cache,
            merged: self.merged_cache,
        }
    }

    /// Whether the stored cuts are in memory ([`Frame::set_stored_cache`]).
    fn stored_cache_on(&self) -> bool {
        self.objects.iter().flat_map(|s| s.svc.iter().chain(&s.field)).any(|a| a.is_resident())
    }

    /// Keeps the file's stored cuts in memory (`on`, the default) or leaves them in the file
    /// and reads each cut a merge needs from there (one positional read of its block: ~32
    /// cuts' bytes), holding only each array's header and block offsets. The cuts read are the
    /// same bytes, checked against the file's checksums when it was opened (turning it on
    /// again reads and checks them anew), so images are the same bit for bit (tested). A file
    /// changed in place since it was opened fails the merges that read it (the
    /// [`CutFailure::Decode`] names the file).
    pub fn set_stored_cache(&mut self, on: bool) -> Result<(), FrameError> {
        for (o, s) in self.objects.iter_mut().enumerate() {
            for a in s.svc.iter_mut().chain(&mut s.field) {
                if on {
                    a.restore().map_err(|error| FrameError::Stored { object: o, error })?;
                } else {
                    a.evict();
                }
            }
        }
        Ok(())
    }

    /// Drops caches, the one that saves least first — the stored cuts (read from the file
    /// instead: a move within the machine's noise, ~5 % on `builtin:showroom:32` with no
    /// other cache), the merged cuts (lighting changes and camera turns), the field cells (the
    /// next move's), the SVCs (every merge) — until [`Frame::memory`] is within `budget`
    /// bytes; adds none (filling one would take the memory it measures). Returns the caches
    /// kept; the frame's memory without any is over `budget` when none is. The cell cache is
    /// measured as the last merges left it: a move that uses more cells may take it past
    /// `budget` until the next call.
    pub fn fit_memory(&mut self, budget: usize) -> Result<FrameCaches, FrameError> {
        if self.memory().total() > budget {
            self.set_stored_cache(false)?;
        }
        if self.memory().total() > budget {
            self.set_merged_cache(false)?;
        }
        if self.memory().total() > budget {
            self.set_cell_cache(false);
        }
        if self.memory().total() > budget {
            self.set_svc_cache(false)?;
        }
        Ok(self.caches())
    }
}
