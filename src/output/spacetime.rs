//! The space-time plot (Rapaport fig. 1): time left to right, axial position vertical (`+z`
//! up), grey level the volume fraction of the biggest species: dark = small, light = big.

use std::io::BufWriter;
use std::path::Path;

/// Width and height of the picture in pixels; every plot has the same size, whatever the
/// length of the run and of the drum (as in the paper).
pub const SIZE: (u32, u32) = (800, 320);

/// Render `columns` (one per sample, each `nz` values of the big species' volume fraction,
/// NaN for empty slices) to a greyscale PNG at `path`.
pub fn write_png(path: &Path, columns: &[Vec<f64>]) -> std::io::Result<()> {
    let (w, h) = SIZE;
    let mut img = vec![128u8; (w * h) as usize];
    if let Some(nz) = columns.first().map(Vec::len) {
        let nt = columns.len();
        for py in 0..h {
            // top row = largest z
            let k = ((h - 1 - py) as usize * nz) / h as usize;
            for px in 0..w {
                let t = (px as usize * nt) / w as usize;
                let c = columns[t][k];
                img[(py * w + px) as usize] = if c.is_finite() {
                    (c.clamp(0.0, 1.0) * 255.0).round() as u8
                } else {
                    128
                };
            }
        }
    }
    let file = std::fs::File::create(path)?;
    let mut enc = png::Encoder::new(BufWriter::new(file), w, h);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().map_err(std::io::Error::other)?;
    writer
        .write_image_data(&img)
        .map_err(std::io::Error::other)?;
    Ok(())
}
