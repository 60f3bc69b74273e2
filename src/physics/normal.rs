//! The normal slot of the contact law: the force along the line of centres with its
//! damping, the normal stiffness the tangential and rolling springs scale with, and the
//! range of a contact.
//!
//! - The thesis' linear spring and dashpot (Chen 2008, eqs. 2.4-2.12) from the collision
//!   time `t_c` and restitution `e_n`: `F_n = m_eff (k0 a - 2 gamma_n v_n)` with
//!   `gamma_n = -ln(e_n)/t_c` and `k0 = (pi/t_c)^2 + gamma_n^2`, so that every pair has
//!   exactly `t_c` and `e_n`; SI units.
//! - Hertz with its non-linear damping (eqs. 2.13-2.14).
//! - Either with each pair's own coefficients, when species or `[[pairs]]` differ.
//! - Rapaport (2002, eqs. 1-2): the truncated Lennard-Jones repulsion acting to
//!   `2^(1/6) d_ij`, less `gamma_n v_n`; reduced units.
//!
//! This file holds all of a normal model, as [`super::rolling`] does for rolling: the run's
//! choice ([`NormalLaw::of`]), the scalar law ([`NormalLaw::force`], the walls' law and the
//! reference), its batched lanes (a [`NormalPart`], the same IEEE operations in the same
//! order) and the match that turns the run's choice into a type for the monomorphised pair
//! pass ([`NormalLaw::visit`]).
//!
//! Conventions as in [`super::rapaport`]: `r = x_a - x_b`, `n = r/|r|`, force on `a`.

use super::materials::{effective_modulus, hertz_kh, linear_coefficients, Materials};
use super::rapaport::{self, Friction};
use crate::case::{Case, Family, Normal};
use std::f64::consts::PI;

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

/// One contact of the time-step check: `(d_ij, m_eff, wall, species a, species b)` of the
/// smallest particles (for a wall contact `d_ij` is the particle's diameter, `b = a`).
pub type StepContact = (f64, f64, bool, usize, usize);

