//! `cargo xtask leaves`: the plant-leaf renderer end to end — build (or load) a plant, precompute
//! the sun's light-visibility convolution and the SH transfer, shade a frame in two passes, and
//! compare it and the SH-only rendering with the path-traced reference; images and key=value
//! figures. Also the `leaves` section of `cargo xtask bench`.

use crate::progress::Bar;
pub use crate::resources::EstimateArgs;
use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vcut_envmap::EnvMap;
use vcut_leaf::breakdown::breakdown;
use vcut_leaf::image::{render, render_triangles};
use vcut_leaf::lod::{Lod, LodParams};
use vcut_leaf::lvc::{Content, LvcParams};
use vcut_leaf::material::LeafMaterial;
use vcut_leaf::plant::{PlantParams, plant};
use vcut_leaf::prt::PrtParams;
use vcut_leaf::reference::{ReferenceParams, reference, rel_l2};
use vcut_leaf::scene::LeafScene;
use vcut_leaf::shade::{LeafData, Lighting, Shader, SunMethod, TwoSided, sun_at, sun_direction};
use vcut_leaf::store::{Inputs, LeafEstimate, Reuse};
use vcut_scene::Camera;
use vcut_scene::budget::human;
use vcut_scene::raster::Target;
use vcut_shade::image::{Image, auto_exposure, pixel_errors, write_png};
use vcut_shade::measure::median;

/// The plant, its leaves and the sun: shared by `cargo xtask leaves` and `cargo xtask view --leaves`.
#[derive(clap::Args, Clone)]
pub struct PlantArgs {
    /// `procedural` (the built-in plant), `asset` (the shared potted plant, every surface a leaf)
    /// or a glTF/OBJ file read the same way.
    #[arg(long, default_value = "procedural")]
    pub plant: String,
    /// Leaves of the procedural plant.
    #[arg(long, default_value_t = 48)]
    pub leaf_count: u32,
    /// Instead of --leaf-count: about this many leaf vertices (16 × 8 quads per leaf).
    #[arg(long)]
    pub vertices: Option<usize>,
    /// Sun direction as ELEVATION,AZIMUTH in degrees (azimuth from +Z toward +X); default the map's.
    #[arg(long, allow_hyphen_values = true)]
    pub sun: Option<String>,
    /// Sun direction from a time of day in hours (6 = sunrise in the east, 12 = noon at 60°,
    /// 18 = sunset in the west); overrides --sun.
    #[arg(long)]
    pub time_of_day: Option<f32>,
    /// Sun disk diameter in degrees.
    #[arg(long, default_value_t = 0.53)]
    pub sun_diameter: f32,
    /// LVC cube face resolution (6·R² sun directions).
    #[arg(long, default_value_t = 32)]
    pub lvc_resolution: u32,
    /// Store the paper's cosine-weighted V in the maps instead of the visibility alone.
    #[arg(long)]
    pub cosine_baked: bool,
    /// PRT rays per vertex side.
    #[arg(long, default_value_t = 256)]
    pub prt_rays: u32,
    /// Rays per vertex toward the true sun where the maps around its direction disagree (a
    /// shadow edge passes between them); 0: those maps blended only.
    #[arg(long, default_value_t = 4)]
    pub sun_edge_rays: u32,
    /// PRT scatterings in the indirect transfer.
    #[arg(long, default_value_t = 3)]
    pub bounces: u32,
    /// Leaf reflectance R,G,B (with --transmittance and --thickness: the tissue is fitted).
    #[arg(long)]
    pub reflectance: Option<String>,
    /// Leaf transmittance R,G,B.
    #[arg(long)]
    pub transmittance: Option<String>,
    /// Leaf thickness (mm).
    #[arg(long)]
    pub thickness: Option<f32>,
    /// Absorption σ_a R,G,B (per mm), instead of a fit.
    #[arg(long)]
    pub sigma_a: Option<String>,
    /// Scattering σ_s R,G,B (per mm), instead of a fit.
    #[arg(long)]
    pub sigma_s: Option<String>,
    /// Gloss of the upper side: RHO_S,ROUGHNESS.
    #[arg(long)]
    pub gloss_top: Option<String>,
    /// Gloss of the lower side: RHO_S,ROUGHNESS.
    #[arg(long)]
    pub gloss_bottom: Option<String>,
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
    pub estimate: EstimateArgs,
}

