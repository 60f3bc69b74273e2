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
