//! The plant, its leaves and the sun as the command line gives them ([`PlantArgs`], shared by
//! `vcuts leaves`, `vcuts view --leaves` and Python's `vcuts.leaves`): the plant's source, the
//! leaf material, the lighting, the precompute's parameters and the camera.

use crate::values::{Pair, Rgb};
use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::path::PathBuf;
use vcut_envmap::EnvMap;
use vcut_leaf::lvc::{Content, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::PrtParams;
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{Lighting, sun_at, sun_direction};
use vcut_scene::Camera;
use vcut_scene::limits::Limit;

/// Where a plant comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PlantSource {
    /// The built-in procedural plant.
    Procedural,
    /// The shared assets' potted plant, every surface a leaf.
    Asset,
    /// A glTF or OBJ file read the same way.
    File(PathBuf),
}

impl std::str::FromStr for PlantSource {
    type Err = String;

    fn from_str(s: &str) -> Result<PlantSource, String> {
        Ok(match s {
            "procedural" => PlantSource::Procedural,
            "asset" => PlantSource::Asset,
            "" => return Err("expected `procedural`, `asset` or a glTF/OBJ file".into()),
            path => PlantSource::File(path.into()),
        })
    }
}

impl std::fmt::Display for PlantSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlantSource::Procedural => f.write_str("procedural"),
            PlantSource::Asset => f.write_str("asset"),
            PlantSource::File(p) => write!(f, "{}", p.display()),
        }
    }
}

/// The plant, its leaves and the sun: shared by `vcuts leaves` and `vcuts view --leaves`.
#[derive(clap::Args, Clone)]
pub struct PlantArgs {
    /// `procedural` (the built-in plant), `asset` (the shared potted plant, every surface a leaf)
    /// or a glTF/OBJ file read the same way.
    #[arg(long, default_value = "procedural")]
    pub plant: PlantSource,
    /// Leaves of the procedural plant (at least 1).
    #[arg(long, default_value_t = 48, value_parser = crate::options::whole::<u32>("leaf-count"), allow_hyphen_values = true)]
    pub leaf_count: u32,
    /// Instead of --leaf-count: about this many leaf vertices (16 × 8 quads per leaf).
    #[arg(long, value_parser = crate::options::whole::<u64>("vertices"), allow_hyphen_values = true)]
    pub vertices: Option<u64>,
    /// Sun direction as ELEVATION,AZIMUTH in degrees (azimuth from +Z toward +X); default the map's.
    #[arg(long, allow_hyphen_values = true)]
    pub sun: Option<Pair>,
    /// Sun direction from a time of day in hours (6 = sunrise in the east, 12 = noon at 60°,
    /// 18 = sunset in the west); overrides --sun.
    #[arg(long, value_parser = crate::options::real("time-of-day"), allow_hyphen_values = true)]
    pub time_of_day: Option<f32>,
    /// Sun disk diameter in degrees (above 0, below 180).
    #[arg(long, default_value_t = 0.53, value_parser = crate::options::real("sun-diameter"), allow_hyphen_values = true)]
    pub sun_diameter: f32,
    /// LVC cube face resolution (6·R² sun directions).
    #[arg(long, default_value_t = 32, value_parser = crate::options::whole::<u32>("lvc-resolution"), allow_hyphen_values = true)]
    pub lvc_resolution: u32,
    /// Store the paper's cosine-weighted V in the maps instead of the visibility alone.
    #[arg(long)]
    pub cosine_baked: bool,
    /// PRT rays per vertex side.
    #[arg(long, default_value_t = 256, value_parser = crate::options::whole::<u32>("prt-rays"), allow_hyphen_values = true)]
    pub prt_rays: u32,
    /// Rays per vertex toward the true sun where the maps around its direction disagree (a
    /// shadow edge passes between them); 0: those maps blended only.
    #[arg(long, default_value_t = 4, value_parser = crate::options::whole::<u32>("sun-edge-rays"), allow_hyphen_values = true)]
    pub sun_edge_rays: u32,
    /// PRT scatterings in the indirect transfer.
    #[arg(long, default_value_t = 3, value_parser = crate::options::whole::<u32>("bounces"), allow_hyphen_values = true)]
    pub bounces: u32,
    /// Leaf reflectance R,G,B (with --transmittance and --thickness: the tissue is fitted).
    #[arg(long, requires = "transmittance")]
    pub reflectance: Option<Rgb>,
    /// Leaf transmittance R,G,B.
    #[arg(long, requires = "reflectance")]
    pub transmittance: Option<Rgb>,
    /// Leaf thickness (mm, finite and above 0).
    #[arg(long, value_parser = crate::options::real("thickness"), allow_hyphen_values = true)]
    pub thickness: Option<f32>,
    /// Absorption σ_a R,G,B (per mm), instead of a fit.
    #[arg(long)]
    pub sigma_a: Option<Rgb>,
    /// Scattering σ_s R,G,B (per mm), instead of a fit.
    #[arg(long)]
    pub sigma_s: Option<Rgb>,
    /// Gloss of the upper side: RHO_S,ROUGHNESS (ρ_s ≥ 0, roughness > 0).
    #[arg(long, value_parser = gloss)]
    pub gloss_top: Option<Pair>,
    /// Gloss of the lower side: RHO_S,ROUGHNESS.
    #[arg(long, value_parser = gloss)]
    pub gloss_bottom: Option<Pair>,
    /// No parameter maps on the procedural leaves.
    #[arg(long)]
    pub no_maps: bool,
    /// Where the precomputed maps and transfer are kept (a `.vleaf` file, reused while it holds
    /// this plant's; resumed after an interrupted run). Default:
    /// target/vleaf/<plant>-<inputs' CRC-32>.vleaf.
    #[arg(long)]
    pub leaf_data: Option<PathBuf>,
    /// Compute the leaf data again even if the file holds it.
    #[arg(long)]
    pub fresh: bool,
    /// What computing the leaf data takes, printed before it starts (unless it is only loaded).
    #[command(flatten)]
    pub estimate: crate::resources::EstimateArgs,
}

