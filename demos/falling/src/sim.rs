//! The demo's own rigid-body integrator, on top of bvol's contacts.
//!
//! One step (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005,
//! as Box2D's contact solver does it):
//! 1. sleeping bodies that an awake body touches fast wake up;
//! 2. gravity and damping act on the awake bodies' velocities;
//! 3. every contact point of the last [`World::update`] becomes a normal
//!    constraint (impulse `>= 0`, Baumgarte position bias past a slop,
//!    restitution above an approach speed) and two friction constraints
//!    (impulses within `mu` times the normal one), and each touching pair a
//!    rolling-resistance constraint; all are warm-started with last step's
//!    impulses (points matched by position in body A's frame) and solved by
//!    sequential impulses, sleeping bodies and the floor immovable;
//! 4. positions integrate; bodies slow on average for `sleep_time` fall
//!    asleep (the world keeps them with the static bodies);
//! 5. the awake bodies' poses go to the world in one `set_poses` call, and
//!    the world's update finds the contacts of the next step (and wakes a
//!    sleeping body whose contact with an awake one ended).
//!
//! Nothing allocates per step once the reused buffers have grown (the
//! world's update aside), and nothing depends on hash order: pairs are
//! solved in the world's event order, the warm-start map is only looked up.
//!
//! A body's origin is its centre of mass: [`crate::shapes`] centres every
//! shape so. Density is 1, so a body's mass is its volume.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use bvol::narrow::Contact;
use bvol::volumes::Pose;
use bvol::{BodyDesc, BodyId, BodyKind, EventKind, FrameStats, Shape, World, WorldError};
use glam::{Mat3, Quat, Vec3};

/// Half the side of the square floor.
const FLOOR_HALF_EXTENT: f32 = 25.0;
/// Half the floor's thickness: thick, so that a fast body cannot pass its
/// middle in one step and be pushed out below (1 unit a step is 60 m/s).
const FLOOR_HALF_THICKNESS: f32 = 1.0;
/// A body that fell off the floor is parked asleep once it is this far below
/// it, so that its numbers stay bounded.
const FALL_LIMIT: f32 = 50.0;
/// The most a body moves and turns in one step (Box2D's `b2_maxTranslation`
/// and `b2_maxRotation`): a bound that keeps a bad contact from launching it.
const MAX_TRANSLATION: f32 = 2.0;
/// The most a body turns in one step (rad).
const MAX_ROTATION: f32 = 0.25 * std::f32::consts::PI;
/// Time constant (s) of the velocity average the sleep test reads: a body
/// wedged between sleeping ones may rock a little each step, one way then
/// the other, as its contacts switch features; on average it is still.
const SLEEP_SMOOTHING: f32 = 0.1;
/// Contact points of a pair, this step and the last, are the same point for
/// warm starting when they are this close in body A's frame.
const WARM_MATCH_DISTANCE: f32 = 0.1;
/// Solver index of "no body": the floor, and anything static.
const STATIC: u32 = u32::MAX;

/// The simulation's tunables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimConfig {
    /// Acceleration of gravity (m/s²).
    pub gravity: Vec3,
    /// Time step (s).
    pub dt: f32,
    /// Velocity iterations of the contact solver per step.
    pub iterations: usize,
    /// Coefficient of restitution of every contact.
    pub restitution: f32,
    /// Approach speed (m/s) under which contacts do not bounce: resting
    /// contacts would jitter otherwise (Box2D's `b2_velocityThreshold`).
    pub restitution_threshold: f32,
    /// Coefficient of friction of every contact.
    pub friction: f32,
    /// Rolling resistance (m): the most angular impulse a contact resists
    /// relative turning with, per unit of normal impulse (Box2D v3's
    /// `rollingResistance`, a lever arm here). Without it a ball rolls on
    /// forever and a rounded mesh rocks for long.
    pub rolling_resistance: f32,
    /// Fraction of the penetration past `slop` removed per step (Baumgarte).
    pub baumgarte: f32,
    /// Penetration (m) left alone, so that resting contacts persist.
    pub slop: f32,
    /// Cap (m/s) on the speed the position bias asks for: deep overlaps
    /// separate over several steps instead of exploding.
    pub max_bias_speed: f32,
    /// Linear damping (1/s), as Box2D's `linearDamping`.
    pub linear_damping: f32,
    /// Angular damping (1/s).
    pub angular_damping: f32,
    /// A body slower than this (m/s) ...
    pub sleep_linear_speed: f32,
    /// ... and turning slower than this (rad/s) ...
    pub sleep_angular_speed: f32,
    /// ... for this long (s) falls asleep.
    pub sleep_time: f32,
    /// A sleeping body wakes when a touching awake body moves faster than
    /// this (m/s) relative to it at a contact point.
    pub wake_speed: f32,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            dt: 1.0 / 60.0,
            iterations: 10,
            restitution: 0.2,
            restitution_threshold: 1.0,
            friction: 0.6,
            rolling_resistance: 0.05,
            baumgarte: 0.2,
            slop: 0.005,
            max_bias_speed: 4.0,
            linear_damping: 0.05,
            angular_damping: 0.1,
            sleep_linear_speed: 0.08,
            sleep_angular_speed: 0.15,
            sleep_time: 0.5,
            wake_speed: 0.5,
        }
    }
}

/// A dynamic body: its handle in the world, its shape and its motion.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its handle in [`Sim::world`]; its user data there is its index in
    /// [`Sim::bodies`].
    pub id: BodyId,
    /// Index of its shape in the shape library.
    pub shape: usize,
    /// Position of its origin, the centre of mass.
    pub position: Vec3,
    /// Orientation (unit).
    pub rotation: Quat,
    /// Linear velocity (m/s).
    pub velocity: Vec3,
    /// Angular velocity (rad/s), in world axes.
    pub angular_velocity: Vec3,
    /// Whether it sleeps: it neither moves nor is moved until woken.
    pub asleep: bool,
    inv_mass: f32,
    /// Inverse inertia about the origin, in the body's axes.
    inv_inertia: Mat3,
    /// How long it has been slow enough to sleep (s).
    still_time: f32,
    /// Linear and angular velocity averaged over about [`SLEEP_SMOOTHING`]:
    /// what the sleep test reads.
    mean_velocity: Vec3,
    mean_angular_velocity: Vec3,
}

