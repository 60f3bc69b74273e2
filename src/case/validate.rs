//! Semantic checks of a parsed case: every impossible value is refused with the key that
//! holds it and the reason, all of them at once.

use super::load::CaseError;
use super::schema::{
    Arrangement, Case, Cohesion, Ends, Family, InitKind, Normal, Rolling, Shape, Tangential,
};
use crate::physics::law;

/// Fewest time steps per drum rotation accepted: a wall that turns more than 1/20 of a turn
/// in a step is not resolved (and the run length, counted in rotations, is then meaningless).
pub const STEPS_PER_ROTATION_MIN: f64 = 20.0;

/// Most time steps a run may have (`run.rotations` rotations of `2 pi / (|omega| dt)` steps):
/// 10^12 steps is years of computing even for a handful of particles; a longer run is a typo
/// (`run.dt = 1e-300`, `run.rotations = 1e30`), not a plan.
pub const STEPS_MAX: f64 = 1e12;

/// Most memory the initial state may take on one rank, in bytes: 16 GiB, about 2.4e7
/// particles at `report::memory_estimate`'s bytes per particle (about 700 without contact
/// histories; the largest case of cases/ has 9e4).
/// Each rank makes only its own slab's part. Checked by [`initial_memory`] on the estimate
/// of [`estimated_particles`] before anything is allocated.
pub const INITIAL_MEMORY_MAX: f64 = 16.0 * (1u64 << 30) as f64;

/// Most samples (of the axial profiles, diagnostics, paths, snapshots) or checkpoints a run
/// may write: an interval so short that more are asked for fills the disk.
pub const SAMPLES_MAX: f64 = 1e7;

/// Most axial slices of the profiles (`drum length / output.slice_width`).
pub const SLICES_MAX: f64 = 1e6;

struct Checker {
    errs: Vec<CaseError>,
    /// Keys already refused as not finite: no second message for them.
    not_finite: Vec<String>,
}

impl Checker {
    fn bad(&mut self, key: &str, why: String) {
        if self.not_finite.iter().any(|k| k == key) {
            return;
        }
        self.errs.push(CaseError::new(key, why));
    }
    fn positive(&mut self, key: &str, x: f64) {
        if !(x.is_finite() && x > 0.0) {
            self.bad(key, format!("must be positive, got {x}"));
        }
    }
    fn non_negative(&mut self, key: &str, x: f64) {
        if !(x.is_finite() && x >= 0.0) {
            self.bad(key, format!("must be zero or positive, got {x}"));
        }
    }
    /// A sub-model's coefficient: zero or positive when `on`, refused when given while
    /// `model_key` is "none".
    fn sub_model_value(&mut self, key: &str, x: Option<f64>, on: bool, model_key: &str) {
        match (x, on) {
            (Some(v), true) => self.non_negative(key, v),
            (Some(_), false) => self.bad(
                key,
                format!("has no effect without {model_key} (it is \"none\")"),
            ),
            (None, _) => {}
        }
    }
    fn required(&mut self, key: &str, x: Option<f64>, why: &str) -> f64 {
        match x {
            Some(v) if v.is_finite() => v,
            Some(_) => f64::NAN, // refused by `finite_numbers`
            None => {
                self.bad(key, format!("is required {why}"));
                f64::NAN
            }
        }
    }
    fn restitution(&mut self, key: &str, e: f64) {
        if !(e > 0.0 && e <= 1.0) {
            self.bad(key, format!("must be in (0, 1], got {e}"));
        }
    }
    fn forbidden<T>(&mut self, key: &str, x: &Option<T>, why: &str) {
        if x.is_some() {
            self.bad(key, format!("does not apply {why}"));
        }
    }
}

