//! The World's public API: any sequence of edits, updates and queries, given
//! to a world on the tree and to one on brute force.

use std::sync::{Arc, OnceLock};

use arbitrary::{Result, Unstructured};
use bvol::glam::{DVec3, Vec3};
use bvol::volumes::{Aabb, DPose, Pose, Ray};
use bvol::{
    BodyDesc, BodyId, BodyKind, Broadphase, BruteForce, FrameStats, Shape, Snapshot, World,
};

use crate::checks::{finite, one_line_error, unit};
use crate::floats;

/// Most operations in one input.
const MAX_OPS: usize = 256;

const KINDS: [BodyKind; 3] = [BodyKind::Dynamic, BodyKind::Static, BodyKind::Sleeping];

/// Runs the operations `data` spells on both worlds (poses in f32 and in
/// f64, the tree world now and then saved and loaded). After each: the same
/// answer from both (errors included, each one line, the body's pose left as
/// it was); after each update, the same counts and events, finite contacts
/// with unit normals, and the same ray hits and region queries. A snapshot
/// with any number in it replaced loads or is refused in one line.
pub fn run(data: &[u8]) {
    let u = &mut Unstructured::new(data);
    let mut pair = Pair { tree: World::new(), brute: World::<BruteForce>::default(), ids: vec![] };
    for _ in 0..MAX_OPS {
        if u.is_empty() || pair.step(u).is_err() {
            break;
        }
    }
}

struct Pair {
    tree: World,
    brute: World<BruteForce>,
    /// Every handle either world gave, removed ones included.
    ids: Vec<BodyId>,
}

impl Pair {
    fn step(&mut self, u: &mut Unstructured) -> Result<()> {
        let op = u.int_in_range(0u8..=13)?;
        // Edits of a body need one: the first is always an add.
        let op = if self.ids.is_empty() && matches!(op, 3..=7 | 11) { 0 } else { op };
        match op {
            0..=2 => {
                let shape = u.choose(shapes())?.clone();
                let kind = *u.choose(&KINDS)?;
                let desc = BodyDesc::new(shape, pose(u)?)
                    .with_kind(kind)
                    .with_filter(u.arbitrary()?, u.arbitrary()?)
                    .with_user_data(u.arbitrary()?);
                let id = same(self.tree.add_body(desc.clone()), self.brute.add_body(desc));
                self.ids.extend(id);
            }
            3 => {
                let id = self.pick(u)?;
                let _ = same(self.tree.remove_body(id), self.brute.remove_body(id));
            }
            4 => {
                let (id, pose) = (self.pick(u)?, pose(u)?);
                let before = self.tree.pose(id);
                let result = same(self.tree.set_pose(id, pose), self.brute.set_pose(id, pose));
                if result.is_err() {
                    assert_eq!(fmt(&self.tree.pose(id)), fmt(&before), "a refused pose moved it");
                }
            }
            5 => {
                let n = u.int_in_range(0..=self.ids.len())?;
                let ids = (0..n).map(|_| self.pick(u)).collect::<Result<Vec<_>>>()?;
                let mut poses = (0..n).map(|_| pose(u)).collect::<Result<Vec<_>>>()?;
                if u.ratio(1u8, 8)? {
                    poses.pop();
                }
                let _ = same(self.tree.set_poses(&ids, &poses), self.brute.set_poses(&ids, &poses));
            }
            6 => {
                let (id, kind) = (self.pick(u)?, *u.choose(&KINDS)?);
                let _ = same(self.tree.set_kind(id, kind), self.brute.set_kind(id, kind));
            }
            7 => {
                let (a, b) = (self.pick(u)?, self.pick(u)?);
                let contact = same(self.tree.contact(a, b), self.brute.contact(a, b));
                if let Ok(Some(c)) = contact {
                    unit(c.normal, "a contact normal");
                }
            }
            8 => self.queries(u)?,
            9 => self.update(),
            10 => self.add_cluster(u)?,
            11 => {
                let n = u.int_in_range(0..=self.ids.len())?;
                let ids = (0..n).map(|_| self.pick(u)).collect::<Result<Vec<_>>>()?;
                let poses = (0..n).map(|_| far_pose(u)).collect::<Result<Vec<_>>>()?;
                let (tree, brute) =
                    (self.tree.set_poses_f64(&ids, &poses), self.brute.set_poses_f64(&ids, &poses));
                let _ = same(tree, brute);
            }
            // The tree world saved and loaded: it goes on as the brute-force
            // one does.
            12 => {
                let loaded = World::from_snapshot(&self.tree.snapshot());
                self.tree = loaded.expect("a world's own snapshot loads");
            }
            _ => corrupted(&self.tree, u)?,
        }
        Ok(())
    }

