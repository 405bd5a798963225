//! An object at run time: what every merge reads (`ObjectData`: its mesh and material, its
//! translation and turn, its stored cuts) and what its vertices' last merge left (`MergeState`: merged
//! cuts, shading lists, field inputs, the decoded field cuts and refined cells kept for the
//! next move, which merges wait); and [`FrameObject`], how a frame shows an object.

use super::kept::KeptCut;
use super::keys::FieldKey;
use super::lists::{ShadeList, ShadeNode};
use super::merge::FieldCache;
use super::turn::Turn;
use crate::brdf;
use crate::sun::Placed;
use glam::Vec3;
use vcut_cut::Cut;
use vcut_data::FieldLayout;
use vcut_data::sections::CutArray;
use vcut_merge::Prepared;
use vcut_scene::{Material, Mesh, Motion};

/// An object at run time, as every merge reads it: its mesh and material, its translation
/// and turn, its stored cuts and its decoded SVCs.
pub(super) struct ObjectData {
    pub(super) name: String,
    /// Its mesh as it stands turned (the rest mesh while it has not turned), at no translation.
    pub(super) mesh: Mesh,
    pub(super) material: Material,
    /// Its glTF material's textures (the base colour multiplies `material.kd`).
    pub(super) textures: vcut_scene::loaders::MaterialTextures,
    /// Per vertex, the material its textures give it there ([`ObjectData::vertex_materials`];
    /// empty where they do not vary it: then `material` everywhere).
    pub(super) vertex_materials: Vec<Material>,
    /// The material it was loaded with: a metallic-roughness texture applies while `material`
    /// is this one (an edit overrides it; undoing the edit brings it back).
    pub(super) loaded_material: Material,
    /// `x^exponent` of the material, tabled (`None` above the table's range).
    pub(super) pow: Option<brdf::PowTable>,
    pub(super) motion: Motion,
    pub(super) translation: Vec3,
    /// Its turn about the vertical axis through `centre` ([`super::turn`]).
    pub(super) turn: Turn,
    /// Its bounding-sphere centre at rest: what it turns about.
    pub(super) centre: Vec3,
    /// Its mesh at rest, kept once it has turned (`mesh` is then the rest mesh turned).
    pub(super) rest_mesh: Option<Box<Mesh>>,
    /// The file's direction set's turn shape (`None`: not symmetric; nothing turns).
    pub(super) shape: Option<vcut_cut::turn::TurnShape>,
    pub(super) svc: Vec<CutArray>,
    /// First vertex of every SVC chunk.
    pub(super) svc_starts: Vec<usize>,
    pub(super) layout: Option<FieldLayout>,
    pub(super) field: Vec<CutArray>,
    /// Its outline when it is flat and convex: then its shadow is cut exactly at each vertex
    /// ([`crate::flat`]) and its field, if the file has one, is not read.
    pub(super) flat: Option<vcut_scene::flat::FlatOutline>,
    /// How far along the normal its vertices' rays start ([`vcut_rays::origin_offset`] of the
    /// file's SVC offset).
    pub(super) ray_offset: f32,
    /// Every vertex's SVC decoded once, ready to merge (empty with the cache off: then each
    /// merge decodes it from the file's bytes).
    pub(super) svc_refined: Vec<Prepared>,
    /// Per vertex, a cone holding the normals of its triangles ([`ViewCone`]).
    pub(super) cones: Vec<ViewCone>,
    /// Per vertex, its exact field factors ([`super::refine`]; empty until a refinement casts
    /// one).
    pub(super) exact: Vec<Vec<super::refine::ExactFactor>>,
}

/// What an object's vertices' last merge left: merged cuts, shading lists, field inputs, the
/// decoded field cuts and refined cells kept for the next move, and which merges wait.
#[derive(Default)]
pub(super) struct MergeState {
    pub(super) merged: Vec<KeptCut>,
    pub(super) lists: Vec<ShadeList>,
    pub(super) keys: Vec<Vec<FieldKey>>,
    /// Decoded field cuts its vertices' last merge used.
    pub(super) decoded: FieldCache,
    /// Vertices whose merge waits ([`super::FrameSettings::deferred_merges`]): their field
    /// inputs changed while they faced away from the eye; `merged` and `keys` are still the
    /// last merge's.
    pub(super) pending: Vec<bool>,
    /// Per vertex, the turn its kept cut's SVC took ([`Turn::svc_stamp`]; empty: none ever
    /// turned), so a turn of the object merges its vertices again even where no field input
    /// changes.
    pub(super) svc_turns: Vec<u64>,
}

