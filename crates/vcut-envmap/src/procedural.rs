//! Built-in environment maps, so everything runs with no file at all.
//!
//! - [`PreethamSky`]: the Preetham, Shirley & Smits (1999) analytic daylight model for the sky
//!   dome, a sun disk of its real angular size (0.53° by default) and a Lambertian ground lit by
//!   both. The sun is `sun_to_zenith` times brighter than the zenith sky (default 10⁵).
//! - [`Studio`]: a dim vertical gradient with a few small, bright, coloured disk lights — the
//!   high-frequency case.
//!
//! Both are continuous functions ([`PreethamSky::radiance`], [`Studio::radiance`]) with a known
//! total ([`PreethamSky::analytic_power`], [`Studio::analytic_power`]), baked into lat-long maps
//! by [`PreethamSky::bake`] / [`Studio::bake`]. Baking averages the smooth part over each texel
//! (supersampled) and spreads every disk over the texels it covers by its exact covered solid
//! angle, rescaled so that the disk's baked power equals `radiance × 2π(1 − cos r)` exactly:
//! a sun smaller than a texel keeps its power.

use crate::{EnvMap, Layout, layout};
use glam::Vec3;
use std::f64::consts::PI;

/// Solid angle of a cone of half-angle `r` radians: 2π(1 − cos r), stable for tiny `r`.
pub fn cone_solid_angle(r: f64) -> f64 {
    let s = (0.5 * r).sin();
    4.0 * PI * s * s
}

/// The Preetham analytic sky with a sun disk and a Lambertian ground.
#[derive(Debug, Clone, PartialEq)]
pub struct PreethamSky {
    /// Direction towards the sun (world space, +Y up; normalised on use).
    pub sun_dir: Vec3,
    /// Atmospheric turbidity, 2 (clear) .. 10 (hazy).
    pub turbidity: f32,
    /// Apparent diameter of the sun disk in degrees (the real sun: 0.53).
    pub sun_diameter_deg: f32,
    /// Sun radiance divided by the zenith sky luminance.
    pub sun_to_zenith: f32,
    /// Ground albedo (the lower hemisphere is a Lambertian ground lit by sky and sun).
    pub ground_albedo: f32,
}

impl Default for PreethamSky {
    fn default() -> Self {
        Self::from_elevation_azimuth(30.0, 45.0)
    }
}

/// Perez luminance distribution coefficients A..E.
type Perez = [f64; 5];

fn perez(c: &Perez, cos_theta: f64, gamma: f64) -> f64 {
    let cos_theta = cos_theta.max(1e-3);
    let cg = gamma.cos();
    (1.0 + c[0] * (c[1] / cos_theta).exp()) * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * cg * cg)
}

fn xyz_to_linear_srgb(x: f64, y: f64, z: f64) -> [f64; 3] {
    [
        (3.2406 * x - 1.5372 * y - 0.4986 * z).max(0.0),
        (-0.9689 * x + 1.8758 * y + 0.0415 * z).max(0.0),
        (0.0557 * x - 0.2040 * y + 1.0570 * z).max(0.0),
    ]
}

/// Precomputed per-sky constants.
struct SkyModel {
    sun: Vec3,
    coeffs: [Perez; 3],
    zenith: [f64; 3],
    norm: [f64; 3],
}

impl SkyModel {
    fn new(sky: &PreethamSky) -> Self {
        let sun = sky.sun_dir.normalize_or(Vec3::Y);
        let t = f64::from(sky.turbidity.clamp(1.7, 10.0));
        let theta_s = f64::from(sun.y).clamp(-1.0, 1.0).acos().min(PI / 2.0 - 1e-3);
        let y_c = [
            0.1787 * t - 1.4630,
            -0.3554 * t + 0.4275,
            -0.0227 * t + 5.3251,
            0.1206 * t - 2.5771,
            -0.0670 * t + 0.3703,
        ];
        let x_c = [
            -0.0193 * t - 0.2592,
            -0.0665 * t + 0.0008,
            -0.0004 * t + 0.2125,
            -0.0641 * t - 0.8989,
            -0.0033 * t + 0.0452,
        ];
        let yy_c = [
            -0.0167 * t - 0.2608,
            -0.0950 * t + 0.0092,
            -0.0079 * t + 0.2102,
            -0.0441 * t - 1.6537,
            -0.0109 * t + 0.0529,
        ];
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
        let yz = ((4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192).max(0.05);
        let (t2, s1, s2, s3) = (t * t, theta_s, theta_s * theta_s, theta_s * theta_s * theta_s);
        let xz = t2 * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s1)
            + t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s1 + 0.00394)
            + (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s1 + 0.25886);
        let yyz = t2 * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s1)
            + t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s1 + 0.00516)
            + (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s1 + 0.26688);
        let coeffs = [y_c, x_c, yy_c];
        // Luminance in units of the zenith luminance: Y(zenith) = 1.
        let zenith = [1.0, xz, yyz];
        let _ = yz;
        let norm = [0, 1, 2].map(|i| perez(&coeffs[i], 1.0, theta_s));
        Self { sun, coeffs, zenith, norm }
    }

    /// Linear sRGB sky radiance (upper hemisphere only), zenith luminance = 1.
    fn sky(&self, d: Vec3) -> [f64; 3] {
        let cos_theta = f64::from(d.y);
        let gamma = f64::from(d.dot(self.sun)).clamp(-1.0, 1.0).acos();
        let v = [0, 1, 2].map(|i| self.zenith[i] * perez(&self.coeffs[i], cos_theta, gamma) / self.norm[i]);
        let (big_y, x, y) = (v[0], v[1], v[2].max(1e-6));
        xyz_to_linear_srgb(x / y * big_y, big_y, (1.0 - x - y) / y * big_y)
    }
}