/// Check every value of `case`; return all refusals.
pub fn validate(case: &Case) -> Result<(), Vec<CaseError>> {
    let mut c = Checker {
        errs: Vec::new(),
        not_finite: Vec::new(),
    };
    finite_numbers(case, &mut c);
    let d = &case.drum;
    c.positive("drum.diameter", d.diameter);
    match d.shape {
        Shape::Cylinder => {
            let l = c.required("drum.length", d.length, "for a cylinder");
            if !l.is_nan() {
                c.positive("drum.length", l);
            }
            if d.ends.is_none() {
                c.bad(
                    "drum.ends",
                    "is required for a cylinder: \"periodic\" or \"capped\"".into(),
                );
            }
        }
        Shape::Sphere => {
            c.forbidden(
                "drum.length",
                &d.length,
                "to a sphere (its axial extent is its diameter)",
            );
            c.forbidden("drum.ends", &d.ends, "to a sphere");
        }
        // other shapes' keys are checked with their vessel (physics/walls/)
        _ => {}
    }
    let wall_reach = {
        let largest = case
            .species
            .iter()
            .map(law::largest_diameter)
            .fold(0.0, f64::max);
        law::ContactLaw::new(case).wall_reach(largest)
    };
    for (key, why) in crate::physics::walls::check(d, wall_reach) {
        c.bad(&key, why);
    }
    if let Some(rw) = &d.rough_wall {
        if !(rw.diameter.is_finite() && rw.diameter > 0.0 && rw.diameter < 0.25 * d.diameter) {
            c.bad(
                "drum.rough_wall.diameter",
                format!("must be positive and below D/4, got {}", rw.diameter),
            );
        }
        if d.shape == Shape::Sphere {
            c.bad(
                "drum.rough_wall",
                "a rough wall lines a cylinder's curved wall; a sphere has none".into(),
            );
        }
    }
    if !d.omega.is_finite() || d.omega == 0.0 {
        c.bad(
            "drum.omega",
            format!(
                "must be non-zero (the run length is counted in rotations), got {}",
                d.omega
            ),
        );
    }

    let m = &case.model;
    c.non_negative("model.gravity", m.gravity);
    c.positive("model.density", m.density);
    match m.family {
        Family::Rapaport => {
            let g = c.required("model.gamma_n", m.gamma_n, "by the rapaport family");
            if !g.is_nan() {
                c.non_negative("model.gamma_n", g);
            }
            c.non_negative("model.mu_max", m.mu_max);
            c.positive("model.wall_diameter", m.wall_diameter);
            let why = "to the rapaport family";
            c.forbidden("model.collision_time", &m.collision_time, why);
            c.forbidden("model.restitution", &m.restitution, why);
            c.forbidden("model.gamma_s", &m.gamma_s, why);
            c.forbidden("model.youngs_modulus", &m.youngs_modulus, why);
            if m.normal != Normal::Linear || m.tangential != Tangential::Viscous {
                c.bad(
                    "model.normal",
                    "normal/tangential choose spring-dashpot laws; the rapaport family has its own"
                        .into(),
                );
            }
            if m.rolling != Rolling::None {
                c.bad(
                    "model.rolling",
                    "rolling resistance is a sub-model of the spring-dashpot family".into(),
                );
            }
            if m.cohesion != Cohesion::None {
                c.bad(
                    "model.cohesion",
                    "cohesion is a sub-model of the spring-dashpot family".into(),
                );
            }
        }
        Family::SpringDashpot => {
            c.forbidden(
                "model.gamma_n",
                &m.gamma_n,
                "to the spring-dashpot family (use restitution and collision_time)",
            );
            let e = c.required(
                "model.restitution",
                m.restitution,
                "by the spring-dashpot family",
            );
            if !(e.is_nan() || (e > 0.0 && e <= 1.0)) {
                c.bad("model.restitution", format!("must be in (0, 1], got {e}"));
            }
            match m.normal {
                Normal::Linear => {
                    let t = c.required(
                        "model.collision_time",
                        m.collision_time,
                        "by the linear normal force",
                    );
                    if !t.is_nan() {
                        c.positive("model.collision_time", t);
                    }
                }
                Normal::Hertz => {
                    let y = c.required(
                        "model.youngs_modulus",
                        m.youngs_modulus,
                        "by the Hertz normal force",
                    );
                    let nu = c.required(
                        "model.poisson_ratio",
                        m.poisson_ratio,
                        "by the Hertz normal force",
                    );
                    let g = c.required(
                        "model.hertz_damping",
                        m.hertz_damping,
                        "by the Hertz normal force",
                    );
                    if !y.is_nan() {
                        c.positive("model.youngs_modulus", y);
                    }
                    if !(nu.is_nan() || (-1.0 < nu && nu < 0.5)) {
                        c.bad(
                            "model.poisson_ratio",
                            format!("must be in (-1, 0.5), got {nu}"),
                        );
                    }
                    if !g.is_nan() {
                        c.non_negative("model.hertz_damping", g);
                    }
                    if case.run.dt.is_none() {
                        c.bad("run.dt", "is required with the Hertz normal force (its contact time depends on the impact speed)".into());
                    }
                }
            }
            if m.tangential == Tangential::History {
                c.positive("model.stiffness_ratio", m.stiffness_ratio);
                c.forbidden(
                    "model.gamma_s",
                    &m.gamma_s,
                    "to the history tangential force",
                );
            }
            if let Some(g) = m.gamma_s {
                c.non_negative("model.gamma_s", g);
            }
            match m.rolling {
                Rolling::Viscous => {
                    let eta = c.required(
                        "model.rolling_viscosity",
                        m.rolling_viscosity,
                        "by the viscous rolling resistance",
                    );
                    if !eta.is_nan() {
                        c.non_negative("model.rolling_viscosity", eta);
                    }
                }
                other => c.forbidden(
                    "model.rolling_viscosity",
                    &m.rolling_viscosity,
                    if other == Rolling::Sds {
                        "to the sds rolling resistance (see rolling_stiffness, rolling_damping)"
                    } else {
                        "except with rolling = \"viscous\""
                    },
                ),
            }
            if m.rolling == Rolling::Sds {
                c.positive("model.rolling_stiffness", m.rolling_stiffness);
                c.non_negative("model.rolling_damping", m.rolling_damping);
            }
        }
    }

    if case.species.is_empty() {
        c.bad("species", "at least one [[species]] table is needed".into());
    }
    if case.species.len() > 255 {
        c.bad(
            "species",
            format!("at most 255 species, got {}", case.species.len()),
        );
    }
    for (k, s) in case.species.iter().enumerate() {
        let key = |f: &str| format!("species.{k}.{f}");
        if s.name.trim().is_empty() {
            c.bad(&key("name"), "must not be empty".into());
        }
        if case.species[..k].iter().any(|o| o.name == s.name) {
            c.bad(&key("name"), format!("`{}` names two species", s.name));
        }
        if !(s.diameter.is_finite() && s.diameter > 0.0) {
            c.bad(
                &key("diameter"),
                format!("must be a positive length, got {}", s.diameter),
            );
        } else if d.diameter > 0.0 && s.diameter >= d.diameter {
            c.bad(
                &key("diameter"),
                format!(
                    "a particle of diameter {} does not fit in a drum of diameter {}",
                    s.diameter, d.diameter
                ),
            );
        }
        if !(s.diameter_spread.is_finite()
            && s.diameter_spread >= 0.0
            && s.diameter_spread < s.diameter)
        {
            c.bad(
                &key("diameter_spread"),
                format!(
                    "must be in [0, diameter) so that diameters stay positive, got {}",
                    s.diameter_spread
                ),
            );
        }
        if !(s.diameter_sd.is_finite() && (0.0..0.3).contains(&s.diameter_sd)) {
            c.bad(
                &key("diameter_sd"),
                format!("must be in [0, 0.3) (relative), got {}", s.diameter_sd),
            );
        }
        if s.diameter_sd > 0.0 && s.diameter_spread > 0.0 {
            c.bad(
                &key("diameter_sd"),
                "choose either diameter_sd (normal) or diameter_spread (uniform)".into(),
            );
        }
        match m.family {
            Family::Rapaport => {
                for (f, v) in [("gamma_s", s.gamma_s), ("gamma_s_wall", s.gamma_s_wall)] {
                    let v = c.required(&key(f), v, "by the rapaport family");
                    if !v.is_nan() {
                        c.non_negative(&key(f), v);
                    }
                }
            }
            Family::SpringDashpot => {
                let mu = c.required(&key("mu"), s.mu, "by the spring-dashpot family");
                if !mu.is_nan() {
                    c.non_negative(&key("mu"), mu);
                }
                let why = "to the spring-dashpot family (see model.gamma_s)";
                c.forbidden(&key("gamma_s"), &s.gamma_s, why);
                c.forbidden(&key("gamma_s_wall"), &s.gamma_s_wall, why);
            }
        }
        for (f, v) in [("mu", s.mu), ("mu_wall", s.mu_wall), ("mu_cap", s.mu_cap)] {
            if let Some(v) = v {
                c.non_negative(&key(f), v);
            }
        }
        let groups = [
            (
                m.rolling != Rolling::None,
                "model.rolling",
                [("mu_roll", s.mu_roll), ("mu_roll_wall", s.mu_roll_wall)],
            ),
            (
                m.cohesion != Cohesion::None,
                "model.cohesion",
                [
                    ("cohesion_energy", s.cohesion_energy),
                    ("cohesion_energy_wall", s.cohesion_energy_wall),
                ],
            ),
        ];
        for (on, model_key, group) in groups {
            for (f, v) in group {
                c.sub_model_value(&key(f), v, on, model_key);
            }
        }
        // the normal coefficients of a species: restitution for the linear law, the material
        // for Hertz
        let linear = m.family == Family::SpringDashpot && m.normal == Normal::Linear;
        let hertz = m.family == Family::SpringDashpot && m.normal == Normal::Hertz;
        for (f, v) in [
            ("restitution", s.restitution),
            ("restitution_wall", s.restitution_wall),
        ] {
            match v {
                Some(e) if linear => c.restitution(&key(f), e),
                Some(_) => c.bad(&key(f), not_linear(m.family).into()),
                None => {}
            }
        }
        match (s.youngs_modulus, hertz) {
            (Some(y), true) => c.positive(&key("youngs_modulus"), y),
            (Some(_), false) => c.bad(&key("youngs_modulus"), not_hertz(m.family).into()),
            (None, _) => {}
        }
        match (s.poisson_ratio, hertz) {
            (Some(nu), true) => {
                if !(-1.0 < nu && nu < 0.5) {
                    c.bad(
                        &key("poisson_ratio"),
                        format!("must be in (-1, 0.5), got {nu}"),
                    );
                }
            }
            (Some(_), false) => c.bad(&key("poisson_ratio"), not_hertz(m.family).into()),
            (None, _) => {}
        }
        if let Some(v) = s.volume_fraction {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                c.bad(
                    &key("volume_fraction"),
                    format!("must be in [0, 1], got {v}"),
                );
            }
        }
    }

    check_pairs(case, &mut c);

    let i = &case.init;
    match i.kind {
        InitKind::Lattice => {
            let rho = c.required("init.density", i.density, "by the lattice fill");
            if !rho.is_nan() {
                c.positive("init.density", rho);
            }
            if i.arrangement == Arrangement::Segregated && i.bands < 2 {
                c.bad(
                    "init.bands",
                    format!("a segregated start needs at least 2 bands, got {}", i.bands),
                );
            }
            let most = (d.axial_length() / case.d_max()).floor();
            if i.arrangement == Arrangement::Segregated
                && i.bands >= 2
                && !at_most(i.bands as f64, most)
            {
                c.bad(
                    "init.bands",
                    format!(
                        "{} bands of a drum {} long are thinner than the largest diameter {}; at most {most} fit",
                        i.bands,
                        d.axial_length(),
                        case.d_max()
                    ),
                );
            }
            c.non_negative("init.speed", i.speed);
            if !(i.wall_gap.is_finite() && i.wall_gap >= 0.0 && i.wall_gap < 0.5 * d.diameter) {
                c.bad(
                    "init.wall_gap",
                    format!(
                        "must be in [0, D/2) so that the lattice has room, got {}",
                        i.wall_gap
                    ),
                );
            }
            if d.shape != Shape::Cylinder {
                c.bad(
                    "init.kind",
                    "the lattice fill is for cylinders; use \"pour\" or \"particles\" in a sphere or a cone"
                        .into(),
                );
            }
        }
        InitKind::Pour => {
            let f = c.required("init.fill", i.fill, "by the pour fill");
            if !(f.is_nan() || (f > 0.0 && f < 1.0)) {
                c.bad(
                    "init.fill",
                    format!("must be in (0, 1) (a fraction of the drum volume), got {f}"),
                );
            }
            for (f, v) in [
                ("init.grow_time", i.grow_time),
                ("init.settle_time", i.settle_time),
            ] {
                if let Some(v) = v {
                    c.positive(f, v);
                }
            }
            let total: f64 = case
                .species
                .iter()
                .map(|s| s.volume_fraction.unwrap_or(f64::NAN))
                .sum();
            if case.species.len() == 1 && case.species[0].volume_fraction.is_none() {
                // a single species takes the whole volume
            } else if !(total - 1.0).abs().lt(&1e-9) {
                c.bad("species.N.volume_fraction", format!("the pour needs each species' volume_fraction, adding up to 1 (got {total})"));
            }
        }
        InitKind::Particles => {
            if i.file.is_some() != i.particle.is_empty() {
                c.bad(
                    "init.file",
                    "give either init.file or [[init.particle]] tables, not both or neither".into(),
                );
            }
            for (k, p) in i.particle.iter().enumerate() {
                if p.species as usize >= case.species.len() {
                    c.bad(
                        &format!("init.particle.{k}.species"),
                        format!("there is no species {}", p.species),
                    );
                }
                if !(p.diameter.is_finite() && p.diameter > 0.0) {
                    c.bad(
                        &format!("init.particle.{k}.diameter"),
                        format!("must be positive, got {}", p.diameter),
                    );
                }
            }
        }
    }

    if let Some(dt) = case.run.dt {
        c.positive("run.dt", dt);
    } else if !(m.family == Family::SpringDashpot && m.normal == Normal::Linear) {
        c.bad(
            "run.dt",
            "is required (only the linear spring-dashpot has a default, t_c/40)".into(),
        );
    }
    c.positive("run.rotations", case.run.rotations);
    if let Some(s) = case.run.skin {
        c.positive("run.skin", s);
    }
    if !(case.run.max_overlap > 0.0 && case.run.max_overlap < 1.0) {
        c.bad(
            "run.max_overlap",
            format!(
                "must be in (0, 1) (a fraction of the diameter), got {}",
                case.run.max_overlap
            ),
        );
    }

    c.positive("run.balance_every", case.run.balance_every);
    if !(case.run.balance_tolerance.is_finite() && case.run.balance_tolerance >= 1.0) {
        c.bad(
            "run.balance_tolerance",
            format!(
                "must be at least 1 (max / mean work per rank), got {}",
                case.run.balance_tolerance
            ),
        );
    }

    let o = &case.output;
    c.positive("output.sample_every", o.sample_every);
    c.positive("output.progress_every", o.progress_every);
    if let Some(k) = o.checkpoint_every {
        c.positive("output.checkpoint_every", k);
    }
    if let Some(k) = o.thermo_every {
        c.positive("output.thermo_every", k);
    }
    if let Some(w) = o.slice_width {
        if !(w.is_finite() && w > 0.0 && w <= d.axial_length()) {
            c.bad(
                "output.slice_width",
                format!("must be positive and at most the drum length, got {w}"),
            );
        }
    }
    check_diagnostics(case, &mut c);

    if c.errs.is_empty() {
        cross_checks(case, &mut c);
    }
    if c.errs.is_empty() {
        size_checks(case, &mut c);
    }
    if c.errs.is_empty() {
        Ok(())
    } else {
        Err(c.errs)
    }
}

