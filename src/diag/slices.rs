//! Per-slice window diagnostics (thesis §4.5 and appendix A): the upstream and downstream
//! axial flow rates of each species, the cross-sectional concentrations and mean axial
//! velocities, and the generalized diffusivity `K`.

use super::fixed::unfix;
use super::grid::{flux, BinnedSums};
use std::f64::consts::PI;

/// Packing fraction by which the thesis divides the flow rates (random dense packing).
pub const PACKING: f64 = 0.64;

/// The derived per-slice diagnostics of one window; flat arrays in C order.
#[derive(Debug, Clone, PartialEq)]
pub struct SliceWindow {
    /// Samples averaged.
    pub samples: u64,
    /// `S x Z`: `<C_s>`.
    pub concentration: Vec<f64>,
    /// `S x Z`: `<w_s>`, volume-weighted.
    pub mean_axial_velocity: Vec<f64>,
    /// `Z`: `<w>` of the mixture.
    pub mixture_axial_velocity: Vec<f64>,
    /// `S x Z`: upstream flow rate.
    pub q_up: Vec<f64>,
    /// `S x Z`: downstream flow rate.
    pub q_down: Vec<f64>,
    /// `Z`: upstream flow rate of the mixture.
    pub q_up_mixture: Vec<f64>,
    /// `Z`: downstream flow rate of the mixture.
    pub q_down_mixture: Vec<f64>,
    /// `S x Z`: `<C_s>(<w_s> - <w>)`.
    pub relative_flux: Vec<f64>,
    /// `S x Z`: `d<C_s>/dz`.
    pub gradient: Vec<f64>,
    /// `S x Z`: `K`.
    pub diffusivity: Vec<f64>,
    /// `Z x Y`: streamwise position separating upstream from downstream bins.
    pub split_x: Vec<f64>,
    /// `Z x Y`: 1 where the split is a sign change of the axial velocity, 0 where `x = 0`.
    pub split_by_sign: Vec<u8>,
}

/// Values per axial slice in a record of [`slice_records`]: per species `<C_s>`, `<w_s>`,
/// `Q_up`, `Q_down`, `<C_s>(<w_s> - <w>)`; then `<w>`, `Q_up` and `Q_down` of the mixture;
/// then per depth row the split and whether it is a sign change (1 or 0).
pub fn record_len(ns: usize, ny: usize) -> usize {
    5 * ns + 3 + 2 * ny
}

/// The per-slice records of the axial slices this rank holds of the reduced sums
/// (`acc.own()`), one [`record_len`] run per slice in order: everything of a slice that
/// needs only its own bins. [`assemble`] puts every rank's records together.
pub fn slice_records(acc: &BinnedSums) -> Vec<f64> {
    let g = &acc.grid;
    let [nx, ny, nz] = g.n;
    let ns = acc.ns;
    let sc = acc.scales;
    let samples = acc.samples.max(1) as f64;
    let vol = |b: usize, s: usize| PI / 6.0 * unfix(acc.get(b, s, flux::VOLUME), sc.volume);
    let vol_w = |b: usize, s: usize| {
        PI / 6.0 * unfix(acc.get(b, s, flux::VOLUME_W), sc.volume * sc.velocity)
    };
    let bin = |ix: usize, iy: usize, iz: usize| (ix * ny + iy) * nz + iz;
    let xcs = g.centres(0);
    let to_rate = 1.0 / (samples * g.size[2] * PACKING);
    let len = record_len(ns, ny);
    let own = acc.own();
    let mut out = vec![0.0; own.len() * len];
    for (iz, rec) in own.zip(out.chunks_exact_mut(len)) {
        let (per_s, rest) = rec.split_at_mut(5 * ns);
        let (mix, rows) = rest.split_at_mut(3);
        let (split_x, by_sign) = rows.split_at_mut(ny);
        // per species: concentration, mean axial velocity, q_up, q_down, relative flux
        for s in 0..ns {
            per_s[5 * s] = f64::NAN;
            per_s[5 * s + 1] = f64::NAN;
            per_s[5 * s + 4] = f64::NAN;
        }
        mix[0] = f64::NAN;
        split_x.fill(f64::NAN);
        // cross-sectional sums
        let mut v_s = vec![0.0; ns];
        let mut vw_s = vec![0.0; ns];
        for ix in 0..nx {
            for iy in 0..ny {
                for s in 0..ns {
                    v_s[s] += vol(bin(ix, iy, iz), s);
                    vw_s[s] += vol_w(bin(ix, iy, iz), s);
                }
            }
        }
        let (v, vw): (f64, f64) = (v_s.iter().sum(), vw_s.iter().sum());
        if v > 0.0 {
            let w_mix = vw / v;
            mix[0] = w_mix;
            for s in 0..ns {
                let c = v_s[s] / v;
                per_s[5 * s] = c;
                if v_s[s] > 0.0 {
                    per_s[5 * s + 1] = vw_s[s] / v_s[s];
                }
                per_s[5 * s + 4] = (vw_s[s] - c * vw) / v;
            }
        }
        // upstream / downstream, row by row in depth
        for iy in 0..ny {
            let w_row: Vec<(f64, f64)> = (0..nx)
                .filter_map(|ix| {
                    let b = bin(ix, iy, iz);
                    let v: f64 = (0..ns).map(|s| vol(b, s)).sum();
                    (v > 0.0).then(|| (xcs[ix], (0..ns).map(|s| vol_w(b, s)).sum::<f64>() / v))
                })
                .collect();
            if w_row.is_empty() {
                continue;
            }
            let (split, sign) = split_row(&w_row);
            split_x[iy] = split;
            by_sign[iy] = if sign { 1.0 } else { 0.0 };
            for ix in 0..nx {
                let b = bin(ix, iy, iz);
                for s in 0..ns {
                    let q = vol_w(b, s) * to_rate;
                    if xcs[ix] < split {
                        per_s[5 * s + 2] += q;
                        mix[1] += q;
                    } else {
                        per_s[5 * s + 3] += q;
                        mix[2] += q;
                    }
                }
            }
        }
    }
    out
}

