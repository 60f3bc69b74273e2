//! A colour map of values on a rectangular grid of bins, with a colour bar, axis labels,
//! tick values, a title and optional curves drawn over it.

use super::canvas::{edges, text, ticks, Area, DrawResult, Figure, AXIS_TITLE, TICK, TITLE};
use super::colormap::ColorMap;
use super::lines::Curve;
use plotters::prelude::*;

/// Values on a grid of bins: `h` horizontal and `v` vertical bin centres (increasing).
#[derive(Debug, Clone)]
pub struct Grid {
    /// Horizontal bin centres.
    pub h: Vec<f64>,
    /// Vertical bin centres.
    pub v: Vec<f64>,
    /// Value of bin `(i, j)` at `values[i * v.len() + j]` (`i` horizontal); NaN = empty.
    pub values: Vec<f64>,
    /// Label of the horizontal axis.
    pub h_label: String,
    /// Label of the vertical axis.
    pub v_label: String,
}

impl Grid {
    /// A grid of `h x v` bins filled by `value(i, j)`.
    pub fn from_fn(
        h: Vec<f64>,
        v: Vec<f64>,
        labels: (String, String),
        mut value: impl FnMut(usize, usize) -> f64,
    ) -> Self {
        let mut values = Vec::with_capacity(h.len() * v.len());
        for i in 0..h.len() {
            for j in 0..v.len() {
                values.push(value(i, j));
            }
        }
        Grid {
            h,
            v,
            values,
            h_label: labels.0,
            v_label: labels.1,
        }
    }
}

/// Everything drawn in a colour-map picture.
#[derive(Debug, Clone)]
pub struct Heatmap {
    /// Title above the picture.
    pub title: String,
    /// The binned values.
    pub grid: Grid,
    /// Colours of the values.
    pub cmap: ColorMap,
    /// Label of the colour bar (quantity and units).
    pub bar_label: String,
    /// Curves drawn over the map, in the grid's coordinates (with a legend if labelled).
    pub overlays: Vec<Curve>,
    /// Picture size in pixels.
    pub size: (u32, u32),
}

/// Width of the colour bar strip on the right (the bar, its tick values and its title
/// beside it), in pixels.
const BAR_WIDTH: u32 = 160;
/// Width of the bar itself, in pixels.
const BAR: u32 = 30;

impl Figure for Heatmap {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, root: &Area<DB>) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let body = root.titled(&self.title, text(TITLE))?;
        let (w, _) = body.dim_in_pixel();
        let (main, bar) = body.split_horizontally(w.saturating_sub(BAR_WIDTH));
        draw_grid(&main, self)?;
        draw_bar(&bar, &self.cmap, &self.bar_label)
    }
}

fn draw_grid<DB: DrawingBackend>(area: &Area<DB>, map: &Heatmap) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let g = &map.grid;
    let (he, ve) = (edges(&g.h), edges(&g.v));
    if he.is_empty() || ve.is_empty() {
        return Err("the grid has no bins".into());
    }
    let h_range = he[0]..he[he.len() - 1];
    let v_range = ve[0]..ve[ve.len() - 1];
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .margin_right(16)
        .x_label_area_size(62)
        .y_label_area_size(104)
        .build_cartesian_2d(h_range.clone(), v_range.clone())?;
    let (h_fmt, v_fmt) = (ticks(&h_range), ticks(&v_range));
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(g.h_label.as_str())
        .y_desc(g.v_label.as_str())
        .x_label_formatter(&h_fmt)
        .y_label_formatter(&v_fmt)
        .label_style(text(TICK))
        .axis_desc_style(text(AXIS_TITLE))
        .draw()?;
    let nv = g.v.len();
    chart.draw_series((0..g.h.len()).flat_map(|i| {
        let (he, ve) = (&he, &ve);
        (0..nv).map(move |j| {
            let color = map.cmap.color(g.values[i * nv + j]);
            Rectangle::new([(he[i], ve[j]), (he[i + 1], ve[j + 1])], color.filled())
        })
    }))?;
    super::lines::draw_curves(&mut chart, &map.overlays)
}

/// The colour bar: the map's colours from `lo` (bottom) to `hi` (top), a narrow strip with
/// its tick values and its title right beside it, on its right.
fn draw_bar<DB: DrawingBackend>(area: &Area<DB>, cmap: &ColorMap, label: &str) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let range = cmap.lo..cmap.hi;
    let (w, _) = area.dim_in_pixel();
    let mut chart = ChartBuilder::on(area)
        .margin(10)
        .margin_left(12)
        .margin_right(14)
        .x_label_area_size(62)
        .right_y_label_area_size(w.saturating_sub(BAR + 12 + 14))
        .build_cartesian_2d(0.0..1.0, range.clone())?;
    const STEPS: usize = 200;
    let step = (cmap.hi - cmap.lo) / STEPS as f64;
    chart.draw_series((0..STEPS).map(|k| {
        let lo = cmap.lo + k as f64 * step;
        let color = cmap.color(lo + 0.5 * step);
        Rectangle::new([(0.0, lo), (1.0, lo + step)], color.filled())
    }))?;
    let fmt = ticks(&range);
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .set_tick_mark_size(LabelAreaPosition::Right, 6)
        .y_desc(label)
        .y_label_formatter(&fmt)
        .label_style(text(TICK))
        .axis_desc_style(text(AXIS_TITLE))
        .draw()?;
    Ok(())
}
