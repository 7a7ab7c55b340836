//! The demo's shape library: the primitives (box, ball, capsule,
//! tetrahedron) and the meshes of OBJ files, each as a bvol [`Shape`] for
//! collision and a [`RenderMesh`] for drawing, both in the same body frame.
//!
//! Every shape is about one unit across (a bounding-sphere radius of 0.3 to
//! 0.5) and centred on its centre of mass, which is where the simulation
//! ([`crate::sim`]) puts a body's origin. OBJ meshes are moved so that the
//! centre of mass of their convex hull (a uniform solid) is the origin, and
//! scaled so that their farthest vertex is [`MESH_RADIUS`] from it; the one
//! transform is applied to the collision mesh and the render mesh alike.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bvol::volumes::ConvexHull;
use bvol::{FitOptions, Mesh, Part, Shape, ShapeError};
use glam::{DVec3, Vec3};

/// Distance from a loaded mesh's centre of mass to its farthest vertex.
pub const MESH_RADIUS: f32 = 0.5;

/// Half extents of the box primitive.
const BOX_HALF: Vec3 = Vec3::new(0.35, 0.22, 0.28);
/// Radius of the ball primitive.
const BALL_RADIUS: f32 = 0.32;
/// Radius and half height (of the inner segment) of the capsule primitive.
const CAPSULE: (f32, f32) = (0.18, 0.24);
/// Distance from the tetrahedron's centre to its corners.
const TETRA_RADIUS: f32 = 0.5;
/// Segments of the ball's render mesh around its axis and from pole to pole.
const BALL_SEGMENTS: (u32, u32) = (20, 12);

/// Triangles for drawing: counter-clockwise seen from outside, one normal
/// per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderMesh {
    /// Vertex positions in the body frame.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, pointing out of the body.
    pub normals: Vec<Vec3>,
    /// Three indices into `positions` per triangle.
    pub indices: Vec<u32>,
}

/// One shape of the library.
#[derive(Clone, Debug)]
pub struct ShapeEntry {
    /// What the UI calls it: the primitive's name or the file's stem.
    pub name: String,
    /// The collision shape, with its bounds fitted by the library's methods.
    pub shape: Arc<Shape>,
    /// The mesh to draw, in the shape's frame.
    pub mesh: RenderMesh,
    /// The OBJ file it came from, `None` for a primitive.
    pub source: Option<PathBuf>,
}

/// The shapes bodies are made of, in a fixed order: the four primitives, then
/// the OBJ files that loaded, in the order given.
#[derive(Clone, Debug, Default)]
pub struct ShapeLibrary {
    /// The shapes.
    pub entries: Vec<ShapeEntry>,
    /// One line per OBJ file that did not load, naming the file and the problem.
    pub errors: Vec<String>,
}

impl ShapeLibrary {
    /// Box, ball, capsule, tetrahedron, then one entry per OBJ file that
    /// loads; a file that does not load (missing, broken, NaN, flat, ...)
    /// becomes one line in `errors` naming the file and the problem, and
    /// loading goes on with the rest. Never panics.
    pub fn load(mesh_files: &[PathBuf], fit: FitOptions) -> ShapeLibrary {
        let mut library = ShapeLibrary::default();
        match primitives(fit) {
            Ok(entries) => library.entries = entries,
            // The sizes are constants: this cannot happen, but is no reason to panic.
            Err(e) => library.errors.push(format!("primitives: {e}")),
        }
        for path in mesh_files {
            match mesh_entry(path, fit) {
                Ok(entry) => library.entries.push(entry),
                Err(e) => library.errors.push(file_error(path, &e)),
            }
        }
        library
    }

    /// The same shapes with their bounds refitted by other methods (the
    /// collision parts and render meshes are unchanged). On error no shape
    /// has changed.
    pub fn refit(&mut self, fit: FitOptions) -> Result<(), ShapeError> {
        let shapes: Vec<Shape> =
            self.entries.iter().map(|e| e.shape.refit(fit)).collect::<Result<_, _>>()?;
        for (entry, shape) in self.entries.iter_mut().zip(shapes) {
            entry.shape = Arc::new(shape);
        }
        Ok(())
    }

