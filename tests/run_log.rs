//! The run's log `NAME.log`: every line the run prints, thermo columns that parse, the same
//! thermo numbers on 1 and 2 ranks, appended to by a restart, and thermo lines that change
//! no particle bit.

mod common;

use common::{case_path, mpirun, thermo_bits, thermo_column, thermo_rows, tmpdir};
use std::path::Path;

fn run(ranks: usize, out: &Path, extra: &[&str]) -> String {
    let case = case_path("sd_periodic.toml");
    let mut args = vec!["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let o = mpirun(ranks, &args);
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{ranks} ranks failed:\n{stderr}");
    stderr
}

fn particle_bits(path: &Path) -> Vec<(String, Vec<u64>)> {
    let f = hdf5::File::open(path).unwrap();
    ["position", "velocity", "angular_velocity"]
        .iter()
        .map(|name| {
            let v: Vec<f64> = f
                .dataset(&format!("particles/{name}"))
                .unwrap()
                .read_raw()
                .unwrap();
            (name.to_string(), v.iter().map(|x| x.to_bits()).collect())
        })
        .collect()
}

#[test]
fn the_log_holds_every_line_and_thermo_columns_that_parse() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    let stderr = run(
        1,
        &out,
        &[
            "--set",
            "run.rotations=0.04",
            "--set",
            "output.thermo_every=0.01",
        ],
    );
    let log = std::fs::read_to_string(dir.path().join("a.log")).expect("a.log was not written");
    // every line printed on stderr is in the log, in order
    let mut rest = log.as_str();
    for line in stderr.lines() {
        let at = rest
            .find(line)
            .unwrap_or_else(|| panic!("stderr line {line:?} is not in the log:\n{log}"));
        rest = &rest[at + line.len()..];
    }
    assert!(log.starts_with("======== tumbler "), "{log}");
    let segments = thermo_rows(&log);
    assert_eq!(segments.len(), 1, "{log}");
    let rows = &segments[0];
    // step 0, every 0.01 rotations, and the last step (unless it is on the schedule)
    assert!((5..=6).contains(&rows.len()), "{log}");
    assert_eq!(rows[0][0], 0.0);
    let last = rows.last().unwrap();
    assert!((last[1] - 0.04).abs() < 1e-3, "{log}");
    let n = rows[0][2];
    assert!(n > 100.0, "{log}");
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r[2], n, "the particle count changed: {log}");
        assert!(r[3].is_finite() && r[3] >= 0.0 && r[4].is_finite() && r[4] >= 0.0);
        assert!(r[5] >= 0.0 && r[5] < 3.0 * n, "contacts {}", r[5]);
        assert!(r[6] >= 0.0 && r[6] < 0.25, "largest overlap {}", r[6]);
        let airborne = r[thermo_column("Airborne")];
        assert!((0.0..=1.0).contains(&airborne), "airborne {airborne}");
        let rate = r[thermo_column("PSteps/s")];
        assert!(k == 0 || rate > 0.0, "rate {rate}");
        if k > 0 {
            assert!(r[0] > rows[k - 1][0], "steps go up: {log}");
        }
    }
    // the drum has started the bed moving
    assert!(last[3] > rows[0][3], "{log}");
    assert!(rows[0][5] > 0.0, "a settled bed has contacts");
    let airborne = rows[0][thermo_column("Airborne")];
    assert!(
        airborne < 0.05,
        "a settled bed: {airborne} of it touching nothing"
    );
}

#[test]
fn thermo_numbers_are_the_same_on_one_and_two_ranks() {
    let dir = tmpdir();
    let set = [
        "--set",
        "run.rotations=0.03",
        "--set",
        "output.thermo_every=0.01",
    ];
    let mut tables = Vec::new();
    for ranks in [1, 2] {
        let out = dir.path().join(format!("r{ranks}.h5"));
        run(ranks, &out, &set);
        let log = std::fs::read_to_string(dir.path().join(format!("r{ranks}.log"))).unwrap();
        // all columns but the rate
        tables.push((thermo_bits(&log), log));
    }
    assert!(tables[0].0.len() >= 4);
    assert_eq!(tables[0].0, tables[1].0, "{}\n{}", tables[0].1, tables[1].1);
}

#[test]
fn a_restart_appends_to_the_log_and_thermo_changes_no_particle() {
    let dir = tmpdir();
    let a = dir.path().join("a.h5");
    run(
        2,
        &a,
        &[
            "--set",
            "run.rotations=0.02",
            "--set",
            "output.thermo_every=0.002",
        ],
    );
    let first = std::fs::read_to_string(dir.path().join("a.log")).unwrap();
    let ck = dir.path().join("a.ckpt.h5");
    run(
        2,
        &a,
        &[
            "--set",
            "run.rotations=0.03",
            "--set",
            "output.thermo_every=0.002",
            "--restart",
            ck.to_str().unwrap(),
        ],
    );
    let log = std::fs::read_to_string(dir.path().join("a.log")).unwrap();
    assert!(
        log.starts_with(&first),
        "the restart kept the first run's log"
    );
    let appended = &log[first.len()..];
    assert!(
        appended.starts_with("\n======== tumbler ") && appended.contains("restart of"),
        "{appended}"
    );
    let segments = thermo_rows(&log);
    assert_eq!(segments.len(), 2, "{log}");
    // the restart's first line is the first run's last state
    let (end, resumed) = (segments[0].last().unwrap(), &segments[1][0]);
    assert_eq!(end[..8], resumed[..8], "{log}");

    // the same run in one piece, with thermo lines far apart: the same particles, bit for bit
    let b = dir.path().join("b.h5");
    run(
        2,
        &b,
        &[
            "--set",
            "run.rotations=0.03",
            "--set",
            "output.thermo_every=100",
        ],
    );
    let blog = std::fs::read_to_string(dir.path().join("b.log")).unwrap();
    assert_eq!(
        thermo_rows(&blog)[0].len(),
        2,
        "only the first and last step: {blog}"
    );
    assert_eq!(particle_bits(&a), particle_bits(&b));
}

#[test]
fn a_fresh_run_does_not_replace_a_log_without_overwrite() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    let log = dir.path().join("a.log");
    // a log left by a run that wrote no output is appended to
    std::fs::write(&log, "an earlier run's line\n").unwrap();
    run(1, &out, &["--set", "run.rotations=0.005"]);
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(
        text.starts_with("an earlier run's line\n\n======== "),
        "{text}"
    );
    // the output exists now: refused without --overwrite, the log untouched
    let case = case_path("sd_periodic.toml");
    let args = ["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()];
    let o = mpirun(1, &args);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--overwrite"));
    assert_eq!(std::fs::read_to_string(&log).unwrap(), text);
    // with --overwrite the log starts again
    run(1, &out, &["--set", "run.rotations=0.005", "--overwrite"]);
    let again = std::fs::read_to_string(&log).unwrap();
    assert!(
        again.starts_with("======== ") && !again.contains("earlier"),
        "{again}"
    );
}
