//! bvol
pub use bvol_volumes as volumes;
