//! What the viewer shows, apart from any window: the frame (merged cuts, materials, lighting),
//! the camera, the display mode, the progressive exact reference, and the cost of every edit.
//! Every edit a person makes in the window is a method here, so tests drive the same code.

use crate::camera::OrbitCamera;
use crate::shown::{ShownLight, ShownObject, light_of, objects_of};
use glam::Vec3;
use rayon::prelude::*;
use std::sync::MutexGuard;
use std::time::{Duration, Instant};
use vcut_envmap::EnvMap;
use vcut_scene::{Material, Motion};
use vcut_shade::reference::ExactReference;
use vcut_shade::{BackgroundFrame, FlatEdges, Frame, FrameSettings};

mod moves;
pub use moves::Polled;

/// What the image shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Shading from the merged visibility cuts (the interactive path).
    Cuts,
    /// The exact-direction reference (every leaf direction cast), computed progressively;
    /// vertices not reached yet show the cuts' value.
    Exact,
    /// Per-vertex relative difference between the cuts and the reference as a heat map.
    Difference,
    /// Screen-space ambient occlusion (no precomputation; WGSL passes, `vcut_view::ssdo`).
    Ssao,
    /// Screen-space directional occlusion with one indirect bounce (no precomputation).
    Ssdo,
}

impl Mode {
    /// Every mode, in menu order.
    pub const ALL: [Mode; 5] = [Mode::Cuts, Mode::Exact, Mode::Difference, Mode::Ssao, Mode::Ssdo];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            Mode::Cuts => "precomputed cuts",
            Mode::Exact => "exact reference",
            Mode::Difference => "difference (heat map)",
            Mode::Ssao => "SSAO (screen space)",
            Mode::Ssdo => "SSDO + bounce (screen space)",
        }
    }

    /// Whether the mode can be chosen.
    pub fn available(self) -> bool {
        true
    }

    /// Whether the image is computed per pixel in screen space (no cuts involved).
    pub fn screen_space(self) -> bool {
        matches!(self, Mode::Ssao | Mode::Ssdo)
    }
}

/// How vertex colours are to be displayed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Display {
    /// Linear radiance: exposure, tone mapping, sRGB.
    Radiance,
    /// Display colours already (the heat map): sRGB-encoded values shown as they are.
    Colour,
}

/// The heat map's scale: relative errors at or above this show as the hottest colour.
pub const HEAT_MAX: f32 = 0.2;

/// The heat map colour (sRGB, 0..1) of a relative error `e` (0 black-blue … `HEAT_MAX` red).
pub fn heat(e: f32) -> Vec3 {
    const STOPS: [[f32; 3]; 5] =
        [[0.05, 0.05, 0.25], [0.1, 0.35, 0.85], [0.1, 0.8, 0.6], [0.95, 0.85, 0.1], [0.9, 0.1, 0.1]];
    let x = if e.is_finite() { (e / HEAT_MAX).clamp(0.0, 1.0) } else { 1.0 } * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    Vec3::from(STOPS[i]).lerp(Vec3::from(STOPS[i + 1]), f)
}

/// The cost of the last edits, in milliseconds.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Timings {
    /// Last object move: re-merge of the vertices whose field inputs changed (on the frame's
    /// worker thread).
    pub merge_ms: f64,
    /// Vertices re-merged by the last move.
    pub merged_vertices: usize,
    /// The last drag's settle: its dragged vertices merged again in full.
    pub settle_ms: f64,
    /// Vertices the last camera turn merged: those a move left facing away
    /// (`FrameSettings::deferred_merges`).
    pub turn_merged: usize,

    /// Last shading pass (all vertices toward the eye).
    pub shade_ms: f64,
    /// How long the last shading to arrive took after the move it follows was asked for: the
    /// time the image's shading lagged its geometry.
    pub shading_lag_ms: f64,
    /// Last light-tree rebuild (environment change or rotation).
    pub light_ms: f64,
    /// Last upload of vertex data to the GPU (set by the renderer's caller).
    pub upload_ms: f64,
    /// Last GPU frame, encode to present (set by the renderer's caller).
    pub draw_ms: f64,
}

/// The exact reference, filled in a few vertices at a time.
struct Progressive {
    exact: ExactReference,
    eye: Vec3,
    values: Vec<Vec<Option<Vec3>>>,
    /// Next (object, vertex) to compute.
    cursor: (usize, usize),
    done: usize,
    total: usize,
}

