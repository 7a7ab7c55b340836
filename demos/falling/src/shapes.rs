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
/// Points on the capsule's render mesh: the caps' share of them each.
const CAPSULE_POINTS: usize = 128;
/// Segments of the ball's render mesh around its axis and from pole to pole.
const BALL_SEGMENTS: (u32, u32) = (20, 12);
/// The same for its far mesh.
const BALL_FAR_SEGMENTS: (u32, u32) = (10, 6);
/// A far mesh keeps about this fraction of the full mesh's triangles...
const FAR_TRIANGLE_FRACTION: f32 = 0.05;
/// ... unless that moves the surface by more than this fraction of the
/// mesh's extent (meshoptimizer's relative error).
const FAR_MAX_ERROR: f32 = 0.03;

/// Triangles for drawing, counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RenderMesh {
    /// Vertex positions in the body frame.
    pub positions: Vec<Vec3>,
    /// Per vertex, its unit outward normal for smooth shading, or zero
    /// where each triangle's own normal is meant (flat shading, which the
    /// shader takes from the triangle's plane): flat triangles can then
    /// share vertices, a third or less of the vertex shading.
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
    /// The mesh to draw where the body is small on screen: `mesh` with
    /// fewer triangles, made of a subset of its vertices (so inside the same
    /// bounds). Software rasterisers pay for every triangle, even sub-pixel
    /// ones: a pile of full-detail bunnies is what slows a frame most.
    pub far_mesh: RenderMesh,
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
    /// loads; a file that does not load (missing, broken, NaN, a line, ...)
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

    /// The same shapes with their bounds fitted by other methods (the
    /// collision parts and render meshes are unchanged). On error no shape
    /// has changed.
    pub fn set_fit(&mut self, fit: FitOptions) -> Result<(), ShapeError> {
        let shapes: Vec<Shape> =
            self.entries.iter().map(|e| e.shape.with_fit(fit)).collect::<Result<_, _>>()?;
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
            // Only the ball has a coarser mesh: the others have few triangles.
            let (mesh, far_mesh) = match name {
                "ball" => (
                    uv_sphere(BALL_RADIUS, BALL_SEGMENTS),
                    uv_sphere(BALL_RADIUS, BALL_FAR_SEGMENTS),
                ),
                _ => {
                    let mesh = match name {
                        "capsule" => smooth_capsule(&shape),
                        _ => flat_hull_mesh(&shape),
                    };
                    (mesh.clone(), mesh)
                }
            };
            let shape = if fit == FitOptions::default() { shape } else { shape.with_fit(fit)? };
            let name = name.to_owned();
            Ok(ShapeEntry { name, shape: Arc::new(shape), mesh, far_mesh, source: None })
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
    let simplified: Vec<Mesh> = moved.iter().map(simplify).collect();
    let [mesh, far_mesh] = [&moved, &simplified].map(|meshes| {
        let mesh = flat_mesh(meshes);
        if mesh.indices.is_empty() { flat_hull_mesh(&shape) } else { mesh }
    });
    let name = path.file_stem().map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into());
    let source = Some(path.to_path_buf());
    Ok(ShapeEntry { name, shape: Arc::new(shape), mesh, far_mesh, source })
}

