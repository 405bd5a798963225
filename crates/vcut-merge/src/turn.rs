//! Prepared groups turned by whole wedges of a wedged tree (`vcut_cut::turn`): the same
//! relabelling as [`vcut_cut::Cut::turned`], done on a prepared group's nodes, so a frame turns
//! an object's prepared SVCs without decoding them again. A group turned by `k` equals the
//! group of its cuts turned by `k`, bit for bit (tested), and turns compose: turning by `a`
//! then by `b` is turning by `a + b`.

use crate::prepared::Prepared;
use crate::refined::Refinement;
use vcut_cut::turn::TurnShape;

/// Why a prepared group cannot turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum TurnError {
    /// A node spans part of a band's wedges (its height between the wedge and the band
    /// heights): it has no turned image.
    #[error("node {node} (height {height}) spans part of a band's wedges: it has no turned image")]
    AboveWedges {
        /// The node's index.
        node: usize,
        /// Its height.
        height: u32,
    },
    /// An index-coded group ([`crate::Algorithm::Index`]): prepare the turned cuts instead.
    #[error("an index-coded group does not turn; prepare the turned cuts instead")]
    Indexed,
}

impl Prepared {
    /// The group turned by `steps` wedges of `shape` (only the counter merge's refinements
    /// turn: [`TurnError::Indexed`] for the index baseline's).
    pub fn turned(&self, shape: TurnShape, steps: u32) -> Result<Prepared, TurnError> {
        let mut turned = self.clone();
        turned.turn(shape, steps)?;
        Ok(turned)
    }

    /// [`Prepared::turned`] in place (left as it was on an error).
    pub fn turn(&mut self, shape: TurnShape, steps: u32) -> Result<(), TurnError> {
        match self {
            Prepared::Refined(r) => r.turn(shape, steps),
            Prepared::Indexed(_) => Err(TurnError::Indexed),
        }
    }
}

impl Refinement {
    /// The refinement turned by `steps` wedges of `shape`: within each band, the nodes of its
    /// last `k` wedges (k = steps mod M) come first; every node keeps its values, masks and
    /// non-zero flag.
    pub fn turned(&self, shape: TurnShape, steps: u32) -> Result<Refinement, TurnError> {
        let mut turned = self.clone();
        turned.turn(shape, steps)?;
        Ok(turned)
    }

    /// [`Refinement::turned`] in place: each band's nodes rotated, O(nodes) with no allocation
    /// (left as it was on an error).
    pub fn turn(&mut self, shape: TurnShape, steps: u32) -> Result<(), TurnError> {
        let n = self.ends.len();
        if let Some(node) = (0..n).find(|&i| shape.splits(self.height(i))) {
            return Err(TurnError::AboveWedges { node, height: self.height(node) });
        }
        let k = u64::from(steps) % shape.wedges();
        let per_node = if self.values.is_empty() { 0 } else { self.values.len() / n.max(1) };
        let mut i = 0;
        while i < n && k != 0 {
            let start = self.start(i);
            if self.height(i) >= shape.band_height {
                // A whole band (or more) turns onto itself.
                i += 1;
                continue;
            }
            // The band's nodes, each within a wedge: those from the split leaf on come first.
            let band_end = u64::from(start) + (1u64 << shape.band_height);
            let end = i + self.ends[i..].partition_point(|&e| u64::from(e) < band_end) + 1;
            let split_leaf = u64::from(start) + ((shape.wedges() - k) << shape.wedge_height);
            let at = i + self.ends[i..end].partition_point(|&e| u64::from(e) <= split_leaf);
            let moved = end - at;
            // Ends to sizes, rotated, and back to ends from the band's start.
            let mut prev = start;
            for e in &mut self.ends[i..end] {
                (*e, prev) = (*e - prev, *e);
            }
            self.ends[i..end].rotate_right(moved);
            let mut end_leaf = start;
            for e in &mut self.ends[i..end] {
                end_leaf += *e;
                *e = end_leaf;
            }
            self.values[i * per_node..end * per_node].rotate_right(moved * per_node);
            if !self.masks.is_empty() {
                self.masks[i..end].rotate_right(moved);
            }
            if !self.nonzero.is_empty() {
                self.nonzero[i..end].rotate_right(moved);
            }
            i = end;
        }
        Ok(())
    }

    /// The leaf where node `i` starts.
    fn start(&self, i: usize) -> u32 {
        if i == 0 { 0 } else { self.ends[i - 1] }
    }

    /// The height of node `i`.
    fn height(&self, i: usize) -> u32 {
        (self.ends[i] - self.start(i)).trailing_zeros()
    }
}
