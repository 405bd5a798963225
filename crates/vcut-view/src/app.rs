//! The cut viewer's window (hosted by [`crate::host`]): the scene drawn by
//! [`crate::SceneRenderer`], an egui panel beside it.
//!
//! Mouse: left-drag on empty space orbits, right- or middle-drag pans, the wheel zooms;
//! left-drag on a movable object moves it over the horizontal plane through the grabbed point
//! (with Shift: vertically). The object follows the pointer at once; each mouse move posts a
//! [`vcut_shade::Frame::drag`] step to the frame's worker thread ([`Session::post_drag`]: a
//! step still queued is replaced, stale), the last shading shows until the new one arrives, and
//! the release posts the settle. The window thread never merges, so it never waits for one.

use crate::camera::{OrbitCamera, ray_plane};
use crate::gpu::ViewError;
use crate::host::{ViewportPoint, WindowApp};
use crate::render::Viewport;
use crate::report::{Quantiles, ScriptedDrag, WindowReport};
use crate::session::{Mode, Session};
use crate::window::WindowState;
use glam::Vec3;
use std::time::{Duration, Instant};
use vcut_envmap::EnvMap;
use vcut_scene::{BrdfModel, Material, Motion};
use vcut_ssdo::gpu::{GpuSsdo, SsdoFrame};

/// Loads an environment map by name (for the panel's environment menu).
pub type EnvLoader = Box<dyn Fn(&str) -> Result<EnvMap, String>>;

/// What the window shows besides the session.
pub struct ViewOptions {
    /// Window title.
    pub title: String,
    /// Lines about the data (file, preset, directions, size), shown in the panel.
    pub summary: Vec<(String, String)>,
    /// Environment maps to choose from (names given to `load_env`).
    pub envs: Vec<String>,
    /// Loads one of `envs`.
    pub load_env: EnvLoader,
    /// Close after this many frames (for scripted runs); `None`: until the window closes.
    pub max_frames: Option<u64>,
    /// A drag the window performs by itself, from its first frame (measurements).
    pub scripted_drag: Option<ScriptedDrag>,
    /// Refine the frame while nothing moves ([`Session::refine_when_idle`]).
    pub refine: bool,
}

/// A movable object being dragged: grabbed at `grab` (world), from translation `start`, over
/// the horizontal plane (or, `vertical`, a vertical one).
struct ObjectDrag {
    o: usize,
    grab: Vec3,
    start: Vec3,
    vertical: bool,
}

/// What a window run records for its [`WindowReport`].
#[derive(Default)]
struct Record {
    frames: u64,
    /// Frame times (ms) of the frames measured.
    frame_ms: Vec<f64>,
    /// The scripted drag's next step, and where its object started (`None` once released).
    script: Option<(u64, Vec3)>,
    drag_frames: u64,
    /// Encode-to-present times (ms) of the frames measured.
    draw_ms: Vec<f64>,
    merge_ms: Vec<f64>,
    lags: Vec<f64>,
}

/// What a screen-space frame was made from: the session's colour version and the viewport size.
type ScreenKey = (u64, (u32, u32));

struct App {
    session: Session,
    options: ViewOptions,
    /// The screen-space passes, compiled on first use.
    ssdo: Option<GpuSsdo>,
    /// The last screen-space frame and what it was made from (the session's colour version and
    /// the viewport size): redrawn only when either changes.
    screen: Option<(ScreenKey, SsdoFrame)>,
    drag: Option<ObjectDrag>,
    /// What the panel asked for this frame.
    actions: PanelActions,
    /// Last screen-space frame (lighting set-up + passes), ms.
    screen_ms: f64,
    record: Record,
}

/// Opens the window and runs until it is closed; returns what it measured.
pub fn run_window(session: Session, options: ViewOptions) -> Result<WindowReport, ViewError> {
    let script = options.scripted_drag.map(|d| (0, session.objects()[d.object].translation));
    let app = App {
        session,
        options,
        ssdo: None,
        screen: None,
        drag: None,
        actions: PanelActions::default(),
        screen_ms: 0.0,
        record: Record { script, ..Record::default() },
    };
    let app = crate::host::run(app)?;
    Ok(app.report())
}

impl App {
    /// A step of the mouse's drag of object `o` to `t`, posted ([`Session::post_drag`]).
    fn apply_move(&mut self, o: usize, t: Vec3, status: &mut String) {
        if let Err(e) = self.session.post_drag(o, t) {
            *status = e.to_string();
        }
    }

