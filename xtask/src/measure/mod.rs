//! What the bench measures beyond a scene's Table 1 row, each a section of `report.json`: the
//! accuracy under every map (`accuracy`), how every cost grows with objects and vertices
//! (`scaling`), drags in dense assemblies against the same objects apart (`assembly`), a
//! precompute whole and sharded (`distributed`), objects turning (`turns`), and the machine
//! itself (`machine`).

pub mod accuracy;
pub mod assembly;
pub mod distributed;
pub mod machine;
pub mod scaling;
pub mod turns;

use glam::Vec3;
use rayon::prelude::*;
use vcut_scene::Motion;
use vcut_shade::Frame;
use vcut_shade::reference::{ExactReference, relative_errors};

/// A scene's frame opened from its precomputed file, facing its first camera.
pub struct OpenedFrame {
    /// The frame, every vertex merged.
    pub frame: Frame,
    /// The scene's first camera's position.
    pub eye: Vec3,
    /// The SVCs' ray offset (what the exact reference starts its rays with).
    pub offset: f32,
}

/// Opens `file` (`scene` precomputed) under the default settings, or with eager merges (every
/// changed vertex merged at once, so that a step's time is the whole move's), facing `scene`'s
/// first camera.
pub fn open_frame(scene: &str, file: &std::path::Path, eager: bool) -> anyhow::Result<OpenedFrame> {
    use anyhow::Context;
    let opened = vcut_scene::Scene::open(scene)?;
    let eye = opened.cameras.first().map(|c| c.position).context("the scene has no camera")?;
    let mut data = vcut_data::Precomputed::open(file)?;
    let offset = data.svc_origin_offset();
    let settings = vcut_shade::FrameSettings { deferred_merges: !eager, ..vcut_shade::FrameSettings::default() };
    let frame = Frame::open(&mut data, &opened.environment, &settings, Some(eye))?;
    Ok(OpenedFrame { frame, eye, offset })
}

/// The movable object nearest the movable objects' centre (by bounding-box centres at rest).
pub fn central_movable(frame: &Frame) -> Option<usize> {
    let movers: Vec<(usize, Vec3)> = (0..frame.object_count())
        .filter(|&o| frame.object(o).motion == Motion::Movable)
        .map(|o| (o, frame.object(o).mesh.bounds().center))
        .collect();
    let centre = movers.iter().map(|m| m.1).sum::<Vec3>() / movers.len().max(1) as f32;
    movers.iter().min_by(|a, b| (a.1 - centre).length().total_cmp(&(b.1 - centre).length())).map(|m| m.0)
}

/// Relative L2 of `shaded` (the frame's radiance from `eye`, per object and vertex) against
/// the exact-direction reference at the frame's translations, over every k-th vertex of the
/// scene, k chosen for about `count` of them; returns it and the vertices compared.
pub fn exact_error(frame: &Frame, origin_offset: f32, eye: Vec3, shaded: &[Vec<Vec3>], count: usize) -> (f64, usize) {
    let vertices: usize = (0..frame.object_count()).map(|o| frame.object(o).mesh.vertex_count()).sum();
    let reference = ExactReference::new(frame, origin_offset);
    let subset: Vec<(usize, usize)> = (0..frame.object_count())
        .flat_map(|o| (0..frame.object(o).mesh.vertex_count()).map(move |v| (o, v)))
        .step_by(vertices.div_ceil(count).max(1))
        .collect();
    let pairs: Vec<(Vec3, Vec3)> = subset
        .par_iter()
        .map(|&(o, v)| {
            let x = frame.object(o).mesh.positions()[v] + frame.object(o).translation;
            (shaded[o][v], reference.vertex(frame, o, v, x, eye))
        })
        .collect();
    (relative_errors(pairs.into_iter()).0, subset.len())
}