impl PreethamSky {
    /// A sky with the sun at `elevation_deg` above the horizon and `azimuth_deg` measured from +Z
    /// towards +X; turbidity 3, sun 0.53°, sun/zenith 10⁵, ground albedo 0.3.
    pub fn from_elevation_azimuth(elevation_deg: f32, azimuth_deg: f32) -> Self {
        let (el, az) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
        Self {
            sun_dir: Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos()),
            turbidity: 3.0,
            sun_diameter_deg: 0.53,
            sun_to_zenith: 1.0e5,
            ground_albedo: 0.3,
        }
    }

    fn sun_radius(&self) -> f64 {
        0.5 * f64::from(self.sun_diameter_deg.max(1e-4)).to_radians()
    }

    /// Sun disk radiance (RGB): a slightly warm white, `sun_to_zenith` × the zenith luminance.
    pub fn sun_radiance(&self) -> [f64; 3] {
        let s = f64::from(self.sun_to_zenith.max(0.0));
        [1.0 * s, 0.96 * s, 0.88 * s]
    }

    /// Radiance of the ground (constant): albedo × (sky + sun irradiance on a horizontal plane)/π.
    pub fn ground_radiance(&self) -> [f64; 3] {
        let model = SkyModel::new(self);
        let irr = hemisphere_quadrature(&|d| model.sky(d), 256, 512, true);
        let sun = self.sun_radiance();
        let cos_s = f64::from(model.sun.y).max(0.0);
        let omega = cone_solid_angle(self.sun_radius());
        let a = f64::from(self.ground_albedo.clamp(0.0, 1.0));
        [0, 1, 2].map(|i| a * (irr[i] + sun[i] * omega * cos_s) / PI)
    }

    /// An evaluator of the continuous radiance (precomputes the model and the ground once).
    pub fn evaluator(&self) -> SkyEvaluator {
        SkyEvaluator {
            model: SkyModel::new(self),
            ground: self.ground_radiance(),
            sun: self.sun_radiance(),
            cos_sun_radius: self.sun_radius().cos(),
        }
    }

    /// ∫ L dω: the sky dome by a fine quadrature of the continuous model (independent of any
    /// texel grid), the ground and the sun disk in closed form.
    pub fn analytic_power(&self) -> [f64; 3] {
        let model = SkyModel::new(self);
        let sky = hemisphere_quadrature(&|d| model.sky(d), 2048, 2048, false);
        let ground = self.ground_radiance();
        let sun = self.sun_radiance();
        let omega = cone_solid_angle(self.sun_radius());
        [0, 1, 2].map(|i| sky[i] + ground[i] * 2.0 * PI + sun[i] * omega)
    }

    /// Bakes into a `width × width/2` lat-long map (smooth part supersampled 4×4 per texel, the
    /// sun disk with exact power).
    pub fn bake(&self, width: u32) -> EnvMap {
        let model = SkyModel::new(self);
        let ground = self.ground_radiance();
        let smooth = |d: Vec3| if d.y >= 0.0 { model.sky(d) } else { ground };
        let layout = Layout::LatLong { width: width.max(4), height: width.max(4) / 2 };
        let mut texels = bake_smooth(layout, 4, &smooth);
        add_disk(&mut texels, layout, model.sun, self.sun_radius(), self.sun_radiance());
        finish(layout, texels, "builtin:sky")
    }
}

/// Continuous radiance of a [`PreethamSky`], cheap to evaluate.
pub struct SkyEvaluator {
    model: SkyModel,
    ground: [f64; 3],
    sun: [f64; 3],
    cos_sun_radius: f64,
}

