//! The Utah teapot (Newell, 1975) tessellated from its 32 bicubic Bézier patches.
//!
//! The control-point data is the classic 127-point, 10-patch set; the other 22 patches are mirror
//! images (rim, body, lid and bottom in x and y; handle and spout in y only). Data axes are z-up
//! with the spout along +x; we return it y-up (`(x, y, z) → (x, z, −y)`), standing on y = 0, in
//! the data's units (3.15 tall, about 6.4 long spout tip to handle).
//!
//! Shared patch edges are welded exactly by position, so the pot is one connected surface whose
//! normals are area-weighted across patch seams. The pot is not watertight — the lid and the body
//! leave the classic ring-shaped gap at the rim, and the handle and spout pierce the body — which
//! is what real scenes look like to a ray caster.

use crate::mesh::{Mesh, MeshError, MeshOptions, MeshReport, RecomputeNormals, Weld};
use glam::Vec3;

/// Control-point indices of the ten stored patches (row-major 4×4).
const PATCHES: [[usize; 16]; 10] = [
    [102, 103, 104, 105, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
    [12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27],
    [24, 25, 26, 27, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40],
    [96, 96, 96, 96, 97, 98, 99, 100, 101, 101, 101, 101, 0, 1, 2, 3],
    [0, 1, 2, 3, 106, 107, 108, 109, 110, 111, 112, 113, 114, 115, 116, 117],
    [118, 118, 118, 118, 124, 122, 119, 121, 123, 126, 125, 120, 40, 39, 38, 37],
    [41, 42, 43, 44, 45, 46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56],
    [53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63, 64, 28, 65, 66, 67],
    [68, 69, 70, 71, 72, 73, 74, 75, 76, 77, 78, 79, 80, 81, 82, 83],
    [80, 81, 82, 83, 84, 85, 86, 87, 88, 89, 90, 91, 92, 93, 94, 95],
];

/// The first six patches (rim, body, lid, bottom) are mirrored in both x and y.
const FOUR_WAY: usize = 6;

#[rustfmt::skip]
const POINTS: [[f32; 3]; 127] = [
    [0.2, 0.0, 2.7], [0.2, -0.112, 2.7], [0.112, -0.2, 2.7], [0.0, -0.2, 2.7],
    [1.3375, 0.0, 2.53125], [1.3375, -0.749, 2.53125], [0.749, -1.3375, 2.53125],
    [0.0, -1.3375, 2.53125], [1.4375, 0.0, 2.53125], [1.4375, -0.805, 2.53125],
    [0.805, -1.4375, 2.53125], [0.0, -1.4375, 2.53125], [1.5, 0.0, 2.4],
    [1.5, -0.84, 2.4], [0.84, -1.5, 2.4], [0.0, -1.5, 2.4], [1.75, 0.0, 1.875],
    [1.75, -0.98, 1.875], [0.98, -1.75, 1.875], [0.0, -1.75, 1.875],
    [2.0, 0.0, 1.35], [2.0, -1.12, 1.35], [1.12, -2.0, 1.35], [0.0, -2.0, 1.35],
    [2.0, 0.0, 0.9], [2.0, -1.12, 0.9], [1.12, -2.0, 0.9], [0.0, -2.0, 0.9],
    [-2.0, 0.0, 0.9], [2.0, 0.0, 0.45], [2.0, -1.12, 0.45], [1.12, -2.0, 0.45],
    [0.0, -2.0, 0.45], [1.5, 0.0, 0.225], [1.5, -0.84, 0.225], [0.84, -1.5, 0.225],
    [0.0, -1.5, 0.225], [1.5, 0.0, 0.15], [1.5, -0.84, 0.15], [0.84, -1.5, 0.15],
    [0.0, -1.5, 0.15], [-1.6, 0.0, 2.025], [-1.6, -0.3, 2.025], [-1.5, -0.3, 2.25],
    [-1.5, 0.0, 2.25], [-2.3, 0.0, 2.025], [-2.3, -0.3, 2.025], [-2.5, -0.3, 2.25],
    [-2.5, 0.0, 2.25], [-2.7, 0.0, 2.025], [-2.7, -0.3, 2.025], [-3.0, -0.3, 2.25],
    [-3.0, 0.0, 2.25], [-2.7, 0.0, 1.8], [-2.7, -0.3, 1.8], [-3.0, -0.3, 1.8],
    [-3.0, 0.0, 1.8], [-2.7, 0.0, 1.575], [-2.7, -0.3, 1.575], [-3.0, -0.3, 1.35],
    [-3.0, 0.0, 1.35], [-2.5, 0.0, 1.125], [-2.5, -0.3, 1.125], [-2.65, -0.3, 0.9375],
    [-2.65, 0.0, 0.9375], [-2.0, -0.3, 0.9], [-1.9, -0.3, 0.6], [-1.9, 0.0, 0.6],
    [1.7, 0.0, 1.425], [1.7, -0.66, 1.425], [1.7, -0.66, 0.6], [1.7, 0.0, 0.6],
    [2.6, 0.0, 1.425], [2.6, -0.66, 1.425], [3.1, -0.66, 0.825], [3.1, 0.0, 0.825],
    [2.3, 0.0, 2.1], [2.3, -0.25, 2.1], [2.4, -0.25, 2.025], [2.4, 0.0, 2.025],
    [2.7, 0.0, 2.4], [2.7, -0.25, 2.4], [3.3, -0.25, 2.4], [3.3, 0.0, 2.4],
    [2.8, 0.0, 2.475], [2.8, -0.25, 2.475], [3.525, -0.25, 2.49375],
    [3.525, 0.0, 2.49375], [2.9, 0.0, 2.475], [2.9, -0.15, 2.475],
    [3.45, -0.15, 2.5125], [3.45, 0.0, 2.5125], [2.8, 0.0, 2.4], [2.8, -0.15, 2.4],
    [3.2, -0.15, 2.4], [3.2, 0.0, 2.4], [0.0, 0.0, 3.15], [0.8, 0.0, 3.15],
    [0.8, -0.45, 3.15], [0.45, -0.8, 3.15], [0.0, -0.8, 3.15], [0.0, 0.0, 2.85],
    [1.4, 0.0, 2.4], [1.4, -0.784, 2.4], [0.784, -1.4, 2.4], [0.0, -1.4, 2.4],
    [0.4, 0.0, 2.55], [0.4, -0.224, 2.55], [0.224, -0.4, 2.55], [0.0, -0.4, 2.55],
    [1.3, 0.0, 2.55], [1.3, -0.728, 2.55], [0.728, -1.3, 2.55], [0.0, -1.3, 2.55],
    [1.3, 0.0, 2.4], [1.3, -0.728, 2.4], [0.728, -1.3, 2.4], [0.0, -1.3, 2.4],
    [0.0, 0.0, 0.0], [1.425, -0.798, 0.0], [1.5, 0.0, 0.075], [1.425, 0.0, 0.0],
    [0.798, -1.425, 0.0], [0.0, -1.5, 0.075], [0.0, -1.425, 0.0],
    [1.5, -0.84, 0.075], [0.84, -1.5, 0.075],
];

/// The 32 patches as 4×4 control-point grids in data space, orientation-consistent (a mirrored
/// copy has its columns reversed so its faces still point out).
pub fn patches() -> Vec<[Vec3; 16]> {
    let mut out = Vec::with_capacity(32);
    let get = |p: usize, j: usize, k: usize| Vec3::from(POINTS[PATCHES[p][j * 4 + k]]);
    for p in 0..PATCHES.len() {
        let mut variants: Vec<(Vec3, bool)> = vec![(Vec3::ONE, false), (Vec3::new(1.0, -1.0, 1.0), true)];
        if p < FOUR_WAY {
            variants.push((Vec3::new(-1.0, 1.0, 1.0), true));
            variants.push((Vec3::new(-1.0, -1.0, 1.0), false));
        }
        for (scale, reverse) in variants {
            let mut cp = [Vec3::ZERO; 16];
            for j in 0..4 {
                for k in 0..4 {
                    let kk = if reverse { 3 - k } else { k };
                    cp[j * 4 + k] = get(p, j, kk) * scale;
                }
            }
            out.push(cp);
        }
    }
    out
}

fn bernstein(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

fn eval(cp: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    let (bu, bv) = (bernstein(u), bernstein(v));
    let mut p = Vec3::ZERO;
    for j in 0..4 {
        for k in 0..4 {
            p += cp[j * 4 + k] * (bu[j] * bv[k]);
        }
    }
    p
}

/// The teapot with `n × n` quads (2n² triangles) per patch, before welding and before dropping
/// the zero-area triangles at the lid's and bottom's poles.
pub fn teapot(n: u32) -> Result<(Mesh, MeshReport), MeshError> {
    let n = n.max(1);
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for cp in patches() {
        let base = positions.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let p = eval(&cp, i as f32 / n as f32, j as f32 / n as f32);
                // z-up data to y-up world.
                positions.push(Vec3::new(p.x, p.z, -p.y));
            }
        }
        let at = |i: u32, j: u32| base + i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                // The patches' (u, v) orientation makes (i,j)→(i,j+1)→(i+1,j+1) counter-clockwise
                // seen from outside after the axis swap (checked by a test).
                triangles.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
                triangles.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            }
        }
    }
    // Evaluating shared edges from different patches can differ in the last bit; snap within a
    // tolerance far below the tessellation spacing.
    let options = MeshOptions { weld: Weld::Within(1e-4), recompute_normals: RecomputeNormals::Always };
    Mesh::build(positions, None, triangles, options)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn teapot_has_32_patches_and_faces_outwards() {
        assert_eq!(patches().len(), 32);
        let (m, r) = teapot(8).unwrap();
        m.validate().unwrap();
        assert!(r.vertices_welded > 0);
        assert!(r.degenerate_triangles_dropped > 0, "the poles of lid and bottom collapse");
        let b = m.bounds();
        assert!((b.max.y - 3.15).abs() < 1e-3 && b.min.y.abs() < 1e-3, "{b:?}");
        // Faces point outwards: on the body (away from handle/spout), the face normal points away
        // from the vertical axis.
        let mut outward = 0;
        let mut total = 0;
        for t in m.triangles() {
            let [a, bb, c] = t.map(|i| m.positions()[i as usize]);
            let centre = (a + bb + c) / 3.0;
            let radial = Vec3::new(centre.x, 0.0, centre.z);
            if centre.y > 0.5 && centre.y < 2.0 && radial.length() > 1.7 && centre.x.abs() < 1.2 {
                total += 1;
                if (bb - a).cross(c - a).dot(radial) > 0.0 {
                    outward += 1;
                }
            }
        }
        assert!(total > 20 && outward == total, "{outward}/{total}");
        // Vertex normals agree with face orientation.
        let agree = m.triangles().iter().filter(|t| {
            let [a, bb, c] = t.map(|i| m.positions()[i as usize]);
            (bb - a).cross(c - a).dot(m.normals()[t[0] as usize]) > 0.0
        });
        assert!(agree.count() as f64 > 0.97 * m.triangle_count() as f64);
    }
}
