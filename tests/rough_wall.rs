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

#[test]
fn wall_particles_have_infinite_mass() {
    // A bead hitting a wall particle head-on: with the wall particle's mass infinite the
    // contact has m_eff = m and lasts exactly t_c; were the wall particle an ordinary mass
    // the bead would feel half the force and the contact would last sqrt(2) longer.
    use tumbler::comm::SerialComm;
    use tumbler::engine::Sim;
    use tumbler::particles::ParticleState;
    use tumbler::physics::rough_wall::{RoughWall, FIRST_ID};
    let case = common::case_with(
        "rough.toml",
        &[
            "model.gravity=0.0",
            "drum.omega=1e-9",
            // a drum that all but stands still: a short run keeps the step count bounded
            "run.rotations=1e-6",
            "model.restitution=0.9",
        ],
    );
    let rw = RoughWall::of(&case).unwrap();
    let (x_wall, _) = rw.place(FIRST_ID, 0.0, 0.0);
    let (d, dw) = (0.002, rw.diameter);
    let touch = 0.5 * (d + dw);
    let bead = ParticleState::new(
        0,
        0,
        d,
        [x_wall[0] - touch - 1e-4, 0.0, x_wall[2]],
        [0.2, 0.0, 0.0],
        [0.0; 3],
    );
    let comm = SerialComm;
    let mut sim = Sim::new(&case, &comm, &[bead]).unwrap();
    let k = |s: &Sim| s.p.id.iter().position(|&x| x == 0).unwrap();
    let (mut start, mut end, mut prev) = (None, None, f64::MAX);
    for n in 0..20_000 {
        sim.step();
        let gap = x_wall[0] - sim.p.x[k(&sim)][0] - touch;
        let t = (n + 1) as f64 * sim.dt;
        if start.is_none() && gap < 0.0 {
            start = Some(t - sim.dt * gap / (gap - prev));
        } else if start.is_some() && gap >= 0.0 {
            end = Some(t - sim.dt * gap / (gap - prev));
            break;
        }
        prev = gap;
    }
    let tc = case.model.collision_time.unwrap();
    let lasted = end.unwrap() - start.unwrap();
    assert!(
        (lasted - tc).abs() < 0.03 * tc,
        "contact with a wall particle lasted {lasted}, t_c = {tc}"
    );
    let e = -sim.p.v[k(&sim)][0] / 0.2;
    assert!(
        (e - 0.9).abs() < 0.01 * 0.9,
        "restitution against a wall particle {e}"
    );
}
