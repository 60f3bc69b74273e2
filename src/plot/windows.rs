//! Which window a plot shows when none is asked for: the last complete one. A run whose
//! length is not a whole number of windows ends with a short one (a stub of a few samples);
//! its means are noisier and its span differs, so the default steps back over it.

use crate::inspect::{InspectError, RunReader, Window};

/// A window shorter than this fraction of the longest one is a stub.
pub const COMPLETE: f64 = 0.99;

/// Whether the window `[start, end]` of a series whose longest window is `longest` is
/// complete.
pub fn is_complete(start: f64, end: f64, longest: f64) -> bool {
    end - start >= COMPLETE * longest
}

/// The window `requested` of `group` (`slices`, `fields`), or by default the last complete
/// one (the last one if none is).
pub fn chosen(
    reader: &RunReader,
    group: &str,
    requested: Option<usize>,
) -> Result<Window, InspectError> {
    let last = reader.window(group, requested)?;
    if requested.is_some() {
        return Ok(last);
    }
    Ok(last_complete(reader, group, &last)?.unwrap_or(last))
}

/// The last complete window of `group`, if any (`last` is its last window).
pub fn last_complete(
    reader: &RunReader,
    group: &str,
    last: &Window,
) -> Result<Option<Window>, InspectError> {
    let starts = reader.vector(&format!("{group}/rotations_start"))?;
    let ends = reader.vector(&format!("{group}/rotations_end"))?;
    let n = last.count.min(starts.len()).min(ends.len());
    let longest = (0..n).map(|k| ends[k] - starts[k]).fold(0.0, f64::max);
    match (0..n)
        .rev()
        .find(|&k| is_complete(starts[k], ends[k], longest))
    {
        Some(k) => reader.window(group, Some(k)).map(Some),
        None => Ok(None),
    }
}

/// Up to `most` of the complete windows among `count` (`(start, end)` each), evenly spread
/// from the first to the last complete one, in order.
pub fn spread(spans: &[(f64, f64)], most: usize) -> Vec<usize> {
    let longest = spans.iter().map(|(a, b)| b - a).fold(0.0, f64::max);
    let complete: Vec<usize> = (0..spans.len())
        .filter(|&k| is_complete(spans[k].0, spans[k].1, longest))
        .collect();
    let pool = if complete.is_empty() {
        (0..spans.len()).collect()
    } else {
        complete
    };
    if pool.len() <= most || most < 2 {
        return pool.into_iter().take(most.max(1)).collect();
    }
    let mut picked: Vec<usize> = (0..most)
        .map(|i| pool[(i * (pool.len() - 1) + (most - 1) / 2) / (most - 1)])
        .collect();
    picked.dedup();
    picked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trailing_stub_is_not_complete_and_spread_windows_skip_it() {
        // 81 windows of 0.9947 rotations, the last a stub of 21 samples against 50
        let mut spans: Vec<(f64, f64)> = (0..80)
            .map(|k| (k as f64 * 0.9947, (k + 1) as f64 * 0.9947))
            .collect();
        spans.push((80.0 * 0.9947, 80.0 * 0.9947 + 0.42));
        let longest = 0.9947;
        assert!(is_complete(spans[79].0, spans[79].1, longest));
        assert!(!is_complete(spans[80].0, spans[80].1, longest));
        let picked = spread(&spans, 8);
        assert_eq!(picked.len(), 8);
        assert_eq!((picked[0], picked[7]), (0, 79));
        assert!(picked.windows(2).all(|w| w[0] < w[1]));
        // few windows: all of them
        assert_eq!(spread(&spans[..5], 8), vec![0, 1, 2, 3, 4]);
    }
}
