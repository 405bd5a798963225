//! Shading: B = Σ_k weight_k f_r(Ê_k, ω_o) l_k over each vertex's shading list, the diffuse sum
//! times k_d/π, the specular lobe eight nodes at a time where the exponent is tabled, plus the
//! sun's leaves by rays; stale lists and waiting merges done on the spot.
//!
//! Every vertex is shaded in two [`Parts`], `B = k_d · diffuse + specular`: the diffuse part
//! free of the albedo, so a per-pixel albedo (a texture) or an image pass can take it apart.

use super::lists::{ShadeList, blinn_phong_argument, phong_argument};
use super::{Context, Frame};
use crate::brdf;
use glam::Vec3;
use rayon::prelude::*;
use std::borrow::Cow;
use vcut_merge::MergedCut;

/// A vertex's outgoing radiance in two parts: `k_d · diffuse + specular`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Parts {
    /// The diffuse term per unit albedo: `Σ_k weight_k l_k / π` (plus the sun's leaves').
    pub diffuse: Vec3,
    /// Everything else the BRDF reflects (the specular lobe, its sun leaves' share included).
    pub specular: Vec3,
}

impl Parts {
    /// The radiance under diffuse albedo `kd`.
    #[inline]
    pub fn radiance(self, kd: Vec3) -> Vec3 {
        kd * self.diffuse + self.specular
    }
}

impl Frame {
    /// Outgoing radiance toward `eye` of vertex `v` of object `o` if its merged cut were `cut`,
    /// a product with the vertex's SVC as a factor (shaded exactly as [`Frame::shade`] does):
    /// for measuring what other cuts would give.
    pub fn shade_cut(&self, o: usize, v: usize, cut: &MergedCut, eye: Vec3) -> Vec3 {
        let (ctx, s) = (&self.ctx, &self.ctx.objects[o]);
        if !s.seen(v, eye) {
            return Vec3::ZERO;
        }
        let list = ShadeList::new(cut.into(), s.mesh.normals()[v], &ctx.nodes, s.svc_ends(v).as_deref());
        ctx.shade_vertex(o, v, &list, eye).radiance(ctx.albedo(o, v))
    }

    /// As [`Frame::shade_cut`] for a cut whose every value is its own node's mean of
    /// V·max(0, n·ω) (not a product with the SVC).
    pub fn shade_cut_means(&self, o: usize, v: usize, cut: &MergedCut, eye: Vec3) -> Vec3 {
        let (ctx, s) = (&self.ctx, &self.ctx.objects[o]);
        if !s.seen(v, eye) {
            return Vec3::ZERO;
        }
        let list = ShadeList::new(cut.into(), s.mesh.normals()[v], &ctx.nodes, None);
        ctx.shade_vertex(o, v, &list, eye).radiance(ctx.albedo(o, v))
    }
}

impl Context {
    /// Vertex `v`'s diffuse albedo (its material's `kd`).
    fn albedo(&self, o: usize, v: usize) -> Vec3 {
        Vec3::from(self.objects[o].material(v).kd)
    }

    /// Vertex `v`'s radiance toward `eye` through `list`, in its parts; its callers have
    /// checked that `eye` sees it ([`super::FrameObject::seen`]).
    fn shade_vertex(&self, o: usize, v: usize, list: &ShadeList, eye: Vec3) -> Parts {
        let s = &self.objects[o];
        let x = s.mesh.positions()[v] + s.translation;
        let n = s.mesh.normals()[v];
        let wo = brdf::view_direction(n, x, eye);
        let material = s.material(v);
        let pow = match &s.pow {
            Some(t) if material.exponent == s.material.exponent => brdf::Pow::Table(t),
            _ => brdf::Pow::Exact(material.exponent),
        };
        let lobe = brdf::Lobe::with_pow(material, n, wo, pow);
        let sun = self.sun.as_ref().map_or(Parts::default(), |sun| sun.parts(o, v, &lobe, n));
        // One loop per lobe kind, so the match leaves the inner loop.
        let specular = match lobe {
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
        };
        Parts { diffuse: sun.diffuse + list.diffuse / std::f32::consts::PI, specular: sun.specular + specular }
    }
}

