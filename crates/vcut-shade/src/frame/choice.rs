//! Which leaves of the light leave the cuts for rays: the error each would add through the
//! cuts, estimated at sampled vertices, against the target error ([`crate::sun`] has the rule).

use super::lists::{ShadeList, ShadeNode, shade_nodes, unpack};
use super::object::{MergeState, placed};
use super::{Context, Frame};
use crate::sun::{self, CANDIDATES, SAMPLES, SunRays};
use rayon::prelude::*;
use std::time::Instant;
use vcut_merge::MergedCut;

/// What the last lighting change chose ([`Frame::light_choice`]): the leaves cast by rays, the
/// estimate that chose them, and what casting them cost.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LightChoice {
    /// The target error it was chosen for ([`SunRays::target`]; 0 with sun rays off).
    pub target: f64,
    /// The leaves cast by rays, in the order chosen (each lowered the estimate most).
    pub cast: Vec<u32>,
    /// Leaves whose error was estimated ([`sun::candidates`]).
    pub candidates: usize,
    /// Vertices the estimate sampled.
    pub samples: usize,
    /// The estimated relative L2 error the candidates add through the cuts, none cast.
    pub estimate_cuts: f64,
    /// The same with the cast leaves out of the cuts: at most the target unless the cap (or a
    /// leaf that would not lower it) stopped the choice.
    pub estimate: f64,
    /// Seconds the estimate took (merges, lists and rays at the samples).
    pub estimate_s: f64,
    /// Rays cast for every vertex's masks of the cast leaves.
    pub cast_rays: u64,
    /// Seconds that cast took.
    pub cast_s: f64,
    /// Vertices of the scene (the masks').
    pub vertices: usize,
}

impl LightChoice {
    /// Rays per vertex of a full cast (a lighting change; a move casts those of the pairs whose
    /// offset changed).
    pub fn rays_per_vertex(&self) -> f64 {
        self.cast_rays as f64 / self.vertices.max(1) as f64
    }

    /// Microseconds per vertex of a full cast (both cores).
    pub fn cast_us_per_vertex(&self) -> f64 {
        self.cast_s * 1e6 / self.vertices.max(1) as f64
    }
}

/// What every sample of one choice reads: the shading table under the whole light, the objects
/// as the rays see them, each object's ray origin offset, the level-order index of leaf 0.
struct Sampling<'a> {
    table: Vec<ShadeNode>,
    objects: Vec<crate::sun::Placed<'a>>,
    offsets: Vec<f32>,
    first_leaf: usize,
}

impl Frame {
    /// What the last lighting change chose: the leaves cast by rays, the error estimate and its
    /// cost, the cast's cost.
    pub fn light_choice(&self) -> &LightChoice {
        &self.ctx.choice
    }
}

impl Context {
    /// Builds every object's hierarchy at rest ([`Context::occluders`]) if not built yet: the
    /// sun's rays and refinement's cast against them.
    pub(super) fn ensure_occluders(&mut self) {
        if self.occluders.is_empty() {
            self.occluders = sun::occluders(&placed(&self.objects));
        }
    }

    /// [`Context::ensure_occluders`], and the hierarchy of every turned object as it stands
    /// (for casts that walk the tree's own directions: refinement's exact factors); those of
    /// objects turned since are built again.
    pub(super) fn ensure_turned_occluders(&mut self) {
        self.ensure_occluders();
        self.turned_occluders.resize_with(self.objects.len(), || None);
        for (object, kept) in self.objects.iter().zip(&mut self.turned_occluders) {
            let yaw = object.turn.yaw;
            if yaw == 0.0 {
                *kept = None;
            } else if kept.as_ref().is_none_or(|(at, _)| *at != yaw) {
                *kept = Some((yaw, vcut_rays::Occluder::new(&[&object.mesh])));
            }
        }
    }

    /// Object `j`'s hierarchy as it stands turned ([`Context::ensure_turned_occluders`] built
    /// it).
    pub(super) fn turned_occluder(&self, j: usize) -> &vcut_rays::Occluder {
        let yaw = self.objects[j].turn.yaw;
        if yaw == 0.0 {
            return &self.occluders[j];
        }
        match self.turned_occluders.get(j).and_then(Option::as_ref) {
            Some((at, occ)) if *at == yaw => occ,
            _ => unreachable!("the turned hierarchies are built before any cast against them"),
        }
    }

