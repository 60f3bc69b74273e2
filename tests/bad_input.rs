//! Bad case files and command lines are refused with a message that names the key (or the
//! line) and says why, a non-zero exit, and no output file.

mod common;

use common::{case_path, mpirun, tmpdir, tumbler};
use tumbler::case::{apply_overrides, parse_case};

fn base() -> String {
    std::fs::read_to_string(case_path("periodic.toml")).unwrap()
}

/// Parse the base case with `edit` applied to its text; return the refusal messages.
fn refusal(edit: impl Fn(String) -> String) -> String {
    match parse_case(&edit(base()), "bad.toml") {
        Ok(_) => panic!("the case was accepted"),
        Err(errs) => errs
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    }
}

fn with(key_value: &str) -> String {
    refusal(|t| apply_overrides(&t, &[key_value.to_string()], "bad.toml").unwrap())
}

fn expect(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "message {msg:?} lacks {p:?}");
    }
}

#[test]
fn the_base_case_is_accepted() {
    parse_case(&base(), "ok.toml").unwrap();
}

#[test]
fn malformed_toml_names_the_line() {
    let m = refusal(|t| t.replace("diameter = 10.0", "diameter = = 10.0"));
    expect(&m, &["bad.toml line 7"]);
}

#[test]
fn misspelled_key_is_named() {
    let m = refusal(|t| t.replace("diameter = 10.0", "diamter = 10.0"));
    expect(&m, &["unknown field `diamter`", "line 7"]);
}

#[test]
fn missing_key_is_named() {
    let m = refusal(|t| t.replace("length = 24.0\n", ""));
    expect(&m, &["drum.length", "required for a cylinder"]);
    let m = refusal(|t| t.replace("seed = 7\n", ""));
    expect(&m, &["missing field `seed`"]);
}

#[test]
fn wrong_type_is_named() {
    let m = with("drum.diameter=\"wide\"");
    expect(&m, &["invalid type", "line"]);
}

#[test]
fn unknown_choice_is_refused() {
    let m = with("drum.ends=\"open\"");
    expect(&m, &["unknown variant `open`", "periodic", "capped"]);
}

#[test]
fn negative_diameter_is_refused() {
    let m = with("species.0.diameter=-1.0");
    expect(&m, &["species.0.diameter", "positive"]);
}

#[test]
fn particle_larger_than_the_drum_is_refused() {
    let m = with("species.1.diameter=12.0");
    expect(&m, &["species.1.diameter", "does not fit in a drum"]);
}

#[test]
fn spread_as_large_as_the_diameter_is_refused() {
    let m = with("species.0.diameter_spread=1.0");
    expect(&m, &["species.0.diameter_spread"]);
}

#[test]
fn time_step_too_large_for_the_stiffness_is_refused() {
    let m = with("run.dt=0.05");
    expect(&m, &["run.dt", "too large for the contact stiffness"]);
}

#[test]
fn zero_and_negative_values_are_refused() {
    expect(&with("drum.omega=0.0"), &["drum.omega", "non-zero"]);
    expect(&with("run.rotations=-3.0"), &["run.rotations", "positive"]);
    expect(&with("drum.length=0.0"), &["drum.length"]);
    expect(&with("init.density=-0.3"), &["init.density"]);
    expect(&with("run.skin=0.0"), &["run.skin"]);
    expect(&with("model.gamma_n=-5.0"), &["model.gamma_n"]);
}

#[test]
fn overlapping_lattice_is_refused() {
    let m = with("init.density=1.5");
    expect(&m, &["init.density", "overlap"]);
}

#[test]
fn duplicate_species_names_are_refused() {
    let m = with("species.1.name=\"small\"");
    expect(&m, &["species.1.name", "names two species"]);
}

#[test]
fn slices_longer_than_the_drum_are_refused() {
    let m = with("output.slice_width=100.0");
    expect(&m, &["output.slice_width"]);
}

#[test]
fn segregated_start_needs_two_bands() {
    let m = refusal(|t| {
        apply_overrides(
            &t,
            &[
                "init.arrangement=\"segregated\"".into(),
                "init.bands=1".into(),
            ],
            "bad.toml",
        )
        .unwrap()
    });
    expect(&m, &["init.bands"]);
}