impl MergeState {
    /// The turn vertex `v`'s kept cut took its SVC at ([`Turn::svc_stamp`]).
    pub(super) fn svc_turn(&self, v: usize) -> u64 {
        self.svc_turns.get(v).copied().unwrap_or(0)
    }

    /// Records that vertex `v`'s kept cut takes its SVC turned as `steps` says
    /// ([`Turn::svc_stamp`]).
    pub(super) fn set_svc_turn(&mut self, v: usize, steps: u64) {
        if self.svc_turns.is_empty() && steps != 0 {
            self.svc_turns = vec![0; self.pending.len()];
        }
        if let Some(s) = self.svc_turns.get_mut(v) {
            *s = steps;
        }
    }
}

/// One object of a [`super::Frame`], as [`super::Frame::object`] shows it.
#[derive(Clone, Copy)]
pub struct FrameObject<'a> {
    /// Its name (unique in the scene).
    pub name: &'a str,
    /// Its mesh as it stands turned ([`super::Frame::turn`]; at rest until it turns), at no
    /// translation: [`FrameObject::positions`] adds it.
    pub mesh: &'a Mesh,
    /// Its BRDF parameters now.
    pub material: &'a Material,
    /// Its glTF material's textures.
    pub textures: &'a vcut_scene::loaders::MaterialTextures,
    /// Whether it may move.
    pub motion: Motion,
    /// Its translation from rest now.
    pub translation: Vec3,
    /// Its yaw about +Y now (radians in `[0, 2π)`; [`super::Frame::turn`]).
    pub yaw: f32,
    /// The whole wedges of the direction set its cuts are turned by (its yaw snapped).
    pub turn_steps: u32,
    data: &'a ObjectData,
}

impl std::fmt::Debug for FrameObject<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FrameObject")
            .field("name", &self.name)
            .field("motion", &self.motion)
            .field("translation", &self.translation)
            .field("yaw", &self.yaw)
            .finish_non_exhaustive()
    }
}

impl<'a> FrameObject<'a> {
    pub(super) fn of(data: &'a ObjectData) -> FrameObject<'a> {
        FrameObject {
            name: &data.name,
            mesh: &data.mesh,
            material: &data.material,
            textures: &data.textures,
            motion: data.motion,
            translation: data.translation,
            yaw: data.turn.yaw,
            turn_steps: data.turn.steps,
            data,
        }
    }

    /// The diffuse albedo at texture coordinates `uv`: the `kd` of its material there
    /// ([`vcut_scene::texture::MaterialTextures::material_at`]), else its own `kd`.
    pub fn albedo_at(&self, uv: Option<glam::Vec2>) -> Vec3 {
        match uv {
            Some(uv) if self.textures.vary() => Vec3::from(self.data.material_at(uv).kd),
            _ => Vec3::from(self.material.kd),
        }
    }

    /// The diffuse albedo averaged over its vertices (its `kd` when textures do not vary it):
    /// for renderers that take one per object.
    pub fn mean_albedo(&self) -> Vec3 {
        match self.data.vertex_materials.len() {
            0 => Vec3::from(self.material.kd),
            n => self.data.vertex_materials.iter().map(|m| Vec3::from(m.kd)).sum::<Vec3>() / n as f32,
        }
    }

    /// Vertex `v`'s material: the object's, varied by its textures at the vertex's coordinates
    /// (the BRDF every shading of the vertex evaluates).
    pub fn vertex_material(&self, v: usize) -> &'a Material {
        self.data.material(v)
    }

    /// Vertex `v`'s diffuse albedo (its material's `kd`).
    pub fn albedo(&self, v: usize) -> Vec3 {
        Vec3::from(self.data.material(v).kd)
    }

    /// What it turns about ([`super::Frame::turn`]): the vertical through this point, its
    /// bounding-sphere centre at rest.
    pub fn turn_centre(&self) -> Vec3 {
        self.data.centre
    }

