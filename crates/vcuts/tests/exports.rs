//! What `render` writes for other tools: an EXR with alpha and passes (read back with the `exr`
//! crate: every layer's channels, the passes agreeing with the image and the scene), and a `.glb`
//! with the shading baked (re-imported through the glTF loader, which validates it in full).

use glam::Vec3;
use std::path::Path;

mod common;
use common::scratch;

/// Every channel of an EXR file by name, as f32.
fn channels(path: &Path) -> std::collections::HashMap<String, Vec<f32>> {
    let image = exr::prelude::read_all_flat_layers_from_file(path).unwrap();
    let mut out = std::collections::HashMap::new();
    for layer in &image.layer_data {
        for c in &layer.channel_data.list {
            out.insert(c.name.to_string(), c.sample_data.values_as_f32().collect());
        }
    }
    out
}

#[test]
fn the_exr_holds_alpha_and_passes_and_the_glb_reimports() {
    let s = scratch("exports");
    common::precomputed(&s, "scene.toml", &[]);
    let mut args = vcuts::render::RenderArgs::new(&s.0.join("scene.vcuts"), &s.0.join("f.png"));
    (args.width, args.height) = (64, 48);
    args.exr = Some(s.0.join("f.exr"));
    args.exr_passes = Some(vcuts::render::Passes(vcut_shade::passes::Pass::ALL.to_vec()));
    args.export_glb = Some(s.0.join("f.glb"));
    vcuts::render::run(&args).unwrap();

    let c = channels(&s.0.join("f.exr"));
    let mut names: Vec<&str> = c.keys().map(String::as_str).collect();
    names.sort();
    assert_eq!(
        names,
        [
            "A",
            "B",
            "G",
            "R",
            "albedo.B",
            "albedo.G",
            "albedo.R",
            "depth.Z",
            "diffuse.B",
            "diffuse.G",
            "diffuse.R",
            "normal.X",
            "normal.Y",
            "normal.Z",
            "specular.B",
            "specular.G",
            "specular.R"
        ]
    );
    let (mut covered, mut shiny) = (0, 0);
    for k in 0..64 * 48 {
        let a = c["A"][k];
        assert!(a == 0.0 || a == 1.0, "alpha {a}");
        if a == 0.0 {
            assert_eq!(c["depth.Z"][k], vcut_shade::passes::BACKGROUND_DEPTH);
            assert_eq!(c["albedo.R"][k], 0.0);
            continue;
        }
        covered += 1;
        for (ch, d, sp) in
            [("R", "diffuse.R", "specular.R"), ("G", "diffuse.G", "specular.G"), ("B", "diffuse.B", "specular.B")]
        {
            let sum = c[d][k] + c[sp][k];
            assert!((sum - c[ch][k]).abs() <= 1e-4 * c[ch][k].abs().max(1e-3), "pixel {k}: {sum} vs {}", c[ch][k]);
        }
        shiny += usize::from(c["specular.G"][k] > 0.0);
        // The ground's k_d is 0.5; the ball's the default 0.6.
        assert!([0.5, 0.6].iter().any(|kd| (c["albedo.G"][k] - kd).abs() < 1e-5), "albedo {}", c["albedo.G"][k]);
        let n = Vec3::new(c["normal.X"][k], c["normal.Y"][k], c["normal.Z"][k]);
        assert!((n.length() - 1.0).abs() < 1e-4, "normal {n}");
        assert!(c["depth.Z"][k] > 0.0 && c["depth.Z"][k] < 100.0, "depth {}", c["depth.Z"][k]);
    }
    assert!(covered > 64 * 48 / 10 && covered < 64 * 48, "{covered} pixels covered");
    assert!(shiny > 0, "the Blinn-Phong ball has a specular share");

    let bytes = std::fs::read(s.0.join("f.glb")).unwrap();
    let options = vcut_scene::MeshOptions::default();
    let grouping = vcut_scene::loaders::GltfObjects::MeshNodes;
    let back = vcut_scene::loaders::load_gltf_bytes(&bytes, None, Path::new("f.glb"), grouping, options).unwrap();
    let names: Vec<&str> = back.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["ground", "ball"]);
    let data = vcut_data::Precomputed::open(&s.0.join("scene.vcuts")).unwrap();
    let triangles: usize = data.objects.iter().map(|o| o.mesh.triangles().len()).sum();
    assert_eq!(back.file_triangles, triangles);
    // The ball's node carries its translation: the re-imported ball sits where the scene put it.
    let ball = &back.objects[1].mesh;
    let centre = ball.positions().iter().copied().sum::<Vec3>() / ball.positions().len() as f32;
    assert!((centre - Vec3::new(0.0, 0.7, 0.0)).length() < 0.05, "ball centre {centre}");
    // The render's camera comes first, looking at the scene.
    let camera = &back.cameras[0];
    let ahead = (camera.target - camera.position).normalize();
    assert!(ahead.dot((Vec3::new(0.0, 0.35, 0.0) - camera.position).normalize()) > 0.9, "{camera:?}");
    // COLOR_0 is the tone-mapped colour, within [0, 1], and not all black.
    let gltf = gltf::Gltf::from_slice(&bytes).unwrap();
    assert!(gltf.extensions_used().any(|e| e == "KHR_materials_unlit"));
    let blob = gltf.blob.as_deref().unwrap();
    let mut lit = 0;
    for mesh in gltf.meshes() {
        let prim = mesh.primitives().next().unwrap();
        let colour = prim.get(&gltf::Semantic::Colors(0)).unwrap();
        let view = colour.view().unwrap();
        let at = view.offset() + colour.offset();
        for x in blob[at..at + colour.count() * 12].chunks(4) {
            let x = f32::from_le_bytes([x[0], x[1], x[2], x[3]]);
            assert!((0.0..=1.0).contains(&x), "COLOR_0 {x}");
            lit += usize::from(x > 0.05);
        }
    }
    assert!(lit > 0);
}

