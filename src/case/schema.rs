//! The case file: every key a run is described by, with its default.
//!
//! The structs mirror the TOML layout one to one; unknown keys are refused by serde
//! (`deny_unknown_fields`) so a misspelled key never silently falls back to a default.

use serde::{Deserialize, Serialize};

impl Case {
    /// Whether a run of `other` is a run of this case: every key the same but the title
    /// (comments are not part of the parsed case either).
    pub fn same_run_as(&self, other: &Case) -> bool {
        let untitled = |c: &Case| {
            format!(
                "{:?}",
                Case {
                    title: String::new(),
                    ..c.clone()
                }
            )
        };
        untitled(self) == untitled(other)
    }

    /// Interval between thermo lines, in rotations: `output.thermo_every`, or a tenth of
    /// `run.rotations` but at most one rotation.
    pub fn thermo_every(&self) -> f64 {
        self.output
            .thermo_every
            .unwrap_or_else(|| (0.1 * self.run.rotations).min(1.0))
    }

    /// Largest nominal diameter.
    pub fn d_max(&self) -> f64 {
        self.species.iter().map(|s| s.diameter).fold(0.0, f64::max)
    }

    /// Smallest nominal diameter.
    pub fn d_min(&self) -> f64 {
        self.species
            .iter()
            .map(|s| s.diameter)
            .fold(f64::MAX, f64::min)
    }

    /// The time step: `run.dt`, or `t_c / 40` for the linear spring-dashpot.
    pub fn dt(&self) -> f64 {
        self.run
            .dt
            .or_else(|| self.model.collision_time.map(|t| t / 40.0))
            .unwrap_or(f64::NAN)
    }

    /// The Verlet skin: `run.skin`, or `d_max (0.25 + 10 omega R dt / d_max)` clamped to
    /// `[0.25, 0.5] d_max`. Results do not depend on it (a test); speed and memory do.
    pub fn skin(&self) -> f64 {
        // A quarter of the largest diameter, more where the wall moves far in a step (lists
        // are then rebuilt often): 0.26 d for the thesis' drums, 0.40 d for Rapaport's.
        self.run.skin.unwrap_or_else(|| {
            let d = self.d_max();
            let per_step = self.drum.omega.abs() * 0.5 * self.drum.diameter * self.dt() / d;
            let f = 0.25 + 10.0 * per_step;
            d * if f.is_finite() {
                f.clamp(0.25, 0.5)
            } else {
                0.4
            }
        })
    }

    /// Bins of the binned fields along `x`, `y`, `z`: `diagnostics.fields.grid`, or as many
    /// as fit bins at least the largest diameter wide across the drum's diameter and axial
    /// length, at most [`FIELD_GRID_MAX`] (a particle counts whole in the bin of its centre,
    /// so narrower bins give a speckled map whose volume fraction exceeds 1).
    pub fn field_grid(&self) -> [usize; 3] {
        self.diagnostics.fields.grid.unwrap_or_else(|| {
            let d = self.d_max();
            let extent = [
                self.drum.diameter,
                self.drum.diameter,
                self.drum.axial_length(),
            ];
            let mut n = [1; 3];
            for k in 0..3 {
                let fit = extent[k] / d;
                n[k] = if fit.is_finite() && fit >= 1.0 {
                    (fit.floor() as usize).min(FIELD_GRID_MAX[k])
                } else {
                    1
                };
            }
            n
        })
    }

    /// Thickness of the axial slices: `output.slice_width`, or the smallest diameter.
    pub fn slice_width(&self) -> f64 {
        self.output.slice_width.unwrap_or(self.d_min())
    }
}

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
    /// Coefficients of pairs of species that override the mixing rules (`[[pairs]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pairs: Vec<PairOverride>,
    /// How the drum is filled at time zero.
    pub init: Init,
    /// Length of the run and time stepping.
    pub run: Run,
    /// What is written, and how often.
    #[serde(default)]
    pub output: Output,
    /// Diagnostics beyond the axial profiles: fluxes, fields, bands, paths, snapshots.
    #[serde(default)]
    pub diagnostics: Diagnostics,
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

