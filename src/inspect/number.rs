//! Numbers as short text, for tables, titles and tick labels.

/// `v` with four significant digits at most and no trailing zeros; magnitudes from `1e5` up
/// and below `1e-3` in scientific notation (`1.5e-6`).
pub fn short(v: f64) -> String {
    if v.is_nan() {
        return "NaN".into();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        let s = format!("{v:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim_zeros(mantissa));
    }
    let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
    trim_zeros(&format!("{v:.decimals$}"))
}

/// A tick label on an axis spanning `span`: as [`short`], with rounding noise around zero
/// (`1e-17` on an axis from -1 to 1) shown as `0`.
pub fn tick(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span.abs() {
        "0".into()
    } else {
        short(v)
    }
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers() {
        assert_eq!(short(0.1 + 0.2), "0.3");
        assert_eq!(short(12345.0), "12345");
        assert_eq!(short(-2.5), "-2.5");
        assert_eq!(short(1.5e-6), "1.5e-6");
        assert_eq!(short(2.0e6), "2e6");
        assert_eq!(short(f64::NAN), "NaN");
        assert_eq!(tick(1e-17, 2.0), "0");
    }
}
