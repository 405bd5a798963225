//! BRDFs evaluated at run time (never precomputed), from a [`Material`]:
//! Lambert `kd/π`; normalised Blinn-Phong `kd/π + ks (n+8)/(8π) cos^n θ_h`; normalised Phong
//! `kd/π + ks (n+2)/(2π) cos^n α_r`; microfacet GGX (Trowbridge-Reitz D, height-correlated Smith
//! G, Schlick Fresnel from `ks`) plus the Lambert term.
//!
//! `eval(m, n, wi, wo)` is f_r without the cosine (the cuts carry max(0, n·ω)); it is 0 when
//! either direction is below the surface.

use glam::Vec3;
use std::f32::consts::PI;
use vcut_scene::material::{EXPONENT, REFLECTANCE, ROUGHNESS};
use vcut_scene::{BrdfModel, Material};

/// sin 1°: how far above its tangent plane a silhouette vertex is viewed ([`view_direction`]).
pub const GRAZING: f32 = 0.017_452_406;

/// The direction ω_o a vertex at `x` with unit normal `n` is shaded toward for an eye at `eye`:
/// the eye's direction where the normal faces it at least 1° above the tangent plane; below that
/// (a vertex of a visible triangle whose smooth normal turns away, along every silhouette of a
/// curved mesh) the eye's direction bent onto the tangent plane and raised to 1° above it, so the
/// shading runs on continuously across the silhouette instead of dropping to black; an eye
/// straight behind the vertex views it along its normal. The frame and every reference use it.
#[inline]
pub fn view_direction(n: Vec3, x: Vec3, eye: Vec3) -> Vec3 {
    let wo = (eye - x).normalize_or_zero();
    let c = n.dot(wo);
    if c >= GRAZING {
        return wo;
    }
    let t = (wo - c * n).normalize_or_zero();
    if t == Vec3::ZERO {
        return n;
    }
    (t * (1.0 - GRAZING * GRAZING).sqrt() + n * GRAZING).normalize()
}

