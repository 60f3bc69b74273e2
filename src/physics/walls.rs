//! The drum's walls as analytic surfaces turning with the drum: the curved cylinder wall and,
//! for capped drums, the two flat end caps; or a sphere. The wall moves with `omega z x r` at
//! the contact point (axis `z`, rotation about `+z`).

use super::contact::Body;
use super::law::ContactLaw;
use super::materials::{Materials, Wall, WALLS};
use super::rapaport::V3;

/// Geometry and motion of the drum's walls.
#[derive(Debug, Clone, Copy)]
pub struct DrumWalls {
    /// Radius `D/2` of the curved wall or sphere.
    pub radius: f64,
    /// Half length `L/2`; the caps (if any) are at `z = -L/2` and `z = +L/2`.
    pub half_length: f64,
    /// Whether the ends are capped (cylinder).
    pub capped: bool,
    /// Whether the drum is a sphere.
    pub sphere: bool,
    /// Angular velocity of the drum about `+z`.
    pub omega: f64,
}

/// Force and torque that the walls exert on one particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallLoad {
    /// Total force.
    pub force: V3,
    /// Total torque about the particle centre.
    pub torque: V3,
}

impl DrumWalls {
    /// Whether a particle centred at `x` is within `reach` of a wall (where [`Self::load`]
    /// may find a contact for a particle of that reach or less).
    pub fn near(&self, x: [f64; 3], reach: f64) -> bool {
        let inner = self.radius - reach;
        let rho2 = if self.sphere {
            x[0] * x[0] + x[1] * x[1] + x[2] * x[2]
        } else {
            x[0] * x[0] + x[1] * x[1]
        };
        let curved = inner <= 0.0 || rho2 > inner * inner;
        let caps = self.capped
            && !self.sphere
            && (x[2] + self.half_length < reach || self.half_length - x[2] < reach);
        curved || caps
    }

    /// Sum of the wall forces on a particle at `x` (curved wall or sphere first, then the cap
    /// at `-L/2`, then at `+L/2`), updating its wall histories `hist` ([`WALLS`] slots of
    /// the law's history words, one after the other).
    #[inline]
    pub fn load(
        &self,
        law: &ContactLaw,
        mat: &Materials,
        species: u8,
        x: V3,
        body: &Body,
        hist: &mut [f64],
    ) -> WallLoad {
        let reach = law.wall_reach(body.d);
        let mut out = WallLoad {
            force: V3::zeros(),
            torque: V3::zeros(),
        };
        let words = hist.len() / WALLS;
        let (h0, rest) = hist.split_at_mut(words);
        let (h1, h2) = rest.split_at_mut(words);
        let w_wall = V3::new(0.0, 0.0, self.omega);
        let rolling = law.has_rolling();
        let mut touch = |wall: Wall, r: V3, v_wall: V3, hist: &mut [f64]| {
            if let Some(c) = law.wall(r, body, v_wall, w_wall, mat.wall(species, wall), hist) {
                out.force += c.force;
                out.torque -= c.n_cross_fs * (0.5 * body.d);
                if rolling {
                    out.torque += c.torque_roll;
                }
            }
        };

        let inner = self.radius - reach;
        if self.sphere {
            let rho2 = x.norm_squared();
            if rho2 > 0.0 && (inner <= 0.0 || rho2 > inner * inner) {
                let rho = rho2.sqrt();
                let s = self.radius / rho;
                let v_wall = V3::new(-x.y * s, x.x * s, 0.0) * self.omega;
                touch(Wall::Curved, x * (1.0 - s), v_wall, h0);
            } else {
                h0.fill(0.0);
            }
            return out;
        }

        // Curved wall: r'_iw = (1 - R/rho) rho_vec, from the wall point to the centre (on
        // the axis itself the wall has no direction: only a drum narrower than the reach).
        let rho2 = x.x * x.x + x.y * x.y;
        if rho2 > 0.0 && (inner <= 0.0 || rho2 > inner * inner) {
            let rho = rho2.sqrt();
            let s = self.radius / rho;
            let radial = V3::new(x.x, x.y, 0.0);
            let v_wall = V3::new(-x.y * s, x.x * s, 0.0) * self.omega;
            touch(Wall::Curved, radial * (1.0 - s), v_wall, h0);
        } else {
            h0.fill(0.0);
        }

        if self.capped {
            let v_wall = V3::new(-x.y, x.x, 0.0) * self.omega;
            let h_low = x.z + self.half_length;
            if h_low < reach {
                touch(Wall::CapLow, V3::new(0.0, 0.0, h_low), v_wall, h1);
            } else {
                h1.fill(0.0);
            }
            let h_high = self.half_length - x.z;
            if h_high < reach {
                touch(Wall::CapHigh, V3::new(0.0, 0.0, -h_high), v_wall, h2);
            } else {
                h2.fill(0.0);
            }
        }
        out
    }
}
