//! Shading lists: per tree node what shading reads (the shading table), and per vertex the
//! nodes of its merged cut that can reflect light with their weights and the diffuse sum — and
//! the specular sums over them.

use super::kept::CutNodes;
use crate::brdf;
use crate::sun;
use glam::Vec3;
use vcut_dirtree::DirectionTree;
use vcut_lighttree::LightTree;

/// Blinn-Phong's power argument n·ĥ, ĥ = (ω + wo)/|ω + wo|, as [`brdf::Lobe::eval`] forms it.
pub(super) fn blinn_phong_argument(n: Vec3, wo: Vec3) -> impl Fn([f32; 3]) -> f32 {
    move |d| {
        let s = Vec3::from(d) + wo;
        n.dot(s) / s.length()
    }
}

/// Phong's power argument r_o·ω (r_o: wo mirrored about the normal).
pub(super) fn phong_argument(mirror: Vec3) -> impl Fn([f32; 3]) -> f32 {
    move |d| mirror.dot(Vec3::from(d))
}

/// What the specular loop reads of one tree node: Ê_k and l_k.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(32))]
pub(super) struct SpecularNode {
    pub(super) dir: Vec3,
    pub(super) light: Vec3,
}

pub(super) fn specular_nodes(nodes: &[ShadeNode]) -> Vec<SpecularNode> {
    nodes.iter().map(|n| SpecularNode { dir: n.dir, light: n.light }).collect()
}

/// What shading needs of one tree node, in one cache line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
pub(super) struct ShadeNode {
    /// Ê_k: the node's light-weighted mean direction, normalised (its plain mean direction when
    /// the node holds no light).
    pub(super) dir: Vec3,
    /// l_k, the node's light (RGB). Beside `dir`: the specular loop reads these two only.
    pub(super) light: Vec3,
    /// E_k: the light-weighted mean of the leaf directions (not normalised).
    pub(super) centroid: Vec3,
    /// m_k: the plain mean of the leaf directions (not normalised).
    pub(super) mean: Vec3,
    /// Axis of the node's bounding cone.
    pub(super) axis: Vec3,
    /// Sine of the cone's half-angle (2 when the cone exceeds a hemisphere): the node lies
    /// wholly above the horizon of `n` when `n·axis ≥ sin_half`.
    pub(super) sin_half: f32,
}

/// The shading table of every node (level order) under `light`.
pub(super) fn shade_nodes(tree: &DirectionTree, light: &LightTree) -> Vec<ShadeNode> {
    let leaves = tree.leaf_directions();
    // Sums over leaves, bottom-up in level order (children of k are 2k+1, 2k+2).
    let count = tree.node_count();
    let first_leaf = count - leaves.len();
    let mut plain = vec![glam::DVec3::ZERO; count];
    let mut weighted = vec![glam::DVec3::ZERO; count];
    let mut total = vec![0.0f64; count];
    for (l, d) in leaves.iter().enumerate() {
        let y = sun::luminance(light.leaves()[l]).max(0.0);
        plain[first_leaf + l] = d.as_dvec3();
        weighted[first_leaf + l] = d.as_dvec3() * y;
        total[first_leaf + l] = y;
    }
    for k in (0..first_leaf).rev() {
        plain[k] = plain[2 * k + 1] + plain[2 * k + 2];
        weighted[k] = weighted[2 * k + 1] + weighted[2 * k + 2];
        total[k] = total[2 * k + 1] + total[2 * k + 2];
    }
    (0..count)
        .map(|k| {
            let n = tree.leaf_range(k as u32).len() as f64;
            let mean = (plain[k] / n).as_vec3();
            let centroid = if total[k] > 0.0 { (weighted[k] / total[k]).as_vec3() } else { mean };
            let cone = tree.cone(k as u32);
            let c = cone.cos_half_angle;
            ShadeNode {
                dir: centroid.try_normalize().unwrap_or(tree.mean_directions()[k]),
                centroid,
                mean,
                axis: cone.axis,
                sin_half: if c < 0.0 { 2.0 } else { (1.0 - c * c).max(0.0).sqrt() },
                light: Vec3::from(light.node_f32(k as u32)),
            }
        })
        .collect()
}

