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
use crate::particles::ParticleState;
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

/// Parse a LAMMPS data file (`atom_style sphere`).
fn parse_data(path: &Path, text: &str) -> Result<Vec<Atom>, InspectError> {
    let mut declared: Option<usize> = None;
    let mut section = String::new();
    let mut atoms: Vec<Atom> = Vec::new();
    let mut velocities: Vec<(u64, [f64; 3], [f64; 3], usize)> = Vec::new();
    let mut seen_atoms = false;
    let raw: Vec<&str> = text.lines().collect();
    for (n, line) in lines(text).skip(1) {
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if words[0]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic())
        {
            section = line.to_string();
            if words[0] == "Atoms" {
                seen_atoms = true;
                // the style is in the comment: `Atoms # sphere`
                let style = raw[n - 1].split('#').nth(1).map(str::trim).unwrap_or("");
                if !style.is_empty() && style != "sphere" {
                    return Err(at(path, n, format!("the Atoms section is for atom_style {style}; tumbler reads atom_style sphere (id type diameter density x y z)")));
                }
            }
            continue;
        }
        if section.is_empty() {
            // header: `N atoms`, `T atom types`, box bounds...
            if words.len() == 2 && words[1] == "atoms" {
                declared = Some(words[0].parse().map_err(|_| {
                    at(
                        path,
                        n,
                        format!("`{line}`: the number of atoms is not a whole number"),
                    )
                })?);
            }
            continue;
        }
        match section.as_str() {
            "Atoms" => {
                if words.len() != 7 && words.len() != 10 {
                    return Err(at(path, n, format!("an Atoms line of atom_style sphere has 7 columns (id type diameter density x y z) or 10 (with image flags); this one has {}", words.len())));
                }
                let f = |c: usize, what: &str| number(path, n, c + 1, words[c], what);
                let diameter = f(2, "diameter")?;
                if diameter <= 0.0 {
                    return Err(at(
                        path,
                        n,
                        format!(
                            "column 3 (diameter) is {}: a particle needs a positive diameter",
                            words[2]
                        ),
                    ));
                }
                f(3, "density")?;
                atoms.push(Atom {
                    id: positive(path, n, 1, words[0], "id")?,
                    kind: positive(path, n, 2, words[1], "type")?,
                    diameter,
                    x: [f(4, "x")?, f(5, "y")?, f(6, "z")?],
                    v: [0.0; 3],
                    w: [0.0; 3],
                    line: n,
                });
            }
            "Velocities" => {
                if words.len() != 7 {
                    return Err(at(path, n, format!("a Velocities line of atom_style sphere has 7 columns (id vx vy vz wx wy wz); this one has {}", words.len())));
                }
                let f = |c: usize, what: &str| number(path, n, c + 1, words[c], what);
                velocities.push((
                    positive(path, n, 1, words[0], "id")?,
                    [f(1, "vx")?, f(2, "vy")?, f(3, "vz")?],
                    [f(4, "wx")?, f(5, "wy")?, f(6, "wz")?],
                    n,
                ));
            }
            _ => {}
        }
    }
    let Some(declared) = declared else {
        return Err(at(
            path,
            1,
            "the header has no `N atoms` line: not a LAMMPS data file?",
        ));
    };
    if !seen_atoms {
        return Err(at(path, raw.len(), "the file has no Atoms section"));
    }
    if atoms.len() != declared {
        return Err(at(
            path,
            atoms.last().map_or(1, |a| a.line),
            format!(
                "the header declares {declared} atoms but the Atoms section has {}",
                atoms.len()
            ),
        ));
    }
    let index = index_of(path, &atoms)?;
    if !velocities.is_empty() && velocities.len() != atoms.len() {
        return Err(at(
            path,
            velocities.last().map_or(1, |v| v.3),
            format!(
                "the Velocities section has {} lines for {} atoms",
                velocities.len(),
                atoms.len()
            ),
        ));
    }
    let mut seen = vec![false; atoms.len()];
    for (id, v, w, n) in velocities {
        let Some(&k) = index.get(&id) else {
            return Err(at(
                path,
                n,
                format!("Velocities: atom {id} is not in the Atoms section"),
            ));
        };
        if std::mem::replace(&mut seen[k], true) {
            return Err(at(
                path,
                n,
                format!("Velocities: atom {id} is listed twice"),
            ));
        }
        atoms[k].v = v;
        atoms[k].w = w;
    }
    Ok(atoms)
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

