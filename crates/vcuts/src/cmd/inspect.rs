//! `vcuts inspect`: what a scene, mesh file or environment map holds.

use anyhow::{Context, Result};
use serde::Serialize;
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
    #[arg(long, value_parser = parse_split)]
    pub split: Option<Split>,
    /// Weld mesh vertices closer than this distance (finite, at least 0).
    #[arg(long, value_parser = crate::options::real("weld"), allow_hyphen_values = true)]
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

fn parse_split(s: &str) -> Result<Split, String> {
    match s {
        "mesh-nodes" => Ok(Split::MeshNodes),
        "top-level-nodes" => Ok(Split::TopLevelNodes),
        "groups" => Ok(Split::Groups),
        "file" => Ok(Split::File),
        _ => Err(format!("{s:?}: expected mesh-nodes, top-level-nodes, groups or file")),
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

/// What `inspect` found: a mesh file's own counts, a scene's objects and cameras, a map's power.
#[derive(Debug, Clone, Default, Serialize)]
pub struct InspectOutcome {
    /// A mesh file's counts before and after validation.
    #[serde(flatten)]
    pub file: Option<FileCounts>,
    /// A scene's (or a mesh file's) objects, bounds and cameras.
    #[serde(flatten)]
    pub scene: Option<SceneSummary>,
    /// The environment map: the scene's, or the one inspected.
    #[serde(flatten)]
    pub envmap: Option<EnvMapSummary>,
}

/// A mesh file's own counts and what validation changed.
#[derive(Debug, Clone, Serialize)]
pub struct FileCounts {
    /// Vertices in the file.
    pub file_vertices: usize,
    /// Triangles in the file.
    pub file_triangles: usize,
    /// Primitives not read (not triangles).
    pub skipped_primitives: usize,
    /// Zero-area triangles dropped.
    pub degenerate_triangles_dropped: usize,
    /// Vertices no triangle uses, dropped.
    pub unreferenced_vertices_dropped: usize,
    /// Vertices welded.
    pub vertices_welded: usize,
    /// Normals computed where the file had none.
    pub normals_computed: usize,
}

/// A scene's objects, bounds and cameras.
#[derive(Debug, Clone, Serialize)]
pub struct SceneSummary {
    /// How many objects.
    pub objects: usize,
    /// Vertices of every object.
    pub vertices: usize,
    /// Triangles of every object.
    pub triangles: usize,
    /// The scene's bounds.
    pub bounds_min: [f32; 3],
    /// The scene's bounds.
    pub bounds_max: [f32; 3],
    /// Seconds to load it.
    pub load_s: f64,
    /// How many cameras.
    pub cameras: usize,
    /// Each camera.
    pub camera: Vec<CameraRow>,
    /// Each object.
    pub object: Vec<ObjectRow>,
    /// The environment's source.
    pub environment: String,
}

/// One camera of a scene.
#[derive(Debug, Clone, Serialize)]
pub struct CameraRow {
    /// Its name.
    pub name: String,
    /// Where it is.
    pub position: [f32; 3],
    /// What it looks at.
    pub target: [f32; 3],
    /// Its vertical field of view.
    pub fov_y_deg: f32,
}

/// One object of a scene.
#[derive(Debug, Clone, Serialize)]
pub struct ObjectRow {
    /// Its name.
    pub name: String,
    /// `static` or `moves`.
    pub motion: &'static str,
    /// Its vertices.
    pub vertices: usize,
    /// Its triangles.
    pub triangles: usize,
    /// Its BRDF model.
    pub material: String,
    /// Its bounds.
    pub bounds_min: [f32; 3],
    /// Its bounds.
    pub bounds_max: [f32; 3],
    /// Its bounding sphere's centre.
    pub center: [f32; 3],
    /// Its bounding sphere's radius.
    pub radius: f32,
}

/// An environment map's layout and power.
#[derive(Debug, Clone, Serialize)]
pub struct EnvMapSummary {
    /// Texels clamped on load (`--clamp-invalid`).
    pub clamped_texels: Option<usize>,
    /// Its source.
    pub envmap: String,
    /// Its layout.
    pub layout: String,
    /// Its texels.
    pub texels: usize,
    /// Its rotation about +Y.
    pub rotation_y_deg: f32,
    /// Its intensity factor.
    pub intensity: f32,
    /// Its total power, per channel.
    pub total_power_rgb: [f64; 3],
    /// The brightest texel's luminance.
    pub brightest_texel_luminance: f32,
    /// The brightest texel's direction.
    pub brightest_texel_dir: [f32; 3],
    /// The share of the power in the brightest 0.1 % of texels.
    #[serde(rename = "energy_share_top_0.1pct")]
    pub energy_share_top_0_1pct: f64,
    /// Its reconstruction between texel centres.
    pub reconstruction: &'static str,
    /// A lat-long map's irradiance on an open plane facing up, under the box reconstruction.
    pub irradiance_up_box: Option<f64>,
    /// The same under the bilinear reconstruction.
    pub irradiance_up_bilinear: Option<f64>,
    /// Their relative difference.
    pub reconstruction_difference_up: Option<f64>,
    /// Seconds to load it (a map inspected on its own).
    pub load_s: Option<f64>,
}

/// Runs `inspect`.
pub fn run(args: &InspectArgs) -> Result<InspectOutcome> {
    let t = args.target.as_str();
    if is_envmap(t) {
        let start = Instant::now();
        let mut clamped = None;
        let map = match t {
            "builtin:sky" | "builtin:studio" => load_envmap(t)?,
            _ => {
                let invalid = if args.clamp_invalid { InvalidTexels::Clamp } else { InvalidTexels::Reject };
                let (map, report) = vcut_envmap::load(Path::new(t), invalid)?;
                clamped = (report.clamped_texels > 0).then_some(report.clamped_texels);
                map
            }
        };
        let mut envmap = envmap_summary(&map, Some(start.elapsed().as_secs_f64()));
        envmap.clamped_texels = clamped;
        return Ok(InspectOutcome { envmap: Some(envmap), ..InspectOutcome::default() });
    }
    let start = Instant::now();
    let ext = Path::new(t).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    let mut file = None;
    let scene = if matches!(ext.as_deref(), Some("obj" | "gltf" | "glb")) {
        file = Some(file_counts(Path::new(t), args.split, args.weld)?);
        let desc = SceneDesc {
            objects: vec![ObjectDesc { source: t.into(), split: args.split, weld: args.weld, ..Default::default() }],
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
    crate::warn_ignored(&scene);
    Ok(InspectOutcome {
        file,
        scene: Some(scene_summary(&scene, start.elapsed().as_secs_f64())),
        envmap: Some(envmap_summary(&scene.environment, None)),
    })
}

/// The file's own counts and what validation changed.
fn file_counts(path: &Path, split: Option<Split>, weld: Option<f32>) -> Result<FileCounts> {
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
    Ok(FileCounts {
        file_vertices: out.file_vertices,
        file_triangles: out.file_triangles,
        skipped_primitives: out.skipped_primitives,
        degenerate_triangles_dropped: r.degenerate_triangles_dropped,
        unreferenced_vertices_dropped: r.unreferenced_vertices_dropped,
        vertices_welded: r.vertices_welded,
        normals_computed: r.normals_computed,
    })
}

fn scene_summary(scene: &Scene, load_s: f64) -> SceneSummary {
    let b = scene.bounds();
    let camera = scene
        .cameras
        .iter()
        .map(|c| CameraRow {
            name: c.name.clone(),
            position: c.position.to_array(),
            target: c.target.to_array(),
            fov_y_deg: c.fov_y_deg,
        })
        .collect();
    let object = scene
        .objects
        .iter()
        .map(|o| {
            let b = o.mesh.bounds();
            ObjectRow {
                name: o.name.clone(),
                motion: match o.motion {
                    Motion::Static => "static",
                    Motion::Movable => "moves",
                },
                vertices: o.mesh.vertex_count(),
                triangles: o.mesh.triangle_count(),
                material: format!("{:?}", o.material.model),
                bounds_min: b.min.to_array(),
                bounds_max: b.max.to_array(),
                center: b.center.to_array(),
                radius: b.radius,
            }
        })
        .collect();
    SceneSummary {
        objects: scene.objects.len(),
        vertices: scene.vertex_count(),
        triangles: scene.triangle_count(),
        bounds_min: b.min.to_array(),
        bounds_max: b.max.to_array(),
        load_s,
        cameras: scene.cameras.len(),
        camera,
        object,
        environment: scene.environment.source().to_string(),
    }
}

fn envmap_summary(map: &EnvMap, load_s: Option<f64>) -> EnvMapSummary {
    let s = map.power_stats();
    // What the reconstruction changes: the irradiance of an open plane facing up under each
    // (8 × 8 patches per texel), for a lat-long map.
    let up = |r: vcut_envmap::Reconstruction| {
        let m = map.clone().with_reconstruction(r).ok()?;
        let mut e = 0.0f64;
        m.for_each_patch(8, |d, omega, c| e += f64::from(vcut_envmap::luminance(c)) * f64::from(d.y.max(0.0)) * omega);
        Some(e)
    };
    let lat_long = matches!(map.layout(), vcut_envmap::Layout::LatLong { .. });
    let (b, l) = if lat_long {
        (up(vcut_envmap::Reconstruction::Box), up(vcut_envmap::Reconstruction::Bilinear))
    } else {
        (None, None)
    };
    EnvMapSummary {
        clamped_texels: None,
        envmap: map.source().to_string(),
        layout: map.layout().describe(),
        texels: map.texels().len(),
        rotation_y_deg: map.rotation().to_euler(glam::EulerRot::YXZ).0.to_degrees(),
        intensity: map.intensity(),
        total_power_rgb: s.total_power,
        brightest_texel_luminance: s.brightest_luminance,
        brightest_texel_dir: s.brightest_dir.to_array(),
        energy_share_top_0_1pct: s.top_0_1_percent_share,
        reconstruction: map.reconstruction().name(),
        irradiance_up_box: b,
        irradiance_up_bilinear: l,
        reconstruction_difference_up: b.zip(l).map(|(b, l)| if b > 0.0 { (l - b) / b } else { 0.0 }),
        load_s,
    }
}
