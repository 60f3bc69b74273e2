//! `tumbler plot` for a paper, on a real run whose last window is a stub: PNG, SVG and PDF
//! by `--format` or by `-o`'s extension, titles in words with units, the last complete
//! window by default, a readable subset of windows for `plot flux`, and a refusal instead of
//! an all-grey map for a quantity that is NaN everywhere.

mod common;

use common::{case_path, mpirun, tumbler};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// One run shared by the tests: 0.05 rotations with windows of 0.02, so the third window
/// is a stub of half a window; its directory lives as long as the test process.
fn run_file() -> &'static Path {
    static FILE: OnceLock<PathBuf> = OnceLock::new();
    FILE.get_or_init(|| {
        let dir = Box::leak(Box::new(common::tmpdir()));
        let out = dir.path().join("run.h5");
        let case = case_path("sd_periodic.toml");
        let o = mpirun(
            1,
            &[
                "run",
                case.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--set",
                "run.rotations=0.05",
                "--set",
                "diagnostics.fields.window=0.02",
            ],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    })
}

/// A scratch copy of the run file (for tests that draw beside it or change it).
fn copy(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = common::tmpdir();
    let f = dir.path().join(name);
    std::fs::copy(run_file(), &f).unwrap();
    (dir, f)
}

fn plot(args: &[&str]) -> std::process::Output {
    let mut a = vec!["plot"];
    a.extend_from_slice(args);
    tumbler(&a)
}

fn ok(args: &[&str]) -> String {
    let o = plot(args);
    assert!(
        o.status.success(),
        "plot {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn refused(args: &[&str], says: &[&str]) {
    let o = plot(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "plot {args:?}: {err}");
    for s in says {
        assert!(err.contains(s), "plot {args:?} does not say {s:?}: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn every_plot_writes_png_svg_and_pdf() {
    let (dir, f) = copy("run.h5");
    let f = f.to_str().unwrap();
    for (args, stem) in [
        (vec!["spacetime", f], "run_spacetime"),
        (vec!["profile", f], "run_profile_1"),
        (vec!["flux", f], "run_flux"),
        (
            vec!["field", f, "--quantity", "volume_fraction:large"],
            "run_field_volume_fraction-large_z-0.005_1",
        ),
    ] {
        for format in ["png", "svg", "pdf"] {
            let mut a = args.clone();
            a.extend(["--format", format]);
            let said = ok(&a);
            let path = dir.path().join(format!("{stem}.{format}"));
            assert!(said.contains(&path.display().to_string()), "{said}");
            let bytes = std::fs::read(&path).unwrap();
            let magic: &[u8] = match format {
                "png" => b"\x89PNG",
                "svg" => b"<svg",
                _ => b"%PDF",
            };
            assert!(bytes.starts_with(magic), "{}", path.display());
            assert!(
                bytes.len() > 2000,
                "{}: {} bytes",
                path.display(),
                bytes.len()
            );
        }
    }
    // by -o's extension; a --format that contradicts it is refused
    let pdf = dir.path().join("w.pdf");
    ok(&["field", f, "--quantity", "w", "-o", pdf.to_str().unwrap()]);
    assert!(std::fs::read(&pdf).unwrap().starts_with(b"%PDF"));
    let png = dir.path().join("w.png");
    let png = png.to_str().unwrap();
    refused(
        &["field", f, "--quantity", "w", "-o", png, "--format", "svg"],
        &["--format svg", "w.png"],
    );
    assert!(!Path::new(png).exists());
}

#[test]
fn titles_are_words_with_units() {
    let (dir, f) = copy("run.h5");
    let f = f.to_str().unwrap();
    ok(&["field", f, "--quantity", "ud", "--format", "svg"]);
    let svg = std::fs::read_to_string(dir.path().join("run_field_ud_surface_1.svg")).unwrap();
    assert!(svg.contains("streamwise velocity u, drum frame"), "{svg}");
    assert!(svg.contains("[m/s]"), "the colour bar has its units");
    assert!(
        svg.contains("x [m]") && svg.contains("z [m]"),
        "axes have units"
    );
    ok(&["profile", f, "--format", "svg"]);
    let svg = std::fs::read_to_string(dir.path().join("run_profile_1.svg")).unwrap();
    for title in [
        "concentration &lt;C_s&gt; [-]",
        "axial flow rate Q [",
        "diffusivity K [",
    ] {
        assert!(svg.contains(title), "no axis title {title}");
    }
}

#[test]
fn default_windows_are_complete_and_flux_draws_a_readable_few() {
    let (dir, f) = copy("run.h5");
    let f = f.to_str().unwrap();
    let h5 = hdf5::File::open(f).unwrap();
    let ends: Vec<f64> = h5
        .dataset("slices/rotations_end")
        .unwrap()
        .read_raw()
        .unwrap();
    drop(h5);
    assert_eq!(ends.len(), 3, "two whole windows and a stub: {ends:?}");
    // profile and field default to window 1, not the stub 2
    assert!(ok(&["profile", f]).contains("run_profile_1.png"));
    assert!(ok(&["field", f, "--quantity", "w"]).contains("_1.png"));
    // the stub is still there when asked for
    assert!(ok(&["profile", f, "--window", "2"]).contains("run_profile_2.png"));
    // flux: the complete windows only, each named in the legend
    ok(&["flux", f, "--format", "svg"]);
    let svg = std::fs::read_to_string(dir.path().join("run_flux.svg")).unwrap();
    assert!(svg.contains("window 0:") && svg.contains("window 1:"));
    assert!(!svg.contains("window 2:"), "the stub is left out");
}

#[test]
fn a_quantity_that_is_nan_everywhere_is_refused() {
    let (dir, f) = copy("run.h5");
    {
        let h5 = hdf5::File::open_rw(&f).unwrap();
        let ds = h5.dataset("fields/depth").unwrap();
        let n: usize = ds.shape().iter().product();
        ds.write_raw(&vec![f64::NAN; n]).unwrap();
    }
    let f = f.to_str().unwrap();
    refused(
        &["field", f, "--quantity", "depth"],
        &["--quantity depth", "NaN", "flowing-layer boundary"],
    );
    assert!(!dir.path().join("run_field_depth_columns_1.png").exists());
}

#[test]
fn densities_from_bins_narrower_than_a_particle_come_with_a_warning() {
    // the test case's 12 x 12 x 4 grid over a 30 mm drum: 2.5 mm bins, 3 mm particles
    let (_dir, f) = copy("run.h5");
    let f = f.to_str().unwrap();
    let o = plot(&["field", f, "--quantity", "volume_fraction:large"]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning: the field bins are") && err.contains("diagnostics.fields.grid"),
        "{err}"
    );
    let o = plot(&["field", f, "--quantity", "w"]);
    assert!(o.status.success());
    assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
}