/// `mesh` with fewer triangles on the same vertices: meshoptimizer's
/// edge-collapse simplifier (Garland & Heckbert's quadric error metric),
/// down to [`FAR_TRIANGLE_FRACTION`] of the triangles or [`FAR_MAX_ERROR`].
/// Copies of a position are welded first: the teapot's patches meet along
/// seams of repeated vertices that would otherwise open into cracks.
/// Triangles with an index out of range are left out first (meshoptimizer
/// would abort on them).
fn simplify(mesh: &Mesh) -> Mesh {
    let n = mesh.positions.len();
    let corners: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    // Copies of one position (OBJ files repeat them along seams) weld into
    // the first: a seam between copies is a border to the simplifier.
    let (_, remap) = meshopt::generate_vertex_remap(&corners, None);
    let mut first = vec![u32::MAX; n];
    for (v, &w) in remap.iter().enumerate() {
        if first[w as usize] == u32::MAX {
            first[w as usize] = v as u32;
        }
    }
    let indices: Vec<u32> = mesh
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&i| (i as usize) < n))
        .flatten()
        .map(|&i| first[remap[i as usize] as usize])
        .collect();
    let stride = size_of::<[f32; 3]>();
    let Ok(vertices) = meshopt::VertexDataAdapter::new(bytemuck::cast_slice(&corners), stride, 0)
    else {
        return mesh.clone();
    };
    let target = ((indices.len() / 3) as f32 * FAR_TRIANGLE_FRACTION) as usize * 3;
    let options = meshopt::SimplifyOptions::None;
    let kept = meshopt::simplify(&indices, &vertices, target, FAR_MAX_ERROR, options, None);
    let triangles = kept.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Mesh { name: mesh.name.clone(), positions: mesh.positions.clone(), triangles }
}

/// The error line of a file: bvol's mesh errors name the file already.
fn file_error(path: &Path, e: &ShapeError) -> String {
    match e {
        ShapeError::Mesh(_) => e.to_string(),
        _ => format!("{}: {e}", path.display()),
    }
}

/// The centre of mass of a shape's parts taken as uniform solids (overlaps
/// counted twice: [`Shape::mass_properties`]).
fn centre_of_mass(shape: &Shape) -> Vec3 {
    let mass = shape.mass_properties();
    if mass.volume > 0.0 { mass.center } else { shape.obb().center }
}

/// Flat-shaded triangles of the meshes on their own vertices (zero normals:
/// the shader shades each triangle by its plane), each mesh turned outward
/// if its signed volume is negative (OBJ files do not agree on a winding).
/// Degenerate triangles are left out: they have no normal and draw nothing.
fn flat_mesh(meshes: &[Mesh]) -> RenderMesh {
    let mut out = RenderMesh::default();
    for m in meshes {
        let corners = |t: &[u32; 3]| -> Option<[Vec3; 3]> {
            let [a, b, c] = t.map(|i| m.positions.get(i as usize).copied());
            Some([a?, b?, c?])
        };
        let volume: f32 =
            m.triangles.iter().filter_map(corners).map(|[a, b, c]| a.dot(b.cross(c))).sum();
        let triangles = m.triangles.iter().filter_map(|t| {
            let [a, b, c] = corners(t)?;
            let t = if volume < 0.0 { [t[0], t[2], t[1]] } else { *t };
            (b - a).cross(c - a).try_normalize().map(|_| t)
        });
        push_flat(&mut out, &m.positions, triangles);
    }
    out
}

/// The shape's convex hulls, flat-shaded: the box and the tetrahedron are
/// exactly theirs.
fn flat_hull_mesh(shape: &Shape) -> RenderMesh {
    let mut out = RenderMesh::default();
    for part in shape.parts() {
        if let Part::Hull(part) = part {
            push_flat(&mut out, part.hull.vertices(), part.hull.triangles());
        }
    }
    out
}

/// Appends `positions` with zero (flat) normals and `triangles` on them.
fn push_flat(out: &mut RenderMesh, positions: &[Vec3], triangles: impl Iterator<Item = [u32; 3]>) {
    let base = out.positions.len() as u32;
    out.positions.extend_from_slice(positions);
    out.normals.resize(out.positions.len(), Vec3::ZERO);
    out.indices.extend(triangles.flatten().map(|i| base + i));
}

