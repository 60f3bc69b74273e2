//! Random numbers keyed by the case's seed and a global index, so that any rank can make
//! any particle's random draws without making those of the particles before it: the
//! initial state is then the same bits whichever rank makes which part of it.
//!
//! [`stream`] gives the ChaCha8 stream of one index (a site, a cell, a particle) for one
//! purpose; [`Permutation`] is a keyed bijection of `0..n` (a Feistel network with cycle
//! walking), which deals out exact numbers of each species in random order, or picks which
//! cells of a layer are filled, one index at a time.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What a stream is drawn for: each purpose has its own key, so that two purposes never
/// share draws even at the same index.
#[derive(Debug, Clone, Copy)]
#[repr(u64)]
pub enum Purpose {
    /// A particle's diameter and initial velocity.
    Particle = 1,
    /// The order in which species are dealt out.
    Species = 2,
    /// Which cells of a pour layer hold a point.
    Cells = 3,
    /// Where in its cell a pour point sits.
    Jitter = 4,
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The key of `purpose` under `seed` (and a sub-key, e.g. a layer's index).
fn key(seed: u64, purpose: Purpose, sub: u64) -> u64 {
    mix(mix(seed ^ mix(purpose as u64)) ^ sub)
}

/// The random stream of `index` for `purpose` under the case's `seed`.
pub fn stream(seed: u64, purpose: Purpose, index: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(key(seed, purpose, 0));
    rng.set_stream(index);
    rng
}

/// A keyed random bijection of `0..n`.
#[derive(Debug, Clone)]
pub struct Permutation {
    n: u64,
    /// Bits of each Feistel half.
    half_bits: u32,
    keys: [u64; ROUNDS],
}

/// Feistel rounds: four make a pseudo-random permutation of a good round function.
const ROUNDS: usize = 4;

impl Permutation {
    /// The permutation of `0..n` keyed by `seed`, `purpose` and `sub`.
    pub fn new(n: u64, seed: u64, purpose: Purpose, sub: u64) -> Self {
        let bits = 64 - n.saturating_sub(1).leading_zeros();
        let half_bits = bits.div_ceil(2).max(1);
        let mut rng = ChaCha8Rng::seed_from_u64(key(seed, purpose, sub));
        let keys = std::array::from_fn(|_| rng.gen::<u64>());
        Permutation { n, half_bits, keys }
    }

    /// The image of `i` (`i < n`).
    pub fn apply(&self, i: u64) -> u64 {
        debug_assert!(i < self.n);
        // the network permutes 0..4^half_bits; walk the cycle until back inside 0..n
        let mut x = i;
        loop {
            x = self.feistel(x);
            if x < self.n {
                return x;
            }
        }
    }

    fn feistel(&self, x: u64) -> u64 {
        let mask = (1u64 << self.half_bits) - 1;
        let (mut l, mut r) = (x >> self.half_bits, x & mask);
        for k in self.keys {
            let f = mix(r ^ k) & mask;
            (l, r) = (r, l ^ f);
        }
        (l << self.half_bits) | r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_is_a_bijection_for_awkward_sizes() {
        for n in [1u64, 2, 3, 5, 17, 1000, 4097] {
            let p = Permutation::new(n, 7, Purpose::Species, 0);
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let j = p.apply(i) as usize;
                assert!(!seen[j], "n = {n}: {j} reached twice");
                seen[j] = true;
            }
        }
    }

    #[test]
    fn permutation_depends_on_its_key_and_moves_most_indices() {
        let n = 10_000;
        let a = Permutation::new(n, 1, Purpose::Species, 0);
        let b = Permutation::new(n, 2, Purpose::Species, 0);
        let c = Permutation::new(n, 1, Purpose::Cells, 0);
        let same =
            |p: &Permutation, q: &Permutation| (0..n).filter(|&i| p.apply(i) == q.apply(i)).count();
        assert!(same(&a, &b) < 20 && same(&a, &c) < 20);
        let fixed = (0..n).filter(|&i| a.apply(i) == i).count();
        assert!(fixed < 20, "{fixed} fixed points");
        // the first half of the indices is sent about evenly over both halves
        let low = (0..n / 2).filter(|&i| a.apply(i) < n / 2).count();
        assert!((2300..2700).contains(&low), "{low} of 5000 stay low");
    }

    #[test]
    fn streams_differ_by_index_and_purpose() {
        let x = |p, i| stream(5, p, i).gen::<u64>();
        assert_ne!(x(Purpose::Particle, 0), x(Purpose::Particle, 1));
        assert_ne!(x(Purpose::Particle, 0), x(Purpose::Jitter, 0));
        assert_eq!(x(Purpose::Particle, 9), x(Purpose::Particle, 9));
    }
}
