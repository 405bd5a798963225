//! A procedural plant: leaves on branches around a stem, above a ground plane. The leaf count is a
//! parameter, so the same generator makes a 40-leaf house plant for tests and the 100k- and
//! 500k-vertex plants of the benches.
//!
//! Each leaf is a blade of `(along + 1) × (across + 1)` vertices with leaf coordinates (u from base
//! to tip, v across with the midrib at 0.5), folded along the midrib and drooping toward the tip;
//! the tip keeps a small width so no triangle is degenerate. Branches spiral round the stem by the
//! golden angle; leaves alternate along each branch's outer part.

use crate::material::{LeafMaterial, SideMaps};
use crate::scene::{LeafObject, LeafScene, LeafSceneError, Surface};
use glam::{Quat, Vec2, Vec3};
use vcut_scene::{Mesh, MeshOptions};
use vcut_sphere::rng::SplitMix64;

/// Parameters of [`plant`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlantParams {
    /// Number of leaves.
    pub leaves: u32,
    /// Leaves per branch.
    pub leaves_per_branch: u32,
    /// Quads along and across each blade.
    pub segments: [u32; 2],
    /// Random seed (angles, sizes).
    pub seed: u64,
    /// Whether to add a ground plane.
    pub ground: bool,
    /// Whether the leaves get the procedural vein maps.
    pub maps: bool,
}

impl Default for PlantParams {
    /// A 48-leaf plant of about 4,000 vertices, the size of the shared potted-plant asset.
    fn default() -> PlantParams {
        PlantParams { leaves: 48, leaves_per_branch: 8, segments: [10, 6], seed: 7, ground: true, maps: true }
    }
}

impl PlantParams {
    /// Vertices of one blade.
    pub fn vertices_per_leaf(&self) -> usize {
        ((self.segments[0] + 1) * (self.segments[1] + 1)) as usize
    }

    /// The default plant with enough leaves (16 × 8 quads each) for about `n` leaf vertices.
    pub fn with_vertices(n: usize) -> PlantParams {
        let mut p = PlantParams { segments: [16, 8], leaves_per_branch: 12, ..PlantParams::default() };
        p.leaves = (n / p.vertices_per_leaf()).max(1) as u32;
        p
    }
}

/// Stem and branch bark.
const BARK: Vec3 = Vec3::new(0.20, 0.14, 0.08);
/// Soil.
const GROUND: Vec3 = Vec3::new(0.18, 0.15, 0.11);

/// A thin cylinder from `a` to `b` (8 sides, both ends capped).
fn tube(a: Vec3, b: Vec3, radius: f32, pos: &mut Vec<Vec3>, tris: &mut Vec<[u32; 3]>) {
    let axis = (b - a).normalize();
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let base = pos.len() as u32;
    let sides = 8u32;
    for end in [a, b] {
        for k in 0..sides {
            let phi = std::f32::consts::TAU * k as f32 / sides as f32;
            pos.push(end + (u * phi.cos() + v * phi.sin()) * radius);
        }
    }
    for k in 0..sides {
        let (i0, i1) = (base + k, base + (k + 1) % sides);
        tris.push([i0, i1, i1 + sides]);
        tris.push([i0, i1 + sides, i0 + sides]);
    }
    // Caps: a fan round each end's centre (own vertices, so their normals face out).
    for (end, ring, out) in [(a, base, -axis), (b, base + sides, axis)] {
        let centre = pos.len() as u32;
        pos.push(end);
        let start = pos.len() as u32;
        for k in 0..sides {
            pos.push(pos[(ring + k) as usize]);
        }
        for k in 0..sides {
            let (i0, i1) = (start + k, start + (k + 1) % sides);
            let (p0, p1) = (pos[i0 as usize], pos[i1 as usize]);
            if (p0 - end).cross(p1 - end).dot(out) > 0.0 {
                tris.push([centre, i0, i1]);
            } else {
                tris.push([centre, i1, i0]);
            }
        }
    }
}

/// One blade: base at `base`, midrib along `along`, lamina across `side`, `up` its normal.
#[allow(clippy::too_many_arguments)]
fn blade(
    base: Vec3,
    along: Vec3,
    side: Vec3,
    up: Vec3,
    length: f32,
    width: f32,
    segments: [u32; 2],
    pos: &mut Vec<Vec3>,
    uv: &mut Vec<Vec2>,
    tris: &mut Vec<[u32; 3]>,
) {
    let [na, nc] = segments.map(|s| s.max(1));
    let start = pos.len() as u32;
    let row = nc + 1;
    // Rows run back and forth (serpentine), so consecutive vertices are always neighbours: maps
    // stored in vertex order (the LVC's) then hold longer runs.
    let index = |i: u32, j: u32| start + i * row + if i.is_multiple_of(2) { j } else { nc - j };
    for i in 0..=na {
        let u = i as f32 / na as f32;
        // Ovate blade, never narrower than 6 % of its width (no degenerate tip).
        let w = width * (std::f32::consts::PI * u).sin().powf(0.7).max(0.06);
        let droop = -0.35 * length * u * u;
        for k in 0..=nc {
            let j = if i % 2 == 0 { k } else { nc - k };
            let v = j as f32 / nc as f32;
            let x = (v - 0.5) * w;
            let fold = 0.25 * x.abs();
            pos.push(base + along * (u * length) + side * x + up * (droop + fold));
            uv.push(Vec2::new(u, v));
        }
    }
    for i in 0..na {
        for j in 0..nc {
            let (a, b, c, d) = (index(i, j), index(i, j + 1), index(i + 1, j), index(i + 1, j + 1));
            tris.push([a, b, c]);
            tris.push([b, d, c]);
        }
    }
}

