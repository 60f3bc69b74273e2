//! The normal and tangential slots of the contact law ([`super::ContactLaw`]), scalar form.
//!
//! The thesis' spring-dashpot laws (Chen 2008, ch. 2), SI units. Normal: linear spring and dashpot from the collision time `t_c` and restitution `e_n`,
//! `F_n = m_eff (k0 a - 2 gamma_n v_n)` with `gamma_n = -ln(e_n)/t_c` and
//! `k0 = (pi/t_c)^2 + gamma_n^2` (eqs. 2.4-2.12: every pair then has exactly `t_c` and `e_n`),
//! or Hertz with its non-linear damping (eqs. 2.13-2.14). Tangential: viscous with a Coulomb
//! cap (eq. 2.15), or the Cundall-Strack spring on the accumulated tangential displacement
//! (eqs. 2.17-2.18), turned into the current tangent plane every step and cut back to the
//! Coulomb limit while sliding.
//!
//! Rapaport (2002, section III), reduced units, is one more composition of the same slots:
//! its normal slot is the truncated Lennard-Jones repulsion with the dashpot `-gamma_n v_n`
//! ([`NormalLaw::Rapaport`], acting to `2^(1/6) d_ij`), its tangential slot the viscous
//! friction with each pair's `gamma_s` ([`TangentialLaw::ViscousPairs`]).
//!
//! Two optional sub-models complete a contact, in the manner of LAMMPS' `pair granular`:
//! rolling resistance ([`super::rolling`]) and cohesion ([`super::cohesion`]). A contact's
//! history words are the tangential spring's, then the rolling spring's. The batched lanes
//! of these slots are in [`super::batch`].
//!
//! Conventions as in [`super::rapaport`]: `r = x_a - x_b`, `n = r/|r|`, force on `a`.

use super::rapaport::{self, Friction, V3};

/// Normal force law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NormalLaw {
    /// `F_n = m_eff (k0 a - two_gamma v_n)`.
    Linear {
        /// `(pi/t_c)^2 + gamma_n^2`.
        k0: f64,
        /// `2 gamma_n`.
        two_gamma: f64,
    },
    /// `F_n = kh sqrt(r_eff) a^(3/2) - gamma_h sqrt(a) v_n`.
    Hertz {
        /// `2 Y / (3 (1 - nu^2))`.
        kh: f64,
        /// Damping coefficient `gamma_n^n`.
        gamma_h: f64,
    },
    /// The linear law with each pair's own `k0` and `2 gamma_n` (`Friction::normal_k`,
    /// `Friction::normal_c`): the run's species or pairs differ in restitution.
    LinearPairs,
    /// Hertz with each pair's own `kh` and `gamma_h` (`Friction::normal_k`,
    /// `Friction::normal_c`): the run's species differ in material.
    HertzPairs,
    /// Rapaport's eqs. (1)-(2): the repulsion of the truncated Lennard-Jones potential at
    /// centre distance `r < 2^(1/6) d_ij`, less `gamma_n v_n` (no effective mass).
    Rapaport {
        /// Normal damping coefficient.
        gamma_n: f64,
        /// Diameter attributed to the walls: a wall contact has `d_iw = (d_i + d_wall)/2`.
        wall_diameter: f64,
    },
}

impl NormalLaw {
    /// Centre distance below which two bodies of contact diameter `d_ab` interact.
    #[inline]
    pub fn range(&self, d_ab: f64) -> f64 {
        match self {
            NormalLaw::Rapaport { .. } => rapaport::cutoff(d_ab),
            _ => d_ab,
        }
    }

    /// Contact diameter of a particle of diameter `d` with a wall, the distance from the
    /// wall at which it starts to overlap: `d/2`, or Rapaport's `(d + d_wall)/2`.
    #[inline]
    pub fn wall_contact(&self, d: f64) -> f64 {
        match self {
            NormalLaw::Rapaport { wall_diameter, .. } => 0.5 * (d + wall_diameter),
            _ => 0.5 * d,
        }
    }

    /// Whether the law keeps its paper's arithmetic: `n = r/|r|` and
    /// `w_eff = (w_a d_a + w_b d_b)/(d_a + d_b)` divided out, and the wall's sliding
    /// velocity with the lever `w x r'_iw` as printed (Rapaport), where the thesis' laws
    /// multiply by the reciprocal and take the lever `(d/2) w x n`. Kept so that a run
    /// gives the same bits as the law's own formulas (`rapaport::pair`, `rapaport::wall`).
    #[inline]
    pub fn divides(&self) -> bool {
        matches!(self, NormalLaw::Rapaport { .. })
    }

