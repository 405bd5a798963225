//! `cargo xtask inspect`: what a scene, mesh file or environment map holds.

use anyhow::{Context, Result};
use std::path::Path;
use std::time::Instant;
use vcut_envmap::{EnvMap, InvalidTexels};
use vcut_scene::desc::{EnvironmentDesc, ObjectDesc, SceneDesc, Split};
use vcut_scene::{Motion, Scene};

/// Arguments of `inspect`.
#[derive(clap::Args)]
pub struct InspectArgs {
    /// A scene file (.toml), `builtin:teapot|bunny|spheres`, a mesh (.obj/.gltf/.glb), an
    /// environment map (.hdr/.exr, a folder of cube faces, `builtin:sky|studio`).
    pub target: String,
    /// How a mesh file splits into objects: mesh-nodes, top-level-nodes, groups, file.
    #[arg(long)]
    pub split: Option<String>,
    /// Weld mesh vertices closer than this distance.
    #[arg(long)]
    pub weld: Option<f32>,
    /// Clamp NaN/Inf/negative environment texels instead of refusing the file.
    #[arg(long)]
    pub clamp_invalid: bool,
}

impl InspectArgs {
    /// Defaults for one target.
    pub fn target(t: &str) -> Self {
        Self { target: t.into(), split: None, weld: None, clamp_invalid: false }
    }
}

fn is_envmap(t: &str) -> bool {
    let p = Path::new(t);
    matches!(t, "builtin:sky" | "builtin:studio")
        || p.is_dir()
        || matches!(
            p.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref(),
            Some("hdr" | "exr" | "pic")
        )
}

/// Loads an environment map from a file, a cube folder, or `builtin:sky|studio|constant`.
/// A built-in is baked from the scene file's defaults for `[environment]`
/// ([`EnvironmentDesc::builtin`]), so a `.vcuts` file can record it by that description.
pub fn load_envmap(spec: &str) -> Result<EnvMap> {
    Ok(match EnvironmentDesc::builtin(spec) {
        Some(desc) => desc.load(Path::new("."), Path::new(spec))?,
        None => vcut_envmap::load(Path::new(spec), InvalidTexels::Reject)?.0,
    })
}

/// Runs `inspect`.
pub fn run(args: &InspectArgs) -> Result<()> {
    let t = args.target.as_str();
    if is_envmap(t) {
        let start = Instant::now();
        let map = match t {
            "builtin:sky" | "builtin:studio" => load_envmap(t)?,
            _ => {
                let invalid = if args.clamp_invalid { InvalidTexels::Clamp } else { InvalidTexels::Reject };
                let (map, report) = vcut_envmap::load(Path::new(t), invalid)?;
                if report.clamped_texels > 0 {
                    println!("clamped_texels={}", report.clamped_texels);
                }
                map
            }
        };
        print_envmap(&map, start.elapsed().as_secs_f64());
        return Ok(());
    }
    let start = Instant::now();
    let ext = Path::new(t).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let scene = if matches!(ext.as_deref(), Some("obj" | "gltf" | "glb")) {
        let split = match args.split.as_deref() {
            None => None,
            Some("mesh-nodes") => Some(Split::MeshNodes),
            Some("top-level-nodes") => Some(Split::TopLevelNodes),
            Some("groups") => Some(Split::Groups),
            Some("file") => Some(Split::File),
            Some(s) => anyhow::bail!("--split {s}: expected mesh-nodes, top-level-nodes, groups or file"),
        };
        print_file_counts(Path::new(t), split, args.weld)?;
        let desc = SceneDesc {
            objects: vec![ObjectDesc { source: t.into(), split, weld: args.weld, ..Default::default() }],
            ..Default::default()
        };
        let base = std::env::current_dir().context("current directory")?;
        desc.instantiate(&base, Path::new(t))?
    } else {
        if ext.as_deref() == Some("toml") {
            // The [precompute] table is checked here too, as precompute will read it.
            let desc = SceneDesc::read(Path::new(t))?;
            vcut_precompute::PrecomputeParams::resolve(None, desc.precompute.as_ref(), &[])
                .with_context(|| format!("{t}: [precompute]"))?;
        }
        Scene::open(t)?
    };
    let load_s = start.elapsed().as_secs_f64();
    print_scene(&scene, load_s);
    Ok(())
}

