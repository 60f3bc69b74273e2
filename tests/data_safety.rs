//! Nothing lost, nothing silently wrong: a second run on the same output, outputs that would
//! be inputs, a full disk at a checkpoint, damaged checkpoints, restarts with no steps left
//! or without their output, load-balance records across a restart on another rank count,
//! followed ids that do not exist.

mod common;

use common::{case_path, mpirun, tmp_partial, tmpdir, tumbler};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const CASE: &str = "sd_capped.toml";

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `tumbler run CASE -o out --set run.rotations=R extra...`.
fn run(out: &Path, rotations: &str, extra: &[&str]) -> Output {
    let case = case_path(CASE);
    let rot = format!("run.rotations={rotations}");
    let mut args = vec!["run", s(&case), "-o", s(out), "--set", &rot];
    args.extend_from_slice(extra);
    tumbler(&args)
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", stderr(o));
}

fn refused(o: &Output, words: &[&str]) {
    let e = stderr(o);
    // refused by tumbler itself (1 or 2), not ended by a signal or a crash on the way out
    assert!(
        matches!(o.status.code(), Some(1) | Some(2)),
        "not refused cleanly: {:?}\n{e}",
        o.status
    );
    for w in words {
        assert!(e.contains(w), "{w:?} not in: {e}");
    }
    assert!(!e.contains("panicked"), "{e}");
}

fn f64s(path: &Path, name: &str) -> Vec<u64> {
    let f = hdf5::File::open(path).unwrap();
    let v: Vec<f64> = f.dataset(name).unwrap().read_raw().unwrap();
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn a_second_run_on_the_same_output_is_refused_and_the_first_finishes_whole() {
    let dir = tmpdir();
    let out = dir.path().join("same.h5");
    let case = case_path(CASE);
    let mut first = Command::new(env!("CARGO_BIN_EXE_tumbler"))
        .args(["run", s(&case), "-o", s(&out), "--set", "run.rotations=1"])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let lock = tumbler::output::lock::lock_path(&out);
    let t0 = Instant::now();
    while !tmp_partial(&out).exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "the first run never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(lock.exists());
    for extra in [&["--overwrite"][..], &[], &["--restart", "x.ckpt.h5"]] {
        let o = run(&out, "0.01", extra);
        refused(&o, &["output", "is being written by another run (pid"]);
    }
    assert!(
        first.try_wait().unwrap().is_none(),
        "the first run ended before the second was tried: make it longer"
    );
    let o = first.wait_with_output().unwrap();
    ok(&o);
    // whole and readable: every series read back, the final state there
    tumbler::output::h5::verify(&out).unwrap();
    let f = hdf5::File::open(&out).unwrap();
    assert!(f.dataset("particles/position").unwrap().size() > 0);
    let rot: Vec<f64> = f.dataset("axial/rotations").unwrap().read_raw().unwrap();
    assert!(
        (rot.last().unwrap() - 1.0).abs() < 1e-4,
        "the last sample is at 1 rotation: {rot:?}"
    );
    assert!(!lock.exists(), "the lock file is removed at the end");
}

#[test]
fn outputs_that_would_be_inputs_are_refused_before_anything_is_written() {
    let dir = tmpdir();
    let d = dir.path();
    let case = d.join("c.toml");
    let text = std::fs::read_to_string(case_path(CASE)).unwrap();
    std::fs::write(&case, &text).unwrap();
    let args = |o: &Path| {
        vec![
            "run".to_string(),
            s(&case).to_string(),
            "-o".into(),
            s(o).to_string(),
            "--overwrite".into(),
            "--set".into(),
            "run.rotations=0.01".into(),
        ]
    };
    let call = |a: Vec<String>| tumbler(&a.iter().map(String::as_str).collect::<Vec<_>>());
    // the case file itself, through another spelling, and through a hard link
    let link = d.join("link.h5");
    std::fs::hard_link(&case, &link).unwrap();
    let sub = d.join("sub");
    std::fs::create_dir(&sub).unwrap();
    for o in [case.clone(), sub.join("../c.toml"), link.clone()] {
        refused(&call(args(&o)), &["would be the case file", "c.toml"]);
    }
    // the picture or the XDMF file named after the output
    let pic = d.join("p_spacetime.png");
    std::fs::rename(&case, &pic).unwrap();
    let mut a = args(&d.join("p.h5"));
    a[1] = s(&pic).to_string();
    refused(
        &call(a),
        &[
            "space-time picture",
            "would be the case file",
            "p_spacetime.png",
        ],
    );
    std::fs::rename(&pic, &case).unwrap();
    assert_eq!(std::fs::read_to_string(&case).unwrap(), text);
    // a particle file
    let first = d.join("first.h5");
    ok(&run(&first, "0.01", &[]));
    let bare = text
        .replace("kind = \"pour\"", "kind = \"particles\"")
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "")
        .replace(
            "kind = \"particles\"",
            &format!("kind = \"particles\"\nfile = \"{}\"", first.display()),
        );
    let from_file = d.join("f.toml");
    std::fs::write(&from_file, bare).unwrap();
    let before = std::fs::read(&first).unwrap();
    let mut a = args(&first);
    a[1] = s(&from_file).to_string();
    refused(
        &call(a),
        &["would be the particle file (init.file)", "first.h5"],
    );
    assert_eq!(std::fs::read(&first).unwrap(), before);
    // the checkpoint restarted from
    let ck = d.join("first.ckpt.h5");
    let mut a = args(&ck);
    a.extend(["--restart".into(), s(&ck).to_string()]);
    refused(
        &call(a),
        &["would be the checkpoint restarted from", "first.ckpt.h5"],
    );
    // a directory, at once, leaving nothing behind
    let t0 = Instant::now();
    refused(
        &call(args(&sub)),
        &["is a directory", "-o takes a file name"],
    );
    assert!(t0.elapsed() < Duration::from_secs(5));
    assert_eq!(std::fs::read_dir(&sub).unwrap().count(), 0);
    assert!(!tumbler::output::lock::lock_path(&first).exists());
}

