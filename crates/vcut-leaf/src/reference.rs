//! The path-traced reference the two passes are measured against: the same BSDF (diffuse
//! reflection and gloss per side, diffuse transmission), the sun as a disk sampled at every path
//! vertex (next-event estimation with a shadow ray), the environment without its sun (full
//! resolution, bilinear) sampled both by its luminance and by the BSDF (diffuse lobes and the
//! gloss's Beckmann half vectors), combined by multiple importance sampling (balance heuristic),
//! `depth` scatterings.
//!
//! Like [`crate::shade`], each side of a vertex is shaded toward the eye, mirrored into that side's
//! hemisphere when the eye is on the other side.

use crate::material::Scatter;
use crate::scene::LeafScene;
use crate::shade::{SunLight, TwoSided};
use glam::Vec3;
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;
use vcut_sphere::rng::SplitMix64;

/// Parameters of the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceParams {
    /// Paths per vertex side.
    pub paths: u32,
    /// Scatterings after the first surface (3 = direct + up to three bounces).
    pub depth: u32,
    /// Angular diameter of the sun disk, degrees.
    pub sun_diameter_deg: f32,
    /// Seed.
    pub seed: u64,
}

impl Default for ReferenceParams {
    fn default() -> ReferenceParams {
        ReferenceParams { paths: 256, depth: 3, sun_diameter_deg: 0.53, seed: 11 }
    }
}

/// Importance sampling of the environment by luminance × solid angle over a lat-long resampling
/// (uniform in solid angle within a texel).
struct EnvSampler {
    width: usize,
    height: usize,
    cdf: Vec<f64>,
    /// Per texel, probability / solid angle (the pdf in solid angle there).
    density: Vec<f32>,
}

impl EnvSampler {
    fn new(env: &EnvMap) -> EnvSampler {
        use vcut_envmap::layout::latlong_solid_angle;
        let ll = env.to_latlong(512, 2);
        let (width, height) = (512usize, 256usize);
        let mut weight = vec![0.0f64; width * height];
        let mut omega = vec![0.0f64; width * height];
        for y in 0..height {
            for x in 0..width {
                let t = y * width + x;
                let (u0, v0) = (x as f64 / width as f64, y as f64 / height as f64);
                omega[t] = latlong_solid_angle(u0, u0 + 1.0 / width as f64, v0, v0 + 1.0 / height as f64);
                let c = ll.texels()[t];
                weight[t] = f64::from(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]).max(0.0) * omega[t];
            }
        }
        let total: f64 = weight.iter().sum();
        if total <= 0.0 {
            weight.iter_mut().zip(&omega).for_each(|(w, o)| *w = *o);
        }
        let total: f64 = weight.iter().sum();
        let mut acc = 0.0;
        let cdf = weight
            .iter()
            .map(|w| {
                acc += w / total;
                acc
            })
            .collect();
        let density = weight.iter().zip(&omega).map(|(w, o)| (w / total / o.max(1e-30)) as f32).collect();
        EnvSampler { width, height, cdf, density }
    }

    fn sample(&self, rng: &mut SplitMix64) -> (Vec3, f32) {
        use vcut_envmap::layout::latlong_dir;
        let u = rng.next_f64();
        let t = self.cdf.partition_point(|&c| c < u).min(self.cdf.len() - 1);
        let (x, y) = (t % self.width, t / self.width);
        let uu = (x as f64 + rng.next_f64()) / self.width as f64;
        let (c0, c1) = (
            (std::f64::consts::PI * y as f64 / self.height as f64).cos(),
            (std::f64::consts::PI * (y + 1) as f64 / self.height as f64).cos(),
        );
        let c = c0 + (c1 - c0) * rng.next_f64();
        let v = c.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        (latlong_dir(uu, v).normalize(), self.density[t])
    }

    fn pdf(&self, d: Vec3) -> f32 {
        let (u, v) = vcut_envmap::layout::latlong_uv(d);
        let x = ((u * self.width as f64) as usize).min(self.width - 1);
        let y = ((v * self.height as f64) as usize).min(self.height - 1);
        self.density[y * self.width + x]
    }
}

struct Tracer<'a> {
    scene: &'a LeafScene,
    env: &'a EnvMap,
    sampler: EnvSampler,
    sun: Option<SunLight>,
    sun_cos: f32,
    eps: f32,
}

