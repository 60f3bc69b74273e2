//! Initial states.

mod lattice;

pub use lattice::lattice;
