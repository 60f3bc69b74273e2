//! `tumbler import --lammps data|dump`: a LAMMPS data file or a LAMMPS/LIGGGHTS text dump
//! into the `/particles` layout that `init.file` reads. A run exported with
//! `tumbler export --lammps` and imported back is the same bits, and a run started from it
//! ends in the same state as one started from the original, and so is the dump LAMMPS
//! writes after reading the exported file (when `lmp` is installed); hand-written dumps
//! check the columns, frames and refusals.

mod common;

use common::{tmpdir, tumbler};
use std::path::Path;

/// `/particles` of a file as bits: ids, species, then the f64 datasets.
fn particle_bits(path: &Path) -> Vec<(String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap();
    let mut out = vec![
        (
            "id".to_string(),
            f.dataset("particles/id")
                .unwrap()
                .read_raw::<u64>()
                .unwrap(),
        ),
        (
            "species".to_string(),
            f.dataset("particles/species")
                .unwrap()
                .read_raw::<u8>()
                .unwrap()
                .into_iter()
                .map(u64::from)
                .collect(),
        ),
    ];
    for name in ["diameter", "position", "velocity", "angular_velocity"] {
        let v = f
            .dataset(&format!("particles/{name}"))
            .unwrap()
            .read_raw::<f64>()
            .unwrap();
        out.push((name.to_string(), v.into_iter().map(f64::to_bits).collect()));
    }
    out
}