/// A textured glTF's coordinates and textures travel in the `.vcuts` file (its `surface`
/// section), equal to what the scene loaded.
#[test]
fn the_plants_coordinates_and_textures_travel_in_the_file() {
    if vcut_scene::assets::dir().is_none() {
        eprintln!(
            "SKIPPED the_plants_coordinates_and_textures_travel_in_the_file: shared assets folder not found (set VCUT_ASSETS)"
        );
        return;
    }
    let s = scratch("exports-plant");
    let scene = "[[object]]\nsource = \"asset:plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf\"\n\n\
                 [[object]]\nname = \"ground\"\nsource = \"builtin:plane\"\nsize = 0.3\nresolution = 4\ntranslation = [0.0, -0.01, 0.0]\n";
    std::fs::write(s.0.join("plant.toml"), scene).unwrap();
    let data = common::precomputed(&s, "plant.toml", &["directions=256", "field_spheres=2"]);
    let loaded = vcut_scene::Scene::open(s.0.join("plant.toml").to_str().unwrap()).unwrap();
    assert_eq!(data.objects[0].mesh.uvs(), loaded.objects[0].mesh.uvs());
    assert!(data.objects[0].mesh.uvs().is_some());
    assert_eq!(data.objects[0].textures, loaded.objects[0].textures);
    assert!(data.objects[0].textures.base_colour.is_some());
    // The built-in ground has neither.
    assert!(data.objects[1].mesh.uvs().is_none() && data.objects[1].textures.base_colour.is_none());
    // Rendered, the plant's albedo is its texture's colour, not black: the albedo pass over its
    // pixels is near the texture's mean at its vertices times its kd.
    let mut args = vcuts::render::RenderArgs::new(&s.0.join("plant.vcuts"), &s.0.join("p.png"));
    (args.width, args.height) = (96, 96);
    args.exr = Some(s.0.join("p.exr"));
    use vcut_shade::passes::Pass;
    args.exr_passes = Some(vcuts::render::Passes(vec![Pass::Albedo, Pass::Diffuse, Pass::Specular]));
    vcuts::render::run(&args).unwrap();
    let c = channels(&s.0.join("p.exr"));
    // The image takes the same per-pixel albedo as the passes: diffuse + specular is the image.
    for k in 0..96 * 96 {
        for ch in ["R", "G", "B"] {
            let (sum, rgb) = (c[&format!("diffuse.{ch}")][k] + c[&format!("specular.{ch}")][k], c[ch][k]);
            assert!(
                c["A"][k] == 0.0 || (sum - rgb).abs() <= 1e-4 * rgb.abs().max(1e-3),
                "pixel {k} {ch}: {sum} vs {rgb}"
            );
        }
    }
    let kd = Vec3::from(loaded.objects[0].material.kd);
    let colour = loaded.objects[0].textures.base_colour.as_ref().unwrap();
    let uvs = loaded.objects[0].mesh.uvs().unwrap();
    let want = kd * uvs.iter().map(|&uv| colour.sample(uv)).sum::<Vec3>() / uvs.len() as f32;
    assert!(want.max_element() > 0.02, "black at the vertices: {want}");
    // Plant pixels: covered and not the ground's untextured grey.
    let ground = Vec3::from(loaded.objects[1].material.kd);
    let (mut sum, mut n) = (Vec3::ZERO, 0);
    for k in 0..96 * 96 {
        let a = Vec3::new(c["albedo.R"][k], c["albedo.G"][k], c["albedo.B"][k]);
        if c["A"][k] == 1.0 && (a - ground).length() > 1e-4 {
            sum += a;
            n += 1;
        }
    }
    let mean = sum / n.max(1) as f32;
    println!("plant: {n} pixels, albedo mean {mean}, texture at the vertices × kd {want}, kd {kd}");
    assert!(n > 100 && mean.max_element() > 0.02, "{n} pixels, mean {mean}");
    // Screen area weighs the pot's large faces more than the vertex mean does: within a factor 2
    // of the texture's own mean.
    let texture = kd * colour.mean();
    let ratio = mean.max_element() / texture.max_element();
    assert!((0.5..2.0).contains(&ratio), "pixel albedo {mean} against the texture's mean {texture}");
}
