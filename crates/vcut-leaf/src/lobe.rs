//! How open a gloss lobe is, per vertex and for any lobe direction, from the LVC maps' visibility.
//!
//! A glossy side reflects the sky only where its lobe is open. The order-5 SH of the direct
//! transfer cannot tell (its lobes are finer than order 5 resolves; `cargo run -p vcuts
//! --example gloss_sources` measures the gloss against a Monte Carlo truth either way, and
//! `docs/benchmarks.md` has the figures), but the LVC maps hold each vertex's visibility toward 6·R²
//! directions. Here, per vertex, it is filtered with a fixed lobe cos⁴⁰ (half its peak 10.6° off
//! its centre) at the R_L × R_L nodes of an octahedral map of world directions and kept as
//! bytes; a frame reads it bilinearly at the centre of the vertex's gloss lobe
//! ([`crate::shade`]). The table is derived from the maps when the leaf data is made (not
//! stored): [`LobeVisibility::from_lvc`].

use crate::lvc::{CubeDirections, Lvc};
use crate::rle::RleError;
use glam::Vec3;
use rayon::prelude::*;

/// Nodes per side of the octahedral map (R_L² bytes per vertex).
pub const RESOLUTION: usize = 17;
/// Exponent of the filtering lobe cosᴺ: narrower than the BRDF's lobe, because the table is
/// read at the lobe's centre and interpolated between nodes; the value where `gloss_sources`'s
/// `gloss_rel_l2_lobe_table` is lowest among those tried (`docs/benchmarks.md`).
pub const KERNEL: f32 = 40.0;
/// Lobe weights below this share of the peak are left out of the filter.
const CUTOFF: f32 = 0.02;
/// Vertices filtered together (bounds the decoded span: directions × chunk bytes).
const CHUNK: usize = 1024;

/// Per vertex, the lobe-filtered visibility at the octahedral nodes (0–255).
#[derive(Debug, Clone, PartialEq)]
pub struct LobeVisibility {
    bytes: Vec<u8>,
}

/// The unit direction of node (i, j): the octahedral map of the sphere onto [−1, 1]², nodes on
/// its corners and edges (an edge's nodes are the same directions as the mirrored edge's).
pub fn node_direction(i: usize, j: usize) -> Vec3 {
    let c = |k: usize| -1.0 + 2.0 * k as f32 / (RESOLUTION - 1) as f32;
    let (u, w) = (c(i), c(j));
    let z = 1.0 - u.abs() - w.abs();
    let (x, y) = if z >= 0.0 { (u, w) } else { ((1.0 - w.abs()) * u.signum(), (1.0 - u.abs()) * w.signum()) };
    Vec3::new(x, y, z).normalize()
}

/// Where unit `d` falls on the map, in node units (0 ..= R_L − 1 each way).
fn map_point(d: Vec3) -> (f32, f32) {
    let s = d.x.abs() + d.y.abs() + d.z.abs();
    let (mut u, mut w) = (d.x / s.max(1e-20), d.y / s.max(1e-20));
    if d.z < 0.0 {
        (u, w) = ((1.0 - w.abs()) * sign(u), (1.0 - u.abs()) * sign(w));
    }
    let to = |x: f32| ((x + 1.0) * 0.5 * (RESOLUTION - 1) as f32).clamp(0.0, (RESOLUTION - 1) as f32);
    (to(u), to(w))
}

/// ±1, with +1 at zero (so the fold of the lower hemisphere is defined on the axes).
fn sign(x: f32) -> f32 {
    if x < 0.0 { -1.0 } else { 1.0 }
}

/// The filter: the map's directions coarsened to at most 16² per cube face (bins), and per node
/// the bins it weighs and their weights (lobe × solid angle), normalised per node and per byte —
/// a visibility of 255 everywhere filters to 1.
struct Filter {
    /// Per bin, its map directions.
    members: Vec<Vec<u32>>,
    /// Per node, (bin, weight).
    taps: Vec<Vec<(u32, f32)>>,
}

impl Filter {
    fn new(dirs: CubeDirections) -> Filter {
        let r = dirs.resolution as usize;
        let f = r.div_ceil(16).max(1);
        let rc = r.div_ceil(f);
        let mut members = vec![Vec::new(); 6 * rc * rc];
        let mut sum = vec![Vec3::ZERO; 6 * rc * rc];
        let mut omega = vec![0.0f32; 6 * rc * rc];
        for i in 0..dirs.len() {
            let (face, rest) = (i / (r * r), i % (r * r));
            let (t, s) = (rest / r, rest % r);
            let c = face * rc * rc + (t / f) * rc + s / f;
            members[c].push(i as u32);
            let d = dirs.direction(i);
            // A cube texel's solid angle goes as the cube of the direction's largest component.
            let m = d.abs().max_element();
            sum[c] += d;
            omega[c] += m * m * m;
        }
        let taps = (0..RESOLUTION * RESOLUTION)
            .map(|k| {
                let node = node_direction(k / RESOLUTION, k % RESOLUTION);
                // Lobe × solid angle per bin; a bin holds the sum of its texels' bytes, so its
                // weight is shared by them (normalised: 255 everywhere filters to 1).
                let mut t: Vec<(u32, f32)> = Vec::new();
                let mut total = 0.0f32;
                for (c, (s, &o)) in sum.iter().zip(&omega).enumerate() {
                    let w = s.normalize_or(Vec3::Y).dot(node).max(0.0).powf(KERNEL);
                    if w >= CUTOFF && !members[c].is_empty() {
                        t.push((c as u32, w * o));
                        total += w * o;
                    }
                }
                t.iter_mut().for_each(|(c, w)| *w /= total * 255.0 * members[*c as usize].len() as f32);
                t
            })
            .collect();
        Filter { members, taps }
    }
}