    /// Normal force magnitude along `n`, normal stiffness (for `k_s`) and dashpot
    /// coefficient at centre distance `rr` and contact diameter `d_ab`; `r_eff` is asked
    /// for only by the Hertz laws, `fr` only by a law of per-pair coefficients.
    #[inline]
    pub fn force(
        &self,
        rr: f64,
        d_ab: f64,
        vn: f64,
        m_eff: f64,
        r_eff: impl Fn() -> f64,
        fr: &Friction,
    ) -> (f64, f64, f64) {
        let a = d_ab - rr;
        match *self {
            NormalLaw::Linear { k0, two_gamma } => linear(k0, two_gamma, a, vn, m_eff),
            NormalLaw::Hertz { kh, gamma_h } => hertz(kh, gamma_h, a, vn, r_eff()),
            NormalLaw::LinearPairs => linear(fr.normal_k, fr.normal_c, a, vn, m_eff),
            NormalLaw::HertzPairs => hertz(fr.normal_k, fr.normal_c, a, vn, r_eff()),
            NormalLaw::Rapaport { gamma_n, .. } => (
                rapaport::repulsion(rr, d_ab) - gamma_n * vn,
                rapaport::contact_stiffness(d_ab),
                gamma_n,
            ),
        }
    }
}

#[inline(always)]
fn linear(k0: f64, two_gamma: f64, a: f64, vn: f64, m_eff: f64) -> (f64, f64, f64) {
    let dash = two_gamma * m_eff;
    (m_eff * (k0 * a) - dash * vn, m_eff * k0, dash)
}

#[inline(always)]
fn hertz(kh: f64, gamma_h: f64, a: f64, vn: f64, r_eff: f64) -> (f64, f64, f64) {
    let sa = a.sqrt();
    let k = kh * r_eff.sqrt() * sa;
    let dash = gamma_h * sa;
    (k * a - dash * vn, 1.5 * k, dash)
}

/// Tangential force law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TangentialLaw {
    /// `-min(gamma_s |v_s|, mu |F_n|) v_s/|v_s|`; `gamma_s = None` takes the pair's normal
    /// dashpot coefficient.
    Viscous {
        /// Fixed `gamma_s`, if the case gives one.
        gamma_s: Option<f64>,
    },
    /// The same with each pair's own `gamma_s` (`Friction::gamma_s`): Rapaport's eq. (4).
    ViscousPairs,
    /// Spring `k_s = ratio * k_n` on the accumulated displacement.
    History {
        /// `k_s / k_n`.
        ratio: f64,
        /// Time step (the displacement grows by `v_s dt` per step).
        dt: f64,
    },
}

impl TangentialLaw {
    /// Words of history it keeps (0 or 3).
    pub fn history_words(&self) -> usize {
        if matches!(self, TangentialLaw::History { .. }) {
            3
        } else {
            0
        }
    }

    /// Tangential force from the sliding velocity `v_s`, given the normal force `f_n`,
    /// stiffness `k_n` and dashpot coefficient `dash`, updating the history `hist`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn force(
        &self,
        n: V3,
        v_s: V3,
        f_n: f64,
        k_n: f64,
        dash: f64,
        fr: Friction,
        hist: &mut [f64],
    ) -> V3 {
        let cap = fr.mu * f_n.abs();
        let viscous = |gamma_s: f64| {
            let vs = v_s.norm();
            if vs == 0.0 {
                return V3::zeros();
            }
            let mag = (gamma_s * vs).min(cap);
            v_s * (-mag / vs)
        };
        match *self {
            TangentialLaw::Viscous { gamma_s } => viscous(gamma_s.unwrap_or(dash)),
            TangentialLaw::ViscousPairs => viscous(fr.gamma_s),
            TangentialLaw::History { ratio, dt } => {
                let k_s = ratio * k_n;
                let old = V3::new(hist[0], hist[1], hist[2]);
                // turn the stored displacement into the current tangent plane, keeping its length
                let mut beta = old - n * n.dot(&old);
                let (l_old, l_new) = (old.norm(), beta.norm());
                if l_new > 0.0 {
                    beta *= l_old / l_new;
                }
                beta += v_s * dt;
                let mut f_s = beta * (-k_s);
                let mag = f_s.norm();
                if mag > cap {
                    // sliding: cut back to the Coulomb limit
                    f_s *= cap / mag;
                    beta = f_s * (-1.0 / k_s);
                }
                hist[..3].copy_from_slice(&[beta.x, beta.y, beta.z]);
                f_s
            }
        }
    }
}
