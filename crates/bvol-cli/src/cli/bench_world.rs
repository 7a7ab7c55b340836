//! `bvol bench world`: the whole frame of a [`World`] on a generated scene's
//! motion (the uniform scene's by default; a pile or a heap to time bodies
//! at rest), bodies of one mesh shape spinning slowly while they move: one
//! row per stage, with its pairs and milliseconds per frame; then the same
//! boxes through the tree alone, for the ratio of the whole frame to the
//! broadphase.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use bvol::tree::{PairCache, Tree};
use bvol::volumes::{Aabb, Pose};
use bvol::{BodyDesc, BodyId, FitOptions, FrameStats, Shape, World, WorldConfig};
use bvol_cli::scenes::{Scene, SceneKind};
use clap::Args;
use glam::{Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{RngExt, SeedableRng};

/// The world benchmark's options.
#[derive(Args, Debug)]
pub struct WorldArgs {
    /// Bodies.
    #[arg(long, default_value_t = 100_000)]
    n: usize,
    /// The bodies' shape: a Wavefront OBJ file (one convex part per object),
    /// scaled to the scene's body size. Default: a unit cube.
    #[arg(long)]
    shape: Option<PathBuf>,
    /// The scene whose boxes place the bodies: uniform, clustered, mixed,
    /// pile, teleport, flat, heap, ground or fast (a body sits at its box's
    /// centre, and turns only while it moves).
    #[arg(long, default_value = "uniform")]
    scene: SceneKind,
    /// Frames to time, after one to load the world and the settling ones.
    #[arg(long, default_value_t = 30)]
    frames: usize,
    /// Frames to run untimed first: a pile's bodies fall for about 120
    /// frames at 100 000 bodies before they all rest.
    #[arg(long, default_value_t = 0)]
    settle: usize,
    /// Seed of the scene.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Threads, 1 to 1024 (the output is the same for any).
    #[arg(long, default_value_t = 1, value_parser = super::threads)]
    threads: usize,
    /// The world's margin (`WorldConfig::margin`): bodies apart by at most
    /// this are in contact too. A body's bounding sphere has radius 0.75.
    #[arg(long, default_value_t = 0.0)]
    margin: f32,
    /// The world's reuse tolerance (`WorldConfig::reuse`): touching pairs
    /// that moved by at most this times their size reuse their contact
    /// feature.
    #[arg(long, default_value_t = 0.0)]
    reuse: f32,
    /// Each frame, every body is set about its scene pose, off by up to this
    /// times its radius on each axis and turned by this many radians about a
    /// random axis: a pile as a solver leaves it, jittering by a rounding.
    #[arg(long, default_value_t = 0.0)]
    jitter: f32,
}

/// The radius of a body's bounding sphere in the scene: its boxes are cubes
/// of half side 0.5, so about one contact a body, as in `bench pairs`.
const BODY_RADIUS: f32 = 0.75;
/// Spin per frame, radians.
const SPIN: f32 = 0.02;

pub fn run(args: WorldArgs) -> Result<(), String> {
    if args.frames == 0 || args.n < 2 {
        return Err("--frames must be at least 1, --n at least 2".into());
    }
    let shape = match &args.shape {
        Some(path) => {
            // The mesh's own errors name the file; the shape's name a part.
            let meshes = bvol::load_obj(path).map_err(|e| e.to_string())?;
            let in_file = |e: String| format!("{}: {e}", path.display());
            let shape = Shape::from_meshes(&meshes, FitOptions::default());
            scaled(&shape.map_err(|e| in_file(e.to_string()))?).map_err(in_file)?
        }
        None => Shape::cuboid(Vec3::splat(BODY_RADIUS / 3f32.sqrt())).map_err(|e| e.to_string())?,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .map_err(|e| e.to_string())?;
    let measured = pool.install(|| measure(&args, Arc::new(shape)))?;
    print(&measured, &args);
    Ok(())
}

/// The shape scaled about its sphere's centre so that the sphere's radius is
/// [`BODY_RADIUS`]. A shape read from an OBJ file has hull parts alone.
fn scaled(shape: &Shape) -> Result<Shape, String> {
    let s = shape.sphere();
    let k = BODY_RADIUS / s.radius;
    if !k.is_finite() {
        return Err(format!(
            "the shape (bounding radius {:e}) is too small to scale to a body of radius \
             {BODY_RADIUS} in f32",
            s.radius
        ));
    }
    let meshes: Vec<bvol::Mesh> = shape
        .parts()
        .iter()
        .filter_map(|p| match p {
            bvol::Part::Hull(h) => Some(bvol::Mesh {
                name: String::new(),
                positions: h.polyhedron.vertices().iter().map(|&v| (v - s.center) * k).collect(),
                triangles: Vec::new(),
            }),
            _ => None,
        })
        .collect();
    Shape::from_meshes(&meshes, FitOptions::default()).map_err(|e| e.to_string())
}

/// `pose` off by up to `jitter` times a body's radius on each axis, turned
/// by `jitter` radians about a random axis.
fn jittered(pose: &Pose, jitter: f32, rng: &mut SmallRng) -> Pose {
    let mut unit = || rng.random::<f32>() * 2.0 - 1.0;
    let off = Vec3::new(unit(), unit(), unit()) * jitter * BODY_RADIUS;
    let axis = Vec3::new(unit(), unit(), unit()).try_normalize().unwrap_or(Vec3::X);
    let turn = Quat::from_axis_angle(axis, jitter);
    Pose::new(pose.position + off, (turn * pose.rotation).normalize())
}

/// What a run measured: each timed frame's stats, the mean milliseconds per
/// frame of setting the poses (outside `update`), and of the tree alone.
struct Measured {
    totals: Vec<FrameStats>,
    poses_ms: f64,
    tree_ms: f64,
}

/// Runs the world, then the tree alone on the same leaf boxes.
fn measure(args: &WorldArgs, shape: Arc<Shape>) -> Result<Measured, String> {
    let mut scene = Scene::new(args.scene, args.n, args.seed);
    let config = WorldConfig::default().with_margin(args.margin).with_reuse(args.reuse);
    let mut world = World::with_config(config).map_err(|e| e.to_string())?;
    let mut rng = SmallRng::seed_from_u64(args.seed);
    let mut ids: Vec<BodyId> = Vec::with_capacity(args.n);
    let spins: Vec<Quat> =
        (0..args.n).map(|i| Quat::from_axis_angle(axis(i as u32), SPIN)).collect();
    let mut rotations: Vec<Quat> =
        (0..args.n).map(|i| Quat::from_axis_angle(axis(!(i as u32)), i as f32)).collect();
    let mut poses: Vec<Pose> = Vec::with_capacity(args.n);
    let mut centres: Vec<Vec3> = Vec::with_capacity(args.n);
    let mut totals = Vec::with_capacity(args.frames);
    let mut leaves: Vec<Vec<Aabb>> = Vec::new();
    let mut setting = Duration::ZERO;
    for f in 0..=args.settle + args.frames {
        let boxes = scene.step();
        let first = poses.is_empty();
        for (i, b) in boxes.iter().enumerate() {
            // A body at rest keeps its pose to the bit (or, jittered, its
            // scene pose).
            if first || b.center() != centres[i] {
                rotations[i] = (spins[i] * rotations[i]).normalize();
            }
        }
        centres.clear();
        centres.extend(boxes.iter().map(Aabb::center));
        poses.clear();
        poses.extend(boxes.iter().zip(&rotations).map(|(b, &r)| Pose::new(b.center(), r)));
        if args.jitter > 0.0 {
            for pose in &mut poses {
                *pose = jittered(pose, args.jitter, &mut rng);
            }
        }
        if f == 0 {
            for p in &poses {
                ids.push(
                    world.add_body(BodyDesc::new(shape.clone(), *p)).map_err(|e| e.to_string())?,
                );
            }
        } else {
            let started = Instant::now();
            world.set_poses(&ids, &poses).map_err(|e| e.to_string())?;
            if f > args.settle {
                setting += started.elapsed();
            }
        }
        let stats = *world.update();
        if f > args.settle {
            totals.push(stats);
            leaves.push(ids.iter().map(|&id| leaf(&world, id)).collect());
        }
    }
    // The broadphase alone on the same leaves, as `bench pairs` runs it:
    // its pairs kept in a cache, as the world keeps its moving bodies'.
    let mut tree = Tree::from_bounds(&leaves[0]).map_err(|e| e.to_string())?;
    let mut cache = PairCache::new();
    cache.update(&mut tree);
    let mut spent = Duration::ZERO;
    for frame in &leaves[1..] {
        let started = Instant::now();
        tree.update(frame).map_err(|e| e.to_string())?;
        cache.update(&mut tree);
        spent += started.elapsed();
    }
    let tree_ms = spent.as_secs_f64() * 1e3 / (leaves.len() - 1).max(1) as f64;
    let poses_ms = setting.as_secs_f64() * 1e3 / totals.len().max(1) as f64;
    Ok(Measured { totals, poses_ms, tree_ms })
}

/// The box the world gave a body in its broadphase.
fn leaf(world: &World, id: BodyId) -> Aabb {
    world.world_aabb(id).expect("every body is live")
}

/// A fixed pseudo-random unit axis for body `i`.
fn axis(i: u32) -> Vec3 {
    let h = |k: u32| {
        (i.wrapping_mul(0x9E37_79B9).wrapping_add(k).wrapping_mul(0x85EB_CA6B) >> 8) as f32
            / (1 << 24) as f32
            - 0.5
    };
    Vec3::new(h(1), h(2), h(3)).try_normalize().unwrap_or(Vec3::Y)
}

/// One row per stage: pairs and milliseconds per timed frame.
fn print(measured: &Measured, args: &WorldArgs) {
    let Measured { totals, poses_ms, tree_ms } = measured;
    let k = totals.len().max(1) as f64;
    let ms = |f: fn(&FrameStats) -> Duration| {
        totals.iter().map(|s| f(s).as_secs_f64()).sum::<f64>() * 1e3 / k
    };
    let count = |f: fn(&FrameStats) -> usize| totals.iter().map(f).sum::<usize>() as f64 / k;
    let bounds = ms(|s| s.bounds_time);
    let moved = count(|s| s.moved);
    println!("stage\tpairs_per_frame\tms_per_frame");
    println!("set poses ({} bodies)\t-\t{poses_ms:.3}", args.n);
    println!("world bounds ({moved:.0} bodies)\t-\t{bounds:.3}");
    println!("tree candidates\t{:.1}\t{:.3}", count(|s| s.candidates), ms(|s| s.broadphase_time));
    println!("after spheres\t{:.1}\t{:.3}", count(|s| s.after_spheres), ms(|s| s.spheres_time));
    println!("after OBBs\t{:.1}\t{:.3}", count(|s| s.after_obbs), ms(|s| s.obbs_time));
    println!("touching\t{:.1}\t{:.3}", count(|s| s.touching), ms(|s| s.narrow_time));
    println!("apart within the margin\t{:.1}\t-", count(|s| s.near));
    // Poses in, contacts out.
    let total = poses_ms + ms(|s| s.total_time());
    println!("whole frame\t-\t{total:.3}");
    println!("tree alone (bench pairs)\t-\t{tree_ms:.3}");
    println!(
        "# n {}, scene {}, {} frames after {} settling, {} threads, margin {}, reuse {}, jitter {}; \
         whole frame / tree alone = {:.2}; \
         bounds refit {:.1} M bodies/s, set poses + refit {:.1} M bodies/s",
        args.n,
        args.scene,
        totals.len(),
        args.settle,
        args.threads,
        args.margin,
        args.reuse,
        args.jitter,
        total / tree_ms,
        moved / bounds / 1e3,
        args.n as f64 / (poses_ms + bounds) / 1e3
    );
}