/// f_r(ω_i, ω_o) for unit normal `n`, unit `wi` (towards the light) and `wo` (towards the eye).
#[inline]
pub fn eval(m: &Material, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
    let (cos_i, cos_o) = (n.dot(wi), n.dot(wo));
    if cos_i <= 0.0 || cos_o <= 0.0 {
        return Vec3::ZERO;
    }
    let kd = Vec3::from(m.kd) / PI;
    let ks = Vec3::from(m.ks);
    match m.model {
        BrdfModel::Lambert => kd,
        BrdfModel::BlinnPhong => {
            let h = (wi + wo).normalize_or_zero();
            let c = n.dot(h).max(0.0);
            kd + ks * ((m.exponent + 8.0) / (8.0 * PI) * c.powf(m.exponent))
        }
        BrdfModel::Phong => {
            let r = 2.0 * cos_i * n - wi;
            let c = r.dot(wo).max(0.0);
            kd + ks * ((m.exponent + 2.0) / (2.0 * PI) * c.powf(m.exponent))
        }
        BrdfModel::Ggx => {
            let a2 = (m.roughness * m.roughness).max(1e-8);
            let h = (wi + wo).normalize_or_zero();
            let nh = n.dot(h).max(0.0);
            let d = a2 / (PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
            let lambda = |c: f32| (a2 + (1.0 - a2) * c * c).sqrt();
            // Height-correlated Smith visibility V = G / (4 cos_i cos_o).
            let v = 0.5 / (cos_o * lambda(cos_i) + cos_i * lambda(cos_o)).max(1e-12);
            let f = ks + (Vec3::ONE - ks) * (1.0 - wi.dot(h).clamp(0.0, 1.0)).powi(5);
            kd + f * (d * v)
        }
    }
}

/// `x^a` on [0, 1] from a table of 8,193 values with linear interpolation: for a frame's inner
/// loop, where `powf` was half the shading time. The error is at most `a(a−1)/(8·8192²)` of
/// the lobe's peak (9e-6 at a = 70, 7e-5 at a = 200) plus f32 rounding (`1e-8·a + 2e-7`; tested); [`PowTable::new`] declines
/// exponents above 200, where it would grow past that. Values below 1e-20 are stored as 0:
/// at high exponents most of the table is otherwise subnormal (0.28^70 < 2^-126), and every
/// product with a subnormal costs the CPU a microcode assist, which would make a glossy edit's
/// shading slower than a dull one's for that alone.
#[derive(Debug, Clone)]
pub struct PowTable {
    values: Vec<f32>,
}

impl PowTable {
    const STEPS: usize = 8192;

    /// The table of `x^a`, or `None` for `a > 200` (use `powf`).
    pub fn new(a: f32) -> Option<PowTable> {
        (a.is_finite() && (0.0..=200.0).contains(&a)).then(|| PowTable {
            values: (0..=Self::STEPS)
                .map(|i| (i as f64 / Self::STEPS as f64).powf(a as f64))
                .map(|v| if v < 1e-20 { 0.0 } else { v as f32 })
                .collect(),
        })
    }

    /// `x^a` for `x` in [0, 1] (clamped).
    #[inline(always)]
    pub fn get(&self, x: f32) -> f32 {
        let t = x.clamp(0.0, 1.0) * Self::STEPS as f32;
        let i = (t as usize).min(Self::STEPS - 1);
        let (a, b) = (self.values[i], self.values[i + 1]);
        a + (t - i as f32) * (b - a)
    }
}

/// The part of f_r beyond the Lambert term `kd/π`, for one surface point: normal `n` and view
/// direction `wo` fixed, so what depends only on them is computed once and a frame's inner loop
/// (one evaluation per cut node) does the rest. `kd/π + lobe.eval(wi)` equals [`eval`] wherever
/// both `n·wi` and `n·wo` are positive (the caller's guarantee).
#[derive(Debug, Clone, Copy)]
pub enum Lobe<'a> {
    /// Lambert: nothing beyond `kd/π`.
    None,
    /// Normalised Blinn-Phong: `ks (α+8)/(8π) (n·h)^α`.
    BlinnPhong {
        /// Normal.
        n: Vec3,
        /// View direction.
        wo: Vec3,
        /// `ks (α+8)/(8π)`.
        scale: Vec3,
        /// `x^α`.
        pow: Pow<'a>,
    },
    /// Normalised Phong: `ks (α+2)/(2π) (r·wo)^α` — evaluated as `(r_o·wi)^α` with `r_o` the
    /// mirror of `wo`, the same number.
    Phong {
        /// `wo` mirrored about the normal.
        mirror: Vec3,
        /// `ks (α+2)/(2π)`.
        scale: Vec3,
        /// `x^α`.
        pow: Pow<'a>,
    },
    /// GGX with height-correlated Smith visibility and Schlick Fresnel.
    Ggx {
        /// Normal.
        n: Vec3,
        /// View direction.
        wo: Vec3,
        /// `n·wo`.
        cos_o: f32,
        /// α².
        a2: f32,
        /// Smith Λ term of `wo`: `sqrt(α² + (1 − α²) cos_o²)`.
        lambda_o: f32,
        /// F0.
        ks: Vec3,
    },
}

/// How a lobe raises to its exponent: through a [`PowTable`] or `powf`.
#[derive(Debug, Clone, Copy)]
pub enum Pow<'a> {
    /// Interpolated from a table of this exponent.
    Table(&'a PowTable),
    /// `powf` with this exponent.
    Exact(f32),
}

impl Pow<'_> {
    #[inline(always)]
    fn of(self, x: f32) -> f32 {
        match self {
            Pow::Table(t) => t.get(x),
            Pow::Exact(a) => x.max(0.0).powf(a),
        }
    }
}

