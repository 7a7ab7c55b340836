//! Generated broadphase scenes: N moving boxes, deterministic from a seed, for
//! the pair benchmark and its tests. Each frame hands over every box; the
//! broadphase decides itself what moved.
//!
//! Densities are set so that the uniform scene has about one overlapping pair
//! per body, like the scenes behind ../shared/PEER_NOTES.md.

use std::fmt;
use std::str::FromStr;

use bvol::volumes::Aabb;
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// Which scene to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneKind {
    /// Unit boxes drifting at random in a closed box, bouncing off its walls.
    Uniform,
    /// The same motion, bodies gathered in 16 drifting clusters.
    Clustered,
    /// Uniform, with 1% of the bodies 20 times larger.
    Mixed,
    /// Bodies falling onto a floor and stacking into a pile that comes to rest.
    Pile,
    /// Uniform, with 1% of the bodies jumping anywhere each frame.
    Teleport,
    /// One layer of boxes resting side by side on a floor, each overlapping
    /// its eight neighbours a little (about four pairs a body, as a crowd
    /// or debris on flat ground), 1% of them sliding across the others.
    Flat,
    /// Bodies dropped over a floor a quarter of the pile's side, so that
    /// the heap grows sixteen times as tall.
    Heap,
    /// A static ground of flat tiles, eight bodies wide, and unit bodies
    /// drifting along it, half of them sunk into it: a static tree's case.
    Ground,
    /// Uniform, moving up to three times their size each frame.
    Fast,
}

impl SceneKind {
    /// Every scene.
    pub const ALL: [SceneKind; 9] = [
        SceneKind::Uniform,
        SceneKind::Clustered,
        SceneKind::Mixed,
        SceneKind::Pile,
        SceneKind::Teleport,
        SceneKind::Flat,
        SceneKind::Heap,
        SceneKind::Ground,
        SceneKind::Fast,
    ];

    /// The scene's name on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            SceneKind::Uniform => "uniform",
            SceneKind::Clustered => "clustered",
            SceneKind::Mixed => "mixed",
            SceneKind::Pile => "pile",
            SceneKind::Teleport => "teleport",
            SceneKind::Flat => "flat",
            SceneKind::Heap => "heap",
            SceneKind::Ground => "ground",
            SceneKind::Fast => "fast",
        }
    }
}

impl fmt::Display for SceneKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for SceneKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        SceneKind::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| {
            let names: Vec<&str> = SceneKind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown scene {s:?}; expected one of: {}", names.join(", "))
        })
    }
}

/// Half the side of an ordinary body.
const HALF: f32 = 0.5;
/// Distance an ordinary body moves per frame, at most.
const SPEED: f32 = 0.05;
/// Downward speed gained per frame in the pile.
const GRAVITY: f32 = 0.02;
/// The flat layer's spacing, as a share of a body's width: neighbours
/// overlap by 2% of it.
const FLAT_SPACING: f32 = 0.98;
/// Distance a fast body moves per frame, at most: three body widths.
const FAST_SPEED: f32 = 6.0 * HALF;

/// A running scene: call [`Scene::step`] for each frame's boxes.
///
/// ```
/// use bvol_cli::scenes::{Scene, SceneKind};
/// let mut a = Scene::new(SceneKind::Clustered, 1000, 7);
/// let mut b = Scene::new(SceneKind::Clustered, 1000, 7);
/// for _ in 0..3 {
///     assert_eq!(a.step(), b.step()); // deterministic from the seed
/// }
/// ```
#[derive(Clone, Debug)]
pub struct Scene {
    kind: SceneKind,
    rng: SmallRng,
    /// Side of the world cube (the pile's floor is `side` by `side`).
    side: f32,
    /// The far corner of the region bodies drift in, from the origin: the
    /// world cube, or the flat layer's extent.
    extent: Vec3,
    centres: Vec<Vec3>,
    velocities: Vec<Vec3>,
    halves: Vec<Vec3>,
    /// Cluster drift (clustered scene): each cluster's centre and velocity.
    clusters: Vec<(Vec3, Vec3)>,
    /// Pile: height of the column on each floor cell, and whether a body rests.
    heights: Vec<f32>,
    resting: Vec<bool>,
    frame: usize,
    boxes: Vec<Aabb>,
}

