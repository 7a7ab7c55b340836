//! OBJ files, through the loader the CLI and `Shape::from_obj` use, and the
//! shape built from what it accepts.

use bvol::{FitOptions, Part, Shape, load_obj};

use crate::checks::{behind_every_face, finite, one_line_error};

/// Tokens of the OBJ grammar and numbers at the edges of f32.
pub const DICTIONARY: &[&[u8]] = &[
    b"v ",
    b"vn ",
    b"vt ",
    b"f ",
    b"o ",
    b"g ",
    b"s ",
    b"l ",
    b"p ",
    b"mtllib ",
    b"usemtl ",
    b"\n",
    b" ",
    b"/",
    b"//",
    b"#",
    b"\\\n",
    b"-",
    b"nan",
    b"inf",
    b"-inf",
    b"1e38",
    b"3.4e38",
    b"1e-44",
    b"1e18",
    b"1e19",
    b"0",
    b"-1",
    b"0x1p3",
    b"\r\n",
    b"\0",
    b"\xef\xbb\xbf",
];

/// Loads `data` as an OBJ file. An error names the file in one line; what
/// is accepted has finite vertices, faces that index them, and a shape
/// (when it is a solid) whose sphere and box contain its hulls' vertices,
/// with every mesh vertex behind every face of its hull (to within the
/// hull's tolerance, inside which a vertex counts as on a face: the hull's
/// contract, `ConvexHull::tolerance`).
pub fn run(data: &[u8]) {
    let path = crate::scratch::file("mesh.obj", data);
    let shown = path.display().to_string();
    let meshes = match load_obj(&path) {
        Ok(meshes) => meshes,
        Err(e) => return one_line_error(&e.to_string(), Some(&shown)),
    };
    for m in &meshes {
        m.positions.iter().for_each(|&p| finite(p, "a loaded vertex"));
        let n = m.positions.len() as u32;
        assert!(m.triangles.iter().flatten().all(|&i| i < n), "a face indexes past the vertices");
    }
    let shape = match Shape::from_meshes(&meshes, FitOptions::default()) {
        Ok(shape) => shape,
        Err(e) => return one_line_error(&e.to_string(), None),
    };
    let (sphere, obb) = (shape.sphere(), shape.obb());
    finite(sphere.center, "the shape's sphere");
    assert!(sphere.radius.is_finite(), "the shape's radius is {}", sphere.radius);
    for (m, part) in meshes.iter().zip(shape.parts()) {
        let Part::Hull(hull) = part else { panic!("a mesh gave a part that is not a hull") };
        for &v in hull.hull.vertices() {
            assert!(
                sphere.contains_point(v),
                "hull vertex {v} outside the shape's sphere {sphere:?}"
            );
            assert!(obb.contains_point(v), "hull vertex {v} outside the shape's box {obb:?}");
        }
        behind_every_face(&hull.hull, &m.positions);
    }
    let mass = shape.mass_properties();
    assert!(mass.volume.is_finite() && mass.volume >= 0.0, "volume {}", mass.volume);
    finite(mass.center, "the centre of mass");
    assert!(mass.inertia.is_finite(), "the inertia");
}
