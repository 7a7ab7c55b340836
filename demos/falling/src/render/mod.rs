//! Drawing a frame: the 3D scene, then egui over it, into a window's
//! surface texture or an offscreen image.

mod gpu;
mod offscreen;
mod panel;
mod scene;

pub use gpu::{Gpu, GpuError, INSTALL_SOFTWARE_VULKAN, instance};
pub use offscreen::{Offscreen, write_png};
pub use panel::PanelCache;
pub use scene::{CLEAR_COLOR, DrawList, Instance, LineVertex, SceneRenderer};

use glam::Mat4;

use crate::shapes::RenderMesh;

/// egui's output for one frame, ready to draw.
pub struct UiFrame {
    /// Tessellated shapes.
    pub primitives: Vec<egui::ClippedPrimitive>,
    /// Textures to upload and to free.
    pub textures: egui::TexturesDelta,
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
    /// Width in pixels of the opaque panel on the left (0: none): what the
    /// [`PanelCache`] keeps.
    pub panel_width: u32,
}

/// What draws a frame: the 3D pass and egui's.
pub struct Renderer {
    scene: SceneRenderer,
    egui: egui_wgpu::Renderer,
    /// The panel's cache, where targets take copies.
    panel: Option<PanelCache>,
}

impl Renderer {
    /// Renderers for targets of `format`, with every mesh uploaded. Targets
    /// that take copies (`COPY_DST`) get the panel from a cache.
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        meshes: &[&RenderMesh],
        targets_take_copies: bool,
    ) -> Renderer {
        Renderer {
            scene: SceneRenderer::new(&gpu.device, format, meshes),
            egui: egui_wgpu::Renderer::new(&gpu.device, format, Default::default()),
            panel: targets_take_copies.then(|| PanelCache::new(format)),
        }
    }

    /// Redraws the panel at the next frame, whatever its age.
    pub fn refresh_panel(&mut self) {
        if let Some(cache) = &mut self.panel {
            cache.invalidate();
        }
    }

    /// Draws the scene in `viewport` (pixels: x, y, width, height) and the UI
    /// over the whole `target`, and submits.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        target: &wgpu::Texture,
        scene: (&DrawList, Mat4, [f32; 4]),
        mut ui: UiFrame,
    ) {
        let (list, view_proj, viewport) = scene;
        let (device, queue) = (&gpu.device, &gpu.queue);
        let size = [target.width(), target.height()];
        let view = target.create_view(&Default::default());
        self.scene.prepare(device, queue, view_proj, list, size);
        for (id, deltas) in &ui.textures.set {
            for delta in deltas {
                self.egui.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: size,
            pixels_per_point: ui.pixels_per_point,
        };
        let primitives = std::mem::take(&mut ui.primitives);
        let (cached, rest) = match &mut self.panel {
            Some(cache) if ui.panel_width > 0 => {
                let (inside, rest) = panel::split(primitives, ui.panel_width, ui.pixels_per_point);
                if cache.begin(device, size)
                    && let Some(panel_view) = cache.view()
                {
                    // Its own submission: egui's buffers are rewritten below.
                    let mut encoder = device.create_command_encoder(&Default::default());
                    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
                    let extra = ui_pass(
                        &mut self.egui,
                        gpu,
                        &mut encoder,
                        (&panel_view, clear),
                        &inside,
                        &screen,
                    );
                    queue.submit(extra.into_iter().chain([encoder.finish()]));
                }
                (Some(ui.panel_width), rest)
            }
            _ => (None, primitives),
        };
        let mut encoder = device.create_command_encoder(&Default::default());
        self.scene.draw(&mut encoder, &view, viewport);
        if let (Some(width), Some(cache)) = (cached, &self.panel) {
            cache.copy_into(&mut encoder, target, width);
        }
        let load = wgpu::LoadOp::Load;
        let extra = ui_pass(&mut self.egui, gpu, &mut encoder, (&view, load), &rest, &screen);
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        for id in &ui.textures.free {
            self.egui.free_texture(id);
        }
        // Every delta is applied: tell egui (it checks, in debug builds).
        ui.textures.clear();
    }
}

/// Records egui's `primitives` into `target` (loaded or cleared first);
/// returns the command buffers egui needs submitted before the encoder's.
fn ui_pass(
    egui: &mut egui_wgpu::Renderer,
    gpu: &Gpu,
    encoder: &mut wgpu::CommandEncoder,
    (target, load): (&wgpu::TextureView, wgpu::LoadOp<wgpu::Color>),
    primitives: &[egui::ClippedPrimitive],
    screen: &egui_wgpu::ScreenDescriptor,
) -> Vec<wgpu::CommandBuffer> {
    let extra = egui.update_buffers(&gpu.device, &gpu.queue, encoder, primitives, screen);
    let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("egui"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    egui.render(&mut pass.forget_lifetime(), primitives, screen);
    extra
}
