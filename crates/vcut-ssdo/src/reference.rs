//! The ray-traced reference SSAO and SSDO are measured against: at every pixel's surface,
//! diffuse direct light with visibility (the sun by a shadow ray, the rest of the environment
//! by cosine-weighted rays) plus one indirect diffuse bounce (rays that hit a front face take
//! that surface's direct radiance, interpolated from its vertices, where it was computed the
//! same way).

use crate::gbuffer::{GBuffer, Object};
use crate::samples::basis;
use crate::ssdo::{Lighting, Output};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_rays::Occluder;
use vcut_scene::Mesh;
use vcut_sphere::rng::SplitMix64;

/// Rays of the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceParams {
    /// Cosine-weighted rays per pixel (stratified; rounded to a square).
    pub pixel_rays: usize,
    /// Cosine-weighted rays per vertex for the surfaces' direct light.
    pub vertex_rays: usize,
}

impl Default for ReferenceParams {
    fn default() -> Self {
        ReferenceParams { pixel_rays: 256, vertex_rays: 256 }
    }
}

/// `k` stratified cosine-weighted directions around `n` (k rounded down to a square).
fn cosine_directions(n: Vec3, k: usize, rng: &mut SplitMix64) -> impl Iterator<Item = Vec3> + '_ {
    let m = (k as f64).sqrt().floor().max(1.0) as usize;
    let (t, b) = basis(n);
    (0..m * m).map(move |i| {
        let u = ((i % m) as f64 + rng.next_f64()) / m as f64;
        let v = ((i / m) as f64 + rng.next_f64()) / m as f64;
        let r = u.sqrt() as f32;
        let phi = (2.0 * std::f64::consts::PI * v) as f32;
        let (s, c) = phi.sin_cos();
        (t * (r * c) + b * (r * s) + n * (1.0 - u as f32).max(0.0).sqrt()).normalize_or(n)
    })
}

/// The reference image of `g` (whose geometry is `objects`) under `light`.
pub fn reference(objects: &[Object], g: &GBuffer, light: &Lighting, params: &ReferenceParams) -> Output {
    let meshes: Vec<Mesh> = objects
        .iter()
        .filter_map(|o| Mesh::from_valid_parts(o.positions.clone(), o.normals.clone(), o.triangles.clone()).ok())
        .collect();
    let occ = Occluder::new(&meshes.iter().collect::<Vec<_>>());
    let bounds = vcut_scene::Bounds::of_points(objects.iter().flat_map(|o| o.positions.iter().copied()));
    let eps = 1e-4 * bounds.radius.max(1e-6);
    // Triangle index → (object, triangle).
    let mut starts = vec![0usize];
    for o in objects {
        starts.push(starts.last().copied().unwrap_or(0) + o.triangles.len());
    }
    let direct_at = |p: Vec3, n: Vec3, albedo: Vec3, rays: usize, rng: &mut SplitMix64| -> Vec3 {
        let mut e = Vec3::ZERO;
        if let Some(sun) = light.sun {
            let c = n.dot(sun.dir);
            if c > 0.0 && !occ.occluded(p + n * eps, sun.dir, f32::INFINITY) {
                e += sun.irradiance * c;
            }
        }
        let dirs: Vec<Vec3> = cosine_directions(n, rays, rng).collect();
        let k = dirs.len() as f32;
        for d in dirs {
            if !occ.occluded(p + n * eps, d, f32::INFINITY) {
                e += light.residual.radiance(d) * (PI / k);
            }
        }
        albedo / PI * e
    };
    // The surfaces' direct radiance at their vertices.
    let vertex_direct: Vec<Vec<Vec3>> = objects
        .iter()
        .enumerate()
        .map(|(oi, o)| {
            (0..o.positions.len())
                .into_par_iter()
                .map(|v| {
                    let mut rng = SplitMix64::new(((oi as u64) << 40) ^ v as u64 ^ 0x5eed);
                    direct_at(o.positions[v], o.normals[v], o.albedo, params.vertex_rays, &mut rng)
                })
                .collect()
        })
        .collect();
    let (w, h) = (g.width, g.height);
    let pixels: Vec<(Vec3, Vec3)> = (0..w * h)
        .into_par_iter()
        .map(|k| {
            let Some(s) = g.first[k] else { return (Vec3::ZERO, Vec3::ZERO) };
            let mut rng = SplitMix64::new(k as u64 ^ 0xabcdef);
            let origin = s.position + s.normal * eps;
            let mut sun = Vec3::ZERO;
            if let Some(l) = light.sun {
                let c = s.normal.dot(l.dir);
                if c > 0.0 && !occ.occluded(origin, l.dir, f32::INFINITY) {
                    sun = s.albedo / PI * l.irradiance * c;
                }
            }
            let dirs: Vec<Vec3> = cosine_directions(s.normal, params.pixel_rays, &mut rng).collect();
            let kf = dirs.len() as f32;
            let (mut env, mut bounce) = (Vec3::ZERO, Vec3::ZERO);
            for d in dirs {
                match occ.closest_hit(origin, d, f32::INFINITY) {
                    None => env += light.residual.radiance(d),
                    Some((tri, t)) => {
                        let o = starts.partition_point(|&st| st <= tri) - 1;
                        let obj = &objects[o];
                        let [a, b, c] = obj.triangles[tri - starts[o]].map(|i| i as usize);
                        let hit = origin + d * t;
                        let (pa, pb, pc) = (obj.positions[a], obj.positions[b], obj.positions[c]);
                        let bary = barycentric(hit, pa, pb, pc);
                        let normal = (obj.normals[a] * bary.x + obj.normals[b] * bary.y + obj.normals[c] * bary.z)
                            .normalize_or_zero();
                        if normal.dot(d) < 0.0 {
                            let vd = &vertex_direct[o];
                            bounce += vd[a] * bary.x + vd[b] * bary.y + vd[c] * bary.z;
                        }
                    }
                }
            }
            // Cosine-weighted: ρ/π · π/K · Σ L.
            (sun + s.albedo * env / kf, s.albedo * bounce / kf)
        })
        .collect();
    Output {
        width: w,
        height: h,
        direct: pixels.iter().map(|p| p.0).collect(),
        indirect: pixels.iter().map(|p| p.1).collect(),
        occlusion: vec![0.0; w * h],
        covered: g.first.iter().map(Option::is_some).collect(),
    }
}

/// Barycentric coordinates of `p` (on the triangle's plane) in triangle `a b c`.
fn barycentric(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (v0, v1, v2) = (b - a, c - a, p - a);
    let (d00, d01, d11, d20, d21) = (v0.dot(v0), v0.dot(v1), v1.dot(v1), v2.dot(v0), v2.dot(v1));
    let den = d00 * d11 - d01 * d01;
    if den.abs() < 1e-20 {
        return Vec3::new(1.0, 0.0, 0.0);
    }
    let v = (d11 * d20 - d01 * d21) / den;
    let w = (d00 * d21 - d01 * d20) / den;
    Vec3::new(1.0 - v - w, v, w).clamp(Vec3::ZERO, Vec3::ONE)
}

/// Relative L2 error of `got` against `reference` over the pixels covered in both (NaN when
/// the reference is black there: no relative error exists).
pub fn rel_l2(got: &[Vec3], reference: &[Vec3], covered: &[bool]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for ((g, r), &c) in got.iter().zip(reference).zip(covered) {
        if c {
            num += f64::from((*g - *r).length_squared());
            den += f64::from(r.length_squared());
        }
    }
    if den > 0.0 { (num / den).sqrt() } else { f64::NAN }
}