/// Direction mirrored into the hemisphere of `n` when it lies outside it.
fn into_side(d: Vec3, n: Vec3) -> Vec3 {
    let c = d.dot(n);
    if c > 0.0 { d } else { (d - 2.0 * c * n).normalize_or(n) }
}

/// The BSDF's sampling at one surface point, a mixture: the gloss lobe (Beckmann half vectors)
/// with probability ½ when the outgoing side is glossy, else a cosine-weighted direction on the
/// outgoing side (½, or 1 when opaque) or through the leaf. [`BsdfSampler::pdf`] is the density
/// of [`BsdfSampler::sample`]'s directions over the whole sphere — a gloss sample that leaves
/// below the horizon (a grazing view, a tilted half vector) is a transmission direction the lobe
/// generated, and its density counts there too (it once did not: such a sample was divided by
/// the through-lobe's density alone, near the horizon many times too small, and the reference
/// came out brighter than its own BSDF).
struct BsdfSampler {
    out_side: Vec3,
    wo: Vec3,
    p_gloss: f32,
    p_same: f32,
    m: f32,
}

impl BsdfSampler {
    fn new(n: Vec3, s: &Scatter, wo: Vec3) -> BsdfSampler {
        let out_side = if n.dot(wo) >= 0.0 { n } else { -n };
        let gloss = s.gloss[usize::from(n.dot(wo) < 0.0)];
        BsdfSampler {
            out_side,
            wo,
            p_gloss: if gloss.rho_s == Vec3::ZERO { 0.0 } else { 0.5 },
            p_same: if s.translucent() { 0.5 } else { 1.0 },
            m: gloss.roughness.max(0.02),
        }
    }

    /// The density in solid angle of direction `d` (unit).
    fn pdf(&self, d: Vec3) -> f32 {
        let c = d.dot(self.out_side);
        let diffuse = (if c >= 0.0 { self.p_same } else { 1.0 - self.p_same }) * c.abs() / PI;
        let lobe = if self.p_gloss > 0.0 {
            let h = (d + self.wo).normalize_or_zero();
            let (nh, vh) = (h.dot(self.out_side), h.dot(self.wo));
            if nh > 0.0 && vh > 0.0 { crate::material::beckmann(nh, self.m) * nh / (4.0 * vh) } else { 0.0 }
        } else {
            0.0
        };
        self.p_gloss * lobe + (1.0 - self.p_gloss) * diffuse
    }

    /// A direction from three uniform numbers; `None` when the half vector drawn faces away from
    /// `wo` (no reflection: the sample adds nothing).
    fn sample(&self, [u0, u1, u2]: [f32; 3]) -> Option<Vec3> {
        if u0 < self.p_gloss {
            let m = self.m;
            let tan2 = -m * m * (1.0 - u1).max(1e-12).ln();
            let ch = 1.0 / (1.0 + tan2).sqrt();
            let sh = (1.0 - ch * ch).max(0.0).sqrt();
            let phi = 2.0 * PI * u2;
            let (a, b) = self.out_side.any_orthonormal_pair();
            let h = a * (sh * phi.cos()) + b * (sh * phi.sin()) + self.out_side * ch;
            let vh = self.wo.dot(h);
            (vh > 0.0).then(|| 2.0 * vh * h - self.wo)
        } else {
            let same = (u0 - self.p_gloss) / (1.0 - self.p_gloss) < self.p_same;
            let hemi = if same { self.out_side } else { -self.out_side };
            let (r, phi) = (u1.sqrt(), 2.0 * PI * u2);
            let (a, b) = hemi.any_orthonormal_pair();
            Some((a * (r * phi.cos()) + b * (r * phi.sin()) + hemi * (1.0 - u1).max(0.0).sqrt()).normalize())
        }
    }
}