impl LobeVisibility {
    /// The table of `lvc`'s vertices, or `None` where the maps lack a direction (an LVC computed
    /// for some sun directions only): shading then falls back to the SH visibility.
    pub fn from_lvc(lvc: &Lvc) -> Result<Option<LobeVisibility>, RleError> {
        let dirs = lvc.directions();
        if !(0..dirs.len()).all(|j| lvc.has(j)) {
            return Ok(None);
        }
        let n = lvc.vertex_count();
        let filter = Filter::new(dirs);
        let nodes = RESOLUTION * RESOLUTION;
        let mut cursors: Vec<_> = (0..dirs.len()).map(|j| lvc.cursor(j)).collect();
        let mut bytes = vec![0u8; n * nodes];
        // Direction-, bin- and node-major spans of CHUNK vertices: every step a run over vertices.
        let mut span = vec![0u8; dirs.len() * CHUNK];
        let mut bins = vec![0.0f32; filter.members.len() * CHUNK];
        let mut acc = vec![0.0f32; nodes * CHUNK];
        for (c, out) in bytes.chunks_mut(CHUNK * nodes).enumerate() {
            let len = CHUNK.min(n - c * CHUNK);
            span.par_chunks_mut(CHUNK)
                .zip(cursors.par_iter_mut())
                .try_for_each(|(dst, cursor)| cursor.next_into(&mut dst[..len]))?;
            bins.par_chunks_mut(CHUNK).zip(&filter.members).for_each(|(bin, members)| {
                bin.fill(0.0);
                for &j in members {
                    let row = &span[j as usize * CHUNK..][..CHUNK];
                    bin.iter_mut().zip(row).for_each(|(b, &x)| *b += f32::from(x));
                }
            });
            acc.par_chunks_mut(CHUNK).zip(&filter.taps).for_each(|(a, taps)| {
                a.fill(0.0);
                for &(b, w) in taps {
                    let bin = &bins[b as usize * CHUNK..][..CHUNK];
                    a.iter_mut().zip(bin).for_each(|(a, &x)| *a += w * x);
                }
            });
            out.par_chunks_mut(nodes).enumerate().for_each(|(v, out)| {
                for (k, o) in out.iter_mut().enumerate() {
                    *o = (acc[k * CHUNK + v] * 255.0).round().clamp(0.0, 255.0) as u8;
                }
            });
        }
        Ok(Some(LobeVisibility { bytes }))
    }

    /// Vertex `v`'s lobe-filtered visibility toward unit `d` (0–1), bilinear between nodes.
    pub fn at(&self, v: usize, d: Vec3) -> f32 {
        let t = &self.bytes[v * RESOLUTION * RESOLUTION..(v + 1) * RESOLUTION * RESOLUTION];
        let (x, y) = map_point(d);
        let (i0, j0) = ((x as usize).min(RESOLUTION - 2), (y as usize).min(RESOLUTION - 2));
        let (a, b) = (x - i0 as f32, y - j0 as f32);
        let at = |i: usize, j: usize| f32::from(t[i * RESOLUTION + j]);
        let value = at(i0, j0) * (1.0 - a) * (1.0 - b)
            + at(i0 + 1, j0) * a * (1.0 - b)
            + at(i0, j0 + 1) * (1.0 - a) * b
            + at(i0 + 1, j0 + 1) * a * b;
        value / 255.0
    }

