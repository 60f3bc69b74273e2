//! Rolling resistance, a sub-model of the spring-dashpot law: a torque against the relative
//! rolling of the two surfaces, `omega_r = (w_a - w_b)` less its part along `n` (twisting is
//! left free). Three models, as in LIGGGHTS and LAMMPS:
//! - a constant torque `mu_r R_eff |F_n|` against `omega_r` (LIGGGHTS' `cdt`);
//! - a viscous torque `eta |omega_r|`, capped there;
//! - the spring-dashpot-slider of Ai et al. (2011, model C) in LAMMPS' displacement form
//!   (`rolling sds`): a rolling displacement `xi` (3 history words, after the tangential
//!   spring's) grows by `v_r dt = R_eff (omega_r x n) dt`; the force `-k_r xi - gamma_r v_r`,
//!   `k_r = 2.25 mu_r^2 k_n` (Iwashita & Oda's rolling stiffness `2.25 k_n mu_r^2 R_eff^2`
//!   per radian, over `R_eff^2`), is capped at `mu_r |F_n|`, and the torque is
//!   `R_eff n x f_r` on `a`, its negative on `b`.
//!
//! This file holds all of a rolling model: the run's choice ([`RollingLaw::of`]), the
//! scalar law ([`RollingLaw::torque`], the reference and the walls' law), its batched lanes
//! (a [`RollingPart`], the same IEEE operations in the same order) and the match that turns
//! the run's choice into a type for the monomorphised pair pass ([`RollingLaw::visit`]).

use super::batch::{cross, dot, norm, scale, select3};
use super::rapaport::{Friction, V3};
use crate::case::{Case, Rolling};

/// Rolling resistance (none by default).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum RollingLaw {
    /// No rolling resistance.
    #[default]
    None,
    /// A torque of constant magnitude `mu_r R_eff |F_n|` against `omega_r` (zero when the
    /// surfaces do not roll).
    Constant,
    /// `-min(eta |omega_r|, mu_r R_eff |F_n|) omega_r/|omega_r|`.
    Viscous {
        /// Rolling viscosity `eta` (torque per angular velocity, N m s).
        eta: f64,
    },
    /// Spring-dashpot-slider on the rolling displacement (3 history words).
    Sds {
        /// `k_r / (mu_r^2 k_n)` (2.25).
        stiffness: f64,
        /// Dashpot as a fraction of the critical damping of the rolling spring with the
        /// pair's rolling inertia about the contact point.
        damping: f64,
        /// Time step (the displacement grows by `v_r dt` per step).
        dt: f64,
    },
}

/// What the pair pass does with a rolling model made a type ([`RollingLaw::visit`]).
pub trait WithRolling {
    /// What it returns.
    type Out;
    /// Go on with `rolling`.
    fn with<R: RollingPart>(self, rolling: R) -> Self::Out;
}

impl RollingLaw {
    /// The rolling model of `case` (`model.rolling` and its keys).
    pub fn of(case: &Case) -> Self {
        let m = &case.model;
        match m.rolling {
            Rolling::None => RollingLaw::None,
            Rolling::Constant => RollingLaw::Constant,
            Rolling::Viscous => RollingLaw::Viscous {
                eta: m.rolling_viscosity.unwrap_or(0.0),
            },
            Rolling::Sds => RollingLaw::Sds {
                stiffness: m.rolling_stiffness,
                damping: m.rolling_damping,
                dt: case.dt(),
            },
        }
    }

    /// History words it needs.
    pub fn history_words(&self) -> usize {
        if matches!(self, RollingLaw::Sds { .. }) {
            3
        } else {
            0
        }
    }

    /// The same model with time standing still (its spring not advanced by a step).
    pub fn frozen(mut self) -> Self {
        if let RollingLaw::Sds { dt, .. } = &mut self {
            *dt = 0.0;
        }
        self
    }

