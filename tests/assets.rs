//! Every file in the shared assets folder loads, with the vertex and triangle counts that
//! `SOURCES.md` states (skipped, with a notice, where the folder is absent).

use std::path::Path;
use vcut_envmap::InvalidTexels;
use vcut_scene::loaders::{GltfObjects, ObjObjects, load_file};
use vcut_scene::{MeshOptions, Scene};
use vcut_tests::assets_or_skip;

fn counts(path: &Path) -> (usize, usize, usize, usize) {
    let out = load_file(path, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    for o in &out.objects {
        o.mesh.validate().unwrap_or_else(|e| panic!("{}: {}: {e}", path.display(), o.name));
    }
    let v = out.objects.iter().map(|o| o.mesh.vertex_count()).sum();
    let t = out.objects.iter().map(|o| o.mesh.triangle_count()).sum();
    (out.file_vertices, out.file_triangles, v, t)
}

#[test]
fn meshes_match_sources_md() {
    let Some(a) = assets_or_skip("meshes_match_sources_md") else { return };
    // (file, SOURCES.md vertices, SOURCES.md triangles)
    let expected = [
        ("meshes/stanford-bunny.obj", 35_947, 69_451),
        ("meshes/bunny_2503v_probulator.obj", 2_503, 4_968),
        ("meshes/teapot.obj", 3_644, 6_320),
        ("meshes/ground_plane_16x16.obj", 289, 512),
        ("gltf/2CylinderEngine.glb", 55_843, 75_730),
        ("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf", 4_006, 6_097),
    ];
    for (rel, v, t) in expected {
        let (fv, ft, lv, lt) = counts(&a.join(rel));
        assert_eq!((fv, ft), (v, t), "{rel}: file counts");
        assert!(lv > 0 && lt > 0, "{rel}");
        println!("{rel}: file {fv} v / {ft} t; loaded {lv} v / {lt} t");
    }
    // The bunny's 1,113 vertices that no face uses are dropped; every face is kept.
    let (_, _, lv, lt) = counts(&a.join("meshes/stanford-bunny.obj"));
    assert_eq!((lv, lt), (34_834, 69_451));
}

#[test]
fn the_plants_texture_coordinates_are_read() {
    let Some(a) = assets_or_skip("the_plants_texture_coordinates_are_read") else { return };
    let p = a.join("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf");
    let out = load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()).unwrap();
    let (mut inside, mut total) = (0usize, 0usize);
    for o in &out.objects {
        let uv = o.mesh.uvs().unwrap_or_else(|| panic!("{}: no TEXCOORD_0", o.name));
        assert_eq!(uv.len(), o.mesh.vertex_count(), "{}", o.name);
        inside += uv.iter().filter(|t| (0.0..=1.0).contains(&t.x) && (0.0..=1.0).contains(&t.y)).count();
        total += uv.len();
    }
    // Poly Haven's atlas lies in the unit square.
    assert_eq!(inside, total, "{inside} of {total} coordinates in [0, 1]²");
    println!("plant: {} objects, {total} vertices with texture coordinates", out.objects.len());
    // Its colour is in the base-colour texture (green leaves, not black), and the ARM texture
    // says it is not metal (the factor alone, 1 by glTF's default, made it fully metallic).
    let t = &out.objects[0].textures;
    let colour = t.base_colour.as_ref().expect("a base-colour texture");
    let mean = colour.mean();
    assert!(mean.y > 0.02 && mean.y > mean.z, "base colour mean {mean}");
    let at_vertices =
        out.objects[0].mesh.uvs().unwrap().iter().map(|&uv| colour.sample(uv)).sum::<glam::Vec3>() / total as f32;
    assert!(at_vertices.max_element() > 0.02, "albedo at the vertices {at_vertices}");
    let metallic = t.metallic_roughness.as_ref().expect("a metallic-roughness texture").mean().z;
    assert!(metallic < 0.1, "metallic {metallic}");
    println!("plant: base colour mean {mean}, at the vertices {at_vertices}, metallic mean {metallic}");
    // Its factors travel with the metallic-roughness texture; its normal map is reported, not read.
    assert!(t.factors.is_some());
    println!("plant: not read: {:?}", out.ignored);
    assert!(out.ignored.iter().any(|w| w.contains("normal textures of 1 material(s) not read")), "{:?}", out.ignored);
}

