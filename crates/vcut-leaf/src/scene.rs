//! A scene for the leaf renderer: objects that are either leaves (two-sided, translucent, with
//! leaf coordinates for the parameter maps) or opaque Lambertian surfaces (stems, pots, ground),
//! flattened into one vertex array with each vertex's [`Scatter`], and one ray-tracing structure.

use crate::material::{LeafMaterial, Scatter};
use glam::{Vec2, Vec3};
use rayon::prelude::*;
use vcut_rays::Occluder;
use vcut_scene::{Mesh, Scene};

/// What an object is made of.
#[derive(Debug, Clone, PartialEq)]
pub enum Surface {
    /// A leaf: light passes through it.
    Leaf(Box<LeafMaterial>),
    /// An opaque Lambertian surface of this albedo.
    Opaque(Vec3),
}

/// One object of a [`LeafScene`].
#[derive(Debug, Clone)]
pub struct LeafObject {
    /// Unique name.
    pub name: String,
    /// Geometry, world space.
    pub mesh: Mesh,
    /// Leaf coordinates per vertex (for the parameter maps), if the object has them.
    pub uv: Option<Vec<Vec2>>,
    /// Its material.
    pub surface: Surface,
}

/// Why a leaf scene cannot be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LeafSceneError {
    /// No triangles at all.
    #[error("the scene has no triangles")]
    Empty,
    /// Leaf coordinates that do not match the mesh.
    #[error("object {name}: {uv} leaf coordinates for {vertices} vertices")]
    UvCount {
        /// The object.
        name: String,
        /// Coordinates given.
        uv: usize,
        /// Vertices of its mesh.
        vertices: usize,
    },
    /// A mesh the generator made was changed by validation (a bug in the generator's parameters).
    #[error("object {0}: the generated mesh lost vertices in validation")]
    Generator(String),
    /// More than 2³² − 1 vertices.
    #[error("{0} vertices: more than a u32 index can hold")]
    TooLarge(usize),
}

/// Objects flattened for precomputation and shading.
pub struct LeafScene {
    objects: Vec<LeafObject>,
    /// First vertex of each object in the flattened arrays, and the total at the end.
    vertex_start: Vec<usize>,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    scatter: Vec<Scatter>,
    occluder: Occluder,
    center: Vec3,
    radius: f32,
}

impl LeafScene {
    /// Flattens `objects` and builds the ray-tracing structure.
    pub fn new(objects: Vec<LeafObject>) -> Result<LeafScene, LeafSceneError> {
        let mut vertex_start = vec![0];
        let (mut positions, mut normals, mut triangles) = (Vec::new(), Vec::new(), Vec::new());
        for o in &objects {
            if let Some(uv) = &o.uv
                && uv.len() != o.mesh.vertex_count()
            {
                return Err(LeafSceneError::UvCount {
                    name: o.name.clone(),
                    uv: uv.len(),
                    vertices: o.mesh.vertex_count(),
                });
            }
            let off = positions.len();
            if off + o.mesh.vertex_count() > u32::MAX as usize {
                return Err(LeafSceneError::TooLarge(off + o.mesh.vertex_count()));
            }
            positions.extend_from_slice(o.mesh.positions());
            normals.extend_from_slice(o.mesh.normals());
            triangles.extend(o.mesh.triangles().iter().map(|t| t.map(|i| i + off as u32)));
            vertex_start.push(positions.len());
        }
        if triangles.is_empty() {
            return Err(LeafSceneError::Empty);
        }
        let meshes: Vec<&Mesh> = objects.iter().map(|o| &o.mesh).collect();
        let occluder = Occluder::new(&meshes);
        let (lo, hi) = positions
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let center = (lo + hi) * 0.5;
        let radius = positions.iter().map(|p| p.distance(center)).fold(0.0f32, f32::max).max(1e-6);
        let mut scene = LeafScene {
            objects,
            vertex_start,
            positions,
            normals,
            triangles,
            scatter: Vec::new(),
            occluder,
            center,
            radius,
        };
        scene.update_scatter();
        Ok(scene)
    }

    /// Every object of `scene` as a leaf of `material` (a file's plant whose leaves and pot share
    /// one mesh, as the shared asset's do, is all leaf: documented, not guessed apart). An
    /// object with a base-colour texture and coordinates takes the texture as its albedo map
    /// ([`LeafMaterial::with_reflectance_map`]; coordinates wrapped into the unit square, as
    /// glTF repeats).
    pub fn from_scene_as_leaves(scene: &Scene, material: &LeafMaterial) -> Result<LeafScene, LeafSceneError> {
        LeafScene::new(
            scene
                .objects
                .iter()
                .map(|o| {
                    let (uv, leaf) = match (&o.textures.base_colour, o.mesh.uvs()) {
                        (Some(t), Some(uvs)) => (
                            Some(uvs.iter().map(|uv| Vec2::new(uv.x.rem_euclid(1.0), uv.y.rem_euclid(1.0))).collect()),
                            material.with_reflectance_map(t),
                        ),
                        _ => (None, material.clone()),
                    };
                    LeafObject {
                        name: o.name.clone(),
                        mesh: o.mesh.clone(),
                        uv,
                        surface: Surface::Leaf(Box::new(leaf)),
                    }
                })
                .collect(),
        )
    }

