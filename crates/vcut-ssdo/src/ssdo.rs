//! The screen-space passes: SSAO and SSDO (direct light from unoccluded sample directions, one
//! indirect bounce from the occluding samples), with the geometry-aware blur.

use crate::gbuffer::{GBuffer, Object};
use crate::light::{Prefiltered, ShadowMap, Sun, split_sun};
use crate::samples::{SampleSets, basis};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;

/// The knobs, each with its cost measured by `cargo xtask bench` (the `ssdo` section).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Params {
    /// Samples per pixel N (the paper: 16).
    pub samples: usize,
    /// Sample sets M, interleaved over 4 × 4 pixels (16).
    pub sets: usize,
    /// Sampling radius r_max (world units).
    pub radius: f32,
    /// Without peeling: a stored surface more than this in front of a sample does not occlude
    /// it (world units along the view axis; default r_max).
    pub depth_limit: f32,
    /// Depth peeling: a sample is occluded only between the first and the second depth layer.
    pub peel: bool,
    /// Compute the indirect bounce (SSDO only).
    pub indirect: bool,
    /// Colour-bleeding strength: the sender patch area is `bleed · π r_max² / N`.
    pub bleed: f32,
    /// Blur half-width in pixels (2: five taps, covering the 4 × 4 interleave); 0 disables it.
    pub blur_radius: usize,
}

impl Params {
    /// The defaults for a scene of bounding radius `scene_radius`: N = 16, M = 16, r_max a tenth
    /// of the radius, no peeling, the indirect bounce on.
    pub fn for_scene(scene_radius: f32) -> Params {
        let radius = 0.1 * scene_radius.max(1e-6);
        Params {
            samples: 16,
            sets: 16,
            radius,
            depth_limit: radius,
            peel: false,
            indirect: true,
            bleed: 1.0,
            blur_radius: 2,
        }
    }
}

/// Which screen-space method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Ambient occlusion: the unoccluded environment irradiance scaled by the visible share.
    Ssao,
    /// Directional occlusion: light gathered from the unoccluded sample directions, plus one
    /// indirect bounce from the occluded ones.
    Ssdo,
}

/// What lights the scene in screen space.
#[derive(Debug, Clone)]
pub struct Lighting {
    /// The sun, split off the map, if it has one.
    pub sun: Option<Sun>,
    /// Its shadow map.
    pub shadow: Option<ShadowMap>,
    /// The rest of the environment, pre-filtered.
    pub env: Prefiltered,
    /// The rest of the environment as it is (for references).
    pub residual: EnvMap,
}

impl Lighting {
    /// Lighting of `objects` by `env` for `samples` per pixel (shadow map 2,048²).
    pub fn new(env: &EnvMap, objects: &[Object], samples: usize) -> Lighting {
        let (sun, residual) = split_sun(env);
        let shadow = sun.map(|s| ShadowMap::new(objects, s.dir, 2048));
        Lighting { sun, shadow, env: Prefiltered::new(&residual, samples), residual }
    }

    /// ρ/π · E_sun · max(0, n·s) · lit — the sun's share of a diffuse pixel.
    fn sun_term(&self, s: &crate::gbuffer::Surface) -> Vec3 {
        match (&self.sun, &self.shadow) {
            (Some(sun), Some(map)) => {
                let c = s.normal.dot(sun.dir);
                if c <= 0.0 { Vec3::ZERO } else { s.albedo / PI * sun.irradiance * c * map.lit(s.position) }
            }
            _ => Vec3::ZERO,
        }
    }
}

/// A screen-space image split into its terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// Width.
    pub width: usize,
    /// Height.
    pub height: usize,
    /// Direct light (sun + environment), per pixel.
    pub direct: Vec<Vec3>,
    /// The indirect bounce (zero for SSAO), per pixel.
    pub indirect: Vec<Vec3>,
    /// Share of each pixel's samples found occluded (0 where there is no surface).
    pub occlusion: Vec<f32>,
    /// Whether each pixel shows a surface.
    pub covered: Vec<bool>,
}

impl Output {
    /// Direct + indirect.
    pub fn total(&self) -> Vec<Vec3> {
        self.direct.iter().zip(&self.indirect).map(|(a, b)| *a + *b).collect()
    }
}

