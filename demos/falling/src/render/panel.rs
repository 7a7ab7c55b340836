//! The controls panel drawn now and then, copied into every frame.
//!
//! A software rasteriser pays for every pixel of egui's textured shader, and
//! on lavapipe a panel drawn anew every frame takes a large share of it. Its
//! figures only need to change a few times a second to be
//! readable, so its pixels are drawn into a cache when the user acts or
//! every [`PanelCache::REFRESH`], and copied into each frame, which is a plain
//! memory copy. Whatever egui draws outside the panel (pop-ups, the
//! selection label) is drawn into every frame as before.

use std::time::{Duration, Instant};

/// An image of the panel: the left `width` pixels of the target, its whole
/// height.
pub struct PanelCache {
    texture: Option<wgpu::Texture>,
    format: wgpu::TextureFormat,
    drawn: Option<Instant>,
    redraw: bool,
}

impl PanelCache {
    /// How often the panel is redrawn when nothing happens.
    pub const REFRESH: Duration = Duration::from_millis(200);

    /// An empty cache for targets of `format`.
    pub fn new(format: wgpu::TextureFormat) -> PanelCache {
        PanelCache { texture: None, format, drawn: None, redraw: true }
    }

    /// Asks for a redraw at the next frame (the user acted, or the frame is
    /// the one a screenshot keeps).
    pub fn invalidate(&mut self) {
        self.redraw = true;
    }

    /// Whether this frame redraws the panel into a cache of `size` pixels
    /// (and forgets the request); the texture is made anew when the size
    /// changed.
    pub fn begin(&mut self, device: &wgpu::Device, size: [u32; 2]) -> bool {
        let resized = self.texture.as_ref().is_none_or(|t| [t.width(), t.height()] != size);
        if resized {
            self.texture = Some(device.create_texture(&wgpu::TextureDescriptor {
                label: Some("panel"),
                size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: self.format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            }));
        }
        let stale = self.drawn.is_none_or(|t| t.elapsed() >= Self::REFRESH);
        let redraw = resized || stale || std::mem::take(&mut self.redraw);
        if redraw {
            self.drawn = Some(Instant::now());
        }
        redraw
    }

    /// The cache's view, to draw the panel into.
    pub fn view(&self) -> Option<wgpu::TextureView> {
        self.texture.as_ref().map(|t| t.create_view(&Default::default()))
    }

    /// Copies the panel, `width` pixels wide, into `target`'s left side.
    pub fn copy_into(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::Texture,
        width: u32,
    ) {
        let Some(texture) = &self.texture else { return };
        let width = width.min(texture.width()).min(target.width());
        let height = texture.height().min(target.height());
        if width == 0 || height == 0 {
            return;
        }
        encoder.copy_texture_to_texture(
            texture.as_image_copy(),
            target.as_image_copy(),
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
    }
}

/// Splits egui's primitives into those wholly inside the panel (left of
/// `width` pixels) and the rest, each in egui's order.
pub fn split(
    primitives: Vec<egui::ClippedPrimitive>,
    width: u32,
    pixels_per_point: f32,
) -> (Vec<egui::ClippedPrimitive>, Vec<egui::ClippedPrimitive>) {
    primitives.into_iter().partition(|p| p.clip_rect.max.x * pixels_per_point <= width as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn primitive(right: f32) -> egui::ClippedPrimitive {
        egui::ClippedPrimitive {
            clip_rect: egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(right, 50.0)),
            primitive: egui::epaint::Primitive::Mesh(Default::default()),
        }
    }

    #[test]
    fn split_keeps_only_whole_panel_primitives_and_the_order() {
        let rights = [100.0, 151.0, 150.0, 640.0, 20.0];
        let (inside, rest) = split(rights.map(primitive).to_vec(), 300, 2.0);
        let edges = |v: &[egui::ClippedPrimitive]| -> Vec<f32> {
            v.iter().map(|p| p.clip_rect.max.x).collect()
        };
        assert_eq!(edges(&inside), vec![100.0, 150.0, 20.0]);
        assert_eq!(edges(&rest), vec![151.0, 640.0]);
    }
}