/// Arguments of `cargo xtask leaves`.
#[derive(clap::Args, Clone)]
pub struct LeavesArgs {
    /// The plant, leaves and sun.
    #[command(flatten)]
    pub plant: PlantArgs,
    /// Environment: builtin:sky (default), builtin:studio or a map file; its sun is split off.
    #[arg(long, default_value = "builtin:sky")]
    pub env: String,
    /// Paths per vertex side of the reference (0: no reference).
    #[arg(long, default_value_t = 1024)]
    pub reference_paths: u32,
    /// At most this many vertices get a reference (a spread subset; all of a small scene).
    #[arg(long, default_value_t = 6500)]
    pub reference_vertices: usize,
    /// Also split the error by light path (the sun and the environment, each whole and
    /// unscattered, the sun on the maps' own direction) and by gloss (the environment and the
    /// sun with every leaf's gloss removed): eight more references.
    #[arg(long)]
    pub breakdown: bool,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "960x720")]
    pub size: String,
    /// Output folder (images).
    #[arg(long, default_value = "target/leaves")]
    pub out: PathBuf,
}

fn triple(s: &str, what: &str) -> Result<Vec3> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{what} {s}: expected R,G,B numbers"))?;
    match v.as_slice() {
        [r, g, b] if v.iter().all(|x| x.is_finite() && *x >= 0.0) => Ok(Vec3::new(*r, *g, *b)),
        [x] if x.is_finite() && *x >= 0.0 => Ok(Vec3::splat(*x)),
        _ => bail!("{what} {s}: expected three non-negative numbers R,G,B"),
    }
}

fn pair(s: &str, what: &str) -> Result<(f32, f32)> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("{what} {s}: expected two numbers"))?;
    match v.as_slice() {
        [a, b] if a.is_finite() && b.is_finite() => Ok((*a, *b)),
        _ => bail!("{what} {s}: expected two numbers A,B"),
    }
}

/// The leaf material the arguments describe.
pub fn material(args: &PlantArgs) -> Result<LeafMaterial> {
    let mut m = LeafMaterial::default();
    if args.reflectance.is_some() || args.transmittance.is_some() {
        let r = triple(args.reflectance.as_deref().context("--transmittance needs --reflectance")?, "--reflectance")?;
        let t =
            triple(args.transmittance.as_deref().context("--reflectance needs --transmittance")?, "--transmittance")?;
        let h = args.thickness.unwrap_or(m.thickness);
        m = LeafMaterial::from_measured(r, t, h).map_err(|e| anyhow::anyhow!("--reflectance/--transmittance: {e}"))?;
    } else if let Some(h) = args.thickness {
        if !(h.is_finite() && h > 0.0) {
            bail!("--thickness {h}: must be positive");
        }
        m.thickness = h;
    }
    if let Some(s) = &args.sigma_a {
        m.sigma_a = triple(s, "--sigma-a")?;
    }
    if let Some(s) = &args.sigma_s {
        m.sigma_s = triple(s, "--sigma-s")?;
    }
    for (side, g) in [&args.gloss_top, &args.gloss_bottom].into_iter().enumerate() {
        if let Some(g) = g {
            let (rho, m_rough) = pair(g, if side == 0 { "--gloss-top" } else { "--gloss-bottom" })?;
            if rho < 0.0 || m_rough <= 0.0 {
                bail!("gloss {g}: need ρ_s ≥ 0 and roughness > 0");
            }
            m.gloss[side].rho_s = Vec3::splat(rho);
            m.gloss[side].roughness = m_rough;
        }
    }
    Ok(m)
}

