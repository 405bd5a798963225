//! Procedural shapes: sphere, torus, box and ground plane, with analytic normals, all
//! counter-clockwise seen from outside, centred on the origin (the plane lies in y = 0 facing +Y).

use crate::mesh::{Mesh, MeshError, MeshOptions, Weld};
use glam::Vec3;
use std::f32::consts::{PI, TAU};

fn build(p: Vec<Vec3>, n: Vec<Vec3>, t: Vec<[u32; 3]>, weld: Weld) -> Result<Mesh, MeshError> {
    Mesh::build(p, Some(n), t, MeshOptions { weld, ..MeshOptions::default() }).map(|(m, _)| m)
}

/// Quads of an `(nu+1) × (nv+1)` vertex grid as triangles; `flip` reverses the winding.
fn grid_triangles(base: u32, nu: u32, nv: u32, flip: bool, t: &mut Vec<[u32; 3]>) {
    let at = |i: u32, j: u32| base + j * (nu + 1) + i;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if flip {
                t.push([a, c, b]);
                t.push([a, d, c]);
            } else {
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
    }
}

/// A UV sphere of `radius` with `segments` around and `rings` from pole to pole (each ≥ 3 / 2).
/// Poles are single vertices (welded), so there are `segments·(rings−1) + 2` vertices.
pub fn sphere(radius: f32, segments: u32, rings: u32) -> Result<Mesh, MeshError> {
    let (segments, rings) = (segments.max(3), rings.max(2));
    let (mut p, mut n, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..=rings {
        let theta = PI * j as f32 / rings as f32;
        for i in 0..=segments {
            let phi = TAU * (i % segments) as f32 / segments as f32;
            let d = if j == 0 {
                Vec3::Y
            } else if j == rings {
                -Vec3::Y
            } else {
                Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos())
            };
            p.push(d * radius);
            n.push(d);
        }
    }
    grid_triangles(0, segments, rings, true, &mut t);
    build(p, n, t, Weld::Exact)
}

/// A torus around the y axis: ring radius `major`, tube radius `minor`.
pub fn torus(major: f32, minor: f32, major_segments: u32, minor_segments: u32) -> Result<Mesh, MeshError> {
    let (nu, nv) = (major_segments.max(3), minor_segments.max(3));
    let (mut p, mut n, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..=nv {
        let b = TAU * (j % nv) as f32 / nv as f32;
        for i in 0..=nu {
            let a = TAU * (i % nu) as f32 / nu as f32;
            let ring = Vec3::new(a.sin(), 0.0, a.cos());
            let normal = ring * b.cos() + Vec3::Y * b.sin();
            p.push(ring * major + normal * minor);
            n.push(normal);
        }
    }
    grid_triangles(0, nu, nv, false, &mut t);
    build(p, n, t, Weld::Exact)
}

/// An axis-aligned box of the given full `size`, each face an `n × n` grid with its own
/// vertices (hard edges, flat normals).
pub fn cuboid(size: Vec3, n: u32) -> Result<Mesh, MeshError> {
    let n = n.max(1);
    let h = size * 0.5;
    let (mut p, mut nn, mut t) = (Vec::new(), Vec::new(), Vec::new());
    // (normal, u axis, v axis) with u × v = normal, so the grid winds counter-clockwise.
    let faces = [
        (Vec3::X, -Vec3::Z, Vec3::Y),
        (-Vec3::X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, -Vec3::Z),
        (-Vec3::Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (-Vec3::Z, -Vec3::X, Vec3::Y),
    ];
    for (normal, u, v) in faces {
        let base = p.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (s, r) = (2.0 * i as f32 / n as f32 - 1.0, 2.0 * j as f32 / n as f32 - 1.0);
                p.push((normal + u * s + v * r) * h);
                nn.push(normal);
            }
        }
        grid_triangles(base, n, n, false, &mut t);
    }
    build(p, nn, t, Weld::None)
}

/// A square ground plane of side `size` in y = 0 facing +Y, an `n × n` grid of quads
/// (`(n+1)²` vertices).
pub fn plane(size: f32, n: u32) -> Result<Mesh, MeshError> {
    let n = n.max(1);
    let (mut p, mut nn, mut t) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            p.push(Vec3::new(x * size, 0.0, z * size));
            nn.push(Vec3::Y);
        }
    }
    // x right, z towards the viewer: (i,j)→(i,j+1)→(i+1,j+1) winds counter-clockwise from +Y.
    grid_triangles(0, n, n, true, &mut t);
    build(p, nn, t, Weld::None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_outward(m: &Mesh) {
        m.validate().unwrap();
        for t in m.triangles() {
            let [a, b, c] = t.map(|i| m.positions()[i as usize]);
            let face = (b - a).cross(c - a);
            let n = m.normals()[t[0] as usize] + m.normals()[t[1] as usize] + m.normals()[t[2] as usize];
            assert!(face.dot(n) > 0.0, "triangle {t:?} winds against its normals");
        }
    }

    #[test]
    fn shapes_are_valid_and_wind_outwards() {
        let s = sphere(2.0, 16, 8).unwrap();
        assert_eq!(s.vertex_count(), 16 * 7 + 2); // seam column and poles welded
        check_outward(&s);
        let area = s.area();
        assert!((area - 4.0 * std::f64::consts::PI * 4.0).abs() / area < 0.05);
        check_outward(&torus(1.0, 0.25, 24, 12).unwrap());
        let b = cuboid(Vec3::new(1.0, 2.0, 3.0), 2).unwrap();
        check_outward(&b);
        assert!((b.area() - 22.0).abs() < 1e-4);
        let p = plane(4.0, 8).unwrap();
        check_outward(&p);
        assert_eq!(p.vertex_count(), 81);
        assert!((p.area() - 16.0).abs() < 1e-4);
    }
}
