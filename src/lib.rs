//! tumbler: an MPI-parallel discrete element solver for granular flow, mixing and
//! segregation in rotating tumblers.
//!
//! Layout (see `ARCHITECTURE.md`): [`case`] reads and checks case files; [`physics`] holds
//! the contact laws, walls and integrator as plain functions; [`engine`] is the
//! slab-decomposed step loop; [`comm`] is the only place that speaks MPI; [`diag`] bins and
//! gathers diagnostics; [`output`] writes HDF5 and PNG; [`run`] drives a whole run;
//! [`inspect`] reads a run's file back (`tumbler info`, `tumbler bands`) and [`plot`] draws
//! pictures of it (`tumbler plot ...`); [`validate`] runs the seeds' reduced cases and
//! checks their results (`tumbler validate`).
#![warn(missing_docs)]
// Struct-of-arrays kernels index several parallel arrays with one loop index.
#![allow(clippy::needless_range_loop)]

pub mod case;
pub mod comm;
pub mod diag;
pub mod engine;
pub mod init;
pub mod inspect;
pub mod output;
pub mod particles;
pub mod physics;
pub mod plot;
pub mod report;
pub mod run;
pub mod validate;

/// Git commit the binary was built from.
pub const GIT_HASH: &str = env!("TUMBLER_GIT_HASH");
