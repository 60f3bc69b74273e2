//! Load balance: slab boundaries placed so that every rank gets the same share of the work.
//!
//! The work of a particle is one unit plus one per listed pair it belongs to (the force
//! loop's cost). Each rank bins its owned particles' work in thin axial bins; the integer
//! histogram is summed over all ranks, and every rank cuts it at the same places, so the new
//! boundaries are the same everywhere. Moving a boundary only changes which rank owns a
//! particle, never a force, so the run stays the same bits.

/// Work per rank divided by its mean: `max / mean` (1 = perfect balance).
pub fn imbalance(work: &[u64]) -> f64 {
    let total: u64 = work.iter().sum();
    if total == 0 {
        return 1.0;
    }
    let max = *work.iter().max().unwrap_or(&0) as f64;
    max * work.len() as f64 / total as f64
}

/// Work of each of `ranks` slabs with boundaries `bounds` from a histogram of `hist` over
/// `[z0, z0 + length]`.
pub fn work_per_slab(hist: &[u64], z0: f64, length: f64, bounds: &[f64]) -> Vec<u64> {
    let nb = hist.len();
    let mut w = vec![0u64; bounds.len() - 1];
    for (k, &h) in hist.iter().enumerate() {
        let zc = z0 + (k as f64 + 0.5) * length / nb as f64;
        let r = bounds[1..bounds.len() - 1].partition_point(|&b| b <= zc);
        w[r] += h;
    }
    w
}

/// Boundaries (`ranks + 1`, from `z0` to `z0 + length`) that split the histogram `hist` into
/// `ranks` slabs with the smallest possible largest share, each slab longer than `min_width`
/// (the halo width: a ghost must come from a neighbouring slab); cuts fall on bin edges.
///
/// The smallest feasible largest share is found by bisection; for a given share the cuts
/// are placed greedily from `z0`, each slab taking as many bins as the share allows while
/// leaving room for the slabs after it. `None` if the slabs cannot all be longer than
/// `min_width` with cuts on bin edges.
pub fn balanced_bounds(
    hist: &[u64],
    z0: f64,
    length: f64,
    ranks: usize,
    min_width: f64,
) -> Option<Vec<f64>> {
    let nb = hist.len();
    let bw = length / nb as f64;
    // strictly more than `min_width` bins' worth, so rounding can never make a slab thinner
    let min_bins = (min_width / bw).floor() as usize + 1;
    let to_bounds = |cuts: &[usize]| -> Vec<f64> {
        cuts.iter()
            .map(|&k| {
                if k == nb {
                    z0 + length
                } else {
                    z0 + k as f64 * bw
                }
            })
            .collect()
    };
    if ranks == 1 {
        return Some(vec![z0, z0 + length]);
    }
    if min_bins * ranks > nb {
        return None;
    }
    let mut cum = vec![0u64; nb + 1];
    for (k, &h) in hist.iter().enumerate() {
        cum[k + 1] = cum[k] + h;
    }
    let total = cum[nb];
    let cuts_for = |share: u64| -> Option<Vec<usize>> {
        let mut cuts = vec![0usize; ranks + 1];
        cuts[ranks] = nb;
        for r in 1..ranks {
            let start = cuts[r - 1];
            let (lo, hi) = (start + min_bins, nb - (ranks - r) * min_bins);
            if lo > hi || cum[lo] - cum[start] > share {
                return None;
            }
            // the last edge in [lo, hi] up to which the slab holds at most `share`
            let fits = cum[lo..=hi].partition_point(|&c| c - cum[start] <= share);
            cuts[r] = lo + fits - 1;
        }
        (total - cum[cuts[ranks - 1]] <= share).then_some(cuts)
    };
    let (mut lo, mut hi) = (total.div_ceil(ranks as u64), total);
    let mut best = cuts_for(hi)?;
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        match cuts_for(mid) {
            Some(c) => {
                best = c;
                hi = mid;
            }
            None => lo = mid + 1,
        }
    }
    if let Some(c) = cuts_for(hi) {
        best = c;
    }
    Some(to_bounds(&best))
}

