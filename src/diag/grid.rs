//! Cuboid bins in the surface frame and the fixed-point sums gathered in them.
//!
//! One [`BinnedSums`] serves both the binned fields (a coarse `x, y, z` grid) and the
//! per-slice fluxes (the same `x, y` bins on every thin axial slice); they differ only in the
//! `z` resolution and in which sums they keep ([`Quantities`]).

use super::fixed::{fix, sum_to_root};
use super::surface::Frame;
use crate::comm::Comm;
use crate::particles::Particles;
use crate::physics::rough_wall::is_fixed;
use std::collections::HashMap;

/// Bins over `[-R, R] x [-R, R]` in the surface frame and `[z0, z0 + nz dz]` along the axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Bins along `x`, `y`, `z`.
    pub n: [usize; 3],
    /// Half width of the cross-section (the drum radius).
    pub radius: f64,
    /// Lower end along the axis.
    pub z0: f64,
    /// Bin sizes along `x`, `y`, `z`.
    pub size: [f64; 3],
}

impl Grid {
    /// `n` bins over a drum of `radius` and axial extent `[z0, z0 + length]`.
    pub fn new(n: [usize; 3], radius: f64, z0: f64, length: f64) -> Self {
        Grid {
            n,
            radius,
            z0,
            size: [
                2.0 * radius / n[0] as f64,
                2.0 * radius / n[1] as f64,
                length / n[2] as f64,
            ],
        }
    }

    /// Number of bins.
    pub fn bins(&self) -> usize {
        self.n.iter().product()
    }

    /// Volume of one bin.
    pub fn bin_volume(&self) -> f64 {
        self.size.iter().product()
    }

    /// Centres of the bins along axis `a`.
    pub fn centres(&self, a: usize) -> Vec<f64> {
        let lo = if a == 2 { self.z0 } else { -self.radius };
        (0..self.n[a])
            .map(|k| lo + (k as f64 + 0.5) * self.size[a])
            .collect()
    }

    /// Flat index `(ix * ny + iy) * nz + iz` of the bin holding surface-frame `(xs, ys, z)`
    /// (clamped to the grid).
    #[inline]
    pub fn index(&self, xs: f64, ys: f64, z: f64) -> usize {
        let ix = clamp((xs + self.radius) / self.size[0], self.n[0]);
        let iy = clamp((ys + self.radius) / self.size[1], self.n[1]);
        let iz = clamp((z - self.z0) / self.size[2], self.n[2]);
        (ix * self.n[1] + iy) * self.n[2] + iz
    }
}

#[inline]
fn clamp(f: f64, n: usize) -> usize {
    if f > 0.0 {
        (f as usize).min(n - 1)
    } else {
        0
    }
}

/// Which sums a [`BinnedSums`] keeps per species and bin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantities {
    /// Count, volume, position `(x, y)`, drum-frame velocity and its square (10 sums).
    Fields,
    /// Volume and volume times axial velocity (2 sums).
    Flux,
}

impl Quantities {
    /// Sums per species and bin.
    pub fn len(self) -> usize {
        match self {
            Quantities::Fields => 10,
            Quantities::Flux => 2,
        }
    }

    /// Whether no sums are kept.
    pub fn is_empty(self) -> bool {
        self.len() == 0
    }
}

/// Offsets of the [`Quantities::Fields`] sums.
pub mod field {
    /// Particles.
    pub const COUNT: usize = 0;
    /// Particle volume.
    pub const VOLUME: usize = 1;
    /// Surface-frame `x` of the centres.
    pub const X: usize = 2;
    /// Surface-frame `y` of the centres.
    pub const Y: usize = 3;
    /// Drum-frame velocity `(u, v, w)`.
    pub const VEL: usize = 4;
    /// Squares of the drum-frame velocity components.
    pub const VEL2: usize = 7;
}

/// Offsets of the [`Quantities::Flux`] sums.
pub mod flux {
    /// Particle volume.
    pub const VOLUME: usize = 0;
    /// Volume times axial velocity.
    pub const VOLUME_W: usize = 1;
}

/// Reference scales of the fixed-point sums.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// Lengths (the drum radius).
    pub length: f64,
    /// Volumes (the cube of the largest nominal diameter).
    pub volume: f64,
    /// Velocities (the wall speed or `sqrt(g d)`, whichever is larger).
    pub velocity: f64,
}

/// The reference velocity of a case's fixed-point velocity sums: the wall speed `|omega| R`
/// or `sqrt(g d_max)`, whichever is larger.
pub fn velocity_scale(case: &crate::case::Case) -> f64 {
    (case.drum.omega.abs() * 0.5 * case.drum.diameter)
        .max((case.model.gravity.abs() * case.d_max()).sqrt())
}

/// Fixed-point sums per bin, species and quantity, accumulated over the samples of a window.
#[derive(Debug, Clone, PartialEq)]
pub struct BinnedSums {
    /// The bins.
    pub grid: Grid,
    /// Number of species.
    pub ns: usize,
    /// What is summed.
    pub what: Quantities,
    /// Reference scales.
    pub scales: Scales,
    /// Samples accumulated.
    pub samples: u64,
    /// Sum of the frame angles of the samples (degrees).
    pub angle_sum: f64,
    /// The reduced window, `sums[(bin * ns + species) * q + quantity]`: whole on rank 0
    /// (see [`hold_whole`](Self::hold_whole)), empty on the other ranks.
    pub sums: Vec<i128>,
    /// This rank's own sums since the last reduction, only for the bins its particles
    /// touched (those of its slab, not the whole drum): the offset in `local_values` of
    /// each touched `(bin * ns + species) * q`.
    local_index: HashMap<usize, usize>,
    local_values: Vec<i128>,
}

