//! `tumbler info`, `tumbler bands` and `tumbler plot ...` on a synthetic run file with the
//! layout of docs/diagnostics.md and known values: the band counts, the dataset listing,
//! the pictures (valid PNGs of the documented size, the two signs of `w` in different
//! colours) and the refusals (exit code 2 with a message naming the culprit).
//!
//! Set `TUMBLER_INSPECT_KEEP=DIR` to write the files and pictures in DIR to look at them.

use hdf5::types::VarLenUnicode;
use ndarray::{Array1, ArrayD, IxDyn};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::str::FromStr;

const NZ: usize = 24; // axial slices
const NT: usize = 6; // axial samples: 2 bands in the first three, 4 in the last three
const NW: usize = 3; // slice windows
const NF: usize = 2; // field windows
const NX: usize = 8; // field bins along x, centres -3.5 .. 3.5
const NY: usize = 6; // field bins along y, centres -2.5 .. 2.5 (bed below y = 0)
const NZF: usize = 4; // field slices

/// What to leave out of the synthetic file.
#[derive(Clone, Copy, Default)]
struct Omit {
    /// `/slices/diffusivity`.
    diffusivity: bool,
    /// `/axial/bands` (the band rule then comes from the case).
    bands: bool,
    /// The whole `/fields` group.
    fields: bool,
}

struct Workspace {
    _tmp: Option<tempfile::TempDir>,
    dir: PathBuf,
}

fn workspace(name: &str) -> Workspace {
    match std::env::var_os("TUMBLER_INSPECT_KEEP") {
        Some(d) => {
            let dir = PathBuf::from(d).join(name);
            std::fs::create_dir_all(&dir).unwrap();
            Workspace { _tmp: None, dir }
        }
        None => {
            let tmp = tempfile::tempdir().unwrap();
            let dir = tmp.path().to_path_buf();
            Workspace {
                _tmp: Some(tmp),
                dir,
            }
        }
    }
}

fn tumbler(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tumbler"))
        .args(args)
        .output()
        .expect("the tumbler binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(args: &[&str]) -> String {
    let o = tumbler(args);
    assert!(
        o.status.success(),
        "tumbler {args:?} failed: {}",
        stderr(&o)
    );
    stdout(&o)
}

/// Run a command that must be refused with exit code 2 and a message containing `names`.
fn refused(args: &[&str], names: &str) {
    let o = tumbler(args);
    assert_eq!(o.status.code(), Some(2), "tumbler {args:?}: {}", stderr(&o));
    assert!(
        stderr(&o).contains(names),
        "tumbler {args:?}: message {:?} does not name {names:?}",
        stderr(&o)
    );
}

fn str_attr(loc: &hdf5::Location, name: &str, value: &str) {
    loc.new_attr::<VarLenUnicode>()
        .create(name)
        .unwrap()
        .write_scalar(&VarLenUnicode::from_str(value).unwrap())
        .unwrap();
}

fn put(g: &hdf5::Group, name: &str, shape: &[usize], data: Vec<f64>, units: &str) {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data).unwrap();
    let ds = g.new_dataset_builder().with_data(&a).create(name).unwrap();
    str_attr(&ds, "units", units);
    str_attr(&ds, "definition", &format!("test data for {name}"));
}

/// Fill a `shape` array from a function of its index.
fn fill(shape: &[usize], f: impl Fn(&[usize]) -> f64) -> Vec<f64> {
    let n: usize = shape.iter().product();
    let mut idx = vec![0usize; shape.len()];
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        out.push(f(&idx));
        for d in (0..shape.len()).rev() {
            idx[d] += 1;
            if idx[d] < shape[d] {
                break;
            }
            idx[d] = 0;
        }
    }
    out
}

fn centres(n: usize, spacing: f64) -> Vec<f64> {
    (0..n)
        .map(|k| (k as f64 - 0.5 * (n as f64 - 1.0)) * spacing)
        .collect()
}

/// The big species' volume fraction at sample `t`, slice `k`: 2 bands, then 4.
fn big_fraction(t: usize, k: usize) -> f64 {
    let width = if t < NT / 2 { NZ / 2 } else { NZ / 4 };
    if (k / width).is_multiple_of(2) {
        0.9
    } else {
        0.1
    }
}

