//! The light tree: `l_k = ∫_{Ω_k} L(ω) dω` for every node k of the direction tree, so shading
//! reads the light of a cut node by its level-order index.
//!
//! Each leaf holds the environment map's radiance **integrated over that direction's Voronoi
//! cell** — not point-sampled: every (sub-)texel patch goes, with its exact solid angle, to the
//! leaf nearest its centre, so a sun smaller than a cell keeps its exact power and lands in the
//! leaves that cover it. Parents are sums of children in f64; the root equals ∫ L dω of the map
//! up to f64 rounding.
//!
//! Two builders:
//! - [`LightTreeBuilder::build_exact`]: `k × k` patches per texel, exact nearest-leaf search.
//! - [`LightTreeBuilder::build`]: one patch per texel (its centre, after the map's rotation)
//!   through a precomputed cube-map table of nearest leaves, in parallel — for interactive
//!   rotation and map changes. It conserves power exactly too, and bins like texel-centre exact
//!   search except in slivers of cells too thin to cover a table texel's corner or centre.
//!
//! # Invariants
//! Node values are finite and ≥ 0 (maps are, by `vcut-envmap`'s invariant); node k = node 2k+1 +
//! node 2k+2. This crate knows nothing about visibility or BRDFs.
//!
//! # Example
//! ```
//! use vcut_sphere::{DirectionSet, RepulsionParams};
//! use vcut_dirtree::DirectionTree;
//! use vcut_lighttree::LightTreeBuilder;
//! let set = DirectionSet::generate(1024, &RepulsionParams::default(), |_, _| {}).unwrap();
//! let tree = DirectionTree::build(set.directions(), &set.cell_areas()).unwrap();
//! let map = vcut_envmap::procedural::Studio::default().bake(256);
//! let mut builder = LightTreeBuilder::new(&tree);
//! let lights = builder.build(&map);
//! let total = map.total_power();
//! assert!((lights.root()[0] - total[0]).abs() < 1e-9 * total[0]);
//! ```

use glam::{DVec3, Mat3, Vec3};
use rayon::prelude::*;
use vcut_dirtree::{DirectionTree, level_order_index};
use vcut_envmap::{EnvMap, Layout, layout};
use vcut_sphere::grid::SphereGrid;

/// A light tree breaking one of its invariants ([`LightTree::validate`]): a non-finite or
/// negative node, or a parent that is not the sum of its children.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct InvalidLightTree(pub String);

/// Integrated radiance per node of the direction tree, level order.
#[derive(Debug, Clone, PartialEq)]
pub struct LightTree {
    height: u32,
    nodes: Vec<[f64; 3]>,
}

impl LightTree {
    /// Sums leaf values (leaf order, `2^height` of them) up the tree.
    pub fn from_leaves(height: u32, leaves: &[[f64; 3]]) -> LightTree {
        let n = leaves.len();
        let mut nodes = vec![[0.0f64; 3]; 2 * n - 1];
        for (leaf, v) in leaves.iter().enumerate() {
            nodes[level_order_index(height, 0, leaf as u32) as usize] = *v;
        }
        for k in (0..n - 1).rev() {
            let (a, b) = (nodes[2 * k + 1], nodes[2 * k + 2]);
            nodes[k] = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        }
        LightTree { height, nodes }
    }

    /// Root height of the direction tree.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// `l_k` of a level-order index (RGB, f64).
    pub fn node(&self, index: u32) -> [f64; 3] {
        self.nodes[index as usize]
    }

    /// `l_k` as f32, for shading.
    pub fn node_f32(&self, index: u32) -> [f32; 3] {
        self.nodes[index as usize].map(|x| x as f32)
    }

    /// ∫ L dω over the sphere.
    pub fn root(&self) -> [f64; 3] {
        self.nodes[0]
    }

    /// All nodes, level order.
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    /// Leaf values in leaf order.
    pub fn leaves(&self) -> &[[f64; 3]] {
        let n = self.nodes.len().div_ceil(2);
        &self.nodes[n - 1..]
    }

