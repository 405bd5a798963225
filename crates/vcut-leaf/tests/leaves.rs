//! The two passes against the path-traced reference and against what the geometry says: an open
//! leaf is lit from both sides, a leaf shadows the one below it and passes it green light, the
//! maps decode to what was traced, and the SH-only rendering loses the sun's shadow.

use glam::Vec3;
use vcut_envmap::procedural::PreethamSky;
use vcut_leaf::lvc::{Content, Lvc, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::prt::{PrtParams, Transfer};
use vcut_leaf::reference::{ReferenceParams, reference, rel_l2};
use vcut_leaf::scene::{LeafObject, LeafScene, Surface};
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod, TwoSided};
use vcut_scene::{Mesh, MeshOptions};

/// A horizontal square at height `y`, `n × n` quads, normal up.
fn square(name: &str, y: f32, size: f32, n: u32, surface: Surface) -> LeafObject {
    let h = size / 2.0;
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            pos.push(Vec3::new(-h + size * j as f32 / n as f32, y, -h + size * i as f32 / n as f32));
        }
    }
    for i in 0..n {
        for j in 0..n {
            let a = i * (n + 1) + j;
            tris.push([a, a + n + 1, a + 1]);
            tris.push([a + 1, a + n + 1, a + n + 2]);
        }
    }
    let mesh = Mesh::build(pos, None, tris, MeshOptions::default()).unwrap().0;
    LeafObject { name: name.into(), mesh, uv: None, surface }
}

fn sky() -> (Lighting, vcut_envmap::EnvMap) {
    Lighting::from_map(&PreethamSky::default().bake(256))
}

fn frame(scene: &LeafScene, data: &LeafData, light: &Lighting, method: SunMethod, eye: Vec3) -> Vec<TwoSided> {
    let mut shader = Shader::new();
    shader.prepare(scene, &data.lvc, light).unwrap();
    let mut out = Vec::new();
    shader.shade(scene, data, light, method, eye, &mut out);
    out
}

const LVC: LvcParams =
    LvcParams { resolution: 16, sun_diameter_deg: 0.53, disk_samples: 16, content: Content::Visibility };

