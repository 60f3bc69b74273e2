//! Files a run writes: the HDF5 file (axial series, diagnostics, snapshots) with its XDMF
//! companion, the space-time PNG, checkpoints, and the lock that keeps two runs off the
//! same output.

pub mod checkpoint;
pub mod diag_file;
pub mod dimscales;
pub mod h5;
pub mod lock;
pub mod pario;
pub mod series;
pub mod spacetime;
pub mod xdmf;

pub use h5::{partial_path, RunFile, RunMeta};
