//! The frame loop of the paper, with caching: per vertex the SVC times the fields of the
//! objects that can move relative to it, interpolated from 8 samples each, merged once and kept;
//! a move re-merges only the vertices whose field inputs changed (those facing away from the
//! camera when it sees them: deferred merges, below); BRDF and lighting edits only re-shade,
//! and so do camera edits with nothing waiting.
//!
//! **Which fields a vertex uses.** Object j's field shadows a vertex of object o (o ≠ j) when
//! j has a field and o or j is movable (static–static shadows are baked into the SVCs). Within
//! 0.2r of j's centre (0.05r–0.2r for a flat j: its layout's `inner`) the lookup clamps to the
//! innermost sphere; beyond 10r j casts no shadow
//! (its bounding cone there covers under 0.25 % of the sphere); samples inside j blend in as
//! fully occluded (or are dropped and the rest renormalised: [`Frame::set_inside_samples`],
//! [`InsideSamples`] says why and by how much), and a vertex whose 8 samples are all inside j is
//! fully occluded.
//!
//! **Where in a node the light is.** A merged node k holds v_k, the mean of V·max(0, n·ω) over
//! its leaves, and the light tree the node's total radiance l_k. The paper evaluates
//! `v_k f_r(ω_k, ω_o) l_k` at the node's mean direction ω_k, which is exact only if the light
//! is spread evenly over the node: a sun covering one leaf of a 13° node gets the node's mean
//! cosine and the BRDF 6° off. Here every node also knows the light-weighted mean of its leaf
//! directions E_k = Σ ω_l y_l / Σ y_l (y the luminance) and the plain mean m_k = Σ ω_l / n_k;
//! for a node wholly above the horizon, Σ_l max(0, n·ω_l) L_l = (n·E_k) l_k exactly, so with the
//! node's visibility taken as constant (α = v_k / (n·m_k)) the estimate is
//! `α (n·E_k) f_r(Ê_k, ω_o) l_k`: exact for any light within a fully visible node. Nodes that
//! cross the horizon keep `v_k f_r(Ê_k, ω_o) l_k`. On the teapot scene under the sky (with exact
//! fields, so clustering is the only error) this took the error against the exact reference
//! from 3.1 % to 1.05 % (`cargo run --release -p vcut-benches --example error_sources`).
//!
//! **The SVC's share of a finer node.** A merged node k finer than the SVC node A around it
//! (a field splits A) gets the product's value v_A·F_k, with v_A A's mean of V·max(0, n·ω): A's
//! mean cosine, not k's. Where A lies wholly above the horizon the list takes k's visibility as
//! `v_k / (n·m_A)` instead of `v_k / (n·m_k)` — A's visibility fraction, times the fields — so
//! k's own cosine enters through n·E_k. The merged cuts stay the paper's product (bit for bit
//! with the counter merge); only the list reads the SVC's node ends. On the teapot scene at the
//! paper preset (the bench's frame) this took the error against the exact reference from
//! 2.09 % to 1.77 %, the ground's from 4.4 % to 3.7 %, and with exact field cuts at the
//! vertices from 1.12 % to 0.71 % (`error_sources --scene builtin:teapot`); moves cost ~4 %
//! more (the list walks the SVC's ends beside the cut).
//!
//! **The sun by rays** (the default; [`Frame::set_sun_rays`], [`crate::sun`]). The few leaves
//! of the light that hold a sun leave the cuts' light; each vertex adds their term with the
//! visibility cast at run time against the objects at their translations (a move casts only
//! the object pairs whose offset changed). The sun's shadow edges are then exact instead of
//! blurred between field samples: at the paper preset the teapot scene's error against the
//! exact reference fell from 1.77 % to 0.25 % and the bunny's from 0.92 % to 0.18 %, for
//! ~1 ms of rays a move (`cargo xtask bench`, `rel_l2_exact` against `rel_l2_exact_cuts_only`).
//! The merged cuts are the same either way.
//!
//! **Shading lists.** After a merge (and after a lighting change) each vertex keeps the nodes
//! that can reflect light toward a viewer — value non-zero, Ê_k above the horizon — with the
//! weight `α (n·E_k)` (or v_k) folded in, and the diffuse sum Σ weight·l_k. A BRDF or camera
//! edit then evaluates only the specular lobe over that list and adds `k_d/π` times the sum.
//!
//! A vertex facing away from the camera reflects nothing toward it, so a merge (or a lighting
//! change) builds the lists of the vertices facing the last eye shaded from ([`Frame::shade`]
//! records it; [`Frame::set_eye`] sets it) and marks the others' stale. Shading builds a stale
//! list it needs on the spot, without keeping it; [`Frame::set_eye`] builds and keeps those of
//! the vertices facing a new eye. A move then spends nothing on the back-facing half of an
//! object's lists (the teapot scene's moves 0.89×, the bunny's 0.80× by `move_path`), and a
//! camera turn after it pays for their lists once.
//!
//! **Deferred merges** (the default; [`Frame::set_deferred_merges`]). For the same reason a
//! move merges only the changed vertices facing the last eye; the others keep their old cut and
//! field inputs and wait ([`Frame::pending_merges`]). The next move compares with those inputs
//! (back where it was, a vertex waits no more), [`Frame::set_eye`] merges and keeps the waiting
//! vertices facing the new eye, [`Frame::shade`] merges those it needs on the spot without
//! keeping them, and [`Frame::merge_pending`] merges all. Images are bit for bit the eager
//! frame's (tested); a move on the teapot scene merges ~6,600 of its 11,564 changed vertices
//! and takes ~0.75× the eager time, and the camera turn after it merges what it now sees
//! (`cargo xtask bench`: `move_ms_eager`, `turn_ms`, `turn_ms_eager`). With deferral off a
//! camera change never merges.

use crate::brdf;
use crate::sun::{self, Placed, Sun, SunRays};
use glam::Vec3;
use rayon::prelude::*;
use std::time::Instant;
use vcut_cut::Cut;
use vcut_data::sections::CutArray;
use vcut_data::{FieldLayout, FieldSample, FileError, InsideSamples, Precomputed};
use vcut_dirtree::DirectionTree;
use vcut_envmap::EnvMap;
use vcut_lighttree::{LightTree, LightTreeBuilder};
use vcut_merge::baseline::{self, IndexCut, IndexGroup};
use vcut_merge::{Factor, MergedCut, Refinement, merge_refined};
use vcut_scene::{Material, Mesh, Motion};

/// Why a frame could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    /// The precomputed data is unreadable.
    #[error(transparent)]
    File(#[from] FileError),
    /// A cut in the data does not decode or merge.
    #[error("object {object}, vertex {vertex}: {reason}")]
    Cut {
        /// Object index.
        object: usize,
        /// Vertex index.
        vertex: usize,
        /// What failed.
        reason: String,
    },
}

/// Which merge a move uses. Both give the same merged cuts bit for bit (tested), so they can be
/// timed on the same frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MergeAlgorithm {
    /// The paper's counter merge over height-coded cuts, through refinements: each field cell's
    /// cuts (the 8 samples of a lookup, shared by the vertices around them) are merged once
    /// into their common refinement ([`vcut_merge::Refinement`]), then every vertex merges its
    /// SVC with its cells' refinements ([`vcut_merge::merge_refined`], the same cut to the bit).
    #[default]
    Counter,
    /// The index baseline (Cheslack-Postava 2008 style): cuts converted to level-order indices
    /// when decoded, merged by "advance until nested".
    Index,
}

