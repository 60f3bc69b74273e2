//! Initial states given particle by particle: `[[init.particle]]` tables in the case, or an
//! HDF5 file with the `/particles` layout of a run's output (so a run can start from an
//! edited state or a bed poured elsewhere). Particles must lie inside the drum and may not
//! overlap by more than `run.max_overlap` of the smaller diameter.

use super::Share;
use crate::case::Case;
use crate::comm::Comm;
use crate::particles::ParticleState;
use std::collections::HashMap;

/// The particles of `case` (`init.kind = "particles"`) in `share`, sorted by id.
///
/// A file is read in blocks, keeping only the particles near the share: those in it, and
/// those within a largest diameter of it, against which its own are checked for overlaps.
/// Ids must be unique over the whole state; a rank sees only its part, so the run checks
/// that across the ranks (`Sim::duplicate_id`).
pub fn explicit(case: &Case, share: &Share) -> Result<Vec<ParticleState>, String> {
    let margin = case
        .species
        .iter()
        .map(crate::physics::law::largest_diameter)
        .fold(0.0, f64::max);
    let near = |z: f64| share.owns(z) || share.meets(z - margin, z + margin) || !z.is_finite();
    let mut out: Vec<ParticleState> = match &case.init.file {
        Some(path) => read_file(path, &near)?,
        None => case
            .init
            .particle
            .iter()
            .enumerate()
            .map(|(k, p)| {
                ParticleState::new(
                    k as u64,
                    p.species,
                    p.diameter,
                    p.position,
                    p.velocity,
                    p.angular_velocity,
                )
            })
            .filter(|p| near(p.x[2]))
            .collect(),
    };
    out.sort_by_key(|p| p.id);
    check(case, &out, &|p: &ParticleState| {
        share.owns(p.x[2]) || !p.x[2].is_finite()
    })?;
    out.retain(|p| share.owns(p.x[2]));
    Ok(out)
}

/// The smallest id that two particles share, over the parts `ps` of all ranks (every
/// rank calls this together); each rank checks the ids `id % ranks` that fall to it.
pub fn duplicate_id(ps: &[ParticleState], comm: &dyn Comm) -> Option<u64> {
    let n = comm.size();
    let mut to = vec![Vec::new(); n];
    for p in ps {
        // ids are below 2^40, exact in an f64
        to[(p.id % n as u64) as usize].push(p.id as f64);
    }
    let mut ids: Vec<u64> = comm
        .all_to_all(to)
        .into_iter()
        .flatten()
        .map(|x| x as u64)
        .collect();
    ids.sort_unstable();
    let mine = ids.windows(2).find(|w| w[0] == w[1]).map(|w| w[0] as f64);
    let first = -comm.max_f64(-mine.unwrap_or(f64::INFINITY));
    first.is_finite().then_some(first as u64)
}

/// Where explicit particles come from, as messages name it.
fn source(case: &Case) -> String {
    case.init.file.as_deref().map_or_else(
        || "[[init.particle]]".to_string(),
        |f| format!("init.file {f}"),
    )
}

/// The refusal of two particles sharing the id `id`.
pub fn duplicate(case: &Case, id: u64) -> String {
    format!(
        "init: particle id {id} appears twice in {}: ids must be unique",
        source(case)
    )
}

/// Rows of a particle file read at a time.
const BLOCK: usize = 1 << 18;

/// The particles of the file at `path` whose `z` passes `keep`, read block by block.
fn read_file(path: &str, keep: &dyn Fn(f64) -> bool) -> Result<Vec<ParticleState>, String> {
    let bad = |e: hdf5::Error| format!("init.file: cannot read particles from {path}: {e}");
    let f = hdf5::File::open(path).map_err(bad)?;
    let open = |name: &str| f.dataset(&format!("particles/{name}")).map_err(bad);
    let (id, species, diameter) = (open("id")?, open("species")?, open("diameter")?);
    let (x, v, w) = (
        open("position")?,
        open("velocity")?,
        open("angular_velocity")?,
    );
    let n = id.size();
    if species.size() != n || diameter.size() != n {
        return Err(format!(
            "init.file: {path}: the /particles datasets differ in length"
        ));
    }
    for (name, d) in [("position", &x), ("velocity", &v), ("angular_velocity", &w)] {
        // rows of three, or the same values in one flat list
        if d.shape() != [n, 3] && d.shape() != [3 * n] {
            return Err(format!(
                "init.file: {path}: particles/{name} has shape {:?}, expected [{n}, 3]",
                d.shape()
            ));
        }
    }
    let mut out = Vec::new();
    for lo in (0..n).step_by(BLOCK) {
        let hi = (lo + BLOCK).min(n);
        let rows = |d: &hdf5::Dataset| -> Result<Vec<f64>, String> {
            if d.ndim() == 1 {
                return Ok(d.read_slice_1d(3 * lo..3 * hi).map_err(bad)?.to_vec());
            }
            let a = d
                .read_slice_2d::<f64, _>(ndarray::s![lo..hi, ..])
                .map_err(bad)?;
            Ok(a.iter().copied().collect())
        };
        let xs = rows(&x)?;
        let kept: Vec<usize> = (0..hi - lo).filter(|&i| keep(xs[3 * i + 2])).collect();
        if kept.is_empty() {
            continue;
        }
        let ids: Vec<u64> = id.read_slice_1d(lo..hi).map_err(bad)?.to_vec();
        let sps: Vec<u8> = species.read_slice_1d(lo..hi).map_err(bad)?.to_vec();
        let ds: Vec<f64> = diameter.read_slice_1d(lo..hi).map_err(bad)?.to_vec();
        let (vs, ws) = (rows(&v)?, rows(&w)?);
        for i in kept {
            let t = |a: &[f64]| [a[3 * i], a[3 * i + 1], a[3 * i + 2]];
            out.push(ParticleState::new(
                ids[i],
                sps[i],
                ds[i],
                t(&xs),
                t(&vs),
                t(&ws),
            ));
        }
    }
    Ok(out)
}