impl Body {
    /// The body's pose.
    pub fn pose(&self) -> Pose {
        Pose::new(self.position, self.rotation)
    }
}

/// What the solver reads and writes of a body: zero inverse mass for the
/// floor and sleeping bodies, so that nothing moves them.
#[derive(Clone, Copy, Debug)]
struct SolverBody {
    velocity: Vec3,
    angular_velocity: Vec3,
    inv_mass: f32,
    /// In world axes.
    inv_inertia: Mat3,
}

impl SolverBody {
    /// A body nothing moves. (Not `Default`: glam's default matrix is the
    /// identity, an inverse inertia that would let the floor spin.)
    const FIXED: SolverBody = SolverBody {
        velocity: Vec3::ZERO,
        angular_velocity: Vec3::ZERO,
        inv_mass: 0.0,
        inv_inertia: Mat3::ZERO,
    };

    /// Velocity of the point at `r` from the centre of mass.
    fn point_velocity(&self, r: Vec3) -> Vec3 {
        self.velocity + self.angular_velocity.cross(r)
    }

    /// Applies `impulse` at `r` from the centre of mass.
    fn apply(&mut self, r: Vec3, impulse: Vec3) {
        self.velocity += impulse * self.inv_mass;
        self.angular_velocity += self.inv_inertia * r.cross(impulse);
    }

    /// Applies an angular impulse.
    fn apply_angular(&mut self, impulse: Vec3) {
        self.angular_velocity += self.inv_inertia * impulse;
    }

    /// `r x d . I⁻¹ (r x d)`: the rotational part of the effective mass
    /// along `d`.
    fn angular_mass(&self, r: Vec3, d: Vec3) -> f32 {
        let rd = r.cross(d);
        rd.dot(self.inv_inertia * rd)
    }
}

/// One contact point as a constraint (Box2D's `b2ContactConstraintPoint`).
#[derive(Clone, Copy, Debug, Default)]
struct PointConstraint {
    /// The point in body A's frame (the world's for the floor): how the next
    /// step finds it again for warm starting.
    anchor: Vec3,
    /// From each body's centre of mass to the point.
    ra: Vec3,
    rb: Vec3,
    normal_mass: f32,
    tangent_mass: [f32; 2],
    /// Separating speed the normal constraint aims at (position bias or
    /// restitution).
    bias: f32,
    normal_impulse: f32,
    tangent_impulse: [f32; 2],
}

/// The constraints of one touching pair.
#[derive(Clone, Copy, Debug, Default)]
struct Manifold {
    /// Solver indices of the bodies ([`STATIC`] for the floor), `a` first
    /// as the world orders them: the warm-start key.
    a: u32,
    b: u32,
    /// Unit normal from A to B, and two unit tangents across it.
    normal: Vec3,
    tangents: [Vec3; 2],
    points: [PointConstraint; 4],
    count: usize,
    /// Inverse of the pair's angular inverse inertia, and the accumulated
    /// angular impulse of rolling resistance (on B; A gets the opposite).
    rolling_mass: Mat3,
    rolling_impulse: Vec3,
}

/// The simulation: a [`World`] with a static floor (its top face at y = 0)
/// and the dynamic bodies on it.
#[derive(Debug)]
pub struct Sim {
    config: SimConfig,
    world: World,
    bodies: Vec<Body>,
    /// Body index of each world slot, [`STATIC`] for the floor and free slots.
    body_at_slot: Vec<u32>,
    /// Solver state by body index, then one static entry for the floor.
    solver: Vec<SolverBody>,
    manifolds: Vec<Manifold>,
    /// Last step's manifolds and where each pair is among them.
    previous: Vec<Manifold>,
    previous_at: HashMap<(u32, u32), usize>,
    contacts: Vec<(BodyId, BodyId, Contact)>,
    /// The awake bodies' handles and poses, for `set_poses`.
    ids: Vec<BodyId>,
    poses: Vec<Pose>,
    /// Bodies that fall asleep at the end of this step.
    falling_asleep: Vec<usize>,
    collision_time: Duration,
    solver_time: Duration,
}

/// The floor every [`Sim`] starts with: a static box whose top face is
/// y = 0, the first body of its world.
pub fn floor() -> BodyDesc {
    let half = Vec3::new(FLOOR_HALF_EXTENT, FLOOR_HALF_THICKNESS, FLOOR_HALF_EXTENT);
    let floor = Shape::cuboid(half).expect("the floor's sizes are finite and positive");
    let pose = Pose::new(Vec3::NEG_Y * FLOOR_HALF_THICKNESS, Quat::IDENTITY);
    BodyDesc::new(Arc::new(floor), pose).with_kind(BodyKind::Static)
}

impl Sim {
    /// A world with a static floor: a box whose top face is y = 0.
    pub fn new(config: SimConfig) -> Sim {
        let mut world = World::new();
        world.add_body(floor()).expect("an empty world takes a body at a finite pose");
        Sim {
            config,
            world,
            bodies: Vec::new(),
            body_at_slot: Vec::new(),
            solver: Vec::new(),
            manifolds: Vec::new(),
            previous: Vec::new(),
            previous_at: HashMap::new(),
            contacts: Vec::new(),
            ids: Vec::new(),
            poses: Vec::new(),
            falling_asleep: Vec::new(),
            collision_time: Duration::ZERO,
            solver_time: Duration::ZERO,
        }
    }

