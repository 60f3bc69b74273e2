//! The tangential slot of the contact law: the force in the tangent plane from the sliding
//! velocity at the contact, capped at `mu |F_n|` (Coulomb).
//!
//! - Viscous (thesis eq. 2.15), with a fixed `gamma_s` or the pair's normal dashpot
//!   coefficient; or with each pair's own `gamma_s` (Rapaport eq. 4).
//! - The Cundall-Strack spring on the accumulated tangential displacement (eqs.
//!   2.17-2.18; 3 history words), turned into the current tangent plane every step and cut
//!   back to the Coulomb limit while sliding.
//!
//! This file holds all of a tangential model, as [`super::rolling`] does for rolling: the
//! run's choice ([`TangentialLaw::of`]), the scalar law ([`TangentialLaw::force`]), its
//! batched lanes (a [`TangentialPart`], the same IEEE operations in the same order) and the
//! match that turns the run's choice into a type for the pair pass
//! ([`TangentialLaw::visit`]).

use super::batch::{dot, norm, scale, select3};
use super::rapaport::{Friction, V3};
use crate::case::{Case, Family, Tangential};

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

/// What the pair pass does with a tangential model made a type ([`TangentialLaw::visit`]).
pub trait WithTangential {
    /// What it returns.
    type Out;
    /// Go on with `tangential`.
    fn with<T: TangentialPart>(self, tangential: T) -> Self::Out;
}

impl TangentialLaw {
    /// The tangential model of `case`: Rapaport's viscous sliding with each pair's
    /// `gamma_s` for its family, else `model.tangential`.
    pub fn of(case: &Case) -> Self {
        let m = &case.model;
        match (m.family, m.tangential) {
            (Family::Rapaport, _) => TangentialLaw::ViscousPairs,
            (_, Tangential::Viscous) => TangentialLaw::Viscous { gamma_s: m.gamma_s },
            (_, Tangential::History) => TangentialLaw::History {
                ratio: m.stiffness_ratio,
                dt: case.dt(),
            },
        }
    }

    /// Call `v` with this model as a type.
    pub fn visit<V: WithTangential>(&self, v: V) -> V::Out {
        match *self {
            TangentialLaw::Viscous { gamma_s } => v.with(ViscousTangential { gamma_s }),
            TangentialLaw::ViscousPairs => v.with(ViscousPairTangential),
            TangentialLaw::History { ratio, dt } => v.with(HistoryTangential { ratio, dt }),
        }
    }
}

/// `-min(gamma |v_s|, cap) v_s/|v_s|`, zero when `v_s` is.
#[inline(always)]
fn viscous(v_s: [f64; 3], gamma: f64, cap: f64) -> [f64; 3] {
    let vs = norm(v_s);
    let mag = (gamma * vs).min(cap);
    let f = scale(v_s, -mag / vs);
    select3(vs == 0.0, [0.0; 3], f)
}

/// The tangential slot of a law, as `TangentialLaw::force`.
pub trait TangentialPart: Copy {
    /// History words it keeps (0 or 3).
    const WORDS: usize;
    /// Tangential force from the sliding velocity `v_s`, updating `hist`.
    #[allow(clippy::too_many_arguments)]
    fn lane(
        &self,
        n: [f64; 3],
        v_s: [f64; 3],
        f_n: f64,
        k_n: f64,
        dash: f64,
        gamma_s: f64,
        mu: f64,
        hist: &mut [f64; 3],
    ) -> [f64; 3];
}

/// Viscous with a Coulomb cap (`TangentialLaw::Viscous`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscousTangential {
    /// Fixed `gamma_s`, or the pair's normal dashpot coefficient.
    pub gamma_s: Option<f64>,
}

impl TangentialPart for ViscousTangential {
    const WORDS: usize = 0;

    #[inline(always)]
    fn lane(
        &self,
        _n: [f64; 3],
        v_s: [f64; 3],
        f_n: f64,
        _k_n: f64,
        dash: f64,
        _gamma_s: f64,
        mu: f64,
        _hist: &mut [f64; 3],
    ) -> [f64; 3] {
        viscous(v_s, self.gamma_s.unwrap_or(dash), mu * f_n.abs())
    }
}

/// Viscous with a Coulomb cap and each pair's `gamma_s` (`TangentialLaw::ViscousPairs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViscousPairTangential;

impl TangentialPart for ViscousPairTangential {
    const WORDS: usize = 0;

    #[inline(always)]
    fn lane(
        &self,
        _n: [f64; 3],
        v_s: [f64; 3],
        f_n: f64,
        _k_n: f64,
        _dash: f64,
        gamma_s: f64,
        mu: f64,
        _hist: &mut [f64; 3],
    ) -> [f64; 3] {
        viscous(v_s, gamma_s, mu * f_n.abs())
    }
}

/// The Cundall-Strack spring (`TangentialLaw::History`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryTangential {
    /// `k_s / k_n`.
    pub ratio: f64,
    /// Time step.
    pub dt: f64,
}

impl TangentialPart for HistoryTangential {
    const WORDS: usize = 3;

    #[inline(always)]
    fn lane(
        &self,
        n: [f64; 3],
        v_s: [f64; 3],
        f_n: f64,
        k_n: f64,
        _dash: f64,
        _gamma_s: f64,
        mu: f64,
        hist: &mut [f64; 3],
    ) -> [f64; 3] {
        let cap = mu * f_n.abs();
        let k_s = self.ratio * k_n;
        let old = *hist;
        // turn the stored displacement into the current tangent plane, keeping its length
        let along = dot(n, old);
        let mut beta = [
            old[0] - n[0] * along,
            old[1] - n[1] * along,
            old[2] - n[2] * along,
        ];
        let (l_old, l_new) = (norm(old), norm(beta));
        beta = select3(l_new > 0.0, scale(beta, l_old / l_new), beta);
        for k in 0..3 {
            beta[k] += v_s[k] * self.dt;
        }
        let f_s = scale(beta, -k_s);
        let mag = norm(f_s);
        // sliding: cut back to the Coulomb limit
        let slide = mag > cap;
        let f_cut = scale(f_s, cap / mag);
        let f_s = select3(slide, f_cut, f_s);
        *hist = select3(slide, scale(f_cut, -1.0 / k_s), beta);
        f_s
    }
}
