//! Initial states: the pour fill reaches the requested fill level without overlaps; explicit
//! particles are taken as given, from the case or from a run's HDF5 file, and refused when
//! they overlap or lie outside the drum.

mod common;

use common::{case_path, mpirun, tmpdir, tumbler};
use std::path::Path;

fn read_particles(path: &Path) -> (Vec<u64>, Vec<f64>, Vec<f64>) {
    let f = hdf5::File::open(path).unwrap();
    (
        f.dataset("particles/id").unwrap().read_raw().unwrap(),
        f.dataset("particles/diameter").unwrap().read_raw().unwrap(),
        f.dataset("particles/position").unwrap().read_raw().unwrap(),
    )
}

fn max_relative_overlap(d: &[f64], x: &[f64]) -> f64 {
    let n = d.len();
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            let r: f64 = (0..3)
                .map(|k| (x[3 * i + k] - x[3 * j + k]).powi(2))
                .sum::<f64>()
                .sqrt();
            let overlap = 0.5 * (d[i] + d[j]) - r;
            worst = worst.max(overlap / d[i].min(d[j]));
        }
    }
    worst
}

#[test]
fn pour_reaches_the_fill_level_without_overlaps() {
    // With the thesis' ch. 3 contacts (t_c = 1e-4 s). The ch. 4 value, 1e-3 s, makes contacts
    // 100 times softer: a settled 15 mm deep bed then has force-chain overlaps of up to about
    // 4 % of a diameter under its own weight (mean 0.3 %), whatever the pour does.
    for (case, fill) in [
        ("sd_capped.toml", 0.3),
        ("sd_capped.toml", 0.45),
        ("sphere.toml", 0.3),
    ] {
        let dir = tmpdir();
        let out = dir.path().join("pour.h5");
        let c = case_path(case);
        let fill_arg = format!("init.fill={fill}");
        // one step after time zero: the state as poured
        let o = tumbler(&[
            "run",
            c.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.rotations=1e-6",
            "--set",
            &fill_arg,
            "--set",
            "model.collision_time=1e-4",
            "--set",
            "init.settle_time=0.1",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let f = hdf5::File::open(&out).unwrap();
        let measured: f64 = f.attr("pour_measured_fill").unwrap().read_scalar().unwrap();
        let cut: f64 = f.attr("pour_cut_height").unwrap().read_scalar().unwrap();
        assert!(
            (measured - fill).abs() < 0.02 * fill,
            "{case}: fill {measured}, requested {fill}"
        );
        let (_, d, x) = read_particles(&out);
        let worst = max_relative_overlap(&d, &x);
        assert!(
            worst < 0.01,
            "{case} fill {fill}: overlap {:.3} % of the smaller diameter",
            100.0 * worst
        );
        assert!(
            x.chunks(3).all(|p| p[1] <= cut + 1e-4),
            "{case}: particles above the cut"
        );
    }
}

#[test]
fn pour_is_reproducible_from_the_seed() {
    let dir = tmpdir();
    let c = case_path("sd_capped.toml");
    let run = |name: &str, seed: &str| {
        let out = dir.path().join(name);
        let s = format!("seed={seed}");
        let o = tumbler(&[
            "run",
            c.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "run.rotations=1e-6",
            "--set",
            &s,
        ]);
        assert!(o.status.success());
        read_particles(&out)
    };
    let (a, b, c2) = (run("a.h5", "5"), run("b.h5", "5"), run("c.h5", "6"));
    assert_eq!(
        a.2.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        b.2.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert_ne!(a.2, c2.2, "another seed gives another bed");
}

#[test]
fn explicit_particles_from_the_case_and_from_a_file() {
    let dir = tmpdir();
    let case = dir.path().join("two.toml");
    let base = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap();
    let text = base
        .replace("kind = \"pour\"", "kind = \"particles\"")
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "")
        .replace("volume_fraction = 0.5\n", "")
        + r#"
[[init.particle]]
species = 0
diameter = 0.002
position = [0.0, -0.01, -0.0012]
velocity = [0.0, 0.0, 0.5]

[[init.particle]]
species = 1
diameter = 0.003
position = [0.0, -0.01, 0.0015]
velocity = [0.0, 0.0, -0.5]
"#;
    std::fs::write(&case, &text).unwrap();
    let out = dir.path().join("two.h5");
    let o = tumbler(&[
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "run.rotations=0.0001",
        "--set",
        "model.gravity=0.0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (id, d, x) = read_particles(&out);
    assert_eq!(id, vec![0, 1]);
    assert_eq!(d, vec![0.002, 0.003]);
    // they moved towards each other for 1e-4 rotations (about 17 steps) without touching yet
    assert!(x[2] > -0.0012 && x[5] < 0.0015);

    // start again from that run's file: the state is taken over exactly
    let again = dir.path().join("again.toml");
    let without_tables = text.split("[[init.particle]]").next().unwrap();
    let file_case = without_tables.replace(
        "kind = \"particles\"",
        &format!("kind = \"particles\"\nfile = \"{}\"", out.display()),
    );
    std::fs::write(&again, file_case).unwrap();
    let out2 = dir.path().join("again.h5");
    let o = tumbler(&[
        "run",
        again.to_str().unwrap(),
        "-o",
        out2.to_str().unwrap(),
        "--set",
        "run.rotations=1e-9",
        "--set",
        "model.gravity=0.0",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (id2, d2, _) = read_particles(&out2);
    assert_eq!((id2, d2), (id, d));
}

#[test]
fn overlapping_or_outside_particles_are_refused() {
    let dir = tmpdir();
    let base = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap();
    let make = |p2: &str| {
        base.replace("kind = \"pour\"", "kind = \"particles\"")
            .replace("fill = 0.3\n", "")
            .replace("settle_time = 0.2\n", "")
            + "\n[[init.particle]]\nspecies = 0\ndiameter = 0.002\nposition = [0.0, -0.01, 0.0]\n"
            + &format!("\n[[init.particle]]\nspecies = 0\n{p2}\n")
    };
    for (p2, why) in [
        (
            "diameter = 0.002\nposition = [0.0, -0.01, 0.0014]",
            "overlap by 30.00 %",
        ),
        (
            "diameter = 0.002\nposition = [0.0, -0.0149, 0.01]",
            "is not inside the drum",
        ),
        (
            "diameter = 0.002\nposition = [0.0, 0.0, 0.0201]",
            "is not inside the drum",
        ),
        // species 0 is 2 mm with s.d. 0.1: at most 2.6 mm
        (
            "diameter = 0.0031\nposition = [0.0, 0.005, 0.0]",
            "larger than its species allows",
        ),
    ] {
        let case = dir.path().join("bad.toml");
        std::fs::write(&case, make(p2)).unwrap();
        let out = dir.path().join("bad.h5");
        let o = tumbler(&["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(why), "{p2}: {err}");
        assert!(!out.exists() && !common::tmp_partial(&out).exists());
    }
}

/// A bed read from a file on 1, 2 and 3 ranks: each rank reads only its part of the file
/// (in blocks), and the runs are the same bits. A duplicate id, or an unusable particle, in
/// a part that rank 0 never sees is still refused, by its id, with rank 0's message.
#[test]
fn particle_file_read_in_parts_on_several_ranks() {
    let dir = tmpdir();
    let bed = dir.path().join("bed.h5");
    let o = tumbler(&[
        "run",
        case_path("sd_capped.toml").to_str().unwrap(),
        "-o",
        bed.to_str().unwrap(),
        "--set",
        "run.rotations=0.01",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let base = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap();
    let from = |file: &Path| {
        let case = dir.path().join("from_file.toml");
        let text = base
            .replace(
                "kind = \"pour\"",
                &format!("kind = \"particles\"\nfile = \"{}\"", file.display()),
            )
            .replace("fill = 0.3\n", "")
            .replace("settle_time = 0.2\n", "");
        std::fs::write(&case, text).unwrap();
        case
    };
    let case = from(&bed);
    let mut outs = Vec::new();
    for ranks in [1, 2, 3] {
        let out = dir.path().join(format!("from{ranks}.h5"));
        let o = mpirun(
            ranks,
            &[
                "run",
                case.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--set",
                "run.rotations=0.01",
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        outs.push(out);
    }
    let bits = |p: &Path| {
        let f = hdf5::File::open(p).unwrap();
        let x: Vec<f64> = f.dataset("particles/position").unwrap().read_raw().unwrap();
        let id: Vec<u64> = f.dataset("particles/id").unwrap().read_raw().unwrap();
        (id, x.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
    };
    let one = bits(&outs[0]);
    assert!(one.0.len() > 100);
    for out in &outs[1..] {
        assert!(bits(out) == one, "{} differs from 1 rank", out.display());
    }

    // edit a copy of the bed: the ids run along the axis, so the first and the last
    // particle lie at opposite ends, on the first and the last of 3 ranks
    let edited = |name: &str, edit: &dyn Fn(&hdf5::File)| {
        let copy = dir.path().join(name);
        std::fs::copy(&bed, &copy).unwrap();
        let f = hdf5::File::open_rw(&copy).unwrap();
        edit(&f);
        drop(f);
        copy
    };
    let dup = edited("dup.h5", &|f| {
        let ds = f.dataset("particles/id").unwrap();
        let mut id: Vec<u64> = ds.read_raw().unwrap();
        let n = id.len();
        id[n - 1] = id[0];
        ds.write_raw(&id).unwrap();
    });
    let nan = edited("nan.h5", &|f| {
        let ds = f.dataset("particles/velocity").unwrap();
        let mut v: Vec<f64> = ds.read_raw().unwrap();
        let n = v.len();
        v[n - 3] = f64::NAN;
        ds.write_raw(&v).unwrap();
    });
    let last = one.0.last().copied().unwrap();
    for (file, why) in [
        (dup, format!("particle id {} appears twice", one.0[0])),
        (nan, format!("particle {last} has velocity (NaN")),
    ] {
        let case = from(&file);
        let out = dir.path().join("refused.h5");
        let o = mpirun(
            3,
            &["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(&why), "{why}: {err}");
        assert!(!err.contains("another rank"), "{err}");
        assert!(!out.exists() && !common::tmp_partial(&out).exists());
    }
}
