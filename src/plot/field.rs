//! `tumbler plot field`: one quantity of `/fields` in one window, on a plane through the
//! bins or on the free-surface layer, as a colour map; on a `z` plane the flowing-layer
//! boundary (and the free surface) are drawn over the cross-section.

use super::canvas::{edges, nearest, render, Format};
use super::colormap::ColorMap;
use super::heatmap::{Grid, Heatmap};
use super::lines::Curve;
use super::quantity::{ColumnField, Plane, Quantity, SpeciesField};
use super::{length_label, output_path};
use crate::inspect::{InspectError, RunReader, Window};
use ndarray::ArrayD;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// Picture size of an `x`-`y` cross-section (`z` plane).
pub const SIZE_CROSS_SECTION: (u32, u32) = (980, 820);
/// Picture size of a map along the axis (`surface`, `x` and `y` planes, column fields).
pub const SIZE_ALONG_AXIS: (u32, u32) = (1200, 620);
/// The free-surface layer is the highest bin whose volume fraction (all species) is at least
/// this (as `/fields/surface`).
pub const SURFACE_FRACTION: f64 = 0.25;

/// What to draw.
#[derive(Debug, Clone, Default)]
pub struct FieldOptions {
    /// `--quantity`.
    pub quantity: String,
    /// `--window` (default the last complete one).
    pub window: Option<usize>,
    /// `--plane` (default `surface` for velocities, else the `z` plane nearest 0).
    pub plane: Option<String>,
    /// `-o` (default `STEM_field_<quantity>_<plane>_<window>.png` beside the file; its
    /// extension `.png`, `.svg` or `.pdf` chooses the format).
    pub output: Option<PathBuf>,
}

/// The bin centres of `/fields`.
struct Axes {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
}

/// A map ready to draw: the grid, how the plane is named in the title and in the file name,
/// curves over it and the picture size.
struct View {
    grid: Grid,
    title: String,
    tag: String,
    overlays: Vec<Curve>,
    size: (u32, u32),
}

/// Draw the field plot of `file` (format from `-o`, else PNG); returns the picture's path.
pub fn plot_field(file: &Path, opts: &FieldOptions) -> Result<PathBuf, InspectError> {
    plot_field_in(file, opts, None)
}

/// [`plot_field`] in `format` (`--format`; `None`: from `-o`, else PNG).
pub fn plot_field_in(
    file: &Path,
    opts: &FieldOptions,
    format: Option<Format>,
) -> Result<PathBuf, InspectError> {
    let reader = RunReader::open(file)?;
    let names = reader.species_names();
    let q = Quantity::parse(&opts.quantity, &names)?;
    let plane = opts.plane.as_deref().map(Plane::parse).transpose()?;
    let window = super::windows::chosen(&reader, "fields", opts.window)?;
    let axes = Axes {
        x: reader.centres("fields/x")?,
        y: reader.centres("fields/y")?,
        z: reader.centres("fields/z")?,
    };
    let view = if q.is_column() {
        column_view(&reader, &q, &window, &axes)?
    } else {
        let plane = plane.unwrap_or(if q.surface_by_default() {
            Plane::Surface
        } else {
            Plane::Z(axes.z[nearest(&axes.z, 0.0)])
        });
        plane_view(&reader, &q, plane, &window, &axes)?
    };
    warn_of_narrow_bins(&reader, &q, &axes);
    let qname = q.name(&names);
    let title = q.title(&names);
    if !view.grid.values.iter().any(|v| v.is_finite()) {
        return Err(all_nan(&q, &opts.quantity, &view.title, &window));
    }
    let bar_label = match reader.units(q.dataset()) {
        Some(u) => format!("{title} [{u}]"),
        None => format!("{title} [-]"),
    };
    let what = format!("field_{qname}_{}_{}", view.tag, window.index);
    let (path, format) = output_path(file, opts.output.as_deref(), &what, format)?;
    let map = Heatmap {
        title: format!("{title}, {}, {}", view.title, window.label()),
        cmap: ColorMap::over(view.grid.values.iter().copied(), q.signed()),
        grid: view.grid,
        bar_label,
        overlays: view.overlays,
        size: view.size,
    };
    render(&path, format, &map)?;
    Ok(path)
}