    /// Call `v` with this model as a type.
    pub fn visit<V: WithRolling>(&self, v: V) -> V::Out {
        match *self {
            RollingLaw::None => v.with(NoRolling),
            RollingLaw::Constant => v.with(CappedRolling { eta: None }),
            RollingLaw::Viscous { eta } => v.with(CappedRolling { eta: Some(eta) }),
            RollingLaw::Sds {
                stiffness,
                damping,
                dt,
            } => v.with(SdsRolling {
                stiffness,
                damping,
                dt,
            }),
        }
    }

    /// Rolling torque on `a` from the relative spin `w_rel`, updating the rolling history
    /// `hist`: `r_eff` the effective radius, `inv_ir` the pair's `1 / I_r` about the contact
    /// point.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn torque(
        &self,
        n: V3,
        w_rel: V3,
        f_n: f64,
        k_n: f64,
        r_eff: f64,
        inv_ir: f64,
        fr: Friction,
        hist: &mut [f64],
    ) -> V3 {
        let cap = fr.mu_roll * r_eff * f_n.abs();
        let w_r = w_rel - n * n.dot(&w_rel);
        match *self {
            RollingLaw::None => V3::zeros(),
            RollingLaw::Constant | RollingLaw::Viscous { .. } => {
                let wr = w_r.norm();
                if wr == 0.0 {
                    return V3::zeros();
                }
                let mag = match *self {
                    RollingLaw::Viscous { eta } => (eta * wr).min(cap),
                    _ => cap,
                };
                w_r * (-mag / wr)
            }
            RollingLaw::Sds {
                stiffness,
                damping,
                dt,
            } => {
                let k = stiffness * (fr.mu_roll * fr.mu_roll) * k_n;
                let gamma = damping * 2.0 * (k / (inv_ir * (r_eff * r_eff))).sqrt();
                let v_r = w_r.cross(&n) * r_eff;
                let old = V3::new(hist[0], hist[1], hist[2]);
                let mut xi = old - n * n.dot(&old);
                let (l_old, l_new) = (old.norm(), xi.norm());
                if l_new > 0.0 {
                    xi *= l_old / l_new;
                }
                xi += v_r * dt;
                let mut f_r = xi * (-k) - v_r * gamma;
                let mag = f_r.norm();
                if mag > fr.mu_roll * f_n.abs() {
                    // slipping: cut back to the limit, the spring holding what the limit allows
                    f_r *= fr.mu_roll * f_n.abs() / mag;
                    xi = (f_r + v_r * gamma) * (-1.0 / k);
                }
                hist[..3].copy_from_slice(&[xi.x, xi.y, xi.z]);
                n.cross(&f_r) * r_eff
            }
        }
    }
}

/// `1 / (I + m (d/2)^2)` of a sphere of diameter `d` and `1/m` `inv_mass`: its inverse
/// moment of inertia about a point of its surface, `20 / (7 m d^2)`.
#[inline(always)]
pub fn inv_inertia_at_surface(inv_mass: f64, d: f64) -> f64 {
    20.0 / 7.0 * inv_mass / (d * d)
}

/// The rolling sub-model of a spring-dashpot law, as [`RollingLaw::torque`].
pub trait RollingPart: Copy {
    /// Whether it exerts a torque at all.
    const ACTIVE: bool;
    /// History words it keeps (0 or 3), after the tangential part's.
    const WORDS: usize;
    /// Rolling torque on `a` from the relative spin `w_rel`, updating `hist`.
    #[allow(clippy::too_many_arguments)]
    fn lane(
        &self,
        n: [f64; 3],
        w_rel: [f64; 3],
        f_n: f64,
        k_n: f64,
        r_eff: f64,
        inv_ir: f64,
        mu_r: f64,
        hist: &mut [f64; 3],
    ) -> [f64; 3];
}

/// No rolling resistance (`RollingLaw::None`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoRolling;

impl RollingPart for NoRolling {
    const ACTIVE: bool = false;
    const WORDS: usize = 0;

