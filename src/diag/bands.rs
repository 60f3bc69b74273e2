//! Counting segregation bands in an axial profile (Rapaport Table I, "Bands").
//!
//! A slice is *rich* in the big species when its volume fraction exceeds the drum's mean
//! by more than `threshold`, and *poor* when it falls below the mean by more than
//! `threshold`; slices in between keep the state of the last rich or poor slice (hysteresis),
//! so noise below the threshold never makes a band. Runs of one state narrower than
//! `min_slices` slices that cross the threshold are dropped (their neighbours join). At
//! periodic ends the first and last runs are one band when they have the same state.

/// How bands are recognised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandRule {
    /// Departure from the drum-mean volume fraction that makes a slice rich or poor.
    pub threshold: f64,
    /// Fewest slices beyond the threshold that make a band.
    pub min_slices: usize,
    /// Whether the profile wraps around (periodic ends).
    pub periodic: bool,
}

/// One band of an axial profile: rich or poor in the species, and its width.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Band {
    /// Whether the species is enriched (`true`) or depleted in the band.
    pub rich: bool,
    /// Slices beyond the threshold in the band (slices in between are not counted).
    pub slices: usize,
}

/// The bands of `profile` (volume fraction of one species per slice; NaN for empty slices,
/// which are ignored), in order along the axis. At periodic ends a first and last band of the
/// same state are one band: it is reported first, its width the sum of both. A profile that
/// nowhere departs from its mean by more than the threshold has no bands.
pub fn find_bands(profile: &[f64], rule: &BandRule) -> Vec<Band> {
    let finite: Vec<f64> = profile.iter().copied().filter(|c| c.is_finite()).collect();
    if finite.is_empty() {
        return Vec::new();
    }
    let mean = finite.iter().sum::<f64>() / finite.len() as f64;
    // runs of (state, slices beyond the threshold)
    let mut runs: Vec<(i8, usize)> = Vec::new();
    for c in finite {
        let s = if c > mean + rule.threshold {
            1
        } else if c < mean - rule.threshold {
            -1
        } else {
            0
        };
        if s == 0 {
            continue;
        }
        match runs.last_mut() {
            Some((state, n)) if *state == s => *n += 1,
            _ => runs.push((s, 1)),
        }
    }
    // drop narrow runs, merging the neighbours they separated
    let mut kept: Vec<(i8, usize)> = Vec::new();
    for (s, n) in runs {
        if n < rule.min_slices.max(1) {
            continue;
        }
        match kept.last_mut() {
            Some((state, m)) if *state == s => *m += n,
            _ => kept.push((s, n)),
        }
    }
    if rule.periodic && kept.len() > 1 && kept[0].0 == kept[kept.len() - 1].0 {
        let (_, n) = kept.pop().expect("more than one band");
        kept[0].1 += n;
    }
    kept.into_iter()
        .map(|(s, slices)| Band {
            rich: s > 0,
            slices,
        })
        .collect()
}

/// Number of bands in `profile` ([`find_bands`]).
pub fn count_bands(profile: &[f64], rule: &BandRule) -> usize {
    find_bands(profile, rule).len()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rule(periodic: bool) -> BandRule {
        BandRule {
            threshold: 0.2,
            min_slices: 2,
            periodic,
        }
    }

    /// `n` bands of `w` slices each, alternating from big-rich.
    fn square(n: usize, w: usize) -> Vec<f64> {
        (0..n * w)
            .map(|k| if (k / w).is_multiple_of(2) { 0.9 } else { 0.1 })
            .collect()
    }

    #[test]
    fn counts_alternating_bands() {
        assert_eq!(count_bands(&square(8, 5), &rule(false)), 8);
        assert_eq!(count_bands(&square(8, 5), &rule(true)), 8);
        assert_eq!(count_bands(&square(5, 4), &rule(false)), 5);
    }

    #[test]
    fn bands_say_which_state_they_are() {
        let b = find_bands(&square(5, 4), &rule(false));
        let rich: Vec<bool> = b.iter().map(|b| b.rich).collect();
        assert_eq!(rich, [true, false, true, false, true]);
        assert!(b.iter().all(|b| b.slices == 4));
        // wrapped: the last rich band joins the first
        let b = find_bands(&square(5, 4), &rule(true));
        assert_eq!(b.len(), 4);
        assert_eq!((b[0].rich, b[0].slices), (true, 8));
    }

    #[test]
    fn periodic_wrap_joins_the_end_bands() {
        let mut p = square(4, 6);
        p.rotate_left(3); // a band split across the ends
        assert_eq!(count_bands(&p, &rule(true)), 4);
        assert_eq!(count_bands(&p, &rule(false)), 5);
    }

    #[test]
    fn noise_below_the_threshold_is_ignored() {
        let p: Vec<f64> = (0..60)
            .map(|k| 0.5 + 0.15 * ((k as f64) * 1.7).sin())
            .collect();
        assert_eq!(count_bands(&p, &rule(false)), 0);
        // the same noise on top of two bands leaves two bands
        let q: Vec<f64> = p
            .iter()
            .enumerate()
            .map(|(k, c)| c + if k < 30 { 0.3 } else { -0.3 })
            .collect();
        assert_eq!(count_bands(&q, &rule(false)), 2);
    }

    #[test]
    fn narrow_spikes_are_not_bands_and_empty_slices_are_skipped() {
        let mut p = square(3, 6);
        p[8] = 0.9; // one slice spike inside a poor band
        assert_eq!(count_bands(&p, &rule(false)), 3);
        p[3] = f64::NAN;
        assert_eq!(count_bands(&p, &rule(false)), 3);
        assert_eq!(count_bands(&[f64::NAN; 4], &rule(false)), 0);
    }
}
