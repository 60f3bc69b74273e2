//! The pour fill of thesis 2.2.2: random points in the still drum grow to their diameters
//! without gravity, settle under gravity, and the bed is cut flat at the height that leaves
//! the requested fill level. Species are drawn by volume share; diameters are uniform in
//! `[d - spread, d]` or normal with relative s.d. `diameter_sd` (cut at 3 s.d.).
//!
//! Each rank makes only the points of its own slab, every random draw keyed by the seed and
//! a global index; growth and settling run in the decomposed engine, so the bed is the same
//! bits on any number of ranks.

use super::keyed::{self, Permutation, Purpose};
use super::Share;
use crate::case::Case;
use crate::engine::Sim;
use crate::particles::ParticleState;
use crate::physics::DrumWalls;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Packing fraction of a random bed used to size the pour (random close packing).
pub const PACKING: f64 = 0.64;
/// How many more particles than the fill needs are poured before the cut.
pub const OVERFILL: f64 = 1.25;

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
fn mean_d3(s: &crate::case::Species) -> f64 {
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

/// How many particles of each species the pour makes (before rounding): the fill's volume,
/// packed at [`PACKING`] and [`OVERFILL`] times over, shared out by `volume_fraction`.
pub fn poured_per_species(case: &Case) -> Vec<f64> {
    let solid = case.init.fill.unwrap_or(0.0) * case.drum.volume() * PACKING * OVERFILL;
    let single = case.species.len() == 1;
    case.species
        .iter()
        .map(|s| {
            let fraction = if single {
                1.0
            } else {
                s.volume_fraction.unwrap_or(0.0)
            };
            solid * fraction / (PI / 6.0 * mean_d3(s))
        })
        .collect()
}

/// Share of the eligible cells of the placement grid that hold a point (which ones is drawn
/// at random, layer by layer).
const CELL_OCCUPANCY: f64 = 0.85;

/// The placement grid of a pour: cubic cells (of side `cz` along the axis in a periodic
/// drum, so that whole layers fill its length) whose jittered points cannot overlap at the
/// shrunken size, in layers along the axis; a cell is eligible when every point it may
/// hold is inside the drum with room for the largest particle at full size.
struct Grid {
    /// Cell side across the axis.
    c: f64,
    /// Largest distance of a point from its cell's centre along each axis.
    jitter: f64,
    /// Radius inside which every point must lie.
    room: f64,
    /// How far a centre must stay from the wall (before the lifters and rough wall).
    margin: f64,
    /// The drum body, which shapes the rows of cells.
    vessel: std::sync::Arc<dyn crate::physics::walls::Vessel>,
    /// Centres of the layers along the axis.
    layers: Vec<f64>,
    /// Eligible cells per layer.
    eligible: Vec<u64>,
    /// The factor by which the diameters are shrunk for placement.
    scale: f64,
}

impl Grid {
    fn new(case: &Case, c: f64, d_max: f64, room: f64, walls: &DrumWalls) -> Self {
        let half = 0.5 * case.drum.axial_length();
        let vessel = walls.vessel.clone();
        let cz = if case.drum.periodic() {
            2.0 * half / (2.0 * half / c).floor().max(1.0)
        } else {
            c
        };
        let c_min = c.min(cz);
        let shrunk = (0.5 * c_min).min(0.9 * d_max);
        let jitter = 0.5 * (c_min - shrunk);
        let layers: Vec<f64> = if case.drum.periodic() {
            let nz = (2.0 * half / cz).round() as i64;
            (0..nz).map(|k| -half + (k as f64 + 0.5) * cz).collect()
        } else {
            let z_room = vessel.placement_half_length(room, d_max);
            let mz = ((z_room - jitter) / c).floor();
            if mz < 0.0 {
                Vec::new()
            } else {
                let mz = mz as i64;
                (-mz..=mz).map(|k| k as f64 * c).collect()
            }
        };
        let mut grid = Grid {
            c,
            jitter,
            room,
            margin: 0.5 * d_max,
            vessel,
            layers,
            eligible: Vec::new(),
            scale: shrunk / d_max,
        };
        grid.eligible = grid
            .layers
            .iter()
            .map(|&z| grid.rows(z).map(|(_, k)| 2 * k + 1).sum())
            .collect();
        grid
    }

    /// The rows of eligible cells of the layer at `z`: `(j, k)` for the row at `y = j c`
    /// whose cells are `x = i c`, `-k <= i <= k`.
    fn rows(&self, z: f64) -> impl Iterator<Item = (i64, u64)> + '_ {
        let m = (self.room / self.c).floor() as i64;
        let zz = self
            .vessel
            .placement_cut(self.room, self.margin, z, self.jitter);
        (-m..=m).filter_map(move |j| {
            let y = (j as f64 * self.c).abs() + self.jitter;
            let left = self.room * self.room - y * y - zz;
            if left < 0.0 {
                return None;
            }
            let x = left.sqrt() - self.jitter;
            (x >= 0.0).then(|| (j, (x / self.c).floor() as u64))
        })
    }

    fn cells(&self) -> u64 {
        self.eligible.iter().sum()
    }
}