#[test]
fn a_scene_keeps_the_plants_textures_unless_its_material_replaces_them() {
    let Some(_) = assets_or_skip("a_scene_keeps_the_plants_textures_unless_its_material_replaces_them") else { return };
    let rel = "asset:plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf";
    let dir = std::env::temp_dir().join(format!("vcuts-plant-textures-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let open = |extra: &str| {
        let file = dir.join("scene.toml");
        let text = format!("[[object]]\nsource = \"{rel}\"\ninstances = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]\n{extra}");
        std::fs::write(&file, text).unwrap();
        vcut_scene::Scene::open(file.to_str().unwrap()).unwrap_or_else(|e| panic!("{e}"))
    };
    let scene = open("");
    assert_eq!(scene.objects.len(), 2);
    for o in &scene.objects {
        assert!(o.textures.base_colour.is_some() && o.mesh.uvs().is_some(), "{}", o.name);
    }
    let plain = open("material = { model = \"lambert\", kd = [0.5, 0.5, 0.5] }\n");
    assert!(plain.objects.iter().all(|o| o.textures.base_colour.is_none()));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn gltf_engine_keeps_its_hierarchy() {
    let Some(a) = assets_or_skip("gltf_engine_keeps_its_hierarchy") else { return };
    let p = a.join("gltf/2CylinderEngine.glb");
    let per_node = load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()).unwrap();
    let per_root = load_file(&p, GltfObjects::TopLevelNodes, ObjObjects::File, MeshOptions::default()).unwrap();
    assert!(per_node.objects.len() > 20, "{} objects", per_node.objects.len());
    let v = |o: &vcut_scene::loaders::LoadOutput| o.objects.iter().map(|x| x.mesh.vertex_count()).sum::<usize>();
    assert_eq!(v(&per_node), v(&per_root), "grouping does not change geometry");
    let names: std::collections::HashSet<_> = per_node.objects.iter().map(|o| &o.name).collect();
    assert_eq!(names.len(), per_node.objects.len(), "object names are unique");
}

#[test]
fn the_engines_gltf_camera_is_the_default_view_and_sees_the_engine() {
    let Some(a) = assets_or_skip("the_engines_gltf_camera_is_the_default_view_and_sees_the_engine") else { return };
    let scene = vcut_scene::Scene::open(a.join("gltf/2CylinderEngine.glb").to_str().unwrap()).unwrap();
    let c = scene.cameras.first().expect("the file's camera");
    // The file: node 81, yfov 0.31435 rad, at (1005.99, 766.32, 953.35) looking down its −Z.
    assert!((c.fov_y_deg - 0.314_346_37f32.to_degrees()).abs() < 1e-3, "{}", c.fov_y_deg);
    assert!(c.position.distance(glam::Vec3::new(1005.987, 766.317, 953.346)) < 1e-2, "{}", c.position);
    // The engine's centre lies within the view cone, and the target on its axis ahead.
    let b = scene.bounds();
    let centre = 0.5 * (b.min + b.max);
    let (axis, to) = ((c.target - c.position).normalize(), (centre - c.position).normalize());
    assert!(axis.dot(to).acos().to_degrees() < 0.5 * c.fov_y_deg, "the engine is outside the view");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn envmaps_load_with_finite_power() {
    let Some(a) = assets_or_skip("envmaps_load_with_finite_power") else { return };
    // memorial.exr is a photograph, not an environment map, but it must load all the same.
    for rel in vcut_tests::ENVIRONMENT_MAPS.into_iter().chain(["envmaps/memorial.exr"]) {
        let (map, report) = vcut_envmap::load(&a.join(rel), InvalidTexels::Reject).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(report.clamped_texels, 0);
        let p = map.total_power();
        assert!(p.iter().all(|x| x.is_finite() && *x > 0.0), "{rel}: {p:?}");
    }
    // The quarry map's small strong sun: about half the light in 0.05 % of the pixels.
    let (quarry, _) = vcut_envmap::load(&a.join("envmaps/quarry_01_1k.hdr"), InvalidTexels::Reject).unwrap();
    let s = quarry.power_stats();
    assert!(s.top_0_1_percent_share > 0.45, "{}", s.top_0_1_percent_share);
}

#[test]
fn bunny_scene_builds_from_the_asset() {
    if assets_or_skip("bunny_scene_builds_from_the_asset").is_none() {
        // Without the asset the built-in scene must say what is missing.
        let e = Scene::open("builtin:bunny").unwrap_err().to_string();
        assert!(e.contains("stanford-bunny.obj") && e.contains("VCUT_ASSETS"), "{e}");
        return;
    }
    let s = Scene::open("builtin:bunny").unwrap();
    assert_eq!(s.objects.len(), 2);
    assert_eq!(s.vertex_count(), 34_834 + 65 * 65);
    let b = s.object("bunny").unwrap().mesh.bounds();
    assert!(b.min.y.abs() < 1e-5 && (b.max.y - 1.0).abs() < 1e-5, "stands on the ground, 1 tall: {b:?}");
}

#[test]
fn example_scene_files_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join("examples");
    let teapot = Scene::load_file(&root.join("teapot.toml")).unwrap();
    let builtin = Scene::open("builtin:teapot").unwrap();
    assert_eq!(teapot.vertex_count(), builtin.vertex_count());
    assert_eq!(teapot.objects.len(), 3);
    match Scene::load_file(&root.join("bunny.toml")) {
        Ok(s) => assert_eq!(s.objects.len(), 2),
        Err(e) => {
            assert!(assets_or_skip("example_scene_files_load (bunny)").is_none(), "{e}");
        }
    }
}
