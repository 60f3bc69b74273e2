//! `tumbler export FILE --lammps OUT.data`: a run's particles as a LAMMPS data file for
//! `atom_style sphere`, from a small file written here by hand with the layout of a run's
//! output (root attribute `case`, `/particles`, `/snapshots/NNNNNNNNNN`).

mod common;

use common::{tmpdir, tumbler};
use hdf5::types::VarLenUnicode;
use std::path::Path;
use std::str::FromStr;

/// The case of the file: the test drum (D = 0.03, L = 0.04, capped, density 2500).
const CASE: &str = include_str!("cases/sd_capped.toml");

/// One group of particles as a run writes it.
struct Group {
    id: Vec<u64>,
    species: Vec<u8>,
    diameter: Vec<f64>,
    position: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
    angular_velocity: Vec<[f64; 3]>,
}

fn final_state() -> Group {
    Group {
        id: vec![0, 1, 7],
        species: vec![0, 1, 0],
        diameter: vec![0.0021, 0.0029, 0.0019],
        position: vec![
            [0.001, -0.01, -0.012],
            [-0.004, -0.009, 0.0035],
            [0.0025, -0.0125, 0.017],
        ],
        velocity: vec![[0.01, 0.02, -0.003], [-0.5, 0.25, 1e-7], [0.0, 0.0, 0.0]],
        angular_velocity: vec![[1.0, -2.0, 3.5], [0.0, 0.125, -7.0], [1e-9, 0.0, 0.0]],
    }
}

fn write_group(f: &hdf5::File, name: &str, g: &Group) {
    let grp = f.create_group(name).unwrap();
    let n = g.id.len();
    let flat = |v: &[[f64; 3]]| ndarray::Array2::from_shape_fn((n, 3), |(i, k)| v[i][k]);
    grp.new_dataset_builder()
        .with_data(&g.id)
        .create("id")
        .unwrap();
    grp.new_dataset_builder()
        .with_data(&g.species)
        .create("species")
        .unwrap();
    grp.new_dataset_builder()
        .with_data(&g.diameter)
        .create("diameter")
        .unwrap();
    for (ds, v) in [
        ("position", &g.position),
        ("velocity", &g.velocity),
        ("angular_velocity", &g.angular_velocity),
    ] {
        grp.new_dataset_builder()
            .with_data(&flat(v))
            .create(ds)
            .unwrap();
    }
}

/// A run's file with `case_text`, the final state and one snapshot (two particles).
fn write_run(path: &Path, case_text: &str) {
    let f = hdf5::File::create(path).unwrap();
    f.new_attr::<VarLenUnicode>()
        .create("case")
        .unwrap()
        .write_scalar(&VarLenUnicode::from_str(case_text).unwrap())
        .unwrap();
    write_group(&f, "particles", &final_state());
    f.create_group("snapshots").unwrap();
    let mut snap = final_state();
    for v in [
        &mut snap.position,
        &mut snap.velocity,
        &mut snap.angular_velocity,
    ] {
        v.truncate(2);
    }
    snap.id.truncate(2);
    snap.species.truncate(2);
    snap.diameter.truncate(2);
    snap.position[1][2] = -0.0015;
    write_group(&f, "snapshots/0000000100", &snap);
    f.group("snapshots/0000000100")
        .unwrap()
        .new_attr::<f64>()
        .create("rotations")
        .unwrap()
        .write_scalar(&0.05)
        .unwrap();
}

/// The data file's header (`N atoms`, bounds...) and its sections by title.
struct Data {
    title: String,
    header: Vec<String>,
    atoms: Vec<Vec<f64>>,
    velocities: Vec<Vec<f64>>,
}

fn read_data(path: &Path) -> Data {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let title = lines.next().unwrap().to_string();
    let (mut header, mut atoms, mut velocities) = (Vec::new(), Vec::new(), Vec::new());
    let mut section = "";
    for line in lines {
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with("Atoms") {
            assert_eq!(line, "Atoms # sphere");
            section = "atoms";
            continue;
        }
        if line == "Velocities" {
            section = "velocities";
            continue;
        }
        let numbers = || -> Vec<f64> {
            line.split_whitespace()
                .map(|w| w.parse().unwrap_or_else(|_| panic!("not a number: {w}")))
                .collect()
        };
        match section {
            "atoms" => atoms.push(numbers()),
            "velocities" => velocities.push(numbers()),
            _ => header.push(line.to_string()),
        }
    }
    Data {
        title,
        header,
        atoms,
        velocities,
    }
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-15 * a.abs().max(b.abs())
}

fn bounds(header: &[String], axis: &str) -> (f64, f64) {
    let line = header
        .iter()
        .find(|l| l.ends_with(&format!("{axis}lo {axis}hi")))
        .unwrap_or_else(|| panic!("no {axis}lo {axis}hi line in {header:?}"));
    let w: Vec<f64> = line
        .split_whitespace()
        .take(2)
        .map(|x| x.parse().unwrap())
        .collect();
    (w[0], w[1])
}

