//! **The sun by rays**: the frame's default beside the paper's cuts
//! ([`crate::Frame::set_sun_rays`]; `None` carries the sun through the cuts too, as the paper).
//!
//! A sun is a step in the light: its shadow edge is a step in every field that sees it, and
//! trilinear interpolation between field samples blurs that step over one sample spacing. On
//! the teapot scene under the sky this is most of what is left of the error against the exact
//! reference at the paper preset — the ground's vertices on the sun's shadow edges — and denser
//! fields buy it back only as the square root of their spacing (README, "Where the rest is").
//!
//! With sun rays (the default), the few leaves of the light tree that hold a sun — each at least
//! [`SunRays::min_ratio`] times the mean leaf's luminance, the brightest [`SunRays::max_leaves`]
//! of them — leave the cuts' light: the shading lists sum the light tree without them, and each
//! vertex adds `Σ_s V(x, ω_s) max(0, n·ω_s) f_r(ω_s, ω_o) L_s` over the sun's leaves, V cast at
//! run time against every object at its current translation from the point the SVCs cast from
//! (offset along the normal). That is the exact reference's own term for those leaves, so the
//! sun's share of the error is gone; the sky's stays the cuts'.
//!
//! Each object keeps a bounding volume hierarchy of its mesh at rest, and each vertex one mask
//! of the sun leaves each object blocks. A move casts only what it changes: rays from the moved
//! object's vertices against the other objects, and from the other objects' vertices against
//! the moved one (translations are rigid, so an object's shadow on itself never changes). A
//! lighting change that moves the sun casts them all again. An environment without leaves that
//! bright leaves everything as without sun rays, bit for bit.

use crate::brdf;
use glam::Vec3;
use rayon::prelude::*;
use vcut_lighttree::LightTree;
use vcut_rays::Occluder;
use vcut_scene::{Material, Mesh};

/// Which leaves are the sun's (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunRays {
    /// A leaf is the sun's when its luminance is at least this many times the mean leaf's.
    pub min_ratio: f64,
    /// At most this many leaves, the brightest (at most 64).
    pub max_leaves: usize,
}

impl Default for SunRays {
    /// Leaves 100× the mean, at most 16: under the procedural sky the sun's 1–3 leaves at
    /// 32,768 directions (10⁴–10⁵× the mean) and nothing of the sky around it.
    fn default() -> SunRays {
        SunRays { min_ratio: 100.0, max_leaves: 16 }
    }
}

/// Most sun leaves (one bit each in a vertex's masks).
pub const MAX_SUN_LEAVES: usize = 64;

/// Rec. 709 luminance, by which the shading table weights a node's leaf directions and the sun's
/// leaves are chosen.
pub(crate) fn luminance(l: [f64; 3]) -> f64 {
    0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2]
}

/// The sun's leaves of `light` under `rays`, brightest first.
pub fn sun_leaves(light: &LightTree, rays: &SunRays) -> Vec<u32> {
    let leaves = light.leaves();
    let total: f64 = leaves.iter().map(|&l| luminance(l).max(0.0)).sum();
    let floor = rays.min_ratio * total / leaves.len().max(1) as f64;
    let mut bright: Vec<u32> =
        (0..leaves.len() as u32).filter(|&l| total > 0.0 && luminance(leaves[l as usize]) >= floor).collect();
    bright.sort_by(|&a, &b| luminance(leaves[b as usize]).total_cmp(&luminance(leaves[a as usize])).then(a.cmp(&b)));
    bright.truncate(rays.max_leaves.min(MAX_SUN_LEAVES));
    bright
}

