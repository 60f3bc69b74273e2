//! The pour fill of thesis 2.2.2: random points in the still drum grow to their diameters
//! without gravity, settle under gravity, and the bed is cut flat at the height that leaves
//! the requested fill level. Species are drawn by volume share; diameters are uniform in
//! `[d - spread, d]` or normal with relative s.d. `diameter_sd` (cut at 3 s.d.).
//!
//! The points are made on every rank from the seed alone; growth and settling run in the
//! decomposed engine, so the bed is the same bits on any number of ranks.

use crate::case::{Case, Shape};
use crate::engine::Sim;
use crate::particles::ParticleState;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Packing fraction of a random bed used to size the pour (random close packing).
pub const PACKING: f64 = 0.64;
/// How many more particles than the fill needs are poured before the cut.
pub const OVERFILL: f64 = 1.25;
/// Largest solid fraction at which the points are placed (at their shrunken size).
const PLACEMENT_FRACTION: f64 = 0.12;

/// What the pour did.
#[derive(Debug, Clone)]
pub struct PourReport {
    /// Particles poured.
    pub poured: u64,
    /// Particles left after the cut.
    pub kept: u64,
    /// Height of the cut (centres above it were removed).
    pub cut_height: f64,
    /// Fill level implied by the highest centres of the bed (mean over axial slices).
    pub measured_fill: f64,
}

fn diameter(s: &crate::case::Species, rng: &mut ChaCha8Rng) -> f64 {
    if s.diameter_sd > 0.0 {
        loop {
            // Box-Muller
            let (u1, u2): (f64, f64) = (rng.gen::<f64>().max(f64::MIN_POSITIVE), rng.gen());
            let z = (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos();
            if z.abs() <= 3.0 {
                return s.diameter * (1.0 + s.diameter_sd * z);
            }
        }
    }
    s.diameter - s.diameter_spread * rng.gen::<f64>()
}

/// Mean cube of a species' diameter.
pub(crate) fn mean_d3(s: &crate::case::Species) -> f64 {
    let d = s.diameter;
    if s.diameter_sd > 0.0 {
        d * d * d * (1.0 + 3.0 * s.diameter_sd * s.diameter_sd)
    } else if s.diameter_spread > 0.0 {
        let lo = d - s.diameter_spread;
        (d.powi(4) - lo.powi(4)) / (4.0 * s.diameter_spread)
    } else {
        d * d * d
    }
}

/// Fraction of the drum's volume below height `h` (`-R <= h <= R`).
pub fn fill_below(shape: Shape, radius: f64, h: f64) -> f64 {
    let h = h.clamp(-radius, radius);
    match shape {
        Shape::Cylinder => {
            let area = h * (radius * radius - h * h).sqrt()
                + radius * radius * (h / radius).asin()
                + 0.5 * PI * radius * radius;
            area / (PI * radius * radius)
        }
        Shape::Sphere => {
            let c = radius + h;
            PI * c * c * (3.0 * radius - c) / 3.0 / (4.0 / 3.0 * PI * radius.powi(3))
        }
    }
}

/// Height below which the drum's volume is the fraction `fill`.
pub fn cut_height(shape: Shape, radius: f64, fill: f64) -> f64 {
    let (mut lo, mut hi) = (-radius, radius);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if fill_below(shape, radius, mid) < fill {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The random points of the pour (at rest), sorted by id, and the factor by which their
/// diameters are shrunk for placement.
pub fn points(case: &Case) -> Result<(Vec<ParticleState>, f64), String> {
    let mut rng = ChaCha8Rng::seed_from_u64(case.seed);
    let fill = case.init.fill.unwrap_or(0.0);
    let solid = fill * case.drum.volume() * PACKING * OVERFILL;
    let single = case.species.len() == 1;
    let mut labels: Vec<u8> = Vec::new();
    for (k, s) in case.species.iter().enumerate() {
        let share = if single {
            1.0
        } else {
            s.volume_fraction.unwrap_or(0.0)
        };
        let n = (solid * share / (PI / 6.0 * mean_d3(s))).round() as usize;
        labels.extend(std::iter::repeat_n(k as u8, n));
    }
    labels.shuffle(&mut rng);
    let diameters: Vec<f64> = labels
        .iter()
        .map(|&s| diameter(&case.species[s as usize], &mut rng))
        .collect();

    let radius = 0.5 * case.drum.diameter;
    let half = 0.5 * case.drum.axial_length();
    let total: f64 = diameters.iter().map(|d| PI / 6.0 * d * d * d).sum();
    let scale = (PLACEMENT_FRACTION * case.drum.volume() / total)
        .cbrt()
        .min(0.9);
    let d_max = diameters.iter().cloned().fold(0.0, f64::max) * scale;

    // Random sequential addition at the shrunken size, on a hash grid of cells `d_max`.
    let cell = d_max.max(1e-12);
    let mut grid: std::collections::HashMap<[i64; 3], Vec<usize>> =
        std::collections::HashMap::new();
    let key = |x: &[f64; 3]| {
        [
            (x[0] / cell).floor() as i64,
            (x[1] / cell).floor() as i64,
            (x[2] / cell).floor() as i64,
        ]
    };
    let images: &[f64] = if case.drum.periodic() {
        &[0.0, 2.0 * half, -2.0 * half]
    } else {
        &[0.0]
    };
    let mut placed: Vec<ParticleState> = Vec::with_capacity(labels.len());
    for (k, (&s, &d)) in labels.iter().zip(&diameters).enumerate() {
        // at full size no wall overlap (a rough wall's particles stick out by half their size)
        let rough = case
            .drum
            .rough_wall
            .as_ref()
            .map_or(0.0, |r| 0.5 * r.diameter);
        let room = radius - 0.5 * d - rough;
        let mut found = None;
        for _ in 0..10_000 {
            let x = [
                (2.0 * rng.gen::<f64>() - 1.0) * room,
                (2.0 * rng.gen::<f64>() - 1.0) * room,
                match case.drum.shape {
                    Shape::Sphere => (2.0 * rng.gen::<f64>() - 1.0) * room,
                    Shape::Cylinder if case.drum.periodic() => {
                        (2.0 * rng.gen::<f64>() - 1.0) * half
                    }
                    Shape::Cylinder => (2.0 * rng.gen::<f64>() - 1.0) * (half - 0.5 * d),
                },
            ];
            let inside = match case.drum.shape {
                Shape::Sphere => x[0] * x[0] + x[1] * x[1] + x[2] * x[2] <= room * room,
                Shape::Cylinder => x[0] * x[0] + x[1] * x[1] <= room * room,
            };
            if !inside {
                continue;
            }
            let mut free = true;
            // with periodic ends, a point near one end also meets those near the other
            'scan: for shift in images {
                let c = key(&[x[0], x[1], x[2] + shift]);
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let Some(list) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                                continue;
                            };
                            for &j in list {
                                let o = &placed[j];
                                let mut sep = [x[0] - o.x[0], x[1] - o.x[1], x[2] - o.x[2]];
                                if case.drum.periodic() {
                                    sep[2] =
                                        crate::physics::integrate::min_image(sep[2], 2.0 * half);
                                }
                                let min = 0.5 * scale * (d + o.diameter);
                                if sep[0] * sep[0] + sep[1] * sep[1] + sep[2] * sep[2] < min * min {
                                    free = false;
                                    break 'scan;
                                }
                            }
                        }
                    }
                }
            }
            if free {
                found = Some(x);
                break;
            }
        }
        let x = found.ok_or_else(|| {
            format!(
                "init.fill: could not place particle {k} of {} at random; the fill is too high",
                labels.len()
            )
        })?;
        grid.entry(key(&x)).or_default().push(k);
        placed.push(ParticleState::new(k as u64, s, d, x, [0.0; 3], [0.0; 3]));
    }
    number_along_axis(&mut placed, d_max / scale);
    Ok((placed, scale))
}

