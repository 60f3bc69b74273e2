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
