//! `tumbler export FILE --lammps OUT.data [--group G]`: a run's particles (the final
//! `/particles`, or one `/snapshots/NNNNNNNNNN`) as a LAMMPS data file for
//! `atom_style sphere`, so that another code can start from the same bed.
//!
//! The file holds `N atoms`, `S atom types` (one per species of the case, type = species
//! index + 1), a box around the drum (`[-R, R] x [-R, R] x [-L/2, L/2]`, padded by
//! [`BOX_PAD`] of `D` on every side that is not periodic; a periodic drum's `z` extent is
//! exactly its length, for `boundary f f p`), an `Atoms # sphere` section
//! (`id type diameter density x y z`) and a `Velocities` section (`id vx vy vz wx wy wz`).
//! LAMMPS ids start at 1: the atom id is the particle's id + 1. The density is the case's
//! `model.density`; units are the case's (SI for the spring-dashpot family: `units si`).
//! The first line says which units and boundaries to declare before `read_data`.

use super::reader::attr_number;
use super::{InspectError, RunReader};
use crate::case::{Case, Family, Shape};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Padding of the box beyond the walls, as a fraction of the drum diameter (each side).
pub const BOX_PAD: f64 = 0.005;

/// What `tumbler export` wrote.
#[derive(Debug, Clone)]
pub struct Exported {
    /// The data file.
    pub path: PathBuf,
    /// The group the particles came from (`/particles`, `/snapshots/NNNNNNNNNN`).
    pub group: String,
    /// Number of atoms written.
    pub atoms: usize,
    /// Number of atom types (species of the case).
    pub types: usize,
    /// `boundary` flags to declare in LAMMPS (`f f f`, `f f p`).
    pub boundary: &'static str,
}

impl std::fmt::Display for Exported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "wrote {}: {} atoms of {} types from {} (atom_style sphere, boundary {}; LAMMPS id = id + 1, type = species + 1)",
            self.path.display(),
            self.atoms,
            self.types,
            self.group,
            self.boundary
        )
    }
}

/// The particles of one group, as read (vectors flattened, three per particle).
pub(super) struct Particles {
    pub(super) id: Vec<u64>,
    pub(super) species: Vec<u64>,
    pub(super) diameter: Vec<f64>,
    pub(super) position: Vec<f64>,
    pub(super) velocity: Vec<f64>,
    pub(super) angular_velocity: Vec<f64>,
}

/// `particles` (default) or `snapshots/NNNNNNNNNN`, without slashes at the ends.
pub(super) fn group_name(group: Option<&str>) -> String {
    group
        .map(|g| g.trim().trim_matches('/').to_string())
        .filter(|g| !g.is_empty())
        .unwrap_or_else(|| "particles".to_string())
}

/// The refusal for a group the file does not hold, with what it does hold.
fn missing_group(reader: &RunReader, group: &str) -> InspectError {
    let snapshots: Vec<String> = reader
        .file()
        .group("snapshots")
        .and_then(|g| g.member_names())
        .unwrap_or_default();
    let listed = match snapshots.len() {
        0 => "the file holds no snapshots".to_string(),
        n if n <= 4 => format!("its snapshots: snapshots/{}", snapshots.join(", snapshots/")),
        n => format!(
            "its snapshots: snapshots/{}, ..., snapshots/{} ({n}; `tumbler info FILE --all` lists them)",
            snapshots[0],
            snapshots[n - 1]
        ),
    };
    let hint = if group == "particles" {
        format!(
            " (a run writes /particles when it finishes; an unfinished run's .partial file has none). Choose a snapshot with --group; {listed}"
        )
    } else {
        format!("; --group takes `particles` or `snapshots/NNNNNNNNNN`, and {listed}")
    };
    reader.missing(group, &hint)
}

/// The particles of `group`, or a refusal naming what the file holds.
pub(super) fn read_group(reader: &RunReader, group: &str) -> Result<Particles, InspectError> {
    if !reader.has(group) || reader.file().group(group).is_err() {
        return Err(missing_group(reader, group));
    }
    let name = |d: &str| format!("{group}/{d}");
    let ints = |d: &str| -> Result<Vec<u64>, InspectError> {
        let n = name(d);
        reader
            .dataset(&n)?
            .read_raw::<u64>()
            .map_err(|e| reader.layout(&n, format!("cannot be read as integers ({e})")))
    };
    let id = ints("id")?;
    let species = ints("species")?;
    let diameter = reader.vector(&name("diameter"))?;
    let n = id.len();
    reader.check_len(&name("species"), species.len(), n, "particles")?;
    reader.check_len(&name("diameter"), diameter.len(), n, "particles")?;
    let vec3 = |d: &str| -> Result<Vec<f64>, InspectError> {
        let full = name(d);
        let a = reader.array(&full, &["N", "3"])?;
        if a.shape() != [n, 3] {
            return Err(reader.layout(
                &full,
                format!(
                    "has shape {} where {n} x 3 was expected",
                    super::format_shape(a.shape())
                ),
            ));
        }
        Ok(a.iter().copied().collect())
    };
    Ok(Particles {
        position: vec3("position")?,
        velocity: vec3("velocity")?,
        angular_velocity: vec3("angular_velocity")?,
        id,
        species,
        diameter,
    })
}

