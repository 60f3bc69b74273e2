//! Reading the windowed axial series of `/slices` (`W x S x Z` per species, `W x Z` for
//! the mixture) at one window, checked against `/slices/z`.

use crate::inspect::{InspectError, RunReader, Window};

/// Each species' profile along `z` of `/slices/NAME` (`W x S x Z`) in `window`.
pub fn per_species(
    reader: &RunReader,
    name: &str,
    window: &Window,
    nz: usize,
) -> Result<Vec<Vec<f64>>, InspectError> {
    let data = reader.array(name, &["W", "S", "Z"])?;
    let s = data.shape();
    check(reader, name, s[0], s[2], window, nz)?;
    Ok((0..s[1])
        .map(|sp| (0..nz).map(|k| data[[window.index, sp, k]]).collect())
        .collect())
}

/// The mixture's profile along `z` of `/slices/NAME` (`W x Z`) in each of `windows`.
pub fn mixture(
    reader: &RunReader,
    name: &str,
    windows: &[Window],
    nz: usize,
) -> Result<Vec<Vec<f64>>, InspectError> {
    let data = reader.array(name, &["W", "Z"])?;
    let s = data.shape();
    windows
        .iter()
        .map(|w| {
            check(reader, name, s[0], s[1], w, nz)?;
            Ok((0..nz).map(|k| data[[w.index, k]]).collect())
        })
        .collect()
}

fn check(
    reader: &RunReader,
    name: &str,
    windows: usize,
    slices: usize,
    window: &Window,
    nz: usize,
) -> Result<(), InspectError> {
    if window.index >= windows {
        return Err(InspectError::Invalid(format!(
            "window {} is out of range: /{name} holds {windows} windows",
            window.index
        )));
    }
    reader.check_len(name, slices, nz, "slices")
}
