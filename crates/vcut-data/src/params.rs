//! Precompute parameters and their presets `fast`, `balanced`, `paper`.
//!
//! Every parameter has a name (the key in a scene file's `[precompute]` table and in
//! `vcuts precompute --set KEY=VALUE`), is recorded in the output's `params` section
//! ([`PrecomputeParams::to_toml`]; read back typed as [`crate::Precomputed::record`]), and is
//! checked when set.

use crate::RadialSpacing;
use std::f64::consts::PI;
use vcut_cut::codec::{ShapeCoding, ValueFormat};
use vcut_cut::select::SelectParams;
use vcut_cut::turn::TurnShape;
use vcut_scene::limits::Limit;

/// Everything that decides the precomputed data.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecomputeParams {
    /// Preset the values started from.
    pub preset: String,
    /// Number of directions N (a power of two, 2^6..2^16).
    pub directions: u32,
    /// Seed of the direction set (spherical-Fibonacci start, so the seed only names the cache).
    pub direction_seed: u64,
    /// SVC cut selection: split nodes whose error E_k is above this.
    pub svc_max_error: f64,
    /// SVC cut selection: split non-zero nodes whose solid angle is above 4π / this.
    pub svc_solid_angle_divisor: f64,
    /// SVC ray origin offset along the normal, as a fraction of the object's bounding radius.
    pub svc_origin_offset: f32,
    /// Vertices per SVC section (the unit of resume).
    pub svc_chunk: u32,
    /// How SVC values are stored.
    pub svc_values: ValueFormat,
    /// How cut shapes are stored (both SVCs and fields).
    pub shape_coding: ShapeCoding,
    /// Field spheres S.
    pub field_spheres: u32,
    /// Field cube-map resolution R (6·R² points per sphere).
    pub field_resolution: u32,
    /// Innermost field sphere radius / bounding radius.
    pub field_inner: f32,
    /// The innermost radius for a flat object (a ground, a leaf): each field's innermost sphere
    /// sits at its object's smallest bounding-box half-extent / r, kept within
    /// [`field_inner_flat`, `field_inner`]. Inside it lookups clamp, which costs nothing inside a
    /// solid object (no receivers there) but blurs the shadow a flat one casts on what stands on
    /// it. Setting it to `field_inner` restores the paper's one radius for every object.
    pub field_inner_flat: f32,
    /// Outermost field sphere radius / bounding radius.
    pub field_outer: f32,
    /// How the field spheres are spaced between inner and outer (geometric: a constant ratio,
    /// dense near the object; linear: evenly, as the paper).
    pub field_spacing: RadialSpacing,
    /// Field cut selection error threshold (0 = exact; must stay below 0.25). Setting it above
    /// 0 switches one-bit field values to u8.
    pub field_max_error: f64,
    /// How field values are stored (`u1` for exact fields).
    pub field_values: ValueFormat,
    /// Turn steps M per full turn about +Y (0: none). A set of M > 0 is symmetric under turns
    /// by 360°/M (`vcut_sphere::symmetric`), its tree is wedged and no stored cut uses a node
    /// above the wedges (`vcut_cut::turn`), so an object can turn by whole steps at run time.
    /// Recorded only when set, so files made without it keep their bytes.
    pub turn_steps: u32,
    /// Bands of latitude a turnable set's tree splits into above its wedges (a power of two;
    /// `vcut_dirtree`'s module docs say why), or 0 for `DirectionTree::default_bands`, which
    /// [`PrecomputeParams::settle`] puts in its place: a file records the bands it was made
    /// with, whatever later defaults become. Recorded with `turn_steps`.
    pub turn_bands: u32,
}

/// The range of `svc_max_error`.
pub const SVC_MAX_ERROR: Limit = Limit::within(0.0, 1.0, "");
/// The range of `field_spheres`.
pub const FIELD_SPHERES: Limit = Limit::within(1.0, 256.0, "spheres");
/// The range of `field_resolution`.
pub const FIELD_RESOLUTION: Limit = Limit::within(1.0, 256.0, "texels a face side");
/// The range of `field_max_error`: binary visibility never has more variance than 0.25.
pub const FIELD_MAX_ERROR: Limit = Limit::at_least_below(0.0, 0.25, "");