    /// Bytes it takes.
    pub fn bytes(&self) -> usize {
        self.bytes.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lvc::LvcParams;
    use crate::scene::{LeafObject, LeafScene, Surface};
    use vcut_scene::{Mesh, MeshOptions};

    /// A square at height `y`, its centre moved by `shift` in x and z (off the leaf's diagonal,
    /// along which a ray may slip between two triangles).
    fn quad(name: &str, y: f32, half: f32, shift: f32, surface: Surface) -> LeafObject {
        let pos = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, z)| Vec3::new(x * half + shift, y, z * half + 0.6 * shift))
            .to_vec();
        let mesh = Mesh::build(pos, None, vec![[0, 2, 1], [0, 3, 2]], MeshOptions::default()).unwrap().0;
        LeafObject { name: name.into(), mesh, uv: None, surface }
    }

    fn params() -> LvcParams {
        LvcParams { resolution: 16, disk_samples: 4, ..LvcParams::default() }
    }

    #[test]
    fn every_node_is_found_where_it_points() {
        for i in 0..RESOLUTION {
            for j in 0..RESOLUTION {
                let d = node_direction(i, j);
                assert!((d.length() - 1.0).abs() < 1e-5);
                let (x, y) = map_point(d);
                // Edge nodes of the lower half are one direction twice: compare directions.
                let back = node_direction(x.round() as usize, y.round() as usize);
                assert!(back.dot(d) > 1.0 - 1e-5, "node ({i}, {j}) {d} comes back as ({x}, {y}) {back}");
            }
        }
    }

    #[test]
    fn a_roof_closes_the_lobes_above_and_nothing_else() {
        // A small leaf under a wide opaque roof: open below and sideways, shut above.
        let leaf = quad("leaf", 0.0, 0.1, 0.0, Surface::Leaf(Box::default()));
        let roof = quad("roof", 0.3, 3.0, 0.37, Surface::Opaque(Vec3::splat(0.5)));
        let scene = LeafScene::new(vec![leaf, roof]).unwrap();
        let lvc = Lvc::compute(&scene, &params(), |_, _| {});
        let table = LobeVisibility::from_lvc(&lvc).unwrap().unwrap();
        assert_eq!(table.bytes(), scene.vertex_count() * RESOLUTION * RESOLUTION);
        for v in scene.vertex_range(0) {
            assert!(table.at(v, Vec3::Y) < 0.02, "vertex {v} up: {}", table.at(v, Vec3::Y));
            assert!(table.at(v, -Vec3::Y) > 0.98, "vertex {v} down: {}", table.at(v, -Vec3::Y));
            // Level with the leaf the lobe is open below the horizon and up to the roof's edge
            // (3.4 away, 0.3 up: 5° up), shut above it: about 0.7.
            let side = table.at(v, Vec3::X);
            assert!(side > 0.55 && side < 0.85, "vertex {v} sideways: {side}");
        }
        // Alone, the leaf sees everything everywhere.
        let alone = LeafScene::new(vec![quad("leaf", 0.0, 0.1, 0.0, Surface::Leaf(Box::default()))]).unwrap();
        let open = LobeVisibility::from_lvc(&Lvc::compute(&alone, &params(), |_, _| {})).unwrap().unwrap();
        for k in 0..64 {
            let d = Vec3::new((k as f32 * 0.7).sin(), (k as f32 * 1.3).cos(), (k as f32 * 0.37).sin()).normalize();
            assert!(open.at(0, d) > 0.995, "{d}: {}", open.at(0, d));
        }
    }

    #[test]
    fn the_table_is_the_lobe_filtered_map_and_none_without_every_direction() {
        let leaf = quad("leaf", 0.0, 0.1, 0.0, Surface::Leaf(Box::default()));
        let wall = {
            let pos = vec![
                Vec3::new(0.2, -1.0, -2.0),
                Vec3::new(0.2, -1.0, 2.0),
                Vec3::new(0.2, 1.0, 2.0),
                Vec3::new(0.2, 1.0, -2.0),
            ];
            let mesh = Mesh::build(pos, None, vec![[0, 1, 2], [0, 2, 3]], MeshOptions::default()).unwrap().0;
            LeafObject { name: "wall".into(), mesh, uv: None, surface: Surface::Opaque(Vec3::splat(0.5)) }
        };
        let scene = LeafScene::new(vec![leaf, wall]).unwrap();
        let lvc = Lvc::compute(&scene, &params(), |_, _| {});
        let table = LobeVisibility::from_lvc(&lvc).unwrap().unwrap();
        // Straight from the maps: every direction's byte, weighed by the lobe and solid angle.
        let dirs = lvc.directions();
        let maps: Vec<Vec<u8>> = (0..dirs.len())
            .map(|j| {
                let mut m = vec![0u8; scene.vertex_count()];
                lvc.decode(j, &mut m).unwrap();
                m
            })
            .collect();
        for (i, j) in [(8, 8), (12, 8), (16, 8), (8, 3), (2, 14), (0, 0)] {
            let node = node_direction(i, j);
            for v in [0, 2] {
                let (mut num, mut den) = (0.0f64, 0.0f64);
                for (k, map) in maps.iter().enumerate() {
                    let d = dirs.direction(k);
                    let w = f64::from(d.dot(node).max(0.0).powf(KERNEL) * d.abs().max_element().powi(3));
                    num += w * f64::from(map[v]) / 255.0;
                    den += w;
                }
                let want = (num / den) as f32;
                let got = table.at(v, node);
                assert!((got - want).abs() < 0.02, "vertex {v} node ({i}, {j}) {node}: {got} vs {want}");
            }
        }
        // Toward the wall the lobe is shut, away from it open.
        assert!(table.at(0, Vec3::X) < 0.1 && table.at(0, -Vec3::X) > 0.9);
        let some = Lvc::compute_suns(&scene, &params(), &[0, 5], |_, _| {});
        assert_eq!(LobeVisibility::from_lvc(&some).unwrap(), None);
    }
}