impl Tracer<'_> {
    /// A point inside the sun's disk, uniformly over its solid angle.
    fn sun_sample(&self, sun: &SunLight, rng: &mut SplitMix64) -> Vec3 {
        let (u1, u2) = (rng.next_f64() as f32, rng.next_f64() as f32);
        let cos = 1.0 - u1 * (1.0 - self.sun_cos);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u2;
        let (a, b) = sun.dir.any_orthonormal_pair();
        (sun.dir * cos + (a * phi.cos() + b * phi.sin()) * sin).normalize()
    }

    /// Radiance leaving point `p` (normal `n`, scattering `s`) in unit direction `wo`.
    fn radiance(&self, p: Vec3, n: Vec3, s: &Scatter, wo: Vec3, depth: u32, rng: &mut SplitMix64) -> Vec3 {
        let mut out = Vec3::ZERO;
        // The sun, sampled over its disk.
        if let Some(sun) = self.sun {
            let l = self.sun_sample(&sun, rng);
            let f = s.eval(n, l, wo);
            if f != Vec3::ZERO {
                let side = if n.dot(l) >= 0.0 { n } else { -n };
                if !self.scene.occluder().occluded(p + side * self.eps, l, f32::INFINITY) {
                    out += f * n.dot(l).abs() * sun.irradiance;
                }
            }
        }
        let bsdf = BsdfSampler::new(n, s, wo);
        // The environment by its luminance (MIS weight against the BSDF's pdf).
        let (d, pdf_env) = self.sampler.sample(rng);
        let f = s.eval(n, d, wo);
        if f != Vec3::ZERO && pdf_env > 0.0 {
            let side = if n.dot(d) >= 0.0 { n } else { -n };
            if !self.scene.occluder().occluded(p + side * self.eps, d, f32::INFINITY) {
                out += f * n.dot(d).abs() * self.env.radiance(d) / (pdf_env + bsdf.pdf(d));
            }
        }
        let u = [rng.next_f64() as f32, rng.next_f64() as f32, rng.next_f64() as f32];
        let Some(d) = bsdf.sample(u) else {
            return out;
        };
        let pdf = bsdf.pdf(d);
        let f = s.eval(n, d, wo);
        if f == Vec3::ZERO || pdf <= 0.0 {
            return out;
        }
        let cos = n.dot(d).abs();
        let hemi = if n.dot(d) >= 0.0 { n } else { -n };
        let throughput = f * cos / pdf;
        let origin = p + hemi * self.eps;
        match self.scene.occluder().closest_hit(origin, d, f32::INFINITY) {
            None => out += f * cos * self.env.radiance(d) / (pdf + self.sampler.pdf(d)),
            Some((tri, dist)) if depth > 0 => {
                let q = origin + d * dist;
                let b = self.scene.barycentric(tri, q);
                let nq = self.scene.hit_normal(tri, b);
                let sq = interpolate(self.scene, tri, b);
                out += throughput * self.radiance(q, nq, &sq, -d, depth - 1, rng);
            }
            Some(_) => {}
        }
        out
    }
}

/// The scattering at a point of triangle `tri` (barycentric `b`): vertex values interpolated.
fn interpolate(scene: &LeafScene, tri: usize, b: [f32; 3]) -> Scatter {
    let t = scene.triangles()[tri].map(|i| &scene.scatter()[i as usize]);
    let mut s = *t[0];
    s.r = [0, 1].map(|k| t[0].r[k] * b[0] + t[1].r[k] * b[1] + t[2].r[k] * b[2]);
    s.t = t[0].t * b[0] + t[1].t * b[1] + t[2].t * b[2];
    for k in 0..2 {
        s.gloss[k].rho_s = t[0].gloss[k].rho_s * b[0] + t[1].gloss[k].rho_s * b[1] + t[2].gloss[k].rho_s * b[2];
        s.gloss[k].roughness =
            t[0].gloss[k].roughness * b[0] + t[1].gloss[k].roughness * b[1] + t[2].gloss[k].roughness * b[2];
    }
    s
}

/// A reference: per listed vertex, both sides' radiance, and the two independent halves of the
/// paths it averages (their difference measures the reference's own noise).
#[derive(Debug, Clone)]
pub struct Reference {
    /// Mean over all paths.
    pub radiance: Vec<TwoSided>,
    /// Means over the first and the second half of the paths.
    pub halves: [Vec<TwoSided>; 2],
}

impl Reference {
    /// The reference's own relative L2 noise: |A − B| / (2 |mean|) over the two halves (the
    /// standard deviation of the full mean, as a share of it). An error measured against it is
    /// meaningful down to about this level.
    pub fn noise(&self) -> f64 {
        rel_l2(&self.halves[0], &self.halves[1]) * 0.5 * rel_norm(&self.halves[1], &self.radiance)
    }
}

/// |a| / |b| over both sides of every vertex.
fn rel_norm(a: &[TwoSided], b: &[TwoSided]) -> f64 {
    let norm =
        |x: &[TwoSided]| x.iter().flat_map(|v| v.iter()).map(|c| f64::from(c.length_squared())).sum::<f64>().sqrt();
    norm(a) / norm(b).max(f64::MIN_POSITIVE)
}