/// Why a session refused an edit.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// A display mode this build or data cannot show.
    #[error("{0} is not available")]
    Unavailable(&'static str),
    /// No such object.
    #[error("no object {0}")]
    NoObject(usize),
    /// A static object (precomputed without a visibility field) cannot move.
    #[error("'{0}' is static: it was precomputed without a visibility field")]
    Static(String),
    /// A translation with a NaN or infinite component.
    #[error("translation {0:?} is not finite")]
    NotFinite([f32; 3]),
    /// A yaw that is NaN or infinite.
    #[error("yaw {0} is not finite")]
    NotFiniteYaw(f32),
    /// The frame failed to re-merge.
    #[error(transparent)]
    Frame(#[from] vcut_shade::FrameError),
}

/// Everything the viewer shows.
///
/// The frame lives with a worker thread ([`BackgroundFrame`]). The `post_*` methods and
/// [`Session::update_later`] hand it work and return at once; [`Session::poll`] takes in what
/// it finished. The other edits, and [`Session::frame`], wait for it first. Drawing and picking
/// read the session's own copy of the objects ([`Session::objects`]), never the frame, so a
/// window stays live whatever a merge costs.
pub struct Session {
    frame: BackgroundFrame,
    objects: Vec<ShownObject>,
    light: ShownLight,
    settings: FrameSettings,
    env: EnvMap,
    env_name: String,
    env_rotation_deg: f32,
    env_version: u64,
    /// Display exposure (a factor before tone mapping); `None`: automatic.
    pub exposure: Option<f32>,
    /// The camera.
    pub camera: OrbitCamera,
    mode: Mode,
    origin_offset: f32,
    radiance: Vec<Vec<Vec3>>,
    parts: Vec<Vec<vcut_shade::Parts>>,
    shaded_eye: Option<Vec3>,
    /// The eye the worker was last asked to shade toward (`None`: a shading is owed).
    requested_eye: Option<Vec3>,
    /// The last move taken in, and when it was posted: the shading after it lags by the time
    /// since.
    last_move: Option<(u64, Instant)>,
    auto_exposure: f32,
    reference: Option<Progressive>,
    screen: Option<(Vec<vcut_ssdo::Object>, vcut_ssdo::Lighting)>,
    geometry_version: u64,
    colour_version: u64,
    /// The wedges of the frame's direction set when it is symmetric about +Y.
    wedges: Option<u32>,
    /// The cost of the last edits.
    pub timings: Timings,
    /// The selected object.
    pub selected: Option<usize>,
    /// Why the last camera turn could not merge what a move left facing away (those vertices
    /// shade black until a merge succeeds).
    pub turn_error: Option<String>,
    /// Why a posted move failed (the object stays where the frame had it).
    pub move_error: Option<SessionError>,
    /// The last refinement slice taken in since the last move ([`Session::refine_when_idle`]):
    /// how far the frame's refinement is (`None`: none since).
    pub refined: Option<vcut_shade::RefineStats>,
    /// The ticket of the last job posted that is not a refinement: a refinement posted before
    /// it no longer says how far the frame is.
    last_change: u64,
}

impl Session {
    /// A session on `frame` (built from data whose SVC rays started `origin_offset` off the
    /// surface, as `Precomputed::svc_origin_offset`), lit by `env` called `env_name`.
    pub fn new(frame: Frame, env: EnvMap, env_name: &str, origin_offset: f32, camera: OrbitCamera) -> Session {
        let selected = (0..frame.object_count()).find(|&o| frame.object(o).motion == Motion::Movable);
        let (objects, light, settings) = (objects_of(&frame), light_of(&frame), frame.settings().clone());
        let wedges = frame.turn_shape().map(|s| s.wedges() as u32);
        let mut s = Session {
            frame: BackgroundFrame::new(frame),
            objects,
            light,
            settings,
            env_rotation_deg: 0.0,
            env,
            env_name: env_name.into(),
            env_version: 0,
            exposure: None,
            camera,
            mode: Mode::Cuts,
            origin_offset,
            radiance: Vec::new(),
            parts: Vec::new(),
            shaded_eye: None,
            requested_eye: None,
            last_move: None,
            auto_exposure: 1.0,
            reference: None,
            screen: None,
            geometry_version: 0,
            colour_version: 0,
            wedges,
            timings: Timings::default(),
            selected,
            turn_error: None,
            move_error: None,
            refined: None,
            last_change: 0,
        };
        s.update();
        s
    }

    /// The frame (merged cuts, materials, lighting), once the moves posted are done (waits
    /// for them). The guard locks the frame: drop it before any other call that reads or
    /// changes the frame (a second `frame()` while one is held waits forever).
    pub fn frame(&self) -> MutexGuard<'_, Frame> {
        self.frame.frame()
    }

    /// Every object as drawn: its mesh, name, material, and where the last move asked for put
    /// it (the frame's cuts follow when the worker is done: [`ShownObject::placed`]).
    pub fn objects(&self) -> &[ShownObject] {
        &self.objects
    }

    /// The lighting facts the panel shows.
    pub fn light(&self) -> &ShownLight {
        &self.light
    }

    /// Whether the frame's worker has moves or a shading to finish.
    pub fn busy(&self) -> bool {
        self.frame.busy()
    }

    /// What the frame's worker has done (jobs posted, dropped as stale, run).
    pub fn background(&self) -> vcut_shade::BackgroundStats {
        self.frame.stats()
    }

    /// How far the shading lags the geometry now: the largest distance between where an
    /// object is drawn and where the shown shading has it.
    pub fn shading_behind(&self) -> f32 {
        self.objects.iter().map(|o| o.translation.distance(o.placed)).fold(0.0, f32::max)
    }

    /// The SVC rays' origin offset the exact reference uses (fraction of each object's radius).
    pub fn origin_offset(&self) -> f32 {
        self.origin_offset
    }

    /// The environment as lit and drawn (rotation and intensity applied).
    pub fn env(&self) -> &EnvMap {
        &self.env
    }

    /// The environment's name.
    pub fn env_name(&self) -> &str {
        &self.env_name
    }

    /// Changes whenever the environment's texels change (a new map), not on rotation.
    pub fn env_version(&self) -> u64 {
        self.env_version
    }

    /// Changes whenever any vertex position changes.
    pub fn geometry_version(&self) -> u64 {
        self.geometry_version
    }

    /// Changes whenever any displayed vertex colour may have changed.
    pub fn colour_version(&self) -> u64 {
        self.colour_version
    }

    /// The environment's rotation about +Y, degrees.
    pub fn env_rotation_deg(&self) -> f32 {
        self.env_rotation_deg
    }

    /// The display mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Chooses the display mode (an unavailable one is refused).
    pub fn set_mode(&mut self, mode: Mode) -> Result<(), SessionError> {
        if !mode.available() {
            return Err(SessionError::Unavailable(mode.label()));
        }
        if mode != self.mode {
            self.mode = mode;
            self.colour_version += 1;
        }
        Ok(())
    }

    /// The exposure in use (the set one, or automatic: the log-average luminance of the
    /// covered pixels of the cuts' shading to middle grey 0.18, as `vcut_shade::image::auto_exposure`,
    /// measured on a 160 × 90 raster).
    pub fn exposure_in_use(&self) -> f32 {
        self.exposure.unwrap_or(self.auto_exposure)
    }

    fn invalidate_shading(&mut self) {
        self.requested_eye = None;
        self.reference = None;
        self.screen = None;
        self.colour_version += 1;
    }

    /// Changes object `o`'s BRDF (shading only, no merge).
    pub fn set_material(&mut self, o: usize, material: Material) {
        if self.objects.get(o).is_some_and(|x| x.material != material) {
            let mut frame = self.frame.frame();
            frame.set_material(o, material);
            (self.objects[o].material, self.objects[o].albedo) = (material, frame.object(o).mean_albedo());
            drop(frame);
            self.invalidate_shading();
            self.update();
        }
    }

    /// Switches to a new environment map `env` called `name` (its rotation is kept).
    pub fn set_environment(&mut self, name: &str, mut env: EnvMap) {
        env.set_rotation_y_degrees(self.env_rotation_deg);
        self.env = env;
        self.env_name = name.into();
        self.env_version += 1;
        self.relight();
    }

    /// Rotates the environment about +Y (rebuilds the light tree, no merge).
    pub fn set_env_rotation(&mut self, degrees: f32) {
        if degrees.is_finite() && degrees != self.env_rotation_deg {
            self.env_rotation_deg = degrees;
            self.env.set_rotation_y_degrees(degrees);
            self.relight();
        }
    }

    /// The frame's settings ([`vcut_shade::FrameSettings`]).
    pub fn settings(&self) -> &FrameSettings {
        &self.settings
    }

    /// Changes the frame's settings (`Frame::reconfigure`: it merges only what they change) and
    /// re-shades; the time goes to `timings.light_ms` (a settings change is not a move).
    pub fn reconfigure(&mut self, settings: &FrameSettings) -> Result<(), SessionError> {
        if *settings == self.settings {
            return Ok(());
        }
        let mut frame = self.frame.frame();
        let start = Instant::now();
        let done = frame.reconfigure(settings);
        self.timings.light_ms = start.elapsed().as_secs_f64() * 1e3;
        (self.settings, self.light) = (frame.settings().clone(), light_of(&frame));
        drop(frame);
        done?;
        self.invalidate_shading();
        self.update();
        Ok(())
    }

    /// Whether the sun's leaves are cast by rays (see `vcut_shade::sun`).
    pub fn sun_rays(&self) -> bool {
        self.settings.sun_rays
    }

    /// Casts the light's brightest leaves by rays at run time (`on`, the frame's default) or
    /// carries all light through the cuts, as the paper (no merge either way).
    pub fn set_sun_rays(&mut self, on: bool) -> Result<(), SessionError> {
        self.reconfigure(&FrameSettings { sun_rays: on, ..self.settings().clone() })
    }

    /// How finely a ground's shadow follows its edges ([`FlatEdges`]: 1, the default, exact;
    /// `interactive` the setting measured for drags). Re-merges the vertices a ground shadows
    /// (not counted as a move's timing).
    pub fn set_flat_edge_leaves(&mut self, edges: FlatEdges) -> Result<(), SessionError> {
        self.reconfigure(&FrameSettings { flat_edge_leaves: edges, ..self.settings().clone() })
    }

    /// The target error of the light left in the cuts (`vcut_shade::SunRays::target`).
    pub fn light_error(&self) -> f64 {
        self.light.target
    }

    /// Sets the target error of the light left in the cuts and, with sun rays on, chooses and
    /// casts the leaves again (no merge). A value outside (0, 1) is an error naming it.
    pub fn set_light_error(&mut self, target: f64) -> Result<(), SessionError> {
        self.reconfigure(&FrameSettings { light_error: Some(target), ..self.settings().clone() })
    }

    fn relight(&mut self) {
        let mut frame = self.frame.frame();
        let start = Instant::now();
        frame.set_environment(&self.env);
        self.timings.light_ms = start.elapsed().as_secs_f64() * 1e3;
        self.light = light_of(&frame);
        drop(frame);
        self.invalidate_shading();
        self.update();
    }

    /// Re-shades if the camera moved or anything was edited since the last shading, and waits
    /// for it (and for every move posted before).
    pub fn update(&mut self) {
        self.wait();
    }

    /// Asks the frame's worker to re-shade if the camera moved or anything was edited since
    /// the last shading (building the lists of the vertices now facing the camera: a move
    /// built only those facing the last one), and returns at once; [`Session::poll`] takes the
    /// shading in.
    pub fn update_later(&mut self) {
        let eye = self.camera.eye();
        if self.requested_eye != Some(eye) {
            self.frame.set_eye(eye);
            self.requested_eye = Some(eye);
        }
    }

    /// Per-vertex radiance from the cuts (as of the last shading taken in).
    pub fn radiance(&self) -> &[Vec<Vec3>] {
        &self.radiance
    }

    /// Per-vertex shading from the cuts in its two parts (as of the last shading taken in):
    /// what [`Session::radiance`] is made of, for a per-pixel albedo.
    pub fn parts(&self) -> &[Vec<vcut_shade::Parts>] {
        &self.parts
    }

    /// Share of vertices the exact reference has reached (1 when complete; 0 before it starts).
    pub fn reference_progress(&self) -> f64 {
        self.reference.as_ref().map_or(0.0, |r| r.done as f64 / r.total.max(1) as f64)
    }

    /// Advances the exact reference for about `budget` (only in the modes that show it).
    /// Returns whether there is more to do; while the frame's worker has moves or a shading to
    /// finish it does nothing and returns `true` at once ([`Session::update`] waits for them).
    pub fn step_reference(&mut self, budget: Duration) -> bool {
        if !matches!(self.mode, Mode::Exact | Mode::Difference) {
            return false;
        }
        self.update_later();
        self.poll();
        // Not while the worker has the frame: a move or shading is on its way.
        let Some(frame) = self.frame.try_frame() else { return true };
        let eye = self.camera.eye();
        if self.reference.as_ref().is_none_or(|r| r.eye != eye) {
            let values: Vec<Vec<Option<Vec3>>> = self.radiance.iter().map(|r| vec![None; r.len()]).collect();
            let total = values.iter().map(Vec::len).sum();
            self.reference = Some(Progressive {
                exact: ExactReference::new(&frame, self.origin_offset),
                eye,
                values,
                cursor: (0, 0),
                done: 0,
                total,
            });
        }
        let start = Instant::now();
        let frame = &*frame;
        let Some(r) = self.reference.as_mut() else { return false };
        let chunk = 64 * rayon::current_num_threads().max(1);
        while r.done < r.total && start.elapsed() < budget {
            let (o, v0) = r.cursor;
            if v0 >= r.values[o].len() {
                r.cursor = (o + 1, 0);
                continue;
            }
            let v1 = (v0 + chunk).min(r.values[o].len());
            let positions = frame.object(o).positions();
            let exact = &r.exact;
            let got: Vec<Vec3> =
                (v0..v1).into_par_iter().map(|v| exact.vertex(frame, o, v, positions[v], eye)).collect();
            for (v, b) in (v0..v1).zip(got) {
                r.values[o][v] = Some(b);
            }
            r.done += v1 - v0;
            r.cursor = (o, v1);
        }
        self.colour_version += 1;
        r.done < r.total
    }

    /// Relative L2 difference between the cuts and the reference over the vertices the
    /// reference has reached (`None` before any).
    pub fn reference_error(&self) -> Option<f64> {
        let r = self.reference.as_ref()?;
        let pairs = r
            .values
            .iter()
            .zip(&self.radiance)
            .flat_map(|(refs, got)| refs.iter().zip(got).filter_map(|(e, &g)| e.map(|e| (g, e))));
        let (mut num, mut den, mut n) = (0.0f64, 0.0f64, 0usize);
        for (g, e) in pairs {
            num += f64::from((g - e).length_squared());
            den += f64::from(e.length_squared());
            n += 1;
        }
        (n > 0).then(|| if den > 0.0 { (num / den).sqrt() } else { num.sqrt() })
    }

    /// How the current mode's colours are displayed.
    pub fn display(&self) -> Display {
        if self.mode == Mode::Difference { Display::Colour } else { Display::Radiance }
    }

    /// The vertex colours to draw and how to display them.
    pub fn colours(&self) -> (Vec<Vec<Vec3>>, Display) {
        match (self.mode, &self.reference) {
            (Mode::Exact, Some(r)) => {
                let c = r
                    .values
                    .iter()
                    .zip(&self.radiance)
                    .map(|(refs, got)| refs.iter().zip(got).map(|(e, &g)| e.unwrap_or(g)).collect())
                    .collect();
                (c, Display::Radiance)
            }
            (Mode::Difference, r) => {
                // Relative to the mean reference luminance, so dark regions do not dominate.
                let luminance = |c: Vec3| 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
                let (mut sum, mut n) = (0.0f64, 0usize);
                if let Some(r) = r {
                    for e in r.values.iter().flatten().flatten() {
                        sum += f64::from(luminance(*e));
                        n += 1;
                    }
                }
                let mean = if n > 0 { (sum / n as f64) as f32 } else { 0.0 };
                let c = self
                    .radiance
                    .iter()
                    .enumerate()
                    .map(|(o, got)| {
                        got.iter()
                            .enumerate()
                            .map(|(v, &g)| match r.as_ref().and_then(|r| r.values[o][v]) {
                                Some(e) if mean > 0.0 => heat(luminance((g - e).abs()) / mean),
                                Some(_) => heat(0.0),
                                None => Vec3::splat(0.35),
                            })
                            .collect()
                    })
                    .collect();
                (c, Display::Colour)
            }
            _ => (self.radiance.clone(), Display::Radiance),
        }
    }

    /// What the screen-space modes draw: every object at its position with its diffuse albedo,
    /// and their lighting (the sun split off and shadow-mapped, the rest pre-filtered); built
    /// on first use after any edit.
    pub fn screen_space_inputs(&mut self) -> (&[vcut_ssdo::Object], &vcut_ssdo::Lighting, vcut_ssdo::Params) {
        let shown = &self.objects;
        let env = &self.env;
        let (objects, light) = self.screen.get_or_insert_with(|| {
            let objects: Vec<vcut_ssdo::Object> =
                shown.iter().map(|o| vcut_ssdo::Object::from_mesh(&o.turned_mesh(), o.translation, o.albedo)).collect();
            let light = vcut_ssdo::Lighting::new(env, &objects, 16);
            (objects, light)
        });
        let b = vcut_scene::Bounds::of_points(objects.iter().flat_map(|o| o.positions.iter().copied()));
        (objects, light, vcut_ssdo::Params::for_scene(b.radius))
    }

    /// The object and distance hit first by the ray (`origin`, `dir`), at current positions.
    pub fn pick(&self, origin: Vec3, dir: Vec3) -> Option<(usize, f32)> {
        let placed: Vec<Vec<Vec3>> = self.objects.iter().map(ShownObject::positions).collect();
        let objects = self.objects.iter().zip(&placed).map(|(o, p)| (o.mesh.triangles(), p.as_slice()));
        vcut_rays::pick(objects, origin, dir)
    }
}

