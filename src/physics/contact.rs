//! What every contact law takes and returns, and the shape of a contact's history.

use super::rapaport::V3;

/// Most history words a contact can carry: the tangential spring's displacement (3) and the
/// rolling spring's (3). A run's law uses `ContactLaw::history_words` of them (0, 3 or 6):
/// the pair list, the wall histories, the messages and the checkpoint store that many.
pub const HISTORY_MAX: usize = 6;

/// One contact's history in transit (saved at a rebuild, in a message, read from a
/// checkpoint): the first `history_words` entries are used, the rest are zero.
pub type History = [f64; HISTORY_MAX];

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

/// Result of a contact: force on `a`, the vector `n x f_s` from which the torques of the
/// tangential force follow (`tau_a = -(d_a/2) n x f_s`, `tau_b = -(d_b/2) n x f_s`; for a
/// wall only the first), and the rolling torque on `a` (`b` receives its negative).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Total force on `a` (`f_n + f_s`, less the cohesion); `b` receives its negative.
    pub force: V3,
    /// `n x f_s`, with `n` the unit vector from `b` (or the wall) to `a`.
    pub n_cross_fs: V3,
    /// Rolling-resistance torque on `a` (zero without a rolling sub-model).
    pub torque_roll: V3,
}