    /// Checks parents equal the sums of their children and every value is finite and ≥ 0.
    pub fn validate(&self) -> Result<(), InvalidLightTree> {
        let n = self.nodes.len().div_ceil(2);
        for (k, v) in self.nodes.iter().enumerate() {
            if v.iter().any(|x| !x.is_finite() || *x < 0.0) {
                return Err(InvalidLightTree(format!("node {k} is {v:?}")));
            }
            if k < n - 1 {
                let (a, b) = (self.nodes[2 * k + 1], self.nodes[2 * k + 2]);
                for c in 0..3 {
                    if (a[c] + b[c] - v[c]).abs() > 1e-12 * v[c].max(1e-300) {
                        return Err(InvalidLightTree(format!("node {k} channel {c} is not the sum of its children")));
                    }
                }
            }
        }
        Ok(())
    }
}

/// Exact nearest-leaf search over the tree's leaf directions.
pub struct LeafLocator {
    dirs: Vec<DVec3>,
    grid: SphereGrid,
}

impl LeafLocator {
    /// A locator for the tree's leaves.
    pub fn new(tree: &DirectionTree) -> Self {
        let dirs: Vec<DVec3> = tree.leaf_directions().iter().map(|d| d.as_dvec3()).collect();
        let s = (4.0 * std::f64::consts::PI / dirs.len() as f64).sqrt();
        let grid = SphereGrid::new(&dirs, 2.0 * s);
        LeafLocator { dirs, grid }
    }

    /// Leaf position nearest to `d` (unit); ties go to the lower leaf.
    pub fn nearest(&self, d: DVec3) -> u32 {
        let mut best = (f64::INFINITY, u32::MAX);
        self.grid.for_each_near(d, |j| {
            let d2 = d.distance_squared(self.dirs[j as usize]);
            if d2 < best.0 || (d2 == best.0 && j < best.1) {
                best = (d2, j);
            }
        });
        // Only a neighbour within one grid cell is certainly the nearest.
        if best.0.sqrt() > self.grid.cell_size() {
            for (j, q) in self.dirs.iter().enumerate() {
                let d2 = d.distance_squared(*q);
                if d2 < best.0 {
                    best = (d2, j as u32);
                }
            }
        }
        best.1
    }
}

/// Edge of the square tiles the table is stored in: 4 × 4 u32 entries fill one 64-byte cache
/// line, so the curve a row of map texels traces across a face stays in one line for several
/// steps (row-major storage made nearly every lookup a cache miss).
const TILE: usize = 4;

/// Position of face texel (i, j) in the tiled table.
#[inline]
fn tiled(res: usize, face: usize, i: usize, j: usize) -> usize {
    let tiles = res / TILE;
    ((face * tiles + j / TILE) * tiles + i / TILE) * TILE * TILE + (j % TILE) * TILE + i % TILE
}

/// Inverse of [`tiled`]: `(face, i, j)`.
fn untile(res: usize, t: usize) -> (usize, usize, usize) {
    let tiles = res / TILE;
    let (tile, within) = (t / (TILE * TILE), t % (TILE * TILE));
    let (ti, rest) = (tile % tiles, tile / tiles);
    let (tj, face) = (rest % tiles, rest / tiles);
    (face, ti * TILE + within % TILE, tj * TILE + within / TILE)
}

/// Marks a table entry that holds candidate leaves rather than one leaf.
const BOUNDARY: u32 = 1 << 31;
/// Where a boundary entry keeps its candidate count (2..=5).
const COUNT_SHIFT: u32 = 28;
/// A boundary entry's offset into the candidate lists.
const OFFSET_MASK: u32 = (1 << COUNT_SHIFT) - 1;
/// Table texels per cell edge. Fewer texels mean more of them straddle a boundary (and carry
/// candidates) but a smaller table: at 2, the table and lists of 32,768 leaves take about 1.3 MB
/// and stay in cache during a rebuild, which is what decides its speed.
const TABLE_TEXELS_PER_CELL: f64 = 2.0;

/// Builds light trees for one direction tree; keeps the lookup table and per-layout texel
/// geometry so rebuilds after a rotation or a new map of the same layout are fast.
pub struct LightTreeBuilder {
    height: u32,
    leaves: usize,
    locator: LeafLocator,
    table_res: usize,
    /// Leaf id, or `BOUNDARY | count << COUNT_SHIFT | offset` into `candidates`.
    table: Vec<u32>,
    /// Sorted, distinct candidate leaves of boundary texels (the nearest leaves of centre and
    /// corners), packed one list after another.
    candidates: Vec<u32>,
    leaf_dirs: Vec<Vec3>,
    texel_cache: Option<(Layout, TexelGeometry)>,
    yaw_cache: Option<YawAssignment>,
}

