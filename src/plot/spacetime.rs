//! `tumbler plot spacetime`: the space-time plot of `/axial/volume_fraction` (time left to
//! right, `z` up, grey level the big species' volume fraction: dark = small, light = big;
//! an empty slice in [`EMPTY`], a colour no volume fraction has), with axes and a grey
//! scale; `--bare` writes the run's own picture instead (`output::spacetime`, no axes).

use super::canvas::{edges, render, text, ticks, Area, DrawResult, Figure, Format};
use super::canvas::{AXIS_TITLE, TICK, TITLE};
use super::{length_label, output_path};
use crate::inspect::{InspectError, RunReader};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Picture size in pixels (with axes).
pub const SIZE: (u32, u32) = (1200, 560);
/// Width of the grey scale strip on the right, in pixels.
const BAR_WIDTH: u32 = 150;
/// Colour of a slice with no particle (no volume fraction is drawn in a hue).
pub const EMPTY: RGBColor = RGBColor(214, 96, 77);

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct SpacetimeOptions {
    /// `-o` (default `STEM_spacetime.png` beside the file).
    pub output: Option<PathBuf>,
    /// Write the run's picture (`crate::output::spacetime`) without axes.
    pub bare: bool,
}

/// Draw the space-time plot of `file` (format from `-o`, else PNG); returns the picture's
/// path.
pub fn plot_spacetime(file: &Path, opts: &SpacetimeOptions) -> Result<PathBuf, InspectError> {
    plot_spacetime_in(file, opts, None)
}

/// [`plot_spacetime`] in `format` (`--format`; `None`: from `-o`, else PNG; `--bare` is
/// always the run's PNG).
pub fn plot_spacetime_in(
    file: &Path,
    opts: &SpacetimeOptions,
    format: Option<Format>,
) -> Result<PathBuf, InspectError> {
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
    if opts.bare && format.is_some_and(|f| f != Format::Png) {
        return Err(InspectError::Invalid(
            "--bare writes the run's own PNG: leave out --format".into(),
        ));
    }
    let (path, format) = output_path(file, opts.output.as_deref(), "spacetime", format)?;
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
    let figure = Spacetime {
        title: format!("volume fraction of {big_name} along the axis over time"),
        z_label: length_label(&reader, "z", "axial/z"),
        times: edges(&rotations[..nt]),
        slices: edges(&z),
        columns,
    };
    render(&path, format, &figure)?;
    Ok(path)
}

/// The space-time picture: one cell per sample and slice.
struct Spacetime {
    title: String,
    z_label: String,
    /// Cell edges in time (rotations) and along the axis.
    times: Vec<f64>,
    slices: Vec<f64>,
    /// Volume fraction per sample, per slice.
    columns: Vec<Vec<f64>>,
}

impl Figure for Spacetime {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(&self, root: &Area<DB>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let body = root.titled(&self.title, text(TITLE))?;
        let (w, _) = body.dim_in_pixel();
        let (main, bar) = body.split_horizontally(w.saturating_sub(BAR_WIDTH));
        let (nt, nz) = (self.times.len() - 1, self.slices.len() - 1);
        let t_range = self.times[0]..self.times[nt];
        let z_range = self.slices[0]..self.slices[nz];
        let mut chart = ChartBuilder::on(&main)
            .margin(10)
            .margin_right(16)
            .x_label_area_size(62)
            .y_label_area_size(104)
            .build_cartesian_2d(t_range.clone(), z_range.clone())?;
        chart.draw_series((0..nt).flat_map(|i| {
            (0..nz).map(move |k| {
                Rectangle::new(
                    [
                        (self.times[i], self.slices[k]),
                        (self.times[i + 1], self.slices[k + 1]),
                    ],
                    shade(self.columns[i][k]).filled(),
                )
            })
        }))?;
        let (t_fmt, z_fmt) = (ticks(&t_range), ticks(&z_range));
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("time [rotations]")
            .y_desc(self.z_label.as_str())
            .x_label_formatter(&t_fmt)
            .y_label_formatter(&z_fmt)
            .label_style(text(TICK))
            .axis_desc_style(text(AXIS_TITLE))
            .draw()?;
        grey_scale(&bar)
    }
}

/// The grey scale beside the picture (dark = small, light = big), its values and title
/// right of it, and a swatch of the empty-slice colour under it.
fn grey_scale<DB: DrawingBackend>(area: &Area<DB>) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let mut scale = ChartBuilder::on(area)
        .margin(10)
        .margin_left(12)
        .margin_right(14)
        .x_label_area_size(62)
        .right_y_label_area_size(w.saturating_sub(30 + 12 + 14))
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)?;
    scale.draw_series((0..100).map(|k| {
        let c = k as f64 / 100.0;
        Rectangle::new([(0.0, c), (1.0, c + 0.01)], shade(c + 0.005).filled())
    }))?;
    let fmt = ticks(&(0.0..1.0));
    scale
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .y_desc("volume fraction [-]")
        .y_label_formatter(&fmt)
        .label_style(text(TICK))
        .axis_desc_style(text(AXIS_TITLE))
        .draw()?;
    // the empty-slice swatch in the label area below the scale
    let (_, h) = area.dim_in_pixel();
    let y = h as i32 - 40;
    area.draw(&Rectangle::new([(12, y), (40, y + 18)], EMPTY.filled()))?;
    area.draw(&Text::new("empty", (46, y), text(TICK)))?;
    Ok(())
}

/// Grey level of a volume fraction, as in the run's picture; an empty slice (NaN) in
/// [`EMPTY`].
fn shade(c: f64) -> RGBColor {
    if !c.is_finite() {
        return EMPTY;
    }
    let g = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    RGBColor(g, g, g)
}
