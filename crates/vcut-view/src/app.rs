//! The window: winit 0.30 events, the scene drawn by [`SceneRenderer`], an egui panel on top.
//!
//! Mouse: left-drag on empty space orbits, right- or middle-drag pans, the wheel zooms;
//! left-drag on a movable object moves it over the horizontal plane through the grabbed point
//! (with Shift: vertically). While dragging, the object is re-merged at every mouse move if
//! the last move cost less than [`ViewOptions::live_move_ms`], otherwise once on release.

use crate::camera::ray_plane;
use crate::gpu::ViewError;
use crate::render::Viewport;
use crate::session::{Mode, Session};
use crate::window::WindowState;
use glam::Vec3;
use std::time::{Duration, Instant};
use vcut_envmap::EnvMap;
use vcut_scene::{BrdfModel, Material, Motion};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

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
    /// Re-merge at every mouse move while dragging when the last move took less than this.
    pub live_move_ms: f64,
    /// Close after this many frames (for scripted runs); `None`: until the window closes.
    pub max_frames: Option<u64>,
}

enum Drag {
    Orbit,
    Pan,
    Object { o: usize, grab: Vec3, start: Vec3, vertical: bool, pending: Option<Vec3> },
}

/// What a screen-space frame was made from: the session's colour version and the viewport size.
type ScreenKey = (u64, (u32, u32));

struct App {
    session: Session,
    options: ViewOptions,
    state: Option<WindowState>,
    /// The screen-space passes, compiled on first use.
    ssdo: Option<crate::ssdo::GpuSsdo>,
    /// The last screen-space frame and what it was made from (the session's colour version and
    /// the viewport size): redrawn only when either changes.
    screen: Option<(ScreenKey, crate::ssdo::SsdoFrame)>,
    error: Option<ViewError>,
    cursor: Option<(f32, f32)>,
    drag: Option<Drag>,
    shift: bool,
    frames: u64,
    status: String,
    last_frame: Instant,
    frame_ms: f64,
    /// Last screen-space frame (lighting set-up + passes), ms.
    screen_ms: f64,
    /// Where the scene is drawn (right of the panel), physical pixels.
    viewport: Viewport,
}