/// A vertex's shading list: the nodes that can reflect light (see the module documentation),
/// their weights, and the diffuse sum Σ weight·l_k.
///
/// Each entry is one `u32` ([`pack`]): the node's level-order index in 17 bits (a tree of at
/// most 65,536 directions has 131,071 nodes) and its weight as a half float without sign bit
/// (10 mantissa bits: relative rounding error ≤ 2⁻¹¹; weights below 2⁻¹⁴ — a node that
/// adds under 0.006 % of a fully visible one's light — are left out). The diffuse sum is
/// formed from the unrounded weights.
#[derive(Debug, Clone, Default)]
pub(super) struct ShadeList {
    pub(super) entries: Vec<u32>,
    pub(super) diffuse: Vec3,
    /// Not built since the vertex's last merge or lighting change (empty meanwhile).
    pub(super) stale: bool,
}

/// Bits of an entry's weight ([`ShadeList`]).
const WEIGHT_BITS: u32 = 15;
/// Nodes a list entry can name.
pub(super) const MAX_NODES: usize = 1 << (32 - WEIGHT_BITS);
/// 2⁻¹¹² and 2¹¹²: between an f32 and a half float's exponent bias (15 against 127).
const TO_HALF: f32 = 1.0 / (1u128 << 112) as f32;
const FROM_HALF: f32 = (1u128 << 112) as f32;
/// Smallest weight kept (the smallest normal half float).
const MIN_WEIGHT: f32 = 1.0 / (1 << 14) as f32;

/// The entry of node `k` with weight `w` (≥ [`MIN_WEIGHT`]): rounded to nearest.
#[inline]
pub(super) fn pack(k: u32, w: f32) -> u32 {
    let bits = (w.min(65_504.0) * TO_HALF).to_bits();
    (k << WEIGHT_BITS) | ((bits + 0x1000) >> 13)
}

/// The node and weight of an entry.
#[inline]
pub(super) fn unpack(e: u32) -> (usize, f32) {
    ((e >> WEIGHT_BITS) as usize, f32::from_bits((e & ((1 << WEIGHT_BITS) - 1)) << 13) * FROM_HALF)
}

impl ShadeList {
    /// The list of merged cut `cut` at normal `n` (`svc`: see [`ShadeList::rebuild`]).
    pub(super) fn new(cut: CutNodes<'_>, n: Vec3, table: &[ShadeNode], svc: Option<&[u32]>) -> ShadeList {
        let mut list = ShadeList::default();
        list.rebuild(cut, n, table, svc, &mut Vec::new());
        list
    }