/// The smallest imbalance any `ranks` slabs longer than `min_width` can reach on `hist`
/// (cuts on bin edges, as [`balanced_bounds`] places them): a slab holding bin `k` holds at
/// least the lightest run of that many bins around `k`, so the heaviest such run bounds
/// the largest share from below. On too many ranks for the drum's length, or a drum with a
/// dense band narrower than a few slabs, this is what keeps the balance from 1.
pub fn imbalance_bound(hist: &[u64], length: f64, ranks: usize, min_width: f64) -> f64 {
    let nb = hist.len();
    let total: u64 = hist.iter().sum();
    if total == 0 || ranks <= 1 {
        return 1.0;
    }
    let min_bins = ((min_width / (length / nb as f64)).floor() as usize + 1).min(nb);
    let mut cum = vec![0u64; nb + 1];
    for (k, &h) in hist.iter().enumerate() {
        cum[k + 1] = cum[k] + h;
    }
    // work of the run of min_bins bins starting at bin i
    let run = |i: usize| cum[i + min_bins] - cum[i];
    let starts = nb - min_bins; // last start
    let heaviest = (0..nb)
        .map(|k| {
            let (a, b) = (k.saturating_sub(min_bins - 1), k.min(starts));
            (a..=b).map(run).min().unwrap_or(0)
        })
        .max()
        .unwrap_or(0);
    let share = (heaviest as f64).max(total as f64 / ranks as f64);
    share * ranks as f64 / total as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_work_gives_equal_slabs() {
        let h = vec![10u64; 100];
        let b = balanced_bounds(&h, -50.0, 100.0, 4, 1.0).unwrap();
        assert_eq!(b, vec![-50.0, -25.0, 0.0, 25.0, 50.0]);
        assert_eq!(imbalance(&work_per_slab(&h, -50.0, 100.0, &b)), 1.0);
    }

    #[test]
    fn segregated_halves_are_evened_out() {
        // eight times more work per length in the lower half
        let h: Vec<u64> = (0..200).map(|k| if k < 100 { 80 } else { 10 }).collect();
        let uniform = [-1.0, 0.0, 1.0];
        assert!(imbalance(&work_per_slab(&h, -1.0, 2.0, &uniform)) > 1.7);
        let b = balanced_bounds(&h, -1.0, 2.0, 2, 0.1).unwrap();
        let i = imbalance(&work_per_slab(&h, -1.0, 2.0, &b));
        assert!(i < 1.01, "{i}");
        assert!(b[1] < -0.3);
    }

    #[test]
    fn slabs_keep_their_minimum_width() {
        let mut h = vec![0u64; 100];
        h[0] = 1000; // all the work at one end
        let b = balanced_bounds(&h, 0.0, 10.0, 3, 2.0).unwrap();
        for w in b.windows(2) {
            assert!(w[1] - w[0] > 2.0, "{b:?}");
        }
    }

    #[test]
    fn the_largest_share_is_the_smallest_possible() {
        // a dense band in the middle of a long drum, eight slabs: every slab within one bin
        // of its share, none thinner than the minimum
        let h: Vec<u64> = (0..4000)
            .map(|k| {
                if (1500..2500).contains(&k) {
                    90
                } else {
                    3 + (k % 7) as u64
                }
            })
            .collect();
        for ranks in [2, 3, 4, 6, 8] {
            let b = balanced_bounds(&h, -20.0, 40.0, ranks, 0.5).unwrap();
            assert_eq!(b.len(), ranks + 1);
            assert_eq!((b[0], b[ranks]), (-20.0, 20.0));
            for w in b.windows(2) {
                assert!(w[1] - w[0] > 0.5, "{ranks} ranks: {b:?}");
            }
            let i = imbalance(&work_per_slab(&h, -20.0, 40.0, &b));
            assert!(i < 1.01, "{ranks} ranks: imbalance {i}");
        }
    }

    #[test]
    fn the_bound_is_reached_where_the_width_limits_and_is_1_where_it_does_not() {
        // all the work in one bin: the slab holding it holds everything
        let mut h = vec![0u64; 100];
        h[40] = 1000;
        assert_eq!(imbalance_bound(&h, 10.0, 4, 2.0), 4.0);
        let b = balanced_bounds(&h, 0.0, 10.0, 4, 2.0).unwrap();
        assert_eq!(imbalance(&work_per_slab(&h, 0.0, 10.0, &b)), 4.0);
        // even work: nothing keeps the balance from 1
        assert_eq!(imbalance_bound(&[7u64; 100], 10.0, 4, 2.0), 1.0);
        // a dense band 3 long, slabs at least 1 long: 3 slabs can share it, not 4
        let h: Vec<u64> = (0..100).map(|k| if k < 30 { 100 } else { 1 }).collect();
        let bound = imbalance_bound(&h, 10.0, 8, 0.95);
        let b = balanced_bounds(&h, 0.0, 10.0, 8, 0.95).unwrap();
        let reached = imbalance(&work_per_slab(&h, 0.0, 10.0, &b));
        assert!(
            bound > 2.0 && reached >= bound && reached < 1.05 * bound,
            "{bound} {reached}"
        );
    }

    #[test]
    fn too_many_slabs_for_the_minimum_width_are_refused() {
        let h = vec![5u64; 10];
        assert_eq!(balanced_bounds(&h, 0.0, 10.0, 4, 3.0), None);
        assert!(balanced_bounds(&h, 0.0, 10.0, 2, 3.0).is_some());
    }
}
