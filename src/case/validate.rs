//! Semantic checks of a parsed case: every impossible value is refused with the key that
//! holds it and the reason, all of them at once.

use super::load::CaseError;
use super::schema::{Arrangement, Case, Ends};
use crate::physics::rapaport;

/// Check every value of `case`; return all refusals.
pub fn validate(case: &Case) -> Result<(), Vec<CaseError>> {
    let mut errs = Vec::new();
    let mut bad = |key: &str, why: String| errs.push(CaseError::new(key, why));

    let positive = |x: f64| x.is_finite() && x > 0.0;
    let non_negative = |x: f64| x.is_finite() && x >= 0.0;

    let d = &case.drum;
    if !positive(d.diameter) {
        bad(
            "drum.diameter",
            format!("must be a positive length, got {}", d.diameter),
        );
    }
    if !positive(d.length) {
        bad(
            "drum.length",
            format!("must be a positive length, got {}", d.length),
        );
    }
    if !d.omega.is_finite() || d.omega == 0.0 {
        bad(
            "drum.omega",
            format!(
                "must be non-zero (the run length is counted in rotations), got {}",
                d.omega
            ),
        );
    }

    let m = &case.model;
    if !non_negative(m.gravity) {
        bad(
            "model.gravity",
            format!("must be zero or positive, got {}", m.gravity),
        );
    }
    if !non_negative(m.gamma_n) {
        bad(
            "model.gamma_n",
            format!("must be zero or positive, got {}", m.gamma_n),
        );
    }
    if !non_negative(m.mu_max) {
        bad(
            "model.mu_max",
            format!("must be zero or positive, got {}", m.mu_max),
        );
    }
    if !positive(m.wall_diameter) {
        bad(
            "model.wall_diameter",
            format!("must be positive, got {}", m.wall_diameter),
        );
    }
    if !positive(m.density) {
        bad(
            "model.density",
            format!("must be positive, got {}", m.density),
        );
    }

    if case.species.is_empty() {
        bad("species", "at least one [[species]] table is needed".into());
    }
    if case.species.len() > 255 {
        bad(
            "species",
            format!("at most 255 species, got {}", case.species.len()),
        );
    }
    for (k, s) in case.species.iter().enumerate() {
        let key = |f: &str| format!("species.{k}.{f}");
        if s.name.trim().is_empty() {
            bad(&key("name"), "must not be empty".into());
        }
        if case.species[..k].iter().any(|o| o.name == s.name) {
            bad(&key("name"), format!("`{}` names two species", s.name));
        }
        if !positive(s.diameter) {
            bad(
                &key("diameter"),
                format!("must be a positive length, got {}", s.diameter),
            );
        } else if positive(d.diameter) && s.diameter >= d.diameter {
            bad(
                &key("diameter"),
                format!(
                    "a particle of diameter {} does not fit in a drum of diameter {}",
                    s.diameter, d.diameter
                ),
            );
        }
        if !non_negative(s.diameter_spread) || s.diameter_spread >= s.diameter {
            bad(
                &key("diameter_spread"),
                format!(
                    "must be in [0, diameter) so that diameters stay positive, got {}",
                    s.diameter_spread
                ),
            );
        }
        if !non_negative(s.gamma_s) {
            bad(
                &key("gamma_s"),
                format!("must be zero or positive, got {}", s.gamma_s),
            );
        }
        if !non_negative(s.gamma_s_wall) {
            bad(
                &key("gamma_s_wall"),
                format!("must be zero or positive, got {}", s.gamma_s_wall),
            );
        }
        for (f, v) in [("mu", s.mu), ("mu_wall", s.mu_wall)] {
            if let Some(v) = v {
                if !non_negative(v) {
                    bad(&key(f), format!("must be zero or positive, got {v}"));
                }
            }
        }
    }

    let i = &case.init;
    if !positive(i.density) {
        bad(
            "init.density",
            format!("must be a positive number density, got {}", i.density),
        );
    }
    if i.arrangement == Arrangement::Segregated && i.bands < 2 {
        bad(
            "init.bands",
            format!("a segregated start needs at least 2 bands, got {}", i.bands),
        );
    }
    if !non_negative(i.speed) {
        bad(
            "init.speed",
            format!("must be zero or positive, got {}", i.speed),
        );
    }
    if !non_negative(i.wall_gap) || (positive(d.diameter) && i.wall_gap >= d.diameter / 2.0) {
        bad(
            "init.wall_gap",
            format!(
                "must be in [0, D/2) so that the lattice has room, got {}",
                i.wall_gap
            ),
        );
    }

    let r = &case.run;
    if !positive(r.rotations) {
        bad(
            "run.rotations",
            format!("must be positive, got {}", r.rotations),
        );
    }
    if !positive(r.dt) {
        bad(
            "run.dt",
            format!("must be a positive time step, got {}", r.dt),
        );
    }
    if !positive(r.skin) {
        bad(
            "run.skin",
            format!("must be a positive length, got {}", r.skin),
        );
    }

    let o = &case.output;
    if !positive(o.sample_every) {
        bad(
            "output.sample_every",
            format!("must be positive (rotations), got {}", o.sample_every),
        );
    }
    if !positive(o.slice_width) || (positive(d.length) && o.slice_width > d.length) {
        bad(
            "output.slice_width",
            format!(
                "must be positive and at most the drum length, got {}",
                o.slice_width
            ),
        );
    }
    if !positive(o.progress_every) {
        bad(
            "output.progress_every",
            format!("must be positive (rotations), got {}", o.progress_every),
        );
    }

    // Checks that combine several keys; only meaningful once the single values are sane.
    if errs.is_empty() {
        cross_checks(case, &mut errs);
    }
    if errs.is_empty() {
        Ok(())
    } else {
        Err(errs)
    }
}