/// The byte offset of the first chunk of `name` in the HDF5 file `path`.
fn chunk_address(path: &Path, name: &str) -> u64 {
    let f = hdf5::File::open(path).unwrap();
    let ds = f.dataset(name).unwrap();
    assert!(ds
        .filters()
        .iter()
        .any(|f| matches!(f, hdf5::filters::Filter::Fletcher32)));
    ds.chunk_info(0).expect("a chunked dataset").addr
}

#[test]
fn a_flipped_byte_in_a_checkpoint_is_refused_naming_it() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    ok(&run(&out, "0.02", &[]));
    let ck = dir.path().join("a.ckpt.h5");
    let good = std::fs::read(&ck).unwrap();
    let output = std::fs::read(&out).unwrap();
    tumbler::output::checkpoint::read(&ck).unwrap();
    let at = chunk_address(&ck, "particles/position") as usize + 8 * 7 + 3;
    let mut bad = good.clone();
    bad[at] ^= 0x10;
    std::fs::write(&ck, &bad).unwrap();
    let e = tumbler::output::checkpoint::read(&ck).unwrap_err();
    assert!(
        e.contains("particles/position") && e.contains("checksum"),
        "{e}"
    );
    let o = run(&out, "0.04", &["--restart", s(&ck)]);
    refused(
        &o,
        &["a.ckpt.h5", "particles/position", "fails its checksum"],
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        output,
        "the output is untouched"
    );
    // and a good copy still continues
    std::fs::write(&ck, &good).unwrap();
    ok(&run(&out, "0.04", &["--restart", s(&ck)]));
}

#[test]
fn a_restart_with_no_steps_left_leaves_the_finished_output_unchanged() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    // 0.047 rotations ends between two samples: the last one is off the schedule
    ok(&run(&out, "0.047", &[]));
    let ck = dir.path().join("a.ckpt.h5");
    let before = std::fs::read(&out).unwrap();
    let o = run(&out, "0.047", &["--restart", s(&ck)]);
    ok(&o);
    assert!(stderr(&o).contains("nothing to do"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&out).unwrap(), before, "the output changed");
    // fewer rotations than the checkpoint holds: refused, unchanged
    let o = run(&out, "0.03", &["--restart", s(&ck)]);
    refused(&o, &["past run.rotations", "a.ckpt.h5"]);
    assert_eq!(std::fs::read(&out).unwrap(), before);
    // a run stopped after its last checkpoint but before its output was renamed: the
    // restart finishes it, with the same last sample
    let full = dir.path().join("full.h5");
    std::fs::copy(&out, &full).unwrap();
    std::fs::rename(&out, tmp_partial(&out)).unwrap();
    ok(&run(&out, "0.047", &["--restart", s(&ck)]));
    for ds in [
        "axial/rotations",
        "axial/volume_fraction",
        "particles/position",
    ] {
        assert_eq!(f64s(&full, ds), f64s(&out, ds), "{ds}");
    }
    common::assert_same_diagnostics(&full, &out, "finished again");
}

