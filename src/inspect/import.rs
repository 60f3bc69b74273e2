//! `tumbler import --lammps data|dump FILE -o OUT.h5`: a bed made by LAMMPS or LIGGGHTS
//! as an HDF5 file with the `/particles` layout of a run's output, which `init.file` reads
//! (docs/interop.md).
//!
//! - A **data file** (`atom_style sphere`): the `N atoms` header, the `Atoms` section
//!   (`id type diameter density x y z`, optional image flags, which are ignored: the
//!   coordinates are taken as they are) and the optional `Velocities` section
//!   (`id vx vy vz wx wy wz`); other sections are skipped.
//! - A **text dump** (`dump custom`, LIGGGHTS' `dump custom` too): the snapshot of the last
//!   `ITEM: TIMESTEP` (or the chosen one), whose `ITEM: ATOMS` line names the columns in any
//!   order: `id`, `type`, the position as `x y z`, `xu yu zu` (unwrapped) or `xs ys zs`,
//!   `xsu ysu zsu` (scaled by the box of `ITEM: BOX BOUNDS`), `radius` or `diameter`, and
//!   optionally `vx vy vz` and `omegax omegay omegaz` (zero when absent, which the summary
//!   says). Other columns are ignored.
//!
//! The particle's id is the LAMMPS id - 1 (the inverse of `tumbler export --lammps`), its
//! species the atom type - 1 unless `--species` maps the types. tumbler's drum axis is `z`
//! and gravity points along `-y`; a bed in another frame is turned with `--axes` (which
//! LAMMPS axis, with its sign, becomes tumbler's `x`, `y` and `z`: a rotation, not a
//! mirror) and moved with `--offset` (added after turning; tumbler's origin is on the
//! axis at mid-length). Values are taken as they are: no unit conversion.
//!
//! Every refusal names the file, the line and what is wrong; nothing is written then. The
//! output is written under a temporary name and renamed when complete.

use super::InspectError;

mod lammps_data;
mod lammps_dump;

use crate::particles::ParticleState;
use lammps_data::parse_data;
use lammps_dump::parse_dump;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Which LAMMPS text format the input is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LammpsKind {
    /// A data file (`read_data`/`write_data`), `atom_style sphere`.
    Data,
    /// A text dump (`dump custom`/LIGGGHTS).
    Dump,
}

/// What `tumbler import` is asked to do.
#[derive(Debug, Clone)]
pub struct ImportOptions {
    /// The input file.
    pub input: PathBuf,
    /// Its format.
    pub kind: LammpsKind,
    /// The HDF5 file to write.
    pub output: PathBuf,
    /// Dump: the timestep to take (default the last).
    pub timestep: Option<u64>,
    /// `TYPE=SPECIES,...` (default: species = type - 1).
    pub species: Option<String>,
    /// `A,B,C`: the (signed) LAMMPS axes that become tumbler's x, y, z (default `x,y,z`).
    pub axes: Option<String>,
    /// `DX,DY,DZ` added to the positions after turning them.
    pub offset: Option<String>,
    /// Replace the output if it exists.
    pub overwrite: bool,
}

/// What `tumbler import` wrote.
#[derive(Debug, Clone)]
pub struct Imported {
    /// The HDF5 file.
    pub path: PathBuf,
    /// Particles written.
    pub particles: usize,
    /// Where they came from (`timestep 1000 of ...`, `data file ...`).
    pub source: String,
    /// Columns that were absent and set to zero.
    pub zeroed: Vec<&'static str>,
}

impl std::fmt::Display for Imported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "wrote {}: {} particles from {} (id = LAMMPS id - 1; start a run from it with init.kind = \"particles\", init.file = \"{}\")",
            self.path.display(),
            self.particles,
            self.source,
            self.path.display()
        )?;
        if !self.zeroed.is_empty() {
            writeln!(
                f,
                "note: the dump has no {} columns: set to zero",
                self.zeroed.join(", ")
            )?;
        }
        Ok(())
    }
}

