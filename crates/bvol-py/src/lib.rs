//! The native half of the Python package `bvol`: fitting bounds to numpy
//! point arrays, batched tests of bounds, and the World. The Python half
//! (`python/bvol`) re-exports it, lays out events and ray hits as
//! structured arrays, and carries the type stubs.
//!
//! Every call that works on arrays runs without the GIL. Errors are
//! Python exceptions carrying the Rust API's one-line messages.

mod arrays;
mod batch;
mod errors;
mod fit;
mod mesh;
mod shape;
mod world;

use pyo3::prelude::*;

/// bvol's native module (import `bvol`, which re-exports it).
#[pymodule]
mod _bvol {
    #[pymodule_export]
    use crate::batch::{boxes_overlap, ray_boxes, ray_spheres, spheres_overlap};
    #[pymodule_export]
    use crate::fit::{
        PyAabb, PyKdop, PyOrientedBox, PySphere, aabb, bounding_sphere, convex_hull, kdop,
        oriented_box,
    };
    #[pymodule_export]
    use crate::mesh::{PyMesh, load_obj};
    #[pymodule_export]
    use crate::shape::PyShape;
    #[pymodule_export]
    use crate::world::PyWorld;

    use pyo3::prelude::*;

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        m.add("NO_BODY", crate::world::NO_BODY)?;
        for (name, kind) in crate::world::EVENT_KINDS {
            m.add(name, crate::world::event_code(kind))?;
        }
        m.add("MAX_COORDINATE", bvol::MAX_COORDINATE)?;
        m.add("SPHERE_METHODS", sphere_names())?;
        m.add("OBB_METHODS", obb_names())?;
        Ok(())
    }

    fn sphere_names() -> Vec<&'static str> {
        bvol::volumes::SphereMethod::ALL.iter().map(|m| m.name()).collect()
    }

    fn obb_names() -> Vec<&'static str> {
        bvol::volumes::ObbMethod::ALL.iter().map(|m| m.name()).collect()
    }
}
