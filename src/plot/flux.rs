//! `tumbler plot flux`: `|Q_up|` (solid) and `|Q_down|` (dashed) of the mixture along `z`,
//! one pair of lines per window, coloured from dark (early) to light (late); by default at
//! most [`DEFAULT_WINDOWS`] complete windows spread over the run, so the lines can be told
//! apart.

use super::canvas::{edges, render, Format};
use super::colormap::ColorMap;
use super::lines::{Curve, Panel, Stack};
use super::series::mixture;
use super::{length_label, output_path};
use crate::inspect::{short_number, InspectError, RunReader, Window};
use std::path::{Path, PathBuf};

/// Picture size in pixels.
pub const SIZE: (u32, u32) = (1200, 760);
/// Most windows named in the legend (the others are drawn, their colour between).
pub const LEGEND_WINDOWS: usize = 8;
/// Windows drawn when `--windows` is not given.
pub const DEFAULT_WINDOWS: usize = 6;

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct FluxOptions {
    /// `--windows a,b,c` (default up to [`DEFAULT_WINDOWS`] complete windows, evenly spread).
    pub windows: Option<Vec<usize>>,
    /// `-o` (default `STEM_flux.png` beside the file).
    pub output: Option<PathBuf>,
}

/// Draw the flux plot of `file` (format from `-o`, else PNG); returns the picture's path.
pub fn plot_flux(file: &Path, opts: &FluxOptions) -> Result<PathBuf, InspectError> {
    plot_flux_in(file, opts, None)
}

/// [`plot_flux`] in `format` (`--format`; `None`: from `-o`, else PNG).
pub fn plot_flux_in(
    file: &Path,
    opts: &FluxOptions,
    format: Option<Format>,
) -> Result<PathBuf, InspectError> {
    let reader = RunReader::open(file)?;
    let last = reader.window("slices", None)?;
    let indices: Vec<usize> = match &opts.windows {
        Some(list) if list.is_empty() => {
            return Err(InspectError::Invalid("--windows: no window given".into()))
        }
        Some(list) => list.clone(),
        None => {
            let starts = reader.vector("slices/rotations_start")?;
            let ends = reader.vector("slices/rotations_end")?;
            let spans: Vec<(f64, f64)> = starts.into_iter().zip(ends).take(last.count).collect();
            super::windows::spread(&spans, DEFAULT_WINDOWS)
        }
    };
    let windows = indices
        .iter()
        .map(|&k| reader.window("slices", Some(k)))
        .collect::<Result<Vec<Window>, _>>()?;
    let z = reader.centres("slices/z")?;
    let up = mixture(&reader, "slices/q_up_mixture", &windows, z.len())?;
    let down = mixture(&reader, "slices/q_down_mixture", &windows, z.len())?;
    // dark (early) to light (late), stopping short of viridis' pale yellow
    let ends: Vec<f64> = windows.iter().map(|w| w.end).collect();
    let cmap = ColorMap::over(ends.iter().copied(), false);
    let shade = |t: f64| {
        let f = if cmap.hi > cmap.lo {
            (t - cmap.lo) / (cmap.hi - cmap.lo)
        } else {
            0.0
        };
        cmap.color(cmap.lo + 0.85 * f * (cmap.hi - cmap.lo))
    };
    let every = windows.len().div_ceil(LEGEND_WINDOWS).max(1);
    let mut curves = vec![];
    for (n, w) in windows.iter().enumerate() {
        let named = n % every == 0 || n + 1 == windows.len();
        let color = shade(w.end);
        let points = |v: &[f64]| -> Vec<(f64, f64)> {
            z.iter().zip(v).map(|(&z, &q)| (z, q.abs())).collect()
        };
        curves.push(Curve {
            label: if named {
                format!(
                    "window {}: {}-{} rotations",
                    w.index,
                    short_number(w.start),
                    short_number(w.end)
                )
            } else {
                String::new()
            },
            color,
            dashed: false,
            width: 2,
            points: points(&up[n]),
        });
        curves.push(Curve {
            label: String::new(),
            color,
            dashed: true,
            width: 2,
            points: points(&down[n]),
        });
    }
    let e = edges(&z);
    let y_label = match reader.units("slices/q_up_mixture") {
        Some(u) => format!("axial flow rate |Q| [{u}]"),
        None => "axial flow rate |Q| [-]".into(),
    };
    let panel = Panel {
        caption: String::new(),
        x_label: length_label(&reader, "z", "slices/z"),
        y_label,
        x_range: e[0]..e[e.len() - 1],
        curves,
    };
    let (path, format) = output_path(file, opts.output.as_deref(), "flux", format)?;
    let figure = Stack {
        title:
            "axial flow rate of the mixture: upstream |Q_up| (solid), downstream |Q_down| (dashed)"
                .into(),
        panels: vec![panel],
        size: SIZE,
    };
    render(&path, format, &figure)?;
    Ok(path)
}