#[test]
fn a_restart_without_its_output_is_refused_unless_a_new_file_is_asked_for() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    ok(&run(&out, "0.02", &[]));
    let ck = dir.path().join("a.ckpt.h5");
    let other = dir.path().join("b.h5");
    let o = run(&other, "0.03", &["--restart", s(&ck)]);
    refused(&o, &["b.h5", "does not exist", "--new-output"]);
    assert!(!other.exists() && !tmp_partial(&other).exists());
    let o = run(&other, "0.03", &["--restart", s(&ck), "--new-output"]);
    ok(&o);
    let rot: Vec<f64> = hdf5::File::open(&other)
        .unwrap()
        .dataset("axial/rotations")
        .unwrap()
        .read_raw()
        .unwrap();
    assert!(
        rot[0] > 0.019,
        "the new file holds only the continuation: {rot:?}"
    );
    // onto an existing file, --new-output is refused
    let o = run(&out, "0.03", &["--restart", s(&ck), "--new-output"]);
    refused(&o, &["--new-output", "already exists"]);
}

#[test]
fn load_balance_records_and_ranks_survive_a_restart_on_another_rank_count() {
    let dir = tmpdir();
    let d = dir.path();
    let case = case_path(CASE);
    let go = |ranks: usize, out: &Path, rot: &str, restart: Option<&Path>| {
        let rot = format!("run.rotations={rot}");
        let mut args = vec![
            "run",
            s(&case),
            "-o",
            s(out),
            "--set",
            &rot,
            "--set",
            "run.balance_every=0.01",
        ];
        if let Some(r) = restart {
            args.extend(["--restart", s(r)]);
        }
        let o = mpirun(ranks, &args);
        ok(&o);
    };
    let full = d.join("full.h5");
    go(1, &full, "0.06", None);
    let part = d.join("part.h5");
    go(1, &part, "0.035", None);
    go(2, &part, "0.06", Some(&d.join("part.ckpt.h5")));
    let f = hdf5::File::open(&part).unwrap();
    let ranks: u64 = f.attr("ranks").unwrap().read_scalar().unwrap();
    assert_eq!(ranks, 2, "the root attribute ranks is the last segment's");
    let seg: u64 = f
        .group("balance")
        .unwrap()
        .attr("ranks")
        .unwrap()
        .read_scalar()
        .unwrap();
    assert_eq!(seg, 2);
    let earlier = f.group("balance_earlier/segment_0").unwrap();
    let r0: u64 = earlier.attr("ranks").unwrap().read_scalar().unwrap();
    assert_eq!(r0, 1);
    let first: Vec<f64> = earlier.dataset("rotations").unwrap().read_raw().unwrap();
    let later: Vec<f64> = f.dataset("balance/rotations").unwrap().read_raw().unwrap();
    let whole: Vec<f64> = hdf5::File::open(&full)
        .unwrap()
        .dataset("balance/rotations")
        .unwrap()
        .read_raw()
        .unwrap();
    // the first segment's checks up to the checkpoint, then the second's
    let joined: Vec<u64> = first.iter().chain(&later).map(|x| x.to_bits()).collect();
    let expected: Vec<u64> = whole.iter().map(|x| x.to_bits()).collect();
    assert_eq!(joined, expected, "{first:?} + {later:?} vs {whole:?}");
    assert!(first.len() >= 3 && !later.is_empty());
}

#[test]
fn followed_ids_that_do_not_exist_are_refused_naming_them() {
    let dir = tmpdir();
    let out = dir.path().join("a.h5");
    let o = run(
        &out,
        "0.01",
        &["--set", "diagnostics.paths.ids=[3, 999999]"],
    );
    refused(&o, &["diagnostics.paths.ids", "no particle has id 999999"]);
    assert!(!out.exists() && !tmp_partial(&out).exists());
}

/// A small tmpfs at `dir` (root only); `None`, with a message, where it cannot be mounted.
struct Tmpfs(PathBuf);

impl Tmpfs {
    fn mount(dir: &Path, bytes: u64) -> Option<Tmpfs> {
        let o = Command::new("mount")
            .args([
                "-t",
                "tmpfs",
                "-o",
                &format!("size={bytes}"),
                "tmpfs",
                s(dir),
            ])
            .output();
        match o {
            Ok(o) if o.status.success() => Some(Tmpfs(dir.to_path_buf())),
            Ok(o) => {
                eprintln!(
                    "skipped: cannot mount a tmpfs (not root?): {}",
                    String::from_utf8_lossy(&o.stderr)
                );
                None
            }
            Err(e) => {
                eprintln!("skipped: cannot run mount: {e}");
                None
            }
        }
    }
}

impl Drop for Tmpfs {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(&self.0).status();
    }
}