/// The position columns of a dump: names and whether they are scaled by the box.
const POSITIONS: [([&str; 3], bool); 4] = [
    (["x", "y", "z"], false),
    (["xu", "yu", "zu"], false),
    (["xs", "ys", "zs"], true),
    (["xsu", "ysu", "zsu"], true),
];

/// The header of one dump snapshot.
struct DumpHeader<'a> {
    step: u64,
    atoms: usize,
    bounds: [[f64; 2]; 3],
    triclinic: bool,
    columns: Vec<&'a str>,
    /// Index (0-based) of the `ITEM: ATOMS` line.
    header: usize,
}

/// The chosen snapshot of a dump (the last, or `timestep`): its timestep, atoms and the
/// velocity columns it lacks. Only the headers of the others are read.
fn parse_dump(
    path: &Path,
    text: &str,
    timestep: Option<u64>,
) -> Result<(u64, Vec<Atom>, Vec<&'static str>), InspectError> {
    let all: Vec<&str> = text.lines().collect();
    let item = |k: usize| all.get(k).map(|l| l.trim()).unwrap_or("");
    let whole = |k: usize, what: &str| -> Result<u64, InspectError> {
        item(k).parse().map_err(|_| {
            at(
                path,
                k + 1,
                format!("{what} `{}` is not a whole number", item(k)),
            )
        })
    };
    let mut snapshots: Vec<DumpHeader> = Vec::new();
    let mut i = 0;
    while i < all.len() {
        if item(i).is_empty() {
            i += 1;
            continue;
        }
        if item(i) != "ITEM: TIMESTEP" {
            return Err(at(path, i + 1, format!("`{}` where `ITEM: TIMESTEP` was expected: not a LAMMPS text dump, or the previous snapshot has more atom lines than it declares", item(i))));
        }
        let step = whole(i + 1, "the timestep")?;
        if item(i + 2) != "ITEM: NUMBER OF ATOMS" {
            return Err(at(
                path,
                i + 3,
                "`ITEM: NUMBER OF ATOMS` expected after the timestep",
            ));
        }
        let atoms = whole(i + 3, "the number of atoms")? as usize;
        let b = i + 4;
        if !item(b).starts_with("ITEM: BOX BOUNDS") {
            return Err(at(
                path,
                b + 1,
                "`ITEM: BOX BOUNDS` expected after the number of atoms",
            ));
        }
        let triclinic = item(b).split_whitespace().any(|w| w == "xy");
        let mut bounds = [[0.0; 2]; 3];
        for (a, lohi) in bounds.iter_mut().enumerate() {
            let l = b + 1 + a;
            let w: Vec<&str> = item(l).split_whitespace().collect();
            if w.len() < 2 {
                return Err(at(path, l + 1, "a box bounds line needs `lo hi`"));
            }
            *lohi = [
                number(path, l + 1, 1, w[0], "lo")?,
                number(path, l + 1, 2, w[1], "hi")?,
            ];
        }
        let header = b + 4;
        let Some(rest) = item(header).strip_prefix("ITEM: ATOMS") else {
            return Err(at(
                path,
                header + 1,
                "`ITEM: ATOMS` with the column names expected after the box bounds",
            ));
        };
        snapshots.push(DumpHeader {
            step,
            atoms,
            bounds,
            triclinic,
            columns: rest.split_whitespace().collect(),
            header,
        });
        i = header + 1 + atoms;
    }
    let chosen = match timestep {
        None => snapshots.last(),
        Some(t) => snapshots.iter().find(|s| s.step == t),
    };
    let Some(s) = chosen else {
        let steps: Vec<u64> = snapshots.iter().map(|s| s.step).collect();
        return Err(InspectError::Invalid(match timestep {
            Some(t) => format!(
                "{}: --timestep {t}: the dump has no such timestep; it has {}",
                path.display(),
                list_steps(&steps)
            ),
            None => format!(
                "{}: the file holds no dump snapshot (ITEM: TIMESTEP)",
                path.display()
            ),
        }));
    };
    let end = (s.header + 1 + s.atoms).min(all.len());
    let atoms = dump_atoms(path, s, &all[s.header + 1..end])?;
    Ok((s.step, atoms, dump_zeroed(&s.columns)))
}

fn list_steps(steps: &[u64]) -> String {
    match steps.len() {
        0 => "none".into(),
        n if n <= 6 => steps
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(", "),
        n => format!("{}, {}, ..., {} ({n})", steps[0], steps[1], steps[n - 1]),
    }
}