    /// Up to 16 bodies of one shape and kind, half a unit apart around a
    /// point: a pile, in few bytes.
    fn add_cluster(&mut self, u: &mut Unstructured) -> Result<()> {
        let (shape, kind, centre) = (u.choose(shapes())?.clone(), *u.choose(&KINDS)?, pose(u)?);
        for k in 0..u.int_in_range(1..=16)? {
            let offset = Vec3::new((k % 4) as f32, (k / 4 % 2) as f32, (k / 8) as f32) * 0.5;
            let at = Pose::new(centre.position + offset, centre.rotation);
            let desc = BodyDesc::new(shape.clone(), at).with_kind(kind).with_user_data(k as u64);
            self.ids.extend(same(self.tree.add_body(desc.clone()), self.brute.add_body(desc)));
        }
        Ok(())
    }

    /// A handle either world gave: live, or removed (whose slot may since
    /// hold another body).
    fn pick(&self, u: &mut Unstructured) -> Result<BodyId> {
        Ok(*u.choose(&self.ids)?)
    }

    fn update(&mut self) {
        let (a, b) = (*self.tree.update(), *self.brute.update());
        assert_eq!(counts(&a), counts(&b), "the stages' counts differ");
        let (m, c, s, o, t) = counts(&a);
        assert!(t <= o && o <= s && s <= c, "counts grow down the stages: {:?}", (m, c, s, o, t));
        assert_eq!(fmt(&self.tree.events()), fmt(&self.brute.events()), "events differ");
        for e in self.tree.events() {
            if let Some(c) = e.contact {
                unit(c.normal, "a contact normal");
                assert!(c.depth.is_finite() && c.depth >= 0.0, "depth {}", c.depth);
                c.points().iter().for_each(|p| finite(p.position, "a contact point"));
            }
        }
        let keys: Vec<(u32, u32)> =
            self.tree.contacts().map(|(a, b, _)| (a.index(), b.index())).collect();
        assert!(keys.windows(2).all(|w| w[0] < w[1]), "contacts out of order");
    }

    fn queries(&self, u: &mut Unstructured) -> Result<()> {
        let ray = Ray::new(floats::position(u)?, floats::vec3(u)?);
        let max_t = floats::float(u)?;
        let hit = same_value(self.tree.ray_cast(&ray, max_t), self.brute.ray_cast(&ray, max_t));
        if let Some(hit) = hit {
            assert!(hit.t.is_finite() && hit.t >= 0.0 && hit.t <= max_t, "ray hit at {}", hit.t);
            finite(hit.point, "a ray hit");
        }
        let (p, q) = (floats::position(u)?, floats::vec3(u)?);
        let region = Aabb::new(p.min(q), p.max(q));
        assert_eq!(queried(&self.tree, &region), queried(&self.brute, &region), "queries differ");
        Ok(())
    }
}