fn write_run(path: &Path, omit: Omit) {
    let case = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases/periodic.toml"),
    )
    .unwrap();
    let f = hdf5::File::create(path).unwrap();
    str_attr(&f, "case", &case);
    str_attr(&f, "version", "0.1.0");
    str_attr(&f, "git_hash", "test");
    f.new_attr::<u64>()
        .create("ranks")
        .unwrap()
        .write_scalar(&1u64)
        .unwrap();
    f.new_attr::<u64>()
        .create("steps")
        .unwrap()
        .write_scalar(&1200u64)
        .unwrap();

    let axial = f.create_group("axial").unwrap();
    str_attr(&axial, "species", "small,big");
    let z = centres(NZ, 1.0);
    put(&axial, "z", &[NZ], z.clone(), "length");
    let rotations: Vec<f64> = (1..=NT).map(|t| 0.5 * t as f64).collect();
    put(&axial, "rotations", &[NT], rotations, "rotations");
    let vf = fill(&[NT, 2, NZ], |i| {
        let big = big_fraction(i[0], i[2]);
        if i[1] == 1 {
            big
        } else {
            1.0 - big
        }
    });
    put(&axial, "volume_fraction", &[NT, 2, NZ], vf, "-");
    if !omit.bands {
        // deliberately not what the rule gives, to tell the stored series from a recount
        let ds = axial
            .new_dataset_builder()
            .with_data(&Array1::from(vec![5u64, 5, 5, 6, 6, 6]))
            .create("bands")
            .unwrap();
        ds.new_attr::<f64>()
            .create("threshold")
            .unwrap()
            .write_scalar(&0.2)
            .unwrap();
        for (name, v) in [("min_slices", 2u64), ("periodic", 1), ("species", 1)] {
            ds.new_attr::<u64>()
                .create(name)
                .unwrap()
                .write_scalar(&v)
                .unwrap();
        }
    }

    let s = f.create_group("slices").unwrap();
    put(&s, "z", &[NZ], z.clone(), "length");
    put(
        &s,
        "rotations_start",
        &[NW],
        vec![0.0, 1.0, 2.0],
        "rotations",
    );
    put(&s, "rotations_end", &[NW], vec![1.0, 2.0, 3.0], "rotations");
    let wave = |w: usize, k: usize| (1.0 + w as f64) * (0.4 * k as f64).sin();
    let sz = [NW, 2, NZ];
    put(
        &s,
        "concentration",
        &sz,
        fill(&sz, |i| {
            let c = 0.5 + 0.3 * (0.5 * i[2] as f64).sin();
            if i[1] == 0 {
                c
            } else {
                1.0 - c
            }
        }),
        "-",
    );
    put(
        &s,
        "q_up",
        &sz,
        fill(&sz, |i| 0.5 * wave(i[0], i[2]) + i[1] as f64),
        "length^3/time",
    );
    put(
        &s,
        "q_down",
        &sz,
        fill(&sz, |i| -0.5 * wave(i[0], i[2]) - i[1] as f64),
        "length^3/time",
    );
    put(
        &s,
        "q_up_mixture",
        &[NW, NZ],
        fill(&[NW, NZ], |i| wave(i[0], i[1]) + 1.0),
        "length^3/time",
    );
    put(
        &s,
        "q_down_mixture",
        &[NW, NZ],
        fill(&[NW, NZ], |i| -wave(i[0], i[1]) - 1.0),
        "length^3/time",
    );
    if !omit.diffusivity {
        put(
            &s,
            "diffusivity",
            &sz,
            fill(&sz, |i| {
                if i[2] == 5 {
                    f64::NAN
                } else {
                    0.1 + 0.01 * i[2] as f64
                }
            }),
            "length^2/time",
        );
    }

    let snapshots = f.create_group("snapshots").unwrap();
    for k in 0..5u64 {
        let g = snapshots.create_group(&format!("{k:06}")).unwrap();
        g.new_attr::<u64>()
            .create("step")
            .unwrap()
            .write_scalar(&(100 * k))
            .unwrap();
        put(&g, "id", &[3], vec![0.0, 1.0, 2.0], "-");
    }

    if omit.fields {
        return;
    }
    let g = f.create_group("fields").unwrap();
    let (x, y, zf) = (centres(NX, 1.0), centres(NY, 1.0), centres(NZF, 6.0));
    put(
        &g,
        "x",
        &[NX],
        x.clone(),
        "length (m for SI cases, small-particle diameters for reduced ones)",
    );
    put(&g, "y", &[NY], y.clone(), "length");
    put(&g, "z", &[NZF], zf, "length");
    put(&g, "rotations_start", &[NF], vec![0.0, 1.5], "rotations");
    put(&g, "rotations_end", &[NF], vec![1.5, 3.0], "rotations");
    let filled = |iy: usize| y[iy] < 0.0;
    let species = [NF, 2, NX, NY, NZF];
    put(
        &g,
        "volume_fraction",
        &species,
        fill(&species, |i| if filled(i[3]) { 0.3 } else { 0.0 }),
        "-",
    );
    put(
        &g,
        "number_density",
        &species,
        fill(&species, |i| {
            if filled(i[3]) {
                0.6 + 0.1 * i[1] as f64
            } else {
                0.0
            }
        }),
        "1/length^3",
    );
    put(
        &g,
        "axial_flux",
        &species,
        fill(&species, |i| if x[i[2]] < 0.0 { 0.2 } else { -0.2 }),
        "1/(length^2 time)",
    );
    // w = +1 for x < 0 and -1 for x > 0; u = x; v = y; NaN in the empty bins above the bed
    let vel = [NF, 3, NX, NY, NZF];
    let velocity = |i: &[usize]| {
        if !filled(i[3]) {
            return f64::NAN;
        }
        match i[1] {
            0 => x[i[2]],
            1 => y[i[3]],
            _ => {
                if x[i[2]] < 0.0 {
                    1.0
                } else {
                    -1.0
                }
            }
        }
    };
    put(&g, "velocity", &vel, fill(&vel, velocity), "length/time");
    put(
        &g,
        "velocity_drum",
        &vel,
        fill(&vel, velocity),
        "length/time",
    );
    let rms = [NF, 4, NX, NY, NZF];
    put(
        &g,
        "rms",
        &rms,
        fill(&rms, |i| 0.1 * (i[1] + 1) as f64),
        "length/time",
    );
    let col = [NF, NX, NZF];
    put(&g, "surface", &col, fill(&col, |_| 0.0), "length");
    put(
        &g,
        "boundary",
        &col,
        fill(&col, |i| {
            if i[1] == 0 {
                f64::NAN
            } else {
                -1.0 - 0.1 * i[1] as f64
            }
        }),
        "length",
    );
    put(
        &g,
        "depth",
        &col,
        fill(&col, |i| 1.0 + 0.1 * i[1] as f64),
        "length",
    );
}

