//! A run's `.xmf` opened in ParaView itself: `pvpython` (Debian's `python3-paraview`)
//! opens it with the default reader (`OpenDataFile`, which picks Xdmf3ReaderS for `.xmf`),
//! and `tests/paraview/read_xdmf.py` reports, per time step and block, the points, cells,
//! arrays, sums of the arrays and the first point; these are checked against the HDF5 file.
//! Skipped, with a message, when `pvpython` is not installed.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The `pvpython` to use, if installed.
fn pvpython() -> Option<PathBuf> {
    let ok = Command::new("pvpython")
        .args(["-c", "import paraview.simple"])
        .env("QT_QPA_PLATFORM", "offscreen")
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        Some(PathBuf::from("pvpython"))
    } else {
        eprintln!(
            "SKIPPED: pvpython is not installed (Debian: apt-get install python3-paraview); the .xmf/.vtu files are not checked in ParaView"
        );
        None
    }
}

/// One leaf block as ParaView read it at one time.
#[derive(Debug, Default, Clone)]
struct Block {
    points: usize,
    cells: usize,
    point_arrays: Vec<String>,
    cell_arrays: Vec<String>,
    bounds: Vec<f64>,
    /// `(point|cell, name) -> (sum of the finite values, first tuple)`
    sums: BTreeMap<(String, String), (f64, Vec<f64>)>,
    point0: Vec<f64>,
}

/// The leaf blocks ParaView read at each time (`None` for a file without time), in order.
type Steps = Vec<(Option<f64>, Vec<Block>)>;

/// What `read_xdmf.py` printed: the reader's name and the blocks per time.
fn read_in_paraview(pv: &Path, file: &Path) -> (String, Steps) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/paraview/read_xdmf.py");
    let o = Command::new(pv)
        .arg(&script)
        .arg(file.canonicalize().unwrap())
        .env("QT_QPA_PLATFORM", "offscreen")
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "pvpython failed on {}:\n{out}\n{}",
        file.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    let mut reader = String::new();
    let mut steps: Steps = Vec::new();
    let nums = |s: &str| -> Vec<f64> {
        s.split_whitespace()
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect()
    };
    let list = |s: &str| -> Vec<String> {
        s.split(',')
            .filter(|x| !x.is_empty())
            .map(String::from)
            .collect()
    };
    for line in out.lines() {
        let w: Vec<&str> = line.split('\t').collect();
        let time = |s: &str| s.parse::<f64>().ok();
        match w[0] {
            "reader" => reader = w[1].to_string(),
            "block" => {
                let t = time(w[1]);
                if steps
                    .last()
                    .is_none_or(|(s, _)| s.map(f64::to_bits) != t.map(f64::to_bits))
                {
                    steps.push((t, Vec::new()));
                }
                steps.last_mut().unwrap().1.push(Block {
                    points: w[3].parse().unwrap(),
                    cells: w[4].parse().unwrap(),
                    point_arrays: list(w[5]),
                    cell_arrays: list(w[6]),
                    bounds: nums(w[7]),
                    ..Default::default()
                });
            }
            "array" => {
                let b = steps.last_mut().unwrap().1.last_mut().unwrap();
                b.sums.insert(
                    (w[3].to_string(), w[4].to_string()),
                    (w[5].parse().unwrap(), nums(w[6])),
                );
            }
            "point0" => steps.last_mut().unwrap().1.last_mut().unwrap().point0 = nums(w[3]),
            _ => {}
        }
    }
    (reader, steps)
}

fn read_f64(f: &hdf5::File, path: &str) -> Vec<f64> {
    f.dataset(path).unwrap().read_raw::<f64>().unwrap()
}

/// Sum of the finite values, in order (as the script sums them).
fn finite_sum(v: impl Iterator<Item = f64>) -> f64 {
    v.filter(|x| x.is_finite()).fold(0.0, |a, b| a + b)
}