    /// The floor is a square of this half size, centred on the origin.
    pub fn floor_half_extent(&self) -> f32 {
        FLOOR_HALF_EXTENT
    }

    /// The tunables.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// The tunables, to change between steps.
    pub fn config_mut(&mut self) -> &mut SimConfig {
        &mut self.config
    }

    /// Adds an awake body of `shape` (entry `shape_index` of the library) at
    /// `pose`, moving at `velocity` (a non-finite velocity counts as zero).
    /// It touches others from the next step on.
    pub fn add_body(
        &mut self,
        shape_index: usize,
        shape: Arc<Shape>,
        pose: Pose,
        velocity: Vec3,
    ) -> Result<(), WorldError> {
        let rotation = unit(pose.rotation).unwrap_or(pose.rotation);
        let pose = Pose::new(pose.position, rotation);
        let (inv_mass, inv_inertia) = mass_properties(&shape);
        let index = self.bodies.len();
        let desc = BodyDesc::new(shape, pose).with_user_data(index as u64);
        let id = self.world.add_body(desc)?;
        self.bodies.push(Body {
            id,
            shape: shape_index,
            position: pose.position,
            rotation,
            velocity: if velocity.is_finite() { velocity } else { Vec3::ZERO },
            angular_velocity: Vec3::ZERO,
            asleep: false,
            inv_mass,
            inv_inertia,
            still_time: 0.0,
            mean_velocity: Vec3::ZERO,
            mean_angular_velocity: Vec3::ZERO,
        });
        self.map_slot(id, index);
        Ok(())
    }

    /// Removes every body but the floor.
    pub fn reset(&mut self) {
        for body in self.bodies.iter().rev() {
            // Every handle in `bodies` is live: removing it cannot fail.
            self.world.remove_body(body.id).ok();
        }
        self.bodies.clear();
        self.body_at_slot.fill(STATIC);
        self.manifolds.clear();
        self.previous.clear();
        self.previous_at.clear();
        self.contacts.clear();
    }

    /// After the library's bounds were fitted anew: body `i` gets
    /// `shapes[body.shape]` (bodies whose index has no shape keep theirs),
    /// with its pose, motion, sleep and warm-start impulses kept. bvol has no call to change a
    /// body's shape, so each body is removed and added again (same slot, new
    /// handle); the world is updated once so that
    /// [`contacts`](Sim::contacts) names the new handles. Fails only if the
    /// world refuses a body it held a moment before.
    pub fn replace_shapes(&mut self, shapes: &[Arc<Shape>]) -> Result<(), WorldError> {
        let mut new_shapes = Vec::with_capacity(self.bodies.len());
        for body in &self.bodies {
            new_shapes.push(match shapes.get(body.shape) {
                Some(shape) => shape.clone(),
                None => self.world.shape(body.id)?.clone(),
            });
        }
        // Removed last first, the slots are taken again in the same order.
        for body in self.bodies.iter().rev() {
            self.world.remove_body(body.id)?;
        }
        self.body_at_slot.fill(STATIC);
        for (index, shape) in new_shapes.into_iter().enumerate() {
            let body = &mut self.bodies[index];
            (body.inv_mass, body.inv_inertia) = mass_properties(&shape);
            let kind = if body.asleep { BodyKind::Sleeping } else { BodyKind::Dynamic };
            let desc =
                BodyDesc::new(shape, body.pose()).with_kind(kind).with_user_data(index as u64);
            body.id = self.world.add_body(desc)?;
            let id = body.id;
            self.map_slot(id, index);
        }
        self.update_world();
        Ok(())
    }

    /// One step: wake, solve, integrate, sleep, then [`World::update`] for
    /// the next step's contacts. Returns that update's counts and times.
    pub fn step(&mut self) -> FrameStats {
        let start = Instant::now();
        self.wake_touched();
        self.integrate_velocities();
        self.prepare_contacts();
        self.warm_start();
        for _ in 0..self.config.iterations {
            self.solve_contacts();
        }
        self.integrate_positions();
        self.update_sleep();
        self.send_poses();
        self.solver_time = start.elapsed();
        self.update_world()
    }