/// Opens the window and runs until it is closed.
pub fn run_window(session: Session, options: ViewOptions) -> Result<(), ViewError> {
    let event_loop = EventLoop::new().map_err(|e| ViewError::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = App {
        session,
        options,
        state: None,
        ssdo: None,
        screen: None,
        error: None,
        cursor: None,
        drag: None,
        shift: false,
        frames: 0,
        status: String::new(),
        last_frame: Instant::now(),
        frame_ms: 0.0,
        screen_ms: 0.0,
        viewport: Viewport::full(1, 1),
    };
    event_loop.run_app(&mut app).map_err(|e| ViewError::Window(e.to_string()))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl App {
    fn create(&mut self, event_loop: &ActiveEventLoop) -> Result<WindowState, ViewError> {
        let state = WindowState::create(event_loop, &self.options.title, self.session.env())?;
        self.status = format!("adapter: {}", state.gpu.describe());
        Ok(state)
    }

    /// The cursor position `(x, y)` relative to the scene's viewport, and the viewport's size.
    fn in_viewport(&self, (x, y): (f32, f32)) -> (f32, f32, f32, f32) {
        let v = self.viewport;
        (x - v.x, y - v.y, v.width.max(1.0), v.height.max(1.0))
    }

    fn pointer(&mut self, button: MouseButton, pressed: bool) {
        if !pressed {
            if let Some(Drag::Object { o, pending: Some(t), .. }) = self.drag.take() {
                self.apply_move(o, t);
            }
            self.drag = None;
            return;
        }
        let Some(cursor) = self.cursor else { return };
        let (x, y, w, h) = self.in_viewport(cursor);
        if x < 0.0 || y < 0.0 {
            return;
        }
        self.drag = match button {
            MouseButton::Left => {
                let (origin, dir) = self.session.camera.ray(x, y, w, h);
                match self.session.pick(origin, dir) {
                    Some((o, t)) => {
                        self.session.selected = Some(o);
                        let vcut_shade::FrameObject { motion, translation: start, .. } = self.session.frame().object(o);
                        if motion == Motion::Movable {
                            Some(Drag::Object { o, grab: origin + dir * t, start, vertical: self.shift, pending: None })
                        } else {
                            Some(Drag::Orbit)
                        }
                    }
                    None => Some(Drag::Orbit),
                }
            }
            MouseButton::Right | MouseButton::Middle => Some(Drag::Pan),
            _ => None,
        };
    }

    fn apply_move(&mut self, o: usize, t: Vec3) {
        match self.session.translate(o, t) {
            Ok(()) => {
                let tm = self.session.timings;
                self.status = format!("moved: {} vertices re-merged in {:.1} ms", tm.merged_vertices, tm.merge_ms);
            }
            Err(e) => self.status = e,
        }
    }

    fn cursor_moved(&mut self, x: f32, y: f32) {
        let previous = self.cursor.replace((x, y));
        let Some((px, py)) = previous else { return };
        let (dx, dy) = (x - px, y - py);
        let (x, y, w, h) = self.in_viewport((x, y));
        let live = self.session.timings.merge_ms < self.options.live_move_ms;
        let camera = self.session.camera;
        match &mut self.drag {
            Some(Drag::Orbit) => self.session.camera.orbit(dx * 0.01, dy * 0.01),
            Some(Drag::Pan) => self.session.camera.pan(dx / h, dy / h),
            Some(Drag::Object { o, grab, start, vertical, pending }) => {
                let (origin, dir) = camera.ray(x, y, w, h);
                let target = if *vertical {
                    let forward = camera.target - camera.eye();
                    let normal = Vec3::new(forward.x, 0.0, forward.z).normalize_or(Vec3::Z);
                    ray_plane(origin, dir, *grab, normal).map(|p| Vec3::new(0.0, p.y - grab.y, 0.0))
                } else {
                    ray_plane(origin, dir, *grab, Vec3::Y).map(|p| Vec3::new(p.x - grab.x, 0.0, p.z - grab.z))
                };
                if let Some(delta) = target {
                    let t = *start + delta;
                    let o = *o;
                    if live {
                        *pending = None;
                        self.apply_move(o, t);
                    } else {
                        *pending = Some(t);
                        self.status = format!(
                            "release to move (the last move took {:.0} ms, over {:.0} ms)",
                            self.session.timings.merge_ms, self.options.live_move_ms
                        );
                    }
                }
            }
            None => return,
        }
        self.request_redraw();
    }

    fn request_redraw(&self) {
        if let Some(s) = &self.state {
            s.window.request_redraw();
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else { return };
        let now = Instant::now();
        self.frame_ms = (now - self.last_frame).as_secs_f64() * 1e3;
        self.last_frame = now;
        self.session.update();
        let more_reference = self.session.step_reference(Duration::from_millis(40));
        let upload_ms = match state.scene.upload(&state.gpu, &self.session) {
            Ok(ms) => ms,
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
                return;
            }
        };
        if upload_ms > 0.0 {
            self.session.timings.upload_ms = upload_ms;
        }
        let Some(texture) = state.acquire() else { return };
        let draw_start = Instant::now();
        if let Some(e) = self.session.turn_error.take() {
            self.status = e;
        }
        // The panel first: its width decides the scene's viewport.
        let raw = state.egui_state.take_egui_input(&state.window);
        let ctx = state.egui_ctx.clone();
        let mut actions = PanelActions::default();
        let mut panel_points = 0.0;
        let output = ctx.run_ui(raw, |ui| {
            panel_points = panel(
                ui,
                &mut self.session,
                &self.options,
                &self.status,
                (self.frame_ms, self.screen_ms),
                &mut actions,
            );
        });
        let size = (state.config.width, state.config.height);
        let left = (panel_points * output.pixels_per_point).round().clamp(0.0, size.0 as f32 - 1.0);
        self.viewport = Viewport { x: left, y: 0.0, width: size.0 as f32 - left, height: size.1 as f32 };
        let view = texture.texture.create_view(&Default::default());
        // The screen-space modes: their passes run first, then their image is displayed.
        if self.session.mode().screen_space() {
            let size = (self.viewport.width as u32, self.viewport.height as u32);
            let key = (self.session.colour_version(), size);
            if self.screen.as_ref().is_none_or(|(k, _)| *k != key) {
                let start = Instant::now();
                if self.ssdo.is_none() {
                    // An adapter lacking what the passes need: said on the status line, and the
                    // viewer goes back to the precomputed cuts.
                    match crate::ssdo::GpuSsdo::new(&state.gpu) {
                        Ok(p) => self.ssdo = Some(p),
                        Err(e) => {
                            self.status = e.to_string();
                            let _ = self.session.set_mode(Mode::Cuts);
                        }
                    }
                }
                if let Some(passes) = &self.ssdo {
                    match crate::ssdo::SsdoFrame::of_session(&state.gpu, passes, &mut self.session, size) {
                        Ok(f) => self.screen = f.map(|f| ((self.session.colour_version(), size), f)),
                        Err(e) => self.status = e.to_string(),
                    }
                }
                self.screen_ms = start.elapsed().as_secs_f64() * 1e3;
            }
        } else {
            self.screen = None;
        }
        let image = self.screen.as_ref().map(|(_, f)| f.output());
        let mut encoder = state.gpu.device.create_command_encoder(&Default::default());
        state.scene.draw_with(
            &state.gpu,
            &mut encoder,
            &view,
            &state.depth,
            &self.session,
            &self.session.camera,
            self.viewport,
            image.as_ref(),
        );
        let repaint = output.viewport_output.values().any(|v| v.repaint_delay.is_zero());
        if let Err(e) = state.paint_and_present(encoder, &view, texture, output) {
            self.error = Some(e);
            event_loop.exit();
            return;
        }
        self.session.timings.draw_ms = draw_start.elapsed().as_secs_f64() * 1e3;
        self.frames += 1;

        if let Some(name) = actions.env {
            match (self.options.load_env)(&name) {
                Ok(env) => self.session.set_environment(&name, env),
                Err(e) => self.status = format!("{name}: {e}"),
            }
        }
        if let Some(e) = actions.error {
            self.status = e;
        }
        if self.options.max_frames.is_some_and(|n| self.frames >= n) {
            event_loop.exit();
            return;
        }
        if more_reference || actions.changed || repaint {
            state.window.request_redraw();
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
                    actions.error = Some(e);
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

            object_controls(ui, session, actions);
            ui.separator();

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
            let label = format!("sun by rays ({} leaves)", session.frame().sun_leaves());
            if ui
                .checkbox(&mut sun_rays, label)
                .on_hover_text("the sun's leaves cast at run time, the sky from the cuts")
                .changed()
            {
                session.set_sun_rays(sun_rays);
                actions.changed = true;
            }
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

fn object_controls(ui: &mut egui::Ui, session: &mut Session, actions: &mut PanelActions) {
    ui.strong("object");
    let names: Vec<String> =
        (0..session.frame().object_count()).map(|o| session.frame().object(o).name.into()).collect();
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
    let vcut_shade::FrameObject { mesh, material, motion, translation, .. } = session.frame().object(o);
    let radius = mesh.bounds().radius;
    let mut m: Material = *material;
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
    if m != *material {
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
                actions.error = Some(e);
            }
            actions.changed = true;
        }
    } else {
        ui.label("static (no visibility field): cannot move");
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match self.create(event_loop) {
            Ok(s) => {
                s.window.request_redraw();
                self.state = Some(s);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(state) = self.state.as_mut() else { return };
        let (response, done) = state.common_event(event_loop, &event);
        if done {
            return;
        }
        match event {
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::ModifiersChanged(m) => self.shift = m.state().shift_key(),
            WindowEvent::CursorMoved { position, .. } => {
                if response.consumed && self.drag.is_none() {
                    self.cursor = Some((position.x as f32, position.y as f32));
                } else {
                    self.cursor_moved(position.x as f32, position.y as f32);
                }
            }
            WindowEvent::MouseInput { state: s, button, .. } => {
                let pressed = s == ElementState::Pressed;
                if !(pressed && response.consumed) {
                    self.pointer(button, pressed);
                    self.request_redraw();
                }
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                self.session.camera.zoom(0.9f32.powf(crate::window::wheel_lines(delta)));
                self.request_redraw();
            }
            _ => {}
        }
    }
}