/// Nearest leaves of world directions on the map's rows, `SUBCOLUMNS` samples per texel column:
/// a map rotated about +Y by any angle moves its texel centres along their rows, so each texel's
/// leaf is read at the sample nearest its rotated centre — an array lookup, row-coherent, exact
/// up to a sliver of 1/(2·SUBCOLUMNS) texel.
struct YawAssignment {
    width: u32,
    height: u32,
    leaves: Vec<u32>,
    /// Per map column (sin φ, cos φ) of its centre.
    cols: Vec<(f32, f32)>,
    /// Per row (sin θ, cos θ) of its centre.
    rows: Vec<(f32, f32)>,
}

/// Samples per map column in [`YawAssignment`]. Between two samples a texel takes whichever of
/// the two samples' leaves is nearer its rotated centre (two dot products when they differ), so
/// binning is exact unless a third cell fits between samples half a texel apart — and cells are
/// several texels wide.
const SUBCOLUMNS: usize = 2;

/// Texel centre directions and solid angles of one layout, cached between rebuilds.
enum TexelGeometry {
    /// Lat-long is separable: a direction is (sin φ sin θ, cos θ, −cos φ sin θ), so rows and
    /// columns are stored apart (a few KB instead of 24 bytes per texel streamed every build).
    LatLong {
        /// Per row: (sin θ, cos θ, texel solid angle).
        rows: Vec<(f32, f32, f64)>,
        /// Per column: (sin φ, cos φ).
        cols: Vec<(f32, f32)>,
    },
    /// Any other layout: per texel (direction, solid angle).
    PerTexel(Vec<(Vec3, f64)>),
}

/// (sin φ, cos φ) of every lat-long column centre.
fn column_trig(width: u32) -> Vec<(f32, f32)> {
    (0..width)
        .map(|i| {
            let phi = 2.0 * std::f64::consts::PI * (f64::from(i) + 0.5) / f64::from(width);
            (phi.sin() as f32, phi.cos() as f32)
        })
        .collect()
}

impl TexelGeometry {
    fn new(layout: Layout) -> TexelGeometry {
        match layout {
            Layout::LatLong { width, height } => {
                let rows = (0..height)
                    .map(|j| {
                        let (v0, v1) = (f64::from(j) / f64::from(height), f64::from(j + 1) / f64::from(height));
                        let theta = std::f64::consts::PI * 0.5 * (v0 + v1);
                        let omega = layout::latlong_solid_angle(0.0, 1.0 / f64::from(width), v0, v1);
                        (theta.sin() as f32, theta.cos() as f32, omega)
                    })
                    .collect();
                TexelGeometry::LatLong { rows, cols: column_trig(width) }
            }
            Layout::Cube { .. } => {
                let mut geo = Vec::with_capacity(layout.texel_count());
                layout.for_each_patch(1, |_, d, omega| geo.push((d, omega)));
                TexelGeometry::PerTexel(geo)
            }
        }
    }
}

impl LightTreeBuilder {
    /// Precomputes the nearest-leaf table: 6 × R × R texels (R ≈ 4 per cell edge). A texel
    /// whose centre and four corners share their nearest leaf stores it; any other texel stores
    /// those candidate leaves, and a lookup picks the nearest of them.
    pub fn new(tree: &DirectionTree) -> Self {
        let locator = LeafLocator::new(tree);
        let n = tree.leaf_count();
        let res = (((n as f64 / 6.0).sqrt() * TABLE_TEXELS_PER_CELL).ceil().max(8.0) as usize).next_multiple_of(TILE);
        let near = |face: usize, s: f64, t: f64| locator.nearest(layout::cube_dir(face, s, t).as_dvec3().normalize());
        let coord = |i: f64| 2.0 * i / res as f64 - 1.0;
        let corners: Vec<u32> = (0..6 * (res + 1) * (res + 1))
            .into_par_iter()
            .map(|c| {
                let face = c / ((res + 1) * (res + 1));
                let r = c % ((res + 1) * (res + 1));
                near(face, coord((r % (res + 1)) as f64), coord((r / (res + 1)) as f64))
            })
            .collect();
        // Entries in tiled order, so the candidate lists are laid out as coherently as the table.
        let entries: Vec<[u32; 5]> = (0..6 * res * res)
            .into_par_iter()
            .map(|t| {
                let (face, i, j) = untile(res, t);
                let at = |ii: usize, jj: usize| corners[(face * (res + 1) + jj) * (res + 1) + ii];
                let centre = near(face, coord(i as f64 + 0.5), coord(j as f64 + 0.5));
                [centre, at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]
            })
            .collect();
        let mut table = Vec::with_capacity(entries.len());
        let mut candidates = Vec::new();
        for e in entries {
            let mut unique = e;
            unique.sort_unstable();
            let mut count = 1;
            for k in 1..unique.len() {
                if unique[k] != unique[count - 1] {
                    unique[count] = unique[k];
                    count += 1;
                }
            }
            if count == 1 {
                table.push(e[0]);
            } else {
                table.push(BOUNDARY | ((count as u32) << COUNT_SHIFT) | candidates.len() as u32);
                candidates.extend_from_slice(&unique[..count]);
            }
        }
        let leaf_dirs = tree.leaf_directions().to_vec();
        LightTreeBuilder {
            height: tree.height(),
            leaves: n,
            locator,
            table_res: res,
            table,
            candidates,
            leaf_dirs,
            texel_cache: None,
            yaw_cache: None,
        }
    }

