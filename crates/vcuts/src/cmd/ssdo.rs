//! The screen-space methods (`vcut-ssdo`) on a frame's geometry: `render --mode ssao|ssdo|
//! ssdo-peeled`, and the `ssdo` section of `bench`.

use std::time::Instant;

use vcut_envmap::EnvMap;
use vcut_scene::Camera;
use vcut_shade::Frame;
use vcut_shade::image::Image;
use vcut_ssdo::{GBuffer, Lighting, Method, Object, Output, Params, SampleSets, render};

/// A screen-space method: `render --mode` and the bench's `ssdo` section.
#[derive(clap::ValueEnum, Clone, Copy, PartialEq, Eq, Debug, PartialOrd, Ord)]
pub enum ScreenMode {
    /// Ambient occlusion (Ritschel et al.'s baseline).
    Ssao,
    /// Directional occlusion and one indirect bounce.
    Ssdo,
    /// SSDO with a second depth layer.
    SsdoPeeled,
}

impl ScreenMode {
    /// Every method, in the order reports list them.
    pub const ALL: [ScreenMode; 3] = [ScreenMode::Ssao, ScreenMode::Ssdo, ScreenMode::SsdoPeeled];

    /// Its name on the command line: `ssao`, `ssdo`, `ssdo-peeled`.
    pub fn name(self) -> &'static str {
        match self {
            ScreenMode::Ssao => "ssao",
            ScreenMode::Ssdo => "ssdo",
            ScreenMode::SsdoPeeled => "ssdo-peeled",
        }
    }

    /// Its name in report keys: `ssao`, `ssdo`, `ssdo_peeled`.
    pub fn key(self) -> &'static str {
        match self {
            ScreenMode::SsdoPeeled => "ssdo_peeled",
            other => other.name(),
        }
    }
}

/// Every object of `frame` at its current translation, with its diffuse albedo.
pub fn objects(frame: &Frame) -> Vec<Object> {
    (0..frame.object_count())
        .map(|o| {
            let vcut_shade::FrameObject { mesh, translation, .. } = frame.object(o);
            Object::from_mesh(mesh, translation, frame.object(o).mean_albedo())
        })
        .collect()
}

/// Default parameters for `objects` (r_max a tenth of the scene's bounding radius).
pub fn params(objects: &[Object]) -> Params {
    let b = vcut_scene::Bounds::of_points(objects.iter().flat_map(|o| o.positions.iter().copied()));
    Params::for_scene(b.radius)
}

/// One screen-space frame and what each step cost.
pub struct ScreenFrame {
    /// The image's terms.
    pub output: Output,
    /// The G-buffer it was computed from.
    pub gbuffer: GBuffer,
    /// Milliseconds: G-buffer, then the method's passes (samples, blur, bounce).
    pub gbuffer_ms: f64,
    /// Milliseconds of the passes.
    pub pass_ms: f64,
}

/// Renders `mode` of `objects` lit by `light`.
pub fn frame(
    objects: &[Object],
    light: &Lighting,
    camera: &Camera,
    (width, height): (u32, u32),
    mode: ScreenMode,
) -> ScreenFrame {
    let mut p = params(objects);
    p.peel = mode == ScreenMode::SsdoPeeled;
    let method = if mode == ScreenMode::Ssao { Method::Ssao } else { Method::Ssdo };
    let t = Instant::now();
    let gbuffer = GBuffer::new(objects, camera, width as usize, height as usize);
    let gbuffer_ms = t.elapsed().as_secs_f64() * 1e3;
    let sets = SampleSets::halton(p.samples, p.sets);
    let t = Instant::now();
    let output = render(&gbuffer, light, &sets, &p, method);
    let pass_ms = t.elapsed().as_secs_f64() * 1e3;
    ScreenFrame { output, gbuffer, gbuffer_ms, pass_ms }
}

/// The lighting of `objects` by `env` at the default sample count.
pub fn lighting(env: &EnvMap, objects: &[Object]) -> Lighting {
    Lighting::new(env, objects, params(objects).samples)
}

/// An output's total as an image.
pub fn image(o: &Output) -> Image {
    Image { width: o.width as u32, height: o.height as u32, rgb: o.total(), covered: o.covered.clone() }
}
