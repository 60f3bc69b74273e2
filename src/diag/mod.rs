//! Diagnostics computed in the run and gathered to rank 0 (definitions and file layout in
//! `docs/diagnostics.md`). The kernels here know nothing of files; `crate::output` writes
//! what they return.
//!
//! - [`axial`]: counts, volume fractions and axial velocities per thin slice, every sample;
//! - [`bands`]: the band count of an axial profile;
//! - [`surface`]: the angle of repose measured from the particles, and the surface frame;
//! - [`grid`]: cuboid bins in the surface frame and the exact sums gathered in them;
//! - [`slices`]: upstream/downstream axial flow rates and the diffusivity `K` per slice;
//! - [`fields`]: binned density, velocity and fluctuation fields, and the flowing layer;
//! - [`windows`]: sampling and averaging windows of the two above;
//! - [`paths`]: positions and velocities of chosen particles;
//! - [`fixed`]: the fixed-point sums that make all of these rank-count invariant.

pub mod axial;
pub mod bands;
pub mod fields;
pub mod fixed;
pub mod grid;
pub mod paths;
pub mod slices;
pub mod surface;
pub mod windows;

pub use axial::{AxialBins, AxialSample};
pub use bands::{count_bands, find_bands, Band, BandRule};
pub use paths::PathTracker;
pub use windows::{SliceRecord, Windows};