/// The normal model's part of the time-step check (`law::step_limits`): the shortest
/// contact time of `contacts` and the largest damping rate `gamma / m_eff` (normal and
/// viscous tangential, the latter with the rotational contribution `3.5`).
pub fn contact_limits(case: &Case, contacts: &[StepContact]) -> (f64, f64) {
    let m = &case.model;
    let mut t_min = f64::INFINITY;
    let mut rate: f64 = 0.0;
    match m.family {
        Family::Rapaport => {
            let gamma_s_max = case
                .species
                .iter()
                .flat_map(|s| [s.gamma_s.unwrap_or(0.0), s.gamma_s_wall.unwrap_or(0.0)])
                .fold(0.0, f64::max);
            for &(d, m_eff, wall, ..) in contacts {
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
                        for &(_, m_eff, ..) in contacts {
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
                    for &(d, m_eff, wall, i, j) in contacts {
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
    (t_min, rate)
}

/// What the pair pass does with a normal model made a type ([`NormalLaw::visit`]).
pub trait WithNormal {
    /// What it returns.
    type Out;
    /// Go on with `normal`.
    fn with<N: NormalPart>(self, normal: N) -> Self::Out;
}

impl NormalLaw {
    /// The normal model of `case`: Rapaport's for its family, else `model.normal` with the
    /// model's coefficients, or each pair's when the species or `[[pairs]]` differ.
    pub fn of(case: &Case) -> Self {
        let m = &case.model;
        if m.family == Family::Rapaport {
            return NormalLaw::Rapaport {
                gamma_n: m.gamma_n.unwrap_or(0.0),
                wall_diameter: m.wall_diameter,
            };
        }
        let mat = Materials::new(case);
        match m.normal {
            Normal::Linear => {
                let e = m.restitution.unwrap_or(1.0);
                let (k0, two_gamma) = linear_coefficients(e, m.collision_time.unwrap_or(1.0));
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
        }
    }

    /// Call `v` with this model as a type.
    pub fn visit<V: WithNormal>(&self, v: V) -> V::Out {
        match *self {
            NormalLaw::Linear { k0, two_gamma } => v.with(LinearNormal { k0, two_gamma }),
            NormalLaw::Hertz { kh, gamma_h } => v.with(HertzNormal { kh, gamma_h }),
            NormalLaw::LinearPairs => v.with(LinearPairNormal),
            NormalLaw::HertzPairs => v.with(HertzPairNormal),
            NormalLaw::Rapaport { gamma_n, .. } => v.with(RapaportNormal { gamma_n }),
        }
    }
}

/// The normal slot of a law: force along `n`, normal stiffness (for the tangential and
/// rolling springs) and dashpot coefficient, as `NormalLaw::force`.
pub trait NormalPart: Copy {
    /// Whether it reads the pair's own coefficients (`k`, `c` of [`NormalPart::lane`]);
    /// otherwise it has its constants and the batch's columns are not loaded.
    const PAIRS: bool;
    /// Whether the law keeps its paper's divisions (`NormalLaw::divides`).
    const DIVIDES: bool = false;
    /// `(f_n, k_n, dash)` at centre distance `rr` and contact diameter `d_ab`, normal
    /// velocity `vn`, effective mass `m_eff` and effective radius `r_eff`; `k`, `c` are the
    /// pair's coefficients when [`Self::PAIRS`].
    #[allow(clippy::too_many_arguments)]
    fn lane(
        &self,
        rr: f64,
        d_ab: f64,
        vn: f64,
        m_eff: f64,
        r_eff: f64,
        k: f64,
        c: f64,
    ) -> (f64, f64, f64);
}

/// Linear spring and dashpot (`NormalLaw::Linear`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearNormal {
    /// `(pi/t_c)^2 + gamma_n^2`.
    pub k0: f64,
    /// `2 gamma_n`.
    pub two_gamma: f64,
}

impl NormalPart for LinearNormal {
    const PAIRS: bool = false;

    #[inline(always)]
    fn lane(&self, rr: f64, d_ab: f64, vn: f64, m_eff: f64, r_eff: f64, _: f64, _: f64) -> Out3 {
        LinearPairNormal.lane(rr, d_ab, vn, m_eff, r_eff, self.k0, self.two_gamma)
    }
}

/// Linear spring and dashpot with each pair's `k0` and `2 gamma_n`
/// (`NormalLaw::LinearPairs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPairNormal;

impl NormalPart for LinearPairNormal {
    const PAIRS: bool = true;

    #[inline(always)]
    fn lane(
        &self,
        rr: f64,
        d_ab: f64,
        vn: f64,
        m_eff: f64,
        _r_eff: f64,
        k0: f64,
        two_gamma: f64,
    ) -> Out3 {
        let a = d_ab - rr;
        let dash = two_gamma * m_eff;
        (m_eff * (k0 * a) - dash * vn, m_eff * k0, dash)
    }
}

/// Hertz with its non-linear damping (`NormalLaw::Hertz`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzNormal {
    /// `2 Y / (3 (1 - nu^2))`.
    pub kh: f64,
    /// Damping coefficient.
    pub gamma_h: f64,
}

impl NormalPart for HertzNormal {
    const PAIRS: bool = false;

    #[inline(always)]
    fn lane(&self, rr: f64, d_ab: f64, vn: f64, m_eff: f64, r_eff: f64, _: f64, _: f64) -> Out3 {
        HertzPairNormal.lane(rr, d_ab, vn, m_eff, r_eff, self.kh, self.gamma_h)
    }
}

/// Hertz with each pair's `kh` and `gamma_h` (`NormalLaw::HertzPairs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzPairNormal;

impl NormalPart for HertzPairNormal {
    const PAIRS: bool = true;

    #[inline(always)]
    fn lane(
        &self,
        rr: f64,
        d_ab: f64,
        vn: f64,
        _m_eff: f64,
        r_eff: f64,
        kh: f64,
        gamma_h: f64,
    ) -> Out3 {
        let a = d_ab - rr;
        let sa = a.sqrt();
        let k = kh * r_eff.sqrt() * sa;
        let dash = gamma_h * sa;
        (k * a - dash * vn, 1.5 * k, dash)
    }
}

/// Rapaport's repulsion and dashpot (`NormalLaw::Rapaport`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RapaportNormal {
    /// Normal damping coefficient.
    pub gamma_n: f64,
}

impl NormalPart for RapaportNormal {
    const PAIRS: bool = false;
    const DIVIDES: bool = true;

    #[inline(always)]
    fn lane(&self, rr: f64, d_ab: f64, vn: f64, _: f64, _: f64, _: f64, _: f64) -> Out3 {
        // eq. (1), zero at and beyond the cutoff (the pass's test is on r^2), and eq. (2)
        (
            rapaport::repulsion(rr, d_ab) - self.gamma_n * vn,
            rapaport::contact_stiffness(d_ab),
            self.gamma_n,
        )
    }
}

/// A normal slot's `(f_n, k_n, dash)`.
type Out3 = (f64, f64, f64);
