//! Fuzz target: glTF/GLB and OBJ loading from arbitrary bytes (the first byte picks the format)
//! must return an object list or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use vcut_scene::MeshOptions;
use vcut_scene::loaders::{GltfObjects, ObjObjects, load_gltf_bytes, load_obj_bytes};

fuzz_target!(|data: &[u8]| {
    let Some((&which, rest)) = data.split_first() else { return };
    let options = MeshOptions::default();
    match which % 3 {
        0 => {
            if let Ok(out) = load_gltf_bytes(rest, None, Path::new("fuzz.glb"), GltfObjects::MeshNodes, options) {
                for o in &out.objects {
                    assert!(o.mesh.validate().is_ok());
                }
            }
        }
        1 => {
            let _ = load_gltf_bytes(rest, None, Path::new("fuzz.gltf"), GltfObjects::TopLevelNodes, options);
        }
        _ => {
            if let Ok(out) = load_obj_bytes(rest, Path::new("fuzz.obj"), ObjObjects::Groups, options) {
                for o in &out.objects {
                    assert!(o.mesh.validate().is_ok());
                }
            }
        }
    }
});