    /// The scripted drag's step for this frame, or its release after the last.
    fn script_step(&mut self, status: &mut String) {
        let (Some(d), Some((i, start))) = (self.options.scripted_drag, self.record.script) else { return };
        if self.record.frames < 2 {
            // Past the window's set-up frames first (`App::measured`).
            return;
        }
        if i < d.steps {
            self.apply_move(d.object, d.at(start, i + 1), status);
            self.record.script = Some((i + 1, start));
            self.record.drag_frames += 1;
        } else {
            self.session.post_settle();
            self.record.script = None;
        }
    }

    /// Takes in what the frame's worker finished, says it on the status line and records it.
    fn take_in(&mut self, status: &mut String) {
        let polled = self.session.poll();
        let tm = self.session.timings;
        if polled.moves > 0 {
            self.record.merge_ms.push(tm.merge_ms);
            *status = format!("moved: {} vertices re-merged in {:.1} ms", tm.merged_vertices, tm.merge_ms);
        }
        self.record.lags.extend(polled.lag_ms);
        if let Some(e) = self.session.move_error.take() {
            *status = e.to_string();
        }
        // Nothing held or scripted: the frame refines toward the exact reference.
        if self.options.refine && self.drag.is_none() && self.record.script.is_none() {
            self.session.refine_when_idle();
        }
    }

    /// Whether this frame counts in the report: a frame's time runs from the last frame's start,
    /// so the second's holds the first's one-time set-up (the driver compiles its shaders on
    /// first use); without a script every later frame counts, with one the drag's.
    fn measured(&self) -> bool {
        self.record.frames > 1 && (self.options.scripted_drag.is_none() || self.record.script.is_some())
    }

    /// What the run measured.
    fn report(&self) -> WindowReport {
        let r = &self.record;
        let stats = self.session.background();
        WindowReport {
            frames: r.frames,
            drag_frames: r.drag_frames,
            frame_ms: Quantiles::of(&r.frame_ms),
            draw_ms: Quantiles::of(&r.draw_ms),
            steps_posted: stats.posted,
            steps_dropped: stats.dropped,
            merges: stats.finished,
            merge_ms_mean: r.merge_ms.iter().sum::<f64>() / r.merge_ms.len().max(1) as f64,
            shading_lag_ms: Quantiles::of(&r.lags),
            refine_slices: stats.refines_finished,
            refined_share: self.session.refined.map(|r| r.exact as f64 / (r.exact + r.remaining).max(1) as f64),
        }
    }

    /// The screen-space modes: their passes run (when the colours or the viewport changed) and
    /// their image is returned for display.
    fn screen_image(
        &mut self,
        state: &WindowState,
        viewport: Viewport,
        status: &mut String,
    ) -> Option<wgpu::TextureView> {
        if !self.session.mode().screen_space() {
            self.screen = None;
            return None;
        }
        let size = (viewport.width as u32, viewport.height as u32);
        let key = (self.session.colour_version(), size);
        if self.screen.as_ref().is_none_or(|(k, _)| *k != key) {
            let start = Instant::now();
            if self.ssdo.is_none() {
                // An adapter lacking what the passes need: said on the status line, and the
                // viewer goes back to the precomputed cuts.
                match GpuSsdo::new(&state.gpu) {
                    Ok(p) => self.ssdo = Some(p),
                    Err(e) => {
                        *status = e.to_string();
                        let _ = self.session.set_mode(Mode::Cuts);
                    }
                }
            }
            if let Some(passes) = &self.ssdo {
                match crate::screen::session_frame(&state.gpu, passes, &mut self.session, size) {
                    Ok(f) => self.screen = f.map(|f| ((self.session.colour_version(), size), f)),
                    Err(e) => *status = e.to_string(),
                }
            }
            self.screen_ms = start.elapsed().as_secs_f64() * 1e3;
        }
        self.screen.as_ref().map(|(_, f)| f.output())
    }
}

impl WindowApp for App {
    fn title(&self) -> &str {
        &self.options.title
    }

    fn env(&self) -> &EnvMap {
        self.session.env()
    }

    fn max_frames(&self) -> Option<u64> {
        self.options.max_frames
    }

    fn camera(&mut self) -> &mut OrbitCamera {
        &mut self.session.camera
    }

    fn prepare(&mut self, state: &mut WindowState, status: &mut String) -> Result<bool, ViewError> {
        self.script_step(status);
        self.session.update_later();
        self.take_in(status);
        let more_reference = self.session.step_reference(Duration::from_millis(40));
        let upload_ms = state.scene.upload(&state.gpu, &self.session)?;
        if upload_ms > 0.0 {
            self.session.timings.upload_ms = upload_ms;
        }
        if let Some(e) = self.session.turn_error.take() {
            *status = e;
        }
        // While the worker runs, frames keep coming to take its results in.
        Ok(more_reference || self.session.busy() || self.record.script.is_some())
    }

