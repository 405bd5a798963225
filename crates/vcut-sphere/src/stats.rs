//! Uniformity statistics of a direction set: nearest-neighbour angles against the ideal spacing
//! √(4π/N), the coefficient of variation of the exact Voronoi cell areas, and a chi-squared test
//! over equal-area bins.

use crate::grid::SphereGrid;
use glam::DVec3;
use rayon::prelude::*;

/// Uniformity figures; `cargo xtask directions` prints them as `key=value` lines.
#[derive(Debug, Clone, PartialEq)]
pub struct Uniformity {
    /// Number of directions.
    pub n: usize,
    /// Ideal spacing √(4π/N) in radians.
    pub ideal_spacing: f64,
    /// Smallest nearest-neighbour angle (radians).
    pub min_nn: f64,
    /// Mean nearest-neighbour angle (radians).
    pub mean_nn: f64,
    /// `min_nn / mean_nn` (goal ≥ 0.9).
    pub min_nn_ratio: f64,
    /// Coefficient of variation (std/mean) of the Voronoi cell solid angles (goal ≤ 0.01).
    pub cv_cell_area: f64,
    /// Smallest and largest cell solid angle over the mean.
    pub cell_area_range: (f64, f64),
    /// Σ cell areas − 4π (should be ~0).
    pub cell_area_sum_error: f64,
    /// Chi-squared statistic over equal-area bins.
    pub chi2: f64,
    /// Its degrees of freedom.
    pub chi2_dof: usize,
    /// Upper-tail p-value (Wilson–Hilferty); near 1 for sets more even than random.
    pub chi2_p: f64,
}

/// Computes [`Uniformity`] from unit directions and their cell areas.
pub fn uniformity(points: &[DVec3], cell_areas: &[f64]) -> Uniformity {
    let n = points.len();
    let s = (4.0 * std::f64::consts::PI / n as f64).sqrt();
    let grid = SphereGrid::new(points, 2.0 * s);
    let nn: Vec<f64> = points
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            let mut best = f64::INFINITY;
            grid.for_each_near(p, |j| {
                if j as usize != i {
                    best = best.min(p.distance_squared(points[j as usize]));
                }
            });
            if !best.is_finite() {
                best = points
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != i)
                    .map(|(_, q)| p.distance_squared(*q))
                    .fold(f64::INFINITY, f64::min);
            }
            // Chord to angle.
            2.0 * (0.5 * best.sqrt()).min(1.0).asin()
        })
        .collect();
    let min_nn = nn.iter().cloned().fold(f64::INFINITY, f64::min);
    let mean_nn = nn.iter().sum::<f64>() / n as f64;
    let mean_a = cell_areas.iter().sum::<f64>() / n as f64;
    let var = cell_areas.iter().map(|a| (a - mean_a) * (a - mean_a)).sum::<f64>() / n as f64;
    let (lo, hi) = cell_areas.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &a| (l.min(a), h.max(a)));
    let (chi2, dof) = chi_squared(points);
    Uniformity {
        n,
        ideal_spacing: s,
        min_nn,
        mean_nn,
        min_nn_ratio: min_nn / mean_nn,
        cv_cell_area: var.sqrt() / mean_a,
        cell_area_range: (lo / mean_a, hi / mean_a),
        cell_area_sum_error: cell_areas.iter().sum::<f64>() - 4.0 * std::f64::consts::PI,
        chi2,
        chi2_dof: dof,
        chi2_p: chi2_upper_p(chi2, dof),
    }
}

/// Chi-squared over `B × 2B` equal-area bins (equal z-bands × equal φ-sectors), about 16
/// expected points per bin.
pub fn chi_squared(points: &[DVec3]) -> (f64, usize) {
    let n = points.len();
    let b = (((n / 16).max(2) as f64 / 2.0).sqrt().round() as usize).max(1);
    let (bands, sectors) = (b, 2 * b);
    let mut counts = vec![0u32; bands * sectors];
    for p in points {
        let zb = (((p.z + 1.0) * 0.5 * bands as f64) as usize).min(bands - 1);
        let mut phi = p.y.atan2(p.x) / (2.0 * std::f64::consts::PI);
        if phi < 0.0 {
            phi += 1.0;
        }
        let sb = ((phi * sectors as f64) as usize).min(sectors - 1);
        counts[zb * sectors + sb] += 1;
    }
    let e = n as f64 / counts.len() as f64;
    let chi2 = counts.iter().map(|&c| (f64::from(c) - e) * (f64::from(c) - e) / e).sum();
    (chi2, counts.len() - 1)
}

/// P(χ²_k ≥ x) by the Wilson–Hilferty normal approximation.
pub fn chi2_upper_p(x: f64, k: usize) -> f64 {
    let k = k.max(1) as f64;
    let z = ((x / k).cbrt() - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    0.5 * erfc(z / std::f64::consts::SQRT_2)
}

/// Complementary error function (Numerical Recipes' erfcc, |error| < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806
                            + t * (0.27886807
                                + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 { r } else { 2.0 - r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi2_p_values_are_sane() {
        // Mean of χ²_k is k: p ≈ 0.5.
        assert!((chi2_upper_p(1000.0, 1000) - 0.5).abs() < 0.02);
        assert!(chi2_upper_p(1300.0, 1000) < 1e-6);
        assert!(chi2_upper_p(100.0, 1000) > 0.999999);
    }
}
