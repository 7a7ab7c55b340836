//! The windowed mode: winit's event loop, a wgpu surface, egui-winit input.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

use crate::app::App;
use crate::frontend::Frontend;
use crate::render::{self, Gpu, GpuError};
use crate::stats::StatsLog;

/// What a windowed run does.
pub struct WindowedRun {
    /// The window's first inner size in pixels.
    pub size: [u32; 2],
    /// Close after this many frames (for tests), or run until closed.
    pub frames: Option<usize>,
    /// Where the per-frame figures go as JSON when the window closes.
    pub stats: Option<PathBuf>,
}

/// The event loop could not start: no display (the caller goes headless).
pub struct NoDisplay(pub String);

/// Makes the event loop; fails when there is no display to open a window on.
pub fn event_loop() -> Result<EventLoop<()>, NoDisplay> {
    EventLoop::new().map_err(|e| NoDisplay(e.to_string()))
}

/// Runs `app` in a window until it is closed (or `run.frames` are drawn).
pub fn run(app: App, event_loop: EventLoop<()>, run: WindowedRun) -> Result<(), String> {
    let mut handler =
        Handler { app, run, window: None, error: None, log: StatsLog::default(), drawn: 0 };
    event_loop.run_app(&mut handler).map_err(|e| e.to_string())?;
    if let Some(error) = handler.error {
        return Err(error);
    }
    if let (Some(path), Some(w)) = (&handler.run.stats, &handler.window) {
        let mode = ("windowed", w.gpu.describe());
        handler.log.write(path, (mode.0, &mode.1), &handler.app, w.frontend.last_view)?;
    }
    eprintln!("falling: {} frames drawn in the window", handler.drawn);
    Ok(())
}

/// The window and what draws into it.
struct WindowState {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    gpu: Gpu,
    frontend: Frontend,
    egui: egui_winit::State,
}

struct Handler {
    app: App,
    run: WindowedRun,
    window: Option<WindowState>,
    error: Option<String>,
    log: StatsLog,
    drawn: usize,
}

impl WindowState {
    fn new(event_loop: &ActiveEventLoop, app: &App, size: [u32; 2]) -> Result<Self, String> {
        let attributes = Window::default_attributes()
            .with_title("bvol · falling objects")
            .with_inner_size(PhysicalSize::new(size[0], size[1]));
        let window = Arc::new(event_loop.create_window(attributes).map_err(|e| e.to_string())?);
        let instance = render::instance();
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| GpuError::Surface(e.to_string()).to_string())?;
        let gpu = Gpu::new(&instance, Some(&surface)).map_err(|e| e.to_string())?;
        eprintln!("falling: windowed on {}", gpu.describe());
        let inner = window.inner_size();
        let mut config = surface
            .get_default_config(&gpu.adapter, inner.width.max(1), inner.height.max(1))
            .ok_or_else(|| GpuError::Surface("the adapter cannot draw to it".into()).to_string())?;
        // egui wants a non-sRGB target (it blends in gamma space).
        let caps = surface.get_capabilities(&gpu.adapter);
        if let Some(format) = caps.formats.iter().find(|f| !f.is_srgb()) {
            config.format = *format;
        }
        // Copies into the frame let the UI panel be drawn only now and then.
        let copies = caps.usages.contains(wgpu::TextureUsages::COPY_DST);
        if copies {
            config.usage |= wgpu::TextureUsages::COPY_DST;
        }
        surface.configure(&gpu.device, &config);
        let frontend = Frontend::new(&gpu, config.format, app, copies);
        let egui = egui_winit::State::new(
            frontend.ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        Ok(WindowState { window, surface, config, gpu, frontend, egui })
    }

    fn resize(&mut self, size: PhysicalSize<u32>) {
        self.config.width = size.width.max(1);
        self.config.height = size.height.max(1);
        self.surface.configure(&self.gpu.device, &self.config);
    }

    /// Draws one frame; `None` when the surface gave no texture this time.
    fn draw(&mut self, app: &mut App) -> Result<Option<crate::app::FrameRecord>, String> {
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.resize(self.window.inner_size());
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(None);
            }
            other => return Err(format!("the window's surface failed: {other:?}")),
        };
        let start = Instant::now();
        let input = self.egui.take_egui_input(&self.window);
        let (mut record, platform) = self.frontend.frame(app, &self.gpu, &texture.texture, input);
        self.egui.handle_platform_output(&self.window, platform);
        self.gpu.queue.present(texture);
        record.frame = start.elapsed();
        record.render = record.frame.saturating_sub(record.physics);
        Ok(Some(record))
    }
}

impl ApplicationHandler for Handler {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        match WindowState::new(event_loop, &self.app, self.run.size) {
            Ok(state) => self.window = Some(state),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(state) = &mut self.window else { return };
        let _ = state.egui.on_window_event(&state.window, &event);
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => state.resize(size),
            WindowEvent::RedrawRequested => match state.draw(&mut self.app) {
                Ok(Some(record)) => {
                    self.log.push(&record);
                    self.app.record(record);
                    self.drawn += 1;
                    if self.run.frames.is_some_and(|n| self.drawn >= n) {
                        event_loop.exit();
                    }
                }
                Ok(None) => {}
                Err(e) => {
                    self.error = Some(e);
                    event_loop.exit();
                }
            },
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(state) = &self.window {
            state.window.request_redraw();
        }
    }
}