fn ok(o: &std::process::Output) -> String {
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The test drum's case starting from the particles of `file`.
fn case_from(dir: &Path, name: &str, file: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(common::case_path("sd_capped.toml")).unwrap();
    let text = text
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "")
        .replace(
            "kind = \"pour\"",
            &format!("kind = \"particles\"\nfile = \"{}\"", file.display()),
        );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Whether LAMMPS (`lmp`, Debian's `lammps`) is installed; says so when it is not.
fn lammps_found() -> bool {
    let found = std::process::Command::new("lmp")
        .arg("-h")
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        eprintln!("SKIPPED (part): lmp is not installed (apt-get install lammps); LAMMPS does not re-dump the exported bed");
    }
    found
}

#[test]
fn an_exported_run_imports_back_bit_for_bit_and_runs_the_same() {
    let dir = tmpdir();
    let d = dir.path();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let first = d.join("first.h5");
    let case = common::case_path("sd_capped.toml");
    ok(&common::mpirun(
        1,
        &[
            "run",
            &s(&case),
            "-o",
            &s(&first),
            "--set",
            "run.rotations=0.02",
        ],
    ));
    let data = d.join("bed.data");
    ok(&tumbler(&["export", &s(&first), "--lammps", &s(&data)]));
    let bed = d.join("bed.h5");
    let said = ok(&tumbler(&[
        "import",
        "--lammps",
        "data",
        &s(&data),
        "-o",
        &s(&bed),
    ]));
    let original = particle_bits(&first);
    let n = original[0].1.len();
    assert!(n > 100, "{n} particles");
    assert!(said.contains(&format!("{n} particles")), "{said}");
    // the text of the data file holds every bit
    assert_eq!(particle_bits(&bed), original);

    // a run from the imported bed ends as a run from the original, on 2 ranks
    let mut ends = Vec::new();
    for (name, from) in [("a", &first), ("b", &bed)] {
        let c = case_from(d, &format!("{name}.toml"), from);
        let out = d.join(format!("{name}.h5"));
        ok(&common::mpirun(
            2,
            &["run", &s(&c), "-o", &s(&out), "--set", "run.rotations=0.01"],
        ));
        ends.push(particle_bits(&out));
    }
    assert_eq!(ends[0], ends[1]);
    assert_ne!(ends[0], original, "the particles moved");

    // LAMMPS itself reads the data file and dumps it back (every digit): the same bits
    if lammps_found() {
        let input = d.join("in.redump");
        std::fs::write(
            &input,
            format!(
                "units si\natom_style sphere\nboundary f f f\nread_data {}\nwrite_dump all custom {} id type x y z vx vy vz omegax omegay omegaz diameter modify format float %.17g\n",
                s(&data),
                s(&d.join("lammps.dump"))
            ),
        )
        .unwrap();
        let o = std::process::Command::new("lmp")
            .args(["-in", &s(&input), "-log", "none", "-screen", "none"])
            .current_dir(d)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let redumped = d.join("redumped.h5");
        ok(&tumbler(&[
            "import",
            "--lammps",
            "dump",
            &s(&d.join("lammps.dump")),
            "-o",
            &s(&redumped),
        ]));
        assert_eq!(particle_bits(&redumped), original);
    }

    // refusing to replace a file, unless asked
    let o = tumbler(&["import", "--lammps", "data", &s(&data), "-o", &s(&bed)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--overwrite"));
    ok(&tumbler(&[
        "import",
        "--lammps",
        "data",
        &s(&data),
        "-o",
        &s(&bed),
        "--overwrite",
    ]));
}

/// A LIGGGHTS-style dump of a drum along x (gravity along -z), two timesteps, columns in
/// an unusual order, radius instead of diameter, an extra column.
const LIGGGHTS: &str = "ITEM: TIMESTEP
1000
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS pp ff ff
-0.02 0.02
-0.015 0.015
-0.015 0.015
ITEM: ATOMS radius omegaz id vz x type y z vx vy omegax omegay mass
0.001 0.5 1 0 0.01 1 0.002 -0.005 0 0 0 0 1e-5
0.0015 0 2 0 -0.01 2 -0.003 -0.008 0 0 0 0 2e-5
ITEM: TIMESTEP
2000
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS pp ff ff
-0.02 0.02
-0.015 0.015
-0.015 0.015
ITEM: ATOMS radius omegaz id vz x type y z vx vy omegax omegay mass
0.0015 -1.25 7 0.125 -0.011 2 -0.0031 -0.0081 0.25 0.5 2.5 3.5 2e-5
0.001 0.75 3 -0.375 0.0105 1 0.0021 -0.0051 1.5 -2.5 -0.5 0.25 1e-5
";

#[test]
fn a_liggghts_dump_in_another_frame() {
    let dir = tmpdir();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let dump = dir.path().join("bed.dump");
    std::fs::write(&dump, LIGGGHTS).unwrap();
    let out = dir.path().join("bed.h5");
    // LIGGGHTS' x (the axis) becomes z, its z (up) becomes y: tumbler (x, y, z) = (y, z, x)
    let said = ok(&tumbler(&[
        "import",
        "--lammps",
        "dump",
        &s(&dump),
        "-o",
        &s(&out),
        "--axes",
        "y,z,x",
        "--offset",
        "0,0.0005,0",
        "--species",
        "1=1,2=0",
    ]));
    assert!(said.contains("2 particles from timestep 2000"), "{said}");
    let f = hdf5::File::open(&out).unwrap();
    let read = |n: &str| {
        f.dataset(&format!("particles/{n}"))
            .unwrap()
            .read_raw::<f64>()
            .unwrap()
    };
    // sorted by id: LAMMPS ids 3, 7 -> 2, 6
    assert_eq!(
        f.dataset("particles/id")
            .unwrap()
            .read_raw::<u64>()
            .unwrap(),
        [2, 6]
    );
    assert_eq!(
        f.dataset("particles/species")
            .unwrap()
            .read_raw::<u8>()
            .unwrap(),
        [1, 0]
    );
    assert_eq!(read("diameter"), [0.002, 0.003]);
    assert_eq!(
        read("position"),
        [
            0.0021,
            -0.0051 + 0.0005,
            0.0105,
            -0.0031,
            -0.0081 + 0.0005,
            -0.011
        ]
    );
    assert_eq!(read("velocity"), [-2.5, -0.375, 1.5, 0.5, 0.125, 0.25]);
    assert_eq!(
        read("angular_velocity"),
        [0.25, 0.75, -0.5, 3.5, -1.25, 2.5]
    );

    // the first timestep, on request; no velocity columns: zero, and said
    let plain = dir.path().join("plain.dump");
    std::fs::write(
        &plain,
        LIGGGHTS
            .replace(" vz", "")
            .replace(" vx vy", "")
            .replace(
                "0.001 0.5 1 0 0.01 1 0.002 -0.005 0 0",
                "0.001 0.5 1 0.01 1 0.002 -0.005",
            )
            .replace(
                "0.0015 0 2 0 -0.01 2 -0.003 -0.008 0 0",
                "0.0015 0 2 -0.01 2 -0.003 -0.008",
            )
            .replace(
                "0.0015 -1.25 7 0.125 -0.011 2 -0.0031 -0.0081 0.25 0.5",
                "0.0015 -1.25 7 -0.011 2 -0.0031 -0.0081",
            )
            .replace(
                "0.001 0.75 3 -0.375 0.0105 1 0.0021 -0.0051 1.5 -2.5",
                "0.001 0.75 3 0.0105 1 0.0021 -0.0051",
            ),
    )
    .unwrap();
    let first = dir.path().join("first.h5");
    let said = ok(&tumbler(&[
        "import",
        "--lammps",
        "dump",
        &s(&plain),
        "-o",
        &s(&first),
        "--timestep",
        "1000",
    ]));
    assert!(said.contains("timestep 1000"), "{said}");
    assert!(said.contains("no vx vy vz columns"), "{said}");
    let f = hdf5::File::open(&first).unwrap();
    let pos = f
        .dataset("particles/position")
        .unwrap()
        .read_raw::<f64>()
        .unwrap();
    assert_eq!(pos, [0.01, 0.002, -0.005, -0.01, -0.003, -0.008]);
    let v = f
        .dataset("particles/velocity")
        .unwrap()
        .read_raw::<f64>()
        .unwrap();
    assert_eq!(v, [0.0; 6]);
    let sp = f
        .dataset("particles/species")
        .unwrap()
        .read_raw::<u8>()
        .unwrap();
    assert_eq!(sp, [0, 1], "type - 1 by default");
}

/// `tumbler import` refuses with exit code 2, saying `what`, and writes nothing.
fn refused(dir: &Path, kind: &str, text: &str, extra: &[&str], what: &[&str]) {
    let input = dir.join(format!("in.{kind}"));
    std::fs::write(&input, text).unwrap();
    let out = dir.join("out.h5");
    let mut args = vec![
        "import",
        "--lammps",
        kind,
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = tumbler(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for w in what {
        assert!(err.contains(w), "`{w}` not in: {err}");
    }
    assert!(!out.exists(), "nothing is written: {err}");
    let tmp = dir.join("out.h5.tmp");
    assert!(!tmp.exists());
}

const DATA: &str = "LAMMPS data file for atom_style sphere

2 atoms
1 atom types

-0.02 0.02 xlo xhi
-0.02 0.02 ylo yhi
-0.02 0.02 zlo zhi

Atoms # sphere

1 1 0.002 2500 0.001 -0.01 0.0
2 1 0.002 2500 -0.004 -0.01 0.003

Velocities

1 0 0 0 0 0 0
2 0 0 0 0 0 0
";

#[test]
fn bad_files_are_refused_with_the_line() {
    let dir = tmpdir();
    let d = dir.path();
    // dumps
    refused(
        d,
        "dump",
        &LIGGGHTS.replace("radius omegaz", "r omegaz"),
        &[],
        &["in.dump:20:", "no `radius` or `diameter`"],
    );
    refused(
        d,
        "dump",
        &LIGGGHTS.replace(" x type y z", " type y z"),
        &[],
        &["in.dump:20:", "no position"],
    );
    refused(
        d,
        "dump",
        &LIGGGHTS.replace("0.0015 -1.25 7", "0.0015 nan 7"),
        &[],
        &["in.dump:21:", "column 2 (omegaz)", "finite"],
    );
    let cut: String = LIGGGHTS
        .lines()
        .take(21)
        .map(|l| format!("{l}\n"))
        .collect();
    refused(d, "dump", &cut, &[], &["declares 2 atoms", "ends after 1"]);
    refused(
        d,
        "dump",
        &LIGGGHTS.replace(
            "1000\nITEM: NUMBER OF ATOMS\n2",
            "1000\nITEM: NUMBER OF ATOMS\n3",
        ),
        &[],
        &["in.dump:13:", "`2000` where `ITEM: TIMESTEP` was expected"],
    );
    refused(
        d,
        "dump",
        LIGGGHTS,
        &["--timestep", "1500"],
        &["--timestep 1500", "1000, 2000"],
    );
    refused(
        d,
        "dump",
        &LIGGGHTS.replace("0.001 0.75 3", "0.001 0.75 7"),
        &[],
        &["in.dump:22:", "atom id 7 again (first on line 21)"],
    );
    refused(
        d,
        "dump",
        LIGGGHTS,
        &["--axes", "y,x,z"],
        &["--axes", "mirror"],
    );
    refused(
        d,
        "dump",
        LIGGGHTS,
        &["--species", "1=0"],
        &["type 2", "--species"],
    );
    // data files
    refused(
        d,
        "data",
        &DATA.replace("2 atoms", "3 atoms"),
        &[],
        &["in.data:", "declares 3 atoms", "has 2"],
    );
    refused(
        d,
        "data",
        &DATA.replace("2500 -0.004", "2500 inf"),
        &[],
        &["in.data:13:", "column 5 (x)"],
    );
    refused(
        d,
        "data",
        &DATA.replace("Atoms # sphere", "Atoms # atomic"),
        &[],
        &["in.data:10:", "atom_style atomic"],
    );
    refused(
        d,
        "data",
        &DATA.replace("1 1 0.002 2500 0.001", "1 1 0.002 0.001"),
        &[],
        &["in.data:12:", "7 columns", "has 6"],
    );
    refused(
        d,
        "data",
        &DATA.replace("\n2 0 0 0 0 0 0", "\n5 0 0 0 0 0 0"),
        &[],
        &["in.data:18:", "atom 5 is not in the Atoms section"],
    );
    let o = tumbler(&[
        "import",
        "--lammps",
        "data",
        d.join("missing.data").to_str().unwrap(),
        "-o",
        d.join("x.h5").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing.data"));
}