/// Say on stderr when a density is drawn from bins narrower than the largest particle: each
/// particle counts whole in the bin of its centre, so such bins alternate between empty and
/// over-full (a volume fraction above 1) instead of averaging over particles.
fn warn_of_narrow_bins(reader: &RunReader, q: &Quantity, axes: &Axes) {
    let density = matches!(
        q,
        Quantity::Species {
            field: SpeciesField::VolumeFraction | SpeciesField::NumberDensity,
            ..
        }
    );
    let Some(d) = reader.case().ok().map(|c| c.d_max()) else {
        return;
    };
    let width = |c: &[f64]| {
        let e = edges(c);
        (e[e.len() - 1] - e[0]) / c.len().max(1) as f64
    };
    let spans = [&axes.x, &axes.y, &axes.z].map(|c| {
        let e = edges(c);
        e[e.len() - 1] - e[0]
    });
    let narrowest = [&axes.x, &axes.y, &axes.z]
        .map(|c| width(c))
        .into_iter()
        .fold(f64::INFINITY, f64::min);
    if density && narrowest < d {
        let most = spans.map(|s| ((s / d).floor() as usize).max(1));
        log::warn!(
            "the field bins are {} wide, narrower than the largest particle ({}): a particle \
             counts whole in the bin of its centre, so the map is speckled and can exceed a \
             volume fraction of 1; for bins at least a diameter wide, run with \
             diagnostics.fields.grid = [{}, {}, {}] or coarser",
            short(narrowest),
            short(d),
            most[0],
            most[1],
            most[2]
        );
    }
}

/// The refusal of a quantity with no finite value where it would be drawn.
fn all_nan(q: &Quantity, asked: &str, place: &str, window: &Window) -> InspectError {
    let why = match q {
        Quantity::Column(ColumnField::Depth | ColumnField::Boundary) => {
            "the flowing-layer boundary was found in no column: the drum-frame streamwise \
             velocity never fell to 0.05 u0 below the surface (a bed that does not flow, or \
             a window too short to average it)"
        }
        _ => "every bin is empty or unmeasured there",
    };
    InspectError::Invalid(format!(
        "--quantity {asked}: nothing to draw, /{} is NaN everywhere on {place} in {} ({why}); \
         try another --window or --plane",
        q.dataset(),
        window.label()
    ))
}

/// A column quantity (`F x X x ZF`) as a `z`-`x` map.
fn column_view(
    reader: &RunReader,
    q: &Quantity,
    window: &Window,
    axes: &Axes,
) -> Result<View, InspectError> {
    let name = q.dataset();
    let data = reader.array(name, &["F", "X", "ZF"])?;
    let s = data.shape();
    check_window(name, s[0], window)?;
    reader.check_len(name, s[1], axes.x.len(), "x bins")?;
    reader.check_len(name, s[2], axes.z.len(), "z slices")?;
    let labels = (
        length_label(reader, "z", "fields/z"),
        length_label(reader, "x", "fields/x"),
    );
    Ok(View {
        grid: Grid::from_fn(axes.z.clone(), axes.x.clone(), labels, |i, j| {
            data[[window.index, j, i]]
        }),
        title: "per (x, z) column".into(),
        tag: "columns".into(),
        overlays: vec![],
        size: SIZE_ALONG_AXIS,
    })
}

/// A binned quantity (`F x C x X x Y x ZF`) on `plane`.
fn plane_view(
    reader: &RunReader,
    q: &Quantity,
    plane: Plane,
    window: &Window,
    axes: &Axes,
) -> Result<View, InspectError> {
    let data = read_binned(reader, q.dataset(), window, axes)?;
    let channels = data.shape()[1];
    if q.channel() >= channels {
        let (what, of) = match q {
            Quantity::Species { species, .. } => (format!("species {species}"), "species"),
            _ => (format!("component {}", q.channel()), "components"),
        };
        return Err(InspectError::Invalid(format!(
            "{what} is out of range: /{} holds {channels} {of}",
            q.dataset()
        )));
    }
    let at = |ix: usize, iy: usize, iz: usize| data[[window.index, q.channel(), ix, iy, iz]];
    let lx = length_label(reader, "x", "fields/x");
    let ly = length_label(reader, "y", "fields/y");
    let lz = length_label(reader, "z", "fields/z");
    let view = |grid, title: String, tag: String, size| View {
        grid,
        title,
        tag,
        overlays: vec![],
        size,
    };
    Ok(match plane {
        Plane::X(v) => {
            let ix = bin_of("x", &axes.x, v)?;
            let g = Grid::from_fn(axes.z.clone(), axes.y.clone(), (lz, ly), |i, j| {
                at(ix, j, i)
            });
            let x = short(axes.x[ix]);
            view(
                g,
                format!("plane x = {x}"),
                format!("x{x}"),
                SIZE_ALONG_AXIS,
            )
        }
        Plane::Y(v) => {
            let iy = bin_of("y", &axes.y, v)?;
            let g = Grid::from_fn(axes.z.clone(), axes.x.clone(), (lz, lx), |i, j| {
                at(j, iy, i)
            });
            let y = short(axes.y[iy]);
            view(
                g,
                format!("plane y = {y}"),
                format!("y{y}"),
                SIZE_ALONG_AXIS,
            )
        }
        Plane::Z(v) => {
            let iz = bin_of("z", &axes.z, v)?;
            let g = Grid::from_fn(axes.x.clone(), axes.y.clone(), (lx, ly), |i, j| {
                at(i, j, iz)
            });
            let z = short(axes.z[iz]);
            let mut v = view(
                g,
                format!("plane z = {z}"),
                format!("z{z}"),
                SIZE_CROSS_SECTION,
            );
            v.overlays = layer_lines(reader, window, axes, iz)?;
            v
        }
        Plane::Surface => {
            let top = surface_bins(reader, window, axes)?;
            let g = Grid::from_fn(axes.z.clone(), axes.x.clone(), (lz, lx), |i, j| {
                top[j * axes.z.len() + i].map_or(f64::NAN, |iy| at(j, iy, i))
            });
            let title = format!("free-surface layer (volume fraction >= {SURFACE_FRACTION})");
            view(g, title, "surface".into(), SIZE_ALONG_AXIS)
        }
    })
}

