//! Headless runs: an offscreen image, N frames, then the screenshot and the
//! per-frame figures.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use crate::app::App;
use crate::frontend::Frontend;
use crate::render::{self, Gpu, Offscreen};
use crate::stats::StatsLog;

/// What a headless run does.
pub struct HeadlessRun {
    /// Frames to draw.
    pub frames: usize,
    /// Image size in pixels.
    pub size: [u32; 2],
    /// Where the last frame goes as PNG.
    pub screenshot: Option<PathBuf>,
    /// Where the per-frame figures go as JSON.
    pub stats: Option<PathBuf>,
}

/// Runs `app` headless; errors are one line for the user.
pub fn run(mut app: App, run: HeadlessRun) -> Result<(), String> {
    let instance = render::instance();
    let gpu = Gpu::new(&instance, None).map_err(|e| e.to_string())?;
    eprintln!("falling: headless on {}", gpu.describe());
    let target = Offscreen::new(&gpu, run.size);
    let mut frontend = Frontend::new(&gpu, Offscreen::FORMAT, &app, true);
    let mut log = StatsLog::default();
    let started = Instant::now();
    for frame in 0..run.frames {
        let input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(run.size[0] as f32, run.size[1] as f32),
            )),
            time: Some(frame as f64 / 60.0),
            predicted_dt: 1.0 / 60.0,
            ..Default::default()
        };
        let start = Instant::now();
        if frame + 1 == run.frames {
            frontend.refresh_panel();
        }
        let (mut record, _) = frontend.frame(&mut app, &gpu, &target.texture, input);
        // Wait for the GPU, so a frame's time is the whole of it.
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| e.to_string())?;
        record.frame = start.elapsed();
        record.render = record.frame.saturating_sub(record.physics);
        log.push(&record);
        app.record(record);
    }
    let elapsed = started.elapsed();
    report(&app, run.frames, elapsed);
    if let Some(path) = &run.screenshot {
        let pixels = target.read(&gpu)?;
        render::write_png(path, run.size, &pixels)?;
    }
    if let Some(path) = &run.stats {
        log.write(path, ("headless", &gpu.describe()), &app, frontend.last_view)?;
    }
    Ok(())
}

/// One summary line on stderr.
fn report(app: &App, frames: usize, elapsed: Duration) {
    let fps = frames as f64 / elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "falling: {frames} frames in {:.2} s ({fps:.1} fps), {} bodies",
        elapsed.as_secs_f64(),
        app.sim.bodies().len()
    );
}
