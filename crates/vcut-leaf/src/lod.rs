//! Level of detail for leaves (the paper's scheme): each leaf — a connected piece of a
//! translucent object — is simplified to coarser meshes by meshoptimizer (through the `meshopt`
//! crate; its simplifier keeps a subset of the original vertices), and the transfer vectors of a
//! coarse vertex are the Gaussian-weighted average of the finest mesh's vertices of the same leaf
//! within a surface radius (Euclidean distance inside one leaf standing for the surface distance;
//! σ = half the coarse level's mean edge length, vertices within 3σ). The sun's map is read at the
//! kept vertex itself: its shadows stay sharp. A frame picks each leaf's level by its size on
//! screen; opaque surfaces are drawn as they are.

use crate::material::Scatter;
use crate::prt::Transfer;
use crate::scene::LeafScene;
use crate::sh::COEFFS;
use glam::Vec3;
use meshopt::SimplifyOptions;
use rayon::prelude::*;

/// Parameters of [`Lod::build`].
#[derive(Debug, Clone, PartialEq)]
pub struct LodParams {
    /// Triangle share each coarser level aims at, relative to the finest (decreasing).
    pub ratios: Vec<f32>,
    /// Largest geometric error the simplifier may introduce, relative to a leaf's size.
    pub max_error: f32,
    /// A leaf whose bounding sphere spans fewer pixels (radius) than `switch_px[k]` is drawn at
    /// level k + 1 or coarser.
    pub switch_px: Vec<f32>,
}

impl Default for LodParams {
    fn default() -> LodParams {
        LodParams { ratios: vec![0.3, 0.1], max_error: 0.05, switch_px: vec![40.0, 12.0] }
    }
}

/// One leaf (a connected piece of a translucent object).
#[derive(Debug, Clone)]
struct Leaf {
    center: Vec3,
    radius: f32,
}

/// One level: per leaf, its triangles and its vertices with their averaged transfer.
#[derive(Debug, Clone)]
struct Level {
    /// Per leaf, the range of `vertices` (and of the transfer arrays) and of `triangles`.
    leaf_vertices: Vec<std::ops::Range<usize>>,
    leaf_triangles: Vec<std::ops::Range<usize>>,
    /// Scene vertex indices kept.
    vertices: Vec<u32>,
    /// Triangles (scene vertex indices).
    triangles: Vec<[u32; 3]>,
    direct: Vec<[[f32; COEFFS]; 2]>,
    indirect: Vec<[[Vec3; COEFFS]; 2]>,
    scatter: Vec<Scatter>,
}

/// The levels of detail of every leaf of a scene.
#[derive(Debug, Clone)]
pub struct Lod {
    leaves: Vec<Leaf>,
    /// Level 0 is the original mesh (its own transfer); then the coarser ones.
    levels: Vec<Level>,
    /// Triangles of opaque objects (never simplified).
    opaque_triangles: Vec<[u32; 3]>,
    opaque_vertices: Vec<u32>,
    switch_px: Vec<f32>,
}

/// The vertices and triangles a frame draws, each leaf at its chosen level.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    /// Scene vertex indices to shade.
    pub vertices: Vec<u32>,
    /// Triangles to draw (scene vertex indices).
    pub triangles: Vec<[u32; 3]>,
    direct: Vec<[[f32; COEFFS]; 2]>,
    indirect: Vec<[[Vec3; COEFFS]; 2]>,
    scatter: Vec<Scatter>,
    /// Leaves drawn at each level.
    pub leaves_per_level: Vec<usize>,
}

impl Selection {
    /// The k-th vertex: its scene index, transfer and (averaged) scattering.
    pub fn vertex(&self, k: usize) -> (usize, &[[f32; COEFFS]; 2], &[[Vec3; COEFFS]; 2], &Scatter) {
        (self.vertices[k] as usize, &self.direct[k], &self.indirect[k], &self.scatter[k])
    }
}

/// A leaf, and per level its triangles and its vertices.
type LeafLevels = (Leaf, Vec<Vec<[u32; 3]>>, Vec<Vec<u32>>);

/// Connected pieces of the translucent triangles (union–find over shared vertices): per piece,
/// its triangle indices.
fn leaves_of(scene: &LeafScene) -> Vec<Vec<usize>> {
    let n = scene.vertex_count();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let translucent = |t: &[u32; 3]| t.iter().all(|&v| scene.scatter()[v as usize].translucent());
    for t in scene.triangles().iter().filter(|t| translucent(t)) {
        let a = find(&mut parent, t[0]);
        for &v in &t[1..] {
            let b = find(&mut parent, v);
            parent[b as usize] = a;
        }
    }
    let mut index = std::collections::HashMap::new();
    let mut pieces: Vec<Vec<usize>> = Vec::new();
    for (i, t) in scene.triangles().iter().enumerate() {
        if !translucent(t) {
            continue;
        }
        let root = find(&mut parent, t[0]);
        let k = *index.entry(root).or_insert_with(|| {
            pieces.push(Vec::new());
            pieces.len() - 1
        });
        pieces[k].push(i);
    }
    pieces
}

