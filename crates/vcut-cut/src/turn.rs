//! Cuts over a wedged direction tree (`vcut_dirtree::DirectionTree::build_wedged`), shaped so
//! that a turn of the directions by whole wedges is a relabelling.
//!
//! A wedged tree of root height H ([`TurnShape`]) splits first into bands of latitude (nodes of
//! height `band_height` and above: each a union of whole turn orbits, so a turn maps it onto
//! itself), then each band into M wedges (nodes of height `wedge_height` and below lie in one
//! wedge: a turn by `k` wedges moves them `k` wedges on within their band). A node between the
//! two heights spans some wedges of a band but not all, and no node is its turned image, so a
//! turnable cut has none ([`Cut::turnable`]). Such a cut is, band by band, either one node of
//! band height or more, or M runs of nodes one per wedge; turning it rotates each band's runs
//! ([`Cut::turned`]): O(cut size), values untouched, no resampling.

use crate::{Cut, CutError};

/// Heights that describe a wedged tree's turn structure (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TurnShape {
    /// A node this high or lower lies within one wedge.
    pub wedge_height: u32,
    /// A node this high or higher is a union of whole bands (turns map it onto itself).
    pub band_height: u32,
}

impl TurnShape {
    /// Whether a node of height `h` has no turned image (it spans part of a band's wedges).
    pub fn splits(&self, h: u32) -> bool {
        h > self.wedge_height && h < self.band_height
    }

    /// Wedges per band, M.
    pub fn wedges(&self) -> u64 {
        1u64 << (self.band_height - self.wedge_height)
    }
}

impl Cut {
    /// The cut with every node that has no turned image replaced by its descendants of wedge
    /// height, each with the node's value: the same function of the leaves, exactly.
    pub fn turnable(self, shape: TurnShape) -> Cut {
        if !self.heights.iter().any(|&h| shape.splits(u32::from(h))) {
            return self;
        }
        let (mut heights, mut values) = (Vec::with_capacity(self.len()), Vec::with_capacity(self.len()));
        for (&h, &v) in self.heights.iter().zip(&self.values) {
            let h = u32::from(h);
            let (h_out, copies) =
                if shape.splits(h) { (shape.wedge_height, 1usize << (h - shape.wedge_height)) } else { (h, 1) };
            heights.extend(std::iter::repeat_n(h_out as u8, copies));
            values.extend(std::iter::repeat_n(v, copies));
        }
        Cut::from_valid_walk(self.root_height, heights, values)
    }

    /// The cut of the directions turned by `steps` wedges (see the module docs). An error if a
    /// node has no turned image ([`TurnShape::splits`]).
    pub fn turned(&self, shape: TurnShape, steps: u32) -> Result<Cut, CutError> {
        if let Some(node) = self.heights.iter().position(|&h| shape.splits(u32::from(h))) {
            return Err(CutError::AboveWedges { node, height: self.heights[node], wedge_height: shape.wedge_height });
        }
        let k = u64::from(steps) % shape.wedges();
        if k == 0 {
            return Ok(self.clone());
        }
        let (mut heights, mut values) = (Vec::with_capacity(self.len()), Vec::with_capacity(self.len()));
        let offsets: Vec<u64> = self.offsets().collect();
        let mut i = 0;
        while i < self.len() {
            if u32::from(self.heights[i]) >= shape.band_height {
                heights.push(self.heights[i]);
                values.push(self.values[i]);
                i += 1;
                continue;
            }
            // The band's nodes, all within wedges: its last k wedges' nodes come first.
            let band_start = offsets[i];
            let band_end = band_start + (1u64 << shape.band_height);
            let end = offsets[i..].iter().position(|&o| o >= band_end).map_or(self.len(), |p| i + p);
            let split_leaf = band_start + ((shape.wedges() - k) << shape.wedge_height);
            let at = i + offsets[i..end]
                .iter()
                .position(|&o| o == split_leaf)
                .unwrap_or_else(|| unreachable!("every wedge begins a node when no node spans part of a band"));
            for range in [at..end, i..at] {
                heights.extend_from_slice(&self.heights[range.clone()]);
                values.extend_from_slice(&self.values[range]);
            }
            i = end;
        }
        Ok(Cut::from_valid_walk(self.root_height, heights, values))
    }
}