/// The scene the arguments name.
pub fn scene(args: &PlantArgs, material: &LeafMaterial) -> Result<LeafScene> {
    Ok(match args.plant.as_str() {
        "procedural" => {
            let mut p = match args.vertices {
                Some(n) => PlantParams::with_vertices(n),
                None => PlantParams { leaves: args.leaf_count.max(1), ..PlantParams::default() },
            };
            p.maps = !args.no_maps;
            plant(&p, material)?
        }
        spec => {
            let path = if spec == "asset" {
                vcut_scene::assets::locate("plants/polyhaven_potted_plant_04_1k/potted_plant_04_1k.gltf")?
            } else {
                PathBuf::from(spec)
            };
            let s = vcut_scene::Scene::open(&path.to_string_lossy())?;
            LeafScene::from_scene_as_leaves(&s, material).with_context(|| path.display().to_string())?
        }
    })
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

/// A progress bar over a plant's vertices.
pub fn bar(len: usize, what: &str) -> Bar {
    Bar::new(what, len as u64, "vertices")
}

/// Everything precomputed for a scene.
pub struct Precomputed {
    /// The LVC maps and the SH transfer.
    pub data: LeafData,
    /// Seconds: LVC, PRT (0 when loaded).
    pub seconds: (f64, f64),
    /// Where they are saved, and what loading, resuming or computing them did.
    pub file: PathBuf,
    /// What the store did.
    pub outcome: vcut_leaf::store::Outcome,
}

/// The `.vleaf` file of these inputs: `--leaf-data`, else `target/vleaf/<plant>-<inputs' CRC>.vleaf`.
pub fn data_path(args: &PlantArgs, inputs: &Inputs<'_>) -> PathBuf {
    args.leaf_data.clone().unwrap_or_else(|| {
        let stem: String = Path::new(&args.plant)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "plant".into())
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_')
            .collect();
        PathBuf::from("target/vleaf").join(inputs.file_name(&stem))
    })
}

/// The LVC maps (every sun direction, or only `suns`) and the transfer of `scene`, in `file`:
/// loaded when it holds them (and `reuse` allows), else estimated (printed, checked against the
/// free memory and disk), computed — resuming a partial file — and saved there. `None` after a
/// dry run.
pub fn precompute(
    scene: &LeafScene,
    (lvc, prt): (&LvcParams, &PrtParams),
    suns: Option<&[usize]>,
    file: &Path,
    reuse: Reuse,
    est: EstimateArgs,
) -> Result<Option<Precomputed>> {
    let inputs = Inputs { scene, lvc: *lvc, prt: *prt, suns };
    let loads = reuse == Reuse::IfMatching && file.exists() && vcut_leaf::store::holds(file, &inputs).is_ok();
    let estimate = (!loads).then(|| vcut_leaf::store::estimate(&inputs, est.budget()));
    if let Some(e) = &estimate {
        print_estimate(e);
        crate::resources::check("the leaf precompute", e.peak_bytes, (file, e.output_bytes), est.force)?;
        if est.dry_run {
            return Ok(None);
        }
    } else if est.dry_run {
        println!("estimate: nothing to compute: {} holds this plant's leaf data", file.display());
        return Ok(None);
    }
    let bars = [bar(scene.vertex_count(), "LVC"), bar(scene.vertex_count(), "PRT")];
    let progress = |stage: &str, done: usize, _total: usize| {
        bars[usize::from(stage == "PRT")].set_position(done as u64);
    };
    let (data, outcome) = vcut_leaf::store::precompute(&inputs, file, reuse, &progress)?;
    bars.iter().for_each(Bar::finish_and_clear);
    if let Some(why) = &outcome.replaced {
        println!("leaf data: not reused ({why}); computed again");
    }
    let pre = Precomputed { data, seconds: (outcome.lvc_s, outcome.prt_s), file: file.into(), outcome };
    if let Some(e) = &estimate {
        print_against(e, &pre);
    }
    Ok(Some(pre))
}

