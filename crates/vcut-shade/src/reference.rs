//! The exact-direction reference: per vertex, all N leaf directions cast against the true
//! geometry of every object at its current position, no clustering and no fields:
//! B = Σ_l V(x, ω_l) max(0, n·ω_l) f_r(ω_l, ω_o) L_l, with L_l the light tree's leaf l. Against
//! it, a frame's error is the cut error alone (clustering, field interpolation, quantisation).
//! Ray origins are offset along the normal exactly as the SVCs were.
//!
//! The Monte Carlo reference integrates the environment map itself (every texel, at its exact
//! solid angle) instead of the N-direction light tree: directions are drawn in proportion to
//! texel power (luminance × solid angle; texels of maps under 2^19 texels split into patches),
//! visibility is cast against the moved geometry, and
//! each vertex draws batches until the estimate's standard error is below a target share of
//! its mean. Against it, a frame's error adds the direction discretisation to the cut error.

use crate::brdf;
use crate::frame::Frame;
use glam::Vec3;
use rayon::prelude::*;
use vcut_envmap::EnvMap;
use vcut_rays::{Occluder, origin, origin_offset};
use vcut_scene::Mesh;
use vcut_sphere::rng::SplitMix64;

/// The occluder of every object at its current translation.
fn moved_occluder(frame: &Frame) -> Occluder {
    let moved: Vec<Mesh> = (0..frame.object_count())
        .map(|o| {
            let crate::FrameObject { mesh, .. } = frame.object(o);
            Mesh::from_valid_parts(frame.object(o).positions(), mesh.normals().to_vec(), mesh.triangles().to_vec())
                .unwrap_or_else(|e| unreachable!("a translated valid mesh stays valid: {e}"))
        })
        .collect();
    Occluder::new(&moved.iter().collect::<Vec<_>>())
}

/// Outgoing radiance toward `eye` of every vertex, by casting every leaf direction.
/// `origin_offset` is the SVCs' (a fraction of each object's bounding radius).
pub fn exact_direction(frame: &Frame, eye: Vec3, origin_offset: f32) -> Vec<Vec<Vec3>> {
    let reference = ExactReference::new(frame, origin_offset);
    (0..frame.object_count())
        .map(|o| {
            let positions = frame.object(o).positions();
            (0..positions.len()).into_par_iter().map(|v| reference.vertex(frame, o, v, positions[v], eye)).collect()
        })
        .collect()
}

/// The exact-direction reference one vertex at a time (for progressive display): the moved
/// geometry is built once, then any vertex can be shaded.
pub struct ExactReference {
    occ: Occluder,
    origin_offset: f32,
}

impl ExactReference {
    /// The reference of `frame` at its current translations; `origin_offset` as the SVCs'.
    pub fn new(frame: &Frame, origin_offset: f32) -> ExactReference {
        ExactReference { occ: moved_occluder(frame), origin_offset }
    }

    /// Outgoing radiance toward `eye` of vertex `v` of object `o`, at world position `x` (its
    /// current position, as `frame.object(o).positions()[v]`).
    pub fn vertex(&self, frame: &Frame, o: usize, v: usize, x: Vec3, eye: Vec3) -> Vec3 {
        let crate::FrameObject { mesh, .. } = frame.object(o);
        let material = frame.object(o).vertex_material(v);
        let offset = origin_offset(self.origin_offset, mesh);
        let n = mesh.normals()[v];
        if !frame.object(o).seen(v, eye) {
            return Vec3::ZERO;
        }
        let leaves = frame.tree().leaf_directions();
        let light = frame.light().leaves();
        let wo = brdf::view_direction(n, x, eye);
        let origin = origin(x, n, offset);
        let mut b = Vec3::ZERO;
        for (l, &d) in leaves.iter().enumerate() {
            let c = n.dot(d);
            if c <= 0.0 || self.occ.occluded(origin, d, f32::INFINITY) {
                continue;
            }
            let li = light[l];
            b += c * brdf::eval(material, n, d, wo) * Vec3::new(li[0] as f32, li[1] as f32, li[2] as f32);
        }
        b
    }
}

/// Relative L2 error of `got` against `reference` over all vertices and channels, and the
/// largest per-vertex error relative to the reference's mean radiance.
pub fn errors(got: &[Vec<Vec3>], reference: &[Vec<Vec3>]) -> (f64, f64) {
    relative_errors(got.iter().zip(reference).flat_map(|(g, r)| g.iter().copied().zip(r.iter().copied())))
}

/// Relative L2 error over (value, reference) pairs of RGB, and the largest error relative to
/// the references' mean.
pub fn relative_errors(pairs: impl Iterator<Item = (Vec3, Vec3)>) -> (f64, f64) {
    let (mut num, mut den, mut sum, mut count, mut worst) = (0.0f64, 0.0f64, 0.0f64, 0usize, 0.0f64);
    for (a, b) in pairs {
        let d = (a - b).as_dvec3();
        num += d.length_squared();
        den += b.as_dvec3().length_squared();
        sum += b.as_dvec3().length();
        count += 1;
        worst = worst.max(d.length());
    }
    let mean = sum / count.max(1) as f64;
    ((num / den.max(1e-300)).sqrt(), worst / mean.max(1e-300))
}