/// The file's own counts and what validation changed.
fn print_file_counts(path: &Path, split: Option<Split>, weld: Option<f32>) -> Result<()> {
    use vcut_scene::loaders::{GltfObjects, ObjObjects, load_file};
    let (g, o) = match split {
        Some(Split::TopLevelNodes | Split::File) => (GltfObjects::TopLevelNodes, ObjObjects::File),
        Some(Split::Groups) => (GltfObjects::MeshNodes, ObjObjects::Groups),
        _ => (GltfObjects::MeshNodes, ObjObjects::File),
    };
    let options = vcut_scene::MeshOptions {
        weld: weld.map_or(vcut_scene::Weld::None, vcut_scene::Weld::Within),
        ..Default::default()
    };
    let out = load_file(path, g, o, options)?;
    let mut r = vcut_scene::MeshReport::default();
    for obj in &out.objects {
        r.accumulate(&obj.report);
    }
    println!("file_vertices={}", out.file_vertices);
    println!("file_triangles={}", out.file_triangles);
    println!("skipped_primitives={}", out.skipped_primitives);
    println!("degenerate_triangles_dropped={}", r.degenerate_triangles_dropped);
    println!("unreferenced_vertices_dropped={}", r.unreferenced_vertices_dropped);
    println!("vertices_welded={}", r.vertices_welded);
    println!("normals_computed={}", r.normals_computed);
    Ok(())
}

fn print_scene(scene: &Scene, load_s: f64) {
    println!("objects={}", scene.objects.len());
    println!("vertices={}", scene.vertex_count());
    println!("triangles={}", scene.triangle_count());
    let b = scene.bounds();
    println!("bounds_min={:.4},{:.4},{:.4}", b.min.x, b.min.y, b.min.z);
    println!("bounds_max={:.4},{:.4},{:.4}", b.max.x, b.max.y, b.max.z);
    println!("load_s={load_s:.3}");
    println!("cameras={}", scene.cameras.len());
    for c in &scene.cameras {
        let (p, t) = (c.position, c.target);
        println!(
            "camera {}: position {:.3},{:.3},{:.3} target {:.3},{:.3},{:.3} fov_y {:.2} deg",
            c.name, p.x, p.y, p.z, t.x, t.y, t.z, c.fov_y_deg
        );
    }
    crate::warn_ignored(scene);
    println!(
        "{:<24} {:>7} {:>9} {:>9} {:>11}  {:<28} {:<28} {:<30}",
        "object",
        "motion",
        "vertices",
        "triangles",
        "material",
        "bounds min",
        "bounds max",
        "bounding sphere (centre, r)"
    );
    for o in &scene.objects {
        let b = o.mesh.bounds();
        let motion = match o.motion {
            Motion::Static => "static",
            Motion::Movable => "moves",
        };
        println!(
            "{:<24} {:>7} {:>9} {:>9} {:>11}  {:<28} {:<28} {:<30}",
            o.name,
            motion,
            o.mesh.vertex_count(),
            o.mesh.triangle_count(),
            format!("{:?}", o.material.model),
            format!("({:.3}, {:.3}, {:.3})", b.min.x, b.min.y, b.min.z),
            format!("({:.3}, {:.3}, {:.3})", b.max.x, b.max.y, b.max.z),
            format!("({:.3}, {:.3}, {:.3}), {:.3}", b.center.x, b.center.y, b.center.z, b.radius),
        );
    }
    if !scene.cameras.is_empty() {
        let c = &scene.cameras[0];
        println!("camera={} position={} target={} fov_y_deg={}", c.name, c.position, c.target, c.fov_y_deg);
    }
    println!("environment={}", scene.environment.source());
    print_envmap(&scene.environment, f64::NAN);
}

fn print_envmap(map: &EnvMap, load_s: f64) {
    let s = map.power_stats();
    println!("envmap={}", map.source());
    println!("layout={}", map.layout().describe());
    println!("texels={}", map.texels().len());
    println!("rotation_y_deg={:.2}", map.rotation().to_euler(glam::EulerRot::YXZ).0.to_degrees());
    println!("intensity={}", map.intensity());
    println!("total_power_rgb={:.6},{:.6},{:.6}", s.total_power[0], s.total_power[1], s.total_power[2]);
    println!("brightest_texel_luminance={:.6e}", s.brightest_luminance);
    println!("brightest_texel_dir={:.4},{:.4},{:.4}", s.brightest_dir.x, s.brightest_dir.y, s.brightest_dir.z);
    println!("energy_share_top_0.1pct={:.4}", s.top_0_1_percent_share);
    println!("reconstruction={}", map.reconstruction().name());
    // What the reconstruction changes: the irradiance of an open plane facing up under each
    // (8 × 8 patches per texel), for a lat-long map.
    if let vcut_envmap::Layout::LatLong { .. } = map.layout() {
        let up = |r: vcut_envmap::Reconstruction| {
            let m = map.clone().with_reconstruction(r).expect("a lat-long map");
            let mut e = 0.0f64;
            m.for_each_patch(8, |d, omega, c| {
                e += f64::from(vcut_envmap::luminance(c)) * f64::from(d.y.max(0.0)) * omega
            });
            e
        };
        let (b, l) = (up(vcut_envmap::Reconstruction::Box), up(vcut_envmap::Reconstruction::Bilinear));
        println!("irradiance_up_box={b:.6}");
        println!("irradiance_up_bilinear={l:.6}");
        println!("reconstruction_difference_up={:.5}", if b > 0.0 { (l - b) / b } else { 0.0 });
    }
    if load_s.is_finite() {
        println!("load_s={load_s:.3}");
    }
}
