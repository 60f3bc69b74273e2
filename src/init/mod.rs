//! Initial states: Rapaport's fcc lattice, the thesis' pour fill, explicit particles.

mod explicit;
mod lattice;
pub mod pour;

pub use explicit::explicit;
pub use lattice::{fcc_spacing, lattice};

use crate::case::{Case, InitKind};
use crate::particles::ParticleState;

/// The particles a run starts from, sorted by id, and the factor by which their diameters
/// start (below 1 only for a pour, whose points then grow and settle in the engine).
pub fn initial_particles(case: &Case) -> Result<(Vec<ParticleState>, f64), String> {
    match case.init.kind {
        InitKind::Lattice => Ok((lattice(case), 1.0)),
        InitKind::Particles => Ok((explicit(case)?, 1.0)),
        InitKind::Pour => pour::points(case),
    }
}
