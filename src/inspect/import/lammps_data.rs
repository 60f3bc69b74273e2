//! LAMMPS data files (`atom_style sphere`) for `tumbler import` (the parent module says
//! what is read).

use super::{at, index_of, lines, number, positive, Atom};
use crate::inspect::InspectError;
use std::path::Path;

/// Parse a LAMMPS data file (`atom_style sphere`).
pub(super) fn parse_data(path: &Path, text: &str) -> Result<Vec<Atom>, InspectError> {
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