/// A particle as read, in the LAMMPS frame, with the line it came from.
#[derive(Debug, Clone)]
struct Atom {
    id: u64,
    kind: u64,
    diameter: f64,
    x: [f64; 3],
    v: [f64; 3],
    w: [f64; 3],
    line: usize,
}

/// A refusal about `path` at `line` (1-based).
fn at(path: &Path, line: usize, what: impl std::fmt::Display) -> InspectError {
    InspectError::Invalid(format!("{}:{line}: {what}", path.display()))
}

/// A finite number in column `col` (1-based) of a line.
fn number(
    path: &Path,
    line: usize,
    col: usize,
    word: &str,
    what: &str,
) -> Result<f64, InspectError> {
    match word.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(at(
            path,
            line,
            format!("column {col} ({what}) is {word}: it must be a finite number"),
        )),
        Err(_) => Err(at(
            path,
            line,
            format!("column {col} ({what}) is `{word}`, not a number"),
        )),
    }
}

/// A positive integer (id, type) in column `col` of a line.
fn positive(
    path: &Path,
    line: usize,
    col: usize,
    word: &str,
    what: &str,
) -> Result<u64, InspectError> {
    match word.parse::<u64>() {
        Ok(v) if v >= 1 => Ok(v),
        _ => Err(at(
            path,
            line,
            format!("column {col} ({what}) is `{word}`: it must be a whole number from 1"),
        )),
    }
}

/// The lines of a text file without comments (`#` to the end) and surrounding blanks,
/// numbered from 1.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().map(|(i, l)| {
        let l = l.split('#').next().unwrap_or("").trim();
        (i + 1, l)
    })
}
/// Atom index by id; refuses a duplicate id.
fn index_of(path: &Path, atoms: &[Atom]) -> Result<HashMap<u64, usize>, InspectError> {
    let mut index = HashMap::with_capacity(atoms.len());
    for (k, a) in atoms.iter().enumerate() {
        if let Some(first) = index.insert(a.id, k) {
            return Err(at(
                path,
                a.line,
                format!(
                    "atom id {} again (first on line {}): ids must be unique",
                    a.id, atoms[first].line
                ),
            ));
        }
    }
    Ok(index)
}
/// `TYPE=SPECIES,...` as a map (`--species`).
fn species_map(text: &str) -> Result<HashMap<u64, u8>, InspectError> {
    let bad = |why: String| {
        InspectError::Invalid(format!(
            "--species {text}: {why}; write it as TYPE=SPECIES pairs, e.g. `1=0,2=1`"
        ))
    };
    let mut map = HashMap::new();
    for pair in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (t, s) = pair
            .split_once('=')
            .ok_or_else(|| bad(format!("`{pair}` has no `=`")))?;
        let t: u64 = t
            .trim()
            .parse()
            .ok()
            .filter(|&t| t >= 1)
            .ok_or_else(|| bad(format!("`{t}` is not an atom type (a whole number from 1)")))?;
        let s: u8 = s
            .trim()
            .parse()
            .map_err(|_| bad(format!("`{s}` is not a species index (0 to 255)")))?;
        if map.insert(t, s).is_some() {
            return Err(bad(format!("type {t} is mapped twice")));
        }
    }
    if map.is_empty() {
        return Err(bad("no pairs".into()));
    }
    Ok(map)
}