/// How concentrated the light left in the cuts is: √(Σ s²) over the leaves of `light` other than
/// `cast`, s a leaf's share of the whole light's luminance — 1 for all light in one leaf, 1/√N
/// for light spread evenly over N leaves, 0 for no light. Errors the cuts make leaf by leaf,
/// independent of each other, add up as this does.
pub fn concentration(light: &LightTree, cast: &[u32]) -> f64 {
    let leaves = light.leaves();
    let total: f64 = leaves.iter().map(|&l| luminance(l).max(0.0)).sum();
    if total <= 0.0 {
        return 0.0;
    }
    let squares: f64 = (0..leaves.len() as u32)
        .filter(|l| !cast.contains(l))
        .map(|l| (luminance(leaves[l as usize]).max(0.0) / total).powi(2))
        .sum();
    squares.sqrt()
}

/// `light` without the leaves `sun` (their light set to zero), for the cuts to carry the rest.
pub fn without(light: &LightTree, sun: &[u32]) -> LightTree {
    let mut leaves = light.leaves().to_vec();
    for &l in sun {
        leaves[l as usize] = [0.0; 3];
    }
    LightTree::from_leaves(light.height(), &leaves)
}

/// The sun at run time: its leaves, every object's hierarchy at rest, and per vertex the mask of
/// sun leaves each object blocks.
pub(crate) struct Sun {
    dirs: Vec<Vec3>,
    light: Vec<Vec3>,
    occluders: Vec<Occluder>,
    /// Per object: ray origin offset along the normal (the SVCs').
    offsets: Vec<f32>,
    /// Per object, `vertices × objects` masks: `blocked[o][v·J + j]` holds bit s when object j
    /// blocks sun leaf s from vertex v of object o (only leaves above v's horizon are cast).
    blocked: Vec<Vec<u64>>,
    /// The translations the masks were cast at.
    at: Vec<Vec3>,
}

/// An object as the sun sees it: mesh at rest and translation.
pub(crate) struct Placed<'a> {
    pub mesh: &'a Mesh,
    pub translation: Vec3,
}

