//! Human-readable reports: `tumbler check`'s derived quantities and small formatting helpers.

use crate::case::{Case, Family, InitKind};
use crate::init::{count_by_species, pour};
use crate::physics::law;
use std::fmt::Write;

/// One rank's memory per particle of its share, by part, as `tumbler check` estimates it
/// (beside the process's fixed cost: libraries, MPI, HDF5; and the window sums, which go
/// with the drum's length and the diagnostics' bins, not with the particles). Measured by
/// `benches/memory.sh` (docs/scaling.md, "Memory per particle").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryEstimate {
    /// Bytes of one particle's arrays (`Particles`: id, species, diameter, inverse mass and
    /// inertia, position, velocity, spin, force, torque, axial image offset, and its wall
    /// histories' index and, for the particles touching a wall, their block), with the
    /// sixteenth of room `Particles::trim` leaves; a ghost's too.
    pub arrays: f64,
    /// Pairs listed per particle (half the neighbours within the list's range, at the
    /// number density of a bed packed at 0.6, or of the initial lattice if denser or if the
    /// run ends before the lattice can settle).
    pub pairs: f64,
    /// Bytes of the neighbour list per particle: its pairs (indices, contact distance, the
    /// pass's touching index, the history's block index and, for those touching, its
    /// words), their capacity grown by doubling (half again on average), and the build
    /// positions and near-wall indices.
    pub list: f64,
    /// Bytes the neighbour build keeps per local particle, owned or ghost, besides the list
    /// ([`SCRATCH_BYTES`](crate::engine::neighbor::SCRATCH_BYTES): the cell sort, the order
    /// of rank and the search's slots).
    pub scratch: f64,
    /// Bytes per particle of the largest transient that goes with the particles: a
    /// checkpoint's particles in id order (each particle's packed record, sent once and, on
    /// more than one rank, half a share's received from the others; the sort's index or the
    /// widest column being written) or, if more, its contacts (saved, packed, received,
    /// sorted), gathered after the particles are written.
    pub gather: f64,
}

impl MemoryEstimate {
    /// Bytes per owned particle, all told (ghosts, the cell grid and window sums aside).
    pub fn per_particle(&self) -> f64 {
        self.arrays + self.list + self.scratch + self.gather
    }
}

/// The estimate of [`MemoryEstimate`] for `case` on `ranks` ranks.
pub fn memory_estimate(case: &Case, ranks: usize) -> MemoryEstimate {
    use crate::physics::materials::WALLS;
    let words = law::ContactLaw::new(case).history_words() as f64;
    // the wall histories: a block index, and a block for the particles touching a wall
    // (about one in ten of a bed; blocks are kept for the most at once); none without words
    let wall = if words > 0.0 {
        4.0 + 0.15 * WALLS as f64 * 8.0 * words
    } else {
        0.0
    };
    let arrays = (8.0 + 8.0 + 1.0 + 3.0 * 8.0 + 5.0 * 24.0 + 8.0 + wall) * 17.0 / 16.0;
    // number density of a bed packed at 0.6; a lattice keeps its own, unless it is looser and
    // the run lasts longer than a fall across the drum, so that it settles into such a bed
    // (whose pairs the lists then hold)
    let ns = case.species.len().max(1) as f64;
    let d = case.species.iter().map(|s| s.diameter).sum::<f64>() / ns;
    let d = if d.is_finite() && d > 0.0 { d } else { 1.0 };
    let bed = 0.6 / (std::f64::consts::PI / 6.0 * d * d * d);
    let density = match (case.init.kind, case.init.density) {
        (InitKind::Lattice, Some(rho)) if lattice_settles(case) => rho.max(bed),
        (InitKind::Lattice, Some(rho)) => rho,
        _ => bed,
    };
    let range = law::ContactLaw::new(case).cutoff(d, d) + case.skin();
    let pairs = 0.5 * density * 4.0 / 3.0 * std::f64::consts::PI * range.powi(3);
    let pairs = if pairs.is_finite() {
        pairs.max(1.0)
    } else {
        1.0
    };
    // a pair's history: a block index, and a block for the quarter of the pairs that touch
    let hist = if words > 0.0 {
        4.0 + 0.25 * 8.0 * words
    } else {
        0.0
    };
    let list = pairs * (8.0 + 8.0 + 4.0 + hist) * 1.5 + 24.0 + 4.0;
    // the records of the particles as sent and, on more than one rank, those received from
    // the others (the id order does not follow the slabs: about half a share); then the
    // sort's index (24 B) or the widest column written (the wall histories)
    let exchange = if ranks > 1 { 1.5 } else { 1.0 };
    let record = 8.0 * crate::particles::packed_words(words as usize) as f64;
    let file_words = words.max(crate::output::checkpoint::FILE_WORDS_MIN as f64);
    let column = (8.0 * WALLS as f64 * file_words).max(16.0);
    let mut gather = exchange * record + column;
    if words > 0.0 {
        // the contacts, each once, gathered once the particles are written: about 2 per
        // particle (a frictional bed's mean coordination number is about 4; the flowing
        // bench bed has 1.3-1.5), each saved, packed into its message, received and kept
        let contacts = pairs.min(2.0);
        let saved = std::mem::size_of::<crate::engine::neighbor::SavedContact>() as f64;
        let packed = 8.0 * crate::engine::neighbor::record_words(words as usize) as f64;
        gather = gather.max(contacts * (saved + exchange * packed));
    }
    MemoryEstimate {
        arrays,
        pairs,
        list,
        scratch: crate::engine::neighbor::SCRATCH_BYTES as f64,
        gather,
    }
}

