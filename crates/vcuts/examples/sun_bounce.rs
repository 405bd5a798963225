//! What the leaves would err with the sun's first bounce gathered from the frame's own sun map
//! instead of passed through order-5 SH: at each measured vertex side, cosine-weighted rays read
//! what the surfaces they hit send on of the sun's direct light (their map bytes, interpolated).
//!
//! `cargo run --release -p vcuts --example sun_bounce -- [PLANT OPTIONS of vcuts leaves]
//! [--rays N]` prints `key=value` lines: `whole_rel_l2_frame`, `whole_rel_l2_gathered` (the
//! sun's first bounce gathered with N rays, its second and third through SH), their ratios, and
//! the same for the sun alone (`sun_rel_l2_*`, against a 512-path reference).

#[path = "shared/gloss.rs"]
mod gloss;

use anyhow::{Context, Result};
use clap::Parser;
use glam::Vec3;
use gloss::{Measured, Plant, load, ratio, rel, shade_frame};
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;
use vcut_leaf::lvc::Content;
use vcut_leaf::prt::{PrtParams, Transfer};
use vcut_leaf::reference::{ReferenceParams, reference};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting, Shader};
use vcut_sphere::rng::SplitMix64;

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    measured: Measured,
    /// Rays per vertex side of the gather.
    #[arg(long, default_value_t = 1024)]
    rays: u32,
}

/// Per vertex and side, the radiance it sends on of the sun's direct light (diffusely, its
/// gloss as in the PRT's bounces).
fn emission(scene: &LeafScene, map: &[u8], content: Content, light: &Lighting) -> Vec<[Vec3; 2]> {
    let Some(sun) = light.sun else { return vec![[Vec3::ZERO; 2]; scene.vertex_count()] };
    (0..scene.vertex_count())
        .map(|v| {
            let s = &scene.scatter()[v];
            let cos = scene.normals()[v].dot(sun.dir);
            let q = f32::from(map[v]) / 255.0;
            let vis = match content {
                Content::Visibility => q * cos.abs(),
                Content::CosineBaked => q,
            };
            let e = sun.irradiance * vis;
            let lit = usize::from(cos < 0.0);
            let mut out = [Vec3::ZERO; 2];
            out[lit] = (s.r[lit] + vcut_leaf::shade::gloss_reflectance(&s.gloss[lit])) / PI * e;
            out[1 - lit] = s.t / PI * e;
            out
        })
        .collect()
}

/// The irradiance arriving at side `side` of `v` from what the hit surfaces send on.
fn gathered(scene: &LeafScene, emit: &[[Vec3; 2]], (v, side): (usize, usize), rays: u32) -> Vec3 {
    let n = scene.normals()[v];
    let ns = if side == 0 { n } else { -n };
    let origin = scene.positions()[v] + ns * scene.ray_offset();
    let (t1, t2) = ns.any_orthonormal_pair();
    let k = (rays as f32).sqrt().max(1.0) as u32;
    let mut rng = SplitMix64::new((v as u64) << 1 | side as u64);
    let mut sum = Vec3::ZERO;
    for i in 0..k {
        for j in 0..k {
            let u1 = (i as f32 + rng.next_f64() as f32) / k as f32;
            let u2 = (j as f32 + rng.next_f64() as f32) / k as f32;
            let r = u1.sqrt();
            let phi = 2.0 * PI * u2;
            let d = (t1 * (r * phi.cos()) + t2 * (r * phi.sin()) + ns * (1.0 - u1).max(0.0).sqrt()).normalize();
            if let Some((tri, dist)) = scene.occluder().closest_hit(origin, d, f32::INFINITY) {
                let b = scene.barycentric(tri, origin + d * dist);
                let facing = usize::from(scene.hit_normal(tri, b).dot(d) > 0.0);
                let t = scene.triangles()[tri];
                sum += (0..3).map(|c| emit[t[c] as usize][facing] * b[c].max(0.0)).sum::<Vec3>();
            }
        }
    }
    sum * (PI / (k * k) as f32)
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    let Plant { scene, light, rest, data, eye, verts } = load(&cli.measured)?;
    let edge_rays = cli.measured.plant.sun_edge_rays;
    let frame = |l: &Lighting, d: &LeafData| shade_frame(&scene, l, d, edge_rays, eye);
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(&scene, &data.lvc, &light)?;
    let map = shader.sun_map().context("no sun map")?.to_vec();
    let emit = emission(&scene, &map, data.lvc.params().content, &light);
    let first = Transfer::compute(&scene, &PrtParams { bounces: 1, ..data.transfer.params }, |_, _| {});
    let sides: Vec<(usize, usize)> = verts
        .iter()
        .flat_map(|&v| (0..2).map(move |s| (v, s)))
        .filter(|&(v, s)| s == 0 || scene.scatter()[v].translucent())
        .collect();
    let gathered: Vec<Vec3> = sides.par_iter().map(|&vs| gathered(&scene, &emit, vs, cli.rays)).collect();
    // The first bounce through SH replaced by the gathered one, on the DC coefficient.
    let replaced = |through: &[Vec3; 25]| -> LeafData {
        let mut d = data.clone();
        for (&(v, s), g) in sides.iter().zip(&gathered) {
            let sh: Vec3 = (0..25).map(|i| light.sun_sh[i] * first.indirect[v][s][i]).sum();
            let dc = through[0];
            let fix = (*g - sh) / Vec3::select(dc.cmpgt(Vec3::ZERO), dc, Vec3::ONE);
            d.transfer.indirect[v][s][0] += fix;
        }
        d
    };
    let through: [Vec3; 25] = std::array::from_fn(|i| light.env[i] + light.sun_sh[i]);
    let sun_only = Lighting { env: [Vec3::ZERO; 25], ..light.clone() };
    let pick = |f: &[[Vec3; 2]]| -> Vec<Vec3> { verts.iter().flat_map(|&v| f[v]).collect() };
    let traced = |env: &EnvMap, paths| -> Vec<Vec3> {
        let rp = ReferenceParams { paths, ..ReferenceParams::default() };
        reference(&scene, env, light.sun, eye, &verts, &rp).radiance.into_iter().flatten().collect()
    };
    let want = traced(&rest, cli.measured.reference_paths);
    let (f0, f1) = (pick(&frame(&light, &data)?), pick(&frame(&light, &replaced(&through))?));
    println!("vertices={}", verts.len());
    println!("whole_rel_l2_frame={:.4}", rel(&f0, &want));
    println!("whole_ratio_frame={:.4}", ratio(&f0, &want));
    println!("whole_rel_l2_gathered={:.4}", rel(&f1, &want));
    println!("whole_ratio_gathered={:.4}", ratio(&f1, &want));
    let want = traced(&EnvMap::constant([0.0; 3]), 512);
    let (s0, s1) = (pick(&frame(&sun_only, &data)?), pick(&frame(&sun_only, &replaced(&sun_only.sun_sh))?));
    println!("sun_rel_l2_frame={:.4}", rel(&s0, &want));
    println!("sun_ratio_frame={:.4}", ratio(&s0, &want));
    println!("sun_rel_l2_gathered={:.4}", rel(&s1, &want));
    println!("sun_ratio_gathered={:.4}", ratio(&s1, &want));
    Ok(())
}