/// The plant of `params`: objects `leaves` (leaf material, with maps when asked), `stems` and,
/// when asked, `ground`. The stem stands on the origin, 1 unit tall.
pub fn plant(params: &PlantParams, material: &LeafMaterial) -> Result<LeafScene, LeafSceneError> {
    let mut rng = SplitMix64::new(params.seed);
    let mut rand = move || rng.next_f64() as f32;
    let (mut lpos, mut luv, mut ltris) = (Vec::new(), Vec::new(), Vec::new());
    let (mut spos, mut stris) = (Vec::new(), Vec::new());
    let height = 1.0f32;
    tube(Vec3::ZERO, Vec3::Y * height, 0.012, &mut spos, &mut stris);
    let per_branch = params.leaves_per_branch.max(1);
    let branches = params.leaves.div_ceil(per_branch).max(1);
    let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
    // Leaves shrink as they multiply so the plant keeps its size.
    let scale = (48.0 / params.leaves.max(1) as f32).sqrt().clamp(0.12, 1.0);
    let mut placed = 0;
    for b in 0..branches {
        let t = (b as f32 + 0.5) / branches as f32;
        let attach = Vec3::Y * (0.2 + 0.75 * t) * height;
        let azimuth = golden * b as f32;
        let rise = (25.0 + 30.0 * t + 10.0 * rand()).to_radians();
        let dir = Vec3::new(azimuth.cos() * rise.cos(), rise.sin(), azimuth.sin() * rise.cos());
        let reach = (0.55 - 0.3 * t) * height;
        tube(attach, attach + dir * reach, 0.006, &mut spos, &mut stris);
        for k in 0..per_branch.min(params.leaves - placed) {
            let s = 0.3 + 0.7 * (k as f32 + 0.5) / per_branch as f32;
            let at = attach + dir * (reach * s);
            // Alternate sides, pointing outward and a little up, rolled at random.
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let out = dir.cross(Vec3::Y).normalize_or(Vec3::X) * sign;
            let along = (out * 0.8 + dir * 0.5 + Vec3::Y * (0.2 + 0.3 * rand())).normalize();
            let roll = Quat::from_axis_angle(along, (rand() - 0.5) * 0.8);
            let side = roll * along.cross(Vec3::Y).normalize_or(Vec3::X);
            let up = side.cross(along).normalize();
            let length = (0.22 + 0.08 * rand()) * scale;
            let width = length * (0.42 + 0.1 * rand());
            blade(at, along, side, up, length, width, params.segments, &mut lpos, &mut luv, &mut ltris);
            placed += 1;
        }
    }
    let mut objects = Vec::new();
    let build = |name: &str, pos: Vec<Vec3>, tris: Vec<[u32; 3]>| -> Result<Mesh, LeafSceneError> {
        let n = pos.len();
        let (mesh, _) =
            Mesh::build(pos, None, tris, MeshOptions::default()).map_err(|_| LeafSceneError::Generator(name.into()))?;
        if mesh.vertex_count() != n {
            return Err(LeafSceneError::Generator(name.into()));
        }
        Ok(mesh)
    };
    let mut leaf = material.clone();
    if params.maps {
        leaf.maps = [
            Some(SideMaps::veins(128, 7, leaf.albedo(), 1.0, leaf.gloss[0].roughness)),
            Some(SideMaps::veins(128, 7, leaf.albedo(), 1.0, leaf.gloss[1].roughness)),
        ];
    }
    objects.push(LeafObject {
        name: "leaves".into(),
        mesh: build("leaves", lpos, ltris)?,
        uv: Some(luv),
        surface: Surface::Leaf(Box::new(leaf)),
    });
    objects.push(LeafObject {
        name: "stems".into(),
        mesh: build("stems", spos, stris)?,
        uv: None,
        surface: Surface::Opaque(BARK),
    });
    if params.ground {
        // Fine enough for the plant's shadow to show in per-vertex shading.
        let (h, k) = (1.5f32, 48u32);
        let mut pos = Vec::new();
        let mut tris = Vec::new();
        for i in 0..=k {
            for j in 0..=k {
                pos.push(Vec3::new(-h + 2.0 * h * j as f32 / k as f32, 0.0, -h + 2.0 * h * i as f32 / k as f32));
            }
        }
        for i in 0..k {
            for j in 0..k {
                let a = i * (k + 1) + j;
                tris.push([a, a + k + 1, a + 1]);
                tris.push([a + 1, a + k + 1, a + k + 2]);
            }
        }
        objects.push(LeafObject {
            name: "ground".into(),
            mesh: build("ground", pos, tris)?,
            uv: None,
            surface: Surface::Opaque(GROUND),
        });
    }
    LeafScene::new(objects)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plant_has_the_leaves_asked_for_and_faces_up() {
        let p = PlantParams::default();
        let s = plant(&p, &LeafMaterial::default()).unwrap();
        assert_eq!(s.objects()[0].mesh.vertex_count(), 48 * p.vertices_per_leaf());
        assert_eq!(s.objects().len(), 3);
        // The ground's normal is up; leaves are translucent, the ground is not.
        let ground = s.vertex_range(2);
        assert!(s.normals()[ground.start].y > 0.99);
        assert!(s.scatter()[0].translucent() && !s.scatter()[ground.start].translucent());
        // A 100k-vertex plant has about 100k leaf vertices.
        let big = PlantParams::with_vertices(100_000);
        let n = big.leaves as usize * big.vertices_per_leaf();
        assert!((95_000..=100_000).contains(&n), "{n}");
    }
}
