//! The Rapaport (2002, section III) contact model in reduced units: the truncated
//! Lennard-Jones-derived repulsion (eq. 1), normal damping (eq. 2) and sliding friction with
//! a Coulomb cap (eqs. 3-4), for particle pairs and walls.
//!
//! A run evaluates it as one composition of the contact law's slots (`NormalLaw::Rapaport`,
//! `TangentialLaw::ViscousPairs`); [`pair`] and [`wall`] write the paper's formulas out in
//! one piece, and `tests/contact_kernels.rs` checks the composition against them bit for
//! bit. The repulsion and its range are shared by both.
//!
//! Conventions: `r = x_a - x_b` points from `b` to `a`; the returned force acts on `a` and its
//! negative on `b`. The pair is always evaluated with `a` the particle of lower global id, so
//! every rank that evaluates it does the same arithmetic.

pub use super::contact::Contact;
use nalgebra::Vector3;

/// 3-vector of `f64`.
pub type V3 = Vector3<f64>;

/// `2^(1/6)`: the repulsion acts for `r < 2^(1/6) d_ij`.
pub const CUTOFF_FACTOR: f64 = 1.122_462_048_309_373;

/// Numerical factor of the moment of inertia of a solid sphere in Rapaport's torque rule
/// (`I = KAPPA m d^2 / 2 = m d^2 / 10`).
pub const KAPPA: f64 = 0.2;

/// Interaction range of a pair of effective diameter `d_ij`.
#[inline]
pub fn cutoff(d_ij: f64) -> f64 {
    CUTOFF_FACTOR * d_ij
}

/// The contact coefficients of one pair of materials (or a material and a wall): sliding
/// and static friction, for the spring-dashpot family's optional sub-models rolling
/// friction and cohesion, and the pair's own normal coefficients (read by the
/// spring-dashpot laws whose coefficients differ between pairs, see
/// `normal::NormalLaw::LinearPairs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    /// Sliding friction coefficient `gamma_s`.
    pub gamma_s: f64,
    /// Static friction coefficient `mu` (Coulomb cap).
    pub mu: f64,
    /// Rolling friction coefficient `mu_r`: the rolling torque is at most `mu_r R_eff |F_n|`.
    pub mu_roll: f64,
    /// Cohesion energy density `k_c` (simplified JKR: an attraction `k_c A` over the contact
    /// area `A`).
    pub cohesion: f64,
    /// Normal stiffness coefficient of the pair: `k0 = (pi/t_c)^2 + gamma_n^2` of the linear
    /// law, `kh = 4 Y* / 3` of Hertz (0 in the Rapaport family).
    pub normal_k: f64,
    /// Normal damping coefficient of the pair: `2 gamma_n` of the linear law, `gamma_h` of
    /// Hertz (0 in the Rapaport family).
    pub normal_c: f64,
}

impl Friction {
    /// Sliding and static friction only (no rolling friction, no cohesion, no normal
    /// coefficients of its own).
    pub const fn sliding(gamma_s: f64, mu: f64) -> Self {
        Friction {
            gamma_s,
            mu,
            mu_roll: 0.0,
            cohesion: 0.0,
            normal_k: 0.0,
            normal_c: 0.0,
        }
    }
}

/// Magnitude of the repulsion of eq. (1) at distance `r` for effective diameter `d_ij`
/// (positive = repulsive); zero at and beyond the cutoff.
#[inline]
pub fn repulsion(r: f64, d_ij: f64) -> f64 {
    // computed, then discarded beyond the cutoff: no branch, so the batched pass
    // (`batch::RapaportNormal`) can call it in its vectorised lanes
    let s = d_ij / r;
    let s6 = s * s * s * s * s * s;
    let f = 48.0 / r * (s6 * s6 - 0.5 * s6);
    if r >= cutoff(d_ij) {
        0.0
    } else {
        f
    }
}

/// Sliding friction of eq. (4): `-min(gamma_s |v_s|, mu |f_n|) v_s/|v_s|`.
#[inline]
fn sliding(v_s: V3, f_n_mag: f64, fr: Friction) -> V3 {
    let vs = v_s.norm();
    if vs == 0.0 {
        return V3::zeros();
    }
    let mag = (fr.gamma_s * vs).min(fr.mu * f_n_mag.abs());
    v_s * (-mag / vs)
}

/// Force between particles `a` and `b` (section III), or `None` beyond the cutoff.
///
/// `r` is `x_a - x_b` (already the periodic minimum image), `v_*` the velocities, `w_*` the
/// angular velocities, `d_*` the diameters.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn pair(
    r: V3,
    v_a: V3,
    v_b: V3,
    w_a: V3,
    w_b: V3,
    d_a: f64,
    d_b: f64,
    gamma_n: f64,
    fr: Friction,
) -> Option<Contact> {
    let d_ab = 0.5 * (d_a + d_b);
    let rc = cutoff(d_ab);
    let r2 = r.norm_squared();
    if r2 >= rc * rc {
        return None;
    }
    let rr = r2.sqrt();
    let n = r / rr;
    let v = v_a - v_b;
    let vn = n.dot(&v);
    // eq. (1) + eq. (2): total force along n.
    let f_n = repulsion(rr, d_ab) - gamma_n * vn;
    // eq. (3): relative transverse velocity at the contact, with both spins.
    let w_eff = (w_a * d_a + w_b * d_b) / (d_a + d_b);
    let v_s = v - n * vn - w_eff.cross(&r);
    let f_s = sliding(v_s, f_n, fr);
    Some(Contact {
        force: n * f_n + f_s,
        n_cross_fs: n.cross(&f_s),
        torque_roll: V3::zeros(),
    })
}

/// Force of a wall on a particle (eq. 5 and the paragraph before it).
///
/// `r` is the vector from the effective wall point to the particle centre (`r'_iw`), `v_wall`
/// the wall's velocity there, `d_iw = (d_i + d_wall)/2`. The sliding velocity is the paper's
/// `v_iw - (n . v_iw) n - w_i x r'_iw`, as printed.
#[inline]
pub fn wall(
    r: V3,
    v: V3,
    w: V3,
    v_wall: V3,
    d_iw: f64,
    gamma_n: f64,
    fr: Friction,
) -> Option<Contact> {
    let rc = cutoff(d_iw);
    let r2 = r.norm_squared();
    if r2 >= rc * rc || r2 == 0.0 {
        return None;
    }
    let rr = r2.sqrt();
    let n = r / rr;
    let v_iw = v - v_wall;
    let vn = n.dot(&v_iw);
    let f_n = repulsion(rr, d_iw) - gamma_n * vn;
    let v_s = v_iw - n * vn - w.cross(&r);
    let f_s = sliding(v_s, f_n, fr);
    Some(Contact {
        force: n * f_n + f_s,
        n_cross_fs: n.cross(&f_s),
        torque_roll: V3::zeros(),
    })
}

/// Stiffness of the repulsion at contact (`r = d_ij`): `|dF/dr| = 456 / d_ij^2`.
pub fn contact_stiffness(d_ij: f64) -> f64 {
    456.0 / (d_ij * d_ij)
}