impl Sun {
    /// The sun of `light`'s leaves `leaves` (directions `tree_dirs` of the tree's leaves) over
    /// `objects`, every mask cast. `origin_offset`: the SVCs', a fraction of each object's
    /// bounding radius. `old`: the sun of an earlier light over the same objects, whose
    /// hierarchies serve again.
    pub(crate) fn new(
        light: &LightTree,
        leaves: &[u32],
        tree_dirs: &[Vec3],
        objects: &[Placed<'_>],
        origin_offset: f32,
        old: Option<Sun>,
    ) -> Sun {
        let occluders = match old {
            Some(old) => old.occluders,
            None => objects.par_iter().map(|p| Occluder::new(&[p.mesh])).collect(),
        };
        let mut sun = Sun {
            dirs: leaves.iter().map(|&l| tree_dirs[l as usize]).collect(),
            light: leaves
                .iter()
                .map(|&l| {
                    let c = light.leaves()[l as usize];
                    Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
                })
                .collect(),
            occluders,
            offsets: objects.iter().map(|p| vcut_rays::origin_offset(origin_offset, p.mesh)).collect(),
            blocked: objects.iter().map(|p| vec![0; p.mesh.vertex_count() * objects.len()]).collect(),
            at: objects.iter().map(|p| p.translation).collect(),
        };
        sun.cast(objects, |_, _| true);
        sun
    }

    /// Sun leaves.
    pub(crate) fn len(&self) -> usize {
        self.dirs.len()
    }

    /// Casts again what the objects' new translations change; returns the rays cast.
    pub(crate) fn update(&mut self, objects: &[Placed<'_>]) -> u64 {
        let new: Vec<Vec3> = objects.iter().map(|p| p.translation).collect();
        let old = std::mem::replace(&mut self.at, new.clone());
        // A pair's shadows change with the two objects' offset from each other.
        self.cast(objects, |o, j| o != j && new[o] - new[j] != old[o] - old[j])
    }

    /// Casts the masks of the pairs (receiver o, occluder j) that `stale` names.
    fn cast(&mut self, objects: &[Placed<'_>], stale: impl Fn(usize, usize) -> bool + Sync) -> u64 {
        let count = objects.len();
        let mut rays = 0;
        for (o, p) in objects.iter().enumerate() {
            let pairs: Vec<usize> = (0..count).filter(|&j| stale(o, j)).collect();
            if pairs.is_empty() || self.dirs.is_empty() {
                continue;
            }
            let (dirs, occluders, offset) = (&self.dirs, &self.occluders, self.offsets[o]);
            let positions = p.mesh.positions();
            let normals = p.mesh.normals();
            rays += self.blocked[o]
                .par_chunks_mut(count)
                .enumerate()
                .map(|(v, masks)| {
                    let n = normals[v];
                    let origin = vcut_rays::origin(positions[v] + p.translation, n, offset);
                    let mut cast = 0u64;
                    for &j in &pairs {
                        let from = origin - objects[j].translation;
                        let mut mask = 0u64;
                        for (s, &d) in dirs.iter().enumerate() {
                            if n.dot(d) > 0.0 {
                                cast += 1;
                                if occluders[j].occluded(from, d, f32::INFINITY) {
                                    mask |= 1 << s;
                                }
                            }
                        }
                        masks[j] = mask;
                    }
                    cast
                })
                .sum::<u64>();
        }
        rays
    }

    /// `Σ_s V max(0, n·ω_s) f_r(ω_s, ω_o) L_s` at vertex `v` of object `o` (normal `n`, toward
    /// `wo`), as the exact reference adds it.
    pub(crate) fn radiance(&self, o: usize, v: usize, material: &Material, n: Vec3, wo: Vec3) -> Vec3 {
        let count = self.at.len();
        let blocked = self.blocked[o][v * count..(v + 1) * count].iter().fold(0u64, |a, &m| a | m);
        let mut b = Vec3::ZERO;
        for (s, (&d, &l)) in self.dirs.iter().zip(&self.light).enumerate() {
            let c = n.dot(d);
            if c <= 0.0 || blocked >> s & 1 == 1 {
                continue;
            }
            b += c * brdf::eval(material, n, d, wo) * l;
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_is_the_few_leaves_far_above_the_mean() {
        // 1,024 leaves: a sky of 1 with one leaf at 1e5 and one at 50, under the 100× floor
        // once the sun lifts the mean to ~99.
        let mut leaves = vec![[1.0f64; 3]; 1024];
        leaves[5] = [1e5; 3];
        leaves[9] = [50.0; 3];
        let light = LightTree::from_leaves(10, &leaves);
        assert_eq!(sun_leaves(&light, &SunRays::default()), vec![5]);
        // A lower floor takes both, brightest first; the cap keeps the brightest.
        let low = SunRays { min_ratio: 0.05, max_leaves: 16 };
        assert_eq!(sun_leaves(&light, &low), vec![5, 9]);
        assert_eq!(sun_leaves(&light, &SunRays { min_ratio: 0.05, max_leaves: 1 }), vec![5]);
        // A constant sky has no sun; nor has a black one.
        assert!(sun_leaves(&LightTree::from_leaves(10, &[[1.0; 3]; 1024]), &SunRays::default()).is_empty());
        assert!(sun_leaves(&LightTree::from_leaves(10, &[[0.0; 3]; 1024]), &SunRays::default()).is_empty());
        let even = LightTree::from_leaves(10, &[[1.0; 3]; 1024]);
        assert!((concentration(&even, &[]) - 1.0 / 32.0).abs() < 1e-12);
        assert!(concentration(&light, &[]) > concentration(&light, &[5]));
        assert_eq!(concentration(&LightTree::from_leaves(10, &[[0.0; 3]; 1024]), &[]), 0.0);
        // Without it the tree keeps the rest.
        let sky = without(&light, &[5]);
        assert_eq!(sky.leaves()[5], [0.0; 3]);
        assert_eq!(sky.root()[0], light.root()[0] - 1e5);
    }
}
