//! Fixed-point sums that are the same bits on any number of ranks.
//!
//! A value is stored as a 128-bit integer count of `2^-40` of a reference scale (a length,
//! volume or velocity chosen per quantity). Integer addition does not depend on order, so
//! sums over particles, samples and ranks are exact and rank-count invariant; only the final
//! conversion back to floating point rounds, once.

use crate::comm::Comm;

/// Values reduced per message in [`sum_to_root`].
const CHUNK: usize = 1 << 16;

/// One unit of the reference scale.
const ONE: f64 = (1u64 << 40) as f64;

/// `x` in units of `2^-40 scale`, rounded.
#[inline]
pub fn fix(x: f64, scale: f64) -> i128 {
    (x / scale * ONE).round() as i128
}

/// Back to floating point.
#[inline]
pub fn unfix(v: i128, scale: f64) -> f64 {
    v as f64 / ONE * scale
}

/// Element-wise sum of `v` over all ranks, delivered to rank 0 (others keep theirs). Each
/// value travels as three `i64` limbs (high 64 bits, and two 32-bit halves of the low 64):
/// the low limbs sum without overflow on up to `2^31` ranks, the high one as long as the
/// values stay below `2^95` (sums here stay far below `2^80`).
pub fn sum_to_root(v: &mut [i128], comm: &dyn Comm) {
    if comm.size() == 1 {
        return;
    }
    // in chunks, so that the limbs and rank 0's receive buffer stay small (a window's
    // sums are megabytes)
    let mut limbs = Vec::with_capacity(3 * CHUNK.min(v.len()));
    for part in v.chunks_mut(CHUNK) {
        limbs.clear();
        for &x in part.iter() {
            let low = x as u64;
            limbs.push((x >> 64) as i64);
            limbs.push((low >> 32) as i64);
            limbs.push((low & 0xffff_ffff) as i64);
        }
        comm.sum_i64_to_root(&mut limbs);
        if comm.rank() == 0 {
            for (x, l) in part.iter_mut().zip(limbs.chunks_exact(3)) {
                *x = ((l[0] as i128) << 64) + ((l[1] as i128) << 32) + l[2] as i128;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limbs_recombine_exactly() {
        for x in [
            0i128,
            1,
            -1,
            1 << 70,
            -(1 << 70) + 12345,
            i64::MIN as i128 * 3,
        ] {
            let low = x as u64;
            let l = [
                (x >> 64) as i64,
                (low >> 32) as i64,
                (low & 0xffff_ffff) as i64,
            ];
            // two copies summed limb by limb give 2x
            let y = ((2 * l[0] as i128) << 64) + ((2 * l[1] as i128) << 32) + 2 * l[2] as i128;
            assert_eq!(y, 2 * x);
        }
    }

    #[test]
    fn round_trip_is_within_one_unit() {
        let x = 0.123456789;
        assert!((unfix(fix(x, 2.0), 2.0) - x).abs() < 2.0 / ONE);
    }
}