/// The bin of `centres` nearest `v`, refused when `v` lies outside the grid.
fn bin_of(axis: &str, centres: &[f64], v: f64) -> Result<usize, InspectError> {
    let e = edges(centres);
    let (lo, hi) = (e[0], e[e.len() - 1]);
    if v < lo || v > hi {
        return Err(InspectError::Invalid(format!(
            "--plane {axis}={v} is outside the field grid, where {axis} runs from {} to {}",
            short(lo),
            short(hi)
        )));
    }
    Ok(nearest(centres, v))
}

/// Refuse a window beyond the `windows` records of dataset `name`.
fn check_window(name: &str, windows: usize, window: &Window) -> Result<(), InspectError> {
    if window.index >= windows {
        return Err(InspectError::Invalid(format!(
            "window {} is out of range: /{name} holds {windows} windows",
            window.index
        )));
    }
    Ok(())
}

fn short(v: f64) -> String {
    crate::inspect::short_number(v)
}

/// A binned dataset (`F x C x X x Y x ZF`), checked against the grid and the window.
fn read_binned(
    reader: &RunReader,
    name: &str,
    window: &Window,
    axes: &Axes,
) -> Result<ArrayD<f64>, InspectError> {
    let data = reader.array(name, &["F", "C", "X", "Y", "ZF"])?;
    let s = data.shape();
    check_window(name, s[0], window)?;
    reader.check_len(name, s[2], axes.x.len(), "x bins")?;
    reader.check_len(name, s[3], axes.y.len(), "y bins")?;
    reader.check_len(name, s[4], axes.z.len(), "z slices")?;
    Ok(data)
}

/// For each `(x, z)` column (index `ix * nz + iz`), the highest `y` bin whose volume
/// fraction summed over species is at least [`SURFACE_FRACTION`].
fn surface_bins(
    reader: &RunReader,
    window: &Window,
    axes: &Axes,
) -> Result<Vec<Option<usize>>, InspectError> {
    let vf = read_binned(reader, "fields/volume_fraction", window, axes)?;
    let (ns, nx, ny, nz) = (vf.shape()[1], axes.x.len(), axes.y.len(), axes.z.len());
    let mut order: Vec<usize> = (0..ny).collect();
    order.sort_by(|a, b| axes.y[*b].total_cmp(&axes.y[*a]));
    let mut top = vec![None; nx * nz];
    for ix in 0..nx {
        for iz in 0..nz {
            top[ix * nz + iz] = order.iter().copied().find(|&iy| {
                let total: f64 = (0..ns)
                    .map(|s| vf[[window.index, s, ix, iy, iz]])
                    .filter(|v| v.is_finite())
                    .sum();
                total >= SURFACE_FRACTION
            });
        }
    }
    Ok(top)
}

/// The flowing-layer boundary and the free surface of slice `iz` as `y(x)` curves, from
/// `/fields/boundary` and `/fields/surface` when the run wrote them.
fn layer_lines(
    reader: &RunReader,
    window: &Window,
    axes: &Axes,
    iz: usize,
) -> Result<Vec<Curve>, InspectError> {
    let mut curves = vec![];
    for (name, label, dashed) in [
        ("fields/boundary", "flowing-layer boundary", false),
        ("fields/surface", "free surface", true),
    ] {
        if !reader.has(name) {
            continue;
        }
        let data = reader.array(name, &["F", "X", "ZF"])?;
        let s = data.shape();
        if s[0] <= window.index || s[1] != axes.x.len() || s[2] != axes.z.len() {
            return Err(reader.layout(
                name,
                format!(
                    "has shape {} x {} x {}, not F x X x ZF of the field grid",
                    s[0], s[1], s[2]
                ),
            ));
        }
        curves.push(Curve {
            label: label.into(),
            color: RGBColor(0, 0, 0),
            dashed,
            width: 2,
            points: (0..axes.x.len())
                .map(|ix| (axes.x[ix], data[[window.index, ix, iz]]))
                .collect(),
        });
    }
    Ok(curves)
}
