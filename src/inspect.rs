//! Reading a run's HDF5 file back (docs/diagnostics.md, "Commands"): `tumbler info` lists
//! what a file holds, `tumbler bands` tabulates the band count over time, `tumbler export`
//! writes a run's particles as a LAMMPS data file, `tumbler import` reads a LAMMPS data file
//! or dump into the `/particles` layout, `tumbler export --vtu` writes snapshots as VTK files,
//! and [`RunReader`] is the reading layer
//! the plots (`crate::plot`) share.
//!
//! Every refusal is an [`InspectError`] that names the file, the dataset or the argument at
//! fault; the command line turns each into exit code [`EXIT_BAD_INPUT`].

mod bands;
mod export;
mod import;
mod info;
mod number;
mod reader;
mod vtu;

pub use bands::{band_table, effective_rule, BandTable, BandsOptions};
pub use export::{export_lammps, Exported, BOX_PAD};
pub use import::{import_lammps, ImportOptions, Imported, LammpsKind};
pub use info::{info, InfoOptions, CASE_LINES};
pub use number::{short as short_number, tick as tick_label};
pub use reader::{attr_display, attr_number, attr_string, format_shape, RunReader, Window};
pub use vtu::{export_vtu, VtuExported};

/// Exit code of `info`, `bands` and `plot` for every refusal (as for a refused case).
pub const EXIT_BAD_INPUT: u8 = 2;

/// Why a file could not be read or a plot could not be made.
#[derive(Debug, thiserror::Error)]
pub enum InspectError {
    /// The file does not exist or is not a readable HDF5 file.
    #[error("{path}: {reason}")]
    File {
        /// The file.
        path: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A dataset or attribute the command needs is not in the file.
    #[error("{path} has no {name}: the run did not write it{hint}")]
    Missing {
        /// The file.
        path: String,
        /// The dataset (`/slices/q_up`) or attribute (`attribute case`).
        name: String,
        /// Further explanation, starting with a separator (or empty).
        hint: String,
    },
    /// A dataset is there but not of the documented shape or type.
    #[error("{path}: {name} {reason}")]
    Layout {
        /// The file.
        path: String,
        /// The dataset.
        name: String,
        /// What does not match.
        reason: String,
    },
    /// A command-line value that cannot be used with this file (quantity, plane, window...).
    #[error("{0}")]
    Invalid(String),
    /// The picture could not be drawn or written.
    #[error("cannot write {path}: {reason}")]
    Write {
        /// The picture's path.
        path: String,
        /// Why.
        reason: String,
    },
}
