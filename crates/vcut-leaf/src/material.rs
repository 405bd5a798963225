//! The leaf appearance model: a two-sided slab whose diffuse reflectance and transmittance come
//! from [`crate::slab`], plus a Torrance–Sparrow gloss on each surface (Beckmann distribution with
//! roughness m, Cook–Torrance shadowing, dielectric Fresnel), modulated by per-side parameter maps
//! in the paper's layout: albedo γ(x) RGB + thickness detail δ(x) in one RGBA texture, specular
//! intensity ρ_s(x) RGB + roughness m(x) in another.
//!
//! Reading of the maps (the paper gives the layout, not the arithmetic): γ is the tissue's
//! single-scattering albedo σ_s/(σ_s + σ_a) with σ_s + σ_a kept, δ ∈ [0, 1] scales the thickness
//! to h·(0.5 + δ) (δ = 0.5 leaves it), ρ_s multiplies the gloss and m replaces the roughness.
//! Transmission is reciprocal, so it takes the mean of the two sides' γ and δ.
//!
//! The diffuse terms are not reduced by the gloss's Fresnel share (as in the paper's sum of a
//! subsurface and a surface term); with the default ρ_s the total stays below 1.

use crate::slab::{FitError, slab};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Refractive index of the leaf cuticle (waxy surface).
pub const CUTICLE_IOR: f32 = 1.45;

/// A rough dielectric surface's gloss: ρ_s · D G F / (4 |n·l| |n·v|).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gloss {
    /// Specular intensity per channel (0 = no gloss).
    pub rho_s: Vec3,
    /// Beckmann roughness m (RMS slope), clamped to ≥ 0.02 when evaluated.
    pub roughness: f32,
}

impl Gloss {
    /// No gloss at all.
    pub const NONE: Gloss = Gloss { rho_s: Vec3::ZERO, roughness: 1.0 };

    /// The gloss BRDF for unit `l` (toward the light) and `v` (toward the viewer), both on the side
    /// of unit normal `n` (0 otherwise).
    pub fn eval(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        if self.rho_s == Vec3::ZERO {
            return Vec3::ZERO;
        }
        let (nl, nv) = (n.dot(l), n.dot(v));
        if nl <= 1e-6 || nv <= 1e-6 {
            return Vec3::ZERO;
        }
        let h = (l + v).normalize_or_zero();
        let nh = n.dot(h).max(1e-6);
        let vh = v.dot(h).max(1e-6);
        let m = self.roughness.max(0.02);
        let d = beckmann(nh, m);
        let g = (2.0 * nh * nv / vh).min(2.0 * nh * nl / vh).min(1.0);
        let f = fresnel_dielectric(vh, CUTICLE_IOR);
        self.rho_s * (d * g * f / (4.0 * nl * nv))
    }
}

/// Beckmann distribution D = exp(−tan²α/m²) / (π m² cos⁴α), `cos_a` = n·h.
pub fn beckmann(cos_a: f32, m: f32) -> f32 {
    let c2 = cos_a * cos_a;
    let tan2 = (1.0 - c2).max(0.0) / c2;
    (-tan2 / (m * m)).exp() / (PI * m * m * c2 * c2)
}

/// Unpolarised Fresnel reflectance of a dielectric of index `eta` (from air) at cosine `cos_i`.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let c = cos_i.clamp(0.0, 1.0);
    let s2 = (1.0 - c * c) / (eta * eta);
    if s2 >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - s2).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    0.5 * (rs * rs + rp * rp)
}

/// What one surface point scatters: diffuse reflectance per side, diffuse transmittance, and a
/// gloss per side. Side 0 faces along the vertex normal ("top"), side 1 against it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scatter {
    /// Diffuse reflectance seen from each side (hemispherical).
    pub r: [Vec3; 2],
    /// Diffuse transmittance (hemispherical, the same both ways); 0 for opaque surfaces.
    pub t: Vec3,
    /// The gloss of each side.
    pub gloss: [Gloss; 2],
}

impl Scatter {
    /// An opaque Lambertian surface of albedo `kd` (pots, stems): reflects on its outer side only.
    pub fn opaque(kd: Vec3) -> Scatter {
        Scatter { r: [kd, Vec3::ZERO], t: Vec3::ZERO, gloss: [Gloss::NONE; 2] }
    }

    /// Whether light passes through (a leaf) or not (an opaque surface).
    pub fn translucent(&self) -> bool {
        self.t != Vec3::ZERO
    }

