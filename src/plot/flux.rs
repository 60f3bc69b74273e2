//! `tumbler plot flux`: `|Q_up|` (solid) and `|Q_down|` (dashed) of the mixture along `z`,
//! one pair of lines per window, coloured from dark (early) to light (late).

use super::canvas::{edges, render_png};
use super::colormap::ColorMap;
use super::lines::{draw_panel, Curve, Panel};
use super::series::mixture;
use super::{default_output, length_label};
use crate::inspect::{short_number, InspectError, RunReader, Window};
use std::path::{Path, PathBuf};

/// Picture size in pixels.
pub const SIZE: (u32, u32) = (1000, 620);
/// Most windows named in the legend (the others are drawn, their colour between).
pub const LEGEND_WINDOWS: usize = 8;

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct FluxOptions {
    /// `--windows a,b,c` (default every window).
    pub windows: Option<Vec<usize>>,
    /// `-o` (default `STEM_flux.png` beside the file).
    pub output: Option<PathBuf>,
}

/// Draw the flux plot of `file`; returns the picture's path.
pub fn plot_flux(file: &Path, opts: &FluxOptions) -> Result<PathBuf, InspectError> {
    let reader = RunReader::open(file)?;
    let last = reader.window("slices", None)?;
    let indices: Vec<usize> = match &opts.windows {
        Some(list) if list.is_empty() => {
            return Err(InspectError::Invalid("--windows: no window given".into()))
        }
        Some(list) => list.clone(),
        None => (0..last.count).collect(),
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
                    "window {} ({}-{})",
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
        Some(u) => format!("|Q| of the mixture [{u}]"),
        None => "|Q| of the mixture".into(),
    };
    let panel = Panel {
        caption: "|Q_up| (solid) and |Q_down| (dashed) of the mixture; windows in rotations".into(),
        x_label: length_label(&reader, "z", "slices/z"),
        y_label,
        x_range: e[0]..e[e.len() - 1],
        curves,
    };
    let path = opts
        .output
        .clone()
        .unwrap_or_else(|| default_output(file, "flux"));
    render_png(&path, SIZE, |root| draw_panel(root, &panel))?;
    Ok(path)
}
