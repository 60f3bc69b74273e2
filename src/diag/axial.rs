//! Axial profiles: per thin slice along `z`, the count and volume of each species.
//!
//! Each rank bins its own particles; the sums are reduced to rank 0. Volumes are summed in
//! fixed point (units of `2^-40` of the largest nominal particle volume), and so are the
//! axial velocities (units of `2^-32` of a reference velocity), so the sums, and the volume
//! fractions and mean velocities derived from them, are exactly the same on any number of
//! ranks.

use crate::comm::Comm;
use crate::particles::Particles;

const FIXED_ONE: f64 = (1u64 << 40) as f64;
const FIXED_VELOCITY: f64 = (1u64 << 32) as f64;

/// The slices of the axial profiles.
#[derive(Debug, Clone)]
pub struct AxialBins {
    /// Number of slices.
    pub nz: usize,
    /// Number of species.
    pub ns: usize,
    /// Lower end of the drum (`-L/2`).
    pub z0: f64,
    /// Slice thickness (`L / nz`).
    pub width: f64,
    /// Reference volume scale (largest nominal diameter cubed).
    d3_ref: f64,
    /// Reference velocity of the fixed-point velocity sums.
    v_ref: f64,
}

/// One gathered sample: `count[s * nz + k]` and `volume_fraction[s * nz + k]`.
#[derive(Debug, Clone, PartialEq)]
pub struct AxialSample {
    /// Particles of each species per slice.
    pub count: Vec<u64>,
    /// Each species' share of the particle volume per slice (NaN where the slice is empty).
    pub volume_fraction: Vec<f64>,
    /// Mean axial velocity of each species' particles per slice (NaN where there are none).
    pub mean_axial_velocity: Vec<f64>,
}

impl AxialBins {
    /// Slices of about `slice_width` over a drum of `length`, for `ns` species whose largest
    /// nominal diameter is `d_max`; velocities are summed in units of `v_ref`.
    pub fn new(length: f64, slice_width: f64, ns: usize, d_max: f64, v_ref: f64) -> Self {
        let nz = ((length / slice_width).round() as usize).max(1);
        AxialBins {
            nz,
            ns,
            z0: -0.5 * length,
            width: length / nz as f64,
            d3_ref: d_max * d_max * d_max,
            v_ref,
        }
    }

    /// Slice centres.
    pub fn centres(&self) -> Vec<f64> {
        (0..self.nz)
            .map(|k| self.z0 + (k as f64 + 0.5) * self.width)
            .collect()
    }

    fn slice(&self, z: f64) -> usize {
        let k = ((z - self.z0) / self.width).floor();
        if k < 0.0 {
            0
        } else {
            (k as usize).min(self.nz - 1)
        }
    }

    /// Bin this rank's owned particles: `[counts | fixed-point volumes | fixed-point axial
    /// velocities]`, each `ns * nz` long.
    pub fn bin_local(&self, p: &Particles) -> Vec<i64> {
        let m = self.ns * self.nz;
        let mut acc = vec![0i64; 3 * m];
        for i in 0..p.n_owned {
            if crate::physics::rough_wall::is_fixed(p.species[i]) {
                continue;
            }
            let idx = p.species[i] as usize * self.nz + self.slice(p.x[i][2]);
            let d = p.diameter[i];
            acc[idx] += 1;
            acc[m + idx] += (d * d * d / self.d3_ref * FIXED_ONE).round() as i64;
            acc[2 * m + idx] += (p.v[i][2] / self.v_ref * FIXED_VELOCITY).round() as i64;
        }
        acc
    }

    /// Bin, reduce to rank 0 and return the sample there (`None` on other ranks).
    pub fn gather(&self, p: &Particles, comm: &dyn Comm) -> Option<AxialSample> {
        let mut acc = self.bin_local(p);
        comm.sum_i64_to_root(&mut acc);
        (comm.rank() == 0).then(|| self.finish(&acc))
    }

    /// Turn reduced sums into counts and volume fractions.
    pub fn finish(&self, acc: &[i64]) -> AxialSample {
        let m = self.ns * self.nz;
        let count = acc[..m].iter().map(|&c| c as u64).collect();
        let mut volume_fraction = vec![f64::NAN; m];
        let mean_axial_velocity = (0..m)
            .map(|k| {
                if acc[k] > 0 {
                    acc[2 * m + k] as f64 / FIXED_VELOCITY * self.v_ref / acc[k] as f64
                } else {
                    f64::NAN
                }
            })
            .collect();
        for k in 0..self.nz {
            let total: i64 = (0..self.ns).map(|s| acc[m + s * self.nz + k]).sum();
            if total > 0 {
                for s in 0..self.ns {
                    volume_fraction[s * self.nz + k] =
                        acc[m + s * self.nz + k] as f64 / total as f64;
                }
            }
        }
        AxialSample {
            count,
            volume_fraction,
            mean_axial_velocity,
        }
    }
}