    /// The collision shapes, by entry: what [`crate::sim::Sim::replace_shapes`] takes.
    pub fn shapes(&self) -> Vec<Arc<Shape>> {
        self.entries.iter().map(|e| e.shape.clone()).collect()
    }

    /// The default assets: the .obj files in demos/falling/assets (bunny,
    /// teapot, duck), sorted by name.
    pub fn default_mesh_files() -> Vec<PathBuf> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map(|entries| {
                entries
                    .filter_map(|e| Some(e.ok()?.path()))
                    .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("obj")))
                    .collect()
            })
            .unwrap_or_default();
        files.sort();
        files
    }
}

/// The four primitives, their bounds fitted by `fit`.
fn primitives(fit: FitOptions) -> Result<Vec<ShapeEntry>, ShapeError> {
    let (radius, half_height) = CAPSULE;
    let shapes = [
        ("box", Shape::cuboid(BOX_HALF)?),
        ("ball", Shape::ball(BALL_RADIUS)?),
        ("capsule", Shape::capsule(radius, half_height)?),
        ("tetrahedron", Shape::tetrahedron(TETRA_RADIUS)?),
    ];
    shapes
        .into_iter()
        .map(|(name, shape)| {
            let mesh = match name {
                "ball" => uv_sphere(BALL_RADIUS, BALL_SEGMENTS),
                "capsule" => smooth_capsule(&shape, half_height),
                _ => flat_hull_mesh(&shape),
            };
            let shape = if fit == FitOptions::default() { shape } else { shape.refit(fit)? };
            Ok(ShapeEntry { name: name.to_owned(), shape: Arc::new(shape), mesh, source: None })
        })
        .collect()
}

/// A shape and render mesh from every object of an OBJ file, recentred and
/// scaled as the module docs say.
fn mesh_entry(path: &Path, fit: FitOptions) -> Result<ShapeEntry, ShapeError> {
    let meshes = bvol::load_obj(path)?;
    // The raw shape checks every object (solid, finite) and gives the hulls.
    let raw = Shape::from_meshes(&meshes, FitOptions::default())?;
    let centre = centre_of_mass(&raw);
    let far = meshes
        .iter()
        .flat_map(|m| &m.positions)
        .map(|&p| p.distance(centre))
        .fold(0.0f32, f32::max);
    if !(far.is_finite() && far > 0.0) {
        return Err(ShapeError::BadSize { primitive: "mesh" });
    }
    let scale = MESH_RADIUS / far;
    let moved: Vec<Mesh> = meshes
        .into_iter()
        .map(|m| Mesh {
            positions: m.positions.iter().map(|&p| (p - centre) * scale).collect(),
            ..m
        })
        .collect();
    let shape = Shape::from_meshes(&moved, fit)?;
    let mesh = flat_mesh(&moved);
    let mesh = if mesh.indices.is_empty() { flat_hull_mesh(&shape) } else { mesh };
    let name = path.file_stem().map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into());
    Ok(ShapeEntry { name, shape: Arc::new(shape), mesh, source: Some(path.to_path_buf()) })
}

/// The error line of a file: bvol's mesh errors name the file already.
fn file_error(path: &Path, e: &ShapeError) -> String {
    match e {
        ShapeError::Mesh(_) => e.to_string(),
        _ => format!("{}: {e}", path.display()),
    }
}

/// The centre of mass of a shape's parts taken as uniform solids (overlaps
/// counted twice), in f64: each hull split into tetrahedra from its first
/// vertex, whose centroids weigh by their signed volumes.
fn centre_of_mass(shape: &Shape) -> Vec3 {
    let (mut volume, mut moment) = (0.0f64, DVec3::ZERO);
    for part in shape.parts() {
        let (v, c) = match part {
            Part::Hull(part) => hull_mass(&part.hull),
            Part::Ball(s) => (s.volume() as f64, s.center.as_dvec3()),
        };
        volume += v;
        moment += c * v;
    }
    if volume > 0.0 { (moment / volume).as_vec3() } else { shape.obb().center }
}

