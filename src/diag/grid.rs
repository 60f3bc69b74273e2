//! Cuboid bins in the surface frame and the fixed-point sums gathered in them.
//!
//! One [`BinnedSums`] serves both the binned fields (a coarse `x, y, z` grid) and the
//! per-slice fluxes (the same `x, y` bins on every thin axial slice); they differ only in the
//! `z` resolution and in which sums they keep ([`Quantities`]).

use super::fixed::fix;
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

/// Which rank holds which axial bins of a [`BinnedSums`] once reduced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// Every rank an even block of the axial bins: rank `r` of `P` holds bins
    /// `[r nz / P, (r + 1) nz / P)` (the per-slice sums, whose size grows with the drum).
    Even,
    /// Rank 0 holds all of them (the fields, a fixed coarse grid derived on rank 0).
    Root,
}

/// The axial bins `[lo, hi)` rank `rank` of `size` holds of `nz` split as `split` says.
pub fn own_range(split: Split, nz: usize, rank: usize, size: usize) -> std::ops::Range<usize> {
    let at = |r: usize| match split {
        Split::Even => (nz as u128 * r as u128 / size.max(1) as u128) as usize,
        Split::Root => {
            if r == 0 {
                0
            } else {
                nz
            }
        }
    };
    at(rank)..at(rank + 1)
}

/// Fixed-point sums per bin, species and quantity, accumulated over the samples of a window.
///
/// The reduced sums are held in blocks of axial bins ([`Split`]): each rank holds its own
/// block, for every `x, y` bin the run of its axial bins, in the order of the whole sums
/// (`x, y, z, species, quantity`, `z` before the species). A rank adds its particles in
/// its block directly and those elsewhere to a table of the bins they touched (those of its
/// slab, not the whole drum), which [`reduce`](Self::reduce) sends to the bins' holders.
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
    /// Who holds which axial bins.
    pub split: Split,
    /// Samples accumulated.
    pub samples: u64,
    /// Sum of the frame angles of the samples (degrees).
    pub angle_sum: f64,
    /// This rank's block of the reduced window (see [`hold_own`](Self::hold_own)), in the
    /// whole sums' order: `sums[((xy * nown + iz - lo) * ns + species) * q + quantity]` for
    /// `x, y` bin `xy` and axial bin `iz` in `[lo, lo + nown)`.
    pub sums: Vec<i128>,
    /// `(rank, ranks)` whose block `sums` is, once held.
    held: Option<(usize, usize)>,
    /// The axial bins of this rank's block.
    own: std::ops::Range<usize>,
    /// This rank's own sums since the last reduction outside its block, only for the bins
    /// its particles touched: the offset in `local_values` of each touched
    /// `(bin * ns + species) * q` (a whole-sums index).
    local_index: HashMap<usize, usize>,
    local_values: Vec<i128>,
}

impl BinnedSums {
    /// Empty sums, held as `split` says once [`hold_own`](Self::hold_own) is called.
    pub fn new(grid: Grid, ns: usize, what: Quantities, scales: Scales, split: Split) -> Self {
        BinnedSums {
            grid,
            ns,
            what,
            scales,
            split,
            samples: 0,
            angle_sum: 0.0,
            sums: Vec::new(),
            held: None,
            own: 0..0,
            local_index: HashMap::new(),
            local_values: Vec::new(),
        }
    }

    /// Hold this rank's block (rank `rank` of `size`) from now on: its particles there are
    /// added to it directly. Any sums held before are dropped.
    pub fn hold_own(&mut self, rank: usize, size: usize) {
        if self.held == Some((rank, size)) {
            return;
        }
        self.own = own_range(self.split, self.grid.n[2], rank, size);
        self.held = Some((rank, size));
        // zeroed pages stay unmapped until a particle reaches them
        self.sums = vec![0; self.block_len()];
    }

    /// The axial bins of this rank's block (empty before [`hold_own`](Self::hold_own)).
    pub fn own(&self) -> std::ops::Range<usize> {
        self.own.clone()
    }

    /// Length of the whole sums (bins x species x quantities).
    pub fn len(&self) -> usize {
        self.grid.bins() * self.ns * self.what.len()
    }