/// The two worlds' answers, which must be the same; an error is one line.
fn same<T: std::fmt::Debug, E: std::fmt::Debug + std::fmt::Display>(
    tree: std::result::Result<T, E>,
    brute: std::result::Result<T, E>,
) -> std::result::Result<T, E> {
    assert_eq!(fmt(&tree), fmt(&brute), "the two worlds answer differently");
    if let Err(e) = &tree {
        one_line_error(&e.to_string(), None);
    }
    tree
}

fn same_value<T: std::fmt::Debug>(tree: T, brute: T) -> T {
    assert_eq!(fmt(&tree), fmt(&brute), "the two worlds answer differently");
    tree
}

/// Debug text: compares values that may hold NaN (a refused pose).
fn fmt(value: &impl std::fmt::Debug) -> String {
    format!("{value:?}")
}

fn counts(s: &FrameStats) -> (usize, usize, usize, usize, usize) {
    (s.moved, s.candidates, s.after_spheres, s.after_obbs, s.touching)
}

fn queried<B: Broadphase>(world: &World<B>, region: &Aabb) -> Vec<BodyId> {
    let mut found = Vec::new();
    world.query(region, |id| found.push(id));
    found.sort();
    found
}

/// A pose with an f64 position: any f32 one moved by a multiple of an
/// f64 step that no f32 has.
fn far_pose(u: &mut Unstructured) -> Result<DPose> {
    let step = DVec3::splat(f64::from(u.arbitrary::<i32>()?) * 0.377_777_777_777_777_7);
    Ok(DPose::new(floats::position(u)?.as_dvec3() + step, floats::rotation(u)?))
}

/// Loads a copy of `world`'s snapshot with one number in it replaced: a
/// world, which then updates, or a one-line error; never a panic.
fn corrupted(world: &World, u: &mut Unstructured) -> Result<()> {
    let mut value = serde_json::to_value(world.snapshot()).expect("a snapshot is JSON");
    let mut numbers = Vec::new();
    number_paths(&value, String::new(), &mut numbers);
    let Ok(path) = u.choose(&numbers) else { return Ok(()) };
    let number = if u.arbitrary()? {
        serde_json::json!(u.arbitrary::<i64>()?)
    } else {
        serde_json::json!(f64::from(floats::float(u)?))
    };
    *value.pointer_mut(path).expect("a path found in it") = number;
    let Ok(snapshot) = serde_json::from_value::<Snapshot>(value) else { return Ok(()) };
    match World::from_snapshot(&snapshot) {
        Ok(mut loaded) => {
            loaded.update();
        }
        Err(e) => one_line_error(&e.to_string(), None),
    }
    Ok(())
}

/// The JSON pointers of every number in `value`, under `at`.
fn number_paths(value: &serde_json::Value, at: String, out: &mut Vec<String>) {
    match value {
        serde_json::Value::Number(_) => out.push(at),
        serde_json::Value::Array(items) => {
            for (k, item) in items.iter().enumerate() {
                number_paths(item, format!("{at}/{k}"), out);
            }
        }
        serde_json::Value::Object(fields) => {
            for (key, item) in fields {
                number_paths(item, format!("{at}/{key}"), out);
            }
        }
        _ => {}
    }
}

fn pose(u: &mut Unstructured) -> Result<Pose> {
    Ok(Pose::new(floats::position(u)?, floats::rotation(u)?))
}

/// Shapes of each kind at sizes from 1e-3 to 1e3.
fn shapes() -> &'static [Arc<Shape>] {
    static SHAPES: OnceLock<Vec<Arc<Shape>>> = OnceLock::new();
    SHAPES.get_or_init(|| {
        [
            Shape::cuboid(Vec3::new(1.0, 0.5, 0.25)),
            Shape::ball(0.5),
            Shape::capsule(0.3, 0.6),
            Shape::tetrahedron(0.7),
            Shape::cuboid(Vec3::splat(1e-3)),
            Shape::ball(1e3),
        ]
        .into_iter()
        .map(|s| Arc::new(s.expect("a valid primitive")))
        .collect()
    })
}
