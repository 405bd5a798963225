//! Environment and indirect light by precomputed radiance transfer in order-5 SH.
//!
//! Per vertex and side (side 0 along the normal, side 1 against it) two transfer vectors map the
//! lighting's 25 SH coefficients to the irradiance arriving on that side:
//! - **direct**: ∫_H V(ω) cos θ Y_i(ω) dω — scalar, the unshadowed part of the distant light;
//! - **indirect**: light that reached the side after ≥ 1 scattering by other surfaces — reflected
//!   or *transmitted* through leaves — up to `bounces` scatterings, per RGB channel (leaves colour
//!   what they pass on). Computed with the materials at precompute time.
//!
//! Shading (in [`crate::shade`]) adds the environment through both and the sun through the
//! indirect one only (its direct part is the LVC pass), and applies each vertex's *current*
//! diffuse reflectance and transmittance: L_σ = R_σ/π·E_σ + T/π·E_{−σ} — so a leaf edit changes the
//! direct response exactly and the bounced light approximately (it was computed with the old
//! parameters).
//!
//! Sampling: `rays` stratified cosine-weighted directions per side, the pattern rotated per vertex
//! by a hash of its index (deterministic whatever the thread count). Rays that hit a surface are
//! kept (triangle, barycentrics, the side facing the ray) and reused by every bounce.

use crate::scene::LeafScene;
use crate::sh::{COEFFS, basis};
use glam::{Vec3, Vec3A};
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_sphere::rng::SplitMix64;

/// Parameters of the PRT precompute.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrtParams {
    /// Rays per vertex side (rounded down to a square).
    pub rays: u32,
    /// Scatterings carried by the indirect transfer (default 3, as deep as the reference's paths;
    /// a bounce reuses the hits: ~2 % of the precompute).
    pub bounces: u32,
    /// Seed of the per-vertex rotations.
    pub seed: u64,
}

impl Default for PrtParams {
    fn default() -> PrtParams {
        PrtParams { rays: 256, bounces: 3, seed: 1 }
    }
}

/// The transfer vectors of every vertex.
#[derive(Debug, Clone)]
pub struct Transfer {
    /// Per vertex and side, the direct (visibility × cosine) transfer.
    pub direct: Vec<[[f32; COEFFS]; 2]>,
    /// Per vertex and side, the indirect transfer per channel.
    pub indirect: Vec<[[Vec3; COEFFS]; 2]>,
    /// Parameters used.
    pub params: PrtParams,
    /// Rays traced.
    pub rays_traced: u64,
}

/// A ray that hit a surface: the triangle, its barycentrics (16-bit), and whether the side facing
/// the ray is side 1 (top bit of `tri`).
#[derive(Debug, Clone, Copy)]
struct Hit {
    tri: u32,
    b1: u16,
    b2: u16,
}

impl Hit {
    fn side(&self) -> usize {
        (self.tri >> 31) as usize
    }
    fn tri(&self) -> usize {
        (self.tri & 0x7fff_ffff) as usize
    }
    fn weights(&self) -> [f32; 3] {
        let (b1, b2) = (f32::from(self.b1) / 65535.0, f32::from(self.b2) / 65535.0);
        [(1.0 - b1 - b2).max(0.0), b1, b2]
    }
}

/// A vertex's direct transfer per side and the hits each side's rays made.
type Traced = ([[f32; COEFFS]; 2], [Vec<Hit>; 2]);

/// Cosine-weighted stratified directions around +Z, `k × k` strata.
fn cosine_pattern(k: u32) -> Vec<Vec3> {
    let mut out = Vec::with_capacity((k * k) as usize);
    for i in 0..k {
        for j in 0..k {
            let (u1, u2) = ((i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32);
            let r = u1.sqrt();
            let phi = 2.0 * PI * u2;
            out.push(Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt()));
        }
    }
    out
}

