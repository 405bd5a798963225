//! The `ssdo` section of `cargo xtask bench`: SSAO, SSDO and peeled SSDO on the CPU
//! (`vcut-ssdo`) and as WGSL passes (`vcut-view`), timed and measured against the ray-traced
//! reference.

use crate::report::{SsdoGpu, SsdoScene, SsdoSection};
use glam::Vec3;
use std::collections::BTreeMap;
use std::time::Instant;
use vcut_scene::Camera;
use vcut_shade::measure::median;
use vcut_ssdo::{Lighting, Method, Object, Params};
use vcuts::ssdo::{ScreenMode, frame, lighting, params};

/// The `ssdo` section of `bench`: per scene, SSAO / SSDO / peeled SSDO timed at
/// `timing` resolution (median of `runs`) and measured at `eval` resolution against the
/// ray-traced reference (`pixel_rays` per pixel).
pub fn run(
    scenes: &[String],
    timing: (u32, u32),
    eval: (u32, u32),
    pixel_rays: usize,
    runs: usize,
) -> anyhow::Result<SsdoSection> {
    let mut out = BTreeMap::new();
    for name in scenes {
        let spec = match name.as_str() {
            "plant" => {
                match vcut_scene::assets::locate("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf") {
                    Ok(p) => p.display().to_string(),
                    Err(e) => {
                        println!("ssdo {name}: SKIPPED ({e})");
                        continue;
                    }
                }
            }
            other => format!("builtin:{other}"),
        };
        let scene = match vcut_scene::Scene::open(&spec) {
            Ok(s) => s,
            Err(e) => {
                println!("ssdo {name}: SKIPPED ({e})");
                continue;
            }
        };
        // Screen space is diffuse only, one albedo per object (its textures' mean over its
        // vertices): an object with none (a metal) gets grey 0.5, and says so.
        let mut grey = Vec::new();
        let objects: Vec<Object> = scene
            .objects
            .iter()
            .map(|o| {
                let kd = o.textures.mean_albedo(&o.material, o.mesh.uvs());
                let albedo = if kd.max_element() < 0.01 {
                    grey.push(o.name.clone());
                    Vec3::splat(0.5)
                } else {
                    kd
                };
                Object::from_mesh(&o.mesh, Vec3::ZERO, albedo)
            })
            .collect();
        let camera = scene.cameras.first().cloned().unwrap_or_else(|| {
            vcuts::render::auto_camera(vcut_scene::Bounds::of_points(
                objects.iter().flat_map(|o| o.positions.iter().copied()),
            ))
        });
        let light = lighting(&scene.environment, &objects);
        let mut ms = BTreeMap::new();
        for mode in ScreenMode::ALL {
            let times: Vec<f64> =
                (0..runs.max(1)).map(|_| frame(&objects, &light, &camera, timing, mode).pass_ms).collect();
            ms.insert(mode.name(), median(times));
        }
        let gpu = gpu_times(&objects, &light, &camera, timing, runs)
            .inspect_err(|e| println!("ssdo {name}: GPU passes SKIPPED ({e})"))
            .ok();
        let small = frame(&objects, &light, &camera, eval, ScreenMode::Ssao);
        let t = Instant::now();
        let params = vcut_ssdo::ReferenceParams { pixel_rays, vertex_rays: pixel_rays };
        let reference = vcut_ssdo::reference(&objects, &small.gbuffer, &light, &params).total();
        let reference_s = t.elapsed().as_secs_f64();
        let rel_l2 = |mode| {
            let f = frame(&objects, &light, &camera, eval, mode);
            vcut_ssdo::rel_l2(&f.output.total(), &reference, &f.output.covered)
        };
        let entry = SsdoScene {
            gpu,
            rel_l2_ssao: rel_l2(ScreenMode::Ssao),
            rel_l2_ssdo: rel_l2(ScreenMode::Ssdo),
            rel_l2_ssdo_peeled: rel_l2(ScreenMode::SsdoPeeled),
            ms_ssao_cpu: ms["ssao"],
            ms_ssdo_cpu: ms["ssdo"],
            ms_ssdo_peeled_cpu: ms["ssdo-peeled"],
            cost_ratio_vs_ssao_cpu: ms["ssdo"] / ms["ssao"],
            reference_s,
            vertices: objects.iter().map(|o| o.positions.len()).sum(),
            grey_albedo_objects: grey,
        };
        println!("ssdo {name}: {}", serde_json::to_string(&entry)?);
        out.insert(name.clone(), entry);
    }
    let p = Params::for_scene(1.0);
    // The keys at the top: the first scene measured (the teapot when it ran).
    let first = out.get("teapot").or(out.values().next()).cloned();
    let gpu = first.as_ref().and_then(|f| f.gpu.as_ref());
    let section = SsdoSection {
        device: "ms_*: the WGSL passes on the first wgpu adapter (see gpu_adapter); ms_*_cpu: vcut-ssdo on the CPU"
            .into(),
        cpu_threads: rayon::current_num_threads(),
        timing_resolution: [timing.0, timing.1],
        eval_resolution: [eval.0, eval.1],
        samples: p.samples,
        sets: p.sets,
        radius: "0.1 x scene radius".into(),
        reference: format!("ray traced: direct (sun shadow ray + {pixel_rays} cosine rays) + one diffuse bounce"),
        ms_ssao: gpu.map(|g| g.ms_ssao),
        ms_ssdo: gpu.map(|g| g.ms_ssdo),
        cost_ratio_vs_ssao: gpu.map(|g| g.cost_ratio_vs_ssao),
        rel_l2_ssao: first.as_ref().map(|f| f.rel_l2_ssao),
        rel_l2_ssdo: first.as_ref().map(|f| f.rel_l2_ssdo),
        rel_l2_ssdo_peeled: first.as_ref().map(|f| f.rel_l2_ssdo_peeled),
        scenes: out,
    };
    Ok(section)
}

