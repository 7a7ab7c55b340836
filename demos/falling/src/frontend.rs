//! One drawn frame, the same in a window and headless: advance the
//! simulation, lay out the UI, build the draw list, draw.

use std::time::Instant;

use egui::Rect;

use crate::app::{App, FrameRecord};
use crate::overlay;
use crate::render::{DrawList, Gpu, Renderer, UiFrame};
use crate::shapes::RenderMesh;

/// What draws the app: the renderer, the UI context, the reused draw list.
pub struct Frontend {
    renderer: Renderer,
    /// egui's context.
    pub ctx: egui::Context,
    list: DrawList,
    /// The last frame's world-to-clip matrix and 3D viewport (pixels: x, y,
    /// width, height), for what the stats file says of the image.
    pub last_view: (glam::Mat4, [f32; 4]),
}

impl Frontend {
    /// A frontend drawing `app`'s shapes into targets of `format`; targets
    /// that take copies (`COPY_DST`) get the controls panel from a cache
    /// ([`crate::render::PanelCache`]).
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        app: &App,
        targets_take_copies: bool,
    ) -> Frontend {
        // The full meshes, then the far ones: what overlay::build indexes.
        let entries = &app.library.entries;
        let meshes: Vec<&RenderMesh> =
            entries.iter().map(|e| &e.mesh).chain(entries.iter().map(|e| &e.far_mesh)).collect();
        let ctx = egui::Context::default();
        ctx.set_visuals(egui::Visuals::dark());
        Frontend {
            renderer: Renderer::new(gpu, format, &meshes, targets_take_copies),
            ctx,
            list: DrawList::default(),
            last_view: (glam::Mat4::IDENTITY, [0.0; 4]),
        }
    }

    /// Redraws the controls panel in the next frame (the frame a
    /// screenshot keeps shows the figures of its own step).
    pub fn refresh_panel(&mut self) {
        self.renderer.refresh_panel();
    }

    /// Runs one frame into `target`: the simulation steps it owes, the UI
    /// from `input` (any input redraws the panel), the scene and the UI
    /// drawn and submitted. Returns the frame's figures (frame time up to
    /// the submit: the caller adds presenting or waiting) and egui's
    /// platform output.
    pub fn frame(
        &mut self,
        app: &mut App,
        gpu: &Gpu,
        target: &wgpu::Texture,
        input: egui::RawInput,
    ) -> (FrameRecord, egui::PlatformOutput) {
        let start = Instant::now();
        let size = [target.width(), target.height()];
        if !input.events.is_empty() {
            self.renderer.refresh_panel();
        }
        let mut record = app.advance();
        let mut view = Rect::NOTHING;
        let output = self.ctx.run_ui(input, |ui| view = crate::ui::show(ui, app));
        let ppp = output.pixels_per_point;
        let viewport =
            [view.left() * ppp, view.top() * ppp, view.width() * ppp, view.height() * ppp];
        let seen_from = overlay::View {
            eye: app.camera.eye(),
            pixels_per_unit: app.camera.pixels_per_unit(viewport[3]),
        };
        overlay::build(app, &mut self.list, seen_from);
        let view_proj = app.camera.view_proj(view.width() / view.height().max(1.0));
        let ui = UiFrame {
            primitives: self.ctx.tessellate(output.shapes, ppp),
            textures: output.textures_delta,
            pixels_per_point: ppp,
            // The panel fills the target's left side up to the 3D view.
            panel_width: (view.left() * ppp).ceil().clamp(0.0, size[0] as f32) as u32,
        };
        let viewport = clamp_viewport(viewport, size);
        self.last_view = (view_proj, viewport);
        self.renderer.render(gpu, target, (&self.list, view_proj, viewport), ui);
        record.frame = start.elapsed();
        record.render = record.frame.saturating_sub(record.physics);
        (record, output.platform_output)
    }
}

/// The viewport inside the target (wgpu rejects one that sticks out).
fn clamp_viewport([x, y, w, h]: [f32; 4], [width, height]: [u32; 2]) -> [f32; 4] {
    let (width, height) = (width as f32, height as f32);
    let (x, y) = (x.clamp(0.0, width), y.clamp(0.0, height));
    [x, y, w.clamp(0.0, width - x), h.clamp(0.0, height - y)]
}
