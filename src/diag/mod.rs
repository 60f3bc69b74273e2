//! Diagnostics computed in the run and gathered to rank 0.

pub mod axial;

pub use axial::{AxialBins, AxialSample};
