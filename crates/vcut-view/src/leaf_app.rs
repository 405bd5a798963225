//! The leaf viewer's window: the plant drawn two-sided by [`crate::SceneRenderer`], a panel for
//! the sun (direction or time of day), the method (two passes or SH alone), level of detail, the
//! leaf tissue (σ_a, σ_s per channel, thickness), each side's gloss (ρ_s, m) and the vein maps.
//! Left-drag orbits, right-drag pans, the wheel zooms.

use crate::gpu::ViewError;
use crate::leaf::LeafSession;
use crate::render::Viewport;
use crate::window::WindowState;
use glam::Vec3;
use std::time::Instant;
use vcut_leaf::material::SideMaps;
use vcut_leaf::shade::{SunMethod, sun_at};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

/// What the leaf window shows besides the session.
pub struct LeafViewOptions {
    /// Window title.
    pub title: String,
    /// Lines about the plant and its data, shown in the panel.
    pub summary: Vec<(String, String)>,
    /// Close after this many frames (scripted runs); `None`: until the window closes.
    pub max_frames: Option<u64>,
}

#[derive(Clone, Copy, PartialEq)]
enum Drag {
    Orbit,
    Pan,
}

struct LeafApp {
    session: LeafSession,
    options: LeafViewOptions,
    state: Option<WindowState>,
    error: Option<ViewError>,
    cursor: Option<(f32, f32)>,
    drag: Option<Drag>,
    frames: u64,
    status: String,
    last_frame: Instant,
    frame_ms: f64,
    /// Sun by time of day (else by elevation and azimuth), and the hour shown.
    by_time: Option<f32>,
    viewport: Viewport,
}

/// Opens the leaf window and runs until it is closed.
pub fn run_leaf_window(session: LeafSession, options: LeafViewOptions) -> Result<(), ViewError> {
    let event_loop = EventLoop::new().map_err(|e| ViewError::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut app = LeafApp {
        session,
        options,
        state: None,
        error: None,
        cursor: None,
        drag: None,
        frames: 0,
        status: String::new(),
        last_frame: Instant::now(),
        frame_ms: 0.0,
        by_time: None,
        viewport: Viewport::full(1, 1),
    };
    event_loop.run_app(&mut app).map_err(|e| ViewError::Window(e.to_string()))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

impl LeafApp {
    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else { return };
        let now = Instant::now();
        self.frame_ms = (now - self.last_frame).as_secs_f64() * 1e3;
        self.last_frame = now;
        let Some(texture) = state.acquire() else { return };
        let draw_start = Instant::now();
        let raw = state.egui_state.take_egui_input(&state.window);
        let ctx = state.egui_ctx.clone();
        let mut changed = false;
        let mut panel_points = 0.0;
        let output = ctx.run_ui(raw, |ui| {
            panel_points = leaf_panel(
                ui,
                &mut self.session,
                (&self.options, &self.status),
                self.frame_ms,
                &mut self.by_time,
                &mut changed,
            );
        });
        let size = (state.config.width, state.config.height);
        let left = (panel_points * output.pixels_per_point).round().clamp(0.0, size.0 as f32 - 1.0);
        self.viewport = Viewport { x: left, y: 0.0, width: size.0 as f32 - left, height: size.1 as f32 };
        if let Err(e) = self.session.update(self.viewport.height as u32) {
            self.status = format!("LVC map: {e}");
        }
        let upload = match state.scene.upload_leaves(&state.gpu, &self.session) {
            Ok(ms) => ms,
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
                return;
            }
        };
        if upload > 0.0 {
            self.session.timings.upload_ms = upload;
        }
        let view = texture.texture.create_view(&Default::default());
        let mut encoder = state.gpu.device.create_command_encoder(&Default::default());
        state.scene.draw_leaves(&state.gpu, &mut encoder, (&view, &state.depth), &self.session, self.viewport);
        let repaint = output.viewport_output.values().any(|v| v.repaint_delay.is_zero());
        if let Err(e) = state.paint_and_present(encoder, &view, texture, output) {
            self.error = Some(e);
            event_loop.exit();
            return;
        }
        self.session.timings.draw_ms = draw_start.elapsed().as_secs_f64() * 1e3;
        self.frames += 1;
        if self.options.max_frames.is_some_and(|n| self.frames >= n) {
            event_loop.exit();
            return;
        }
        if changed || repaint || self.options.max_frames.is_some() {
            state.window.request_redraw();
        }
    }

    fn request_redraw(&self) {
        if let Some(s) = &self.state {
            s.window.request_redraw();
        }
    }
}

