//! Fuzz target, structure-aware: command lines of `precompute`, `render`, `leaves` and `view
//! --screenshot` with NaN, ±inf, 0, negative, huge, empty and malformed values for every option
//! they take (drawn from the options table, `vcuts::options::table`, so a new option is fuzzed
//! without a change here). Each line is parsed as the binary parses it; one that passes is run
//! in-process when its work is small (a tiny scene, images of at most 64 × 64 pixels, a plant of
//! a leaf or two), else run up to its estimate (`--dry-run`). Parsing and running must end in a
//! value or an error with a message — never a panic, never an abort — and a run that succeeds
//! must have written what it says it wrote: what passes the checks does not fail later.
#![no_main]

use clap::{CommandFactory, Parser};
use libfuzzer_sys::arbitrary::{self, Arbitrary};
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;
use vcuts::options::{OptionRow, table};
use vcuts::{Cli, Command};

/// A tiny scene: a movable ball over a ground, few directions, coarse fields.
const SCENE: &str = r#"
[environment]
source = "builtin:sky"
resolution = 32

[[object]]
name = "ground"
source = "builtin:plane"
size = 4.0
resolution = 3

[[object]]
name = "ball"
source = "builtin:sphere"
size = 0.5
resolution = 4
translation = [0.0, 0.6, 0.0]
moves = true

[precompute]
preset = "fast"
directions = 64
field_spheres = 2
field_resolution = 2
"#;

/// This process's scratch folder, with the scene and its precomputed file.
fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let d = std::env::temp_dir().join(format!("vcut-fuzz-cli-{}", std::process::id()));
        std::fs::create_dir_all(&d).expect("a scratch folder");
        std::fs::write(d.join("scene.toml"), SCENE).expect("the scene");
        let mut args = vcuts::precompute::PrecomputeArgs::new(d.join("scene.toml").to_str().unwrap(), "fast");
        args.output = Some(d.join("scene.vcuts"));
        args.cache_dir = d.join("cache");
        args.estimate.seconds = 0.0;
        vcuts::precompute::run(&args).expect("the tiny scene precomputes");
        d
    })
}

/// A value as a user might mistype it.
#[derive(Arbitrary, Debug, Clone)]
enum Value {
    Nan,
    Inf,
    NegInf,
    Zero,
    NegativeZero,
    NegativeOne,
    Half,
    One,
    Two,
    Huge,
    HugeWhole,
    Tiny,
    Empty,
    /// One of [`MALFORMED`].
    Malformed(u8),
    /// Well inside the option's range, or one of its choices.
    Valid(u8),
    /// Arbitrary text.
    Text(String),
}

const MALFORMED: &[&str] = &[
    "1,",
    ",",
    "1,2",
    "1,2,3",
    "a",
    "1e",
    "--",
    "-",
    "=",
    "x=",
    "=1,2,3",
    "ball=",
    "ball=nan,0,0",
    "ball=1e30,0,0",
    "ball=1e38,1e38,1e38",
    "ball=0,0",
    "ground=1,0,0",
    "ball=lambert:kd=2",
    "ball=ggx:roughness=0",
    "0x10",
    "1_000",
    "640x",
    "x480",
    "0x0",
    "99999x2",
    "2x99999",
    "1/2",
    "2/1",
    "0/0",
    "env/0",
    "nan,nan",
    "inf,0",
    "1,2,3,4",
    " 1 ",
    "\u{0}",
    "1e-45",
    "3.4e38",
    "-3.4e38",
    "4294967296",
    "18446744073709551616",
    "interactive",
    "outermost",
];

/// The command line argument for `value` given to option `row`.
fn text(row: &OptionRow, value: &Value) -> String {
    match value {
        Value::Nan => "nan".into(),
        Value::Inf => "inf".into(),
        Value::NegInf => "-inf".into(),
        Value::Zero => "0".into(),
        Value::NegativeZero => "-0".into(),
        Value::NegativeOne => "-1".into(),
        Value::Half => "0.5".into(),
        Value::One => "1".into(),
        Value::Two => "2".into(),
        Value::Huge => "1e30".into(),
        Value::HugeWhole => "4294967297".into(),
        Value::Tiny => "1e-30".into(),
        Value::Empty => String::new(),
        Value::Malformed(i) => MALFORMED[usize::from(*i) % MALFORMED.len()].into(),
        Value::Valid(i) => valid(row, *i),
        Value::Text(s) => s.chars().take(64).collect(),
    }
}

