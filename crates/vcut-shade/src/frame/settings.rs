//! A frame's settings: how it looks up fields, cuts flat occluders, merges, what it keeps as
//! caches and which light it casts by rays. One value, given to [`super::Frame::open`] and
//! changed with [`super::Frame::reconfigure`]; the command line, the viewer, Python and the
//! examples build it (`FrameArgs` behind the feature `clap`; serde for Python's keywords and
//! `--json`).

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use vcut_data::InsideSamples;
use vcut_merge::Algorithm as MergeAlgorithm;
use vcut_scene::check::LIGHT_ERROR;
use vcut_scene::limits::Limit;

/// A field's default reach, in its object's bounding radii ([`FieldReach`]).
pub const FIELD_REACH: f32 = 6.0;

/// The range of a field's reach in radii ([`FieldReach::Radii`]).
pub const REACH: Limit = Limit::above(0.0, "radii (or `outermost`)");

/// The range of a memory budget on the command line, in MB (`--memory-budget`): above 0 and at
/// most a petabyte (which a u64 of bytes holds with room to spare).
pub const BUDGET_MB: Limit = Limit::above_up_to(0.0, 1e9, "MB");

/// The range of the leaves of the light cast by rays (`light_max_leaves`,
/// `--light-max-leaves`).
pub const LIGHT_MAX_LEAVES: Limit = Limit::within(1.0, crate::sun::MAX_SUN_LEAVES as f64, "leaves");

/// The share of the sphere of directions (1/256) whose nodes [`FlatEdges::Interactive`]
/// estimates across a ground's edges.
pub const INTERACTIVE_EDGE_SHARE: u32 = 256;

/// How a frame merges, caches and lights. [`FrameSettings::default`] is what every command uses
/// unless told otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrameSettings {
    /// What a field lookup does with samples inside the field's object.
    #[serde(with = "inside_serde")]
    pub inside_samples: InsideSamples,
    /// Leave out of a vertex's product a field whose object lies wholly below the vertex's
    /// horizon: it hides none of the light the vertex's cut weighs by max(0, n·ω), and its sum
    /// over a node that straddles the horizon would darken the node's upper part. Off: the
    /// paper's product of every field within reach.
    pub horizon_culling: bool,
    /// How far a field shadows ([`FieldReach`]).
    pub field_reach: FieldReach,
    /// How finely a flat convex occluder's cut (a ground's) follows its edges ([`FlatEdges`]).
    pub flat_edge_leaves: FlatEdges,
    /// A move merges only the vertices facing the last eye and leaves the others until an eye
    /// sees them (the images are the same bit for bit: a vertex facing away reflects nothing
    /// toward the eye). Off: every move merges all it changes.
    pub deferred_merges: bool,
    /// Which merge moves use (both give the same cuts bit for bit).
    #[serde(with = "algorithm_serde")]
    pub merge_algorithm: MergeAlgorithm,
    /// Cast the leaves of the light whose error through the cuts is largest by rays at run
    /// time ([`crate::sun`]). Off: all light through the cuts, as the paper.
    pub sun_rays: bool,
    /// The target error of the light left in the cuts, relative ([`crate::SunRays::target`]);
    /// `None`: the file's recorded target (a scene's `[environment] light_error`), else
    /// [`crate::sun::DEFAULT_TARGET`].
    pub light_error: Option<f64>,
    /// At most this many leaves cast by rays (at most [`crate::sun::MAX_SUN_LEAVES`]).
    pub light_max_leaves: usize,
    /// What the frame keeps beyond its shading lists and field inputs ([`FrameCaches`]).
    pub caches: FrameCaches,
    /// Hold the frame's memory to this many bytes: the stored cuts stay in the file, no merged
    /// cuts and no field cells are kept, and the decoded SVCs only if they fit.
    pub memory_budget: Option<u64>,
}

impl Default for FrameSettings {
    fn default() -> FrameSettings {
        FrameSettings {
            inside_samples: InsideSamples::Occluded,
            horizon_culling: true,
            field_reach: FieldReach::Radii(FIELD_REACH),
            flat_edge_leaves: FlatEdges::Leaves(1),
            deferred_merges: true,
            merge_algorithm: MergeAlgorithm::Counter,
            sun_rays: true,
            light_error: None,
            light_max_leaves: crate::sun::DEFAULT_MAX_LEAVES,
            caches: FrameCaches::default(),
            memory_budget: None,
        }
    }
}

