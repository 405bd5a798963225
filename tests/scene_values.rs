//! Every numeric key of a scene file is range-checked before anything is built: an error names
//! the file, the table and the key — never a panic, never an allocation discovered too late,
//! never silent acceptance. The held-out inputs of the portability issue and their neighbours,
//! and the fuzzer's findings (`fuzz/fuzz_targets/scene_toml.rs`).

use std::path::Path;
use std::time::{Duration, Instant};
use vcut_scene::{Budget, SceneDesc, SceneError};

/// The error of instantiating `toml` as `scene.toml` within `budget`.
fn refused(toml: &str, budget: Budget) -> SceneError {
    let file = Path::new("scene.toml");
    let desc = SceneDesc::parse(toml, file).unwrap_or_else(|e| panic!("parses: {e}\n{toml}"));
    let start = Instant::now();
    let e = match desc.instantiate_within(Path::new("."), file, &budget) {
        Ok(_) => panic!("accepted:\n{toml}"),
        Err(e) => e,
    };
    assert!(start.elapsed() < Duration::from_secs(5), "refused only after {:?}:\n{toml}", start.elapsed());
    e
}

const ONE_GB: Budget = Budget { max_bytes: 1_000_000_000 };

/// (scene file, what the message must name: table, key, and part of the reason)
const CASES: &[(&str, [&str; 3])] = &[
    // The held-out inputs.
    ("[environment]\nresolution = 4000000000", ["[environment]", "resolution = 4000000000", "[8, 16384]"]),
    ("[environment]\nintensity = nan", ["[environment]", "intensity = NaN", "finite"]),
    (
        "[[object]]\nsource = \"builtin:teapot\"\nresolution = 100000",
        ["object 0 ('builtin:teapot')", "resolution = 100000", "makes 320006400032 vertices, above the limit"],
    ),
    ("[[object]]\nsource = \"builtin:sphere\"\nsize = -1", ["object 0 ('builtin:sphere')", "size = -1.0", "above 0"]),
    // Their neighbours.
    ("[environment]\nresolution = 0", ["[environment]", "resolution = 0", "[8, 16384]"]),
    ("[environment]\nintensity = -1.0", ["[environment]", "intensity = -1.0", "at least 0"]),
    ("[environment]\nintensity = inf", ["[environment]", "intensity = inf", "finite"]),
    ("[environment]\nrotation_deg = -inf", ["[environment]", "rotation_deg = -inf", "finite"]),
    ("[environment]\nsun_elevation_deg = 91", ["[environment]", "sun_elevation_deg = 91.0", "[-90, 90]"]),
    ("[environment]\nsun_azimuth_deg = nan", ["[environment]", "sun_azimuth_deg = NaN", "finite"]),
    ("[environment]\nturbidity = 0", ["[environment]", "turbidity = 0.0", "[1.7, 10]"]),
    ("[environment]\nsun_diameter_deg = 0", ["[environment]", "sun_diameter_deg = 0.0", "(0, 45]"]),
    ("[environment]\nsun_to_zenith = -3", ["[environment]", "sun_to_zenith = -3.0", "[0.000001, 1000000000]"]),
    ("[environment]\nsource = \"\"", ["[environment]", "source = \"\"", "must name a map"]),
    ("[environment]\nlight_error = 0", ["[environment]", "light_error = 0.0", "(0, 1)"]),
    ("[environment]\nlight_error = 1.5", ["[environment]", "light_error = 1.5", "(0, 1)"]),
    ("[environment]\nlight_error = nan", ["[environment]", "light_error = NaN", "(0, 1)"]),
    (
        "[[object]]\nsource = \"builtin:sphere\"\nresolution = 4294967295",
        ["object 0", "resolution = 4294967295", "above the limit"],
    ),
    ("[[object]]\nsource = \"builtin:torus\"\nresolution = 2", ["object 0", "resolution = 2", "at least 3"]),
    ("[[object]]\nsource = \"builtin:plane\"\nresolution = 0", ["object 0", "resolution = 0", "at least 1"]),
    ("[[object]]\nsource = \"builtin:box\"\nsize = nan", ["object 0", "size = NaN", "above 0"]),
    ("[[object]]\nsource = \"builtin:box\"\nsize = 0", ["object 0", "size = 0.0", "above 0"]),
    ("[[object]]\nname = \"b\"\nsource = \"builtin:box\"\nscale = -2", ["object 0 ('b')", "scale = -2.0", "mirroring"]),
    ("[[object]]\nsource = \"builtin:box\"\nscale = 0", ["object 0", "scale = 0.0", "above 0"]),
    ("[[object]]\nsource = \"builtin:box\"\nstand_height = -1", ["object 0", "stand_height = -1.0", "above 0"]),
    (
        "[[object]]\nsource = \"builtin:box\"\ntranslation = [0, nan, 0]",
        ["object 0", "translation = [0.0, NaN, 0.0]", "finite"],
    ),
    (
        "[[object]]\nsource = \"builtin:box\"\nrotation_deg = [inf, 0, 0]",
        ["object 0", "rotation_deg = [inf, 0.0, 0.0]", "finite"],
    ),
    ("[[object]]\nsource = \"builtin:box\"\nweld = -0.1", ["object 0", "weld = -0.1", "at least 0"]),
    (
        "[[object]]\nsource = \"mesh.obj\"\nresolution = 8",
        ["object 0 ('mesh.obj')", "resolution", "built-in shapes only"],
    ),
    (
        "[[object]]\nsource = \"builtin:box\"\nmaterial = { kd = [2, 0, 0] }",
        ["object 0", "material = BlinnPhong", "kd = [2.0, 0.0, 0.0]: must be a number in [0, 1]"],
    ),
    (
        "[[object]]\nsource = \"builtin:box\"\nmaterial = { model = \"ggx\", roughness = 0 }",
        ["object 0", "material = Ggx", "roughness = 0: must be a number in (0, 1]"],
    ),
    (
        "[[camera]]\nposition = [0, 0, 0]\ntarget = [0, 0, 0]",
        ["camera 0 ('main')", "target = [0.0, 0.0, 0.0]", "differ"],
    ),
    (
        "[[camera]]\nposition = [0, 5, 0]\ntarget = [0, 0, 0]",
        ["camera 0 ('main')", "up = [0.0, 1.0, 0.0]", "view direction"],
    ),
    ("[[camera]]\nname = \"c\"\nfov_y_deg = 180", ["camera 0 ('c')", "fov_y_deg = 180.0", "(0, 180)"]),
    ("[[camera]]\nposition = [nan, 0, 0]", ["camera 0", "position = [NaN, 0.0, 0.0]", "finite"]),
];

