//! The rough curved wall (particles fixed to the turning drum) grips the bed by its shape
//! alone: with no wall friction at all, a smooth wall leaves the bed where it is while the
//! rough one drags it up the side the wall moves towards.

mod common;

use common::{case_path, tmpdir, tumbler};

/// Angle (degrees) of the bed's centre of mass from the bottom, towards +x.
fn bed_angle(case: &std::path::Path) -> f64 {
    let dir = tmpdir();
    let out = dir.path().join("out.h5");
    let o = tumbler(&[
        "run",
        case.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--set",
        "run.rotations=0.25",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let f = hdf5::File::open(&out).unwrap();
    let x: Vec<f64> = f.dataset("particles/position").unwrap().read_raw().unwrap();
    let n = (x.len() / 3) as f64;
    let (mx, my) = x
        .chunks(3)
        .fold((0.0, 0.0), |(a, b), p| (a + p[0] / n, b + p[1] / n));
    mx.atan2(-my).to_degrees()
}

#[test]
fn rough_wall_drags_the_bed_where_a_frictionless_smooth_wall_cannot() {
    let rough = case_path("rough.toml");
    let dir = tmpdir();
    let smooth = dir.path().join("smooth.toml");
    let text = std::fs::read_to_string(&rough).unwrap();
    assert!(text.contains("[drum.rough_wall]\ndiameter = 0.002\n"));
    std::fs::write(
        &smooth,
        text.replace("[drum.rough_wall]\ndiameter = 0.002\n", ""),
    )
    .unwrap();
    let (a_rough, a_smooth) = (bed_angle(&rough), bed_angle(&smooth));
    assert!(
        a_rough > 8.0,
        "rough wall: bed turned by only {a_rough} degrees"
    );
    assert!(
        a_smooth.abs() < 3.0,
        "frictionless smooth wall: bed turned by {a_smooth} degrees"
    );
}
