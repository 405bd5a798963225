//! What every window of the viewer shares: the winit window and its wgpu surface, the device,
//! the scene renderer, and egui — created, resized, and painted over the scene then presented.

use crate::gpu::{Gpu, ViewError};
use crate::render::{SceneRenderer, depth_view};
use std::sync::Arc;
use vcut_envmap::EnvMap;
use winit::event::{ElementState, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};
use winit::window::Window;

/// Mouse-wheel motion in lines (pixels at 40 a line).
pub(crate) fn wheel_lines(delta: MouseScrollDelta) -> f32 {
    match delta {
        MouseScrollDelta::LineDelta(_, y) => y,
        MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
    }
}

/// A window with its surface, device, scene renderer and egui.
pub(crate) struct WindowState {
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub config: wgpu::SurfaceConfiguration,
    pub gpu: Gpu,
    pub scene: SceneRenderer,
    pub depth: wgpu::TextureView,
    pub egui_ctx: egui::Context,
    pub egui_state: egui_winit::State,
    pub egui_renderer: egui_wgpu::Renderer,
}

impl WindowState {
    /// A 1280 × 800 window titled `title`, its scene renderer set up for `env`.
    pub fn create(event_loop: &ActiveEventLoop, title: &str, env: &EnvMap) -> Result<WindowState, ViewError> {
        let attributes =
            Window::default_attributes().with_title(title).with_inner_size(winit::dpi::LogicalSize::new(1280.0, 800.0));
        let window = Arc::new(event_loop.create_window(attributes).map_err(|e| ViewError::Window(e.to_string()))?);
        // OpenGL (EGL) needs the display the window lives on to present to it.
        let display = Box::new(event_loop.owned_display_handle());
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(display));
        let surface = instance.create_surface(window.clone()).map_err(|e| ViewError::Window(e.to_string()))?;
        let gpu = Gpu::with_instance(instance, Some(&surface))?;
        let size = window.inner_size();
        let caps = surface.get_capabilities(&gpu.adapter);
        let format = caps.formats.iter().copied().find(|f| !f.is_srgb()).or(caps.formats.first().copied());
        let mut config = surface
            .get_default_config(&gpu.adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| ViewError::Window(format!("the adapter '{}' cannot present here", gpu.describe())))?;
        if let Some(f) = format {
            config.format = f;
        }
        gpu.checked("configure the window's surface", || surface.configure(&gpu.device, &config))?;
        let scene = SceneRenderer::new(&gpu, config.format, env)?;
        let depth = depth_view(&gpu, config.width, config.height);
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(&gpu.device, config.format, Default::default());
        Ok(WindowState { window, surface, config, gpu, scene, depth, egui_ctx, egui_state, egui_renderer })
    }

    /// Passes `event` to egui (asking for a redraw when egui wants one) and handles what every
    /// window does alike — close, resize, Escape (when egui did not take it); returns egui's
    /// response, and whether the event is dealt with.
    pub fn common_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        event: &WindowEvent,
    ) -> (egui_winit::EventResponse, bool) {
        let response = self.egui_state.on_window_event(&self.window, event);
        if response.repaint {
            self.window.request_redraw();
        }
        let done = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                true
            }
            WindowEvent::Resized(size) => {
                self.resize(*size);
                true
            }
            WindowEvent::KeyboardInput { event, .. }
                if !response.consumed
                    && event.state == ElementState::Pressed
                    && event.logical_key == Key::Named(NamedKey::Escape) =>
            {
                event_loop.exit();
                true
            }
            _ => false,
        };
        (response, done)
    }

    /// Follows a new window size.
    pub fn resize(&mut self, size: winit::dpi::PhysicalSize<u32>) {
        self.config.width = size.width.max(1);
        self.config.height = size.height.max(1);
        self.surface.configure(&self.gpu.device, &self.config);
        self.depth = depth_view(&self.gpu, self.config.width, self.config.height);
        self.window.request_redraw();
    }

    /// The next surface texture, or `None` (surface reconfigured, redraw requested).
    pub fn acquire(&mut self) -> Option<wgpu::SurfaceTexture> {
        match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => Some(t),
            _ => {
                self.surface.configure(&self.gpu.device, &self.config);
                self.window.request_redraw();
                None
            }
        }
    }

    /// Paints egui's `output` over `view` after the scene recorded in `encoder`, submits, and
    /// presents `texture`; fails with what wgpu reported while drawing the frame.
    pub fn paint_and_present(
        &mut self,
        encoder: wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        texture: wgpu::SurfaceTexture,
        output: egui::FullOutput,
    ) -> Result<(), ViewError> {
        self.paint(encoder, view, texture, output);
        Ok(self.gpu.take_errors("draw a frame")?)
    }

    fn paint(
        &mut self,
        mut encoder: wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        texture: wgpu::SurfaceTexture,
        output: egui::FullOutput,
    ) {
        let size = (self.config.width, self.config.height);
        let egui::FullOutput { platform_output, mut textures_delta, shapes, pixels_per_point, .. } = output;
        self.egui_state.handle_platform_output(&self.window, platform_output);
        let primitives = self.egui_ctx.tessellate(shapes, pixels_per_point);
        let screen = egui_wgpu::ScreenDescriptor { size_in_pixels: [size.0, size.1], pixels_per_point };
        for (id, deltas) in &textures_delta.set {
            for delta in deltas {
                self.egui_renderer.update_texture(&self.gpu.device, &self.gpu.queue, *id, delta);
            }
        }
        let extra =
            self.egui_renderer.update_buffers(&self.gpu.device, &self.gpu.queue, &mut encoder, &primitives, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.egui_renderer.render(&mut pass, &primitives, &screen);
        }
        for id in &textures_delta.free {
            self.egui_renderer.free_texture(id);
        }
        // Every delta is applied above; egui asserts (in debug builds) that none is dropped
        // unapplied.
        textures_delta.clear();
        self.gpu.queue.submit(extra.into_iter().chain([encoder.finish()]));
        self.gpu.queue.present(texture);
    }
}