/// Box bounds `[lo, hi]` along x, y, z and the `boundary` flags.
fn box_of(case: &Case) -> ([[f64; 2]; 3], &'static str) {
    let r = 0.5 * case.drum.diameter;
    let pad = BOX_PAD * case.drum.diameter;
    let side = [-r - pad, r + pad];
    match case.drum.shape {
        Shape::Sphere => ([side, side, side], "f f f"),
        _ => {
            let h = 0.5 * case.drum.axial_length();
            if case.drum.periodic() {
                ([side, side, [-h, h]], "f f p")
            } else {
                ([side, side, [-h - pad, h + pad]], "f f f")
            }
        }
    }
}

/// Write the particles of `group` (default `particles`) of the run open in `reader` to `out`
/// as a LAMMPS data file (module documentation).
pub fn export_lammps(
    reader: &RunReader,
    out: &Path,
    group: Option<&str>,
) -> Result<Exported, InspectError> {
    let group = group_name(group);
    let case = reader.case()?;
    let p = read_group(reader, &group)?;
    let types = case.species.len();
    if let Some((i, s)) = p
        .species
        .iter()
        .enumerate()
        .find(|(_, &s)| s as usize >= types)
    {
        return Err(reader.layout(
            &format!("{group}/species"),
            format!(
                "gives particle {} species {s}, but the case has {types} species",
                p.id[i]
            ),
        ));
    }
    let (bounds, boundary) = box_of(&case);
    let units = match case.model.family {
        Family::SpringDashpot => "units si",
        Family::Rapaport => "units lj (Rapaport's reduced units)",
    };
    let at = reader
        .file()
        .group(&group)
        .ok()
        .and_then(|g| attr_number(&g, "rotations"))
        .map(|r| format!(" at {r} rotations"))
        .unwrap_or_default();
    let title: String = case
        .title
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let density = case.model.density;

    let mut text = String::with_capacity(160 * (p.id.len() + 1));
    let _ = writeln!(
        text,
        "LAMMPS data file for atom_style sphere, {units}, boundary {boundary}: tumbler export of {} /{group}{at} ({title}); id = tumbler id + 1, type = species + 1",
        reader.path().display()
    );
    let _ = writeln!(text);
    let _ = writeln!(text, "{} atoms", p.id.len());
    let _ = writeln!(text, "{types} atom types");
    let _ = writeln!(text);
    for (b, axis) in bounds.iter().zip(["x", "y", "z"]) {
        let _ = writeln!(text, "{:e} {:e} {axis}lo {axis}hi", b[0], b[1]);
    }
    let _ = writeln!(text);
    let _ = writeln!(text, "Atoms # sphere");
    let _ = writeln!(text);
    for i in 0..p.id.len() {
        let x = &p.position[3 * i..3 * i + 3];
        let _ = writeln!(
            text,
            "{} {} {:e} {density} {:e} {:e} {:e}",
            p.id[i] + 1,
            p.species[i] + 1,
            p.diameter[i],
            x[0],
            x[1],
            x[2]
        );
    }
    let _ = writeln!(text);
    let _ = writeln!(text, "Velocities");
    let _ = writeln!(text);
    for i in 0..p.id.len() {
        let v = &p.velocity[3 * i..3 * i + 3];
        let w = &p.angular_velocity[3 * i..3 * i + 3];
        let _ = writeln!(
            text,
            "{} {:e} {:e} {:e} {:e} {:e} {:e}",
            p.id[i] + 1,
            v[0],
            v[1],
            v[2],
            w[0],
            w[1],
            w[2]
        );
    }
    let write_err = |e: std::io::Error| InspectError::Write {
        path: out.display().to_string(),
        reason: e.to_string(),
    };
    write_atomically(out, text.as_bytes()).map_err(write_err)?;
    Ok(Exported {
        path: out.to_path_buf(),
        group: format!("/{group}"),
        atoms: p.id.len(),
        types,
        boundary,
    })
}

/// Write `bytes` to `path` through a temporary file beside it, renamed when complete (a
/// failed write leaves no partial file).
pub(super) fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write as _;
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let written = std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}