/// The WGSL passes (`vcut_ssdo::gpu`) timed per mode at `size` by
/// `vcut_ssdo::gpu_timing::time_frames`: a whole frame (G-buffer, shadow map, sampling, bounce,
/// blur, composite), and each pass alone.
fn gpu_times(
    objects: &[Object],
    light: &Lighting,
    camera: &Camera,
    size: (u32, u32),
    runs: usize,
) -> anyhow::Result<SsdoGpu> {
    let gpu = vcut_view::Gpu::headless()?;
    let passes = vcut_view::ssdo::GpuSsdo::new(&gpu)?;
    let mut frames = Vec::new();
    for mode in ScreenMode::ALL {
        let mut p = params(objects);
        p.peel = mode == ScreenMode::SsdoPeeled;
        let method = if mode == ScreenMode::Ssao { Method::Ssao } else { Method::Ssdo };
        frames.push((mode.name(), passes.frame(&gpu, objects, light, camera, &p, method, size)?));
    }
    let named: Vec<_> = frames.iter().map(|(name, f)| (*name, f)).collect();
    let mut t = vcut_ssdo::gpu_timing::time_frames(&gpu, &named, runs)?;
    for (mode, timing) in &t {
        println!("  {mode} passes (ms): {}", serde_json::to_string(&timing.passes_ms)?);
    }
    let mut take = |mode: &str| t.remove(mode).unwrap_or_default();
    let (ssao, ssdo, peeled) = (take("ssao"), take("ssdo"), take("ssdo-peeled"));
    Ok(SsdoGpu {
        gpu_adapter: gpu.describe(),
        cost_ratio_vs_ssao: ssdo.frame_ms / ssao.frame_ms,
        ms_ssao: ssao.frame_ms,
        ms_ssdo: ssdo.frame_ms,
        ms_ssdo_peeled: peeled.frame_ms,
        passes_ms_ssao: ssao.passes_ms,
        passes_ms_ssdo: ssdo.passes_ms,
        passes_ms_ssdo_peeled: peeled.passes_ms,
    })
}