/// The panel; returns its right edge (points).
fn leaf_panel(
    ui: &mut egui::Ui,
    s: &mut LeafSession,
    (options, status): (&LeafViewOptions, &str),
    frame_ms: f64,
    by_time: &mut Option<f32>,
    changed: &mut bool,
) -> f32 {
    let response = egui::Panel::left("leaf controls").default_size(300.0).show(ui, |ui| {
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.heading("plant leaves");
            egui::Grid::new("leaf summary").num_columns(2).show(ui, |ui| {
                for (k, v) in &options.summary {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                }
            });
            ui.separator();

            ui.strong("sun");
            let mut timed = by_time.is_some();
            ui.checkbox(&mut timed, "by time of day");
            if timed {
                let mut h = by_time.unwrap_or(12.0);
                if ui.add(egui::Slider::new(&mut h, 5.0..=19.0).text("hour")).changed() || by_time.is_none() {
                    let (e, a) = sun_at(h);
                    s.set_sun(e, a);
                    *changed = true;
                }
                *by_time = Some(h);
            } else {
                *by_time = None;
            }
            let (mut e, mut a) = s.sun();
            let r1 = ui.add_enabled(!timed, egui::Slider::new(&mut e, -10.0..=90.0).text("elevation °"));
            let r2 = ui.add_enabled(!timed, egui::Slider::new(&mut a, -180.0..=180.0).text("azimuth °"));
            if r1.changed() || r2.changed() {
                s.set_sun(e, a);
                *changed = true;
            }
            ui.separator();

            ui.strong("method");
            let mut method = s.method();
            ui.radio_value(&mut method, SunMethod::Lvc, "sun by LVC + rest by SH PRT");
            ui.radio_value(&mut method, SunMethod::ShOnly, "everything by SH (Fig. 8)");
            if method != s.method() {
                s.set_method(method);
                *changed = true;
            }
            let mut lod = s.lod_enabled;
            if ui.checkbox(&mut lod, "level of detail by screen size").changed() {
                s.lod_enabled = lod;
                s.touch();
                *changed = true;
            }
            if s.lod_enabled {
                ui.label(format!("leaves per level: {:?}", s.leaves_per_level()));
            }
            ui.separator();

            ui.strong("leaf tissue");
            let mut m = s.material().clone();
            for (label, v) in [("σ_a /mm", &mut m.sigma_a), ("σ_s /mm", &mut m.sigma_s)] {
                ui.horizontal(|ui| {
                    ui.label(label);
                    for c in 0..3 {
                        ui.add(
                            egui::DragValue::new(&mut v[c])
                                .speed(0.05)
                                .range(0.0..=200.0)
                                .prefix(["R ", "G ", "B "][c]),
                        );
                    }
                });
            }
            ui.add(egui::Slider::new(&mut m.thickness, 0.02..=2.0).logarithmic(true).text("thickness h mm"));
            let at = m.scatter(glam::Vec2::new(0.5, 0.25));
            ui.label(format!(
                "lamina: R {:.3} {:.3} {:.3}, T {:.3} {:.3} {:.3}",
                at.r[0].x, at.r[0].y, at.r[0].z, at.t.x, at.t.y, at.t.z
            ));
            for (side, name) in ["upper side", "lower side"].iter().enumerate() {
                let mut rho = m.gloss[side].rho_s.x;
                ui.horizontal(|ui| {
                    ui.label(*name);
                    ui.add(egui::DragValue::new(&mut rho).speed(0.01).range(0.0..=1.0).prefix("ρ_s "));
                    ui.add(
                        egui::DragValue::new(&mut m.gloss[side].roughness).speed(0.01).range(0.02..=1.0).prefix("m "),
                    );
                });
                m.gloss[side].rho_s = Vec3::splat(rho);
            }
            let mut maps = m.maps[0].is_some();
            if ui.checkbox(&mut maps, "vein maps (albedo + thickness, gloss + roughness)").changed() {
                m.maps = if maps {
                    let a = m.albedo();
                    [
                        Some(SideMaps::veins(128, 7, a, 1.0, m.gloss[0].roughness)),
                        Some(SideMaps::veins(128, 7, a, 1.0, m.gloss[1].roughness)),
                    ]
                } else {
                    [None, None]
                };
            }
            if m != *s.material() {
                s.set_material(m);
                *changed = true;
            }
            ui.separator();

            let mut auto = s.exposure.is_none();
            ui.checkbox(&mut auto, "automatic exposure");
            let mut ev = s.exposure_in_use().max(1e-8).log2();
            let slider = ui.add_enabled(!auto, egui::Slider::new(&mut ev, -12.0..=12.0).text("exposure EV"));
            s.exposure = if auto { None } else { Some(2f32.powf(ev)) };
            if slider.changed() {
                *changed = true;
            }
            ui.separator();

            ui.strong("timings");
            let t = s.timings;
            egui::Grid::new("leaf timings").num_columns(2).show(ui, |ui| {
                for (k, v) in [
                    ("decode sun map", format!("{:.2} ms", t.decode_ms)),
                    ("shade", format!("{:.1} ms", t.shade_ms)),
                    ("material edit", format!("{:.1} ms", t.material_ms)),
                    ("upload", format!("{:.1} ms", t.upload_ms)),
                    ("draw", format!("{:.1} ms", t.draw_ms)),
                    ("frame", format!("{frame_ms:.0} ms")),
                ] {
                    ui.label(k);
                    ui.label(v);
                    ui.end_row();
                }
            });
            ui.separator();
            ui.label("left-drag: orbit · right-drag: pan · wheel: zoom");
            if !status.is_empty() {
                ui.label(status);
            }
        });
    });
    response.response.rect.right()
}