    /// The BSDF for unit `l` and `v` at a point of unit normal `n`: the side's diffuse reflectance
    /// and gloss when both are on one side, the diffuse transmittance when they are on opposite
    /// sides (light through the leaf).
    pub fn eval(&self, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
        let (nl, nv) = (n.dot(l), n.dot(v));
        if nl * nv > 0.0 {
            let side = usize::from(nv < 0.0);
            let ns = if side == 0 { n } else { -n };
            self.r[side] / PI + self.gloss[side].eval(ns, l, v)
        } else if nl * nv < 0.0 {
            self.t / PI
        } else {
            Vec3::ZERO
        }
    }
}

/// A texture of RGBA texels, sampled bilinearly with clamped coordinates (u right, v down).
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    width: usize,
    height: usize,
    texels: Vec<[f32; 4]>,
}

/// Why a texture cannot be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TextureError {
    /// The texel count is not width × height, or a size is zero.
    #[error("texture of {width}×{height} needs {} texels, got {got}", width * height)]
    Size {
        /// Width given.
        width: usize,
        /// Height given.
        height: usize,
        /// Texels given.
        got: usize,
    },
    /// A texel is not finite or lies outside [0, 1].
    #[error("texel {index} is {value:?}: parameter maps hold values in [0, 1]")]
    Value {
        /// The texel's index.
        index: usize,
        /// Its value.
        value: [f32; 4],
    },
}

impl Texture {
    /// A texture from texels in row-major order, each channel in [0, 1].
    pub fn new(width: usize, height: usize, texels: Vec<[f32; 4]>) -> Result<Texture, TextureError> {
        if width == 0 || height == 0 || texels.len() != width * height {
            return Err(TextureError::Size { width, height, got: texels.len() });
        }
        if let Some((index, &value)) =
            texels.iter().enumerate().find(|(_, t)| t.iter().any(|c| !(0.0..=1.0).contains(c)))
        {
            return Err(TextureError::Value { index, value });
        }
        Ok(Texture { width, height, texels })
    }

    /// Width and height in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The bilinear value at `uv` (clamped to the texture).
    pub fn sample(&self, uv: Vec2) -> [f32; 4] {
        let x = (uv.x.clamp(0.0, 1.0) * self.width as f32 - 0.5).clamp(0.0, (self.width - 1) as f32);
        let y = (uv.y.clamp(0.0, 1.0) * self.height as f32 - 0.5).clamp(0.0, (self.height - 1) as f32);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let at = |x: usize, y: usize| self.texels[y * self.width + x];
        let mut out = [0.0; 4];
        for (c, o) in out.iter_mut().enumerate() {
            let top = at(x0, y0)[c] * (1.0 - fx) + at(x1, y0)[c] * fx;
            let bottom = at(x0, y1)[c] * (1.0 - fx) + at(x1, y1)[c] * fx;
            *o = top * (1.0 - fy) + bottom * fy;
        }
        out
    }
}

/// One side's parameter maps, in the paper's layout.
#[derive(Debug, Clone, PartialEq)]
pub struct SideMaps {
    /// RGB: single-scattering albedo γ(x); A: thickness detail δ(x).
    pub albedo_thickness: Texture,
    /// RGB: specular intensity ρ_s(x); A: roughness m(x).
    pub specular_roughness: Texture,
}

impl SideMaps {
    /// Procedural maps of a leaf blade in leaf coordinates (u along the midrib from base to tip,
    /// v across, 0.5 on the midrib): veins (midrib and `veins` pairs of secondary veins) are
    /// thicker, paler and less glossy than the lamina; `glossy` scales ρ_s (the upper side is
    /// glossier than the lower one).
    pub fn veins(size: usize, veins: u32, lamina_albedo: Vec3, glossy: f32, roughness: f32) -> SideMaps {
        let size = size.max(2);
        let mut at = Vec::with_capacity(size * size);
        let mut sr = Vec::with_capacity(size * size);
        for y in 0..size {
            for x in 0..size {
                let (u, v) = ((x as f32 + 0.5) / size as f32, (y as f32 + 0.5) / size as f32);
                let across = (v - 0.5).abs();
                let mid = (-(across / 0.012).powi(2)).exp();
                // Secondary veins leave the midrib at 40° toward the tip.
                let phase = (u - across * 1.2) * veins as f32;
                let secondary = (-((phase - phase.round()) / 0.06).powi(2)).exp() * (1.0 - across * 1.6).max(0.0);
                let vein = mid.max(0.6 * secondary).clamp(0.0, 1.0);
                let pale = lamina_albedo + (Vec3::splat(0.97) - lamina_albedo) * (0.6 * vein);
                let thickness = 0.5 + 0.4 * vein;
                at.push([pale.x.min(1.0), pale.y.min(1.0), pale.z.min(1.0), thickness]);
                let s = (glossy * (1.0 - 0.7 * vein)).clamp(0.0, 1.0);
                sr.push([s, s, s, (roughness + 0.2 * vein).clamp(0.0, 1.0)]);
            }
        }
        SideMaps {
            albedo_thickness: Texture::new(size, size, at).expect("values are clamped to [0, 1]"),
            specular_roughness: Texture::new(size, size, sr).expect("values are clamped to [0, 1]"),
        }
    }
}

