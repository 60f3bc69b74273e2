//! Human-readable reports: `tumbler check`'s derived quantities and small formatting helpers.

use crate::case::{Case, Family, InitKind};
use crate::init::{count_by_species, pour};
use crate::physics::law;
use std::fmt::Write;

/// Bytes of per-particle storage (owned arrays, neighbour list with histories, build
/// positions, cells), used for the memory estimate.
pub const BYTES_PER_PARTICLE: usize = 8 + 1 + 8 * 3 + 24 * 5 + 72 + 8 + 24 + 4 * 3 + 8 * (8 + 24);

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
pub fn check_report(case: &Case, ranks: usize) -> Result<String, String> {
    let mut out = String::new();
    if ranks == 0 {
        return Err("--ranks: at least 1 rank is needed, got 0".into());
    }
    crate::engine::sim::slabs_fit(case, ranks).map_err(|e| format!("--ranks {ranks}: {e}"))?;
    crate::case::initial_memory(case, ranks).map_err(|e| e.to_string())?;
    let reach = law::reach(case);
    let length = case.drum.axial_length();
    let slab = length / ranks as f64;
    let per_species = count_by_species(case)?;
    let made: u64 = per_species.iter().sum();
    let radius = 0.5 * case.drum.diameter;
    let walls = crate::physics::DrumWalls::of(&case.drum);
    let poured = case.init.kind == InitKind::Pour;
    // A pour keeps the part below the cut: estimate it by volume, for a bed packed at 0.6.
    let kept = if poured {
        0.6 / (pour::PACKING * pour::OVERFILL)
    } else {
        1.0
    };
    let n = (made as f64 * kept).round() as usize;
    let dt = case.dt();
    let steps_per_rot = 2.0 * std::f64::consts::PI / (case.drum.omega.abs() * dt);
    let total_steps = crate::run::steps_for(case.run.rotations, case.drum.omega, dt);
    let limits = law::step_limits(case);
    let froude =
        case.drum.omega * case.drum.omega * radius / case.model.gravity.max(f64::MIN_POSITIVE);
    let ghosts_per_rank = if ranks > 1 || case.drum.periodic() {
        2.0 * reach / length * n as f64
    } else {
        0.0
    };
    let mem = (n as f64 / ranks as f64 + ghosts_per_rank) * BYTES_PER_PARTICLE as f64;

    let _ = writeln!(out, "case           {}", case.title);
    let _ = writeln!(out, "drum           {}", drum_line(case, &walls));
    if poured {
        let _ = writeln!(
            out,
            "particles      about {n} after the cut ({} poured), fill {}",
            made,
            case.init.fill.unwrap_or(0.0)
        );
        let _ = writeln!(
            out,
            "cut height     y = {:.5}",
            walls.cut_height(case.init.fill.unwrap_or(0.0))
        );
    } else {
        let _ = writeln!(out, "particles      {n}");
    }
    for (s, c) in case.species.iter().zip(&per_species) {
        let _ = writeln!(
            out,
            "  {:<12} {c}{} (d = {} - {})",
            s.name,
            if poured { " poured" } else { "" },
            law::smallest_diameter(s),
            law::largest_diameter(s)
        );
    }
    match case.model.family {
        Family::Rapaport => {
            let _ = writeln!(
                out,
                "stiffness      {:.1} at contact for d_ij = 1 (|dF/dr| of eq. 1)",
                crate::physics::rapaport::contact_stiffness(1.0)
            );
        }
        Family::SpringDashpot => {
            if let (Some(tc), Some(e)) = (case.model.collision_time, case.model.restitution) {
                let gamma = -e.ln() / tc;
                let k0 = (std::f64::consts::PI / tc).powi(2) + gamma * gamma;
                let m = |d: f64| case.model.density * std::f64::consts::PI / 6.0 * d.powi(3);
                for (i, a) in case.species.iter().enumerate() {
                    for b in &case.species[i..] {
                        let (ma, mb) = (m(a.diameter), m(b.diameter));
                        let _ = writeln!(
                            out,
                            "k_n {:>6}-{:<6} {:.4e} N/m (nominal sizes; gamma_n = {:.3} 1/s)",
                            a.name,
                            b.name,
                            k0 * ma * mb / (ma + mb),
                            gamma
                        );
                    }
                    let _ = writeln!(
                        out,
                        "k_n {:>6}-wall   {:.4e} N/m",
                        a.name,
                        k0 * m(a.diameter)
                    );
                }
            }
        }
    }
    let _ = writeln!(out, "dt             {dt:.4e} ({:.1} steps per shortest contact {:.4e}; at most {:.4e} accepted)", limits.contact_time_min / dt, limits.contact_time_min, limits.dt_max);
    let _ = writeln!(out, "steps/rotation {steps_per_rot:.1}");
    let _ = writeln!(
        out,
        "run            {} rotations = {} steps",
        case.run.rotations, total_steps
    );
    let _ = writeln!(out, "Froude number  {froude:.4} (omega^2 R / g)");
    let _ = writeln!(
        out,
        "ranks          {ranks}: slabs {slab:.4} long (at least {reach:.4} needed)"
    );
    let _ = writeln!(
        out,
        "memory         about {:.1} MiB per rank ({} B per particle)",
        mem / (1 << 20) as f64,
        BYTES_PER_PARTICLE
    );
    let g = &case.diagnostics;
    let nz = (case.drum.axial_length() / case.slice_width())
        .round()
        .max(1.0) as usize;
    let [nx, ny, nzf] = case.field_grid();
    let ns = case.species.len();
    // 128-bit sums: 10 per species and field bin (on rank 0), 2 per species and slice bin
    // (each rank an even block of the slices)
    let field_sums = 16 * ns * nx * ny * 10 * nzf;
    let slice_sums = 16 * ns * nx * ny * 2 * nz.div_ceil(ranks);
    let _ = writeln!(
        out,
        "diagnostics    {:.1} MiB of per-slice window sums per rank, {:.1} MiB of field sums on rank 0; fields {}x{}x{} bins every {} rotations, slices {} x {}x{} bins every {} rotations, sampled every {} rotations",
        slice_sums as f64 / (1 << 20) as f64,
        field_sums as f64 / (1 << 20) as f64,
        nx,
        ny,
        nzf,
        g.fields.window,
        nz,
        nx,
        ny,
        g.window,
        g.sample_every
    );
    Ok(out)
}