/// Where the last move's time went (seconds, wall clock over both cores).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MoveTiming {
    /// Field lookups of every vertex (the keys).
    pub keys_s: f64,
    /// Decoding the field samples the changed vertices need (once each).
    pub decode_s: f64,
    /// Refining the field cells the changed vertices use (once each).
    pub refine_s: f64,
    /// Merging the changed vertices and building their shading lists (SVC decode included).
    pub merge_s: f64,
    /// Casting the sun's rays the move changed (with [`Frame::set_sun_rays`]; 0 without).
    pub sun_s: f64,
    /// Sun rays cast.
    pub sun_rays: u64,
    /// Vertices re-merged.
    pub vertices: usize,
    /// Vertices whose field inputs changed but whose merge waits: they face away from the eye
    /// ([`Frame::set_deferred_merges`]).
    pub deferred: usize,
}

/// One field's contribution to a vertex: the object, and its 8 samples (`None`: all inside it,
/// the vertex is fully occluded).
#[derive(Debug, Clone, Copy, PartialEq)]
struct FieldKey {
    object: u32,
    samples: Option<[FieldSample; 8]>,
}

/// A field lookup's kept samples — (object, sphere, point), in lookup order, the order of the
/// sum — the cuts one factor of a vertex's product sums. Vertices near each other share cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct CellKey {
    samples: [(u32, u32, u32); 8],
    len: u8,
}

impl CellKey {
    /// The cell of lookup `k` and the kept samples' weights (`None`: no samples kept).
    fn of(k: &FieldKey) -> Option<(CellKey, [f32; 8])> {
        let samples = k.samples?;
        let mut cell = CellKey { samples: [(0, 0, 0); 8], len: 0 };
        let mut weights = [0.0f32; 8];
        for x in samples.iter().filter(|x| x.weight > 0.0) {
            cell.samples[usize::from(cell.len)] = (k.object, x.sphere, x.point);
            weights[usize::from(cell.len)] = x.weight;
            cell.len += 1;
        }
        Some((cell, weights))
    }

    fn samples(&self) -> &[(u32, u32, u32)] {
        &self.samples[..usize::from(self.len)]
    }
}

/// For every key of `wanted` (sorted), the value `held` has for it (`keys` sorted too, the
/// values beside them), moved out; `None` where it has none.
fn take_held<K: Ord, V>(keys: Vec<K>, held: Vec<V>, wanted: &[K]) -> Vec<Option<V>> {
    let mut held = keys.into_iter().zip(held).peekable();
    wanted
        .iter()
        .map(|key| {
            while held.next_if(|(k, _)| k < key).is_some() {}
            held.next_if(|(k, _)| k == key).map(|(_, v)| v)
        })
        .collect()
}

/// What the last merge of an object's vertices built, for the next move (a move along a path
/// needs mostly the same cells and samples again): the cells' refinements, sorted by cell, and
/// the field cuts it decoded, by (object, sphere, point), sorted.
#[derive(Default)]
struct FieldCache {
    keys: Vec<(u32, u32, u32)>,
    cuts: Vec<Cut>,
    cells: Vec<CellKey>,
    refined: Vec<Refinement>,
}

/// An object at run time.
struct ObjectState {
    name: String,
    mesh: Mesh,
    material: Material,
    /// `x^exponent` of the material, tabled (`None` above the table's range).
    pow: Option<brdf::PowTable>,
    motion: Motion,
    translation: Vec3,
    svc: Vec<CutArray>,
    /// First vertex of every SVC chunk.
    svc_starts: Vec<usize>,
    layout: Option<FieldLayout>,
    field: Vec<CutArray>,
    merged: Vec<MergedCut>,
    lists: Vec<ShadeList>,
    keys: Vec<Vec<FieldKey>>,
    /// Decoded field cuts its vertices' last merge used.
    decoded: FieldCache,
    /// Every vertex's SVC decoded once, ready to merge (empty with the cache off: then each
    /// merge decodes it from the file's bytes).
    svc_refined: Vec<Refinement>,
    /// Vertices whose merge waits ([`Frame::set_deferred_merges`]): their field inputs changed
    /// while they faced away from the eye; `merged` and `keys` are still the last merge's.
    pending: Vec<bool>,
}

impl ObjectState {
    /// Whether vertex `v` at the current translation faces `eye`.
    fn faces(&self, v: usize, eye: Vec3) -> bool {
        faces(self.mesh.normals()[v], self.mesh.positions()[v] + self.translation, eye)
    }

    /// Builds vertex `v`'s shading list from its kept merged cut into `list`.
    fn relist(&self, v: usize, nodes: &[ShadeNode], list: &mut ShadeList, below: &mut Vec<f32>) {
        list.rebuild(&self.merged[v], self.mesh.normals()[v], nodes, self.svc_ends(v).as_deref(), below);
    }

    fn svc_cut(&self, v: usize) -> Result<Cut, String> {
        let chunk = self.svc_starts.partition_point(|&s| s <= v) - 1;
        self.svc[chunk].cut(v - self.svc_starts[chunk])
    }

    /// The node ends (leaves) of vertex `v`'s SVC: kept when the SVCs are, decoded otherwise
    /// (`None` if that fails; the setup's merge decoded it once, so it does not in practice).
    fn svc_ends(&self, v: usize) -> Option<std::borrow::Cow<'_, [u32]>> {
        if let Some(r) = self.svc_refined.get(v) {
            return Some(std::borrow::Cow::Borrowed(r.ends()));
        }
        Some(std::borrow::Cow::Owned(node_ends(&self.svc_cut(v).ok()?)))
    }
}

/// The objects at their translations, as the sun's rays see them.
fn placed(objects: &[ObjectState]) -> Vec<Placed<'_>> {
    objects.iter().map(|s| Placed { mesh: &s.mesh, translation: s.translation }).collect()
}

/// The leaf where each of `cut`'s nodes ends, left to right.
fn node_ends(cut: &Cut) -> Vec<u32> {
    cut.heights()
        .iter()
        .scan(0u32, |end, &h| {
            *end += 1u32 << h;
            Some(*end)
        })
        .collect()
}

/// The scene at run time: translations, materials, lighting, and the merged cuts.
pub struct Frame {
    tree: DirectionTree,
    objects: Vec<ObjectState>,
    builder: LightTreeBuilder,
    light: LightTree,
    /// The sun by rays, when asked for and the light has one ([`crate::sun`]).
    sun_rays: Option<SunRays>,
    sun: Option<Sun>,
    /// Where the SVCs' rays start: this fraction of an object's bounding radius along the normal.
    origin_offset: f32,
    /// Per tree node (level order): what shading needs (under the light less the sun's leaves
    /// when the sun is cast).
    nodes: Vec<ShadeNode>,
    /// Per tree node: what the specular loop reads ([`ShadeNode::dir`] and `light`), half a
    /// cache line each, so the nodes a frame's lists use stay in cache.
    specular: Vec<SpecularNode>,
    merges: u64,
    algorithm: MergeAlgorithm,
    inside: InsideSamples,
    last_move: MoveTiming,
    /// The last eye shaded from or set: merges build the lists of the vertices facing it only
    /// (all while `None`).
    eye: std::sync::Mutex<Option<Vec3>>,
    /// Whether a move leaves the vertices facing away from the eye for later.
    defer: bool,
    /// Merges [`Frame::shade`] did on the spot.
    spot_merges: std::sync::atomic::AtomicU64,
}

