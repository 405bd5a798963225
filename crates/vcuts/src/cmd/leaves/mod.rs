//! `vcuts leaves`: the plant-leaf renderer end to end — build (or load) a plant, precompute the
//! sun's light-visibility convolution and the SH transfer, shade a frame in two passes, and
//! compare it and the SH-only rendering with the path-traced reference; images and a typed
//! [`LeavesOutcome`]. `plant.rs`: the plant and its options (shared with `view --leaves` and
//! Python); `data.rs`: the leaf data's `.vleaf` file; `frame.rs`: per-frame costs and levels of
//! detail; `outcome.rs`: what it reports.

mod data;
mod frame;
mod outcome;
pub mod plant;

pub use crate::resources::EstimateArgs;
pub use data::{AgainstOutcome, LeafEstimateOutcome, Precomputed, Prepared, StoreOutcome, bar, data_path, precompute};
pub use frame::{FrameFigures, LodDistance, LodOutcome, frame_figures, lod_figures, subset, to_image};
pub use outcome::{DataOutcome, LeavesOutcome, PlantOutcome, ReferenceOutcome};
pub use plant::{PlantArgs, PlantSource, camera, lighting, material, params, scene, sun_angles};

use anyhow::{Context, Result};
use std::path::PathBuf;
use std::time::Instant;
use vcut_leaf::breakdown::breakdown;
use vcut_leaf::image::render;
use vcut_leaf::reference::{ReferenceParams, reference, rel_l2};
use vcut_leaf::shade::{Shader, SunMethod, TwoSided};
use vcut_leaf::store::{Inputs, Reuse};
use vcut_shade::image::{Image, auto_exposure, write_png};

/// Arguments of `vcuts leaves`.
#[derive(clap::Args, Clone)]
pub struct LeavesArgs {
    /// The plant, leaves and sun.
    #[command(flatten)]
    pub plant: PlantArgs,
    /// Environment: builtin:sky (default), builtin:studio or a map file; its sun is split off.
    #[arg(long, default_value = "builtin:sky")]
    pub env: String,
    /// Paths per vertex side of the reference (0: no reference).
    #[arg(long, default_value_t = 1024, value_parser = crate::options::whole::<u32>("reference-paths"), allow_hyphen_values = true)]
    pub reference_paths: u32,
    /// At most this many vertices get a reference (a spread subset; all of a small scene).
    #[arg(long, default_value_t = 6500, value_parser = crate::options::whole::<u64>("reference-vertices"), allow_hyphen_values = true)]
    pub reference_vertices: u64,
    /// Also split the error by light path (the sun and the environment, each whole and
    /// unscattered, the sun on the maps' own direction) and by gloss (the environment and the
    /// sun with every leaf's gloss removed): eight more references.
    #[arg(long)]
    pub breakdown: bool,
    /// Image width in pixels (1 to 16,384).
    #[arg(long, default_value_t = 960, value_parser = crate::options::whole::<u32>("width"), conflicts_with = "size", allow_hyphen_values = true)]
    pub width: u32,
    /// Image height in pixels (1 to 16,384).
    #[arg(long, default_value_t = 720, value_parser = crate::options::whole::<u32>("height"), conflicts_with = "size", allow_hyphen_values = true)]
    pub height: u32,
    /// The image size as WIDTHxHEIGHT (as --width and --height; kept for earlier scripts).
    #[arg(long)]
    pub size: Option<crate::values::Size>,
    /// Output folder (images).
    #[arg(long, default_value = "target/leaves")]
    pub out: PathBuf,
}

impl LeavesArgs {
    /// The image size: `--size`, else `--width` and `--height`.
    pub fn size(&self) -> (u32, u32) {
        self.size.map_or((self.width, self.height), |s| (s.width, s.height))
    }
}