impl ApplicationHandler for LeafApp {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match WindowState::create(event_loop, &self.options.title, self.session.env()) {
            Ok(s) => {
                self.status = format!("adapter: {}", s.gpu.describe());
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
            WindowEvent::CursorMoved { position, .. } => {
                let (x, y) = (position.x as f32, position.y as f32);
                let previous = self.cursor.replace((x, y));
                if let (Some((px, py)), Some(drag)) = (previous, self.drag) {
                    let (dx, dy) = (x - px, y - py);
                    match drag {
                        Drag::Orbit => self.session.camera.orbit(dx * 0.01, dy * 0.01),
                        Drag::Pan => self
                            .session
                            .camera
                            .pan(dx / self.viewport.height.max(1.0), dy / self.viewport.height.max(1.0)),
                    }
                    self.session.touch();
                    self.request_redraw();
                }
            }
            WindowEvent::MouseInput { state: s, button, .. } => {
                let pressed = s == ElementState::Pressed;
                let inside = self.cursor.is_some_and(|(x, _)| x >= self.viewport.x);
                self.drag = match (pressed && !response.consumed && inside, button) {
                    (true, MouseButton::Left) => Some(Drag::Orbit),
                    (true, MouseButton::Right | MouseButton::Middle) => Some(Drag::Pan),
                    _ => None,
                };
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                self.session.camera.zoom(0.9f32.powf(crate::window::wheel_lines(delta)));
                self.session.touch();
                self.request_redraw();
            }
            _ => {}
        }
    }
}