/// The pixel whose stored surface occludes sample point `s`, if any: `s` projects to a pixel
/// whose nearest surface lies in front of it (`s` is behind that surface's tangent plane), and
/// either — unpeeled — within [`Params::depth_limit`] of it along the view axis, or — peeled —
/// in front of the pixel's second layer.
#[inline]
pub fn occluder(g: &GBuffer, s: Vec3, p: &Params) -> Option<usize> {
    let (x, y, d) = g.project(s)?;
    let k = g.pixel(x, y)?;
    let front = g.first[k]?;
    // Behind the stored surface (against its normal, which faces the camera), not merely
    // farther than the depth at the pixel's centre: a sample just above a surface seen at a
    // grazing angle would otherwise be occluded by that very surface.
    if (s - front.position).dot(front.normal) >= -0.02 * p.radius || front.depth >= d {
        return None;
    }
    if p.peel {
        match g.second[k] {
            Some(back) if d >= back.depth => None,
            _ => Some(k),
        }
    } else if d - front.depth > p.depth_limit {
        None
    } else {
        Some(k)
    }
}

/// World sample points of pixel `(x, y)` on surface `position`, `normal`: `(direction,
/// point)` pairs.
#[inline]
fn sample_points<'a>(
    sets: &'a SampleSets,
    x: usize,
    y: usize,
    position: Vec3,
    normal: Vec3,
    radius: f32,
) -> impl Iterator<Item = (Vec3, Vec3)> + 'a {
    let (t, b) = basis(normal);
    sets.for_pixel(x, y).iter().map(move |q| {
        let w = (t * q.x + b * q.y + normal * q.z).normalize_or(normal);
        (w, position + w * (q.length() * radius))
    })
}

/// Renders `method` over G-buffer `g`.
///
/// One sampling pass per pixel: occlusion, the environment gathered from the unoccluded
/// directions (SSDO) or the visible share (SSAO), and — SSDO — the pixel each occluded sample
/// projected to. Then, SSDO only, the bounce from those recorded senders, lit by their
/// unblurred direct light (the 16 senders average the noise out). Finally one geometry-aware
/// blur over the sampled terms (environment + bounce); the sun's shadow-mapped term is added
/// after it, unblurred.
pub fn render(g: &GBuffer, light: &Lighting, sets: &SampleSets, params: &Params, method: Method) -> Output {
    let (w, h) = (g.width, g.height);
    let n = sets.n;
    let nf = n as f32;
    let d_omega = 2.0 * PI / nf;
    let ssdo = method == Method::Ssdo;
    let bounce = ssdo && params.indirect;
    let sun: Vec<Vec3> =
        (0..w * h).into_par_iter().map(|k| g.first[k].as_ref().map_or(Vec3::ZERO, |s| light.sun_term(s))).collect();
    let mut senders = vec![u32::MAX; if bounce { w * h * n } else { 0 }];
    let sampled: Vec<(Vec3, f32)> = if bounce {
        senders
            .par_chunks_mut(n)
            .enumerate()
            .map(|(k, rec)| sample_pixel(g, light, sets, params, method, k, rec))
            .collect()
    } else {
        (0..w * h).into_par_iter().map(|k| sample_pixel(g, light, sets, params, method, k, &mut [])).collect()
    };
    let occlusion: Vec<f32> = sampled.iter().map(|e| e.1 / nf).collect();
    let env: Vec<Vec3> = sampled.into_iter().map(|e| e.0 * if ssdo { d_omega } else { 1.0 }).collect();
    let indirect_raw: Vec<Vec3> = if bounce {
        let area = params.bleed * PI * params.radius * params.radius / nf;
        let d_min2 = params.radius * params.radius * 0.5;
        (0..w * h)
            .into_par_iter()
            .map(|k| {
                let Some(s) = g.first[k] else { return Vec3::ZERO };
                let mut sum = Vec3::ZERO;
                for &q in &senders[k * n..(k + 1) * n] {
                    if q == u32::MAX {
                        continue;
                    }
                    let q = q as usize;
                    let Some(sender) = g.first[q] else { continue };
                    let d = sender.position - s.position;
                    let d2 = d.length_squared();
                    if d2 <= 0.0 {
                        continue;
                    }
                    let dir = d / d2.sqrt();
                    let (cos_r, cos_s) = (s.normal.dot(dir), -sender.normal.dot(dir));
                    if cos_r <= 0.0 || cos_s <= 0.0 {
                        continue;
                    }
                    sum += (env[q] + sun[q]) * (area * cos_s * cos_r / d2.max(d_min2));
                }
                s.albedo / PI * sum
            })
            .collect()
    } else {
        vec![Vec3::ZERO; w * h]
    };
    // One blur over both sampled terms (blurred as a pair, so the weights are computed once).
    let (env, indirect) = blur_pair(g, &env, &indirect_raw, params);
    let direct = env.iter().zip(&sun).map(|(a, b)| *a + *b).collect();
    Output { width: w, height: h, direct, indirect, occlusion, covered: g.first.iter().map(Option::is_some).collect() }
}

