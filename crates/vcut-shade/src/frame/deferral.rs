//! Deferred merges (the default): a vertex facing away from the camera reflects nothing toward
//! it, so a move leaves its merge for an eye that sees it — [`Frame::set_eye`] merges and
//! keeps the waiting vertices facing it, [`Frame::shade`] merges those it needs on the spot
//! without keeping them, [`Frame::merge_pending`] merges all.

use super::merge::Rekey;
use super::{Frame, FrameError};
use glam::Vec3;

impl Frame {
    /// Vertices whose merge waits for an eye that sees them.
    pub fn pending_merges(&self) -> usize {
        self.states.iter().map(|s| s.pending.iter().filter(|&&p| p).count()).sum()
    }

    /// Merges every vertex whose merge waits, whichever way it faces (for reading all merged
    /// cuts with [`Frame::merged`]). Returns how many.
    pub fn merge_pending(&mut self) -> Result<usize, FrameError> {
        if self.pending_merges() == 0 {
            return Ok(0);
        }
        Ok(count(&self.rekey(Rekey::waiting(true))?))
    }

    /// Sets the eye later merges and lighting changes build shading lists for (only the
    /// vertices facing it need one; [`Frame::shade`] sets it too) and builds the stale lists of
    /// the vertices facing it now: after a camera turn, so that shading from it again need not
    /// build them each time. Merges the vertices facing it whose merge waits (none unless a
    /// move left some); returns how many.
    pub fn set_eye(&mut self, eye: Vec3) -> Result<usize, FrameError> {
        self.ctx.eye = Some(eye);
        let objects = &self.ctx.objects;
        let waiting = self
            .states
            .iter()
            .enumerate()
            .any(|(o, s)| s.pending.iter().enumerate().any(|(v, &p)| p && objects[o].seen(v, eye)));
        let mut merged = if waiting { count(&self.rekey(Rekey::waiting(false))?) } else { 0 };
        for (o, state) in self.states.iter_mut().enumerate() {
            let me = &self.ctx.objects[o];
            let which: Vec<bool> =
                state.lists.iter().enumerate().map(|(v, l)| l.stale && !state.pending[v] && me.seen(v, eye)).collect();
            if which.contains(&true) {
                let again = self.ctx.relist(o, state, &which)?;
                self.tally.merges += again as u64;
                merged += again;
            }
        }
        Ok(merged)
    }
}

/// How many vertices a [`Frame::rekey`] merged.
pub(super) fn count(merged: &[Vec<bool>]) -> usize {
    merged.iter().flatten().filter(|&&m| m).count()
}
