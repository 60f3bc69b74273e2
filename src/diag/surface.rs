//! The free surface: the dynamic angle of repose measured from the particles, and the
//! surface frame (thesis fig. 1.1) the binned diagnostics use.
//!
//! Each thin axial slice is cut into vertical columns one largest diameter wide; the highest
//! particle top (`y + d/2`) in a column is the free surface there. The maxima are reduced
//! over ranks (exact), then every rank fits the same lines: least squares over the columns
//! in the middle half of the occupied width, slope `tan theta`. The whole-drum angle shares
//! one slope between slices, each with its own height.

use crate::particles::Particles;
use crate::physics::rough_wall::is_fixed;

/// Column maxima of the free surface per axial slice.
#[derive(Debug, Clone)]
pub struct SurfaceGauge {
    nz: usize,
    z0: f64,
    dz: f64,
    ncol: usize,
    radius: f64,
    cw: f64,
    sign: f64,
}

/// Angles of repose of one sample, in degrees (NaN where a slice has too few columns).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceAngles {
    /// One per axial slice.
    pub slice: Vec<f64>,
    /// The whole drum.
    pub drum: f64,
}

impl SurfaceGauge {
    /// `nz` slices of width `dz` from `z0`, in a drum of `radius`, columns about `d_max`
    /// wide; `omega` sets which way the bed leans.
    pub fn new(nz: usize, z0: f64, dz: f64, radius: f64, d_max: f64, omega: f64) -> Self {
        let ncol = ((2.0 * radius / d_max).floor() as usize).max(8);
        SurfaceGauge {
            nz,
            z0,
            dz,
            ncol,
            radius,
            cw: 2.0 * radius / ncol as f64,
            sign: if omega < 0.0 { -1.0 } else { 1.0 },
        }
    }

    /// Number of values [`local_tops`](Self::local_tops) returns.
    pub fn len(&self) -> usize {
        self.nz * self.ncol
    }

    /// Whether the gauge has no columns.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Highest particle top per (slice, column) among this rank's particles (`-inf` where
    /// there is none); reduce with an element-wise maximum.
    pub fn local_tops(&self, p: &Particles) -> Vec<f64> {
        let mut tops = vec![f64::NEG_INFINITY; self.len()];
        for i in 0..p.n_owned {
            if is_fixed(p.species[i]) {
                continue;
            }
            let [x, y, z] = p.x[i];
            let k = clamp_index((z - self.z0) / self.dz, self.nz);
            let c = clamp_index((x + self.radius) / self.cw, self.ncol);
            let t = &mut tops[k * self.ncol + c];
            *t = t.max(y + 0.5 * p.diameter[i]);
        }
        tops
    }

    /// Fit the angles to reduced column maxima.
    pub fn angles(&self, tops: &[f64]) -> SurfaceAngles {
        let mut slice = vec![f64::NAN; self.nz];
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (k, a) in slice.iter_mut().enumerate() {
            let row = &tops[k * self.ncol..(k + 1) * self.ncol];
            if let Some((xy, xx)) = self.fit(row) {
                *a = (self.sign * xy / xx).atan().to_degrees();
                sxy += xy;
                sxx += xx;
            }
        }
        let drum = if sxx > 0.0 {
            (self.sign * sxy / sxx).atan().to_degrees()
        } else {
            f64::NAN
        };
        SurfaceAngles { slice, drum }
    }

    /// Centred sums `(Sxy, Sxx)` of the surface columns in the middle half of the occupied
    /// width, or `None` with fewer than three.
    fn fit(&self, row: &[f64]) -> Option<(f64, f64)> {
        let occupied: Vec<usize> = (0..row.len()).filter(|&c| row[c].is_finite()).collect();
        let (&lo, &hi) = (occupied.first()?, occupied.last()?);
        let span = (hi - lo) as f64;
        let pts: Vec<(f64, f64)> = occupied
            .iter()
            .filter(|&&c| {
                let f = (c - lo) as f64;
                f >= 0.25 * span && f <= 0.75 * span
            })
            .map(|&c| (-self.radius + (c as f64 + 0.5) * self.cw, row[c]))
            .collect();
        if pts.len() < 3 {
            return None;
        }
        let n = pts.len() as f64;
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
        let sxy = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let sxx = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
        Some((sxy, sxx))
    }
}

fn clamp_index(f: f64, n: usize) -> usize {
    if f > 0.0 {
        (f as usize).min(n - 1)
    } else {
        0
    }
}

/// The surface frame: `x` down the free surface, `y` normal to it out of the bed, `z` the
/// axis (see `docs/diagnostics.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Unit streamwise vector in the lab `(x, y)` plane.
    pub ex: [f64; 2],
    /// Unit surface normal in the lab `(x, y)` plane.
    pub ey: [f64; 2],
    /// The angle of repose it was built from, degrees.
    pub angle: f64,
}

impl Frame {
    /// The frame of a surface at `angle` degrees in a drum turning at `omega`.
    pub fn new(angle: f64, omega: f64) -> Self {
        let s = if omega < 0.0 { -1.0 } else { 1.0 };
        let (sin, cos) = angle.to_radians().sin_cos();
        Frame {
            ex: [-s * cos, -sin],
            ey: [-s * sin, cos],
            angle,
        }
    }

    /// Lab `(x, y)` components to surface-frame `(x, y)` components.
    #[inline]
    pub fn project(&self, a: f64, b: f64) -> (f64, f64) {
        (
            a * self.ex[0] + b * self.ex[1],
            a * self.ey[0] + b * self.ey[1],
        )
    }

    /// `+1` when `(x, y, z)` is right-handed (`omega < 0`), `-1` otherwise: in surface
    /// components, `omega z x r = handedness * omega * (-y, x)`.
    pub fn handedness(&self) -> f64 {
        self.ex[0] * self.ey[1] - self.ex[1] * self.ey[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_axes_are_orthonormal_and_x_points_downhill() {
        for omega in [1.0, -1.0] {
            let f = Frame::new(30.0, omega);
            let dot = f.ex[0] * f.ey[0] + f.ex[1] * f.ey[1];
            assert!(dot.abs() < 1e-15);
            // downhill: x goes down in the lab
            assert!(f.ex[1] < 0.0);
            assert!(f.ey[1] > 0.0);
            assert_eq!(f.handedness().round(), -omega);
        }
    }
}
