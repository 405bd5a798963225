//! Lighting and materials: the environment's light tree, the sun by rays, the shading table
//! and the lists rebuilt after a lighting change; BRDF edits. None of them merges.

use super::Frame;
use super::lists::{shade_nodes, specular_nodes};
use super::object::placed;
use crate::brdf;
use crate::sun::{self, Sun, SunRays};
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_scene::Material;

impl Frame {
    /// Changes object `o`'s material (no merge). An object with a metallic-roughness texture
    /// takes the new material everywhere (the texture applies again when its loaded material
    /// is set back); a base-colour texture keeps multiplying `kd`.
    pub fn set_material(&mut self, o: usize, material: Material) {
        let s = &mut self.objects[o];
        if s.material.exponent != material.exponent {
            s.pow = brdf::PowTable::new(material.exponent);
        }
        s.material = material;
        s.vertex_materials = s.vertex_materials();
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

    /// Leaves of the light cast by rays (0 with sun rays off, or none chosen):
    /// [`Frame::light_choice`] has which and why.
    pub fn sun_leaves(&self) -> usize {
        self.sun.as_ref().map_or(0, Sun::len)
    }

    /// The sun, the shading table and every list for the current light and sun setting.
    fn relight(&mut self) {
        self.light_state();
        self.relist_all();
    }

    /// The leaves cast by rays (chosen by their estimated error, [`crate::sun`]), their masks,
    /// and the shading table of the light the cuts carry, for the current light and setting.
    pub(super) fn light_state(&mut self) {
        let mut choice = match self.sun_rays {
            Some(rays) => self.choose(&rays),
            None => super::LightChoice::default(),
        };
        self.sun = None;
        if choice.cast.is_empty() {
            self.nodes = shade_nodes(&self.tree, &self.light);
        } else {
            let start = Instant::now();
            let (dirs, offset) = (self.tree.leaf_directions(), self.origin_offset);
            let objects = placed(&self.objects);
            let (sun, rays) = Sun::new(&self.light, &choice.cast, dirs, &objects, &self.occluders, offset);
            (choice.cast_rays, choice.cast_s) = (rays, start.elapsed().as_secs_f64());
            self.sun = Some(sun);
            self.nodes = shade_nodes(&self.tree, &sun::without(&self.light, &choice.cast));
        }
        self.specular = specular_nodes(&self.nodes);
        self.choice = choice;
    }

    /// Rebuilds the shading lists after a lighting change: those of the vertices facing the
    /// last eye (all without one); the others' are marked stale. With the merged cache off this
    /// merges them again; a cut that fails to merge there (the same bytes merged at setup, so
    /// not in practice) leaves its list stale, and a shading that needs it shades it black.
    fn relist_all(&mut self) {
        for o in 0..self.objects.len() {
            let s = &mut self.objects[o];
            let which: Vec<bool> = s.pending.iter().map(|p| !p).collect();
            for (list, _) in s.lists.iter_mut().zip(&s.pending).filter(|(_, p)| **p) {
                list.mark_stale();
            }
            let _ = self.relist(o, &which);
        }
    }
}
