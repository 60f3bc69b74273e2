//! Parallel HDF5: the O(N) datasets (a checkpoint's particles and contacts, `/particles`, the
//! snapshots) are written by every rank, each its rows, and are the same bytes on any rank
//! count; a restart reads only its share of the checkpoint.

mod common;

use common::{case_path, mpirun_with_log, tmpdir};
use std::path::Path;

/// Every dataset under `groups` of the HDF5 file `path`, as (name, element size, bytes).
fn datasets(path: &Path, groups: &[&str]) -> Vec<(String, usize, Vec<u8>)> {
    let f = hdf5::File::open(path).unwrap();
    let mut out = Vec::new();
    let mut todo: Vec<hdf5::Group> = groups.iter().map(|g| f.group(g).unwrap()).collect();
    while let Some(g) = todo.pop() {
        let mut names = g.member_names().unwrap();
        names.sort();
        for name in names {
            if let Ok(sub) = g.group(&name) {
                todo.push(sub);
                continue;
            }
            let ds = g.dataset(&name).unwrap();
            let dt = ds.dtype().unwrap();
            let bytes: Vec<u8> = if dt.is::<f64>() {
                let v: Vec<f64> = ds.read_raw().unwrap();
                v.iter().flat_map(|x| x.to_le_bytes()).collect()
            } else if dt.is::<u64>() {
                let v: Vec<u64> = ds.read_raw().unwrap();
                v.iter().flat_map(|x| x.to_le_bytes()).collect()
            } else if dt.is::<i64>() {
                let v: Vec<i64> = ds.read_raw().unwrap();
                v.iter().flat_map(|x| x.to_le_bytes()).collect()
            } else if dt.is::<u8>() {
                ds.read_raw().unwrap()
            } else {
                panic!("{}: unexpected type", ds.name());
            };
            out.push((ds.name(), dt.size(), bytes));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// The storage of dataset `name` of `path`: its chunk shape (`None`: contiguous), whether
/// it is shuffled and gzipped, and its number of chunks.
fn storage(path: &Path, name: &str) -> (Option<Vec<usize>>, bool, usize) {
    use hdf5::filters::Filter;
    let f = hdf5::File::open(path).unwrap();
    let ds = f.dataset(name).unwrap();
    let filters = ds.filters();
    let gzip = filters.iter().any(|f| matches!(f, Filter::Deflate(_)))
        && filters.iter().any(|f| matches!(f, Filter::Shuffle));
    (ds.chunk(), gzip, ds.num_chunks().unwrap_or(0))
}

fn run(n: usize, out: &Path, rotations: &str, extra: &[&str]) -> std::process::Output {
    let case = case_path("sd_capped.toml");
    let rot = format!("run.rotations={rotations}");
    let mut args = vec![
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        &rot,
        "--set",
        "diagnostics.snapshots.every=0.01",
        "--set",
        "run.balance_every=0.01",
    ];
    args.extend_from_slice(extra);
    let o = mpirun_with_log(n, &args, Some("info,tumbler::run=debug"));
    assert!(
        o.status.success(),
        "{n} ranks: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

#[test]
fn checkpoints_particles_and_snapshots_are_the_same_bytes_on_1_3_and_8_ranks() {
    let dir = tmpdir();
    let d = dir.path();
    let mut first: Option<(Vec<_>, Vec<_>)> = None;
    for n in [1, 3, 8] {
        let out = d.join(format!("r{n}.h5"));
        run(n, &out, "0.03", &[]);
        let ck = datasets(&d.join(format!("r{n}.ckpt.h5")), &["particles", "contacts"]);
        let file = datasets(&out, &["particles", "snapshots"]);
        assert!(ck
            .iter()
            .any(|x| x.0 == "/contacts/history" && !x.2.is_empty()));
        assert!(file.iter().filter(|x| x.0.ends_with("/position")).count() >= 3);
        // compressed where not tiny, in the same chunks on any rank count
        for (path, name) in [
            (d.join(format!("r{n}.ckpt.h5")), "particles/position"),
            (d.join(format!("r{n}.ckpt.h5")), "contacts/history"),
            (out.clone(), "particles/velocity"),
        ] {
            let (chunk, gzip, _) = storage(&path, name);
            let rows = hdf5::File::open(&path)
                .unwrap()
                .dataset(name)
                .unwrap()
                .shape()[0];
            assert!(gzip, "{n} ranks: {name} is not compressed");
            assert_eq!(chunk, Some(vec![rows, 3]), "{n} ranks: {name}'s chunks");
        }
        match &first {
            None => first = Some((ck, file)),
            Some((ck1, file1)) => {
                assert_eq!(ck1.len(), ck.len(), "{n} ranks: checkpoint datasets");
                for (a, b) in ck1.iter().zip(&ck) {
                    assert!(a == b, "{n} ranks: checkpoint {} differs", a.0);
                }
                assert_eq!(file1.len(), file.len(), "{n} ranks: output datasets");
                for (a, b) in file1.iter().zip(&file) {
                    assert!(a == b, "{n} ranks: output {} differs", a.0);
                }
            }
        }
    }
}

#[test]
fn a_restart_on_8_ranks_reads_only_its_share_of_the_checkpoint() {
    let dir = tmpdir();
    let d = dir.path();
    let out = d.join("a.h5");
    run(2, &out, "0.02", &[]);
    let ck = d.join("a.ckpt.h5");
    let f = hdf5::File::open(&ck).unwrap();
    let n = f.dataset("particles/id").unwrap().shape()[0];
    let nh = f.dataset("contacts/id_a").unwrap().shape()[0];
    drop(f);
    assert!(n >= 8 && nh >= 8, "{n} particles, {nh} contacts");
    let o = run(8, &out, "0.03", &["--restart", ck.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    // "rank R: read K of N particles and H contact histories of the checkpoint", searched
    // in the whole text: the 8 ranks' lines can interleave (one ran on into the next)
    let mut read = vec![None; 8];
    for (at, _) in err.match_indices("rank ") {
        let words: Vec<&str> = err[at..].split_whitespace().take(14).collect();
        if words.len() < 14 || words[2] != "read" || !words[13].starts_with("checkpoint") {
            continue;
        }
        let rank: usize = words[1].trim_end_matches(':').parse().unwrap();
        let k: usize = words[3].parse().unwrap();
        let total: usize = words[5].parse().unwrap();
        let h: usize = words[8].parse().unwrap();
        assert_eq!(total, n);
        assert!(
            read[rank].replace((k, h)).is_none(),
            "rank {rank} read twice"
        );
    }
    let read: Vec<(usize, usize)> = read
        .into_iter()
        .enumerate()
        .map(|(r, x)| x.unwrap_or_else(|| panic!("no read reported by rank {r}: {err}")))
        .collect();
    for (r, &(k, h)) in read.iter().enumerate() {
        assert_eq!(k, (r + 1) * n / 8 - r * n / 8, "rank {r}'s particle rows");
        assert_eq!(h, (r + 1) * nh / 8 - r * nh / 8, "rank {r}'s contact rows");
    }
    assert_eq!(read.iter().map(|x| x.0).sum::<usize>(), n);
    assert_eq!(read.iter().map(|x| x.1).sum::<usize>(), nh);
}

#[test]
fn a_rough_wall_drum_with_histories_restarts_onto_another_rank_count_bit_identically() {
    // Contacts with the rough wall's particles (which are not in the checkpoint) go to the
    // rank that owns the wall particle's z. (A rough wall's particle has the curved wall's
    // friction: with the case's mu_wall = 0 its contacts would keep no history.)
    let dir = tmpdir();
    let d = dir.path();
    let case = case_path("rough.toml");
    let go = |n: usize, out: &str, rotations: &str, restart: Option<&str>| {
        let out = d.join(out);
        let rot = format!("run.rotations={rotations}");
        let mut args = vec![
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "model.tangential=\"history\"",
            "--set",
            "species.0.mu_wall=0.5",
            "--set",
            &rot,
        ];
        let ck;
        if let Some(c) = restart {
            ck = d.join(c);
            args.extend(["--restart", ck.to_str().unwrap()]);
        }
        let o = common::mpirun(n, &args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    go(1, "full.h5", "0.06", None);
    go(3, "part.h5", "0.031", None);
    let f = hdf5::File::open(d.join("part.ckpt.h5")).unwrap();
    let b: Vec<u64> = f.dataset("contacts/id_b").unwrap().read_raw().unwrap();
    assert!(
        b.iter()
            .any(|&id| id >= tumbler::physics::rough_wall::FIRST_ID),
        "no contact with the rough wall in the checkpoint"
    );
    drop(f);
    go(2, "part.h5", "0.06", Some("part.ckpt.h5"));
    let full = datasets(&d.join("full.h5"), &["particles"]);
    let part = datasets(&d.join("part.h5"), &["particles"]);
    assert_eq!(full.len(), part.len());
    for (a, b) in full.iter().zip(&part) {
        assert!(a == b, "3 -> 2 ranks: {} differs", a.0);
    }
}

#[test]
fn rows_of_several_compressed_chunks_are_the_same_on_1_2_and_4_ranks_and_restart_exactly() {
    // A lattice of about 12,400 particles: the position rows (24 bytes) fill two chunks and
    // the ranks' shares end inside chunks, so several ranks write parts of one compressed
    // chunk (HDF5 gathers them on one rank to filter it).
    let dir = tmpdir();
    let d = dir.path();
    let case = case_path("periodic.toml");
    let go = |n: usize, out: &Path, rotations: &str, restart: Option<&Path>| {
        let rot = format!("run.rotations={rotations}");
        let mut args = vec![
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "drum.length=800",
            "--set",
            &rot,
            "--set",
            "diagnostics.snapshots.every=0.01",
            "--set",
            "output.checkpoint_every=0.01",
        ];
        if let Some(ck) = restart {
            args.extend(["--restart", ck.to_str().unwrap()]);
        }
        let o = common::mpirun(n, &args);
        assert!(
            o.status.success(),
            "{n} ranks: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    let mut first: Option<(Vec<_>, Vec<_>)> = None;
    for n in [1, 2, 4] {
        let out = d.join(format!("r{n}.h5"));
        go(n, &out, "0.02", None);
        let ckpt = d.join(format!("r{n}.ckpt.h5"));
        let (chunk, gzip, chunks) = storage(&ckpt, "particles/position");
        let rows = hdf5::File::open(&ckpt)
            .unwrap()
            .dataset("particles/id")
            .unwrap()
            .shape()[0];
        let per_chunk = tumbler::output::series::CHUNK_BYTES / 24;
        assert!(rows > per_chunk, "{rows} particles fill one chunk only");
        assert_eq!(chunk, Some(vec![per_chunk, 3]));
        assert!(
            gzip && chunks == rows.div_ceil(per_chunk),
            "{chunks} chunks"
        );
        assert_eq!(
            storage(&out, "particles/position").0,
            Some(vec![per_chunk, 3])
        );
        let ck = datasets(&ckpt, &["particles"]);
        let file = datasets(&out, &["particles", "snapshots"]);
        match &first {
            None => first = Some((ck, file)),
            Some((ck1, file1)) => {
                assert!(ck1 == &ck, "{n} ranks: the checkpoint's rows differ");
                assert!(file1 == &file, "{n} ranks: the output's rows differ");
            }
        }
    }
    // half-way on 4 ranks, then on to the end from its checkpoint on 3
    let part = d.join("part.h5");
    go(4, &part, "0.01", None);
    go(3, &part, "0.02", Some(&d.join("part.ckpt.h5")));
    let full = datasets(&d.join("r1.h5"), &["particles"]);
    assert!(
        datasets(&part, &["particles"]) == full,
        "4 -> 3 ranks: the particles differ from the run never stopped"
    );
}