    /// Share of table texels that hold candidate lists (texels crossed by a cell boundary).
    pub fn boundary_share(&self) -> f64 {
        self.table.iter().filter(|&&e| e & BOUNDARY != 0).count() as f64 / self.table.len() as f64
    }

    /// The exact nearest-leaf search.
    pub fn locator(&self) -> &LeafLocator {
        &self.locator
    }

    /// Leaf for a unit world direction through the table (the GL cube-face convention of
    /// `vcut_envmap::layout::cube_face_st`, in f32 for speed).
    #[inline]
    pub fn table_leaf(&self, d: Vec3) -> u32 {
        let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
        let (face, sc, tc, ma) = if ax >= ay && ax >= az {
            if d.x >= 0.0 { (0, -d.z, -d.y, ax) } else { (1, d.z, -d.y, ax) }
        } else if ay >= az {
            if d.y >= 0.0 { (2, d.x, d.z, ay) } else { (3, d.x, -d.z, ay) }
        } else if d.z >= 0.0 {
            (4, d.x, -d.y, az)
        } else {
            (5, -d.x, -d.y, az)
        };
        let res = self.table_res;
        let half = 0.5 * res as f32 / ma.max(f32::MIN_POSITIVE);
        let fi = (sc * half + 0.5 * res as f32).max(0.0);
        let fj = (tc * half + 0.5 * res as f32).max(0.0);
        let (i, j) = ((fi as usize).min(res - 1), (fj as usize).min(res - 1));
        let e = self.table[tiled(res, face, i, j)];
        if e & BOUNDARY == 0 {
            return e;
        }
        // Candidates are sorted ascending, so a strict `>` leaves ties to the lowest leaf; the
        // selects compile to conditional moves (these comparisons are unpredictable).
        let offset = (e & OFFSET_MASK) as usize;
        let count = ((e >> COUNT_SHIFT) & 7) as usize;
        let c = &self.candidates[offset..offset + count];
        let mut best = c[0];
        let mut best_dot = d.dot(self.leaf_dirs[c[0] as usize]);
        for &leaf in &c[1..] {
            let dot = d.dot(self.leaf_dirs[leaf as usize]);
            let better = dot > best_dot;
            best_dot = if better { dot } else { best_dot };
            best = if better { leaf } else { best };
        }
        best
    }

