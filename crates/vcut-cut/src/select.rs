//! Cut selection from leaf values (the paper's eq. 4).
//!
//! Per tree node k, with leaf values Ṽ and leaf solid angles a (in leaf order):
//! the mean `v_k = Σ aṼ / Σ a`, the solid angle `|Ω_k| = Σ a`, and the error
//! `E_k = (1/|Ω_k|) ∫_{Ω_k} (v_k − Ṽ)² dω = Σ aṼ²/Σ a − v_k²` (an area-weighted variance).
//! From the root, every node whose error exceeds `max_error` or whose solid angle exceeds
//! `max_solid_angle` is split; the nodes left form the cut. A node whose leaves are all zero is
//! never split for its solid angle (it contributes nothing whatever the BRDF does across it).
//! Every node without a turned image is split, whatever its error (the cut of a wedged tree).
//!
//! Fields: the paper asks for no solid-angle limit and an error threshold "below 0.25, so that
//! only regions of equal V_n merge". Read literally (a threshold just under 0.25, the variance of
//! an even 0/1 split), a node that is 90 % visible has variance 0.09 and would merge, erasing
//! every shadow smaller than half a node; so [`SelectParams::field`] takes the stated intent:
//! threshold 0, only leaves of equal visibility merge, the field cut is exact and its values
//! are 0 or 1. Thresholds between 0 and 0.25 trade exactness for size and stay available.
//!
//! Sums are taken bottom-up in f64, so a node's statistics are exact for its leaves.

use crate::turn::TurnShape;
use crate::{Cut, CutError};

/// Thresholds of [`select`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelectParams {
    /// Split nodes whose error E_k is above this.
    pub max_error: f64,
    /// Split nodes whose solid angle is above this (steradians; `f64::INFINITY` for none).
    pub max_solid_angle: f64,
    /// A wedged tree's shape: split every node that has no turned image, so the cut can turn
    /// ([`crate::turn`]; `None` for an ordinary tree).
    pub turn: Option<TurnShape>,
}

impl SelectParams {
    /// The visibility-cut-field setting: no solid-angle limit and error threshold 0, so only
    /// leaves of equal visibility merge (see the module docs for why not 0.2499).
    pub fn field() -> Self {
        Self { max_error: 0.0, max_solid_angle: f64::INFINITY, turn: None }
    }
}

/// Per-node statistics in level order (`2N − 1` entries): (Σa, Σaṽ, Σaṽ²).
pub fn node_sums(leaf_values: &[f32], leaf_solid_angles: &[f64]) -> Vec<[f64; 3]> {
    let mut sums = Vec::new();
    node_sums_into(leaf_values, leaf_solid_angles, &mut sums);
    sums
}

/// [`node_sums`] into a reused buffer.
fn node_sums_into(leaf_values: &[f32], leaf_solid_angles: &[f64], sums: &mut Vec<[f64; 3]>) {
    let n = leaf_values.len();
    sums.clear();
    sums.resize(2 * n - 1, [0.0; 3]);
    for (i, (&v, &a)) in leaf_values.iter().zip(leaf_solid_angles).enumerate() {
        let v = f64::from(v);
        sums[n - 1 + i] = [a, a * v, a * v * v];
    }
    for k in (0..n - 1).rev() {
        let (l, r) = (sums[2 * k + 1], sums[2 * k + 2]);
        sums[k] = [l[0] + r[0], l[1] + r[1], l[2] + r[2]];
    }
}

/// Selects the cut of leaf values `leaf_values` (2^H of them, leaf order) with leaf solid angles
/// `leaf_solid_angles`. Values of the cut are the nodes' area-weighted means.
pub fn select(leaf_values: &[f32], leaf_solid_angles: &[f64], params: SelectParams) -> Result<Cut, CutError> {
    Selector::default().select(leaf_values, leaf_solid_angles, params)
}

/// [`select`] with its node statistics buffer kept between calls (one per worker thread: a
/// 32,768-leaf tree needs 1.5 MB of sums per cut).
#[derive(Debug, Default, Clone)]
pub struct Selector {
    sums: Vec<[f64; 3]>,
}

impl Selector {
    /// As [`select`].
    pub fn select(
        &mut self,
        leaf_values: &[f32],
        leaf_solid_angles: &[f64],
        params: SelectParams,
    ) -> Result<Cut, CutError> {
        select_with(leaf_values, leaf_solid_angles, params, &mut self.sums)
    }
}