/// Samples pixel `k`: returns (the environment term before Δω: Σ L_in V cos for SSDO,
/// ρ/π E(n) × visible share for SSAO; the number of occluded samples), recording each
/// occluded sample's pixel in `senders` (when it has room).
#[inline]
fn sample_pixel(
    g: &GBuffer,
    light: &Lighting,
    sets: &SampleSets,
    params: &Params,
    method: Method,
    k: usize,
    senders: &mut [u32],
) -> (Vec3, f32) {
    let Some(s) = g.first[k] else { return (Vec3::ZERO, 0.0) };
    let (x, y) = (k % g.width, k / g.width);
    let (mut gathered, mut visible_cos, mut all_cos, mut occluded) = (Vec3::ZERO, 0.0, 0.0, 0.0);
    for (i, (dir, point)) in sample_points(sets, x, y, s.position, s.normal, params.radius).enumerate() {
        let c = dir.dot(s.normal).max(0.0);
        all_cos += c;
        if let Some(q) = occluder(g, point, params) {
            occluded += 1.0;
            if let Some(slot) = senders.get_mut(i) {
                *slot = q as u32;
            }
            continue;
        }
        visible_cos += c;
        if method == Method::Ssdo {
            gathered += light.env.radiance(dir) * c;
        }
    }
    let env = match method {
        Method::Ssao => {
            let ao = if all_cos > 0.0 { visible_cos / all_cos } else { 1.0 };
            s.albedo / PI * light.env.irradiance(s.normal) * ao
        }
        Method::Ssdo => s.albedo / PI * gathered,
    };
    (env, occluded)
}

/// Separable geometry-aware blur: box taps weighted by depth similarity (Gaussian, σ = r_max/4)
/// and normal similarity (cos⁸); never across the background.
pub fn blur(g: &GBuffer, image: &[Vec3], params: &Params) -> Vec<Vec3> {
    blur_pair(g, image, image, params).0
}

/// [`blur`] of two images at once (same weights).
pub fn blur_pair(g: &GBuffer, a: &[Vec3], b: &[Vec3], params: &Params) -> (Vec<Vec3>, Vec<Vec3>) {
    let r = params.blur_radius as i64;
    if r == 0 {
        return (a.to_vec(), b.to_vec());
    }
    let (w, h) = (g.width as i64, g.height as i64);
    let inv_sigma = 1.0 / (0.25 * params.radius).max(1e-6);
    let pass = |src: &[(Vec3, Vec3)], dx: i64, dy: i64| -> Vec<(Vec3, Vec3)> {
        (0..w * h)
            .into_par_iter()
            .map(|k| {
                let Some(c) = g.first[k as usize] else { return (Vec3::ZERO, Vec3::ZERO) };
                let (x, y) = (k % w, k / w);
                let (mut acc_a, mut acc_b, mut wsum) = (Vec3::ZERO, Vec3::ZERO, 0.0f32);
                for i in -r..=r {
                    let (qx, qy) = (x + i * dx, y + i * dy);
                    if qx < 0 || qy < 0 || qx >= w || qy >= h {
                        continue;
                    }
                    let q = (qy * w + qx) as usize;
                    let Some(s) = g.first[q] else { continue };
                    let dd = (s.depth - c.depth) * inv_sigma;
                    let wn = c.normal.dot(s.normal).max(0.0).powi(8);
                    let wt = (-0.5 * dd * dd).exp() * wn;
                    acc_a += src[q].0 * wt;
                    acc_b += src[q].1 * wt;
                    wsum += wt;
                }
                if wsum > 0.0 { (acc_a / wsum, acc_b / wsum) } else { src[k as usize] }
            })
            .collect()
    };
    let both: Vec<(Vec3, Vec3)> = a.iter().copied().zip(b.iter().copied()).collect();
    let horizontal = pass(&both, 1, 0);
    let out = pass(&horizontal, 0, 1);
    out.into_iter().unzip()
}
