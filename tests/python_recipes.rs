//! The Python recipes of docs/python.md, each run with python3 (h5py, xarray, h5netcdf,
//! matplotlib) on a real output made here, and their printed numbers checked against the
//! file. Skipped, with a message, where python3 or those modules are missing (CI installs
//! them: .ci/run).

mod common;

use std::path::Path;
use std::process::Command;

/// A python3 that imports everything the recipes use: `python3` on the PATH, else Debian's.
fn python() -> Option<String> {
    ["python3", "/usr/bin/python3"].into_iter().find_map(|p| {
        Command::new(p)
            .args(["-c", "import h5py, xarray, h5netcdf, matplotlib, numpy"])
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|_| p.to_string())
    })
}

/// The recipes of the guide: `(name, code)` of every ```python block, named by its first
/// line `# recipe: NAME`.
fn recipes() -> Vec<(String, String)> {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/python.md"))
        .unwrap();
    let mut out = Vec::new();
    let mut rest = doc.as_str();
    while let Some(i) = rest.find("```python\n") {
        let body = &rest[i + "```python\n".len()..];
        let end = body
            .find("```")
            .expect("an unclosed python block in docs/python.md");
        let code = &body[..end];
        let name = code
            .lines()
            .next()
            .and_then(|l| l.strip_prefix("# recipe: "))
            .expect("every python block of docs/python.md starts with `# recipe: NAME`");
        out.push((name.trim().to_string(), code.to_string()));
        rest = &body[end + 3..];
    }
    out
}

/// The numbers in `line`, in order.
fn numbers(line: &str) -> Vec<f64> {
    line.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|w| {
            w.trim_matches(|c| c == '.' || c == '-' || c == 'e')
                .parse()
                .ok()
        })
        .collect()
}

#[test]
fn every_recipe_of_the_python_guide_runs_on_a_real_output() {
    let recipes = recipes();
    let names: Vec<&str> = recipes.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["spacetime", "profile", "field"]);
    let Some(py) = python() else {
        eprintln!(
            "skipped: no python3 with h5py, xarray, h5netcdf and matplotlib (Debian: apt-get install python3-h5py python3-xarray python3-h5netcdf python3-matplotlib)"
        );
        return;
    };
    let dir = common::tmpdir();
    // the recipes read quickstart.h5 in the working directory
    let out = dir.path().join("quickstart.h5");
    common::run_case(2, "sd_capped.toml", &out, &["run.rotations=0.12"]);
    let f = hdf5::File::open(&out).unwrap();
    let shape = |n: &str| f.dataset(n).unwrap().shape();
    for (name, code) in &recipes {
        let r = Command::new(&py)
            .args(["-c", code])
            .current_dir(dir.path())
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&r.stdout).to_string();
        assert!(
            r.status.success(),
            "recipe {name} failed:\n{stdout}\n{}",
            String::from_utf8_lossy(&r.stderr)
        );
        let png = dir.path().join(format!("{name}.png"));
        let size = std::fs::metadata(&png).map(|m| m.len()).unwrap_or(0);
        assert!(size > 10_000, "recipe {name} wrote {size} bytes of {png:?}");
        let lines: Vec<&str> = stdout
            .lines()
            .filter(|l| l.starts_with(&format!("{name}:")))
            .collect();
        assert!(!lines.is_empty(), "recipe {name} printed:\n{stdout}");
        for l in &lines {
            assert!(
                numbers(l).iter().all(|x| x.is_finite()),
                "{name}: not a number in {l:?}"
            );
        }
        match name.as_str() {
            "spacetime" => {
                // samples x slices as in the file, fractions within [0, 1]
                let n = numbers(lines[0]);
                let vf = shape("axial/volume_fraction");
                assert_eq!(
                    (n[0] as usize, n[1] as usize),
                    (vf[0], vf[2]),
                    "{}",
                    lines[0]
                );
                assert!(0.0 <= n[2] && n[2] < n[3] && n[3] <= 1.0, "{}", lines[0]);
            }
            "profile" => {
                // one line per species; the species' shares of each slice add up to one
                assert_eq!(lines.len(), shape("species")[0]);
                let means: Vec<f64> = lines.iter().map(|l| numbers(l)[0]).collect();
                let sum: f64 = means.iter().sum();
                assert!(
                    (sum - 1.0).abs() < 2e-3,
                    "shares add up to {sum}: {lines:?}"
                );
                let per: u64 = f
                    .group("slices")
                    .unwrap()
                    .attr("samples_per_window")
                    .unwrap()
                    .read_scalar()
                    .unwrap();
                let samples = *numbers(lines[0]).last().unwrap();
                assert_eq!(samples as u64, per, "not a whole window: {}", lines[0]);
            }
            "field" => {
                // the axes h5py reports are the dimension scales
                assert!(
                    lines[0].contains(
                        "['/fields/rotations_end', '/fields/component', '/fields/x', '/fields/y', '/fields/z']"
                    ),
                    "{}",
                    lines[0]
                );
                let n = numbers(lines[1]);
                let bins = shape("fields/x")[0] * shape("fields/y")[0];
                assert_eq!(n[2] as usize, bins, "{}", lines[1]);
                assert!(n[1] > 0.0 && n[1] < bins as f64, "{}", lines[1]);
                assert!(n[3] < n[4], "{}", lines[1]);
            }
            other => panic!("no check for recipe {other}"),
        }
    }
}