    #[inline(always)]
    fn lane(
        &self,
        _n: [f64; 3],
        _w_rel: [f64; 3],
        _f_n: f64,
        _k_n: f64,
        _r_eff: f64,
        _inv_ir: f64,
        _mu_r: f64,
        _hist: &mut [f64; 3],
    ) -> [f64; 3] {
        [0.0; 3]
    }
}

/// `w_rel` less its part along `n`.
#[inline(always)]
fn rolling_spin(n: [f64; 3], w_rel: [f64; 3]) -> [f64; 3] {
    let along = dot(n, w_rel);
    [
        w_rel[0] - n[0] * along,
        w_rel[1] - n[1] * along,
        w_rel[2] - n[2] * along,
    ]
}

/// A capped rolling torque against the rolling spin: constant (`eta` infinite) or viscous
/// (`RollingLaw::Constant`, `RollingLaw::Viscous`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CappedRolling {
    /// Rolling viscosity; `None`: the constant torque.
    pub eta: Option<f64>,
}

impl RollingPart for CappedRolling {
    const ACTIVE: bool = true;
    const WORDS: usize = 0;

    #[inline(always)]
    fn lane(
        &self,
        n: [f64; 3],
        w_rel: [f64; 3],
        f_n: f64,
        _k_n: f64,
        r_eff: f64,
        _inv_ir: f64,
        mu_r: f64,
        _hist: &mut [f64; 3],
    ) -> [f64; 3] {
        let cap = mu_r * r_eff * f_n.abs();
        let w_r = rolling_spin(n, w_rel);
        let wr = norm(w_r);
        let mag = match self.eta {
            Some(eta) => (eta * wr).min(cap),
            None => cap,
        };
        select3(wr == 0.0, [0.0; 3], scale(w_r, -mag / wr))
    }
}

/// The rolling spring-dashpot-slider (`RollingLaw::Sds`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SdsRolling {
    /// `k_r / (mu_r^2 k_n)`.
    pub stiffness: f64,
    /// Fraction of critical damping.
    pub damping: f64,
    /// Time step.
    pub dt: f64,
}

impl RollingPart for SdsRolling {
    const ACTIVE: bool = true;
    const WORDS: usize = 3;

    #[inline(always)]
    fn lane(
        &self,
        n: [f64; 3],
        w_rel: [f64; 3],
        f_n: f64,
        k_n: f64,
        r_eff: f64,
        inv_ir: f64,
        mu_r: f64,
        hist: &mut [f64; 3],
    ) -> [f64; 3] {
        let w_r = rolling_spin(n, w_rel);
        let k = self.stiffness * (mu_r * mu_r) * k_n;
        let gamma = self.damping * 2.0 * (k / (inv_ir * (r_eff * r_eff))).sqrt();
        let v_r = scale(cross(w_r, n), r_eff);
        let old = *hist;
        let along = dot(n, old);
        let mut xi = [
            old[0] - n[0] * along,
            old[1] - n[1] * along,
            old[2] - n[2] * along,
        ];
        let (l_old, l_new) = (norm(old), norm(xi));
        xi = select3(l_new > 0.0, scale(xi, l_old / l_new), xi);
        for k in 0..3 {
            xi[k] += v_r[k] * self.dt;
        }
        let f_r = [
            xi[0] * (-k) - v_r[0] * gamma,
            xi[1] * (-k) - v_r[1] * gamma,
            xi[2] * (-k) - v_r[2] * gamma,
        ];
        let mag = norm(f_r);
        let slip = mag > mu_r * f_n.abs();
        let f_cut = scale(f_r, mu_r * f_n.abs() / mag);
        let xi_cut = scale(
            [
                f_cut[0] + v_r[0] * gamma,
                f_cut[1] + v_r[1] * gamma,
                f_cut[2] + v_r[2] * gamma,
            ],
            -1.0 / k,
        );
        let f_r = select3(slip, f_cut, f_r);
        *hist = select3(slip, xi_cut, xi);
        scale(cross(n, f_r), r_eff)
    }
}
