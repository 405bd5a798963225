//! The screen-space methods (`vcut-ssdo`) on a frame's geometry: `render --mode ssao|ssdo|
//! ssdo-peeled`, and the `ssdo` section of `bench`.

use glam::Vec3;
use std::time::Instant;

use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_shade::Frame;
use vcut_shade::image::Image;
use vcut_ssdo::{GBuffer, Lighting, Method, Object, Output, Params, SampleSets, render};

/// The screen-space variants `render --mode` and `bench` know.
pub const MODES: [&str; 3] = ["ssao", "ssdo", "ssdo-peeled"];

/// Every object of `frame` at its current translation, with its diffuse albedo.
pub fn objects(frame: &Frame) -> Vec<Object> {
    (0..frame.object_count())
        .map(|o| {
            let vcut_shade::FrameObject { mesh, material, translation, .. } = frame.object(o);
            Object::from_mesh(mesh, translation, Vec3::from(material.kd))
        })
        .collect()
}

/// Default parameters for `objects` (r_max a tenth of the scene's bounding radius).
pub fn params(objects: &[Object]) -> Params {
    let b = vcut_scene::Bounds::of_points(objects.iter().flat_map(|o| o.positions.iter().copied()));
    Params::for_scene(b.radius)
}

/// One screen-space frame and what each step cost.
pub struct ScreenFrame {
    /// The image's terms.
    pub output: Output,
    /// The G-buffer it was computed from.
    pub gbuffer: GBuffer,
    /// Milliseconds: G-buffer, then the method's passes (samples, blur, bounce).
    pub gbuffer_ms: f64,
    /// Milliseconds of the passes.
    pub pass_ms: f64,
}

/// Renders `mode` (one of [`MODES`]) of `objects` lit by `light`.
pub fn frame(
    objects: &[Object],
    light: &Lighting,
    camera: &Camera,
    (width, height): (u32, u32),
    mode: &str,
) -> anyhow::Result<ScreenFrame> {
    let mut p = params(objects);
    let method = match mode {
        "ssao" => Method::Ssao,
        "ssdo" => Method::Ssdo,
        "ssdo-peeled" => {
            p.peel = true;
            Method::Ssdo
        }
        _ => anyhow::bail!("--mode {mode}: expected cuts, {}", MODES.join(", ")),
    };
    let t = Instant::now();
    let gbuffer = GBuffer::new(objects, camera, width as usize, height as usize);
    let gbuffer_ms = t.elapsed().as_secs_f64() * 1e3;
    let sets = SampleSets::halton(p.samples, p.sets);
    let t = Instant::now();
    let output = render(&gbuffer, light, &sets, &p, method);
    let pass_ms = t.elapsed().as_secs_f64() * 1e3;
    Ok(ScreenFrame { output, gbuffer, gbuffer_ms, pass_ms })
}

/// The lighting of `objects` by `env` at the default sample count.
pub fn lighting(env: &EnvMap, objects: &[Object]) -> Lighting {
    Lighting::new(env, objects, params(objects).samples)
}

/// An output's total as an image.
pub fn image(o: &Output) -> Image {
    Image { width: o.width as u32, height: o.height as u32, rgb: o.total(), covered: o.covered.clone() }
}

