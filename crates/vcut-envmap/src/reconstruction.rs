//! How a map's texels become radiance between their centres, and what each texel then holds.
//!
//! - [`Reconstruction::Box`]: each texel's value is the radiance over its whole area (pbrt-v4's
//!   image infinite light looks texels up this way). A texel's power is its value × its solid
//!   angle.
//! - [`Reconstruction::Bilinear`]: Mitsuba 3's `envmap` lookup — radiance interpolated
//!   bilinearly between nodes at `u = (i + ½)/w` (wrapping; column i's centre) and
//!   `v = j/(h − 1)` (row 0 on the north pole, row h − 1 on the south one: the image's rows
//!   stretched pole to pole, not centred in their bands). Lat-long maps only (a cube map's faces
//!   would need blending across seams: refused); a one-row map is constant in v.
//!
//! Every integrator (the light tree, the references, [`crate::EnvMap::total_power`]) reads a
//! texel's *mean* radiance under the reconstruction over the texel's own band
//! ([`crate::EnvMap::integrated_texels`]), so summing mean × solid angle over texels integrates
//! the chosen reconstruction exactly. For bilinear that mean is a fixed stencil: in u the
//! column hats put ¾ of a texel's own column and ⅛ of each neighbour's over it; in v the row
//! hats are weighted by sin θ over the band, in closed form ([`row_weights`]).

use serde::{Deserialize, Serialize};

/// How radiance is reconstructed from a map's texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reconstruction {
    /// Constant over each texel (the default; see docs/scene-file.md for why).
    #[default]
    Box,
    /// Bilinear between texel centres (Mitsuba 3's `envmap`; lat-long maps only).
    Bilinear,
}

impl Reconstruction {
    /// The name a scene file and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Reconstruction::Box => "box",
            Reconstruction::Bilinear => "bilinear",
        }
    }
}

impl std::str::FromStr for Reconstruction {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "box" => Ok(Reconstruction::Box),
            "bilinear" => Ok(Reconstruction::Bilinear),
            _ => Err(format!("'{s}': expected box or bilinear")),
        }
    }
}

/// `∫ f(v) sin(πv) dv` over `[v0, v1]` for `f` linear from `f0` at `v0` to `f1` at `v1`, in
/// closed form (`θ = πv`).
fn linear_times_sine(v0: f64, v1: f64, f0: f64, f1: f64) -> f64 {
    use std::f64::consts::PI;
    if v1 <= v0 {
        return 0.0;
    }
    let s = (f1 - f0) / (v1 - v0);
    let a = f0 - s * v0;
    let antiderivative = |v: f64| -(a + s * v) * (PI * v).cos() / PI + s * (PI * v).sin() / (PI * PI);
    antiderivative(v1) - antiderivative(v0)
}

/// For texel row `j` of `h` (the band `v ∈ [j/h, (j+1)/h]`): each source row `k` with its
/// weight `∫_band V_k(v) sin(πv) dv`, `V_k` row k's hat between the nodes `v = (k ± 1)/(h − 1)`.
/// The weights sum to `∫_band sin(πv) dv`.
pub fn row_weights(j: u32, h: u32) -> Vec<(u32, f64)> {
    let hf = f64::from(h);
    let (top, bottom) = (f64::from(j) / hf, f64::from(j + 1) / hf);
    if h == 1 {
        return vec![(0, linear_times_sine(top, bottom, 1.0, 1.0))];
    }
    let n = f64::from(h - 1);
    let mut out: Vec<(u32, f64)> = Vec::with_capacity(3);
    let mut add = |k: u32, w: f64| match out.iter_mut().find(|(r, _)| *r == k) {
        Some(e) => e.1 += w,
        None => out.push((k, w)),
    };
    // The node intervals [m/n, (m+1)/n] the band overlaps.
    let first = ((top * n).floor() as u32).min(h - 2);
    let last = (((bottom * n).ceil() as u32).max(1) - 1).min(h - 2);
    for m in first..=last {
        let (v0, v1) = (f64::from(m) / n, f64::from(m + 1) / n);
        let (a, b) = (top.max(v0), bottom.min(v1));
        if b <= a {
            continue;
        }
        let t = |v: f64| (v - v0) * n;
        add(m, linear_times_sine(a, b, 1.0 - t(a), 1.0 - t(b)));
        add(m + 1, linear_times_sine(a, b, t(a), t(b)));
    }
    out
}