    /// Its mesh at rest (before any turn).
    pub fn rest_mesh(&self) -> &'a Mesh {
        self.data.rest_mesh.as_deref().unwrap_or(self.mesh)
    }

    /// World positions of its vertices at its current translation and turn.
    pub fn positions(&self) -> Vec<Vec3> {
        self.mesh.positions().iter().map(|&p| p + self.translation).collect()
    }

    /// Whether vertex `v` may be seen from `eye`, and so is shaded toward it: its normal faces
    /// the eye, or one of its triangles may (a silhouette vertex of a visible triangle, shaded
    /// toward [`brdf::view_direction`]). What is not seen shades black in
    /// [`super::Frame::shade`] and its merges may wait.
    pub fn seen(&self, v: usize, eye: Vec3) -> bool {
        self.data.seen(v, eye)
    }
}

impl ObjectData {
    /// The material at every vertex ([`vcut_scene::texture::MaterialTextures::material_at`] its
    /// coordinates); empty when textures do not vary it.
    pub(super) fn vertex_materials(&self) -> Vec<Material> {
        match self.mesh.uvs() {
            Some(uvs) if self.textures.vary() => uvs.iter().map(|&uv| self.material_at(uv)).collect(),
            _ => Vec::new(),
        }
    }

    /// The material at texture coordinates `uv`: [`vcut_scene::texture::MaterialTextures::material_at`],
    /// or, once `material` is edited, [`vcut_scene::texture::MaterialTextures::base_colour_at`].
    pub(super) fn material_at(&self, uv: glam::Vec2) -> Material {
        if self.material == self.loaded_material {
            self.textures.material_at(&self.material, uv)
        } else {
            self.textures.base_colour_at(&self.material, uv)
        }
    }

    /// Vertex `v`'s material.
    #[inline]
    pub(super) fn material(&self, v: usize) -> &Material {
        self.vertex_materials.get(v).unwrap_or(&self.material)
    }
}

/// The normals of a vertex's triangles, bounded by a cone (unit axis, sine of its half-angle):
/// some triangle of the vertex may face a point seen in direction `d` only if `axis·d > −sin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ViewCone {
    axis: Vec3,
    sin: f32,
}

impl ViewCone {
    /// Every vertex's cone over `mesh`'s triangles (degenerate triangles left out; a vertex with
    /// no proper triangle, or whose triangles' normals cancel, gets the whole sphere).
    pub(super) fn of(mesh: &Mesh) -> Vec<ViewCone> {
        let p = mesh.positions();
        let normals: Vec<Vec3> = mesh
            .triangles()
            .iter()
            .map(|t| {
                (p[t[1] as usize] - p[t[0] as usize]).cross(p[t[2] as usize] - p[t[0] as usize]).normalize_or_zero()
            })
            .collect();
        let mut sum = vec![Vec3::ZERO; p.len()];
        for (t, n) in mesh.triangles().iter().zip(&normals) {
            for &i in t {
                sum[i as usize] += *n;
            }
        }
        let mut cones: Vec<ViewCone> =
            sum.iter().map(|s| ViewCone { axis: s.normalize_or_zero(), sin: -1.0 }).collect();
        for (t, n) in mesh.triangles().iter().zip(&normals) {
            if *n == Vec3::ZERO {
                continue;
            }
            for &i in t {
                let c = &mut cones[i as usize];
                // sin of the angle between the axis and this normal, or past 90°: 1 + (1 − cos).
                let cos = c.axis.dot(*n);
                let sin = if cos >= 0.0 { (1.0 - cos * cos).max(0.0).sqrt() } else { 2.0 - cos };
                c.sin = c.sin.max(sin);
            }
        }
        for c in &mut cones {
            if c.axis == Vec3::ZERO || c.sin < 0.0 {
                *c = ViewCone { axis: Vec3::ZERO, sin: 2.0 };
            }
        }
        cones
    }

    /// Whether some triangle of the vertex may face direction `d` (unit).
    #[inline]
    pub(super) fn may_face(&self, d: Vec3) -> bool {
        self.axis.dot(d) > -self.sin
    }
}

impl ObjectData {
    /// Whether vertex `v` at the current translation may be seen from `eye`: its normal faces
    /// the eye, or one of its triangles may ([`ViewCone`]); else it reflects nothing toward it.
    /// The one test of what is shaded, merged at once and listed for an eye.
    pub(super) fn seen(&self, v: usize, eye: Vec3) -> bool {
        let d = (eye - (self.mesh.positions()[v] + self.translation)).normalize_or_zero();
        self.mesh.normals()[v].dot(d) > 0.0 || self.cones[v].may_face(d)
    }

