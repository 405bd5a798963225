//! The one window host of the viewer's apps (the cut viewer and the leaf viewer): the event
//! loop, the window and its device ([`WindowState`]), the frame skeleton — prepare, side
//! panel, scene viewport right of it, draw, egui over it, present, scripted frame counts — and
//! the camera gestures every app shares (left-drag orbits, right- or middle-drag pans, the wheel
//! zooms). An app ([`WindowApp`]) supplies its panel, its drawing and, if it wants, its own
//! left-drag (the cut viewer drags objects).

use crate::camera::OrbitCamera;
use crate::gpu::ViewError;
use crate::render::Viewport;
use crate::window::{WindowState, wheel_lines};
use std::time::Instant;
use vcut_envmap::EnvMap;
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

/// A cursor position in the scene's viewport (physical pixels from its top left) and the
/// viewport's size.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ViewportPoint {
    pub x: f32,
    pub y: f32,
    pub width: f32,
    pub height: f32,
}

/// What a window app does within the host's frame and gestures.
pub(crate) trait WindowApp {
    /// The window's title.
    fn title(&self) -> &str;
    /// The environment the scene renderer starts with.
    fn env(&self) -> &EnvMap;
    /// Close after this many frames (scripted runs).
    fn max_frames(&self) -> Option<u64>;
    /// The camera the host's gestures move.
    fn camera(&mut self) -> &mut OrbitCamera;
    /// The host moved the camera.
    fn camera_moved(&mut self) {}
    /// Work before the frame's texture is taken (updates, uploads); `true` asks for another
    /// frame right after this one.
    fn prepare(&mut self, _state: &mut WindowState, _status: &mut String) -> Result<bool, ViewError> {
        Ok(false)
    }
    /// The side panel, given the last frame's time (ms); returns its right edge (points).
    fn panel(&mut self, ui: &mut egui::Ui, frame_ms: f64, status: &str) -> f32;
    /// Records the scene into `encoder` over `viewport` of `view`.
    fn draw(
        &mut self,
        state: &mut WindowState,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        viewport: Viewport,
        status: &mut String,
    ) -> Result<(), ViewError>;
    /// The frame was presented, `draw_ms` after its texture was taken; `true` asks for another.
    fn presented(&mut self, draw_ms: f64, status: &mut String) -> bool;
    /// A left press in the viewport (`shift` held or not): whether the app drags from here
    /// (else the host orbits).
    fn press(&mut self, _at: ViewportPoint, _shift: bool) -> bool {
        false
    }
    /// The app's drag moved to `at`.
    fn drag(&mut self, _at: ViewportPoint, _status: &mut String) {}
    /// The app's drag ended.
    fn release(&mut self, _status: &mut String) {}
}

#[derive(Clone, Copy, PartialEq)]
enum Drag {
    Orbit,
    Pan,
    App,
}

struct Host<A> {
    app: A,
    state: Option<WindowState>,
    error: Option<ViewError>,
    status: String,
    cursor: Option<(f32, f32)>,
    drag: Option<Drag>,
    shift: bool,
    frames: u64,
    last_frame: Instant,
    frame_ms: f64,
    /// Where the scene is drawn (right of the panel), physical pixels.
    viewport: Viewport,
}

