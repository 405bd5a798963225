//! Per-object BRDF parameters, and how glTF's metallic-roughness materials map onto them.
//!
//! The BRDFs themselves are evaluated at run time by the shading crate; this module only holds
//! their parameters, so a scene file can name them and a loader can fill them in.
//!
//! # glTF PBR → our parameters
//! glTF's `pbrMetallicRoughness` (base colour `c`, metallic `m`, perceptual roughness `ρ`) becomes
//! a microfacet GGX material with
//! - diffuse albedo `kd = c · (1 − m)` (metals have no diffuse lobe),
//! - specular reflectance at normal incidence `ks = 0.04 · (1 − m) + c · m` (4 % for dielectrics),
//! - GGX α = ρ² (the usual remapping of perceptual roughness),
//! - and, for users who switch the object to Blinn-Phong, the exponent `n = 2/α² − 2`
//!   (Walter et al. 2007's equivalence), clamped to [1, 10⁴].
//!
//! The factors map to one BRDF per object, as in the paper. A material's base-colour and
//! metallic-roughness textures vary it over the surface through the mesh's `TEXCOORD_0`
//! ([`crate::texture::MaterialTextures::material_at`]: the same mapping of factor × texture at
//! each point); the renderers take the BRDF per vertex and the diffuse albedo per pixel. The
//! object's own material then stands for it where one per object is needed: the factors with
//! the metallic-roughness texture's mean over the vertices. A primitive without a material gets
//! glTF's default (white, fully metallic, fully rough — which we map as above).

use crate::limits::Limit;
use serde::{Deserialize, Serialize};

/// The BRDF families the shading crate evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum BrdfModel {
    /// Ideal diffuse, `kd/π`.
    Lambert,
    /// Normalised Blinn-Phong: `kd/π + ks (n+8)/(8π) cos^n θ_h`.
    #[default]
    BlinnPhong,
    /// Normalised Phong: `kd/π + ks (n+2)/(2π) cos^n α_r`.
    Phong,
    /// Microfacet GGX (Trowbridge-Reitz) with Smith shadowing and Schlick Fresnel.
    Ggx,
}

/// Parameters of an object's BRDF. Every field is used by some model; each model ignores the
/// ones it does not need.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Material {
    /// Which BRDF.
    pub model: BrdfModel,
    /// Diffuse albedo (linear RGB, 0..1).
    pub kd: [f32; 3],
    /// Specular reflectance (linear RGB, 0..1).
    pub ks: [f32; 3],
    /// Phong / Blinn-Phong exponent (the paper edits it from 15 to 70).
    pub exponent: f32,
    /// GGX roughness α (0 < α ≤ 1).
    pub roughness: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self { model: BrdfModel::BlinnPhong, kd: [0.6, 0.6, 0.6], ks: [0.2, 0.2, 0.2], exponent: 15.0, roughness: 0.3 }
    }
}

impl Material {
    /// The mapping documented at the top of this module.
    pub fn from_gltf_pbr(base_color: [f32; 3], metallic: f32, perceptual_roughness: f32) -> Material {
        let m = sanitize(metallic, 1.0);
        let c = base_color.map(|x| sanitize(x, 1.0));
        let rho = sanitize(perceptual_roughness, 1.0).max(0.02);
        let alpha = rho * rho;
        Material {
            model: BrdfModel::Ggx,
            kd: c.map(|x| x * (1.0 - m)),
            ks: c.map(|x| 0.04 * (1.0 - m) + x * m),
            exponent: (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 1.0e4),
            roughness: alpha,
        }
    }

    /// A diffuse material of albedo `kd`.
    pub fn lambert(kd: [f32; 3]) -> Material {
        Material { model: BrdfModel::Lambert, kd, ks: [0.0; 3], ..Material::default() }
    }

    /// A Blinn-Phong material.
    pub fn blinn_phong(kd: [f32; 3], ks: [f32; 3], exponent: f32) -> Material {
        Material { model: BrdfModel::BlinnPhong, kd, ks, exponent, ..Material::default() }
    }

    /// Checks the parameters are finite and in range ([`REFLECTANCE`], [`EXPONENT`],
    /// [`ROUGHNESS`]); names the first one that is not.
    pub fn validate(&self) -> Result<(), MaterialError> {
        let refuse =
            |key: &'static str, value: String, limit: Limit| MaterialError { key, value, range: limit.describe() };
        for (key, v) in [("kd", self.kd), ("ks", self.ks)] {
            if !v.iter().all(|x| REFLECTANCE.contains(f64::from(*x))) {
                return Err(refuse(key, format!("{v:?}"), REFLECTANCE));
            }
        }
        if !EXPONENT.contains(f64::from(self.exponent)) {
            return Err(refuse("exponent", self.exponent.to_string(), EXPONENT));
        }
        if !ROUGHNESS.contains(f64::from(self.roughness)) {
            return Err(refuse("roughness", self.roughness.to_string(), ROUGHNESS));
        }
        Ok(())
    }
}

/// The range of `kd` and `ks`, each channel.
pub const REFLECTANCE: Limit = Limit::within(0.0, 1.0, "");
/// The range of a Phong or Blinn-Phong `exponent`.
pub const EXPONENT: Limit = Limit::at_least(0.0, "");
/// The range of a GGX `roughness` (α).
pub const ROUGHNESS: Limit = Limit::above_up_to(0.0, 1.0, "");

/// A material parameter out of its range ([`Material::validate`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} = {value}: must be {range}")]
pub struct MaterialError {
    /// The parameter (`kd`, `ks`, `exponent`, `roughness`).
    pub key: &'static str,
    /// Its value as written.
    pub value: String,
    /// The range it must lie in ([`Limit::describe`]).
    pub range: String,
}

/// A glTF factor as the material takes it: clamped into [0, `max`], 0 when not finite (glTF
/// loaders keep what they can of a file's material rather than refuse the file).
fn sanitize(x: f32, max: f32) -> f32 {
    if x.is_finite() { x.clamp(0.0, max) } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gltf_dielectric_and_metal() {
        let d = Material::from_gltf_pbr([0.8, 0.2, 0.1], 0.0, 0.5);
        assert_eq!(d.kd, [0.8, 0.2, 0.1]);
        assert!((d.ks[0] - 0.04).abs() < 1e-6);
        assert!((d.roughness - 0.25).abs() < 1e-6);
        assert!((d.exponent - 30.0).abs() < 1e-3);
        let m = Material::from_gltf_pbr([0.9, 0.6, 0.2], 1.0, 0.2);
        assert_eq!(m.kd, [0.0; 3]);
        assert!((m.ks[1] - 0.6).abs() < 1e-6);
        d.validate().unwrap();
        m.validate().unwrap();
        let e = Material { kd: [2.0, 0.0, 0.0], ..d }.validate().unwrap_err();
        assert_eq!((e.key, e.to_string().as_str()), ("kd", "kd = [2.0, 0.0, 0.0]: must be a number in [0, 1]"));
    }
}