/// Settings of [`monte_carlo`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MonteCarloParams {
    /// Samples per batch.
    pub batch: u32,
    /// Stop a vertex once its standard error is below this share of its mean luminance.
    pub rel_error: f64,
    /// Samples at most per vertex.
    pub max_samples: u32,
    /// Seed (each vertex draws from its own stream).
    pub seed: u64,
}

impl Default for MonteCarloParams {
    /// Batches of 256, 1 % standard error, at most 65,536 samples.
    fn default() -> Self {
        Self { batch: 256, rel_error: 0.01, max_samples: 65_536, seed: 1 }
    }
}

/// What [`monte_carlo`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MonteCarloStats {
    /// Samples drawn over all vertices.
    pub samples: u64,
    /// Vertices that stopped at `max_samples` before reaching `rel_error`.
    pub unconverged: u64,
}

fn luminance(c: [f32; 3]) -> f64 {
    f64::from(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2])
}

/// The Monte Carlo reference (see the module docs), with its sample counts.
pub fn monte_carlo(
    frame: &Frame,
    env: &EnvMap,
    eye: Vec3,
    origin_offset: f32,
    params: &MonteCarloParams,
) -> (Vec<Vec<Vec3>>, MonteCarloStats) {
    let occ = moved_occluder(frame);
    // Texels (split into sub-texel patches when the map has fewer than 2^19 texels) as
    // (direction, radiance / luminance), with a CDF over luminance × solid angle.
    let texels = env.layout().texel_count().max(1) as f64;
    let k = ((524_288.0 / texels).sqrt().ceil() as u32).max(1);
    let mut dirs = Vec::new();
    let mut cdf = Vec::new();
    let mut total = 0.0f64;
    env.for_each_patch(k, |d, omega, c| {
        let w = luminance(c) * omega;
        if w > 0.0 {
            total += w;
            dirs.push((d.normalize(), Vec3::from(c) / luminance(c) as f32));
            cdf.push(total);
        }
    });
    let results: Vec<Vec<(Vec3, u64, bool)>> = (0..frame.object_count())
        .map(|o| {
            let crate::FrameObject { mesh, .. } = frame.object(o);
            let offset = vcut_rays::origin_offset(origin_offset, mesh);
            let positions = frame.object(o).positions();
            (0..positions.len())
                .into_par_iter()
                .map(|v| {
                    let (x, n) = (positions[v], mesh.normals()[v]);
                    if !frame.object(o).seen(v, eye) {
                        return (Vec3::ZERO, 0, false);
                    }
                    let wo = brdf::view_direction(n, x, eye);
                    let material = frame.object(o).vertex_material(v);
                    let origin = vcut_rays::origin(x, n, offset);
                    let mut rng = SplitMix64::new(params.seed ^ ((o as u64) << 40) ^ v as u64);
                    let (mut sum, mut lum, mut lum2, mut count) = (glam::DVec3::ZERO, 0.0f64, 0.0f64, 0u64);
                    if cdf.is_empty() {
                        return (Vec3::ZERO, 0, false);
                    }
                    loop {
                        for _ in 0..params.batch {
                            let u = rng.next_f64() * total;
                            let i = cdf.partition_point(|&c| c <= u).min(cdf.len() - 1);
                            let (d, colour) = dirs[i];
                            let c = n.dot(d);
                            let mut e = Vec3::ZERO;
                            if c > 0.0 && !occ.occluded(origin, d, f32::INFINITY) {
                                // L Ω f cos / (lum(L) Ω / total) = (L / lum(L)) · total · f cos.
                                e = colour * (total as f32) * c * brdf::eval(material, n, d, wo);
                            }
                            let l = f64::from(0.2126 * e.x + 0.7152 * e.y + 0.0722 * e.z);
                            sum += e.as_dvec3();
                            lum += l;
                            lum2 += l * l;
                            count += 1;
                        }
                        let mean = lum / count as f64;
                        let var = (lum2 / count as f64 - mean * mean).max(0.0);
                        let se = (var / count as f64).sqrt();
                        let converged = se <= params.rel_error * mean.abs()
                            || (mean == 0.0 && count >= 4 * u64::from(params.batch));
                        if converged || count >= u64::from(params.max_samples) {
                            return ((sum / count as f64).as_vec3(), count, !converged);
                        }
                    }
                })
                .collect()
        })
        .collect();
    let mut stats = MonteCarloStats::default();
    let out = results
        .into_iter()
        .map(|obj| {
            obj.into_iter()
                .map(|(b, n, unconverged)| {
                    stats.samples += n;
                    stats.unconverged += u64::from(unconverged);
                    b
                })
                .collect()
        })
        .collect();
    (out, stats)
}
