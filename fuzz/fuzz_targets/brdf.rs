//! Fuzz target: BRDF parameters and edits. An arbitrary edit string (`MODEL:KEY=VALUE,...`) over
//! one of four base materials is refused with a typed error or gives a material that passes
//! `Material::validate` (what a scene file must) and whose BRDF — evaluated whole and as the
//! specular lobe, with exact and tabled powers — is finite and ≥ 0 for directions above the
//! surface.
#![no_main]

use glam::Vec3;
use libfuzzer_sys::fuzz_target;
use vcut_scene::Material;
use vcut_shade::brdf::{Lobe, Pow, PowTable, eval, parse_spec};

/// A unit direction above the plane of `n` = +Y from three bytes (`None` if degenerate).
fn above(b: &[u8]) -> Option<Vec3> {
    let v = Vec3::new(f32::from(b[0]) - 127.5, f32::from(b[1]) / 2.0 + 0.01, f32::from(b[2]) - 127.5);
    v.try_normalize()
}

fuzz_target!(|data: &[u8]| {
    let [base, w @ .., d0, d1, d2, d3, d4, d5] = data else { return };
    let base = match base % 4 {
        0 => Material::default(),
        1 => Material::lambert([0.5, 0.25, 1.0]),
        2 => Material::from_gltf_pbr([0.8, 0.2, 0.1], 1.0, 0.05),
        _ => Material::from_gltf_pbr([1.0, 1.0, 1.0], 0.0, 1.0),
    };
    let spec = String::from_utf8_lossy(w);
    let m = match parse_spec(base, &spec) {
        Ok(m) => m,
        Err(e) => {
            assert!(!e.to_string().is_empty());
            return;
        }
    };
    m.validate().expect("an accepted edit gives a valid material");
    let (Some(wi), Some(wo)) = (above(&[*d0, *d1, *d2]), above(&[*d3, *d4, *d5])) else { return };
    let n = Vec3::Y;
    let ok = |v: Vec3| v.is_finite() && v.min_element() >= 0.0;
    let f = eval(&m, n, wi, wo);
    assert!(ok(f), "f_r = {f} for {m:?}, wi {wi}, wo {wo}");
    assert!(ok(Lobe::new(&m, n, wo).eval(wi)), "lobe of {m:?}");
    if let Some(table) = PowTable::new(m.exponent) {
        let lobe = Lobe::with_pow(&m, n, wo, Pow::Table(&table));
        assert!(ok(lobe.eval(wi)), "tabled lobe of {m:?}");
    }
});
