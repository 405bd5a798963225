//! The leaf tissue as a homogeneous slab: diffuse reflectance R and transmittance T from its
//! thickness h, absorption σ_a and scattering σ_s (Kubelka–Munk, the closed form the paper's
//! LEAFMOD may be replaced by), in forms that stay finite at every extreme, and the inverse: the
//! coefficients that reproduce a measured R and T.
//!
//! With optical thicknesses x = σ_s h, y = σ_a h and β = √(y² + 2xy) (= bσ_s h),
//!
//! ```text
//! R = x / (x + y + β·coth β)        T = β / ((x + y)·sinh β + β·cosh β)
//! ```
//!
//! which is the textbook `R = sinh(bσ_s h)/(a sinh + b cosh)`, `T = b/(a sinh + b cosh)` divided
//! through by `sinh`; `β·coth β → 1` and `sinh β / β → 1` as β → 0 (no 0/0 when σ_a → 0, σ_s → 0
//! or h → 0), and the exponentials are taken as `e^{−β}` (no overflow as h → ∞).
//!
//! R and T depend on σ h only: (σ_a, σ_s, h) and (σ_a/k, σ_s/k, k·h) are the same leaf. A fit can
//! therefore recover the coefficients *given* a thickness ([`fit`]); the thickness itself is a
//! measurement (or a choice), not something R and T determine.

/// Diffuse reflectance and transmittance of a slab, one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Slab {
    /// Diffuse reflectance, hemispherical (0 ≤ R).
    pub r: f64,
    /// Diffuse transmittance, hemispherical (0 ≤ T, R + T ≤ 1).
    pub t: f64,
}

/// `β coth β` and `sinh β / β`, `cosh β` scaled by `e^{−β}`… in the forms [`slab`] needs.
fn hyperbolic_terms(beta: f64) -> (f64, f64, f64) {
    if beta < 1e-4 {
        // Series: β coth β = 1 + β²/3, sinh β/β = 1 + β²/6, cosh β = 1 + β²/2 (errors O(β⁴)).
        let b2 = beta * beta;
        return (1.0 + b2 / 3.0, 1.0 + b2 / 6.0, 1.0 + b2 / 2.0);
    }
    // e^{−β}·sinh β = (1 − e^{−2β})/2 and e^{−β}·cosh β = (1 + e^{−2β})/2: finite for any β.
    let e2 = (-2.0 * beta).exp();
    let (s, c) = ((1.0 - e2) / 2.0, (1.0 + e2) / 2.0);
    // β coth β = β c / s; for T we return the scaled (sinh β/β, cosh β), both times e^{−β}.
    (beta * c / s, s / beta, c)
}

/// R and T of a slab of thickness `h` with absorption `sigma_a` and scattering `sigma_s`
/// (all ≥ 0; negative or non-finite inputs are treated as 0 or ∞ by clamping, so the result is
/// always finite with R, T ≥ 0 and R + T ≤ 1).
pub fn slab(sigma_a: f64, sigma_s: f64, h: f64) -> Slab {
    let clean = |v: f64| if v.is_nan() { 0.0 } else { v.clamp(0.0, f64::MAX) };
    let (sigma_a, sigma_s, h) = (clean(sigma_a), clean(sigma_s), clean(h));
    let x = sigma_s * h;
    let y = sigma_a * h;
    let beta = (y * y + 2.0 * x * y).sqrt();
    if !(x + y).is_finite() || !beta.is_finite() {
        // Infinitely thick: the semi-infinite slab, R∞ = x/(x+y+β) = 1/(a+b); nothing gets through.
        let r = if sigma_s == 0.0 {
            0.0
        } else {
            let a = 1.0 + sigma_a / sigma_s;
            1.0 / (a + (a * a - 1.0).sqrt())
        };
        return Slab { r, t: 0.0 };
    }
    let (beta_coth, sinhc, cosh) = hyperbolic_terms(beta);
    let r = x / (x + y + beta_coth);
    let t = if beta < 1e-4 {
        1.0 / ((x + y) * sinhc + cosh)
    } else {
        // T = β e^{−β} / ((x+y)·e^{−β} sinh β + β·e^{−β} cosh β); here sinhc·β = e^{−β} sinh β.
        let e = (-beta).exp();
        beta * e / ((x + y) * sinhc * beta + beta * cosh)
    };
    Slab { r: r.clamp(0.0, 1.0), t: t.clamp(0.0, 1.0 - r.clamp(0.0, 1.0)) }
}

