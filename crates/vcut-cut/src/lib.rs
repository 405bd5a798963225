//! Visibility cuts and their codecs.
//!
//! A [`Cut`] is the list of direction-tree nodes, left to right, that cover every leaf exactly
//! once, each with a height (0 = leaf) and a value. Because every node sits on exactly one
//! root-to-leaf path, the heights alone locate every node: node j starts at leaf
//! Σ_{i<j} 2^{h_i}, and its level-order index is `2^(H−h) + offset/2^h − 1`.
//!
//! Codecs ([`codec`]):
//! - **height codec** (the paper's): heights packed in 4 bits while the root height H ≤ 15, in 5
//!   bits above (65,536 leaves have heights 0..=16), then the values as f32, f16, u16 or u8
//!   ([`ValueFormat`], each with a documented maximum error);
//! - **index baseline** (Akerlund 2007 / Cheslack-Postava 2008): each node's level-order index
//!   (u16 while 2N−1 fits, u32 above) followed by its f32 value.
//!
//! Selection ([`select`]): the cut of leaf values by the paper's top-down split on the node
//! error `E_k` (eq. 4) and solid angle.
//!
//! # Invariants
//! Heights ≤ H; Σ 2^{h_i} = 2^H; every node starts at a multiple of its own size (so it is a
//! node of the tree); values are finite. Constructors check all of it; [`Cut::validate`] re-checks
//! for tests. This crate knows nothing about rays, scenes or shading.
//!
//! # Example
//! ```
//! use vcut_cut::{Cut, codec::{self, ValueFormat}};
//! // H = 2 (4 leaves): a height-1 node over leaves 0..2, then two leaves.
//! let cut = Cut::new(2, vec![1, 0, 0], vec![0.5, 1.0, 0.0]).unwrap();
//! assert_eq!(cut.expand(), vec![0.5, 0.5, 1.0, 0.0]);
//! assert_eq!(cut.level_order_indices().collect::<Vec<_>>(), vec![1, 5, 6]);
//! let bytes = codec::encode_heights(&cut, ValueFormat::F32).unwrap();
//! assert_eq!(codec::decode_heights(&bytes, 2, ValueFormat::F32).unwrap(), cut);
//! ```

pub mod codec;
pub mod select;
pub mod turn;

pub use codec::ValueFormat;

/// Level-order index of the node of height `h` whose first leaf is `offset`, in a tree of root
/// height `root_height`: `2^(H−h) + offset/2^h − 1`.
#[inline]
pub fn level_order_index(root_height: u32, h: u32, offset: u32) -> u32 {
    (1u32 << (root_height - h)) + (offset >> h) - 1
}

/// `(height, first leaf offset)` of a level-order index ([`level_order_index`]'s inverse).
#[inline]
pub fn node_of_index(root_height: u32, index: u32) -> (u32, u32) {
    let depth = 31 - (index + 1).leading_zeros();
    let h = root_height - depth;
    let offset = ((index + 1) - (1u32 << depth)) << h;
    (h, offset)
}

/// Largest root height supported (2^24 leaves).
pub const MAX_ROOT_HEIGHT: u32 = 24;

/// Why a cut is invalid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CutError {
    /// Root height beyond [`MAX_ROOT_HEIGHT`].
    #[error("root height {0} exceeds {MAX_ROOT_HEIGHT}")]
    RootHeight(u32),
    /// Heights and values differ in length.
    #[error("{heights} heights but {values} values")]
    Lengths {
        /// Heights given.
        heights: usize,
        /// Values given.
        values: usize,
    },
    /// A node higher than the root.
    #[error("node {node} has height {height} above the root height {root}")]
    TooHigh {
        /// Node position in the cut.
        node: usize,
        /// Its height.
        height: u8,
        /// Root height.
        root: u32,
    },
    /// A node that does not start at a multiple of its size is not a tree node.
    #[error("node {node} (height {height}) starts at leaf {offset}, not a multiple of {}", 1u64 << height)]
    Misaligned {
        /// Node position in the cut.
        node: usize,
        /// Its height.
        height: u8,
        /// Its first leaf.
        offset: u64,
    },
    /// The nodes do not cover exactly 2^H leaves.
    #[error("the nodes cover {covered} leaves, the tree has {leaves}")]
    Coverage {
        /// Leaves covered.
        covered: u64,
        /// Leaves in the tree.
        leaves: u64,
    },
    /// A node spanning part of a band's wedges in a wedged tree: it has no turned image.
    #[error(
        "node {node} (height {height}) spans part of a band's wedges (a wedge's nodes are at most {wedge_height} high): it has no turned image"
    )]
    AboveWedges {
        /// Node position in the cut.
        node: usize,
        /// Its height.
        height: u8,
        /// The wedges' height.
        wedge_height: u32,
    },
    /// A NaN or infinite value.
    #[error("node {node} has a non-finite value")]
    Value {
        /// Node position in the cut.
        node: usize,
    },
}

/// A cut of the direction tree of root height `H`: nodes left to right with heights and values.
#[derive(Debug, Clone, PartialEq)]
pub struct Cut {
    root_height: u32,
    heights: Vec<u8>,
    values: Vec<f32>,
}

impl Cut {
    /// A checked cut (see the crate invariants).
    pub fn new(root_height: u32, heights: Vec<u8>, values: Vec<f32>) -> Result<Cut, CutError> {
        check(root_height, &heights, &values)?;
        Ok(Cut { root_height, heights, values })
    }

