//! Human-readable reports: `tumbler check`'s derived quantities and small formatting helpers.

use crate::case::{Case, Ends};
use crate::init::lattice;
use crate::physics::rapaport;
use std::fmt::Write;

/// Bytes of per-particle storage (owned arrays, neighbour list, build positions), used for
/// the memory estimate.
pub const BYTES_PER_PARTICLE: usize = 8 + 1 + 8 * 3 + 24 * 5 + 8 + 1 + 24 + 4 * 3 + 8 * 8;

/// `h m s` form of a duration in seconds.
pub fn duration(secs: f64) -> String {
    if !secs.is_finite() {
        return "?".into();
    }
    let s = secs.round() as u64;
    match s {
        0..=59 => format!("{s}s"),
        60..=3599 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, (s % 3600) / 60),
    }
}

/// The derived quantities of a case, as `tumbler check` prints them; `ranks` sizes the slabs.
pub fn check_report(case: &Case, ranks: usize) -> String {
    let mut out = String::new();
    let initial = lattice(case);
    let n = initial.len();
    let mut per_species = vec![0usize; case.species.len()];
    for p in &initial {
        per_species[p.species as usize] += 1;
    }
    let steps_per_rot = 2.0 * std::f64::consts::PI / (case.drum.omega.abs() * case.run.dt);
    let total_steps = crate::run::steps_for(case.run.rotations, case.drum.omega, case.run.dt);
    let limits = rapaport::step_limits(case);
    let radius = 0.5 * case.drum.diameter;
    let froude = case.drum.omega * case.drum.omega * radius / case.model.gravity;
    let d_max = case.species.iter().map(|s| s.diameter).fold(0.0, f64::max);
    let reach = rapaport::cutoff(d_max) + case.run.skin;
    let slab = case.drum.length / ranks as f64;
    let vol_particles: f64 = initial
        .iter()
        .map(|p| std::f64::consts::PI / 6.0 * p.diameter.powi(3))
        .sum();
    let vol_drum = std::f64::consts::PI * radius * radius * case.drum.length;
    let ghosts_per_rank = if ranks > 1 || case.drum.ends == Ends::Periodic {
        2.0 * reach / case.drum.length * n as f64
    } else {
        0.0
    };
    let mem = (n as f64 / ranks as f64 + ghosts_per_rank) * BYTES_PER_PARTICLE as f64;

    let _ = writeln!(out, "case           {}", case.title);
    let _ = writeln!(out, "particles      {n}");
    for (s, c) in case.species.iter().zip(&per_species) {
        let _ = writeln!(
            out,
            "  {:<12} {c} (d = {} - {})",
            s.name,
            s.diameter - s.diameter_spread,
            s.diameter
        );
    }
    let _ = writeln!(
        out,
        "fill           {:.3} of the drum volume (solid fraction of particles)",
        vol_particles / vol_drum
    );
    let _ = writeln!(
        out,
        "dt             {} (contact period {:.4}, {:.1} steps per period; max accepted {:.4})",
        case.run.dt,
        limits.period_min,
        limits.period_min / case.run.dt,
        limits.dt_max
    );
    let _ = writeln!(
        out,
        "stiffness      {:.1} at contact for d_ij = {} (|dF/dr| of eq. 1)",
        rapaport::contact_stiffness(1.0),
        1.0
    );
    let _ = writeln!(out, "steps/rotation {steps_per_rot:.1}");
    let _ = writeln!(
        out,
        "run            {} rotations = {} steps",
        case.run.rotations, total_steps
    );
    let _ = writeln!(out, "Froude number  {froude:.4} (omega^2 R / g)");
    let _ = writeln!(
        out,
        "ranks          {ranks}: slabs {slab:.3} long (at least {reach:.3} needed{})",
        if slab < reach { " -- TOO THIN" } else { "" }
    );
    let _ = writeln!(
        out,
        "memory         about {:.1} MiB per rank ({} B per particle)",
        mem / (1 << 20) as f64,
        BYTES_PER_PARTICLE
    );
    out
}
