//! Colour maps: a sequential one (viridis, dark blue to yellow) for quantities of one sign
//! and a diverging one (blue - white - red, centred on zero) for signed quantities; empty
//! bins (NaN) are grey.

use plotters::style::RGBColor;

/// Colour of a bin with no value (NaN).
pub const EMPTY: RGBColor = RGBColor(150, 150, 150);

/// Viridis at nine evenly spaced stops.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// Blue (negative) through white (zero) to red (positive), nine evenly spaced stops.
const DIVERGING: [(u8, u8, u8); 9] = [
    (5, 48, 97),
    (33, 102, 172),
    (103, 169, 207),
    (209, 229, 240),
    (247, 247, 247),
    (253, 219, 199),
    (239, 138, 98),
    (178, 24, 43),
    (103, 0, 31),
];

/// How values are turned into colours.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorMap {
    /// Value of the first colour.
    pub lo: f64,
    /// Value of the last colour.
    pub hi: f64,
    /// Diverging (symmetric about zero) rather than sequential.
    pub diverging: bool,
}

impl ColorMap {
    /// A map over the finite `values`: from their smallest to their largest, or for a
    /// diverging map from `-m` to `m` with `m` their largest magnitude.
    pub fn over(values: impl IntoIterator<Item = f64>, diverging: bool) -> Self {
        let (lo, hi) = super::canvas::finite_range(values);
        let (lo, hi) = if !lo.is_finite() {
            (0.0, 1.0)
        } else if diverging {
            let m = lo.abs().max(hi.abs());
            if m > 0.0 {
                (-m, m)
            } else {
                (-1.0, 1.0)
            }
        } else if hi > lo {
            (lo, hi)
        } else {
            let r = super::canvas::padded(lo, hi, 0.0);
            (r.start, r.end)
        };
        ColorMap { lo, hi, diverging }
    }

    /// The colour of `v` (values outside the range take the end colours; NaN is grey).
    pub fn color(&self, v: f64) -> RGBColor {
        if !v.is_finite() {
            return EMPTY;
        }
        let t = ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        let stops = if self.diverging { &DIVERGING } else { &VIRIDIS };
        let x = t * (stops.len() - 1) as f64;
        let k = (x.floor() as usize).min(stops.len() - 2);
        let f = x - k as f64;
        let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
        let (a, b) = (stops[k], stops[k + 1]);
        RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_is_symmetric_and_nan_is_grey() {
        let m = ColorMap::over([-0.5, 2.0, f64::NAN], true);
        assert_eq!((m.lo, m.hi), (-2.0, 2.0));
        assert_eq!(m.color(0.0), RGBColor(247, 247, 247));
        let (neg, pos) = (m.color(-1.0), m.color(1.0));
        assert!(neg.2 > neg.0 && pos.0 > pos.2);
        assert_eq!(m.color(f64::NAN), EMPTY);
        let s = ColorMap::over([3.0, 3.0], false);
        assert!(s.hi > s.lo);
    }
}
