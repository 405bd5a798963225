//! Flat convex objects: a mesh whose vertices all lie in one plane and whose triangles cover
//! exactly their convex hull (a ground quad, a floor grid, a tabletop, a wall). Such an
//! object's shadow at any point is a convex polygon's solid angle, exact to compute where it
//! is needed instead of interpolated from a precomputed field ([`FlatOutline`]).
//!
//! # Example
//! ```
//! use vcut_scene::{flat::FlatOutline, shapes};
//! let ground = shapes::plane(4.0, 8).unwrap();
//! let outline = FlatOutline::of(&ground).unwrap();
//! assert_eq!(outline.corners().len(), 4);
//! // A sphere is not flat.
//! assert!(FlatOutline::of(&shapes::sphere(1.0, 16, 8).unwrap()).is_none());
//! ```

use crate::Mesh;
use glam::{DVec2, DVec3, Vec3};

/// How far (as a share of the mesh's bounding radius) a vertex may lie off the plane.
const PLANE_TOLERANCE: f64 = 1e-5;
/// How much the triangles' area may differ from the hull's (relative).
const AREA_TOLERANCE: f64 = 1e-4;

/// The outline of a flat convex object: its plane and the corners of its convex hull in
/// order, counter-clockwise seen from the side `normal` points to, in the mesh's space.
#[derive(Debug, Clone, PartialEq)]
pub struct FlatOutline {
    normal: Vec3,
    corners: Vec<Vec3>,
}

impl FlatOutline {
    /// The outline of `mesh` if it is flat and convex: every vertex within 10⁻⁵ of its
    /// bounding radius of one plane, and the triangles' total area within 10⁻⁴ of the convex
    /// hull's (so they cover it: no hole, no notch). `None` for anything else, a mesh with no
    /// area included.
    pub fn of(mesh: &Mesh) -> Option<FlatOutline> {
        let p: Vec<DVec3> = mesh.positions().iter().map(|v| v.as_dvec3()).collect();
        // The plane: the area-weighted normal (Newell's sum over triangles) through the centroid.
        let mut sum = DVec3::ZERO;
        let mut area = 0.0;
        for t in mesh.triangles() {
            let [a, b, c] = t.map(|i| p[i as usize]);
            let cross = (b - a).cross(c - a);
            sum += cross;
            area += 0.5 * cross.length();
        }
        let normal = sum.try_normalize()?;
        let centre = p.iter().sum::<DVec3>() / p.len().max(1) as f64;
        let radius = f64::from(mesh.bounds().radius).max(f64::MIN_POSITIVE);
        if p.iter().any(|v| (*v - centre).dot(normal).abs() > PLANE_TOLERANCE * radius) {
            return None;
        }
        // Its 2-D convex hull, counter-clockwise about the normal.
        let u = normal.any_orthonormal_vector();
        let w = normal.cross(u);
        let flat: Vec<DVec2> = p.iter().map(|v| DVec2::new((*v - centre).dot(u), (*v - centre).dot(w))).collect();
        let hull = convex_hull(&flat);
        let hull_area = 0.5
            * (0..hull.len())
                .map(|i| {
                    let (a, b) = (flat[hull[i]], flat[hull[(i + 1) % hull.len()]]);
                    a.perp_dot(b)
                })
                .sum::<f64>();
        if hull.len() < 3 || (area - hull_area).abs() > AREA_TOLERANCE * hull_area {
            return None;
        }
        let corners = hull.iter().map(|&i| (centre + u * flat[i].x + w * flat[i].y).as_vec3()).collect();
        Some(FlatOutline { normal: normal.as_vec3(), corners })
    }

    /// The plane's unit normal (the side the triangles face, by area).
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The hull's corners, counter-clockwise about [`FlatOutline::normal`], no three in line.
    pub fn corners(&self) -> &[Vec3] {
        &self.corners
    }
}

/// Indices of the convex hull of `points`, counter-clockwise, without collinear points
/// (Andrew's monotone chain).
fn convex_hull(points: &[DVec2]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].x.total_cmp(&points[b].x).then(points[a].y.total_cmp(&points[b].y)));
    order.dedup_by(|a, b| points[*a] == points[*b]);
    if order.len() < 3 {
        return order;
    }
    let turn = |o: usize, a: usize, b: usize| (points[a] - points[o]).perp_dot(points[b] - points[o]);
    let mut hull: Vec<usize> = Vec::with_capacity(2 * order.len());
    for pass in [order.clone(), order.iter().rev().copied().collect()] {
        let start = hull.len();
        for &i in &pass {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], i) <= 0.0 {
                hull.pop();
            }
            hull.push(i);
        }
        hull.pop();
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes;

    #[test]
    fn a_ground_grid_is_its_square() {
        let g = shapes::plane(6.0, 5).unwrap();
        let o = FlatOutline::of(&g).unwrap();
        assert!((o.normal() - Vec3::Y).length() < 1e-6);
        let mut c: Vec<(i32, i32)> = o.corners().iter().map(|v| (v.x.round() as i32, v.z.round() as i32)).collect();
        c.sort_unstable();
        assert_eq!(c, vec![(-3, -3), (-3, 3), (3, -3), (3, 3)]);
        assert!(o.corners().iter().all(|v| v.y.abs() < 1e-6));
        // Counter-clockwise seen from above (+Y).
        let [a, b, c] = [o.corners()[0], o.corners()[1], o.corners()[2]];
        assert!((b - a).cross(c - b).dot(o.normal()) > 0.0);
    }

    #[test]
    fn a_hole_a_notch_or_a_bend_is_not_flat_convex() {
        let g = shapes::plane(4.0, 4).unwrap();
        // Drop one cell's two triangles: a hole (inner cell) leaves less area than the hull.
        let mut tris = g.triangles().to_vec();
        tris.remove(10);
        tris.remove(10);
        let holed = Mesh::from_valid_parts(g.positions().to_vec(), g.normals().to_vec(), tris).unwrap();
        assert!(FlatOutline::of(&holed).is_none());
        // Lift one vertex: not flat.
        let mut p = g.positions().to_vec();
        p[7].y += 0.01;
        let bent = Mesh::from_valid_parts(p, g.normals().to_vec(), g.triangles().to_vec()).unwrap();
        assert!(FlatOutline::of(&bent).is_none());
        assert!(FlatOutline::of(&shapes::sphere(1.0, 12, 6).unwrap()).is_none());
    }

    #[test]
    fn a_tilted_triangle_keeps_its_corners() {
        let p = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)];
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        let m = Mesh::from_valid_parts(p.clone(), vec![n; 3], vec![[0, 1, 2]]).unwrap();
        let o = FlatOutline::of(&m).unwrap();
        assert!((o.normal() - n).length() < 1e-6);
        assert_eq!(o.corners().len(), 3);
        for c in o.corners() {
            assert!(p.iter().any(|q| q.distance(*c) < 1e-6), "{c}");
        }
    }
}