/// Why a restitution of a species or pair does not apply to a run that is not of the linear
/// spring-dashpot law.
fn not_linear(family: Family) -> &'static str {
    match family {
        Family::Rapaport => "does not apply to the rapaport family (its damping is model.gamma_n)",
        Family::SpringDashpot => {
            "does not apply to the Hertz normal force (its damping is model.hertz_damping)"
        }
    }
}

/// Why a material constant of a species does not apply to a run without the Hertz law.
fn not_hertz(family: Family) -> &'static str {
    match family {
        Family::Rapaport => "does not apply to the rapaport family",
        Family::SpringDashpot => {
            "does not apply to the linear normal force (only with model.normal = \"hertz\")"
        }
    }
}

/// The `[[pairs]]` overrides: two known species, each pair once, values in range and of
/// the run's model.
fn check_pairs(case: &Case, c: &mut Checker) {
    let m = &case.model;
    let names = || {
        case.species
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut seen: Vec<(usize, usize, usize)> = Vec::new();
    for (k, p) in case.pairs.iter().enumerate() {
        let key = |f: &str| format!("pairs.{k}.{f}");
        if p.species.len() != 2 {
            c.bad(
                &key("species"),
                format!(
                    "must name two species (the same twice for the pair of one), got {}",
                    p.species.len()
                ),
            );
        } else {
            let index: Vec<Option<usize>> = p
                .species
                .iter()
                .map(|n| case.species.iter().position(|s| &s.name == n))
                .collect();
            for (n, i) in p.species.iter().zip(&index) {
                if i.is_none() {
                    c.bad(
                        &key("species"),
                        format!("`{n}` is not the name of a species (they are: {})", names()),
                    );
                }
            }
            if let [Some(a), Some(b)] = index[..] {
                let (a, b) = (a.min(b), a.max(b));
                if let Some(&(j, ..)) = seen.iter().find(|&&(_, x, y)| (x, y) == (a, b)) {
                    c.bad(
                        &key("species"),
                        format!(
                            "the pair {} / {} is given twice (also pairs.{j})",
                            p.species[0], p.species[1]
                        ),
                    );
                } else {
                    seen.push((k, a, b));
                }
            }
        }
        if p.mu.is_none()
            && p.mu_roll.is_none()
            && p.cohesion_energy.is_none()
            && p.restitution.is_none()
        {
            c.bad(
                &format!("pairs.{k}"),
                "gives no coefficient (mu, mu_roll, cohesion_energy or restitution)".into(),
            );
        }
        if let Some(mu) = p.mu {
            c.non_negative(&key("mu"), mu);
        }
        for (f, v, on, model_key) in [
            (
                "mu_roll",
                p.mu_roll,
                m.rolling != Rolling::None,
                "model.rolling",
            ),
            (
                "cohesion_energy",
                p.cohesion_energy,
                m.cohesion != Cohesion::None,
                "model.cohesion",
            ),
        ] {
            c.sub_model_value(&key(f), v, on, model_key);
        }
        match p.restitution {
            Some(e) if m.family == Family::SpringDashpot && m.normal == Normal::Linear => {
                c.restitution(&key("restitution"), e)
            }
            Some(_) => c.bad(&key("restitution"), not_linear(m.family).into()),
            None => {}
        }
    }
}

fn cross_checks(case: &Case, c: &mut Checker) {
    let d_max = case.d_max();
    if case.init.kind == InitKind::Lattice {
        let rho = case.init.density.unwrap_or(1.0);
        let nn = crate::init::fcc_spacing(rho) / 2f64.sqrt();
        let needed = match case.init.arrangement {
            Arrangement::Mixed => d_max,
            Arrangement::Segregated => case.d_min(),
        };
        if nn < needed {
            c.bad(
                "init.density",
                format!(
                    "the fcc lattice at density {rho} has neighbours {nn:.3} apart, less than the diameter \
                     {needed} (particles would overlap); lower the density"
                ),
            );
        }
    }

    let dt = case.dt();
    let limits = law::step_limits(case);
    if dt > limits.dt_max {
        c.bad(
            "run.dt",
            format!(
                "{dt} is too large for the contact stiffness: the shortest contact time is {:.4e}, so dt \
                 must be at most {:.4e} (contact time / {})",
                limits.contact_time_min,
                limits.dt_max,
                law::STEPS_PER_CONTACT_MIN
            ),
        );
    }
    if dt * limits.damping_rate_max > 2.0 {
        c.bad(
            "run.dt",
            format!(
                "{dt} is too large for the damping: dt times the largest damping rate ({:.1}) must be below \
                 2 for a stable explicit step",
                limits.damping_rate_max
            ),
        );
    }

    let reach = law::reach(case);
    let l = case.drum.axial_length();
    if case.drum.periodic() && l <= 2.0 * reach {
        c.bad(
            "drum.length",
            format!(
                "a periodic drum must be longer than twice the interaction range + skin ({:.3})",
                2.0 * reach
            ),
        );
    }
    if case.drum.ends == Some(Ends::Capped)
        && case.init.kind == InitKind::Lattice
        && l <= 2.0 * case.init.wall_gap
    {
        c.bad(
            "drum.length",
            format!("a capped drum of length {l} leaves no room between the end gaps (init.wall_gap = {})", case.init.wall_gap),
        );
    }
}

fn check_diagnostics(case: &Case, c: &mut Checker) {
    let g = &case.diagnostics;
    c.positive("diagnostics.sample_every", g.sample_every);
    if !(g.window.is_finite() && g.window >= g.sample_every) {
        c.bad(
            "diagnostics.window",
            format!(
                "must be at least diagnostics.sample_every ({}), got {}",
                g.sample_every, g.window
            ),
        );
    }
    if let Some(a) = g.surface_angle {
        if !(a.is_finite() && a.abs() < 90.0) {
            c.bad(
                "diagnostics.surface_angle",
                format!("must be an angle in degrees between -90 and 90, got {a}"),
            );
        }
    }
    for (k, n) in g.fields.grid.iter().flatten().enumerate() {
        if !(1..=1000).contains(n) {
            c.bad(
                "diagnostics.fields.grid",
                format!("entry {k} must be between 1 and 1000 bins, got {n}"),
            );
        }
    }
    let cells: usize = g.fields.grid.map_or(1, |n| n.iter().product());
    if cells > 4_000_000 {
        c.bad(
            "diagnostics.fields.grid",
            format!("{cells} bins is more than the 4,000,000 a window can hold"),
        );
    }
    // the window sums of one rank, and their reduction in 64-bit limbs (MPI counts are i32)
    let [nx, ny, nzf] = case.field_grid();
    let slices = case.drum.axial_length() / case.slice_width();
    let nz = if slices.is_finite() && slices < 1e7 {
        slices.round().max(1.0) as usize
    } else {
        0
    };
    let sums =
        case.species.len().min(256) * nx.min(1000) * ny.min(1000) * (10 * nzf.min(1000) + 2 * nz);
    if 3 * sums > i32::MAX as usize / 2 {
        c.bad(
            "diagnostics.fields.grid",
            format!(
                "with {nz} axial slices the window sums need {} MiB per rank; use fewer bins or wider output.slice_width",
                (16 * sums) >> 20
            ),
        );
    }
    for (key, w) in [
        ("diagnostics.window", g.window),
        ("diagnostics.fields.window", g.fields.window),
    ] {
        let r = w / g.sample_every;
        if w.is_finite() && r >= 1.0 && (r - r.round()).abs() > 1e-6 * r {
            c.bad(
                key,
                format!(
                    "must be a whole number of diagnostics.sample_every ({}), got {w} ({r:.3} samples)",
                    g.sample_every
                ),
            );
        }
    }
    {
        let w = g.fields.window;
        if !(w.is_finite() && w >= g.sample_every) {
            c.bad(
                "diagnostics.fields.window",
                format!(
                    "must be at least diagnostics.sample_every ({}), got {w}",
                    g.sample_every
                ),
            );
        }
    }
    if !(g.bands.threshold.is_finite() && g.bands.threshold > 0.0 && g.bands.threshold < 1.0) {
        c.bad(
            "diagnostics.bands.threshold",
            format!(
                "must be a volume-fraction departure in (0, 1), got {}",
                g.bands.threshold
            ),
        );
    }
    if let Some(w) = g.bands.min_width {
        c.non_negative("diagnostics.bands.min_width", w);
    }
    for (k, id) in g.paths.ids.iter().enumerate() {
        if *id >= crate::physics::rough_wall::FIRST_ID {
            c.bad(
                "diagnostics.paths.ids",
                format!("entry {k} ({id}) is not a particle id (ids are below 2^40)"),
            );
        }
    }
    for (k, r) in g.paths.regions.iter().enumerate() {
        if (0..3).any(|a| !(r.min[a].is_finite() && r.max[a].is_finite() && r.min[a] < r.max[a])) {
            c.bad(
                &format!("diagnostics.paths.regions[{k}]"),
                format!(
                    "min must be below max on every axis, got min {:?}, max {:?}",
                    r.min, r.max
                ),
            );
        }
    }
    if let Some(e) = g.paths.every {
        c.positive("diagnostics.paths.every", e);
    }
    if let Some(e) = g.snapshots.every {
        c.positive("diagnostics.snapshots.every", e);
    }
}

/// Every number of the case, wherever it is (used by the chosen model or not), must be
/// finite: NaN and infinities are refused naming the key, before any other check.
fn finite_numbers(case: &Case, c: &mut Checker) {
    fn walk(key: &str, v: &toml::Value, c: &mut Checker) {
        match v {
            toml::Value::Float(x) if !x.is_finite() => {
                c.errs.push(CaseError::new(
                    key,
                    format!("must be a finite number, got {}", number(*x)),
                ));
                c.not_finite.push(key.to_string());
            }
            toml::Value::Table(t) => {
                for (k, v) in t {
                    let sub = if key.is_empty() {
                        k.clone()
                    } else {
                        format!("{key}.{k}")
                    };
                    walk(&sub, v, c);
                }
            }
            toml::Value::Array(a) => {
                let tables = a.iter().all(|v| v.is_table());
                for (k, v) in a.iter().enumerate() {
                    if tables {
                        walk(&format!("{key}.{k}"), v, c);
                    } else if let toml::Value::Float(x) = v {
                        if !x.is_finite() {
                            c.errs.push(CaseError::new(
                                key,
                                format!("entry {k} must be a finite number, got {}", number(*x)),
                            ));
                            c.not_finite.push(key.to_string());
                        }
                    }
                }
            }
            _ => {}
        }
    }
    match toml::Value::try_from(case) {
        Ok(v) => walk("", &v, c),
        // the case came from TOML, so it goes back to TOML; refuse rather than skip if not
        Err(e) => c.bad("case", format!("cannot be checked: {e}")),
    }
}

/// `nan`, `inf` and `-inf` as TOML writes them.
fn number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x > 0.0 {
        "inf".into()
    } else {
        "-inf".into()
    }
}