    fn build_yaw(&mut self, map: &EnvMap, width: u32, height: u32, yaw: f64) -> LightTree {
        if self.yaw_cache.as_ref().is_none_or(|y| y.width != width || y.height != height) {
            let sub = width as usize * SUBCOLUMNS;
            let leaves = (0..height as usize * sub)
                .into_par_iter()
                .map(|t| {
                    let (j, c) = (t / sub, t % sub);
                    // Samples at sub-column edges: with an even SUBCOLUMNS every unrotated texel
                    // centre is a sample, so yaw 0 (and multiples of a sub-column) is exact.
                    let u = c as f64 / sub as f64;
                    let v = (j as f64 + 0.5) / f64::from(height);
                    self.locator.nearest(layout::latlong_dir(u, v).as_dvec3().normalize())
                })
                .collect();
            let rows = (0..height)
                .map(|j| {
                    let theta = std::f64::consts::PI * (f64::from(j) + 0.5) / f64::from(height);
                    (theta.sin() as f32, theta.cos() as f32)
                })
                .collect();
            self.yaw_cache = Some(YawAssignment { width, height, leaves, cols: column_trig(width), rows });
        }
        let Some(assign) = &self.yaw_cache else { unreachable!("filled above") };
        let (w, h) = (width as usize, height as usize);
        let sub = w * SUBCOLUMNS;
        // A rotation by ψ about +Y moves azimuth φ to φ − ψ (see `vcut_envmap::layout`), i.e.
        // the centre of texel column i to sample (i + ½ − ψ·w/2π)·SUBCOLUMNS.
        let shift = -yaw / (2.0 * std::f64::consts::PI) * sub as f64;
        let (sin_y, cos_y) = (yaw.sin() as f32, yaw.cos() as f32);
        let scale = f64::from(map.intensity());
        let texels = map.integrated_texels();
        let threads = rayon::current_num_threads().max(1);
        let rows_per = h.div_ceil(threads).max(1);
        let partials: Vec<Vec<[f64; 3]>> = (0..h)
            .collect::<Vec<_>>()
            .par_chunks(rows_per)
            .map(|rows| {
                let mut acc = vec![[0.0f64; 3]; self.leaves];
                for &j in rows {
                    let v0 = j as f64 / h as f64;
                    let v1 = (j + 1) as f64 / h as f64;
                    let w_row = layout::latlong_solid_angle(0.0, 1.0 / w as f64, v0, v1) * scale;
                    let row_leaves = &assign.leaves[j * sub..(j + 1) * sub];
                    let row = &texels[j * w..(j + 1) * w];
                    let (st, ct) = assign.rows[j];
                    for (i, c) in row.iter().enumerate() {
                        let pos = (i as f64 + 0.5) * SUBCOLUMNS as f64 + shift;
                        let c0 = (pos.floor() as i64).rem_euclid(sub as i64) as usize;
                        let c1 = if c0 + 1 == sub { 0 } else { c0 + 1 };
                        let (la, lb) = (row_leaves[c0], row_leaves[c1]);
                        let leaf = if la == lb {
                            la
                        } else {
                            // The rotated centre: azimuth φ − ψ.
                            let (sp, cp) = assign.cols[i];
                            let (s2, c2) = (sp * cos_y - cp * sin_y, cp * cos_y + sp * sin_y);
                            let d = Vec3::new(s2 * st, ct, -c2 * st);
                            let (da, db) = (d.dot(self.leaf_dirs[la as usize]), d.dot(self.leaf_dirs[lb as usize]));
                            if db > da || (db == da && lb < la) { lb } else { la }
                        };
                        let a = &mut acc[leaf as usize];
                        a[0] += f64::from(c[0]) * w_row;
                        a[1] += f64::from(c[1]) * w_row;
                        a[2] += f64::from(c[2]) * w_row;
                    }
                }
                acc
            })
            .collect();
        self.sum_partials(&partials)
    }

    fn sum_partials(&self, partials: &[Vec<[f64; 3]>]) -> LightTree {
        let mut leaves = vec![[0.0f64; 3]; self.leaves];
        for p in partials {
            for (l, v) in leaves.iter_mut().zip(p) {
                l[0] += v[0];
                l[1] += v[1];
                l[2] += v[2];
            }
        }
        LightTree::from_leaves(self.height, &leaves)
    }

    /// Exact build: `k × k` sub-texel patches, each to the exactly nearest leaf.
    pub fn build_exact(&self, map: &EnvMap, k: u32) -> LightTree {
        let mut leaves = vec![[0.0f64; 3]; self.leaves];
        map.for_each_patch(k, |d, omega, c| {
            let leaf = self.locator.nearest(d.as_dvec3());
            let l = &mut leaves[leaf as usize];
            for i in 0..3 {
                l[i] += f64::from(c[i]) * omega;
            }
        });
        LightTree::from_leaves(self.height, &leaves)
    }

