//! Real spherical harmonics of order 5 (bands 0–4, 25 coefficients), the basis of the PRT pass:
//! evaluation by the closed-form polynomials, projection of an environment map (exact texel solid
//! angles, f64 sums) and of a distant light.

use glam::Vec3;
use vcut_envmap::EnvMap;

/// Bands (the paper's order 5).
pub const BANDS: usize = 5;
/// Coefficients: BANDS².
pub const COEFFS: usize = BANDS * BANDS;

/// RGB coefficients of a function on the sphere.
pub type ShRgb = [Vec3; COEFFS];

/// The 25 basis functions at unit direction `d` (index l² + l + m).
#[inline]
pub fn basis(d: Vec3) -> [f32; COEFFS] {
    let (x, y, z) = (d.x, d.y, d.z);
    let (x2, y2, z2) = (x * x, y * y, z * z);
    [
        0.282_094_8,
        0.488_602_5 * y,
        0.488_602_5 * z,
        0.488_602_5 * x,
        1.092_548_4 * x * y,
        1.092_548_4 * y * z,
        0.315_391_57 * (3.0 * z2 - 1.0),
        1.092_548_4 * x * z,
        0.546_274_2 * (x2 - y2),
        0.590_043_6 * y * (3.0 * x2 - y2),
        2.890_611_4 * x * y * z,
        0.457_045_8 * y * (5.0 * z2 - 1.0),
        0.373_176_33 * z * (5.0 * z2 - 3.0),
        0.457_045_8 * x * (5.0 * z2 - 1.0),
        1.445_305_7 * z * (x2 - y2),
        0.590_043_6 * x * (x2 - 3.0 * y2),
        2.503_343 * x * y * (x2 - y2),
        1.770_130_8 * y * z * (3.0 * x2 - y2),
        0.946_174_7 * x * y * (7.0 * z2 - 1.0),
        0.669_046_5 * y * z * (7.0 * z2 - 3.0),
        0.105_785_55 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0),
        0.669_046_5 * x * z * (7.0 * z2 - 3.0),
        0.473_087_34 * (x2 - y2) * (7.0 * z2 - 1.0),
        1.770_130_8 * x * z * (x2 - 3.0 * y2),
        0.625_835_7 * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2)),
    ]
}

/// ∫ L(ω) Y_i(ω) dω of `env` (rotation and intensity applied), over sub-texel patches fine
/// enough for band 4 (at least 2¹⁸ patches: a tiny map is subdivided, a large one is not).
pub fn project_env(env: &EnvMap) -> ShRgb {
    let texels = env.layout().texel_count().max(1) as f64;
    let k = ((262_144.0 / texels).sqrt().ceil() as u32).clamp(1, 128);
    let mut sum = [[0.0f64; 3]; COEFFS];
    env.for_each_patch(k, |d, omega, c| {
        let y = basis(d.normalize());
        for (s, yi) in sum.iter_mut().zip(y) {
            for ch in 0..3 {
                s[ch] += f64::from(c[ch]) * f64::from(yi) * omega;
            }
        }
    });
    sum.map(|s| Vec3::new(s[0] as f32, s[1] as f32, s[2] as f32))
}

/// The coefficients of a distant light of irradiance `e` from unit direction `d` (a δ on the
/// sphere): e·Y_i(d).
pub fn project_delta(d: Vec3, e: Vec3) -> ShRgb {
    basis(d).map(|y| e * y)
}

/// Σ_i a_i·b_i per channel.
#[inline]
pub fn dot_rgb(scalar: &[f32; COEFFS], light: &ShRgb) -> Vec3 {
    let mut out = Vec3::ZERO;
    for (a, l) in scalar.iter().zip(light) {
        out += *l * *a;
    }
    out
}

/// Σ_i a_i ⊙ b_i: a per-channel transfer applied to light.
#[inline]
pub fn dot_each(transfer: &ShRgb, light: &ShRgb) -> Vec3 {
    transfer.iter().zip(light).map(|(a, l)| *a * *l).sum()
}

/// The band-limited reconstruction at `d`.
pub fn eval(coeffs: &ShRgb, d: Vec3) -> Vec3 {
    dot_rgb(&basis(d), coeffs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fibonacci(n: usize) -> Vec<Vec3> {
        let golden = std::f32::consts::PI * (3.0 - 5.0f32.sqrt());
        (0..n)
            .map(|i| {
                let z = 1.0 - (2 * i + 1) as f32 / n as f32;
                let r = (1.0 - z * z).sqrt();
                let (s, c) = (golden * i as f32).sin_cos();
                Vec3::new(r * c, r * s, z)
            })
            .collect()
    }

    #[test]
    fn the_basis_is_orthonormal() {
        let dirs = fibonacci(200_000);
        let w = 4.0 * std::f64::consts::PI / dirs.len() as f64;
        let mut gram = [[0.0f64; COEFFS]; COEFFS];
        for &d in &dirs {
            let y = basis(d);
            for i in 0..COEFFS {
                for j in 0..COEFFS {
                    gram[i][j] += f64::from(y[i]) * f64::from(y[j]) * w;
                }
            }
        }
        for (i, row) in gram.iter().enumerate() {
            for (j, g) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((g - want).abs() < 1e-3, "⟨Y{i}, Y{j}⟩ = {g}");
            }
        }
    }

    #[test]
    fn a_constant_map_projects_to_band_zero_and_a_smooth_one_is_recovered() {
        let c = project_env(&EnvMap::constant([2.0, 1.0, 0.5]));
        assert!((c[0] - Vec3::new(2.0, 1.0, 0.5) * (4.0 * std::f32::consts::PI).sqrt()).abs().max_element() < 1e-3);
        assert!(c[1..].iter().all(|v| v.abs().max_element() < 1e-3));
        for d in [Vec3::Y, Vec3::new(0.6, -0.3, 0.7).normalize()] {
            assert!((eval(&c, d) - Vec3::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-3);
        }
        // A δ light: its SH integrated against the clamped cosine at the light gives the
        // band-limited irradiance Σ_l Â_l (2l+1)/4π with Â = π, 2π/3, π/4, 0, −π/24: 31/32.
        let light = project_delta(Vec3::Y, Vec3::ONE);
        let dirs = fibonacci(20_000);
        let mut irr = 0.0f64;
        for d in dirs {
            irr += f64::from(eval(&light, d).x) * f64::from(d.y.max(0.0)) * 4.0 * std::f64::consts::PI / 20_000.0;
        }
        assert!((irr - 31.0 / 32.0).abs() < 1e-3, "{irr}");
    }
}