/// Runs `vcuts leaves`.
pub fn run(args: &LeavesArgs) -> Result<LeavesOutcome> {
    let (w, h) = args.size();
    crate::resources::check_image(w, h, crate::resources::ImageCost::Leaves)?;
    let p = &args.plant;
    let m = material(p)?;
    let t = Instant::now();
    let scene = scene(p, &m)?;
    let (light, rest) = lighting(p, &args.env)?;
    let sun = light.sun.context("the environment has no sun: the leaf renderer's direct pass needs one")?;
    let mut out = LeavesOutcome::new(PlantOutcome::of(p, &scene, &m, t.elapsed().as_secs_f64(), sun.dir));
    let (lvc_params, prt) = params(p);
    let inputs = Inputs { scene: &scene, lvc: lvc_params, prt, suns: None };
    let reuse = if p.fresh { Reuse::Never } else { Reuse::IfMatching };
    let pre = match precompute(&scene, (&lvc_params, &prt), None, &data_path(p, &inputs), reuse, p.estimate)? {
        Prepared::Ready(pre) => *pre,
        Prepared::DryRun(estimate) => {
            out.estimate = estimate;
            return Ok(out);
        }
    };
    out.data(&pre);
    let cam = camera(&scene);
    out.frame = Some(frame_figures(&scene, &pre, &light, (cam.position, p.sun_edge_rays), 5)?);
    let mut shader = Shader::with_edge_rays(p.sun_edge_rays);
    shader.prepare(&scene, &pre.data.lvc, &light)?;
    out.sun_edge_vertices = Some(shader.edge_vertices());
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
    out.png_lvc_prt = Some(write("leaves.png", &lvc_img)?);
    let sh_img = to_image(render(&scene, &sh_rad, &cam, w, h, Some(&rest)));
    out.png_sh_only = Some(write("leaves-sh-only.png", &sh_img)?);
    out.lod = Some(lod_figures(&scene, &pre.data, (&light, p.sun_edge_rays), &cam, (w, h), &rest)?);
    if args.reference_paths > 0 {
        let shaded = Shaded { scene: &scene, pre: &pre, light: &light, rest: &rest, cam: &cam, size: (w, h) };
        let (r, image) = compare(args, &shaded, (&lvc_rad, &sh_rad))?;
        out.png_reference = image.map(|img| write("leaves-reference.png", &img)).transpose()?;
        out.reference = Some(r);
    }
    Ok(out)
}

/// A plant as shaded for its images: what the reference compares.
struct Shaded<'a> {
    scene: &'a vcut_leaf::scene::LeafScene,
    pre: &'a Precomputed,
    light: &'a vcut_leaf::shade::Lighting,
    rest: &'a vcut_envmap::EnvMap,
    cam: &'a vcut_scene::Camera,
    size: (u32, u32),
}

/// The path-traced reference at a spread subset of the vertices against the two passes and the
/// SH alone, per object and (with `--breakdown`) per light path; its image when it covers every
/// vertex.
fn compare(
    args: &LeavesArgs,
    s: &Shaded<'_>,
    (lvc_rad, sh_rad): (&[TwoSided], &[TwoSided]),
) -> Result<(ReferenceOutcome, Option<Image>)> {
    let verts = subset(s.scene.vertex_count(), args.reference_vertices as usize);
    let rp = ReferenceParams {
        paths: args.reference_paths,
        sun_diameter_deg: args.plant.sun_diameter,
        ..Default::default()
    };
    let t = Instant::now();
    let reference_out = reference(s.scene, s.rest, s.light.sun, s.cam.position, &verts, &rp);
    let reference_rad = &reference_out.radiance;
    let mut r = ReferenceOutcome::new(t.elapsed().as_secs_f64(), verts.len(), reference_out.noise());
    let pick = |rad: &[TwoSided]| verts.iter().map(|&v| rad[v]).collect::<Vec<_>>();
    (r.rel_l2_lvc_prt, r.rel_l2_sh_only) =
        (rel_l2(&pick(lvc_rad), reference_rad), rel_l2(&pick(sh_rad), reference_rad));
    for (o, obj) in s.scene.objects().iter().enumerate() {
        let range = s.scene.vertex_range(o);
        let k: Vec<usize> = (0..verts.len()).filter(|&i| range.contains(&verts[i])).collect();
        let of = |rad: &[TwoSided]| k.iter().map(|&i| rad[verts[i]]).collect::<Vec<_>>();
        let refs: Vec<TwoSided> = k.iter().map(|&i| reference_rad[i]).collect();
        r.per_object.0.push((format!("rel_l2_lvc_prt_{}", obj.name), rel_l2(&of(lvc_rad), &refs)));
        r.per_object.0.push((format!("rel_l2_sh_only_{}", obj.name), rel_l2(&of(sh_rad), &refs)));
    }
    if args.breakdown {
        let parts = breakdown(s.scene, &s.pre.data, (s.light, s.rest), s.cam.position, (&verts, reference_rad), &rp)?;
        for part in parts {
            r.breakdown.0.push((format!("breakdown_{}_rel_l2", part.name), part.rel_l2));
            r.breakdown.0.push((format!("breakdown_{}_share_of_whole", part.name), part.share_of_whole));
            r.breakdown.0.push((format!("breakdown_{}_weight", part.name), part.weight));
        }
    }
    let (w, h) = s.size;
    let image = (verts.len() == s.scene.vertex_count())
        .then(|| to_image(render(s.scene, reference_rad, s.cam, w, h, Some(s.rest))));
    Ok((r, image))
}