/// `--axes A,B,C`: for each tumbler axis the LAMMPS axis and sign it takes.
fn axes(text: &str) -> Result<[(usize, f64); 3], InspectError> {
    let bad = |why: &str| {
        InspectError::Invalid(format!("--axes {text}: {why}; give the LAMMPS axes (x, y, z, each with an optional -) that become tumbler's x, y and z, e.g. `y,z,x` for a drum along LAMMPS x with gravity along -z"))
    };
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(bad("three axes are needed"));
    }
    let mut out = [(0, 1.0); 3];
    for (k, p) in parts.iter().enumerate() {
        let (sign, name) = match p.strip_prefix('-') {
            Some(rest) => (-1.0, rest),
            None => (1.0, p.strip_prefix('+').unwrap_or(p)),
        };
        let a = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return Err(bad(&format!("`{p}` is not an axis"))),
        };
        out[k] = (a, sign);
    }
    let mut used = [false; 3];
    for (a, _) in out {
        if std::mem::replace(&mut used[a], true) {
            return Err(bad("each LAMMPS axis can be used once"));
        }
    }
    // determinant of the signed permutation: +1 for a rotation
    let perm_sign = {
        let p = [out[0].0, out[1].0, out[2].0];
        let inversions = (0..3)
            .flat_map(|i| (i + 1..3).map(move |j| (i, j)))
            .filter(|&(i, j)| p[i] > p[j])
            .count();
        if inversions % 2 == 0 {
            1.0
        } else {
            -1.0
        }
    };
    if perm_sign * out[0].1 * out[1].1 * out[2].1 < 0.0 {
        return Err(bad("this is a mirror image, which would turn the particles' spins and the drum's sense of rotation around (negate one axis to make it a rotation)"));
    }
    Ok(out)
}

/// `--offset DX,DY,DZ`.
fn offset(text: &str) -> Result<[f64; 3], InspectError> {
    let v: Vec<f64> = text
        .split(',')
        .filter_map(|w| w.trim().parse::<f64>().ok())
        .filter(|x| x.is_finite())
        .collect();
    if v.len() != 3 || text.split(',').count() != 3 {
        return Err(InspectError::Invalid(format!("--offset {text}: give three finite numbers DX,DY,DZ (added to the positions after --axes)")));
    }
    Ok([v[0], v[1], v[2]])
}

/// Read the input of `opts` into particle states (sorted by id) and a description.
fn read(
    opts: &ImportOptions,
) -> Result<(Vec<ParticleState>, String, Vec<&'static str>), InspectError> {
    let path = &opts.input;
    let text = std::fs::read_to_string(path).map_err(|e| InspectError::File {
        path: path.display().to_string(),
        reason: e.to_string().to_lowercase(),
    })?;
    let map = opts.species.as_deref().map(species_map).transpose()?;
    let turn =
        opts.axes
            .as_deref()
            .map(axes)
            .transpose()?
            .unwrap_or([(0, 1.0), (1, 1.0), (2, 1.0)]);
    let shift = opts
        .offset
        .as_deref()
        .map(offset)
        .transpose()?
        .unwrap_or([0.0; 3]);
    let (atoms, source, zeroed) = match opts.kind {
        LammpsKind::Data => (
            parse_data(path, &text)?,
            format!("data file {}", path.display()),
            Vec::new(),
        ),
        LammpsKind::Dump => {
            let (step, atoms, zeroed) = parse_dump(path, &text, opts.timestep)?;
            (
                atoms,
                format!("timestep {step} of {}", path.display()),
                zeroed,
            )
        }
    };
    let rotate = |v: [f64; 3]| {
        [
            turn[0].1 * v[turn[0].0],
            turn[1].1 * v[turn[1].0],
            turn[2].1 * v[turn[2].0],
        ]
    };
    let mut out = Vec::with_capacity(atoms.len());
    for a in atoms {
        let species = match &map {
            Some(m) => *m.get(&a.kind).ok_or_else(|| {
                at(
                    path,
                    a.line,
                    format!(
                        "atom {} has type {}, which --species does not map",
                        a.id, a.kind
                    ),
                )
            })?,
            None => u8::try_from(a.kind - 1).map_err(|_| {
                at(
                    path,
                    a.line,
                    format!(
                        "atom {} has type {}: more types than species; map them with --species",
                        a.id, a.kind
                    ),
                )
            })?,
        };
        let mut x = rotate(a.x);
        for k in 0..3 {
            x[k] += shift[k];
        }
        out.push(ParticleState::new(
            a.id - 1,
            species,
            a.diameter,
            x,
            rotate(a.v),
            rotate(a.w),
        ));
    }
    out.sort_by_key(|p| p.id);
    Ok((out, source, zeroed))
}

