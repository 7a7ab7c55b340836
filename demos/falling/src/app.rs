//! The demo's state, independent of how it is shown: the shapes, the
//! simulation, what the user chose in the panels, the camera and the
//! history of per-frame figures.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use bvol::volumes::Pose;
use bvol::{BodyId, FitOptions, FrameStats, Shape};
use glam::{Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

use crate::camera::OrbitCamera;
use crate::shapes::ShapeLibrary;
use crate::sim::{Sim, SimConfig};

/// How many frames of figures the plot keeps (about 10 s at 60 fps).
pub const HISTORY: usize = 600;

/// What the user chose in the panels.
#[derive(Clone, Debug)]
pub struct Settings {
    /// The simulation is stopped.
    pub paused: bool,
    /// One step is asked for while paused.
    pub step_once: bool,
    /// Simulation steps per drawn frame (fractions skip frames).
    pub speed: f32,
    /// Draw every body's bounding sphere.
    pub show_spheres: bool,
    /// Draw every body's OBB.
    pub show_obbs: bool,
    /// Draw the trees' nodes whose depth lies in `tree_depths`.
    pub show_tree: bool,
    /// The depths of the tree nodes drawn, first and last.
    pub tree_depths: (usize, usize),
    /// Draw contact points and normals.
    pub show_contacts: bool,
    /// Per shape of the library, its weight in the mix of new bodies.
    pub mix: Vec<f32>,
    /// The bounds' fitting methods.
    pub fit: FitOptions,
}

/// The figures of one drawn frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameRecord {
    /// bvol's own counts and times of the last simulation step (zero when
    /// none ran).
    pub stats: FrameStats,
    /// Time in `World::update` (the collision pipeline) this frame.
    pub collision: Duration,
    /// Time of the whole simulation this frame (collision included).
    pub physics: Duration,
    /// Time of the rest: the UI's layout, the draw list, drawing.
    pub render: Duration,
    /// Time of the whole frame, UI included.
    pub frame: Duration,
    /// Bodies, the floor aside.
    pub bodies: usize,
    /// Of those, awake.
    pub awake: usize,
}

/// The demo.
pub struct App {
    /// The shapes bodies are made of.
    pub library: ShapeLibrary,
    /// The simulation and its bvol World.
    pub sim: Sim,
    /// The panels' choices.
    pub settings: Settings,
    /// The view.
    pub camera: OrbitCamera,
    /// The last [`HISTORY`] frames' figures, oldest first.
    pub history: VecDeque<FrameRecord>,
    /// The body clicked last.
    pub selected: Option<BodyId>,
    /// Messages for the user (bad assets, errors), also printed to stderr.
    pub log: Vec<String>,
    rng: SmallRng,
    /// Steps owed at a fractional speed.
    step_credit: f32,
}

impl App {
    /// A demo over `library`, with no bodies yet; random choices from `seed`.
    pub fn new(library: ShapeLibrary, seed: u64) -> App {
        let mut app = App {
            settings: Settings {
                paused: false,
                step_once: false,
                speed: 1.0,
                show_spheres: false,
                show_obbs: false,
                show_tree: false,
                tree_depths: (0, 4),
                show_contacts: false,
                mix: vec![1.0; library.entries.len()],
                fit: FitOptions::default(),
            },
            sim: Sim::new(SimConfig::default()),
            library,
            camera: OrbitCamera::default(),
            history: VecDeque::with_capacity(HISTORY),
            selected: None,
            log: Vec::new(),
            rng: SmallRng::seed_from_u64(seed),
            step_credit: 0.0,
        };
        for error in app.library.errors.clone() {
            app.report(error);
        }
        app
    }

    /// Shows a message in the UI's log and on stderr.
    pub fn report(&mut self, message: String) {
        eprintln!("falling: {message}");
        self.log.push(message);
    }

