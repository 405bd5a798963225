//! The leaf viewer's window: the plant drawn two-sided by [`crate::SceneRenderer`], a panel for
//! the sun (direction or time of day), the method (two passes or SH alone), level of detail, the
//! leaf tissue (σ_a, σ_s per channel, thickness), each side's gloss (ρ_s, m) and the vein maps.
//! Left-drag orbits, right-drag pans, the wheel zooms (the host's gestures, [`crate::host`]).

use crate::camera::OrbitCamera;
use crate::gpu::ViewError;
use crate::host::WindowApp;
use crate::leaf::LeafSession;
use crate::render::Viewport;
use crate::window::WindowState;
use glam::Vec3;
use vcut_envmap::EnvMap;
use vcut_leaf::material::SideMaps;
use vcut_leaf::shade::{SunMethod, sun_at};

/// What the leaf window shows besides the session.
pub struct LeafViewOptions {
    /// Window title.
    pub title: String,
    /// Lines about the plant and its data, shown in the panel.
    pub summary: Vec<(String, String)>,
    /// Close after this many frames (scripted runs); `None`: until the window closes.
    pub max_frames: Option<u64>,
}

struct LeafApp {
    session: LeafSession,
    options: LeafViewOptions,
    /// Sun by time of day (else by elevation and azimuth), and the hour shown.
    by_time: Option<f32>,
    /// The panel changed something this frame.
    changed: bool,
}

/// Opens the leaf window and runs until it is closed.
pub fn run_leaf_window(session: LeafSession, options: LeafViewOptions) -> Result<(), ViewError> {
    crate::host::run(LeafApp { session, options, by_time: None, changed: false }).map(drop)
}

impl WindowApp for LeafApp {
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

    fn camera_moved(&mut self) {
        self.session.touch();
    }

    fn panel(&mut self, ui: &mut egui::Ui, frame_ms: f64, status: &str) -> f32 {
        leaf_panel(ui, &mut self.session, (&self.options, status), frame_ms, &mut self.by_time, &mut self.changed)
    }

    fn draw(
        &mut self,
        state: &mut WindowState,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        viewport: Viewport,
        status: &mut String,
    ) -> Result<(), ViewError> {
        // The level of detail follows the viewport's height.
        if let Err(e) = self.session.update(viewport.height as u32) {
            *status = format!("LVC map: {e}");
        }
        let upload = state.scene.upload_leaves(&state.gpu, &self.session.mesh())?;
        if upload > 0.0 {
            self.session.timings.upload_ms = upload;
        }
        state.scene.draw_leaves(&state.gpu, encoder, (view, &state.depth), self.session.shown(viewport));
        Ok(())
    }

    fn presented(&mut self, draw_ms: f64, _status: &mut String) -> bool {
        self.session.timings.draw_ms = draw_ms;
        std::mem::take(&mut self.changed)
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
            let mut rays = s.edge_rays();
            if ui.add(egui::Slider::new(&mut rays, 0..=16).text("rays per shadow-edge vertex")).changed() {
                s.set_edge_rays(rays);
                *changed = true;
            }
            ui.label(format!("shadow-edge vertices: {}", s.edge_vertices()));
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
