//! Rolling resistance raises a drum's dynamic angle of repose, monotonically with its
//! coefficient: the small capped drum of `sd_capped.toml` (slumping at 6 rad/s) turned
//! half a rotation with the rolling spring at `mu_r` = 0, 0.1 and 0.3.

mod common;

use common::{run_case, tmpdir};

/// Mean whole-drum angle of repose over the windows after the first 0.1 rotation.
fn mean_angle(path: &std::path::Path) -> f64 {
    let f = hdf5::File::open(path).unwrap();
    let a: Vec<f32> = f.dataset("slices/angle_drum").unwrap().read_raw().unwrap();
    let late: Vec<f64> = a[5..]
        .iter()
        .map(|&x| x as f64)
        .filter(|x| x.is_finite())
        .collect();
    assert!(late.len() >= 15, "{} windows", late.len());
    late.iter().sum::<f64>() / late.len() as f64
}

#[test]
fn rolling_resistance_raises_the_angle_of_repose_monotonically() {
    let dir = tmpdir();
    let mut angles = Vec::new();
    for mu_r in [0.0, 0.1, 0.3] {
        let out = dir.path().join(format!("mu{mu_r}.h5"));
        let m0 = format!("species.0.mu_roll={mu_r}");
        let m1 = format!("species.1.mu_roll={mu_r}");
        let sets = [
            "run.rotations=0.5",
            "model.rolling=\"sds\"",
            m0.as_str(),
            m1.as_str(),
        ];
        run_case(2, "sd_capped.toml", &out, &sets);
        angles.push(mean_angle(&out));
    }
    // measured: about 30, 36 and 41 degrees; the windows' scatter is 1-2 degrees
    assert!(
        angles[1] > angles[0] + 2.0 && angles[2] > angles[1] + 2.0,
        "angles of repose {angles:?} for mu_r 0, 0.1, 0.3"
    );
}
