//! A uniform 3D grid over the unit sphere's bounding cube, for fixed-radius neighbour queries in
//! O(1) per query: points are bucketed by cell (compressed rows), a query visits the 27 cells
//! around it. The cell edge is at least the query radius.

use glam::DVec3;

/// Neighbour grid over points on (or near) the unit sphere.
pub struct SphereGrid {
    res: usize,
    cell: f64,
    /// `starts[c]..starts[c+1]` indexes `items` for cell `c`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

/// Largest grid resolution per axis (keeps the cell table ≤ 128³ entries).
const MAX_RES: usize = 128;

impl SphereGrid {
    /// Buckets `points` into cells of edge ≥ `radius`.
    pub fn new(points: &[DVec3], radius: f64) -> SphereGrid {
        let res = ((2.0 / radius.max(1e-9)).floor() as usize).clamp(1, MAX_RES);
        let cell = 2.0 / res as f64;
        let n_cells = res * res * res;
        let mut counts = vec![0u32; n_cells + 1];
        let keys: Vec<usize> = points.iter().map(|p| Self::key_of(res, cell, *p)).collect();
        for &k in &keys {
            counts[k + 1] += 1;
        }
        for c in 0..n_cells {
            counts[c + 1] += counts[c];
        }
        let starts = counts.clone();
        let mut fill = counts;
        let mut items = vec![0u32; points.len()];
        for (i, &k) in keys.iter().enumerate() {
            items[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        SphereGrid { res, cell, starts, items }
    }

    fn coord(res: usize, cell: f64, x: f64) -> usize {
        (((x + 1.0) / cell).floor().max(0.0) as usize).min(res - 1)
    }

    fn key_of(res: usize, cell: f64, p: DVec3) -> usize {
        let (i, j, k) = (Self::coord(res, cell, p.x), Self::coord(res, cell, p.y), Self::coord(res, cell, p.z));
        (i * res + j) * res + k
    }

    /// Cell edge length.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Calls `f(index)` for every point in the 27 cells around `p` (a superset of the points
    /// within one cell edge of `p`), in a fixed order.
    pub fn for_each_near(&self, p: DVec3, mut f: impl FnMut(u32)) {
        let r = self.res as isize;
        let c = [p.x, p.y, p.z].map(|x| Self::coord(self.res, self.cell, x) as isize);
        for di in -1..=1 {
            let i = c[0] + di;
            if i < 0 || i >= r {
                continue;
            }
            for dj in -1..=1 {
                let j = c[1] + dj;
                if j < 0 || j >= r {
                    continue;
                }
                for dk in -1..=1 {
                    let k = c[2] + dk;
                    if k < 0 || k >= r {
                        continue;
                    }
                    let key = ((i * r + j) * r + k) as usize;
                    for &item in &self.items[self.starts[key] as usize..self.starts[key + 1] as usize] {
                        f(item);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_every_neighbour_within_the_cell_edge() {
        let pts: Vec<DVec3> = (0..500)
            .map(|i| {
                let z = 1.0 - (2.0 * i as f64 + 1.0) / 500.0;
                let phi = i as f64 * 2.399963;
                let s = (1.0 - z * z).sqrt();
                DVec3::new(s * phi.cos(), s * phi.sin(), z)
            })
            .collect();
        let grid = SphereGrid::new(&pts, 0.3);
        for (i, p) in pts.iter().enumerate() {
            let mut near = Vec::new();
            grid.for_each_near(*p, |j| near.push(j as usize));
            for (j, q) in pts.iter().enumerate() {
                if p.distance(*q) <= grid.cell_size() {
                    assert!(near.contains(&j), "{i} misses {j}");
                }
            }
        }
    }
}
