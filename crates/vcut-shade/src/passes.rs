//! Image passes for compositing: what each pixel shows, taken apart — the diffuse albedo, the
//! shading normal, the depth, and the radiance's diffuse and specular shares (whose sum is the
//! image, [`crate::Parts`]) — written with the image and its alpha (coverage) as one OpenEXR
//! file.
//!
//! Each pass is the rasteriser's perspective-correct interpolation of a per-vertex value over
//! the same triangles and depth test as the image: `albedo` the object's k_d, times its
//! base-colour texture at the pixel's interpolated coordinates ([`crate::image::albedo_image`],
//! as the image takes it); `normal` the
//! world-space vertex normal, renormalised per pixel; `depth` the distance along the camera's
//! view axis in scene units (linear, exact under perspective-correct interpolation; 10¹⁰ where
//! nothing is drawn, as Blender's Z pass); `diffuse` that albedo · [`crate::Parts::diffuse`];
//! `specular` [`crate::Parts::specular`]. Background pixels are 0 in every other pass.
//!
//! Channels follow OpenEXR's layer convention: `R G B A` for the image (its RGB straight, not
//! premultiplied: the background shows the map where alpha is 0, as Mitsuba 3 writes it), then
//! `albedo.{R,G,B}`, `normal.{X,Y,Z}`, `depth.Z`, `diffuse.{R,G,B}`, `specular.{R,G,B}`.

use crate::frame::{Frame, Parts};
use crate::image::{Image, ImageError, rasterize};
use glam::Vec3;
use std::path::Path;
use vcut_scene::Camera;

/// Depth where no geometry is drawn.
pub const BACKGROUND_DEPTH: f32 = 1.0e10;

/// One image pass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    /// Diffuse albedo (k_d, times the base-colour texture).
    Albedo,
    /// World-space shading normal.
    Normal,
    /// Distance along the view axis.
    Depth,
    /// The diffuse share of the radiance.
    Diffuse,
    /// The specular share of the radiance.
    Specular,
}

impl Pass {
    /// Every pass, in the order they are listed.
    pub const ALL: [Pass; 5] = [Pass::Albedo, Pass::Normal, Pass::Depth, Pass::Diffuse, Pass::Specular];

    /// Its name (the EXR layer's and the command line's).
    pub fn name(self) -> &'static str {
        match self {
            Pass::Albedo => "albedo",
            Pass::Normal => "normal",
            Pass::Depth => "depth",
            Pass::Diffuse => "diffuse",
            Pass::Specular => "specular",
        }
    }

    /// Its channels' names within its layer.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            Pass::Normal => &["X", "Y", "Z"],
            Pass::Depth => &["Z"],
            _ => &["R", "G", "B"],
        }
    }

    /// Reads a comma-separated list (`albedo,normal`, or `all`); an unknown name is an error
    /// listing the known ones.
    pub fn parse_list(list: &str) -> Result<Vec<Pass>, String> {
        if list.trim() == "all" {
            return Ok(Pass::ALL.to_vec());
        }
        let mut out = Vec::new();
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let pass = Pass::ALL.into_iter().find(|p| p.name() == name).ok_or_else(|| {
                let known: Vec<&str> = Pass::ALL.iter().map(|p| p.name()).collect();
                format!("unknown pass '{name}' (passes: {}, or all)", known.join(", "))
            })?;
            if !out.contains(&pass) {
                out.push(pass);
            }
        }
        Ok(out)
    }
}

/// Rasterises `passes` of `frame` shaded as `parts` (from [`Frame::shade_parts`]) for `camera`,
/// each at `width × height` as the image is: one value per pixel (depth in `x`).
pub fn render_passes(
    frame: &Frame,
    parts: &[Vec<Parts>],
    camera: &Camera,
    width: u32,
    height: u32,
    passes: &[Pass],
) -> Vec<(Pass, Image)> {
    let forward = (camera.target - camera.position).normalize_or_zero();
    let albedo = passes
        .iter()
        .any(|p| matches!(p, Pass::Albedo | Pass::Diffuse))
        .then(|| crate::image::albedo_image(frame, camera, width, height));
    passes
        .iter()
        .map(|&pass| {
            let draw = |per_vertex: Vec<Vec<Vec3>>| rasterize(frame, &per_vertex, camera, width, height, None);
            let mut image = match pass {
                Pass::Albedo => albedo.clone().expect("drawn for this pass"),
                Pass::Normal => {
                    draw((0..frame.object_count()).map(|o| frame.object(o).mesh.normals().to_vec()).collect())
                }
                Pass::Depth => draw(
                    (0..frame.object_count())
                        .map(|o| {
                            let depth = |p: &Vec3| Vec3::splat((*p - camera.position).dot(forward));
                            frame.object(o).positions().iter().map(depth).collect()
                        })
                        .collect(),
                ),
                Pass::Diffuse => {
                    let mut image = draw(parts.iter().map(|p| p.iter().map(|x| x.diffuse).collect()).collect());
                    let albedo = albedo.as_ref().expect("drawn for this pass");
                    image.rgb.iter_mut().zip(&albedo.rgb).for_each(|(c, a)| *c *= *a);
                    image
                }
                Pass::Specular => draw(parts.iter().map(|p| p.iter().map(|x| x.specular).collect()).collect()),
            };
            for (c, &covered) in image.rgb.iter_mut().zip(&image.covered) {
                match pass {
                    Pass::Normal => *c = c.normalize_or_zero(),
                    Pass::Depth if !covered => *c = Vec3::splat(BACKGROUND_DEPTH),
                    _ => {}
                }
            }
            (pass, image)
        })
        .collect()
}

/// Writes `image` with its alpha (coverage) and `passes` as one OpenEXR file, atomically.
pub fn write_exr_passes(image: &Image, passes: &[(Pass, Image)], path: &Path) -> Result<(), ImageError> {
    let channel = |img: &Image, c: usize| img.rgb.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let mut channels: Vec<(String, Vec<f32>)> =
        ["R", "G", "B"].iter().enumerate().map(|(c, n)| (n.to_string(), channel(image, c))).collect();
    channels.push(("A".into(), image.covered.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect()));
    for (pass, img) in passes {
        for (c, n) in pass.channels().iter().enumerate() {
            channels.push((format!("{}.{n}", pass.name()), channel(img, c)));
        }
    }
    vcut_envmap::io::write_exr_channels(path, image.width, image.height, channels)
        .map_err(|e| ImageError::Write { path: path.into(), reason: e.to_string() })
}
