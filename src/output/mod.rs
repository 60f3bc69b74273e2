//! Files a run writes: the HDF5 file (axial series, diagnostics, snapshots) with its XDMF
//! companion, the space-time PNG, checkpoints.

pub mod checkpoint;
pub mod diag_file;
pub mod h5;
pub mod series;
pub mod spacetime;
pub mod xdmf;

pub use h5::{partial_path, RunFile, RunMeta};
