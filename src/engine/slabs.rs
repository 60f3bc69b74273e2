//! The axial-slab decomposition: rank `k` owns particles with `z` in `[z_k, z_{k+1})`.

/// Slab boundaries and the neighbour structure of the ranks.
#[derive(Debug, Clone)]
pub struct Slabs {
    /// `size + 1` boundaries from `-L/2` to `L/2`.
    pub bounds: Vec<f64>,
    /// Whether the first and last slab are neighbours across the periodic ends.
    pub periodic: bool,
    /// Drum length `L`.
    pub length: f64,
}

impl Slabs {
    /// `size` slabs of equal length over a drum of length `length`.
    pub fn uniform(size: usize, length: f64, periodic: bool) -> Self {
        let bounds = (0..=size)
            .map(|k| {
                if k == size {
                    0.5 * length
                } else {
                    -0.5 * length + length * k as f64 / size as f64
                }
            })
            .collect();
        Slabs {
            bounds,
            periodic,
            length,
        }
    }

    /// Number of slabs.
    pub fn size(&self) -> usize {
        self.bounds.len() - 1
    }

    /// `[z_lo, z_hi)` of slab `rank`.
    pub fn range(&self, rank: usize) -> (f64, f64) {
        (self.bounds[rank], self.bounds[rank + 1])
    }

    /// The axial positions `rank` owns: its range, reaching out to infinity at the ends (where
    /// positions clamp to the end slabs, as in [`Slabs::owner`]).
    pub fn owned_span(&self, rank: usize) -> (f64, f64) {
        let (lo, hi) = self.range(rank);
        let lo = if rank == 0 { f64::NEG_INFINITY } else { lo };
        let hi = if rank + 1 == self.size() {
            f64::INFINITY
        } else {
            hi
        };
        (lo, hi)
    }

    /// Thinnest slab.
    pub fn min_width(&self) -> f64 {
        self.bounds
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
    }

    /// The rank owning axial position `z` (positions at or beyond the ends clamp to the end slabs).
    pub fn owner(&self, z: f64) -> usize {
        let n = self.size();
        // first boundary strictly greater than z, minus one
        let k = self.bounds[1..n].partition_point(|&b| b <= z);
        k.min(n - 1)
    }

    /// The neighbour below `rank` (towards `-z`), if any.
    pub fn down(&self, rank: usize) -> Option<usize> {
        match rank {
            0 if self.periodic => Some(self.size() - 1),
            0 => None,
            r => Some(r - 1),
        }
    }

    /// The neighbour above `rank` (towards `+z`), if any.
    pub fn up(&self, rank: usize) -> Option<usize> {
        let n = self.size();
        if rank + 1 < n {
            Some(rank + 1)
        } else if self.periodic {
            Some(0)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn owner_and_neighbours() {
        let s = Slabs::uniform(3, 30.0, true);
        assert_eq!(s.owner(-15.0), 0);
        assert_eq!(s.owner(-5.0), 1);
        assert_eq!(s.owner(-5.000001), 0);
        assert_eq!(s.owner(14.9), 2);
        assert_eq!(s.owner(15.0), 2);
        assert_eq!(s.down(0), Some(2));
        assert_eq!(s.up(2), Some(0));
        let c = Slabs::uniform(1, 30.0, false);
        assert_eq!((c.down(0), c.up(0)), (None, None));
        let p = Slabs::uniform(1, 30.0, true);
        assert_eq!((p.down(0), p.up(0)), (Some(0), Some(0)));
    }
}