    fn panel(&mut self, ui: &mut egui::Ui, frame_ms: f64, status: &str) -> f32 {
        if self.measured() {
            self.record.frame_ms.push(frame_ms);
        }
        self.actions = PanelActions::default();
        panel(ui, &mut self.session, &self.options, status, (frame_ms, self.screen_ms), &mut self.actions)
    }

    fn draw(
        &mut self,
        state: &mut WindowState,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        viewport: Viewport,
        status: &mut String,
    ) -> Result<(), ViewError> {
        let image = self.screen_image(state, viewport, status);
        state.scene.draw(&state.gpu, encoder, (view, &state.depth), self.session.shown(viewport), image.as_ref());
        Ok(())
    }

    fn presented(&mut self, draw_ms: f64, status: &mut String) -> bool {
        self.session.timings.draw_ms = draw_ms;
        if self.measured() {
            self.record.draw_ms.push(draw_ms);
        }
        self.record.frames += 1;
        let actions = std::mem::take(&mut self.actions);
        if let Some(name) = actions.env {
            match (self.options.load_env)(&name) {
                Ok(env) => self.session.set_environment(&name, env),
                Err(e) => *status = format!("{name}: {e}"),
            }
        }
        if let Some(e) = actions.error {
            *status = e;
        }
        actions.changed
    }

    fn press(&mut self, at: ViewportPoint, shift: bool) -> bool {
        let (origin, dir) = self.session.camera.ray(at.x, at.y, at.width, at.height);
        let Some((o, t)) = self.session.pick(origin, dir) else { return false };
        self.session.selected = Some(o);
        let object = &self.session.objects()[o];
        if object.motion != Motion::Movable {
            return false;
        }
        self.drag = Some(ObjectDrag { o, grab: origin + dir * t, start: object.translation, vertical: shift });
        true
    }

    fn drag(&mut self, at: ViewportPoint, status: &mut String) {
        let camera = self.session.camera;
        let Some(ObjectDrag { o, grab, start, vertical }) = &self.drag else { return };
        let (origin, dir) = camera.ray(at.x, at.y, at.width, at.height);
        let target = if *vertical {
            let forward = camera.target - camera.eye();
            let normal = Vec3::new(forward.x, 0.0, forward.z).normalize_or(Vec3::Z);
            ray_plane(origin, dir, *grab, normal).map(|p| Vec3::new(0.0, p.y - grab.y, 0.0))
        } else {
            ray_plane(origin, dir, *grab, Vec3::Y).map(|p| Vec3::new(p.x - grab.x, 0.0, p.z - grab.z))
        };
        let Some(delta) = target else { return };
        let (t, o) = (*start + delta, *o);
        self.apply_move(o, t, status);
    }

    /// The drag's settle, posted ([`Session::post_settle`]).
    fn release(&mut self, _status: &mut String) {
        if self.drag.take().is_some() {
            self.session.post_settle();
        }
    }
}

#[derive(Default)]
struct PanelActions {
    env: Option<String>,
    error: Option<String>,
    changed: bool,
}

