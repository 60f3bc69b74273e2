//! A conical drum (a frustum): the wall's radius varies linearly along the axis, from
//! `r_low` at the cap `z = -L/2` to `r_high` at the cap `z = +L/2`; both ends are capped.
//!
//! In the half plane `(rho, z)` the wall is the line through `(r_low, -h)` and
//! `(r_high, h)`; its inward unit normal is `n = (-2h, r_high - r_low) / len`. A centre at
//! signed distance `s = (q - p0) . n` from it (positive inside) has the wall point
//! `q - s n` closest, and `r = s n` (turned out of the half plane) from there to the centre.

use super::cylinder::{caps, frustum_mesh, near_caps};
use super::{segment_area, DrumMesh, Touch, Vessel};
use crate::case::Drum;
use crate::physics::rapaport::V3;
use std::f64::consts::PI;

/// Sub-intervals of the Simpson rule for the volume below a height.
const FILL_INTERVALS: usize = 400;

/// A capped frustum along `z`.
#[derive(Debug, Clone, Copy)]
pub struct Cone {
    /// Radius at `z = -h`.
    pub r_low: f64,
    /// Radius at `z = +h`.
    pub r_high: f64,
    /// Half length `h = L/2`.
    pub half_length: f64,
    /// Radial component of the inward unit normal (negative).
    n_rho: f64,
    /// Axial component of the inward unit normal.
    n_z: f64,
}

impl Cone {
    /// A frustum of radii `r_low` at `z = -h`, `r_high` at `z = +h`.
    pub fn new(r_low: f64, r_high: f64, h: f64) -> Self {
        let len = (4.0 * h * h + (r_high - r_low).powi(2)).sqrt();
        Cone {
            r_low,
            r_high,
            half_length: h,
            n_rho: -2.0 * h / len,
            n_z: (r_high - r_low) / len,
        }
    }

    /// Radius of the wall at `z`.
    pub fn radius_at(&self, z: f64) -> f64 {
        self.r_low + (self.r_high - self.r_low) * (z + self.half_length) / (2.0 * self.half_length)
    }

    /// Signed distance of `(rho, z)` from the slanted wall, positive inside.
    pub fn depth(&self, rho: f64, z: f64) -> f64 {
        (rho - self.r_low) * self.n_rho + (z + self.half_length) * self.n_z
    }
}

/// Refusals of a cone's keys.
pub(super) fn check(drum: &Drum, out: &mut Vec<(String, String)>) {
    match drum.diameter_high {
        None => out.push((
            "drum.diameter_high".into(),
            "is required for a cone: the diameter at z = +L/2 (drum.diameter is at z = -L/2)"
                .into(),
        )),
        Some(d) if !(d > 0.0 && d <= drum.diameter) => out.push((
            "drum.diameter_high".into(),
            format!(
                "must be positive and at most drum.diameter ({}): the cone narrows from z = -L/2 \
                 to z = +L/2 (turn the case around for one that widens), got {d}",
                drum.diameter
            ),
        )),
        Some(_) => {}
    }
    match drum.length {
        None => out.push(("drum.length".into(), "is required for a cone".into())),
        Some(l) if l.is_nan() || l <= 0.0 => {
            out.push(("drum.length".into(), format!("must be positive, got {l}")))
        }
        Some(_) => {}
    }
    if drum.ends == Some(crate::case::Ends::Periodic) {
        out.push((
            "drum.ends".into(),
            "a cone is capped at both ends: periodic ends would join two different radii".into(),
        ));
    }
    if drum.rough_wall.is_some() {
        out.push((
            "drum.rough_wall".into(),
            "a rough wall lines a cylinder's curved wall; a cone has none".into(),
        ));
    }
}

impl Vessel for Cone {
    fn contacts(&self, x: V3, reach: f64) -> [Option<Touch>; 3] {
        let rho2 = x.x * x.x + x.y * x.y;
        let wall = if rho2 > 0.0 {
            let rho = rho2.sqrt();
            let s = self.depth(rho, x.z);
            (s < reach).then(|| {
                let (ux, uy) = (x.x / rho, x.y / rho);
                let (dr, dz) = (s * self.n_rho, s * self.n_z);
                let rho_w = rho - dr;
                Touch {
                    r: V3::new(dr * ux, dr * uy, dz),
                    at: V3::new(rho_w * ux, rho_w * uy, x.z - dz),
                }
            })
        } else {
            None
        };
        caps(x, reach, self.half_length, wall)
    }

    fn near(&self, x: [f64; 3], reach: f64) -> bool {
        let rho = (x[0] * x[0] + x[1] * x[1]).sqrt();
        self.depth(rho, x[2]) < reach || near_caps(x, reach, self.half_length)
    }

    fn inside(&self, x: [f64; 3], margin: f64) -> bool {
        let rho = (x[0] * x[0] + x[1] * x[1]).sqrt();
        self.depth(rho, x[2]) >= margin && x[2].abs() + margin <= self.half_length
    }

    fn volume(&self) -> f64 {
        let (a, b) = (self.r_low, self.r_high);
        PI * (2.0 * self.half_length) / 3.0 * (a * a + a * b + b * b)
    }

    fn fill_below(&self, h: f64) -> f64 {
        // Simpson's rule over z of the area below h of each circular section
        let (n, lo) = (FILL_INTERVALS, -self.half_length);
        let dz = 2.0 * self.half_length / n as f64;
        let mut sum = 0.0;
        for k in 0..=n {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += w * segment_area(self.radius_at(lo + k as f64 * dz), h);
        }
        (sum * dz / 3.0 / self.volume()).clamp(0.0, 1.0)
    }

    fn radius(&self) -> f64 {
        self.r_low.max(self.r_high)
    }

    fn half_length(&self) -> f64 {
        self.half_length
    }

    fn placement_cut(&self, room: f64, margin: f64, z: f64, jitter: f64) -> f64 {
        // the narrower end of the layer's range, moved in by the margin measured across the
        // slanted wall (1 / |n_rho| times the margin)
        let r = self.radius_at(z - jitter).min(self.radius_at(z + jitter));
        let here = (r + margin / self.n_rho).max(0.0);
        room * room - here * here
    }

    fn placement_half_length(&self, _room: f64, d_max: f64) -> f64 {
        self.half_length - 0.5 * d_max
    }

    fn placement_volume(&self, _room: f64, margin: f64) -> f64 {
        let shrink = -margin / self.n_rho;
        let (a, b) = (
            (self.r_low - shrink).max(0.0),
            (self.r_high - shrink).max(0.0),
        );
        PI * (2.0 * self.half_length) / 3.0 * (a * a + a * b + b * b)
    }

    fn mesh(&self, mesh: &mut DrumMesh) {
        frustum_mesh(mesh, self.r_low, self.r_high, self.half_length, true);
    }
}