/// The estimate as a sentence and key=value lines.
fn print_estimate(e: &LeafEstimate) {
    let (lv, pv, ss) = e.sampled;
    println!(
        "estimate: {} vertices, {:.1} M rays; about {:.1} s on {} threads (LVC {:.1} s, PRT {:.1} s); file {}; \
         peak memory {} (from a {ss:.1} s sample of {lv} + {pv} vertices)",
        e.vertices,
        (e.lvc_rays + e.prt_rays) as f64 / 1e6,
        e.lvc_seconds + e.prt_seconds,
        rayon::current_num_threads(),
        e.lvc_seconds,
        e.prt_seconds,
        human(e.output_bytes),
        human(e.peak_bytes),
    );
    println!("estimate_vertices={}", e.vertices);
    println!("estimate_rays={}", e.lvc_rays + e.prt_rays);
    println!("estimate_lvc_s={:.2}", e.lvc_seconds);
    println!("estimate_prt_s={:.2}", e.prt_seconds);
    println!("estimate_output_mb={:.3}", e.output_bytes as f64 / 1e6);
    println!("estimate_peak_mb={:.1}", e.peak_bytes as f64 / 1e6);
    println!("estimate_sample_s={ss:.2}");
}

/// The computed figures against the estimate's.
fn print_against(e: &LeafEstimate, pre: &Precomputed) {
    let peak = vcut_scene::budget::peak_memory().unwrap_or(0);
    println!("peak_rss_mb={:.1}", peak as f64 / 1e6);
    println!("estimate_vs_actual_s={:.3}", (e.lvc_seconds + e.prt_seconds) / (pre.seconds.0 + pre.seconds.1).max(1e-9));
    println!("estimate_vs_actual_output={:.3}", e.output_bytes as f64 / pre.outcome.file_bytes.max(1) as f64);
    if peak > 0 {
        println!("estimate_vs_actual_peak={:.3}", e.peak_bytes as f64 / peak as f64);
    }
}

/// Prints where the leaf data is and what was done to get it, as key=value lines.
pub fn print_store(pre: &Precomputed) {
    println!("leaf_data={}", pre.file.display());
    println!("leaf_data_loaded={}", pre.outcome.loaded);
    println!("leaf_data_bytes={}", pre.outcome.file_bytes);
    if pre.outcome.loaded {
        println!("leaf_data_load_s={:.3}", pre.outcome.load_s);
    } else {
        println!("lvc_chunks_resumed={}", pre.outcome.lvc_chunks_resumed);
    }
}

/// The sun direction the arguments ask for, as (elevation, azimuth) degrees, if any.
pub fn sun_angles(args: &PlantArgs) -> Result<Option<(f32, f32)>> {
    Ok(match (args.time_of_day, &args.sun) {
        (Some(h), _) => Some(sun_at(h)),
        (None, Some(s)) => Some(pair(s, "--sun")?),
        _ => None,
    })
}

/// The lighting the arguments describe, and the map without its sun (for the reference).
pub fn lighting(args: &PlantArgs, env_spec: &str) -> Result<(Lighting, EnvMap)> {
    let env = crate::inspect::load_envmap(env_spec)?;
    let (mut light, rest) = Lighting::from_map(&env);
    if let Some((e, a)) = sun_angles(args)? {
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
            resolution: p.lvc_resolution.max(1),
            sun_diameter_deg: p.sun_diameter,
            content: if p.cosine_baked { Content::CosineBaked } else { Content::Visibility },
            ..LvcParams::default()
        },
        PrtParams { rays: p.prt_rays, bounces: p.bounces, ..PrtParams::default() },
    )
}

/// A spread subset of at most `max` vertices.
pub fn subset(n: usize, max: usize) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    (0..max).map(|i| i * n / max).collect()
}