/// Shape of the tumbler.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// A cylinder along `z`.
    #[default]
    Cylinder,
    /// A sphere (axial slabs along `z` all the same).
    Sphere,
    /// A cone (frustum) along `z`, capped: diameter `diameter` at `z = -L/2`, narrowing
    /// linearly to `diameter_high` at `z = +L/2`.
    Cone,
}

/// Surface of an end cap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CapSurface {
    /// With the species' cap friction.
    #[default]
    Frictional,
    /// No tangential force (lateral confinement only).
    Frictionless,
}

/// The drum: axis `z`, centred at the origin, turning about `+z`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Drum {
    /// `"cylinder"` (default), `"sphere"` or `"cone"`.
    #[serde(default)]
    pub shape: Shape,
    /// Inner diameter `D` of the curved wall (of the sphere; of a cone at `z = -L/2`, its
    /// widest).
    pub diameter: f64,
    /// A cone's inner diameter at `z = +L/2` (at most `diameter`).
    #[serde(default)]
    pub diameter_high: Option<f64>,
    /// Length `L` of a cylinder or cone along the axis (from `-L/2` to `L/2`); a sphere has
    /// none.
    #[serde(default)]
    pub length: Option<f64>,
    /// `"periodic"` or `"capped"` (cylinders only).
    #[serde(default)]
    pub ends: Option<Ends>,
    /// Angular velocity about `+z` (rad per time unit; counterclockwise seen from `+z`).
    pub omega: f64,
    /// The end cap at `z = -L/2`: `"frictional"` (default) or `"frictionless"`.
    #[serde(default)]
    pub cap_low: CapSurface,
    /// The end cap at `z = +L/2`.
    #[serde(default)]
    pub cap_high: CapSurface,
    /// An optional rough curved wall: particles fixed to the turning drum (thesis ch. 3).
    #[serde(default)]
    pub rough_wall: Option<RoughWall>,
    /// Flat lifters fixed to a cylinder's curved wall, turning with it.
    #[serde(default)]
    pub lifters: Option<DrumLifters>,
}

/// Lifters (flights, baffles): flat plates along the axis fixed to the curved wall, equally
/// spaced in angle, turning with the drum (`physics/walls/lifters.rs`).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DrumLifters {
    /// How many, equally spaced in angle.
    pub count: u32,
    /// Radial height from the wall inward (to the lifter's innermost point).
    pub height: f64,
    /// Thickness of a plate (its edges are rounded with half of it).
    pub thickness: f64,
    /// Axial span `[low, high]` (default: the whole drum).
    #[serde(default)]
    pub span: Option<[f64; 2]>,
    /// Angle of the first lifter at time zero, from `+x` towards `+y` (radians, default 0).
    #[serde(default)]
    pub angle: f64,
}

/// A curved wall roughened by particles fixed to it: rings of spheres centred on the wall
/// surface, one diameter apart along the axis and around, alternate rings staggered.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RoughWall {
    /// Diameter of the wall particles.
    pub diameter: f64,
}

impl Drum {
    /// Axial extent: `L` for a cylinder, `D` for a sphere.
    pub fn axial_length(&self) -> f64 {
        match self.shape {
            Shape::Cylinder | Shape::Cone => self.length.unwrap_or(0.0),
            Shape::Sphere => self.diameter,
        }
    }

    /// Whether the axial ends are periodic.
    pub fn periodic(&self) -> bool {
        self.shape == Shape::Cylinder && self.ends == Some(Ends::Periodic)
    }

    /// Volume inside the walls (less the lifters').
    pub fn volume(&self) -> f64 {
        crate::physics::DrumWalls::of(self).volume()
    }
}

/// Contact model families.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// Rapaport (2002) section III, reduced units.
    Rapaport,
    /// Spring-dashpot models of the thesis (ch. 2), SI units.
    SpringDashpot,
}

/// Normal force of the spring-dashpot family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Normal {
    /// Linear spring and dashpot from the pair's collision time and restitution (eqs. 2.4-2.12).
    #[default]
    Linear,
    /// Hertz spring with its non-linear damping (eqs. 2.13-2.14).
    Hertz,
}