impl Scene {
    /// A scene of `n` bodies, deterministic from `seed`.
    pub fn new(kind: SceneKind, n: usize, seed: u64) -> Scene {
        let mut rng = SmallRng::seed_from_u64(seed ^ (kind as u64).wrapping_mul(0x9E37_79B9));
        // 4 n h^3 / L^3 pairs per body for uniform cubes of half side h: one at L = (32 n)^(1/3) h.
        let side = (32.0 * n.max(1) as f32).cbrt() * HALF;
        let mut halves = vec![Vec3::splat(HALF); n];
        if kind == SceneKind::Mixed {
            for h in halves.iter_mut().step_by(100) {
                *h = Vec3::splat(20.0 * HALF);
            }
        }
        let ground = ground_side(n);
        let tiles = ground_tiles(n);
        let tile = ground / (2.0 * tiles.max(1) as f32);
        if kind == SceneKind::Ground {
            halves[..tiles * tiles].fill(Vec3::new(tile, HALF, tile));
        }
        let row = flat_row(n);
        let flat_step = FLAT_SPACING * 2.0 * HALF;
        let clusters = (0..16)
            .map(|_| (random_in(&mut rng, side * 0.15, side * 0.85), random_dir(&mut rng) * SPEED))
            .collect::<Vec<_>>();
        let centres: Vec<Vec3> = (0..n)
            .map(|i| match kind {
                SceneKind::Clustered => {
                    let c = clusters[i % clusters.len()].0;
                    (c + gaussian3(&mut rng) * side * 0.04).clamp(Vec3::ZERO, Vec3::splat(side))
                }
                SceneKind::Pile | SceneKind::Heap => {
                    // Dropped in index order from rising heights: all fall alike, so
                    // lower bodies land first and the stacks build from the floor.
                    let p = random_in(&mut rng, 0.0, floor_side(kind, side));
                    Vec3::new(p.x, 2.0 * HALF + 2.0 * side * i as f32 / n as f32, p.z)
                }
                SceneKind::Flat => {
                    let jitter = random_in(&mut rng, -0.005, 0.005);
                    let cell = Vec3::new((i % row) as f32, 0.0, (i / row) as f32);
                    cell * flat_step + Vec3::new(jitter.x, HALF, jitter.z)
                }
                SceneKind::Ground if i < tiles * tiles => {
                    let cell = Vec3::new((i % tiles) as f32, 0.0, (i / tiles) as f32);
                    cell * 2.0 * tile + Vec3::new(tile, -HALF, tile)
                }
                SceneKind::Ground => {
                    let p = random_in(&mut rng, 0.0, ground);
                    Vec3::new(p.x, rng.random::<f32>() * 2.0 * HALF, p.z)
                }
                _ => random_in(&mut rng, 0.0, side),
            })
            .collect();
        let velocities = (0..n)
            .map(|i| match kind {
                SceneKind::Pile | SceneKind::Heap => Vec3::ZERO,
                SceneKind::Flat if i % 100 != 0 => Vec3::ZERO,
                SceneKind::Ground if i < tiles * tiles => Vec3::ZERO,
                SceneKind::Flat | SceneKind::Ground => {
                    flat_dir(&mut rng) * SPEED * rng.random::<f32>()
                }
                SceneKind::Fast => random_dir(&mut rng) * FAST_SPEED * rng.random::<f32>(),
                _ => random_dir(&mut rng) * SPEED * rng.random::<f32>(),
            })
            .collect();
        let cells = pile_cells(floor_side(kind, side));
        let layer = row as f32 * flat_step;
        let extent = match kind {
            SceneKind::Flat => Vec3::new(layer, side, layer),
            SceneKind::Ground => Vec3::new(ground, side, ground),
            _ => Vec3::splat(side),
        };
        Scene {
            kind,
            rng,
            side,
            extent,
            centres,
            velocities,
            halves,
            clusters,
            heights: vec![0.0; cells * cells],
            resting: vec![false; n],
            frame: 0,
            boxes: Vec::with_capacity(n),
        }
    }

    /// The scene's kind.
    pub fn kind(&self) -> SceneKind {
        self.kind
    }

    /// The boxes of the next frame (the first call gives the starting frame).
    pub fn step(&mut self) -> &[Aabb] {
        if self.frame > 0 {
            match self.kind {
                SceneKind::Pile | SceneKind::Heap => self.fall(),
                SceneKind::Clustered => self.drift_clusters(),
                _ => self.drift(),
            }
            if self.kind == SceneKind::Teleport {
                self.teleport();
            }
        }
        self.frame += 1;
        self.boxes.clear();
        self.boxes
            .extend(self.centres.iter().zip(&self.halves).map(|(&c, &h)| Aabb::new(c - h, c + h)));
        &self.boxes
    }

