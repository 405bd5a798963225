//! **The sun by rays**: the frame's default beside the paper's cuts
//! ([`crate::FrameSettings::sun_rays`]; off carries the sun through the cuts too, as the paper).
//!
//! A sun is a step in the light: its shadow edge is a step in every field that sees it, and
//! trilinear interpolation between field samples blurs that step over one sample spacing. On
//! the teapot scene under the sky this is most of what is left of the error against the exact
//! reference at the paper preset — the ground's vertices on the sun's shadow edges — and denser
//! fields buy it back only as the square root of their spacing (README, "Where the rest is").
//!
//! With sun rays (the default), the leaves of the light tree whose error through the cuts is
//! largest leave the cuts' light: the shading lists sum the light tree without them, and each
//! vertex adds `Σ_s V(x, ω_s) max(0, n·ω_s) f_r(ω_s, ω_o) L_s` over the cast leaves, V cast at
//! run time against every object at its current translation from the point the SVCs cast from
//! (offset along the normal). That is the exact reference's own term for those leaves, so their
//! share of the error is gone; the rest stays the cuts'.
//!
//! **Which leaves: by the error they would add.** On every lighting change the frame estimates,
//! for the [`CANDIDATES`] brightest leaves of at least [`CANDIDATE_RATIO`] times the mean, the
//! error each adds through the cuts
//! (`crate::frame` `choice`): at [`SAMPLES`] vertices spread over the objects it merges the
//! cut (as a move would), reads the weight its shading list gives the leaf's node, and casts the
//! leaf's ray; the leaf's error at the vertex is `(w − V·max(0, n·ω)) · Y_leaf` (Y: luminance),
//! the diffuse light the cuts give the leaf less the exact. The estimate for a set of leaves
//! left in the cuts is the relative L2 of the sum of their errors over the sampled vertices
//! against the cuts' diffuse light there (errors of leaves in one shadow edge add up; errors
//! that cancel count as cancelled). Leaves are cast greedily — the one whose casting lowers
//! the estimate most — until it is at most [`SunRays::target`], [`SunRays::max_leaves`] are
//! cast, or the best leaf lowers the squared estimate by less than target² / max_leaves (not
//! worth its rays). A smaller target casts the same leaves and more (the order
//! does not depend on the target). A sun is one to three leaves with large errors at its
//! shadow edges; a constant or dim map has no candidate worth a ray; several suns or a
//! window get their brightest leaves, up to the cap. What the estimate leaves out — the error
//! of the leaves below the candidates, the cuts' coarseness under diffuse light — is the
//! floor no ray removes (docs/benchmarks.md, "Accuracy under any light").
//!
//! Each object keeps a bounding volume hierarchy of its mesh at rest, and each vertex one mask
//! of the cast leaves each object blocks. A move casts only what it changes: rays from the moved
//! object's vertices against the other objects, and from the other objects' vertices against
//! the moved one (translations are rigid, so an object's shadow on itself never changes). A
//! lighting change chooses the leaves again and casts them all. A light with no leaf cast
//! leaves everything as without sun rays, bit for bit.

use crate::brdf;
use crate::frame::Parts;
use glam::Vec3;
use rayon::prelude::*;
use vcut_lighttree::LightTree;
use vcut_rays::Occluder;
use vcut_scene::Mesh;

/// Which leaves leave the cuts (see the module documentation): the target error and the cost cap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SunRays {
    /// The target: the estimated relative L2 error that the brightest leaves, left in the cuts,
    /// add to the diffuse light at the frame's sampled vertices. Leaves are cast, the one whose
    /// casting lowers the estimate most first, until it is at most this (or the cap is reached).
    pub target: f64,
    /// The cost cap: at most this many leaves (at most [`MAX_SUN_LEAVES`]).
    pub max_leaves: usize,
}