    /// A cut whose shape a decoder's top-down walk produced (valid by construction) and whose
    /// values it checked: the checks [`Cut::new`] makes, re-made in debug builds only.
    pub(crate) fn from_valid_walk(root_height: u32, heights: Vec<u8>, values: Vec<f32>) -> Cut {
        debug_assert_eq!(check(root_height, &heights, &values), Ok(()));
        Cut { root_height, heights, values }
    }

    /// The one-node cut: the root with `value` (e.g. "all visible").
    pub fn root(root_height: u32, value: f32) -> Result<Cut, CutError> {
        Cut::new(root_height, vec![root_height as u8], vec![value])
    }

    /// The finest cut: every leaf with its value.
    pub fn from_leaves(root_height: u32, values: Vec<f32>) -> Result<Cut, CutError> {
        Cut::new(root_height, vec![0; values.len()], values)
    }

    /// Root height H.
    pub fn root_height(&self) -> u32 {
        self.root_height
    }

    /// Node heights, left to right.
    pub fn heights(&self) -> &[u8] {
        &self.heights
    }

    /// Node values, left to right.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.heights.len()
    }

    /// Never true: a cut covers at least the root.
    pub fn is_empty(&self) -> bool {
        self.heights.is_empty()
    }

    /// First leaf of every node.
    pub fn offsets(&self) -> impl Iterator<Item = u64> + '_ {
        self.heights.iter().scan(0u64, |at, &h| {
            let start = *at;
            *at += 1u64 << h;
            Some(start)
        })
    }

    /// Level-order index `2^(H−h) + offset/2^h − 1` of every node.
    pub fn level_order_indices(&self) -> impl Iterator<Item = u32> + '_ {
        let root = self.root_height;
        self.heights
            .iter()
            .zip(self.offsets())
            // Checked cuts have at most 2^24 leaves: every offset fits in u32.
            .map(move |(&h, off)| level_order_index(root, u32::from(h), off as u32))
    }

    /// The value at every leaf (2^H entries).
    pub fn expand(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(1usize << self.root_height);
        for (&h, &v) in self.heights.iter().zip(&self.values) {
            out.extend(std::iter::repeat_n(v, 1usize << h));
        }
        out
    }

    /// Re-checks every invariant (for tests).
    pub fn validate(&self) -> Result<(), CutError> {
        check(self.root_height, &self.heights, &self.values)
    }

    /// Mutable values (heights stay fixed, so the cut stays valid; values must stay finite).
    pub fn values_mut(&mut self) -> &mut [f32] {
        &mut self.values
    }

    /// The cut's heights and values, as buffers to build the next cut in (a caller that makes
    /// many cuts in turn reuses them instead of allocating).
    ///
    /// ```
    /// use vcut_cut::Cut;
    /// let cut = Cut::new(1, vec![0, 0], vec![1.0, 0.0]).unwrap();
    /// let (mut heights, mut values) = cut.into_parts();
    /// assert_eq!((&heights[..], &values[..]), (&[0u8, 0][..], &[1.0f32, 0.0][..]));
    /// (heights.clear(), values.clear());
    /// heights.push(1);
    /// values.push(0.5);
    /// assert_eq!(Cut::new(1, heights, values).unwrap(), Cut::root(1, 0.5).unwrap());
    /// ```
    pub fn into_parts(self) -> (Vec<u8>, Vec<f32>) {
        (self.heights, self.values)
    }
}

fn check(root: u32, heights: &[u8], values: &[f32]) -> Result<(), CutError> {
    if root > MAX_ROOT_HEIGHT {
        return Err(CutError::RootHeight(root));
    }
    if heights.len() != values.len() {
        return Err(CutError::Lengths { heights: heights.len(), values: values.len() });
    }
    let leaves = 1u64 << root;
    let mut at = 0u64;
    for (node, &h) in heights.iter().enumerate() {
        if u32::from(h) > root {
            return Err(CutError::TooHigh { node, height: h, root });
        }
        if !at.is_multiple_of(1u64 << h) {
            return Err(CutError::Misaligned { node, height: h, offset: at });
        }
        at += 1u64 << h;
        if at > leaves {
            return Err(CutError::Coverage { covered: at, leaves });
        }
    }
    if at != leaves {
        return Err(CutError::Coverage { covered: at, leaves });
    }
    if let Some(node) = values.iter().position(|v| !v.is_finite()) {
        return Err(CutError::Value { node });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_invalid_cuts_with_the_reason() {
        assert_eq!(Cut::new(2, vec![1, 0], vec![0.0; 2]).unwrap_err(), CutError::Coverage { covered: 3, leaves: 4 });
        // A height-1 node starting at leaf 1 is not a tree node.
        assert_eq!(
            Cut::new(2, vec![0, 1, 0], vec![0.0; 3]).unwrap_err(),
            CutError::Misaligned { node: 1, height: 1, offset: 1 }
        );
        assert!(matches!(Cut::new(2, vec![3], vec![0.0]), Err(CutError::TooHigh { .. })));
        assert!(matches!(Cut::new(1, vec![0, 0], vec![0.0, f32::NAN]), Err(CutError::Value { node: 1 })));
        assert!(matches!(Cut::new(1, vec![0, 0], vec![0.0]), Err(CutError::Lengths { .. })));
    }

    #[test]
    fn sixteen_is_a_valid_root_height() {
        let c = Cut::new(16, vec![15, 14, 14], vec![1.0, 0.5, 0.0]).unwrap();
        assert_eq!(c.level_order_indices().collect::<Vec<_>>(), vec![1, 5, 6]);
        assert_eq!(Cut::root(16, 1.0).unwrap().level_order_indices().next(), Some(0));
    }
}
