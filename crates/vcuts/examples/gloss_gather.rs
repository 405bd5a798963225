//! Where the leaves' whole error is, against the path tracer with all the light: how dark or
//! bright each light path comes out, and what the frame would err with its gloss replaced by
//! Monte Carlo gathers over each lobe.
//!
//! `cargo run --release -p vcuts --example gloss_gather -- [PLANT OPTIONS of vcuts leaves]
//! [--reference-vertices N] [--samples S] [--reference-paths P] [--parts]` prints `key=value`
//! lines:
//! - `whole_rel_l2_frame` (the frame as `vcuts leaves` measures it) and `whole_ratio_frame` (its
//!   summed radiance over the reference's: below 1, too dark);
//! - `whole_rel_l2_gather_frame`: the matte frame, the sun's direct gloss as the frame has it,
//!   and each lobe sampled (`S` Beckmann samples per vertex side): an open sample reads the sky
//!   map, a blocked one the frame's radiance at the hit (its facing side, interpolated) — what a
//!   gather of the lobe's occluders could reach; `_gather_matte` reads the matte frame there;
//! - `whole_rel_l2_mean_bounce`: blocked samples read the frame's own model of them (the side's
//!   bounced irradiance over π(1 − open)): the lobe's visibility and sky exact, its occluders'
//!   radiance the mean; `_mean_bounce_sh_sky`: the same with open samples reading the sky's
//!   order-5 SH; `_gather_black`: blocked samples read nothing (how much they weigh);
//! - each of those `_true_sun_direct` too: the sun's unscattered part replaced by the path
//!   tracer's (depth 0), what a perfect sun map would give;
//! - with `--parts`, per light path (`sun_direct`, `sun`, `env_direct`, `env_direct_matte`,
//!   `env`, `env_matte`, against references of 512 paths): `ratio_PART` and `rel_l2_PART`.

#[path = "shared/gloss.rs"]
mod gloss;

