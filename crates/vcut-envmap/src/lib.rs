//! Environment maps for precomputed visibility-cut rendering.
//!
//! An [`EnvMap`] is distant radiance `L(ω)` stored as texels in a [`Layout`] (lat-long or six
//! cube faces), with a rotation and an intensity scale on top. It answers three questions:
//!
//! - **lookup**: [`EnvMap::radiance`] (bilinear, for display), [`EnvMap::texel_radiance`]
//!   (nearest) and [`EnvMap::reconstructed`] (the map's [`Reconstruction`]);
//! - **integration**: [`EnvMap::total_power`] is ∫ L dω exactly for the map's reconstruction,
//!   box or bilinear ([`reconstruction`]; texel solid angles in closed form, not approximated
//!   by `sin θ`), and
//!   [`EnvMap::integrate_region`] / [`EnvMap::integrate_cone`] integrate over a part of the sphere
//!   by sub-texel patches. [`EnvMap::for_each_patch`] hands those patches out, so a light tree can
//!   bin radiance into any partition of the sphere without losing power;
//! - **statistics**: [`EnvMap::power_stats`] (total power, brightest texel, share of energy in the
//!   brightest 0.1 % of texels) for `cargo xtask inspect`.
//!
//! Files: Radiance `.hdr` (RLE and flat scanlines) and OpenEXR through [`load`]; a folder (or
//! six files) of cube faces through [`load_cube_faces`]. NaN, infinite or negative texels are an
//! error naming the file and texel unless [`InvalidTexels::Clamp`] is chosen. Built-in maps
//! (no file needed): [`procedural::PreethamSky`] (analytic sky with a 0.53° sun disk) and
//! [`procedural::Studio`] (a few small bright area lights).
//!
//! Conventions — +Y up, the lat-long image centre looks at +Z as in Mitsuba 3 — are in
//! [`layout`].
//!
//! # Invariants
//! Every texel is finite and ≥ 0; the texel count matches the layout; `intensity` is finite and
//! ≥ 0. This crate knows nothing about meshes, rays or trees.
//!
//! # Example
//! ```
//! use vcut_envmap::{EnvMap, procedural::Studio};
//! let map = Studio::default().bake(64);
//! let total = map.total_power();
//! let analytic = Studio::default().analytic_power();
//! assert!((total[1] - analytic[1]).abs() / analytic[1] < 1e-3);
//! let up = map.radiance(glam::Vec3::Y);
//! assert!(up.x >= 0.0);
//! ```

pub mod embed;
pub mod io;
pub mod layout;
pub mod procedural;
pub mod reconstruction;
mod rgbe;
pub mod sun;

pub use io::{EnvMapError, InvalidTexels, LoadReport, load, load_bytes, load_cube_faces};
pub use layout::{CubeHandedness, Layout};
pub use reconstruction::Reconstruction;

use glam::{Quat, Vec3};

/// Distant radiance stored as texels, with a rotation and an intensity scale.
#[derive(Debug, Clone)]
pub struct EnvMap {
    layout: Layout,
    texels: Vec<[f32; 3]>,
    /// World-from-map rotation: the map's own +Z is seen in world direction `rotation * Z`.
    rotation: Quat,
    intensity: f32,
    /// Where the texels came from (file path or built-in name), for messages.
    source: String,
    reconstruction: Reconstruction,
    /// Each texel's mean radiance under a bilinear reconstruction (empty for box: the texels).
    means: Vec<[f32; 3]>,
}

/// Power statistics of a map, as `cargo xtask inspect` prints them.
#[derive(Debug, Clone, PartialEq)]
pub struct PowerStats {
    /// ∫ L dω per RGB channel (W·m⁻² if texels are W·m⁻²·sr⁻¹).
    pub total_power: [f64; 3],
    /// Largest texel luminance (Rec. 709 Y), after intensity scaling.
    pub brightest_luminance: f32,
    /// World direction of that texel's centre.
    pub brightest_dir: Vec3,
    /// Share (0..1) of the luminous power carried by the brightest 0.1 % of texels (at least one).
    pub top_0_1_percent_share: f64,
}

