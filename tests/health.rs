//! Run health: a run that blows up (here: particles started far too fast for the contact
//! stiffness) stops on every rank with the particle, the step and the likely cause, never
//! silently and never hanging.

mod common;

use common::{case_path, mpirun, tmpdir};
use std::time::{Duration, Instant};

#[test]
fn an_unstable_run_stops_with_the_particle_and_the_cause() {
    let case = case_path("periodic.toml");
    for (ranks, speed, what) in [
        (1, "20", "overlap by"),
        (2, "20", "overlap by"),
        (2, "200", "has left the drum"),
    ] {
        let dir = tmpdir();
        let out = dir.path().join("u.h5");
        let s = format!("init.speed={speed}");
        let t0 = Instant::now();
        let o = mpirun(
            ranks,
            &[
                "run",
                case.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--set",
                &s,
            ],
        );
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "{ranks} ranks took {:?} to stop",
            t0.elapsed()
        );
        assert_eq!(o.status.code(), Some(1), "{ranks} ranks, speed {speed}");
        let err = String::from_utf8_lossy(&o.stderr);
        for part in [
            "run stopped at step",
            "particle",
            what,
            "time step is probably too large",
        ] {
            assert!(
                err.contains(part),
                "{ranks} ranks, speed {speed}: {part:?} missing from\n{err}"
            );
        }
        assert!(!out.exists(), "no output under the final name");
    }
}

#[test]
fn a_stable_run_is_not_stopped() {
    // the default limit leaves ordinary runs alone (the other tests run to the end too)
    let dir = tmpdir();
    let out = dir.path().join("ok.h5");
    let case = case_path("capped.toml");
    let o = mpirun(
        2,
        &[
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.rotations=0.5",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}