/// A per-vertex rotation of the pattern: a random frame around the side's normal.
fn frame(n: Vec3, seed: u64, v: usize, side: usize) -> (Vec3, Vec3, Vec3) {
    let mut rng = SplitMix64::new(seed ^ (v as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (side as u64) << 63);
    let phi = rng.next_f64() as f32 * 2.0 * PI;
    let (a, b) = n.any_orthonormal_pair();
    let t = a * phi.cos() + b * phi.sin();
    (t, n.cross(t), n)
}

/// The stratified pattern and its weight (π over its size) for `params.rays`.
fn pattern_of(params: &PrtParams) -> (Vec<Vec3>, f32) {
    let k = (params.rays.max(1) as f32).sqrt().floor().max(1.0) as u32;
    let pattern = cosine_pattern(k);
    let weight = PI / pattern.len() as f32;
    (pattern, weight)
}

/// Pass 0 for vertex `v`: its direct transfer per side and the hits its rays made.
fn trace(scene: &LeafScene, params: &PrtParams, (pattern, weight): (&[Vec3], f32), v: usize) -> Traced {
    let (occ, eps) = (scene.occluder(), scene.ray_offset());
    let (p, nrm) = (scene.positions()[v], scene.normals()[v]);
    let s = scene.scatter()[v];
    let mut direct = [[0.0f32; COEFFS]; 2];
    let mut hits: [Vec<Hit>; 2] = [Vec::new(), Vec::new()];
    for side in 0..2 {
        // Opaque surfaces receive light on their outer side only.
        if side == 1 && !s.translucent() {
            continue;
        }
        let ns = if side == 0 { nrm } else { -nrm };
        let (t, b, z) = frame(ns, params.seed, v, side);
        for &l in pattern {
            let d = (t * l.x + b * l.y + z * l.z).normalize();
            match occ.closest_hit(p + ns * eps, d, f32::INFINITY) {
                None => {
                    for (acc, y) in direct[side].iter_mut().zip(basis(d)) {
                        *acc += weight * y;
                    }
                }
                Some((tri, dist)) => {
                    let q = p + ns * eps + d * dist;
                    let [_, b1, b2] = scene.barycentric(tri, q);
                    let nq = scene.hit_normal(tri, [1.0 - b1 - b2, b1, b2]);
                    let back = u32::from(nq.dot(d) > 0.0);
                    hits[side].push(Hit {
                        tri: tri as u32 | back << 31,
                        b1: (b1 * 65535.0).round() as u16,
                        b2: (b2 * 65535.0).round() as u16,
                    });
                }
            }
        }
    }
    (direct, hits)
}

/// One bounce at a vertex whose rays made `hits`: what the previous order's transfer at the hit
/// points sends back. What leaves a hit point's facing side is (R_side + G_side)/π·E_side +
/// T/π·E_other, G the side's gloss as it reflects light from everywhere
/// ([`crate::shade::gloss_reflectance`]): without it a glossy plant's bounced light was a quarter
/// short of the path tracer's (`cargo run -p vcuts --example gloss_gather`).
fn bounce(
    scene: &LeafScene,
    reflect: &[[Vec3; 2]],
    weight: f32,
    hits: &[Vec<Hit>; 2],
    previous: &[[[Vec3; COEFFS]; 2]],
) -> [[Vec3; COEFFS]; 2] {
    let (tris, scatter) = (scene.triangles(), scene.scatter());
    let mut out = [[Vec3A::ZERO; COEFFS]; 2];
    for side in 0..2 {
        for h in &hits[side] {
            let w = h.weights();
            let t = tris[h.tri()];
            let facing = h.side();
            for (c, &vi) in t.iter().enumerate() {
                let vi = vi as usize;
                let s = &scatter[vi];
                let rf = Vec3A::from(reflect[vi][facing] * (w[c] * weight / PI));
                let tf = Vec3A::from(s.t * (w[c] * weight / PI));
                let (pf, po) = (&previous[vi][facing], &previous[vi][1 - facing]);
                for i in 0..COEFFS {
                    out[side][i] += rf * Vec3A::from(pf[i]) + tf * Vec3A::from(po[i]);
                }
            }
        }
    }
    out.map(|s| s.map(Vec3::from))
}

/// Per vertex and side, what it reflects of light from everywhere: the diffuse R and the gloss's
/// share ([`crate::shade::gloss_reflectance`]).
fn reflectance(scene: &LeafScene) -> Vec<[Vec3; 2]> {
    scene.scatter().iter().map(|s| [0, 1].map(|k| s.r[k] + crate::shade::gloss_reflectance(&s.gloss[k]))).collect()
}

/// What [`Transfer::sample`] measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PrtSample {
    /// Vertices sampled.
    pub vertices: usize,
    /// Wall seconds of their ray pass (on all cores).
    pub trace_seconds: f64,
    /// Wall seconds of one bounce over them.
    pub bounce_seconds: f64,
    /// Rays they traced.
    pub rays: u64,
    /// Of which hit a surface (kept for the bounces, 8 bytes each).
    pub hits: u64,
}