impl Lod {
    /// Simplifies every leaf of `scene` and averages `transfer` and the vertices' scattering onto
    /// the kept vertices (after a material edit, build again: coarse levels keep the scattering
    /// they were built with).
    pub fn build(scene: &LeafScene, transfer: &Transfer, params: &LodParams) -> Lod {
        let pieces = leaves_of(scene);
        let pos = scene.positions();
        let tris = scene.triangles();
        let positions: Vec<[f32; 3]> = pos.iter().map(|p| p.to_array()).collect();
        let mut in_leaf = vec![false; scene.vertex_count()];
        let per_leaf: Vec<LeafLevels> = pieces
            .par_iter()
            .map(|piece| {
                let fine: Vec<[u32; 3]> = piece.iter().map(|&t| tris[t]).collect();
                let mut verts: Vec<u32> = fine.iter().flatten().copied().collect();
                verts.sort_unstable();
                verts.dedup();
                let (lo, hi) = verts.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &v| {
                    (lo.min(pos[v as usize]), hi.max(pos[v as usize]))
                });
                let center = (lo + hi) * 0.5;
                let radius = verts.iter().map(|&v| pos[v as usize].distance(center)).fold(0.0f32, f32::max);
                let indices: Vec<u32> = fine.iter().flatten().copied().collect();
                let mut levels_t = vec![fine.clone()];
                let mut levels_v = vec![verts.clone()];
                for &ratio in &params.ratios {
                    let target = ((indices.len() as f32 * ratio) as usize / 3 * 3).max(3);
                    let out = meshopt::simplify_decoder(
                        &indices,
                        &positions,
                        target,
                        params.max_error,
                        SimplifyOptions::Sparse,
                        None,
                    );
                    let coarse: Vec<[u32; 3]> = out.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
                    // A leaf the simplifier cannot reduce keeps the previous level.
                    let coarse = if coarse.is_empty() { levels_t.last().cloned().unwrap_or_default() } else { coarse };
                    let mut cv: Vec<u32> = coarse.iter().flatten().copied().collect();
                    cv.sort_unstable();
                    cv.dedup();
                    levels_t.push(coarse);
                    levels_v.push(cv);
                }
                (Leaf { center, radius }, levels_t, levels_v)
            })
            .collect();
        for (_, _, lv) in &per_leaf {
            for &v in &lv[0] {
                in_leaf[v as usize] = true;
            }
        }
        let nlevels = params.ratios.len() + 1;
        let mut levels: Vec<Level> = (0..nlevels)
            .map(|_| Level {
                leaf_vertices: Vec::new(),
                leaf_triangles: Vec::new(),
                vertices: Vec::new(),
                triangles: Vec::new(),
                direct: Vec::new(),
                indirect: Vec::new(),
                scatter: Vec::new(),
            })
            .collect();
        for (_, lt, lv) in &per_leaf {
            for (k, level) in levels.iter_mut().enumerate() {
                let (v0, t0) = (level.vertices.len(), level.triangles.len());
                level.vertices.extend_from_slice(&lv[k]);
                level.triangles.extend_from_slice(&lt[k]);
                level.leaf_vertices.push(v0..level.vertices.len());
                level.leaf_triangles.push(t0..level.triangles.len());
            }
        }
        // Transfer: level 0 as computed; coarser levels Gaussian-averaged within each leaf.
        for (k, level) in levels.iter_mut().enumerate() {
            let averaged: Vec<Averaged> = (0..per_leaf.len())
                .into_par_iter()
                .flat_map_iter(|leaf| {
                    let (_, lt, lv) = &per_leaf[leaf];
                    let fine = &lv[0];
                    let sigma = if k == 0 { 0.0 } else { 0.5 * mean_edge(&lt[k], pos) };
                    lv[k].iter().map(move |&c| average(c, fine, sigma, scene, transfer)).collect::<Vec<_>>()
                })
                .collect();
            for (d, i, sc) in averaged {
                level.direct.push(d);
                level.indirect.push(i);
                level.scatter.push(sc);
            }
        }
        let opaque_triangles: Vec<[u32; 3]> =
            tris.iter().filter(|t| !t.iter().all(|&v| in_leaf[v as usize])).copied().collect();
        let mut opaque_vertices: Vec<u32> = opaque_triangles.iter().flatten().copied().collect();
        opaque_vertices.sort_unstable();
        opaque_vertices.dedup();
        Lod {
            leaves: per_leaf.into_iter().map(|(l, _, _)| l).collect(),
            levels,
            opaque_triangles,
            opaque_vertices,
            switch_px: params.switch_px.clone(),
        }
    }

    /// Number of levels (the original mesh included).
    pub fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// Vertices of level `k` over all leaves.
    pub fn vertices_at(&self, k: usize) -> usize {
        self.levels[k].vertices.len()
    }

    /// Triangles of level `k` over all leaves.
    pub fn triangles_at(&self, k: usize) -> usize {
        self.levels[k].triangles.len()
    }

    /// The level a leaf of bounding radius `radius` at `center` gets in a `height`-pixel-tall
    /// image seen from `eye` with vertical field of view `fov_y_deg`.
    pub fn level_for(&self, center: Vec3, radius: f32, eye: Vec3, fov_y_deg: f32, height: u32) -> usize {
        let d = center.distance(eye).max(1e-6);
        let px = radius / (d * (fov_y_deg.to_radians() * 0.5).tan()) * height as f32 * 0.5;
        self.switch_px.iter().take_while(|&&s| px < s).count().min(self.levels.len() - 1)
    }

    /// Each leaf at the level its size on screen asks for (`force`: every leaf at one level),
    /// plus every opaque surface with its transfer from `transfer`.
    pub fn select(
        &self,
        scene: &LeafScene,
        transfer: &Transfer,
        eye: Vec3,
        fov_y_deg: f32,
        height: u32,
        force: Option<usize>,
    ) -> Selection {
        let scene_scatter = scene.scatter();
        let mut s = Selection { leaves_per_level: vec![0; self.levels.len()], ..Selection::default() };
        for (i, leaf) in self.leaves.iter().enumerate() {
            let k = force
                .unwrap_or_else(|| self.level_for(leaf.center, leaf.radius, eye, fov_y_deg, height))
                .min(self.levels.len() - 1);
            s.leaves_per_level[k] += 1;
            let level = &self.levels[k];
            let vr = level.leaf_vertices[i].clone();
            s.vertices.extend_from_slice(&level.vertices[vr.clone()]);
            s.direct.extend_from_slice(&level.direct[vr.clone()]);
            s.indirect.extend_from_slice(&level.indirect[vr.clone()]);
            if k == 0 {
                // The full mesh reads the scene's scattering as it is now (after any edit).
                s.scatter.extend(level.vertices[vr].iter().map(|&v| scene_scatter[v as usize]));
            } else {
                s.scatter.extend_from_slice(&level.scatter[vr]);
            }
            s.triangles.extend_from_slice(&level.triangles[level.leaf_triangles[i].clone()]);
        }
        for &v in &self.opaque_vertices {
            s.vertices.push(v);
            s.direct.push(transfer.direct[v as usize]);
            s.indirect.push(transfer.indirect[v as usize]);
            s.scatter.push(scene_scatter[v as usize]);
        }
        s.triangles.extend_from_slice(&self.opaque_triangles);
        s
    }
}

