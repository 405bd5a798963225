//! Where the leaves' gloss error is: the environment's unscattered light (no sun, no bounces) at
//! a subset of the plant's vertices, the frame against a Monte Carlo truth of the gloss alone.
//!
//! `cargo run --release -p vcuts --example gloss_sources -- [PLANT OPTIONS of vcuts leaves]
//! [--reference-vertices N] [--samples S] [--reference-paths P]` prints `key=value` lines:
//! - `gloss_rel_l2_lobe_table`: the frame's gloss (the frame minus the same frame with every
//!   leaf matte) against the truth — ∫ f·cos·V·L over the BRDF's own lobe, `S` Beckmann samples
//!   per vertex side with a shadow ray each — with the lobe's visibility from the LVC-derived
//!   table (`vcut_leaf::lobe`, what a frame uses);
//! - `gloss_rel_l2_lobe_sh`: the same with the order-5 SH visibility (no table);
//! - `env_direct_rel_l2_lobe_table`, `env_direct_rel_l2_lobe_sh`: the whole unscattered
//!   environment part (diffuse + transmission + gloss) against the path tracer at depth 0;
//!   `env_direct_rel_l2_true_gloss`: the matte frame plus the Monte Carlo gloss — what a
//!   perfect gloss would leave (the diffuse part's own error and the reference's noise);
//! - `shade_ms_lobe_table`, `shade_ms_lobe_sh`: a whole frame (sun and sky, every vertex) with
//!   each, medians of 9 alternated frames — the table's cost against the SH's in one run.

#[path = "shared/gloss.rs"]
mod gloss;

use anyhow::Result;
use clap::Parser;
use glam::Vec3;
use gloss::{Measured, Plant, Reads, gather, load, rel};
use rayon::prelude::*;
use vcut_leaf::reference::{ReferenceParams, reference};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod};

#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    measured: Measured,
    /// Beckmann samples per vertex side of the gloss truth.
    #[arg(long, default_value_t = 1024)]
    samples: u32,
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    let Plant { scene, light, rest, data, eye, verts } = load(&cli.measured)?;
    anyhow::ensure!(data.lobe.is_some(), "the leaf data has no lobe table (its maps lack directions)");
    // The environment's unscattered light only.
    let mut direct = data.clone();
    for t in &mut direct.transfer.indirect {
        *t = [[Vec3::ZERO; 25]; 2];
    }
    let env_only = Lighting { sun: None, sun_sh: [Vec3::ZERO; 25], ..light.clone() };
    let matte = vcut_leaf::breakdown::matte(&scene);
    let frame = |s: &LeafScene, d: &LeafData| -> Vec<Vec3> {
        let mut out = Vec::new();
        Shader::new().shade(s, d, &env_only, SunMethod::Lvc, eye, &mut out);
        verts.iter().flat_map(|&v| out[v]).collect()
    };
    let without_table = LeafData { lobe: None, ..direct.clone() };
    let matte_frame = frame(&matte, &direct);
    let (with_table, with_sh) = (frame(&scene, &direct), frame(&scene, &without_table));
    let gloss = |f: &[Vec3]| -> Vec<Vec3> { f.iter().zip(&matte_frame).map(|(a, b)| *a - *b).collect() };
    let truth: Vec<Vec3> = verts
        .par_iter()
        .flat_map_iter(|&v| (0..2).map(move |side| (v, side)))
        .map(|vs| gather(&scene, &rest, vs, eye, cli.samples, Reads::Constant(Vec3::ZERO, None)))
        .collect();
    let seen: Vec<Vec3> = truth;
    println!("vertices={}", verts.len());
    println!("gloss_rel_l2_lobe_table={:.4}", rel(&gloss(&with_table), &seen));
    println!("gloss_rel_l2_lobe_sh={:.4}", rel(&gloss(&with_sh), &seen));
    // What the table costs a frame: the whole lighting, both ways, alternated.
    let mut shader = Shader::new();
    shader.prepare(&scene, &data.lvc, &light)?;
    let sh_only = LeafData { lobe: None, ..data.clone() };
    let (mut table_ms, mut sh_ms, mut out) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..9 {
        for (data, times) in [(&data, &mut table_ms), (&sh_only, &mut sh_ms)] {
            let t = std::time::Instant::now();
            shader.shade(&scene, data, &light, SunMethod::Lvc, eye, &mut out);
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    println!("shade_ms_lobe_table={:.3}", vcut_shade::measure::median(table_ms));
    println!("shade_ms_lobe_sh={:.3}", vcut_shade::measure::median(sh_ms));
    let rp = ReferenceParams { paths: cli.measured.reference_paths, depth: 0, ..ReferenceParams::default() };
    let want: Vec<Vec3> = reference(&scene, &rest, None, eye, &verts, &rp).radiance.into_iter().flatten().collect();
    println!("env_direct_rel_l2_lobe_table={:.4}", rel(&with_table, &want));
    println!("env_direct_rel_l2_lobe_sh={:.4}", rel(&with_sh, &want));
    let perfect: Vec<Vec3> = matte_frame.iter().zip(&seen).map(|(a, b)| *a + *b).collect();
    println!("env_direct_rel_l2_true_gloss={:.4}", rel(&perfect, &want));
    Ok(())
}