/// The shape's capsules as the hulls of [`CAPSULE_POINTS`] points on each,
/// with the round capsule's normals (from the nearest point of its core): it
/// looks round, and no vertex pokes out of its bounds.
fn smooth_capsule(shape: &Shape) -> RenderMesh {
    let mut out = RenderMesh::default();
    for part in shape.parts() {
        let Part::Capsule(capsule) = part else { continue };
        let (r, h) = (capsule.radius, capsule.half_height);
        let normals: Vec<Vec3> = fibonacci_sphere(CAPSULE_POINTS).collect();
        let points: Vec<Vec3> =
            normals.iter().map(|&n| n * r + Vec3::Y * h.copysign(n.y)).collect();
        let Ok(hull) = ConvexHull::new(&points) else { continue };
        let base = out.positions.len() as u32;
        out.positions.extend_from_slice(hull.vertices());
        out.normals.extend(hull.vertices().iter().map(|&p| {
            let core = Vec3::Y * p.y.clamp(-h, h);
            (p - core).try_normalize().unwrap_or(Vec3::Y * p.y.signum())
        }));
        out.indices.extend(hull.triangles().flatten().map(|i| base + i));
    }
    out
}

/// `n` points spread evenly on the unit sphere (the Fibonacci lattice), in
/// f64 and then rounded.
fn fibonacci_sphere(n: usize) -> impl Iterator<Item = Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n).map(move |i| {
        let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let r = (1.0 - y * y).sqrt();
        let a = golden * i as f64;
        DVec3::new(r * a.cos(), y, r * a.sin()).as_vec3()
    })
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

#[cfg(test)]
mod tests {
    use super::*;
    use bvol::volumes::{Obb, ObbMethod, SphereMethod};

    /// A file in a fresh temporary folder of this test run.
    fn temp_file(name: &str, contents: &[u8]) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("falling-shapes-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, contents).unwrap();
        path
    }