/// Mean edge length of `tris`.
fn mean_edge(tris: &[[u32; 3]], pos: &[Vec3]) -> f32 {
    let (mut sum, mut n) = (0.0f32, 0usize);
    for t in tris {
        for e in 0..3 {
            sum += pos[t[e] as usize].distance(pos[t[(e + 1) % 3] as usize]);
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { sum / n as f32 }
}

/// A coarse vertex's transfer and scattering.
type Averaged = ([[f32; COEFFS]; 2], [[Vec3; COEFFS]; 2], Scatter);

/// The Gaussian-weighted average (σ) of `fine` vertices' transfer and scattering around vertex
/// `c` (within 3σ) — the scattering too, so parameter maps sampled at the vertices are filtered
/// like the light; σ = 0 returns `c`'s own.
fn average(c: u32, fine: &[u32], sigma: f32, scene: &LeafScene, transfer: &Transfer) -> Averaged {
    let c = c as usize;
    let (pos, scatter) = (scene.positions(), scene.scatter());
    if sigma <= 0.0 {
        return (transfer.direct[c], transfer.indirect[c], scatter[c]);
    }
    let mut d = [[0.0f32; COEFFS]; 2];
    let mut ind = [[Vec3::ZERO; COEFFS]; 2];
    let mut sc = Scatter { r: [Vec3::ZERO; 2], t: Vec3::ZERO, gloss: scatter[c].gloss };
    for g in &mut sc.gloss {
        g.rho_s = Vec3::ZERO;
        g.roughness = 0.0;
    }
    let mut wsum = 0.0f32;
    for &j in fine {
        let j = j as usize;
        let r2 = pos[j].distance_squared(pos[c]);
        if r2 > 9.0 * sigma * sigma {
            continue;
        }
        let w = (-r2 / (2.0 * sigma * sigma)).exp();
        wsum += w;
        for side in 0..2 {
            for i in 0..COEFFS {
                d[side][i] += w * transfer.direct[j][side][i];
                ind[side][i] += w * transfer.indirect[j][side][i];
            }
            sc.r[side] += w * scatter[j].r[side];
            sc.gloss[side].rho_s += w * scatter[j].gloss[side].rho_s;
            sc.gloss[side].roughness += w * scatter[j].gloss[side].roughness;
        }
        sc.t += w * scatter[j].t;
    }
    let inv = 1.0 / wsum.max(f32::MIN_POSITIVE);
    for side in 0..2 {
        for i in 0..COEFFS {
            d[side][i] *= inv;
            ind[side][i] *= inv;
        }
        sc.r[side] *= inv;
        sc.gloss[side].rho_s *= inv;
        sc.gloss[side].roughness *= inv;
    }
    sc.t *= inv;
    (d, ind, sc)
}