#[test]
fn an_open_leaf_is_lit_from_both_sides_as_the_reference_says() {
    let scene = LeafScene::new(vec![square("leaf", 0.0, 1.0, 1, Surface::Leaf(Box::default()))]).unwrap();
    let lvc = Lvc::compute(&scene, &LVC, |_, _| {});
    // Nothing occludes anything: every byte of every map is 255 — above and below the leaf.
    let mut map = vec![0u8; scene.vertex_count()];
    for j in 0..lvc.directions().len() {
        lvc.decode(j, &mut map).unwrap();
        assert!(map.iter().all(|&b| b == 255), "sun direction {j}");
    }
    assert!(lvc.compressed_bytes() * 4 <= lvc.raw_bytes(), "{} of {}", lvc.compressed_bytes(), lvc.raw_bytes());
    let t = Transfer::compute(&scene, &PrtParams { rays: 1024, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, t).unwrap();
    let (light, rest) = sky();
    let eye = Vec3::new(1.0, 2.0, 3.0);
    let verts: Vec<usize> = (0..scene.vertex_count()).collect();
    let rp = ReferenceParams { paths: 3000, ..ReferenceParams::default() };
    for (what, l) in [("sun above", light.clone()), ("sun below", light.with_sun_dir(Vec3::new(0.4, -0.7, 0.3)))] {
        let got = frame(&scene, &data, &l, SunMethod::Lvc, eye);
        let want = reference(&scene, &rest, l.sun, eye, &verts, &rp);
        let e = rel_l2(&got, &want.radiance);
        assert!(e < 0.03, "{what}: two passes vs reference {e} (reference noise {})", want.noise());
    }
    // Lit from below, the upper side seen from above glows with transmitted sunlight.
    let none = Lighting { sun: None, sun_sh: [Vec3::ZERO; 25], ..light.clone() };
    let shader = Shader::new();
    let mut dark = Vec::new();
    shader.shade(&scene, &data, &none, SunMethod::Lvc, eye, &mut dark);
    let below = frame(&scene, &data, &light.with_sun_dir(Vec3::new(0.0, -1.0, 0.0)), SunMethod::Lvc, eye);
    let gain = below[0][0] - dark[0][0];
    // T_green/π · E_sun: the leaf's 0.16 transmittance.
    let want = 0.16 / std::f32::consts::PI * light.sun.unwrap().irradiance.y;
    assert!((gain.y - want).abs() < 0.02 * want, "transmitted {} vs {want}", gain.y);
}

#[test]
fn a_leaf_shadows_the_leaf_below_and_passes_it_green_light() {
    let upper = square("upper", 0.5, 2.0, 2, Surface::Leaf(Box::default()));
    let lower = square("lower", 0.0, 1.0, 2, Surface::Leaf(Box::default()));
    let scene = LeafScene::new(vec![upper, lower]).unwrap();
    let lvc = Lvc::compute(&scene, &LVC, |_, _| {});
    let mut map = vec![0u8; scene.vertex_count()];
    let (up, low) = (scene.vertex_range(0), scene.vertex_range(1));
    lvc.decode(lvc.sun_index(Vec3::Y), &mut map).unwrap();
    assert!(map[up.clone()].iter().all(|&b| b == 255) && map[low.clone()].iter().all(|&b| b == 0), "{map:?}");
    lvc.decode(lvc.sun_index(Vec3::new(1.0, 0.05, 0.0).normalize()), &mut map).unwrap();
    assert!(map.iter().all(|&b| b == 255), "a grazing sun reaches both: {map:?}");
    lvc.decode(lvc.sun_index(-Vec3::Y), &mut map).unwrap();
    assert!(map[low.clone()].iter().all(|&b| b == 255), "from below the lower leaf is lit");

    let t = Transfer::compute(&scene, &PrtParams { rays: 400, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, t).unwrap();
    let (light, rest) = sky();
    let light = light.with_sun_dir(Vec3::new(0.1, 1.0, 0.05).normalize());
    let eye = Vec3::new(0.3, 3.0, 0.5);
    let got = frame(&scene, &data, &light, SunMethod::Lvc, eye);
    // The lower leaf's upper side is in the sun's shadow; what reaches it came through the upper
    // leaf, so it is greener than the upper leaf's sunlit side.
    let (a, b) = (got[up.start + 4][0], got[low.start + 4][0]);
    assert!(b.y / b.x > 1.2 * (a.y / a.x), "lower {b} vs upper {a}");
    assert!(b.y < 0.5 * a.y, "and darker: {b} vs {a}");
    // The two passes follow the reference; SH alone blurs the sun's shadow away and does worse.
    let verts: Vec<usize> = (0..scene.vertex_count()).collect();
    let want = reference(
        &scene,
        &rest,
        light.sun,
        eye,
        &verts,
        &ReferenceParams { paths: 1500, ..ReferenceParams::default() },
    );
    let sh = frame(&scene, &data, &light, SunMethod::ShOnly, eye);
    let (e_lvc, e_sh) = (rel_l2(&got, &want.radiance), rel_l2(&sh, &want.radiance));
    assert!(e_lvc < 0.08, "two passes {e_lvc} (reference noise {})", want.noise());
    assert!(e_sh > 2.0 * e_lvc, "SH only {e_sh} vs two passes {e_lvc}");
}

#[test]
fn a_sun_between_cube_directions_blends_their_maps() {
    // A leaf over a leaf: the lower one's shadow moves as the sun moves between directions.
    let upper = square("upper", 0.3, 1.0, 4, Surface::Leaf(Box::default()));
    let lower = square("lower", 0.0, 1.2, 6, Surface::Leaf(Box::default()));
    let scene = LeafScene::new(vec![upper, lower]).unwrap();
    let lvc = Lvc::compute(&scene, &LVC, |_, _| {});
    let data =
        LeafData::new(lvc, Transfer::compute(&scene, &PrtParams { rays: 16, ..PrtParams::default() }, |_, _| {}))
            .unwrap();
    let (light, _) = sky();
    let dirs = data.lvc.directions();
    // Two neighbouring directions of the +Y face whose maps differ.
    let (a, b) = (2 * 256 + 6 * 16 + 9, 2 * 256 + 6 * 16 + 10);
    let decoded = |j: usize| {
        let mut m = vec![0u8; scene.vertex_count()];
        data.lvc.decode(j, &mut m).unwrap();
        m
    };
    let (ma, mb) = (decoded(a), decoded(b));
    assert_ne!(ma, mb, "the shadow moves between the two directions");
    let mut shader = Shader::new();
    shader.set_edge_rays(0);
    let made = |shader: &mut Shader, d: Vec3| {
        assert!(shader.prepare(&scene, &data.lvc, &light.with_sun_dir(d)).unwrap());
        shader.sun_map().unwrap().to_vec()
    };
    // At a direction's centre its own map; between two, every byte the blend of the maps
    // around it.
    assert_eq!(made(&mut shader, dirs.direction(a)), ma);
    let between = (dirs.direction(a) + dirs.direction(b)).normalize();
    let w = data.lvc.sun_weights(between);
    assert!(w.iter().any(|x| x.0 == a) && w.iter().any(|x| x.0 == b), "{w:?}");
    let maps: Vec<(Vec<u8>, f32)> = w.iter().map(|&(j, x)| (decoded(j), x)).collect();
    let half = made(&mut shader, between);
    for (v, h) in half.iter().enumerate() {
        let blend: f32 = maps.iter().map(|(m, x)| x * f32::from(m[v])).sum();
        assert!((f32::from(*h) - blend).abs() <= 0.51, "vertex {v}: {h} for {blend}");
    }
    assert!(half != ma && half != mb);
    // The same sun again decodes nothing.
    assert!(!shader.prepare(&scene, &data.lvc, &light.with_sun_dir(between)).unwrap());
    assert_eq!(shader.edge_vertices(), 0);
    // With rays, the vertices where the two maps disagree, or whose triangle's blended bytes do,
    // see the true sun: lit or not as a ray from them toward it says; the others keep the blend.
    shader.set_edge_rays(4);
    let exact = made(&mut shader, between);
    let mut edge: Vec<bool> =
        (0..scene.vertex_count()).map(|v| maps.iter().any(|(m, _)| m[v] != maps[0].0[v])).collect();
    for t in scene.triangles() {
        let t = t.map(|v| v as usize);
        if half[t[0]] != half[t[1]] || half[t[1]] != half[t[2]] {
            t.iter().for_each(|&v| edge[v] = true);
        }
    }
    let edges: Vec<usize> = (0..scene.vertex_count()).filter(|&v| edge[v]).collect();
    assert_eq!(shader.edge_vertices(), edges.len());
    assert!(!edges.is_empty());
    for v in 0..scene.vertex_count() {
        if !edges.contains(&v) {
            assert_eq!(exact[v], half[v], "vertex {v} keeps the blend");
            continue;
        }
        let (p, n) = (scene.positions()[v], scene.normals()[v]);
        let side = if n.dot(between) >= 0.0 { n } else { -n };
        let lit = !scene.occluder().occluded(p + side * scene.ray_offset(), between, f32::INFINITY);
        assert!(if lit { exact[v] > 127 } else { exact[v] < 128 }, "vertex {v}: {} lit {lit}", exact[v]);
    }
}

#[test]
fn a_vertex_in_the_penumbra_sees_part_of_the_sun() {
    // A wide sun (2°) behind the edge of a roof: the floor's vertices under the edge see part of
    // its disk. The maps sample one direction per texel (the disk fits in one), so alone they say
    // all or nothing there; the vertices whose triangles straddle the shadow's edge cast rays
    // over the disk, and those whose first rays disagree cast more and take their share.
    let roof = {
        let pos = vec![
            Vec3::new(-2.0, 1.0, -2.0),
            Vec3::new(0.0, 1.0, -2.0),
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(-2.0, 1.0, 2.0),
        ];
        let mesh = Mesh::build(pos, None, vec![[0, 2, 1], [0, 3, 2]], MeshOptions::default()).unwrap().0;
        LeafObject { name: "roof".into(), mesh, uv: None, surface: Surface::Opaque(Vec3::splat(0.3)) }
    };
    let floor = square("floor", 0.0, 1.0, 40, Surface::Opaque(Vec3::splat(0.5)));
    let scene = LeafScene::new(vec![roof, floor]).unwrap();
    let params = LvcParams { resolution: 8, sun_diameter_deg: 2.0, disk_samples: 16, content: Content::Visibility };
    let lvc = Lvc::compute(&scene, &params, |_, _| {});
    let data =
        LeafData::new(lvc, Transfer::compute(&scene, &PrtParams { rays: 16, ..PrtParams::default() }, |_, _| {}))
            .unwrap();
    // The sun near the zenith at a texel's centre: one map, no blend.
    let sun = data.lvc.directions().direction(data.lvc.sun_index(Vec3::Y));
    assert!(sun.y > 0.95, "{sun}");
    let light = sky().0.with_sun_dir(sun);
    let floor_verts = scene.vertex_range(1);
    // The share of the disk each floor vertex sees, by 4,096 rays.
    let radius = 1.0f32.to_radians();
    let (a, b) = sun.any_orthonormal_pair();
    let truth: Vec<f32> = floor_verts
        .clone()
        .map(|v| {
            let o = scene.positions()[v] + Vec3::Y * scene.ray_offset();
            let open = (0..4096)
                .filter(|&k| {
                    let r = radius * ((k as f32 + 0.5) / 4096.0).sqrt();
                    let phi = k as f32 * 2.399_963;
                    let d = (sun * r.cos() + (a * phi.cos() + b * phi.sin()) * r.sin()).normalize();
                    !scene.occluder().occluded(o, d, f32::INFINITY)
                })
                .count();
            open as f32 / 4096.0
        })
        .collect();
    let penumbra: Vec<usize> = (0..truth.len()).filter(|&i| truth[i] > 0.1 && truth[i] < 0.9).collect();
    assert!(penumbra.len() >= 20, "the penumbra holds vertices: {}", penumbra.len());
    let map_of = |rays: u32| {
        let mut shader = Shader::with_edge_rays(rays);
        assert!(shader.prepare(&scene, &data.lvc, &light).unwrap());
        (shader.sun_map().unwrap()[floor_verts.clone()].to_vec(), shader.edge_vertices())
    };
    let (alone, none) = map_of(0);
    assert_eq!(none, 0);
    assert!(penumbra.iter().all(|&i| alone[i] == 0 || alone[i] == 255), "the map alone: all or nothing");
    let (cast, edges) = map_of(4);
    assert!(edges >= penumbra.len() && edges < scene.vertex_count() / 2, "{edges} vertices cast");
    for &i in &penumbra {
        let got = f32::from(cast[i]) / 255.0;
        assert!((got - truth[i]).abs() < 0.1, "floor vertex {i}: {got} for {}", truth[i]);
    }
    // Away from the edge the map's bytes stand.
    for i in (0..truth.len()).filter(|&i| truth[i] == 0.0 || truth[i] == 1.0) {
        assert_eq!(cast[i], (truth[i] * 255.0) as u8, "floor vertex {i}");
    }
}

#[test]
fn a_glossy_leaf_reflects_what_its_mirror_direction_sees() {
    // A glossy leaf beside an opaque wall under a constant sky: seen from the wall's side, its
    // gloss mirrors the open sky; from the far side, the wall. Both match the path tracer.
    let leaf = square("leaf", 0.0, 1.0, 4, Surface::Leaf(Box::default()));
    let wall = {
        let pos = vec![
            Vec3::new(-2.0, -0.1, -0.6),
            Vec3::new(2.0, -0.1, -0.6),
            Vec3::new(2.0, 3.0, -0.6),
            Vec3::new(-2.0, 3.0, -0.6),
        ];
        let mesh = Mesh::build(pos, None, vec![[0, 1, 2], [0, 2, 3]], MeshOptions::default()).unwrap().0;
        LeafObject { name: "wall".into(), mesh, uv: None, surface: Surface::Opaque(Vec3::splat(0.2)) }
    };
    let scene = LeafScene::new(vec![leaf, wall]).unwrap();
    let lvc = Lvc::compute(&scene, &LvcParams { resolution: 4, ..LVC }, |_, _| {});
    let data =
        LeafData::new(lvc, Transfer::compute(&scene, &PrtParams { rays: 1024, ..PrtParams::default() }, |_, _| {}))
            .unwrap();
    let sky = vcut_envmap::EnvMap::constant([1.0; 3]);
    let light = Lighting::new(&sky, None);
    let verts: Vec<usize> = scene.vertex_range(0).collect();
    for eye in [Vec3::new(0.0, 1.0, 2.0), Vec3::new(0.0, 1.0, -0.5)] {
        let got = frame(&scene, &data, &light, SunMethod::Lvc, eye);
        let want =
            reference(&scene, &sky, None, eye, &verts, &ReferenceParams { paths: 2048, ..ReferenceParams::default() });
        let got: Vec<TwoSided> = verts.iter().map(|&v| got[v]).collect();
        let e = rel_l2(&got, &want.radiance);
        println!("eye {eye}: {e} (reference noise {})", want.noise());
        assert!(e < 0.05, "eye {eye}: {e} (reference noise {})", want.noise());
    }
}

#[test]
fn leaf_edits_change_the_frame_without_a_new_precompute() {
    let mut scene = LeafScene::new(vec![square("leaf", 0.0, 1.0, 1, Surface::Leaf(Box::default()))]).unwrap();
    let lvc = Lvc::compute(&scene, &LVC, |_, _| {});
    let t = Transfer::compute(&scene, &PrtParams { rays: 64, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, t).unwrap();
    let (light, _) = sky();
    let eye = Vec3::new(1.0, 2.0, 3.0);
    let before = frame(&scene, &data, &light, SunMethod::Lvc, eye);
    // A thicker leaf transmits far less: its underside, lit through it, darkens.
    let mut thick = LeafMaterial::default();
    thick.thickness *= 3.0;
    assert!(scene.set_surface("leaf", Surface::Leaf(Box::new(thick))));
    let after = frame(&scene, &data, &light, SunMethod::Lvc, eye);
    assert!(after[0][1].y < 0.5 * before[0][1].y, "{} vs {}", after[0][1], before[0][1]);
    assert_ne!(after[0][0], before[0][0]);
    assert!(!scene.set_surface("no such leaf", Surface::Opaque(Vec3::ONE)));
    for side in after.iter().flatten() {
        assert!(side.is_finite() && side.min_element() >= 0.0);
    }
}

#[test]
fn the_shared_potted_plant_renders_as_leaves() {
    let Some(dir) = vcut_scene::assets::dir() else {
        // Straight to stderr: the harness shows captured output only for failing tests.
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED the_shared_potted_plant_renders_as_leaves: shared assets folder not found (set VCUT_ASSETS)"
        );
        return;
    };
    let path = dir.join("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf");
    let s = vcut_scene::Scene::open(&path.to_string_lossy()).unwrap();
    let scene = LeafScene::from_scene_as_leaves(&s, &LeafMaterial::default()).unwrap();
    assert_eq!(scene.vertex_count(), 4006);
    // Its base-colour texture is the leaves' albedo map: each vertex reflects the texture's
    // colour at its coordinates (both sides), not the default leaf's green.
    let texture = s.objects[0].textures.base_colour.as_ref().expect("the plant's base colour");
    let uvs = s.objects[0].mesh.uvs().expect("the plant's coordinates");
    let (mut worst, mut mean_r, mut mean_t) = (0.0f32, Vec3::ZERO, Vec3::ZERO);
    for (v, scatter) in scene.scatter().iter().enumerate() {
        let uv = glam::Vec2::new(uvs[v].x.rem_euclid(1.0), uvs[v].y.rem_euclid(1.0));
        let want = texture.sample(uv);
        worst = worst.max((scatter.r[0] - want).abs().max_element());
        mean_r += scatter.r[0] / uvs.len() as f32;
        mean_t += want / uvs.len() as f32;
    }
    println!("plant leaves: reflectance mean {mean_r} against the texture's {mean_t}, worst {worst}");
    // Within the clamping texture sampling (the leaf maps clamp at the edges, glTF repeats).
    assert!((mean_r - mean_t).abs().max_element() < 0.01, "mean {mean_r} vs {mean_t}");
    let lvc = Lvc::compute(&scene, &LvcParams { resolution: 4, ..LVC }, |_, _| {});
    let t = Transfer::compute(&scene, &PrtParams { rays: 16, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, t).unwrap();
    let (light, _) = sky();
    let (c, r) = scene.bounds();
    let got = frame(&scene, &data, &light, SunMethod::Lvc, c + Vec3::new(0.0, 0.5, 2.0) * r);
    assert!(got.iter().flatten().all(|v| v.is_finite() && v.min_element() >= 0.0));
    // Some leaves are in shadow, some are lit.
    let mut map = vec![0u8; scene.vertex_count()];
    data.lvc.decode(data.lvc.sun_index(light.sun.unwrap().dir), &mut map).unwrap();
    assert!(map.contains(&0) && map.contains(&255));
}

#[test]
fn coarser_leaves_keep_their_light_and_far_leaves_get_them() {
    use vcut_leaf::lod::{Lod, LodParams};
    use vcut_leaf::plant::{PlantParams, plant};
    // Uniform leaves (no maps), so a coarse vertex differs from the full shading of the same
    // vertex by the averaging of its light alone.
    let scene = plant(&PlantParams { maps: false, ..PlantParams::default() }, &LeafMaterial::default()).unwrap();
    let lvc = Lvc::compute(&scene, &LvcParams { resolution: 8, ..LVC }, |_, _| {});
    let t = Transfer::compute(&scene, &PrtParams { rays: 64, ..PrtParams::default() }, |_, _| {});
    let data = LeafData::new(lvc, t).unwrap();
    let lod = Lod::build(&scene, &data.transfer, &LodParams::default());
    assert_eq!(lod.leaf_count(), 48);
    assert_eq!(lod.level_count(), 3);
    let fine = lod.triangles_at(0);
    assert_eq!(fine, 48 * 10 * 6 * 2);
    assert!(
        lod.triangles_at(1) < fine / 2 && lod.triangles_at(2) < lod.triangles_at(1),
        "{} {} {fine}",
        lod.triangles_at(2),
        lod.triangles_at(1)
    );
    // Near the plant every leaf is at level 0, far away every leaf at the coarsest.
    let (c, r) = scene.leaf_bounds();
    let near = lod.select(&scene, &data.transfer, c + Vec3::Z * 2.0 * r, 40.0, 720, None);
    let far = lod.select(&scene, &data.transfer, c + Vec3::Z * 200.0 * r, 40.0, 720, None);
    assert_eq!(near.leaves_per_level, vec![48, 0, 0]);
    assert_eq!(far.leaves_per_level, vec![0, 0, 48]);
    assert!(lod.vertices_at(2) < lod.vertices_at(0) / 2, "{} of {}", lod.vertices_at(2), lod.vertices_at(0));
    assert_eq!(near.vertices.len() - far.vertices.len(), lod.vertices_at(0) - lod.vertices_at(2));
    // Level 0 shades exactly as the full mesh does.
    let (light, _) = sky();
    let eye = c + Vec3::new(0.5, 0.4, 1.0) * 3.0 * r;
    let full = frame(&scene, &data, &light, SunMethod::Lvc, eye);
    let mut shader = Shader::new();
    shader.prepare(&scene, &data.lvc, &light).unwrap();
    let mut out = Vec::new();
    shader.shade_lod(&scene, &data, &near, &light, SunMethod::Lvc, eye, &mut out);
    for (k, &v) in near.vertices.iter().enumerate() {
        assert_eq!(out[k], full[v as usize]);
    }
    // The coarsest level's vertices, with their averaged transfer, stay near the full shading
    // of the same vertices (averaging smooths, it does not shift the light).
    let coarse = lod.select(&scene, &data.transfer, eye, 40.0, 720, Some(2));
    shader.shade_lod(&scene, &data, &coarse, &light, SunMethod::Lvc, eye, &mut out);
    let same: Vec<TwoSided> = coarse.vertices.iter().map(|&v| full[v as usize]).collect();
    let e = rel_l2(&out, &same);
    assert!(e > 0.0 && e < 0.1, "{e}");
}