/// Tangential force of the spring-dashpot family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Tangential {
    /// Viscous friction capped by Coulomb, no memory (eq. 2.15).
    #[default]
    Viscous,
    /// Cundall-Strack spring on the accumulated tangential displacement (eqs. 2.17-2.18).
    History,
}

/// Rolling resistance of the spring-dashpot family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Rolling {
    /// No rolling resistance.
    #[default]
    None,
    /// A torque `mu_r R_eff |F_n|` against the rolling (LIGGGHTS `rolling_friction cdt`).
    Constant,
    /// `-min(eta |omega_r|, mu_r R_eff |F_n|)` along the rolling (`rolling_viscosity` = eta).
    Viscous,
    /// Spring-dashpot-slider (Ai et al. 2011, model C; LAMMPS `rolling sds`).
    Sds,
}

/// Cohesion of the spring-dashpot family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Cohesion {
    /// No cohesion.
    #[default]
    None,
    /// Simplified JKR (LIGGGHTS `cohesion sjkr`): `k_c` times the contact area.
    Sjkr,
}

/// Contact model and global physical constants.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Contact model family (`"rapaport"` or `"spring-dashpot"`).
    pub family: Family,
    /// Gravitational acceleration along `-y`.
    pub gravity: f64,
    /// Rapaport: normal damping coefficient `gamma_n` (eq. 2), the same for every pair and wall.
    #[serde(default)]
    pub gamma_n: Option<f64>,
    /// Spring-dashpot: `"linear"` (default) or `"hertz"`.
    #[serde(default)]
    pub normal: Normal,
    /// Spring-dashpot: `"viscous"` (default, no memory) or `"history"` (Cundall-Strack).
    #[serde(default)]
    pub tangential: Tangential,
    /// Spring-dashpot, linear: binary collision time `t_c` (s).
    #[serde(default)]
    pub collision_time: Option<f64>,
    /// Spring-dashpot: normal restitution coefficient `e_n` (linear), in (0, 1].
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Spring-dashpot, history: `k_s / k_n` (default 2/7).
    #[serde(default = "default_stiffness_ratio")]
    pub stiffness_ratio: f64,
    /// Spring-dashpot, viscous: tangential coefficient `gamma_s` (kg/s). The thesis gives no
    /// value; by default each pair uses its normal dashpot coefficient `2 gamma_n m_eff`.
    #[serde(default)]
    pub gamma_s: Option<f64>,
    /// Spring-dashpot: rolling resistance, `"none"` (default), `"constant"`, `"viscous"` or
    /// `"sds"`; each species' `mu_roll` sets its limit.
    #[serde(default)]
    pub rolling: Rolling,
    /// Rolling `"viscous"`: rolling viscosity `eta` (N m s in SI cases).
    #[serde(default)]
    pub rolling_viscosity: Option<f64>,
    /// Rolling `"sds"`: rolling stiffness `k_r / (mu_r^2 k_n)` (default 2.25, Iwashita & Oda).
    #[serde(default = "default_rolling_stiffness")]
    pub rolling_stiffness: f64,
    /// Rolling `"sds"`: rolling dashpot as a fraction of critical damping (default 0.3, Ai et
    /// al. 2011).
    #[serde(default = "default_rolling_damping")]
    pub rolling_damping: f64,
    /// Spring-dashpot: cohesion, `"none"` (default) or `"sjkr"`; each species'
    /// `cohesion_energy` sets its strength.
    #[serde(default)]
    pub cohesion: Cohesion,
    /// Spring-dashpot, Hertz: Young's modulus `Y` (Pa).
    #[serde(default)]
    pub youngs_modulus: Option<f64>,
    /// Spring-dashpot, Hertz: Poisson ratio `nu`.
    #[serde(default)]
    pub poisson_ratio: Option<f64>,
    /// Spring-dashpot, Hertz: damping coefficient `gamma_n^n` of eq. 2.14 (kg / (m^1/2 s)).
    #[serde(default)]
    pub hertz_damping: Option<f64>,
    /// The larger static friction coefficient of each pair of `mu` values (Rapaport: 0.5);
    /// the others follow the ratio of the corresponding `gamma_s`.
    #[serde(default = "default_mu_max")]
    pub mu_max: f64,
    /// Diameter associated with the walls (Rapaport: 1).
    #[serde(default = "default_wall_diameter")]
    pub wall_diameter: f64,
    /// Material density; particle mass is `density * pi/6 * d^3` (Rapaport: `m = d^3`, i.e.
    /// `6/pi`; glass: 2500 kg/m^3).
    #[serde(default = "default_density")]
    pub density: f64,
}

