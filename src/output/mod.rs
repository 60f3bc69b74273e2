//! Files a run writes: the HDF5 file, the space-time PNG, checkpoints.

pub mod checkpoint;
pub mod h5;
pub mod spacetime;

pub use h5::{partial_path, RunFile, RunMeta};
