//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;
use tumbler::case::{apply_overrides, parse_case, Case};

/// Path of a test case file.
pub fn case_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/cases")
        .join(name)
}

/// A test case with `key=value` overrides applied.
pub fn case_with(name: &str, overrides: &[&str]) -> Case {
    let text = std::fs::read_to_string(case_path(name)).unwrap();
    let ov: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let text = apply_overrides(&text, &ov, name).unwrap();
    parse_case(&text, name).unwrap_or_else(|e| panic!("{e:?}"))
}

/// `mpirun -np n tumbler args...`, with what OpenMPI needs to run as root and oversubscribed.
pub fn mpirun(n: usize, args: &[&str]) -> std::process::Output {
    mpirun_with_log(n, args, None)
}

/// [`mpirun`] with `RUST_LOG` set to `log` on every rank, when given.
pub fn mpirun_with_log(n: usize, args: &[&str], log: Option<&str>) -> std::process::Output {
    let mut c = Command::new("mpirun");
    c.args(["--oversubscribe", "-np", &n.to_string()]);
    if let Some(log) = log {
        c.args(["-x", "RUST_LOG"]).env("RUST_LOG", log);
    }
    c.arg(env!("CARGO_BIN_EXE_tumbler"))
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        // more ranks than cores: let waiting ranks yield instead of spinning
        .env("OMPI_MCA_mpi_yield_when_idle", "1")
        .output()
        .expect("mpirun could not be started (is openmpi-bin installed?)")
}

/// `mpirun -np n tumbler run CASE -o OUT --set S...` for a case of `tests/cases/`, asserting
/// that it succeeds.
pub fn run_case(n: usize, case: &str, out: &Path, sets: &[&str]) {
    let case = case_path(case);
    let mut args = vec!["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = mpirun(n, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// `tumbler args...` without mpirun.
pub fn tumbler(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tumbler"))
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .unwrap()
}

/// A fresh temporary directory.
pub fn tmpdir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

/// The name an output is written under until complete.
pub fn tmp_partial(out: &Path) -> PathBuf {
    tumbler::output::partial_path(out)
}

/// Every diagnostics dataset of an output (`/axial`, `/slices`, `/fields`, `/paths`), as
/// bits, for exact comparisons between runs.
pub fn diagnostics_bits(path: &Path) -> Vec<(String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap();
    let mut out = Vec::new();
    for group in ["axial", "slices", "fields", "paths"] {
        if !f.link_exists(group) {
            continue;
        }
        let g = f.group(group).unwrap();
        let mut names = g.member_names().unwrap();
        names.sort();
        for name in names {
            let ds = g.dataset(&name).unwrap();
            let dt = ds.dtype().unwrap();
            let v: Vec<u64> = if dt.is::<f64>() {
                let x: Vec<f64> = ds.read_raw().unwrap();
                x.iter().map(|v| v.to_bits()).collect()
            } else if dt.is::<f32>() {
                let x: Vec<f32> = ds.read_raw().unwrap();
                x.iter().map(|v| v.to_bits() as u64).collect()
            } else if dt.is::<u8>() {
                let x: Vec<u8> = ds.read_raw().unwrap();
                x.iter().map(|&v| v as u64).collect()
            } else if dt.is::<hdf5::types::VarLenUnicode>() {
                // names (species, components): their bytes, each name ended by a zero
                let x: Vec<hdf5::types::VarLenUnicode> = ds.read_raw().unwrap();
                x.iter()
                    .flat_map(|v| v.as_bytes().iter().map(|&b| b as u64).chain([0]))
                    .collect()
            } else {
                ds.read_raw().unwrap()
            };
            out.push((format!("{group}/{name}"), v));
        }
    }
    out
}

/// Assert two outputs hold the same diagnostics, bit for bit.
pub fn assert_same_diagnostics(a: &Path, b: &Path, what: &str) {
    let (x, y) = (diagnostics_bits(a), diagnostics_bits(b));
    let names = |v: &[(String, Vec<u64>)]| v.iter().map(|d| d.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(&x), names(&y), "{what}: datasets");
    for ((name, u), (_, v)) in x.iter().zip(&y) {
        let differing = u.iter().zip(v).filter(|(p, q)| p != q).count();
        assert!(
            u.len() == v.len() && differing == 0,
            "{what}: {name} differs ({} vs {} values, {differing} differ)",
            u.len(),
            v.len()
        );
    }
    let records = |name: &str| x.iter().find(|d| d.0 == name).map_or(0, |d| d.1.len());
    assert!(records("slices/samples") > 0, "{what}: no slice windows");
    assert!(records("fields/samples") > 0, "{what}: no field windows");
}

/// The thermo rows of a log (each a line of numbers following a column header, up to the
/// run's `done:` line; other lines between them, such as a load-balance report, are passed
/// over), per run segment (a separator line starts a segment).
pub fn thermo_rows(log: &str) -> Vec<Vec<Vec<f64>>> {
    use tumbler::run::thermo::COLUMNS;
    let header = COLUMNS.join(" ");
    let mut segments: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut in_table = false;
    for line in log.lines() {
        if line.starts_with("======== ") {
            segments.push(Vec::new());
            in_table = false;
        } else if line.split_whitespace().collect::<Vec<_>>().join(" ") == header {
            in_table = true;
        } else if in_table {
            let row: Result<Vec<f64>, _> = line.split_whitespace().map(str::parse).collect();
            match row {
                Ok(row) if row.len() == COLUMNS.len() => segments.last_mut().unwrap().push(row),
                // the table ends with the run's summary
                _ if line.starts_with("done:") => in_table = false,
                _ => {}
            }
        }
    }
    segments
}

/// Column `name` of the thermo rows ([`tumbler::run::thermo::COLUMNS`]).
pub fn thermo_column(name: &str) -> usize {
    tumbler::run::thermo::COLUMNS
        .iter()
        .position(|&c| c == name)
        .unwrap_or_else(|| panic!("no thermo column {name}"))
}

/// The thermo rows of a log's first segment as bits, every column but the rate
/// (`PSteps/s`, wall clock): what must be the same on any number of ranks.
pub fn thermo_bits(log: &str) -> Vec<Vec<u64>> {
    let rate = thermo_column("PSteps/s");
    thermo_rows(log)
        .remove(0)
        .iter()
        .map(|r| {
            r.iter()
                .enumerate()
                .filter(|&(k, _)| k != rate)
                .map(|(_, x)| x.to_bits())
                .collect()
        })
        .collect()
}
