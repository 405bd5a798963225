//! Textured glTF objects: the viewer takes the base colour per pixel as the CPU renderer does,
//! and a metallic-roughness texture varies the BRDF per vertex in the frame and its references.
//!
//! Without a wgpu adapter the GPU test says it was skipped, unless `VCUT_REQUIRE_GPU=1` (as
//! `.ci/run` sets it), where a missing adapter fails.

mod common;
use common::{gpu, session_of};
use glam::Vec3;
use std::path::Path;
use vcut_scene::Camera;
use vcut_shade::image::tone_map;
use vcut_view::OrbitCamera;

/// A 2 × 2 square at y = 0 as an `n × n` grid of vertices, its texture coordinates spanning
/// `[0, uv_span]²`, textured with an 8 × 8 checker of `dark` and `light` texels and, with
/// `metal_right`, a metallic-roughness texture whose left half is a rough dielectric and right
/// half a glossy metal (α = 0.5): `quad.gltf` with `quad.bin`, `checker.png` and `mr.png`.
fn write_textured_quad(dir: &Path, n: u32, uv_span: f32, (dark, light): ([u8; 3], [u8; 3]), metal_right: bool) {
    let (mut positions, mut uvs, mut indices) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..n {
        for i in 0..n {
            let (s, t) = (i as f32 / (n - 1) as f32, j as f32 / (n - 1) as f32);
            positions.extend([2.0 * s - 1.0, 0.0, 2.0 * t - 1.0]);
            uvs.extend([uv_span * s, uv_span * t]);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let k = j * n + i;
            indices.extend([k, k + n, k + 1, k + 1, k + n, k + n + 1]);
        }
    }
    let normals: Vec<f32> = (0..n * n).flat_map(|_| [0.0, 1.0, 0.0]).collect();
    let indices_f: Vec<[u8; 4]> = indices.iter().map(|i| i.to_le_bytes()).collect();
    let arrays: [Vec<[u8; 4]>; 4] = [
        positions.iter().map(|x| x.to_le_bytes()).collect(),
        normals.iter().map(|x| x.to_le_bytes()).collect(),
        uvs.iter().map(|x| x.to_le_bytes()).collect(),
        indices_f,
    ];
    let (mut bin, mut views) = (Vec::new(), Vec::new());
    for a in &arrays {
        views.push((bin.len(), 4 * a.len()));
        bin.extend(a.iter().flatten());
    }
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    image::RgbImage::from_fn(8, 8, |x, y| image::Rgb(if (x + y) % 2 == 0 { dark } else { light }))
        .save(dir.join("checker.png"))
        .unwrap();
    image::RgbImage::from_fn(2, 1, |x, _| image::Rgb(if x == 0 { [0, 255, 0] } else { [0, 180, 255] }))
        .save(dir.join("mr.png"))
        .unwrap();
    let views_json: Vec<String> =
        views.iter().map(|(o, l)| format!(r#"{{"buffer": 0, "byteOffset": {o}, "byteLength": {l}}}"#)).collect();
    let (count, nidx) = (n * n, indices.len());
    let mr = if metal_right {
        r#", "metallicRoughnessTexture": {"index": 1}, "metallicFactor": 1.0, "roughnessFactor": 1.0"#
    } else {
        r#", "metallicFactor": 0.0, "roughnessFactor": 1.0"#
    };
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
      "nodes": [{{"name": "quad", "mesh": 0}}],
      "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}}, "indices": 3, "material": 0}}]}}],
      "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}{mr}}}}}],
      "textures": [{{"source": 0}}, {{"source": 1}}], "images": [{{"uri": "checker.png"}}, {{"uri": "mr.png"}}],
      "buffers": [{{"uri": "quad.bin", "byteLength": {}}}],
      "bufferViews": [{}],
      "accessors": [
        {{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1]}},
        {{"bufferView": 1, "componentType": 5126, "count": {count}, "type": "VEC3"}},
        {{"bufferView": 2, "componentType": 5126, "count": {count}, "type": "VEC2"}},
        {{"bufferView": 3, "componentType": 5125, "count": {nidx}, "type": "SCALAR"}}]}}"#,
        bin.len(),
        views_json.join(", ")
    );
    std::fs::write(dir.join("quad.gltf"), gltf).unwrap();
}

const QUAD_AND_BALL: &str = "[[object]]\nsource = \"quad.gltf\"\n\n[[object]]\nname = \"ball\"\n\
                             source = \"builtin:sphere\"\nsize = 0.3\nresolution = 10\n\
                             translation = [0.0, 0.5, 0.0]\nmoves = true\n";