impl<'a> Lobe<'a> {
    /// The lobe of `m` at normal `n` seen from `wo` (both unit), with exact powers.
    pub fn new(m: &Material, n: Vec3, wo: Vec3) -> Lobe<'a> {
        Self::with_pow(m, n, wo, Pow::Exact(m.exponent))
    }

    /// The lobe of `m` at normal `n` seen from `wo` (both unit), raising to `m.exponent` by
    /// `pow` (a table of that exponent, or exact).
    pub fn with_pow(m: &Material, n: Vec3, wo: Vec3, pow: Pow<'a>) -> Lobe<'a> {
        let ks = Vec3::from(m.ks);
        match m.model {
            BrdfModel::Lambert => Lobe::None,
            BrdfModel::BlinnPhong => Lobe::BlinnPhong { n, wo, scale: ks * ((m.exponent + 8.0) / (8.0 * PI)), pow },
            BrdfModel::Phong => {
                Lobe::Phong { mirror: 2.0 * n.dot(wo) * n - wo, scale: ks * ((m.exponent + 2.0) / (2.0 * PI)), pow }
            }
            BrdfModel::Ggx => {
                let a2 = (m.roughness * m.roughness).max(1e-8);
                let cos_o = n.dot(wo);
                Lobe::Ggx { n, wo, cos_o, a2, lambda_o: (a2 + (1.0 - a2) * cos_o * cos_o).sqrt(), ks }
            }
        }
    }

    /// The lobe's value toward `wi` (unit, above the surface).
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> Vec3 {
        match *self {
            Lobe::None => Vec3::ZERO,
            Lobe::BlinnPhong { n, wo, scale, pow } => {
                // n·h without normalising h; wi + wo ≠ 0 as both are above the surface.
                let s = wi + wo;
                scale * pow.of(n.dot(s) / s.length())
            }
            Lobe::Phong { mirror, scale, pow } => scale * pow.of(mirror.dot(wi)),
            Lobe::Ggx { n, wo, cos_o, a2, lambda_o, ks } => {
                let h = (wi + wo).normalize_or_zero();
                let nh = n.dot(h).max(0.0);
                let d = a2 / (PI * (nh * nh * (a2 - 1.0) + 1.0).powi(2));
                let cos_i = n.dot(wi);
                let lambda_i = (a2 + (1.0 - a2) * cos_i * cos_i).sqrt();
                let v = 0.5 / (cos_o * lambda_i + cos_i * lambda_o).max(1e-12);
                let f = ks + (Vec3::ONE - ks) * (1.0 - wi.dot(h).clamp(0.0, 1.0)).powi(5);
                f * (d * v)
            }
        }
    }
}

/// Why a material edit ([`parse_spec`]) was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpecError {
    /// MODEL is none of the known ones.
    #[error("unknown BRDF model '{0}' (lambert, blinn-phong, phong, ggx)")]
    Model(String),
    /// A parameter without `=`.
    #[error("'{0}': expected KEY=VALUE")]
    NotKeyValue(String),
    /// A value out of its key's range, or not one value or `r/g/b`.
    #[error("{key} = {value}: {reason}")]
    Value {
        /// The key.
        key: String,
        /// The value as given.
        value: String,
        /// What is wrong with it.
        reason: String,
    },
    /// KEY is none of the known ones.
    #[error("unknown BRDF parameter '{0}' (kd, ks, alpha, roughness)")]
    Parameter(String),
    /// The edited material is out of range (as a scene file's would be refused).
    #[error(transparent)]
    Material(#[from] vcut_scene::MaterialError),
}

