//! What a run's thermo lines report about the state, measured by reading the particles and
//! the pair list, never changing them: particle count, kinetic energies, contacts, the
//! largest overlap, the dynamic angle of repose and the share of particles in the air.
//!
//! Every value is the same bits on any number of ranks. The energies are summed in fixed
//! point: each particle's energy is rounded to a multiple of a quantum derived from the
//! largest single-particle energy (a maximum, exact over ranks) and the particle count, so
//! the integer sum over ranks cannot overflow and does not depend on how the particles are
//! shared out. A pair that spans two slabs is listed on both ranks; it is counted on the
//! rank that owns its lower-id particle (the pair's `a`), so each contact counts once. The
//! airborne count is a sum of integers: each rank counts the particles it owns that touch
//! nothing, and a pair that spans two slabs marks its particle on each side.

use super::Sim;
use crate::diag::surface::SurfaceGauge;
use crate::physics::integrate::min_image;
use crate::physics::rough_wall::is_fixed;

/// One thermo measurement of the whole run (every rank gets the same values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermoState {
    /// Step of the measurement.
    pub step: u64,
    /// Mobile particles (rough-wall particles left out).
    pub particles: u64,
    /// Translational kinetic energy `sum m v^2 / 2` of the mobile particles.
    pub ke_trans: f64,
    /// Rotational kinetic energy `sum I w^2 / 2` of the mobile particles.
    pub ke_rot: f64,
    /// Pairs of mobile particles closer than the contact law's interaction range.
    pub contacts: u64,
    /// Largest overlap `(d_a + d_b)/2 - r` of a listed pair over the smaller diameter (the
    /// quantity `run.max_overlap` limits); rough-wall particles included.
    pub max_overlap: f64,
    /// Whole-drum dynamic angle of repose in degrees (NaN when the bed has too few surface
    /// columns to fit).
    pub repose_deg: f64,
    /// Fraction of the mobile particles that touch nothing ([`in_contact`]: no particle
    /// within the law's interaction range, no wall or lifter within its wall reach); 0
    /// without particles.
    pub airborne: f64,
}

/// Fixed-point quantum for summing `n` non-negative values no larger than `max`: the sum
/// of the rounded values stays below `2^63`.
fn quantum(max: f64, n: u64) -> f64 {
    if max <= 0.0 || !max.is_finite() {
        return 1.0;
    }
    let bits = 62 - (64 - n.max(1).leading_zeros() as i32);
    max * 2f64.powi(-bits)
}

/// Measure the state of `sim` (every rank calls this together: it reduces over ranks).
/// `gauge` is the surface gauge of the run's axial slices.
pub fn measure(sim: &Sim, gauge: &SurfaceGauge) -> ThermoState {
    let comm = sim.comm();
    let p = &sim.p;
    let mobile = || (0..p.n_owned).filter(|&i| !is_fixed(p.species[i]));
    let energy = |i: usize| {
        let [v, w] = [p.v[i], p.w[i]];
        let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        let w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        (0.5 * v2 / p.inv_mass[i], 0.5 * w2 / p.inv_inertia[i])
    };
    let (pairs, period) = sim.pair_list();
    let (mut contacts, mut overlap) = (0u64, 0.0f64);
    for &(a, b) in pairs {
        let (a, b) = (a as usize, b as usize);
        let (xa, xb) = (p.x[a], p.x[b]);
        let mut dz = xa[2] - xb[2];
        if let Some(l) = period {
            dz = min_image(dz, l);
        }
        let r2 = (xa[0] - xb[0]).powi(2) + (xa[1] - xb[1]).powi(2) + dz * dz;
        let (da, db) = (p.diameter[a] * sim.scale, p.diameter[b] * sim.scale);
        let touch = 0.5 * (da + db);
        if r2 < touch * touch {
            overlap = overlap.max((touch - r2.sqrt()) / da.min(db));
        }
        let cut = sim.law.cutoff(da, db);
        let mobile_pair = !is_fixed(p.species[a]) && !is_fixed(p.species[b]);
        if a < p.n_owned && mobile_pair && r2 < cut * cut {
            contacts += 1;
        }
    }
    let mut maxima = [0.0f64, 0.0, overlap];
    for i in mobile() {
        let (t, r) = energy(i);
        maxima[0] = maxima[0].max(t);
        maxima[1] = maxima[1].max(r);
    }
    comm.max_f64_all(&mut maxima);
    let n = sim.global_count();
    let (qt, qr) = (quantum(maxima[0], n), quantum(maxima[1], n));
    let touched = in_contact(sim);
    let mut sums = [0u64, 0, contacts, 0];
    for i in mobile() {
        let (t, r) = energy(i);
        sums[0] += (t / qt).round() as u64;
        sums[1] += (r / qr).round() as u64;
        sums[3] += u64::from(!touched[i]);
    }
    comm.sum_u64_all(&mut sums);
    let mut tops = gauge.local_tops(p);
    comm.max_f64_all(&mut tops);
    ThermoState {
        step: sim.step,
        particles: n,
        ke_trans: sums[0] as f64 * qt,
        ke_rot: sums[1] as f64 * qr,
        contacts: sums[2],
        max_overlap: maxima[2],
        repose_deg: gauge.angles(&tops).drum,
        airborne: if n > 0 {
            sums[3] as f64 / n as f64
        } else {
            0.0
        },
    }
}

