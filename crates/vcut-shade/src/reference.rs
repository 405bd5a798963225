//! The exact-direction reference: per vertex, all N leaf directions cast against the true
//! geometry of every object at its current position, no clustering and no fields:
//! B = Σ_l V(x, ω_l) max(0, n·ω_l) f_r(ω_l, ω_o) L_l, with L_l the light tree's leaf l. Against
//! it, a frame's error is the cut error alone (clustering, field interpolation, quantisation).
//! Ray origins are offset along the normal exactly as the SVCs were.

use crate::brdf;
use crate::frame::Frame;
use glam::Vec3;
use rayon::prelude::*;
use vcut_precompute::Occluder;
use vcut_scene::Mesh;

/// Outgoing radiance toward `eye` of every vertex, by casting every leaf direction.
/// `origin_offset` is the SVCs' (a fraction of each object's bounding radius).
pub fn exact_direction(frame: &Frame, eye: Vec3, origin_offset: f32) -> Vec<Vec<Vec3>> {
    let moved: Vec<Mesh> = (0..frame.object_count())
        .map(|o| {
            let (_, mesh, _, _, _) = frame.object(o);
            Mesh::from_valid_parts(frame.positions(o), mesh.normals().to_vec(), mesh.triangles().to_vec())
                .unwrap_or_else(|e| unreachable!("a translated valid mesh stays valid: {e}"))
        })
        .collect();
    let occ = Occluder::new(&moved.iter().collect::<Vec<_>>());
    let tree = frame.tree();
    let leaves = tree.leaf_directions();
    let light = frame.light().leaves();
    (0..frame.object_count())
        .map(|o| {
            let (_, mesh, material, _, _) = frame.object(o);
            let offset = origin_offset * mesh.bounds().radius.max(f32::MIN_POSITIVE);
            let positions = frame.positions(o);
            positions
                .par_iter()
                .zip(mesh.normals().par_iter())
                .map(|(&x, &n)| {
                    let wo = (eye - x).normalize_or_zero();
                    let origin = x + n * offset;
                    let mut b = Vec3::ZERO;
                    for (l, &d) in leaves.iter().enumerate() {
                        let c = n.dot(d);
                        if c <= 0.0 || occ.occluded(origin, d, f32::INFINITY) {
                            continue;
                        }
                        let li = light[l];
                        b += c * brdf::eval(material, n, d, wo) * Vec3::new(li[0] as f32, li[1] as f32, li[2] as f32);
                    }
                    b
                })
                .collect()
        })
        .collect()
}

/// Relative L2 error of `got` against `reference` over all vertices and channels, and the
/// largest per-vertex error relative to the reference's mean radiance.
pub fn errors(got: &[Vec<Vec3>], reference: &[Vec<Vec3>]) -> (f64, f64) {
    let (mut num, mut den, mut sum, mut count, mut worst) = (0.0f64, 0.0f64, 0.0f64, 0usize, 0.0f64);
    for (g, r) in got.iter().zip(reference) {
        for (a, b) in g.iter().zip(r) {
            let d = (*a - *b).as_dvec3();
            num += d.length_squared();
            den += b.as_dvec3().length_squared();
            sum += b.as_dvec3().length();
            count += 1;
            worst = worst.max(d.length());
        }
    }
    let mean = sum / count.max(1) as f64;
    ((num / den.max(1e-300)).sqrt(), worst / mean.max(1e-300))
}