    /// Straight-line motion, bouncing off the walls of the region.
    fn drift(&mut self) {
        let extent = self.extent;
        for (c, v) in self.centres.iter_mut().zip(&mut self.velocities) {
            *c += *v;
            for axis in 0..3 {
                if c[axis] < 0.0 || c[axis] > extent[axis] {
                    v[axis] = -v[axis];
                    c[axis] = c[axis].clamp(0.0, extent[axis]);
                }
            }
        }
    }

    /// Clusters drift as wholes; their bodies jitter around them.
    fn drift_clusters(&mut self) {
        let side = self.side;
        for (c, v) in &mut self.clusters {
            *c += *v;
            for axis in 0..3 {
                if c[axis] < side * 0.1 || c[axis] > side * 0.9 {
                    v[axis] = -v[axis];
                }
            }
        }
        let k = self.clusters.len();
        for (i, (c, v)) in self.centres.iter_mut().zip(&self.velocities).enumerate() {
            *c += self.clusters[i % k].1 + *v * 0.2;
        }
    }

    /// Gravity until a body lands on the floor or on the column of bodies under
    /// its centre's floor cell; then it rests. Columns stack independently, so
    /// bodies in a column land in the order they were dropped.
    fn fall(&mut self) {
        let floor = floor_side(self.kind, self.side);
        let cells = pile_cells(floor);
        let cell = floor / cells as f32;
        let index = |v: f32| ((v / cell).max(0.0) as usize).min(cells - 1);
        for i in 0..self.centres.len() {
            if self.resting[i] {
                continue;
            }
            self.velocities[i].y -= GRAVITY;
            let (c, h) = (self.centres[i], self.halves[i]);
            let column = index(c.z) * cells + index(c.x);
            let ground = self.heights[column];
            let y = c.y + self.velocities[i].y;
            if y - h.y <= ground {
                self.centres[i].y = ground + h.y;
                self.resting[i] = true;
                self.heights[column] = ground + 2.0 * h.y;
            } else {
                self.centres[i].y = y;
            }
        }
    }

    /// 1% of the bodies, a different 1% each frame, jump anywhere.
    fn teleport(&mut self) {
        let n = self.centres.len();
        for _ in 0..n.div_ceil(100) {
            let i = self.rng.random_range(0..n);
            self.centres[i] = random_in(&mut self.rng, 0.0, self.side);
        }
    }
}

/// The side of the floor bodies fall on: the world's for the pile, a
/// quarter of it for the heap.
fn floor_side(kind: SceneKind, side: f32) -> f32 {
    if kind == SceneKind::Heap { side / 4.0 } else { side }
}

/// Bodies per row of the flat layer: a square.
fn flat_row(n: usize) -> usize {
    (n as f64).sqrt().ceil().max(1.0) as usize
}

/// The side of the ground: room for the bodies in a layer two wide at the
/// uniform scene's density (one pair a body).
fn ground_side(n: usize) -> f32 {
    (2.0 * n as f32).sqrt() * 2.0 * HALF
}

/// Ground tiles per side: eight body widths each, at most half the bodies
/// in all.
fn ground_tiles(n: usize) -> usize {
    let wide = (ground_side(n) / (16.0 * HALF)).round() as usize;
    wide.min(((n / 2) as f64).sqrt() as usize)
}

/// A random direction along the floor.
fn flat_dir(rng: &mut SmallRng) -> Vec3 {
    let g = gaussian3(rng);
    Vec3::new(g.x, 0.0, g.z).try_normalize().unwrap_or(Vec3::X)
}

/// Floor cells per side of the pile: one per body width.
fn pile_cells(side: f32) -> usize {
    ((side / (2.0 * HALF)) as usize).max(1)
}

fn random_in(rng: &mut SmallRng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(rng.random_range(lo..hi), rng.random_range(lo..hi), rng.random_range(lo..hi))
}

fn random_dir(rng: &mut SmallRng) -> Vec3 {
    gaussian3(rng).try_normalize().unwrap_or(Vec3::X)
}

/// Three standard normal deviates (Box-Muller).
fn gaussian3(rng: &mut SmallRng) -> Vec3 {
    let mut g = || {
        let (u, v): (f32, f32) = (rng.random::<f32>().max(1e-7), rng.random());
        (-2.0 * u.ln()).sqrt() * (std::f32::consts::TAU * v).cos()
    };
    Vec3::new(g(), g(), g())
}
