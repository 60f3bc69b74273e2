//! Binned fields of one window (thesis §2.2.3 and ch. 3): densities, volume fractions, mean
//! velocities in the lab and drum frames, velocity fluctuations, and from them the flowing
//! layer: the surface velocity `u0`, the free surface, the layer's lower boundary and depth.

use super::fixed::unfix;
use super::grid::{field, BinnedSums};
use std::f64::consts::PI;

/// Volume fraction above which a bin counts as part of the bed when finding the surface.
pub const SURFACE_FRACTION: f64 = 0.25;
/// The flowing layer is where the drum-frame streamwise velocity exceeds this share of `u0`.
pub const FLOWING_SHARE: f64 = 0.05;

/// The derived fields of one window; arrays are flat in C order over the shapes named.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldWindow {
    /// Samples averaged.
    pub samples: u64,
    /// Mean frame angle, degrees.
    pub angle: f64,
    /// `S x X x Y x Z`, particles per unit volume.
    pub number_density: Vec<f64>,
    /// `S x X x Y x Z`.
    pub volume_fraction: Vec<f64>,
    /// `3 x X x Y x Z`, mixture mean velocity, lab frame, surface-frame components.
    pub velocity: Vec<f64>,
    /// `3 x X x Y x Z`, the same in the drum frame.
    pub velocity_drum: Vec<f64>,
    /// `4 x X x Y x Z`: `u_rms, v_rms, w_rms` and their quadrature sum.
    pub rms: Vec<f64>,
    /// `S x X x Y x Z`, `n_s w_s`.
    pub axial_flux: Vec<f64>,
    /// Drum-frame streamwise surface velocity at the centre.
    pub u0: f64,
    /// `X x Z`, height of the free surface.
    pub surface: Vec<f64>,
    /// `X x Z`, lower edge of the flowing layer.
    pub boundary: Vec<f64>,
    /// `X x Z`, `surface - boundary`.
    pub depth: Vec<f64>,
}

/// Derive the fields from gathered sums over a drum turning at `omega`.
pub fn derive(acc: &BinnedSums, omega: f64) -> FieldWindow {
    let g = &acc.grid;
    let (nb, ns) = (g.bins(), acc.ns);
    let sc = acc.scales;
    let samples = acc.samples.max(1) as f64;
    let norm = 1.0 / (samples * g.bin_volume());
    let mut out = FieldWindow {
        samples: acc.samples,
        angle: acc.angle_sum / samples,
        number_density: vec![0.0; ns * nb],
        volume_fraction: vec![0.0; ns * nb],
        velocity: vec![f64::NAN; 3 * nb],
        velocity_drum: vec![f64::NAN; 3 * nb],
        rms: vec![f64::NAN; 4 * nb],
        axial_flux: vec![0.0; ns * nb],
        u0: f64::NAN,
        surface: vec![f64::NAN; g.n[0] * g.n[2]],
        boundary: vec![f64::NAN; g.n[0] * g.n[2]],
        depth: vec![f64::NAN; g.n[0] * g.n[2]],
    };
    let hand = super::surface::Frame::new(0.0, omega).handedness();
    for b in 0..nb {
        let mut tot = [0i128; 10];
        for s in 0..ns {
            for (q, t) in tot.iter_mut().enumerate() {
                *t += acc.get(b, s, q);
            }
            let n = acc.get(b, s, field::COUNT) as f64;
            out.number_density[s * nb + b] = n * norm;
            out.volume_fraction[s * nb + b] =
                PI / 6.0 * unfix(acc.get(b, s, field::VOLUME), sc.volume) * norm;
            out.axial_flux[s * nb + b] = unfix(acc.get(b, s, field::VEL + 2), sc.velocity) * norm;
        }
        let n = tot[field::COUNT] as f64;
        if n == 0.0 {
            continue;
        }
        let mean = |q: usize, scale: f64| unfix(tot[q], scale) / n;
        let (xm, ym) = (mean(field::X, sc.length), mean(field::Y, sc.length));
        let mut var_sum = 0.0;
        for k in 0..3 {
            let m = mean(field::VEL + k, sc.velocity);
            let m2 = mean(field::VEL2 + k, sc.velocity * sc.velocity);
            let var = (m2 - m * m).max(0.0);
            out.velocity_drum[k * nb + b] = m;
            out.rms[k * nb + b] = var.sqrt();
            var_sum += var;
        }
        out.rms[3 * nb + b] = var_sum.sqrt();
        // lab = drum + omega z x r; in surface components omega z x r = hand omega (-y, x)
        out.velocity[b] = out.velocity_drum[b] - hand * omega * ym;
        out.velocity[nb + b] = out.velocity_drum[nb + b] + hand * omega * xm;
        out.velocity[2 * nb + b] = out.velocity_drum[2 * nb + b];
    }
    flowing_layer(acc, &mut out);
    out
}

/// `u0`, the free surface, and the flowing layer's boundary and depth per `(x, z)` column.
fn flowing_layer(acc: &BinnedSums, out: &mut FieldWindow) {
    let g = &acc.grid;
    let [nx, ny, nz] = g.n;
    let nb = g.bins();
    let ycs = g.centres(1);
    let bin = |ix: usize, iy: usize, iz: usize| (ix * ny + iy) * nz + iz;
    let solid = |b: usize| -> f64 { (0..acc.ns).map(|s| out.volume_fraction[s * nb + b]).sum() };
    let u = |b: usize| out.velocity_drum[b];
    // the highest bed bin of each column
    let top = |ix: usize, iz: usize| {
        (0..ny)
            .rev()
            .find(|&iy| solid(bin(ix, iy, iz)) >= SURFACE_FRACTION)
    };
    let central = |n: usize| {
        if n.is_multiple_of(2) {
            vec![n / 2 - 1, n / 2]
        } else {
            vec![n / 2]
        }
    };
    let mut u0s = Vec::new();
    for &ix in &central(nx) {
        for &iz in &central(nz) {
            if let Some(t) = top(ix, iz) {
                let m = (0..=t)
                    .map(|iy| u(bin(ix, iy, iz)))
                    .filter(|v| v.is_finite())
                    .fold(f64::NEG_INFINITY, f64::max);
                if m.is_finite() {
                    u0s.push(m);
                }
            }
        }
    }
    if !u0s.is_empty() {
        out.u0 = u0s.iter().sum::<f64>() / u0s.len() as f64;
    }
    let threshold = FLOWING_SHARE * out.u0;
    for ix in 0..nx {
        for iz in 0..nz {
            let Some(t) = top(ix, iz) else { continue };
            let c = ix * nz + iz;
            out.surface[c] = ycs[t] + 0.5 * g.size[1];
            if out.u0.is_nan() || out.u0 <= 0.0 {
                continue;
            }
            // walk down from the surface bin while the column flows
            let mut above: Option<usize> = None;
            for iy in (0..=t).rev() {
                let v = u(bin(ix, iy, iz));
                if !v.is_finite() {
                    break;
                }
                if v < threshold {
                    if let Some(a) = above {
                        let va = u(bin(ix, a, iz));
                        out.boundary[c] = ycs[iy] + (threshold - v) / (va - v) * (ycs[a] - ycs[iy]);
                    }
                    break;
                }
                above = Some(iy);
            }
            out.depth[c] = out.surface[c] - out.boundary[c];
        }
    }
}