#[test]
fn the_xmf_opens_in_paravews_default_reader_with_particles_drum_and_fields() {
    let Some(pv) = pvpython() else { return };
    let dir = common::tmpdir();
    let out = dir.path().join("drum.h5");
    common::run_case(
        2,
        "sd_capped.toml",
        &out,
        &[
            "run.rotations=0.06",
            "diagnostics.snapshots.every=0.02",
            "diagnostics.fields.window=0.03",
        ],
    );
    let (reader, steps) = read_in_paraview(&pv, &dir.path().join("drum.xmf"));
    assert_eq!(reader, "Xdmf3ReaderS", "ParaView's default reader for .xmf");

    let f = hdf5::File::open(&out).unwrap();
    let mut snaps: Vec<(f64, String)> = f
        .group("snapshots")
        .unwrap()
        .member_names()
        .unwrap()
        .into_iter()
        .map(|n| {
            let g = f.group(&format!("snapshots/{n}")).unwrap();
            (g.attr("rotations").unwrap().read_scalar().unwrap(), n)
        })
        .collect();
    snaps.sort_by(|a, b| a.0.total_cmp(&b.0));
    let ends = read_f64(&f, "fields/rotations_end");
    assert!(
        snaps.len() >= 3,
        "snapshots at 0, 0.02, 0.04 rotations: {snaps:?}"
    );
    assert!(
        ends.len() >= 2,
        "field windows ending at 0.03, 0.06: {ends:?}"
    );
    let mut times: Vec<f64> = snaps.iter().map(|s| s.0).chain(ends.clone()).collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    let got: Vec<f64> = steps.iter().map(|s| s.0.unwrap()).collect();
    assert_eq!(
        got, times,
        "one time step per snapshot and per field window"
    );

    let (x, y, z) = (
        read_f64(&f, "fields/x"),
        read_f64(&f, "fields/y"),
        read_f64(&f, "fields/z"),
    );
    let (r, half) = (0.015, 0.02); // sd_capped: D = 0.03, L = 0.04
    let species = ["small", "large"];
    for (t, blocks) in &steps {
        let t = t.unwrap();
        let snap = snaps.iter().rev().find(|s| s.0 <= t).unwrap();
        let window = ends.iter().rposition(|&e| e <= t);
        assert_eq!(
            blocks.len(),
            2 + window.is_some() as usize,
            "t = {t}: particles, drum{}",
            if window.is_some() { ", fields" } else { "" }
        );

        // particles: one vertex cell per particle, every particle array
        let p = &blocks[0];
        let g = format!("snapshots/{}", snap.1);
        let pos = read_f64(&f, &format!("{g}/position"));
        let n = pos.len() / 3;
        assert!(n > 100);
        assert_eq!((p.points, p.cells), (n, n), "t = {t}");
        assert_eq!(
            p.point_arrays,
            [
                "diameter:1",
                "species:1",
                "id:1",
                "velocity:3",
                "angular_velocity:3"
            ],
            "t = {t}"
        );
        assert_eq!(p.point0, pos[..3], "t = {t}: first particle's position");
        for name in ["diameter", "velocity", "angular_velocity"] {
            let v = read_f64(&f, &format!("{g}/{name}"));
            let (sum, first) = &p.sums[&("point".to_string(), name.to_string())];
            assert_eq!(*sum, finite_sum(v.iter().copied()), "t = {t}: {name}");
            assert_eq!(first[..], v[..first.len()], "t = {t}: {name}");
        }

        // the drum: a capped cylinder of D = 0.03, L = 0.04 in the lab frame
        let d = &blocks[1];
        assert_eq!((d.points, d.cells), (2 * 48 + 2, 4 * 48), "t = {t}: drum");
        let b = &d.bounds;
        for (k, want) in [-r, r, -r, r, -half, half].into_iter().enumerate() {
            assert!((b[k] - want).abs() < 1e-12, "t = {t}: drum bounds {b:?}");
        }

        // fields: the bins as cells with the binned fields, from the latest window
        let Some(w) = window else { continue };
        let fl = &blocks[2];
        let (nx, ny, nz) = (x.len(), y.len(), z.len());
        assert_eq!(
            (fl.points, fl.cells),
            ((nx + 1) * (ny + 1) * (nz + 1), nx * ny * nz),
            "t = {t}: fields"
        );
        assert_eq!(fl.point0, [-r, -r, -half], "t = {t}: first bin corner");
        let mut want: Vec<String> = Vec::new();
        for q in ["number_density", "volume_fraction", "axial_flux"] {
            want.extend(species.iter().map(|s| format!("{q}_{s}:1")));
        }
        for c in [
            "u", "v", "w", "ud", "vd", "wd", "u_rms", "v_rms", "w_rms", "rms",
        ] {
            want.push(format!("{c}:1"));
        }
        assert_eq!(fl.cell_arrays, want, "t = {t}");
        let bins = nx * ny * nz;
        let slab = |name: &str, parts: usize, c: usize| -> Vec<f64> {
            let v = read_f64(&f, &format!("fields/{name}"));
            let start = (w * parts + c) * bins;
            v[start..start + bins].to_vec()
        };
        let mut checks: Vec<(String, Vec<f64>)> = Vec::new();
        for q in ["number_density", "volume_fraction", "axial_flux"] {
            for (s, sp) in species.iter().enumerate() {
                checks.push((format!("{q}_{sp}"), slab(q, 2, s)));
            }
        }
        for (k, c) in ["u", "v", "w"].iter().enumerate() {
            checks.push((c.to_string(), slab("velocity", 3, k)));
        }
        for (k, c) in ["u_rms", "v_rms", "w_rms", "rms"].iter().enumerate() {
            checks.push((c.to_string(), slab("rms", 4, k)));
        }
        for (name, v) in checks {
            let (sum, _) = &fl.sums[&("cell".to_string(), name.clone())];
            assert!(v.iter().any(|x| x.is_finite() && *x != 0.0), "{name}");
            assert_eq!(*sum, finite_sum(v.into_iter()), "t = {t}: {name}");
        }
    }

    // the same snapshots as .vtu files and a .pvd series
    let vtk = dir.path().join("vtk");
    let o = common::tumbler(&[
        "export",
        out.to_str().unwrap(),
        "--vtu",
        vtk.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (reader, steps) = read_in_paraview(&pv, &vtk.join("drum.pvd"));
    assert_eq!(reader, "PVDReader");
    let got: Vec<f64> = steps.iter().map(|s| s.0.unwrap()).collect();
    let want: Vec<f64> = snaps.iter().map(|s| s.0).collect();
    assert_eq!(got, want, "one time step per snapshot");
    for ((t, blocks), snap) in steps.iter().zip(&snaps) {
        assert_eq!(blocks.len(), 2, "t = {t:?}: particles and drum");
        let g = format!("snapshots/{}", snap.1);
        let pos = read_f64(&f, &format!("{g}/position"));
        let n = pos.len() / 3;
        let p = &blocks[0];
        assert_eq!((p.points, p.cells), (n, n), "t = {t:?}");
        assert_eq!(
            p.point_arrays,
            [
                "diameter:1",
                "species:1",
                "id:1",
                "velocity:3",
                "angular_velocity:3"
            ]
        );
        assert_eq!(p.point0, pos[..3]);
        for name in ["diameter", "velocity", "angular_velocity"] {
            let v = read_f64(&f, &format!("{g}/{name}"));
            let (sum, _) = &p.sums[&("point".to_string(), name.to_string())];
            assert_eq!(*sum, finite_sum(v.iter().copied()), "t = {t:?}: {name}");
        }
        assert_eq!((blocks[1].points, blocks[1].cells), (2 * 48 + 2, 4 * 48));
    }
}
