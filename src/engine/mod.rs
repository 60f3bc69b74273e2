//! The slab-decomposed engine: particles, halo, neighbour lists, forces and the step loop.

pub mod balance;
pub mod forces;
pub mod halo;
pub mod neighbor;
pub mod order;
pub mod sim;
pub mod slabs;
pub mod thermo;
pub mod timers;
pub mod wall_pass;

pub use sim::{DecompositionError, Sim};
pub use slabs::Slabs;
pub use timers::{Phase, Timers, PHASES};