/// Why R and T cannot be fitted.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// R or T is negative or not finite, T is 0 (no thickness follows), or R + T > 1.
    #[error("reflectance {r} and transmittance {t} are not a slab's: need R ≥ 0, T > 0, R + T ≤ 1")]
    OutOfRange {
        /// The reflectance given.
        r: f64,
        /// The transmittance given.
        t: f64,
    },
    /// The thickness is not positive and finite.
    #[error("thickness {0} must be positive and finite")]
    Thickness(f64),
}

/// Absorption and scattering coefficients, one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// σ_a (per unit length).
    pub sigma_a: f64,
    /// σ_s (per unit length).
    pub sigma_s: f64,
}

/// The σ_a, σ_s of a slab of thickness `h` whose reflectance and transmittance are `r`, `t`: the
/// Kubelka–Munk inversion in closed form, a = (1 + R² − T²)/(2R), b = √(a² − 1),
/// σ_s h = ln((1 − R(a − b))/T)/b, σ_a = σ_s (a − 1); R = 0 is pure absorption (σ_a h = −ln T).
pub fn fit(r: f64, t: f64, h: f64) -> Result<Coefficients, FitError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(FitError::Thickness(h));
    }
    if !(r.is_finite() && t.is_finite() && r >= 0.0 && t > 0.0 && r + t <= 1.0) {
        return Err(FitError::OutOfRange { r, t });
    }
    if r == 0.0 {
        return Ok(Coefficients { sigma_a: -t.ln() / h, sigma_s: 0.0 });
    }
    let a = (1.0 + r * r - t * t) / (2.0 * r);
    let b = (a * a - 1.0).max(0.0).sqrt();
    let x = if b < 1e-7 {
        // No absorption: R = x/(1+x).
        r / (1.0 - r)
    } else {
        ((1.0 - r * (a - b)) / t).ln() / b
    };
    Ok(Coefficients { sigma_a: x * (a - 1.0) / h, sigma_s: x / h })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The textbook form, for moderate arguments only.
    fn textbook(sa: f64, ss: f64, h: f64) -> Slab {
        let a = (ss + sa) / ss;
        let b = (a * a - 1.0).sqrt();
        let (s, c) = ((b * ss * h).sinh(), (b * ss * h).cosh());
        Slab { r: s / (a * s + b * c), t: b / (a * s + b * c) }
    }

    #[test]
    fn matches_the_textbook_form_where_it_is_safe() {
        for (sa, ss, h) in [(1.0, 5.0, 0.2), (0.3, 20.0, 0.1), (4.0, 1.0, 0.5), (0.01, 10.0, 1.0)] {
            let (a, b) = (slab(sa, ss, h), textbook(sa, ss, h));
            assert!((a.r - b.r).abs() < 1e-12 && (a.t - b.t).abs() < 1e-12, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn limits_are_the_physical_ones() {
        // h → 0: nothing reflected, everything through.
        let thin = slab(3.0, 7.0, 1e-12);
        assert!(thin.r < 1e-10 && (thin.t - 1.0).abs() < 1e-10, "{thin:?}");
        assert_eq!(slab(3.0, 7.0, 0.0), Slab { r: 0.0, t: 1.0 });
        // σ_a → 0: the conservative slab, R = σ_s h/(1 + σ_s h), T = 1/(1 + σ_s h).
        let c = slab(1e-14, 4.0, 0.5);
        assert!((c.r - 2.0 / 3.0).abs() < 1e-9 && (c.t - 1.0 / 3.0).abs() < 1e-9, "{c:?}");
        assert_eq!(slab(0.0, 4.0, 0.5).r, 2.0 / 3.0);
        // σ_s → 0: Beer–Lambert, R = 0, T = e^{−σ_a h}.
        let b = slab(2.0, 0.0, 0.75);
        assert!(b.r == 0.0 && (b.t - (-1.5f64).exp()).abs() < 1e-12, "{b:?}");
        // h → ∞ (where sinh/cosh overflow): T → 0, R → the semi-infinite R∞ = 1/(a + b).
        let a = 1.0 + 1.0 / 5.0;
        let r_inf = 1.0 / (a + (a * a - 1.0f64).sqrt());
        for h in [1e3, 1e6, 1e300, f64::INFINITY] {
            let s = slab(1.0, 5.0, h);
            assert!(s.t < 1e-100 && (s.r - r_inf).abs() < 1e-12, "h = {h}: {s:?}");
        }
        // Nonsense in, finite out.
        for s in [slab(f64::NAN, 1.0, 1.0), slab(-1.0, f64::INFINITY, 1.0), slab(0.0, 0.0, f64::INFINITY)] {
            assert!(s.r.is_finite() && s.t.is_finite() && s.r + s.t <= 1.0, "{s:?}");
        }
    }

    proptest! {
        #[test]
        fn r_plus_t_never_exceeds_one(la in -12.0f64..12.0, ls in -12.0f64..12.0, lh in -12.0f64..12.0) {
            let s = slab(10f64.powf(la), 10f64.powf(ls), 10f64.powf(lh));
            prop_assert!(s.r.is_finite() && s.t.is_finite());
            prop_assert!(s.r >= 0.0 && s.t >= 0.0 && s.r + s.t <= 1.0 + 1e-12, "{:?}", s);
        }

        #[test]
        fn the_fit_recovers_known_coefficients(sa in 0.05f64..40.0, ss in 0.05f64..40.0, h in 0.01f64..2.0) {
            let s = slab(sa, ss, h);
            prop_assume!(s.t > 1e-9 && s.r > 1e-9);
            let c = fit(s.r, s.t, h).unwrap();
            prop_assert!((c.sigma_a - sa).abs() < 1e-5 * sa.max(1.0), "σ_a {} vs {}", c.sigma_a, sa);
            prop_assert!((c.sigma_s - ss).abs() < 1e-5 * ss.max(1.0), "σ_s {} vs {}", c.sigma_s, ss);
        }
    }

    #[test]
    fn the_fit_names_what_no_slab_can_do() {
        assert_eq!(fit(0.6, 0.5, 1.0), Err(FitError::OutOfRange { r: 0.6, t: 0.5 }));
        assert!(matches!(fit(0.1, 0.0, 1.0), Err(FitError::OutOfRange { .. })));
        assert!(matches!(fit(f64::NAN, 0.2, 1.0), Err(FitError::OutOfRange { .. })));
        assert_eq!(fit(0.1, 0.2, 0.0), Err(FitError::Thickness(0.0)));
        // Pure absorption and pure scattering are inverted too.
        let c = fit(0.0, 0.5, 2.0).unwrap();
        assert!((c.sigma_a - 0.5f64.ln().abs() / 2.0).abs() < 1e-12 && c.sigma_s == 0.0);
        let s = slab(0.0, 3.0, 1.0);
        let c = fit(s.r, s.t, 1.0).unwrap();
        assert!(c.sigma_a.abs() < 1e-6 && (c.sigma_s - 3.0).abs() < 1e-6, "{c:?}");
        // Only σh is determined: the same R, T at twice the thickness halves the coefficients.
        let s = slab(2.0, 8.0, 0.3);
        let (c1, c2) = (fit(s.r, s.t, 0.3).unwrap(), fit(s.r, s.t, 0.6).unwrap());
        assert!((c1.sigma_a - 2.0 * c2.sigma_a).abs() < 1e-9 && (c1.sigma_s - 2.0 * c2.sigma_s).abs() < 1e-9);
    }
}
