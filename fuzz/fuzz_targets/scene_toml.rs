//! Fuzz target, structure-aware: scene files (TOML) with arbitrary values for every key of every
//! table — `[environment]`, `[[object]]` with its material, `[[camera]]`, `[precompute]` — and
//! arbitrary extra keys and tables. Parsing, the checks and building within an 8 MB budget
//! must return a scene or an error, never panic, never exceed the budget by much (libFuzzer's
//! RSS limit), never loop.
#![no_main]

use libfuzzer_sys::arbitrary::{self, Arbitrary};
use libfuzzer_sys::fuzz_target;
use std::path::Path;
use toml::Value;
use vcut_scene::{Budget, SceneDesc};

const ENVIRONMENT: &[&str] = &[
    "source",
    "rotation_deg",
    "intensity",
    "resolution",
    "sun_elevation_deg",
    "sun_azimuth_deg",
    "turbidity",
    "sun_diameter_deg",
    "sun_to_zenith",
    "clamp_invalid",
];
const OBJECT: &[&str] = &[
    "name",
    "source",
    "resolution",
    "size",
    "stand_height",
    "translation",
    "rotation_deg",
    "scale",
    "moves",
    "material",
    "split",
    "weld",
];
const MATERIAL: &[&str] = &["model", "kd", "ks", "exponent", "roughness"];
const CAMERA: &[&str] = &["name", "position", "target", "up", "fov_y_deg"];
const TEXTS: &[&str] = &[
    "builtin:sky",
    "builtin:studio",
    "builtin:constant",
    "builtin:teapot",
    "builtin:sphere",
    "builtin:torus",
    "builtin:box",
    "builtin:plane",
    "builtin:",
    "lambert",
    "blinn-phong",
    "phong",
    "ggx",
    "mesh-nodes",
    "top-level-nodes",
    "groups",
    "file",
    "fast",
    "balanced",
    "paper",
    "",
    "missing.obj",
    "u8",
    "u1",
    "heights",
    "geometric",
];

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Special {
    Nan,
    Inf,
    NegInf,
    NegZero,
    Huge,
    Tiny,
    U32Max,
    AboveU32,
    I64Min,
}

#[derive(Arbitrary, Debug, Clone)]
enum Num {
    Int(i16),
    Wide(i64),
    Float(f64),
    Special(Special),
}

#[derive(Arbitrary, Debug, Clone)]
enum Leaf {
    Num(Num),
    Text(u8),
    AnyText(String),
    Bool(bool),
    Triple([Num; 3]),
    List(Vec<Num>),
}

#[derive(Arbitrary, Debug, Clone)]
enum Key {
    Known(u8),
    Any(String),
}

#[derive(Arbitrary, Debug, Clone)]
enum Val {
    Leaf(Leaf),
    Table(Vec<(Key, Leaf)>),
}

#[derive(Arbitrary, Debug)]
struct Doc {
    environment: Option<Vec<(Key, Val)>>,
    objects: Vec<Vec<(Key, Val)>>,
    cameras: Vec<Vec<(Key, Val)>>,
    precompute: Option<Vec<(Key, Val)>>,
    extra: Vec<(String, Val)>,
}

fn num(n: &Num) -> Value {
    match n {
        Num::Int(i) => Value::Integer(i64::from(*i)),
        Num::Wide(i) => Value::Integer(*i),
        Num::Float(f) => Value::Float(*f),
        Num::Special(s) => match s {
            Special::Nan => Value::Float(f64::NAN),
            Special::Inf => Value::Float(f64::INFINITY),
            Special::NegInf => Value::Float(f64::NEG_INFINITY),
            Special::NegZero => Value::Float(-0.0),
            Special::Huge => Value::Float(1e300),
            Special::Tiny => Value::Float(1e-300),
            Special::U32Max => Value::Integer(i64::from(u32::MAX)),
            Special::AboveU32 => Value::Integer(i64::from(u32::MAX) + 1),
            Special::I64Min => Value::Integer(i64::MIN),
        },
    }
}

fn leaf(l: &Leaf) -> Value {
    match l {
        Leaf::Num(n) => num(n),
        Leaf::Text(i) => Value::String(TEXTS[*i as usize % TEXTS.len()].into()),
        Leaf::AnyText(s) => Value::String(s.clone()),
        Leaf::Bool(b) => Value::Boolean(*b),
        Leaf::Triple(t) => Value::Array(t.iter().map(num).collect()),
        Leaf::List(v) => Value::Array(v.iter().take(8).map(num).collect()),
    }
}

fn key(k: &Key, known: &[&str]) -> String {
    match k {
        Key::Known(i) => known[*i as usize % known.len()].into(),
        Key::Any(s) => s.chars().take(16).collect(),
    }
}

fn table(entries: &[(Key, Val)], known: &[&str]) -> toml::Table {
    let mut t = toml::Table::new();
    for (k, v) in entries.iter().take(16) {
        let name = key(k, known);
        let value = match v {
            Val::Leaf(l) => leaf(l),
            // A sub-table is a material where the key is `material`.
            Val::Table(inner) => Value::Table(inner.iter().take(8).map(|(k, l)| (key(k, MATERIAL), leaf(l))).collect()),
        };
        t.insert(name, value);
    }
    t
}

fuzz_target!(|doc: Doc| {
    let mut root = toml::Table::new();
    if let Some(e) = &doc.environment {
        root.insert("environment".into(), Value::Table(table(e, ENVIRONMENT)));
    }
    let objects: Vec<Value> = doc.objects.iter().take(4).map(|o| Value::Table(table(o, OBJECT))).collect();
    if !objects.is_empty() {
        root.insert("object".into(), Value::Array(objects));
    }
    let cameras: Vec<Value> = doc.cameras.iter().take(3).map(|c| Value::Table(table(c, CAMERA))).collect();
    if !cameras.is_empty() {
        root.insert("camera".into(), Value::Array(cameras));
    }
    if let Some(p) = &doc.precompute {
        root.insert("precompute".into(), Value::Table(table(p, &vcut_precompute::params::KEYS)));
    }
    for (k, v) in doc.extra.iter().take(2) {
        root.insert(
            k.clone(),
            match v {
                Val::Leaf(l) => leaf(l),
                Val::Table(t) => Value::Table(t.iter().map(|(k, l)| (key(k, OBJECT), leaf(l))).collect()),
            },
        );
    }
    let Ok(text) = toml::to_string(&root) else { return };
    let file = Path::new("fuzz.toml");
    let Ok(desc) = SceneDesc::parse(&text, file) else { return };
    if let Ok(scene) = desc.instantiate_within(Path::new("/nonexistent-fuzz-base"), file, &Budget::bytes(8 << 20)) {
        for o in &scene.objects {
            assert!(o.mesh.validate().is_ok(), "{text}");
        }
        assert!(scene.environment.texels().iter().all(|t| t.iter().all(|x| x.is_finite() && *x >= 0.0)), "{text}");
    }
    let _ = vcut_precompute::PrecomputeParams::resolve(None, desc.precompute.as_ref(), &[]);
});