/// 2 × 2 box filter of an image twice the size (a pixel is covered when any sample is).
fn downsample(i: &Target) -> Image {
    let (w, h) = (i.width / 2, i.height / 2);
    let mut rgb = Vec::with_capacity(w * h);
    let mut covered = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let k = |dx: usize, dy: usize| (2 * y + dy) * i.width + 2 * x + dx;
            let ks = [k(0, 0), k(1, 0), k(0, 1), k(1, 1)];
            rgb.push(ks.iter().map(|&k| i.rgb[k]).sum::<Vec3>() * 0.25);
            covered.push(ks.iter().any(|&k| i.covered[k]));
        }
    }
    Image { width: w as u32, height: h as u32, rgb, covered }
}

/// A raster target as an image.
pub fn to_image(i: Target) -> Image {
    Image { width: i.width as u32, height: i.height as u32, rgb: i.rgb, covered: i.covered }
}

/// Runs `cargo xtask leaves`.
pub fn run(args: &LeavesArgs) -> Result<()> {
    let (w, h) = {
        let (a, b) = args.size.split_once('x').context("--size: expected WIDTHxHEIGHT")?;
        (a.parse::<u32>().context("--size width")?, b.parse::<u32>().context("--size height")?)
    };
    let p = &args.plant;
    let m = material(p)?;
    let t = Instant::now();
    let scene = scene(p, &m)?;
    println!("plant={}", p.plant);
    println!("vertices={}", scene.vertex_count());
    println!("triangles={}", scene.triangles().len());
    println!("leaf_sigma_a={:?}", m.sigma_a.to_array());
    println!("leaf_sigma_s={:?}", m.sigma_s.to_array());
    println!("leaf_thickness_mm={}", m.thickness);
    println!("scene_s={:.3}", t.elapsed().as_secs_f64());
    let (light, rest) = lighting(p, &args.env)?;
    let sun = light.sun.context("the environment has no sun: the leaf renderer's direct pass needs one")?;
    println!("sun_dir={:?}", sun.dir.to_array());
    let (lvc_params, prt) = params(p);
    let inputs = Inputs { scene: &scene, lvc: lvc_params, prt, suns: None };
    let reuse = if p.fresh { Reuse::Never } else { Reuse::IfMatching };
    let Some(pre) = precompute(&scene, (&lvc_params, &prt), None, &data_path(p, &inputs), reuse, p.estimate)? else {
        return Ok(());
    };
    print_store(&pre);
    println!("lvc_s={:.3}", pre.seconds.0);
    println!("lvc_raw_bytes={}", pre.data.lvc.raw_bytes());
    println!("lvc_rle_bytes={}", pre.data.lvc.compressed_bytes());
    println!("rle_ratio={:.2}", pre.data.lvc.raw_bytes() as f64 / pre.data.lvc.compressed_bytes().max(1) as f64);
    println!("prt_s={:.3}", pre.seconds.1);
    println!("transfer_bytes={}", pre.data.transfer.bytes());
    let cam = camera(&scene);
    let figures = frame_figures(&scene, &pre, &light, (cam.position, p.sun_edge_rays), 5)?;
    println!("decode_ms={:.3}", figures.decode_ms);
    println!("shade_ms={:.3}", figures.shade_ms);
    println!("sun_change_ms={:.3}", figures.sun_change_ms);
    let mut shader = Shader::with_edge_rays(p.sun_edge_rays);
    shader.prepare(&scene, &pre.data.lvc, &light)?;
    println!("sun_edge_vertices={}", shader.edge_vertices());
    let (mut lvc_rad, mut sh_rad) = (Vec::new(), Vec::new());
    shader.shade(&scene, &pre.data, &light, SunMethod::Lvc, cam.position, &mut lvc_rad);
    shader.shade(&scene, &pre.data, &light, SunMethod::ShOnly, cam.position, &mut sh_rad);
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let lvc_img = to_image(render(&scene, &lvc_rad, &cam, w, h, Some(&rest)));
    let exposure = auto_exposure(&lvc_img);
    let write = |name: &str, img: &Image| -> Result<PathBuf> {
        let p = args.out.join(name);
        write_png(img, &p, exposure)?;
        Ok(p)
    };
    println!("png_lvc_prt={}", write("leaves.png", &lvc_img)?.display());
    let sh_img = to_image(render(&scene, &sh_rad, &cam, w, h, Some(&rest)));
    println!("png_sh_only={}", write("leaves-sh-only.png", &sh_img)?.display());
    let lod_figures = lod_report(&scene, &pre.data, (&light, p.sun_edge_rays), &cam, (w, h), &rest)?;
    for (k, v) in &lod_figures {
        println!("{k}={v}");
    }
    if args.reference_paths > 0 {
        let verts = subset(scene.vertex_count(), args.reference_vertices);
        let rp = ReferenceParams {
            paths: args.reference_paths,
            sun_diameter_deg: p.sun_diameter,
            ..ReferenceParams::default()
        };
        let t = Instant::now();
        let reference_out = reference(&scene, &rest, light.sun, cam.position, &verts, &rp);
        let reference_rad = &reference_out.radiance;
        println!("reference_s={:.3}", t.elapsed().as_secs_f64());
        println!("reference_vertices={}", verts.len());
        println!("reference_noise_rel_l2={:.4}", reference_out.noise());
        let pick = |r: &[TwoSided]| verts.iter().map(|&v| r[v]).collect::<Vec<_>>();
        println!("rel_l2_lvc_prt={:.4}", rel_l2(&pick(&lvc_rad), reference_rad));
        println!("rel_l2_sh_only={:.4}", rel_l2(&pick(&sh_rad), reference_rad));
        for (o, obj) in scene.objects().iter().enumerate() {
            let range = scene.vertex_range(o);
            let k: Vec<usize> = (0..verts.len()).filter(|&i| range.contains(&verts[i])).collect();
            let (a, b, r) = (
                k.iter().map(|&i| lvc_rad[verts[i]]).collect::<Vec<_>>(),
                k.iter().map(|&i| sh_rad[verts[i]]).collect::<Vec<_>>(),
                k.iter().map(|&i| reference_rad[i]).collect::<Vec<_>>(),
            );
            println!("rel_l2_lvc_prt_{}={:.4}", obj.name, rel_l2(&a, &r));
            println!("rel_l2_sh_only_{}={:.4}", obj.name, rel_l2(&b, &r));
        }
        if args.breakdown {
            let parts = breakdown(&scene, &pre.data, (&light, &rest), cam.position, (&verts, reference_rad), &rp)?;
            for part in parts {
                println!("breakdown_{}_rel_l2={:.4}", part.name, part.rel_l2);
                println!("breakdown_{}_share_of_whole={:.4}", part.name, part.share_of_whole);
                println!("breakdown_{}_weight={:.4}", part.name, part.weight);
            }
        }
        if verts.len() == scene.vertex_count() {
            let img = to_image(render(&scene, reference_rad, &cam, w, h, Some(&rest)));
            println!("png_reference={}", write("leaves-reference.png", &img)?.display());
        }
    }
    Ok(())
}

