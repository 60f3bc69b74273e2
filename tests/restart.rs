//! Checkpoints and restarts: N steps, a checkpoint, a restart (on the same or another number
//! of ranks) and the rest gives the same bits and the same axial series as the run never
//! interrupted, with the Cundall-Strack history model.

mod common;

use common::{case_path, mpirun, tmpdir};
use std::path::Path;

fn bits(f: &hdf5::File, name: &str) -> Vec<u64> {
    let v: Vec<f64> = f.dataset(name).unwrap().read_raw().unwrap();
    v.iter().map(|x| x.to_bits()).collect()
}

fn run(
    ranks: usize,
    dir: &Path,
    out: &str,
    rotations: &str,
    restart: Option<&str>,
) -> std::process::Output {
    run_with(ranks, dir, out, rotations, restart, &[])
}

fn run_with(
    ranks: usize,
    dir: &Path,
    out: &str,
    rotations: &str,
    restart: Option<&str>,
    extra: &[&str],
) -> std::process::Output {
    let case = case_path("sd_capped.toml");
    let out = dir.join(out);
    let rot = format!("run.rotations={rotations}");
    let mut args = vec![
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        &rot,
    ];
    let ck;
    if let Some(c) = restart {
        ck = dir.join(c);
        args.extend(["--restart", ck.to_str().unwrap()]);
    }
    args.extend_from_slice(extra);
    let o = mpirun(ranks, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

#[test]
fn restart_is_bit_identical_to_the_run_never_interrupted() {
    let dir = tmpdir();
    let d = dir.path();
    run(2, d, "full.h5", "0.1", None);
    // 0.047 rotations ends between two samples: that last sample is dropped on restart
    for (a, b) in [(1, 1), (2, 2), (1, 3), (3, 2)] {
        let name = format!("part{a}{b}.h5");
        run(a, d, &name, "0.047", None);
        let ck = format!("part{a}{b}.ckpt.h5");
        run(b, d, &name, "0.1", Some(&ck));
        assert_same_run(d, "full.h5", &name, &format!("{a} -> {b} ranks"));
    }
}

/// The run `name` (interrupted and restarted) holds the same bits and series as `full`.
fn assert_same_run(d: &Path, full: &str, name: &str, what: &str) {
    let full_file = hdf5::File::open(d.join(full)).unwrap();
    let part = hdf5::File::open(d.join(name)).unwrap();
    for ds in [
        "particles/position",
        "particles/velocity",
        "particles/angular_velocity",
        "axial/rotations",
        "axial/volume_fraction",
    ] {
        assert_eq!(
            bits(&full_file, ds),
            bits(&part, ds),
            "{what}: {ds} differs"
        );
    }
    let c1: Vec<u64> = full_file
        .dataset("axial/count")
        .unwrap()
        .read_raw()
        .unwrap();
    let c2: Vec<u64> = part.dataset("axial/count").unwrap().read_raw().unwrap();
    assert_eq!(c1, c2, "{what}: axial counts");
    common::assert_same_diagnostics(&d.join(full), &d.join(name), what);
}

#[test]
fn restart_onto_many_more_or_fewer_ranks_with_balancing_is_bit_identical() {
    // The slab boundaries move every 0.02 rotations; the checkpoint holds the moved ones,
    // and a restart cuts the drum for its own rank count, so particles and their contact
    // histories go from any rank to any rank.
    let dir = tmpdir();
    let d = dir.path();
    let balance = ["--set", "run.balance_every=0.02"];
    run_with(1, d, "full.h5", "0.1", None, &balance);
    for (a, b) in [(8, 3), (2, 8), (4, 6)] {
        let name = format!("part{a}{b}.h5");
        run_with(a, d, &name, "0.047", None, &balance);
        let ck = format!("part{a}{b}.ckpt.h5");
        run_with(b, d, &name, "0.1", Some(&ck), &balance);
        assert_same_run(d, "full.h5", &name, &format!("{a} -> {b} ranks, balanced"));
    }
}

#[test]
fn restart_with_rolling_and_cohesion_onto_another_rank_count_is_bit_identical() {
    // six history words per contact and per wall slot in the checkpoint
    let dir = tmpdir();
    let d = dir.path();
    let sets = [
        "--set",
        "model.rolling=\"sds\"",
        "--set",
        "species.0.mu_roll=0.2",
        "--set",
        "species.1.mu_roll=0.3",
        "--set",
        "model.cohesion=\"sjkr\"",
        "--set",
        "species.0.cohesion_energy=2000.0",
        "--set",
        "species.1.cohesion_energy=3000.0",
    ];
    run_with(2, d, "full.h5", "0.1", None, &sets);
    for (a, b) in [(4, 1), (1, 3)] {
        let name = format!("part{a}{b}.h5");
        run_with(a, d, &name, "0.047", None, &sets);
        let ck = format!("part{a}{b}.ckpt.h5");
        let f = hdf5::File::open(d.join(&ck)).unwrap();
        let width = f.dataset("contacts/history").unwrap().shape()[1];
        assert_eq!(width, 6, "contact history words in the checkpoint");
        drop(f);
        run_with(b, d, &name, "0.1", Some(&ck), &sets);
        assert_same_run(d, "full.h5", &name, &format!("{a} -> {b} ranks, rolling"));
    }
}

#[test]
fn checkpoint_without_order_keys_resumes_in_the_order_of_the_ids() {
    // A checkpoint written before the spatial sort has no `particles/order_key`: its
    // particles resume with key 0, the order of the ids, which a run with
    // `run.sort_every = 0` keeps throughout; with the sort on they sort at the next sort.
    let dir = tmpdir();
    let d = dir.path();
    let drop_keys = |ck: &str| {
        let f = hdf5::File::open_rw(d.join(ck)).unwrap();
        f.unlink("particles/order_key").unwrap();
    };
    let off = ["--set", "run.sort_every=0"];
    run_with(2, d, "full.h5", "0.1", None, &off);
    run_with(2, d, "part.h5", "0.047", None, &off);
    drop_keys("part.ckpt.h5");
    run_with(3, d, "part.h5", "0.1", Some("part.ckpt.h5"), &off);
    assert_same_run(
        d,
        "full.h5",
        "part.h5",
        "2 -> 3 ranks, a checkpoint without keys",
    );
    run_with(2, d, "sorted.h5", "0.047", None, &[]);
    drop_keys("sorted.ckpt.h5");
    run_with(3, d, "sorted.h5", "0.1", Some("sorted.ckpt.h5"), &[]);
}

#[test]
fn checkpoint_with_an_id_out_of_range_is_refused() {
    // ids travel as f64 words (exact below 2^53) and a run's are below 2^40 (the rough
    // wall's start there): a checkpoint holding another is refused by name, not loaded
    let dir = tmpdir();
    let d = dir.path();
    run(1, d, "a.h5", "0.01", None);
    // each damaged checkpoint is edited in a file of its own and copied to the one restarted
    // from: HDF5 opens files without close-on-exec, so a `tumbler` another test thread starts
    // while the edit is open inherits the descriptor and HDF5's lock with it ("unable to lock
    // file, errno = 11" for the restart); the copy is a new file nobody holds
    let set_id = |id: u64, k: usize| {
        let edited = d.join(format!("edited{k}.h5"));
        std::fs::copy(d.join("a.ckpt.h5"), &edited).unwrap();
        {
            let f = hdf5::File::open_rw(&edited).unwrap();
            let ds = f.dataset("particles/id").unwrap();
            let mut ids: Vec<u64> = ds.read_raw().unwrap();
            ids[3] = id;
            ds.write_raw(&ids).unwrap();
        }
        let ck = d.join(format!("bad{k}.ckpt.h5"));
        std::fs::copy(&edited, &ck).unwrap();
        ck
    };
    let case = case_path("sd_capped.toml");
    let out = d.join("b.h5");
    for (k, (id, ranks)) in [((1u64 << 53) + 1, 1), ((1 << 53) + 1, 2), (1 << 40, 2)]
        .into_iter()
        .enumerate()
    {
        let ck = set_id(id, k);
        let args = [
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--restart",
            ck.to_str().unwrap(),
        ];
        let o = mpirun(ranks, &args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!("particles/id: id {id} is out of range"))
                && !err.contains("panicked"),
            "{err}"
        );
    }
}

#[test]
fn checkpoint_of_another_case_is_refused() {
    let dir = tmpdir();
    let d = dir.path();
    run(1, d, "a.h5", "0.01", None);
    let case = case_path("sd_capped.toml");
    let out = d.join("b.h5");
    let ck = d.join("a.ckpt.h5");
    let args = [
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--restart",
        ck.to_str().unwrap(),
        "--set",
        "drum.omega=3.0",
    ];
    let o = mpirun(1, &args);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("different drum") && err.contains("--allow-different-case"),
        "{err}"
    );
    // other averaging windows would cut the output back to the wrong records
    let mut other = args.to_vec();
    other[7] = "diagnostics.window=0.04";
    let o = mpirun(1, &other);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("different diagnostics"), "{err}");
    // not even when asked
    other.push("--allow-different-case");
    assert!(!mpirun(1, &other).status.success());
    let mut args = args.to_vec();
    args.push("--allow-different-case");
    // b.h5 does not exist yet: a restart into a fresh output must say so
    let o = mpirun(1, &args);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--new-output"), "{err}");
    args.push("--new-output");
    assert!(mpirun(1, &args).status.success());
}