/// The random points of the pour (at rest) in `share`, sorted by id, and the factor by
/// which their diameters are shrunk for placement.
///
/// Every point sits at random in a cell of a grid too fine for two points to touch; the
/// points are dealt out over the layers of cells in proportion to their eligible cells, and
/// which cells of a layer hold one is drawn per layer. Ids run along the axis (layers, then
/// rows along `y`, then `x`): the force pass adds each pair in order of ids, so neighbours
/// with nearby ids are neighbours in memory, and the beds mix quickly across the drum but
/// slowly along it. Species are dealt out in exact numbers by a keyed permutation of the
/// ids; each point's place and diameter are drawn from its own keyed stream.
pub fn points(case: &Case, share: &Share) -> Result<(Vec<ParticleState>, f64), String> {
    // species k takes the dealt positions ends[k-1]..ends[k]
    let mut ends: Vec<u64> = Vec::new();
    let mut d_max: f64 = 0.0;
    for (s, n) in case.species.iter().zip(poured_per_species(case)) {
        let n = n.round() as u64;
        if n > 0 {
            d_max = d_max.max(crate::physics::law::largest_diameter(s));
        }
        ends.push(ends.last().copied().unwrap_or(0) + n);
    }
    let n = ends.last().copied().unwrap_or(0);
    if n == 0 {
        return Ok((Vec::new(), 1.0));
    }

    let walls = DrumWalls::of(&case.drum);
    // inside the lifters' tips, if any
    let radius = walls.clear_radius();
    // at full size no wall overlap (a rough wall's particles stick out by half their size)
    let rough = case
        .drum
        .rough_wall
        .as_ref()
        .map_or(0.0, |r| 0.5 * r.diameter);
    let room = radius - 0.5 * d_max - rough;
    if room <= 0.0 {
        return Err(format!(
            "init.fill: a particle of diameter {d_max} does not fit in the drum (diameter {})",
            case.drum.diameter
        ));
    }
    let room_volume = walls.vessel.placement_volume(room, 0.5 * d_max);
    let mut c = (room_volume * CELL_OCCUPANCY / n as f64).cbrt();
    let grid = loop {
        let grid = Grid::new(case, c, d_max, room, &walls);
        if grid.cells() as f64 * CELL_OCCUPANCY >= n as f64 {
            break grid;
        }
        c *= 0.99;
        if c < 1e-3 * d_max {
            return Err(format!(
                "init.fill: {n} particles do not fit in the drum; the fill is too high"
            ));
        }
    };

    // points per layer in proportion to its cells, and the id of each layer's first point
    let cells = grid.cells() as u128;
    let mut before = 0u128;
    let mut firsts = Vec::with_capacity(grid.layers.len() + 1);
    firsts.push(0u64);
    for &e in &grid.eligible {
        before += e as u128;
        firsts.push((before * n as u128 / cells) as u64);
    }

    let dealt = Permutation::new(n, case.seed, Purpose::Species, 0);
    let a = grid.jitter;
    let mut placed = Vec::new();
    for (l, &z) in grid.layers.iter().enumerate() {
        let (first, count) = (firsts[l], firsts[l + 1] - firsts[l]);
        if count == 0 || !share.meets(z - a, z + a) {
            continue;
        }
        let chosen = Permutation::new(grid.eligible[l], case.seed, Purpose::Cells, l as u64);
        let (mut cell, mut id) = (0u64, first);
        'layer: for (j, k) in grid.rows(z) {
            for i in -(k as i64)..=k as i64 {
                let take = chosen.apply(cell) < count;
                cell += 1;
                if !take {
                    continue;
                }
                let mut at = keyed::stream(case.seed, Purpose::Jitter, id);
                let mut off = || a * (2.0 * at.gen::<f64>() - 1.0);
                let x = [
                    i as f64 * grid.c + off(),
                    j as f64 * grid.c + off(),
                    z + off(),
                ];
                if share.owns(x[2]) {
                    let s = ends.partition_point(|&e| e <= dealt.apply(id));
                    let mut rng = keyed::stream(case.seed, Purpose::Particle, id);
                    let d = diameter(&case.species[s], &mut rng);
                    placed.push(ParticleState::new(id, s as u8, d, x, [0.0; 3], [0.0; 3]));
                }
                id += 1;
                if id == first + count {
                    break 'layer;
                }
            }
        }
    }
    Ok((placed, grid.scale))
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
    let fill = case.init.fill.unwrap_or(0.0);
    let h = sim.walls.cut_height(fill);
    sim.remove_where(|s| s.x[1] > h);
    let kept = sim.global_count();

    // How high the bed reaches: the highest centre in each axial slice, averaged. Slices
    // three largest diameters wide hold enough of the top layer that the highest centre
    // lies within a few percent of a diameter of the cut (one diameter wide: ~15 %).
    let top = sim.bed_top(3.0 * case.d_max());
    let measured_fill = sim.walls.fill_below(top);
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
        let (points, scale) = points(&case, &Share::everything()).unwrap();
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