/// The merged cut of a vertex inside an object (a cut of one zero node).
fn full_zero(h: u32) -> MergedCut {
    MergedCut { root_height: h, heights: vec![h as u8], values: vec![0.0], indices: vec![0] }
}

/// Blinn-Phong's power argument n·ĥ, ĥ = (ω + wo)/|ω + wo|, as [`brdf::Lobe::eval`] forms it.
fn blinn_phong_argument(n: Vec3, wo: Vec3) -> impl Fn([f32; 3]) -> f32 {
    move |d| {
        let s = Vec3::from(d) + wo;
        n.dot(s) / s.length()
    }
}

/// Phong's power argument r_o·ω (r_o: wo mirrored about the normal).
fn phong_argument(mirror: Vec3) -> impl Fn([f32; 3]) -> f32 {
    move |d| mirror.dot(Vec3::from(d))
}

/// What the specular loop reads of one tree node: Ê_k and l_k.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(32))]
struct SpecularNode {
    dir: Vec3,
    light: Vec3,
}

fn specular_nodes(nodes: &[ShadeNode]) -> Vec<SpecularNode> {
    nodes.iter().map(|n| SpecularNode { dir: n.dir, light: n.light }).collect()
}

/// What shading needs of one tree node, in one cache line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(64))]
struct ShadeNode {
    /// Ê_k: the node's light-weighted mean direction, normalised (its plain mean direction when
    /// the node holds no light).
    dir: Vec3,
    /// l_k, the node's light (RGB). Beside `dir`: the specular loop reads these two only.
    light: Vec3,
    /// E_k: the light-weighted mean of the leaf directions (not normalised).
    centroid: Vec3,
    /// m_k: the plain mean of the leaf directions (not normalised).
    mean: Vec3,
    /// Axis of the node's bounding cone.
    axis: Vec3,
    /// Sine of the cone's half-angle (2 when the cone exceeds a hemisphere): the node lies
    /// wholly above the horizon of `n` when `n·axis ≥ sin_half`.
    sin_half: f32,
}

