//! Cohesion, a sub-model of the spring-dashpot law: the simplified JKR model of LIGGGHTS
//! (`cohesion sjkr`), an attraction `k_c A` along `-n` while the bodies overlap, `A` the
//! area of the circle in which their surfaces intersect. The Coulomb caps of the
//! tangential and rolling forces use the normal part's force alone.
//!
//! This file holds all of a cohesion model: the run's choice ([`CohesionLaw::of`]), the
//! scalar law ([`CohesionLaw::attraction`]), its batched lanes (a [`CohesionPart`]) and the
//! match that makes the choice a type for the pair pass ([`CohesionLaw::visit`]).

use crate::case::{Case, Cohesion};
use std::f64::consts::PI;

/// Cohesion (none by default).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum CohesionLaw {
    /// No cohesion.
    #[default]
    None,
    /// Simplified JKR: `k_c A` along `-n` while the bodies overlap.
    Sjkr,
}

/// What the pair pass does with a cohesion model made a type ([`CohesionLaw::visit`]).
pub trait WithCohesion {
    /// What it returns.
    type Out;
    /// Go on with `cohesion`.
    fn with<C: CohesionPart>(self, cohesion: C) -> Self::Out;
}

impl CohesionLaw {
    /// The cohesion model of `case` (`model.cohesion`).
    pub fn of(case: &Case) -> Self {
        match case.model.cohesion {
            Cohesion::None => CohesionLaw::None,
            Cohesion::Sjkr => CohesionLaw::Sjkr,
        }
    }

    /// Call `v` with this model as a type.
    pub fn visit<V: WithCohesion>(&self, v: V) -> V::Out {
        match self {
            CohesionLaw::None => v.with(NoCohesion),
            CohesionLaw::Sjkr => v.with(SjkrCohesion),
        }
    }

    /// Attraction (along `-n`) of spheres of radii `ra` and `rb` (`None`: a wall) at centre
    /// distance `rr`, energy density `k_c`; the scalar law.
    #[inline]
    pub fn attraction(&self, k_c: f64, ra: f64, rb: Option<f64>, rr: f64) -> f64 {
        match self {
            CohesionLaw::None => 0.0,
            CohesionLaw::Sjkr => k_c * contact_area(ra, rb, rr),
        }
    }
}

/// The area of the circle in which two spheres of radii `ra`, `rb` intersect at centre
/// distance `rr` (`rb` infinite for a wall: pass `None`).
#[inline(always)]
pub fn contact_area(ra: f64, rb: Option<f64>, rr: f64) -> f64 {
    match rb {
        Some(rb) => {
            -PI / 4.0 * ((rr - ra - rb) * (rr + ra - rb) * (rr - ra + rb) * (rr + ra + rb))
                / (rr * rr)
        }
        None => PI * ((ra - rr) * (ra + rr)),
    }
}

/// The cohesion sub-model of a spring-dashpot law, as [`CohesionLaw::attraction`].
pub trait CohesionPart: Copy {
    /// Whether it attracts at all.
    const ACTIVE: bool;
    /// Attraction (along `-n`) of bodies of radii `ra`, `rb` at distance `rr`, energy density
    /// `k_c`.
    fn lane(&self, k_c: f64, ra: f64, rb: f64, rr: f64) -> f64;
    /// Attraction (along `-n`) of a body of radius `ra` to a wall at distance `rr`.
    fn wall_lane(&self, k_c: f64, ra: f64, rr: f64) -> f64;
}

/// No cohesion (`CohesionLaw::None`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoCohesion;

impl CohesionPart for NoCohesion {
    const ACTIVE: bool = false;

    #[inline(always)]
    fn lane(&self, _k_c: f64, _ra: f64, _rb: f64, _rr: f64) -> f64 {
        0.0
    }

    #[inline(always)]
    fn wall_lane(&self, _k_c: f64, _ra: f64, _rr: f64) -> f64 {
        0.0
    }
}

/// Simplified JKR (`CohesionLaw::Sjkr`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SjkrCohesion;

impl CohesionPart for SjkrCohesion {
    const ACTIVE: bool = true;

    #[inline(always)]
    fn lane(&self, k_c: f64, ra: f64, rb: f64, rr: f64) -> f64 {
        k_c * contact_area(ra, Some(rb), rr)
    }

    #[inline(always)]
    fn wall_lane(&self, k_c: f64, ra: f64, rr: f64) -> f64 {
        k_c * contact_area(ra, None, rr)
    }
}