impl SkyEvaluator {
    /// Radiance along `d` (sky or ground, plus the sun disk), linear sRGB.
    pub fn radiance(&self, d: Vec3) -> [f64; 3] {
        let d = d.normalize_or(Vec3::Y);
        let mut c = if d.y >= 0.0 { self.model.sky(d) } else { self.ground };
        if f64::from(d.dot(self.model.sun)) >= self.cos_sun_radius {
            for i in 0..3 {
                c[i] += self.sun[i];
            }
        }
        c
    }
}

/// A studio: dim vertical gradient plus small bright disk lights.
#[derive(Debug, Clone, PartialEq)]
pub struct Studio {
    /// Background radiance at the horizon (RGB).
    pub background: [f32; 3],
    /// Background gradient: radiance is `background × (1 + gradient·y)`, |gradient| ≤ 1.
    pub gradient: f32,
    /// The lights: (direction, angular radius in degrees, RGB radiance), added to the background.
    pub lights: Vec<(Vec3, f32, [f32; 3])>,
}

impl Default for Studio {
    fn default() -> Self {
        Self {
            background: [0.05, 0.05, 0.055],
            gradient: 0.6,
            lights: vec![
                (Vec3::new(0.6, 0.7, 0.4), 4.0, [400.0, 380.0, 350.0]),
                (Vec3::new(-0.8, 0.35, 0.5), 8.0, [40.0, 50.0, 70.0]),
                (Vec3::new(0.1, 0.45, -0.9), 2.0, [1500.0, 1200.0, 900.0]),
            ],
        }
    }
}

impl Studio {
    fn background_at(&self, d: Vec3) -> [f64; 3] {
        let g = f64::from(self.gradient.clamp(-1.0, 1.0));
        self.background.map(|b| f64::from(b.max(0.0)) * (1.0 + g * f64::from(d.y)))
    }

    /// Continuous radiance along `d`.
    pub fn radiance(&self, d: Vec3) -> [f64; 3] {
        let d = d.normalize_or(Vec3::Y);
        let mut c = self.background_at(d);
        for (dir, r, l) in &self.lights {
            let r = f64::from(r.to_radians());
            if f64::from(d.dot(dir.normalize_or(Vec3::Y))).clamp(-1.0, 1.0).acos() <= r {
                for i in 0..3 {
                    c[i] += f64::from(l[i].max(0.0));
                }
            }
        }
        c
    }

    /// ∫ L dω in closed form: 4π × background (the gradient integrates to zero) plus every
    /// light's radiance × its cone solid angle.
    pub fn analytic_power(&self) -> [f64; 3] {
        let mut p = self.background.map(|b| 4.0 * PI * f64::from(b.max(0.0)));
        for (_, r, l) in &self.lights {
            let omega = cone_solid_angle(f64::from(r.to_radians()));
            for i in 0..3 {
                p[i] += f64::from(l[i].max(0.0)) * omega;
            }
        }
        p
    }

    /// Bakes into a `width × width/2` lat-long map with exact light powers.
    pub fn bake(&self, width: u32) -> EnvMap {
        let layout = Layout::LatLong { width: width.max(4), height: width.max(4) / 2 };
        let mut texels = bake_smooth(layout, 2, &|d| self.background_at(d));
        for (dir, r, l) in &self.lights {
            let l = l.map(|x| f64::from(x.max(0.0)));
            add_disk(&mut texels, layout, dir.normalize_or(Vec3::Y), f64::from(r.to_radians()), l);
        }
        finish(layout, texels, "builtin:studio")
    }
}

/// ∫ over the upper hemisphere of `f` (optionally × cos θ), midpoint rule in cos θ and φ with the
/// given numbers of intervals.
fn hemisphere_quadrature(f: &dyn Fn(Vec3) -> [f64; 3], n_mu: usize, n_phi: usize, cosine: bool) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    let d_mu = 1.0 / n_mu as f64;
    let d_phi = 2.0 * PI / n_phi as f64;
    for i in 0..n_mu {
        let mu = (i as f64 + 0.5) * d_mu;
        let s = (1.0 - mu * mu).sqrt();
        let w = d_mu * d_phi * if cosine { mu } else { 1.0 };
        for j in 0..n_phi {
            let phi = (j as f64 + 0.5) * d_phi;
            let d = Vec3::new((s * phi.cos()) as f32, mu as f32, (s * phi.sin()) as f32);
            let c = f(d);
            for k in 0..3 {
                sum[k] += c[k] * w;
            }
        }
    }
    sum
}

/// Texel averages of a smooth function by `k × k` solid-angle-weighted supersampling.
fn bake_smooth(layout: Layout, k: u32, f: &dyn Fn(Vec3) -> [f64; 3]) -> Vec<[f64; 4]> {
    let mut acc = vec![[0.0f64; 4]; layout.texel_count()];
    layout.for_each_patch(k, |t, d, omega| {
        let c = f(d);
        let a = &mut acc[t];
        for i in 0..3 {
            a[i] += c[i] * omega;
        }
        a[3] += omega;
    });
    acc
}