    /// Chooses the leaves to cast under `rays` for the current light and translations; builds
    /// the objects' hierarchies when there is a candidate and they are not built yet. The
    /// vertices sampled take their kept merged cuts from `states` unless `stale`.
    pub(super) fn choose(&mut self, rays: &SunRays, states: &[MergeState], stale: bool) -> LightChoice {
        let start = Instant::now();
        let candidates = sun::candidates(&self.light, CANDIDATES);
        let vertices: usize = self.objects.iter().map(|s| s.mesh.vertex_count()).sum();
        let mut choice =
            LightChoice { target: rays.target, candidates: candidates.len(), vertices, ..LightChoice::default() };
        if candidates.is_empty() || rays.max_leaves == 0 {
            return choice;
        }
        self.ensure_occluders();
        let samples = self.samples();
        let at = Sampling {
            table: shade_nodes(&self.tree, &self.light),
            objects: placed(&self.objects),
            offsets: (0..self.objects.len()).map(|o| self.sun_origin_offset(o)).collect(),
            first_leaf: self.tree.node_count() - self.tree.leaf_directions().len(),
        };
        let errors: Vec<(f64, Vec<f32>)> = samples
            .par_iter()
            .filter_map(|&(o, v)| self.sample_errors(o, v, &candidates, &at, &states[o], stale))
            .collect();
        let norm = errors.iter().map(|(r, _)| r * r).sum::<f64>().sqrt();
        let columns: Vec<&[f32]> = errors.iter().map(|(_, e)| e.as_slice()).collect();
        let cap = rays.max_leaves.min(sun::MAX_SUN_LEAVES);
        let (order, before, after) = greedy(&columns, candidates.len(), norm, rays.target, cap);
        choice.cast = order.iter().map(|&c| candidates[c]).collect();
        (choice.samples, choice.estimate_cuts, choice.estimate) = (errors.len(), before, after);
        choice.estimate_s = start.elapsed().as_secs_f64();
        choice
    }

    /// The vertices the estimate samples: [`SAMPLES`] (or every vertex, if fewer) evenly over
    /// the objects' vertices in order.
    fn samples(&self) -> Vec<(usize, usize)> {
        let counts: Vec<usize> = self.objects.iter().map(|s| s.mesh.vertex_count()).collect();
        let total: usize = counts.iter().sum();
        let count = SAMPLES.min(total);
        (0..count)
            .map(|i| {
                let mut g = (2 * i + 1) * total / (2 * count);
                let mut o = 0;
                while g >= counts[o] {
                    g -= counts[o];
                    o += 1;
                }
                (o, g)
            })
            .collect()
    }

    /// At vertex `v` of object `o`: the luminance of the cuts' diffuse light under the whole
    /// light (`table`), and each candidate leaf's error through the cuts, `(w − V·max(0, n·ω))·Y`
    /// (w: the weight the vertex's shading list gives the node holding the leaf). `None` when the
    /// vertex's cut does not merge (the setup's merge then fails too).
    fn sample_errors(
        &self,
        o: usize,
        v: usize,
        candidates: &[u32],
        at: &Sampling<'_>,
        state: &MergeState,
        stale: bool,
    ) -> Option<(f64, Vec<f32>)> {
        let s = &self.objects[o];
        // The kept cut where it is current (a lighting change), else merged here (the setup's
        // choice, before its merges; the merged cache off; a merge that waits; settings that
        // change the cuts).
        let mut merged = MergedCut::default();
        let kept = state.merged.get(v).filter(|_| !stale && !state.pending.get(v).copied().unwrap_or(true));
        let cut = match kept {
            Some(kept) => kept.nodes(),
            None => {
                self.merge_one(o, v, &self.keys(o, v), &mut merged).ok()?;
                (&merged).into()
            }
        };
        let n = s.mesh.normals()[v];
        let list = ShadeList::new(cut, n, &at.table, s.svc_ends(v).as_deref());
        let mut weights: Vec<(usize, f32)> = list.entries.iter().map(|&e| unpack(e)).collect();
        weights.sort_unstable_by_key(|&(k, _)| k);
        let weight = |leaf: u32| {
            let mut k = at.first_leaf + leaf as usize;
            loop {
                if let Ok(i) = weights.binary_search_by_key(&k, |&(node, _)| node) {
                    return weights[i].1;
                }
                if k == 0 {
                    return 0.0;
                }
                k = (k - 1) / 2;
            }
        };
        let origin = vcut_rays::origin(s.mesh.positions()[v] + s.translation, n, at.offsets[o]);
        let dirs = self.tree.leaf_directions();
        let leaves = self.light.leaves();
        let errors = candidates
            .iter()
            .map(|&l| {
                let d = dirs[l as usize];
                let c = n.dot(d);
                let exact = if c > 0.0 && !sun::blocked(&at.objects, &self.occluders, origin, d) { c } else { 0.0 };
                (weight(l) - exact) * sun::luminance(leaves[l as usize]) as f32
            })
            .collect();
        Some((sun::luminance(list.diffuse.as_dvec3().to_array()), errors))
    }

