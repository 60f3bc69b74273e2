//! What every contact law takes and returns.

use super::rapaport::V3;

/// The state of one body of a contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Velocity.
    pub v: V3,
    /// Angular velocity.
    pub w: V3,
    /// Diameter.
    pub d: f64,
    /// `1/m`.
    pub inv_mass: f64,
}

/// Result of a contact: force on `a` and the vector `n x f_s` from which both torques follow
/// (`tau_a = -(d_a/2) n x f_s`, `tau_b = -(d_b/2) n x f_s`; for a wall only the first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Total force on `a` (`f_n + f_s`); `b` receives its negative.
    pub force: V3,
    /// `n x f_s`, with `n` the unit vector from `b` (or the wall) to `a`.
    pub n_cross_fs: V3,
}