/// The `ssdo` section of `bench`: per scene, SSAO / SSDO / peeled SSDO timed at
/// `timing` resolution (median of `runs`) and measured at `eval` resolution against the
/// ray-traced reference (`pixel_rays` per pixel).
pub fn bench(
    scenes: &[String],
    timing: (u32, u32),
    eval: (u32, u32),
    pixel_rays: usize,
    runs: usize,
) -> anyhow::Result<serde_json::Value> {
    use serde_json::json;
    let mut out = serde_json::Map::new();
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
        // Screen space is diffuse only: an object with no diffuse albedo (a glTF material
        // read as fully metallic, as the plant's textured one is) gets grey 0.5, and says so.
        let mut grey = Vec::new();
        let objects: Vec<Object> = scene
            .objects
            .iter()
            .map(|o| {
                let kd = Vec3::from(o.material.kd);
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
            crate::render::auto_camera(vcut_scene::Bounds::of_points(
                objects.iter().flat_map(|o| o.positions.iter().copied()),
            ))
        });
        let light = lighting(&scene.environment, &objects);
        let mut entry = serde_json::Map::new();
        let mut ms = std::collections::BTreeMap::new();
        for mode in MODES {
            let times: Vec<f64> = (0..runs.max(1))
                .map(|_| frame(&objects, &light, &camera, timing, mode).map(|f| f.pass_ms))
                .collect::<anyhow::Result<_>>()?;
            ms.insert(mode, crate::bench::median(times));
        }
        match gpu_times(&objects, &light, &camera, timing, runs) {
            Ok(gpu) => {
                for (k, v) in gpu {
                    entry.insert(k, json!(v));
                }
            }
            Err(e) => println!("ssdo {name}: GPU passes SKIPPED ({e})"),
        }
        let small = frame(&objects, &light, &camera, eval, "ssao")?;
        let t = Instant::now();
        let params = vcut_ssdo::ReferenceParams { pixel_rays, vertex_rays: pixel_rays };
        let reference = vcut_ssdo::reference(&objects, &small.gbuffer, &light, &params).total();
        let reference_s = t.elapsed().as_secs_f64();
        for mode in MODES {
            let f = frame(&objects, &light, &camera, eval, mode)?;
            let e = vcut_ssdo::rel_l2(&f.output.total(), &reference, &f.output.covered);
            entry.insert(format!("rel_l2_{}", mode.replace('-', "_")), json!(e));
        }
        entry.insert("ms_ssao_cpu".into(), json!(ms["ssao"]));
        entry.insert("ms_ssdo_cpu".into(), json!(ms["ssdo"]));
        entry.insert("ms_ssdo_peeled_cpu".into(), json!(ms["ssdo-peeled"]));
        entry.insert("cost_ratio_vs_ssao_cpu".into(), json!(ms["ssdo"] / ms["ssao"]));
        entry.insert("reference_s".into(), json!(reference_s));
        entry.insert("vertices".into(), json!(objects.iter().map(|o| o.positions.len()).sum::<usize>()));
        if !grey.is_empty() {
            entry.insert("grey_albedo_objects".into(), json!(grey));
        }
        println!("ssdo {name}: {}", serde_json::Value::Object(entry.clone()));
        out.insert(name.clone(), serde_json::Value::Object(entry));
    }
    let p = Params::for_scene(1.0);
    let mut section = json!({
        "device": "ms_*: the WGSL passes on the first wgpu adapter (see gpu_adapter); ms_*_cpu: vcut-ssdo on the CPU",
        "cpu_threads": rayon::current_num_threads(),
        "timing_resolution": [timing.0, timing.1],
        "eval_resolution": [eval.0, eval.1],
        "samples": p.samples,
        "sets": p.sets,
        "radius": "0.1 x scene radius",
        "reference": format!("ray traced: direct (sun shadow ray + {pixel_rays} cosine rays) + one diffuse bounce"),
        "scenes": out,
    });
    // The keys at the top: the first scene measured (the teapot when it ran).
    if let Some(first) = section["scenes"].as_object().and_then(|m| m.get("teapot").or(m.values().next())).cloned() {
        for k in ["ms_ssao", "ms_ssdo", "cost_ratio_vs_ssao", "rel_l2_ssao", "rel_l2_ssdo", "rel_l2_ssdo_peeled"] {
            section[k] = first[k].clone();
        }
    }
    Ok(section)
}

/// The WGSL passes (`vcut_view::ssdo`) timed per mode at `size`: a whole frame (G-buffer,
/// shadow map, sampling, bounce, blur, composite) submitted and waited for, median of `runs`
/// after one warm-up. Keys `ms_ssao`, `ms_ssdo`, `ms_ssdo_peeled`, `cost_ratio_vs_ssao`,
/// `gpu_adapter`.
fn gpu_times(
    objects: &[Object],
    light: &Lighting,
    camera: &Camera,
    size: (u32, u32),
    runs: usize,
) -> anyhow::Result<Vec<(String, serde_json::Value)>> {
    let gpu = vcut_view::Gpu::headless()?;
    let passes = vcut_view::ssdo::GpuSsdo::new(&gpu)?;
    let mut out = vec![("gpu_adapter".to_string(), serde_json::json!(gpu.describe()))];
    // The three modes' frames timed in turn within each run, so a change of load on this shared
    // machine hits all of them alike; medians over the runs.
    let mut frames = Vec::new();
    for mode in MODES {
        let mut p = params(objects);
        p.peel = mode == "ssdo-peeled";
        let method = if mode == "ssao" { Method::Ssao } else { Method::Ssdo };
        let f = passes.frame(&gpu, objects, light, camera, &p, method, size)?;
        f.run(&gpu)?;
        frames.push((mode, f, Vec::new()));
    }
    for _ in 0..runs.max(1) {
        for (_, f, times) in &mut frames {
            let t = Instant::now();
            f.run(&gpu)?;
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    // Where the time goes: every pass submitted and waited for alone, medians over the runs.
    for (mode, f, _) in &frames {
        let mut per_pass: Vec<(&str, Vec<f64>)> = Vec::new();
        for _ in 0..runs.max(1) {
            for (k, (label, t)) in f.run_passes(&gpu)?.into_iter().enumerate() {
                if per_pass.len() <= k {
                    per_pass.push((label, Vec::new()));
                }
                per_pass[k].1.push(t);
            }
        }
        let passes: serde_json::Map<String, serde_json::Value> = per_pass
            .into_iter()
            .map(|(label, times)| (label.to_string(), serde_json::json!(crate::bench::median(times))))
            .collect();
        println!("  {mode} passes (ms): {}", serde_json::Value::Object(passes.clone()));
        out.push((format!("passes_ms_{}", mode.replace('-', "_")), serde_json::Value::Object(passes)));
    }
    let ms: std::collections::BTreeMap<&str, f64> =
        frames.into_iter().map(|(mode, _, times)| (mode, crate::bench::median(times))).collect();
    out.push(("ms_ssao".into(), serde_json::json!(ms["ssao"])));
    out.push(("ms_ssdo".into(), serde_json::json!(ms["ssdo"])));
    out.push(("ms_ssdo_peeled".into(), serde_json::json!(ms["ssdo-peeled"])));
    out.push(("cost_ratio_vs_ssao".into(), serde_json::json!(ms["ssdo"] / ms["ssao"])));
    Ok(out)
}