    /// Where object `o`'s sun rays start along the normal (the SVCs' offset).
    pub(super) fn sun_origin_offset(&self, o: usize) -> f32 {
        self.objects[o].ray_offset
    }
}

/// The greedy choice over `count` candidates whose errors at each sample are `samples[s][c]`,
/// relative to `norm`: casts the candidate whose removal lowers the estimate `‖Σ errors‖ / norm`
/// most, while the estimate is above `target`, fewer than `cap` are cast, and the best lowers
/// the squared estimate by at least `target² / cap` (a leaf worth its rays: `cap` such leaves
/// would remove the whole target's worth). Returns the candidates cast in order, the estimate
/// before and after. A smaller target stops later on the same order: it casts the same
/// candidates and more.
pub(super) fn greedy(samples: &[&[f32]], count: usize, norm: f64, target: f64, cap: usize) -> (Vec<usize>, f64, f64) {
    let mut residual: Vec<f64> = samples.iter().map(|e| e.iter().map(|&x| x as f64).sum()).collect();
    let estimate = |r: &[f64]| if norm > 0.0 { r.iter().map(|x| x * x).sum::<f64>().sqrt() / norm } else { 0.0 };
    let before = estimate(&residual);
    let (mut after, mut cast) = (before, Vec::new());
    let mut taken = vec![false; count];
    while after > target && cast.len() < cap {
        // Σ_s r² − (r − e)² = Σ_s e·(2r − e), for each candidate left.
        let gains: Vec<f64> = (0..count)
            .into_par_iter()
            .map(|c| {
                if taken[c] {
                    return f64::NEG_INFINITY;
                }
                samples.iter().zip(&residual).map(|(e, r)| e[c] as f64 * (2.0 * r - e[c] as f64)).sum()
            })
            .collect();
        let best = (0..count).max_by(|&a, &b| gains[a].total_cmp(&gains[b]).then(b.cmp(&a))).unwrap_or(0);
        // Worth its rays: at least 1/cap of the target's square off the squared estimate.
        if gains.get(best).is_none_or(|&g| g <= 0.0 || g / (norm * norm) < target * target / cap as f64) {
            break;
        }
        for (r, e) in residual.iter_mut().zip(samples) {
            *r -= e[best] as f64;
        }
        taken[best] = true;
        cast.push(best);
        after = estimate(&residual);
    }
    (cast, before, after)
}

#[cfg(test)]
mod tests {
    use super::greedy;

    #[test]
    fn greedy_casts_the_largest_error_first_and_stops_at_the_target() {
        // Three samples, three candidates: 0 errs a lot at sample 0, 1 a little, 2 cancels 0
        // at sample 1 (casting it first would raise the error; once 0 is cast, it is next).
        let rows: Vec<Vec<f32>> = vec![vec![0.5, 0.1, 0.0], vec![0.2, 0.0, -0.2], vec![0.0, 0.05, 0.0]];
        let refs: Vec<&[f32]> = rows.iter().map(|r| r.as_slice()).collect();
        let (order, before, after) = greedy(&refs, 3, 10.0, 0.0, 3);
        assert_eq!(order, [0, 2, 1]);
        assert!(before > after);
        assert!((before - (0.6f64.powi(2) + 0.0 + 0.05f64.powi(2)).sqrt() / 10.0).abs() < 1e-6);
        // A target met after the first stops there; a cap of 1 too; a target met at once casts none.
        assert_eq!(greedy(&refs, 3, 10.0, 0.025, 3).0, vec![0]);
        assert_eq!(greedy(&refs, 3, 10.0, 0.02, 3).0, vec![0, 2]);
        assert_eq!(greedy(&refs, 3, 10.0, 0.0, 1).0, vec![0]);
        assert!(greedy(&refs, 3, 10.0, 1.0, 3).0.is_empty());
        // Light spread over many leaves: 100 candidates, each erring 0.001 at its own sample;
        // the estimate is 0.01. Each lowers the squared estimate by 1e-6: under 0.005²/4, so a
        // cap of 4 casts none (4 could not reach the target); over 0.005²/64, so a cap of 64
        // casts all 64 (75 would reach it).
        let spread: Vec<Vec<f32>> =
            (0..100).map(|s| (0..100).map(|c| if c == s { 0.001 } else { 0.0 }).collect()).collect();
        let refs: Vec<&[f32]> = spread.iter().map(|r| r.as_slice()).collect();
        assert!(greedy(&refs, 100, 1.0, 0.005, 4).0.is_empty());
        assert_eq!(greedy(&refs, 100, 1.0, 0.005, 64).0.len(), 64);
        // No light: nothing to estimate.
        assert_eq!(greedy(&refs, 3, 0.0, 0.0, 3), (vec![], 0.0, 0.0));
    }
}
