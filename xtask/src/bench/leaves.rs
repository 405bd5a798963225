//! The `leaves` section of `cargo xtask bench`: the plant-leaf renderer at 100k and 500k
//! vertices — RLE ratio, decode and shade times, errors against the path-traced reference —
//! and its precomputes' estimates.

use crate::report::{LeafGoals, LeavesSection};
use anyhow::{Context, Result};
use std::path::Path;
use std::time::Instant;
use vcut_leaf::image::render;
use vcut_leaf::lvc::{Content, Lvc, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::PrtParams;
use vcut_leaf::reference::{ReferenceParams, reference, rel_l2};
use vcut_leaf::shade::{Lighting, Shader, SunMethod, TwoSided};
use vcut_leaf::store::{Inputs, LeafEstimate, Reuse};
use vcut_shade::image::{auto_exposure, write_png};
use vcuts::leaves::{EstimateArgs, bar, camera, frame_figures, precompute, subset, to_image};

/// The `leaves` section's precomputes, estimated from samples of `seconds` each: the large
/// plant's maps (twice: as stored and cosine-baked) and transfer, the larger plant's one sun
/// direction. Returns (label, estimate) per precompute.
pub fn estimates(quick: bool, seconds: f64) -> Result<Vec<(String, LeafEstimate)>> {
    let m = LeafMaterial::default();
    let (big, huge, prt_rays) = if quick { (10_000, 50_000, 64) } else { (100_000, 500_000, 128) };
    let lvc = LvcParams::default();
    let budget = std::time::Duration::from_secs_f64(seconds);
    let scene = plant(&PlantParams::with_vertices(big), &m)?;
    let main = vcut_leaf::store::estimate(
        &Inputs { scene: &scene, lvc, prt: PrtParams { rays: prt_rays, ..PrtParams::default() }, suns: None },
        budget,
    );
    // The cosine-baked maps: the same rays again, no transfer.
    let baked = LeafEstimate { prt_rays: 0, prt_seconds: 0.0, output_bytes: 0, ..main };
    let huge_scene = plant(&PlantParams::with_vertices(huge), &m)?;
    // The built-in sky's sun, as the bench lights the plant.
    let sun_dir = vcut_envmap::procedural::PreethamSky::default().sun_dir.normalize();
    let sun = [vcut_leaf::lvc::CubeDirections { resolution: lvc.resolution }.nearest(sun_dir)];
    let one = vcut_leaf::store::estimate(
        &Inputs { scene: &huge_scene, lvc, prt: PrtParams { rays: 16, ..PrtParams::default() }, suns: Some(&sun) },
        budget,
    );
    Ok(vec![
        (format!("leaves: {} vertices, every sun direction", main.vertices), main),
        ("leaves: the same maps cosine-baked".into(), baked),
        (format!("leaves: {} vertices, one sun direction", one.vertices), one),
    ])
}

/// The `leaves` section of `cargo xtask bench`: RLE ratio, decode and shade times for a 100k-vertex
/// plant (and shade time for 500k), errors against the path-traced reference. `quick` runs a
/// smaller plant so CI stays short (the keys then say which size they measured).
pub fn run(quick: bool, out: &Path) -> Result<LeavesSection> {
    let est = EstimateArgs::default();
    println!("== leaves: LVC + PRT against the path-traced reference");
    let m = LeafMaterial::default();
    let env = vcut_envmap::procedural::PreethamSky::default().bake(512);
    let (light, rest) = Lighting::from_map(&env);
    let sun = light.sun.context("the built-in sky has a sun")?;
    let (big, huge, prt_rays, ref_vertices, ref_paths) =
        if quick { (10_000, 50_000, 64, 300, 512) } else { (100_000, 500_000, 128, 1500, 2048) };
    let lvc_params = LvcParams::default();
    // The 100k plant: everything precomputed.
    let scene = plant(&PlantParams::with_vertices(big), &m)?;
    println!("vertices={}", scene.vertex_count());
    // Timed: computed every run (Reuse::Never), and saved beside the report.
    let prt_params = PrtParams { rays: prt_rays, ..PrtParams::default() };
    let pre = precompute(&scene, (&lvc_params, &prt_params), None, &out.join("plant-100k.vleaf"), Reuse::Never, est)?
        .ready()
        .context("the bench never runs dry")?;
    let cam = camera(&scene);
    let f = frame_figures(&scene, &pre, &light, (cam.position, Shader::new().edge_rays()), 7)?;
    // The cosine-baked maps, for their ratio (the paper's byte content), on the same plant.
    let baked_ratio = {
        let t = Instant::now();
        let pb = bar(scene.vertex_count(), "LVC cos");
        let baked = Lvc::compute(&scene, &LvcParams { content: Content::CosineBaked, ..lvc_params }, |d, _| {
            pb.set_position(d as u64)
        });
        pb.finish_and_clear();
        println!("lvc_cosine_baked_s={:.1}", t.elapsed().as_secs_f64());
        baked.raw_bytes() as f64 / baked.compressed_bytes().max(1) as f64
    };
    let verts = subset(scene.vertex_count(), ref_vertices);
    let rp = ReferenceParams { paths: ref_paths, ..ReferenceParams::default() };
    let t = Instant::now();
    let reference_out = reference(&scene, &rest, Some(sun), cam.position, &verts, &rp);
    let reference_rad = &reference_out.radiance;
    let reference_s = t.elapsed().as_secs_f64();
    let mut shader = Shader::new();
    shader.prepare(&scene, &pre.data.lvc, &light)?;
    let (mut lvc_rad, mut sh_rad) = (Vec::new(), Vec::new());
    shader.shade(&scene, &pre.data, &light, SunMethod::Lvc, cam.position, &mut lvc_rad);
    shader.shade(&scene, &pre.data, &light, SunMethod::ShOnly, cam.position, &mut sh_rad);
    let pick = |r: &[TwoSided]| verts.iter().map(|&v| r[v]).collect::<Vec<_>>();
    let rel_lvc = rel_l2(&pick(&lvc_rad), reference_rad);
    let rel_sh = rel_l2(&pick(&sh_rad), reference_rad);
    let noise = reference_out.noise();
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let img = to_image(render(&scene, &lvc_rad, &cam, 960, 720, Some(&rest)));
    let exposure = auto_exposure(&img);
    write_png(&img, &out.join("leaves.png"), exposure)?;
    write_png(
        &to_image(render(&scene, &sh_rad, &cam, 960, 720, Some(&rest))),
        &out.join("leaves-sh-only.png"),
        exposure,
    )?;
    // The 500k plant: shading needs the current sun direction's map only.
    let huge_scene = plant(&PlantParams::with_vertices(huge), &m)?;
    let j = pre.data.lvc.sun_index(sun.dir);
    let huge_prt = PrtParams { rays: 16, ..PrtParams::default() };
    let huge_pre = precompute(
        &huge_scene,
        (&lvc_params, &huge_prt),
        Some(&[j]),
        &out.join("plant-500k.vleaf"),
        Reuse::Never,
        est,
    )?
    .ready()
    .context("the bench never runs dry")?;
    let fh =
        frame_figures(&huge_scene, &huge_pre, &light, (camera(&huge_scene).position, Shader::new().edge_rays()), 5)?;
    let rle_ratio = pre.data.lvc.raw_bytes() as f64 / pre.data.lvc.compressed_bytes().max(1) as f64;
    for (k, v) in [
        ("rle_ratio", rle_ratio),
        ("rle_ratio_cosine_baked", baked_ratio),
        ("decode_ms", f.decode_ms),
        ("shade_ms", f.shade_ms),
        ("shade_ms_large", fh.shade_ms),
        ("sun_change_ms", f.sun_change_ms),
        ("sun_change_ms_large", fh.sun_change_ms),
        ("rel_l2_lvc_prt", rel_lvc),
        ("rel_l2_sh_only", rel_sh),
        ("reference_noise_rel_l2", noise),
    ] {
        println!("{k}={v:.4}");
    }
    Ok(LeavesSection {
        vertices_100k: scene.vertex_count(),
        vertices_500k: huge_scene.vertex_count(),
        quick,
        rle_ratio,
        rle_ratio_cosine_baked: baked_ratio,
        lvc_raw_bytes: pre.data.lvc.raw_bytes(),
        lvc_rle_bytes: pre.data.lvc.compressed_bytes(),
        lvc_s: pre.seconds.0,
        prt_s: pre.seconds.1,
        prt_rays,
        transfer_bytes: pre.data.transfer.bytes(),
        decode_ms_100k: f.decode_ms,
        shade_ms_100k: f.shade_ms,
        shade_ms_500k: fh.shade_ms,
        sun_change_ms_100k: f.sun_change_ms,
        sun_change_ms_500k: fh.sun_change_ms,
        prt_s_500k: huge_pre.seconds.1,
        rel_l2_lvc_prt: rel_lvc,
        rel_l2_sh_only: rel_sh,
        reference_noise_rel_l2: noise,
        reference_vertices: verts.len(),
        reference_paths: ref_paths,
        reference_s,
        goals: LeafGoals::PAPER,
        images: vec![out.join("leaves.png"), out.join("leaves-sh-only.png")],
    })
}
