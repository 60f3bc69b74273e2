//! The contact law of a run, chosen once from the case: an enum dispatched per contact,
//! never a trait object in the inner loop.

use super::cohesion::CohesionLaw;
use super::contact::{Body, Contact};
use super::materials::{effective_modulus, hertz_kh, linear_coefficients, Materials};
use super::rapaport::{self, Friction, V3};
use super::rolling::RollingLaw;
use super::spring_dashpot::{NormalLaw, SpringDashpot, TangentialLaw};
use crate::case::{Case, Family, Normal, Rolling, Tangential};
use std::f64::consts::PI;

/// Fewest steps per binary contact accepted by the time-step check.
pub const STEPS_PER_CONTACT_MIN: f64 = 5.0;

/// A run's contact law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLaw {
    /// Rapaport (2002) section III.
    Rapaport {
        /// Normal damping coefficient.
        gamma_n: f64,
        /// Diameter attributed to the walls.
        wall_diameter: f64,
    },
    /// The thesis' spring-dashpot laws.
    SpringDashpot(SpringDashpot),
}

impl ContactLaw {
    /// The law of `case`.
    pub fn new(case: &Case) -> Self {
        let m = &case.model;
        match m.family {
            Family::Rapaport => ContactLaw::Rapaport {
                gamma_n: m.gamma_n.unwrap_or(0.0),
                wall_diameter: m.wall_diameter,
            },
            Family::SpringDashpot => {
                let e = m.restitution.unwrap_or(1.0);
                // the model's coefficients; a law whose pairs differ reads each pair's
                let mat = Materials::new(case);
                let normal = match m.normal {
                    Normal::Linear => {
                        let (k0, two_gamma) =
                            linear_coefficients(e, m.collision_time.unwrap_or(1.0));
                        if mat.normal_uniform(k0, two_gamma) {
                            NormalLaw::Linear { k0, two_gamma }
                        } else {
                            NormalLaw::LinearPairs
                        }
                    }
                    Normal::Hertz => {
                        let (y, nu) = (
                            m.youngs_modulus.unwrap_or(0.0),
                            m.poisson_ratio.unwrap_or(0.0),
                        );
                        let kh = hertz_kh(y, nu, y, nu);
                        let gamma_h = m.hertz_damping.unwrap_or(0.0);
                        if mat.normal_uniform(kh, gamma_h) {
                            NormalLaw::Hertz { kh, gamma_h }
                        } else {
                            NormalLaw::HertzPairs
                        }
                    }
                };
                let tangential = match m.tangential {
                    Tangential::Viscous => TangentialLaw::Viscous { gamma_s: m.gamma_s },
                    Tangential::History => TangentialLaw::History {
                        ratio: m.stiffness_ratio,
                        dt: case.dt(),
                    },
                };
                let rolling = RollingLaw::of(case);
                let cohesion = CohesionLaw::of(case);
                ContactLaw::SpringDashpot(SpringDashpot {
                    normal,
                    tangential,
                    rolling,
                    cohesion,
                })
            }
        }
    }

    /// The same law with time standing still: a tangential history is turned into the
    /// tangent plane and cut back, but not advanced by the sliding of a step.
    pub fn frozen(&self) -> Self {
        match *self {
            ContactLaw::SpringDashpot(mut sd) => {
                if let TangentialLaw::History { dt, .. } = &mut sd.tangential {
                    *dt = 0.0;
                }
                sd.rolling = sd.rolling.frozen();
                ContactLaw::SpringDashpot(sd)
            }
            other => other,
        }
    }

    /// Whether contacts carry a history.
    pub fn has_history(&self) -> bool {
        self.history_words() > 0
    }

    /// Whether contacts exert a rolling-resistance torque.
    pub fn has_rolling(&self) -> bool {
        matches!(self, ContactLaw::SpringDashpot(sd) if sd.rolling != RollingLaw::None)
    }

    /// Words of history per contact (pair or wall): the tangential spring's, then the
    /// rolling spring's; at most [`super::contact::HISTORY_MAX`].
    pub fn history_words(&self) -> usize {
        match self {
            ContactLaw::Rapaport { .. } => 0,
            ContactLaw::SpringDashpot(sd) => sd.history_words(),
        }
    }