use anyhow::Result;
use clap::Parser;
use glam::Vec3;
use gloss::{Measured, Plant, Reads, gather, load, ratio, rel, shade_frame};
use rayon::prelude::*;
use std::f32::consts::PI;
use vcut_envmap::EnvMap;
use vcut_leaf::reference::{ReferenceParams, reference};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting};

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    measured: Measured,
    /// Beckmann samples per vertex side of each gather.
    #[arg(long, default_value_t = 256)]
    samples: u32,
    /// Also each light path's ratio and error.
    #[arg(long)]
    parts: bool,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    let Plant { scene, light, rest, data, eye, verts } = load(&cli.measured)?;
    let data = &data;
    let matte = vcut_leaf::breakdown::matte(&scene);
    let edge_rays = cli.measured.plant.sun_edge_rays;
    let frame = |s: &LeafScene, l: &Lighting, d: &LeafData| shade_frame(s, l, d, edge_rays, eye);
    let pick = |f: &[[Vec3; 2]]| -> Vec<Vec3> { verts.iter().flat_map(|&v| f[v]).collect() };
    let traced = |s: &LeafScene, env: &EnvMap, sun, depth, paths| -> Vec<Vec3> {
        let rp = ReferenceParams { paths, depth, ..ReferenceParams::default() };
        reference(s, env, sun, eye, &verts, &rp).radiance.into_iter().flatten().collect()
    };
    let (whole, whole_matte) = (frame(&scene, &light, data)?, frame(&matte, &light, data)?);
    let mut direct = data.clone();
    for t in &mut direct.transfer.indirect {
        *t = [[Vec3::ZERO; 25]; 2];
    }
    let sun_only = Lighting { env: [Vec3::ZERO; 25], ..light.clone() };
    let env_only = Lighting { sun: None, sun_sh: [Vec3::ZERO; 25], ..light.clone() };
    let black = EnvMap::constant([0.0; 3]);
    let default_depth = ReferenceParams::default().depth;
    let want = traced(&scene, &rest, light.sun, default_depth, cli.measured.reference_paths);
    println!("vertices={}", verts.len());
    println!("whole_rel_l2_frame={:.4}", rel(&pick(&whole), &want));
    println!("whole_ratio_frame={:.4}", ratio(&pick(&whole), &want));
    if cli.parts {
        let parts = [
            ("sun_direct", frame(&scene, &sun_only, &direct)?, traced(&scene, &black, light.sun, 0, 512)),
            ("sun", frame(&scene, &sun_only, data)?, traced(&scene, &black, light.sun, default_depth, 512)),
            ("env_direct", frame(&scene, &env_only, &direct)?, traced(&scene, &rest, None, 0, 512)),
            ("env_direct_matte", frame(&matte, &env_only, &direct)?, traced(&matte, &rest, None, 0, 512)),
            ("env", frame(&scene, &env_only, data)?, traced(&scene, &rest, None, default_depth, 512)),
            ("env_matte", frame(&matte, &env_only, data)?, traced(&matte, &rest, None, default_depth, 512)),
        ];
        for (name, got, want) in parts {
            let got = pick(&got);
            println!("ratio_{name}={:.4}", ratio(&got, &want));
            println!("rel_l2_{name}={:.4}", rel(&got, &want));
        }
    }
    // The sun's direct gloss as the frame has it (the sun alone, no bounces, glossy less matte),
    // and the sun's unscattered part as the path tracer has it.
    let (sun_gloss, sun_matte) = (frame(&scene, &sun_only, &direct)?, frame(&matte, &sun_only, &direct)?);
    let sun_true = traced(&scene, &black, light.sun, 0, cli.measured.reference_paths);
    let true_sun = |got: &[Vec3]| -> Vec<Vec3> {
        got.iter().zip(pick(&sun_gloss)).zip(&sun_true).map(|((g, f), t)| *g - f + *t).collect()
    };
    let sides: Vec<(usize, usize)> = verts.iter().flat_map(|&v| (0..2).map(move |s| (v, s))).collect();
    let base: Vec<Vec3> = sides.iter().map(|&(v, s)| whole_matte[v][s] + sun_gloss[v][s] - sun_matte[v][s]).collect();
    // The frame's model of a blocked lobe: the side's bounced irradiance over the occluded part
    // of the cosine-weighted hemisphere.
    let mean_bounce = |v: usize, s: usize| -> Vec3 {
        let open = data.transfer.direct[v][s][0] * (4.0 * PI).sqrt() / PI;
        let e_ind: Vec3 = (0..25).map(|i| (light.env[i] + light.sun_sh[i]) * data.transfer.indirect[v][s][i]).sum();
        e_ind.max(Vec3::ZERO) / (PI * (1.0 - open.clamp(0.0, 1.0)).max(0.05))
    };
    let modes = ["gather_frame", "gather_matte", "mean_bounce", "mean_bounce_sh_sky", "gather_black"];
    for name in modes {
        let gloss: Vec<Vec3> = sides
            .par_iter()
            .map(|&(v, s)| {
                let reads = match name {
                    "gather_frame" => Reads::Gather(&whole),
                    "gather_matte" => Reads::Gather(&whole_matte),
                    "mean_bounce" => Reads::Constant(mean_bounce(v, s), None),
                    "mean_bounce_sh_sky" => Reads::Constant(mean_bounce(v, s), Some(&light.env)),
                    _ => Reads::Constant(Vec3::ZERO, None),
                };
                gather(&scene, &rest, (v, s), eye, cli.samples, reads)
            })
            .collect();
        let got: Vec<Vec3> = base.iter().zip(&gloss).map(|(a, b)| *a + *b).collect();
        println!("whole_rel_l2_{name}={:.4}", rel(&got, &want));
        println!("whole_rel_l2_{name}_true_sun_direct={:.4}", rel(&true_sun(&got), &want));
    }
    println!("whole_rel_l2_true_sun_direct={:.4}", rel(&true_sun(&pick(&whole)), &want));
    Ok(())
}
