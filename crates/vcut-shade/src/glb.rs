//! The scene as a binary glTF 2.0 file (`.glb`) with its shading baked per vertex, for Blender,
//! three.js and any glTF viewer.
//!
//! One node per object (its translation now, its mesh at rest), each mesh with `POSITION`,
//! `NORMAL`, `COLOR_0` — the radiance tone-mapped as the PNG is (exposure, then ACES filmic)
//! but left linear, so a viewer's sRGB output shows the render's colours — and `_RADIANCE`, the
//! linear outgoing radiance itself (an application-specific attribute, ignored by viewers);
//! a `KHR_materials_unlit` material (white), so viewers show the baked colour without
//! lighting it again; and the camera the image was rendered from, as the first camera.

use crate::frame::Frame;
use crate::image::{ImageError, aces, write_file};
use glam::{Quat, Vec3};
use serde_json::{Value, json};
use std::path::Path;
use vcut_scene::Camera;

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// The binary buffer and the JSON lists that index into it.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends `values` as one buffer view and accessor; returns the accessor's index.
    fn vec3(&mut self, values: &[Vec3], bounds: bool) -> usize {
        let offset = self.bin.len();
        for v in values {
            for x in v.to_array() {
                self.bin.extend_from_slice(&x.to_le_bytes());
            }
        }
        let mut accessor = json!({
            "bufferView": self.view(offset, ARRAY_BUFFER), "componentType": FLOAT,
            "count": values.len(), "type": "VEC3",
        });
        if bounds {
            let (lo, hi) = values
                .iter()
                .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            accessor["min"] = json!(lo.to_array());
            accessor["max"] = json!(hi.to_array());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn indices(&mut self, triangles: &[[u32; 3]]) -> usize {
        let offset = self.bin.len();
        for i in triangles.iter().flatten() {
            self.bin.extend_from_slice(&i.to_le_bytes());
        }
        let view = self.view(offset, ELEMENT_ARRAY_BUFFER);
        self.accessors.push(json!({
            "bufferView": view, "componentType": UNSIGNED_INT, "count": triangles.len() * 3, "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    /// The bytes from `offset` to the end as a buffer view; pads the buffer to 4 bytes.
    fn view(&mut self, offset: usize, target: u32) -> usize {
        let length = self.bin.len() - offset;
        self.views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": length, "target": target }));
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.len() - 1
    }
}

/// Writes `frame`'s objects at their current positions with `radiance` (per object, per vertex:
/// give it [`Frame::shade_all`]'s, so every vertex is shaded) baked as described above, tone-
/// mapped with `exposure`, and `camera` at `aspect` (width / height), as a `.glb` file,
/// atomically.
pub fn write_glb(
    frame: &Frame,
    radiance: &[Vec<Vec3>],
    camera: &Camera,
    aspect: f32,
    exposure: f32,
    path: &Path,
) -> Result<(), ImageError> {
    let mut b = Builder::default();
    let (mut meshes, mut nodes) = (Vec::new(), Vec::new());
    for (o, rad) in radiance.iter().enumerate().take(frame.object_count()) {
        let object = frame.object(o);
        let colour: Vec<Vec3> = rad.iter().map(|c| Vec3::from(c.to_array().map(|x| aces(x, exposure)))).collect();
        let attributes = json!({
            "POSITION": b.vec3(object.mesh.positions(), true),
            "NORMAL": b.vec3(object.mesh.normals(), false),
            "COLOR_0": b.vec3(&colour, false),
            "_RADIANCE": b.vec3(rad, false),
        });
        let indices = b.indices(object.mesh.triangles());
        meshes.push(json!({ "name": object.name, "primitives": [{ "attributes": attributes, "indices": indices, "material": 0 }] }));
        nodes.push(json!({ "name": object.name, "mesh": o, "translation": object.translation.to_array() }));
    }
    // glTF cameras look down their −Z with +Y up: the inverse of the view matrix, as a rotation.
    let to_world = glam::camera::rh::view::look_at_mat4(camera.position, camera.target, camera.up).inverse();
    let (_, rotation, _) = to_world.to_scale_rotation_translation();
    let rotation = if rotation.is_finite() { rotation.normalize() } else { Quat::IDENTITY };
    nodes.push(json!({
        "name": camera.name, "camera": 0,
        "translation": camera.position.to_array(), "rotation": rotation.to_array(),
    }));
    let json = json!({
        "asset": { "version": "2.0", "generator": concat!("vcuts ", env!("CARGO_PKG_VERSION")) },
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [{
            "name": "baked radiance",
            "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0 },
            "extensions": { "KHR_materials_unlit": {} },
        }],
        "cameras": [{ "type": "perspective", "perspective": {
            "yfov": camera.fov_y_deg.to_radians(), "aspectRatio": aspect, "znear": 0.01, "zfar": 1.0e4,
        }}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{ "byteLength": b.bin.len() }],
    });
    let mut text =
        serde_json::to_vec(&json).map_err(|e| ImageError::Write { path: path.into(), reason: e.to_string() })?;
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + b.bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(&(b.bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b.bin);
    write_file(path, &out)
}