/// Renumber the points in order of layers of width `layer` along the drum's axis (then
/// rows along `y`, then `x`), as the lattice numbers its sites. The force pass adds each
/// pair in order of ids, so neighbours with nearby ids are neighbours in memory; the beds
/// mix quickly across the drum but slowly along it, so the numbering stays local for long.
fn number_along_axis(placed: &mut [ParticleState], layer: f64) {
    let cell = |x: f64| (x / layer).floor() as i64;
    placed.sort_by_key(|p| (cell(p.x[2]), cell(p.x[1]), cell(p.x[0]), p.id));
    for (k, p) in placed.iter_mut().enumerate() {
        p.id = k as u64;
    }
}

/// Steps between the pour's health checks (each one a reduction over the ranks).
const CHECK_EVERY: u64 = 1000;

/// The largest overlap the pour tolerates, relative to the smaller diameter, whatever
/// `run.max_overlap`: settling drops beads from up to a drum diameter high, and with soft
/// contacts (the thesis' `t_c = 1e-3 s`) a pair meeting at 2.5 m/s overlaps by 40 % of a
/// 2 mm bead without anything going wrong.
const POUR_MAX_OVERLAP: f64 = 0.5;

/// The run's health check (`Sim::health`, with `run.max_overlap` or [`POUR_MAX_OVERLAP`]),
/// made during the pour every [`CHECK_EVERY`] steps and at the end of a stage, so that a
/// pour that blows up stops there, not in the run's first steps with particles far outside
/// the drum.
fn healthy(sim: &Sim, case: &Case, stage: &str, last: bool) -> Result<(), String> {
    if !sim.step.is_multiple_of(CHECK_EVERY) && !last {
        return Ok(());
    }
    let health = sim.health(
        case.run.max_overlap.max(POUR_MAX_OVERLAP),
        "the pour's limit (the larger of run.max_overlap and 50 %)",
    );
    if let Err(e) = &health {
        log::error!("pour, {stage}: {e}");
    }
    if sim.comm().all_ok(health.is_ok()) {
        return Ok(());
    }
    let what = health
        .err()
        .unwrap_or_else(|| "another rank found an unhealthy particle (see its message)".into());
    Err(format!(
        "init: the pour failed while {stage} its particles: {what}"
    ))
}

