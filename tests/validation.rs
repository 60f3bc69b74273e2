//! `tumbler validate --tier ci` on two ranks: the analytic checks and the CI subset of the
//! seed checks pass, the report says so, and `--reuse` judges the same files again without
//! rerunning them (docs/validation.md).

mod common;

use common::{mpirun, tumbler};

#[test]
fn the_ci_tier_passes_and_reuse_judges_the_same_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("v");
    let out_s = out.to_str().unwrap();
    let first = mpirun(2, &["validate", "--tier", "ci", "-o", out_s]);
    let stdout = String::from_utf8_lossy(&first.stdout);
    assert!(
        first.status.success(),
        "validate --tier ci failed ({:?}):\n{stdout}\n{}",
        first.status.code(),
        String::from_utf8_lossy(&first.stderr)
    );
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for check in [
        "restitution",
        "rolling",
        "rapaport-friction-rule",
        "rapaport-segregated-start",
    ] {
        assert!(
            report.contains(&format!("## {check} — pass")),
            "{check} is not reported as passed:\n{report}"
        );
    }
    assert!(!report.contains("FAIL"), "{report}");
    assert!(
        report.ends_with("ci tier: every check passed\n"),
        "{report}"
    );
    // the figures the report names exist
    for line in report.lines().filter(|l| l.starts_with("![")) {
        let path = &line[line.find("](").unwrap() + 2..line.len() - 1];
        assert!(out.join(path).is_file(), "missing figure {path}");
    }
    // judged again from the same files: the same report, without the runs
    let again = mpirun(2, &["validate", "--tier", "ci", "-o", out_s, "--reuse"]);
    assert!(again.status.success());
    assert_eq!(
        std::fs::read_to_string(out.join("report.md")).unwrap(),
        report
    );
    let log = String::from_utf8_lossy(&again.stderr);
    assert_eq!(log.matches("reusing").count(), 4, "{log}");
    assert!(
        !log.contains("particle-steps/s"),
        "--reuse ran a case again:\n{log}"
    );
}

#[test]
fn an_unknown_check_is_refused_with_the_list() {
    let out = tumbler(&["validate", "--only", "rolling,bands-of-doom"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("`bands-of-doom`") && err.contains("rapaport-capped"),
        "{err}"
    );
    let list = tumbler(&["validate", "--list"]);
    assert!(list.status.success());
    assert_eq!(String::from_utf8_lossy(&list.stdout).lines().count(), 10);
}
