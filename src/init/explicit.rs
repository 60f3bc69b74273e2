//! Initial states given particle by particle: `[[init.particle]]` tables in the case, or an
//! HDF5 file with the `/particles` layout of a run's output (so a run can start from an
//! edited state or a bed poured elsewhere). Particles must lie inside the drum and may not
//! overlap by more than `run.max_overlap` of the smaller diameter.

use crate::case::{Case, Shape};
use crate::particles::ParticleState;
use std::collections::HashMap;

/// The particles of `case` (`init.kind = "particles"`), sorted by id.
pub fn explicit(case: &Case) -> Result<Vec<ParticleState>, String> {
    let mut out = match &case.init.file {
        Some(path) => read_file(path)?,
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
            .collect(),
    };
    out.sort_by_key(|p| p.id);
    check(case, &out)?;
    Ok(out)
}

fn read_file(path: &str) -> Result<Vec<ParticleState>, String> {
    let bad = |e: hdf5::Error| format!("init.file: cannot read particles from {path}: {e}");
    let f = hdf5::File::open(path).map_err(bad)?;
    let id: Vec<u64> = f
        .dataset("particles/id")
        .and_then(|d| d.read_raw())
        .map_err(bad)?;
    let species: Vec<u8> = f
        .dataset("particles/species")
        .and_then(|d| d.read_raw())
        .map_err(bad)?;
    let diameter: Vec<f64> = f
        .dataset("particles/diameter")
        .and_then(|d| d.read_raw())
        .map_err(bad)?;
    let vec3 = |name: &str| -> Result<Vec<f64>, String> {
        let v: Vec<f64> = f
            .dataset(&format!("particles/{name}"))
            .and_then(|d| d.read_raw())
            .map_err(bad)?;
        if v.len() != 3 * id.len() {
            return Err(format!(
                "init.file: {path}: particles/{name} has {} values, expected {}",
                v.len(),
                3 * id.len()
            ));
        }
        Ok(v)
    };
    let (x, v, w) = (
        vec3("position")?,
        vec3("velocity")?,
        vec3("angular_velocity")?,
    );
    if species.len() != id.len() || diameter.len() != id.len() {
        return Err(format!(
            "init.file: {path}: the /particles datasets differ in length"
        ));
    }
    Ok((0..id.len())
        .map(|i| {
            let t = |a: &[f64]| [a[3 * i], a[3 * i + 1], a[3 * i + 2]];
            ParticleState::new(id[i], species[i], diameter[i], t(&x), t(&v), t(&w))
        })
        .collect())
}

fn check(case: &Case, ps: &[ParticleState]) -> Result<(), String> {
    let radius = 0.5 * case.drum.diameter;
    let half = 0.5 * case.drum.axial_length();
    let max_overlap = case.run.max_overlap;
    for w in ps.windows(2) {
        if w[0].id == w[1].id {
            return Err(format!("init: particle id {} appears twice", w[0].id));
        }
    }
    let source = case.init.file.as_deref().map_or_else(
        || "[[init.particle]]".to_string(),
        |f| format!("init.file {f}"),
    );
    let unusable: Vec<String> = ps.iter().filter_map(unusable).collect();
    if let Some(first) = unusable.first() {
        let more = match unusable.len() {
            1 => String::new(),
            n => format!(" ({n} particles of {source} are unusable)"),
        };
        return Err(format!("init: {first}{more}"));
    }
    for p in ps {
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
        let outside = match case.drum.shape {
            Shape::Sphere => (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt() + r > radius,
            Shape::Cylinder => {
                (x[0] * x[0] + x[1] * x[1]).sqrt() + r > radius
                    || (!case.drum.periodic() && x[2].abs() + r > half)
                    || (case.drum.periodic() && !(-half..half).contains(&x[2]))
            }
        };
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