#[test]
fn out_of_range_values_are_refused_naming_file_table_and_key() {
    for (toml, [table, key, reason]) in CASES {
        let e = refused(toml, ONE_GB);
        let msg = e.to_string();
        assert!(matches!(e, SceneError::Value { .. }), "{msg}\n{toml}");
        for part in ["scene.toml", table, key, reason] {
            assert!(msg.contains(part), "'{part}' missing from: {msg}\n{toml}");
        }
    }
}

#[test]
fn the_memory_estimate_refuses_before_allocating() {
    // Within its limits but over this budget: refused at once with the estimate.
    let e = refused("[[object]]\nsource = \"builtin:teapot\"\nresolution = 2000", ONE_GB).to_string();
    assert!(e.contains("about 16.39 GB") && e.contains("1.00 GB of memory available"), "{e}");
    // The built-ins together: two planes of ~600 MB each fit one at a time, not both.
    let two = "[[object]]\nname = \"a\"\nsource = \"builtin:plane\"\nresolution = 2500\n\
               [[object]]\nname = \"b\"\nsource = \"builtin:plane\"\nresolution = 2500";
    let e = refused(two, ONE_GB).to_string();
    assert!(e.contains("object 1 ('b')") && e.contains("the scene so far"), "{e}");
    // A wide baked sky: 16,384 × 8,192 texels.
    let e = refused("[environment]\nresolution = 16384", ONE_GB).to_string();
    assert!(e.contains("baking the map would take about 6.44 GB"), "{e}");
    // The same files within a budget that holds them pass the check (not built here).
    let file = Path::new("scene.toml");
    let big = Budget::bytes(100_000_000_000);
    for toml in [two, "[environment]\nresolution = 16384"] {
        SceneDesc::parse(toml, file).unwrap().check(file, &big).unwrap();
    }
}

#[test]
fn the_defaults_and_the_built_in_scenes_pass_the_checks() {
    let file = Path::new("scene.toml");
    for name in vcut_scene::scenes::BUILTIN_SCENES {
        let d = vcut_scene::scenes::builtin(name).unwrap();
        let bytes = d.check(file, &Budget::bytes(u64::MAX)).unwrap();
        assert!(bytes > 0 && bytes < 200_000_000, "{name}: {bytes}");
    }
    SceneDesc::default().check(file, &ONE_GB).unwrap();
    for example in ["examples/teapot.toml", "examples/bunny.toml"] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(example);
        SceneDesc::read(&path).unwrap().check(&path, &ONE_GB).unwrap();
    }
}

/// A placement f32 cannot hold — so far out that a triangle's corners round onto one line or
/// its positions round by more than 2^-12 of its radius, or scaled down until its area
/// underflows — is refused as the scene loads (naming the file, the object, the keys and the
/// spacing f32 keeps there), not by the renderer after a precompute.
#[test]
fn placements_f32_cannot_hold_are_refused_as_the_scene_loads() {
    let cases = [
        ("box", "translation = [0, 0, 1e38]", "translation = [0.0, 0.0, 1e38]", "zero area"),
        ("box", "instances = [[0, 0, 0], [1e38, 0, 0]]", "instances[1] = [1e38, 0.0, 0.0]", "zero area"),
        ("box", "stand_height = 1e-30", "stand_height = 1e-30", "zero area"),
        // A sphere's vertices are not on a grid f32 keeps exactly out there, as a box's are.
        ("sphere", "translation = [1e4, 0, 0]", "translation = [10000.0, 0.0, 0.0]", "round by up to"),
    ];
    for (shape, key, says, why) in cases {
        let toml = format!("[[object]]\nname = \"b\"\nsource = \"builtin:{shape}\"\n{key}");
        let msg = refused(&toml, ONE_GB).to_string();
        for part in ["scene.toml", "object 0", says, why, "f32 holds a position that far out only to"] {
            assert!(msg.contains(part), "'{part}' missing from: {msg}\n{toml}");
        }
    }
    // Far out but kept to 2^-12 of its radius: loaded.
    let toml = "[[object]]\nsource = \"builtin:sphere\"\ntranslation = [1000, 0, 0]";
    let desc = SceneDesc::parse(toml, Path::new("scene.toml")).unwrap();
    desc.instantiate_within(Path::new("."), Path::new("scene.toml"), &ONE_GB).unwrap();
}
