//! What a precompute builds before it casts rays — the direction set and tree, the field
//! layouts, the occluders (built on first use) — and the one cut of a vertex or sample point:
//! shared by the run ([`crate::run`]) and its estimate ([`crate::estimate`]), so the estimate
//! times exactly the work the run does.

use crate::field::{leaf_solid_angles, point_cut};
use crate::params::PrecomputeParams;
use crate::run::{Job, PrecomputeError, directions, objects_needing_fields};
use crate::svc::leaf_visibility;
use crate::{Occluder, RayStats};
use glam::Vec3;
use std::sync::OnceLock;
use vcut_cut::Cut;
use vcut_cut::select::Selector;
use vcut_data::FieldLayout;
use vcut_dirtree::DirectionTree;
use vcut_scene::{Motion, Scene};
use vcut_sphere::DirectionSet;

/// Per object, the layout of its field if it gets one ([`objects_needing_fields`]).
pub fn field_layouts(scene: &Scene, p: &PrecomputeParams) -> Vec<Option<FieldLayout>> {
    let needs = objects_needing_fields(scene);
    scene
        .objects
        .iter()
        .zip(&needs)
        .map(|(o, &n)| {
            n.then(|| {
                crate::field::layout_around(
                    &o.mesh,
                    p.field_spheres,
                    p.field_resolution,
                    [p.field_inner, p.field_inner_flat],
                    p.field_outer,
                    p.field_spacing,
                )
            })
        })
        .collect()
}

/// A per-thread buffer of leaf values and a cut selector.
pub type Scratch = (Vec<f32>, Selector);

/// The directions, layouts and occluders of a job.
pub struct Setup<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The parameters.
    pub params: &'a PrecomputeParams,
    /// The direction set (generation order).
    pub set: DirectionSet,
    /// Its cells' solid angles.
    pub areas: Vec<f64>,
    /// The direction tree.
    pub tree: DirectionTree,
    /// The tree's leaf solid angles in leaf order.
    pub leaf_areas: Vec<f64>,
    /// Per object, its field's layout if it gets one.
    pub layouts: Vec<Option<FieldLayout>>,
    /// Every static object together: what a static object's SVC sees.
    statics: OnceLock<Occluder>,
    /// Each object alone: a movable object's SVC and any object's field.
    alone: Vec<OnceLock<Occluder>>,
}

impl<'a> Setup<'a> {
    /// Loads or generates the directions, builds the tree and lays out the fields.
    pub fn new(job: &'a Job<'a>) -> Result<Setup<'a>, PrecomputeError> {
        let (p, scene) = (&job.params, job.scene);
        let (set, areas, tree) = directions(p, job.cache_dir.as_deref())?;
        let layouts = field_layouts(scene, p);
        let leaf_areas = leaf_solid_angles(&tree);
        let alone = scene.objects.iter().map(|_| OnceLock::new()).collect();
        Ok(Setup { scene, params: p, set, areas, tree, leaf_areas, layouts, statics: OnceLock::new(), alone })
    }

    /// What object `i`'s SVCs are cast against: itself if it moves, every static object if not.
    pub fn svc_occluder(&self, i: usize) -> &Occluder {
        match self.scene.objects[i].motion {
            Motion::Movable => self.alone(i),
            Motion::Static => self.statics.get_or_init(|| {
                let statics: Vec<&vcut_scene::Mesh> =
                    self.scene.objects.iter().filter(|o| o.motion == Motion::Static).map(|o| &o.mesh).collect();
                Occluder::new(&statics)
            }),
        }
    }

    /// Object `i` alone (its field is cast against it).
    pub fn alone(&self, i: usize) -> &Occluder {
        self.alone[i].get_or_init(|| Occluder::new(&[&self.scene.objects[i].mesh]))
    }

    /// The objects with a field, in order.
    pub fn field_objects(&self) -> Vec<usize> {
        (0..self.layouts.len()).filter(|&i| self.layouts[i].is_some()).collect()
    }

    /// Where vertex `v` of object `i` casts its SVC rays from, and its normal: the vertex moved
    /// along its normal by `svc_origin_offset` × the object's bounding radius.
    pub fn svc_origin(&self, i: usize, v: usize) -> (Vec3, Vec3) {
        let mesh = &self.scene.objects[i].mesh;
        let offset = vcut_rays::origin_offset(self.params.svc_origin_offset, mesh);
        let (pos, nrm) = (mesh.positions()[v], mesh.normals()[v]);
        (vcut_rays::origin(pos, nrm, offset), nrm)
    }

    /// The SVC of vertex `v` of object `i`, and the rays it took.
    pub fn svc_cut(&self, i: usize, v: usize, (values, selector): &mut Scratch) -> (Cut, RayStats) {
        let (origin, normal) = self.svc_origin(i, v);
        let stats = leaf_visibility(self.svc_occluder(i), &self.tree, origin, normal, values);
        let cut = selector
            .select(values, &self.leaf_areas, self.params.svc_select())
            .unwrap_or_else(|_| unreachable!("a tree's leaf count is a power of two"));
        (cut, stats)
    }

    /// The field cut of object `i` at point `k` of sphere `s`, whether the point is inside the
    /// object, and the rays it took.
    pub fn field_cut(&self, i: usize, s: u32, k: u32, scratch: &mut Scratch) -> (Cut, bool, RayStats) {
        let l =
            self.layouts[i].as_ref().unwrap_or_else(|| unreachable!("asked for the field of an object without one"));
        point_cut(self.alone(i), &self.tree, &self.leaf_areas, l.point(s, k), l, self.params.field_select(), scratch)
    }

    /// A fresh scratch buffer.
    pub fn scratch(&self) -> Scratch {
        (vec![0.0f32; self.tree.leaf_count()], Selector::default())
    }
}
