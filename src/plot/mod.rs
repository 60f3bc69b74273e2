//! `tumbler plot ...`: pictures of a run's HDF5 file (docs/diagnostics.md, "Commands"):
//! the space-time plot, axial profiles of a window, a binned field on a plane, and the
//! mixture's upstream/downstream fluxes over the windows.
//!
//! Each plot reads what it needs through [`crate::inspect::RunReader`] (a missing dataset
//! or a bad option is an [`InspectError`] naming it), draws with `plotters` on a bitmap
//! with an embedded font, and writes a PNG, by default `STEM_<what>.png` beside the file.

mod canvas;
mod colormap;
mod heatmap;
mod lines;
mod quantity;
mod series;

pub mod field;
pub mod flux;
pub mod profile;
pub mod spacetime;

pub use field::{plot_field, FieldOptions};
pub use flux::{plot_flux, FluxOptions};
pub use profile::{plot_profile, ProfileOptions};
pub use quantity::{Plane, Quantity, QUANTITIES};
pub use spacetime::{plot_spacetime, SpacetimeOptions};

use crate::inspect::{InspectError, RunReader};
use std::path::{Path, PathBuf};

/// `STEM_<what>.png` beside `file` (characters other than letters, digits, `-`, `_` and `.`
/// in `what` become `-`).
pub fn default_output(file: &Path, what: &str) -> PathBuf {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "tumbler".into());
    let what: String = what
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '-'
            }
        })
        .collect();
    file.with_file_name(format!("{stem}_{what}.png"))
}

/// `z [m]`: an axis name with the `units` attribute of `dataset`, if it has one.
fn length_label(reader: &RunReader, axis: &str, dataset: &str) -> String {
    match reader.units(dataset) {
        Some(u) => format!("{axis} [{u}]"),
        None => axis.to_string(),
    }
}

/// Parse `--windows a,b,c`.
pub fn parse_windows(text: &str) -> Result<Vec<usize>, InspectError> {
    text.split(',')
        .map(|w| {
            w.trim().parse::<usize>().map_err(|_| {
                InspectError::Invalid(format!(
                    "bad window '{w}' in --windows {text}: expected indices like 0,3,7"
                ))
            })
        })
        .collect()
}