impl Default for SunRays {
    /// [`DEFAULT_TARGET`], at most [`DEFAULT_MAX_LEAVES`] leaves.
    fn default() -> SunRays {
        SunRays { target: DEFAULT_TARGET, max_leaves: DEFAULT_MAX_LEAVES }
    }
}

/// The default target error (0.2 %): see the module documentation for what it costs.
pub const DEFAULT_TARGET: f64 = 0.002;
/// The default cost cap in leaves.
pub const DEFAULT_MAX_LEAVES: usize = 32;
/// Most sun leaves (one bit each in a vertex's masks).
pub const MAX_SUN_LEAVES: usize = 64;
/// Leaves whose error is estimated: the brightest this many of at least [`CANDIDATE_RATIO`]
/// times the mean leaf.
pub const CANDIDATES: usize = 256;
/// A leaf within this factor of the mean leaf's luminance is sky, not a source: its error
/// through the cuts is the cuts' error under diffuse light, shared with the thousands of leaves
/// like it, which no affordable number of rays removes. So a constant map has no candidate.
pub const CANDIDATE_RATIO: f64 = 4.0;
/// Vertices at which the leaves' errors are estimated (spread over the objects by their vertex
/// counts).
pub const SAMPLES: usize = 1024;

/// Rec. 709 luminance, by which the shading table weights a node's leaf directions and the
/// leaves are ranked.
pub(crate) fn luminance(l: [f64; 3]) -> f64 {
    0.2126 * l[0] + 0.7152 * l[1] + 0.0722 * l[2]
}

/// The leaves of `light` whose error through the cuts is estimated: the brightest `count` of at
/// least [`CANDIDATE_RATIO`] times the mean leaf's luminance, brightest first (ties by index).
/// None of a constant or a black light.
pub fn candidates(light: &LightTree, count: usize) -> Vec<u32> {
    let leaves = light.leaves();
    let total: f64 = leaves.iter().map(|&l| luminance(l).max(0.0)).sum();
    let floor = CANDIDATE_RATIO * total / leaves.len().max(1) as f64;
    let mut bright: Vec<u32> =
        (0..leaves.len() as u32).filter(|&l| total > 0.0 && luminance(leaves[l as usize]) >= floor).collect();
    bright.sort_by(|&a, &b| luminance(leaves[b as usize]).total_cmp(&luminance(leaves[a as usize])).then(a.cmp(&b)));
    bright.truncate(count);
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
    /// Per object: ray origin offset along the normal (the SVCs').
    offsets: Vec<f32>,
    /// Per receiver o and occluder j, the vertices' masks: `blocked[o][j][v]` holds bit s when
    /// object j blocks sun leaf s from vertex v of object o (only leaves above v's horizon are
    /// cast); an empty list where j blocks nothing from o, as most pairs of a large scene (the
    /// masks of every pair would grow with the objects squared).
    blocked: Vec<Vec<Vec<u64>>>,
    /// The translations and yaws the masks were cast at.
    at: Vec<(Vec3, f32)>,
}