/// The reference radiance of both sides of each of `vertices`, toward `eye`, under
/// `env_without_sun` and `sun`.
pub fn reference(
    scene: &LeafScene,
    env_without_sun: &EnvMap,
    sun: Option<SunLight>,
    eye: Vec3,
    vertices: &[usize],
    params: &ReferenceParams,
) -> Reference {
    let tracer = Tracer {
        scene,
        env: env_without_sun,
        sampler: EnvSampler::new(env_without_sun),
        sun,
        sun_cos: (params.sun_diameter_deg * 0.5).to_radians().cos(),
        eps: scene.ray_offset(),
    };
    let half = params.paths.max(2) / 2;
    let per_vertex: Vec<[TwoSided; 2]> = vertices
        .par_iter()
        .map(|&v| {
            let mut rng = SplitMix64::new(params.seed ^ (v as u64).wrapping_mul(0xA076_1D64_78BD_642F));
            let (p, n) = (scene.positions()[v], scene.normals()[v]);
            let s = &scene.scatter()[v];
            let view = (eye - p).normalize_or(n);
            let mut out = [[Vec3::ZERO; 2]; 2];
            for side in 0..2 {
                if side == 1 && !s.translucent() {
                    continue;
                }
                let ns = if side == 0 { n } else { -n };
                let wo = into_side(view, ns);
                for h in out.iter_mut() {
                    let mut sum = Vec3::ZERO;
                    for _ in 0..half {
                        sum += tracer.radiance(p, n, s, wo, params.depth, &mut rng);
                    }
                    h[side] = sum / half as f32;
                }
            }
            out
        })
        .collect();
    let halves = [0, 1].map(|h| per_vertex.iter().map(|x| x[h]).collect::<Vec<_>>());
    let radiance = per_vertex.iter().map(|x| [(x[0][0] + x[1][0]) * 0.5, (x[0][1] + x[1][1]) * 0.5]).collect();
    Reference { radiance, halves }
}

/// Relative L2 error of `got` against `reference` over the listed vertices' both sides (RGB):
/// √(Σ|a − b|² / Σ|b|²); NaN when the reference is black.
pub fn rel_l2(got: &[TwoSided], reference: &[TwoSided]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for (a, b) in got.iter().zip(reference) {
        for side in 0..2 {
            num += f64::from((a[side] - b[side]).length_squared());
            den += f64::from(b[side].length_squared());
        }
    }
    if den > 0.0 { (num / den).sqrt() } else { f64::NAN }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Gloss;

    /// A glossy translucent leaf's transmission, ∫ T/π |cos| over the far hemisphere = T, as the
    /// path tracer estimates it with its BSDF samples: exact at every view, grazing included,
    /// where the gloss lobe sends many of its samples below the horizon.
    #[test]
    fn bsdf_samples_weigh_transmission_by_their_whole_density() {
        let t = Vec3::splat(0.4);
        let s = Scatter { r: [Vec3::splat(0.1); 2], t, gloss: [Gloss { rho_s: Vec3::ONE, roughness: 0.4 }; 2] };
        let n = Vec3::Z;
        for deg in [0.0f32, 60.0, 85.0] {
            let wo = Vec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
            let bsdf = BsdfSampler::new(n, &s, wo);
            let mut rng = SplitMix64::new(7);
            let (samples, mut through, mut lobe_below) = (400_000, 0.0f64, 0);
            for _ in 0..samples {
                let u = [rng.next_f64() as f32, rng.next_f64() as f32, rng.next_f64() as f32];
                let Some(d) = bsdf.sample(u) else { continue };
                if d.z < 0.0 {
                    lobe_below += usize::from(u[0] < bsdf.p_gloss);
                    through += f64::from(s.eval(n, d, wo).x * d.z.abs() / bsdf.pdf(d));
                }
            }
            let got = through / samples as f64;
            let want = f64::from(t.x);
            assert!((got - want).abs() < 0.01 * want, "{deg}°: transmission estimated {got}, want {want}");
            if deg == 85.0 {
                // What this checks: at a grazing view the lobe's samples below the horizon are many.
                assert!(lobe_below > samples / 50, "{lobe_below} lobe samples below the horizon");
            }
        }
    }
}
