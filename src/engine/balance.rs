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
/// `ranks` equal shares, each slab at least `min_width` long; cuts fall on bin edges.
pub fn balanced_bounds(
    hist: &[u64],
    z0: f64,
    length: f64,
    ranks: usize,
    min_width: f64,
) -> Vec<f64> {
    let nb = hist.len();
    let bw = length / nb as f64;
    let total: u64 = hist.iter().sum();
    let mut bounds = vec![z0; ranks + 1];
    bounds[ranks] = z0 + length;
    let mut cum = 0u64;
    let mut k = 0usize;
    for r in 1..ranks {
        // the first bin edge where the cumulative work reaches r/ranks of the total
        let target = (total as u128 * r as u128 / ranks as u128) as u64;
        while k < nb && cum + hist[k] <= target {
            cum += hist[k];
            k += 1;
        }
        // take the nearer of the edges around the target
        if k < nb && target - cum > cum + hist[k] - target {
            cum += hist[k];
            k += 1;
        }
        let lo = bounds[r - 1] + min_width;
        let hi = z0 + length - (ranks - r) as f64 * min_width;
        bounds[r] = (z0 + k as f64 * bw).clamp(lo, hi.max(lo));
    }
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_work_gives_equal_slabs() {
        let h = vec![10u64; 100];
        let b = balanced_bounds(&h, -50.0, 100.0, 4, 1.0);
        assert_eq!(b, vec![-50.0, -25.0, 0.0, 25.0, 50.0]);
        assert_eq!(imbalance(&work_per_slab(&h, -50.0, 100.0, &b)), 1.0);
    }

    #[test]
    fn segregated_halves_are_evened_out() {
        // eight times more work per length in the lower half
        let h: Vec<u64> = (0..200).map(|k| if k < 100 { 80 } else { 10 }).collect();
        let uniform = [-1.0, 0.0, 1.0];
        assert!(imbalance(&work_per_slab(&h, -1.0, 2.0, &uniform)) > 1.7);
        let b = balanced_bounds(&h, -1.0, 2.0, 2, 0.1);
        let i = imbalance(&work_per_slab(&h, -1.0, 2.0, &b));
        assert!(i < 1.01, "{i}");
        assert!(b[1] < -0.3);
    }

    #[test]
    fn slabs_keep_their_minimum_width() {
        let mut h = vec![0u64; 100];
        h[0] = 1000; // all the work at one end
        let b = balanced_bounds(&h, 0.0, 10.0, 3, 2.0);
        for w in b.windows(2) {
            assert!(w[1] - w[0] >= 2.0 - 1e-12, "{b:?}");
        }
    }
}