/// The window's slice diagnostics from the records of every axial slice in order
/// ([`slice_records`] of every rank, concatenated in rank order) of sums `acc` describes
/// (its grid, species and samples); `periodic` ends wrap the concentration gradient.
pub fn assemble(acc: &BinnedSums, records: &[f64], periodic: bool) -> SliceWindow {
    let g = &acc.grid;
    let [_, ny, nz] = g.n;
    let ns = acc.ns;
    let len = record_len(ns, ny);
    assert_eq!(records.len(), nz * len, "one record per axial slice");
    let mut out = SliceWindow {
        samples: acc.samples,
        concentration: vec![f64::NAN; ns * nz],
        mean_axial_velocity: vec![f64::NAN; ns * nz],
        mixture_axial_velocity: vec![f64::NAN; nz],
        q_up: vec![0.0; ns * nz],
        q_down: vec![0.0; ns * nz],
        q_up_mixture: vec![0.0; nz],
        q_down_mixture: vec![0.0; nz],
        relative_flux: vec![f64::NAN; ns * nz],
        gradient: vec![f64::NAN; ns * nz],
        diffusivity: vec![f64::NAN; ns * nz],
        split_x: vec![f64::NAN; nz * ny],
        split_by_sign: vec![0; nz * ny],
    };
    for (iz, rec) in records.chunks_exact(len).enumerate() {
        for s in 0..ns {
            let r = &rec[5 * s..5 * s + 5];
            out.concentration[s * nz + iz] = r[0];
            out.mean_axial_velocity[s * nz + iz] = r[1];
            out.q_up[s * nz + iz] = r[2];
            out.q_down[s * nz + iz] = r[3];
            out.relative_flux[s * nz + iz] = r[4];
        }
        let mix = &rec[5 * ns..5 * ns + 3];
        out.mixture_axial_velocity[iz] = mix[0];
        out.q_up_mixture[iz] = mix[1];
        out.q_down_mixture[iz] = mix[2];
        let rows = &rec[5 * ns + 3..];
        out.split_x[iz * ny..(iz + 1) * ny].copy_from_slice(&rows[..ny]);
        for (b, &x) in out.split_by_sign[iz * ny..(iz + 1) * ny]
            .iter_mut()
            .zip(&rows[ny..])
        {
            *b = x as u8;
        }
    }
    // gradient and diffusivity
    let dz = g.size[2];
    for s in 0..ns {
        let c = &out.concentration[s * nz..(s + 1) * nz];
        let grad: Vec<f64> = (0..nz).map(|k| gradient(c, k, dz, periodic)).collect();
        for k in 0..nz {
            out.gradient[s * nz + k] = grad[k];
            if grad[k] != 0.0 && grad[k].is_finite() {
                out.diffusivity[s * nz + k] = -out.relative_flux[s * nz + k] / grad[k];
            }
        }
    }
    out
}

/// Derive the window's slice diagnostics from sums held whole (one rank holding every
/// axial slice); `periodic` ends wrap the concentration gradient.
pub fn derive(acc: &BinnedSums, periodic: bool) -> SliceWindow {
    assert_eq!(acc.own(), 0..acc.grid.n[2], "the sums are not held whole");
    assemble(acc, &slice_records(acc), periodic)
}

/// Where a row of occupied bins `(x, w)` changes from upstream to downstream: the sign
/// change of `w` nearest `x = 0` (interpolated), or `x = 0` when `w` keeps its sign.
pub fn split_row(row: &[(f64, f64)]) -> (f64, bool) {
    let mut best: Option<f64> = None;
    for pair in row.windows(2) {
        let ((x1, w1), (x2, w2)) = (pair[0], pair[1]);
        if w1 * w2 < 0.0 {
            let x = x1 + w1 / (w1 - w2) * (x2 - x1);
            if best.is_none_or(|b| x.abs() < b.abs()) {
                best = Some(x);
            }
        }
    }
    match best {
        Some(x) => (x, true),
        None => (0.0, false),
    }
}

/// Central difference of `c` at slice `k` (one-sided at capped ends; wrapping when periodic).
fn gradient(c: &[f64], k: usize, dz: f64, periodic: bool) -> f64 {
    let n = c.len();
    if n < 2 {
        return f64::NAN;
    }
    let (lo, hi, span) = if periodic {
        ((k + n - 1) % n, (k + 1) % n, 2.0)
    } else if k == 0 {
        (0, 1, 1.0)
    } else if k == n - 1 {
        (n - 2, n - 1, 1.0)
    } else {
        (k - 1, k + 1, 2.0)
    };
    (c[hi] - c[lo]) / (span * dz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_is_the_sign_change_nearest_the_centre() {
        let row = [(-3.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (3.0, 1.0)];
        assert_eq!(split_row(&row), (0.0, true));
        let row = [(-3.0, 2.0), (-1.0, 1.0), (1.0, 1.0)];
        assert_eq!(split_row(&row), (0.0, false));
        let row = [(-3.0, 3.0), (-1.0, 1.0), (1.0, -3.0)];
        assert_eq!(split_row(&row), (-0.5, true));
    }

    #[test]
    fn gradient_wraps_only_when_periodic() {
        let c = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(gradient(&c, 0, 1.0, false), 1.0);
        assert_eq!(gradient(&c, 0, 1.0, true), -1.0);
        assert_eq!(gradient(&c, 2, 1.0, true), 1.0);
    }
}