    /// Centre distance below which two particles interact.
    #[inline]
    pub fn cutoff(&self, d_a: f64, d_b: f64) -> f64 {
        match self {
            ContactLaw::Rapaport { .. } => rapaport::cutoff(0.5 * (d_a + d_b)),
            ContactLaw::SpringDashpot(_) => 0.5 * (d_a + d_b),
        }
    }

    /// Distance from a wall below which a particle of diameter `d` touches it.
    #[inline]
    pub fn wall_reach(&self, d: f64) -> f64 {
        match self {
            ContactLaw::Rapaport { wall_diameter, .. } => {
                rapaport::cutoff(0.5 * (d + wall_diameter))
            }
            ContactLaw::SpringDashpot(_) => 0.5 * d,
        }
    }

    /// Contact between `a` and `b`, `r = x_a - x_b`.
    #[inline]
    pub fn pair(
        &self,
        r: V3,
        a: &Body,
        b: &Body,
        fr: Friction,
        hist: &mut [f64],
    ) -> Option<Contact> {
        match self {
            ContactLaw::Rapaport { gamma_n, .. } => {
                rapaport::pair(r, a.v, b.v, a.w, b.w, a.d, b.d, *gamma_n, fr)
            }
            ContactLaw::SpringDashpot(sd) => sd.pair(r, a, b, fr, hist),
        }
    }

    /// Contact of `p` with a wall: `r` from the wall point to the centre, `v_wall` the wall's
    /// velocity there, `w_wall` its angular velocity.
    #[inline]
    pub fn wall(
        &self,
        r: V3,
        p: &Body,
        v_wall: V3,
        w_wall: V3,
        fr: Friction,
        hist: &mut [f64],
    ) -> Option<Contact> {
        match self {
            ContactLaw::Rapaport {
                gamma_n,
                wall_diameter,
            } => rapaport::wall(
                r,
                p.v,
                p.w,
                v_wall,
                0.5 * (p.d + wall_diameter),
                *gamma_n,
                fr,
            ),
            ContactLaw::SpringDashpot(sd) => sd.wall(r, p, v_wall, w_wall, fr, hist),
        }
    }
}

/// The smallest diameter a species can have.
pub fn smallest_diameter(s: &crate::case::Species) -> f64 {
    (s.diameter - s.diameter_spread) * (1.0 - 3.0 * s.diameter_sd)
}

/// Largest diameter a species can have.
pub fn largest_diameter(s: &crate::case::Species) -> f64 {
    s.diameter * (1.0 + 3.0 * s.diameter_sd)
}

/// Halo width and cell size: the largest interaction range plus the skin.
pub fn reach(case: &Case) -> f64 {
    // a rough wall's particles take part in pairs too
    let rough = case.drum.rough_wall.as_ref().map_or(0.0, |r| r.diameter);
    let d = case
        .species
        .iter()
        .map(largest_diameter)
        .fold(rough, f64::max);
    ContactLaw::new(case).cutoff(d, d) + case.skin()
}

/// Limits on the time step implied by a case.
#[derive(Debug, Clone, Copy)]
pub struct StepLimits {
    /// Shortest binary contact time of any pair or wall contact.
    pub contact_time_min: f64,
    /// Largest accepted time step (`contact_time_min / STEPS_PER_CONTACT_MIN`).
    pub dt_max: f64,
    /// Largest damping rate `gamma / m_eff` (normal and tangential, the latter with the
    /// rotational contribution to the tangential effective mass).
    pub damping_rate_max: f64,
}

