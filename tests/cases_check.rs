//! Every case in `cases/` is accepted by `tumbler check`, and each says in a comment which
//! seed result it reproduces.

mod common;

#[test]
fn every_case_is_accepted_and_documented() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        n += 1;
        let o = common::tumbler(&["check", path.to_str().unwrap(), "--ranks", "2"]);
        assert!(
            o.status.success(),
            "{}: {}",
            path.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.starts_with('#'),
            "{} starts with no comment saying what it reproduces",
            path.display()
        );
    }
    assert!(n >= 17, "only {n} cases");
}

/// Without `diagnostics.fields.grid`, every bin of the binned fields (and of the per-slice
/// flux maps, which share its `x, y` bins) is at least one largest diameter wide, and as fine
/// as that allows up to 40 x 40 x 16; a grid the case gives is kept as given.
#[test]
fn default_field_bins_are_no_narrower_than_the_largest_particle() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let quick = tumbler::case::load_case(&dir.join("quickstart.toml"), &[])
        .unwrap()
        .case;
    // 16 wide and 64 long with diameters up to 1.3: 12 bins across, 16 along
    assert_eq!(quick.field_grid(), [12, 12, 16]);
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let case = tumbler::case::load_case(&path, &[]).unwrap().case;
        let n = case.field_grid();
        if let Some(given) = case.diagnostics.fields.grid {
            assert_eq!(n, given, "{}", path.display());
            continue;
        }
        let extent = [
            case.drum.diameter,
            case.drum.diameter,
            case.drum.axial_length(),
        ];
        for k in 0..3 {
            let width = extent[k] / n[k] as f64;
            assert!(
                width >= case.d_max(),
                "{}: bins {width} wide along axis {k}, particles up to {}",
                path.display(),
                case.d_max()
            );
            let finer = extent[k] / (n[k] + 1) as f64;
            assert!(
                n[k] == [40, 40, 16][k] || finer < case.d_max(),
                "{}: {} bins along axis {k} where {} would fit",
                path.display(),
                n[k],
                n[k] + 1
            );
        }
    }
    let set = |s: &str| {
        tumbler::case::load_case(&dir.join("quickstart.toml"), &[s.to_string()])
            .unwrap()
            .case
    };
    assert_eq!(
        set("diagnostics.fields.grid=[3, 4, 5]").field_grid(),
        [3, 4, 5]
    );
    // a drum 46 diameters wide is capped at 40 bins across
    assert_eq!(set("drum.diameter=60.0").field_grid()[..2], [40, 40]);
}