/// What a frame keeps beyond the shading lists and field inputs, each a trade of memory for
/// time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrameCaches {
    /// The file's stored cuts (SVCs and fields, coded) in memory: without, each cut a merge
    /// reads is read from the file (its block's bytes, one positional read: the operating
    /// system's file cache, not the frame, holds them), checked against the checksums the file
    /// had when it was opened.
    pub stored: bool,
    /// Every vertex's SVC decoded and prepared: spares each merge the SVC's decoding.
    pub svc: bool,
    /// The field cells the last merge of each object refined, and their decoded samples: the
    /// next move along a path needs most of them again.
    pub cells: bool,
    /// Every vertex's merged cut: a lighting change, a sun toggle or a camera turn rebuilds
    /// lists from it instead of merging again.
    pub merged: bool,
}

impl Default for FrameCaches {
    /// All kept.
    fn default() -> FrameCaches {
        FrameCaches { stored: true, svc: true, cells: true, merged: true }
    }
}

impl FrameCaches {
    /// None kept.
    pub const NONE: FrameCaches = FrameCaches { stored: false, svc: false, cells: false, merged: false };

    /// The caches kept, by name, comma-separated (`none` when none is).
    pub fn names(self) -> String {
        let kept: Vec<&str> =
            [("stored", self.stored), ("svc", self.svc), ("cells", self.cells), ("merged", self.merged)]
                .iter()
                .filter(|c| c.1)
                .map(|c| c.0)
                .collect();
        if kept.is_empty() { "none".into() } else { kept.join(",") }
    }

    /// These caches without the one called `name`; `None` for a name that is none of them.
    pub fn without(self, name: &str) -> Option<FrameCaches> {
        let mut c = self;
        match name {
            "stored" => c.stored = false,
            "svc" => c.svc = false,
            "cells" => c.cells = false,
            "merged" => c.merged = false,
            _ => return None,
        }
        Some(c)
    }

    /// Each cache kept in both.
    pub fn and(self, other: FrameCaches) -> FrameCaches {
        FrameCaches {
            stored: self.stored && other.stored,
            svc: self.svc && other.svc,
            cells: self.cells && other.cells,
            merged: self.merged && other.merged,
        }
    }

    /// What a frame under a memory budget starts with: the stored cuts left in the file, no
    /// merged cuts and no field cells, so that its setup's peak stays low too (it then merges
    /// in ranges); the decoded SVCs as asked.
    pub const BUDGETED: FrameCaches = FrameCaches { stored: false, svc: true, cells: false, merged: false };
}

/// How far a field shadows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FieldReach {
    /// To this many of its object's bounding radii (above 0; beyond the outermost sphere it
    /// changes nothing). A shorter reach multiplies fewer fields into each vertex's cut — a
    /// move re-merges fewer vertices, each faster — and leaves out the sky shadows of objects
    /// farther away (the sun's shadows are cast by rays at any distance); the trilinear
    /// samples of the far spheres overstate those (`docs/benchmarks.md`, "Field reach").
    Radii(f32),
    /// To the outermost sphere (the precompute's `field_outer`): the paper's reach.
    Outermost,
}

impl FieldReach {
    /// The reach in radii, `None` to the outermost sphere.
    pub fn radii(self) -> Option<f32> {
        match self {
            FieldReach::Radii(r) => Some(r),
            FieldReach::Outermost => None,
        }
    }
}

impl std::fmt::Display for FieldReach {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FieldReach::Radii(r) => write!(f, "{r}"),
            FieldReach::Outermost => f.write_str("outermost"),
        }
    }
}

impl std::str::FromStr for FieldReach {
    type Err = String;

    fn from_str(s: &str) -> Result<FieldReach, String> {
        match s {
            "outermost" => Ok(FieldReach::Outermost),
            _ => REACH.parse_f32(s).map(FieldReach::Radii),
        }
    }
}

/// How finely a flat convex occluder's cut (a ground's) follows its edges: a node of at most
/// N leaves (a power of two) across an edge takes its estimated visible share
/// ([`crate::flat`]) instead of being split down to its leaves. Walking down along the edges is
/// most of a move's merge on a scene with a ground, and the share only shifts light near the
/// occluder's silhouette (`docs/benchmarks.md`, "A ground's edges").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlatEdges {
    /// Nodes of up to this many leaves (a power of two; 1: the exact cut).
    Leaves(u32),
    /// The setting measured for interactive drags: nodes of 1/[`INTERACTIVE_EDGE_SHARE`] of
    /// the directions (4π/256 ≈ 0.049 sr, ~13° across), so as coarse on the sphere at every
    /// direction count.
    Interactive,
}