impl crate::render::Meshes for Session {
    fn versions(&self) -> [u64; 3] {
        [self.env_version, self.geometry_version, self.colour_version]
    }

    fn env(&self) -> &EnvMap {
        &self.env
    }

    fn triangles(&self) -> Vec<&[[u32; 3]]> {
        self.objects.iter().map(|o| o.mesh.triangles()).collect()
    }

    /// The cuts' own shading takes a textured object's albedo per pixel (its specular share
    /// added, its diffuse share times `kd` multiplied by the texture); the exact reference and
    /// the heat map are per vertex.
    fn vertices(&self) -> Vec<crate::render::ObjectVertices> {
        let (colours, _) = self.colours();
        let per_pixel = matches!(self.mode, Mode::Cuts) && self.parts.len() == colours.len();
        colours
            .into_iter()
            .enumerate()
            .map(|(o, colours)| {
                let object = &self.objects[o];
                let positions = object.positions();
                match (object.texture.as_ref(), object.mesh.uvs()) {
                    (Some(_), Some(uvs)) if per_pixel => {
                        let kd = Vec3::from(object.material.kd);
                        crate::render::ObjectVertices {
                            positions,
                            colours: self.parts[o].iter().map(|p| p.specular).collect(),
                            textured: self.parts[o].iter().map(|p| kd * p.diffuse).collect(),
                            uvs: uvs.to_vec(),
                        }
                    }
                    _ => crate::render::ObjectVertices { positions, colours, textured: Vec::new(), uvs: Vec::new() },
                }
            })
            .collect()
    }

    fn albedo_textures(&self) -> Vec<Option<&vcut_scene::texture::Texture>> {
        self.objects.iter().map(|o| o.texture.as_ref()).collect()
    }
}

impl Session {
    /// How its frame is shown in `viewport`: its environment, camera and exposure, its colours
    /// as radiance or (the difference mode) as they are.
    pub fn shown(&self, viewport: crate::render::Viewport) -> crate::render::Shown<'_> {
        crate::render::Shown {
            env: &self.env,
            camera: &self.camera,
            exposure: self.exposure_in_use(),
            radiance: self.display() == Display::Radiance,
            viewport,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heat_runs_from_cold_to_hot_and_saturates() {
        assert_eq!(heat(0.0), Vec3::new(0.05, 0.05, 0.25));
        assert_eq!(heat(HEAT_MAX), Vec3::new(0.9, 0.1, 0.1));
        assert_eq!(heat(10.0), heat(HEAT_MAX));
        assert_eq!(heat(f32::NAN), heat(HEAT_MAX));
        assert!(heat(HEAT_MAX * 0.5).y > 0.5, "the middle is bright: {}", heat(HEAT_MAX * 0.5));
    }
}
