//! A cylinder along `z`: the curved wall of radius `R` and, unless the ends are periodic,
//! two flat end caps at `z = -L/2` and `z = +L/2`.

use super::{segment_area, DrumMesh, Touch, Vessel, DRUM_SEGMENTS};
use crate::physics::rapaport::V3;
use std::f64::consts::PI;

/// A cylinder of radius `radius` from `-half_length` to `half_length`, capped or periodic.
#[derive(Debug, Clone, Copy)]
pub struct Cylinder {
    /// Radius `D/2` of the curved wall.
    pub radius: f64,
    /// Half length `L/2`.
    pub half_length: f64,
    /// Whether the ends are capped (else periodic).
    pub capped: bool,
}

impl Vessel for Cylinder {
    fn contacts(&self, x: V3, reach: f64) -> [Option<Touch>; 3] {
        // Curved wall: r'_iw = (1 - R/rho) rho_vec, from the wall point to the centre (on
        // the axis itself the wall has no direction: only a drum narrower than the reach).
        let inner = self.radius - reach;
        let rho2 = x.x * x.x + x.y * x.y;
        let curved = (rho2 > 0.0 && (inner <= 0.0 || rho2 > inner * inner)).then(|| {
            let s = self.radius / rho2.sqrt();
            Touch {
                r: V3::new(x.x, x.y, 0.0) * (1.0 - s),
                at: V3::new(x.x * s, x.y * s, x.z),
            }
        });
        if !self.capped {
            return [curved, None, None];
        }
        caps(x, reach, self.half_length, curved)
    }

    fn near(&self, x: [f64; 3], reach: f64) -> bool {
        let inner = self.radius - reach;
        let rho2 = x[0] * x[0] + x[1] * x[1];
        let curved = inner <= 0.0 || rho2 > inner * inner;
        curved || (self.capped && near_caps(x, reach, self.half_length))
    }

    fn inside(&self, x: [f64; 3], margin: f64) -> bool {
        (x[0] * x[0] + x[1] * x[1]).sqrt() + margin <= self.radius
            && (!self.capped || x[2].abs() + margin <= self.half_length)
    }

    fn volume(&self) -> f64 {
        PI * self.radius * self.radius * (2.0 * self.half_length)
    }

    fn fill_below(&self, h: f64) -> f64 {
        let r = self.radius;
        segment_area(r, h) / (PI * r * r)
    }

    fn radius(&self) -> f64 {
        self.radius
    }

    fn half_length(&self) -> f64 {
        self.half_length
    }

    fn placement_cut(&self, _room: f64, _margin: f64, _z: f64, _jitter: f64) -> f64 {
        0.0
    }

    fn placement_half_length(&self, _room: f64, d_max: f64) -> f64 {
        self.half_length - 0.5 * d_max
    }

    fn placement_volume(&self, room: f64, _margin: f64) -> f64 {
        PI * room * room * (2.0 * self.half_length)
    }

    fn mesh(&self, mesh: &mut DrumMesh) {
        frustum_mesh(
            mesh,
            self.radius,
            self.radius,
            self.half_length,
            self.capped,
        );
    }
}

/// The end caps' contacts (at `-h`, then at `+h`) after the curved wall's.
pub(super) fn caps(x: V3, reach: f64, h: f64, curved: Option<Touch>) -> [Option<Touch>; 3] {
    let h_low = x.z + h;
    let low = (h_low < reach).then(|| Touch {
        r: V3::new(0.0, 0.0, h_low),
        at: V3::new(x.x, x.y, -h),
    });
    let h_high = h - x.z;
    let high = (h_high < reach).then(|| Touch {
        r: V3::new(0.0, 0.0, -h_high),
        at: V3::new(x.x, x.y, h),
    });
    [curved, low, high]
}

/// Whether `x` is within `reach` of an end cap at `-h` or `+h`.
pub(super) fn near_caps(x: [f64; 3], reach: f64, h: f64) -> bool {
    x[2] + h < reach || h - x[2] < reach
}

/// A frustum's mesh: the curved wall from radius `r_low` at `z = -h` to `r_high` at `+h`,
/// and its end discs when `capped`.
pub(super) fn frustum_mesh(mesh: &mut DrumMesh, r_low: f64, r_high: f64, h: f64, capped: bool) {
    let n = DRUM_SEGMENTS;
    let angle = |k: usize| 2.0 * PI * (k % n) as f64 / n as f64;
    let o = mesh.points.len();
    for (z, r) in [(-h, r_low), (h, r_high)] {
        for k in 0..n {
            mesh.points
                .push([r * angle(k).cos(), r * angle(k).sin(), z]);
        }
    }
    for k in 0..n {
        let (a, b) = (o + k, o + (k + 1) % n);
        mesh.triangles.push([a, b, n + b]);
        mesh.triangles.push([a, n + b, n + a]);
    }
    if capped {
        let (lo, hi) = (mesh.points.len(), mesh.points.len() + 1);
        mesh.points.push([0.0, 0.0, -h]);
        mesh.points.push([0.0, 0.0, h]);
        for k in 0..n {
            let (a, b) = (o + k, o + (k + 1) % n);
            mesh.triangles.push([lo, b, a]);
            mesh.triangles.push([hi, n + a, n + b]);
        }
    }
}
