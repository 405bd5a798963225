//! The `vcuts` binary as a user's shell sees it: a closed stdout, a run from another folder,
//! progress in a log file, `-q`, `--threads`.

use std::path::Path;
use std::process::{Command, Output, Stdio};

mod common;
use common::scratch;

fn vcuts(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vcuts"))
        .current_dir(cwd)
        .args(args)
        .env_remove("VCUTS_PROGRESS_SECONDS")
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

#[test]
fn a_closed_stdout_ends_quietly_not_with_a_panic() {
    // `vcuts inspect builtin:teapot | head -0`: the reader is gone before the first line.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vcuts"))
        .args(["inspect", "builtin:teapot"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(out.status.code(), Some(141), "{stderr}");
}

#[test]
fn precompute_logs_progress_without_a_terminal_and_render_works_from_another_folder() {
    let s = scratch("cli-render");
    let work = s.0.join("work");
    let elsewhere = s.0.join("elsewhere");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    let scene = s.0.join("scene.toml");
    let scene = scene.to_str().unwrap();
    // stderr is a pipe here, as in a log file: each stage says when it starts and ends.
    let o = vcuts(
        &work,
        &[
            "--threads",
            "1",
            "precompute",
            "--scene",
            scene,
            "--cache-dir",
            "cache",
            "--estimate-seconds",
            "0.2",
            "-o",
            "s.vcuts",
        ],
    );
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("estimate_s=") && out.contains("total_s="), "no outcome on stdout:\n{out}");
    assert!(o.status.success(), "{}", text(&o));
    assert!(err.contains(" 1 threads"), "--threads 1 not applied:\n{err}");
    assert!(err.contains(": started,") && err.contains(": done,"), "no progress lines on stderr:\n{err}");
    assert!(!err.contains('\r') && !err.contains("\u{1b}["), "terminal output in a log:\n{err}");
    // The file renders from another working directory, into a path relative to that one.
    let file = work.join("s.vcuts");
    let o =
        vcuts(&elsewhere, &["render", file.to_str().unwrap(), "-o", "frame.png", "--width", "64", "--height", "48"]);
    assert!(o.status.success(), "{}", text(&o));
    let png = std::fs::read(elsewhere.join("frame.png")).expect("frame.png written where the command ran");
    assert!(png.starts_with(b"\x89PNG"), "not a PNG");
    // The light-error target reaches the frame, and one out of range is refused by name.
    let small = ["render", file.to_str().unwrap(), "-o", "t.png", "--width", "16", "--height", "12"];
    let o = vcuts(&elsewhere, &[&small[..], &["--light-error", "0.01"]].concat());
    assert!(o.status.success(), "{}", text(&o));
    for key in ["light_error_target=0.01", "light_error_estimate=", "sun_rays_per_vertex="] {
        assert!(String::from_utf8_lossy(&o.stdout).contains(key), "no {key}: {}", text(&o));
    }
    let o = vcuts(&elsewhere, &[&small[..], &["--light-error", "2"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--light-error") && text(&o).contains("must be a number in (0, 1)"), "{}", text(&o));
    // The cost cap reaches the frame: at most that many leaves cast; 0 is refused by name.
    let o = vcuts(&elsewhere, &[&small[..], &["--light-error", "0.0001", "--light-max-leaves", "1"]].concat());
    assert!(o.status.success(), "{}", text(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("light_max_leaves=1\n"), "{}", text(&o));
    let leaves: usize =
        stdout.lines().find_map(|l| l.strip_prefix("sun_leaves=")).and_then(|v| v.parse().ok()).unwrap();
    assert!(leaves <= 1, "{}", text(&o));
    let o = vcuts(&elsewhere, &[&small[..], &["--light-max-leaves", "0"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--light-max-leaves"), "{}", text(&o));
    // The ground's edge setting reaches the frame (`interactive`: 1/256 of the 256 directions,
    // so 1); a value neither a number nor `interactive`, or not a power of two, is refused.
    for (value, printed) in [("interactive", "flat_edge_leaves=1\n"), ("4", "flat_edge_leaves=4\n")] {
        let o = vcuts(&elsewhere, &[&small[..], &["--flat-edge-leaves", value]].concat());
        assert!(o.status.success() && String::from_utf8_lossy(&o.stdout).contains(printed), "{}", text(&o));
    }
    let o = vcuts(&elsewhere, &[&small[..], &["--flat-edge-leaves", "fine"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("`interactive`"), "{}", text(&o));
    let o = vcuts(&elsewhere, &[&small[..], &["--flat-edge-leaves", "3"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--flat-edge-leaves") && text(&o).contains("power of two"), "{}", text(&o));
    // Every setting of the frame given: each vertex merges once, at setup.
    let every = [
        "--inside-samples",
        "dropped",
        "--no-horizon-culling",
        "--field-reach",
        "outermost",
        "--flat-edge-leaves",
        "4",
        "--eager-merges",
        "--merge-algorithm",
        "index",
        "--light-error",
        "0.001",
        "--light-max-leaves",
        "4",
        "--no-cache",
        "cells,svc",
        "--json",
    ];
    let o = vcuts(&elsewhere, &[&small[..], &every].concat());
    assert!(o.status.success(), "{}", text(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).expect("--json prints one object");
    assert_eq!(json["setup_merges"], json["vertices"], "{json}");
    assert_eq!((json["merges"].as_u64(), json["inside_samples"].as_str()), (Some(0), Some("dropped")), "{json}");
    assert_eq!(json["frame_caches"], "stored,merged", "{json}");
    // More leaves than the file has directions: refused once the file is read, naming the option.
    let o = vcuts(&elsewhere, &[&small[..], &["--flat-edge-leaves", "512"]].concat());
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("--flat-edge-leaves 512: must be at most the number of directions, 256"), "{}", text(&o));
    // Under a memory budget the stored cuts stay in the file and no cache is kept when none
    // fits: the same picture, byte for byte, from a frame that says so; 0 MB is refused.
    let budget = |extra: &[&str], png: &str| {
        let args = ["render", file.to_str().unwrap(), "-o", png, "--width", "64", "--height", "48", "--move"];
        let o = vcuts(&elsewhere, &[&args[..], &["ball=0.2,0,0.1"], extra].concat());
        assert!(o.status.success(), "{}", text(&o));
        (String::from_utf8_lossy(&o.stdout).into_owned(), std::fs::read(elsewhere.join(png)).unwrap())
    };
    let (full, full_png) = budget(&[], "full.png");
    let (lean, lean_png) = budget(&["--memory-budget", "0.001"], "lean.png");
    assert!(full.contains("frame_caches=stored,svc,cells,merged\n"), "{full}");
    assert!(lean.contains("frame_caches=none\n"), "{lean}");
    let stored = |out: &str| -> f64 {
        out.lines().find_map(|l| l.strip_prefix("frame_memory_stored_mb=")).and_then(|v| v.parse().ok()).unwrap()
    };
    assert!(stored(&lean) * 4.0 < stored(&full), "{lean}\n{full}");
    assert!(lean_png == full_png, "the picture under a budget differs");
    let o = vcuts(&elsewhere, &[&small[..], &["--memory-budget", "0"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(
        text(&o).contains("--memory-budget") && text(&o).contains("must be a number in (0, 1000000000] MB"),
        "{}",
        text(&o)
    );
    // A move f32 cannot hold the ball at is refused naming --move, the object and the
    // spacing, and nothing is written.
    let far = ["render", file.to_str().unwrap(), "-o", "moved.png", "--move", "ball=1e6,1e6,1e6"];
    let o = vcuts(&elsewhere, &far);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    for says in ["--move ball=1000000,1000000,1000000", "(ball) moved to", "zero area", "f32 holds"] {
        assert!(text(&o).contains(says), "no {says:?}: {}", text(&o));
    }
    assert!(!elsewhere.join("moved.png").exists(), "an image was written");
    // A turn of an object of a file made without a symmetric set is refused naming --turn and
    // the key that makes one, and nothing is written; a yaw that is not a number is clap's.
    let turn = ["render", file.to_str().unwrap(), "-o", "turned.png", "--turn", "ball=30"];
    let o = vcuts(&elsewhere, &turn);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    for says in ["--turn ball=30", "(ball) cannot turn", "turn_steps"] {
        assert!(text(&o).contains(says), "no {says:?}: {}", text(&o));
    }
    assert!(!elsewhere.join("turned.png").exists(), "an image was written");
    let o = vcuts(&elsewhere, &["render", file.to_str().unwrap(), "--turn", "ball=nan"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--turn") && text(&o).contains("not finite"), "{}", text(&o));
    // An image larger than memory is refused naming its size, before anything is allocated.
    let free = vcut_scene::budget::available_memory().unwrap_or(0);
    if free < 16_384 * 16_384 * vcuts::resources::ImageCost::Cuts as u64 {
        let o = vcuts(
            &elsewhere,
            &["render", file.to_str().unwrap(), "-o", "big.png", "--width", "16384", "--height", "16384"],
        );
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains("--width 16384 --height 16384: an image this size needs about"), "{}", text(&o));
    } else {
        eprintln!("SKIPPED the image-memory check: {free} bytes available hold a 16384 × 16384 render");
    }
    // -q: results on stdout as before, nothing about progress on stderr.
    let o = vcuts(
        &work,
        &[
            "-q",
            "precompute",
            "--scene",
            scene,
            "--cache-dir",
            "cache",
            "--fresh",
            "--estimate-seconds",
            "0.2",
            "-o",
            "q.vcuts",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(o.stderr.is_empty(), "-q printed on stderr:\n{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("output="), "{}", text(&o));
}

#[test]
fn bad_global_options_are_refused_by_name() {
    let o = vcuts(Path::new("."), &["--threads", "0", "inspect", "builtin:teapot"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("--threads") && text(&o).contains("must be a whole number in [1, 4096]"), "{}", text(&o));
    let o = vcuts(Path::new("."), &["render", "x.vcuts", "--mode", "ssdo-fancy"]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("ssdo-peeled"), "the choices are listed: {}", text(&o));
}

/// A `.vcuts` file holds its scene's cameras, light-error target and map: it renders the same
/// image from another folder after the scene file and the map file are gone.
#[test]
fn a_vcuts_file_renders_the_same_after_its_scene_and_map_are_gone() {
    let s = scratch("cli-travel");
    let work = s.0.join("work");
    let elsewhere = s.0.join("elsewhere");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::create_dir_all(&elsewhere).unwrap();
    // A 32x16 map with a bright patch, and a camera of the scene's own.
    let texels: Vec<[f32; 3]> = (0..32 * 16)
        .map(|i| if (i % 32, i / 32) == (9, 4) { [400.0, 380.0, 300.0] } else { [0.4, 0.5, 0.7] })
        .collect();
    vcut_envmap::io::write_exr(&work.join("probe.exr"), 32, 16, &texels).unwrap();
    let scene_text = format!(
        "{}\n[environment]\nsource = \"probe.exr\"\nlight_error = 0.01\n\n[[camera]]\nname = \"side\"\n\
         position = [3.0, 1.5, 0.5]\ntarget = [0.0, 0.5, 0.0]\nfov_y_deg = 35.0\n",
        common::SCENE
    );
    std::fs::write(work.join("travel.toml"), scene_text).unwrap();
    let o = vcuts(
        &work,
        &[
            "-q",
            "precompute",
            "--scene",
            "travel.toml",
            "--estimate-seconds",
            "0.1",
            "--cache-dir",
            "cache",
            "-o",
            "t.vcuts",
        ],
    );
    assert!(o.status.success(), "{}", text(&o));
    let render = |cwd: &Path, file: &str, exr: &str, more: &[&str]| {
        let args = ["render", file, "--camera", "side", "--width", "64", "--height", "48", "-o", "f.png", "--exr", exr];
        let o = vcuts(cwd, &[&args[..], more].concat());
        assert!(o.status.success(), "{}", text(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains("light_error_target=0.01"), "{}", text(&o));
        std::fs::read(cwd.join(exr)).unwrap()
    };
    let here = render(&work, "t.vcuts", "here.exr", &[]);
    // The embedded map is the file's, texel for texel.
    assert!(here == render(&work, "t.vcuts", "file.exr", &["--env", "probe.exr"]), "the embedded map differs");
    std::fs::rename(work.join("travel.toml"), s.0.join("moved.toml")).unwrap();
    std::fs::remove_file(work.join("probe.exr")).unwrap();
    let file = work.join("t.vcuts");
    let there = render(&elsewhere, file.to_str().unwrap(), "there.exr", &[]);
    assert!(here == there, "the image changed once the scene and map were gone");
}

/// A built-in map travels as its description, not its texels: the file holds no `environment`
/// section, bakes the scene's own sky again (its sun, size and rotation) and renders the same
/// image once the scene file is gone.
#[test]
fn a_built_in_map_travels_as_its_description() {
    let s = scratch("cli-recipe");
    let scene_text = format!(
        "{}\n[environment]\nsource = \"builtin:sky\"\nsun_elevation_deg = 14.0\nsun_azimuth_deg = -60.0\n\
         resolution = 128\nrotation_deg = 25.0\nreconstruction = \"bilinear\"\n",
        common::SCENE
    );
    std::fs::write(s.0.join("sky.toml"), scene_text).unwrap();
    let mut data = common::precomputed(&s, "sky.toml", &[]);
    let recipe = data.view.as_ref().and_then(|v| v.environment.clone()).expect("the view records the sky");
    assert_eq!((recipe.sun_elevation_deg, recipe.resolution, recipe.rotation_deg), (14.0, 128, 25.0));
    assert_eq!(recipe.reconstruction, vcut_envmap::Reconstruction::Bilinear);
    let baked = data.environment().unwrap().expect("the file bakes its map");
    let scene = vcut_scene::Scene::open(s.0.join("sky.toml").to_str().unwrap()).unwrap();
    assert!(baked.texels() == scene.environment.texels(), "the re-baked sky differs from the scene's");
    assert_eq!(baked.rotation(), scene.environment.rotation());
    assert_eq!(baked.integrated_texels(), scene.environment.integrated_texels(), "reconstructed as the scene's");
    let embedded = <vcut_data::file::SectionId as vcut_data::file::Sections>::environment();
    assert!(!data.reader().has(embedded), "the texels were embedded");
    let file = s.0.join("sky.vcuts");
    let render = |exr: &str, extra: &[&str]| {
        let mut args =
            vec!["render", file.to_str().unwrap(), "--width", "48", "--height", "32", "-o", "f.png", "--exr", exr];
        args.extend_from_slice(extra);
        let o = vcuts(&s.0, &args);
        assert!(o.status.success(), "{}", text(&o));
        (std::fs::read(s.0.join(exr)).unwrap(), text(&o))
    };
    let (before, out) = render("before.exr", &[]);
    assert!(out.contains("reconstruction=bilinear"), "{out}");
    std::fs::remove_file(s.0.join("sky.toml")).unwrap();
    assert!(before == render("after.exr", &[]).0, "the image changed once the scene file was gone");
    // --reconstruction overrides the recorded one, and the light changes with it.
    let (boxed, out) = render("box.exr", &["--reconstruction", "box"]);
    assert!(out.contains("reconstruction=box") && boxed != before, "{out}");
    let o = vcuts(&s.0, &["render", file.to_str().unwrap(), "-o", "g.png", "--reconstruction", "cubic"]);
    assert!(!o.status.success() && text(&o).contains("box or bilinear"), "{}", text(&o));
}

#[test]
fn directions_in_wedges_report_their_symmetry_and_bad_wedges_name_the_options() {
    let s = scratch("cli-wedges");
    let o = vcuts(
        &s.0,
        &["-q", "--json", "directions", "--n", "1024", "--wedges", "16", "--no-cache", "--env", "builtin:studio"],
    );
    assert!(o.status.success(), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("\"wedges\":16") && out.contains("\"tree_height\":10"), "{out}");
    let o = vcuts(&s.0, &["directions", "--n", "1024", "--wedges", "16", "--start", "random", "--no-cache"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("--start random --wedges 16") && text(&o).contains("Fibonacci"), "{}", text(&o));
    let o = vcuts(
        &s.0,
        &["directions", "--n", "1024", "--wedges", "16", "--bands", "3", "--no-cache", "--env", "builtin:studio"],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("--wedges 16 --bands 3") && text(&o).contains("powers of two"), "{}", text(&o));
    assert!(!text(&o).contains("panicked"));
}
