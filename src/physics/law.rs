//! The contact law of a run: one composition of the sub-model slots, chosen once from the
//! case, in the manner of LAMMPS' `pair granular`. A normal slot (linear, Hertz, Rapaport;
//! each with its damping), a tangential slot (viscous, Cundall-Strack), rolling resistance
//! and cohesion ([`super::normal`], [`super::tangential`], [`super::rolling`],
//! [`super::cohesion`]). Here the slots are matched per contact (the scalar form, which
//! serves the walls and is the pair pass's reference); the batched pair pass turns each
//! slot into a type instead, so that its inner loop is monomorphised (`engine::forces`).

use super::cohesion::CohesionLaw;
use super::contact::{Body, Contact};
use super::normal::NormalLaw;
use super::rapaport::{Friction, V3};
use super::rolling::{inv_inertia_at_surface, RollingLaw};
use super::tangential::TangentialLaw;
use crate::case::{Case, Family, Rolling, Tangential};
use std::f64::consts::PI;

/// Fewest steps per binary contact accepted by the time-step check.
pub const STEPS_PER_CONTACT_MIN: f64 = 5.0;

/// A run's contact law: a normal and a tangential slot, and the optional rolling and
/// cohesion sub-models.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Normal part, with its damping.
    pub normal: NormalLaw,
    /// Tangential part.
    pub tangential: TangentialLaw,
    /// Rolling resistance.
    pub rolling: RollingLaw,
    /// Cohesion.
    pub cohesion: CohesionLaw,
}

impl ContactLaw {
    /// The law of `case`.
    pub fn new(case: &Case) -> Self {
        ContactLaw {
            normal: NormalLaw::of(case),
            tangential: TangentialLaw::of(case),
            rolling: RollingLaw::of(case),
            cohesion: CohesionLaw::of(case),
        }
    }

    /// The same law with time standing still: a tangential history is turned into the
    /// tangent plane and cut back, but not advanced by the sliding of a step.
    pub fn frozen(&self) -> Self {
        let mut law = *self;
        if let TangentialLaw::History { dt, .. } = &mut law.tangential {
            *dt = 0.0;
        }
        law.rolling = law.rolling.frozen();
        law
    }

    /// Whether contacts carry a history.
    pub fn has_history(&self) -> bool {
        self.history_words() > 0
    }

    /// Whether contacts exert a rolling-resistance torque.
    pub fn has_rolling(&self) -> bool {
        self.rolling != RollingLaw::None
    }

    /// Words of history per contact (pair or wall): the tangential spring's, then the
    /// rolling spring's; at most [`super::contact::HISTORY_MAX`].
    pub fn history_words(&self) -> usize {
        self.tangential.history_words() + self.rolling.history_words()
    }

    /// Centre distance below which two particles interact.
    #[inline]
    pub fn cutoff(&self, d_a: f64, d_b: f64) -> f64 {
        self.normal.range(0.5 * (d_a + d_b))
    }

    /// Distance from a wall below which a particle of diameter `d` touches it.
    #[inline]
    pub fn wall_reach(&self, d: f64) -> f64 {
        self.normal.range(self.normal.wall_contact(d))
    }

