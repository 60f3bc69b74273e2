//! The drum's walls as analytic surfaces turning with the drum: the curved cylinder wall and,
//! for capped drums, the two flat end caps (Rapaport section III, rotated to our frame: axis
//! `z`, rotation `omega` about `+z`, so the wall moves with `omega z x r`).

use super::rapaport::{self, Friction, V3};

/// Geometry and motion of the drum's walls.
#[derive(Debug, Clone, Copy)]
pub struct DrumWalls {
    /// Radius `D/2` of the curved wall.
    pub radius: f64,
    /// Half length `L/2`; the caps (if any) are at `z = -L/2` and `z = +L/2`.
    pub half_length: f64,
    /// Whether the ends are capped (otherwise periodic).
    pub capped: bool,
    /// Angular velocity of the drum about `+z`.
    pub omega: f64,
    /// Diameter attributed to the walls.
    pub wall_diameter: f64,
    /// Normal damping coefficient.
    pub gamma_n: f64,
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
    /// Sum of the wall forces on a particle at `x` with velocity `v`, spin `w`, diameter `d`
    /// and wall friction `fr`; curved wall first, then the cap at `-L/2`, then at `+L/2`.
    #[inline]
    pub fn load(&self, x: V3, v: V3, w: V3, d: f64, fr: Friction) -> WallLoad {
        let d_iw = 0.5 * (d + self.wall_diameter);
        let reach = rapaport::cutoff(d_iw);
        let mut out = WallLoad {
            force: V3::zeros(),
            torque: V3::zeros(),
        };
        let mut add = |c: Option<rapaport::Contact>| {
            if let Some(c) = c {
                out.force += c.force;
                out.torque -= c.n_cross_fs * (0.5 * d);
            }
        };

        // Curved wall: r'_iw = (1 - R/rho) rho_vec, from the wall point to the centre.
        let rho2 = x.x * x.x + x.y * x.y;
        let inner = self.radius - reach;
        if inner <= 0.0 || rho2 > inner * inner {
            let rho = rho2.sqrt();
            if rho > 0.0 {
                let radial = V3::new(x.x, x.y, 0.0);
                let r = radial * (1.0 - self.radius / rho);
                let s = self.radius / rho;
                let v_wall = V3::new(-x.y * s, x.x * s, 0.0) * self.omega;
                add(rapaport::wall(r, v, w, v_wall, d_iw, self.gamma_n, fr));
            }
        }

        if self.capped {
            let v_wall = V3::new(-x.y, x.x, 0.0) * self.omega;
            let h_low = x.z + self.half_length;
            if h_low < reach {
                add(rapaport::wall(
                    V3::new(0.0, 0.0, h_low),
                    v,
                    w,
                    v_wall,
                    d_iw,
                    self.gamma_n,
                    fr,
                ));
            }
            let h_high = self.half_length - x.z;
            if h_high < reach {
                add(rapaport::wall(
                    V3::new(0.0, 0.0, -h_high),
                    v,
                    w,
                    v_wall,
                    d_iw,
                    self.gamma_n,
                    fr,
                ));
            }
        }
        out
    }
}