impl Frame {
    /// Outgoing radiance toward `eye` of every vertex of every object: B = Σ_k v_k f_r l_k over
    /// its merged cut, with the light-weighted node directions and cosines of the module
    /// documentation (plus the sun's leaves by rays, with [`super::FrameSettings::sun_rays`]).
    /// Vertices the eye cannot see ([`super::FrameObject::seen`]) are black; silhouette vertices are shaded toward
    /// [`brdf::view_direction`].
    ///
    /// Vertices whose list is stale build it on the spot without keeping it ([`Frame::set_eye`]
    /// keeps them; without the merged cache they merge again for it), and so do vertices
    /// seen from `eye` whose merge waits with their cut (a read error there, which setup's
    /// decoding of the same file makes unlikely, shades the vertex black; [`Frame::set_eye`]
    /// reports it). `eye` becomes the eye later merges build lists for.
    pub fn shade(&mut self, eye: Vec3) -> Vec<Vec<Vec3>> {
        let parts = self.shade_parts(eye, false);
        self.radiance(&parts)
    }

    /// [`Frame::shade`] for every vertex, for exports: those seen from `eye` as there, each
    /// other one toward its own normal (as seen head-on from outside; its waiting merge done).
    pub fn shade_all(&mut self, eye: Vec3) -> Vec<Vec<Vec3>> {
        let parts = self.shade_parts(eye, true);
        self.radiance(&parts)
    }

    /// Each object's radiance from its [`Parts`] under its own albedo at each vertex
    /// ([`super::FrameObject::albedo`]: its `kd`, times its texture at the vertex's coordinates).
    pub fn radiance(&self, parts: &[Vec<Parts>]) -> Vec<Vec<Vec3>> {
        parts
            .iter()
            .enumerate()
            .map(|(o, p)| p.iter().enumerate().map(|(v, x)| x.radiance(self.ctx.albedo(o, v))).collect())
            .collect()
    }

    /// [`Frame::shade`] (or, with `all`, [`Frame::shade_all`]) in [`Parts`]: for a per-pixel
    /// albedo and for image passes.
    pub fn shade_parts(&mut self, eye: Vec3, all: bool) -> Vec<Vec<Parts>> {
        self.ctx.eye = Some(eye);
        let ctx = &self.ctx;
        let (parts, spot): (Vec<Vec<Parts>>, Vec<u64>) = self
            .states
            .iter()
            .enumerate()
            .map(|(o, state)| {
                let s = &ctx.objects[o];
                let shaded: Vec<(Parts, bool)> = state
                    .lists
                    .par_iter()
                    .enumerate()
                    .map_init(
                        || (ShadeList::default(), Vec::new(), MergedCut::default()),
                        |(built, below, cut), (v, list)| {
                            let seen = s.seen(v, eye);
                            if !seen && !all {
                                return (Parts::default(), false);
                            }
                            // Unseen (in `all`): viewed along its normal.
                            let eye =
                                if seen { eye } else { s.mesh.positions()[v] + s.translation + s.mesh.normals()[v] };
                            let pending = state.pending[v];
                            if pending || (list.stale && !ctx.caches.merged) {
                                // At its current inputs if waiting, else at its kept ones.
                                let keys =
                                    if pending { Cow::Owned(ctx.keys(o, v)) } else { Cow::Borrowed(&state.keys[v]) };
                                if ctx.merge_one(o, v, &keys, cut).is_err() {
                                    return (Parts::default(), true);
                                }
                                let ends = s.svc_ends(v);
                                built.rebuild((&*cut).into(), s.mesh.normals()[v], &ctx.nodes, ends.as_deref(), below);
                                (ctx.shade_vertex(o, v, built, eye), true)
                            } else if list.stale {
                                s.relist(v, &state.merged[v], &ctx.nodes, built, below);
                                (ctx.shade_vertex(o, v, built, eye), false)
                            } else {
                                (ctx.shade_vertex(o, v, list, eye), false)
                            }
                        },
                    )
                    .collect();
                let spot = shaded.iter().filter(|x| x.1).count() as u64;
                (shaded.into_iter().map(|x| x.0).collect(), spot)
            })
            .unzip();
        self.tally.spot_merges += spot.iter().sum::<u64>();
        parts
    }
}