/// `--time-of-day`.
pub const HOURS: Limit = Limit::within(0.0, 24.0, "hours");
/// `--sun-diameter`.
pub const SUN_DIAMETER: Limit = Limit::between(0.0, 180.0, "degrees");
/// `--thickness`.
pub const THICKNESS: Limit = Limit::above(0.0, "mm");
/// The specular albedo of `--gloss-top`, `--gloss-bottom`.
pub const RHO_S: Limit = Limit::at_least(0.0, "");
/// The roughness of `--gloss-top`, `--gloss-bottom`.
pub const ROUGHNESS: Limit = Limit::above(0.0, "");

fn gloss(s: &str) -> Result<Pair, String> {
    let p: Pair = s.parse()?;
    RHO_S.check(f64::from(p.0)).map_err(|r| format!("{s:?}: ρ_s {r}"))?;
    ROUGHNESS.check(f64::from(p.1)).map_err(|r| format!("{s:?}: roughness {r}"))?;
    Ok(p)
}

/// The leaf material the arguments describe.
pub fn material(args: &PlantArgs) -> Result<LeafMaterial> {
    let mut m = LeafMaterial::default();
    if let (Some(r), Some(t)) = (args.reflectance, args.transmittance) {
        let h = args.thickness.unwrap_or(m.thickness);
        m = LeafMaterial::from_measured(r.0, t.0, h)
            .map_err(|e| anyhow::anyhow!("--reflectance/--transmittance: {e}"))?;
    } else if let Some(h) = args.thickness {
        m.thickness = h;
    }
    if let Some(s) = args.sigma_a {
        m.sigma_a = s.0;
    }
    if let Some(s) = args.sigma_s {
        m.sigma_s = s.0;
    }
    for (side, g) in [args.gloss_top, args.gloss_bottom].into_iter().enumerate() {
        if let Some(Pair(rho, roughness)) = g {
            m.gloss[side].rho_s = Vec3::splat(rho);
            m.gloss[side].roughness = roughness;
        }
    }
    Ok(m)
}

/// The scene the arguments name.
pub fn scene(args: &PlantArgs, material: &LeafMaterial) -> Result<LeafScene> {
    let path = match &args.plant {
        PlantSource::Procedural => {
            let mut p = match args.vertices {
                Some(n) => PlantParams::with_vertices(n as usize),
                None => PlantParams { leaves: args.leaf_count, ..PlantParams::default() },
            };
            p.maps = !args.no_maps;
            return Ok(plant(&p, material)?);
        }
        PlantSource::Asset => {
            vcut_scene::assets::locate("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf")?
        }
        PlantSource::File(path) => path.clone(),
    };
    let s = vcut_scene::Scene::open(&path.to_string_lossy())?;
    LeafScene::from_scene_as_leaves(&s, material).with_context(|| path.display().to_string())
}

/// A camera looking at the scene's bounding sphere from the front, a little above.
pub fn camera(scene: &LeafScene) -> Camera {
    let (c, r) = scene.leaf_bounds();
    let target = c - Vec3::Y * 0.15 * r;
    Camera {
        name: "leaves".into(),
        position: target + Vec3::new(0.55, 0.45, 1.0).normalize() * 3.2 * r,
        target,
        up: Vec3::Y,
        fov_y_deg: 40.0,
    }
}

/// The sun direction the arguments ask for, as (elevation, azimuth) degrees, if any.
pub fn sun_angles(args: &PlantArgs) -> Option<(f32, f32)> {
    match (args.time_of_day, args.sun) {
        (Some(h), _) => Some(sun_at(h)),
        (None, Some(Pair(e, a))) => Some((e, a)),
        _ => None,
    }
}

/// The lighting the arguments describe, and the map without its sun (for the reference).
pub fn lighting(args: &PlantArgs, env_spec: &str) -> Result<(Lighting, EnvMap)> {
    let env = crate::inspect::load_envmap(env_spec)?;
    let (mut light, rest) = Lighting::from_map(&env);
    if let Some((e, a)) = sun_angles(args) {
        let d = sun_direction(e, a);
        if light.sun.is_none() {
            bail!("{env_spec}: no sun found in the map to move (a sun holds ≥ 2 % of the power)");
        }
        light = light.with_sun_dir(d);
    }
    Ok((light, rest))
}

/// The LVC and PRT parameters the arguments ask for.
pub fn params(p: &PlantArgs) -> (LvcParams, PrtParams) {
    (
        LvcParams {
            resolution: p.lvc_resolution,
            sun_diameter_deg: p.sun_diameter,
            content: if p.cosine_baked { Content::CosineBaked } else { Content::Visibility },
            ..LvcParams::default()
        },
        PrtParams { rays: p.prt_rays, bounces: p.bounces, ..PrtParams::default() },
    )
}
