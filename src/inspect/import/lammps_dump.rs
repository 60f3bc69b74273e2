//! LAMMPS and LIGGGHTS text dumps for `tumbler import` (the parent module says what is
//! read).

use super::{at, index_of, number, positive, Atom};
use crate::inspect::InspectError;
use std::path::Path;

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
pub(super) fn parse_dump(
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
