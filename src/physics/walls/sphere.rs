//! A spherical drum of radius `R` centred at the origin: one surface, in the curved wall's
//! slot.

use super::{DrumMesh, Touch, Vessel, DRUM_SEGMENTS, SPHERE_RINGS};
use crate::physics::rapaport::V3;
use std::f64::consts::PI;

/// A sphere of radius `radius`.
#[derive(Debug, Clone, Copy)]
pub struct Sphere {
    /// Radius `D/2`.
    pub radius: f64,
}

impl Vessel for Sphere {
    fn contacts(&self, x: V3, reach: f64) -> [Option<Touch>; 3] {
        let inner = self.radius - reach;
        let rho2 = x.norm_squared();
        let wall = (rho2 > 0.0 && (inner <= 0.0 || rho2 > inner * inner)).then(|| {
            let s = self.radius / rho2.sqrt();
            Touch {
                r: x * (1.0 - s),
                at: x * s,
            }
        });
        [wall, None, None]
    }

    fn near(&self, x: [f64; 3], reach: f64) -> bool {
        let inner = self.radius - reach;
        inner <= 0.0 || x[0] * x[0] + x[1] * x[1] + x[2] * x[2] > inner * inner
    }

    fn inside(&self, x: [f64; 3], margin: f64) -> bool {
        (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt() + margin <= self.radius
    }

    fn volume(&self) -> f64 {
        4.0 / 3.0 * PI * self.radius * self.radius * self.radius
    }

    fn fill_below(&self, h: f64) -> f64 {
        let radius = self.radius;
        let h = h.clamp(-radius, radius);
        let c = radius + h;
        PI * c * c * (3.0 * radius - c) / 3.0 / (4.0 / 3.0 * PI * radius.powi(3))
    }

    fn radius(&self) -> f64 {
        self.radius
    }

    fn half_length(&self) -> f64 {
        self.radius
    }

    fn placement_cut(&self, _room: f64, _margin: f64, z: f64, jitter: f64) -> f64 {
        (z.abs() + jitter).powi(2)
    }

    fn placement_half_length(&self, room: f64, _d_max: f64) -> f64 {
        room
    }

    fn placement_volume(&self, room: f64, _margin: f64) -> f64 {
        4.0 / 3.0 * PI * room.powi(3)
    }

    fn mesh(&self, mesh: &mut DrumMesh) {
        let (n, m, r) = (DRUM_SEGMENTS, SPHERE_RINGS, self.radius);
        let angle = |k: usize| 2.0 * PI * (k % n) as f64 / n as f64;
        let o = mesh.points.len();
        let (pts, tri) = (&mut mesh.points, &mut mesh.triangles);
        pts.push([0.0, 0.0, -r]);
        for i in 1..m {
            let polar = PI * i as f64 / m as f64;
            let (s, c) = (polar.sin(), polar.cos());
            for k in 0..n {
                pts.push([r * s * angle(k).cos(), r * s * angle(k).sin(), -r * c]);
            }
        }
        pts.push([0.0, 0.0, r]);
        let ring = |i: usize, k: usize| o + 1 + (i - 1) * n + k % n;
        let top = pts.len() - 1;
        for k in 0..n {
            tri.push([o, ring(1, k + 1), ring(1, k)]);
            tri.push([top, ring(m - 1, k), ring(m - 1, k + 1)]);
        }
        for i in 1..m - 1 {
            for k in 0..n {
                tri.push([ring(i, k), ring(i, k + 1), ring(i + 1, k + 1)]);
                tri.push([ring(i, k), ring(i + 1, k + 1), ring(i + 1, k)]);
            }
        }
    }
}
