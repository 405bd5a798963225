//! Malformed inputs give an error that names the file and the problem — never a panic.

use std::path::Path;
use vcut_envmap::{EnvMapError, InvalidTexels, load};
use vcut_scene::loaders::{GltfObjects, ObjObjects, load_file};
use vcut_scene::{MeshOptions, Scene};
use vcut_tests::{glb_triangle, rgbe_flat, scratch, write};

fn message<T, E: std::fmt::Display>(r: Result<T, E>) -> String {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn truncated_hdr_is_refused_naming_the_file() {
    let dir = scratch("hdr");
    let good = rgbe_flat(8, 4, [1.0, 0.5, 0.25]);
    let ok = write(&dir, "ok.hdr", &good);
    let (map, _) = load(&ok, InvalidTexels::Reject).unwrap();
    assert!((map.texels()[0][0] - 1.0).abs() < 0.01);
    for cut in [good.len() - 5, good.len() / 2, 20, 3] {
        let p = write(&dir, "cut.hdr", &good[..cut]);
        let msg = message(load(&p, InvalidTexels::Reject));
        assert!(msg.contains("cut.hdr") && msg.contains("Radiance HDR"), "{msg}");
    }
    // A real RLE file, truncated.
    if let Some(a) = vcut_tests::assets_or_skip("truncated_hdr (real RLE file)") {
        let bytes = std::fs::read(a.join("envmaps/pisa.hdr")).unwrap();
        let p = write(&dir, "pisa_cut.hdr", &bytes[..bytes.len() * 2 / 3]);
        let msg = message(load(&p, InvalidTexels::Reject));
        assert!(msg.contains("pisa_cut.hdr"), "{msg}");
    }
}

/// Old-style run-length scanlines (Radiance before 2.0): a run marker `[1, 1, 1, n]` repeats the
/// previous texel `n × 256^k` times, `k` the markers before it in a row. Nine markers in a row
/// overflowed the `image` decoder's multiplier (0.25.9 and 0.25.10: a panic where overflow is
/// checked, a wrapped count where it is not — found by the fuzzer).
#[test]
fn hdr_with_a_long_chain_of_run_markers_is_refused() {
    let dir = scratch("hdr-rle");
    // Width 4 (under 8) is always read as old-style RLE: one texel, then the markers.
    let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 4\n".to_vec();
    bytes.extend_from_slice(&[10, 10, 10, 128]);
    for _ in 0..12 {
        bytes.extend_from_slice(&[1, 1, 1, 0]);
    }
    bytes.extend_from_slice(&[1, 1, 1, 1]);
    let p = write(&dir, "chain.hdr", &bytes);
    let msg = message(load(&p, InvalidTexels::Reject));
    assert!(msg.contains("chain.hdr") && msg.contains("Radiance HDR"), "{msg}");
    // A short chain is a valid old-style file: 1 texel + 3 repeats.
    let mut ok = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 4\n".to_vec();
    ok.extend_from_slice(&[128, 64, 32, 129, 1, 1, 1, 3]);
    let (map, _) = load(&write(&dir, "short.hdr", &ok), InvalidTexels::Reject).unwrap();
    assert!(map.texels().iter().all(|t| (t[0] - 1.0).abs() < 1e-6 && (t[2] - 0.25).abs() < 1e-6), "{:?}", map.texels());
}

#[test]
fn exr_with_unexpected_channels_is_refused() {
    use exr::prelude::*;
    let dir = scratch("exr");
    let p = dir.join("depth.exr");
    let z = AnyChannel::new("Z", FlatSamples::F32(vec![1.0; 16]));
    let n = AnyChannel::new("N.x", FlatSamples::F32(vec![0.0; 16]));
    let image = Image::from_channels((4, 4), AnyChannels::sort(vec![z, n].into()));
    image.write().to_file(&p).unwrap();
    let e = load(&p, InvalidTexels::Reject).unwrap_err();
    assert!(matches!(e, EnvMapError::ExrChannels { .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.contains("depth.exr") && msg.contains('Z'), "{msg}");
    // Garbage with an .exr name.
    let g = write(&dir, "garbage.exr", b"\x76\x2f\x31\x01not really an exr");
    let msg = message(load(&g, InvalidTexels::Reject));
    assert!(msg.contains("garbage.exr") && msg.contains("OpenEXR"), "{msg}");
}

#[test]
fn nan_inf_negative_texels_are_named_or_clamped_on_request() {
    let dir = scratch("nan");
    for (name, bad) in [("nan.exr", f32::NAN), ("inf.exr", f32::INFINITY), ("neg.exr", -1.0)] {
        let p = dir.join(name);
        exr::prelude::write_rgb_file(&p, 8, 4, |x, y| if (x, y) == (5, 2) { (0.5, bad, 0.5) } else { (1.0, 1.0, 1.0) })
            .unwrap();
        let msg = message(load(&p, InvalidTexels::Reject));
        assert!(msg.contains(name) && msg.contains("(5, 2)"), "{msg}");
        let (map, report) = load(&p, InvalidTexels::Clamp).unwrap();
        assert_eq!(report.clamped_texels, 1);
        assert!(map.texels().iter().flatten().all(|c| c.is_finite() && *c >= 0.0));
    }
}

#[test]
fn glb_with_wrong_buffer_length_is_refused() {
    let dir = scratch("glb");
    let ok = write(&dir, "ok.glb", &glb_triangle(36, 36));
    let out = load_file(&ok, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()).unwrap();
    assert_eq!(out.objects[0].mesh.triangle_count(), 1);
    for (declared, actual) in [(400, 36), (36, 12)] {
        let p = write(&dir, "short.glb", &glb_triangle(declared, actual));
        let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
        assert!(msg.contains("short.glb") && msg.contains("glTF"), "{msg}");
    }
    // Regression (fuzz target `scene_files`): a GLB header declaring fewer than 12 bytes
    // overflowed gltf's length arithmetic.
    let mut short_header = glb_triangle(36, 36);
    short_header[8..12].copy_from_slice(&0u32.to_le_bytes());
    let p = write(&dir, "header.glb", &short_header);
    let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
    assert!(msg.contains("header.glb") && msg.contains("header"), "{msg}");
    let mut truncated = glb_triangle(36, 36);
    truncated.truncate(30);
    let p = write(&dir, "trunc.glb", &truncated);
    let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
    assert!(msg.contains("trunc.glb"), "{msg}");
}

#[test]
fn obj_with_out_of_range_indices_is_refused() {
    let dir = scratch("obj");
    let p = write(&dir, "bad.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
    assert!(msg.contains("bad.obj") && msg.contains("out of"), "{msg}");
    let p = write(&dir, "nan.obj", b"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
    assert!(msg.contains("nan.obj"), "{msg}");
    let p = write(&dir, "flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    let msg = message(load_file(&p, GltfObjects::MeshNodes, ObjObjects::File, MeshOptions::default()));
    assert!(msg.contains("flat.obj") && msg.contains("no triangles with non-zero area"), "{msg}");
}

#[test]
fn scene_file_naming_a_missing_mesh_is_refused() {
    let dir = scratch("scene");
    let p = write(&dir, "scene.toml", b"[[object]]\nsource = \"meshes/missing.obj\"\n");
    let msg = message(Scene::load_file(&p));
    assert!(msg.contains("missing.obj") && msg.contains("scene.toml"), "{msg}");
    let p = write(&dir, "env.toml", b"[environment]\nsource = \"sky.hdr\"\n");
    let msg = message(Scene::load_file(&p));
    assert!(msg.contains("sky.hdr") && msg.contains("env.toml"), "{msg}");
}

#[test]
fn cube_folder_problems_are_named() {
    let dir = scratch("cube");
    for f in ["px", "nx", "py", "ny", "pz"] {
        write(&dir, &format!("{f}.hdr"), &rgbe_flat(4, 4, [1.0; 3]));
    }
    let msg = message(load(&dir, InvalidTexels::Reject));
    assert!(msg.contains("'nz'"), "{msg}");
    write(&dir, "nz.hdr", &rgbe_flat(4, 2, [1.0; 3]));
    let msg = message(load(&dir, InvalidTexels::Reject));
    assert!(msg.contains("nz.hdr") && msg.contains("square"), "{msg}");
    write(&dir, "nz.hdr", &rgbe_flat(4, 4, [1.0; 3]));
    let (map, _) = load(&dir, InvalidTexels::Reject).unwrap();
    let p = map.total_power()[0];
    assert!((p - 4.0 * std::f64::consts::PI).abs() < 1e-2, "{p}");
    let msg = message(load(Path::new("image.png"), InvalidTexels::Reject));
    assert!(msg.contains("image.png") && msg.contains("unknown environment map format"), "{msg}");
}

/// Regression (fuzz target `scene_files`): a primitive naming a POSITION accessor that does not
/// exist made gltf-json's validation index out of bounds and panic.
#[test]
fn gltf_naming_a_missing_accessor_is_refused() {
    let text = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[1,0,0],"children":[1]},{"mesh":0,"scale":[2,2,2]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"accessffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}]}"#;
    let msg = message(vcut_scene::loaders::load_gltf_bytes(
        text.as_bytes(),
        None,
        Path::new("fuzz-crash.gltf"),
        GltfObjects::MeshNodes,
        MeshOptions::default(),
    ));
    assert!(msg.contains("fuzz-crash.gltf") && msg.contains("accessor 0"), "{msg}");
}

/// Regression (fuzz target `scene_files`): float indices reached an `unreachable!` in gltf's
/// index reader (the file also has a node that is its own child).
#[test]
fn gltf_with_float_indices_is_refused() {
    let text = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translatioF":[1,0,0],"children":[0]},{"mesh":0,"saale":[2,2,2]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":0}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":43,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}]}"#;
    let msg = message(vcut_scene::loaders::load_gltf_bytes(
        text.as_bytes(),
        None,
        Path::new("fuzz-crash2.gltf"),
        GltfObjects::MeshNodes,
        MeshOptions::default(),
    ));
    assert!(msg.contains("fuzz-crash2.gltf"), "{msg}");
}

/// Regression (fuzz target `scene_files`): a buffer URI that percent-decodes to invalid UTF-8
/// made gltf's buffer import unwrap and panic; we import buffers ourselves.
#[test]
fn gltf_with_a_broken_buffer_uri_is_refused() {
    let bytes: &[u8] = &[
        123, 34, 97, 115, 115, 101, 116, 34, 58, 123, 34, 118, 101, 114, 115, 105, 111, 110, 34, 58, 34, 50, 46, 48,
        34, 125, 44, 34, 115, 34, 58, 91, 123, 34, 98, 117, 104, 34, 58, 54, 125, 93, 44, 34, 98, 117, 102, 102, 101,
        114, 115, 34, 58, 91, 123, 34, 98, 121, 116, 101, 76, 101, 110, 103, 116, 104, 34, 58, 52, 52, 44, 34, 117,
        114, 105, 34, 58, 34, 100, 97, 116, 65, 65, 65, 65, 65, 65, 65, 65, 65, 65, 65, 40, 65, 65, 105, 99, 97, 74,
        83, 79, 78, 111, 116, 111, 105, 110, 37, 99, 65, 73, 65, 65, 65, 65, 61, 34, 125, 93, 125,
    ];
    let msg = message(vcut_scene::loaders::load_gltf_bytes(
        bytes,
        Some(Path::new(".")),
        Path::new("fuzz-crash3.gltf"),
        GltfObjects::MeshNodes,
        MeshOptions::default(),
    ));
    assert!(msg.contains("fuzz-crash3.gltf"), "{msg}");
}

/// Regression (fuzz target `scene_files`): relative OBJ indices pointing before the first
/// element overflowed tobj's index arithmetic; we check indices first and name the line.
#[test]
fn obj_with_a_relative_index_before_the_start_is_refused() {
    let bytes: &[u8] = &[
        118, 127, 32, 48, 32, 48, 32, 48, 10, 118, 32, 49, 32, 48, 32, 48, 10, 116, 32, 48, 32, 34, 115, 112, 97, 114,
        115, 101, 34, 49, 34, 78, 79, 82, 77, 65, 76, 34, 102, 32, 49, 47, 10, 102, 32, 49, 47, 49, 10, 118, 116, 32,
        48, 32, 49, 32, 48, 50, 48, 50, 0, 0, 0, 8, 10, 102, 32, 49, 47, 10, 102, 32, 49, 47, 49, 10, 118, 116, 32, 48,
        32, 49, 32, 48, 50, 44, 111, 32, 49, 47, 10, 103, 32, 49, 47, 49, 10, 118, 116, 32, 48, 49, 32, 48, 50, 32, 91,
        123, 34, 109, 101, 115, 104, 34, 58, 9, 9, 9, 9, 9, 44, 34, 34, 58, 48, 44, 34, 99, 116, 109, 112, 111, 110,
        101, 48, 32, 34, 115, 112, 97, 114, 115, 101, 34, 49, 32, 48, 50, 0, 0, 0, 8, 49, 47, 10, 102, 32, 49, 47, 45,
        53, 10, 13, 13, 13, 13, 13, 13, 13, 13, 13, 13, 13, 9, 13, 13, 13, 13, 13, 13, 13, 13, 13, 13, 13, 13, 53, 32,
        33, 0, 0, 0, 48, 10, 118, 32, 49, 32, 48, 32, 48, 10, 116, 32, 48, 32, 34, 115, 112, 97, 114, 115, 101, 34, 49,
        32, 48, 50, 0, 0, 0, 8, 10, 102, 32, 49, 47, 10, 102, 32, 49, 47, 49, 10, 118, 116, 32, 48, 32, 49, 32, 48, 50,
        44, 102, 13, 32, 50, 32,
    ];
    let msg = message(vcut_scene::loaders::load_obj_bytes(
        bytes,
        Path::new("fuzz-crash4.obj"),
        ObjObjects::Groups,
        MeshOptions::default(),
    ));
    assert!(msg.contains("fuzz-crash4.obj") && msg.contains("line "), "{msg}");
}

/// Regression (fuzz target `scene_files`): an accessor with `count: 0` overflowed gltf's
/// `count - 1`.
#[test]
fn gltf_with_an_empty_accessor_is_refused() {
    let text = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[1,0,0],"=hildren":[1]},{"mesh":0,"scale":[2,2,2]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},{"bufferView":1,"componentType":5123,"count":0,"type":"SCALAR"}],"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}]}"#;
    let msg = message(vcut_scene::loaders::load_gltf_bytes(
        text.as_bytes(),
        None,
        Path::new("fuzz-crash5.gltf"),
        GltfObjects::MeshNodes,
        MeshOptions::default(),
    ));
    assert!(msg.contains("fuzz-crash5.gltf") && msg.contains("accessor 1"), "{msg}");
}

/// Regression (fuzz target `exr`): a 690-byte EXR whose header promised 189 GB made the decoder
/// abort on allocation; headers are now checked against the file size first.
#[test]
fn exr_promising_more_pixels_than_it_holds_is_refused() {
    let bytes: &[u8] = &[
        118, 47, 49, 1, 2, 2, 0, 0, 99, 178, 117, 110, 107, 33, 111, 117, 110, 116, 0, 105, 110, 116, 0, 4, 0, 0, 0, 1,
        0, 0, 0, 99, 104, 97, 110, 110, 101, 108, 115, 0, 99, 104, 108, 105, 115, 116, 0, 55, 0, 0, 0, 66, 0, 2, 0, 0,
        0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 71, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 82, 0, 2, 0, 0,
        0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 99, 111, 109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 99, 111,
        109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 1, 0, 0, 0, 1, 108, 105, 110, 101, 79, 114, 100, 101, 114, 0,
        108, 105, 110, 101, 79, 114, 100, 101, 114, 0, 1, 0, 0, 0, 2, 100, 105, 115, 112, 108, 97, 121, 87, 105, 110,
        100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 3, 0, 0, 0, 112,
        105, 120, 101, 108, 65, 115, 112, 101, 99, 116, 82, 97, 116, 105, 111, 0, 102, 108, 111, 97, 116, 0, 4, 0, 0,
        0, 0, 0, 128, 63, 115, 99, 114, 101, 101, 110, 87, 105, 110, 100, 111, 119, 67, 101, 110, 116, 101, 114, 0,
        118, 50, 102, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 115, 99, 114, 101, 101, 110, 87, 105, 110, 100, 111, 119,
        87, 105, 100, 116, 104, 0, 102, 108, 111, 97, 116, 0, 4, 0, 0, 0, 0, 0, 128, 63, 100, 97, 116, 97, 87, 105,
        110, 100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 6, 0, 0, 0, 0, 255, 253, 128, 0, 0, 0, 3, 0,
        0, 0, 116, 121, 112, 101, 0, 115, 116, 114, 105, 110, 103, 0, 10, 0, 0, 0, 116, 105, 108, 101, 100, 105, 109,
        97, 103, 101, 116, 105, 108, 101, 115, 0, 116, 105, 108, 101, 100, 101, 115, 99, 0, 9, 0, 0, 0, 64, 0, 0, 0,
        64, 0, 0, 0, 0, 0, 142, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 218, 0, 128, 0, 0, 0, 0, 0, 4, 0, 0, 0, 1, 0, 0, 0,
        99, 104, 97, 110, 110, 101, 108, 115, 0, 99, 104, 108, 105, 115, 154, 0, 55, 0, 0, 0, 66, 0, 2, 0, 0, 0, 0, 0,
        0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 71, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 82, 0, 2, 0, 0, 0, 0, 0,
        0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 163, 144, 146, 143, 141, 154, 140, 140, 105, 111, 110, 0, 99, 111, 109, 112,
        114, 101, 115, 115, 105, 111, 110, 0, 1, 0, 0, 0, 1, 108, 105, 110, 101, 79, 114, 100, 101, 114, 0, 108, 105,
        110, 101, 79, 114, 100, 101, 110, 116, 0, 4, 0, 0, 0, 1, 0, 0, 0, 99, 104, 97, 110, 110, 101, 108, 115, 104,
        99, 0, 115, 105, 108, 154, 0, 55, 0, 0, 0, 66, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 71, 0, 2, 0,
        0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 82, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 163, 144,
        146, 143, 141, 154, 140, 140, 105, 111, 110, 0, 99, 111, 109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 1, 0,
        0, 0, 1, 108, 105, 110, 101, 79, 114, 100, 101, 114, 0, 108, 105, 110, 121, 87, 105, 110, 100, 191, 218, 39,
        64, 192, 166, 90, 12, 244, 115, 141, 217, 39, 64, 192, 166, 90,
    ];
    let msg = message(vcut_envmap::load_bytes(
        bytes,
        vcut_envmap::io::Format::Exr,
        Path::new("fuzz-crash6.exr"),
        InvalidTexels::Clamp,
    ));
    assert!(msg.contains("fuzz-crash6.exr"), "{msg}");
}

/// Regression (fuzz target `exr`): a single-level tiled EXR with a chunk claiming mip level
/// (2, 0) reached an assertion in exr's level filtering (debug builds); it is contained.
#[test]
fn exr_chunk_at_a_missing_level_is_refused() {
    let bytes: &[u8] = &[
        118, 47, 49, 1, 2, 2, 0, 0, 99, 104, 117, 110, 107, 67, 111, 117, 110, 116, 0, 105, 110, 116, 0, 4, 0, 0, 0, 1,
        0, 0, 0, 99, 104, 97, 110, 110, 101, 108, 115, 0, 99, 104, 108, 105, 115, 116, 0, 55, 0, 0, 0, 66, 0, 2, 0, 0,
        0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 71, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 82, 0, 2, 0, 0,
        0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 99, 111, 109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 99, 111,
        109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 1, 0, 0, 0, 9, 108, 105, 110, 101, 79, 114, 100, 101, 114, 0,
        108, 105, 110, 101, 79, 114, 100, 101, 114, 0, 1, 0, 0, 0, 2, 100, 105, 115, 112, 108, 97, 121, 87, 105, 110,
        100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 3, 0, 0, 0, 112,
        105, 120, 101, 108, 65, 115, 112, 101, 99, 116, 82, 97, 116, 105, 111, 0, 102, 108, 128, 77, 30, 128, 239, 77,
        111, 97, 116, 0, 4, 0, 0, 0, 0, 0, 128, 63, 115, 99, 114, 101, 101, 110, 87, 105, 110, 100, 111, 119, 67, 101,
        110, 116, 101, 114, 0, 118, 50, 102, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 115, 99, 114, 101, 101, 110, 87,
        105, 110, 100, 111, 119, 87, 105, 100, 116, 104, 0, 102, 108, 111, 97, 116, 0, 4, 0, 0, 0, 0, 0, 128, 63, 100,
        97, 116, 97, 87, 105, 110, 100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7,
        0, 0, 0, 3, 0, 0, 0, 116, 121, 112, 101, 0, 115, 116, 114, 105, 110, 103, 0, 10, 0, 0, 0, 116, 105, 108, 101,
        100, 105, 109, 97, 103, 101, 116, 105, 108, 101, 115, 0, 116, 105, 108, 101, 100, 101, 115, 99, 0, 9, 0, 0, 0,
        64, 0, 0, 0, 64, 0, 0, 0, 0, 0, 142, 1, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16,
        1, 0, 0, 0, 0, 0, 0, 255, 0, 32, 128, 241, 77, 127, 129, 255, 118, 47, 49, 206, 1, 2, 2, 0, 0, 127, 180,
    ];
    // In debug builds the exr decoder panics on this input (integer overflow checks), which
    // we contain and report; release builds wrap and decode something. Either way: no panic
    // escapes, and what comes back is an error naming the file or a valid map.
    match vcut_envmap::load_bytes(
        bytes,
        vcut_envmap::io::Format::Exr,
        Path::new("fuzz-crash7.exr"),
        InvalidTexels::Clamp,
    ) {
        Err(e) => assert!(e.to_string().contains("fuzz-crash7.exr"), "{e}"),
        Ok((map, _)) => assert!(map.texels().iter().flatten().all(|x| x.is_finite() && *x >= 0.0)),
    }
}

/// Regression (fuzz target `exr`, found by CI): a panic inside exr's parallel block decoder aborted
/// the process from a rayon worker; decoding is now sequential, so the panic is contained.
#[test]
fn exr_fuzz_crash_8_is_refused() {
    let bytes: &[u8] = &[
        118, 47, 49, 1, 2, 2, 0, 0, 99, 104, 117, 110, 107, 67, 111, 117, 110, 116, 0, 105, 110, 116, 0, 4, 0, 0, 0, 1,
        0, 0, 0, 99, 104, 97, 110, 110, 101, 108, 115, 0, 99, 104, 108, 105, 115, 116, 0, 55, 0, 0, 0, 66, 0, 2, 0, 0,
        0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 71, 0, 2, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 82, 0, 1, 0, 0,
        0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 99, 111, 109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 99, 111,
        109, 112, 114, 101, 115, 115, 105, 111, 110, 0, 1, 0, 0, 0, 7, 148, 150, 145, 154, 176, 141, 155, 101, 114, 0,
        108, 105, 110, 101, 79, 114, 100, 101, 114, 0, 1, 0, 0, 0, 2, 100, 105, 115, 112, 108, 97, 121, 87, 105, 110,
        100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 3, 0, 0, 0, 112,
        105, 120, 101, 108, 65, 115, 112, 101, 99, 116, 82, 97, 116, 105, 111, 0, 102, 108, 111, 97, 116, 0, 4, 0, 0,
        0, 0, 0, 128, 63, 115, 99, 114, 101, 101, 110, 87, 105, 110, 100, 108, 119, 67, 101, 110, 116, 101, 114, 0,
        118, 50, 102, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 115, 99, 114, 101, 101, 110, 87, 105, 110, 100, 111, 119,
        87, 105, 100, 116, 104, 0, 102, 108, 111, 97, 116, 0, 4, 0, 0, 0, 0, 0, 128, 63, 100, 97, 116, 97, 87, 105,
        110, 100, 111, 119, 0, 98, 111, 120, 50, 105, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 7, 0, 0, 0, 3, 0, 0, 0,
        116, 121, 112, 101, 0, 115, 116, 114, 105, 110, 103, 0, 10, 0, 0, 0, 116, 105, 108, 101, 100, 105, 109, 97,
        103, 101, 116, 105, 108, 101, 115, 0, 116, 105, 108, 101, 100, 101, 115, 99, 0, 9, 0, 0, 0, 64, 0, 64, 0, 64,
        0, 0, 0, 0, 0, 142, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 16, 1, 0, 0, 255, 0,
        32, 128, 241, 77, 127, 129, 255, 206, 127, 180, 127, 180, 128, 26, 255, 154, 128, 77, 30, 128, 239, 77, 255,
        155, 127, 26, 0, 205, 63, 142, 127, 78, 191, 13, 0, 205, 64, 192, 30, 128, 239, 77, 127, 78, 191, 14, 255, 205,
        64, 141, 128, 231, 31, 71, 191, 167, 96, 109, 30, 128, 129, 26, 255, 103, 160, 199, 63, 39, 223, 135, 128, 231,
        31, 71, 192, 167, 95, 58, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 191, 65, 191,
        65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 128, 76, 241, 15, 242, 14, 219, 37, 242, 66, 191,
        218, 38, 116, 140, 65, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 191, 65, 191,
        65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 13, 243, 167, 89, 65, 191, 13, 243, 218, 38, 167, 89,
        116, 140, 65, 191, 65, 192, 64, 192, 64, 192, 64, 192, 64, 91, 192, 64, 192, 64, 192, 64, 175, 192, 64, 191,
        65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 13, 243, 218, 38, 167, 89, 116, 140, 65, 192,
        166, 90, 12, 244, 115, 141, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 192, 64, 191,
        65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 65, 191, 218, 39, 64, 192, 166, 90, 12, 244, 115, 141,
        217, 39, 64, 192, 166, 90,
    ];
    let result = vcut_envmap::load_bytes(
        bytes,
        vcut_envmap::io::Format::Exr,
        Path::new("fuzz-crash8.exr"),
        InvalidTexels::Clamp,
    );
    if let Err(e) = result {
        assert!(e.to_string().contains("fuzz-crash8.exr"), "{e}");
    }
}
