//! Deferred merges (the default): a vertex facing away from the camera reflects nothing toward
//! it, so a move leaves its merge for an eye that sees it — [`Frame::set_eye`] merges and
//! keeps the waiting vertices facing it, [`Frame::shade`] merges those it needs on the spot
//! without keeping them, [`Frame::merge_pending`] merges all.

use super::keys::Changed;
use super::{Frame, FrameError};
use glam::Vec3;

impl Frame {
    /// Whether a move merges only the vertices facing the last eye (the default) and leaves
    /// the others' merges for when an eye sees them ([`Frame::set_eye`] merges and keeps them;
    /// [`Frame::shade`] merges those it needs on the spot without keeping them). A vertex facing
    /// away reflects nothing toward the eye, so the images are the same bit for bit either way;
    /// moves get faster (the teapot scene's ~0.75×, the bunny's ~0.73×: see the README), and a
    /// camera turn after a move merges what the move left (`false`: every move merges all it
    /// changes, and camera changes never merge). Turning it off merges what waits now; returns
    /// how many.
    pub fn set_deferred_merges(&mut self, defer: bool) -> Result<usize, FrameError> {
        self.defer = defer;
        if defer || self.pending_merges() == 0 { Ok(0) } else { self.rekey(Changed::Nothing, false) }
    }

    /// Whether moves leave the vertices facing away for later ([`Frame::set_deferred_merges`]).
    pub fn deferred_merges(&self) -> bool {
        self.defer
    }

    /// Vertices whose merge waits for an eye that sees them.
    pub fn pending_merges(&self) -> usize {
        self.objects.iter().map(|s| s.pending.iter().filter(|&&p| p).count()).sum()
    }

    /// Merges every vertex whose merge waits, whichever way it faces (for reading all merged
    /// cuts with [`Frame::merged`]). Returns how many.
    pub fn merge_pending(&mut self) -> Result<usize, FrameError> {
        if self.pending_merges() == 0 {
            return Ok(0);
        }
        let defer = std::mem::replace(&mut self.defer, false);
        let merged = self.rekey(Changed::Nothing, false);
        self.defer = defer;
        merged
    }

    /// Sets the eye later merges and lighting changes build shading lists for (only the
    /// vertices facing it need one; [`Frame::shade`] sets it too) and builds the stale lists of
    /// the vertices facing it now: after a camera turn, so that shading from it again need not
    /// build them each time. Merges the vertices facing it whose merge waits (none unless a
    /// move left some: [`Frame::set_deferred_merges`]); returns how many.
    pub fn set_eye(&mut self, eye: Vec3) -> Result<usize, FrameError> {
        self.eye = Some(eye);
        let waiting = self.objects.iter().any(|s| s.pending.iter().enumerate().any(|(v, &p)| p && s.seen(v, eye)));
        let mut merged = if waiting { self.rekey(Changed::Nothing, false)? } else { 0 };
        for o in 0..self.objects.len() {
            let s = &self.objects[o];
            let which: Vec<bool> =
                s.lists.iter().enumerate().map(|(v, l)| l.stale && !s.pending[v] && s.seen(v, eye)).collect();
            if which.contains(&true) {
                merged += self.relist(o, &which)?;
            }
        }
        Ok(merged)
    }
}