/// A 16 MiB tmpfs at `dir/mnt`, filled so that only the output of `out_size` bytes and one
/// and a half checkpoints of `ck_size` fit: the first checkpoint fits, the next (written
/// while the first still exists) does not. `None` where no tmpfs can be mounted.
fn nearly_full_disk(dir: &Path, out_size: u64, ck_size: u64) -> Option<(Tmpfs, PathBuf)> {
    let mnt = dir.join("mnt");
    std::fs::create_dir(&mnt).unwrap();
    let disk = 16 << 20;
    let fs = Tmpfs::mount(&mnt, disk)?;
    let room = out_size + ck_size * 3 / 2;
    std::fs::write(mnt.join("filler"), vec![1u8; (disk - room) as usize]).unwrap();
    Some((fs, mnt))
}

#[test]
fn a_full_disk_at_a_checkpoint_keeps_the_previous_one_and_a_restartable_output() {
    let dir = tmpdir();
    let ck_every = ["--set", "output.checkpoint_every=0.05"];
    // sizes on an ordinary disk: the finished output and a checkpoint
    let reference = dir.path().join("ref.h5");
    ok(&run(&reference, "0.1", &ck_every));
    let out_size = std::fs::metadata(&reference).unwrap().len();
    let ck_size = std::fs::metadata(dir.path().join("ref.ckpt.h5"))
        .unwrap()
        .len();
    // the checkpoint at 0.05 rotations fits, the final one does not
    let Some((_fs, mnt)) = nearly_full_disk(dir.path(), out_size, ck_size) else {
        return;
    };
    let filler = mnt.join("filler");
    let out = mnt.join("a.h5");
    let o = run(&out, "0.1", &ck_every);
    refused(&o, &["No space left on device", "a.ckpt.h5"]);
    let names: Vec<String> = std::fs::read_dir(&mnt)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        !names.iter().any(|n| n.ends_with(".tmp")),
        "a temporary file is left: {names:?}"
    );
    let ck = mnt.join("a.ckpt.h5");
    let kept = tumbler::output::checkpoint::read(&ck).unwrap();
    assert!(kept.step > 0, "the checkpoint at 0.05 rotations is kept");
    tumbler::output::h5::verify(&tmp_partial(&out)).unwrap();
    // with room again, the restart continues to the same bits as the run never stopped
    std::fs::remove_file(&filler).unwrap();
    ok(&run(&out, "0.1", &["--restart", s(&ck)]));
    for ds in [
        "axial/rotations",
        "axial/volume_fraction",
        "particles/position",
    ] {
        assert_eq!(f64s(&reference, ds), f64s(&out, ds), "{ds}");
    }
    common::assert_same_diagnostics(&reference, &out, "after a full disk");
}

#[test]
fn a_full_disk_at_a_checkpoint_on_3_ranks_stops_every_rank_and_keeps_the_previous_one() {
    // The checkpoint is written by every rank together: the one that meets the full disk
    // must not leave the others waiting in a collective call.
    let dir = tmpdir();
    let case = case_path(CASE);
    let reference = dir.path().join("ref.h5");
    let args = |out: &Path| -> Vec<String> {
        [
            "run",
            s(&case),
            "-o",
            s(out),
            "--set",
            "run.rotations=0.1",
            "--set",
            "output.checkpoint_every=0.05",
        ]
        .iter()
        .map(|x| x.to_string())
        .collect()
    };
    let to_str = |v: &[String]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let a = to_str(&args(&reference));
    let a: Vec<&str> = a.iter().map(|x| x.as_str()).collect();
    ok(&mpirun(3, &a));
    let out_size = std::fs::metadata(&reference).unwrap().len();
    let ck_size = std::fs::metadata(dir.path().join("ref.ckpt.h5"))
        .unwrap()
        .len();
    let Some((_fs, mnt)) = nearly_full_disk(dir.path(), out_size, ck_size) else {
        return;
    };
    let out = mnt.join("a.h5");
    let a = to_str(&args(&out));
    let a: Vec<&str> = a.iter().map(|x| x.as_str()).collect();
    let t0 = Instant::now();
    let o = mpirun(3, &a);
    refused(&o, &["No space left on device", "a.ckpt.h5"]);
    assert!(
        t0.elapsed() < Duration::from_secs(120),
        "a rank was left waiting"
    );
    let names: Vec<String> = std::fs::read_dir(&mnt)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        !names.iter().any(|n| n.ends_with(".tmp")),
        "a temporary file is left: {names:?}"
    );
    let kept = tumbler::output::checkpoint::read(&mnt.join("a.ckpt.h5")).unwrap();
    assert!(kept.step > 0, "the checkpoint at 0.05 rotations is kept");
    assert!(kept.particles.len() as u64 == kept.n_particles && kept.n_particles > 0);
}
