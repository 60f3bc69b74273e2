//! Per-species-pair and per-species-wall friction tables, built once from the case.
//!
//! Rapaport family: `gamma_s^{bs} = min(gamma_s^{bb}, gamma_s^{ss})`, and the `mu` values of
//! each family (particle-particle, particle-wall) in the ratio of the corresponding
//! `gamma_s`, the largest being `mu_max` (0.5); explicit `mu` / `mu_wall` override the rule.
//! Spring-dashpot family: each species' `mu`, `mu_wall` (default `mu`) and `mu_cap` (default
//! `mu_wall`); a mixed pair takes the smaller `mu`. Rolling friction (`mu_roll`, against the
//! walls `mu_roll_wall`, default `mu_roll`) mixes as `mu` does, by the smaller; cohesion
//! energy densities (`cohesion_energy`, `cohesion_energy_wall`) by the geometric mean
//! `sqrt(k_a k_b)` (the Berthelot rule for a work of adhesion; a pair of one species keeps
//! its value exactly). A frictionless cap has no friction, rolling friction or cohesion.

use super::rapaport::Friction;
use crate::case::{CapSurface, Case, Family};

/// The walls a particle can touch, each with its own friction and history slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wall {
    /// The curved cylinder wall, or the sphere.
    Curved = 0,
    /// The end cap at `z = -L/2`.
    CapLow = 1,
    /// The end cap at `z = +L/2`.
    CapHigh = 2,
    /// A lifter (one slot for all of a drum's lifters: a particle touches at most one, see
    /// `physics/walls/lifters.rs`), with the curved wall's friction.
    Lifter = 3,
}

/// Number of wall history slots per particle.
pub const WALLS: usize = 4;

/// Friction of every species pair and of every species against each wall.
#[derive(Debug, Clone)]
pub struct Materials {
    n: usize,
    pair: Vec<Friction>,
    wall: Vec<[Friction; WALLS]>,
    /// Material density (mass = density * pi/6 * d^3).
    pub density: f64,
}

impl Materials {
    /// Build the tables of `case`.
    pub fn new(case: &Case) -> Self {
        let sp = &case.species;
        let n = sp.len();
        let rapaport = case.model.family == Family::Rapaport;
        let g = |x: Option<f64>| x.unwrap_or(0.0);
        let g_max = sp.iter().map(|s| g(s.gamma_s)).fold(0.0, f64::max);
        let gw_max = sp.iter().map(|s| g(s.gamma_s_wall)).fold(0.0, f64::max);
        let ratio = |x: f64, max: f64| if max > 0.0 { x / max } else { 1.0 };
        let mu_self: Vec<f64> = sp
            .iter()
            .map(|s| match (s.mu, rapaport) {
                (Some(mu), _) => mu,
                (None, true) => case.model.mu_max * ratio(g(s.gamma_s), g_max),
                (None, false) => 0.0,
            })
            .collect();
        let mix = |ka: f64, kb: f64| if ka == kb { ka } else { (ka * kb).sqrt() };
        let mut pair = Vec::with_capacity(n * n);
        for a in 0..n {
            for b in 0..n {
                pair.push(Friction {
                    gamma_s: g(sp[a].gamma_s).min(g(sp[b].gamma_s)),
                    mu: mu_self[a].min(mu_self[b]),
                    mu_roll: g(sp[a].mu_roll).min(g(sp[b].mu_roll)),
                    cohesion: mix(g(sp[a].cohesion_energy), g(sp[b].cohesion_energy)),
                });
            }
        }
        let wall = sp
            .iter()
            .zip(&mu_self)
            .map(|(s, &mu)| {
                let mu_wall = match (s.mu_wall, rapaport) {
                    (Some(m), _) => m,
                    (None, true) => case.model.mu_max * ratio(g(s.gamma_s_wall), gw_max),
                    (None, false) => mu,
                };
                let curved = Friction {
                    gamma_s: g(s.gamma_s_wall),
                    mu: mu_wall,
                    mu_roll: s.mu_roll_wall.unwrap_or(g(s.mu_roll)),
                    cohesion: s.cohesion_energy_wall.unwrap_or(g(s.cohesion_energy)),
                };
                let cap = Friction {
                    mu: s.mu_cap.unwrap_or(mu_wall),
                    ..curved
                };
                let none = Friction::sliding(0.0, 0.0);
                let surface = |c: CapSurface| {
                    if c == CapSurface::Frictional {
                        cap
                    } else {
                        none
                    }
                };
                [
                    curved,
                    surface(case.drum.cap_low),
                    surface(case.drum.cap_high),
                    curved,
                ]
            })
            .collect();
        Materials {
            n,
            pair,
            wall,
            density: case.model.density,
        }
    }

    /// Friction between species `a` and `b` (a rough-wall particle counts as the curved wall).
    #[inline]
    pub fn pair(&self, a: u8, b: u8) -> Friction {
        use super::rough_wall::is_fixed;
        if is_fixed(b) {
            return self.wall(a, Wall::Curved);
        }
        if is_fixed(a) {
            return self.wall(b, Wall::Curved);
        }
        self.pair[a as usize * self.n + b as usize]
    }

    /// Friction between species `a` and wall `w`.
    #[inline]
    pub fn wall(&self, a: u8, w: Wall) -> Friction {
        self.wall[a as usize][w as usize]
    }

    /// Mass of a particle of diameter `d`.
    #[inline]
    pub fn mass(&self, d: f64) -> f64 {
        self.density * (std::f64::consts::PI / 6.0) * d * d * d
    }
}