fn cross_checks(case: &Case, errs: &mut Vec<CaseError>) {
    let mut bad = |key: &str, why: String| errs.push(CaseError::new(key, why));
    let d_max = case.species.iter().map(|s| s.diameter).fold(0.0, f64::max);
    let d_min_nominal = case
        .species
        .iter()
        .map(|s| s.diameter)
        .fold(f64::MAX, f64::min);

    // fcc nearest-neighbour distance must keep the lattice free of overlaps.
    let nn = rapaport::fcc_spacing(case.init.density) / 2f64.sqrt();
    let needed = match case.init.arrangement {
        Arrangement::Mixed => d_max,
        Arrangement::Segregated => d_min_nominal,
    };
    if nn < needed {
        bad(
            "init.density",
            format!(
                "the fcc lattice at density {} has neighbours {:.3} apart, less than the diameter {} \
                 (particles would overlap); lower the density",
                case.init.density, nn, needed
            ),
        );
    }

    // Time step against the stiffest contact and the strongest damping.
    let limits = rapaport::step_limits(case);
    if case.run.dt > limits.dt_max {
        bad(
            "run.dt",
            format!(
                "{} is too large for the contact stiffness: the shortest contact period is {:.4}, \
                 so dt must be at most {:.4} (period / {})",
                case.run.dt,
                limits.period_min,
                limits.dt_max,
                rapaport::STEPS_PER_PERIOD_MIN
            ),
        );
    }
    if case.run.dt * limits.damping_rate_max > 2.0 {
        bad(
            "run.dt",
            format!(
                "{} is too large for the damping: dt times the largest damping rate ({:.1}) must be \
                 below 2 for a stable explicit step",
                case.run.dt, limits.damping_rate_max
            ),
        );
    }

    let reach = rapaport::cutoff(d_max) + case.run.skin;
    if case.drum.ends == Ends::Periodic && case.drum.length <= 2.0 * reach {
        bad(
            "drum.length",
            format!(
                "a periodic drum must be longer than twice the interaction range + skin ({:.3})",
                2.0 * reach
            ),
        );
    }
    if case.drum.ends == Ends::Capped && case.drum.length <= 2.0 * case.init.wall_gap {
        bad(
            "drum.length",
            format!(
                "a capped drum of length {} leaves no room between the end gaps (init.wall_gap = {})",
                case.drum.length, case.init.wall_gap
            ),
        );
    }
}
