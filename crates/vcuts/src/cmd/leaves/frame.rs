//! A plant's frame measured: its per-frame costs (decoding a sun direction's map, a sun move,
//! shading) and its levels of detail (per level, and from farther away the automatic choice
//! against the full meshes); images as the leaf renderer draws them.

use super::data::Precomputed;
use anyhow::{Context, Result};
use glam::Vec3;
use serde::ser::SerializeMap;
use serde::{Serialize, Serializer};
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_leaf::image::render_triangles;
use vcut_leaf::lod::{Lod, LodParams};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod, TwoSided};
use vcut_scene::Camera;
use vcut_scene::raster::Target;
use vcut_shade::image::{Image, pixel_errors};
use vcut_shade::measure::median;

/// Per-frame costs.
#[derive(Debug, Clone, Serialize)]
pub struct FrameFigures {
    /// Median time to decode one sun direction's map.
    pub decode_ms: f64,
    /// Median time to shade every vertex (both passes, both sides).
    pub shade_ms: f64,
    /// Median time of a sun move's preparation: the maps around the sun decoded and blended
    /// ([`Shader::prepare`]).
    pub sun_change_ms: f64,
}

/// Medians over `runs` frames seen from `eye`: decoding the map of the lighting's sun, making the
/// sun's map (its neighbours blended, `edge_rays` rays per shadow-edge vertex), and shading.
pub fn frame_figures(
    scene: &LeafScene,
    pre: &Precomputed,
    light: &Lighting,
    (eye, edge_rays): (Vec3, u32),
    runs: usize,
) -> Result<FrameFigures> {
    let mut decode = Vec::new();
    let sun = light.sun.context("no sun")?;
    let mut buf = vec![0u8; scene.vertex_count()];
    let j = pre.data.lvc.sun_index(sun.dir);
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        pre.data.lvc.decode(j, &mut buf)?;
        decode.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut change = Vec::new();
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        Shader::with_edge_rays(edge_rays).prepare(scene, &pre.data.lvc, light)?;
        change.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(scene, &pre.data.lvc, light)?;
    let mut out = Vec::new();
    let mut shade = Vec::new();
    for _ in 0..runs.max(1) + 1 {
        let t = Instant::now();
        shader.shade(scene, &pre.data, light, SunMethod::Lvc, eye, &mut out);
        shade.push(t.elapsed().as_secs_f64() * 1e3);
    }
    shade.remove(0);
    Ok(FrameFigures { decode_ms: median(decode), shade_ms: median(shade), sun_change_ms: median(change) })
}

/// Levels of detail measured: per level at the frame's camera, and from farther away the
/// automatic per-leaf choice against the full meshes.
#[derive(Debug, Clone, Default)]
pub struct LodOutcome {
    /// Seconds to build the levels.
    pub build_s: f64,
    /// Per level: leaf triangles, vertices shaded, shade time (ms).
    pub levels: Vec<(usize, usize, f64)>,
    /// Per distance (times the camera's): the full meshes and the automatic choice.
    pub distances: Vec<LodDistance>,
}

/// The automatic level choice against the full meshes from `times` the camera's distance.
#[derive(Debug, Clone)]
pub struct LodDistance {
    /// The distance, in the camera's.
    pub times: f32,
    /// Every leaf in full: shade time (ms) and vertices shaded.
    pub full: (f64, usize),
    /// Each leaf at its level: shade time (ms) and vertices shaded.
    pub auto: (f64, usize),
    /// Leaves at each level in the automatic choice.
    pub leaves_per_level: Vec<usize>,
    /// The automatic choice's image against the full meshes' (relative L2 over the pixels).
    pub pixel_rel_l2_vs_full: f64,
}

impl Serialize for LodOutcome {
    /// `lod_build_s`; `lod_<k>_leaf_triangles`, `lod_<k>_vertices_shaded`, `lod_<k>_shade_ms`;
    /// `lod_x<d>_{full,auto}_shade_ms`, `…_vertices_shaded`, `lod_x<d>_auto_leaves_per_level`,
    /// `lod_x<d>_pixel_rel_l2_vs_full`.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("lod_build_s", &self.build_s)?;
        for (k, (triangles, vertices, ms)) in self.levels.iter().enumerate() {
            m.serialize_entry(&format!("lod_{k}_leaf_triangles"), triangles)?;
            m.serialize_entry(&format!("lod_{k}_vertices_shaded"), vertices)?;
            m.serialize_entry(&format!("lod_{k}_shade_ms"), ms)?;
        }
        for d in &self.distances {
            let x = format!("lod_x{}", d.times);
            for (name, (ms, vertices)) in [("full", d.full), ("auto", d.auto)] {
                m.serialize_entry(&format!("{x}_{name}_shade_ms"), &ms)?;
                m.serialize_entry(&format!("{x}_{name}_vertices_shaded"), &vertices)?;
            }
            m.serialize_entry(&format!("{x}_auto_leaves_per_level"), &d.leaves_per_level)?;
            m.serialize_entry(&format!("{x}_pixel_rel_l2_vs_full"), &d.pixel_rel_l2_vs_full)?;
        }
        m.end()
    }
}