/// Which owned particles touch something now: a wall, or another particle closer than
/// the law's interaction range (rough-wall particles included). Read from the state and
/// the pair list, changing nothing; local to the rank.
pub fn in_contact(sim: &Sim) -> Vec<bool> {
    let p = &sim.p;
    let (pairs, period) = sim.pair_list();
    let mut touched = vec![false; p.n_owned];
    for &(a, b) in pairs {
        let (a, b) = (a as usize, b as usize);
        let (xa, xb) = (p.x[a], p.x[b]);
        let mut dz = xa[2] - xb[2];
        if let Some(l) = period {
            dz = min_image(dz, l);
        }
        let r2 = (xa[0] - xb[0]).powi(2) + (xa[1] - xb[1]).powi(2) + dz * dz;
        let cut = sim
            .law
            .cutoff(p.diameter[a] * sim.scale, p.diameter[b] * sim.scale);
        if r2 < cut * cut {
            for i in [a, b] {
                if i < p.n_owned {
                    touched[i] = true;
                }
            }
        }
    }
    for (i, t) in touched.iter_mut().enumerate() {
        if !*t {
            let reach = sim.law.wall_reach(p.diameter[i] * sim.scale);
            *t = sim.walls.touches(p.x[i], reach);
        }
    }
    touched
}

/// Mobile particles touching nothing now ([`in_contact`]) and all mobile particles, summed
/// over ranks: `[airborne, mobile]` (every rank calls this together).
pub fn airborne(sim: &Sim) -> [u64; 2] {
    let p = &sim.p;
    let touched = in_contact(sim);
    let mut sums = [0u64, 0];
    for i in (0..p.n_owned).filter(|&i| !is_fixed(p.species[i])) {
        sums[1] += 1;
        sums[0] += u64::from(!touched[i]);
    }
    sim.comm().sum_u64_all(&mut sums);
    sums
}

#[cfg(test)]
mod tests {
    use super::quantum;

    #[test]
    fn the_fixed_point_sum_of_n_values_up_to_the_largest_fits_in_63_bits() {
        for n in [1u64, 2, 3, 1000, 13_800, 1 << 24, 1 << 40] {
            let q = quantum(7.3e-5, n);
            let each = (7.3e-5 / q).round() as u128;
            assert!(each * n as u128 <= 1u128 << 63, "n = {n}");
            // and keeps at least 20 bits of the largest value
            assert!(each >= 1 << 20, "n = {n}: {each}");
        }
        assert_eq!(quantum(0.0, 10), 1.0);
    }
}