/// Check the particles `mine` holds (the others of `ps` only take part in its overlaps).
fn check(
    case: &Case,
    ps: &[ParticleState],
    mine: &dyn Fn(&ParticleState) -> bool,
) -> Result<(), String> {
    let walls = crate::physics::DrumWalls::of(&case.drum);
    let half = 0.5 * case.drum.axial_length();
    let max_overlap = case.run.max_overlap;
    let source = source(case);
    for w in ps.windows(2) {
        if w[0].id == w[1].id && (mine(&w[0]) || mine(&w[1])) {
            return Err(duplicate(case, w[0].id));
        }
    }
    let unusable: Vec<String> = ps.iter().filter(|p| mine(p)).filter_map(unusable).collect();
    if let Some(first) = unusable.first() {
        let more = match unusable.len() {
            1 => String::new(),
            n => format!(" ({n} particles of {source} are unusable)"),
        };
        return Err(format!("init: {first}{more}"));
    }
    for p in ps.iter().filter(|p| mine(p)) {
        if p.species as usize >= case.species.len() {
            return Err(format!(
                "init: particle {} has species {}, but the case has {}",
                p.id,
                p.species,
                case.species.len()
            ));
        }
        if p.id >= crate::physics::rough_wall::FIRST_ID {
            return Err(format!(
                "init: particle id {} is too large (ids below 2^40 are accepted)",
                p.id
            ));
        }
        // the interaction range (cells, halo) is sized from the species' diameters
        let largest = crate::physics::law::largest_diameter(&case.species[p.species as usize]);
        if p.diameter > largest * (1.0 + 1e-12) {
            return Err(format!(
                "init: particle {} has diameter {}, larger than its species allows ({largest}): raise \
                 species.{}.diameter or diameter_sd",
                p.id, p.diameter, p.species
            ));
        }
        // overlaps up to the run's health limit are accepted (with walls as between particles):
        // a settled bed of soft particles, a run's own output, overlaps by several percent
        let r = 0.5 * p.diameter - max_overlap * p.diameter;
        let x = p.x;
        let outside =
            !walls.inside(x, r) || (case.drum.periodic() && !(-half..half).contains(&x[2]));
        if outside || !x.iter().all(|c| c.is_finite()) {
            return Err(format!(
                "init: particle {} at ({}, {}, {}) is not inside the drum",
                p.id, x[0], x[1], x[2]
            ));
        }
    }
    let cell = ps.iter().map(|p| p.diameter).fold(0.0, f64::max).max(1e-12);
    let key = |x: &[f64; 3]| {
        [
            (x[0] / cell).floor() as i64,
            (x[1] / cell).floor() as i64,
            (x[2] / cell).floor() as i64,
        ]
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in ps.iter().enumerate() {
        grid.entry(key(&p.x)).or_default().push(i);
    }
    for (i, p) in ps.iter().enumerate() {
        let c = key(&p.x);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                        .map(Vec::as_slice)
                        .unwrap_or(&[])
                    {
                        if j <= i {
                            continue;
                        }
                        let q = &ps[j];
                        if !mine(p) && !mine(q) {
                            continue;
                        }
                        let d: f64 = (0..3)
                            .map(|k| (p.x[k] - q.x[k]).powi(2))
                            .sum::<f64>()
                            .sqrt();
                        let overlap = 0.5 * (p.diameter + q.diameter) - d;
                        if overlap > max_overlap * p.diameter.min(q.diameter) {
                            return Err(format!(
                                "init: particles {} and {} overlap by {:.2} % of the smaller diameter (at most {} % is accepted: run.max_overlap)",
                                p.id, q.id, 100.0 * overlap / p.diameter.min(q.diameter), 100.0 * max_overlap
                            ));
                        }
                    }
                }
            }
        }
    }
    Ok(())
}

/// Why particle `p` cannot start a run: a diameter that is not a positive number, or a
/// position, velocity or angular velocity that is not finite.
fn unusable(p: &ParticleState) -> Option<String> {
    if !(p.diameter.is_finite() && p.diameter > 0.0) {
        return Some(format!(
            "particle {} has diameter {}: it must be a positive length",
            p.id, p.diameter
        ));
    }
    for (what, a) in [
        ("position", p.x),
        ("velocity", p.v),
        ("angular velocity", p.w),
    ] {
        if !a.iter().all(|c| c.is_finite()) {
            return Some(format!(
                "particle {} has {what} ({}, {}, {}): every component must be a finite number",
                p.id, a[0], a[1], a[2]
            ));
        }
    }
    None
}