/// Adds a disk of constant radiance `l` around `axis` with angular radius `r` to the texel
/// accumulators (`[power_r, power_g, power_b, solid angle]`) by [`disk_shares`].
fn add_disk(acc: &mut [[f64; 4]], layout: Layout, axis: Vec3, r: f64, l: [f64; 3]) {
    for (t, share) in disk_shares(layout, axis, r) {
        for i in 0..3 {
            acc[t][i] += l[i] * share;
        }
    }
}

/// The solid angle of the disk around `axis` (map space) with angular radius `r` that each
/// lat-long texel holds: coverage measured on a fine sub-texel grid, then rescaled so the shares
/// sum to the disk's exact solid angle (a disk smaller than the grid lands whole in the texel
/// holding its axis). Empty for a cube layout.
pub(crate) fn disk_shares(layout: Layout, axis: Vec3, r: f64) -> Vec<(usize, f64)> {
    let Layout::LatLong { width, height } = layout else { return Vec::new() };
    let (w, h) = (f64::from(width), f64::from(height));
    let (_, v_axis) = layout::latlong_uv(axis);
    let theta_axis = v_axis * PI;
    let dtheta = PI / h;
    let margin = r + 2.0 * dtheta;
    let cos_r = r.cos();
    let axis64 = [f64::from(axis.x), f64::from(axis.y), f64::from(axis.z)];
    let k = 24u32;
    let mut covered: Vec<(usize, f64)> = Vec::new();
    for j in 0..height {
        let (t0, t1) = (f64::from(j) * dtheta, f64::from(j + 1) * dtheta);
        if t1 < theta_axis - margin || t0 > theta_axis + margin {
            continue;
        }
        for i in 0..width {
            let mut c = 0.0;
            for sj in 0..k {
                let v0 = (f64::from(j) + f64::from(sj) / f64::from(k)) / h;
                let v1 = (f64::from(j) + f64::from(sj + 1) / f64::from(k)) / h;
                let omega = layout::latlong_solid_angle(0.0, 1.0 / (w * f64::from(k)), v0, v1);
                for si in 0..k {
                    let u = (f64::from(i) + (f64::from(si) + 0.5) / f64::from(k)) / w;
                    let d = layout::latlong_dir(u, 0.5 * (v0 + v1));
                    let dot = f64::from(d.x) * axis64[0] + f64::from(d.y) * axis64[1] + f64::from(d.z) * axis64[2];
                    if dot >= cos_r {
                        c += omega;
                    }
                }
            }
            if c > 0.0 {
                covered.push((j as usize * width as usize + i as usize, c));
            }
        }
    }
    if covered.is_empty() {
        // Smaller than the sub-texel grid: all of it lands in the texel holding the axis.
        covered.push((layout.texel_of(axis), 1.0));
    }
    let total: f64 = covered.iter().map(|c| c.1).sum();
    let exact = cone_solid_angle(r);
    covered.into_iter().map(|(t, c)| (t, exact * c / total)).collect()
}

fn finish(layout: Layout, acc: Vec<[f64; 4]>, name: &str) -> EnvMap {
    let texels = acc.iter().map(|a| [0, 1, 2].map(|i| ((a[i] / a[3]) as f32).max(0.0))).collect();
    // Values are finite and ≥ 0 by construction.
    match EnvMap::new(layout, texels, name, crate::InvalidTexels::Clamp) {
        Ok((map, _)) => map,
        Err(_) => EnvMap::constant([0.0; 3]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sky_zenith_is_unit_luminance_and_sun_is_bright() {
        let sky = PreethamSky::default();
        let eval = sky.evaluator();
        let z = eval.radiance(Vec3::Y);
        let y = 0.2126 * z[0] + 0.7152 * z[1] + 0.0722 * z[2];
        assert!((y - 1.0).abs() < 0.05, "zenith luminance {y}");
        let s = eval.radiance(sky.sun_dir);
        assert!(s[0] > 0.5e5);
        // Blue sky: more blue than red away from the sun.
        let away = eval.radiance(Vec3::new(-sky.sun_dir.x, 0.8, -sky.sun_dir.z));
        assert!(away[2] > away[0], "{away:?}");
    }

    #[test]
    fn cone_solid_angle_matches_closed_form() {
        let r: f64 = 0.3;
        assert!((cone_solid_angle(r) - 2.0 * PI * (1.0 - r.cos())).abs() < 1e-12);
        assert!((cone_solid_angle(PI) - 4.0 * PI).abs() < 1e-12);
    }
}