/// A value the option takes.
fn valid(row: &OptionRow, i: u8) -> String {
    if !row.choices.is_empty() {
        return row.choices[usize::from(i) % row.choices.len()].clone();
    }
    let choices: &[&str] = match row.option.as_str() {
        "--move" => &["ball=0.3,0,0", "ball=-0.2,0.1,0.4", "ball=0,0,0"],
        "--brdf" => &["ball=lambert:kd=0.4", "ball=blinn-phong:alpha=70", "ground=ggx:roughness=0.3"],
        "--size" => &["32x24", "1x1", "64x64"],
        "--sun" => &["45,30", "-10,0", "90,400"],
        "--reflectance" | "--transmittance" => &["0.2", "0.1,0.3,0.05"],
        "--sigma-a" | "--sigma-s" => &["0.5", "1,2,3"],
        "--gloss-top" | "--gloss-bottom" => &["0.1,0.3", "0,1"],
        "--flat-edge-leaves" => &["1", "4", "interactive"],
        "--field-reach" => &["6", "0.5", "outermost"],
        "--directions" => &["64", "128"],
        "--shard" => &["0/2", "1/2"],
        "--plant" => &["procedural"],
        "--inside-samples" => &["occluded", "dropped"],
        "--merge-algorithm" => &["counter", "index"],
        "--camera" => &["main", "nowhere"],
        "--preset" => &["fast", "balanced"],
        _ => &[],
    };
    if !choices.is_empty() {
        return choices[usize::from(i) % choices.len()].into();
    }
    match row.number {
        Some(n) => {
            use vcut_scene::limits::End;
            let (low, high) = match (n.limit.low, n.limit.high) {
                (End::Closed(l) | End::Open(l), End::Closed(h) | End::Open(h)) => (l, h.min(l + 64.0)),
                (End::Closed(l) | End::Open(l), End::None) => (l, l + 8.0),
                (End::None, End::Closed(h) | End::Open(h)) => (h - 8.0, h),
                (End::None, End::None) => (-8.0, 8.0),
            };
            let v = low + (high - low) * (f64::from(i) + 0.5) / 256.0;
            if n.whole { (v.round().max(low.ceil()) as i64).to_string() } else { v.to_string() }
        }
        None => "1".into(),
    }
}

/// The options the harness sets itself (files, folders, scenes, what would open a window or run
/// for long), never drawn.
const FIXED: &[&str] = &[
    "--scene",
    "--output",
    "--cache-dir",
    "--env",
    "--gather",
    "--out",
    "--leaf-data",
    "--screenshot",
    "--exr",
    "--export-ply",
    "--export-glb",
    "--set",
    "--estimate-seconds",
    "--threads",
    "--fresh",
    "--plan",
];

#[derive(Arbitrary, Debug)]
struct Input {
    command: u8,
    options: Vec<(u8, Value)>,
}

fuzz_target!(|input: Input| {
    let d = dir();
    let cli = Cli::command();
    let rows = table(&cli);
    let commands = ["precompute", "render", "leaves", "view"];
    let command = commands[usize::from(input.command) % commands.len()];
    let drawable: Vec<&OptionRow> =
        rows.iter().filter(|r| r.command == command && !FIXED.contains(&r.option.as_str())).collect();
    let mut argv: Vec<String> = vec!["vcuts".into(), command.into()];
    let file = d.join("scene.vcuts").display().to_string();
    let scene = d.join("scene.toml").display().to_string();
    let out = d.join("out");
    match command {
        "precompute" => argv.extend([
            "--scene".into(),
            scene,
            "-o".into(),
            d.join("p.vcuts").display().to_string(),
            "--cache-dir".into(),
            d.join("cache").display().to_string(),
        ]),
        "render" => argv.extend([file, "-o".into(), out.with_extension("png").display().to_string()]),
        "leaves" => argv.extend(["--out".into(), out.display().to_string()]),
        _ => argv.extend([file, "--screenshot".into(), out.with_extension("png").display().to_string()]),
    }
    for (i, value) in input.options.iter().take(8) {
        if drawable.is_empty() {
            break;
        }
        let row = drawable[usize::from(*i) % drawable.len()];
        argv.push(row.option.clone());
        if !row.value.is_empty() {
            argv.push(text(row, value));
        }
    }
    let parsed = match Cli::try_parse_from(&argv) {
        Ok(c) => c,
        Err(e) => {
            assert!(!e.to_string().trim().is_empty(), "an empty error for {argv:?}");
            return;
        }
    };
    run(parsed.command, d, &argv);
});