/// Write `ps` as `/particles` of a new HDF5 file at `path` (through a temporary name).
fn write_particles(
    path: &Path,
    ps: &[ParticleState],
    source: &str,
    overwrite: bool,
) -> Result<(), InspectError> {
    let fail = |e: String| InspectError::Write {
        path: path.display().to_string(),
        reason: e,
    };
    if path.exists() && !overwrite {
        return Err(InspectError::Invalid(format!(
            "{} exists: choose another -o, or add --overwrite to replace it",
            path.display()
        )));
    }
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let n = ps.len();
    let written = (|| -> hdf5::Result<()> {
        let f = hdf5::File::create(&tmp)?;
        let g = f.create_group("particles")?;
        let id: Vec<u64> = ps.iter().map(|p| p.id).collect();
        let species: Vec<u8> = ps.iter().map(|p| p.species).collect();
        let diameter: Vec<f64> = ps.iter().map(|p| p.diameter).collect();
        g.new_dataset_builder().with_data(&id).create("id")?;
        g.new_dataset_builder()
            .with_data(&species)
            .create("species")?;
        g.new_dataset_builder()
            .with_data(&diameter)
            .create("diameter")?;
        for (name, get) in [
            (
                "position",
                (|p: &ParticleState| p.x) as fn(&ParticleState) -> [f64; 3],
            ),
            ("velocity", |p: &ParticleState| p.v),
            ("angular_velocity", |p: &ParticleState| p.w),
        ] {
            let a = ndarray::Array2::from_shape_fn((n, 3), |(i, k)| get(&ps[i])[k]);
            g.new_dataset_builder().with_data(&a).create(name)?;
        }
        let text: hdf5::types::VarLenUnicode = format!("tumbler import: {source}")
            .parse()
            .map_err(|e| hdf5::Error::from(format!("{e:?}").as_str()))?;
        f.new_attr::<hdf5::types::VarLenUnicode>()
            .create("source")?
            .write_scalar(&text)?;
        f.flush()
    })();
    if let Err(e) = written
        .map_err(|e| e.to_string())
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| e.to_string()))
    {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(e));
    }
    Ok(())
}

/// `tumbler import --lammps`: read the input, write `/particles` (module documentation).
pub fn import_lammps(opts: &ImportOptions) -> Result<Imported, InspectError> {
    let (ps, source, zeroed) = read(opts)?;
    write_particles(&opts.output, &ps, &source, opts.overwrite)?;
    Ok(Imported {
        path: opts.output.clone(),
        particles: ps.len(),
        source,
        zeroed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_are_rotations_only() {
        assert_eq!(axes("x,y,z").unwrap(), [(0, 1.0), (1, 1.0), (2, 1.0)]);
        assert_eq!(axes("y,z,x").unwrap(), [(1, 1.0), (2, 1.0), (0, 1.0)]);
        assert!(axes("-y,x,z").is_ok());
        assert!(axes("y,x,z").unwrap_err().to_string().contains("mirror"));
        assert!(axes("x,x,z").unwrap_err().to_string().contains("once"));
        assert!(axes("x,y").is_err());
    }

    #[test]
    fn species_maps_and_offsets_are_checked() {
        let m = species_map("1=0, 2=1,3=0").unwrap();
        assert_eq!((m[&1], m[&2], m[&3]), (0, 1, 0));
        assert!(species_map("0=1").is_err());
        assert!(species_map("1=0,1=1")
            .unwrap_err()
            .to_string()
            .contains("twice"));
        assert_eq!(offset("0, -0.5,1e-3").unwrap(), [0.0, -0.5, 1e-3]);
        assert!(offset("0,nan,1").is_err());
        assert!(offset("1,2").is_err());
    }
}