    /// Signed volume of a closed triangle mesh (positive when wound outward);
    /// nearly so for a mesh with small holes.
    fn signed_volume(mesh: &RenderMesh) -> f32 {
        let p = |i: u32| mesh.positions[i as usize];
        mesh.indices.chunks_exact(3).map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2])))).sum::<f32>() / 6.0
    }

    /// Whether `p` lies in the OBB grown by `pad`.
    fn in_obb(obb: &Obb, p: Vec3, pad: f32) -> bool {
        let d = p - obb.center;
        (0..3).all(|i| d.dot(obb.axes.col(i)).abs() <= obb.half_extents[i] + pad)
    }

    #[test]
    fn default_library_has_the_primitives_and_the_assets() {
        let files = ShapeLibrary::default_mesh_files();
        let stems: Vec<_> = files.iter().filter_map(|f| f.file_stem()?.to_str()).collect();
        for asset in ["bunny", "duck", "teapot"] {
            assert!(stems.contains(&asset), "{asset} missing from {files:?}");
        }
        let library = ShapeLibrary::load(&files, FitOptions::default());
        assert!(library.errors.is_empty(), "{:?}", library.errors);
        let names: Vec<&str> = library.entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names[..4], ["box", "ball", "capsule", "tetrahedron"]);
        assert_eq!(names[4..], stems);
        for entry in &library.entries {
            let radius = entry.shape.sphere().radius;
            assert!((0.3..=0.6).contains(&radius), "{}: radius {radius}", entry.name);
        }
        assert!(matches!(library.entries[1].shape.parts(), [Part::Ball(_)]));
    }

    #[test]
    fn bad_files_are_reported_and_the_rest_load() {
        let missing = std::env::temp_dir().join("falling-no-such-dir/none.obj");
        let broken = temp_file("broken.obj", b"v 0 0 0\nv 1 0 nan\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
        // Points on a line are no solid (a flat sheet would be: a thin slab).
        let line = temp_file("line.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
        let binary = temp_file("binary.obj", &[0xff, 0xfe, 0x00, 0x81]);
        let mut files = vec![missing.clone(), broken.clone(), line.clone(), binary.clone()];
        files.extend(ShapeLibrary::default_mesh_files());
        let library = ShapeLibrary::load(&files, FitOptions::default());
        let good = ShapeLibrary::default_mesh_files().len();
        assert_eq!(library.entries.len(), 4 + good, "primitives and the good assets");
        assert_eq!(library.errors.len(), 4, "{:#?}", library.errors);
        for (error, file) in library.errors.iter().zip([&missing, &broken, &line, &binary]) {
            assert!(error.contains(&*file.to_string_lossy()), "{error} should name {file:?}");
        }
    }

    #[test]
    fn inside_out_files_are_turned_outward() {
        // A cube off the origin whose quads all wind clockwise seen from outside.
        let mut obj = String::new();
        for i in 0..8 {
            let bit = |b: i32| if i >> b & 1 == 1 { 3.0 } else { 1.0 };
            obj += &format!("v {} {} {}\n", bit(0), bit(1), bit(2) + 5.0);
        }
        for quad in ["1 2 4 3", "5 7 8 6", "1 5 6 2", "3 4 8 7", "1 3 7 5", "2 6 8 4"] {
            obj += &format!("f {quad}\n");
        }
        let path = temp_file("inside-out.obj", obj.as_bytes());
        let raw = bvol::load_obj(&path).unwrap();
        let at = |i: u32| raw[0].positions[i as usize];
        let raw_volume: f32 =
            raw[0].triangles.iter().map(|t| at(t[0]).dot(at(t[1]).cross(at(t[2])))).sum();
        assert!(raw_volume < 0.0, "the file is wound inward");
        let library = ShapeLibrary::load(&[path], FitOptions::default());
        assert!(library.errors.is_empty(), "{:?}", library.errors);
        let mesh = &library.entries[4].mesh;
        assert_eq!(mesh.indices.len(), 36);
        assert!(signed_volume(mesh) > 0.0);
        assert!(mesh.normals.iter().all(|&n| n == Vec3::ZERO), "flat shaded");
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            let centre = (a + b + c) / 3.0;
            assert!((b - a).cross(c - a).dot(centre) > 0.0, "the cube is centred");
        }
        // Side 2 scaled so that its corners are MESH_RADIUS from the centre.
        let half = library.entries[4].shape.obb().half_extents;
        let expected = MESH_RADIUS / 3f32.sqrt();
        assert!((half - Vec3::splat(expected)).abs().max_element() < 1e-4, "{half}");
    }

    #[test]
    fn render_meshes_are_outward_and_inside_the_bounds() {
        let mut library =
            ShapeLibrary::load(&ShapeLibrary::default_mesh_files(), FitOptions::default());
        let fits = [
            FitOptions::default(),
            FitOptions { sphere: SphereMethod::Ritter, obb: ObbMethod::PcaPoints },
            FitOptions { sphere: SphereMethod::Centroid, obb: ObbMethod::Dito14 },
        ];
        for fit in fits {
            library.set_fit(fit).unwrap();
            for (entry, mesh) in
                library.entries.iter().flat_map(|e| [(e, &e.mesh), (e, &e.far_mesh)])
            {
                let name = &entry.name;
                assert_eq!(mesh.positions.len(), mesh.normals.len());
                assert!(!mesh.indices.is_empty() && mesh.indices.len() % 3 == 0);
                assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.positions.len()));
                let unit_or_flat = |n: &Vec3| *n == Vec3::ZERO || (n.length() - 1.0).abs() < 1e-4;
                assert!(mesh.normals.iter().all(unit_or_flat), "{name}");
                assert!(signed_volume(mesh) > 0.0, "{name} is wound inward");
                let (obb, sphere) = (entry.shape.obb(), entry.shape.sphere());
                for &p in &mesh.positions {
                    assert!(in_obb(&obb, p, 1e-4), "{name}: {p} out of its OBB");
                    assert!(p.distance(sphere.center) <= sphere.radius + 1e-4, "{name}: {p}");
                }
            }
        }
    }

    /// The far meshes of the real meshes keep at most half the triangles
    /// (a twentieth where the error bound allows), yet the same solid: the same extent along every axis
    /// (their vertices are a subset of the full mesh's) and within 15% of
    /// its volume, about 5% in size: a pixel at the largest on-screen size
    /// they are drawn at (a radius of 24 pixels).
    #[test]
    fn far_meshes_are_small_and_like_the_full_ones() {
        let library =
            ShapeLibrary::load(&ShapeLibrary::default_mesh_files(), FitOptions::default());
        let extent = |m: &RenderMesh| {
            let lo = m.positions.iter().fold(Vec3::MAX, |a, &p| a.min(p));
            let hi = m.positions.iter().fold(Vec3::MIN, |a, &p| a.max(p));
            hi - lo
        };
        for entry in library.entries.iter().filter(|e| e.source.is_some()) {
            let (full, far, name) = (&entry.mesh, &entry.far_mesh, &entry.name);
            let (n_full, n_far) = (full.indices.len() / 3, far.indices.len() / 3);
            let (v_full, v_far) = (signed_volume(full), signed_volume(far));
            assert!(n_far * 2 <= n_full && n_far >= 20, "{name}: {n_full} -> {n_far} triangles");
            assert!((v_far / v_full - 1.0).abs() < 0.15, "{name}: volume {v_full} -> {v_far}");
            let ratio = extent(far) / extent(full);
            assert!(ratio.cmple(Vec3::splat(1.0 + 1e-6)).all(), "{name}: extent {ratio}");
            assert!(ratio.cmpge(Vec3::splat(0.85)).all(), "{name}: extent {ratio}");
        }
    }

    #[test]
    fn convex_primitives_face_away_from_their_centre() {
        let library = ShapeLibrary::load(&[], FitOptions::default());
        assert_eq!(library.entries.len(), 4);
        for entry in &library.entries {
            let m = &entry.mesh;
            for t in m.indices.chunks_exact(3) {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                let centre = (a + b + c) / 3.0;
                // Winding and smooth normals agree, and both point out of
                // the convex solid (zero normals: flat, by the winding).
                let face = (b - a).cross(c - a);
                assert!(face.dot(centre) > 0.0, "{}: triangle {t:?} faces in", entry.name);
                let n = m.normals[t[0] as usize];
                assert!(n == Vec3::ZERO || n.dot(centre) > 0.0, "{}: normal {n}", entry.name);
            }
        }
        let volume = signed_volume(&library.entries[1].mesh);
        let ball = 4.0 / 3.0 * std::f32::consts::PI * BALL_RADIUS.powi(3);
        assert!((volume - ball).abs() < 0.05 * ball, "the ball mesh is a sphere");
    }

    #[test]
    fn meshes_are_centred_on_their_hull_centre_of_mass() {
        let library =
            ShapeLibrary::load(&ShapeLibrary::default_mesh_files(), FitOptions::default());
        for entry in library.entries.iter().filter(|e| e.source.is_some()) {
            let [Part::Hull(part)] = entry.shape.parts() else { panic!("one hull") };
            let hull = &part.hull;
            let inside = |p: Vec3| {
                let p = p.as_dvec3();
                (0..hull.face_count()).all(|f| hull.face_normal(f).dot(p) <= hull.face_offset(f))
            };
            // The mean of a grid's points inside the hull: its centroid, measured
            // independently of the tetrahedra that placed it.
            let n = 40;
            let (mut sum, mut count) = (Vec3::ZERO, 0);
            for i in 0..n * n * n {
                let cell = Vec3::new((i % n) as f32, ((i / n) % n) as f32, (i / (n * n)) as f32);
                let p = (cell + 0.5) / n as f32 * 2.0 * MESH_RADIUS - MESH_RADIUS;
                if inside(p) {
                    sum += p;
                    count += 1;
                }
            }
            let centroid = sum / count as f32;
            assert!(centroid.length() < 0.01, "{}: centroid {centroid}", entry.name);
            let far = entry.mesh.positions.iter().map(|p| p.length()).fold(0.0, f32::max);
            assert!((far - MESH_RADIUS).abs() < 1e-4, "{}: scaled to {far}", entry.name);
        }
    }
}
