//! Spatial sorting: the order keys that keep the pair loop's memory accesses local.
//!
//! A drum mixes its bed: particles that were neighbours at the start (in id order, as poured
//! or read) end up anywhere. Every [`crate::case::schema::Run::sort_every`] steps each particle
//! gets a key, the Morton (Z-order) index of the cell of a fixed grid over the whole drum that
//! holds its centre, and the pair list and the owned particles' storage follow the order of
//! `(key, id)` until the next sort, as LAMMPS' `atom_modify sort` does for its atoms.
//!
//! The keys are part of the state: a key is computed from the position alone, on the same
//! grid on every rank (a ghost's coordinates are its owner's, bit for bit), at steps fixed by
//! the step count, and it is saved in checkpoints. The order of every sum of pair forces is
//! then the same on any number of ranks and after a restart. Key 0 for every particle (no
//! sort yet, or `sort_every = 0`) is the order of the ids.

use crate::particles::Particles;

/// Bits of each cell coordinate in a key: three of them make a key of 51 bits, exact as
/// the `f64` it travels as in messages.
const BITS: u32 = 17;

/// The grid of the keys: cubic cells over the drum's bounding box.
#[derive(Debug, Clone, Copy)]
pub struct KeyGrid {
    lo: [f64; 3],
    inv_cell: f64,
}

impl KeyGrid {
    /// Cells of about `cell` (enlarged if needed, so that `2^17` of them span the box) over
    /// `x, y` in `[-radius, radius]` and `z` in `[-length/2, length/2]`.
    pub fn new(radius: f64, length: f64, cell: f64) -> Self {
        let span = (2.0 * radius).max(length);
        let cell = cell.max(span / (1u64 << BITS) as f64);
        KeyGrid {
            lo: [-radius, -radius, -0.5 * length],
            inv_cell: 1.0 / cell,
        }
    }

    /// The key of a particle at `x`; one outside the box (or not finite) has the key of the
    /// nearest cell.
    pub fn key(&self, x: [f64; 3]) -> u64 {
        let max = ((1u64 << BITS) - 1) as f64;
        let c = |k: usize| {
            // `as` saturates and maps NaN to 0
            (((x[k] - self.lo[k]) * self.inv_cell)
                .floor()
                .clamp(0.0, max)) as u64
        };
        spread(c(0)) | spread(c(1)) << 1 | spread(c(2)) << 2
    }

    /// Give every particle of `p` the key of where it is now (called on the owned particles
    /// alone: a ghost's position may be a step behind its owner's, and it gets its key from
    /// the owner with the halo).
    pub fn set_keys(&self, p: &mut Particles) {
        for (k, x) in p.key.iter_mut().zip(&p.x) {
            *k = self.key(*x);
        }
    }
}

/// The low [`BITS`] bits of `v`, two zero bits inserted after each.
fn spread(v: u64) -> u64 {
    let mut v = v & ((1 << BITS) - 1);
    v = (v | v << 32) & 0x1f00000000ffff;
    v = (v | v << 16) & 0x1f0000ff0000ff;
    v = (v | v << 8) & 0x100f00f00f00f00f;
    v = (v | v << 4) & 0x10c30c30c30c30c3;
    (v | v << 2) & 0x1249249249249249
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_interleaves_every_bit() {
        for b in 0..BITS {
            assert_eq!(spread(1 << b), 1 << (3 * b));
        }
        assert_eq!(
            spread((1 << BITS) - 1),
            0x1249249249249249 & ((1 << 51) - 1)
        );
    }

    #[test]
    fn keys_follow_the_z_order_and_stay_below_2_to_the_53() {
        let g = KeyGrid::new(1.0, 4.0, 0.5);
        // cells (0,0,0), (1,0,0), (0,1,0), (1,1,0), (0,0,1)...
        let at = |i: f64, j: f64, k: f64| {
            [
                -1.0 + 0.5 * i + 0.25,
                -1.0 + 0.5 * j + 0.25,
                -2.0 + 0.5 * k + 0.25,
            ]
        };
        let keys: Vec<u64> = [
            (0., 0., 0.),
            (1., 0., 0.),
            (0., 1., 0.),
            (1., 1., 0.),
            (0., 0., 1.),
        ]
        .iter()
        .map(|&(i, j, k)| g.key(at(i, j, k)))
        .collect();
        assert_eq!(keys, vec![0, 1, 2, 3, 4]);
        // far outside, or not finite: an edge cell
        assert_eq!(g.key([-9.0, -9.0, -9.0]), 0);
        assert_eq!(g.key([f64::NAN; 3]), 0);
        let top = g.key([1e300, 1e300, 1e300]);
        assert_eq!(top, (1u64 << 51) - 1);
        assert!(top < 1 << 53);
    }
}