/// The shading table of every node (level order) under `light`.
fn shade_nodes(tree: &DirectionTree, light: &LightTree) -> Vec<ShadeNode> {
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
#[derive(Debug, Clone, Default)]
struct ShadeList {
    nodes: Vec<u32>,
    weights: Vec<f32>,
    diffuse: Vec3,
    /// Not built since the vertex's last merge or lighting change (empty meanwhile).
    stale: bool,
}

/// Whether a vertex at `x` with normal `n` faces `eye` (else it reflects nothing toward it).
#[inline]
fn faces(n: Vec3, x: Vec3, eye: Vec3) -> bool {
    n.dot((eye - x).normalize_or_zero()) > 0.0
}

impl ShadeList {
    /// The list of merged cut `cut` at normal `n` (`svc`: see [`ShadeList::rebuild`]).
    fn new(cut: &MergedCut, n: Vec3, table: &[ShadeNode], svc: Option<&[u32]>) -> ShadeList {
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
    /// `scratch` holds each packed node's n·m_A (0: use its own).
    ///
    /// Two passes without data-dependent branches: the non-zero nodes are packed first, then
    /// every packed node's table entry is read and the node kept or dropped by arithmetic, so
    /// the table reads (the cost: scattered over the tree's levels) are independent of each
    /// other and overlap instead of waiting on mispredicted branches.
    fn rebuild(&mut self, cut: &MergedCut, n: Vec3, table: &[ShadeNode], svc: Option<&[u32]>, scratch: &mut Vec<f32>) {
        // Sized by the non-zero nodes (a list is kept per vertex: no room for the zero ones).
        let len = cut.values.iter().filter(|&&v| v != 0.0).count();
        self.nodes.resize(len, 0);
        self.weights.resize(len, 0.0);
        scratch.clear();
        scratch.resize(len, 0.0);
        let mut packed = 0;
        match svc {
            None => {
                for (&k, &v) in cut.indices.iter().zip(&cut.values) {
                    // The last zero nodes write past the non-zero ones: into the spare slot, if any.
                    if packed < len {
                        self.nodes[packed] = k;
                        self.weights[packed] = v;
                    }
                    packed += usize::from(v != 0.0);
                }
            }
            Some(ends) => {
                let root = cut.root_height;
                // The SVC node around the current one: its end and n·m (0 unless wholly above).
                let (mut leaf, mut j, mut a_end, mut a_below) = (0u32, 0usize, 0u32, 0.0f32);
                for ((&k, &v), &h) in cut.indices.iter().zip(&cut.values).zip(&cut.heights) {
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
                        self.nodes[packed] = k;
                        self.weights[packed] = v;
                        scratch[packed] = a_below;
                    }
                    packed += usize::from(v != 0.0);
                    leaf = end;
                }
            }
        }
        let mut kept = 0;
        let mut diffuse = Vec3::ZERO;
        for i in 0..packed {
            let (k, v, a_below) = (self.nodes[i], self.weights[i], scratch[i]);
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
            self.nodes[kept] = k;
            self.weights[kept] = w;
            diffuse += if keep { w * node.light } else { Vec3::ZERO };
            kept += usize::from(keep);
        }
        self.nodes.truncate(kept);
        self.weights.truncate(kept);
        self.diffuse = diffuse;
        self.stale = false;
    }

    /// Empties the list, keeping its buffers.
    fn clear(&mut self) {
        self.nodes.clear();
        self.weights.clear();
        self.diffuse = Vec3::ZERO;
        self.stale = false;
    }

    /// Empties the list and marks it to be built when a shading needs it.
    fn mark_stale(&mut self) {
        self.clear();
        self.stale = true;
    }

    /// Σ weight · lobe(Ê_k) · l_k for a lobe `scale · pow(x_k)` whose argument is a
    /// function of the node direction alone (Blinn-Phong's n·ĥ, Phong's r_o·ω): eight nodes at
    /// a time, their directions and weighted lights gathered into lanes, so the arithmetic runs
    /// on all lanes together and the eight sums never wait on each other.
    #[inline]
    fn specular_lanes(
        &self,
        table: &[SpecularNode],
        pow: &brdf::PowTable,
        scale: Vec3,
        argument: impl Fn([f32; 3]) -> f32,
    ) -> Vec3 {
        const L: usize = 8;
        let mut sum = [[0.0f32; L]; 3];
        for (ks, ws) in self.nodes.chunks(L).zip(self.weights.chunks(L)) {
            let (mut dir, mut light) = ([[0.0f32; L]; 3], [[0.0f32; L]; 3]);
            for (j, (&k, &w)) in ks.iter().zip(ws).enumerate() {
                let node = &table[k as usize];
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
    fn specular(&self, table: &[SpecularNode], lobe: impl Fn(Vec3) -> Vec3) -> Vec3 {
        let mut b = Vec3::ZERO;
        for (&k, &w) in self.nodes.iter().zip(&self.weights) {
            let node = &table[k as usize];
            b += w * lobe(node.dir) * node.light;
        }
        b
    }
}

impl Frame {
    /// Reads everything from `data`, builds the light tree of `env`, and merges every vertex.
    pub fn new(data: &mut Precomputed, env: &EnvMap) -> Result<Frame, FrameError> {
        let tree = data.tree()?;
        let mut objects = Vec::new();
        for o in 0..data.objects.len() {
            let svc = data.svc_arrays(o)?;
            let mut svc_starts = vec![0];
            for a in &svc {
                svc_starts.push(svc_starts.last().copied().unwrap_or(0) + a.len());
            }
            let stored = &data.objects[o];
            objects.push(ObjectState {
                name: stored.name.clone(),
                mesh: stored.mesh.clone(),
                material: stored.material,
                pow: brdf::PowTable::new(stored.material.exponent),
                motion: stored.motion,
                translation: Vec3::ZERO,
                svc,
                svc_starts,
                layout: data.layouts[o],
                field: data.field_arrays(o)?,
                merged: Vec::new(),
                lists: Vec::new(),
                keys: Vec::new(),
                decoded: FieldCache::default(),
                svc_refined: Vec::new(),
                pending: Vec::new(),
            });
        }
        let mut builder = LightTreeBuilder::new(&tree);
        let light = builder.build(env);
        let mut frame = Frame {
            tree,
            objects,
            builder,
            light,
            sun_rays: Some(SunRays::default()),
            sun: None,
            origin_offset: data.svc_origin_offset(),
            // Built by `light_state` below, with the sun's leaves out when they are cast.
            specular: Vec::new(),
            nodes: Vec::new(),
            merges: 0,
            algorithm: MergeAlgorithm::Counter,
            inside: InsideSamples::default(),
            last_move: MoveTiming::default(),
            eye: std::sync::Mutex::new(None),
            defer: true,
            spot_merges: std::sync::atomic::AtomicU64::new(0),
        };
        frame.set_svc_cache(true)?;
        // The sun and the shading table before the merges build the lists.
        frame.light_state();
        for o in 0..frame.objects.len() {
            let n = frame.objects[o].mesh.vertex_count();
            let keys: Vec<Vec<FieldKey>> = (0..n).map(|v| frame.keys(o, v)).collect();
            let mut merged = vec![MergedCut::default(); n];
            let mut lists = vec![ShadeList::default(); n];
            let mut cache = FieldCache::default();
            frame.merge_all(
                o,
                &keys,
                &vec![true; n],
                &mut merged,
                &mut lists,
                &mut cache,
                &mut MoveTiming::default(),
            )?;
            frame.objects[o].decoded = cache;
            frame.objects[o].pending = vec![false; n];
            frame.objects[o].keys = keys;
            frame.objects[o].merged = merged;
            frame.objects[o].lists = lists;
        }
        Ok(frame)
    }

    /// The direction tree.
    pub fn tree(&self) -> &DirectionTree {
        &self.tree
    }

    /// The light tree of the environment (the sun's leaves included, also with sun rays on).
    pub fn light(&self) -> &LightTree {
        &self.light
    }

    /// Number of objects.
    pub fn object_count(&self) -> usize {
        self.objects.len()
    }

    /// Index of the object called `name`.
    pub fn object_index(&self, name: &str) -> Option<usize> {
        self.objects.iter().position(|o| o.name == name)
    }

    /// Object `o`'s name, mesh at rest, material, motion and translation.
    pub fn object(&self, o: usize) -> (&str, &Mesh, &Material, Motion, Vec3) {
        let s = &self.objects[o];
        (&s.name, &s.mesh, &s.material, s.motion, s.translation)
    }

    /// Vertices re-merged by moves so far, and by camera turns or [`Frame::merge_pending`]
    /// merging what moves left waiting ([`Frame::set_deferred_merges`]; the merges at setup are
    /// not counted, nor [`Frame::shade`]'s on-the-spot ones: [`Frame::spot_merges`]). BRDF and
    /// lighting edits never merge.
    pub fn merges(&self) -> u64 {
        self.merges
    }

    /// Vertices [`Frame::shade`] merged on the spot without keeping them: waiting vertices
    /// (deferred merges) facing an eye that no [`Frame::set_eye`] announced.
    pub fn spot_merges(&self) -> u64 {
        self.spot_merges.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Chooses the merge that later moves use.
    pub fn set_merge_algorithm(&mut self, algorithm: MergeAlgorithm) {
        self.algorithm = algorithm;
    }

    /// Where the last [`Frame::translate`]'s time went.
    pub fn last_move(&self) -> MoveTiming {
        self.last_move
    }

    /// Bytes a shading pass reads from the shading lists (node index and weight per entry, and
    /// the diffuse sum per vertex): with the machine's memory bandwidth, a floor under its time.
    pub fn shade_bytes(&self) -> usize {
        self.objects
            .iter()
            .flat_map(|s| &s.lists)
            .map(|l| l.nodes.len() * (size_of::<u32>() + size_of::<f32>()) + size_of::<Vec3>())
            .sum()
    }

    /// Bytes of every vertex's merged cut (height u8, value f32 and level-order index u32 per
    /// node): streaming them is the floor under a shading pass.
    pub fn merged_bytes(&self) -> usize {
        self.objects
            .iter()
            .flat_map(|s| &s.merged)
            .map(|m| m.heights.len() * (size_of::<u8>() + size_of::<f32>() + size_of::<u32>()))
            .sum()
    }

    /// Keeps every vertex's SVC decoded (`on`, the default) or decodes it at every merge.
    /// Keeping them spares a move the SVCs' decoding (split flags walked bit by bit) at
    /// [`Frame::svc_cache_bytes`] of memory (8 bytes a node); `cargo xtask bench` reports both.
    pub fn set_svc_cache(&mut self, on: bool) -> Result<(), FrameError> {
        for o in 0..self.objects.len() {
            let s = &self.objects[o];
            if !on {
                self.objects[o].svc_refined = Vec::new();
            } else if s.svc_refined.is_empty() {
                let cached = (0..s.mesh.vertex_count())
                    .into_par_iter()
                    .map(|v| {
                        let err = |reason: String| FrameError::Cut { object: o, vertex: v, reason };
                        Refinement::new(&[&s.svc_cut(v).map_err(err)?]).map_err(|e| err(e.to_string()))
                    })
                    .collect::<Result<_, _>>()?;
                self.objects[o].svc_refined = cached;
            }
        }
        Ok(())
    }

    /// Bytes of the decoded SVCs kept for merging (0 with the cache off).
    pub fn svc_cache_bytes(&self) -> usize {
        self.objects.iter().flat_map(|s| &s.svc_refined).map(Refinement::bytes).sum()
    }

    /// The merged cut of vertex `v` of object `o`, as of its last merge: a vertex whose merge
    /// waits ([`Frame::set_deferred_merges`], [`Frame::pending_merges`]) still has the cut of
    /// its field inputs before the move.
    pub fn merged(&self, o: usize, v: usize) -> &MergedCut {
        &self.objects[o].merged[v]
    }

    /// The SVC of vertex `v` of object `o`.
    pub fn svc(&self, o: usize, v: usize) -> Result<Cut, String> {
        self.objects[o].svc_cut(v)
    }

    /// The objects whose fields shadow vertex `v` of object `o` at the current translations,
    /// with their layouts (centre at rest; add the object's translation).
    pub fn field_sources(&self, o: usize, v: usize) -> Vec<(usize, FieldLayout)> {
        self.objects[o].keys[v]
            .iter()
            .filter_map(|k| self.objects.get(k.object as usize)?.layout.map(|l| (k.object as usize, l)))
            .collect()
    }

    /// The field inputs of vertex `v` of object `o` at the current translations.
    fn keys(&self, o: usize, v: usize) -> Vec<FieldKey> {
        let me = &self.objects[o];
        let p = me.mesh.positions()[v] + me.translation;
        let mut keys = Vec::new();
        for (j, other) in self.objects.iter().enumerate() {
            let Some(layout) = other.layout else { continue };
            if j == o || (me.motion == Motion::Static && other.motion == Motion::Static) {
                continue;
            }
            let Some(mut samples) = layout.lookup(p - other.translation) else { continue };
            let kept = self.inside.apply(&mut samples, |x| other.field[x.sphere as usize].inside(x.point as usize));
            keys.push(FieldKey { object: j as u32, samples: (kept > 0).then_some(samples) });
        }
        keys
    }

    /// Decodes the field cuts of `wanted` (sorted samples), taking those `old` holds (sorted
    /// too) from it.
    fn decode_samples(
        &self,
        o: usize,
        vertex: usize,
        wanted: &[(u32, u32, u32)],
        old_keys: Vec<(u32, u32, u32)>,
        old_cuts: Vec<Cut>,
    ) -> Result<Vec<Cut>, FrameError> {
        let reused = take_held(old_keys, old_cuts, wanted);
        wanted
            .par_iter()
            .zip(reused.into_par_iter())
            .map(|(&(j, sphere, point), hit)| match hit {
                Some(c) => Ok(c),
                None => self.objects[j as usize].field[sphere as usize].cut(point as usize),
            })
            .collect::<Result<_, String>>()
            .map_err(|reason| FrameError::Cut { object: o, vertex, reason })
    }

    /// Merges the vertices of object `o` marked in `changed` with their keys into `merged`
    /// and builds their shading `lists` (in place, reusing each buffer), in parallel. Returns
    /// how many were merged.
    #[allow(clippy::too_many_arguments)]
    fn merge_all(
        &self,
        o: usize,
        keys: &[Vec<FieldKey>],
        changed: &[bool],
        merged: &mut [MergedCut],
        lists: &mut [ShadeList],
        cache: &mut FieldCache,
        timing: &mut MoveTiming,
    ) -> Result<usize, FrameError> {
        let vertices: Vec<usize> = (0..changed.len()).filter(|&v| changed[v]).collect();
        let first = vertices.first().copied().unwrap_or(0);
        let me = &self.objects[o];
        let normals = me.mesh.normals();
        let eye = self.eye();
        let facing = |v: usize| eye.is_none_or(|e| me.faces(v, e));
        let table = &self.nodes;
        let h = self.tree.height();
        let old = std::mem::take(cache);
        let occluded = |v: usize| keys[v].iter().any(|k| k.samples.is_none());
        let full_zero = || full_zero(h);
        let start = Instant::now();
        let result = match self.algorithm {
            MergeAlgorithm::Counter => {
                // The cells the vertices use; those the last move refined are kept.
                let mut cells: Vec<CellKey> =
                    vertices.iter().flat_map(|&v| keys[v].iter()).filter_map(|k| CellKey::of(k).map(|c| c.0)).collect();
                cells.sort_unstable();
                cells.dedup();
                let reused = take_held(old.cells, old.refined, &cells);
                // The new cells' samples, each decoded once.
                let mut wanted: Vec<(u32, u32, u32)> = cells
                    .iter()
                    .zip(&reused)
                    .filter(|(_, r)| r.is_none())
                    .flat_map(|(c, _)| c.samples().iter().copied())
                    .collect();
                wanted.sort_unstable();
                wanted.dedup();
                timing.refine_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let decoded = self.decode_samples(o, first, &wanted, old.keys, old.cuts)?;
                timing.decode_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let refined: Vec<Refinement> = cells
                    .par_iter()
                    .zip(reused.into_par_iter())
                    .map(|(c, hit)| match hit {
                        Some(r) => Ok(r),
                        None => {
                            let cuts: Vec<&Cut> = c
                                .samples()
                                .iter()
                                .map(|x| {
                                    &decoded
                                        [wanted.binary_search(x).unwrap_or_else(|_| unreachable!("collected above"))]
                                })
                                .collect();
                            Refinement::new(&cuts)
                        }
                    })
                    .collect::<Result<_, _>>()
                    .map_err(|e| FrameError::Cut { object: o, vertex: first, reason: e.to_string() })?;
                timing.refine_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let result = merged
                    .par_iter_mut()
                    .zip(lists.par_iter_mut())
                    .enumerate()
                    .filter(|(v, _)| changed[*v])
                    .try_for_each_init(
                        || (Refinement::default(), Vec::new()),
                        |(scratch, below), (v, (out, list))| {
                            if occluded(v) {
                                *out = full_zero();
                                list.clear();
                                return Ok(());
                            }
                            let err = |reason: String| FrameError::Cut { object: o, vertex: v, reason };
                            let svc = match me.svc_refined.get(v) {
                                Some(cached) => cached,
                                None => {
                                    scratch.rebuild(&[&me.svc_cut(v).map_err(err)?]).map_err(|e| err(e.to_string()))?;
                                    &*scratch
                                }
                            };
                            let lookups: Vec<(CellKey, [f32; 8])> = keys[v].iter().filter_map(CellKey::of).collect();
                            let mut factors = Vec::with_capacity(1 + lookups.len());
                            factors.push(Factor { refinement: svc, weights: &[1.0] });
                            for (cell, weights) in &lookups {
                                let c = cells.binary_search(cell).unwrap_or_else(|_| unreachable!("collected above"));
                                factors.push(Factor {
                                    refinement: &refined[c],
                                    weights: &weights[..usize::from(cell.len)],
                                });
                            }
                            merge_refined(&factors, out).map_err(|e| err(e.to_string()))?;
                            // The list while the cut is still in cache.
                            if facing(v) {
                                list.rebuild(out, normals[v], table, Some(svc.ends()), below);
                            } else {
                                list.mark_stale();
                            }
                            Ok(())
                        },
                    );
                timing.merge_s += start.elapsed().as_secs_f64();
                *cache = FieldCache { keys: wanted, cuts: decoded, cells, refined };
                result
            }
            MergeAlgorithm::Index => {
                // Every sample the vertices use, decoded once and converted to indices.
                let mut wanted: Vec<(u32, u32, u32)> = vertices
                    .iter()
                    .flat_map(|&v| keys[v].iter())
                    .filter_map(|k| CellKey::of(k).map(|c| c.0))
                    .flat_map(|c| c.samples().to_vec())
                    .collect();
                wanted.sort_unstable();
                wanted.dedup();
                let decoded = self.decode_samples(o, first, &wanted, old.keys, old.cuts)?;
                let decoded_index: Vec<IndexCut> = decoded.par_iter().map(IndexCut::from_cut).collect();
                timing.decode_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let result = merged
                    .par_iter_mut()
                    .zip(lists.par_iter_mut())
                    .enumerate()
                    .filter(|(v, _)| changed[*v])
                    .try_for_each(|(v, (out, list))| {
                        if occluded(v) {
                            *out = full_zero();
                            list.clear();
                            return Ok(());
                        }
                        let err = |reason: String| FrameError::Cut { object: o, vertex: v, reason };
                        let svc_cut = me.svc_cut(v).map_err(err)?;
                        let svc_ends = node_ends(&svc_cut);
                        let svc = IndexCut::from_cut(&svc_cut);
                        let svc_refs = [&svc];
                        let lookups: Vec<(CellKey, [f32; 8])> = keys[v].iter().filter_map(CellKey::of).collect();
                        let cuts: Vec<Vec<&IndexCut>> = lookups
                            .iter()
                            .map(|(c, _)| {
                                c.samples()
                                    .iter()
                                    .map(|x| {
                                        &decoded_index[wanted
                                            .binary_search(x)
                                            .unwrap_or_else(|_| unreachable!("collected above"))]
                                    })
                                    .collect()
                            })
                            .collect();
                        let mut groups = vec![IndexGroup { cuts: &svc_refs, weights: &[1.0] }];
                        groups.extend(
                            cuts.iter()
                                .zip(&lookups)
                                .map(|(c, (cell, w))| IndexGroup { cuts: c, weights: &w[..usize::from(cell.len)] }),
                        );
                        baseline::merge(&groups, out).map_err(|e| err(e.to_string()))?;
                        if facing(v) {
                            list.rebuild(out, normals[v], table, Some(&svc_ends), &mut Vec::new());
                        } else {
                            list.mark_stale();
                        }
                        Ok(())
                    });
                timing.merge_s += start.elapsed().as_secs_f64();
                *cache = FieldCache { keys: wanted, cuts: decoded, cells: Vec::new(), refined: Vec::new() };
                result
            }
        };
        result.map(|()| vertices.len())
    }

    /// Moves object `o` to `translation` (from its rest position) and re-merges the vertices
    /// whose field inputs changed: its own, and other objects' vertices near it. Returns how
    /// many vertices were merged.
    pub fn translate(&mut self, o: usize, translation: Vec3) -> Result<usize, FrameError> {
        self.objects[o].translation = translation;
        self.rekey(true)
    }

    /// How field lookups treat samples inside the object (default [`InsideSamples::Occluded`]);
    /// re-merges the vertices whose field inputs change. Returns how many.
    pub fn set_inside_samples(&mut self, inside: InsideSamples) -> Result<usize, FrameError> {
        self.inside = inside;
        self.rekey(true)
    }

    /// Looks up every vertex's field inputs again and re-merges those that changed (with
    /// deferred merges, those facing the eye; the others wait). `record`: keep the timing as
    /// the last move's.
    fn rekey(&mut self, record: bool) -> Result<usize, FrameError> {
        let mut total = 0;
        let mut timing = MoveTiming::default();
        let eye = self.eye().filter(|_| self.defer);
        for k in 0..self.objects.len() {
            let n = self.objects[k].mesh.vertex_count();
            let start = Instant::now();
            let mut new_keys: Vec<Vec<FieldKey>> = (0..n).into_par_iter().map(|v| self.keys(k, v)).collect();
            let state = &self.objects[k];
            let differs: Vec<bool> = (0..n).map(|v| new_keys[v] != state.keys[v]).collect();
            let changed: Vec<bool> = (0..n).map(|v| differs[v] && eye.is_none_or(|e| state.faces(v, e))).collect();
            timing.keys_s += start.elapsed().as_secs_f64();
            let mut merged = std::mem::take(&mut self.objects[k].merged);
            let mut lists = std::mem::take(&mut self.objects[k].lists);
            let mut cache = std::mem::take(&mut self.objects[k].decoded);
            let result = self.merge_all(k, &new_keys, &changed, &mut merged, &mut lists, &mut cache, &mut timing);
            let state = &mut self.objects[k];
            state.merged = merged;
            state.lists = lists;
            state.decoded = cache;
            // A waiting vertex keeps the keys of its merged cut (the next move compares with
            // them) and no list; one whose inputs are back to its cut's waits no more.
            for v in 0..n {
                state.pending[v] = differs[v] && !changed[v];
                if state.pending[v] {
                    new_keys[v] = state.keys[v].clone();
                    state.lists[v].mark_stale();
                    timing.deferred += 1;
                }
            }
            match result {
                Ok(count) => total += count,
                Err(e) => {
                    // Some changed vertices may hold new cuts: key them as unknown so that any
                    // later move merges them again.
                    let unknown = vec![FieldKey { object: u32::MAX, samples: None }];
                    for (v, c) in changed.iter().enumerate() {
                        if *c {
                            state.keys[v] = unknown.clone();
                        }
                    }
                    return Err(e);
                }
            }
            state.keys = new_keys;
        }
        if let Some(sun) = self.sun.as_mut() {
            let start = Instant::now();
            timing.sun_rays = sun.update(&placed(&self.objects));
            timing.sun_s = start.elapsed().as_secs_f64();
        }
        self.merges += total as u64;
        timing.vertices = total;
        if record {
            self.last_move = timing;
        }
        Ok(total)
    }

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
        if defer || self.pending_merges() == 0 { Ok(0) } else { self.rekey(false) }
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
        let merged = self.rekey(false);
        self.defer = defer;
        merged
    }

    /// Vertex `v`'s cut at the current field inputs, merged on the spot and not kept (for a
    /// vertex whose merge waits): the cut a merge would keep, bit for bit.
    fn merge_one(&self, o: usize, v: usize, out: &mut MergedCut) -> Result<(), FrameError> {
        let me = &self.objects[o];
        let err = |reason: String| FrameError::Cut { object: o, vertex: v, reason };
        let keys = self.keys(o, v);
        if keys.iter().any(|k| k.samples.is_none()) {
            *out = full_zero(self.tree.height());
            return Ok(());
        }
        let own;
        let svc = match me.svc_refined.get(v) {
            Some(cached) => cached,
            None => {
                own = Refinement::new(&[&me.svc_cut(v).map_err(err)?]).map_err(|e| err(e.to_string()))?;
                &own
            }
        };
        let cells = keys
            .iter()
            .filter_map(CellKey::of)
            .map(|(cell, weights)| {
                let cuts = cell
                    .samples()
                    .iter()
                    .map(|&(j, sphere, point)| self.objects[j as usize].field[sphere as usize].cut(point as usize))
                    .collect::<Result<Vec<Cut>, String>>()
                    .map_err(err)?;
                let refined = Refinement::new(&cuts.iter().collect::<Vec<_>>()).map_err(|e| err(e.to_string()))?;
                Ok((refined, weights, usize::from(cell.len)))
            })
            .collect::<Result<Vec<_>, FrameError>>()?;
        let mut factors = vec![Factor { refinement: svc, weights: &[1.0] }];
        factors.extend(cells.iter().map(|(r, w, len)| Factor { refinement: r, weights: &w[..*len] }));
        merge_refined(&factors, out).map_err(|e| err(e.to_string()))?;
        Ok(())
    }

    /// Changes object `o`'s material (no merge).
    pub fn set_material(&mut self, o: usize, material: Material) {
        let s = &mut self.objects[o];
        if s.material.exponent != material.exponent {
            s.pow = brdf::PowTable::new(material.exponent);
        }
        s.material = material;
    }

    /// Rebuilds the light tree for a new or rotated environment (no merge; with sun rays on,
    /// the sun's rays are cast again).
    pub fn set_environment(&mut self, env: &EnvMap) {
        self.light = self.builder.build(env);
        self.relight();
    }

    /// Casts the sun's leaves by rays at run time instead of through the cuts (the default,
    /// [`SunRays::default`]; `None`: the paper's cuts for all light). See [`crate::sun`]. No
    /// merge.
    pub fn set_sun_rays(&mut self, rays: Option<SunRays>) {
        self.sun_rays = rays;
        self.relight();
    }

    /// The sun-rays setting (`None`: all light through the cuts).
    pub fn sun_rays(&self) -> Option<SunRays> {
        self.sun_rays
    }

    /// Leaves of the light cast as the sun by rays (0 with sun rays off, or no sun).
    pub fn sun_leaves(&self) -> usize {
        self.sun.as_ref().map_or(0, Sun::len)
    }

    /// The sun, the shading table and every list for the current light and sun setting.
    fn relight(&mut self) {
        self.light_state();
        self.relist_all();
    }

    /// The sun and the shading table for the current light and sun setting.
    fn light_state(&mut self) {
        let leaves = self.sun_rays.map(|r| sun::sun_leaves(&self.light, &r)).unwrap_or_default();
        // The objects' hierarchies outlive a lighting change.
        let old = self.sun.take();
        if leaves.is_empty() {
            self.nodes = shade_nodes(&self.tree, &self.light);
        } else {
            let (dirs, offset) = (self.tree.leaf_directions(), self.origin_offset);
            self.sun = Some(Sun::new(&self.light, &leaves, dirs, &placed(&self.objects), offset, old));
            self.nodes = shade_nodes(&self.tree, &sun::without(&self.light, &leaves));
        }
        self.specular = specular_nodes(&self.nodes);
    }

    /// Rebuilds the shading lists after a lighting change: those of the vertices facing the
    /// last eye (all without one); the others' are marked stale.
    fn relist_all(&mut self) {
        let eye = self.eye();
        let nodes = &self.nodes;
        for s in &mut self.objects {
            let mut lists = std::mem::take(&mut s.lists);
            let state = &*s;
            lists.par_iter_mut().enumerate().for_each_init(Vec::new, |below, (v, list)| {
                if !state.pending[v] && eye.is_none_or(|e| state.faces(v, e)) {
                    state.relist(v, nodes, list, below);
                } else {
                    list.mark_stale();
                }
            });
            s.lists = lists;
        }
    }

    /// The eye that merges build shading lists for.
    fn eye(&self) -> Option<Vec3> {
        *self.eye.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Sets the eye later merges and lighting changes build shading lists for (only the
    /// vertices facing it need one; [`Frame::shade`] sets it too) and builds the stale lists of
    /// the vertices facing it now: after a camera turn, so that shading from it again need not
    /// build them each time. Merges the vertices facing it whose merge waits (none unless a
    /// move left some: [`Frame::set_deferred_merges`]); returns how many.
    pub fn set_eye(&mut self, eye: Vec3) -> Result<usize, FrameError> {
        *self.eye.get_mut().unwrap_or_else(std::sync::PoisonError::into_inner) = Some(eye);
        let waiting = self.objects.iter().any(|s| s.pending.iter().enumerate().any(|(v, &p)| p && s.faces(v, eye)));
        let merged = if waiting { self.rekey(false)? } else { 0 };
        let nodes = &self.nodes;
        for s in &mut self.objects {
            let mut lists = std::mem::take(&mut s.lists);
            let state = &*s;
            lists
                .par_iter_mut()
                .enumerate()
                .filter(|(v, l)| l.stale && !state.pending[*v] && state.faces(*v, eye))
                .for_each_init(Vec::new, |below, (v, list)| state.relist(v, nodes, list, below));
            s.lists = lists;
        }
        Ok(merged)
    }

    /// World positions of object `o`'s vertices at its current translation.
    pub fn positions(&self, o: usize) -> Vec<Vec3> {
        let s = &self.objects[o];
        s.mesh.positions().iter().map(|&p| p + s.translation).collect()
    }

    /// Outgoing radiance toward `eye` of vertex `v` of object `o` if its merged cut were `cut`,
    /// a product with the vertex's SVC as a factor (shaded exactly as [`Frame::shade`] does):
    /// for measuring what other cuts would give.
    pub fn shade_cut(&self, o: usize, v: usize, cut: &MergedCut, eye: Vec3) -> Vec3 {
        let s = &self.objects[o];
        let list = ShadeList::new(cut, s.mesh.normals()[v], &self.nodes, s.svc_ends(v).as_deref());
        self.shade_vertex(o, v, &list, eye)
    }

    /// As [`Frame::shade_cut`] for a cut whose every value is its own node's mean of
    /// V·max(0, n·ω) (not a product with the SVC).
    pub fn shade_cut_means(&self, o: usize, v: usize, cut: &MergedCut, eye: Vec3) -> Vec3 {
        let s = &self.objects[o];
        let list = ShadeList::new(cut, s.mesh.normals()[v], &self.nodes, None);
        self.shade_vertex(o, v, &list, eye)
    }

    fn shade_vertex(&self, o: usize, v: usize, list: &ShadeList, eye: Vec3) -> Vec3 {
        let s = &self.objects[o];
        let x = s.mesh.positions()[v] + s.translation;
        let n = s.mesh.normals()[v];
        if !faces(n, x, eye) {
            return Vec3::ZERO;
        }
        let wo = (eye - x).normalize_or_zero();
        let diffuse = Vec3::from(s.material.kd) / std::f32::consts::PI * list.diffuse;
        let pow = s.pow.as_ref().map_or(brdf::Pow::Exact(s.material.exponent), brdf::Pow::Table);
        let lobe = brdf::Lobe::with_pow(&s.material, n, wo, pow);
        let sun = self.sun.as_ref().map_or(Vec3::ZERO, |sun| sun.radiance(o, v, &s.material, n, wo));
        // One loop per lobe kind, so the match leaves the inner loop.
        sun + diffuse
            + match lobe {
                brdf::Lobe::None => Vec3::ZERO,
                brdf::Lobe::BlinnPhong { n, wo, scale, pow: brdf::Pow::Table(t) } => {
                    list.specular_lanes(&self.specular, t, scale, blinn_phong_argument(n, wo))
                }
                brdf::Lobe::Phong { mirror, scale, pow: brdf::Pow::Table(t) } => {
                    list.specular_lanes(&self.specular, t, scale, phong_argument(mirror))
                }
                brdf::Lobe::BlinnPhong { .. } => list.specular(&self.specular, |d| lobe.eval(d)),
                brdf::Lobe::Phong { .. } => list.specular(&self.specular, |d| lobe.eval(d)),
                brdf::Lobe::Ggx { .. } => list.specular(&self.specular, |d| lobe.eval(d)),
            }
    }

    /// Outgoing radiance toward `eye` of every vertex of every object: B = Σ_k v_k f_r l_k over
    /// its merged cut, with the light-weighted node directions and cosines of the module
    /// documentation (plus the sun's leaves by rays, with [`Frame::set_sun_rays`]).
    ///
    /// Vertices whose list is stale build it on the spot without keeping it ([`Frame::set_eye`]
    /// keeps them), and so do vertices facing `eye` whose merge waits with their cut (a read
    /// error there, which setup's decoding of the same file makes unlikely, shades the vertex
    /// black; [`Frame::set_eye`] reports it). `eye` becomes the eye later merges build lists for.
    pub fn shade(&self, eye: Vec3) -> Vec<Vec<Vec3>> {
        *self.eye.lock().unwrap_or_else(std::sync::PoisonError::into_inner) = Some(eye);
        self.objects
            .iter()
            .enumerate()
            .map(|(o, s)| {
                s.lists
                    .par_iter()
                    .enumerate()
                    .map_init(
                        || (ShadeList::default(), Vec::new(), MergedCut::default()),
                        |(built, below, cut), (v, list)| {
                            if s.pending[v] && s.faces(v, eye) {
                                self.spot_merges.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                                if self.merge_one(o, v, cut).is_err() {
                                    return Vec3::ZERO;
                                }
                                let ends = s.svc_ends(v);
                                built.rebuild(cut, s.mesh.normals()[v], &self.nodes, ends.as_deref(), below);
                                self.shade_vertex(o, v, built, eye)
                            } else if list.stale && s.faces(v, eye) {
                                s.relist(v, &self.nodes, built, below);
                                self.shade_vertex(o, v, built, eye)
                            } else {
                                self.shade_vertex(o, v, list, eye)
                            }
                        },
                    )
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vcut_scene::BrdfModel;

    /// A merged node inside a larger SVC node takes its share of the SVC as the SVC node's
    /// visibility times its own cosine: an open plane's SVC node split in two by a field that
    /// leaves both halves visible shades as the two halves' own means would, where the old
    /// weight (the SVC node's mean cosine for both) was off.
    #[test]
    fn a_split_svc_node_takes_its_own_cosine() {
        let count = 256usize;
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let dirs: Vec<Vec3> = (0..count)
            .map(|i| {
                let y = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
                let r = (1.0 - y * y).sqrt();
                let phi = golden * i as f32;
                Vec3::new(r * phi.cos(), y, r * phi.sin())
            })
            .collect();
        let tree = DirectionTree::build(&dirs, &vec![4.0 * std::f64::consts::PI / count as f64; count]).unwrap();
        let light = LightTreeBuilder::new(&tree).build(&EnvMap::constant([1.0; 3]));
        let table = shade_nodes(&tree, &light);
        let n = Vec3::new(0.3, 0.9, 0.2).normalize();
        let root = tree.height();
        let h = 3u32;
        let index = |h: u32, leaf: u32| ((1u32 << (root - h)) + (leaf >> h) - 1) as usize;
        // The mean of max(0, n·ω) over a node's leaves: an unoccluded SVC's exact value.
        let mean_cos = |h: u32, leaf: u32| {
            let k = index(h, leaf);
            let r = tree.leaf_range(k as u32);
            tree.leaf_directions()[r.clone()].iter().map(|d| n.dot(*d).max(0.0)).sum::<f32>() / r.len() as f32
        };
        // An SVC node wholly above the horizon whose halves' cosines differ.
        let a = (0..(count as u32 >> h))
            .map(|o| o << h)
            .filter(|&leaf| {
                let t = &table[index(h, leaf)];
                n.dot(t.axis) >= t.sin_half && n.dot(t.mean) > 1e-3
            })
            .max_by(|&x, &y| {
                let split = |l: u32| (mean_cos(h - 1, l) - mean_cos(h - 1, l + (1 << (h - 1)))).abs();
                split(x).total_cmp(&split(y))
            })
            .expect("a node above the horizon");
        let svc_ends: Vec<u32> = (1..=(count as u32 >> h)).map(|i| i << h).collect();
        // The product with the field: A split into its halves, each with A's SVC value; and
        // the same cut with every node's own mean.
        let (mut product, mut own) = (MergedCut { root_height: root, ..MergedCut::default() }, MergedCut::default());
        for start in (0..count as u32).step_by(1 << h) {
            let halves: &[(u32, u32)] =
                if start == a { &[(h - 1, start), (h - 1, start + (1 << (h - 1)))] } else { &[(h, start)] };
            for &(g, leaf) in halves {
                product.heights.push(g as u8);
                product.indices.push(index(g, leaf) as u32);
                product.values.push(mean_cos(h, start));
            }
        }
        own.clone_from(&product);
        for (v, &k) in own.values.iter_mut().zip(&product.indices) {
            let (g, leaf) = tree.node(k);
            *v = mean_cos(g, leaf);
        }
        let split = ShadeList::new(&product, n, &table, Some(&svc_ends));
        let exact = ShadeList::new(&own, n, &table, None);
        let old = ShadeList::new(&product, n, &table, None);
        assert_eq!(split.nodes, exact.nodes);
        for (i, (w, e)) in split.weights.iter().zip(&exact.weights).enumerate() {
            assert!((w - e).abs() <= 1e-5 * e.abs().max(1e-3), "node {i}: {w} vs {e}");
        }
        let worst =
            old.weights.iter().zip(&exact.weights).map(|(w, e)| (w - e).abs() / e.abs().max(1e-3)).fold(0.0, f32::max);
        assert!(worst > 1e-2, "the old weights were off by {worst} only: the test splits nothing");
        assert!((split.diffuse - exact.diffuse).abs().max_element() <= 1e-5 * exact.diffuse.max_element());
    }

    #[test]
    fn take_held_moves_out_the_values_of_wanted_keys() {
        let got = take_held(vec![1, 3, 5, 8], vec!["a", "c", "e", "h"], &[0, 3, 4, 8, 9]);
        assert_eq!(got, vec![None, Some("c"), None, Some("h"), None]);
        assert_eq!(take_held(Vec::<u32>::new(), Vec::<u8>::new(), &[1]), vec![None]);
    }

    /// The eight-lane specular sum is the per-node one up to rounding, for list lengths that
    /// fill the lanes, leave a remainder, or are empty.
    #[test]
    fn lanes_agree_with_the_per_node_sum() {
        let mut seed = 1u64;
        let mut unit = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let n = Vec3::new(0.2, 0.9, 0.1).normalize();
        let table: Vec<SpecularNode> = (0..64)
            .map(|_| {
                // Directions above the horizon of n, lights up to a bright sun.
                let d = (Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) + n).normalize();
                SpecularNode { dir: d, light: Vec3::new(unit(), unit(), unit()) * 1e3 * unit() }
            })
            .collect();
        let wo = Vec3::new(-0.3, 0.8, 0.4).normalize();
        for (model, exponent) in [(BrdfModel::BlinnPhong, 70.0), (BrdfModel::Phong, 15.0)] {
            let m = Material { model, exponent, ..Material::default() };
            let pow = brdf::PowTable::new(exponent).unwrap();
            let lobe = brdf::Lobe::with_pow(&m, n, wo, brdf::Pow::Table(&pow));
            for len in [0usize, 1, 7, 8, 9, 41] {
                let list = ShadeList {
                    nodes: (0..len as u32).map(|k| (k * 7) % 64).collect(),
                    weights: (0..len).map(|_| unit()).collect(),
                    diffuse: Vec3::ZERO,
                    stale: false,
                };
                let each = list.specular(&table, |d| lobe.eval(d));
                let lanes = match lobe {
                    brdf::Lobe::BlinnPhong { scale, .. } => {
                        list.specular_lanes(&table, &pow, scale, blinn_phong_argument(n, wo))
                    }
                    brdf::Lobe::Phong { mirror, scale, .. } => {
                        list.specular_lanes(&table, &pow, scale, phong_argument(mirror))
                    }
                    _ => unreachable!("two table lobes"),
                };
                let err = (lanes - each).abs().max_element();
                assert!(err <= 1e-5 * each.abs().max_element().max(1e-3), "{model:?}, {len} nodes: {lanes} vs {each}");
                if len > 0 {
                    assert!(each.max_element() > 0.0, "{model:?}: the test lights something");
                }
            }
        }
    }
}