/// The drum's shape, size and volume, and its lifters, for `tumbler check`.
fn drum_line(case: &Case, walls: &crate::physics::DrumWalls) -> String {
    let d = &case.drum;
    let mut s = match d.shape {
        crate::case::Shape::Cylinder => format!(
            "cylinder D = {} L = {} ({} ends)",
            d.diameter,
            d.axial_length(),
            if d.periodic() { "periodic" } else { "capped" }
        ),
        crate::case::Shape::Sphere => format!("sphere D = {}", d.diameter),
        crate::case::Shape::Cone => format!(
            "cone D = {} at z = -L/2 to {} at z = +L/2, L = {}",
            d.diameter,
            d.diameter_high.unwrap_or(d.diameter),
            d.axial_length()
        ),
        #[allow(unreachable_patterns)]
        other => format!("{other:?} D = {} L = {}", d.diameter, d.axial_length()),
    };
    if let Some(l) = &walls.lifters {
        let gap = if l.count >= 2 {
            2.0 * l.tip * (std::f64::consts::PI / l.count as f64).sin() - l.thickness
        } else {
            f64::INFINITY
        };
        let _ = write!(
            s,
            "; {} lifters {} high, {} thick, {:.4e} apart at the tips",
            l.count, l.height, l.thickness, gap
        );
    }
    let _ = write!(s, "; volume {:.4e}", walls.volume());
    s
}