/// Levels of detail: per level, triangles, vertices and shade time at the frame's camera; then,
/// from two, four and eight times farther (where leaves are a few pixels across), the automatic
/// per-leaf choice against the full meshes: levels used, shade time, and the image difference.
pub fn lod_figures(
    scene: &LeafScene,
    data: &LeafData,
    (light, edge_rays): (&Lighting, u32),
    cam: &Camera,
    (w, h): (u32, u32),
    background: &EnvMap,
) -> Result<LodOutcome> {
    let t = Instant::now();
    let lod = Lod::build(scene, &data.transfer, &LodParams::default());
    let mut out = LodOutcome { build_s: t.elapsed().as_secs_f64(), ..LodOutcome::default() };
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(scene, &data.lvc, light)?;
    let mut rad = Vec::new();
    let timed = |sel: &vcut_leaf::lod::Selection, eye: Vec3, rad: &mut Vec<TwoSided>| {
        let mut times = Vec::new();
        for _ in 0..5 {
            let t = Instant::now();
            shader.shade_lod(scene, data, sel, light, SunMethod::Lvc, eye, rad);
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        median(times)
    };
    for k in 0..lod.level_count() {
        let sel = lod.select(scene, &data.transfer, cam.position, cam.fov_y_deg, h, Some(k));
        out.levels.push((lod.triangles_at(k), sel.vertices.len(), timed(&sel, cam.position, &mut rad)));
    }
    // From farther away, each leaf at the level its size asks for against every leaf in full:
    // images rendered at 2 × 2 samples per pixel and box-filtered, so silhouettes compare as a
    // display would show them.
    for times in [2.0f32, 4.0, 8.0] {
        let far = Camera { position: cam.target + (cam.position - cam.target) * times, ..cam.clone() };
        let mut images = Vec::new();
        let mut runs = Vec::new();
        for force in [Some(0), None] {
            let sel = lod.select(scene, &data.transfer, far.position, far.fov_y_deg, h, force);
            let ms = timed(&sel, far.position, &mut rad);
            let mut full_rad = vec![[Vec3::ZERO; 2]; scene.vertex_count()];
            for (i, &v) in sel.vertices.iter().enumerate() {
                full_rad[v as usize] = rad[i];
            }
            let big = render_triangles(scene, &sel.triangles, &full_rad, &far, (2 * w, 2 * h), Some(background));
            images.push(downsample(&big));
            runs.push(((ms, sel.vertices.len()), sel.leaves_per_level.clone()));
        }
        let (rel, _) = pixel_errors(&images[1], &images[0]);
        out.distances.push(LodDistance {
            times,
            full: runs[0].0,
            auto: runs[1].0,
            leaves_per_level: runs[1].1.clone(),
            pixel_rel_l2_vs_full: rel,
        });
    }
    Ok(out)
}

/// A spread subset of at most `max` vertices.
pub fn subset(n: usize, max: usize) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    (0..max).map(|i| i * n / max).collect()
}

/// 2 × 2 box filter of an image twice the size (a pixel is covered when any sample is).
fn downsample(i: &Target) -> Image {
    let (w, h) = (i.width / 2, i.height / 2);
    let mut rgb = Vec::with_capacity(w * h);
    let mut covered = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let k = |dx: usize, dy: usize| (2 * y + dy) * i.width + 2 * x + dx;
            let ks = [k(0, 0), k(1, 0), k(0, 1), k(1, 1)];
            rgb.push(ks.iter().map(|&k| i.rgb[k]).sum::<Vec3>() * 0.25);
            covered.push(ks.iter().any(|&k| i.covered[k]));
        }
    }
    Image { width: w as u32, height: h as u32, rgb, covered }
}

/// A raster target as an image.
pub fn to_image(i: Target) -> Image {
    Image { width: i.width as u32, height: i.height as u32, rgb: i.rgb, covered: i.covered }
}
