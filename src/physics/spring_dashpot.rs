//! The thesis' spring-dashpot contact laws (Chen 2008, ch. 2), SI units.
//!
//! Normal: linear spring and dashpot from the collision time `t_c` and restitution `e_n`,
//! `F_n = m_eff (k0 a - 2 gamma_n v_n)` with `gamma_n = -ln(e_n)/t_c` and
//! `k0 = (pi/t_c)^2 + gamma_n^2` (eqs. 2.4-2.12: every pair then has exactly `t_c` and `e_n`),
//! or Hertz with its non-linear damping (eqs. 2.13-2.14). Tangential: viscous with a Coulomb
//! cap (eq. 2.15), or the Cundall-Strack spring on the accumulated tangential displacement
//! (eqs. 2.17-2.18), turned into the current tangent plane every step and cut back to the
//! Coulomb limit while sliding.
//!
//! Two optional sub-models complete a contact, in the manner of LAMMPS' `pair granular`:
//! rolling resistance ([`super::rolling`]) and cohesion ([`super::cohesion`]). A contact's
//! history words are the tangential spring's, then the rolling spring's.
//!
//! Conventions as in [`super::rapaport`]: `r = x_a - x_b`, `n = r/|r|`, force on `a`.

use super::cohesion::CohesionLaw;
use super::contact::{Body, Contact};
use super::rapaport::{Friction, V3};
use super::rolling::{inv_inertia_at_surface, RollingLaw};

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
}

impl NormalLaw {
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
    /// Spring `k_s = ratio * k_n` on the accumulated displacement.
    History {
        /// `k_s / k_n`.
        ratio: f64,
        /// Time step (the displacement grows by `v_s dt` per step).
        dt: f64,
    },
}

/// A spring-dashpot law: a normal and a tangential part, and the optional rolling and
/// cohesion sub-models.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringDashpot {
    /// Normal part.
    pub normal: NormalLaw,
    /// Tangential part.
    pub tangential: TangentialLaw,
    /// Rolling resistance.
    pub rolling: RollingLaw,
    /// Cohesion.
    pub cohesion: CohesionLaw,
}

impl SpringDashpot {
    /// Normal force magnitude along `n`, normal stiffness (for `k_s`) and dashpot coefficient;
    /// `r_eff` is asked for only by the Hertz law, `fr` only by a law of per-pair
    /// coefficients.
    #[inline]
    fn normal(
        &self,
        a: f64,
        vn: f64,
        m_eff: f64,
        r_eff: impl Fn() -> f64,
        fr: &Friction,
    ) -> (f64, f64, f64) {
        match self.normal {
            NormalLaw::Linear { k0, two_gamma } => NormalLaw::linear(k0, two_gamma, a, vn, m_eff),
            NormalLaw::Hertz { kh, gamma_h } => NormalLaw::hertz(kh, gamma_h, a, vn, r_eff()),
            NormalLaw::LinearPairs => NormalLaw::linear(fr.normal_k, fr.normal_c, a, vn, m_eff),
            NormalLaw::HertzPairs => NormalLaw::hertz(fr.normal_k, fr.normal_c, a, vn, r_eff()),
        }
    }

    /// Tangential force from the sliding velocity `v_s`, updating the history `hist`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn tangential(
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
        match self.tangential {
            TangentialLaw::Viscous { gamma_s } => {
                let vs = v_s.norm();
                if vs == 0.0 {
                    return V3::zeros();
                }
                let mag = (gamma_s.unwrap_or(dash) * vs).min(cap);
                v_s * (-mag / vs)
            }
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

    /// Words of history of a contact: the tangential spring's, then the rolling spring's.
    pub fn history_words(&self) -> usize {
        self.tangential_words() + self.rolling.history_words()
    }

    fn tangential_words(&self) -> usize {
        if matches!(self.tangential, TangentialLaw::History { .. }) {
            3
        } else {
            0
        }
    }

    /// Contact between particles `a` and `b` (`r = x_a - x_b`); `None` (and the history
    /// cleared) when they do not touch.
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
        let r2 = r.norm_squared();
        if r2 >= d_ab * d_ab {
            hist.fill(0.0);
            return None;
        }
        let rr = r2.sqrt();
        let n = r * (1.0 / rr);
        let overlap = d_ab - rr;
        let m_eff = 1.0 / (a.inv_mass + b.inv_mass);
        let inv_d = 1.0 / (a.d + b.d);
        let v = a.v - b.v;
        let vn = n.dot(&v);
        let (f_n, k_n, dash) = self.normal(overlap, vn, m_eff, || 0.5 * a.d * b.d * inv_d, &fr);
        // eq. 2.16: sliding velocity with both spins
        let w_eff = (a.w * a.d + b.w * b.d) * inv_d;
        let v_s = v - n * vn - w_eff.cross(&r);
        let tw = self.tangential_words();
        let (h_t, h_r) = hist.split_at_mut(tw);
        let f_s = self.tangential(n, v_s, f_n, k_n, dash, fr, h_t);
        let torque_roll = if self.rolling == RollingLaw::None {
            V3::zeros()
        } else {
            let r_eff = 0.5 * a.d * b.d * inv_d;
            let inv_ir =
                inv_inertia_at_surface(a.inv_mass, a.d) + inv_inertia_at_surface(b.inv_mass, b.d);
            self.rolling
                .torque(n, a.w - b.w, f_n, k_n, r_eff, inv_ir, fr, h_r)
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

    /// Contact with a wall of infinite mass and radius: `r` from the wall point to the centre
    /// (`|r|` = distance), `v_wall` the wall's velocity there and `w_wall` its angular
    /// velocity.
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
        let half = 0.5 * p.d;
        let r2 = r.norm_squared();
        if r2 >= half * half || r2 == 0.0 {
            hist.fill(0.0);
            return None;
        }
        let rr = r2.sqrt();
        let n = r * (1.0 / rr);
        let overlap = half - rr;
        let m_eff = 1.0 / p.inv_mass;
        let v = p.v - v_wall;
        let vn = n.dot(&v);
        let (f_n, k_n, dash) = self.normal(overlap, vn, m_eff, || half, &fr);
        // the particle's surface point at the contact moves with v - (d/2) w x n
        let v_s = v - n * vn - p.w.cross(&n) * half;
        let tw = self.tangential_words();
        let (h_t, h_r) = hist.split_at_mut(tw);
        let f_s = self.tangential(n, v_s, f_n, k_n, dash, fr, h_t);
        let torque_roll = if self.rolling == RollingLaw::None {
            V3::zeros()
        } else {
            let inv_ir = inv_inertia_at_surface(p.inv_mass, p.d);
            self.rolling
                .torque(n, p.w - w_wall, f_n, k_n, half, inv_ir, fr, h_r)
        };
        let f_tot = match self.cohesion {
            CohesionLaw::None => f_n,
            c => f_n - c.attraction(fr.cohesion, half, None, rr),
        };
        Some(Contact {
            force: n * f_tot + f_s,
            n_cross_fs: n.cross(&f_s),
            torque_roll,
        })
    }
}