    /// Makes this the list of `cut` at `n`, reusing its buffers: the nodes that can reflect
    /// light (non-zero, above the horizon of `n`) with their weights, and Σ weight·l_k.
    ///
    /// `svc`: the node ends (leaves) of the vertex's SVC when `cut` is a product with it (a
    /// frame's merge): a node inside a larger SVC node A wholly above the horizon then takes its
    /// visibility as `v_k / (n·m_A)` — the SVC's value is A's mean of V·(n·ω), not the node's
    /// (see the module documentation). `None`: every value is its own node's mean.
    /// `scratch` holds each packed node's value and n·m_A (0: use its own).
    ///
    /// Two passes without data-dependent branches: the non-zero nodes are packed first, then
    /// every packed node's table entry is read and the node kept or dropped by arithmetic, so
    /// the table reads (the cost: scattered over the tree's levels) are independent of each
    /// other and overlap instead of waiting on mispredicted branches.
    pub(super) fn rebuild(
        &mut self,
        cut: CutNodes<'_>,
        n: Vec3,
        table: &[ShadeNode],
        svc: Option<&[u32]>,
        scratch: &mut Vec<[f32; 2]>,
    ) {
        // Sized by the non-zero nodes (a list is kept per vertex: no room for the zero ones).
        let len = cut.values.iter().filter(|&&v| v != 0.0).count();
        self.entries.resize(len, 0);
        scratch.clear();
        scratch.resize(len, [0.0; 2]);
        let mut packed = 0;
        match svc {
            None => {
                for (k, v, ..) in cut.iter() {
                    // The last zero nodes write past the non-zero ones: into the spare slot, if any.
                    if packed < len {
                        self.entries[packed] = k;
                        scratch[packed] = [v, 0.0];
                    }
                    packed += usize::from(v != 0.0);
                }
            }
            Some(ends) => {
                let root = cut.root_height;
                // The SVC node around the current one: its end and n·m (0 unless wholly above).
                let (mut j, mut a_end, mut a_below) = (0usize, 0u32, 0.0f32);
                for (k, v, h, leaf) in cut.iter() {
                    let end = leaf + (1u32 << h);
                    if end > a_end {
                        while ends[j] < end {
                            j += 1;
                        }
                        let a_start = if j == 0 { 0 } else { ends[j - 1] };
                        a_end = ends[j];
                        let ha = (a_end - a_start).trailing_zeros();
                        let a = &table[(1usize << (root - ha)) + (a_start >> ha) as usize - 1];
                        let below = n.dot(a.mean);
                        a_below = if n.dot(a.axis) >= a.sin_half && below > 1e-6 { below } else { 0.0 };
                    }
                    if packed < len {
                        self.entries[packed] = k;
                        scratch[packed] = [v, a_below];
                    }
                    packed += usize::from(v != 0.0);
                }
            }
        }
        let mut kept = 0;
        let mut diffuse = Vec3::ZERO;
        for i in 0..packed {
            let (k, [v, a_below]) = (self.entries[i], scratch[i]);
            let node = &table[k as usize];
            let keep = n.dot(node.dir) > 0.0;
            let below = n.dot(node.mean);
            let above = n.dot(node.axis) >= node.sin_half && below > 1e-6;
            let w = if a_below > 0.0 {
                v * n.dot(node.centroid) / a_below
            } else if above {
                v * n.dot(node.centroid) / below
            } else {
                v
            };
            self.entries[kept] = pack(k, w);
            diffuse += if keep { w * node.light } else { Vec3::ZERO };
            kept += usize::from(keep && w >= MIN_WEIGHT);
        }
        self.entries.truncate(kept);
        self.diffuse = diffuse;
        self.stale = false;
    }

    /// Empties the list, keeping its buffers.
    pub(super) fn clear(&mut self) {
        self.entries.clear();
        self.diffuse = Vec3::ZERO;
        self.stale = false;
    }

    /// Empties the list and marks it to be built when a shading needs it.
    pub(super) fn mark_stale(&mut self) {
        self.clear();
        self.stale = true;
    }

    /// Σ weight · lobe(Ê_k) · l_k for a lobe `scale · pow(x_k)` whose argument is a
    /// function of the node direction alone (Blinn-Phong's n·ĥ, Phong's r_o·ω): eight nodes at
    /// a time, their directions and weighted lights gathered into lanes, so the arithmetic runs
    /// on all lanes together and the eight sums never wait on each other.
    #[inline]
    pub(super) fn specular_lanes(
        &self,
        table: &[SpecularNode],
        pow: &brdf::PowTable,
        scale: Vec3,
        argument: impl Fn([f32; 3]) -> f32,
    ) -> Vec3 {
        const L: usize = 8;
        let mut sum = [[0.0f32; L]; 3];
        for es in self.entries.chunks(L) {
            let (mut dir, mut light) = ([[0.0f32; L]; 3], [[0.0f32; L]; 3]);
            for (j, &e) in es.iter().enumerate() {
                let (k, w) = unpack(e);
                let node = &table[k];
                for c in 0..3 {
                    dir[c][j] = node.dir[c];
                    light[c][j] = w * node.light[c];
                }
            }
            let mut x = [0.0f32; L];
            for j in 0..L {
                x[j] = argument([dir[0][j], dir[1][j], dir[2][j]]);
            }
            let p = x.map(|x| pow.get(x));
            // Lanes past the list's end have no light.
            for (sum, light) in sum.iter_mut().zip(&light) {
                for j in 0..L {
                    sum[j] += p[j] * light[j];
                }
            }
        }
        scale * Vec3::new(sum[0].iter().sum(), sum[1].iter().sum(), sum[2].iter().sum())
    }

    /// Σ weight · lobe(Ê_k) · l_k.
    #[inline]
    pub(super) fn specular(&self, table: &[SpecularNode], lobe: impl Fn(Vec3) -> Vec3) -> Vec3 {
        let mut b = Vec3::ZERO;
        for &e in &self.entries {
            let (k, w) = unpack(e);
            let node = &table[k];
            b += w * lobe(node.dir) * node.light;
        }
        b
    }
}