/// An estimate of the number of particles of the initial state, made from the case alone
/// (nothing is allocated): the lattice sites of the fill volume, the poured points, the
/// explicit particles given in the case, plus the particles of a rough wall. A particle file
/// counts as 0 here: its size is known when it is read.
pub fn estimated_particles(case: &Case) -> f64 {
    let d = &case.drum;
    let radius = 0.5 * d.diameter;
    let length = d.axial_length();
    let inner = match case.init.kind {
        InitKind::Lattice => {
            let gap = case.init.wall_gap;
            let r = (radius - gap).max(0.0);
            let l = if d.ends == Some(Ends::Capped) {
                (length - 2.0 * gap).max(0.0)
            } else {
                length
            };
            case.init.density.unwrap_or(0.0) * std::f64::consts::PI * r * r * l
        }
        InitKind::Pour => crate::init::pour::poured_per_species(case).iter().sum(),
        InitKind::Particles => case.init.particle.len() as f64,
    };
    let wall = d.rough_wall.as_ref().map_or(0.0, |rw| {
        (2.0 * std::f64::consts::PI * radius / rw.diameter).max(1.0)
            * (length / rw.diameter).max(1.0)
    });
    inner + wall
}

/// What the run's size implies: enough steps per rotation, a step count that fits, an
/// initial state that fits in memory, and a bounded number of samples (checked once every
/// value is known to be finite and in range).
fn size_checks(case: &Case, c: &mut Checker) {
    let dt = case.dt();
    let omega = case.drum.omega.abs();
    let per_rotation = 2.0 * std::f64::consts::PI / (omega * dt);
    if !at_most(STEPS_PER_ROTATION_MIN, per_rotation) {
        c.bad(
            "drum.omega",
            format!(
                "{} turns the drum in {} time steps of dt = {}; at least {STEPS_PER_ROTATION_MIN} steps per rotation are needed, so |omega| must be at most {} (or dt smaller)",
                given(case.drum.omega),
                derived(per_rotation),
                given(dt),
                derived(2.0 * std::f64::consts::PI / (STEPS_PER_ROTATION_MIN * dt))
            ),
        );
        return;
    }
    let steps = case.run.rotations * per_rotation;
    if !at_most(steps, STEPS_MAX) {
        c.bad(
            "run.rotations",
            format!(
                "{} rotations of {} steps (dt = {}) are {} time steps; at most {STEPS_MAX:e} are accepted: fewer rotations or a larger run.dt",
                given(case.run.rotations),
                derived(per_rotation),
                given(dt),
                derived(steps)
            ),
        );
        return;
    }
    // what moves a particle far in a step: a fall across the drum, the initial speed
    let d_min = case
        .species
        .iter()
        .map(law::smallest_diameter)
        .fold(f64::MAX, f64::min);
    let fall = (2.0 * case.model.gravity * case.drum.diameter).sqrt() * dt;
    if !at_most(fall, 0.5 * d_min) {
        c.bad(
            "model.gravity",
            format!(
                "{}: a particle falling across the drum moves {} in a step of {}, more than half the smallest diameter {}; lower gravity or dt",
                given(case.model.gravity),
                derived(fall),
                given(dt),
                given(d_min)
            ),
        );
    }
    // (a start merely too fast is the health check's: it stops the run naming a particle)
    let radius = 0.5 * case.drum.diameter;
    if case.init.kind == InitKind::Lattice && !at_most(case.init.speed * dt, radius) {
        c.bad(
            "init.speed",
            format!(
                "{}: a particle moves {} in a step of {}, more than the drum's radius {}; lower the speed or dt",
                given(case.init.speed),
                derived(case.init.speed * dt),
                given(dt),
                given(radius)
            ),
        );
    }
    let slices = case.drum.axial_length() / case.slice_width();
    if !at_most(slices, SLICES_MAX) {
        c.bad(
            "output.slice_width",
            format!(
                "{} cuts the drum (length {}) into {} axial slices; at most {SLICES_MAX:e} are accepted",
                given(case.slice_width()),
                given(case.drum.axial_length()),
                derived(slices)
            ),
        );
    }
    // no run can fit if even the most slabs the drum can be cut into are too full
    if let Err(e) = initial_memory(case, most_ranks(case)) {
        c.errs.push(e);
    }
    let o = &case.output;
    let g = &case.diagnostics;
    for (key, every) in [
        ("output.sample_every", Some(o.sample_every)),
        ("output.checkpoint_every", o.checkpoint_every),
        ("diagnostics.sample_every", Some(g.sample_every)),
        ("diagnostics.paths.every", g.paths.every),
        ("diagnostics.snapshots.every", g.snapshots.every),
    ] {
        let Some(every) = every else { continue };
        let count = case.run.rotations / every;
        if !at_most(count, SAMPLES_MAX) {
            c.bad(
                key,
                format!(
                    "every {} rotations over {} rotations is {} records; at most {SAMPLES_MAX:e} are accepted",
                    given(every),
                    given(case.run.rotations),
                    derived(count)
                ),
            );
        }
    }
}