/// Levels of detail: per level, triangles, vertices and shade time at the frame's camera; then,
/// from four times farther (where leaves are a few pixels across), the automatic per-leaf choice
/// against the full meshes: levels used, shade time, and the image difference. key=value pairs.
fn lod_report(
    scene: &LeafScene,
    data: &LeafData,
    (light, edge_rays): (&Lighting, u32),
    cam: &Camera,
    (w, h): (u32, u32),
    background: &EnvMap,
) -> Result<Vec<(String, String)>> {
    let t = Instant::now();
    let lod = Lod::build(scene, &data.transfer, &LodParams::default());
    let mut out = vec![("lod_build_s".to_string(), format!("{:.3}", t.elapsed().as_secs_f64()))];
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(scene, &data.lvc, light)?;
    let mut rad = Vec::new();
    let timed = |sel: &vcut_leaf::lod::Selection, eye: Vec3, rad: &mut Vec<TwoSided>| {
        let mut times = Vec::new();
        for _ in 0..5 {
            let t = Instant::now();
            shader.shade_lod(scene, data, sel, light, SunMethod::Lvc, eye, rad);
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
        median(times)
    };
    for k in 0..lod.level_count() {
        let sel = lod.select(scene, &data.transfer, cam.position, cam.fov_y_deg, h, Some(k));
        out.push((format!("lod_{k}_leaf_triangles"), lod.triangles_at(k).to_string()));
        out.push((format!("lod_{k}_vertices_shaded"), sel.vertices.len().to_string()));
        out.push((format!("lod_{k}_shade_ms"), format!("{:.3}", timed(&sel, cam.position, &mut rad))));
    }
    // From farther away, each leaf at the level its size asks for against every leaf in full:
    // images rendered at 2 × 2 samples per pixel and box-filtered, so silhouettes compare as a
    // display would show them.
    for dist in [2.0f32, 4.0, 8.0] {
        let far = Camera { position: cam.target + (cam.position - cam.target) * dist, ..cam.clone() };
        let mut images = Vec::new();
        for force in [Some(0), None] {
            let sel = lod.select(scene, &data.transfer, far.position, far.fov_y_deg, h, force);
            let ms = timed(&sel, far.position, &mut rad);
            let mut full_rad = vec![[Vec3::ZERO; 2]; scene.vertex_count()];
            for (i, &v) in sel.vertices.iter().enumerate() {
                full_rad[v as usize] = rad[i];
            }
            let big = render_triangles(scene, &sel.triangles, &full_rad, &far, (2 * w, 2 * h), Some(background));
            images.push(downsample(&big));
            let name = if force.is_some() { "full" } else { "auto" };
            out.push((format!("lod_x{dist}_{name}_shade_ms"), format!("{ms:.3}")));
            out.push((format!("lod_x{dist}_{name}_vertices_shaded"), sel.vertices.len().to_string()));
            if force.is_none() {
                out.push((format!("lod_x{dist}_auto_leaves_per_level"), format!("{:?}", sel.leaves_per_level)));
            }
        }
        let (rel, _) = pixel_errors(&images[1], &images[0]);
        out.push((format!("lod_x{dist}_pixel_rel_l2_vs_full"), format!("{rel:.4}")));
    }
    Ok(out)
}

/// Per-frame costs.
pub struct FrameFigures {
    /// Median time to decode one sun direction's map.
    pub decode_ms: f64,
    /// Median time to shade every vertex (both passes, both sides).
    pub shade_ms: f64,
    /// Median time of a sun move's preparation: the maps around the sun decoded and blended
    /// ([`Shader::prepare`]).
    pub sun_change_ms: f64,
}

/// Medians over `runs` frames seen from `eye`: decoding the map of the lighting's sun, making the
/// sun's map (its neighbours blended, `edge_rays` rays per shadow-edge vertex), and shading.
pub fn frame_figures(
    scene: &LeafScene,
    pre: &Precomputed,
    light: &Lighting,
    (eye, edge_rays): (Vec3, u32),
    runs: usize,
) -> Result<FrameFigures> {
    let mut decode = Vec::new();
    let sun = light.sun.context("no sun")?;
    let mut buf = vec![0u8; scene.vertex_count()];
    let j = pre.data.lvc.sun_index(sun.dir);
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        pre.data.lvc.decode(j, &mut buf)?;
        decode.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut change = Vec::new();
    for _ in 0..runs.max(1) {
        let t = Instant::now();
        Shader::with_edge_rays(edge_rays).prepare(scene, &pre.data.lvc, light)?;
        change.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let mut shader = Shader::with_edge_rays(edge_rays);
    shader.prepare(scene, &pre.data.lvc, light)?;
    let mut out = Vec::new();
    let mut shade = Vec::new();
    for _ in 0..runs.max(1) + 1 {
        let t = Instant::now();
        shader.shade(scene, &pre.data, light, SunMethod::Lvc, eye, &mut out);
        shade.push(t.elapsed().as_secs_f64() * 1e3);
    }
    shade.remove(0);
    Ok(FrameFigures { decode_ms: median(decode), shade_ms: median(shade), sun_change_ms: median(change) })
}
