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

/// Derive the window's slice diagnostics from gathered sums; `periodic` ends wrap the
/// concentration gradient.
pub fn derive(acc: &BinnedSums, periodic: bool) -> SliceWindow {
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
    for iz in 0..nz {
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
            out.mixture_axial_velocity[iz] = w_mix;
            for s in 0..ns {
                let c = v_s[s] / v;
                out.concentration[s * nz + iz] = c;
                if v_s[s] > 0.0 {
                    out.mean_axial_velocity[s * nz + iz] = vw_s[s] / v_s[s];
                }
                out.relative_flux[s * nz + iz] = (vw_s[s] - c * vw) / v;
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
            let (split, by_sign) = split_row(&w_row);
            out.split_x[iz * ny + iy] = split;
            out.split_by_sign[iz * ny + iy] = by_sign as u8;
            for ix in 0..nx {
                let b = bin(ix, iy, iz);
                for s in 0..ns {
                    let q = vol_w(b, s) * to_rate;
                    if xcs[ix] < split {
                        out.q_up[s * nz + iz] += q;
                        out.q_up_mixture[iz] += q;
                    } else {
                        out.q_down[s * nz + iz] += q;
                        out.q_down_mixture[iz] += q;
                    }
                }
            }
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