/// Time-step limits of `case`, from its smallest particles.
pub fn step_limits(case: &Case) -> StepLimits {
    let m = &case.model;
    let mass = |d: f64| m.density * PI / 6.0 * d * d * d;
    // (d_ij, m_eff, wall, species a, species b) of the contacts of the smallest particles,
    // walls included
    let mut contacts = Vec::new();
    for (i, a) in case.species.iter().enumerate() {
        let da = smallest_diameter(a);
        contacts.push((da, mass(da), true, i, i));
        for (j, b) in case.species.iter().enumerate() {
            let db = smallest_diameter(b);
            let (ma, mb) = (mass(da), mass(db));
            contacts.push((0.5 * (da + db), ma * mb / (ma + mb), false, i, j));
        }
    }
    let mut t_min = f64::INFINITY;
    let mut rate: f64 = 0.0;
    match m.family {
        Family::Rapaport => {
            let gamma_s_max = case
                .species
                .iter()
                .flat_map(|s| [s.gamma_s.unwrap_or(0.0), s.gamma_s_wall.unwrap_or(0.0)])
                .fold(0.0, f64::max);
            for &(d, m_eff, wall, ..) in &contacts {
                let d_ij = if wall { 0.5 * (d + m.wall_diameter) } else { d };
                let k = rapaport::contact_stiffness(d_ij);
                t_min = t_min.min(PI * (m_eff / k).sqrt());
                rate = rate.max(m.gamma_n.unwrap_or(0.0).max(gamma_s_max * 3.5) / m_eff);
            }
        }
        Family::SpringDashpot => {
            // the most damped pair or wall: the smallest restitution (a mixed pair's
            // geometric mean is not below the smaller of its species')
            let e = case
                .species
                .iter()
                .flat_map(|s| [s.restitution, s.restitution_wall])
                .chain(case.pairs.iter().map(|p| p.restitution))
                .flatten()
                .fold(m.restitution.unwrap_or(1.0), f64::min);
            match m.normal {
                Normal::Linear => {
                    let tc = m.collision_time.unwrap_or(f64::NAN);
                    t_min = tc;
                    let gamma = -e.ln() / tc;
                    rate = 2.0 * gamma * 3.5;
                    if let Some(gs) = m.gamma_s {
                        for &(_, m_eff, ..) in &contacts {
                            rate = rate.max(gs * 3.5 / m_eff);
                        }
                    }
                }
                Normal::Hertz => {
                    // contact time of a Hertz collision at a characteristic impact speed
                    let r = 0.5 * case.drum.diameter;
                    let v = 2.0
                        * (case.drum.omega.abs() * r).max((m.gravity * case.drum.diameter).sqrt());
                    // each species' material (a wall is of the species' material)
                    let y = |s: usize| {
                        let sp = &case.species[s];
                        (
                            sp.youngs_modulus.or(m.youngs_modulus).unwrap_or(f64::NAN),
                            sp.poisson_ratio.or(m.poisson_ratio).unwrap_or(0.0),
                        )
                    };
                    for &(d, m_eff, wall, i, j) in &contacts {
                        let ((y_a, nu_a), (y_b, nu_b)) = (y(i), y(j));
                        let e_star = effective_modulus(y_a, nu_a, y_b, nu_b);
                        let r_eff = if wall { 0.5 * d } else { 0.25 * d };
                        let t = 2.87 * (m_eff * m_eff / (r_eff * e_star * e_star * v)).powf(0.2);
                        t_min = t_min.min(t);
                        rate = rate
                            .max(m.hertz_damping.unwrap_or(0.0) * (0.05 * d).sqrt() * 3.5 / m_eff);
                    }
                }
            }
        }
    }
    // The Cundall-Strack spring oscillates sqrt(3.5 k_s/k_n) times faster than the normal one
    // (the rotational inertia of a sphere adds 5/2 to the tangential effective mass's inverse).
    if m.family == Family::SpringDashpot && m.tangential == Tangential::History {
        let factor = (3.5 * m.stiffness_ratio).sqrt();
        if factor > 1.0 {
            t_min /= factor;
        }
    }
    // The rolling spring of a sphere on a wall, `k_r = s mu_r^2 k_n` against the rolling mass
    // `I_r / R^2 = 7 m / 5` about the contact point, oscillates `sqrt(5 s mu_r^2 / 7)` times
    // as fast as the normal spring with mass `m` (pairs are slower).
    if m.family == Family::SpringDashpot && m.rolling == Rolling::Sds {
        let mu_r = case
            .species
            .iter()
            .flat_map(|s| [s.mu_roll.unwrap_or(0.0), s.mu_roll_wall.unwrap_or(0.0)])
            .chain(case.pairs.iter().map(|p| p.mu_roll.unwrap_or(0.0)))
            .fold(0.0, f64::max);
        let factor = (5.0 * m.rolling_stiffness * mu_r * mu_r / 7.0).sqrt();
        if factor > 1.0 {
            t_min /= factor;
        }
    }
    StepLimits {
        contact_time_min: t_min,
        dt_max: t_min / STEPS_PER_CONTACT_MIN,
        damping_rate_max: rate,
    }
}
