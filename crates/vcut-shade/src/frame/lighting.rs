//! Lighting and materials: the environment's light tree, the sun by rays, the shading table
//! and the lists rebuilt after a lighting change; BRDF edits. None of them merges but to
//! rebuild lists without the merged cache.

use super::lists::{shade_nodes, specular_nodes};
use super::object::{MergeState, placed};
use super::{Context, Frame};
use crate::brdf;
use crate::sun::{self, Sun};
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_scene::Material;

impl Frame {
    /// Changes object `o`'s material (no merge). An object with a metallic-roughness texture
    /// takes the new material everywhere (the texture applies again when its loaded material
    /// is set back); a base-colour texture keeps multiplying `kd`.
    pub fn set_material(&mut self, o: usize, material: Material) {
        let s = &mut self.ctx.objects[o];
        if s.material.exponent != material.exponent {
            s.pow = brdf::PowTable::new(material.exponent);
        }
        s.material = material;
        s.vertex_materials = s.vertex_materials();
    }

    /// Rebuilds the light tree for a new or rotated environment (no merge; with sun rays on,
    /// the sun's rays are cast again).
    pub fn set_environment(&mut self, env: &EnvMap) {
        self.ctx.light = self.ctx.builder.build(env);
        self.ctx.light_state(&self.states, false);
        self.relist_all(None);
    }

    /// The sun by rays as the frame applies it when on ([`super::FrameSettings::sun_rays`]):
    /// the settings' target error, else the file's recorded one, else the default, and the
    /// settings' cap.
    pub fn sun_rays(&self) -> crate::SunRays {
        let on = super::FrameSettings { sun_rays: true, ..self.ctx.settings.clone() };
        on.sun(self.ctx.recorded_light_error).unwrap_or_default()
    }

    /// Rebuilds the shading lists after a lighting change: those of the vertices facing the
    /// last eye (all without one) that are not waiting and not in `skip` (merged with the
    /// current light already); the others' are marked stale. Without the merged cache this
    /// merges them again; a cut that fails to merge there (the same bytes merged at setup, so
    /// not in practice) leaves its list stale, and a shading that needs it shades it black.
    pub(super) fn relist_all(&mut self, skip: Option<&[Vec<bool>]>) {
        for (o, state) in self.states.iter_mut().enumerate() {
            let fresh = |v: usize| skip.and_then(|s| s.get(o)).is_some_and(|m| m.get(v).copied().unwrap_or(false));
            let which: Vec<bool> = state.pending.iter().enumerate().map(|(v, p)| !p && !fresh(v)).collect();
            for (list, _) in state.lists.iter_mut().zip(&state.pending).filter(|(_, p)| **p) {
                list.mark_stale();
            }
            if let Ok(again) = self.ctx.relist(o, state, &which) {
                self.tally.merges += again as u64;
            }
        }
    }
}

impl Context {
    /// The leaves cast by rays (chosen by their estimated error, [`crate::sun`]), their masks,
    /// and the shading table of the light the cuts carry, for the current light and settings.
    /// `stale`: the kept merged cuts are of settings that changed since (the choice merges its
    /// samples anew).
    pub(super) fn light_state(&mut self, states: &[MergeState], stale: bool) {
        let mut choice = match self.settings.sun(self.recorded_light_error) {
            Some(rays) => self.choose(&rays, states, stale),
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
}
