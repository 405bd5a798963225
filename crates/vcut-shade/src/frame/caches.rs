//! What a frame keeps beyond its shading lists and field inputs, each a trade of memory for
//! time ([`FrameCaches`]): turning each on and off as the settings ask, and dropping them to fit
//! a memory budget.

use super::merge::FieldCache;
use super::{Context, Frame, FrameCaches, FrameError};

impl Context {
    /// Keeps every vertex's SVC decoded and prepared for the merge algorithm (`on`) or decodes
    /// it at every merge.
    pub(super) fn set_svc_cache(&mut self, on: bool) -> Result<(), FrameError> {
        self.caches.svc = on;
        let algorithm = self.settings.merge_algorithm;
        for (o, s) in self.objects.iter_mut().enumerate() {
            if !on {
                s.svc_refined = Vec::new();
            } else if s.svc_refined.is_empty() {
                s.svc_refined = s.prepared_svcs(algorithm).map_err(|(v, e)| FrameError::cut(o, v, e))?;
            }
        }
        Ok(())
    }

    /// Keeps the file's stored cuts in memory (`on`) or leaves them in the file and reads each
    /// cut a merge needs from there (one positional read of its block), holding only each
    /// array's header and block offsets. The cuts read are the same bytes, checked against the
    /// file's checksums when it was opened (turning it on again reads and checks them anew), so
    /// images are the same bit for bit (tested). A file changed in place since it was opened
    /// fails the merges that read it (the [`super::CutFailure::Decode`] names the file).
    pub(super) fn set_stored_cache(&mut self, on: bool) -> Result<(), FrameError> {
        self.caches.stored = on;
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
}

impl Frame {
    /// Turns each cache to what `want` asks, but fills no merged cache: returns whether the
    /// merged cuts must be filled (every vertex merged once to keep its cut).
    pub(super) fn apply_caches(&mut self, want: FrameCaches) -> Result<bool, FrameError> {
        let had = self.ctx.caches;
        if want.stored != had.stored {
            self.ctx.set_stored_cache(want.stored)?;
        }
        if want.svc != had.svc {
            self.ctx.set_svc_cache(want.svc)?;
        }
        if !want.cells {
            self.states.iter_mut().for_each(|s| s.decoded = FieldCache::default());
        }
        self.ctx.caches.cells = want.cells;
        if !want.merged {
            self.states.iter_mut().for_each(|s| s.merged = Vec::new());
        }
        self.ctx.caches.merged = want.merged;
        Ok(want.merged && !had.merged)
    }

    /// Drops caches, the one that saves least first — the stored cuts (read from the file
    /// instead), the merged cuts (lighting changes and camera turns), the field cells (the next
    /// move's), the SVCs (every merge) — until [`Frame::memory`] is within `budget` bytes; adds
    /// none (filling one would take the memory it measures). The frame's memory without any is
    /// over `budget` when none is left. The cell cache is measured as the last merges left it:
    /// a move that uses more cells may take it past `budget` until the next reconfiguration.
    pub(super) fn fit_memory(&mut self, budget: u64) -> Result<(), FrameError> {
        let over = |f: &Frame| f.memory().total() as u64 > budget;
        for drop in ["stored", "merged", "cells", "svc"] {
            if !over(self) {
                break;
            }
            let want = self.ctx.caches.without(drop).unwrap_or_else(|| unreachable!("a cache's name"));
            self.apply_caches(want)?;
        }
        Ok(())
    }
}