fn panel(
    ui: &mut egui::Ui,
    session: &mut Session,
    options: &ViewOptions,
    status: &str,
    (frame_ms, screen_ms): (f64, f64),
    actions: &mut PanelActions,
) -> f32 {
    let response = egui::Panel::left("controls").default_size(300.0).show(ui, |ui| {
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.heading("visibility cuts");
            egui::Grid::new("summary").num_columns(2).show(ui, |ui| {
                for (k, v) in &options.summary {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                }
            });
            ui.separator();

            ui.strong("mode");
            let mut mode = session.mode();
            for m in Mode::ALL {
                ui.add_enabled_ui(m.available(), |ui| ui.radio_value(&mut mode, m, m.label()));
            }
            if mode != session.mode() {
                if let Err(e) = session.set_mode(mode) {
                    actions.error = Some(e.to_string());
                }
                actions.changed = true;
            }
            if matches!(session.mode(), Mode::Exact | Mode::Difference) {
                let p = session.reference_progress();
                ui.add(egui::ProgressBar::new(p as f32).text(format!("reference {:.0} %", p * 100.0)));
                if let Some(e) = session.reference_error() {
                    ui.label(format!("cuts vs reference: rel. L2 {:.2} %", e * 100.0));
                }
                if session.mode() == Mode::Difference {
                    ui.label(format!(
                        "heat: |cuts − reference| / mean, 0 (blue) … {:.0} % (red)",
                        crate::session::HEAT_MAX * 100.0
                    ));
                }
            }
            ui.separator();

            // An edit waits for the frame's worker: not offered while it runs.
            let busy = session.busy();
            ui.add_enabled_ui(!busy, |ui| object_controls(ui, session, actions));
            ui.separator();
            ui.add_enabled_ui(!busy, |ui| environment_controls(ui, session, options, actions));
            let mut auto = session.exposure.is_none();
            ui.checkbox(&mut auto, "automatic exposure");
            let mut ev = session.exposure_in_use().max(1e-8).log2();
            let slider = ui.add_enabled(!auto, egui::Slider::new(&mut ev, -12.0..=12.0).text("exposure EV"));
            session.exposure = if auto { None } else { Some(2f32.powf(ev)) };
            if slider.changed() {
                actions.changed = true;
            }
            ui.separator();

            ui.strong("timings");
            let t = session.timings;
            egui::Grid::new("timings").num_columns(2).show(ui, |ui| {
                for (k, v) in [
                    ("merge (last move)", format!("{:.1} ms, {} vertices", t.merge_ms, t.merged_vertices)),
                    ("shading lag", format!("{:.0} ms, {:.3} behind", t.shading_lag_ms, session.shading_behind())),
                    ("refined at rest", refine_progress(session.refined)),
                    ("merged by the camera", format!("{} vertices", t.turn_merged)),
                    ("shade", format!("{:.1} ms", t.shade_ms)),
                    ("light tree", format!("{:.1} ms", t.light_ms)),
                    ("upload", format!("{:.1} ms", t.upload_ms)),
                    ("draw", format!("{:.1} ms", t.draw_ms)),
                    ("screen space", format!("{screen_ms:.1} ms")),
                    ("frame", format!("{frame_ms:.0} ms")),
                ] {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                }
            });
            ui.separator();
            ui.label("left-drag: orbit · right-drag: pan · wheel: zoom");
            ui.label("left-drag an object: move it (Shift: vertically)");
            if !status.is_empty() {
                ui.label(status);
            }
        });
    });
    response.response.rect.right()
}

fn environment_controls(ui: &mut egui::Ui, session: &mut Session, options: &ViewOptions, actions: &mut PanelActions) {
    ui.strong("environment");
    let mut chosen = None;
    egui::ComboBox::from_id_salt("env").selected_text(session.env_name().to_string()).show_ui(ui, |ui| {
        for name in &options.envs {
            if ui.selectable_label(name == session.env_name(), name).clicked() {
                chosen = Some(name.clone());
            }
        }
    });
    if let Some(name) = chosen.filter(|n| n != session.env_name()) {
        actions.env = Some(name);
        actions.changed = true;
    }
    let mut rotation = session.env_rotation_deg();
    if ui.add(egui::Slider::new(&mut rotation, -180.0..=180.0).text("rotation °")).changed() {
        session.set_env_rotation(rotation);
        actions.changed = true;
    }
    let mut sun_rays = session.sun_rays();
    let light = session.light().clone();
    let choice = &light.choice;
    let label = format!("sun by rays ({} leaves, {:.1} rays/vertex)", light.sun_leaves, choice.rays_per_vertex());
    let hover = format!(
        "the light's brightest leaves cast at run time, the rest from the cuts; estimated error {:.2} % (all in the cuts: {:.2} %)",
        100.0 * choice.estimate,
        100.0 * choice.estimate_cuts
    );
    if ui.checkbox(&mut sun_rays, label).on_hover_text(hover).changed() {
        if let Err(e) = session.set_sun_rays(sun_rays) {
            actions.error = Some(e.to_string());
        }
        actions.changed = true;
    }
    let directions = light.directions;
    let interactive = vcut_shade::FlatEdges::Interactive.leaves(directions);
    let mut estimated = session.settings().flat_edge_leaves.leaves(directions) > 1;
    let label = format!("ground edges estimated ({interactive} directions a node)");
    let hover = "a ground's shadow estimated across its edges instead of cut to single directions: \
                 about half a drag's time at the paper preset, +0.02 to 0.05 point of error";
    let edges = ui.add_enabled(interactive > 1, egui::Checkbox::new(&mut estimated, label));
    if edges.on_hover_text(hover).changed() {
        let edges = if estimated { vcut_shade::FlatEdges::Interactive } else { vcut_shade::FlatEdges::Leaves(1) };
        if let Err(e) = session.set_flat_edge_leaves(edges) {
            actions.error = Some(e.to_string());
        }
        actions.changed = true;
    }
    let mut target = 100.0 * session.light_error();
    let slider = egui::Slider::new(&mut target, 0.02..=5.0).logarithmic(true).text("light error target %");
    if ui.add_enabled(sun_rays, slider).changed() {
        if let Err(e) = session.set_light_error(target / 100.0) {
            actions.error = Some(e.to_string());
        }
        actions.changed = true;
    }
}

