//! What a frame draws, built from the app's state: each body as an instance
//! of its shape's mesh, and the overlays the user switched on as lines.

use bvol::volumes::{Aabb, Obb, Sphere};
use bvol::{BodyId, Broadphase};
use glam::{Mat3, Mat4, Quat, Vec3};

use crate::app::App;
use crate::render::{DrawList, Instance};

/// Segments of a drawn circle.
const CIRCLE_SEGMENTS: usize = 24;
const SPHERE_COLOR: [f32; 4] = [0.3, 0.85, 1.0, 0.55];
const OBB_COLOR: [f32; 4] = [1.0, 0.85, 0.2, 0.7];
const CONTACT_COLOR: [f32; 4] = [1.0, 0.25, 0.2, 1.0];
const NORMAL_COLOR: [f32; 4] = [1.0, 1.0, 0.4, 1.0];
const SELECTED_COLOR: [f32; 4] = [1.0, 0.55, 0.1, 1.0];
const FLOOR_COLOR: [f32; 4] = [0.42, 0.44, 0.46, 1.0];

/// Per shape of the library, a base colour (cycled).
const PALETTE: [[f32; 3]; 8] = [
    [0.85, 0.33, 0.30],
    [0.30, 0.62, 0.86],
    [0.40, 0.75, 0.38],
    [0.90, 0.70, 0.25],
    [0.72, 0.48, 0.85],
    [0.95, 0.55, 0.65],
    [0.45, 0.80, 0.78],
    [0.80, 0.80, 0.80],
];

/// A body whose bounding sphere spans fewer pixels in radius than this is
/// drawn with its shape's far mesh.
const FAR_RADIUS_PIXELS: f32 = 24.0;

/// How far the camera is and how big things look: what picks each body's
/// mesh.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// The eye's position.
    pub eye: Vec3,
    /// Pixels per unit of size at unit distance (the viewport's height over
    /// twice the tangent of half the vertical field of view).
    pub pixels_per_unit: f32,
}

/// Fills `list` for the app's current state as seen from `view`. The
/// uploaded meshes are the library's full meshes, then its far meshes.
pub fn build(app: &App, list: &mut DrawList, view: View) {
    let shapes = app.library.entries.len();
    list.clear(2 * shapes);
    list.eye = view.eye;
    let world = app.sim.world();
    floor_instance(app, list);
    let s = &app.settings;
    for body in app.sim.bodies() {
        let model = Mat4::from_rotation_translation(body.rotation, body.position);
        let color = if app.selected == Some(body.id) {
            SELECTED_COLOR
        } else {
            body_color(body.shape, body.id, body.asleep)
        };
        let radius = app.library.entries[body.shape].shape.sphere().radius;
        let pixels = radius * view.pixels_per_unit / view.eye.distance(body.position).max(1e-3);
        let mesh = if pixels < FAR_RADIUS_PIXELS { shapes + body.shape } else { body.shape };
        list.instances[mesh].push(Instance::new(model, color));
        if s.show_spheres
            && let Ok(sphere) = world.world_sphere(body.id)
        {
            sphere_lines(list, &sphere, SPHERE_COLOR, false);
        }
        if s.show_obbs
            && let Ok(obb) = world.world_obb(body.id)
        {
            obb_lines(list, &obb, OBB_COLOR, false);
        }
    }
    if s.show_tree {
        let (first, last) = s.tree_depths;
        for broadphase in [world.moving_broadphase(), world.resting_broadphase()] {
            Broadphase::visit_nodes(broadphase, |depth, aabb| {
                if (first..=last).contains(&depth) {
                    aabb_lines(list, aabb, depth_color(depth));
                }
            });
        }
    }
    if s.show_contacts {
        contact_lines(app, list, None);
    }
    if let Some(id) = app.selected {
        selection_lines(app, list, id);
    }
}

/// The floor, drawn as the library's first shape (the box primitive)
/// stretched to a slab whose top is y = 0.
fn floor_instance(app: &App, list: &mut DrawList) {
    let Some(entry) = app.library.entries.first() else { return };
    let half = entry.mesh.positions.iter().fold(Vec3::ZERO, |m, p| m.max(p.abs()));
    if half.min_element() <= 0.0 {
        return;
    }
    let (size, thickness) = (app.sim.floor_half_extent(), 0.25);
    let scale = Vec3::new(size, thickness, size) / half;
    let model = Mat4::from_scale_rotation_translation(scale, Quat::IDENTITY, -thickness * Vec3::Y);
    list.instances[0].push(Instance::new(model, FLOOR_COLOR));
}

/// A body's colour: its shape's, varied a little per body, greyed asleep.
fn body_color(shape: usize, id: BodyId, asleep: bool) -> [f32; 4] {
    let [r, g, b] = PALETTE[shape % PALETTE.len()];
    let vary = 0.88 + 0.12 * ((id.index().wrapping_mul(2_654_435_761) >> 24) as f32 / 255.0);
    let c = Vec3::new(r, g, b) * vary;
    let c = if asleep { c.lerp(Vec3::splat(c.dot(Vec3::splat(1.0 / 3.0))), 0.6) * 0.8 } else { c };
    [c.x, c.y, c.z, 1.0]
}