fn default_stiffness_ratio() -> f64 {
    2.0 / 7.0
}

fn default_rolling_stiffness() -> f64 {
    2.25
}

fn default_rolling_damping() -> f64 {
    0.3
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
    /// Diameters are normal with mean `d` and this standard deviation relative to `d`
    /// (thesis: 0.1), cut at three standard deviations. Exclusive with `diameter_spread`.
    #[serde(default)]
    pub diameter_sd: f64,
    /// Rapaport: sliding friction coefficient against the same species, `gamma_s^{cc}`.
    #[serde(default)]
    pub gamma_s: Option<f64>,
    /// Rapaport: sliding friction coefficient against the walls, `gamma_s^{cw}`.
    #[serde(default)]
    pub gamma_s_wall: Option<f64>,
    /// Static friction against the same species (Rapaport: default from the `mu` ratio rule;
    /// spring-dashpot: required). A mixed pair takes the smaller of the two.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Static friction against the curved wall (Rapaport: from the ratio rule;
    /// spring-dashpot: default `mu`).
    #[serde(default)]
    pub mu_wall: Option<f64>,
    /// Static friction against the end caps (default `mu_wall`).
    #[serde(default)]
    pub mu_cap: Option<f64>,
    /// Rolling friction coefficient against the same species (with `model.rolling`; default
    /// 0). A mixed pair takes the smaller of the two.
    #[serde(default)]
    pub mu_roll: Option<f64>,
    /// Rolling friction coefficient against the walls and caps (default `mu_roll`).
    #[serde(default)]
    pub mu_roll_wall: Option<f64>,
    /// Cohesion energy density `k_c` against the same species (with `model.cohesion`; J/m^3
    /// in SI cases; default 0). A mixed pair takes the geometric mean `sqrt(k_a k_b)`.
    #[serde(default)]
    pub cohesion_energy: Option<f64>,
    /// Cohesion energy density against the walls and caps (default `cohesion_energy`).
    #[serde(default)]
    pub cohesion_energy_wall: Option<f64>,
    /// Linear spring-dashpot: restitution `e_n` against the same species (default
    /// `model.restitution`). A mixed pair takes the geometric mean `sqrt(e_a e_b)`.
    #[serde(default)]
    pub restitution: Option<f64>,
    /// Linear spring-dashpot: restitution against the walls and caps (default `restitution`).
    #[serde(default)]
    pub restitution_wall: Option<f64>,
    /// Hertz: Young's modulus `Y` of the species (default `model.youngs_modulus`); a pair
    /// takes the effective modulus `1/Y* = (1 - nu_a^2)/Y_a + (1 - nu_b^2)/Y_b`, a wall is
    /// of the species' material.
    #[serde(default)]
    pub youngs_modulus: Option<f64>,
    /// Hertz: Poisson ratio `nu` of the species (default `model.poisson_ratio`).
    #[serde(default)]
    pub poisson_ratio: Option<f64>,
    /// Share of the particle volume of a poured fill (pour only; shares must add up to 1).
    #[serde(default)]
    pub volume_fraction: Option<f64>,
}