/// Every object's hierarchy at rest, for the sun's rays (built once per frame: translations
/// and turns move the rays, not the hierarchies; [`Placed::local`]).
pub(crate) fn occluders(objects: &[Placed<'_>]) -> Vec<Occluder> {
    objects.par_iter().map(|p| Occluder::new(&[p.rest])).collect()
}

/// Whether any of `objects` (`occluders`: their hierarchies at rest) blocks direction `d` from
/// `origin`.
pub(crate) fn blocked(objects: &[Placed<'_>], occluders: &[Occluder], origin: Vec3, d: Vec3) -> bool {
    objects.iter().zip(occluders).any(|(p, h)| {
        let (from, d) = p.local(origin, d);
        h.occluded(from, d, f32::INFINITY)
    })
}

/// An object as the sun sees it: its mesh as it stands turned (where its vertices are), its
/// mesh at rest (what its hierarchy holds), its translation, and its turn: yaw about the
/// vertical through `centre`.
pub(crate) struct Placed<'a> {
    pub mesh: &'a Mesh,
    pub rest: &'a Mesh,
    pub translation: Vec3,
    pub yaw: f32,
    pub centre: Vec3,
}

impl Placed<'_> {
    /// The turn that takes a world direction into the object's rest frame (`None` at yaw 0).
    fn to_rest(&self) -> Option<glam::Quat> {
        (self.yaw != 0.0).then(|| glam::Quat::from_rotation_y(-self.yaw))
    }

    /// A ray from world point `origin` along `d`, in the frame of the object's hierarchy at
    /// rest: less its translation, turned back about its axis (exactly the ray at yaw 0).
    pub(crate) fn local(&self, origin: Vec3, d: Vec3) -> (Vec3, Vec3) {
        let q = origin - self.translation;
        match self.to_rest() {
            Some(r) => (r * (q - self.centre) + self.centre, r * d),
            None => (q, d),
        }
    }
}