    /// Builds vertex `v`'s shading list from its kept merged cut `merged` into `list`.
    pub(super) fn relist(
        &self,
        v: usize,
        merged: &KeptCut,
        nodes: &[ShadeNode],
        list: &mut ShadeList,
        below: &mut Vec<[f32; 2]>,
    ) {
        list.rebuild(merged.nodes(), self.mesh.normals()[v], nodes, self.svc_ends(v).as_deref(), below);
    }

    /// Vertex `v`'s SVC turned by the nearest whole step of the object's yaw.
    pub(super) fn svc_cut(&self, v: usize) -> Result<Cut, super::CutFailure> {
        turned(self.stored_svc(v)?, self.shape, self.turn.steps)
    }

    /// Vertex `v`'s SVC as it is stored (at rest).
    fn stored_svc(&self, v: usize) -> Result<Cut, vcut_data::sections::CutDecodeError> {
        let chunk = self.svc_starts.partition_point(|&s| s <= v) - 1;
        self.svc[chunk].cut(v - self.svc_starts[chunk])
    }

    /// Vertex `v`'s SVC as the object stands, prepared for `algorithm` into `into`: the stored
    /// cut turned by each whole turn [`Turn::svc_weights`] weighs (one at a whole step, the two
    /// around the yaw between steps).
    pub(super) fn prepare_svc(
        &self,
        v: usize,
        algorithm: vcut_merge::Algorithm,
        into: &mut Prepared,
    ) -> Result<(), super::CutFailure> {
        let stored = self.stored_svc(v)?;
        if self.turn.blend == 0.0 {
            algorithm.prepare_into(&[&turned(stored, self.shape, self.turn.base)?], into)?;
            return Ok(());
        }
        let next = (self.turn.base + 1) % self.shape.map_or(1, |s| s.wedges() as u32);
        let base = turned(stored.clone(), self.shape, self.turn.base)?;
        algorithm.prepare_into(&[&base, &turned(stored, self.shape, next)?], into)?;
        Ok(())
    }

    /// Every vertex's SVC decoded and prepared for `algorithm` (the SVC cache).
    pub(super) fn prepared_svcs(
        &self,
        algorithm: vcut_merge::Algorithm,
    ) -> Result<Vec<Prepared>, (usize, super::CutFailure)> {
        use rayon::prelude::*;
        (0..self.mesh.vertex_count())
            .into_par_iter()
            .map(|v| {
                let mut svc = Prepared::default();
                self.prepare_svc(v, algorithm, &mut svc).map_err(|e| (v, e))?;
                Ok(svc)
            })
            .collect()
    }

    /// The node ends (leaves) of vertex `v`'s SVC: kept when the SVCs are, decoded otherwise
    /// (`None` if that fails; the setup's merge decoded it once, so it does not in practice).
    pub(super) fn svc_ends(&self, v: usize) -> Option<std::borrow::Cow<'_, [u32]>> {
        if let Some(r) = self.svc_refined.get(v) {
            return Some(r.ends());
        }
        if self.turn.blend == 0.0 {
            return Some(std::borrow::Cow::Owned(node_ends(&self.svc_cut(v).ok()?)));
        }
        // Two turns blended: the ends of their common refinement.
        let mut svc = Prepared::default();
        self.prepare_svc(v, vcut_merge::Algorithm::Counter, &mut svc).ok()?;
        Some(std::borrow::Cow::Owned(svc.ends().into_owned()))
    }
}

/// The objects at their translations and turns, as the sun's rays see them.
pub(super) fn placed(objects: &[ObjectData]) -> Vec<Placed<'_>> {
    objects
        .iter()
        .map(|s| Placed {
            mesh: &s.mesh,
            rest: s.rest_mesh.as_deref().unwrap_or(&s.mesh),
            translation: s.translation,
            yaw: s.turn.yaw,
            centre: s.centre,
        })
        .collect()
}

/// A stored cut `cut` turned by `steps` wedges of `shape` (as it is without a turn).
pub(super) fn turned(cut: Cut, shape: Option<vcut_cut::turn::TurnShape>, steps: u32) -> Result<Cut, super::CutFailure> {
    match shape {
        Some(shape) if steps != 0 => Ok(cut.turned(shape, steps)?),
        _ => Ok(cut),
    }
}

/// The leaf where each of `cut`'s nodes ends, left to right.
pub(super) fn node_ends(cut: &Cut) -> Vec<u32> {
    cut.heights()
        .iter()
        .scan(0u32, |end, &h| {
            *end += 1u32 << h;
            Some(*end)
        })
        .collect()
}
