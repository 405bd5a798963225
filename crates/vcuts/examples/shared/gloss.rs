//! What `gloss_sources` and `gloss_gather` share (included by both with `#[path]`): their
//! plant options and the plant they load, a relative error, and a gloss lobe sampled with rays.

#![allow(dead_code)] // each example uses part of it

use anyhow::{Context, Result};
use glam::Vec3;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;
use vcut_leaf::material::{Gloss, beckmann};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod};
use vcut_sphere::rng::SplitMix64;
use vcuts::leaves::{PlantArgs, camera, data_path, lighting, material, params, precompute, scene, subset};

/// The plant, its light and the vertices measured.
#[derive(clap::Args)]
pub struct Measured {
    #[command(flatten)]
    pub plant: PlantArgs,
    /// Environment (its sun split off as the disk light).
    #[arg(long, default_value = "builtin:sky")]
    pub env: String,
    /// Vertices measured (evenly spread over the plant).
    #[arg(long, default_value_t = 1500)]
    pub reference_vertices: usize,
    /// Paths per vertex side of the path-traced reference.
    #[arg(long, default_value_t = 2048)]
    pub reference_paths: u32,
}

/// What [`load`] makes of [`Measured`].
pub struct Plant {
    pub scene: LeafScene,
    pub light: Lighting,
    /// The environment without its sun.
    pub rest: EnvMap,
    pub data: LeafData,
    pub eye: Vec3,
    pub verts: Vec<usize>,
}

/// The plant's scene and light, its leaf data (loaded or computed), the camera's eye and the
/// measured vertices.
pub fn load(m: &Measured) -> Result<Plant> {
    let p = &m.plant;
    let scene = scene(p, &material(p)?)?;
    let (light, rest) = lighting(p, &m.env)?;
    let (lvc, prt) = params(p);
    let inputs = vcut_leaf::store::Inputs { scene: &scene, lvc, prt, suns: None };
    let reuse = vcut_leaf::store::Reuse::IfMatching;
    let pre = precompute(&scene, (&lvc, &prt), None, &data_path(p, &inputs), reuse, p.estimate)?
        .ready()
        .context("the leaf data was not computed")?;
    let eye = camera(&scene).position;
    let verts = subset(scene.vertex_count(), m.reference_vertices);
    Ok(Plant { scene, light, rest, data: pre.data, eye, verts })
}

/// Relative L2 of `a` against `b`.
pub fn rel(a: &[Vec3], b: &[Vec3]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| f64::from((*x - *y).length_squared())).sum();
    let r: f64 = b.iter().map(|y| f64::from(y.length_squared())).sum();
    (d / r.max(f64::MIN_POSITIVE)).sqrt()
}

/// Every vertex's two sides shaded as `vcuts leaves` shades them: the sun map prepared with
/// `edge_rays` rays at its edges, the sun by the LVC maps.
pub fn shade_frame(
    scene: &LeafScene,
    light: &Lighting,
    data: &LeafData,
    edge_rays: u32,
    eye: Vec3,
) -> Result<Vec<[Vec3; 2]>> {
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(scene, &data.lvc, light)?;
    let mut out = Vec::new();
    shader.shade(scene, data, light, SunMethod::Lvc, eye, &mut out);
    Ok(out)
}

/// Summed radiance of `a` over `b`'s (below 1: too dark).
pub fn ratio(a: &[Vec3], b: &[Vec3]) -> f64 {
    let sum = |x: &[Vec3]| x.iter().map(|c| f64::from(c.x + c.y + c.z)).sum::<f64>();
    sum(a) / sum(b).max(f64::MIN_POSITIVE)
}

/// What a lobe sample reads.
#[derive(Clone, Copy)]
pub enum Reads<'a> {
    /// Open: the map; blocked: the hit's facing side, interpolated from these vertex values.
    Gather(&'a [[Vec3; 2]]),
    /// Open: the map, or (`true`) its order-5 SH `sh`; blocked: a constant per vertex side.
    Constant(Vec3, Option<&'a [Vec3; 25]>),
}

/// The gloss of side `side` of vertex `v` by `samples` Beckmann samples of its lobe.
pub fn gather(
    scene: &LeafScene,
    env: &EnvMap,
    (v, side): (usize, usize),
    eye: Vec3,
    samples: u32,
    reads: Reads<'_>,
) -> Vec3 {
    let g: Gloss = scene.scatter()[v].gloss[side];
    if g.rho_s == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let (p, n) = (scene.positions()[v], scene.normals()[v]);
    let ns = if side == 0 { n } else { -n };
    let view = (eye - p).normalize_or_zero();
    let vs = if ns.dot(view) > 0.0 { view } else { (view - 2.0 * ns.dot(view) * ns).normalize_or(ns) };
    let origin = p + ns * scene.ray_offset();
    let m = g.roughness.max(0.02);
    let (t1, t2) = ns.any_orthonormal_pair();
    let mut rng = SplitMix64::new((v as u64) << 1 | side as u64);
    let mut sum = Vec3::ZERO;
    for _ in 0..samples {
        let (u1, u2) = (rng.next_f64() as f32, rng.next_f64() as f32);
        let ch = 1.0 / (1.0 - m * m * (1.0 - u1).ln()).sqrt();
        let sh = (1.0 - ch * ch).max(0.0).sqrt();
        let h = (t1 * (sh * (2.0 * PI * u2).cos()) + t2 * (sh * (2.0 * PI * u2).sin()) + ns * ch).normalize();
        let vh = vs.dot(h);
        let l = 2.0 * vh * h - vs;
        if vh <= 0.0 || ns.dot(l) <= 1e-6 {
            continue;
        }
        let w = g.eval(ns, l, vs) * ns.dot(l) / (beckmann(ch, m) * ch / (4.0 * vh));
        let seen = match (scene.occluder().closest_hit(origin, l, f32::INFINITY), reads) {
            (None, Reads::Constant(_, Some(sky))) => {
                let y = vcut_leaf::sh::basis(l);
                (0..25).map(|i| sky[i] * y[i]).sum::<Vec3>().max(Vec3::ZERO)
            }
            (None, _) => env.radiance(l),
            (Some(_), Reads::Constant(c, _)) => c,
            (Some((tri, dist)), Reads::Gather(rad)) => {
                let b = scene.barycentric(tri, origin + l * dist);
                let facing = usize::from(scene.hit_normal(tri, b).dot(l) > 0.0);
                let t = scene.triangles()[tri];
                (0..3).map(|c| rad[t[c] as usize][facing] * b[c].max(0.0)).sum()
            }
        };
        sum += w * seen;
    }
    sum / samples as f32
}