    /// Contact between `a` and `b`, `r = x_a - x_b`; `None` (and the history cleared)
    /// when they do not touch.
    #[inline]
    pub fn pair(
        &self,
        r: V3,
        a: &Body,
        b: &Body,
        fr: Friction,
        hist: &mut [f64],
    ) -> Option<Contact> {
        let d_ab = 0.5 * (a.d + b.d);
        let rc = self.normal.range(d_ab);
        let r2 = r.norm_squared();
        if r2 >= rc * rc {
            hist.fill(0.0);
            return None;
        }
        let rr = r2.sqrt();
        let paper = self.normal.divides();
        let n = if paper { r / rr } else { r * (1.0 / rr) };
        let m_eff = 1.0 / (a.inv_mass + b.inv_mass);
        let inv_d = 1.0 / (a.d + b.d);
        let v = a.v - b.v;
        let vn = n.dot(&v);
        let r_eff = || 0.5 * a.d * b.d * inv_d;
        let (f_n, k_n, dash) = self.normal.force(rr, d_ab, vn, m_eff, r_eff, &fr);
        // sliding velocity with both spins (thesis eq. 2.16, Rapaport eq. 3)
        let w_eff = if paper {
            (a.w * a.d + b.w * b.d) / (a.d + b.d)
        } else {
            (a.w * a.d + b.w * b.d) * inv_d
        };
        let v_s = v - n * vn - w_eff.cross(&r);
        let (h_t, h_r) = hist.split_at_mut(self.tangential.history_words());
        let f_s = self.tangential.force(n, v_s, f_n, k_n, dash, fr, h_t);
        let torque_roll = if self.rolling == RollingLaw::None {
            V3::zeros()
        } else {
            let inv_ir =
                inv_inertia_at_surface(a.inv_mass, a.d) + inv_inertia_at_surface(b.inv_mass, b.d);
            self.rolling
                .torque(n, a.w - b.w, f_n, k_n, r_eff(), inv_ir, fr, h_r)
        };
        let f_tot = match self.cohesion {
            CohesionLaw::None => f_n,
            c => f_n - c.attraction(fr.cohesion, 0.5 * a.d, Some(0.5 * b.d), rr),
        };
        Some(Contact {
            force: n * f_tot + f_s,
            n_cross_fs: n.cross(&f_s),
            torque_roll,
        })
    }

    /// Contact of `p` with a wall of infinite mass and radius: `r` from the wall point to
    /// the centre (`|r|` = distance), `v_wall` the wall's velocity there, `w_wall` its
    /// angular velocity; `None` (and the history cleared) when they do not touch.
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
        let d_iw = self.normal.wall_contact(p.d);
        let rc = self.normal.range(d_iw);
        let r2 = r.norm_squared();
        if r2 >= rc * rc || r2 == 0.0 {
            hist.fill(0.0);
            return None;
        }
        let rr = r2.sqrt();
        let paper = self.normal.divides();
        let n = if paper { r / rr } else { r * (1.0 / rr) };
        let m_eff = 1.0 / p.inv_mass;
        let v = p.v - v_wall;
        let vn = n.dot(&v);
        let (f_n, k_n, dash) = self.normal.force(rr, d_iw, vn, m_eff, || d_iw, &fr);
        // the particle's surface point at the contact moves with v - (d/2) w x n
        // (Rapaport: v - w x r'_iw, as printed)
        let lever = if paper {
            p.w.cross(&r)
        } else {
            p.w.cross(&n) * d_iw
        };
        let v_s = v - n * vn - lever;
        let (h_t, h_r) = hist.split_at_mut(self.tangential.history_words());
        let f_s = self.tangential.force(n, v_s, f_n, k_n, dash, fr, h_t);
        let torque_roll = if self.rolling == RollingLaw::None {
            V3::zeros()
        } else {
            let inv_ir = inv_inertia_at_surface(p.inv_mass, p.d);
            self.rolling
                .torque(n, p.w - w_wall, f_n, k_n, d_iw, inv_ir, fr, h_r)
        };
        let f_tot = match self.cohesion {
            CohesionLaw::None => f_n,
            c => f_n - c.attraction(fr.cohesion, d_iw, None, rr),
        };
        Some(Contact {
            force: n * f_tot + f_s,
            n_cross_fs: n.cross(&f_s),
            torque_roll,
        })
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
    range(case) + case.skin()
}

/// The interaction range of the largest pair of `case` (the largest particles, a rough
/// wall's among them), without the skin.
pub fn range(case: &Case) -> f64 {
    // a rough wall's particles take part in pairs too
    let rough = case.drum.rough_wall.as_ref().map_or(0.0, |r| r.diameter);
    let d = case
        .species
        .iter()
        .map(largest_diameter)
        .fold(rough, f64::max);
    ContactLaw::new(case).cutoff(d, d)
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
    // the contacts of the smallest particles, walls included
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
    let (mut t_min, rate) = super::normal::contact_limits(case, &contacts);
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