fn object_controls(ui: &mut egui::Ui, session: &mut Session, actions: &mut PanelActions) {
    ui.strong("object");
    let names: Vec<String> = session.objects().iter().map(|o| o.name.clone()).collect();
    let mut selected = session.selected;
    egui::ComboBox::from_id_salt("object")
        .selected_text(selected.map_or("none".to_string(), |o| names[o].clone()))
        .show_ui(ui, |ui| {
            for (o, n) in names.iter().enumerate() {
                ui.selectable_value(&mut selected, Some(o), n);
            }
        });
    session.selected = selected;
    let Some(o) = selected else { return };
    let object = &session.objects()[o];
    let (material, motion, translation) = (object.material, object.motion, object.translation);
    let radius = object.mesh.bounds().radius;
    let mut m: Material = material;
    ui.horizontal(|ui| {
        ui.label("BRDF");
        egui::ComboBox::from_id_salt("brdf").selected_text(format!("{:?}", m.model)).show_ui(ui, |ui| {
            for model in [BrdfModel::Lambert, BrdfModel::BlinnPhong, BrdfModel::Phong, BrdfModel::Ggx] {
                ui.selectable_value(&mut m.model, model, format!("{model:?}"));
            }
        });
    });
    ui.horizontal(|ui| {
        ui.label("kd");
        ui.color_edit_button_rgb(&mut m.kd);
        if m.model != BrdfModel::Lambert {
            ui.label("ks");
            ui.color_edit_button_rgb(&mut m.ks);
        }
    });
    match m.model {
        BrdfModel::BlinnPhong | BrdfModel::Phong => {
            ui.add(egui::Slider::new(&mut m.exponent, 1.0..=1000.0).logarithmic(true).text("exponent α"));
        }
        BrdfModel::Ggx => {
            ui.add(egui::Slider::new(&mut m.roughness, 0.01..=1.0).text("roughness"));
        }
        BrdfModel::Lambert => {}
    }
    if m != material {
        session.set_material(o, m);
        actions.changed = true;
    }
    if motion == Motion::Movable {
        let mut t = translation;
        ui.horizontal(|ui| {
            ui.label("move");
            let speed = f64::from(radius) * 0.01;
            ui.add(egui::DragValue::new(&mut t.x).speed(speed).prefix("x "));
            ui.add(egui::DragValue::new(&mut t.y).speed(speed).prefix("y "));
            ui.add(egui::DragValue::new(&mut t.z).speed(speed).prefix("z "));
        });
        if t != translation {
            if let Err(e) = session.translate(o, t) {
                actions.error = Some(e.to_string());
            }
            actions.changed = true;
        }
        turn_control(ui, session, o, actions);
    } else {
        ui.label("static (no visibility field): cannot move");
    }
}

/// The selected movable object's turn about +Y: a drag handle in degrees, posted as the
/// pointer drags it (the object turns on screen at once; the cuts follow from the worker, by
/// whole wedges of the direction set).
fn turn_control(ui: &mut egui::Ui, session: &mut Session, o: usize, actions: &mut PanelActions) {
    let Some(wedges) = session.turn_wedges() else {
        ui.label("turn: precompute with --set turn_steps=64");
        return;
    };
    let yaw = session.objects()[o].yaw;
    let mut degrees = yaw.to_degrees();
    ui.horizontal(|ui| {
        ui.label("turn");
        ui.add(egui::DragValue::new(&mut degrees).speed(1.0).suffix("°").range(-360.0..=360.0));
        ui.label(format!("cuts by {:.3}° steps", 360.0 / wedges as f32));
    });
    if degrees != yaw.to_degrees() {
        if let Err(e) = session.post_turn(o, degrees.to_radians()) {
            actions.error = Some(e.to_string());
        }
        actions.changed = true;
    }
}

/// How far the frame's refinement at rest is, for the panel.
fn refine_progress(r: Option<vcut_shade::RefineStats>) -> String {
    match r {
        None => "not yet (since the last move)".into(),
        Some(r) => {
            let pairs = r.exact + r.remaining;
            let share = if pairs == 0 { 100.0 } else { 100.0 * r.exact as f64 / pairs as f64 };
            let budget = if r.over_budget > 0 { ", memory budget spent" } else { "" };
            format!("{share:.0} % of {pairs} factors{budget}")
        }
    }
}
