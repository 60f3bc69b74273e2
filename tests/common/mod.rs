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
    Command::new("mpirun")
        .args(["--oversubscribe", "-np", &n.to_string()])
        .arg(env!("CARGO_BIN_EXE_tumbler"))
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        // more ranks than cores: let waiting ranks yield instead of spinning
        .env("OMPI_MCA_mpi_yield_when_idle", "1")
        .output()
        .expect("mpirun could not be started (is openmpi-bin installed?)")
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
