//! Stopping: SIGTERM to the ranks of a running two-rank job (what Slurm's `--signal` does)
//! makes them finish the step, write a checkpoint and exit with code 3, and the restart
//! matches the run never interrupted; a rank killed outright ends the whole job within
//! seconds, and the run continues from its last checkpoint.

mod common;

use common::{case_path, tmpdir};
use std::path::Path;
use std::process::{Child, Command};
use std::time::{Duration, Instant};

fn spawn(ranks: usize, out: &Path, extra: &[&str]) -> Child {
    let case = case_path("sd_capped.toml");
    Command::new("mpirun")
        .args(["--oversubscribe", "-np", &ranks.to_string()])
        .arg(env!("CARGO_BIN_EXE_tumbler"))
        .args(["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(extra)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_mpi_yield_when_idle", "1")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// Process ids of the tumbler ranks writing `out` (not mpirun itself).
fn ranks_of(out: &Path) -> Vec<u32> {
    let mut pids = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(comm) = std::fs::read_to_string(format!("/proc/{pid}/comm")) else {
            continue;
        };
        let Ok(cmd) = std::fs::read(format!("/proc/{pid}/cmdline")) else {
            continue;
        };
        if comm.trim() == "tumbler" && String::from_utf8_lossy(&cmd).contains(out.to_str().unwrap())
        {
            pids.push(pid);
        }
    }
    pids
}

fn wait_for(what: &str, limit: Duration, mut cond: impl FnMut() -> bool) {
    let t0 = Instant::now();
    while !cond() {
        assert!(t0.elapsed() < limit, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn bits(path: &Path, name: &str) -> Vec<u64> {
    let f = hdf5::File::open(path).unwrap();
    let v: Vec<f64> = f.dataset(name).unwrap().read_raw().unwrap();
    v.iter().map(|x| x.to_bits()).collect()
}

fn assert_same_run(a: &Path, b: &Path) {
    for ds in [
        "particles/position",
        "particles/velocity",
        "particles/angular_velocity",
        "axial/volume_fraction",
        "axial/rotations",
    ] {
        assert_eq!(bits(a, ds), bits(b, ds), "{ds} differs");
    }
}

#[test]
fn sigterm_checkpoints_and_the_restart_matches() {
    let dir = tmpdir();
    let (full, part) = (dir.path().join("full.h5"), dir.path().join("part.h5"));
    let rot = ["--set", "run.rotations=1.5"];
    assert!(spawn(2, &full, &rot).wait().unwrap().success());

    let mut child = spawn(2, &part, &rot);
    // follow the log until the drum is turning (past the pour)
    let log = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
    let mut stderr = child.stderr.take().unwrap();
    let sink = std::sync::Arc::clone(&log);
    let reader = std::thread::spawn(move || {
        let mut buf = [0u8; 4096];
        while let Ok(n) = std::io::Read::read(&mut stderr, &mut buf) {
            if n == 0 {
                break;
            }
            sink.lock()
                .unwrap()
                .push_str(&String::from_utf8_lossy(&buf[..n]));
        }
    });
    // generous: the pour takes a few seconds alone, minutes on a machine shared with runs
    wait_for("the drum to turn", Duration::from_secs(300), || {
        log.lock().unwrap().contains("particles on 2 ranks")
    });
    std::thread::sleep(Duration::from_millis(500));
    let pids = ranks_of(&part);
    assert_eq!(pids.len(), 2, "found ranks {pids:?}");
    for pid in pids {
        Command::new("kill")
            .args(["-TERM", &pid.to_string()])
            .status()
            .unwrap();
    }
    let status = child.wait().unwrap();
    reader.join().unwrap();
    let err = log.lock().unwrap().clone();
    assert_eq!(status.code(), Some(3), "{err}");
    assert!(err.contains("stopped by a signal"), "{err}");
    let ck = dir.path().join("part.ckpt.h5");
    assert!(
        ck.exists() && !part.exists(),
        "a checkpoint, and the output still partial"
    );

    let restart = [
        "--set",
        "run.rotations=1.5",
        "--restart",
        ck.to_str().unwrap(),
    ];
    assert!(spawn(2, &part, &restart).wait().unwrap().success());
    assert_same_run(&full, &part);
}

#[test]
fn a_killed_rank_ends_the_job_and_the_checkpoint_restarts() {
    let dir = tmpdir();
    let (full, part) = (dir.path().join("full.h5"), dir.path().join("part.h5"));
    let args = [
        "--set",
        "run.rotations=1.5",
        "--set",
        "output.checkpoint_every=0.1",
    ];
    assert!(spawn(2, &full, &args).wait().unwrap().success());

    let mut child = spawn(2, &part, &args);
    let ck = dir.path().join("part.ckpt.h5");
    wait_for("a checkpoint", Duration::from_secs(300), || ck.exists());
    let pids = ranks_of(&part);
    assert_eq!(pids.len(), 2);
    let t0 = Instant::now();
    Command::new("kill")
        .args(["-KILL", &pids[1].to_string()])
        .status()
        .unwrap();
    let status = child.wait().unwrap();
    assert!(!status.success());
    assert!(
        t0.elapsed() < Duration::from_secs(15),
        "the job took {:?} to stop",
        t0.elapsed()
    );

    let mut restart = args.to_vec();
    restart.extend(["--restart", ck.to_str().unwrap()]);
    let mut again = spawn(2, &part, &restart);
    let ok = again.wait().unwrap();
    let mut err = String::new();
    std::io::Read::read_to_string(again.stderr.as_mut().unwrap(), &mut err).unwrap();
    assert!(ok.success(), "{err}");
    assert_same_run(&full, &part);
}