/// The coefficients of one unordered pair of species, overriding the mixing rules
/// (`[[pairs]]`); a coefficient not given follows the rule.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PairOverride {
    /// The names of the two species (the same name twice: the pair of one species).
    pub species: Vec<String>,
    /// Static friction coefficient of the pair.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Rolling friction coefficient of the pair (with `model.rolling`).
    #[serde(default)]
    pub mu_roll: Option<f64>,
    /// Cohesion energy density of the pair (with `model.cohesion`).
    #[serde(default)]
    pub cohesion_energy: Option<f64>,
    /// Restitution of the pair (linear spring-dashpot), in (0, 1].
    #[serde(default)]
    pub restitution: Option<f64>,
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
    /// Random points grown to their diameters, settled in the still drum and cut to the fill
    /// level (thesis 2.2.2).
    Pour,
    /// An explicit list of particles (`[[init.particle]]` tables or an HDF5 `file`).
    Particles,
}

/// One particle given explicitly in the case.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitParticle {
    /// Species index.
    pub species: u8,
    /// Diameter.
    pub diameter: f64,
    /// Position.
    pub position: [f64; 3],
    /// Velocity.
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Angular velocity.
    #[serde(default)]
    pub angular_velocity: [f64; 3],
}

/// The initial state.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Init {
    /// Method: `"lattice"`, `"pour"` or `"particles"`.
    pub kind: InitKind,
    /// Lattice: number density `rho` of the fcc lattice (for the smallest species' bands).
    #[serde(default)]
    pub density: Option<f64>,
    /// Lattice: `"mixed"` (default) or `"segregated"`.
    #[serde(default = "default_arrangement")]
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
    /// Pour: fill level, the fraction of the drum volume below the flat cut surface.
    #[serde(default)]
    pub fill: Option<f64>,
    /// Pour: time to grow the points to their diameters, without gravity (default 50 `t_c`).
    #[serde(default)]
    pub grow_time: Option<f64>,
    /// Pour: time to settle under gravity before the cut (default `10 sqrt(D/g)`).
    #[serde(default)]
    pub settle_time: Option<f64>,
    /// Particles: HDF5 file with the `/particles` layout of a run's output.
    #[serde(default)]
    pub file: Option<String>,
    /// Particles: the particles themselves (`[[init.particle]]`).
    #[serde(default)]
    pub particle: Vec<ExplicitParticle>,
}

fn default_arrangement() -> Arrangement {
    Arrangement::Mixed
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
    /// Time step (spring-dashpot, linear: default `t_c / 40`).
    #[serde(default)]
    pub dt: Option<f64>,
    /// Verlet skin added to the interaction range in the neighbour lists (default: a quarter
    /// of the largest diameter, up to a half where the wall moves far in a step).
    #[serde(default)]
    pub skin: Option<f64>,
    /// Largest overlap of two particles, as a fraction of the smaller diameter, before the
    /// run stops as unhealthy.
    #[serde(default = "default_max_overlap")]
    pub max_overlap: f64,
    /// Interval between load-balance checks, in rotations (the slab boundaries move when
    /// the work per rank is uneven).
    #[serde(default = "default_balance_every")]
    pub balance_every: f64,
    /// Largest accepted imbalance (max / mean work per rank) before the boundaries move.
    #[serde(default = "default_balance_tolerance")]
    pub balance_tolerance: f64,
    /// Steps between spatial sorts of the particles (`engine::order`), which keep the pair
    /// loop's memory accesses local as the bed mixes; 0 never sorts (the order of the ids).
    /// A performance setting, but one that changes the order of the force sums, so runs
    /// with different values differ in the last bits.
    #[serde(default = "default_sort_every")]
    pub sort_every: u64,
}

fn default_sort_every() -> u64 {
    1000
}

fn default_balance_every() -> f64 {
    1.0
}
fn default_balance_tolerance() -> f64 {
    1.05
}
fn default_max_overlap() -> f64 {
    0.25
}

/// Outputs.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Interval between samples of the axial profiles, in rotations.
    #[serde(default = "default_sample_every")]
    pub sample_every: f64,
    /// Thickness of the axial slices of the profiles (default: the smallest nominal diameter).
    #[serde(default)]
    pub slice_width: Option<f64>,
    /// Interval between progress messages, in rotations.
    #[serde(default = "default_progress_every")]
    pub progress_every: f64,
    /// Interval between checkpoints, in rotations (one is always written at the end).
    #[serde(default)]
    pub checkpoint_every: Option<f64>,
    /// Interval between thermo lines in the log, in rotations (default: a tenth of
    /// `run.rotations`, at most one rotation; see [`Case::thermo_every`]).
    #[serde(default)]
    pub thermo_every: Option<f64>,
}

