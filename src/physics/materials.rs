//! Per-species-pair and per-species-wall contact coefficients, built once from the case.
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
//!
//! Normal coefficients (spring-dashpot family). Linear law: each species' `restitution`
//! (default `model.restitution`) and `restitution_wall` (default `restitution`); a mixed
//! pair takes the geometric mean `sqrt(e_a e_b)` (one species keeps its value exactly).
//! `t_c` is the model's for every pair, so each pair has `gamma_n = -ln(e_n)/t_c` and
//! `k0 = (pi/t_c)^2 + gamma_n^2` ([`linear_coefficients`]) and lasts exactly `t_c`. Hertz:
//! each species' `youngs_modulus` and `poisson_ratio` (default the model's); a pair has
//! `kh = 4 Y*/3` with the effective modulus `1/Y* = (1 - nu_a^2)/Y_a + (1 - nu_b^2)/Y_b` (as
//! LAMMPS and LIGGGHTS), which for one material is `2 Y / (3 (1 - nu^2))`, computed so
//! ([`hertz_kh`]); against a wall, the wall is of the species' material. The Hertz damping
//! `gamma_h` is the model's.
//!
//! A `[[pairs]]` table of the case overrides the rule for one unordered pair: its `mu`,
//! `mu_roll`, `cohesion_energy` and (linear) `restitution` replace the mixed values.

use super::rapaport::Friction;
use crate::case::{CapSurface, Case, Family, Normal};
use std::f64::consts::PI;

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

