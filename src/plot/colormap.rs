//! Colour maps: a sequential one (viridis, dark blue to yellow) for quantities of one sign
//! and a diverging one (ColorBrewer's RdBu: blue - white - red, centred on zero) for signed
//! quantities, both from the `colorous` crate; empty bins (NaN) are grey, a colour neither
//! map has.

use plotters::style::RGBColor;

/// Colour of a bin with no value (NaN).
pub const EMPTY: RGBColor = RGBColor(150, 150, 150);

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
        let c = if self.diverging {
            // RdBu runs red to blue: negative values blue
            colorous::RED_BLUE.eval_continuous(1.0 - t)
        } else {
            colorous::VIRIDIS.eval_continuous(t)
        };
        RGBColor(c.r, c.g, c.b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_is_symmetric_and_nan_is_grey() {
        let m = ColorMap::over([-0.5, 2.0, f64::NAN], true);
        assert_eq!((m.lo, m.hi), (-2.0, 2.0));
        // zero takes RdBu's middle, a near-white
        let white = m.color(0.0);
        let mid = colorous::RED_BLUE.eval_continuous(0.5);
        assert_eq!(white, RGBColor(mid.r, mid.g, mid.b));
        assert!(white.0 > 230 && white.1 > 230 && white.2 > 230, "{white:?}");
        let (neg, pos) = (m.color(-1.0), m.color(1.0));
        assert!(neg.2 > neg.0 && pos.0 > pos.2);
        assert_eq!(m.color(f64::NAN), EMPTY);
        // viridis: dark blue at the bottom, yellow at the top
        let v = ColorMap::over([0.0, 1.0], false);
        let (lo, hi) = (v.color(0.0), v.color(1.0));
        assert!(
            lo.2 > lo.1 && hi.0 > 200 && hi.1 > 200 && hi.2 < 60,
            "{lo:?} {hi:?}"
        );
        let s = ColorMap::over([3.0, 3.0], false);
        assert!(s.hi > s.lo);
    }
}
