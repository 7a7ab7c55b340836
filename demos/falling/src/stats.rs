//! The per-frame figures written by `--stats FILE` (JSON).

use std::path::Path;
use std::time::Duration;

use glam::Mat4;
use serde_json::{Value, json};

use crate::app::{App, FrameRecord};

/// The figures of every frame of a run, and what the run was.
#[derive(Default)]
pub struct StatsLog {
    frames: Vec<Value>,
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl StatsLog {
    /// Keeps one frame's figures.
    pub fn push(&mut self, record: &FrameRecord) {
        let s = &record.stats;
        self.frames.push(json!({
            "bodies": record.bodies,
            "awake": record.awake,
            "moved": s.moved,
            "candidates": s.candidates,
            "after_spheres": s.after_spheres,
            "after_obbs": s.after_obbs,
            "touching": s.touching,
            "bounds_ms": ms(s.bounds_time),
            "broadphase_ms": ms(s.broadphase_time),
            "spheres_ms": ms(s.spheres_time),
            "obbs_ms": ms(s.obbs_time),
            "narrow_ms": ms(s.narrow_time),
            "collision_ms": ms(record.collision),
            "physics_ms": ms(record.physics),
            "render_ms": ms(record.render),
            "frame_ms": ms(record.frame),
        }));
    }

    /// Writes the run as JSON: `mode` and `adapter`, every frame, a summary
    /// (mean frames per second, the collision's share of the frame), the
    /// last frame's camera (`view`: column-major world-to-clip matrix and the
    /// 3D viewport in pixels), the messages shown to the user, and `end`: the
    /// bodies' kinds and poses and the touching pairs at the end.
    pub fn write(
        &self,
        path: &Path,
        (mode, adapter): (&str, &str),
        app: &App,
        (view_proj, viewport): (Mat4, [f32; 4]),
    ) -> Result<(), String> {
        let total: f64 = self.frames.iter().map(|f| f["frame_ms"].as_f64().unwrap_or(0.0)).sum();
        let collision: f64 =
            self.frames.iter().map(|f| f["collision_ms"].as_f64().unwrap_or(0.0)).sum();
        let fps = if total > 0.0 { self.frames.len() as f64 * 1e3 / total } else { 0.0 };
        let share = if total > 0.0 { collision / total } else { 0.0 };
        let doc = json!({
            "mode": mode,
            "adapter": adapter,
            "frames": self.frames,
            "summary": { "frames": self.frames.len(), "fps": fps, "collision_share": share },
            "view": { "view_proj": view_proj.to_cols_array(), "viewport": viewport },
            "messages": app.log,
            "end": end_state(app),
        });
        let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
        std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
    }
}

/// Every body's shape index, kind and pose as the World has them, and the
/// touching pairs of the last step by body slot.
fn end_state(app: &App) -> Value {
    let world = app.sim.world();
    let bodies: Vec<Value> = app
        .sim
        .bodies()
        .iter()
        .filter_map(|b| {
            let pose = world.pose(b.id).ok()?;
            let kind = world.kind(b.id).ok()?;
            Some(json!({
                "slot": b.id.index(),
                "shape": b.shape,
                "kind": format!("{kind:?}"),
                "position": pose.position.to_array(),
                "rotation": pose.rotation.to_array(),
            }))
        })
        .collect();
    let pairs: Vec<[u32; 2]> =
        app.sim.contacts().iter().map(|(a, b, _)| [a.index(), b.index()]).collect();
    json!({ "bodies": bodies, "touching_pairs": pairs })
}