/// The bilinear lookup of [`Reconstruction::Bilinear`] at map coordinates `(u, v)` of a
/// `width × height` lat-long map: four `(texel, weight)` pairs, weights summing to 1.
pub fn bilinear_weights(width: u32, height: u32, u: f64, v: f64) -> [(usize, f32); 4] {
    let w = i64::from(width);
    let px = u * f64::from(width) - 0.5;
    let x0 = px.floor();
    let fx = (px - x0) as f32;
    let (xa, xb) = ((x0 as i64).rem_euclid(w) as usize, (x0 as i64 + 1).rem_euclid(w) as usize);
    let (ya, yb, fy) = if height == 1 {
        (0, 0, 0.0)
    } else {
        let py = (v.clamp(0.0, 1.0) * f64::from(height - 1)).min(f64::from(height - 1));
        let y0 = py.floor().min(f64::from(height - 2));
        (y0 as usize, y0 as usize + 1, (py - y0) as f32)
    };
    let row = width as usize;
    [
        (ya * row + xa, (1.0 - fx) * (1.0 - fy)),
        (ya * row + xb, fx * (1.0 - fy)),
        (yb * row + xa, (1.0 - fx) * fy),
        (yb * row + xb, fx * fy),
    ]
}

/// Each texel's mean radiance under bilinear reconstruction of a `width × height` lat-long map.
pub fn bilinear_means(width: u32, height: u32, texels: &[[f32; 3]]) -> Vec<[f32; 3]> {
    let (w, h) = (width as usize, height as usize);
    let at = |i: isize, j: usize| -> [f64; 3] { texels[j * w + i.rem_euclid(w as isize) as usize].map(f64::from) };
    // Per row, the u-blended values: ¾ own + ⅛ each neighbour (wrapping).
    let blended = |i: usize, j: usize| -> [f64; 3] {
        let (l, c, r) = (at(i as isize - 1, j), at(i as isize, j), at(i as isize + 1, j));
        std::array::from_fn(|k| 0.75 * c[k] + 0.125 * (l[k] + r[k]))
    };
    let mut out = Vec::with_capacity(texels.len());
    for j in 0..h {
        let rw = row_weights(j as u32, height);
        let total: f64 = rw.iter().map(|r| r.1).sum();
        for i in 0..w {
            let mut m = [0.0f64; 3];
            for &(row, weight) in &rw {
                let v = blended(i, row as usize);
                for k in 0..3 {
                    m[k] += weight * v[k];
                }
            }
            out.push(m.map(|x| (x / total).max(0.0) as f32));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_weights_sum_to_the_bands_sine_integral_and_favour_the_nearest_rows() {
        use std::f64::consts::PI;
        for h in [1u32, 2, 3, 8, 512] {
            for j in 0..h {
                let w = row_weights(j, h);
                let exact =
                    ((PI * f64::from(j) / f64::from(h)).cos() - (PI * f64::from(j + 1) / f64::from(h)).cos()) / PI;
                let sum: f64 = w.iter().map(|r| r.1).sum();
                assert!((sum - exact).abs() < 1e-9 * exact, "h {h} row {j}: {w:?}");
                assert!(w.iter().all(|&(k, x)| x >= 0.0 && k < h && k.abs_diff(j) <= 1), "h {h} row {j}: {w:?}");
            }
        }
        // The top band leans on row 0, which sits on the pole.
        let top = row_weights(0, 8);
        assert!(top.iter().any(|&(k, _)| k == 0) && top.iter().all(|&(k, _)| k <= 1), "{top:?}");
        // The lookup: row 0 at the north pole, the last row at the south pole, columns at their centres.
        assert_eq!(bilinear_weights(4, 3, 0.125, 0.0)[0], (0, 1.0));
        assert_eq!(bilinear_weights(4, 3, 0.375, 1.0)[2], (2 * 4 + 1, 1.0));
        let mid = bilinear_weights(4, 3, 0.0, 0.25);
        assert_eq!((mid[0].0, mid[1].0), (3, 0), "u = 0 blends the last column and the first");
        assert!(mid.iter().all(|p| (p.1 - 0.25).abs() < 1e-6));
        assert_eq!("bilinear".parse::<Reconstruction>(), Ok(Reconstruction::Bilinear));
        assert!("trilinear".parse::<Reconstruction>().unwrap_err().contains("box or bilinear"));
    }

    #[test]
    fn a_constant_map_keeps_its_value_and_a_spike_spreads_to_its_neighbours() {
        let means = bilinear_means(4, 3, &[[2.0, 1.0, 0.5]; 12]);
        assert!(means.iter().all(|m| (m[0] - 2.0).abs() < 1e-6 && (m[2] - 0.5).abs() < 1e-6));
        let mut spike = vec![[0.0f32; 3]; 8 * 4];
        spike[8 + 3] = [1.0; 3];
        let means = bilinear_means(8, 4, &spike);
        assert!(means[8 + 3][0] > 0.5 && means[8 + 2][0] > 0.0 && means[8 + 4][0] > 0.0 && means[3][0] > 0.0);
        assert_eq!(means[8 + 5][0], 0.0, "two columns away");
    }
}