impl Transfer {
    /// Ray-traces every vertex's transfer; `progress(done, total)` as vertices finish the trace.
    pub fn compute(scene: &LeafScene, params: &PrtParams, progress: impl Fn(usize, usize) + Sync) -> Transfer {
        let (pattern, weight) = pattern_of(params);
        let n = scene.vertex_count();
        let done = std::sync::atomic::AtomicUsize::new(0);
        // Pass 0: direct transfer, and the hits every bounce reuses.
        let traced: Vec<Traced> = (0..n)
            .into_par_iter()
            .map(|v| {
                let out = trace(scene, params, (&pattern, weight), v);
                let d = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                if d.is_multiple_of(4096) || d == n {
                    progress(d, n);
                }
                out
            })
            .collect();
        let rays_traced =
            (0..n).map(|v| if scene.scatter()[v].translucent() { 2 } else { 1 }).sum::<u64>() * pattern.len() as u64;
        let direct: Vec<[[f32; COEFFS]; 2]> = traced.iter().map(|(d, _)| *d).collect();
        let mut previous: Vec<[[Vec3; COEFFS]; 2]> =
            direct.iter().map(|d| [d[0].map(Vec3::splat), d[1].map(Vec3::splat)]).collect();
        let mut indirect = vec![[[Vec3::ZERO; COEFFS]; 2]; n];
        let reflect = reflectance(scene);
        for _ in 0..params.bounces {
            let next: Vec<[[Vec3; COEFFS]; 2]> =
                traced.par_iter().map(|(_, hits)| bounce(scene, &reflect, weight, hits, &previous)).collect();
            for (acc, x) in indirect.iter_mut().zip(&next) {
                for side in 0..2 {
                    for i in 0..COEFFS {
                        acc[side][i] += x[side][i];
                    }
                }
            }
            previous = next;
        }
        Transfer { direct, indirect, params: *params, rays_traced }
    }

    /// Times [`Transfer::compute`]'s work on `vertices` only — their ray pass, and one bounce
    /// over their hits — for an estimate of the whole.
    pub fn sample(scene: &LeafScene, params: &PrtParams, vertices: &[usize]) -> PrtSample {
        let (pattern, weight) = pattern_of(params);
        let t = std::time::Instant::now();
        let traced: Vec<Traced> = vertices.par_iter().map(|&v| trace(scene, params, (&pattern, weight), v)).collect();
        let trace_seconds = t.elapsed().as_secs_f64();
        let previous = vec![[[Vec3::ZERO; COEFFS]; 2]; scene.vertex_count()];
        let t = std::time::Instant::now();
        let reflect = reflectance(scene);
        let bounced: Vec<_> =
            traced.par_iter().map(|(_, hits)| bounce(scene, &reflect, weight, hits, &previous)).collect();
        std::hint::black_box(bounced);
        let bounce_seconds = t.elapsed().as_secs_f64();
        let sides: u64 = vertices.iter().map(|&v| if scene.scatter()[v].translucent() { 2 } else { 1 }).sum();
        PrtSample {
            vertices: vertices.len(),
            trace_seconds,
            bounce_seconds,
            rays: sides * pattern.len() as u64,
            hits: traced.iter().map(|(_, h)| (h[0].len() + h[1].len()) as u64).sum(),
        }
    }