    /// Fast build, in parallel: each texel centre (after the map's rotation) to its nearest
    /// leaf — through the per-row sub-column assignment when the map is lat-long and rotated
    /// only about +Y (the interactive case), through the cube table otherwise. A map with fewer
    /// than 8 texels per leaf (texels as large as cells, e.g. a constant map) is binned exactly
    /// instead, in sub-texel patches numerous enough for 32 per leaf: binning whole texels
    /// would pour each one into a single leaf.
    pub fn build(&mut self, map: &EnvMap) -> LightTree {
        let layout = map.layout();
        let texels = layout.texel_count();
        if texels < 8 * self.leaves {
            let k = ((32.0 * self.leaves as f64 / texels.max(1) as f64).sqrt().ceil() as u32).max(1);
            return self.build_exact(map, k);
        }
        let q = map.rotation();
        if let Layout::LatLong { width, height } = layout
            && q.x.abs() < 1e-7
            && q.z.abs() < 1e-7
        {
            return self.build_yaw(map, width, height, 2.0 * f64::from(q.y).atan2(f64::from(q.w)));
        }
        if self.texel_cache.as_ref().is_none_or(|(l, _)| *l != layout) {
            self.texel_cache = Some((layout, TexelGeometry::new(layout)));
        }
        let Some((_, geo)) = &self.texel_cache else { unreachable!("filled above") };
        let rot = Mat3::from_quat(map.rotation());
        let scale = f64::from(map.intensity());
        let texels = map.integrated_texels();
        let threads = rayon::current_num_threads().max(1);
        let add = |a: &mut [f64; 3], c: &[f32; 3], w: f64| {
            a[0] += f64::from(c[0]) * w;
            a[1] += f64::from(c[1]) * w;
            a[2] += f64::from(c[2]) * w;
        };
        let partials: Vec<Vec<[f64; 3]>> = match geo {
            TexelGeometry::LatLong { rows, cols } => {
                let width = cols.len();
                let rows_per = rows.len().div_ceil(threads).max(1);
                rows.par_chunks(rows_per)
                    .enumerate()
                    .map(|(chunk, rs)| {
                        let mut acc = vec![[0.0f64; 3]; self.leaves];
                        for (r, &(st, ct, omega)) in rs.iter().enumerate() {
                            let j = chunk * rows_per + r;
                            let w = omega * scale;
                            let row = &texels[j * width..(j + 1) * width];
                            for (&(sp, cp), c) in cols.iter().zip(row) {
                                let d = rot * Vec3::new(sp * st, ct, -cp * st);
                                add(&mut acc[self.table_leaf(d) as usize], c, w);
                            }
                        }
                        acc
                    })
                    .collect()
            }
            TexelGeometry::PerTexel(g) => {
                let chunk = g.len().div_ceil(threads).max(1);
                g.par_chunks(chunk)
                    .zip(texels.par_chunks(chunk))
                    .map(|(g, t)| {
                        let mut acc = vec![[0.0f64; 3]; self.leaves];
                        for (&(d, omega), c) in g.iter().zip(t) {
                            add(&mut acc[self.table_leaf(rot * d) as usize], c, omega * scale);
                        }
                        acc
                    })
                    .collect()
            }
        };
        self.sum_partials(&partials)
    }
}

#[cfg(test)]
mod coarse_map_tests {
    use super::*;

    #[test]
    fn a_constant_map_gives_every_leaf_its_cell_share() {
        let dirs: Vec<glam::Vec3> = (0..1024)
            .map(|i| {
                let z = 1.0 - (2 * i + 1) as f32 / 1024.0;
                let p = i as f32 * std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
                let r = (1.0 - z * z).sqrt();
                glam::Vec3::new(r * p.cos(), z, r * p.sin())
            })
            .collect();
        let areas = vec![4.0 * std::f64::consts::PI / 1024.0; 1024];
        let tree = DirectionTree::build(&dirs, &areas).unwrap();
        let light = LightTreeBuilder::new(&tree).build(&EnvMap::constant([2.0; 3]));
        // Any subtree of 64 leaves holds 2 × its solid angle within 3 %.
        for k in (63..127).step_by(7) {
            let want = 2.0 * tree.solid_angle(k);
            assert!((light.node(k)[0] - want).abs() < 0.03 * want, "node {k}: {} vs {want}", light.node(k)[0]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiling_is_a_bijection() {
        let res = 12;
        let mut seen = vec![false; 6 * res * res];
        for face in 0..6 {
            for j in 0..res {
                for i in 0..res {
                    let t = tiled(res, face, i, j);
                    assert!(!std::mem::replace(&mut seen[t], true));
                    assert_eq!(untile(res, t), (face, i, j));
                }
            }
        }
    }
}