fn default_sample_every() -> f64 {
    0.5
}
fn default_progress_every() -> f64 {
    1.0
}

impl Default for Output {
    fn default() -> Self {
        Output {
            sample_every: default_sample_every(),
            slice_width: None,
            progress_every: default_progress_every(),
            checkpoint_every: None,
            thermo_every: None,
        }
    }
}

/// Diagnostics computed in the run (definitions in `docs/diagnostics.md`).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Diagnostics {
    /// Interval between samples of the windowed diagnostics (surface angle, slice fluxes,
    /// binned fields), in rotations.
    #[serde(default = "default_diag_every")]
    pub sample_every: f64,
    /// Averaging window of the per-slice fluxes, diffusivity and angles, in rotations.
    #[serde(default = "default_window")]
    pub window: f64,
    /// Fixed angle of the surface frame in degrees (default: measured at every sample).
    #[serde(default)]
    pub surface_angle: Option<f64>,
    /// Binned fields.
    #[serde(default)]
    pub fields: Fields,
    /// Band counting.
    #[serde(default)]
    pub bands: Bands,
    /// Particle paths.
    #[serde(default)]
    pub paths: Paths,
    /// Snapshots of every particle.
    #[serde(default)]
    pub snapshots: Snapshots,
}

fn default_diag_every() -> f64 {
    0.02
}
fn default_window() -> f64 {
    1.0
}

impl Default for Diagnostics {
    fn default() -> Self {
        Diagnostics {
            sample_every: default_diag_every(),
            window: default_window(),
            surface_angle: None,
            fields: Fields::default(),
            bands: Bands::default(),
            paths: Paths::default(),
            snapshots: Snapshots::default(),
        }
    }
}

/// The cuboid grid of binned fields in the surface frame.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Fields {
    /// Bins along `x` (streamwise), `y` (surface normal) and `z` (axis); the per-slice fluxes
    /// use the first two on every axial slice. Default: [`Case::field_grid`], bins no
    /// narrower than the largest particle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<[usize; 3]>,
    /// Averaging window in rotations.
    #[serde(default = "default_field_window")]
    pub window: f64,
}

fn default_field_window() -> f64 {
    10.0
}

/// The most bins along `x`, `y` and `z` a default field grid has.
pub const FIELD_GRID_MAX: [usize; 3] = [40, 40, 16];

impl Default for Fields {
    fn default() -> Self {
        Fields {
            grid: None,
            window: default_field_window(),
        }
    }
}

/// How bands are counted in the axial profiles.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Bands {
    /// Departure of the big species' volume fraction from its drum mean that marks a band.
    #[serde(default = "default_band_threshold")]
    pub threshold: f64,
    /// Narrowest band counted, as a length (default: two largest diameters).
    #[serde(default)]
    pub min_width: Option<f64>,
}

fn default_band_threshold() -> f64 {
    0.2
}

impl Default for Bands {
    fn default() -> Self {
        Bands {
            threshold: default_band_threshold(),
            min_width: None,
        }
    }
}

/// Particles whose paths are recorded.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Paths {
    /// Ids of particles to follow.
    #[serde(default)]
    pub ids: Vec<u64>,
    /// Boxes (lab frame); the particles whose centres lie in one at the start are followed.
    #[serde(default)]
    pub regions: Vec<Region>,
    /// Interval between path samples in rotations (default: `diagnostics.sample_every`).
    #[serde(default)]
    pub every: Option<f64>,
}

/// An axis-aligned box in the lab frame.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// Lower corner.
    pub min: [f64; 3],
    /// Upper corner.
    pub max: [f64; 3],
}

/// Snapshots of every particle.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Snapshots {
    /// Interval in rotations (none by default).
    #[serde(default)]
    pub every: Option<f64>,
}