/// Values reduced at a time by [`BinnedSums::reduce`] (then rounded down to whole bins).
const REDUCE_CHUNK: usize = 1 << 16;

impl BinnedSums {
    /// Empty sums.
    pub fn new(grid: Grid, ns: usize, what: Quantities, scales: Scales) -> Self {
        BinnedSums {
            grid,
            ns,
            what,
            scales,
            samples: 0,
            angle_sum: 0.0,
            sums: Vec::new(),
            local_index: HashMap::new(),
            local_values: Vec::new(),
        }
    }

    /// Hold the whole sums from the start (rank 0, which reduces into them): its own
    /// particles are then added there directly, not through the touched bins.
    pub fn hold_whole(&mut self) {
        if self.sums.len() != self.len() {
            self.sums = vec![0; self.len()];
        }
    }

    /// Length of the whole sums (bins x species x quantities).
    pub fn len(&self) -> usize {
        self.grid.bins() * self.ns * self.what.len()
    }

    /// Whether there are no bins.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Forget everything accumulated.
    pub fn clear(&mut self) {
        self.samples = 0;
        self.angle_sum = 0.0;
        // writing only where needed leaves untouched pages unmapped
        self.sums
            .iter_mut()
            .filter(|x| **x != 0)
            .for_each(|x| *x = 0);
        self.local_index.clear();
        self.local_values.clear();
    }

    /// The sum of `quantity` for `species` in `bin`.
    #[inline]
    pub fn get(&self, bin: usize, species: usize, quantity: usize) -> i128 {
        self.sums[(bin * self.ns + species) * self.what.len() + quantity]
    }

    /// Add this rank's particles, seen in `frame`, in a drum turning at `omega`.
    pub fn add(&mut self, p: &Particles, frame: &Frame, omega: f64) {
        let q = self.what.len();
        let Scales {
            length,
            volume,
            velocity,
        } = self.scales;
        for i in 0..p.n_owned {
            if is_fixed(p.species[i]) {
                continue;
            }
            let [x, y, z] = p.x[i];
            let [vx, vy, vz] = p.v[i];
            let (xs, ys) = frame.project(x, y);
            let d = p.diameter[i];
            let vol = d * d * d;
            let base = (self.grid.index(xs, ys, z) * self.ns + p.species[i] as usize) * q;
            let s = if self.sums.is_empty() {
                let values = &mut self.local_values;
                let at = *self.local_index.entry(base).or_insert_with(|| {
                    values.resize(values.len() + q, 0);
                    values.len() - q
                });
                &mut values[at..at + q]
            } else {
                &mut self.sums[base..base + q]
            };
            match self.what {
                Quantities::Fields => {
                    // drum frame: remove omega z x r
                    let (ud, vd) = frame.project(vx + omega * y, vy - omega * x);
                    s[field::COUNT] += 1;
                    s[field::VOLUME] += fix(vol, volume);
                    s[field::X] += fix(xs, length);
                    s[field::Y] += fix(ys, length);
                    for (k, c) in [ud, vd, vz].into_iter().enumerate() {
                        s[field::VEL + k] += fix(c, velocity);
                        s[field::VEL2 + k] += fix(c * c, velocity * velocity);
                    }
                }
                Quantities::Flux => {
                    s[flux::VOLUME] += fix(vol, volume);
                    s[flux::VOLUME_W] += fix(vol * vz, volume * velocity);
                }
            }
        }
        self.samples += 1;
        self.angle_sum += frame.angle;
    }

    /// Add every rank's own sums into the whole sums on rank 0 (all ranks call this
    /// together); each rank starts its own afresh. Every rank sends the whole length in
    /// chunks, made from the bins it touched, so no rank but 0 holds the whole drum's bins.
    pub fn reduce(&mut self, comm: &dyn Comm) {
        let root = comm.rank() == 0;
        let (len, q) = (self.len(), self.what.len());
        if root && self.sums.len() != len {
            self.sums = vec![0; len];
        }
        let mut touched: Vec<(usize, usize)> =
            self.local_index.iter().map(|(&b, &at)| (b, at)).collect();
        touched.sort_unstable();
        // whole bins per chunk, so that no bin's values straddle two chunks
        let step = (REDUCE_CHUNK / q.max(1)).max(1) * q.max(1);
        let mut part = vec![0i128; step.min(len)];
        let mut next = 0;
        for start in (0..len).step_by(step) {
            let end = (start + step).min(len);
            let part = &mut part[..end - start];
            part.fill(0);
            while let Some(&(b, at)) = touched.get(next).filter(|(b, _)| *b < end) {
                for (x, v) in part[b - start..b - start + q]
                    .iter_mut()
                    .zip(&self.local_values[at..at + q])
                {
                    *x += v;
                }
                next += 1;
            }
            sum_to_root(part, comm);
            if root {
                // leave the pages of bins nothing reached untouched (most of a drum's are)
                for (x, v) in self.sums[start..end].iter_mut().zip(part.iter()) {
                    if *v != 0 {
                        *x += v;
                    }
                }
            }
        }
        self.local_index.clear();
        self.local_values.clear();
    }
}