/// Width, height and RGB pixels of a PNG.
fn read_png(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    let mut reader = decoder.read_info().expect("a valid PNG");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("a valid PNG");
    let px = match info.color_type {
        png::ColorType::Rgb => buf[..info.buffer_size()]
            .chunks(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        png::ColorType::Grayscale => buf[..info.buffer_size()]
            .iter()
            .map(|&g| [g, g, g])
            .collect(),
        other => panic!("unexpected PNG colour type {other:?}"),
    };
    (info.width, info.height, px)
}

fn assert_png(path: &Path, size: (u32, u32)) {
    assert!(path.exists(), "{} was not written", path.display());
    let (w, h, _) = read_png(path);
    assert_eq!((w, h), size, "size of {}", path.display());
}

/// `(rotations, bands)` rows of a `bands` table.
fn table(text: &str) -> Vec<(f64, u64)> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("rotations"))
        .map(|l| {
            let mut it = l.split_whitespace();
            let r = it.next().unwrap().parse().unwrap();
            let b = it.next().unwrap().parse().unwrap();
            (r, b)
        })
        .collect()
}

#[test]
fn info_lists_attributes_and_datasets() {
    let ws = workspace("info");
    let file = ws.dir.join("run.h5");
    write_run(&file, Omit::default());
    let f = file.to_str().unwrap();
    let out = ok(&["info", f]);
    for expected in [
        "version:    0.1.0",
        "git_hash:   test",
        "ranks:      1",
        "steps:      1200",
        "time:       0.5 to 3 rotations (6 axial samples)",
        "title = \"test: small periodic drum\"",
        "  /axial/volume_fraction  [6 x 2 x 24]  float64",
        "  /axial/bands  [6]  uint64",
        "attributes: min_slices = 2, periodic = 1, species = 1, threshold = 0.2",
        "  /fields/velocity  [2 x 3 x 8 x 6 x 4]  float64",
        "units: length/time",
        "definition: test data for velocity",
        "  /slices/q_up_mixture  [3 x 24]  float64",
        "/axial/  (group)\n    attributes: species = small,big",
    ] {
        assert!(out.contains(expected), "info lacks {expected:?}:\n{out}");
    }
    // only the first lines of the case, unless --case
    assert!(!out.contains("sample_every"), "{out}");
    assert!(ok(&["info", f, "--case"]).contains("sample_every = 0.1"));
    // numbered groups: the first listed, the others counted, unless --all
    assert!(
        out.contains("  /snapshots/000000/id  [3]  float64"),
        "{out}"
    );
    assert!(
        out.contains("4 more groups like /snapshots/000000/"),
        "{out}"
    );
    assert!(!out.contains("/snapshots/000003/id"), "{out}");
    assert!(ok(&["info", f, "--all"]).contains("  /snapshots/000003/id  [3]  float64"));
}