#[test]
fn final_particles_become_a_lammps_data_file() {
    let dir = tmpdir();
    let run = dir.path().join("run.h5");
    let out = dir.path().join("bed.data");
    write_run(&run, CASE);
    let o = tumbler(&[
        "export",
        run.to_str().unwrap(),
        "--lammps",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("3 atoms of 2 types"), "{said}");

    let d = read_data(&out);
    assert!(d.title.contains("atom_style sphere"), "{}", d.title);
    assert!(d.title.contains("boundary f f f"), "{}", d.title);
    assert!(d.header.iter().any(|l| l == "3 atoms"), "{:?}", d.header);
    assert!(
        d.header.iter().any(|l| l == "2 atom types"),
        "{:?}",
        d.header
    );
    // D = 0.03, L = 0.04, capped: a box slightly larger than the drum on every side
    let (r, h) = (0.015, 0.02);
    for (axis, half) in [("x", r), ("y", r), ("z", h)] {
        let (lo, hi) = bounds(&d.header, axis);
        assert!(lo < -half && lo > -half - 0.001, "{axis}: {lo}");
        assert!(hi > half && hi < half + 0.001, "{axis}: {hi}");
        assert!(close(lo, -hi), "{axis}: {lo} {hi}");
    }

    // Atoms: id + 1, species + 1, diameter, the case's density, position
    let g = final_state();
    assert_eq!(d.atoms.len(), 3);
    for (i, line) in d.atoms.iter().enumerate() {
        assert_eq!(line.len(), 7, "{line:?}");
        assert_eq!(line[0], (g.id[i] + 1) as f64);
        assert_eq!(line[1], (g.species[i] + 1) as f64);
        assert!(close(line[2], g.diameter[i]), "{line:?}");
        assert_eq!(line[3], 2500.0);
        for k in 0..3 {
            assert!(close(line[4 + k], g.position[i][k]), "{line:?}");
        }
    }
    // the second particle, as written: id 2, type 2, d = 0.0029
    assert_eq!(
        d.atoms[1][..4],
        [2.0, 2.0, 0.0029, 2500.0],
        "{:?}",
        d.atoms[1]
    );

    // Velocities: id + 1, velocity, angular velocity
    assert_eq!(d.velocities.len(), 3);
    for (i, line) in d.velocities.iter().enumerate() {
        assert_eq!(line.len(), 7, "{line:?}");
        assert_eq!(line[0], (g.id[i] + 1) as f64);
        for k in 0..3 {
            assert!(close(line[1 + k], g.velocity[i][k]), "{line:?}");
            assert!(close(line[4 + k], g.angular_velocity[i][k]), "{line:?}");
        }
    }
    assert_eq!(d.velocities[1], [2.0, -0.5, 0.25, 1e-7, 0.0, 0.125, -7.0]);
}

#[test]
fn a_snapshot_and_a_periodic_drum() {
    let dir = tmpdir();
    let run = dir.path().join("run.h5");
    let out = dir.path().join("snap.data");
    let periodic = CASE
        .replace("ends = \"capped\"", "ends = \"periodic\"")
        .replace("cap_high = \"frictionless\"\n", "");
    tumbler::case::parse_case(&periodic, "periodic").expect("the periodic variant parses");
    write_run(&run, &periodic);
    let o = tumbler(&[
        "export",
        run.to_str().unwrap(),
        "--lammps",
        out.to_str().unwrap(),
        "--group",
        "snapshots/0000000100",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let d = read_data(&out);
    assert!(d.title.contains("boundary f f p"), "{}", d.title);
    assert!(d.title.contains("/snapshots/0000000100"), "{}", d.title);
    assert!(d.header.iter().any(|l| l == "2 atoms"), "{:?}", d.header);
    assert!(
        d.header.iter().any(|l| l == "2 atom types"),
        "{:?}",
        d.header
    );
    // periodic along z: the box is exactly the drum's length
    assert_eq!(bounds(&d.header, "z"), (-0.02, 0.02));
    assert!(bounds(&d.header, "x").0 < -0.015);
    assert_eq!(d.atoms.len(), 2);
    assert_eq!(d.atoms[1][6], -0.0015);
    assert_eq!(d.velocities.len(), 2);
}

#[test]
fn missing_file_or_group_is_refused_with_exit_code_2() {
    let dir = tmpdir();
    let run = dir.path().join("run.h5");
    let out = dir.path().join("x.data");
    write_run(&run, CASE);
    let o = tumbler(&[
        "export",
        dir.path().join("nothing.h5").to_str().unwrap(),
        "--lammps",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("nothing.h5") && err.contains("no such file"),
        "{err}"
    );

    let o = tumbler(&[
        "export",
        run.to_str().unwrap(),
        "--lammps",
        out.to_str().unwrap(),
        "--group",
        "snapshots/0000000005",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("/snapshots/0000000005"), "{err}");
    assert!(err.contains("snapshots/0000000100"), "{err}");

    // a file without /particles (an unfinished run) says so and names its snapshots
    let partial = dir.path().join("partial.h5");
    {
        let f = hdf5::File::create(&partial).unwrap();
        f.new_attr::<VarLenUnicode>()
            .create("case")
            .unwrap()
            .write_scalar(&VarLenUnicode::from_str(CASE).unwrap())
            .unwrap();
    }
    let o = tumbler(&[
        "export",
        partial.to_str().unwrap(),
        "--lammps",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("/particles") && err.contains("no snapshots"),
        "{err}"
    );
    assert!(
        !out.exists(),
        "nothing is written when the export is refused"
    );
}

/// The `<DataArray>`s of a `.vtu` file by name, as numbers, and its piece's point and cell
/// counts.
fn read_vtu(path: &Path) -> (usize, usize, std::collections::BTreeMap<String, Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("the .vtu file is well-formed XML");
    let piece = doc.descendants().find(|n| n.has_tag_name("Piece")).unwrap();
    let count = |a: &str| piece.attribute(a).unwrap().parse().unwrap();
    let arrays = doc
        .descendants()
        .filter(|n| n.has_tag_name("DataArray"))
        .map(|n| {
            let values = n
                .text()
                .unwrap_or("")
                .split_whitespace()
                .map(|w| w.parse().unwrap())
                .collect();
            (n.attribute("Name").unwrap().to_string(), values)
        })
        .collect();
    (count("NumberOfPoints"), count("NumberOfCells"), arrays)
}

#[test]
fn snapshots_become_vtu_files_with_a_pvd_series() {
    let dir = tmpdir();
    let run = dir.path().join("run.h5");
    write_run(&run, CASE);
    let out = dir.path().join("vtk");
    let o = tumbler(&[
        "export",
        run.to_str().unwrap(),
        "--vtu",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let said = String::from_utf8_lossy(&o.stdout);
    assert!(said.contains("1 time steps, 2 particles"), "{said}");

    // the series: the snapshot and the drum, at 0.05 rotations
    let pvd = std::fs::read_to_string(out.join("run.pvd")).unwrap();
    let doc = roxmltree::Document::parse(&pvd).unwrap();
    let sets: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .map(|n| {
            (
                n.attribute("timestep").unwrap().to_string(),
                n.attribute("part").unwrap().to_string(),
                n.attribute("file").unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(
        sets,
        [
            ("0.05".into(), "0".into(), "run_0000000100.vtu".into()),
            ("0.05".into(), "1".into(), "run_drum.vtu".into()),
        ]
    );

    // the snapshot's particles, every bit, as vertex cells
    let (points, cells, a) = read_vtu(&out.join("run_0000000100.vtu"));
    assert_eq!((points, cells), (2, 2));
    let mut g = final_state();
    g.position[1][2] = -0.0015;
    let flat = |v: &[[f64; 3]]| -> Vec<f64> { v[..2].iter().flatten().copied().collect() };
    assert_eq!(a["position"], flat(&g.position));
    assert_eq!(a["velocity"], flat(&g.velocity));
    assert_eq!(a["angular_velocity"], flat(&g.angular_velocity));
    assert_eq!(a["diameter"], g.diameter[..2]);
    assert_eq!(a["id"], [0.0, 1.0]);
    assert_eq!(a["species"], [0.0, 1.0]);
    assert_eq!(a["connectivity"], [0.0, 1.0]);
    assert_eq!(a["offsets"], [1.0, 2.0]);
    assert_eq!(a["types"], [1.0, 1.0], "VTK_VERTEX");

    // the drum: a capped cylinder, D = 0.03, L = 0.04
    let (points, cells, a) = read_vtu(&out.join("run_drum.vtu"));
    assert_eq!((points, cells), (98, 192));
    let p = &a["position"];
    let r = |k: usize| (p[3 * k].powi(2) + p[3 * k + 1].powi(2)).sqrt();
    assert!((0..96).all(|k| (r(k) - 0.015).abs() < 1e-15 && p[3 * k + 2].abs() == 0.02));

    // the final state on request; a file without snapshots is refused
    let o = tumbler(&[
        "export",
        run.to_str().unwrap(),
        "--vtu",
        out.to_str().unwrap(),
        "--group",
        "particles",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read_vtu(&out.join("run_particles.vtu")).0, 3);
    let bare = dir.path().join("bare.h5");
    {
        let f = hdf5::File::create(&bare).unwrap();
        f.new_attr::<VarLenUnicode>()
            .create("case")
            .unwrap()
            .write_scalar(&VarLenUnicode::from_str(CASE).unwrap())
            .unwrap();
    }
    let o = tumbler(&[
        "export",
        bare.to_str().unwrap(),
        "--vtu",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("/snapshots") && err.contains("snapshots.every"),
        "{err}"
    );
    let o = tumbler(&["export", run.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "neither --lammps nor --vtu");
}
