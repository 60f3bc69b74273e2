//! The case file: every key a run is described by, with its default.
//!
//! The structs mirror the TOML layout one to one; unknown keys are refused by serde
//! (`deny_unknown_fields`) so a misspelled key never silently falls back to a default.

use serde::{Deserialize, Serialize};

/// A whole run, as read from `cases/*.toml`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Free text describing the case (which seed run it reproduces, etc.).
    #[serde(default)]
    pub title: String,
    /// Seed of every random choice of the run (lattice velocities, species, diameters).
    pub seed: u64,
    /// The drum.
    pub drum: Drum,
    /// Contact model and its parameters.
    pub model: Model,
    /// The particle species (one table per species, `[[species]]`).
    pub species: Vec<Species>,
    /// How the drum is filled at time zero.
    pub init: Init,
    /// Length of the run and time stepping.
    pub run: Run,
    /// What is written, and how often.
    #[serde(default)]
    pub output: Output,
}

/// End conditions of the cylinder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Ends {
    /// Periodic along the axis: no end walls.
    Periodic,
    /// Two flat end caps turning with the drum.
    Capped,
}

/// The cylindrical drum: axis `z`, centred at the origin, turning about `+z`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Drum {
    /// Inner diameter `D` of the curved wall.
    pub diameter: f64,
    /// Length `L` along the axis (from `-L/2` to `L/2`).
    pub length: f64,
    /// `"periodic"` or `"capped"`.
    pub ends: Ends,
    /// Angular velocity about `+z` (rad per time unit; counterclockwise seen from `+z`).
    pub omega: f64,
}

/// Contact model families.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Family {
    /// Rapaport (2002) section III, reduced units.
    Rapaport,
}

/// Contact model and global physical constants.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Contact model family (`"rapaport"`).
    pub family: Family,
    /// Gravitational acceleration along `-y`.
    pub gravity: f64,
    /// Normal damping coefficient `gamma_n` (Rapaport eq. 2), the same for every pair and wall.
    pub gamma_n: f64,
    /// The larger static friction coefficient of each pair of `mu` values (Rapaport: 0.5);
    /// the others follow the ratio of the corresponding `gamma_s`.
    #[serde(default = "default_mu_max")]
    pub mu_max: f64,
    /// Diameter associated with the walls (Rapaport: 1).
    #[serde(default = "default_wall_diameter")]
    pub wall_diameter: f64,
    /// Material density; particle mass is `density * pi/6 * d^3` (Rapaport: `m = d^3`, i.e. `6/pi`).
    #[serde(default = "default_density")]
    pub density: f64,
}

fn default_mu_max() -> f64 {
    0.5
}
fn default_wall_diameter() -> f64 {
    1.0
}
fn default_density() -> f64 {
    6.0 / std::f64::consts::PI
}

/// One particle species.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Species {
    /// Name used in outputs (e.g. `"small"`, `"big"`).
    pub name: String,
    /// Nominal (largest) diameter `d`.
    pub diameter: f64,
    /// Diameters are uniform in `[d - spread, d]` (Rapaport: 0.2).
    #[serde(default)]
    pub diameter_spread: f64,
    /// Sliding friction coefficient against the same species, `gamma_s^{cc}`.
    pub gamma_s: f64,
    /// Sliding friction coefficient against the walls, `gamma_s^{cw}`.
    pub gamma_s_wall: f64,
    /// Static friction against the same species; default from the `mu` ratio rule.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Static friction against the walls; default from the `mu` ratio rule.
    #[serde(default)]
    pub mu_wall: Option<f64>,
}

/// How species are laid out in the initial state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Arrangement {
    /// Equal numbers of each species, assigned at random.
    Mixed,
    /// Alternating axial bands of pure species (`bands` of them; 2 = halves).
    Segregated,
}

/// Initial-state method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum InitKind {
    /// fcc lattice of number density `density` filling the drum (Rapaport IV).
    Lattice,
}

/// The initial state.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Init {
    /// Method (`"lattice"`).
    pub kind: InitKind,
    /// Number density `rho` of the fcc lattice (for the smallest species' bands).
    pub density: f64,
    /// `"mixed"` or `"segregated"`.
    pub arrangement: Arrangement,
    /// Number of bands of a segregated start, alternating from species 0 at `z = -L/2`.
    #[serde(default = "default_bands")]
    pub bands: usize,
    /// Speed of the random initial velocities (uniform random directions).
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// Minimum distance of lattice sites from the curved wall and the end caps.
    #[serde(default = "default_wall_gap")]
    pub wall_gap: f64,
}

fn default_bands() -> usize {
    2
}
fn default_speed() -> f64 {
    1.0
}
fn default_wall_gap() -> f64 {
    1.75
}

/// Run length and stepping.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Run {
    /// Length of the run in drum rotations.
    pub rotations: f64,
    /// Time step.
    pub dt: f64,
    /// Verlet skin added to the interaction range in the neighbour lists.
    #[serde(default = "default_skin")]
    pub skin: f64,
}

fn default_skin() -> f64 {
    0.5
}

/// Outputs.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Interval between samples of the axial profiles, in rotations.
    #[serde(default = "default_sample_every")]
    pub sample_every: f64,
    /// Thickness of the axial slices of the profiles.
    #[serde(default = "default_slice_width")]
    pub slice_width: f64,
    /// Interval between progress messages, in rotations.
    #[serde(default = "default_progress_every")]
    pub progress_every: f64,
}

fn default_sample_every() -> f64 {
    0.5
}
fn default_slice_width() -> f64 {
    1.0
}
fn default_progress_every() -> f64 {
    1.0
}

impl Default for Output {
    fn default() -> Self {
        Output {
            sample_every: default_sample_every(),
            slice_width: default_slice_width(),
            progress_every: default_progress_every(),
        }
    }
}