impl FlatEdges {
    /// The number of leaves this is for a tree of `directions` leaves.
    pub fn leaves(self, directions: usize) -> u32 {
        match self {
            FlatEdges::Leaves(n) => n,
            FlatEdges::Interactive => (directions as u32 / INTERACTIVE_EDGE_SHARE).max(1),
        }
    }
}

impl std::fmt::Display for FlatEdges {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FlatEdges::Leaves(n) => write!(f, "{n}"),
            FlatEdges::Interactive => f.write_str("interactive"),
        }
    }
}

impl std::str::FromStr for FlatEdges {
    type Err = String;

    /// A number of leaves (a power of two) or `interactive`: the one parser of the word for
    /// the command line, the viewer, Python and the examples.
    fn from_str(s: &str) -> Result<FlatEdges, String> {
        match s {
            "interactive" => Ok(FlatEdges::Interactive),
            _ => s
                .parse::<u32>()
                .ok()
                .filter(|n| n.is_power_of_two())
                .map(FlatEdges::Leaves)
                .ok_or_else(|| format!("{s:?}: not a number of leaves (a power of two) or `interactive`")),
        }
    }
}

/// A setting out of its range: the key (a [`FrameSettings`] field's name), the value and what
/// it must be.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} = {value}: {reason}")]
pub struct SettingError {
    /// The field of [`FrameSettings`].
    pub key: &'static str,
    /// The value given.
    pub value: String,
    /// What it must be.
    pub reason: String,
}

impl FrameSettings {
    /// Checks every value that does not depend on the data: reach and targets finite and in
    /// range, leaves a power of two, a budget above 0. [`super::Frame::open`] and
    /// [`super::Frame::reconfigure`] call it (and check the leaves against the tree).
    pub fn validate(&self) -> Result<(), SettingError> {
        let bad = |key, value: String, reason: &str| Err(SettingError { key, value, reason: reason.into() });
        if let FieldReach::Radii(r) = self.field_reach
            && let Err(reason) = REACH.check(f64::from(r))
        {
            return bad("field_reach", r.to_string(), &reason);
        }
        if let FlatEdges::Leaves(n) = self.flat_edge_leaves
            && !n.is_power_of_two()
        {
            return bad(
                "flat_edge_leaves",
                n.to_string(),
                "must be a power of two (1: the exact cut) or `interactive`",
            );
        }
        if let Some(e) = self.light_error
            && let Err(reason) = LIGHT_ERROR.check(e)
        {
            return bad("light_error", e.to_string(), &reason);
        }
        if let Err(reason) = LIGHT_MAX_LEAVES.check(self.light_max_leaves as f64) {
            return bad("light_max_leaves", self.light_max_leaves.to_string(), &reason);
        }
        if self.memory_budget == Some(0) {
            return bad("memory_budget", "0".into(), "must be a number of bytes above 0");
        }
        Ok(())
    }

    /// The sun by rays these settings ask for, with `recorded` the file's target error (`None`:
    /// all light through the cuts).
    pub fn sun(&self, recorded: Option<f64>) -> Option<crate::SunRays> {
        self.sun_rays.then(|| crate::SunRays {
            target: self.light_error.or(recorded).unwrap_or(crate::sun::DEFAULT_TARGET),
            max_leaves: self.light_max_leaves,
        })
    }

    /// The caches a frame under these settings keeps before any is dropped to its budget.
    pub fn caches_at_start(&self) -> FrameCaches {
        match self.memory_budget {
            Some(_) => self.caches.and(FrameCaches::BUDGETED),
            None => self.caches,
        }
    }
}

impl Serialize for FieldReach {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            FieldReach::Radii(r) => s.serialize_f32(*r),
            FieldReach::Outermost => s.serialize_str("outermost"),
        }
    }
}

impl<'de> Deserialize<'de> for FieldReach {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<FieldReach, D::Error> {
        match NumberOrWord::deserialize(d)? {
            NumberOrWord::Number(r) => Ok(FieldReach::Radii(r as f32)),
            NumberOrWord::Word(w) => w.parse().map_err(serde::de::Error::custom),
        }
    }
}

impl Serialize for FlatEdges {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            FlatEdges::Leaves(n) => s.serialize_u32(*n),
            FlatEdges::Interactive => s.serialize_str("interactive"),
        }
    }
}

impl<'de> Deserialize<'de> for FlatEdges {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<FlatEdges, D::Error> {
        match NumberOrWord::deserialize(d)? {
            NumberOrWord::Number(n) if n >= 1.0 && n.fract() == 0.0 && n <= u32::MAX as f64 => {
                Ok(FlatEdges::Leaves(n as u32))
            }
            NumberOrWord::Number(n) => {
                Err(serde::de::Error::custom(format!("{n}: not a number of leaves (a power of two) or `interactive`")))
            }
            NumberOrWord::Word(w) => w.parse().map_err(serde::de::Error::custom),
        }
    }
}

