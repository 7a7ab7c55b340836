//! Triangle meshes read from Wavefront OBJ files (with tobj).

use std::fmt;
use std::path::{Path, PathBuf};

use glam::Vec3;

/// One object of an OBJ file: its vertices and triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The object's name in the file (`o` or `g` statement), or `unnamed_object`.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as indices into `positions` (polygons are fan-triangulated).
    pub triangles: Vec<[u32; 3]>,
}

/// What is wrong with a mesh file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MeshProblem {
    /// The file could not be read (missing, unreadable); the OS's reason.
    Read(String),
    /// The path is not a regular file (a directory, a FIFO, a device such as
    /// `/dev/zero`): such a file may block or never end.
    NotAFile,
    /// The file is not text, so not an OBJ file.
    NotText,
    /// The OBJ parser rejected the file; its reason.
    Parse(String),
    /// The file holds no vertices.
    NoVertices,
    /// A vertex has a NaN or infinite coordinate.
    NonFinite {
        /// The object holding it.
        object: String,
        /// The vertex's index in that object.
        vertex: usize,
    },
}

/// A mesh file that could not be loaded, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshError {
    /// The file.
    pub path: PathBuf,
    /// The problem.
    pub problem: MeshProblem,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.problem {
            MeshProblem::Read(why) => write!(f, "{path}: cannot read: {why}"),
            MeshProblem::NotAFile => write!(f, "{path}: not a regular file"),
            MeshProblem::NotText => write!(f, "{path}: not an OBJ file (not text)"),
            MeshProblem::Parse(why) => write!(f, "{path}: not a valid OBJ file: {why}"),
            MeshProblem::NoVertices => write!(f, "{path}: the mesh has no vertices"),
            MeshProblem::NonFinite { object, vertex } => {
                write!(f, "{path}: object {object:?}, vertex {vertex}: NaN or infinite coordinate")
            }
        }
    }
}

impl std::error::Error for MeshError {}

/// Reads every object of an OBJ file: its vertex positions and faces.
/// Materials, texture coordinates and normals are not read.
///
/// ```
/// let meshes = bvol::load_obj("tests/meshes/teapot.obj").unwrap();
/// assert_eq!(meshes.iter().map(|m| m.positions.len()).sum::<usize>(), 792);
/// assert!(bvol::load_obj("no/such/file.obj").is_err());
/// ```
pub fn load_obj(path: impl AsRef<Path>) -> Result<Vec<Mesh>, MeshError> {
    let path = path.as_ref();
    let error = |problem| MeshError { path: path.to_path_buf(), problem };
    let read = |e: std::io::Error| error(MeshProblem::Read(e.to_string()));
    if !std::fs::metadata(path).map_err(read)?.is_file() {
        return Err(error(MeshProblem::NotAFile));
    }
    let bytes = std::fs::read(path).map_err(read)?;
    let text = std::str::from_utf8(&bytes).map_err(|_| error(MeshProblem::NotText))?;
    let text = without_texcoords_and_normals(text);
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed) // materials are not needed
    })
    .map_err(|e| error(MeshProblem::Parse(e.to_string())))?;
    let meshes: Vec<Mesh> = models.into_iter().map(mesh_of).collect();
    if meshes.iter().all(|m| m.positions.is_empty()) {
        return Err(error(MeshProblem::NoVertices));
    }
    for m in &meshes {
        if let Some(vertex) = m.positions.iter().position(|p| !p.is_finite()) {
            return Err(error(MeshProblem::NonFinite { object: m.name.clone(), vertex }));
        }
    }
    Ok(meshes)
}

/// The OBJ text without its `vt` and `vn` lines. bvol reads positions
/// alone, and tobj (4.0) checks a face's texture and normal indices with
/// unchecked arithmetic (`vt * 2 + 1`), which a far relative index such as
/// `f 1/-3 2/1 3/1` overflows: a panic in a debug build, a wrong read in
/// release. With no texture coordinates or normals those indices are not
/// read at all.
fn without_texcoords_and_normals(text: &str) -> String {
    let kept = text.lines().filter(|l| !matches!(l.split_whitespace().next(), Some("vt" | "vn")));
    kept.flat_map(|l| [l, "\n"]).collect()
}

fn mesh_of(model: tobj::Model) -> Mesh {
    let positions =
        model.mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
    let triangles = model.mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Mesh { name: model.name, positions, triangles }
}
