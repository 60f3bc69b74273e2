//! Physics kernels as plain functions on plain data: contact laws, walls, integration.
//! Nothing here speaks MPI or does I/O.

pub mod batch;
pub mod cohesion;
pub mod contact;
pub mod integrate;
pub mod law;
pub mod materials;
pub mod normal;
pub mod rapaport;
pub mod rolling;
pub mod rough_wall;
pub mod tangential;
pub mod wall_batch;
pub mod walls;

pub use contact::{Body, Contact};
pub use law::ContactLaw;
pub use materials::Materials;
pub use rapaport::V3;
pub use walls::DrumWalls;
