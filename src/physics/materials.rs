//! Per-species-pair and per-species-wall friction tables, built once from the case with
//! Rapaport's rules: `gamma_s^{bs} = min(gamma_s^{bb}, gamma_s^{ss})`, and the `mu` values of
//! each family (particle-particle, particle-wall) in the ratio of the corresponding `gamma_s`,
//! the largest being `mu_max` (0.5). Explicit `mu` / `mu_wall` in the case override the rule.

use super::rapaport::Friction;
use crate::case::Case;

/// Friction of every species pair and of every species against the walls.
#[derive(Debug, Clone)]
pub struct Materials {
    n: usize,
    pair: Vec<Friction>,
    wall: Vec<Friction>,
    /// Normal damping coefficient, the same for all contacts.
    pub gamma_n: f64,
    /// Diameter attributed to the walls.
    pub wall_diameter: f64,
    /// Material density (mass = density * pi/6 * d^3).
    pub density: f64,
}

impl Materials {
    /// Build the tables of `case`.
    pub fn new(case: &Case) -> Self {
        let sp = &case.species;
        let n = sp.len();
        let g_max = sp.iter().map(|s| s.gamma_s).fold(0.0, f64::max);
        let gw_max = sp.iter().map(|s| s.gamma_s_wall).fold(0.0, f64::max);
        let ratio = |g: f64, gmax: f64| if gmax > 0.0 { g / gmax } else { 1.0 };
        let mu_self: Vec<f64> = sp
            .iter()
            .map(|s| s.mu.unwrap_or(case.model.mu_max * ratio(s.gamma_s, g_max)))
            .collect();
        let mut pair = Vec::with_capacity(n * n);
        for a in 0..n {
            for b in 0..n {
                pair.push(Friction {
                    gamma_s: sp[a].gamma_s.min(sp[b].gamma_s),
                    mu: mu_self[a].min(mu_self[b]),
                });
            }
        }
        let wall = sp
            .iter()
            .map(|s| Friction {
                gamma_s: s.gamma_s_wall,
                mu: s
                    .mu_wall
                    .unwrap_or(case.model.mu_max * ratio(s.gamma_s_wall, gw_max)),
            })
            .collect();
        Materials {
            n,
            pair,
            wall,
            gamma_n: case.model.gamma_n,
            wall_diameter: case.model.wall_diameter,
            density: case.model.density,
        }
    }

    /// Friction between species `a` and `b`.
    #[inline]
    pub fn pair(&self, a: u8, b: u8) -> Friction {
        self.pair[a as usize * self.n + b as usize]
    }

    /// Friction between species `a` and the walls.
    #[inline]
    pub fn wall(&self, a: u8) -> Friction {
        self.wall[a as usize]
    }

    /// Mass of a particle of diameter `d`.
    #[inline]
    pub fn mass(&self, d: f64) -> f64 {
        self.density * (std::f64::consts::PI / 6.0) * d * d * d
    }
}
