//! A hand-written glTF with nested, scaled, rotated and mirrored nodes lands in the right world
//! positions, with faces still facing out after the mirror; its perspective camera is read in
//! world space and its orthographic one reported as not read; its directional light becomes a
//! sun in world space that joins the map, and its point light and an unread extension are
//! reported.

use glam::Vec3;
use std::path::Path;
use vcut_scene::MeshOptions;
use vcut_scene::loaders::{GltfObjects, load_gltf_bytes};

fn gltf_text() -> String {
    let positions: Vec<u8> =
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0].iter().flat_map(|f| f.to_le_bytes()).collect();
    let uri = format!("data:application/octet-stream;base64,{}", vcut_tests::base64(&positions));
    let s = std::f32::consts::FRAC_1_SQRT_2;
    // parent: T(1,0,0) · R_y(90°) · S(2); child: T(0,1,0) with the mesh;
    // mirror: a child of parent given as a column-major matrix, scale (−1, 1, 1) then T(0,0,5);
    // cam: a child of parent at T(0,0,3) with a perspective camera; ortho: a root orthographic one;
    // sun: a child of parent with a directional light (shining down its −Z); bulb: a point light.
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0,4,6]}}],
"extensionsUsed":["KHR_lights_punctual","KHR_materials_variants"],
"extensions":{{"KHR_lights_punctual":{{"lights":[
 {{"name":"noon","type":"directional","color":[1.0,0.5,0.25],"intensity":683}},
 {{"type":"point","intensity":10}}]}}}},
"cameras":[{{"name":"view","type":"perspective","perspective":{{"yfov":0.5,"znear":0.1}}}},
 {{"type":"orthographic","orthographic":{{"xmag":1,"ymag":1,"znear":0.1,"zfar":10}}}}],