/// Opens `app`'s window and runs until it is closed (or its scripted frames are drawn); gives
/// the app back.
pub(crate) fn run<A: WindowApp>(app: A) -> Result<A, ViewError> {
    let event_loop = EventLoop::new().map_err(|e| ViewError::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    let mut host = Host {
        app,
        state: None,
        error: None,
        status: String::new(),
        cursor: None,
        drag: None,
        shift: false,
        frames: 0,
        last_frame: Instant::now(),
        frame_ms: 0.0,
        viewport: Viewport::full(1, 1),
    };
    event_loop.run_app(&mut host).map_err(|e| ViewError::Window(e.to_string()))?;
    match host.error {
        Some(e) => Err(e),
        None => Ok(host.app),
    }
}

impl<A: WindowApp> Host<A> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: ViewError) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn request_redraw(&self) {
        if let Some(s) = &self.state {
            s.window.request_redraw();
        }
    }

    /// The cursor in the viewport, `None` outside it.
    fn at(&self, (x, y): (f32, f32)) -> Option<ViewportPoint> {
        let v = self.viewport;
        let (x, y) = (x - v.x, y - v.y);
        (x >= 0.0 && y >= 0.0).then_some(ViewportPoint { x, y, width: v.width.max(1.0), height: v.height.max(1.0) })
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(state) = self.state.as_mut() else { return };
        let now = Instant::now();
        self.frame_ms = (now - self.last_frame).as_secs_f64() * 1e3;
        self.last_frame = now;
        let more = match self.app.prepare(state, &mut self.status) {
            Ok(more) => more,
            Err(e) => return self.fail(event_loop, e),
        };
        let Some(texture) = state.acquire() else { return };
        let draw_start = Instant::now();
        // The panel first: its width decides the scene's viewport.
        let raw = state.egui_state.take_egui_input(&state.window);
        let ctx = state.egui_ctx.clone();
        let mut panel_points = 0.0;
        let mut output = ctx.run_ui(raw, |ui| panel_points = self.app.panel(ui, self.frame_ms, &self.status));
        let size = (state.config.width, state.config.height);
        let left = (panel_points * output.pixels_per_point).round().clamp(0.0, size.0 as f32 - 1.0);
        self.viewport = Viewport { x: left, y: 0.0, width: size.0 as f32 - left, height: size.1 as f32 };
        let view = texture.texture.create_view(&Default::default());
        let mut encoder = state.gpu.device.create_command_encoder(&Default::default());
        if let Err(e) = self.app.draw(state, &mut encoder, &view, self.viewport, &mut self.status) {
            // The frame is not painted: its texture changes are dropped on purpose (egui
            // asserts in debug builds that none is dropped unapplied).
            output.textures_delta.clear();
            return self.fail(event_loop, e);
        }
        let repaint = output.viewport_output.values().any(|v| v.repaint_delay.is_zero());
        if let Err(e) = state.paint_and_present(encoder, &view, texture, output) {
            return self.fail(event_loop, e);
        }
        let again = self.app.presented(draw_start.elapsed().as_secs_f64() * 1e3, &mut self.status);
        self.frames += 1;
        let scripted = self.app.max_frames();
        if scripted.is_some_and(|n| self.frames >= n) {
            event_loop.exit();
            return;
        }
        if more || again || repaint || scripted.is_some() {
            state.window.request_redraw();
        }
    }

    fn press(&mut self, button: MouseButton) {
        let Some(at) = self.cursor.and_then(|c| self.at(c)) else { return };
        self.drag = match button {
            MouseButton::Left if self.app.press(at, self.shift) => Some(Drag::App),
            MouseButton::Left => Some(Drag::Orbit),
            MouseButton::Right | MouseButton::Middle => Some(Drag::Pan),
            _ => None,
        };
    }

    fn cursor_moved(&mut self, x: f32, y: f32) {
        let previous = self.cursor.replace((x, y));
        let (Some((px, py)), Some(drag)) = (previous, self.drag) else { return };
        let (dx, dy) = (x - px, y - py);
        let h = self.viewport.height.max(1.0);
        match drag {
            Drag::Orbit => self.app.camera().orbit(dx * 0.01, dy * 0.01),
            Drag::Pan => self.app.camera().pan(dx / h, dy / h),
            Drag::App => {
                let v = self.viewport;
                let at = ViewportPoint { x: x - v.x, y: y - v.y, width: v.width.max(1.0), height: h };
                self.app.drag(at, &mut self.status);
            }
        }
        if drag != Drag::App {
            self.app.camera_moved();
        }
        self.request_redraw();
    }
}

impl<A: WindowApp> ApplicationHandler for Host<A> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match WindowState::create(event_loop, self.app.title(), self.app.env()) {
            Ok(s) => {
                self.status = format!("adapter: {}", s.gpu.describe());
                s.window.request_redraw();
                self.state = Some(s);
            }
            Err(e) => self.fail(event_loop, e),
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
                let (x, y) = (position.x as f32, position.y as f32);
                if response.consumed && self.drag.is_none() {
                    self.cursor = Some((x, y));
                } else {
                    self.cursor_moved(x, y);
                }
            }
            WindowEvent::MouseInput { state: s, button, .. } => {
                if s == ElementState::Pressed {
                    if !response.consumed {
                        self.press(button);
                    }
                } else if let Some(drag) = self.drag.take()
                    && drag == Drag::App
                {
                    self.app.release(&mut self.status);
                }
                self.request_redraw();
            }
            WindowEvent::MouseWheel { delta, .. } if !response.consumed => {
                self.app.camera().zoom(0.9f32.powf(wheel_lines(delta)));
                self.app.camera_moved();
                self.request_redraw();
            }
            _ => {}
        }
    }
}