/// The viewer takes a texture's albedo per pixel as the CPU renderer does: a checker with 16
/// squares a side on a quad of four vertices shows its squares (per-vertex colour could not), and
/// the GPU screenshot matches `rasterize_parts`.
#[test]
fn a_textured_object_shows_its_texture_per_pixel_as_the_cpu_renderer_does() {
    let Some(gpu) = gpu("a_textured_object_shows_its_texture_per_pixel_as_the_cpu_renderer_does") else { return };
    let checker = ([40, 40, 40], [230, 200, 120]);
    let mut s = session_of("textured", QUAD_AND_BALL, |dir| write_textured_quad(dir, 2, 2.0, checker, false));
    assert!(s.frame().has_textures());
    s.camera = OrbitCamera::from_camera(&Camera {
        name: "top".into(),
        position: Vec3::new(0.0, 2.2, 1.2),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
    });
    s.update();
    let (w, h) = (256, 192);
    let shot = vcut_view::screenshot(&gpu, &mut s, w, h).unwrap();
    let image = vcut_shade::image::rasterize_parts(&s.frame(), s.parts(), &s.camera.camera(), w, h, Some(s.env()));
    let e = s.exposure_in_use();
    let cpu: Vec<u8> = image.rgb.iter().flat_map(|c| [tone_map(c.x, e), tone_map(c.y, e), tone_map(c.z, e)]).collect();
    let mut diffs: Vec<u8> = Vec::new();
    for (p, c) in shot.pixels().zip(cpu.chunks(3)) {
        diffs.push((0..3).map(|k| p.0[k].abs_diff(c[k])).max().unwrap());
    }
    let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
    let within = diffs.iter().filter(|&&d| d <= 3).count() as f64 / diffs.len() as f64;
    // The checker's edges: a texel boundary blends over a pixel or two, where the GPU's
    // 8-bit filtering and the CPU's float filtering round differently.
    eprintln!(
        "adapter {}: textured, mean |gpu - cpu| {mean:.3} levels, {:.2} % within 3",
        gpu.describe(),
        within * 100.0
    );
    assert!(mean < 0.5 && within > 0.98, "mean {mean}, within {within}");
    // The squares show: along a row below the ball, the quad's pixels alternate between dark
    // and light many times (the quad has four vertices).
    let row: Vec<u8> = (0..w).map(|x| shot.get_pixel(x, h * 4 / 5).0[1]).collect();
    let (lo, hi) = (*row.iter().min().unwrap(), *row.iter().max().unwrap());
    let mid = (u16::from(lo) + u16::from(hi)) / 2;
    let flips = row.windows(2).filter(|p| (u16::from(p[0]) > mid) != (u16::from(p[1]) > mid)).count();
    eprintln!("levels {lo}..{hi}, {flips} dark–light changes along the row");
    assert!(hi - lo > 60 && flips >= 8, "levels {lo}..{hi}, {flips} dark–light changes along the row");
}

/// A metallic-roughness texture varies the BRDF per vertex: the quad's left half is a rough
/// dielectric with the base colour's albedo, its right half a glossy metal (α = 0.5) with none, and the
/// shading and the exact reference both take it (the metal's specular share dwarfs the
/// dielectric's; the cuts stay close to the reference on both halves). An edit of the object's
/// material overrides the texture, and setting the loaded material back restores it.
#[test]
fn a_metallic_roughness_texture_varies_the_brdf_per_vertex() {
    let grey = ([150, 150, 150], [150, 150, 150]);
    let mut s = session_of("metal", QUAD_AND_BALL, |dir| write_textured_quad(dir, 17, 1.0, grey, true));
    let quad = s.frame().object_index("quad").unwrap();
    let uvs = s.frame().object(quad).mesh.uvs().unwrap().to_vec();
    // The columns at the two texels' centres (u = 1/4 and 3/4; elsewhere they blend, and the
    // texture repeats across u = 0).
    let column = |u: f32| (0..uvs.len()).filter(|&v| (uvs[v].x - u).abs() < 0.01).collect::<Vec<usize>>();
    let (left, right) = (column(0.25), column(0.75));
    assert_eq!((left.len(), right.len()), (17, 17));
    let loaded = *s.frame().object(quad).material;
    for &v in &left {
        let m = *s.frame().object(quad).vertex_material(v);
        assert!(m.kd[0] > 0.25 && (m.ks[0] - 0.04).abs() < 1e-6 && m.roughness > 0.9, "left {v}: {m:?}");
    }
    for &v in &right {
        let m = *s.frame().object(quad).vertex_material(v);
        assert!(
            m.kd[0] < 1e-6 && m.ks[0] > 0.25 && (m.roughness - (180.0f32 / 255.0).powi(2)).abs() < 1e-4,
            "right {v}: {m:?}"
        );
    }
    s.camera = OrbitCamera::from_camera(&Camera {
        name: "low".into(),
        position: Vec3::new(0.0, 1.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
    });
    s.update();
    let parts = s.parts()[quad].clone();
    let mean = |vs: &[usize], f: &dyn Fn(usize) -> f32| vs.iter().map(|&v| f(v)).sum::<f32>() / vs.len() as f32;
    let spec_left = mean(&left, &|v| parts[v].specular.max_element());
    let spec_right = mean(&right, &|v| parts[v].specular.max_element());
    eprintln!("mean specular: rough dielectric {spec_left:.4}, glossy metal {spec_right:.4}");
    assert!(spec_right > 3.0 * spec_left, "metal {spec_right} vs dielectric {spec_left}");
    for &v in &right {
        assert_eq!(s.radiance()[quad][v], parts[v].specular, "a metal vertex has no diffuse share");
    }
    // The exact reference shades each vertex with its own material too.
    let eye = s.camera.eye();
    let exact = vcut_shade::reference::ExactReference::new(&s.frame(), s.origin_offset());
    let positions = s.frame().object(quad).positions();
    for (name, vs) in [("dielectric", &left), ("metal", &right)] {
        let pairs = vs.iter().map(|&v| (s.radiance()[quad][v], exact.vertex(&s.frame(), quad, v, positions[v], eye)));
        let (rel, _) = vcut_shade::reference::relative_errors(pairs);
        eprintln!("{name}: cuts against the exact reference, rel. L2 {:.2} %", rel * 100.0);
        assert!(rel < 0.1, "{name}: {rel}");
    }
    // An edit overrides the texture everywhere; the loaded material brings it back.
    let textured = *s.frame().object(quad).vertex_material(right[0]);
    let mut edited = loaded;
    edited.roughness = 0.9;
    s.set_material(quad, edited);
    assert_eq!(s.frame().object(quad).vertex_material(right[0]).roughness, 0.9);
    s.set_material(quad, loaded);
    assert_eq!(*s.frame().object(quad).vertex_material(right[0]), textured);
}
