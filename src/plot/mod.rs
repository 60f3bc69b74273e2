//! `tumbler plot ...`: pictures of a run's HDF5 file (docs/diagnostics.md, "Commands"):
//! the space-time plot, axial profiles of a window, a binned field on a plane, and the
//! mixture's upstream/downstream fluxes over the windows.
//!
//! Each plot reads what it needs through [`crate::inspect::RunReader`] (a missing dataset
//! or a bad option is an [`InspectError`] naming it), draws with `plotters` with an
//! embedded font, and writes a PNG, an SVG or a PDF (`--format`, or the extension of `-o`),
//! by default `STEM_<what>.png` beside the file. A plot of one window defaults to the last
//! complete one (`windows.rs`).

mod canvas;
mod colormap;
mod heatmap;
mod lines;
mod quantity;
mod series;
pub mod windows;

pub mod field;
pub mod flux;
pub mod profile;
pub mod spacetime;

pub use canvas::Format;
pub use field::{plot_field, plot_field_in, FieldOptions};
pub use flux::{plot_flux, plot_flux_in, FluxOptions};
pub use profile::{plot_profile, plot_profile_in, ProfileOptions};
pub use quantity::{Plane, Quantity, QUANTITIES};
pub use spacetime::{plot_spacetime, plot_spacetime_in, SpacetimeOptions};

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

/// The file to write and its format: `-o` (`output`) if given, else `STEM_<what>.EXT`
/// beside `file`; the format is `--format` (`format`), else that of `-o`'s extension, else
/// PNG. A `--format` that contradicts `-o`'s extension is refused.
pub fn output_path(
    file: &Path,
    output: Option<&Path>,
    what: &str,
    format: Option<Format>,
) -> Result<(PathBuf, Format), InspectError> {
    let Some(out) = output else {
        let format = format.unwrap_or_default();
        let path = default_output(file, what).with_extension(format.extension());
        return Ok((path, format));
    };
    let by_name = out
        .extension()
        .and_then(|e| Format::parse(&e.to_string_lossy().to_ascii_lowercase()).ok());
    match (format, by_name) {
        (Some(f), Some(n)) if f != n => Err(InspectError::Invalid(format!(
            "--format {} but -o {} names a .{} file; give one or make them agree",
            f.extension(),
            out.display(),
            n.extension()
        ))),
        (f, n) => Ok((out.to_path_buf(), f.or(n).unwrap_or_default())),
    }
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