fn select_with(
    leaf_values: &[f32],
    leaf_solid_angles: &[f64],
    params: SelectParams,
    sums: &mut Vec<[f64; 3]>,
) -> Result<Cut, CutError> {
    let n = leaf_values.len();
    if n == 0 || !n.is_power_of_two() || leaf_solid_angles.len() != n {
        return Err(CutError::Coverage { covered: leaf_solid_angles.len() as u64, leaves: n as u64 });
    }
    let root_height = n.trailing_zeros();
    node_sums_into(leaf_values, leaf_solid_angles, sums);
    let mut heights = Vec::new();
    let mut values = Vec::new();
    // Depth-first, left to right: a stack of (index, height), right child pushed first.
    let mut stack = vec![(0usize, root_height)];
    while let Some((k, h)) = stack.pop() {
        let [s0, s1, s2] = sums[k];
        let mean = if s0 > 0.0 { s1 / s0 } else { 0.0 };
        let error = if s0 > 0.0 { (s2 / s0 - mean * mean).max(0.0) } else { 0.0 };
        if h > 0
            && (error > params.max_error
                || (s0 > params.max_solid_angle && s2 > 0.0)
                || params.turn.is_some_and(|t| t.splits(h)))
        {
            stack.push((2 * k + 2, h - 1));
            stack.push((2 * k + 1, h - 1));
        } else {
            heights.push(h as u8);
            values.push(mean as f32);
        }
    }
    Cut::new(root_height, heights, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_visibility_is_one_node_and_a_step_splits_once() {
        let a = vec![0.5f64; 8];
        let c = select(&[1.0; 8], &a, SelectParams::field()).unwrap();
        assert_eq!((c.heights(), c.values()), (&[3u8][..], &[1.0f32][..]));
        // Half visible: one split, into the two constant halves.
        let c = select(&[1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0], &a, SelectParams::field()).unwrap();
        assert_eq!((c.heights(), c.values()), (&[2u8, 2][..], &[1.0f32, 0.0][..]));
        // One occluded leaf in eight: exact, the field keeps it (a threshold of 0.2499 would not).
        let c = select(&[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0], &a, SelectParams::field()).unwrap();
        assert_eq!((c.heights(), c.values()), (&[2u8, 1, 0, 0][..], &[1.0f32, 1.0, 1.0, 0.0][..]));
        let c = select(
            &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0],
            &a,
            SelectParams { max_error: 0.2499, ..SelectParams::field() },
        )
        .unwrap();
        assert_eq!(c.len(), 1);
        // Zero regions are not split for their solid angle.
        let c = select(
            &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
            &a,
            SelectParams { max_error: 1.0, max_solid_angle: 1.0, turn: None },
        )
        .unwrap();
        assert_eq!(c.heights(), &[2, 1, 1]);
        // A solid-angle limit splits even constant regions.
        let c = select(&[1.0; 8], &a, SelectParams { max_error: 1.0, max_solid_angle: 1.0, turn: None }).unwrap();
        assert_eq!(c.heights(), &[1, 1, 1, 1]);
    }

    #[test]
    fn thresholds_loosening_never_grow_the_cut() {
        let n = 1024;
        let values: Vec<f32> =
            (0..n).map(|i| ((i * 7919) % 1000) as f32 / 1000.0 * if i % 64 < 20 { 0.0 } else { 1.0 }).collect();
        let areas: Vec<f64> =
            (0..n).map(|i| 4.0 * std::f64::consts::PI / n as f64 * (1.0 + 0.1 * ((i % 3) as f64 - 1.0))).collect();
        let mut last = usize::MAX;
        for e in [0.0, 0.001, 0.01, 0.05, 0.1, 0.2, 0.3] {
            let c = select(&values, &areas, SelectParams { max_error: e, ..SelectParams::field() }).unwrap();
            c.validate().unwrap();
            assert!(c.len() <= last, "error {e}: {} nodes after {last}", c.len());
            last = c.len();
            // The cut's area-weighted mean equals the leaves' (means are exact per node).
            let total: f64 = values.iter().zip(&areas).map(|(v, a)| f64::from(*v) * a).sum();
            let mut at = 0usize;
            let mut cut_total = 0.0;
            for (&h, &v) in c.heights().iter().zip(c.values()) {
                let a: f64 = areas[at..at + (1 << h)].iter().sum();
                cut_total += f64::from(v) * a;
                at += 1 << h;
            }
            assert!((cut_total - total).abs() < 1e-5 * total.abs().max(1.0));
        }
        assert!(select(&values, &areas, SelectParams::field()).unwrap().len() > 100);
    }
}