    fn update_scatter(&mut self) {
        let mut scatter = Vec::with_capacity(self.positions.len());
        for o in &self.objects {
            match &o.surface {
                Surface::Opaque(kd) => scatter.extend(std::iter::repeat_n(Scatter::opaque(*kd), o.mesh.vertex_count())),
                Surface::Leaf(m) => {
                    let n = o.mesh.vertex_count();
                    let s: Vec<Scatter> = (0..n)
                        .into_par_iter()
                        .map(|i| m.scatter(o.uv.as_ref().map_or(Vec2::splat(0.5), |uv| uv[i])))
                        .collect();
                    scatter.extend(s);
                }
            }
        }
        self.scatter = scatter;
    }

    /// Replaces an object's material (and recomputes its vertices' scattering); false when no
    /// object has that name.
    pub fn set_surface(&mut self, name: &str, surface: Surface) -> bool {
        let Some(o) = self.objects.iter_mut().find(|o| o.name == name) else { return false };
        o.surface = surface;
        self.update_scatter();
        true
    }

    /// The objects.
    pub fn objects(&self) -> &[LeafObject] {
        &self.objects
    }

    /// The vertex range of object `i` in the flattened arrays.
    pub fn vertex_range(&self, i: usize) -> std::ops::Range<usize> {
        self.vertex_start[i]..self.vertex_start[i + 1]
    }

    /// All vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// All vertex normals (unit; side 0 of a leaf faces along them).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// All triangles (indices into the flattened vertices).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Per vertex, what it scatters.
    pub fn scatter(&self) -> &[Scatter] {
        &self.scatter
    }

    /// Vertex count.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The ray-tracing structure over all triangles (triangle ids as in [`LeafScene::triangles`]).
    pub fn occluder(&self) -> &Occluder {
        &self.occluder
    }

    /// Centre and radius of a sphere around every vertex.
    pub fn bounds(&self) -> (Vec3, f32) {
        (self.center, self.radius)
    }

    /// Centre and radius of a sphere around the translucent (leaf) vertices — what a camera should
    /// frame — or around every vertex when there are none.
    pub fn leaf_bounds(&self) -> (Vec3, f32) {
        let leaves: Vec<Vec3> =
            self.positions.iter().zip(&self.scatter).filter(|(_, s)| s.translucent()).map(|(p, _)| *p).collect();
        if leaves.is_empty() {
            return self.bounds();
        }
        let (lo, hi) =
            leaves.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let c = (lo + hi) * 0.5;
        (c, leaves.iter().map(|p| p.distance(c)).fold(0.0f32, f32::max).max(1e-6))
    }

    /// Distance rays start off a surface, along the normal toward the side they leave: a fixed
    /// fraction of the scene's size, as the cut precompute does.
    pub fn ray_offset(&self) -> f32 {
        vcut_rays::offset_for_radius(2e-4, self.radius)
    }

    /// Where triangle `tri` is hit at `p`: its barycentric weights (clamped to the triangle).
    pub fn barycentric(&self, tri: usize, p: Vec3) -> [f32; 3] {
        let [a, b, c] = self.triangles[tri].map(|i| self.positions[i as usize]);
        let (v0, v1, v2) = (b - a, c - a, p - a);
        let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
        let (d20, d21) = (v2.dot(v0), v2.dot(v1));
        let den = d00 * d11 - d01 * d01;
        if den.abs() < f32::MIN_POSITIVE {
            return [1.0 / 3.0; 3];
        }
        let v = ((d11 * d20 - d01 * d21) / den).clamp(0.0, 1.0);
        let w = ((d00 * d21 - d01 * d20) / den).clamp(0.0, 1.0 - v);
        [1.0 - v - w, v, w]
    }

    /// The interpolated (unit) normal of triangle `tri` at barycentric `b`.
    pub fn hit_normal(&self, tri: usize, b: [f32; 3]) -> Vec3 {
        let t = self.triangles[tri];
        (self.normals[t[0] as usize] * b[0] + self.normals[t[1] as usize] * b[1] + self.normals[t[2] as usize] * b[2])
            .normalize_or(Vec3::Y)
    }
}