/// Velocity columns a dump lacks (set to zero).
fn dump_zeroed(cols: &[&str]) -> Vec<&'static str> {
    let mut z = Vec::new();
    if !["vx", "vy", "vz"].iter().all(|c| cols.contains(c)) {
        z.push("vx vy vz");
    }
    if !["omegax", "omegay", "omegaz"]
        .iter()
        .all(|c| cols.contains(c))
    {
        z.push("omegax omegay omegaz");
    }
    z
}

/// The atoms of the dump snapshot `s`, whose atom lines are `table`.
fn dump_atoms(path: &Path, s: &DumpHeader, table: &[&str]) -> Result<Vec<Atom>, InspectError> {
    let (cols, n, bounds, triclinic) = (&s.columns, s.atoms, s.bounds, s.triclinic);
    // 1-based line numbers: the ATOMS line, and the first atom line
    let (header, first) = (s.header + 1, s.header + 2);
    let col = |name: &str| cols.iter().position(|c| *c == name);
    let need = |name: &str, why: &str| {
        col(name).ok_or_else(|| {
            at(
                path,
                header,
                format!(
                    "the ATOMS columns ({}) have no `{name}` ({why})",
                    cols.join(" ")
                ),
            )
        })
    };
    let id = need("id", "the atom id")?;
    let kind = need("type", "the atom type, for the species")?;
    let Some((pos, scaled)) = POSITIONS.iter().find_map(|(names, scaled)| {
        Some(([col(names[0])?, col(names[1])?, col(names[2])?], *scaled))
    }) else {
        return Err(at(
            path,
            header,
            format!(
                "the ATOMS columns ({}) have no position: x y z, xu yu zu, xs ys zs or xsu ysu zsu",
                cols.join(" ")
            ),
        ));
    };
    if scaled && triclinic {
        return Err(at(
            path,
            header,
            "scaled positions in a triclinic box are not supported: dump x y z instead",
        ));
    }
    let size = match (col("diameter"), col("radius")) {
        (Some(c), _) => (c, 1.0),
        (None, Some(c)) => (c, 2.0),
        _ => {
            return Err(at(
                path,
                header,
                format!(
                    "the ATOMS columns ({}) have no `radius` or `diameter`",
                    cols.join(" ")
                ),
            ))
        }
    };
    let three = |names: [&str; 3]| -> Option<[usize; 3]> {
        Some([col(names[0])?, col(names[1])?, col(names[2])?])
    };
    let vel = three(["vx", "vy", "vz"]);
    let omega = three(["omegax", "omegay", "omegaz"]);
    if table.len() < n {
        return Err(at(
            path,
            first + table.len(),
            format!(
                "the snapshot declares {n} atoms but the file ends after {}",
                table.len()
            ),
        ));
    }
    let mut atoms = Vec::with_capacity(n);
    for (k, line) in table.iter().enumerate() {
        let ln = first + k;
        let w: Vec<&str> = line.split_whitespace().collect();
        if line.trim_start().starts_with("ITEM:") {
            return Err(at(
                path,
                ln,
                format!("the snapshot declares {n} atoms but has {k}"),
            ));
        }
        if w.len() != cols.len() {
            return Err(at(
                path,
                ln,
                format!(
                    "{} columns where the ATOMS line names {}",
                    w.len(),
                    cols.len()
                ),
            ));
        }
        let f = |c: usize| number(path, ln, c + 1, w[c], cols[c]);
        let mut x = [f(pos[0])?, f(pos[1])?, f(pos[2])?];
        if scaled {
            for a in 0..3 {
                x[a] = bounds[a][0] + x[a] * (bounds[a][1] - bounds[a][0]);
            }
        }
        let diameter = size.1 * f(size.0)?;
        if diameter <= 0.0 {
            return Err(at(
                path,
                ln,
                format!(
                    "column {} ({}) is {}: a particle needs a positive size",
                    size.0 + 1,
                    cols[size.0],
                    w[size.0]
                ),
            ));
        }
        let get3 = |c: Option<[usize; 3]>| -> Result<[f64; 3], InspectError> {
            match c {
                Some(c) => Ok([f(c[0])?, f(c[1])?, f(c[2])?]),
                None => Ok([0.0; 3]),
            }
        };
        atoms.push(Atom {
            id: positive(path, ln, id + 1, w[id], "id")?,
            kind: positive(path, ln, kind + 1, w[kind], "type")?,
            diameter,
            x,
            v: get3(vel)?,
            w: get3(omega)?,
            line: ln,
        });
    }
    index_of(path, &atoms)?;
    Ok(atoms)
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