    /// The collision world: bounds, trees, stats.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The dynamic bodies, by index (the world's user data).
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The touching pairs of the last world update (this step's end), for
    /// overlays and counts. Pairs of two resting bodies (sleeping or the
    /// floor) are not tested, so not listed.
    pub fn contacts(&self) -> &[(BodyId, BodyId, Contact)] {
        &self.contacts
    }

    /// Time spent in [`World::update`] in the last step.
    pub fn collision_time(&self) -> Duration {
        self.collision_time
    }

    /// Time spent in the last step outside [`World::update`]: the solver,
    /// integration, sleeping and sending the poses.
    pub fn solver_time(&self) -> Duration {
        self.solver_time
    }

    /// Records that world slot `id.index()` holds body `index`.
    fn map_slot(&mut self, id: BodyId, index: usize) {
        let slot = id.index() as usize;
        if self.body_at_slot.len() <= slot {
            self.body_at_slot.resize(slot + 1, STATIC);
        }
        self.body_at_slot[slot] = index as u32;
    }

    /// The body index of a handle, [`STATIC`] for the floor and for a
    /// handle no longer live (the slot's generation tells).
    fn body_index(&self, id: BodyId) -> u32 {
        let index = self.body_at_slot.get(id.index() as usize).copied().unwrap_or(STATIC);
        match self.bodies.get(index as usize) {
            Some(body) if body.id == id => index,
            _ => STATIC,
        }
    }

    /// Runs the collision update and keeps its touching pairs.
    fn update_world(&mut self) -> FrameStats {
        let start = Instant::now();
        let stats = *self.world.update();
        self.collision_time = start.elapsed();
        self.contacts.clear();
        self.contacts
            .extend(self.world.events().iter().filter_map(|e| Some((e.a, e.b, e.contact?))));
        self.wake_left();
        stats
    }

    /// Wakes each sleeping body whose contact with an awake body ended: it
    /// may have lost what held it up (per body, Box2D would wake the island).
    fn wake_left(&mut self) {
        for k in 0..self.world.events().len() {
            let event = self.world.events()[k];
            if event.kind != EventKind::Ended {
                continue;
            }
            let (ia, ib) = (self.body_index(event.a), self.body_index(event.b));
            match (self.asleep(ia), self.asleep(ib)) {
                (Some(true), Some(false)) => self.wake(ia),
                (Some(false), Some(true)) => self.wake(ib),
                _ => {}
            }
        }
    }

    /// Wakes each sleeping body that an awake one touches moving faster than
    /// `wake_speed` relative to it at a contact point (hit, or pushed, or
    /// slid off). Per body, not per island: the bodies it touches then wake
    /// in turn when it moves them.
    fn wake_touched(&mut self) {
        for k in 0..self.contacts.len() {
            let (a, b, contact) = self.contacts[k];
            let (ia, ib) = (self.body_index(a), self.body_index(b));
            let (sleeper, mover) = match (self.asleep(ia), self.asleep(ib)) {
                (Some(true), Some(false)) => (ia, ib),
                (Some(false), Some(true)) => (ib, ia),
                _ => continue,
            };
            let m = &self.bodies[mover as usize];
            let fast = contact.points().iter().any(|p| {
                let v = m.velocity + m.angular_velocity.cross(p.position - m.position);
                v.length_squared() > self.config.wake_speed * self.config.wake_speed
            });
            if fast {
                self.wake(sleeper);
            }
        }
    }

    /// Wakes body `index`: it moves, and is moved, from this step on.
    fn wake(&mut self, index: u32) {
        let body = &mut self.bodies[index as usize];
        body.asleep = false;
        body.still_time = 0.0;
        body.mean_velocity = Vec3::ZERO;
        body.mean_angular_velocity = Vec3::ZERO;
        // A live handle: set_kind cannot fail.
        self.world.set_kind(body.id, BodyKind::Dynamic).ok();
    }

    /// Whether body `index` sleeps; `None` for the floor.
    fn asleep(&self, index: u32) -> Option<bool> {
        self.bodies.get(index as usize).map(|b| b.asleep)
    }

    /// Gravity and damping on the awake bodies, into the solver's state
    /// (Box2D's `b2Island::Solve`: damping as `v /= 1 + dt c`, stable at any
    /// step).
    fn integrate_velocities(&mut self) {
        let c = &self.config;
        let linear = 1.0 / (1.0 + c.dt * c.linear_damping);
        let angular = 1.0 / (1.0 + c.dt * c.angular_damping);
        self.solver.clear();
        self.solver.extend(self.bodies.iter().map(|body| {
            if body.asleep {
                return SolverBody::FIXED;
            }
            let r = Mat3::from_quat(body.rotation);
            SolverBody {
                velocity: (body.velocity + c.gravity * c.dt) * linear,
                angular_velocity: body.angular_velocity * angular,
                inv_mass: body.inv_mass,
                inv_inertia: r * body.inv_inertia * r.transpose(),
            }
        }));
        self.solver.push(SolverBody::FIXED); // the floor
    }

    /// The constraints of every touching pair, in the world's event order,
    /// their impulses warm-started from last step's (Box2D's
    /// `b2ContactSolver` initialisation).
    fn prepare_contacts(&mut self) {
        std::mem::swap(&mut self.manifolds, &mut self.previous);
        self.previous_at.clear();
        self.previous_at.extend(self.previous.iter().enumerate().map(|(i, m)| ((m.a, m.b), i)));
        self.manifolds.clear();
        for k in 0..self.contacts.len() {
            let (a, b, contact) = self.contacts[k];
            if let Some(m) = self.manifold(self.body_index(a), self.body_index(b), &contact) {
                self.manifolds.push(m);
            }
        }
    }

    /// The constraints of one pair, or `None` when neither body can move.
    fn manifold(&self, a: u32, b: u32, contact: &Contact) -> Option<Manifold> {
        let floor = self.solver.len() - 1;
        let solver_index = |i: u32| if i == STATIC { floor } else { i as usize };
        let (sa, sb) = (self.solver[solver_index(a)], self.solver[solver_index(b)]);
        let normal = contact.normal.try_normalize()?;
        if sa.inv_mass == 0.0 && sb.inv_mass == 0.0 {
            return None;
        }
        let (t1, t2) = normal.any_orthonormal_pair();
        let last = self.previous_at.get(&(a, b)).map(|&i| &self.previous[i]);
        let rolling = sa.inv_inertia + sb.inv_inertia;
        let rolling_mass =
            if rolling.determinant() > f32::EPSILON { rolling.inverse() } else { Mat3::ZERO };
        let mut m = Manifold {
            a,
            b,
            normal,
            tangents: [t1, t2],
            rolling_mass,
            rolling_impulse: last.map_or(Vec3::ZERO, |l| l.rolling_impulse),
            ..Manifold::default()
        };
        let (pa, pb) = (self.frame_of(a), self.frame_of(b));
        let c = &self.config;
        for point in contact.points().iter().take(m.points.len()) {
            let (ra, rb) = (point.position - pa.position, point.position - pb.position);
            let k_normal = sa.inv_mass
                + sb.inv_mass
                + sa.angular_mass(ra, normal)
                + sb.angular_mass(rb, normal);
            let tangent_mass = m.tangents.map(|t| {
                inverse_or_zero(
                    sa.inv_mass + sb.inv_mass + sa.angular_mass(ra, t) + sb.angular_mass(rb, t),
                )
            });
            // Baumgarte: push out a fraction of the penetration past the slop per step.
            let push = (c.baumgarte / c.dt * (point.depth - c.slop).max(0.0)).min(c.max_bias_speed);
            // Restitution: bounce only off a fast approach, from the speed before solving.
            let approach = (sb.point_velocity(rb) - sa.point_velocity(ra)).dot(normal);
            let bounce =
                if approach < -c.restitution_threshold { -c.restitution * approach } else { 0.0 };
            let anchor = pa.inverse().transform_point(point.position);
            let mut p = PointConstraint {
                anchor,
                ra,
                rb,
                normal_mass: inverse_or_zero(k_normal),
                tangent_mass,
                bias: push.max(bounce),
                ..PointConstraint::default()
            };
            if let Some(last) = last {
                warm_impulses(&mut p, &m, last);
            }
            m.points[m.count] = p;
            m.count += 1;
        }
        Some(m)
    }

    /// The pose of body `index`, the identity for the floor (whose anchors
    /// are world points).
    fn frame_of(&self, index: u32) -> Pose {
        self.bodies.get(index as usize).map_or(Pose::IDENTITY, Body::pose)
    }

    /// Applies the warm-started impulses.
    fn warm_start(&mut self) {
        for m in &self.manifolds {
            let (ia, ib) = self.solver_pair(m);
            for p in &m.points[..m.count] {
                let impulse = m.normal * p.normal_impulse
                    + m.tangents[0] * p.tangent_impulse[0]
                    + m.tangents[1] * p.tangent_impulse[1];
                self.solver[ia].apply(p.ra, -impulse);
                self.solver[ib].apply(p.rb, impulse);
            }
            self.solver[ia].apply_angular(-m.rolling_impulse);
            self.solver[ib].apply_angular(m.rolling_impulse);
        }
    }

    /// One sequential-impulse pass over every manifold: friction first, then
    /// the normal, which matters most, last (Box2D's `SolveVelocityConstraints`).
    fn solve_contacts(&mut self) {
        let (friction, rolling) = (self.config.friction, self.config.rolling_resistance);
        for k in 0..self.manifolds.len() {
            let (ia, ib) = self.solver_pair(&self.manifolds[k]);
            let (mut a, mut b) = (self.solver[ia], self.solver[ib]);
            let m = &mut self.manifolds[k];
            // Rolling resistance: the relative turning stopped by an angular
            // impulse within `rolling` times the pair's normal impulse.
            let pressing: f32 = m.points[..m.count].iter().map(|p| p.normal_impulse).sum();
            let old = m.rolling_impulse;
            let dw = b.angular_velocity - a.angular_velocity;
            m.rolling_impulse = (old - m.rolling_mass * dw).clamp_length_max(rolling * pressing);
            a.apply_angular(old - m.rolling_impulse);
            b.apply_angular(m.rolling_impulse - old);
            for p in &mut m.points[..m.count] {
                for (t, &tangent) in m.tangents.iter().enumerate() {
                    let dv = b.point_velocity(p.rb) - a.point_velocity(p.ra);
                    let limit = friction * p.normal_impulse;
                    let old = p.tangent_impulse[t];
                    p.tangent_impulse[t] =
                        (old - p.tangent_mass[t] * dv.dot(tangent)).clamp(-limit, limit);
                    let impulse = tangent * (p.tangent_impulse[t] - old);
                    a.apply(p.ra, -impulse);
                    b.apply(p.rb, impulse);
                }
            }
            for p in &mut m.points[..m.count] {
                let dv = b.point_velocity(p.rb) - a.point_velocity(p.ra);
                let old = p.normal_impulse;
                p.normal_impulse = (old - p.normal_mass * (dv.dot(m.normal) - p.bias)).max(0.0);
                let impulse = m.normal * (p.normal_impulse - old);
                a.apply(p.ra, -impulse);
                b.apply(p.rb, impulse);
            }
            // The floor's entry has zero inverse mass: writing it back changes nothing.
            self.solver[ia] = a;
            self.solver[ib] = b;
        }
    }

    /// Solver indices of a manifold's bodies.
    fn solver_pair(&self, m: &Manifold) -> (usize, usize) {
        let floor = self.solver.len() - 1;
        let index = |i: u32| if i == STATIC { floor } else { i as usize };
        (index(m.a), index(m.b))
    }

    /// Moves the awake bodies by their solved velocities, each move capped.
    /// A state that is not finite (it should never be) stops the body where
    /// it was.
    fn integrate_positions(&mut self) {
        let dt = self.config.dt;
        for (body, s) in self.bodies.iter_mut().zip(&self.solver) {
            if body.asleep {
                continue;
            }
            let mut v = s.velocity;
            let mut w = s.angular_velocity;
            if (v * dt).length() > MAX_TRANSLATION {
                v *= MAX_TRANSLATION / (v * dt).length();
            }
            if (w * dt).length() > MAX_ROTATION {
                w *= MAX_ROTATION / (w * dt).length();
            }
            let position = body.position + v * dt;
            // dq/dt = ½ (ω, 0) q, then back to unit length.
            let spin = Quat::from_xyzw(w.x, w.y, w.z, 0.0) * body.rotation * (0.5 * dt);
            let rotation = unit(body.rotation + spin);
            match rotation {
                Some(rotation) if position.is_finite() && v.is_finite() && w.is_finite() => {
                    (body.position, body.rotation) = (position, rotation);
                    (body.velocity, body.angular_velocity) = (v, w);
                }
                _ => (body.velocity, body.angular_velocity) = (Vec3::ZERO, Vec3::ZERO),
            }
        }
    }

    /// Counts how long each awake body has been slow on average, and picks
    /// those slow for `sleep_time` (or fallen far below the floor) to fall
    /// asleep.
    fn update_sleep(&mut self) {
        let c = &self.config;
        self.falling_asleep.clear();
        let k = (c.dt / SLEEP_SMOOTHING).min(1.0);
        for (i, body) in self.bodies.iter_mut().enumerate().filter(|(_, b)| !b.asleep) {
            body.mean_velocity += (body.velocity - body.mean_velocity) * k;
            body.mean_angular_velocity += (body.angular_velocity - body.mean_angular_velocity) * k;
            let slow = body.mean_velocity.length_squared() < c.sleep_linear_speed.powi(2)
                && body.mean_angular_velocity.length_squared() < c.sleep_angular_speed.powi(2);
            body.still_time = if slow { body.still_time + c.dt } else { 0.0 };
            if body.still_time >= c.sleep_time || body.position.y < -FALL_LIMIT {
                self.falling_asleep.push(i);
            }
        }
    }

    /// Sends the awake bodies' poses in one call, then puts the bodies that
    /// fall asleep to sleep (after their last pose is sent).
    fn send_poses(&mut self) {
        self.ids.clear();
        self.poses.clear();
        for body in self.bodies.iter().filter(|b| !b.asleep) {
            self.ids.push(body.id);
            self.poses.push(body.pose());
        }
        // Live handles and finite, unit poses (integrate_positions sees to
        // it): set_poses cannot fail.
        self.world.set_poses(&self.ids, &self.poses).ok();
        for &i in &self.falling_asleep {
            let body = &mut self.bodies[i];
            body.asleep = true;
            body.velocity = Vec3::ZERO;
            body.angular_velocity = Vec3::ZERO;
            self.world.set_kind(body.id, BodyKind::Sleeping).ok();
        }
    }
}

/// Copies the impulses of the nearest of last step's points of the pair
/// (in body A's frame) when it is near enough. The friction impulse is
/// carried as a vector, projected on this step's tangents: the tangents of
/// a slightly turned normal may be quite different.
fn warm_impulses(p: &mut PointConstraint, m: &Manifold, last: &Manifold) {
    let nearest = last.points[..last.count]
        .iter()
        .map(|q| (q, q.anchor.distance_squared(p.anchor)))
        .filter(|&(_, d)| d < WARM_MATCH_DISTANCE * WARM_MATCH_DISTANCE)
        .min_by(|x, y| x.1.total_cmp(&y.1));
    if let Some((q, _)) = nearest {
        p.normal_impulse = q.normal_impulse;
        let friction =
            last.tangents[0] * q.tangent_impulse[0] + last.tangents[1] * q.tangent_impulse[1];
        p.tangent_impulse = m.tangents.map(|t| friction.dot(t));
    }
}

/// `q` scaled to unit length, or `None` when it has no direction.
fn unit(q: Quat) -> Option<Quat> {
    let length = q.length();
    (length.is_finite() && length > 1e-6).then(|| q / length)
}

/// `1 / k`, or 0 when `k` is not a positive finite number.
fn inverse_or_zero(k: f32) -> f32 {
    if k > 0.0 && k.is_finite() { 1.0 / k } else { 0.0 }
}

/// Inverse mass and inverse inertia (about the origin, in the shape's axes)
/// of a shape of density 1: its parts' exact volume and inertia
/// ([`Shape::mass_properties`]), the inertia moved from their centre of mass
/// to the origin (parallel axes).
fn mass_properties(shape: &Shape) -> (f32, Mat3) {
    let properties = shape.mass_properties();
    let volume = properties.volume;
    let mass = if volume.is_finite() && volume > 0.0 { volume } else { 1.0 };
    let inertia = properties.inertia_about(Vec3::ZERO);
    let det = inertia.determinant();
    let inv_inertia = if det.is_finite() && det > 0.0 {
        inertia.inverse()
    } else {
        // A shape of no volume has no inertia: treat it as a ball of its size.
        Mat3::from_diagonal(Vec3::splat(inverse_or_zero(
            0.4 * mass * shape.sphere().radius.powi(2),
        )))
    };
    (1.0 / mass, inv_inertia)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::ShapeLibrary;
    use bvol::volumes::{ObbMethod, SphereMethod};
    use bvol::{FitOptions, Part};

    /// The lowest point of a body: its parts' support points straight down.
    fn lowest_point(body: &Body, shape: &Shape) -> f32 {
        let pose = body.pose();
        let down = pose.rotation.inverse() * Vec3::NEG_Y;
        let part_low = |part: &Part| pose.transform_point(part.support(down)).y;
        shape.parts().iter().map(part_low).fold(f32::MAX, f32::min)
    }

    /// `n` bodies of the library's shapes in turn, on a jittered grid from
    /// 1 m up, each turned differently.
    fn drop_pile(sim: &mut Sim, library: &ShapeLibrary, n: usize) {
        let side = 6;
        for k in 0..n {
            let (x, z, y) = (k % side, (k / side) % side, k / (side * side));
            let jitter = Vec3::new(0.1 * (k * 7 % 5) as f32, 0.0, 0.1 * (k * 3 % 5) as f32);
            let position =
                Vec3::new(x as f32 * 1.3 - 4.0, 1.0 + y as f32 * 1.2, z as f32 * 1.3 - 4.0);
            let rotation = Quat::from_euler(glam::EulerRot::XYZ, k as f32, k as f32 * 1.7, 0.3);
            let s = k % library.entries.len();
            let pose = Pose::new(position + jitter, rotation);
            sim.add_body(s, library.entries[s].shape.clone(), pose, Vec3::ZERO).unwrap();
        }
    }

    fn default_library() -> ShapeLibrary {
        let library =
            ShapeLibrary::load(&ShapeLibrary::default_mesh_files(), FitOptions::default());
        assert!(library.errors.is_empty(), "{:?}", library.errors);
        assert!(library.entries.len() >= 7, "4 primitives and the 3 assets");
        library
    }

    #[test]
    fn pile_comes_to_rest_above_the_floor() {
        let library = default_library();
        let mut sim = Sim::new(SimConfig::default());
        drop_pile(&mut sim, &library, 200);
        let mut deepest = f32::MAX;
        for _ in 0..900 {
            let stats = sim.step();
            // The contacts are the world's touching pairs, no more, no fewer.
            assert_eq!(sim.contacts().len(), stats.touching);
            for body in sim.bodies() {
                assert!(body.position.is_finite() && body.velocity.is_finite());
                deepest = deepest.min(lowest_point(body, &library.entries[body.shape].shape));
            }
        }
        let settled: Vec<f32> =
            sim.bodies().iter().map(|b| lowest_point(b, &library.entries[b.shape].shape)).collect();
        let lowest = settled.iter().copied().fold(f32::MAX, f32::min);
        assert!(lowest >= -0.05, "a body ends {lowest} below the floor");
        // Not even in the impacts does a body sink through.
        assert!(deepest >= -0.5, "a body sank to {deepest}");
        let awake = sim.bodies().iter().filter(|b| !b.asleep).count();
        assert!(awake <= 4, "{awake} of 200 bodies still awake");
        let energy: f32 =
            sim.bodies().iter().map(|b| (b.velocity.length_squared() / b.inv_mass) / 2.0).sum();
        assert!(energy < 1e-3, "kinetic energy {energy}");
        // Asleep means still: the world holds them as sleeping.
        for body in sim.bodies().iter().filter(|b| b.asleep) {
            assert_eq!(sim.world().kind(body.id).unwrap(), BodyKind::Sleeping);
        }
    }

    #[test]
    fn box_dropped_flat_rests_at_its_half_height() {
        let half = Vec3::new(0.4, 0.25, 0.3);
        let mut sim = Sim::new(SimConfig::default());
        let shape = Arc::new(Shape::cuboid(half).unwrap());
        let pose = Pose::new(Vec3::new(3.0, 2.0, -2.0), Quat::IDENTITY);
        sim.add_body(0, shape, pose, Vec3::ZERO).unwrap();
        let mut slept_at = None;
        for frame in 0..600 {
            sim.step();
            if sim.bodies()[0].asleep && slept_at.is_none() {
                slept_at = Some(frame);
            }
        }
        let body = &sim.bodies()[0];
        assert!(slept_at.is_some(), "never fell asleep");
        assert!((body.position.y - half.y).abs() < 0.01, "rests at {}", body.position.y);
        assert!(body.rotation.angle_between(Quat::IDENTITY) < 0.01);
        assert!((body.position - Vec3::new(3.0, body.position.y, -2.0)).length() < 0.01);
    }

    #[test]
    fn collision_in_free_space_conserves_momentum() {
        // No gravity and no damping: no outside force.
        let config = SimConfig {
            gravity: Vec3::ZERO,
            linear_damping: 0.0,
            angular_damping: 0.0,
            ..SimConfig::default()
        };
        let mut sim = Sim::new(config);
        let (half, radius) = (Vec3::new(0.5, 0.3, 0.4), 0.35f32);
        // Masses from the geometry at density 1, not from the simulation.
        let masses =
            [8.0 * half.x * half.y * half.z, 4.0 / 3.0 * std::f32::consts::PI * radius.powi(3)];
        let high = Vec3::Y * 10.0;
        let cuboid = Arc::new(Shape::cuboid(half).unwrap());
        let turned = Quat::from_rotation_z(0.4);
        sim.add_body(0, cuboid, Pose::new(high, turned), Vec3::new(1.0, 0.0, 0.2)).unwrap();
        let ball = Arc::new(Shape::ball(radius).unwrap());
        let start = high + Vec3::new(3.0, 0.2, 0.0);
        sim.add_body(1, ball, Pose::new(start, Quat::IDENTITY), Vec3::new(-4.0, 0.0, 0.0)).unwrap();
        let momentum = |sim: &Sim| -> Vec3 {
            sim.bodies().iter().zip(masses).map(|(b, m)| b.velocity * m).sum()
        };
        let before = momentum(&sim);
        let mut touched = false;
        for _ in 0..90 {
            sim.step();
            touched |= !sim.contacts().is_empty();
        }
        assert!(touched, "the bodies never met");
        let after = momentum(&sim);
        assert!(before.distance(after) < 1e-3 * before.length(), "{before} -> {after}");
        // They did interact: the ball no longer moves as it did.
        assert!(sim.bodies()[1].velocity.x > -3.0);
        assert!(sim.bodies()[0].angular_velocity.length() > 1e-3, "an off-centre hit turns it");
    }

    #[test]
    fn bounces_only_from_a_fast_approach() {
        // No position bias, which pushes out at a speed of its own.
        let config = SimConfig { baumgarte: 0.0, ..SimConfig::default() };
        let radius = 0.3;
        let ball = Arc::new(Shape::ball(radius).unwrap());
        // The speeds just before the first contact and just after it.
        let bounce = |drop: f32| {
            let mut sim = Sim::new(config);
            let pose = Pose::new(Vec3::Y * (radius + drop), Quat::IDENTITY);
            sim.add_body(0, ball.clone(), pose, Vec3::ZERO).unwrap();
            while sim.contacts().is_empty() {
                sim.step();
            }
            let before = sim.bodies()[0].velocity.y;
            sim.step();
            (before, sim.bodies()[0].velocity.y)
        };
        // Dropped 2 m, it meets the floor at about 6.3 m/s, and leaves at e times that.
        let (before, after) = bounce(2.0);
        let expected = -before * config.restitution;
        assert!((after - expected).abs() < 0.1 * expected, "{before} -> {after}, not {expected}");
        // Dropped 2 cm, it meets it at 0.6 m/s, under the threshold: no bounce.
        let (before, after) = bounce(0.02);
        assert!(before < -0.5 && after.abs() < 0.01, "{before} -> {after}");
    }

    #[test]
    fn inertia_of_a_box_is_the_box_formula() {
        let half = Vec3::new(0.5, 0.2, 0.3);
        let (inv_mass, inv_inertia) = mass_properties(&Shape::cuboid(half).unwrap());
        let mass = 8.0 * half.x * half.y * half.z;
        assert!((1.0 / inv_mass - mass).abs() < 1e-4 * mass);
        let h2 = half * half;
        let expected = Vec3::new(h2.y + h2.z, h2.x + h2.z, h2.x + h2.y) * mass / 3.0;
        let inertia = inv_inertia.inverse();
        assert!(inertia.abs_diff_eq(Mat3::from_diagonal(expected), 1e-4), "{inertia}");
        let ball = mass_properties(&Shape::ball(0.5).unwrap());
        let ball_mass = 4.0 / 3.0 * std::f32::consts::PI * 0.125;
        assert!((ball.1.inverse().x_axis.x - 0.4 * ball_mass * 0.25).abs() < 1e-5);
    }

    #[test]
    fn sleeping_body_wakes_when_hit_and_sleeps_again() {
        let mut sim = Sim::new(SimConfig::default());
        let cuboid = Arc::new(Shape::cuboid(Vec3::new(0.5, 0.2, 0.5)).unwrap());
        sim.add_body(0, cuboid, Pose::new(Vec3::Y * 0.2, Quat::IDENTITY), Vec3::ZERO).unwrap();
        for _ in 0..60 {
            sim.step();
        }
        assert!(sim.bodies()[0].asleep);
        let rest = sim.bodies()[0].position;
        let ball = Arc::new(Shape::ball(0.3).unwrap());
        let above = Pose::new(Vec3::new(0.3, 2.0, 0.0), Quat::IDENTITY);
        sim.add_body(1, ball, above, Vec3::ZERO).unwrap();
        let mut woke = false;
        for _ in 0..600 {
            sim.step();
            woke |= !sim.bodies()[0].asleep;
        }
        assert!(woke, "the hit did not wake it");
        assert!(sim.bodies().iter().all(|b| b.asleep), "not back to sleep");
        let ball = &sim.bodies()[1];
        assert!(ball.position.y > 0.2, "the ball fell through the box: {}", ball.position);
        assert!(sim.bodies()[0].position.y > rest.y - 0.01);
    }

    #[test]
    fn replace_shapes_keeps_the_state() {
        let mut library = default_library();
        let mut sim = Sim::new(SimConfig::default());
        drop_pile(&mut sim, &library, 40);
        for _ in 0..120 {
            sim.step();
        }
        let before: Vec<Body> = sim.bodies().to_vec();
        let fit = FitOptions { sphere: SphereMethod::Ritter, obb: ObbMethod::PcaPoints };
        library.set_fit(fit).unwrap();
        sim.replace_shapes(&library.shapes()).unwrap();
        assert_eq!(sim.world().len(), 41, "the floor and the 40 bodies");
        for (i, (old, new)) in before.iter().zip(sim.bodies()).enumerate() {
            assert_eq!((old.position, old.rotation), (new.position, new.rotation));
            assert_eq!((old.velocity, old.asleep), (new.velocity, new.asleep));
            let shape = sim.world().shape(new.id).unwrap();
            assert!(Arc::ptr_eq(shape, &library.entries[new.shape].shape));
            assert_eq!(sim.world().user_data(new.id).unwrap(), i as u64);
            assert_eq!(sim.world().pose(new.id).unwrap(), new.pose());
            let kind = if new.asleep { BodyKind::Sleeping } else { BodyKind::Dynamic };
            assert_eq!(sim.world().kind(new.id).unwrap(), kind);
        }
        for _ in 0..600 {
            sim.step();
        }
        assert!(
            sim.bodies().iter().all(|b| lowest_point(b, &library.entries[b.shape].shape) > -0.05)
        );
    }

    #[test]
    fn reset_leaves_the_floor_alone() {
        let library = default_library();
        let mut sim = Sim::new(SimConfig::default());
        drop_pile(&mut sim, &library, 30);
        for _ in 0..30 {
            sim.step();
        }
        sim.reset();
        assert!(sim.bodies().is_empty() && sim.contacts().is_empty());
        assert_eq!(sim.world().len(), 1);
        sim.step();
        drop_pile(&mut sim, &library, 5);
        for _ in 0..200 {
            sim.step();
        }
        assert_eq!(sim.world().len(), 6);
        assert!(sim.bodies().iter().all(|b| b.position.y > 0.0 && b.position.y < 1.0));
    }

    #[test]
    fn same_input_same_motion() {
        let library = default_library();
        let run = || {
            let mut sim = Sim::new(SimConfig::default());
            drop_pile(&mut sim, &library, 60);
            for _ in 0..200 {
                sim.step();
            }
            sim.bodies().iter().map(|b| (b.position, b.rotation, b.velocity)).collect::<Vec<_>>()
        };
        assert_eq!(run(), run());
    }

    #[test]
    fn bad_input_gives_no_nan() {
        let mut sim = Sim::new(SimConfig::default());
        let ball = Arc::new(Shape::ball(0.3).unwrap());
        let bad = Pose::new(Vec3::new(f32::NAN, 1.0, 0.0), Quat::IDENTITY);
        assert!(sim.add_body(0, ball.clone(), bad, Vec3::ZERO).is_err());
        assert!(sim.bodies().is_empty());
        let unnormalised = Pose::new(Vec3::Y, Quat::from_xyzw(0.0, 0.0, 0.0, 3.0));
        sim.add_body(0, ball, unnormalised, Vec3::splat(f32::INFINITY)).unwrap();
        for _ in 0..120 {
            sim.step();
        }
        let body = &sim.bodies()[0];
        assert!(body.position.is_finite() && body.rotation.is_normalized());
        assert!((body.position.y - 0.3).abs() < 0.01);
    }
}
