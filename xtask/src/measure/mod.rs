//! What the bench measures beyond a scene's Table 1 row, each a section of `report.json`: the
//! accuracy under every map (`accuracy`), how every cost grows with objects and vertices
//! (`scaling`), drags in dense assemblies against the same objects apart (`assembly`), a precompute whole and sharded (`distributed`), and the machine itself
//! (`machine`).

pub mod accuracy;
pub mod assembly;
pub mod distributed;
pub mod machine;
pub mod scaling;

use glam::Vec3;
use rayon::prelude::*;
use vcut_scene::Motion;
use vcut_shade::Frame;
use vcut_shade::reference::{ExactReference, relative_errors};

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