/// Contact coefficients of every species pair and of every species against each wall.
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
        let m = &case.model;
        // the normal coefficients of a pair of species, or of a species and a wall (`b` =
        // `None`); `e` overrides the pair's mixed restitution
        let normal = |a: usize, b: Option<usize>, e: Option<f64>| -> (f64, f64) {
            if rapaport {
                return (0.0, 0.0);
            }
            match m.normal {
                Normal::Linear => {
                    let e_self = |s: usize| sp[s].restitution.or(m.restitution).unwrap_or(1.0);
                    let e = e.unwrap_or_else(|| match b {
                        Some(b) => mix(e_self(a), e_self(b)),
                        None => sp[a].restitution_wall.unwrap_or(e_self(a)),
                    });
                    linear_coefficients(e, m.collision_time.unwrap_or(1.0))
                }
                Normal::Hertz => {
                    let y = |s: usize| sp[s].youngs_modulus.or(m.youngs_modulus).unwrap_or(0.0);
                    let nu = |s: usize| sp[s].poisson_ratio.or(m.poisson_ratio).unwrap_or(0.0);
                    let b = b.unwrap_or(a);
                    (
                        hertz_kh(y(a), nu(a), y(b), nu(b)),
                        m.hertz_damping.unwrap_or(0.0),
                    )
                }
            }
        };
        let mut pair = Vec::with_capacity(n * n);
        for a in 0..n {
            for b in 0..n {
                let (normal_k, normal_c) = normal(a, Some(b), None);
                pair.push(Friction {
                    gamma_s: g(sp[a].gamma_s).min(g(sp[b].gamma_s)),
                    mu: mu_self[a].min(mu_self[b]),
                    mu_roll: g(sp[a].mu_roll).min(g(sp[b].mu_roll)),
                    cohesion: mix(g(sp[a].cohesion_energy), g(sp[b].cohesion_energy)),
                    normal_k,
                    normal_c,
                });
            }
        }
        for o in &case.pairs {
            let index = |name: &str| sp.iter().position(|s| s.name == name);
            let (Some(a), Some(b)) = (
                o.species.first().and_then(|s| index(s)),
                o.species.get(1).and_then(|s| index(s)),
            ) else {
                continue; // refused by the validation
            };
            let mut fr = pair[a * n + b];
            fr.mu = o.mu.unwrap_or(fr.mu);
            fr.mu_roll = o.mu_roll.unwrap_or(fr.mu_roll);
            fr.cohesion = o.cohesion_energy.unwrap_or(fr.cohesion);
            if o.restitution.is_some() {
                (fr.normal_k, fr.normal_c) = normal(a, Some(b), o.restitution);
            }
            pair[a * n + b] = fr;
            pair[b * n + a] = fr;
        }
        let wall = sp
            .iter()
            .zip(&mu_self)
            .enumerate()
            .map(|(k, (s, &mu))| {
                let (normal_k, normal_c) = normal(k, None, None);
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
                    normal_k,
                    normal_c,
                };
                let cap = Friction {
                    mu: s.mu_cap.unwrap_or(mu_wall),
                    ..curved
                };
                // no friction, but the normal force of the wall
                let none = Friction {
                    normal_k,
                    normal_c,
                    ..Friction::sliding(0.0, 0.0)
                };
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

    /// Whether every pair and wall has the normal coefficients `(k, c)` (bit for bit): the
    /// law may then keep them as constants.
    pub fn normal_uniform(&self, k: f64, c: f64) -> bool {
        let same = |f: &Friction| {
            f.normal_k.to_bits() == k.to_bits() && f.normal_c.to_bits() == c.to_bits()
        };
        self.pair.iter().all(same) && self.wall.iter().flatten().all(same)
    }

    /// Coefficients of species `a` and `b` (a rough-wall particle counts as the curved wall).
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

    /// Coefficients of species `a` against wall `w`.
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

/// The linear law's `(k0, 2 gamma_n)` for restitution `e` and collision time `tc`:
/// `gamma_n = -ln(e)/t_c`, `k0 = (pi/t_c)^2 + gamma_n^2`.
pub fn linear_coefficients(e: f64, tc: f64) -> (f64, f64) {
    let gamma = -e.ln() / tc;
    ((PI / tc) * (PI / tc) + gamma * gamma, 2.0 * gamma)
}

/// Hertz's `kh = 4 Y*/3` of two materials, `1/Y* = (1 - nu_a^2)/Y_a + (1 - nu_b^2)/Y_b`; for
/// one material (`Y_a = Y_b`, `nu_a = nu_b`) `2 Y / (3 (1 - nu^2))`, computed so.
pub fn hertz_kh(y_a: f64, nu_a: f64, y_b: f64, nu_b: f64) -> f64 {
    if y_a == y_b && nu_a == nu_b {
        2.0 * y_a / (3.0 * (1.0 - nu_a * nu_a))
    } else {
        4.0 / (3.0 * ((1.0 - nu_a * nu_a) / y_a + (1.0 - nu_b * nu_b) / y_b))
    }
}

/// The effective modulus `Y*` of two materials (`Y / (2 (1 - nu^2))` for one), for the
/// Hertz contact time.
pub fn effective_modulus(y_a: f64, nu_a: f64, y_b: f64, nu_b: f64) -> f64 {
    if y_a == y_b && nu_a == nu_b {
        y_a / (2.0 * (1.0 - nu_a * nu_a))
    } else {
        1.0 / ((1.0 - nu_a * nu_a) / y_a + (1.0 - nu_b * nu_b) / y_b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::normal::NormalLaw;
    use crate::physics::ContactLaw;

    const SD_CAPPED: &str = include_str!("../../tests/cases/sd_capped.toml");

    /// `sd_capped.toml` (species `small`, `large`; `t_c` = 1 ms, `e_n` = 0.9) with `extra`
    /// TOML appended and `overrides` applied.
    fn case(extra: &str, overrides: &[&str]) -> Case {
        let ov: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        crate::case::load_text(&(SD_CAPPED.to_string() + extra), &ov, "t.toml")
            .unwrap()
            .case
    }

    fn normal(fr: Friction) -> (f64, f64) {
        (fr.normal_k, fr.normal_c)
    }

    #[test]
    fn linear_restitution_mixes_by_the_geometric_mean_and_one_species_keeps_its_own() {
        let c = case(
            "",
            &[
                "species.0.restitution=0.7",
                "species.1.restitution_wall=0.6",
            ],
        );
        let m = Materials::new(&c);
        let tc = 1.0e-3;
        assert_eq!(normal(m.pair(0, 0)), linear_coefficients(0.7, tc));
        // the other species keeps the model's value, bit for bit the model's law
        assert_eq!(normal(m.pair(1, 1)), linear_coefficients(0.9, tc));
        let mixed = linear_coefficients((0.7f64 * 0.9).sqrt(), tc);
        assert_eq!(normal(m.pair(0, 1)), mixed);
        assert_eq!(normal(m.pair(1, 0)), mixed);
        // walls: restitution_wall, by default the species' restitution; a frictionless cap
        // (cap_high) has no friction but the wall's normal force
        assert_eq!(
            normal(m.wall(0, Wall::Curved)),
            linear_coefficients(0.7, tc)
        );
        assert_eq!(
            normal(m.wall(1, Wall::Curved)),
            linear_coefficients(0.6, tc)
        );
        assert_eq!(
            normal(m.wall(1, Wall::CapHigh)),
            linear_coefficients(0.6, tc)
        );
        assert_eq!(m.wall(1, Wall::CapHigh).mu, 0.0);
        // every pair lasts t_c: (pi/t_c)^2 = k0 - gamma^2
        let (k0, two_gamma) = mixed;
        let w = (k0 - 0.25 * two_gamma * two_gamma).sqrt();
        assert!((w * tc / std::f64::consts::PI - 1.0).abs() < 1e-12);
        assert_eq!(ContactLaw::new(&c).history_words(), 3);
        assert_eq!(ContactLaw::new(&c).normal, NormalLaw::LinearPairs);
    }

    #[test]
    fn uniform_coefficients_keep_the_model_law_and_its_constants() {
        for ov in [
            &[][..],
            &[
                "species.0.restitution=0.9",
                "species.1.restitution_wall=0.9",
            ],
        ] {
            let c = case("", ov);
            let (k0, two_gamma) = linear_coefficients(0.9, 1.0e-3);
            assert!(Materials::new(&c).normal_uniform(k0, two_gamma));
            let sd = ContactLaw::new(&c);
            assert_eq!(sd.normal, NormalLaw::Linear { k0, two_gamma });
        }
    }

    #[test]
    fn a_pair_override_wins_over_the_rule_for_the_unordered_pair_only() {
        let c = case(
            "[[pairs]]\nspecies = [\"large\", \"small\"]\nmu = 0.2\nrestitution = 0.5\n",
            &["species.0.restitution=0.7"],
        );
        let m = Materials::new(&c);
        for (a, b) in [(0, 1), (1, 0)] {
            assert_eq!(m.pair(a, b).mu, 0.2);
            assert_eq!(normal(m.pair(a, b)), linear_coefficients(0.5, 1.0e-3));
        }
        assert_eq!(m.pair(0, 0).mu, 0.5);
        assert_eq!(normal(m.pair(0, 0)), linear_coefficients(0.7, 1.0e-3));
        assert_eq!(normal(m.pair(1, 1)), linear_coefficients(0.9, 1.0e-3));
        assert_eq!(
            normal(m.wall(1, Wall::Curved)),
            linear_coefficients(0.9, 1.0e-3)
        );
        // rolling friction and cohesion likewise
        let c = case(
            "[[pairs]]\nspecies = [\"small\", \"small\"]\nmu_roll = 0.05\ncohesion_energy = 7.0\n",
            &[
                "model.rolling=\"sds\"",
                "model.cohesion=\"sjkr\"",
                "species.0.mu_roll=0.1",
                "species.1.mu_roll=0.2",
                "species.0.cohesion_energy=100.0",
                "species.1.cohesion_energy=400.0",
            ],
        );
        let m = Materials::new(&c);
        assert_eq!((m.pair(0, 0).mu_roll, m.pair(0, 0).cohesion), (0.05, 7.0));
        assert_eq!((m.pair(0, 1).mu_roll, m.pair(0, 1).cohesion), (0.1, 200.0));
        assert_eq!((m.pair(1, 1).mu_roll, m.pair(1, 1).cohesion), (0.2, 400.0));
        assert_eq!(m.wall(0, Wall::Curved).mu_roll, 0.1);
    }

    #[test]
    fn hertz_moduli_mix_to_the_effective_modulus_and_one_material_keeps_todays_kh() {
        let hertz = [
            "model.normal=\"hertz\"",
            "model.youngs_modulus=1.0e7",
            "model.poisson_ratio=0.3",
            "model.hertz_damping=0.01",
            "run.dt=2e-6",
        ];
        let c = case("", &hertz);
        let m = Materials::new(&c);
        let kh = 2.0 * 1.0e7 / (3.0 * (1.0 - 0.3 * 0.3));
        assert!(m.normal_uniform(kh, 0.01));
        let sd = ContactLaw::new(&c);
        assert_eq!(sd.normal, NormalLaw::Hertz { kh, gamma_h: 0.01 });
        let mut ov = hertz.to_vec();
        ov.extend([
            "species.1.youngs_modulus=4.0e7",
            "species.1.poisson_ratio=0.25",
        ]);
        let c = case("", &ov);
        let m = Materials::new(&c);
        assert_eq!(normal(m.pair(0, 0)), (kh, 0.01));
        let kh1 = 2.0 * 4.0e7 / (3.0 * (1.0 - 0.25 * 0.25));
        assert_eq!(normal(m.pair(1, 1)), (kh1, 0.01));
        assert_eq!(normal(m.wall(1, Wall::CapLow)), (kh1, 0.01));
        let e_star = 1.0 / ((1.0 - 0.09) / 1.0e7 + (1.0 - 0.0625) / 4.0e7);
        let mixed = m.pair(0, 1).normal_k;
        assert!((mixed / (4.0 / 3.0 * e_star) - 1.0).abs() < 1e-14);
        assert_eq!(mixed, m.pair(1, 0).normal_k);
        // between the two materials' values
        assert!(kh < mixed && mixed < kh1);
        let sd = ContactLaw::new(&c);
        assert_eq!(sd.normal, NormalLaw::HertzPairs);
        // the stiffer material shortens the shortest contact
        let t = |c: &Case| crate::physics::law::step_limits(c).contact_time_min;
        assert!(t(&c) < t(&case("", &hertz)));
    }
}