    /// Drops `n` more bodies from above the pile, their shapes drawn from
    /// the mix, in layers over a square that widens with the count.
    pub fn add_bodies(&mut self, n: usize) {
        let total: f32 = self.settings.mix.iter().sum();
        if total <= 0.0 || self.library.entries.is_empty() {
            self.report("no shape has a weight in the mix: nothing added".into());
            return;
        }
        let count = self.sim.bodies().len() + n;
        let half = ((count as f32).sqrt() * 0.3).clamp(4.0, self.sim.floor_half_extent() - 3.0);
        let spacing = 1.6;
        let per_row = ((2.0 * half / spacing) as usize).max(1);
        let top = self.sim.bodies().iter().map(|b| b.position.y).fold(2.0, f32::max);
        for k in 0..n {
            let (row, layer) = (k % (per_row * per_row), k / (per_row * per_row));
            let jitter = Vec3::new(self.rng.random(), 0.0, self.rng.random()) * 0.3;
            let position = Vec3::new(
                (row % per_row) as f32 * spacing - half,
                top + 3.0 + layer as f32 * spacing,
                (row / per_row) as f32 * spacing - half,
            ) + jitter;
            let axis = Vec3::new(self.rng.random(), self.rng.random(), self.rng.random());
            let rotation = Quat::from_scaled_axis((axis - 0.5) * 6.0);
            let index = self.pick_shape();
            let shape = self.library.entries[index].shape.clone();
            let velocity = Vec3::new(self.rng.random(), 0.0, self.rng.random()) - 0.5;
            if let Err(e) = self.sim.add_body(index, shape, Pose::new(position, rotation), velocity)
            {
                self.report(format!("could not add a body: {e}"));
                return;
            }
        }
    }

    /// A shape index drawn by the mix's weights.
    fn pick_shape(&mut self) -> usize {
        let total: f32 = self.settings.mix.iter().sum();
        let mut x = self.rng.random::<f32>() * total;
        for (i, w) in self.settings.mix.iter().enumerate() {
            if x < *w {
                return i;
            }
            x -= w;
        }
        self.settings.mix.iter().rposition(|w| *w > 0.0).unwrap_or(0)
    }

    /// Every body gone; the floor stays.
    pub fn reset(&mut self) {
        self.sim.reset();
        self.selected = None;
    }

    /// Refits every shape's bounds by `fit` and hands the bodies the new
    /// shapes; on failure the old ones stay and the log says why.
    pub fn set_fit(&mut self, fit: FitOptions) {
        if let Err(e) = self.library.set_fit(fit) {
            self.report(format!("fitting with {} / {} failed: {e}", fit.sphere, fit.obb));
            return;
        }
        let shapes: Vec<Arc<Shape>> =
            self.library.entries.iter().map(|e| e.shape.clone()).collect();
        match self.sim.replace_shapes(&shapes) {
            Ok(()) => self.settings.fit = fit,
            Err(e) => {
                self.report(format!("could not hand the bodies their shapes fitted anew: {e}"))
            }
        }
        self.selected = None;
    }

    /// Runs the simulation steps this frame owes (by speed and pause) and
    /// returns this frame's figures, render and frame times left at zero.
    pub fn advance(&mut self) -> FrameRecord {
        let steps = if self.settings.paused {
            usize::from(std::mem::take(&mut self.settings.step_once))
        } else {
            self.step_credit += self.settings.speed;
            let whole = self.step_credit.floor();
            self.step_credit -= whole;
            whole as usize
        };
        let mut record = FrameRecord::default();
        let start = Instant::now();
        for _ in 0..steps {
            record.stats = self.sim.step();
            record.collision += self.sim.collision_time();
        }
        record.physics = start.elapsed();
        record.bodies = self.sim.bodies().len();
        record.awake = self.sim.bodies().iter().filter(|b| !b.asleep).count();
        if self.selected.is_some_and(|id| self.sim.world().pose(id).is_err()) {
            self.selected = None;
        }
        record
    }

    /// Keeps a frame's figures for the plot.
    pub fn record(&mut self, record: FrameRecord) {
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(record);
    }

    /// Selects the body under the viewport point `at` (0..1 from its top
    /// left), or none.
    pub fn pick(&mut self, aspect: f32, at: glam::Vec2) {
        let (origin, direction) = self.camera.ray(aspect, at);
        let ray = bvol::volumes::Ray::new(origin, direction);
        self.selected = self.sim.world().ray_cast(&ray, 1e4).map(|hit| hit.body);
        if self.selected.is_some_and(|id| self.sim.world().kind(id) == Ok(bvol::BodyKind::Static)) {
            self.selected = None;
        }
    }
}