/// A colour per tree depth, cycling through hues.
fn depth_color(depth: usize) -> [f32; 4] {
    let [r, g, b] = PALETTE[depth % PALETTE.len()];
    [r, g, b, 0.8]
}

/// The selected body's sphere, OBB and contacts, over everything.
fn selection_lines(app: &App, list: &mut DrawList, id: BodyId) {
    let world = app.sim.world();
    if let Ok(sphere) = world.world_sphere(id) {
        sphere_lines(list, &sphere, SPHERE_COLOR, true);
    }
    if let Ok(obb) = world.world_obb(id) {
        obb_lines(list, &obb, OBB_COLOR, true);
    }
    contact_lines(app, list, Some(id));
}

/// Each contact point as a small cross, with the normal drawn from it;
/// only `only`'s contacts when given.
fn contact_lines(app: &App, list: &mut DrawList, only: Option<BodyId>) {
    for (a, b, contact) in app.sim.contacts() {
        if only.is_some_and(|id| id != *a && id != *b) {
            continue;
        }
        for p in contact.points() {
            let q = p.position;
            for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
                list.line(q - axis * 0.06, q + axis * 0.06, CONTACT_COLOR, true);
            }
            list.line(q, q + contact.normal * 0.5, NORMAL_COLOR, true);
        }
    }
}

/// Three great circles of a sphere.
fn sphere_lines(list: &mut DrawList, sphere: &Sphere, color: [f32; 4], on_top: bool) {
    let (c, r) = (sphere.center, sphere.radius);
    for (u, v) in [(Vec3::X, Vec3::Y), (Vec3::Y, Vec3::Z), (Vec3::Z, Vec3::X)] {
        let at = |k: usize| {
            let (s, co) = (k as f32 * std::f32::consts::TAU / CIRCLE_SEGMENTS as f32).sin_cos();
            c + r * (co * u + s * v)
        };
        for k in 0..CIRCLE_SEGMENTS {
            list.line(at(k), at(k + 1), color, on_top);
        }
    }
}

/// The 12 edges of a box given by its centre, axes (columns) and half extents.
fn box_lines(
    list: &mut DrawList,
    center: Vec3,
    axes: Mat3,
    half: Vec3,
    color: [f32; 4],
    on_top: bool,
) {
    let corner = |k: usize| {
        let sign = |bit: usize| if k & bit != 0 { 1.0 } else { -1.0 };
        center + axes * Vec3::new(sign(1) * half.x, sign(2) * half.y, sign(4) * half.z)
    };
    for k in 0..8 {
        for bit in [1, 2, 4] {
            if k & bit == 0 {
                list.line(corner(k), corner(k | bit), color, on_top);
            }
        }
    }
}

fn obb_lines(list: &mut DrawList, obb: &Obb, color: [f32; 4], on_top: bool) {
    box_lines(list, obb.center, obb.axes, obb.half_extents, color, on_top);
}

fn aabb_lines(list: &mut DrawList, aabb: &Aabb, color: [f32; 4]) {
    let (center, half) = ((aabb.min + aabb.max) * 0.5, (aabb.max - aabb.min) * 0.5);
    box_lines(list, center, Mat3::IDENTITY, half, color, false);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::ShapeLibrary;
    use bvol::FitOptions;

    /// The instances drawn with full meshes and with far meshes.
    fn split(app: &App, eye: Vec3) -> (usize, usize) {
        let mut list = DrawList::default();
        build(app, &mut list, View { eye, pixels_per_unit: 800.0 });
        let shapes = app.library.entries.len();
        let count = |r: std::ops::Range<usize>| list.instances[r].iter().map(Vec::len).sum();
        // The floor is the one full-mesh instance that is no body.
        (count(0..shapes) - 1, count(shapes..2 * shapes))
    }

    /// Near bodies get their full mesh, far ones their far mesh, each body
    /// once; the boundary is where its sphere spans FAR_RADIUS_PIXELS.
    #[test]
    fn each_body_is_drawn_once_with_the_mesh_its_size_on_screen_calls_for() {
        let mut app = App::new(ShapeLibrary::load(&[], FitOptions::default()), 3);
        app.add_bodies(40);
        let n = app.sim.bodies().len();
        assert_eq!(split(&app, Vec3::new(0.0, 3000.0, 0.0)), (0, n));
        // Where body `i` is, and how far its sphere spans FAR_RADIUS_PIXELS.
        let boundary = |app: &App, i: usize| {
            let body = &app.sim.bodies()[i];
            let radius = app.library.entries[body.shape].shape.sphere().radius;
            (body.position, radius * 800.0 / FAR_RADIUS_PIXELS)
        };
        let (at, distance) = boundary(&app, 7);
        let (near, far) = split(&app, at + Vec3::X * distance * 0.9);
        assert!(near >= 1 && near + far == n, "{near} near, {far} far");
        // Just past the boundary, alone in space: the same body is far.
        let mut alone = App::new(ShapeLibrary::load(&[], FitOptions::default()), 3);
        alone.add_bodies(1);
        let (at, distance) = boundary(&alone, 0);
        assert_eq!(split(&alone, at + Vec3::Z * distance * 0.99), (1, 0));
        assert_eq!(split(&alone, at + Vec3::Z * distance * 1.01), (0, 1));
    }
}