/// Parses a material edit `MODEL[:KEY=VALUE,...]` over `base`: MODEL is `lambert`,
/// `blinn-phong`, `phong`, `ggx` or `same`; keys `kd` and `ks` (one value or `r/g/b`, each in
/// [0, 1]), `alpha` or `exponent` (Phong exponents), `roughness` (GGX α). The result passes
/// [`Material::validate`], as a scene file's material must. Example: `blinn-phong:alpha=70`.
pub fn parse_spec(base: Material, spec: &str) -> Result<Material, SpecError> {
    let (model, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let mut m = base;
    m.model = match model.trim() {
        "lambert" => BrdfModel::Lambert,
        "blinn-phong" => BrdfModel::BlinnPhong,
        "phong" => BrdfModel::Phong,
        "ggx" => BrdfModel::Ggx,
        "same" | "" => base.model,
        other => return Err(SpecError::Model(other.into())),
    };
    for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (k, v) = kv.split_once('=').ok_or_else(|| SpecError::NotKeyValue(kv.into()))?;
        let bad = |x: &str, reason: String| SpecError::Value { key: k.into(), value: x.into(), reason };
        let limit = match k.trim() {
            "kd" | "ks" => REFLECTANCE,
            "roughness" => ROUGHNESS,
            _ => EXPONENT,
        };
        let num = |x: &str| -> Result<f32, SpecError> {
            let f: f32 = x.trim().parse().map_err(|_| bad(x, format!("not a number: must be {}", limit.describe())))?;
            limit.check(f64::from(f)).map(|_| f).map_err(|reason| bad(x, reason))
        };
        let rgb = |x: &str| -> Result<[f32; 3], SpecError> {
            let parts: Vec<f32> = x.split('/').map(num).collect::<Result<_, _>>()?;
            match parts.as_slice() {
                [g] => Ok([*g; 3]),
                [r, g, b] => Ok([*r, *g, *b]),
                _ => Err(bad(x, "one value or r/g/b".into())),
            }
        };
        match k.trim() {
            "kd" => m.kd = rgb(v)?,
            "ks" => m.ks = rgb(v)?,
            "alpha" | "exponent" => m.exponent = num(v)?.max(1e-3),
            "roughness" => m.roughness = num(v)?.max(1e-3),
            other => return Err(SpecError::Parameter(other.into())),
        }
    }
    m.validate()?;
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Above 1° the eye's own direction; below it bent to 1° above the tangent plane, in the
    /// eye's azimuth, continuous at 1°; straight behind, the normal.
    #[test]
    fn view_direction_bends_below_grazing_only() {
        let n = Vec3::Z;
        let x = Vec3::new(0.3, -0.2, 0.1);
        for deg in [90.0f32, 30.0, 1.5, 1.0, 0.5, 0.0, -10.0, -60.0, -89.0] {
            let (s, c) = deg.to_radians().sin_cos();
            let eye = x + 5.0 * Vec3::new(c * 0.6, c * 0.8, s);
            let wo = view_direction(n, x, eye);
            assert!((wo.length() - 1.0).abs() < 1e-5, "{deg}°: not unit");
            assert!(n.dot(wo) >= GRAZING - 1e-5, "{deg}°: below 1°");
            if deg >= 1.0 {
                assert!((wo - (eye - x).normalize()).length() < 1e-5, "{deg}°: bent above 1°");
            } else {
                assert!((n.dot(wo) - GRAZING).abs() < 1e-5, "{deg}°: not at 1°");
                let az = Vec3::new(wo.x, wo.y, 0.0).normalize();
                assert!((az - Vec3::new(0.6, 0.8, 0.0)).length() < 1e-4, "{deg}°: azimuth turned");
            }
        }
        assert_eq!(view_direction(n, x, x - 3.0 * n), n);
    }

    /// ∫ f_r cos dω_i over the hemisphere by a fine midpoint rule.
    fn albedo(m: &Material, wo: Vec3) -> Vec3 {
        let n = Vec3::Y;
        let (nt, np) = (400, 800);
        let mut sum = Vec3::ZERO;
        for i in 0..nt {
            let t = (i as f32 + 0.5) / nt as f32 * PI / 2.0;
            for j in 0..np {
                let p = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let wi = Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
                sum += eval(m, n, wi, wo) * t.cos() * t.sin() * (PI / 2.0 / nt as f32) * (2.0 * PI / np as f32);
            }
        }
        sum
    }

    #[test]
    fn energy_is_conserved_and_lambert_is_exact() {
        let wo = Vec3::new(0.3, 0.9, 0.1).normalize();
        let a = albedo(&Material::lambert([0.5, 0.25, 1.0]), wo);
        assert!((a - Vec3::new(0.5, 0.25, 1.0)).abs().max_element() < 2e-3, "{a}");
        for model in [BrdfModel::BlinnPhong, BrdfModel::Phong, BrdfModel::Ggx] {
            for (exponent, roughness) in [(15.0, 0.5), (70.0, 0.2)] {
                let m = Material { model, kd: [0.0; 3], ks: [1.0; 3], exponent, roughness };
                let a = albedo(&m, Vec3::Y);
                // Normalised lobes reflect about what arrives at normal view; (n+8)/(8π) is the
                // usual approximate Blinn-Phong normalisation (7 % over at n = 15).
                assert!(a.x <= 1.08 && a.x > 0.6, "{model:?} n={exponent} α={roughness}: {a}");
            }
        }
        assert_eq!(eval(&Material::default(), Vec3::Y, -Vec3::Y, Vec3::Y), Vec3::ZERO);
    }

    #[test]
    fn pow_tables_stay_within_their_bound() {
        for a in [0.0f32, 1.0, 15.0, 70.0, 200.0] {
            let t = PowTable::new(a).unwrap();
            let bound = a * (a - 1.0).max(0.0) / (8.0 * 8192.0 * 8192.0) * 1.01 + 1e-8 * a + 2e-7;
            let worst = (0..=100_000)
                .map(|i| i as f32 / 100_000.0)
                .map(|x| (t.get(x) as f64 - (x as f64).powf(a as f64)).abs())
                .fold(0.0, f64::max);
            assert!(worst <= bound as f64, "a = {a}: {worst} > {bound}");
        }
        assert!(PowTable::new(201.0).is_none() && PowTable::new(f32::NAN).is_none());
        // No subnormal values (slow to multiply), however high the exponent.
        let t = PowTable::new(200.0).unwrap();
        assert!(t.values.iter().all(|v| *v == 0.0 || v.is_normal()));
        assert!((0..=1000).map(|i| t.get(i as f32 / 1000.0)).all(|v| v == 0.0 || v.is_normal()));
    }

    #[test]
    fn lobes_plus_lambert_are_the_brdf() {
        let n = Vec3::new(0.2, 0.9, -0.1).normalize();
        let wo = Vec3::new(0.5, 0.8, 0.3).normalize();
        for model in [BrdfModel::Lambert, BrdfModel::BlinnPhong, BrdfModel::Phong, BrdfModel::Ggx] {
            let m = Material { model, kd: [0.3, 0.5, 0.7], ks: [0.4, 0.2, 0.1], exponent: 40.0, roughness: 0.3 };
            let lobe = Lobe::new(&m, n, wo);
            let table = PowTable::new(m.exponent).unwrap();
            let tabled = Lobe::with_pow(&m, n, wo, Pow::Table(&table));
            for i in 0..200 {
                let (t, p) = (i as f32 * 0.0077, i as f32 * 0.61);
                let wi = Vec3::new(t.sin() * p.cos(), t.cos(), t.sin() * p.sin());
                if n.dot(wi) <= 0.0 {
                    continue;
                }
                let want = eval(&m, n, wi, wo);
                let got = Vec3::from(m.kd) / PI + lobe.eval(wi);
                assert!((got - want).abs().max_element() <= 1e-5 * want.max_element().max(1.0), "{model:?} {wi}");
                // The table's error is relative to the lobe's peak, ks (α+8)/(8π) ≈ 0.7 here.
                let got = Vec3::from(m.kd) / PI + tabled.eval(wi);
                assert!((got - want).abs().max_element() <= 2e-5, "{model:?} {wi} tabled");
            }
        }
    }

    #[test]
    fn specs_parse_over_a_base_and_errors_name_the_key() {
        let m = parse_spec(Material::default(), "blinn-phong:alpha=70,kd=0.1/0.2/0.3").unwrap();
        assert_eq!((m.model, m.exponent, m.kd), (BrdfModel::BlinnPhong, 70.0, [0.1, 0.2, 0.3]));
        let g = parse_spec(m, "ggx:roughness=0.2").unwrap();
        assert_eq!((g.model, g.roughness, g.kd), (BrdfModel::Ggx, 0.2, [0.1, 0.2, 0.3]));
        assert_eq!(parse_spec(m, "velvet"), Err(SpecError::Model("velvet".into())));
        assert!(parse_spec(m, "phong:alpha=-3").unwrap_err().to_string().contains("alpha = -3"));
        assert_eq!(parse_spec(m, "phong:shine=3"), Err(SpecError::Parameter("shine".into())));
        // Values a scene file refuses are refused here too.
        assert!(parse_spec(m, "lambert:kd=5").unwrap_err().to_string().contains("[0, 1]"));
    }

    #[test]
    fn blinn_phong_sharpens_with_the_exponent() {
        let n = Vec3::Y;
        let wo = Vec3::new(0.5, 0.8, 0.0).normalize();
        let mirror = Vec3::new(-wo.x, wo.y, -wo.z);
        let off = Vec3::new(-0.2, 0.9, 0.3).normalize();
        let m =
            |e: f32| Material { model: BrdfModel::BlinnPhong, kd: [0.0; 3], ks: [1.0; 3], exponent: e, roughness: 0.3 };
        assert!(eval(&m(70.0), n, mirror, wo).x > eval(&m(15.0), n, mirror, wo).x);
        assert!(eval(&m(70.0), n, off, wo).x < eval(&m(15.0), n, off, wo).x);
    }
}
