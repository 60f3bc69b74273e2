//! Files a run writes: the HDF5 file and the space-time PNG.

pub mod h5;
pub mod spacetime;

pub use h5::{partial_path, RunFile, RunMeta};