/// Rec. 709 / sRGB-primaries luminance of a linear RGB triple.
pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl EnvMap {
    /// A map from texels, checked: the count must match the layout and every texel must be finite
    /// and ≥ 0 (or is clamped, with [`InvalidTexels::Clamp`]; the count comes back in the report).
    pub fn new(
        layout: Layout,
        mut texels: Vec<[f32; 3]>,
        source: impl Into<String>,
        invalid: InvalidTexels,
    ) -> Result<(Self, LoadReport), EnvMapError> {
        let source = source.into();
        let expected = layout.texel_count();
        if expected == 0 || texels.len() != expected {
            return Err(EnvMapError::Shape {
                path: source.into(),
                reason: format!("{} needs {expected} texels, got {}", layout.describe(), texels.len()),
            });
        }
        let clamped = io::check_texels(&mut texels, layout, &source, invalid)?;
        let map = Self {
            layout,
            texels,
            rotation: Quat::IDENTITY,
            intensity: 1.0,
            source,
            reconstruction: Reconstruction::Box,
            means: Vec::new(),
        };
        Ok((map, LoadReport { clamped_texels: clamped }))
    }

    /// A map of constant radiance `c` (a 2×1 lat-long map; negative or non-finite channels
    /// become 0).
    pub fn constant(c: [f32; 3]) -> Self {
        let c = c.map(|x| if x.is_finite() { x.max(0.0) } else { 0.0 });
        Self {
            layout: Layout::LatLong { width: 2, height: 1 },
            texels: vec![c; 2],
            rotation: Quat::IDENTITY,
            intensity: 1.0,
            source: "builtin:constant".into(),
            reconstruction: Reconstruction::Box,
            means: Vec::new(),
        }
    }

    /// How radiance is reconstructed between texel centres (and integrated).
    pub fn reconstruction(&self) -> Reconstruction {
        self.reconstruction
    }

    /// This map reconstructed as `r` ([`reconstruction`]); bilinear needs a lat-long map (an
    /// error naming the map otherwise).
    pub fn with_reconstruction(mut self, r: Reconstruction) -> Result<EnvMap, EnvMapError> {
        self.means = match (r, self.layout) {
            (Reconstruction::Box, _) => Vec::new(),
            (Reconstruction::Bilinear, Layout::LatLong { width, height }) => {
                reconstruction::bilinear_means(width, height, &self.texels)
            }
            (Reconstruction::Bilinear, Layout::Cube { .. }) => {
                return Err(EnvMapError::Shape {
                    path: self.source.clone().into(),
                    reason: "bilinear reconstruction needs a lat-long map; a cube map is integrated as box".into(),
                });
            }
        };
        self.reconstruction = r;
        Ok(self)
    }

    /// Each texel's mean radiance under the map's reconstruction (before rotation and
    /// intensity): the texels themselves for box. What every integrator reads: mean × solid
    /// angle summed over texels is the reconstruction's integral.
    pub fn integrated_texels(&self) -> &[[f32; 3]] {
        if self.means.is_empty() { &self.texels } else { &self.means }
    }

    /// Radiance along world direction `dir` as the map's reconstruction gives it: the texel's
    /// value for box, Mitsuba 3's bilinear lookup for bilinear ([`reconstruction`]; not
    /// [`EnvMap::radiance`], whose rows are centred in their bands).
    pub fn reconstructed(&self, dir: Vec3) -> Vec3 {
        match (self.reconstruction, self.layout) {
            (Reconstruction::Bilinear, Layout::LatLong { width, height }) => {
                let (u, v) = layout::latlong_uv(self.to_map(dir));
                let mut out = Vec3::ZERO;
                for (t, w) in reconstruction::bilinear_weights(width, height, u, v) {
                    out += Vec3::from(self.texels[t]) * w;
                }
                out * self.intensity
            }
            _ => self.texel_radiance(dir),
        }
    }

    /// The texel layout.
    pub fn layout(&self) -> Layout {
        self.layout
    }

    /// The stored texels (before rotation and intensity), layout order.
    pub fn texels(&self) -> &[[f32; 3]] {
        &self.texels
    }

    /// File path or built-in name the map came from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// World-from-map rotation.
    pub fn rotation(&self) -> Quat {
        self.rotation
    }

    /// Sets the world-from-map rotation (normalised; a non-finite one is ignored).
    pub fn set_rotation(&mut self, q: Quat) {
        if q.is_finite() && q.length_squared() > 0.0 {
            self.rotation = q.normalize();
        }
    }

    /// Rotates the map about the world up axis (+Y) by `degrees`, replacing any earlier rotation.
    pub fn set_rotation_y_degrees(&mut self, degrees: f32) {
        self.set_rotation(Quat::from_rotation_y(degrees.to_radians()));
    }

    /// Intensity multiplier applied to every texel.
    pub fn intensity(&self) -> f32 {
        self.intensity
    }

    /// Sets the intensity multiplier (negative or non-finite values are clamped to 0).
    pub fn set_intensity(&mut self, s: f32) {
        self.intensity = if s.is_finite() { s.max(0.0) } else { 0.0 };
    }

    fn to_map(&self, world: Vec3) -> Vec3 {
        self.rotation.inverse() * world
    }

    /// Texel `texel`'s mean radiance under the reconstruction, intensity applied.
    fn scaled(&self, texel: usize) -> [f32; 3] {
        self.integrated_texels()[texel].map(|c| c * self.intensity)
    }

    /// Bilinearly interpolated radiance seen along world direction `dir` (need not be unit),
    /// whatever the map's reconstruction: what backgrounds draw.
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let mut out = Vec3::ZERO;
        for (t, w) in self.layout.bilinear(self.to_map(dir)) {
            out += Vec3::from(self.texels[t]) * w;
        }
        out * self.intensity
    }

    /// Radiance of the texel that world direction `dir` falls in (no filtering).
    pub fn texel_radiance(&self, dir: Vec3) -> Vec3 {
        Vec3::from(self.texels[self.layout.texel_of(self.to_map(dir))].map(|c| c * self.intensity))
    }

    /// Visits `k × k` sub-texel patches of every texel: `f(world direction, exact solid angle,
    /// radiance)`, the radiance its texel's mean under the reconstruction. Summing `radiance ×
    /// solid angle` over any partition of whole texels gives its power with nothing lost: the
    /// solid angles are exact and sum to 4π.
    pub fn for_each_patch(&self, k: u32, mut f: impl FnMut(Vec3, f64, [f32; 3])) {
        self.layout.for_each_patch(k, |texel, d, omega| {
            f(self.rotation * d, omega, self.scaled(texel));
        });
    }

    /// ∫ L dω over the whole sphere per RGB channel, exact for the map's reconstruction
    /// (f64 accumulation).
    pub fn total_power(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        self.for_each_patch(1, |_, omega, c| {
            for (s, x) in sum.iter_mut().zip(c) {
                *s += f64::from(x) * omega;
            }
        });
        sum
    }

    /// ∫ L dω over the region where `inside(world direction)` holds, by `k × k` sub-texel
    /// patches classified at their centres: exact for regions bounded along texel edges, and
    /// otherwise converging as `k` grows (the boundary error is at most one patch ring).
    pub fn integrate_region(&self, k: u32, inside: impl Fn(Vec3) -> bool) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        self.for_each_patch(k, |d, omega, c| {
            if inside(d) {
                for (s, x) in sum.iter_mut().zip(c) {
                    *s += f64::from(x) * omega;
                }
            }
        });
        sum
    }

    /// ∫ L dω over the cone of directions within `half_angle` (radians) of `axis`, with sub-texel
    /// patches fine enough that the cone's rim error is small for cones a few texels wide.
    pub fn integrate_cone(&self, axis: Vec3, half_angle: f32) -> [f64; 3] {
        let axis = axis.normalize_or(Vec3::Y);
        let cos_max = half_angle.cos();
        self.integrate_region(4, |d| d.dot(axis) >= cos_max)
    }

    /// Total power, brightest texel and the energy share of the brightest 0.1 % of texels.
    pub fn power_stats(&self) -> PowerStats {
        let n = self.texels.len();
        let mut power = vec![0.0f64; n];
        let mut dirs = vec![Vec3::ZERO; n];
        let mut total = [0.0f64; 3];
        self.layout.for_each_patch(1, |t, d, omega| {
            let c = self.scaled(t);
            power[t] = f64::from(luminance(c)) * omega;
            dirs[t] = self.rotation * d;
            for (s, x) in total.iter_mut().zip(c) {
                *s += f64::from(x) * omega;
            }
        });
        let (mut best, mut best_lum) = (0usize, f32::MIN);
        for t in 0..n {
            let l = luminance(self.scaled(t));
            if l > best_lum {
                best_lum = l;
                best = t;
            }
        }
        let all: f64 = power.iter().sum();
        let top = (n / 1000).max(1);
        let mut sorted = power;
        sorted.sort_unstable_by(|a, b| b.total_cmp(a));
        let top_sum: f64 = sorted[..top].iter().sum();
        PowerStats {
            total_power: total,
            brightest_luminance: best_lum,
            brightest_dir: dirs[best],
            top_0_1_percent_share: if all > 0.0 { top_sum / all } else { 0.0 },
        }
    }

    /// Resamples into a lat-long map of `width × width/2` texels by `k × k` supersampling of the
    /// bilinear lookup (rotation and intensity baked in). Used to draw backgrounds and to compare
    /// layouts.
    pub fn to_latlong(&self, width: u32, k: u32) -> EnvMap {
        let width = width.max(2);
        let layout = Layout::LatLong { width, height: width / 2 };
        let mut acc = vec![[0.0f64; 4]; layout.texel_count()];
        layout.for_each_patch(k, |t, d, omega| {
            let c = self.radiance(d);
            let a = &mut acc[t];
            a[0] += f64::from(c.x) * omega;
            a[1] += f64::from(c.y) * omega;
            a[2] += f64::from(c.z) * omega;
            a[3] += omega;
        });
        let texels = acc.iter().map(|a| [(a[0] / a[3]) as f32, (a[1] / a[3]) as f32, (a[2] / a[3]) as f32]).collect();
        EnvMap {
            layout,
            texels,
            rotation: Quat::IDENTITY,
            intensity: 1.0,
            source: format!("{} (resampled)", self.source),
            reconstruction: Reconstruction::Box,
            means: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn constant_map_integrates_to_four_pi() {
        let m = EnvMap::constant([1.0, 2.0, 0.5]);
        let p = m.total_power();
        assert!((p[0] - 4.0 * PI).abs() < 1e-9);
        assert!((p[1] - 8.0 * PI).abs() < 1e-9);
        // A hemisphere cone holds half, up to the patch resolution at the rim.
        let h = m.integrate_cone(Vec3::Y, std::f32::consts::FRAC_PI_2);
        assert!((h[0] - 2.0 * PI).abs() < 1e-6, "{h:?}");
    }

    #[test]
    fn rotation_moves_features_and_keeps_power() {
        let layout = Layout::LatLong { width: 64, height: 32 };
        let mut texels = vec![[0.0f32; 3]; layout.texel_count()];
        let bright = layout.texel_of(Vec3::Z);
        texels[bright] = [100.0; 3];
        let (mut m, _) = EnvMap::new(layout, texels, "test", InvalidTexels::Reject).unwrap();
        let before = m.total_power();
        assert!(m.texel_radiance(Vec3::Z).x > 50.0);
        m.set_rotation_y_degrees(90.0);
        // Rotating +Z by +90° about Y gives +X.
        assert!(m.texel_radiance(Vec3::X).x > 50.0);
        assert!(m.texel_radiance(Vec3::Z).x < 1.0);
        let after = m.total_power();
        assert!((before[0] - after[0]).abs() < 1e-9 * before[0]);
    }

    #[test]
    fn rejects_wrong_texel_count() {
        let e = EnvMap::new(Layout::LatLong { width: 4, height: 2 }, vec![[0.0; 3]; 7], "x.hdr", InvalidTexels::Reject)
            .unwrap_err();
        assert!(e.to_string().contains("x.hdr"), "{e}");
    }

    #[test]
    fn power_stats_find_a_single_bright_texel() {
        let layout = Layout::LatLong { width: 128, height: 64 };
        let mut texels = vec![[0.01f32; 3]; layout.texel_count()];
        let t = layout.texel_of(Vec3::new(0.3, 0.8, 0.1));
        texels[t] = [1e5; 3];
        let (m, _) = EnvMap::new(layout, texels, "t", InvalidTexels::Reject).unwrap();
        let s = m.power_stats();
        assert!(s.brightest_dir.dot(Vec3::new(0.3, 0.8, 0.1).normalize()) > 0.99);
        assert!(s.top_0_1_percent_share > 0.9);
    }
}
