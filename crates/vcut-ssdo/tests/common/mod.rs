//! Shared by this crate's tests.

use glam::Vec3;
use vcut_ssdo::Object;

/// A rectangle from `corner` spanned by `u` and `v`, split into `n × n` cells, normal `u × v`.
pub fn rect(corner: Vec3, u: Vec3, v: Vec3, n: u32, albedo: Vec3) -> Object {
    let normal = u.cross(v).normalize();
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(corner + u * (i as f32 / n as f32) + v * (j as f32 / n as f32));
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            triangles.push([a, a + 1, a + n + 2]);
            triangles.push([a, a + n + 2, a + n + 1]);
        }
    }
    Object { normals: vec![normal; positions.len()], positions, triangles, albedo }
}