/// Runs a parsed command when its work is small, else up to its estimate; checks what it wrote.
fn run(command: Command, d: &std::path::Path, argv: &[String]) {
    let png = d.join("out.png");
    let _ = std::fs::remove_file(&png);
    let result: Result<(), String> = match command {
        Command::Precompute(mut a) => {
            let small = a.directions.is_none_or(|n| n <= 256)
                && a.field_spheres.is_none_or(|n| n <= 4)
                && a.field_resolution.is_none_or(|n| n <= 4);
            a.estimate.dry_run |= !small;
            a.estimate.seconds = 0.0;
            vcuts::precompute::run(&a).map(|_| ()).map_err(|e| format!("{e:#}"))
        }
        Command::Render(a) | Command::Reference(a) => {
            if u64::from(a.width) * u64::from(a.height) > 64 * 64 {
                return;
            }
            let r = vcuts::render::run(&a).map(|_| ()).map_err(|e| format!("{e:#}"));
            if r.is_ok() {
                assert_png(&png, argv);
            }
            r
        }
        Command::Leaves(mut a) => {
            let (w, h) = a.size();
            a.plant.estimate.dry_run |= !small_plant(&a.plant)
                || a.reference_paths > 4
                || a.reference_vertices > 64
                || u64::from(w) * u64::from(h) > 64 * 64;
            a.plant.estimate.seconds = 0.0;
            a.plant.leaf_data = Some(d.join("plant.vleaf"));
            vcuts::leaves::run(&a).map(|_| ()).map_err(|e| format!("{e:#}"))
        }
        Command::View(a) => {
            if u64::from(a.width) * u64::from(a.height) > 64 * 64 || (a.leaves && !small_plant(&a.plant)) {
                return;
            }
            view(argv, &png)
        }
        _ => return,
    };
    if let Err(e) = result {
        assert!(!e.trim().is_empty(), "an empty error for {argv:?}");
    }
}

/// `view --screenshot` run by the `vcuts` binary `VCUTS_BIN` (built with the viewer; the fuzz
/// build leaves the GPU stack out): it exits 0 having written a whole PNG, or 1 or 2 with an
/// error — never a panic (101) or a signal. Without `VCUTS_BIN` the view lines are only parsed.
fn view(argv: &[String], png: &std::path::Path) -> Result<(), String> {
    static BIN: OnceLock<Option<PathBuf>> = OnceLock::new();
    let Some(bin) = BIN.get_or_init(|| {
        let bin = std::env::var_os("VCUTS_BIN").map(PathBuf::from);
        if bin.is_none() {
            eprintln!("command_line: VCUTS_BIN not set: view --screenshot lines are parsed, not run");
        }
        bin
    }) else {
        return Ok(());
    };
    let out = std::process::Command::new(bin).args(&argv[1..]).env("VCUTS_PROGRESS_SECONDS", "3600").output();
    let out = out.unwrap_or_else(|e| panic!("{}: {e}", bin.display()));
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(0) => {
            assert_png(png, argv);
            Ok(())
        }
        Some(1 | 2) => {
            assert!(stderr.contains("error"), "{argv:?} failed without an error:\n{stderr}");
            Err(stderr.into_owned())
        }
        status => panic!("{argv:?} ended with {status:?}:\n{stderr}"),
    }
}

/// A plant whose precompute takes a moment.
fn small_plant(p: &vcuts::leaves::plant::PlantArgs) -> bool {
    p.leaf_count <= 2
        && p.vertices.is_none_or(|n| n <= 600)
        && p.prt_rays <= 8
        && p.lvc_resolution <= 4
        && p.bounces <= 1
        && p.sun_edge_rays <= 4
        && matches!(p.plant, vcuts::leaves::plant::PlantSource::Procedural)
}

/// A command that succeeded wrote a whole PNG where it said.
fn assert_png(path: &std::path::Path, argv: &[String]) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{argv:?} succeeded but {}: {e}", path.display()));
    assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.ends_with(b"IEND\xaeB`\x82"), "{argv:?}: a cut PNG");
}
