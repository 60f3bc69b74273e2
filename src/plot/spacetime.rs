//! `tumbler plot spacetime`: the space-time plot of `/axial/volume_fraction` (time left to
//! right, `z` up, grey level the big species' volume fraction: dark = small, light = big,
//! mid grey = empty slice), with axes and a grey scale; `--bare` writes the run's own
//! picture instead (`output::spacetime`, no axes).

use super::canvas::{edges, render_png, text, ticks};
use super::{default_output, length_label};
use crate::inspect::{InspectError, RunReader};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Picture size in pixels (with axes).
pub const SIZE: (u32, u32) = (1000, 440);
/// Width of the grey scale strip on the right, in pixels.
const BAR_WIDTH: u32 = 130;

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct SpacetimeOptions {
    /// `-o` (default `STEM_spacetime.png` beside the file).
    pub output: Option<PathBuf>,
    /// Write the run's picture (`crate::output::spacetime`) without axes.
    pub bare: bool,
}

/// Draw the space-time plot of `file`; returns the picture's path.
pub fn plot_spacetime(file: &Path, opts: &SpacetimeOptions) -> Result<PathBuf, InspectError> {
    let reader = RunReader::open(file)?;
    let rotations = reader.vector("axial/rotations")?;
    let z = reader.centres("axial/z")?;
    let vf = reader.array("axial/volume_fraction", &["T", "S", "Z"])?;
    let big = reader.big_species()?;
    let s = vf.shape();
    reader.check_len("axial/volume_fraction", s[2], z.len(), "slices")?;
    if big >= s[1] {
        return Err(reader.layout(
            "axial/volume_fraction",
            format!(
                "has {} species, so the big species {big} is not in it",
                s[1]
            ),
        ));
    }
    let nt = rotations.len().min(s[0]);
    if nt == 0 {
        return Err(InspectError::Invalid(format!(
            "{}: no axial samples yet",
            file.display()
        )));
    }
    let columns: Vec<Vec<f64>> = (0..nt)
        .map(|t| (0..z.len()).map(|k| vf[[t, big, k]]).collect())
        .collect();
    let path = opts
        .output
        .clone()
        .unwrap_or_else(|| default_output(file, "spacetime"));
    if opts.bare {
        crate::output::spacetime::write_png(&path, &columns).map_err(|e| InspectError::Write {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        return Ok(path);
    }
    let names = reader.species_names();
    let big_name = names
        .get(big)
        .map(|n| format!("species {big} ({n})"))
        .unwrap_or_else(|| format!("species {big}"));
    let title = format!("volume fraction of {big_name}: light = big, dark = small, grey = empty");
    let z_label = length_label(&reader, "z", "axial/z");
    let times = edges(&rotations[..nt]);
    let slices = edges(&z);
    render_png(&path, SIZE, |root| {
        let body = root.titled(&title, text(18))?;
        let (w, _) = body.dim_in_pixel();
        let (main, bar) = body.split_horizontally(w.saturating_sub(BAR_WIDTH));
        let t_range = if nt > 1 {
            rotations[0]..rotations[nt - 1]
        } else {
            rotations[0] - 0.5..rotations[0] + 0.5
        };
        let z_range = slices[0]..slices[z.len()];
        let mut chart = ChartBuilder::on(&main)
            .margin(10)
            .x_label_area_size(48)
            .y_label_area_size(80)
            .build_cartesian_2d(t_range.clone(), z_range.clone())?;
        let (xs, ys) = chart.plotting_area().get_pixel_range();
        let (pw, ph) = ((xs.end - xs.start) as f64, (ys.end - ys.start) as f64);
        for px in xs.clone() {
            let t = t_range.start + (px - xs.start) as f64 / pw * (t_range.end - t_range.start);
            let ti = cell(&times, t);
            for py in ys.clone() {
                let zz = z_range.end - (py - ys.start) as f64 / ph * (z_range.end - z_range.start);
                root.draw_pixel((px, py), &grey(columns[ti][cell(&slices, zz)]))?;
            }
        }
        let (t_fmt, z_fmt) = (ticks(&t_range), ticks(&z_range));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("time [rotations]")
            .y_desc(z_label.as_str())
            .x_label_formatter(&t_fmt)
            .y_label_formatter(&z_fmt)
            .label_style(text(14))
            .axis_desc_style(text(16))
            .draw()?;
        let mut scale = ChartBuilder::on(&bar)
            .margin(10)
            .x_label_area_size(48)
            .y_label_area_size(76)
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)?;
        scale.draw_series((0..100).map(|k| {
            let c = k as f64 / 100.0;
            Rectangle::new([(0.0, c), (1.0, c + 0.01)], grey(c + 0.005).filled())
        }))?;
        let fmt = ticks(&(0.0..1.0));
        scale
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc("volume fraction")
            .y_label_formatter(&fmt)
            .label_style(text(13))
            .axis_desc_style(text(14))
            .draw()?;
        Ok(())
    })?;
    Ok(path)
}

/// Index of the cell of `edges` holding `v` (clamped to the first and last cells).
fn cell(edges: &[f64], v: f64) -> usize {
    edges
        .partition_point(|e| *e <= v)
        .saturating_sub(1)
        .min(edges.len() - 2)
}

/// Grey level of a volume fraction as in the run's picture (NaN: mid grey).
fn grey(c: f64) -> RGBColor {
    let g = if c.is_finite() {
        (c.clamp(0.0, 1.0) * 255.0).round() as u8
    } else {
        128
    };
    RGBColor(g, g, g)
}