#[test]
fn bands_reads_the_stored_series_or_recounts() {
    let ws = workspace("bands");
    let stored = ws.dir.join("stored.h5");
    let bare = ws.dir.join("bare.h5");
    write_run(&stored, Omit::default());
    write_run(
        &bare,
        Omit {
            bands: true,
            ..Omit::default()
        },
    );
    let (s, b) = (stored.to_str().unwrap(), bare.to_str().unwrap());
    let rows = |text: String| table(&text);
    let expect = |counts: [u64; NT]| -> Vec<(f64, u64)> {
        (0..NT).map(|t| (0.5 * (t + 1) as f64, counts[t])).collect()
    };
    // the run's own series, as written
    assert_eq!(rows(ok(&["bands", s])), expect([5, 5, 5, 6, 6, 6]));
    // a rule given: recounted from the volume fractions (2 bands, then 4)
    assert_eq!(
        rows(ok(&["bands", s, "--min-slices", "2"])),
        expect([2, 2, 2, 4, 4, 4])
    );
    // no stored series: recounted with the case's periodic ends and the default rule
    let out = ok(&["bands", b]);
    assert!(
        out.contains("species 1 (big)") && out.contains("periodic"),
        "{out}"
    );
    assert_eq!(rows(out), expect([2, 2, 2, 4, 4, 4]));
    // the profile departs from its mean by 0.4: a threshold of 0.5 sees no band
    assert_eq!(
        rows(ok(&["bands", b, "--threshold", "0.5"])),
        expect([0; NT])
    );
    // bands of 6 slices vanish when a band needs 7
    assert_eq!(
        rows(ok(&["bands", b, "--min-slices", "7"])),
        expect([2, 2, 2, 0, 0, 0])
    );
    refused(&["bands", b, "--min-slices", "0"], "--min-slices");
}

#[test]
fn plots_are_pngs_of_the_documented_size() {
    use tumbler::plot::{field, flux, profile, spacetime};
    let ws = workspace("plots");
    let file = ws.dir.join("run.h5");
    write_run(&file, Omit::default());
    let f = file.to_str().unwrap();
    let beside = |name: &str| ws.dir.join(name);

    assert!(ok(&["plot", "spacetime", f]).contains("run_spacetime.png"));
    assert_png(&beside("run_spacetime.png"), spacetime::SIZE);
    ok(&[
        "plot",
        "spacetime",
        f,
        "--bare",
        "-o",
        beside("bare.png").to_str().unwrap(),
    ]);
    assert_png(&beside("bare.png"), tumbler::output::spacetime::SIZE);

    ok(&["plot", "profile", f]);
    assert_png(&beside("run_profile_2.png"), profile::SIZE);
    ok(&["plot", "profile", f, "--window", "0"]);
    assert_png(&beside("run_profile_0.png"), profile::SIZE);

    ok(&["plot", "flux", f]);
    assert_png(&beside("run_flux.png"), flux::SIZE);
    let sel = beside("some.png");
    ok(&[
        "plot",
        "flux",
        f,
        "--windows",
        "0,2",
        "-o",
        sel.to_str().unwrap(),
    ]);
    assert_png(&sel, flux::SIZE);

    // velocities default to the free-surface layer, an x-z map
    ok(&["plot", "field", f, "--quantity", "w"]);
    assert_png(&beside("run_field_w_surface_1.png"), field::SIZE_ALONG_AXIS);
    for (q, plane, name, size) in [
        (
            "volume_fraction:big",
            None,
            "run_field_volume_fraction-big_z-3_1.png",
            field::SIZE_CROSS_SECTION,
        ),
        (
            "number_density:0",
            Some("y=-1"),
            "run_field_number_density-small_y-1.5_1.png",
            field::SIZE_ALONG_AXIS,
        ),
        (
            "axial_flux:1",
            Some("x=0.4"),
            "run_field_axial_flux-big_x0.5_1.png",
            field::SIZE_ALONG_AXIS,
        ),
        (
            "rms",
            Some("surface"),
            "run_field_rms_surface_1.png",
            field::SIZE_ALONG_AXIS,
        ),
        (
            "depth",
            None,
            "run_field_depth_columns_1.png",
            field::SIZE_ALONG_AXIS,
        ),
        (
            "ud",
            Some("z=-3"),
            "run_field_ud_z-3_1.png",
            field::SIZE_CROSS_SECTION,
        ),
    ] {
        let mut args = vec!["plot", "field", f, "--quantity", q];
        if let Some(p) = plane {
            args.extend(["--plane", p]);
        }
        ok(&args);
        assert_png(&beside(name), size);
    }
}