/// Grow the points to full size without gravity in the still drum, settle them under
/// gravity, cut the bed flat at the fill level and reset the clock: time zero is the start
/// of rotation. Every rank calls this together.
pub fn grow_settle_cut(sim: &mut Sim, case: &Case, start_scale: f64) -> Result<PourReport, String> {
    let dt = sim.dt;
    let poured = sim.global_count();
    let omega = sim.walls.omega;
    sim.walls.omega = 0.0;
    let grow_steps = (case.init.grow_time.unwrap_or(2000.0 * dt) / dt).ceil() as u64;
    let settle_steps = (case
        .init
        .settle_time
        .unwrap_or(10.0 * (case.drum.diameter / case.model.gravity.max(1e-12)).sqrt())
        / dt)
        .ceil() as u64;
    sim.gravity = 0.0;
    sim.scale = start_scale;
    sim.refresh_forces();
    for k in 0..grow_steps {
        sim.scale = start_scale + (1.0 - start_scale) * (k + 1) as f64 / grow_steps as f64;
        sim.step();
        healthy(sim, case, "growing", k + 1 == grow_steps)?;
    }
    sim.scale = 1.0;
    sim.gravity = case.model.gravity;
    sim.refresh_forces();
    for k in 0..settle_steps {
        sim.step();
        healthy(sim, case, "settling", k + 1 == settle_steps)?;
    }
    let radius = 0.5 * case.drum.diameter;
    let fill = case.init.fill.unwrap_or(0.0);
    let h = cut_height(case.drum.shape, radius, fill);
    sim.remove_where(|s| s.x[1] > h);
    let kept = sim.global_count();

    // How high the bed reaches: the highest centre in each axial slice, averaged. Slices
    // three largest diameters wide hold enough of the top layer that the highest centre
    // lies within a few percent of a diameter of the cut (one diameter wide: ~15 %).
    let top = sim.bed_top(3.0 * case.d_max());
    let measured_fill = fill_below(case.drum.shape, radius, top);
    if top < h - case.d_max() {
        return Err(format!(
            "init.fill: the settled bed reaches only y = {top:.4} but the cut is at {h:.4}; pour more \
             (lower init.fill) or settle longer (init.settle_time)"
        ));
    }
    sim.walls.omega = omega;
    sim.step = 0;
    sim.refresh_forces();
    Ok(PourReport {
        poured,
        kept,
        cut_height: h,
        measured_fill,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::parse_case;
    use crate::physics::integrate::min_image;

    /// The ch. 4 periodic drum at 3.14 rad/s: with seed 41 its pour once placed points that
    /// overlapped across the periodic ends, and the run blew up as they grew.
    #[test]
    fn points_do_not_overlap_across_periodic_ends() {
        let text = crate::validate::case_text("chen2008-ch4-periodic-w3.14").unwrap();
        let case = parse_case(text, "periodic").unwrap();
        let (points, scale) = points(&case).unwrap();
        let l = case.drum.axial_length();
        let near_end = |p: &&ParticleState| p.x[2].abs() > 0.5 * l - 2.0 * case.d_max();
        let ends: Vec<&ParticleState> = points.iter().filter(near_end).collect();
        assert!(ends.len() > 100, "{} points near the ends", ends.len());
        for (i, a) in ends.iter().enumerate() {
            for b in &ends[i + 1..] {
                let dz = min_image(a.x[2] - b.x[2], l);
                let r2 = (a.x[0] - b.x[0]).powi(2) + (a.x[1] - b.x[1]).powi(2) + dz * dz;
                let touch = 0.5 * scale * (a.diameter + b.diameter);
                assert!(
                    r2 >= touch * touch * (1.0 - 1e-12),
                    "points {} and {} overlap across the ends: {:.3e} apart, {touch:.3e} needed",
                    a.id,
                    b.id,
                    r2.sqrt()
                );
            }
        }
    }
}
