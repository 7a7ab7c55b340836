//! Drawing a frame: the 3D scene, then egui over it, into a window's
//! surface texture or an offscreen image.

mod gpu;
mod offscreen;
mod scene;

pub use gpu::{Gpu, GpuError, INSTALL_SOFTWARE_VULKAN, instance};
pub use offscreen::{Offscreen, write_png};
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
}

/// What draws a frame: the 3D pass and egui's.
pub struct Renderer {
    scene: SceneRenderer,
    egui: egui_wgpu::Renderer,
}

impl Renderer {
    /// Renderers for targets of `format`, with every mesh uploaded.
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat, meshes: &[&RenderMesh]) -> Renderer {
        Renderer {
            scene: SceneRenderer::new(&gpu.device, format, meshes),
            egui: egui_wgpu::Renderer::new(&gpu.device, format, Default::default()),
        }
    }

    /// Draws the scene in `viewport` (pixels: x, y, width, height) and the UI
    /// over the whole `target` of `size` pixels, and submits.
    pub fn render(
        &mut self,
        gpu: &Gpu,
        target: &wgpu::TextureView,
        size: [u32; 2],
        scene: (&DrawList, Mat4, [f32; 4]),
        mut ui: UiFrame,
    ) {
        let (list, view_proj, viewport) = scene;
        let (device, queue) = (&gpu.device, &gpu.queue);
        self.scene.prepare(device, queue, view_proj, list, size);
        for (id, deltas) in &ui.textures.set {
            for delta in deltas {
                self.egui.update_texture(device, queue, *id, delta);
            }
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        self.scene.draw(&mut encoder, target, viewport);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: size,
            pixels_per_point: ui.pixels_per_point,
        };
        let extra = self.egui.update_buffers(device, queue, &mut encoder, &ui.primitives, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            self.egui.render(&mut pass.forget_lifetime(), &ui.primitives, &screen);
        }
        queue.submit(extra.into_iter().chain([encoder.finish()]));
        for id in &ui.textures.free {
            self.egui.free_texture(id);
        }
        // Every delta is applied: tell egui (it checks, in debug builds).
        ui.textures.clear();
    }
}