/// A value given as a number or a word (`6`, `"outermost"`).
#[derive(Deserialize)]
#[serde(untagged)]
enum NumberOrWord {
    Number(f64),
    Word(String),
}

/// [`InsideSamples`] by name (`occluded`, `dropped`).
mod inside_serde {
    use serde::{Deserialize, Deserializer, Serializer};
    use vcut_data::InsideSamples;

    pub(super) fn serialize<S: Serializer>(v: &InsideSamples, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(v.name())
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<InsideSamples, D::Error> {
        let name = String::deserialize(d)?;
        InsideSamples::named(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("{name:?}: expected `occluded` or `dropped`")))
    }
}

/// [`MergeAlgorithm`] by name (`counter`, `index`).
mod algorithm_serde {
    use serde::{Deserialize, Deserializer, Serializer};
    use vcut_merge::Algorithm;

    pub(super) fn serialize<S: Serializer>(v: &Algorithm, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(super::algorithm_name(*v))
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Algorithm, D::Error> {
        let name = String::deserialize(d)?;
        super::algorithm_named(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("{name:?}: expected `counter` or `index`")))
    }
}

/// A merge algorithm's name on the command line and in reports.
pub fn algorithm_name(a: MergeAlgorithm) -> &'static str {
    match a {
        MergeAlgorithm::Counter => "counter",
        MergeAlgorithm::Index => "index",
    }
}

/// The merge algorithm called `name`.
pub fn algorithm_named(name: &str) -> Option<MergeAlgorithm> {
    [MergeAlgorithm::Counter, MergeAlgorithm::Index].into_iter().find(|a| algorithm_name(*a) == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_round_trip_through_serde_and_refuse_unknown_keys() {
        let s = FrameSettings {
            inside_samples: InsideSamples::Dropped,
            field_reach: FieldReach::Outermost,
            flat_edge_leaves: FlatEdges::Interactive,
            merge_algorithm: MergeAlgorithm::Index,
            light_error: Some(0.01),
            memory_budget: Some(1 << 20),
            caches: FrameCaches { merged: false, ..FrameCaches::default() },
            ..FrameSettings::default()
        };
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(serde_json::from_str::<FrameSettings>(&json).unwrap(), s);
        let reach: FrameSettings = serde_json::from_str(r#"{"field_reach": 4, "flat_edge_leaves": 16}"#).unwrap();
        assert_eq!((reach.field_reach, reach.flat_edge_leaves), (FieldReach::Radii(4.0), FlatEdges::Leaves(16)));
        let e = serde_json::from_str::<FrameSettings>(r#"{"field_rech": 4}"#).unwrap_err().to_string();
        assert!(e.contains("field_rech"), "{e}");
        let e = serde_json::from_str::<FrameSettings>(r#"{"inside_samples": "inside"}"#).unwrap_err().to_string();
        assert!(e.contains("occluded"), "{e}");
    }

    #[test]
    fn validate_names_the_key_of_each_bad_value() {
        let cases: [(FrameSettings, &str); 5] = [
            (FrameSettings { field_reach: FieldReach::Radii(f32::NAN), ..Default::default() }, "field_reach"),
            (FrameSettings { flat_edge_leaves: FlatEdges::Leaves(3), ..Default::default() }, "flat_edge_leaves"),
            (FrameSettings { light_error: Some(1.0), ..Default::default() }, "light_error"),
            (FrameSettings { light_max_leaves: 65, ..Default::default() }, "light_max_leaves"),
            (FrameSettings { memory_budget: Some(0), ..Default::default() }, "memory_budget"),
        ];
        for (s, key) in cases {
            assert_eq!(s.validate().unwrap_err().key, key);
        }
        assert!(FrameSettings::default().validate().is_ok());
    }

    #[test]
    fn words_parse_and_print_back() {
        for w in ["interactive", "1", "128"] {
            assert_eq!(w.parse::<FlatEdges>().unwrap().to_string(), w);
        }
        for w in ["outermost", "6", "0.5"] {
            assert_eq!(w.parse::<FieldReach>().unwrap().to_string(), w);
        }
        assert!("3".parse::<FlatEdges>().is_err());
        assert!("0".parse::<FieldReach>().is_err());
        assert!("nan".parse::<FieldReach>().is_err());
        assert_eq!(FlatEdges::Interactive.leaves(32_768), 128);
        assert_eq!(FlatEdges::Interactive.leaves(64), 1);
    }
}