#[test]
fn periodic_drum_shorter_than_the_interaction_range_is_refused() {
    let m = with("drum.length=2.0");
    expect(&m, &["drum.length", "periodic"]);
}

#[test]
fn every_bad_value_is_reported_at_once() {
    let m = refusal(|t| {
        apply_overrides(
            &t,
            &["drum.omega=0.0".into(), "run.skin=-1.0".into()],
            "bad.toml",
        )
        .unwrap()
    });
    expect(&m, &["drum.omega", "run.skin"]);
}

#[test]
fn bad_overrides_are_refused() {
    let text = base();
    let e = apply_overrides(&text, &["run.rotations".into()], "x").unwrap_err();
    expect(&e.to_string(), &["--set run.rotations", "key=value"]);
    let e = apply_overrides(&text, &["species.5.gamma_s=1".into()], "x").unwrap_err();
    expect(&e.to_string(), &["species.5.gamma_s", "out of range"]);
    let e = apply_overrides(&text, &["drum.ends.x=1".into()], "x").unwrap_err();
    expect(&e.to_string(), &["drum.ends.x", "not a table"]);
}

#[test]
fn overrides_reach_every_key() {
    let text = apply_overrides(
        &base(),
        &[
            "run.rotations=3".into(),
            "species.1.gamma_s=4.5".into(),
            "drum.ends=capped".into(),
        ],
        "x",
    )
    .unwrap();
    let c = parse_case(&text, "x").unwrap();
    assert_eq!(c.run.rotations, 3.0);
    assert_eq!(c.species[1].gamma_s, Some(4.5));
    assert_eq!(c.drum.ends, Some(tumbler::case::Ends::Capped));
}

