//! `tumbler plot profile`: axial profiles in one window of `/slices` as three stacked
//! panels sharing `z`: concentrations, upstream/downstream fluxes (per species and of the
//! mixture), and the diffusivity `K` of species 0.

use super::canvas::{edges, render, Format};
use super::lines::{palette, Curve, Panel, Stack};
use super::series::{mixture, per_species};
use super::{length_label, output_path};
use crate::inspect::{InspectError, RunReader};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Picture size in pixels.
pub const SIZE: (u32, u32) = (1000, 1240);

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct ProfileOptions {
    /// `--window` (default the last complete one).
    pub window: Option<usize>,
    /// `-o` (default `STEM_profile_<window>.png` beside the file).
    pub output: Option<PathBuf>,
}

/// Draw the profile plot of `file` (format from `-o`, else PNG); returns the picture's path.
pub fn plot_profile(file: &Path, opts: &ProfileOptions) -> Result<PathBuf, InspectError> {
    plot_profile_in(file, opts, None)
}

/// [`plot_profile`] in `format` (`--format`; `None`: from `-o`, else PNG).
pub fn plot_profile_in(
    file: &Path,
    opts: &ProfileOptions,
    format: Option<Format>,
) -> Result<PathBuf, InspectError> {
    let reader = RunReader::open(file)?;
    let window = super::windows::chosen(&reader, "slices", opts.window)?;
    let z = reader.centres("slices/z")?;
    let nz = z.len();
    let names = reader.species_names();
    let conc = per_species(&reader, "slices/concentration", &window, nz)?;
    let q_up = per_species(&reader, "slices/q_up", &window, nz)?;
    let q_down = per_species(&reader, "slices/q_down", &window, nz)?;
    let windows = [window.clone()];
    let up_mix = mixture(&reader, "slices/q_up_mixture", &windows, nz)?.remove(0);
    let down_mix = mixture(&reader, "slices/q_down_mixture", &windows, nz)?.remove(0);
    let diff = per_species(&reader, "slices/diffusivity", &window, nz)?;
    let name = |s: usize| {
        names
            .get(s)
            .cloned()
            .unwrap_or_else(|| format!("species {s}"))
    };
    let along =
        |v: &[f64]| -> Vec<(f64, f64)> { z.iter().copied().zip(v.iter().copied()).collect() };
    let curve = |label: String, color, dashed, width, v: &[f64]| Curve {
        label,
        color,
        dashed,
        width,
        points: along(v),
    };
    let e = edges(&z);
    let x_range = e[0]..e[e.len() - 1];
    let z_label = length_label(&reader, "z", "slices/z");
    let with_units = |what: &str, dataset: &str| match reader.units(dataset) {
        Some(u) => format!("{what} [{u}]"),
        None => format!("{what} [-]"),
    };
    let panels = [
        Panel {
            caption: String::new(),
            x_label: z_label.clone(),
            y_label: with_units("concentration <C_s>", "slices/concentration"),
            x_range: x_range.clone(),
            curves: (0..conc.len())
                .map(|s| curve(name(s), palette(s), false, 2, &conc[s]))
                .collect(),
        },
        Panel {
            caption: String::new(),
            x_label: z_label.clone(),
            y_label: with_units("axial flow rate Q", "slices/q_up"),
            x_range: x_range.clone(),
            curves: (0..q_up.len())
                .flat_map(|s| {
                    [
                        curve(format!("Q_up {}", name(s)), palette(s), false, 1, &q_up[s]),
                        curve(
                            format!("Q_down {}", name(s)),
                            palette(s),
                            true,
                            1,
                            &q_down[s],
                        ),
                    ]
                })
                .chain([
                    curve("Q_up mixture".into(), BLACK, false, 2, &up_mix),
                    curve("Q_down mixture".into(), BLACK, true, 2, &down_mix),
                ])
                .collect(),
        },
        Panel {
            caption: String::new(),
            x_label: z_label,
            y_label: with_units("diffusivity K", "slices/diffusivity"),
            x_range,
            curves: vec![curve(
                format!("K of {}", name(0)),
                palette(0),
                false,
                2,
                diff.first().map(Vec::as_slice).unwrap_or(&[]),
            )],
        },
    ];
    let title = format!("axial profiles, {}", window.label());
    let what = format!("profile_{}", window.index);
    let (path, format) = output_path(file, opts.output.as_deref(), &what, format)?;
    let figure = Stack {
        title,
        panels: panels.to_vec(),
        size: SIZE,
    };
    render(&path, format, &figure)?;
    Ok(path)
}