    /// Whether there are no bins.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Length of this rank's block.
    pub fn block_len(&self) -> usize {
        self.grid.n[0] * self.grid.n[1] * self.own.len() * self.ns * self.what.len()
    }

    /// Where this rank's block lies in the whole sums, in their order: one run of its axial
    /// bins per `x, y` bin.
    pub fn blocks(&self) -> crate::output::pario::Blocks {
        let per_z = (self.ns * self.what.len()) as u64;
        let xy = (self.grid.n[0] * self.grid.n[1]) as u64;
        let block = self.own.len() as u64 * per_z;
        crate::output::pario::Blocks {
            offset: self.own.start as u64 * per_z,
            block,
            stride: self.grid.n[2] as u64 * per_z,
            count: if block > 0 { xy } else { 0 },
            total: self.len() as u64,
        }
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

    /// The index in this rank's block of whole-sums index `at` (`None` outside it).
    #[inline]
    fn in_block(&self, at: usize) -> Option<usize> {
        let per_z = self.ns * self.what.len();
        let nz = self.grid.n[2];
        let (xy, rest) = (at / (nz * per_z), at % (nz * per_z));
        let (iz, within) = (rest / per_z, rest % per_z);
        self.own
            .contains(&iz)
            .then(|| (xy * self.own.len() + iz - self.own.start) * per_z + within)
    }

    /// The sum of `quantity` for `species` in `bin` (a whole-grid index of a bin in this
    /// rank's block).
    #[inline]
    pub fn get(&self, bin: usize, species: usize, quantity: usize) -> i128 {
        let at = (bin * self.ns + species) * self.what.len() + quantity;
        match self.in_block(at) {
            Some(k) => self.sums[k],
            None => panic!(
                "bin {bin} is not in this rank's block of axial bins {:?}",
                self.own
            ),
        }
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
            let s = match self.in_block(base) {
                Some(k) => &mut self.sums[k..k + q],
                None => {
                    let values = &mut self.local_values;
                    let at = *self.local_index.entry(base).or_insert_with(|| {
                        values.resize(values.len() + q, 0);
                        values.len() - q
                    });
                    &mut values[at..at + q]
                }
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

    /// Add every rank's sums of the bins it touched outside its block into the blocks of
    /// the ranks that hold them (all ranks call this together): one irregular exchange of
    /// the touched bins only, each as its whole-sums index and its values (two 64-bit words
    /// each, exact). Integer sums do not depend on the order, so the blocks are the same
    /// bits on any number of ranks. Each rank starts its own afresh.
    pub fn reduce(&mut self, comm: &dyn Comm) {
        self.hold_own(comm.rank(), comm.size());
        let q = self.what.len();
        let per_z = self.ns * q;
        let nz = self.grid.n[2];
        // where each rank's block starts; blocks follow in rank order
        let starts: Vec<usize> = (0..comm.size())
            .map(|r| own_range(self.split, nz, r, comm.size()).start)
            .collect();
        let mut touched: Vec<(usize, usize)> =
            self.local_index.iter().map(|(&b, &at)| (b, at)).collect();
        touched.sort_unstable();
        let mut to: Vec<Vec<f64>> = vec![Vec::new(); comm.size()];
        for &(b, at) in &touched {
            let iz = (b / per_z) % nz;
            // the holder: the last rank whose block starts at or before iz
            let r = starts.partition_point(|&lo| lo <= iz) - 1;
            let m = &mut to[r];
            m.push(f64::from_bits(b as u64));
            for &v in &self.local_values[at..at + q] {
                m.push(f64::from_bits((v >> 64) as u64));
                m.push(f64::from_bits(v as u64));
            }
        }
        drop(touched);
        self.local_index.clear();
        self.local_values = Vec::new();
        let from = comm.all_to_all(to);
        for m in &from {
            for rec in m.chunks_exact(1 + 2 * q) {
                let b = rec[0].to_bits() as usize;
                let k = self
                    .in_block(b)
                    .expect("a rank sent window sums to a rank that does not hold them");
                for (x, w) in self.sums[k..k + q].iter_mut().zip(rec[1..].chunks_exact(2)) {
                    *x += ((w[0].to_bits() as i64 as i128) << 64) | w[1].to_bits() as i128;
                }
            }
        }
    }
}
