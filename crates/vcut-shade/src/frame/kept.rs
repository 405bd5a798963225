//! A merged cut as the frame keeps it between passes, and the nodes a shading list reads.
//!
//! The merge emits each node's height, value and level-order index; the index follows from
//! the heights (a node of height h whose leaves start at l is `(1 << (H − h)) + (l >> h) − 1`,
//! l the leaves of the nodes before it), so the frame keeps heights and values only: 5 bytes
//! per node instead of 9, the same cut bit for bit ([`KeptCut::to_merged`]).

use vcut_cut::level_order_index;
use vcut_merge::MergedCut;

/// A merged cut's nodes left to right as a shading list reads them: heights and values, the
/// level-order index derived from the heights ([`CutNodes::iter`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct CutNodes<'a> {
    pub(super) root_height: u32,
    pub(super) heights: &'a [u8],
    pub(super) values: &'a [f32],
}

impl<'a> From<&'a MergedCut> for CutNodes<'a> {
    fn from(cut: &'a MergedCut) -> Self {
        CutNodes { root_height: cut.root_height, heights: &cut.heights, values: &cut.values }
    }
}

impl<'a> CutNodes<'a> {
    /// Every node as (level-order index, value, height, first leaf).
    #[inline]
    pub(super) fn iter(self) -> impl Iterator<Item = (u32, f32, u32, u32)> + 'a {
        let root = self.root_height;
        self.heights.iter().zip(self.values).scan(0u32, move |leaf, (&h, &v)| {
            let (h, start) = (u32::from(h), *leaf);
            *leaf += 1 << h;
            Some((level_order_index(root, h, start), v, h, start))
        })
    }
}

/// A vertex's merged cut as the frame keeps it: heights and values, 5 bytes per node.
#[derive(Debug, Clone, Default)]
pub(super) struct KeptCut {
    root_height: u32,
    heights: Vec<u8>,
    values: Vec<f32>,
}

impl KeptCut {
    /// Keeps `cut` here, reusing the buffers.
    pub(super) fn keep(&mut self, cut: &MergedCut) {
        self.root_height = cut.root_height;
        self.heights.clear();
        self.heights.extend_from_slice(&cut.heights);
        self.values.clear();
        self.values.extend_from_slice(&cut.values);
    }

    /// The nodes, for a shading list.
    pub(super) fn nodes(&self) -> CutNodes<'_> {
        CutNodes { root_height: self.root_height, heights: &self.heights, values: &self.values }
    }

    /// The merged cut kept, its indices derived again.
    pub(super) fn to_merged(&self) -> MergedCut {
        let indices = self.nodes().iter().map(|(k, ..)| k).collect();
        MergedCut { root_height: self.root_height, heights: self.heights.clone(), values: self.values.clone(), indices }
    }

    /// Nodes kept.
    pub(super) fn len(&self) -> usize {
        self.heights.len()
    }

    /// Bytes held (the buffers' capacities and the struct).
    pub(super) fn bytes(&self) -> usize {
        size_of::<KeptCut>() + self.heights.capacity() + size_of::<f32>() * self.values.capacity()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vcut_merge::merge_product;

    #[test]
    fn a_kept_cut_gives_back_the_merged_cut_bit_for_bit() {
        // Two cuts of a height-4 tree whose product has nodes of every height from 0 to 3.
        let a = vcut_cut::Cut::new(4, vec![3, 2, 1, 0, 0], vec![0.5, 1.0, 0.25, 0.0, 1.0]).unwrap();
        let b = vcut_cut::Cut::new(4, vec![2, 2, 3], vec![1.0, 0.75, 0.5]).unwrap();
        let mut out = MergedCut::default();
        merge_product(&[&a, &b], &mut out).unwrap();
        assert!(out.heights.len() > 3, "a product of several nodes: {:?}", out.heights);
        let mut kept = KeptCut::default();
        kept.keep(&out);
        assert_eq!(kept.len(), out.heights.len());
        let back = kept.to_merged();
        assert_eq!(back.indices, out.indices, "indices derived from the heights");
        assert_eq!(back.heights, out.heights);
        assert_eq!(
            back.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            out.values.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(back.root_height, out.root_height);
        let firsts: Vec<u32> = kept.nodes().iter().map(|(.., leaf)| leaf).collect();
        assert_eq!(firsts, vec![0, 4, 8, 12, 14, 15], "each node's first leaf");
        assert!(kept.bytes() - size_of::<KeptCut>() < 9 * out.heights.len(), "fewer bytes than the merge's 9 per node");
    }
}