impl Sun {
    /// The sun of `light`'s leaves `leaves` (directions `tree_dirs` of the tree's leaves) over
    /// `objects` (`occluders`: their hierarchies at rest, [`occluders`]), every mask cast.
    /// `origin_offset`: the SVCs', a fraction of each object's bounding radius. Returns it and
    /// the rays cast.
    pub(crate) fn new(
        light: &LightTree,
        leaves: &[u32],
        tree_dirs: &[Vec3],
        objects: &[Placed<'_>],
        occluders: &[Occluder],
        origin_offset: f32,
    ) -> (Sun, u64) {
        let mut sun = Sun {
            dirs: leaves.iter().map(|&l| tree_dirs[l as usize]).collect(),
            light: leaves
                .iter()
                .map(|&l| {
                    let c = light.leaves()[l as usize];
                    Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
                })
                .collect(),
            offsets: objects.iter().map(|p| vcut_rays::origin_offset(origin_offset, p.mesh)).collect(),
            blocked: objects.iter().map(|_| vec![Vec::new(); objects.len()]).collect(),
            at: objects.iter().map(|p| (p.translation, p.yaw)).collect(),
        };
        let rays = sun.cast(objects, occluders, |_, _| true);
        (sun, rays)
    }

    /// Sun leaves.
    pub(crate) fn len(&self) -> usize {
        self.dirs.len()
    }

    /// Casts again what the objects' new translations and turns change; returns the rays cast.
    pub(crate) fn update(&mut self, objects: &[Placed<'_>], occluders: &[Occluder]) -> u64 {
        let new: Vec<(Vec3, f32)> = objects.iter().map(|p| (p.translation, p.yaw)).collect();
        let old = std::mem::replace(&mut self.at, new.clone());
        // A pair's shadows change with the two objects' offset from each other, and with
        // either one's turn (an object's shadows on itself with its turn alone).
        self.cast(objects, occluders, |o, j| {
            (o != j && new[o].0 - new[j].0 != old[o].0 - old[j].0) || new[o].1 != old[o].1 || new[j].1 != old[j].1
        })
    }

    /// Casts the masks of the pairs (receiver o, occluder j) that `stale` names.
    fn cast(
        &mut self,
        objects: &[Placed<'_>],
        occluders: &[Occluder],
        stale: impl Fn(usize, usize) -> bool + Sync,
    ) -> u64 {
        let count = objects.len();
        let mut rays = 0;
        for (o, p) in objects.iter().enumerate() {
            if self.dirs.is_empty() {
                break;
            }
            let (dirs, offset) = (&self.dirs, self.offsets[o]);
            let positions = p.mesh.positions();
            let normals = p.mesh.normals();
            for j in (0..count).filter(|&j| stale(o, j)) {
                let mut masks = std::mem::take(&mut self.blocked[o][j]);
                masks.resize(p.mesh.vertex_count(), 0);
                // The sun's directions in j's rest frame, once for every vertex.
                let local: Vec<Vec3> = dirs.iter().map(|&d| objects[j].local(Vec3::ZERO, d).1).collect();
                rays += masks
                    .par_iter_mut()
                    .enumerate()
                    .map(|(v, mask)| {
                        let n = normals[v];
                        let (from, _) =
                            objects[j].local(vcut_rays::origin(positions[v] + p.translation, n, offset), Vec3::ZERO);
                        let mut cast = 0u64;
                        *mask = 0;
                        for (s, (&d, &l)) in dirs.iter().zip(&local).enumerate() {
                            if n.dot(d) > 0.0 {
                                cast += 1;
                                if occluders[j].occluded(from, l, f32::INFINITY) {
                                    *mask |= 1 << s;
                                }
                            }
                        }
                        cast
                    })
                    .sum::<u64>();
                if masks.iter().all(|&m| m == 0) {
                    masks = Vec::new();
                }
                self.blocked[o][j] = masks;
            }
        }
        rays
    }

    /// Bytes of the masks.
    pub(crate) fn bytes(&self) -> usize {
        self.blocked.iter().flatten().map(|m| m.capacity() * size_of::<u64>()).sum()
    }

    /// `Σ_s V max(0, n·ω_s) f_r(ω_s, ω_o) L_s` at vertex `v` of object `o` (normal `n`), as the
    /// exact reference adds it, in the frame's two parts: the diffuse per unit albedo, and
    /// `lobe` (the cuts' own, its power tabled where theirs is: within 10⁻⁵ of the lobe's peak).
    pub(crate) fn parts(&self, o: usize, v: usize, lobe: &brdf::Lobe<'_>, n: Vec3) -> Parts {
        let blocked = self.blocked[o].iter().filter_map(|m| m.get(v)).fold(0u64, |a, &m| a | m);
        let mut p = Parts::default();
        for (s, (&d, &l)) in self.dirs.iter().zip(&self.light).enumerate() {
            let c = n.dot(d);
            if c <= 0.0 || blocked >> s & 1 == 1 {
                continue;
            }
            p.diffuse += c * l / std::f32::consts::PI;
            p.specular += c * lobe.eval(d) * l;
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_are_the_leaves_above_the_mean_brightest_first() {
        // 1,024 leaves: a sky of 1 with one leaf at 1e5 and one at 50; the sun lifts the mean
        // to ~99, so only it is 4× above.
        let mut leaves = vec![[1.0f64; 3]; 1024];
        leaves[5] = [1e5; 3];
        leaves[9] = [50.0; 3];
        let light = LightTree::from_leaves(10, &leaves);
        assert_eq!(candidates(&light, 256), vec![5]);
        leaves[5] = [30.0; 3];
        let light = LightTree::from_leaves(10, &leaves);
        assert_eq!(candidates(&light, 256), vec![9, 5]);
        assert_eq!(candidates(&light, 1), vec![9]);
        // A constant sky has none; nor has a black one.
        assert!(candidates(&LightTree::from_leaves(10, &[[1.0; 3]; 1024]), 256).is_empty());
        assert!(candidates(&LightTree::from_leaves(10, &[[0.0; 3]; 1024]), 256).is_empty());
        let even = LightTree::from_leaves(10, &[[1.0; 3]; 1024]);
        assert!((concentration(&even, &[]) - 1.0 / 32.0).abs() < 1e-12);
        assert!(concentration(&light, &[]) > concentration(&light, &[9]));
        assert_eq!(concentration(&LightTree::from_leaves(10, &[[0.0; 3]; 1024]), &[]), 0.0);
        // Without it the tree keeps the rest.
        let sky = without(&light, &[9]);
        assert_eq!(sky.leaves()[9], [0.0; 3]);
        assert_eq!(sky.root()[0], light.root()[0] - 50.0);
    }
}