/// Numeric parameter `key` written as `value`, within [`PrecomputeParams::limit`].
fn number(key: &str, value: &str) -> Result<f64, ParamError> {
    limited(key, value, |l| l.parse(value))
}

/// [`number`] for an f32 parameter: checked as the f32 it becomes.
fn number32(key: &str, value: &str) -> Result<f32, ParamError> {
    limited(key, value, |l| l.parse_f32(value))
}

/// Whole-number parameter `key` written as `value`, within [`PrecomputeParams::limit`].
fn whole(key: &str, value: &str) -> Result<u32, ParamError> {
    limited(key, value, |l| l.parse_whole(value).map(|n| n as u32))
}

/// `parse` with `key`'s limit, its reason (which quotes the value) as the parameter's error.
fn limited<T>(key: &str, value: &str, parse: impl FnOnce(Limit) -> Result<T, String>) -> Result<T, ParamError> {
    let limit = PrecomputeParams::limit(key).unwrap_or(Limit::finite(""));
    parse(limit).map_err(|reason| ParamError::Value {
        key: key.into(),
        value: value.into(),
        reason: reason.trim_start_matches(&format!("{value:?}")).trim_start_matches([':', ' ']).into(),
    })
}

/// A parameter could not be set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParamError {
    /// No such parameter or preset.
    #[error("unknown {what} '{name}' (known: {known})")]
    Unknown {
        /// "parameter" or "preset".
        what: &'static str,
        /// The name given.
        name: String,
        /// The known names.
        known: String,
    },
    /// A value that does not parse or is out of range.
    #[error("parameter {key} = {value}: {reason}")]
    Value {
        /// The parameter.
        key: String,
        /// The value given.
        value: String,
        /// What is wrong.
        reason: String,
    },
}

/// Parameter names, in the order they are recorded.
pub const KEYS: [&str; 19] = [
    "preset",
    "directions",
    "direction_seed",
    "svc_max_error",
    "svc_solid_angle_divisor",
    "svc_origin_offset",
    "svc_chunk",
    "svc_values",
    "shape_coding",
    "field_spheres",
    "field_resolution",
    "field_inner",
    "field_inner_flat",
    "field_outer",
    "field_spacing",
    "field_max_error",
    "field_values",
    "turn_steps",
    "turn_bands",
];

/// Preset names.
pub const PRESETS: [&str; 3] = ["fast", "balanced", "paper"];

impl PrecomputeParams {
    /// The paper's setting: 32,768 directions, 32 spheres from 0.2r to 10r of 6×32×32 points,
    /// exact field cuts — with the spheres spaced geometrically, not evenly as in the paper
    /// (`field_spacing = "linear"` restores that; see `vcut_data::field` for why and by how much),
    /// and a flat object's innermost sphere at down to 0.05r (`field_inner_flat = 0.2` restores
    /// the paper's 0.2r for all).
    pub fn paper() -> Self {
        Self {
            preset: "paper".into(),
            directions: 32_768,
            direction_seed: 0,
            svc_max_error: 0.005,
            svc_solid_angle_divisor: 256.0,
            svc_origin_offset: 1e-4,
            svc_chunk: 2048,
            svc_values: ValueFormat::U16,
            shape_coding: ShapeCoding::SplitFlags,
            field_spheres: 32,
            field_resolution: 32,
            field_inner: 0.2,
            field_inner_flat: 0.05,
            field_outer: 10.0,
            field_spacing: RadialSpacing::Geometric,
            field_max_error: 0.0,
            field_values: ValueFormat::U1,
            turn_steps: 0,
            turn_bands: 0,
        }
    }

    /// The recommended default, from the Pareto front of the full `cargo xtask bench`'s
    /// trade-off sweeps on the teapot scene: 16,384 directions, 32 geometrically spaced spheres
    /// of 6×16×16, SVC values in 8 bits — more spheres were the most accurate step, and 8-bit SVC
    /// values cost no accuracy for their size (`docs/benchmarks.md` has the sweep).
    pub fn balanced() -> Self {
        Self {
            preset: "balanced".into(),
            directions: 16_384,
            svc_solid_angle_divisor: 128.0,
            svc_values: ValueFormat::U8,
            field_spheres: 32,
            field_resolution: 16,
            ..Self::paper()
        }
    }

