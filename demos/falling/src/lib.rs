//! bvol's falling-objects demo: bodies rain onto a floor and pile up, with
//! bvol finding every contact and a small rigid-body integrator of the
//! demo's own answering them. Drawn with wgpu (instanced) and egui, in a
//! window or headless into a PNG.
//!
//! The demo uses only bvol's public API, as an embedding application would:
//! shapes from primitives and OBJ files ([`shapes`]), a [`bvol::World`]
//! updated once per step ([`sim`]), its per-stage figures shown live
//! ([`ui`]) and its bounds, tree and contacts drawn as overlays
//! ([`overlay`]).

#![warn(missing_docs)]

pub mod app;
pub mod camera;
pub mod frontend;
pub mod headless;
pub mod overlay;
pub mod render;
pub mod shapes;
pub mod sim;
pub mod stats;
pub mod ui;
pub mod windowed;