    /// Bytes the transfer vectors take (f32).
    pub fn bytes(&self) -> usize {
        self.direct.len() * (2 * COEFFS * 4 + 2 * COEFFS * 12)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{LeafObject, Surface};
    use crate::sh::{dot_each, dot_rgb, project_env};
    use vcut_envmap::EnvMap;
    use vcut_scene::{Mesh, MeshOptions};

    fn quad(y: f32, size: f32) -> Mesh {
        let h = size / 2.0;
        let pos = vec![Vec3::new(-h, y, -h), Vec3::new(h, y, -h), Vec3::new(h, y, h), Vec3::new(-h, y, h)];
        Mesh::build(pos, None, vec![[0, 2, 1], [0, 3, 2]], MeshOptions::default()).unwrap().0
    }

    #[test]
    fn an_open_leaf_sees_the_whole_sky_on_both_sides_and_nothing_bounces() {
        let leaf =
            LeafObject { name: "leaf".into(), mesh: quad(0.0, 1.0), uv: None, surface: Surface::Leaf(Box::default()) };
        let scene = LeafScene::new(vec![leaf]).unwrap();
        let t = Transfer::compute(&scene, &PrtParams { rays: 400, ..PrtParams::default() }, |_, _| {});
        let sky = project_env(&EnvMap::constant([1.0; 3]));
        for v in 0..scene.vertex_count() {
            for side in 0..2 {
                // Irradiance from a unit constant sky on an open side: π.
                let e = dot_rgb(&t.direct[v][side], &sky);
                assert!((e.x - PI).abs() < 0.02 * PI, "vertex {v} side {side}: {e}");
                assert!(t.indirect[v][side].iter().all(|c| *c == Vec3::ZERO));
            }
        }
    }

    #[test]
    fn a_glossy_leaf_passes_on_what_its_gloss_reflects() {
        // A leaf lying on an opaque ground (its underside sees nothing), a small ceiling facing
        // down at it: the ceiling's first bounce is the leaf's upper side reflecting the sky,
        // (R + G)/π·E with the gloss and R/π·E without it.
        let ceiling = {
            let pos = vec![
                Vec3::new(-0.1, 0.3, -0.1),
                Vec3::new(0.1, 0.3, -0.1),
                Vec3::new(0.1, 0.3, 0.1),
                Vec3::new(-0.1, 0.3, 0.1),
            ];
            let mesh = Mesh::build(pos, None, vec![[0, 1, 2], [0, 2, 3]], MeshOptions::default()).unwrap().0;
            LeafObject { name: "ceiling".into(), mesh, uv: None, surface: Surface::Opaque(Vec3::splat(0.5)) }
        };
        let built = |gloss: bool| {
            let mut m = crate::material::LeafMaterial::default();
            if !gloss {
                m.gloss = [crate::material::Gloss::NONE; 2];
            }
            let leaf =
                LeafObject { name: "leaf".into(), mesh: quad(0.0, 4.0), uv: None, surface: Surface::Leaf(Box::new(m)) };
            let ground = LeafObject {
                name: "ground".into(),
                mesh: quad(-0.05, 8.0),
                uv: None,
                surface: Surface::Opaque(Vec3::splat(0.5)),
            };
            let scene = LeafScene::new(vec![leaf, ground, ceiling.clone()]).unwrap();
            let t = Transfer::compute(&scene, &PrtParams { rays: 400, bounces: 1, seed: 5 }, |_, _| {});
            (scene, t)
        };
        let ((glossy, a), (matte, b)) = (built(true), built(false));
        let sky = project_env(&EnvMap::constant([1.0; 3]));
        let c = glossy.vertex_range(2).start;
        let (with, without) = (dot_each(&a.indirect[c][0], &sky), dot_each(&b.indirect[c][0], &sky));
        let s = glossy.scatter()[0];
        let g = crate::shade::gloss_reflectance(&s.gloss[0]);
        assert!(g.min_element() > 0.01, "the default leaf's top is glossy: {g}");
        assert_eq!(matte.scatter()[0].r, s.r);
        let want = (s.r[0] + g) / s.r[0];
        let got = with / without;
        assert!((got - want).abs().max_element() < 0.03 * want.max_element(), "{got} against {want}");
    }

    #[test]
    fn light_reaches_under_a_leaf_through_it_and_only_coloured() {
        // A ground under a leaf: below the leaf, the ground's direct transfer lacks the blocked
        // sky, and its indirect transfer holds what came through the leaf (green, as the leaf).
        let leaf =
            LeafObject { name: "leaf".into(), mesh: quad(0.2, 4.0), uv: None, surface: Surface::Leaf(Box::default()) };
        let ground = LeafObject {
            name: "ground".into(),
            mesh: quad(0.0, 0.5),
            uv: None,
            surface: Surface::Opaque(Vec3::splat(0.5)),
        };
        let scene = LeafScene::new(vec![leaf, ground]).unwrap();
        let t = Transfer::compute(&scene, &PrtParams { rays: 400, bounces: 2, seed: 3 }, |_, _| {});
        let sky = project_env(&EnvMap::constant([1.0; 3]));
        let g = scene.vertex_range(1).start;
        let direct = dot_rgb(&t.direct[g][0], &sky);
        let indirect = dot_each(&t.indirect[g][0], &sky);
        assert!(direct.x < 0.3 * PI, "the leaf blocks most of the sky: {direct}");
        // Through the leaf: T/π·π (its lower side sees the sky's π through it) ≈ T at ~0.16 green.
        assert!(indirect.y > 0.1 && indirect.y > 2.0 * indirect.x && indirect.y > 3.0 * indirect.z, "{indirect}");
        // The ground stays black from below (opaque: one side).
        assert!(t.direct[g][1].iter().all(|&c| c == 0.0));
    }
}