#[test]
fn field_colours_tell_the_signs_of_w_apart() {
    use tumbler::plot::field::SIZE_CROSS_SECTION;
    let ws = workspace("colours");
    let file = ws.dir.join("run.h5");
    write_run(&file, Omit::default());
    let png = ws.dir.join("w.png");
    ok(&[
        "plot",
        "field",
        file.to_str().unwrap(),
        "--quantity",
        "w",
        "--window",
        "0",
        "--plane",
        "z=3",
        "-o",
        png.to_str().unwrap(),
    ]);
    let (w, h, px) = read_png(&png);
    assert_eq!((w, h), SIZE_CROSS_SECTION);
    // x runs left to right over the main chart (the colour bar is on the far right); the
    // bed (y < 0) is the lower half. Count clearly red (w > 0) and blue (w < 0) pixels.
    let count = |x0: f64, x1: f64| {
        let (mut red, mut blue) = (0, 0);
        for y in (h / 2)..(h * 4 / 5) {
            for x in ((x0 * w as f64) as u32)..((x1 * w as f64) as u32) {
                let [r, _, b] = px[(y * w + x) as usize];
                if r as i32 - b as i32 > 60 {
                    red += 1;
                } else if b as i32 - r as i32 > 60 {
                    blue += 1;
                }
            }
        }
        (red, blue)
    };
    let (red_left, blue_left) = count(0.15, 0.42);
    let (red_right, blue_right) = count(0.47, 0.75);
    assert!(
        red_left > 1000 && blue_left == 0,
        "x < 0: {red_left} red, {blue_left} blue"
    );
    assert!(
        blue_right > 1000 && red_right == 0,
        "x > 0: {red_right} red, {blue_right} blue"
    );
}

#[test]
fn bad_input_exits_2_naming_the_culprit() {
    let ws = workspace("bad");
    let file = ws.dir.join("run.h5");
    write_run(
        &file,
        Omit {
            diffusivity: true,
            ..Omit::default()
        },
    );
    let f = file.to_str().unwrap();
    let missing = ws.dir.join("nowhere.h5");
    refused(
        &["info", missing.to_str().unwrap()],
        "nowhere.h5: no such file",
    );
    let junk = ws.dir.join("junk.h5");
    std::fs::write(&junk, "not hdf5").unwrap();
    refused(
        &["bands", junk.to_str().unwrap()],
        "not a readable HDF5 file",
    );
    refused(
        &["plot", "field", f, "--quantity", "speed"],
        "unknown quantity 'speed'",
    );
    refused(
        &["plot", "field", f, "--quantity", "volume_fraction:medium"],
        "unknown species 'medium'",
    );
    refused(
        &["plot", "field", f, "--quantity", "volume_fraction:5"],
        "species 5 is out of range",
    );
    refused(
        &["plot", "field", f, "--quantity", "w", "--window", "2"],
        "window 2 is out of range",
    );
    refused(
        &["plot", "field", f, "--quantity", "w", "--plane", "q=1"],
        "bad plane 'q=1'",
    );
    refused(
        &["plot", "field", f, "--quantity", "w", "--plane", "z=100"],
        "--plane z=100 is outside the field grid",
    );
    refused(
        &["plot", "profile", f, "--window", "7"],
        "window 7 is out of range",
    );
    refused(&["plot", "profile", f], "has no /slices/diffusivity");
    refused(&["plot", "flux", f, "--windows", "0,x"], "bad window 'x'");
    // a file with no windowed diagnostics at all
    let axial_only = ws.dir.join("axial.h5");
    // written without /fields rather than edited afterwards: reopening a file this process
    // just wrote can fail while a `tumbler` child spawned by another test meanwhile holds
    // the inherited descriptor, and with it HDF5's lock
    write_run(
        &axial_only,
        Omit {
            fields: true,
            ..Omit::default()
        },
    );
    refused(
        &[
            "plot",
            "field",
            axial_only.to_str().unwrap(),
            "--quantity",
            "w",
        ],
        "has no /fields/rotations_start: the run did not write it",
    );
    assert!(!ws.dir.join("run_profile_2.png").exists());
}