"nodes":[
 {{"name":"parent","translation":[1,0,0],"rotation":[0,{s},0,{s}],"scale":[2,2,2],"children":[1,2,3,5]}},
 {{"name":"child","translation":[0,1,0],"mesh":0}},
 {{"name":"mirror","matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1],"mesh":0}},
 {{"name":"cam","translation":[0,0,3],"camera":0}},
 {{"name":"ortho","camera":1}},
 {{"name":"sun","extensions":{{"KHR_lights_punctual":{{"light":0}}}}}},
 {{"name":"bulb","translation":[0,3,0],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}}],
"meshes":[{{"name":"tri","primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,0,1]}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"buffers":[{{"byteLength":36,"uri":"{uri}"}}]}}"#
    )
}

/// The fixture read as `nested.gltf`.
fn load(text: &str, grouping: GltfObjects) -> vcut_scene::loaders::LoadOutput {
    load_gltf_bytes(text.as_bytes(), None, Path::new("nested.gltf"), grouping, MeshOptions::default())
        .unwrap_or_else(|e| panic!("{e}"))
}

fn close(a: Vec3, b: Vec3) -> bool {
    a.distance(b) < 1e-5
}

#[test]
fn nested_nodes_land_in_world_space() {
    let text = gltf_text();
    let out = load(&text, GltfObjects::MeshNodes);
    assert_eq!(out.objects.len(), 2);
    let child = out.objects.iter().find(|o| o.name == "child").unwrap();
    // Worked by hand: local p → +(0,1,0) → ×2 → R_y(90°) (x→−z, z→x) → +(1,0,0).
    let expect = [Vec3::new(1.0, 2.0, 0.0), Vec3::new(1.0, 2.0, -2.0), Vec3::new(3.0, 2.0, 0.0)];
    for (p, e) in child.mesh.positions().iter().zip(expect) {
        assert!(close(*p, e), "{p} vs {e}");
    }
    // Face normal of the local triangle is −Y; rotation and uniform scale keep it −Y.
    assert!(close(child.mesh.normals()[0], -Vec3::Y), "{}", child.mesh.normals()[0]);

    let mirror = out.objects.iter().find(|o| o.name == "mirror").unwrap();
    // mirror: local (x,y,z) → (−x, y, z+5) → ×2 → R_y → +(1,0,0).
    let m = |p: Vec3| {
        let q = Vec3::new(-p.x, p.y, p.z + 5.0) * 2.0;
        Vec3::new(q.z, q.y, -q.x) + Vec3::X
    };
    let local = [Vec3::ZERO, Vec3::X, Vec3::Z];
    let mut found = 0;
    for l in local {
        if mirror.mesh.positions().iter().any(|p| close(*p, m(l))) {
            found += 1;
        }
    }
    assert_eq!(found, 3);
    // The mirror flipped the winding back so the face normal and the vertex normal agree.
    let t = mirror.mesh.triangles()[0];
    let [a, b, c] = t.map(|i| mirror.mesh.positions()[i as usize]);
    assert!((b - a).cross(c - a).normalize().dot(mirror.mesh.normals()[t[0] as usize]) > 0.99);
}

#[test]
fn top_level_grouping_merges_children() {
    let text = gltf_text();
    let out = load(&text, GltfObjects::TopLevelNodes);
    assert_eq!(out.objects.len(), 1);
    assert_eq!(out.objects[0].name, "parent");
    assert_eq!(out.objects[0].mesh.triangle_count(), 2);
}

#[test]
fn the_perspective_camera_is_read_in_world_space_and_the_orthographic_one_reported() {
    let text = gltf_text();
    let out = load(&text, GltfObjects::MeshNodes);
    assert_eq!(out.cameras.len(), 1, "{:?}", out.cameras);
    let c = &out.cameras[0];
    assert_eq!(c.name, "view");
    // (0,0,3) → ×2 → R_y(90°) → +(1,0,0) = (7,0,0); its −Z turns to −X; up stays +Y.
    assert!(close(c.position, Vec3::new(7.0, 0.0, 0.0)), "{}", c.position);
    assert!(close((c.target - c.position).normalize(), -Vec3::X), "{}", c.target);
    assert!(close(c.up, Vec3::Y), "{}", c.up);
    assert!((c.fov_y_deg - 0.5f32.to_degrees()).abs() < 1e-4, "{}", c.fov_y_deg);
    assert!(out.ignored.iter().any(|w| w.contains("nested.gltf") && w.contains("orthographic")), "{:?}", out.ignored);
}

#[test]
fn a_directional_light_becomes_a_sun_and_the_rest_is_reported() {
    let text = gltf_text();
    let out = load(&text, GltfObjects::MeshNodes);
    assert_eq!(out.suns.len(), 1, "{:?}", out.suns);
    let sun = &out.suns[0];
    // The light shines down its node's −Z; the parent's R_y(90°) turns +Z (toward it) to +X.
    assert_eq!(sun.name, "noon");
    assert!(close(sun.dir, Vec3::X), "{}", sun.dir);
    assert!(close(sun.lux, Vec3::new(683.0, 341.5, 170.75)), "{}", sun.lux);
    let warned = |what: &str| out.ignored.iter().any(|w| w.contains("nested.gltf") && w.contains(what));
    assert!(warned("point and spot lights"), "{:?}", out.ignored);
    assert!(warned("extension KHR_materials_variants not read"), "{:?}", out.ignored);
    assert_eq!(out.ignored.len(), 3, "{:?}", out.ignored);

    // In a scene, the sun joins a constant map as E × lux_scale of irradiance, turned with the
    // object's rotation, and the map is no longer a built-in the file can bake again.
    let dir = std::env::temp_dir().join(format!("vcuts-gltf-sun-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("nested.gltf"), &text).unwrap();
    let scene_file = dir.join("scene.toml");
    std::fs::write(
        &scene_file,
        "[environment]\nsource = \"builtin:constant\"\nresolution = 256\n\n\
         [[object]]\nsource = \"nested.gltf\"\nrotation_deg = [0.0, 90.0, 0.0]\n",
    )
    .unwrap();
    let scene = vcut_scene::Scene::open(scene_file.to_str().unwrap()).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(scene.environment_recipe.is_none());
    assert!(scene.warnings.iter().any(|w| w.contains("point and spot lights")), "{:?}", scene.warnings);
    let plain = vcut_envmap::EnvMap::constant([1.0; 3]).to_latlong(256, 4);
    // R_y(90°) takes +X to −Z.
    let toward = -Vec3::Z;
    let cone = 3f32.to_radians();
    let (lit, base) = (scene.environment.integrate_cone(toward, cone), plain.integrate_cone(toward, cone));
    for (c, want) in [1.0, 0.5, 0.25].into_iter().enumerate() {
        assert!((lit[c] - base[c] - want).abs() < 1e-3, "channel {c}: {} added", lit[c] - base[c]);
    }
}
