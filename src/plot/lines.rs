//! Line panels: curves over a horizontal axis with axis labels, tick values and a legend;
//! a NaN leaves a gap in its curve.

use super::canvas::{
    finite_range, padded, text, ticks, Area, DrawResult, Figure, AXIS_TITLE, LEGEND, TICK, TITLE,
};
use plotters::prelude::*;
use std::ops::Range;

/// One curve of a panel.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Legend text (empty: not in the legend).
    pub label: String,
    /// Line colour.
    pub color: RGBColor,
    /// Dashed rather than solid.
    pub dashed: bool,
    /// Line width in pixels.
    pub width: u32,
    /// `(x, y)` points in order of `x`; a point with a NaN breaks the line.
    pub points: Vec<(f64, f64)>,
}

/// A set of curves drawn in one chart.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the chart (empty: none).
    pub caption: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Horizontal range.
    pub x_range: Range<f64>,
    /// The curves.
    pub curves: Vec<Curve>,
}

/// A distinct curve colour for series `k` (eight hues, repeating).
pub fn palette(k: usize) -> RGBColor {
    const COLORS: [RGBColor; 8] = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
        RGBColor(255, 127, 14),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(23, 190, 207),
    ];
    COLORS[k % COLORS.len()]
}

/// Panels stacked top to bottom under one title: a whole picture.
#[derive(Debug, Clone)]
pub struct Stack {
    /// Title above the panels (empty: none).
    pub title: String,
    /// The panels, top first.
    pub panels: Vec<Panel>,
    /// Picture size in pixels.
    pub size: (u32, u32),
}

impl Figure for Stack {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &Area<DB>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let body = if self.title.is_empty() {
            root.clone()
        } else {
            root.titled(&self.title, text(TITLE))?
        };
        for (area, panel) in body
            .split_evenly((self.panels.len().max(1), 1))
            .iter()
            .zip(&self.panels)
        {
            draw_panel(area, panel)?;
        }
        Ok(())
    }
}

/// Draw `panel` on `area`; the vertical range covers every finite value of its curves.
pub fn draw_panel<DB: DrawingBackend>(area: &Area<DB>, panel: &Panel) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (lo, hi) = finite_range(
        panel
            .curves
            .iter()
            .flat_map(|c| c.points.iter().map(|p| p.1)),
    );
    let y_range = padded(lo, hi, 0.06);
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(8)
        .margin_right(20)
        .x_label_area_size(62)
        .y_label_area_size(112);
    if !panel.caption.is_empty() {
        builder.caption(&panel.caption, text(AXIS_TITLE));
    }
    let mut chart = builder.build_cartesian_2d(panel.x_range.clone(), y_range.clone())?;
    let x_fmt = ticks(&panel.x_range);
    let y_fmt = ticks(&y_range);
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(text(TICK))
        .axis_desc_style(text(AXIS_TITLE))
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    if !lo.is_finite() {
        area.draw_text(
            "no finite values",
            &text(AXIS_TITLE),
            (
                area.dim_in_pixel().0 as i32 / 2 - 80,
                area.dim_in_pixel().1 as i32 / 2,
            ),
        )?;
    }
    draw_curves(&mut chart, &panel.curves)
}

/// The chart curves are drawn on (line panels and colour maps alike).
pub type Chart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draw `curves` (a gap at every non-finite point, a dot for a lone point), each with a
/// legend entry if it has a label, and the legend if any has.
pub fn draw_curves<'a, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    curves: &[Curve],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let mut labelled_any = false;
    for curve in curves {
        let style = ShapeStyle::from(&curve.color).stroke_width(curve.width);
        let mut labelled = curve.label.is_empty();
        for run in finite_runs(&curve.points) {
            let anno = if run.len() == 1 {
                chart.draw_series(std::iter::once(Circle::new(run[0], 4, style.filled())))?
            } else if curve.dashed {
                chart.draw_series(DashedLineSeries::new(run, 9, 5, style))?
            } else {
                chart.draw_series(LineSeries::new(run, style))?
            };
            if !labelled {
                let dashed = curve.dashed;
                anno.label(curve.label.as_str()).legend(move |(x, y)| {
                    let (a, b) = if dashed { (10, 16) } else { (26, 0) };
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (a, 0)], style)
                        + PathElement::new(vec![(b, 0), (26, 0)], style)
                });
                labelled = true;
                labelled_any = true;
            }
        }
    }
    if labelled_any {
        chart
            .configure_series_labels()
            .label_font(text(LEGEND))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(120, 120, 120))
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
    }
    Ok(())
}

/// The stretches of `points` with finite coordinates.
fn finite_runs(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let mut runs = vec![];
    let mut run = vec![];
    for &(x, y) in points {
        if x.is_finite() && y.is_finite() {
            run.push((x, y));
        } else if !run.is_empty() {
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}