#[test]
fn the_binary_refuses_bad_cases_and_writes_nothing() {
    let dir = tmpdir();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, base().replace("gamma_n = 5.0", "gamma_n = -5.0")).unwrap();
    let out = dir.path().join("out.h5");
    let o = tumbler(&["check", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["model.gamma_n", "zero or positive"],
    );
    let o = tumbler(&["run", bad.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    expect(&String::from_utf8_lossy(&o.stderr), &["model.gamma_n"]);
    let o = tumbler(&["run", dir.path().join("missing.toml").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["missing.toml", "cannot read"],
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        1,
        "only bad.toml is there"
    );
}

#[test]
fn more_ranks_than_slabs_is_refused_before_any_output() {
    let dir = tmpdir();
    let out = dir.path().join("out.h5");
    let case = case_path("periodic.toml");
    let c = parse_case(&base(), "x").unwrap();
    let reach = tumbler::physics::law::reach(&c);
    let fit = (c.drum.axial_length() / reach).floor() as usize;
    let ranks = fit + 1;
    let o = mpirun(
        ranks,
        &["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()],
    );
    assert!(!o.status.success());
    let (r, most) = (format!("{ranks} ranks"), format!("use at most {fit} ranks"));
    let stderr = String::from_utf8_lossy(&o.stderr);
    expect(&stderr, &[&r, "thinner than the interaction range", &most]);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn an_existing_output_is_not_overwritten_unless_asked() {
    let dir = tmpdir();
    let out = dir.path().join("out.h5");
    std::fs::write(&out, b"precious").unwrap();
    let case = case_path("periodic.toml");
    let args = [
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "run.rotations=0.01",
    ];
    let o = tumbler(&args);
    assert_eq!(o.status.code(), Some(1));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["exists", "--overwrite"],
    );
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
    let mut args = args.to_vec();
    args.push("--overwrite");
    assert!(tumbler(&args).status.success());
    assert!(hdf5::File::open(&out).is_ok());
}

#[test]
fn unreadable_or_foreign_particle_files_are_refused() {
    let dir = tmpdir();
    let text = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap();
    let bare = text
        .replace("kind = \"pour\"", "kind = \"particles\"")
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "");
    // not HDF5 at all, and HDF5 without /particles
    let junk = dir.path().join("junk.h5");
    std::fs::write(&junk, b"not an hdf5 file").unwrap();
    let foreign = dir.path().join("foreign.h5");
    hdf5::File::create(&foreign)
        .unwrap()
        .create_group("other")
        .unwrap();
    for file in [&junk, &foreign, &dir.path().join("missing.h5")] {
        let case = dir.path().join("c.toml");
        let with_file = bare.replace(
            "kind = \"particles\"",
            &format!("kind = \"particles\"\nfile = \"{}\"", file.display()),
        );
        std::fs::write(&case, with_file).unwrap();
        let out = dir.path().join("o.h5");
        let o = tumbler(&["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1));
        expect(
            &String::from_utf8_lossy(&o.stderr),
            &["init.file", "cannot read particles from"],
        );
        assert!(!out.exists());
    }
}

#[test]
fn an_output_path_that_cannot_be_written_is_refused() {
    let dir = tmpdir();
    let case = case_path("periodic.toml");
    let out = dir.path().join("no/such/dir/out.h5");
    let o = tumbler(&["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["cannot open output file", "no/such/dir/out.h5"],
    );
}

#[test]
fn fill_outside_zero_one_and_keys_of_another_model_are_refused() {
    let m = refusal(|t| {
        apply_overrides(
            &t,
            &["init.kind=pour".into(), "init.fill=1.2".into()],
            "bad.toml",
        )
        .unwrap()
    });
    expect(&m, &["init.fill", "must be in (0, 1)"]);
    expect(
        &with("model.restitution=0.9"),
        &["model.restitution", "does not apply to the rapaport family"],
    );
    expect(
        &with("run.max_overlap=1.5"),
        &["run.max_overlap", "must be in (0, 1)"],
    );
}

#[test]
fn impossible_diagnostics_settings_are_refused() {
    let m = with("diagnostics.fields.grid=[0, 40, 16]");
    expect(
        &m,
        &[
            "diagnostics.fields.grid",
            "entry 0 must be between 1 and 1000 bins",
        ],
    );
    let m = with("diagnostics.window=0.001");
    expect(
        &m,
        &["diagnostics.window", "at least diagnostics.sample_every"],
    );
    let m = with("diagnostics.bands.threshold=1.5");
    expect(&m, &["diagnostics.bands.threshold", "(0, 1)"]);
    let m = with("diagnostics.surface_angle=95.0");
    expect(&m, &["diagnostics.surface_angle", "between -90 and 90"]);
    let m = with("diagnostics.paths.regions=[{ min = [0.0, 0.0, 0.0], max = [1.0, -1.0, 1.0] }]");
    expect(
        &m,
        &["diagnostics.paths.regions[0]", "min must be below max"],
    );
    let m = with("diagnostics.snapshots.every=0.0");
    expect(&m, &["diagnostics.snapshots.every", "must be positive"]);
}

/// The refusals of `key_value` on the test case `file`.
fn with_on(file: &str, overrides: &[&str]) -> String {
    let text = std::fs::read_to_string(case_path(file)).unwrap();
    let ov: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match tumbler::case::load_text(&text, &ov, file) {
        Ok(_) => panic!("{overrides:?} on {file} was accepted"),
        Err(errs) => errs
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    }
}

#[test]
fn non_finite_values_are_refused_naming_the_key() {
    let m = with("model.gamma_n=nan");
    expect(&m, &["model.gamma_n: must be a finite number, got nan"]);
    let m = with("species.1.gamma_s=nan");
    expect(&m, &["species.1.gamma_s: must be a finite number, got nan"]);
    let m = with("init.density=inf");
    expect(&m, &["init.density: must be a finite number, got inf"]);
    // once, not again as "must be positive"
    assert_eq!(m.lines().count(), 1, "{m}");
    for key in ["model.restitution", "model.collision_time", "init.fill"] {
        let m = with_on("sd_capped.toml", &[&format!("{key}=nan")]);
        expect(&m, &[&format!("{key}: must be a finite number, got nan")]);
    }
    // in a key the model does not use, and in an array
    let m = with("init.fill=-inf");
    expect(&m, &["init.fill: must be a finite number, got -inf"]);
    let m = with("diagnostics.paths.regions=[{ min = [nan, 0.0, 0.0], max = [1.0, 1.0, 1.0] }]");
    expect(
        &m,
        &["diagnostics.paths.regions.0.min: entry 0 must be a finite number, got nan"],
    );
    // several at once
    let m = with_on(
        "sd_capped.toml",
        &["model.restitution=nan", "init.fill=nan", "drum.omega=inf"],
    );
    expect(&m, &["model.restitution", "init.fill", "drum.omega"]);
}

#[test]
fn too_few_steps_per_rotation_are_refused() {
    for omega in ["1000.0", "1e300", "-1000.0"] {
        let m = with(&format!("drum.omega={omega}"));
        expect(
            &m,
            &[
                "drum.omega",
                "time steps of dt = 0.005",
                "at least 20 steps per rotation are needed",
                "|omega| must be at most 62.83",
            ],
        );
    }
}

#[test]
fn a_step_count_that_does_not_fit_is_refused() {
    let m = with_on("periodic.toml", &["run.dt=1e-300", "run.rotations=1e30"]);
    expect(
        &m,
        &[
            "run.rotations: 1e30 rotations of",
            "time steps; at most 1e12 are accepted",
        ],
    );
    let m = with("run.rotations=1e12");
    expect(
        &m,
        &["run.rotations", "2.513e15 time steps", "at most 1e12"],
    );
}

/// `initial_memory`'s refusal of `file` with `overrides` on `ranks` ranks, if any (the case
/// itself accepted).
fn memory_refusal(file: &str, overrides: &[&str], ranks: usize) -> Option<String> {
    let text = std::fs::read_to_string(case_path(file)).unwrap();
    let ov: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let lc = tumbler::case::load_text(&text, &ov, file).unwrap();
    tumbler::case::initial_memory(&lc.case, ranks)
        .err()
        .map(|e| e.to_string())
}

#[test]
fn a_huge_initial_state_is_refused_before_it_is_built() {
    // 1.4e8 lattice sites: 104 GiB on one rank (report::memory_estimate, its pairs those of
    // the bed the lattice settles into, and the list build's cells), refused at once by
    // check and run on one rank, nothing allocated; the case itself is fine, for 8 ranks or
    // more
    let long = ["drum.length=1e7", "output.slice_width=100"];
    let m = memory_refusal("periodic.toml", &long, 1).expect("refused on 1 rank");
    expect(
        &m,
        &[
            "init.density: the initial state would hold about 1.361e8 particles, 104 GiB on each of 1 ranks",
            "at most 16 GiB",
            "run it on at least 8 ranks",
        ],
    );
    assert!(memory_refusal("periodic.toml", &long, 7).is_some());
    assert_eq!(memory_refusal("periodic.toml", &long, 8), None);
    let m = memory_refusal("sphere.toml", &["drum.diameter=3.0"], 1).expect("refused on 1 rank");
    expect(&m, &["init.fill: the initial state would hold", "GiB"]);
    // a state that no rank count can hold is refused with the case itself
    let m = with_on("rough.toml", &["drum.rough_wall.diameter=1e-7"]);
    expect(&m, &["the initial state would hold", "no rank count fits"]);
    let dir = tmpdir();
    let case = case_path("periodic.toml");
    let out = dir.path().join("o.h5");
    let t = std::time::Instant::now();
    for args in [
        vec![
            "check",
            case.to_str().unwrap(),
            "--set",
            "drum.length=1e7",
            "--set",
            "output.slice_width=100",
        ],
        vec![
            "run",
            case.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--set",
            "drum.length=1e7",
            "--set",
            "output.slice_width=100",
        ],
    ] {
        let o = tumbler(&args);
        assert_eq!(o.status.code(), Some(2));
        expect(
            &String::from_utf8_lossy(&o.stderr),
            &["init.density: the initial state would hold", "particles"],
        );
    }
    assert!(t.elapsed().as_secs_f64() < 10.0, "{:?}", t.elapsed());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn a_sparse_bed_in_a_wide_drum_is_refused_before_its_cells_are_made() {
    // a few hundred particles spread over a drum 1e5 diameters across: the list build's
    // cells over their bounding box would take hundreds of GiB (the run would abort on the
    // allocation); refused with the case, by check and by run, nothing written
    let wide = [
        "drum.diameter=1e5",
        "init.density=1e-9",
        "model.gravity=1e-6",
    ];
    let m = with_on("periodic.toml", &wide);
    expect(
        &m,
        &[
            "drum.diameter: a drum 100000 across is",
            "neighbour cells across",
            "at most 16 GiB per rank is accepted: make the drum smaller or the particles larger",
        ],
    );
    // wide enough for one rank's cells only: more ranks are the remedy
    let m = memory_refusal(
        "periodic.toml",
        &[
            "drum.diameter=1e4",
            "init.density=1e-7",
            "model.gravity=1e-5",
        ],
        1,
    )
    .expect("refused on 1 rank");
    expect(
        &m,
        &["drum.diameter: a drum 10000 across", "run it on more ranks"],
    );
    let dir = tmpdir();
    let case = case_path("periodic.toml");
    let out = dir.path().join("o.h5");
    let mut args = vec!["run", case.to_str().unwrap(), "-o", out.to_str().unwrap()];
    for w in &wide {
        args.extend(["--set", w]);
    }
    let o = tumbler(&args);
    assert_eq!(o.status.code(), Some(2));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["drum.diameter: a drum"],
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn too_many_records_or_slices_are_refused() {
    let m = with("output.sample_every=1e-9");
    expect(
        &m,
        &[
            "output.sample_every: every 1e-9 rotations over 2 rotations is 2.000e9 records",
            "at most 1e7",
        ],
    );
    let m = with("diagnostics.snapshots.every=1e-9");
    expect(&m, &["diagnostics.snapshots.every", "records"]);
    let m = with("output.slice_width=1e-300");
    expect(
        &m,
        &["output.slice_width: 1e-300 cuts the drum (length 24) into 2.400e301 axial slices; at most 1e6"],
    );
}

#[test]
fn a_fall_or_a_start_too_fast_for_the_step_is_refused() {
    let m = with("model.gravity=1e300");
    expect(
        &m,
        &[
            "model.gravity: 1e300: a particle falling across the drum moves",
            "more than half the smallest diameter",
        ],
    );
    let m = with("init.speed=1e6");
    expect(
        &m,
        &[
            "init.speed: 1000000: a particle moves 5000.00 in a step of 0.005",
            "more than the drum's radius 5",
        ],
    );
}

#[test]
fn more_bands_than_fit_are_refused() {
    let m = with_on(
        "periodic.toml",
        &[
            "init.arrangement=\"segregated\"",
            "init.bands=1000000000000",
        ],
    );
    expect(
        &m,
        &["init.bands: 1000000000000 bands of a drum 24 long are thinner than the largest diameter", "at most 18 fit"],
    );
}

#[test]
fn check_refuses_ranks_that_do_not_fit_and_zero_ranks() {
    let case = case_path("periodic.toml");
    let c = parse_case(&base(), "x").unwrap();
    let fit = (c.drum.axial_length() / tumbler::physics::law::reach(&c)).floor() as usize;
    let o = tumbler(&["check", case.to_str().unwrap(), "--ranks", &fit.to_string()]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = tumbler(&[
        "check",
        case.to_str().unwrap(),
        "--ranks",
        &(fit + 1).to_string(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let most = format!("use at most {fit} ranks");
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["--ranks", "thinner than the interaction range", &most],
    );
    let o = tumbler(&["check", case.to_str().unwrap(), "--ranks", "0"]);
    assert_eq!(o.status.code(), Some(2));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["--ranks: at least 1 rank is needed, got 0"],
    );
}

#[test]
fn a_bad_set_value_is_named_as_the_set() {
    let case = case_path("periodic.toml");
    let check = |set: &str| {
        let o = tumbler(&["check", case.to_str().unwrap(), "--set", set]);
        assert_eq!(o.status.code(), Some(2), "{set}");
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let m = check("drum.omega=nan");
    expect(&m, &["--set drum.omega: must be a finite number, got nan"]);
    let m = check("drum.diameter=\"wide\"");
    expect(
        &m,
        &["--set drum.diameter: invalid type: string \"wide\", expected f64"],
    );
    assert!(!m.contains("line"), "{m}");
    let m = check("species.0.diameter=-1.0");
    expect(&m, &["--set species.0.diameter: must be a positive length"]);
    // an error of the file itself keeps its line in the file
    let dir = tmpdir();
    let bad = dir.path().join("bad.toml");
    std::fs::write(
        &bad,
        base().replace("diameter = 10.0", "diameter = \"wide\""),
    )
    .unwrap();
    let o = tumbler(&["check", bad.to_str().unwrap(), "--set", "run.rotations=3"]);
    assert_eq!(o.status.code(), Some(2));
    expect(
        &String::from_utf8_lossy(&o.stderr),
        &["bad.toml line 7", "invalid type"],
    );
}

/// A particle file (`/particles` as a run writes it) holding `n` particles.
fn particle_file(path: &std::path::Path, d: &[f64], x: &[[f64; 3]], v: &[[f64; 3]]) {
    // written beside `path` and copied to it: HDF5 opens its files without close-on-exec, so
    // a `tumbler` another test thread starts while this one is open inherits the descriptor
    // and HDF5's lock on the file with it for as long as it runs ("unable to lock file,
    // errno = 11" when the test then reads it); the copy is a new file nobody holds
    let written = path.with_extension("written.h5");
    let f = hdf5::File::create(&written).unwrap();
    let g = f.create_group("particles").unwrap();
    let n = d.len();
    let flat = |a: &[[f64; 3]]| a.iter().flatten().copied().collect::<Vec<f64>>();
    let id: Vec<u64> = (0..n as u64).collect();
    g.new_dataset_builder().with_data(&id).create("id").unwrap();
    g.new_dataset_builder()
        .with_data(&vec![0u8; n])
        .create("species")
        .unwrap();
    g.new_dataset_builder()
        .with_data(d)
        .create("diameter")
        .unwrap();
    g.new_dataset_builder()
        .with_data(&flat(x))
        .create("position")
        .unwrap();
    g.new_dataset_builder()
        .with_data(&flat(v))
        .create("velocity")
        .unwrap();
    g.new_dataset_builder()
        .with_data(&vec![0.0; 3 * n])
        .create("angular_velocity")
        .unwrap();
    // closed here, every handle with it, before the test opens the file again (HDF5 locks
    // a file while it is open)
    drop(g);
    f.close().unwrap();
    std::fs::copy(&written, path).unwrap();
    std::fs::remove_file(&written).unwrap();
}

/// A particle file's name, diameters, positions, velocities and the refusal it gets.
type BadFile = (
    &'static str,
    [f64; 2],
    [[f64; 3]; 2],
    [[f64; 3]; 2],
    &'static str,
);

#[test]
fn unusable_particles_in_a_file_are_refused_naming_them() {
    let dir = tmpdir();
    let ok = [0.0, -0.005, 0.0];
    let x = [[0.0, 0.0, 0.0], ok];
    let still = [[0.0; 3]; 2];
    let cases: [BadFile; 5] = [
        (
            "inf_v",
            [0.002, 0.002],
            x,
            [[0.0; 3], [f64::INFINITY, 0.0, 0.0]],
            "init: particle 1 has velocity (inf, 0, 0): every component must be a finite number",
        ),
        (
            "nan_x",
            [0.002, 0.002],
            [[f64::NAN, 0.0, 0.0], ok],
            still,
            "init: particle 0 has position (NaN, 0, 0): every component must be a finite number",
        ),
        (
            "zero_d",
            [0.0, 0.002],
            x,
            still,
            "init: particle 0 has diameter 0: it must be a positive length",
        ),
        (
            "negative_d",
            [0.002, -0.002],
            x,
            still,
            "init: particle 1 has diameter -0.002: it must be a positive length",
        ),
        (
            "both",
            [-1.0, f64::NAN],
            x,
            still,
            "init: particle 0 has diameter -1: it must be a positive length (2 particles of init.file",
        ),
    ];
    let text = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap();
    for (name, d, x, v, msg) in cases {
        let file = dir.path().join(format!("{name}.h5"));
        particle_file(&file, &d, &x, &v);
        let with_file = text
            .replace(
                "kind = \"pour\"",
                &format!("kind = \"particles\"\nfile = \"{}\"", file.display()),
            )
            .replace("fill = 0.3\n", "")
            .replace("settle_time = 0.2\n", "");
        let case = parse_case(&with_file, name).unwrap();
        let e = tumbler::init::initial_particles(&case, &tumbler::init::Share::everything())
            .unwrap_err();
        expect(&e, &[msg]);
        // `tumbler check` refuses it too (exit 2), naming the particle
        let path = dir.path().join(format!("{name}.toml"));
        std::fs::write(&path, &with_file).unwrap();
        let o = tumbler(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{name}");
        expect(&String::from_utf8_lossy(&o.stderr), &[msg]);
    }
}

#[test]
fn unusable_particle_tables_are_refused_naming_them() {
    let text = std::fs::read_to_string(case_path("sd_capped.toml"))
        .unwrap()
        .replace("kind = \"pour\"", "kind = \"particles\"")
        .replace("fill = 0.3\n", "")
        .replace("settle_time = 0.2\n", "");
    let table = |d: &str, v: &str| {
        format!("{text}\n[[init.particle]]\nspecies = 0\ndiameter = {d}\nposition = [0.0, 0.0, 0.0]\nvelocity = {v}\n")
    };
    let refused = |t: String| {
        parse_case(&t, "t")
            .unwrap_err()
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    };
    expect(
        &refused(table("0.002", "[inf, 0.0, 0.0]")),
        &["init.particle.0.velocity: entry 0 must be a finite number, got inf"],
    );
    expect(
        &refused(table("0.0", "[0.0, 0.0, 0.0]")),
        &["init.particle.0.diameter: must be positive, got 0"],
    );
}

#[test]
fn inconsistent_species_and_particle_sources_are_refused() {
    let m = with_on("sd_capped.toml", &["species.0.volume_fraction=0.7"]);
    expect(
        &m,
        &["species.N.volume_fraction", "adding up to 1 (got 1.2"],
    );
    let m = with("species.0.diameter_sd=0.1");
    expect(&m, &["species.0.diameter_sd: choose either diameter_sd (normal) or diameter_spread (uniform)"]);
    let m = with_on("sd_capped.toml", &["init.kind=\"particles\""]);
    expect(
        &m,
        &["init.file: give either init.file or [[init.particle]] tables, not both or neither"],
    );
}

/// `sd_capped.toml` (linear spring-dashpot, species `small` and `large`) with `pairs` added
/// as TOML text and `overrides` applied; the refusal messages.
fn pairs_refusal(pairs: &str, overrides: &[&str]) -> String {
    let text = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap() + pairs;
    let ov: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    match tumbler::case::load_text(&text, &ov, "bad.toml") {
        Ok(_) => panic!("{pairs} with {overrides:?} was accepted"),
        Err(errs) => errs
            .iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("\n"),
    }
}

#[test]
fn pair_overrides_and_per_species_normal_coefficients_are_accepted() {
    let text = std::fs::read_to_string(case_path("sd_capped.toml")).unwrap()
        + "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu = 0.3\nrestitution = 0.7\n\n\
           [[pairs]]\nspecies = [\"large\", \"large\"]\nrestitution = 0.95\n";
    let ov = vec![
        "species.0.restitution=0.8".to_string(),
        "species.1.restitution_wall=0.6".to_string(),
    ];
    let case = tumbler::case::load_text(&text, &ov, "ok.toml")
        .unwrap()
        .case;
    assert_eq!(case.pairs.len(), 2);
}

#[test]
fn pair_naming_an_unknown_species_is_refused() {
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"huge\"]\nmu = 0.3\n",
        &[],
    );
    expect(
        &m,
        &[
            "pairs.0.species",
            "`huge` is not the name of a species",
            "small, large",
        ],
    );
    let m = pairs_refusal("[[pairs]]\nspecies = [\"small\"]\nmu = 0.3\n", &[]);
    expect(&m, &["pairs.0.species", "must name two species", "got 1"]);
}

#[test]
fn pair_given_twice_is_refused() {
    // an unordered pair: large / small is small / large
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu = 0.3\n\n\
         [[pairs]]\nspecies = [\"large\", \"small\"]\nrestitution = 0.5\n",
        &[],
    );
    expect(&m, &["pairs.1.species", "is given twice", "also pairs.0"]);
}

#[test]
fn pair_values_out_of_range_are_refused() {
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu = -0.1\nrestitution = 1.5\n",
        &[],
    );
    expect(
        &m,
        &[
            "pairs.0.mu",
            "zero or positive",
            "pairs.0.restitution",
            "(0, 1]",
        ],
    );
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nrestitution = 0.0\n",
        &[],
    );
    expect(&m, &["pairs.0.restitution", "must be in (0, 1], got 0"]);
    let m = pairs_refusal("[[pairs]]\nspecies = [\"small\", \"large\"]\n", &[]);
    expect(&m, &["pairs.0", "gives no coefficient"]);
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu = nan\n",
        &[],
    );
    expect(&m, &["pairs.0.mu", "finite"]);
}

#[test]
fn pair_keys_of_another_model_are_refused() {
    // a restitution with the Hertz law, sub-model coefficients without the sub-model
    let hertz = [
        "model.normal=\"hertz\"",
        "model.youngs_modulus=1e7",
        "model.poisson_ratio=0.3",
        "model.hertz_damping=0.0",
        "run.dt=2e-6",
    ];
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nrestitution = 0.5\n",
        &hertz,
    );
    expect(
        &m,
        &[
            "pairs.0.restitution",
            "does not apply to the Hertz normal force",
        ],
    );
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu_roll = 0.1\ncohesion_energy = 100.0\n",
        &[],
    );
    expect(
        &m,
        &[
            "pairs.0.mu_roll",
            "has no effect without model.rolling",
            "pairs.0.cohesion_energy",
            "has no effect without model.cohesion",
        ],
    );
    let m = pairs_refusal(
        "[[pairs]]\nspecies = [\"small\", \"large\"]\nmu = 0.3\ngamma_s = 1.0\n",
        &[],
    );
    expect(&m, &["unknown field `gamma_s`"]);
    // the rapaport family: a pair's restitution does not apply
    let text = base() + "[[pairs]]\nspecies = [\"small\", \"big\"]\nrestitution = 0.5\n";
    let m = refusal(|_| text.clone());
    expect(
        &m,
        &[
            "pairs.0.restitution",
            "does not apply to the rapaport family",
        ],
    );
}

#[test]
fn per_species_normal_coefficients_out_of_range_or_of_another_model_are_refused() {
    let m = with_on(
        "sd_capped.toml",
        &[
            "species.0.restitution=0.0",
            "species.1.restitution_wall=1.2",
        ],
    );
    expect(
        &m,
        &[
            "species.0.restitution",
            "(0, 1]",
            "species.1.restitution_wall",
            "got 1.2",
        ],
    );
    // Young's modulus and Poisson ratio are Hertz's
    let m = with_on("sd_capped.toml", &["species.0.youngs_modulus=1e7"]);
    expect(
        &m,
        &[
            "species.0.youngs_modulus",
            "only with model.normal = \"hertz\"",
        ],
    );
    let hertz = [
        "model.normal=\"hertz\"",
        "model.youngs_modulus=1e7",
        "model.poisson_ratio=0.3",
        "model.hertz_damping=0.0",
        "run.dt=2e-6",
    ];
    let mut ov = hertz.to_vec();
    ov.extend([
        "species.0.youngs_modulus=-1.0",
        "species.1.poisson_ratio=0.5",
        "species.0.restitution=0.5",
    ]);
    let m = with_on("sd_capped.toml", &ov);
    expect(
        &m,
        &[
            "species.0.youngs_modulus",
            "positive",
            "species.1.poisson_ratio",
            "(-1, 0.5)",
            "species.0.restitution",
            "does not apply to the Hertz normal force",
        ],
    );
    let m = with("species.0.restitution=0.5");
    expect(
        &m,
        &[
            "species.0.restitution",
            "does not apply to the rapaport family",
        ],
    );
}
