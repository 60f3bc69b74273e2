//! Physics kernels as plain functions on plain data: contact laws, walls, integration.
//! Nothing here speaks MPI or does I/O.

pub mod integrate;
pub mod materials;
pub mod rapaport;
pub mod walls;

pub use materials::Materials;
pub use rapaport::V3;
pub use walls::DrumWalls;