/// A leaf's material: the tissue (σ_a, σ_s per channel, thickness h), each side's gloss, and
/// optional parameter maps per side.
#[derive(Debug, Clone, PartialEq)]
pub struct LeafMaterial {
    /// Absorption coefficient per channel (per unit of `thickness`).
    pub sigma_a: Vec3,
    /// Scattering coefficient per channel.
    pub sigma_s: Vec3,
    /// Slab thickness h (same unit as the coefficients' inverse).
    pub thickness: f32,
    /// Gloss of the upper (along the normal) and lower side.
    pub gloss: [Gloss; 2],
    /// Parameter maps of the upper and lower side (`None`: uniform).
    pub maps: [Option<SideMaps>; 2],
}

impl Default for LeafMaterial {
    /// A green leaf fitted to reflectance (0.06, 0.13, 0.04) and transmittance (0.05, 0.16, 0.02)
    /// at a thickness of 0.3 mm — values typical of measured broad leaves — with a glossier top.
    fn default() -> LeafMaterial {
        LeafMaterial::from_measured(Vec3::new(0.06, 0.13, 0.04), Vec3::new(0.05, 0.16, 0.02), 0.3)
            .expect("the default measurements are a slab's")
    }
}

impl LeafMaterial {
    /// The tissue that reflects `r` and transmits `t` (per channel) at thickness `h`, through
    /// [`crate::slab::fit`]; default gloss (top ρ_s 0.5, m 0.3; bottom ρ_s 0.15, m 0.45), no maps.
    pub fn from_measured(r: Vec3, t: Vec3, h: f32) -> Result<LeafMaterial, FitError> {
        let mut sigma_a = Vec3::ZERO;
        let mut sigma_s = Vec3::ZERO;
        for c in 0..3 {
            let k = crate::slab::fit(f64::from(r[c]), f64::from(t[c]), f64::from(h))?;
            sigma_a[c] = k.sigma_a as f32;
            sigma_s[c] = k.sigma_s as f32;
        }
        Ok(LeafMaterial {
            sigma_a,
            sigma_s,
            thickness: h,
            gloss: [
                Gloss { rho_s: Vec3::splat(0.5), roughness: 0.3 },
                Gloss { rho_s: Vec3::splat(0.15), roughness: 0.45 },
            ],
            maps: [None, None],
        })
    }

    /// The single-scattering albedo σ_s/(σ_s+σ_a) per channel.
    pub fn albedo(&self) -> Vec3 {
        let total = self.sigma_a + self.sigma_s;
        Vec3::select(total.cmpgt(Vec3::ZERO), self.sigma_s / total, Vec3::ZERO)
    }

    /// Slab R and T for albedo `gamma` and thickness scale `scale` (the extinction kept).
    fn slab_rt(&self, gamma: Vec3, scale: f32) -> (Vec3, Vec3) {
        let total = self.sigma_a + self.sigma_s;
        let h = f64::from(self.thickness * scale);
        let (mut r, mut t) = (Vec3::ZERO, Vec3::ZERO);
        for c in 0..3 {
            let s = slab(f64::from(total[c] * (1.0 - gamma[c])), f64::from(total[c] * gamma[c]), h);
            r[c] = s.r as f32;
            t[c] = s.t as f32;
        }
        (r, t)
    }