#[cfg(test)]
mod tests {
    use super::TurnShape;
    use crate::Cut;
    use proptest::prelude::*;

    /// A random cut of height `root`: nodes split with probability 2/3.
    fn cut(root: u32) -> impl Strategy<Value = Cut> {
        proptest::collection::vec((0u8..3, 0u8..5), 1usize << root).prop_map(move |bits| {
            let (mut heights, mut values) = (Vec::new(), Vec::new());
            let mut stack = vec![(root, 0usize)];
            while let Some((h, at)) = stack.pop() {
                let (split, v) = bits[at];
                if h > 0 && split > 0 {
                    stack.push((h - 1, at + (1 << (h - 1))));
                    stack.push((h - 1, at));
                } else {
                    heights.push(h as u8);
                    values.push(f32::from(v) / 4.0);
                }
            }
            Cut::new(root, heights, values).unwrap()
        })
    }

    /// A shape of root height 7: wedges of `2^w` leaves, bands of `2^b`.
    fn shape() -> impl Strategy<Value = TurnShape> {
        (0u32..5)
            .prop_flat_map(|w| (Just(w), (w + 1)..8))
            .prop_map(|(w, b)| TurnShape { wedge_height: w, band_height: b })
    }

    proptest! {
        #[test]
        fn turns_relabel_the_leaves_and_m_turns_are_the_identity(c in cut(7), s in shape(), k in 0u32..40) {
            let c = c.turnable(s);
            prop_assert!(c.heights().iter().all(|&h| !s.splits(u32::from(h))));
            let m = s.wedges() as u32;
            let turned = c.turned(s, k).unwrap();
            turned.validate().unwrap();
            // Leaf l of the turned cut is the leaf k wedges back within its band.
            let (a, b) = (c.expand(), turned.expand());
            let (band, wedge) = (1usize << s.band_height, 1usize << s.wedge_height);
            for l in 0..a.len() {
                let start = l / band * band;
                let to = start + (l - start + (k as usize % m as usize) * wedge) % band;
                prop_assert_eq!(b[to], a[l]);
            }
            // Turns compose, and M of them return the cut bit for bit.
            prop_assert_eq!(&turned.turned(s, 3).unwrap(), &c.turned(s, k + 3).unwrap());
            let back = (0..m).fold(c.clone(), |at, _| at.turned(s, 1).unwrap());
            prop_assert_eq!(back, c);
        }

        #[test]
        fn a_turnable_cut_keeps_every_leaf(c in cut(6), s in shape()) {
            let s = TurnShape { band_height: s.band_height.min(6), wedge_height: s.wedge_height.min(5) };
            let t = c.clone().turnable(s);
            t.validate().unwrap();
            prop_assert_eq!(t.expand(), c.expand());
            prop_assert_eq!(t.clone().turnable(s), t);
        }
    }

    #[test]
    fn a_node_spanning_part_of_a_band_has_no_turn() {
        let s = TurnShape { wedge_height: 2, band_height: 4 };
        let c = Cut::new(5, vec![3, 3, 4], vec![1.0, 0.0, 1.0]).unwrap();
        assert_eq!(c.turned(s, 0).unwrap_err(), crate::CutError::AboveWedges { node: 0, height: 3, wedge_height: 2 });
        // The root and band nodes turn onto themselves.
        let c = Cut::new(5, vec![4, 2, 2, 2, 2], vec![0.5, 1.0, 0.0, 0.0, 0.0]).unwrap();
        assert_eq!(c.turned(s, 1).unwrap().values(), &[0.5, 0.0, 1.0, 0.0, 0.0]);
        assert_eq!(Cut::root(5, 1.0).unwrap().turned(s, 3).unwrap(), Cut::root(5, 1.0).unwrap());
    }
}