    /// A first look in seconds: 4,096 directions, 8 spheres of 6×8×8, looser SVC cuts.
    pub fn fast() -> Self {
        Self {
            preset: "fast".into(),
            directions: 4096,
            svc_max_error: 0.01,
            svc_solid_angle_divisor: 64.0,
            field_spheres: 8,
            field_resolution: 8,
            ..Self::paper()
        }
    }

    /// The preset called `name`.
    pub fn preset(name: &str) -> Result<Self, ParamError> {
        match name {
            "fast" => Ok(Self::fast()),
            "balanced" => Ok(Self::balanced()),
            "paper" => Ok(Self::paper()),
            _ => Err(ParamError::Unknown { what: "preset", name: name.into(), known: PRESETS.join(", ") }),
        }
    }

    /// Sets parameter `key` from its text form, checking its range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        let bad = |reason: &str| ParamError::Value { key: key.into(), value: value.into(), reason: reason.into() };
        fn num<T: std::str::FromStr>(v: &str, bad: impl Fn(&str) -> ParamError) -> Result<T, ParamError> {
            v.trim().parse().map_err(|_| bad("not a number of the right kind"))
        }
        match key {
            "preset" => {
                let p = Self::preset(value)?;
                *self = p;
            }
            "directions" => {
                let n: u32 = num(value, bad)?;
                if !n.is_power_of_two() || !(64..=65_536).contains(&n) {
                    return Err(bad("must be a power of two from 64 to 65,536"));
                }
                self.directions = n;
            }
            "direction_seed" => self.direction_seed = num(value, bad)?,
            "svc_max_error" => self.svc_max_error = number(key, value)?,
            "svc_solid_angle_divisor" => self.svc_solid_angle_divisor = number(key, value)?,
            "svc_origin_offset" => self.svc_origin_offset = number32(key, value)?,
            "svc_chunk" => self.svc_chunk = whole(key, value)?,
            "shape_coding" => {
                self.shape_coding =
                    ShapeCoding::named(value.trim()).ok_or_else(|| bad("must be heights or split-flags"))?;
            }
            "svc_values" | "field_values" => {
                let f = ValueFormat::named(value.trim()).ok_or_else(|| bad("must be f32, f16, u16, u8 or u1"))?;
                if key == "svc_values" { self.svc_values = f } else { self.field_values = f }
            }
            "turn_steps" => {
                let m: u32 = num(value, bad)?;
                if m != 0 && (!m.is_power_of_two() || m < 2) {
                    return Err(bad("must be 0 (no turns) or a power of two from 2"));
                }
                self.turn_steps = m;
            }
            "turn_bands" => {
                let b: u32 = num(value, bad)?;
                if b != 0 && !b.is_power_of_two() {
                    return Err(bad("must be 0 (chosen from turn_steps) or a power of two (1: no bands)"));
                }
                self.turn_bands = b;
            }
            "field_spheres" => self.field_spheres = whole(key, value)?,
            "field_resolution" => self.field_resolution = whole(key, value)?,
            "field_inner" => self.field_inner = number32(key, value)?,
            "field_inner_flat" => self.field_inner_flat = number32(key, value)?,
            "field_outer" => self.field_outer = number32(key, value)?,
            "field_spacing" => {
                self.field_spacing =
                    RadialSpacing::named(value.trim()).ok_or_else(|| bad("must be geometric or linear"))?;
            }
            "field_max_error" => {
                let e = number(key, value)?;
                self.field_max_error = e;
                // Inexact fields hold fractions: one-bit values cannot store them.
                if e > 0.0 && self.field_values == ValueFormat::U1 {
                    self.field_values = ValueFormat::U8;
                }
            }
            _ => return Err(ParamError::Unknown { what: "parameter", name: key.into(), known: KEYS.join(", ") }),
        }
        Ok(())
    }

    /// The range of numeric parameter `key` (the one check of a number a user gives,
    /// [`vcut_scene::limits`]); `None` for the others (`directions`, a power of two, and the
    /// named choices).
    pub fn limit(key: &str) -> Option<Limit> {
        Some(match key {
            "svc_max_error" => SVC_MAX_ERROR,
            "svc_solid_angle_divisor" => Limit::at_least(1.0, "(4π/1 = no limit)"),
            "svc_origin_offset" => Limit::at_least_below(0.0, 0.1, "bounding radii"),
            "svc_chunk" => Limit::within(1.0, f64::from(u32::MAX), "vertices"),
            "field_spheres" => FIELD_SPHERES,
            "field_resolution" => FIELD_RESOLUTION,
            "field_inner" | "field_inner_flat" | "field_outer" => Limit::above(0.0, "bounding radii"),
            "field_max_error" => FIELD_MAX_ERROR,
            _ => return None,
        })
    }

    /// Sets every key of a scene file's `[precompute]` table (except `preset`, which chooses the
    /// starting point: see [`PrecomputeParams::resolve`]).
    pub fn apply_table(&mut self, table: &toml::Table) -> Result<(), ParamError> {
        for (k, v) in table.iter().filter(|(k, _)| *k != "preset") {
            let text = match v {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            self.set(k, &text)?;
        }
        Ok(())
    }

    /// The parameters of a run: the preset named on the command line, else the scene file's
    /// `preset`, else `balanced`; then the scene file's other keys; then `overrides` (from the
    /// command line) in order; then [`PrecomputeParams::check`].
    pub fn resolve(
        preset: Option<&str>,
        table: Option<&toml::Table>,
        overrides: &[(&str, &str)],
    ) -> Result<Self, ParamError> {
        let from_table = table.and_then(|t| t.get("preset")).and_then(|v| v.as_str());
        let mut p = Self::preset(preset.or(from_table).unwrap_or("balanced"))?;
        if let Some(t) = table {
            p.apply_table(t)?;
        }
        for (k, v) in overrides {
            p.set(k, v)?;
        }
        p.settle();
        p.check()?;
        Ok(p)
    }

    /// Checks what single parameters cannot: `field_inner < field_outer`; one-bit values only
    /// for exact fields (SVC values are fractional).
    pub fn check(&self) -> Result<(), ParamError> {
        let bad = |key: &str, value: &str, reason: &str| ParamError::Value {
            key: key.into(),
            value: value.into(),
            reason: reason.into(),
        };
        if self.svc_values == ValueFormat::U1 {
            return Err(bad("svc_values", "u1", "SVC values are fractional (cosine × visibility); use u8 or finer"));
        }
        if self.field_values == ValueFormat::U1 && self.field_max_error > 0.0 {
            return Err(bad(
                "field_values",
                "u1",
                "one-bit values need exact fields (field_max_error = 0); use u8 with a non-zero threshold",
            ));
        }
        if self.turn_steps > 0 && self.turn_steps > self.directions / 16 {
            return Err(ParamError::Value {
                key: "turn_steps".into(),
                value: self.turn_steps.to_string(),
                reason: format!(
                    "at most directions / 16 = {} (each step's wedge needs 16 directions or more)",
                    self.directions / 16
                ),
            });
        }
        if self.turn_steps > 0 && self.bands() > self.directions / self.turn_steps {
            return Err(ParamError::Value {
                key: "turn_bands".into(),
                value: self.bands().to_string(),
                reason: format!(
                    "at most directions / turn_steps = {} (each band needs a direction in every wedge)",
                    self.directions / self.turn_steps
                ),
            });
        }
        if self.field_inner >= self.field_outer {
            return Err(ParamError::Value {
                key: "field_inner".into(),
                value: self.field_inner.to_string(),
                reason: format!("must be below field_outer = {}", self.field_outer),
            });
        }
        Ok(())
    }

    /// The value of `key` in its text form (as [`PrecomputeParams::set`] reads it).
    pub fn get(&self, key: &str) -> Option<String> {
        Some(match key {
            "preset" => format!("\"{}\"", self.preset),
            "directions" => self.directions.to_string(),
            "direction_seed" => self.direction_seed.to_string(),
            "svc_max_error" => format!("{:?}", self.svc_max_error),
            "svc_solid_angle_divisor" => format!("{:?}", self.svc_solid_angle_divisor),
            "svc_origin_offset" => format!("{:?}", self.svc_origin_offset),
            "svc_chunk" => self.svc_chunk.to_string(),
            "svc_values" => format!("\"{}\"", self.svc_values.name()),
            "shape_coding" => format!("\"{}\"", self.shape_coding.name()),
            "field_spheres" => self.field_spheres.to_string(),
            "field_resolution" => self.field_resolution.to_string(),
            "field_inner" => format!("{:?}", self.field_inner),
            "field_inner_flat" => format!("{:?}", self.field_inner_flat),
            "field_outer" => format!("{:?}", self.field_outer),
            "field_spacing" => format!("\"{}\"", self.field_spacing.name()),
            "field_max_error" => format!("{:?}", self.field_max_error),
            "field_values" => format!("\"{}\"", self.field_values.name()),
            "turn_steps" => self.turn_steps.to_string(),
            // The bands the tree has, so a file records them whatever later defaults become.
            "turn_bands" => if self.turn_steps > 0 { self.bands() } else { self.turn_bands }.to_string(),
            _ => return None,
        })
    }

    /// All parameters as TOML `key = value` lines, in [`KEYS`] order (`turn_steps` and
    /// `turn_bands` only with turns: a file made without records what files always recorded).
    pub fn to_toml(&self) -> String {
        KEYS.iter()
            .filter(|&&k| !k.starts_with("turn_") || self.turn_steps > 0)
            .map(|k| format!("{k} = {}\n", self.get(k).unwrap_or_default()))
            .collect()
    }

    /// Parses what [`PrecomputeParams::to_toml`] wrote (or any subset of keys over a preset:
    /// `preset` first, then the rest).
    pub fn from_toml(text: &str) -> Result<Self, ParamError> {
        let mut p = Self::paper();
        for line in text.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#')) {
            let (k, v) = line.split_once('=').ok_or_else(|| ParamError::Value {
                key: line.into(),
                value: String::new(),
                reason: "expected key = value".into(),
            })?;
            p.set(k.trim(), v.trim().trim_matches('"'))?;
        }
        p.settle();
        p.check()?;
        Ok(p)
    }

    /// SVC cut selection thresholds.
    pub fn svc_select(&self) -> SelectParams {
        SelectParams {
            max_error: self.svc_max_error,
            max_solid_angle: 4.0 * PI / self.svc_solid_angle_divisor,
            turn: self.turn_shape(),
        }
    }

    /// Field cut selection thresholds (no solid-angle limit).
    pub fn field_select(&self) -> SelectParams {
        SelectParams { max_error: self.field_max_error, max_solid_angle: f64::INFINITY, turn: self.turn_shape() }
    }

    /// Puts the defaults that depend on other parameters in place (`turn_bands` 0 becomes the
    /// bands it stands for), as a run's parameters are recorded.
    pub fn settle(&mut self) {
        if self.turn_steps > 0 {
            self.turn_bands = self.bands();
        }
    }

    /// The bands of a turnable set's tree: `turn_bands`, or its default when 0.
    pub fn bands(&self) -> u32 {
        match self.turn_bands {
            0 => vcut_dirtree::DirectionTree::default_bands(self.directions as usize, self.turn_steps),
            b => b,
        }
    }

    /// The wedged tree's shape with `turn_steps` (stored cuts use no node without a turned
    /// image), else `None`.
    pub fn turn_shape(&self) -> Option<TurnShape> {
        (self.turn_steps > 0).then(|| {
            let band_height = self.directions.trailing_zeros().saturating_sub(self.bands().trailing_zeros());
            TurnShape { wedge_height: band_height.saturating_sub(self.turn_steps.trailing_zeros()), band_height }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_round_trip_through_their_record() {
        for name in PRESETS {
            let p = PrecomputeParams::preset(name).unwrap();
            assert_eq!(PrecomputeParams::from_toml(&p.to_toml()).unwrap(), p, "{name}");
        }
        let p = PrecomputeParams::paper();
        assert_eq!((p.directions, p.field_spheres, p.field_resolution), (32_768, 32, 32));
        let mut q = PrecomputeParams::fast();
        q.set("field_values", "f16").unwrap();
        q.set("shape_coding", "heights").unwrap();
        q.set("svc_max_error", "0.02").unwrap();
        q.set("field_inner_flat", "0.1").unwrap();
        assert_eq!(PrecomputeParams::from_toml(&q.to_toml()).unwrap(), q);
        assert!(q.set("field_inner_flat", "0").unwrap_err().to_string().contains("above 0"));
    }

    #[test]
    fn command_line_over_scene_file_over_preset() {
        let table: toml::Table =
            toml::from_str("preset = \"fast\"\nfield_spheres = 12\nsvc_max_error = 0.02\n").unwrap();
        let p = PrecomputeParams::resolve(None, Some(&table), &[("field_spheres", "10")]).unwrap();
        assert_eq!((p.preset.as_str(), p.directions, p.field_spheres, p.svc_max_error), ("fast", 4096, 10, 0.02));
        let p = PrecomputeParams::resolve(Some("paper"), Some(&table), &[]).unwrap();
        assert_eq!((p.directions, p.field_spheres), (32_768, 12));
        assert_eq!(PrecomputeParams::resolve(None, None, &[]).unwrap(), PrecomputeParams::balanced());
        let bad: toml::Table = toml::from_str("field_sphere = 3").unwrap();
        let e = PrecomputeParams::resolve(None, Some(&bad), &[]).unwrap_err().to_string();
        assert!(e.contains("unknown parameter 'field_sphere'"), "{e}");
    }

    #[test]
    fn bad_values_are_named() {
        let mut p = PrecomputeParams::fast();
        let e = p.set("directions", "1000").unwrap_err().to_string();
        assert!(e.contains("directions = 1000") && e.contains("power of two"), "{e}");
        assert!(p.set("field_max_error", "0.25").is_err());
        assert!(p.set("svc_values", "u4").unwrap_err().to_string().contains("u8"));
        p.set("field_max_error", "0.1").unwrap();
        assert_eq!(p.field_values, ValueFormat::U8, "a non-zero threshold needs fractional values");
        p.set("field_values", "u1").unwrap();
        assert!(p.check().unwrap_err().to_string().contains("exact fields"));
        assert!(p.set("colour", "red").unwrap_err().to_string().contains("unknown parameter 'colour'"));
        assert!(PrecomputeParams::preset("slow").unwrap_err().to_string().contains("fast, balanced, paper"));
        p.set("field_values", "u8").unwrap();
        p.set("field_inner", "20").unwrap();
        assert!(p.check().unwrap_err().to_string().contains("below field_outer"));
    }

    #[test]
    fn turn_steps_are_recorded_only_when_set_and_checked_against_the_directions() {
        let fast = PrecomputeParams::fast();
        assert!(!fast.to_toml().contains("turn_"), "files made without turns keep their record");
        assert_eq!(fast.turn_shape(), None);
        let mut p = fast.clone();
        p.set("turn_steps", "64").unwrap();
        p.check().unwrap();
        // 4,096 directions in 64 wedges of 8 bands (M/8): cells of 8 leaves, bands of 512.
        assert_eq!((p.turn_bands, p.bands()), (0, 8));
        p.settle();
        assert!(p.to_toml().contains("turn_steps = 64\nturn_bands = 8\n"), "a file records the bands it has");
        assert_eq!(PrecomputeParams::from_toml(&p.to_toml()).unwrap(), p);
        // At 32,768 directions the default keeps cells of 32 leaves: 16 bands.
        let mut paper = PrecomputeParams::resolve(Some("paper"), None, &[("turn_steps", "64")]).unwrap();
        assert_eq!(paper.turn_bands, 16);
        paper.set("turn_bands", "4").unwrap();
        assert_eq!(
            PrecomputeParams::resolve(Some("paper"), None, &[("turn_steps", "64"), ("turn_bands", "4")]).unwrap(),
            paper
        );
        assert_eq!(p.turn_shape(), Some(TurnShape { wedge_height: 3, band_height: 9 }));
        assert_eq!(p.field_select().turn, p.turn_shape());
        assert_eq!(p.svc_select().turn, p.turn_shape());
        for (key, value, says) in [
            ("turn_steps", "48", "power of two"),
            ("turn_steps", "1", "power of two from 2"),
            ("turn_bands", "3", "power of two"),
            ("turn_steps", "x", "not a number"),
        ] {
            let e = p.clone().set(key, value).unwrap_err().to_string();
            assert!(e.contains(&format!("{key} = {value}")) && e.contains(says), "{e}");
        }
        p.set("turn_steps", "512").unwrap();
        let e = p.check().unwrap_err().to_string();
        assert!(e.contains("turn_steps = 512") && e.contains("at most directions / 16 = 256"), "{e}");
        p.set("turn_steps", "256").unwrap();
        p.set("turn_bands", "32").unwrap();
        let e = p.check().unwrap_err().to_string();
        assert!(e.contains("turn_bands = 32") && e.contains("at most directions / turn_steps = 16"), "{e}");
    }
}
