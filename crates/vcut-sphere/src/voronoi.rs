//! Exact spherical Voronoi cell areas (solid angles).
//!
//! A cell is the intersection of the half-spaces `x·(p − q) ≥ 0` over the other points `q`. In
//! the gnomonic projection onto the tangent plane at `p` great circles are straight lines, so the
//! cell is a convex polygon clipped from a square by half-planes (Sutherland–Hodgman); its
//! vertices map back to the sphere exactly, and the spherical polygon's area is the sum of the
//! solid angles of the triangles (p, vₖ, vₖ₊₁) (Van Oosterom & Strackee). Only neighbours within a
//! few spacings can bound a cell of a well-spread set; if the clipped polygon still touches the
//! starting square, the search radius doubles.

use crate::grid::SphereGrid;
use glam::{DVec2, DVec3};
use rayon::prelude::*;

/// Solid angle of the spherical triangle (a, b, c) of unit vectors.
pub fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let num = a.dot(b.cross(c)).abs();
    let den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
    2.0 * num.atan2(den)
}

/// No neighbour: an edge of the starting square.
const SQUARE: u32 = u32::MAX;

/// Keeps `n·x + c ≥ 0` of a convex polygon whose vertex `k` carries the label of the edge from
/// it to vertex `k + 1`; the edge the clip line adds is labelled `label`.
fn clip(poly: &[(DVec2, u32)], n: DVec2, c: f64, label: u32) -> Vec<(DVec2, u32)> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    for k in 0..poly.len() {
        let ((a, edge), (b, _)) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fa, fb) = (n.dot(a) + c, n.dot(b) + c);
        let cut = || a + (b - a) * (fa / (fa - fb));
        match (fa >= 0.0, fb >= 0.0) {
            (true, true) => out.push((a, edge)),
            (true, false) => {
                out.push((a, edge));
                out.push((cut(), label));
            }
            (false, true) => out.push((cut(), edge)),
            (false, false) => {}
        }
    }
    out
}

/// The Voronoi cell area of every point (unit vectors, distinct), summing to 4π.
pub fn cell_areas(points: &[DVec3]) -> Vec<f64> {
    cells(points).into_iter().map(|c| c.area).collect()
}

/// The Delaunay edges `(i, j)`, `i < j`, sorted: the pairs whose Voronoi cells share an edge.
/// For points in general position there are `3N − 6` of them.
pub fn delaunay_edges(points: &[DVec3]) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = cells(points)
        .into_iter()
        .enumerate()
        .flat_map(|(i, c)| {
            c.neighbours.into_iter().filter(|&j| j != SQUARE).map(move |j| (j.min(i as u32), j.max(i as u32)))
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

struct Cell {
    area: f64,
    /// The point whose bisector bounds each edge of the cell.
    neighbours: Vec<u32>,
}

fn cells(points: &[DVec3]) -> Vec<Cell> {
    let n = points.len().max(1);
    let s = (4.0 * std::f64::consts::PI / n as f64).sqrt();
    let radii = [3.0 * s, 6.0 * s, 12.0 * s, 2.5];
    let grids: Vec<SphereGrid> = radii.iter().map(|&r| SphereGrid::new(points, r)).collect();
    points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            for (level, grid) in grids.iter().enumerate() {
                if let Some(c) = cell(points, i, p, grid, radii[level], level == radii.len() - 1) {
                    return c;
                }
            }
            Cell { area: 0.0, neighbours: Vec::new() }
        })
        .collect()
}

fn cell(points: &[DVec3], i: usize, p: DVec3, grid: &SphereGrid, radius: f64, last: bool) -> Option<Cell> {
    let a = if p.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = p.cross(a).normalize();
    let v = p.cross(u);
    // Starting square in gnomonic coordinates: tan of the search radius's angle, with margin.
    let half = if last { 1e3 } else { 2.0 * radius };
    let mut poly: Vec<(DVec2, u32)> =
        [(-half, -half), (half, -half), (half, half), (-half, half)].map(|(x, y)| (DVec2::new(x, y), SQUARE)).to_vec();
    let mut visit = |j: u32| {
        if j as usize == i {
            return;
        }
        let q = points[j as usize];
        if !last && (p - q).length() > radius {
            return;
        }
        let m = p - q;
        // x = p + a u + b v:  m·x = m·p + a (m·u) + b (m·v) ≥ 0.
        poly = clip(&poly, DVec2::new(m.dot(u), m.dot(v)), m.dot(p), j);
    };
    if last {
        (0..points.len() as u32).for_each(&mut visit);
    } else {
        grid.for_each_near(p, &mut visit);
    }
    if poly.len() < 3 {
        return Some(Cell { area: 0.0, neighbours: Vec::new() });
    }
    if !last && poly.iter().any(|(q, _)| q.x.abs() >= half * 0.999 || q.y.abs() >= half * 0.999) {
        return None;
    }
    let verts: Vec<DVec3> = poly.iter().map(|(q, _)| (p + q.x * u + q.y * v).normalize()).collect();
    let mut area = 0.0;
    for k in 0..verts.len() {
        area += triangle_solid_angle(p, verts[k], verts[(k + 1) % verts.len()]);
    }
    Some(Cell { area, neighbours: poly.into_iter().map(|(_, j)| j).collect() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedron_cells_are_sixths() {
        let pts = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        let a = cell_areas(&pts);
        for x in a {
            assert!((x - 4.0 * std::f64::consts::PI / 6.0).abs() < 1e-9, "{x}");
        }
    }

    #[test]
    fn octahedron_edges_are_its_twelve_edges() {
        let pts = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z];
        let e = delaunay_edges(&pts);
        assert_eq!(e.len(), 12, "{e:?}");
        // Antipodes are never neighbours.
        assert!(!e.contains(&(0, 1)) && !e.contains(&(2, 3)) && !e.contains(&(4, 5)));
    }

    #[test]
    fn triangle_of_an_octant() {
        let w = triangle_solid_angle(DVec3::X, DVec3::Y, DVec3::Z);
        assert!((w - std::f64::consts::PI / 2.0).abs() < 1e-12);
    }
}