/// A value of the case as given: plain unless very large or small.
/// The most ranks the drum of `case` can be cut into: slabs no thinner than the
/// interaction range + skin (as `engine::sim::slabs_fit` requires).
fn most_ranks(case: &Case) -> usize {
    let most = (case.drum.axial_length() / crate::physics::law::reach(case)).floor();
    if most.is_finite() && most >= 1.0 {
        most.min(1e9) as usize
    } else {
        1
    }
}

/// Refuse an initial state that would take more than [`INITIAL_MEMORY_MAX`] on one of
/// `ranks` ranks (each makes only its own slab's part: the estimate of
/// [`estimated_particles`] over the ranks), before anything is built. The case check
/// applies it on the most ranks the drum can be cut into; `run` and `check --ranks` on
/// their own rank count.
pub fn initial_memory(case: &Case, ranks: usize) -> Result<(), CaseError> {
    let n = estimated_particles(case);
    let per_particle = crate::report::memory_estimate(case, ranks).per_particle();
    let cells = crate::report::cell_grid_bytes(case, ranks);
    let ranks = ranks.max(1) as f64;
    let bytes = n * per_particle / ranks + cells;
    if at_most(bytes, INITIAL_MEMORY_MAX) {
        return Ok(());
    }
    let gib = |b: f64| {
        if b.is_finite() {
            format!("{:.0} GiB", b / (1u64 << 30) as f64)
        } else {
            "more than 1e299 GiB".into()
        }
    };
    if cells > n * per_particle / ranks {
        // a sparse bed in a wide drum: the list build's cells, not the particles
        let cell = crate::physics::law::reach(case) / crate::engine::neighbor::SPAN as f64;
        let most = most_ranks(case);
        let remedy = if at_most(
            crate::report::cell_grid_bytes(case, most),
            INITIAL_MEMORY_MAX,
        ) {
            "run it on more ranks, or make the drum smaller or the particles larger"
        } else {
            "make the drum smaller or the particles larger"
        };
        return Err(CaseError::new(
            "drum.diameter",
            format!(
                "a drum {} across is {} neighbour cells across (cells of {}, half the reach of the largest pair plus the skin): the list build's cells would take {} on each of {ranks:.0} ranks, for about {} particles; at most {:.0} GiB per rank is accepted: {remedy}",
                given(case.drum.diameter),
                derived(case.drum.diameter / cell),
                derived(cell),
                gib(cells),
                derived(n),
                INITIAL_MEMORY_MAX / (1u64 << 30) as f64,
            ),
        ));
    }
    // on more than one rank a particle costs a little more (the gather's exchange)
    let per_many = crate::report::memory_estimate(case, 2).per_particle();
    let all_cells = crate::report::cell_grid_bytes(case, 1);
    let needed = ((n * per_many + all_cells) / INITIAL_MEMORY_MAX)
        .ceil()
        .max(2.0);
    let most = most_ranks(case) as f64;
    let remedy = if needed.is_finite() && needed <= most {
        format!("run it on at least {needed:.0} ranks, or make")
    } else {
        format!("no rank count fits (the drum can be cut into at most {most:.0} slabs): make")
    };
    Err(CaseError::new(
        match case.init.kind {
            InitKind::Lattice => "init.density",
            InitKind::Pour => "init.fill",
            InitKind::Particles => "init.particle",
        },
        format!(
            "the initial state would hold {} particles, {} on each of {ranks:.0} ranks; at most {:.0} GiB ({:.2e} particles) per rank is accepted: {remedy} the drum, fill or density smaller, or the particles larger",
            if n.is_finite() { format!("about {}", derived(n)) } else { derived(n) },
            gib(bytes),
            INITIAL_MEMORY_MAX / (1u64 << 30) as f64,
            INITIAL_MEMORY_MAX / per_particle
        ),
    ))
}

fn given(x: f64) -> String {
    if x == 0.0 || (1e-4..1e9).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A derived quantity, to four figures.
fn derived(x: f64) -> String {
    if !x.is_finite() {
        "more than 1e308".into()
    } else if (0.1..1e6).contains(&x.abs()) {
        format!("{x:.2}")
    } else {
        format!("{x:.3e}")
    }
}

/// `x <= max`, false when either is NaN.
fn at_most(x: f64, max: f64) -> bool {
    x <= max
}