    /// The single-scattering albedo per channel whose slab (this tissue's extinction and
    /// thickness) reflects `r`: R grows with the albedo, so bisection finds it; a reflectance
    /// beyond what an albedo of 0.9999 gives is clamped there.
    pub fn albedo_for_reflectance(&self, r: Vec3) -> Vec3 {
        let mut gamma = Vec3::ZERO;
        for c in 0..3 {
            let (mut lo, mut hi) = (0.0f32, 0.9999f32);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                let (rr, _) = self.slab_rt(Vec3::splat(mid), 1.0);
                if rr[c] < r[c] { lo = mid } else { hi = mid }
            }
            gamma[c] = 0.5 * (lo + hi);
        }
        gamma
    }

    /// This tissue with a colour texture (a glTF base colour: what the leaf reflects) as both
    /// sides' albedo map: each texel's albedo [`LeafMaterial::albedo_for_reflectance`] its
    /// linear colour (a table over the 256 levels per channel), thickness detail and gloss
    /// unchanged.
    pub fn with_reflectance_map(&self, texture: &vcut_scene::texture::Texture) -> LeafMaterial {
        let table: Vec<Vec3> =
            (0..=255u8).map(|l| self.albedo_for_reflectance(Vec3::splat(texture.level_value(l)))).collect();
        let (w, h) = texture.size();
        let albedo = texture
            .texels()
            .iter()
            .map(|t| [table[t[0] as usize].x, table[t[1] as usize].y, table[t[2] as usize].z, 0.5]);
        let albedo = Texture::new(w as usize, h as usize, albedo.collect()).expect("albedos lie in [0, 1)");
        let mut out = self.clone();
        out.maps = std::array::from_fn(|side| {
            let r = self.gloss[side].roughness;
            Some(SideMaps {
                albedo_thickness: albedo.clone(),
                specular_roughness: Texture::new(1, 1, vec![[1.0, 1.0, 1.0, r.clamp(0.0, 1.0)]]).expect("in [0, 1]"),
            })
        });
        out
    }

    /// What the leaf scatters at leaf coordinates `uv` (ignored without maps).
    pub fn scatter(&self, uv: Vec2) -> Scatter {
        let base = self.albedo();
        let mut gamma = [base; 2];
        let mut scale = [1.0f32; 2];
        let mut gloss = self.gloss;
        for side in 0..2 {
            if let Some(maps) = &self.maps[side] {
                let a = maps.albedo_thickness.sample(uv);
                gamma[side] = Vec3::new(a[0], a[1], a[2]).min(Vec3::splat(0.9999));
                scale[side] = 0.5 + a[3];
                let s = maps.specular_roughness.sample(uv);
                gloss[side].rho_s *= Vec3::new(s[0], s[1], s[2]);
                gloss[side].roughness = s[3].max(0.02);
            }
        }
        let (r0, _) = self.slab_rt(gamma[0], scale[0]);
        let (r1, _) = self.slab_rt(gamma[1], scale[1]);
        let (_, t) = self.slab_rt((gamma[0] + gamma[1]) * 0.5, (scale[0] + scale[1]) * 0.5);
        Scatter { r: [r0, r1], t, gloss }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hemispherical albedo of `s` lit from `l`, reflected and transmitted, by a fine midpoint
    /// quadrature over both hemispheres.
    fn albedo(s: &Scatter, n: Vec3, l: Vec3) -> (f32, f32) {
        let (mut refl, mut trans) = (0.0f64, 0.0f64);
        let steps = 400;
        for i in 0..steps {
            let mu = (i as f32 + 0.5) / steps as f32;
            for j in 0..steps {
                let phi = 2.0 * PI * (j as f32 + 0.5) / steps as f32;
                let r = (1.0 - mu * mu).sqrt();
                let local = Vec3::new(r * phi.cos(), mu, r * phi.sin());
                let w = f64::from(mu) * (1.0 / steps as f64) * (2.0 * std::f64::consts::PI / steps as f64);
                refl += f64::from(s.eval(n, l, local).y) * w;
                trans += f64::from(s.eval(n, l, -local).y) * w;
            }
        }
        (refl as f32, trans as f32)
    }

    #[test]
    fn the_default_leaf_reflects_and_transmits_what_it_was_fitted_to() {
        let leaf = LeafMaterial::default();
        let s = leaf.scatter(Vec2::splat(0.5));
        assert!((s.r[0] - Vec3::new(0.06, 0.13, 0.04)).abs().max_element() < 1e-5, "{}", s.r[0]);
        assert!((s.t - Vec3::new(0.05, 0.16, 0.02)).abs().max_element() < 1e-5, "{}", s.t);
        // Lit from straight above: diffuse reflection + gloss above, transmission below, < 1 in all.
        let (refl, trans) = albedo(&s, Vec3::Y, Vec3::Y);
        assert!((trans - 0.16).abs() < 2e-3, "transmitted {trans}");
        assert!(refl > 0.13 && refl < 0.13 + 0.1, "reflected {refl}");
        assert!(refl + trans < 1.0);
        // Reciprocity: swapping light and viewer changes nothing.
        let (l, v) = (Vec3::new(0.3, 0.8, 0.1).normalize(), Vec3::new(-0.5, 0.6, 0.3).normalize());
        assert!((s.eval(Vec3::Y, l, v) - s.eval(Vec3::Y, v, l)).abs().max_element() < 1e-5);
        // Light through the leaf: the same transmittance from either side.
        assert_eq!(s.eval(Vec3::Y, l, -v), s.eval(Vec3::Y, -l, v));
    }

    #[test]
    fn gloss_peaks_at_the_mirror_direction_and_fresnel_has_its_limits() {
        let g = Gloss { rho_s: Vec3::ONE, roughness: 0.2 };
        let l = Vec3::new(0.5, 0.8, 0.0).normalize();
        let mirror = Vec3::new(-l.x, l.y, 0.0);
        let off = Vec3::new(-0.6, 0.5, 0.6).normalize();
        assert!(g.eval(Vec3::Y, l, mirror).x > 5.0 * g.eval(Vec3::Y, l, off).x);
        assert_eq!(g.eval(Vec3::Y, l, -mirror), Vec3::ZERO);
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(0.0, 1.5), 1.0);
        // The Beckmann distribution is normalised: ∫ D cos α dω = 1.
        let mut sum = 0.0f64;
        let n = 4000;
        for i in 0..n {
            let c = (i as f32 + 0.5) / n as f32;
            sum += f64::from(beckmann(c, 0.3) * c) * 2.0 * std::f64::consts::PI / n as f64;
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }

    #[test]
    fn maps_modulate_the_leaf_and_bad_textures_are_refused() {
        let mut leaf = LeafMaterial::default();
        leaf.maps[0] = Some(SideMaps::veins(64, 6, leaf.albedo(), 1.0, 0.3));
        let vein = leaf.scatter(Vec2::new(0.5, 0.5));
        let lamina = leaf.scatter(Vec2::new(0.5, 0.25));
        assert!(vein.r[0].y > lamina.r[0].y, "veins are paler: {} vs {}", vein.r[0], lamina.r[0]);
        assert!(vein.gloss[0].rho_s.x < lamina.gloss[0].rho_s.x, "and less glossy");
        assert_ne!(vein.r[0], vein.r[1], "the two sides differ");
        assert_eq!(Texture::new(2, 2, vec![[0.0; 4]; 3]), Err(TextureError::Size { width: 2, height: 2, got: 3 }));
        assert!(matches!(Texture::new(1, 1, vec![[f32::NAN, 0.0, 0.0, 0.0]]), Err(TextureError::Value { .. })));
    }

    #[test]
    fn a_colour_texture_becomes_an_albedo_map_that_reflects_its_colour() {
        let leaf = LeafMaterial::default();
        // The inversion: an albedo's reflectance gives that albedo back.
        let gamma = Vec3::new(0.3, 0.7, 0.95);
        let (r, _) = leaf.slab_rt(gamma, 1.0);
        assert!((leaf.albedo_for_reflectance(r) - gamma).abs().max_element() < 1e-4);
        // A reflectance no albedo reaches is clamped to the brightest.
        assert!((leaf.albedo_for_reflectance(Vec3::ONE) - Vec3::splat(0.9999)).abs().max_element() < 1e-4);
        // A 2×1 sRGB texture, green then dark red: each texel's centre reflects its linear colour
        // on both sides.
        let bytes = [2, 0, 0, 0, 1, 0, 0, 0, 1, 60, 110, 40, 70, 20, 10];
        let t = vcut_scene::texture::Texture::from_bytes(&bytes, "leaf").unwrap();
        let mapped = leaf.with_reflectance_map(&t);
        for (uv, texel) in [(Vec2::new(0.25, 0.5), [60u8, 110, 40]), (Vec2::new(0.75, 0.5), [70, 20, 10])] {
            let want = Vec3::from(texel.map(|l| t.level_value(l)));
            let s = mapped.scatter(uv);
            for side in 0..2 {
                assert!((s.r[side] - want).abs().max_element() < 1e-4, "side {side}: {} vs {want}", s.r[side]);
            }
            assert_eq!(s.gloss, leaf.gloss, "gloss unchanged");
        }
    }
}