/// Bytes of one rank's cell grid during a list build, at most: cells of a `SPAN`-th of the
/// reach over the drum's square section and the rank's slab with its halo (the grid covers
/// the particles' bounding box, so a lattice that fills the drum takes all of it; a bed,
/// less), [`CELL_BYTES`](crate::engine::neighbor::CELL_BYTES) each.
pub fn cell_grid_bytes(case: &Case, ranks: usize) -> f64 {
    use crate::engine::neighbor::{CELL_BYTES, SPAN};
    let reach = law::reach(case);
    let cell = reach / SPAN as f64;
    let halo = if ranks > 1 || case.drum.periodic() {
        2.0 * reach
    } else {
        0.0
    };
    let along = case.drum.axial_length() / ranks.max(1) as f64 + halo;
    let count = |span: f64| (span / cell).floor().max(1.0);
    let cells = count(case.drum.diameter).powi(2) * count(along);
    if cells.is_finite() {
        cells * CELL_BYTES as f64
    } else {
        f64::INFINITY
    }
}

/// Whether a run of `case` lasts longer than a fall from rest across the drum under its
/// gravity, `sqrt(2 D / g)`: time for a lattice to settle into a bed.
fn lattice_settles(case: &Case) -> bool {
    let dt = case.dt();
    let steps = crate::run::steps_for(case.run.rotations, case.drum.omega, dt) as f64;
    let fall = (2.0 * case.drum.diameter / case.model.gravity).sqrt();
    steps * dt > fall
}

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
    let est = memory_estimate(case, ranks);
    let share = n as f64 / ranks as f64;
    let persistent = share * (est.arrays + est.list + est.scratch)
        + ghosts_per_rank * (est.arrays + est.scratch)
        + cell_grid_bytes(case, ranks);
    // the window sums (the diagnostics line below): rank 0 holds the field sums and its block
    // of the per-slice sums, another rank its block; their pages are committed only where
    // the bed reached, about half
    let (field_sums, slice_sums) = window_sums_bytes(case, ranks);
    let sums_rank0 = 0.5 * (field_sums + slice_sums) as f64;
    let sums_other = 0.5 * slice_sums as f64;
    // a checkpoint writes the sums last, one half of one of them at a time (8 B a sum, all
    // its pages), beside HDF5's chunk and gzip buffers: the peak is that or the particles'
    // gather, whichever is larger
    let sums_write = |bytes: usize| 0.5 * bytes as f64 + 1.5 * (1 << 20) as f64;
    let gather = share * est.gather;
    let mem_rank0 = persistent + sums_rank0 + gather.max(sums_write(field_sums.max(slice_sums)));
    let mem_other = persistent + sums_other + gather.max(sums_write(slice_sums));
    let mem_all = mem_rank0 + (ranks - 1) as f64 * mem_other;

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
    let mib = |b: f64| b / (1 << 20) as f64;
    let _ = writeln!(
        out,
        "memory         about {:.1} MiB on rank 0{}, {:.1} MiB over the ranks ({:.0} B per particle), beside each process's fixed cost (libraries, MPI, HDF5)",
        mib(mem_rank0),
        if ranks > 1 {
            format!(", {:.1} MiB on each other rank", mib(mem_other))
        } else {
            String::new()
        },
        mib(mem_all),
        est.per_particle()
    );
    let _ = writeln!(
        out,
        "               per particle: {:.0} B of arrays, {:.0} B of neighbour list ({:.1} pairs) and {:.0} B of its build, {:.0} B gathered in id order for a checkpoint; {:.1} MiB of cells per rank at most; {:.1} MiB of window sums on rank 0 (half of those below: the bins a bed reaches)",
        est.arrays,
        est.list,
        est.pairs,
        est.scratch,
        est.gather,
        mib(cell_grid_bytes(case, ranks)),
        mib(sums_rank0)
    );
    let g = &case.diagnostics;
    let nz = slices(case);
    let [nx, ny, nzf] = case.field_grid();
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

/// Axial slices of the per-slice diagnostics.
fn slices(case: &Case) -> usize {
    (case.drum.axial_length() / case.slice_width())
        .round()
        .max(1.0) as usize
}

/// Bytes of the window sums (128-bit), as `(field sums, one rank's per-slice sums)`: 10 per
/// species and field bin, all on rank 0; 2 per species and slice bin, each rank holding an
/// even block of the slices.
fn window_sums_bytes(case: &Case, ranks: usize) -> (usize, usize) {
    let [nx, ny, nzf] = case.field_grid();
    let bins = 16 * case.species.len() * nx * ny;
    (
        bins * 10 * nzf,
        bins * 2 * slices(case).div_ceil(ranks.max(1)),
    )
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
