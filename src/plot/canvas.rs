//! The drawing surface shared by every plot: a [`Figure`] drawn with `plotters` on any
//! backend and written as a PNG (a bitmap, text in DejaVu Sans compiled into the binary, no
//! system fonts needed), an SVG (`plotters`' SVG backend, text as text) or a PDF (that SVG
//! converted by `svg2pdf`, the embedded DejaVu Sans as its font). Sizes are in pixels of the
//! PNG; text sizes are chosen to stay readable when a figure is printed a column wide.

use crate::inspect::{tick_label, InspectError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::error::Error;
use std::io::BufWriter;
use std::path::Path;
use std::sync::Once;

/// The font family every text of the plots uses (registered from the embedded bytes).
pub const FONT: &str = "sans-serif";

/// Text sizes, in pixels: titles, axis titles, tick labels, legends.
pub const TITLE: u32 = 24;
/// Axis titles and colour-bar titles.
pub const AXIS_TITLE: u32 = 21;
/// Tick labels.
pub const TICK: u32 = 18;
/// Legend entries.
pub const LEGEND: u32 = 17;

/// A drawing area on some backend.
pub type Area<'a, DB> = DrawingArea<DB, Shift>;

/// What a drawing closure returns.
pub type DrawResult = Result<(), Box<dyn Error>>;

/// The file formats of `tumbler plot --format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// A bitmap.
    #[default]
    Png,
    /// Vector graphics, text as text.
    Svg,
    /// Vector graphics for a paper, the font embedded.
    Pdf,
}

impl Format {
    /// Parse `--format`.
    pub fn parse(text: &str) -> Result<Self, InspectError> {
        match text {
            "png" => Ok(Format::Png),
            "svg" => Ok(Format::Svg),
            "pdf" => Ok(Format::Pdf),
            _ => Err(InspectError::Invalid(format!(
                "unknown format '{text}' (--format): expected png, svg or pdf"
            ))),
        }
    }

    /// The file name extension.
    pub fn extension(self) -> &'static str {
        match self {
            Format::Png => "png",
            Format::Svg => "svg",
            Format::Pdf => "pdf",
        }
    }
}

/// A picture that can be drawn on any backend.
pub trait Figure {
    /// Size in pixels (of the PNG; the SVG and PDF have the same proportions).
    fn size(&self) -> (u32, u32);
    /// Draw on the whole of `root` (white already).
    fn draw<DB: DrawingBackend>(&self, root: &Area<DB>) -> DrawResult
    where
        DB::ErrorType: 'static;
}

/// Register the embedded font once per process.
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TrueType font, so this cannot fail in practice; if it did,
        // text would be missing from the picture, not the picture itself.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// Draw `fig` on a white background and write it to `path` in `format`.
pub fn render(path: &Path, format: Format, fig: &impl Figure) -> Result<(), InspectError> {
    register_font();
    let fail = |reason: String| InspectError::Write {
        path: path.display().to_string(),
        reason,
    };
    let drawing = |e: Box<dyn Error>| fail(format!("drawing failed ({e})"));
    let size = fig.size();
    let bytes = match format {
        Format::Png => return write_png(path, size, fig),
        Format::Svg => svg(size, fig).map_err(drawing)?.into_bytes(),
        Format::Pdf => {
            let svg = svg(size, fig).map_err(drawing)?;
            pdf(&svg).map_err(|e| fail(format!("converting to PDF failed ({e})")))?
        }
    };
    std::fs::write(path, bytes).map_err(|e| fail(e.to_string()))
}

/// The figure as SVG text.
fn svg(size: (u32, u32), fig: &impl Figure) -> Result<String, Box<dyn Error>> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        root.fill(&WHITE)?;
        fig.draw(&root)?;
        root.present()?;
    }
    Ok(text)
}

/// An SVG drawing as a one-page PDF, its text set in the embedded DejaVu Sans.
fn pdf(svg: &str) -> Result<Vec<u8>, Box<dyn Error>> {
    let mut fonts = usvg::fontdb::Database::new();
    fonts.load_font_data(dejavu::sans::regular().to_vec());
    fonts.set_sans_serif_family("DejaVu Sans");
    let options = usvg::Options {
        fontdb: std::sync::Arc::new(fonts),
        font_family: "DejaVu Sans".into(),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options)?;
    svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions::default(),
    )
    .map_err(|e| e.to_string().into())
}

/// Draw `fig` on a bitmap and write it to `path` as an RGB PNG.
fn write_png(path: &Path, size: (u32, u32), fig: &impl Figure) -> Result<(), InspectError> {
    let fail = |reason: String| InspectError::Write {
        path: path.display().to_string(),
        reason,
    };
    let (w, h) = size;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.to_string()))?;
        fig.draw(&root)
            .map_err(|e| fail(format!("drawing failed ({e})")))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let file = std::fs::File::create(path).map_err(|e| fail(e.to_string()))?;
    let mut enc = png::Encoder::new(BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(|e| fail(e.to_string()))?;
    writer
        .write_image_data(&rgb)
        .map_err(|e| fail(e.to_string()))?;
    writer.finish().map_err(|e| fail(e.to_string()))
}

/// Text style of `size` pixels in the plots' font.
pub fn text(size: u32) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// Tick label formatter for an axis over `range`.
pub fn ticks(range: &std::ops::Range<f64>) -> impl Fn(&f64) -> String {
    let span = range.end - range.start;
    move |v: &f64| tick_label(*v, span)
}

/// `lo..hi` widened by `pad` of its span each side; a span of zero (or no finite value)
/// becomes a unit interval.
pub fn padded(lo: f64, hi: f64, pad: f64) -> std::ops::Range<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return 0.0..1.0;
    }
    let span = hi - lo;
    if span <= 0.0 {
        let half = if lo == 0.0 { 0.5 } else { 0.05 * lo.abs() };
        return lo - half..hi + half;
    }
    lo - pad * span..hi + pad * span
}

/// Smallest and largest finite value of `values` (`(inf, -inf)` if none).
pub fn finite_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// Bin edges from bin centres: midpoints between neighbours, the ends half a spacing out
/// (a single bin is one unit wide).
pub fn edges(centres: &[f64]) -> Vec<f64> {
    match centres.len() {
        0 => vec![],
        1 => vec![centres[0] - 0.5, centres[0] + 0.5],
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(centres[0] - 0.5 * (centres[1] - centres[0]));
            for k in 1..n {
                e.push(0.5 * (centres[k - 1] + centres[k]));
            }
            e.push(centres[n - 1] + 0.5 * (centres[n - 1] - centres[n - 2]));
            e
        }
    }
}

/// Index of the centre nearest to `v` (centres in increasing order).
pub fn nearest(centres: &[f64], v: f64) -> usize {
    let mut best = 0;
    for (k, c) in centres.iter().enumerate() {
        if (c - v).abs() < (centres[best] - v).abs() {
            best = k;
        }
    }
    best
}