/// The volume and centroid of a solid hull.
fn hull_mass(hull: &ConvexHull) -> (f64, DVec3) {
    let vertices = hull.vertices();
    let o = vertices[0].as_dvec3();
    let (mut volume, mut moment) = (0.0f64, DVec3::ZERO);
    for [a, b, c] in hull.triangles() {
        let [a, b, c] = [a, b, c].map(|i| vertices[i as usize].as_dvec3());
        let v = (a - o).dot((b - o).cross(c - o)) / 6.0;
        volume += v;
        moment += (o + a + b + c) / 4.0 * v;
    }
    if volume > 0.0 { (volume, moment / volume) } else { (0.0, o) }
}

/// Flat-shaded triangles of the meshes (three vertices of their own per
/// triangle), each mesh turned outward if its signed volume is negative
/// (OBJ files do not agree on a winding). Degenerate triangles are left out:
/// they have no normal and draw nothing.
fn flat_mesh(meshes: &[Mesh]) -> RenderMesh {
    let mut out = RenderMesh::default();
    for m in meshes {
        let triangles: Vec<[Vec3; 3]> = m
            .triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| m.positions.get(i as usize).copied());
                Some([a?, b?, c?])
            })
            .collect();
        let volume: f32 = triangles.iter().map(|[a, b, c]| a.dot(b.cross(*c))).sum();
        for &[a, b, c] in &triangles {
            let [a, b, c] = if volume < 0.0 { [a, c, b] } else { [a, b, c] };
            if let Some(n) = (b - a).cross(c - a).try_normalize() {
                push_triangle(&mut out, [a, b, c], [n; 3]);
            }
        }
    }
    out
}

/// The shape's convex hulls, flat-shaded: the box and the tetrahedron are
/// exactly theirs.
fn flat_hull_mesh(shape: &Shape) -> RenderMesh {
    let mut out = RenderMesh::default();
    for part in shape.parts() {
        if let Part::Hull(part) = part {
            let v = part.hull.vertices();
            for [a, b, c] in part.hull.triangles() {
                let [a, b, c] = [a, b, c].map(|i| v[i as usize]);
                if let Some(n) = (b - a).cross(c - a).try_normalize() {
                    push_triangle(&mut out, [a, b, c], [n; 3]);
                }
            }
        }
    }
    out
}

/// The capsule's hull with the normals of the round capsule (from the
/// nearest point of its axis segment): it looks round and matches the
/// collision hull exactly, so no vertex pokes out of its bounds.
fn smooth_capsule(shape: &Shape, half_height: f32) -> RenderMesh {
    let mut out = RenderMesh::default();
    for part in shape.parts() {
        if let Part::Hull(part) = part {
            let v = part.hull.vertices();
            let normal = |p: Vec3| {
                let axis = Vec3::Y * p.y.clamp(-half_height, half_height);
                (p - axis).try_normalize().unwrap_or(Vec3::Y * p.y.signum())
            };
            out.positions.extend_from_slice(v);
            out.normals.extend(v.iter().map(|&p| normal(p)));
            out.indices.extend(part.hull.triangles().flatten());
        }
    }
    out
}

/// A UV sphere with smooth normals: `segments.0` around y, `segments.1` from
/// pole to pole.
fn uv_sphere(radius: f32, (around, down): (u32, u32)) -> RenderMesh {
    let mut out = RenderMesh::default();
    for j in 0..=down {
        let polar = std::f32::consts::PI * j as f32 / down as f32;
        for i in 0..=around {
            let azimuth = std::f32::consts::TAU * i as f32 / around as f32;
            let n =
                Vec3::new(polar.sin() * azimuth.cos(), polar.cos(), -polar.sin() * azimuth.sin());
            out.positions.push(n * radius);
            out.normals.push(n);
        }
    }
    let row = around + 1;
    for j in 0..down {
        for i in 0..around {
            let (p, q) = (j * row + i, (j + 1) * row + i);
            // The poles' rows collapse to a point: leave out their flat triangles.
            if j != 0 {
                out.indices.extend([p, q, p + 1]);
            }
            if j + 1 != down {
                out.indices.extend([p + 1, q, q + 1]);
            }
        }
    }
    out
}

/// Appends one triangle with vertices of its own.
fn push_triangle(out: &mut RenderMesh, corners: [Vec3; 3], normals: [Vec3; 3]) {
    let base = out.positions.len() as u32;
    out.positions.extend(corners);
    out.normals.extend(normals);
    out.indices.extend([base, base + 1, base + 2]);
}
