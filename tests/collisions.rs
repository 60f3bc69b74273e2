//! Scenario tests on the engine in one process: binary collisions lose exactly the energy the
//! normal damping takes, and the turning wall carries a particle round.

mod common;

use common::case_with;
use tumbler::comm::SerialComm;
use tumbler::engine::Sim;
use tumbler::particles::ParticleState;

fn kinetic(sim: &Sim) -> f64 {
    let p = &sim.p;
    (0..p.n_owned)
        .map(|i| {
            let v2: f64 = p.v[i].iter().map(|x| x * x).sum();
            let w2: f64 = p.w[i].iter().map(|x| x * x).sum();
            0.5 * v2 / p.inv_mass[i] + 0.5 * w2 / p.inv_inertia[i]
        })
        .sum()
}

fn ball(id: u64, d: f64, x: [f64; 3], v: [f64; 3]) -> ParticleState {
    ParticleState::new(id, 0, d, x, v, [0.0; 3])
}

/// Run until the contact is over; return (kinetic energy lost, energy the damping took by
/// the trapezoid rule on the normal approach speed `vn(sim)` while in contact).
fn collide(sim: &mut Sim, vn: impl Fn(&Sim) -> Option<f64>, gamma_n: f64) -> (f64, f64) {
    let dt = sim.dt;
    let e0 = kinetic(sim);
    let mut dissipated = 0.0;
    let mut prev = vn(sim).unwrap_or(0.0);
    let mut touched = false;
    for _ in 0..200_000 {
        sim.step();
        let now = vn(sim);
        let v = now.unwrap_or(0.0);
        if now.is_some() || prev != 0.0 {
            dissipated += 0.5 * dt * gamma_n * (prev * prev + v * v);
        }
        prev = v;
        touched |= now.is_some();
        if touched && now.is_none() {
            return (e0 - kinetic(sim), dissipated);
        }
    }
    panic!("the contact never ended");
}

fn pair_case(gamma_n: &str) -> tumbler::case::Case {
    case_with(
        "capped.toml",
        &[
            "model.gravity=0.0",
            &format!("model.gamma_n={gamma_n}"),
            "run.dt=0.0005",
        ],
    )
}

#[test]
fn head_on_collision_loses_the_damping_energy() {
    for (gamma_n, d2) in [(5.0, 1.0), (5.0, 1.3), (2.0, 0.9)] {
        let case = pair_case(&gamma_n.to_string());
        let d_ab = 0.5 * (1.0 + d2);
        let rc = tumbler::physics::rapaport::cutoff(d_ab);
        let a = ball(0, 1.0, [0.0, 0.0, -0.5 * rc - 0.05], [0.0, 0.0, 1.0]);
        let b = ball(1, d2, [0.0, 0.0, 0.5 * rc + 0.05], [0.0, 0.0, -1.0]);
        let comm = SerialComm;
        let mut sim = Sim::new(&case, &comm, &[a, b]).unwrap();
        let vn = |s: &Sim| {
            let p = &s.p;
            let (i, j) = if p.id[0] == 0 { (0, 1) } else { (1, 0) };
            let gap = p.x[j][2] - p.x[i][2];
            (gap < rc).then(|| p.v[i][2] - p.v[j][2])
        };
        let (lost, damped) = collide(&mut sim, vn, gamma_n);
        assert!(lost > 0.05, "a damped collision loses energy: {lost}");
        let rel = (lost - damped).abs() / damped;
        assert!(
            rel < 5e-3,
            "gamma_n {gamma_n}, d2 {d2}: lost {lost}, damping took {damped}, rel {rel}"
        );
        // head on: no sliding, so no spin and no sideways motion
        for i in 0..2 {
            assert_eq!(sim.p.w[i], [0.0; 3]);
            assert_eq!((sim.p.v[i][0], sim.p.v[i][1]), (0.0, 0.0));
        }
    }
}

#[test]
fn elastic_head_on_collision_conserves_energy() {
    let case = pair_case("0.0");
    let rc = tumbler::physics::rapaport::cutoff(1.0);
    let a = ball(0, 1.0, [0.0, 0.0, -0.5 * rc - 0.05], [0.0, 0.0, 1.0]);
    let b = ball(1, 1.0, [0.0, 0.0, 0.5 * rc + 0.05], [0.0, 0.0, -1.0]);
    let comm = SerialComm;
    let mut sim = Sim::new(&case, &comm, &[a, b]).unwrap();
    let e0 = kinetic(&sim);
    for _ in 0..2000 {
        sim.step();
    }
    let e1 = kinetic(&sim);
    assert!((e1 - e0).abs() < 1e-5 * e0, "{e0} -> {e1}");
    // and the particles bounced back
    let z_of = |id: u64| {
        let k = sim.p.id.iter().position(|&x| x == id).unwrap();
        sim.p.v[k][2]
    };
    assert!(z_of(0) < -0.99 && z_of(1) > 0.99);
}

#[test]
fn end_cap_collision_loses_the_damping_energy() {
    let gamma_n = 5.0;
    let case = pair_case("5.0");
    let half = 0.5 * case.drum.axial_length();
    let d_iw = 0.5 * (1.0 + case.model.wall_diameter);
    let rc = tumbler::physics::rapaport::cutoff(d_iw);
    let _ = &case;
    // on the axis the cap does not move, so the collision is purely normal
    let a = ball(0, 1.0, [0.0, 0.0, -half + rc + 0.05], [0.0, 0.0, -1.5]);
    let comm = SerialComm;
    let mut sim = Sim::new(&case, &comm, &[a]).unwrap();
    let vn = |s: &Sim| {
        let h = s.p.x[0][2] + half;
        (h < rc).then(|| s.p.v[0][2])
    };
    let (lost, damped) = collide(&mut sim, vn, gamma_n);
    let rel = (lost - damped).abs() / damped;
    assert!(
        lost > 0.05 && rel < 5e-3,
        "lost {lost}, damping took {damped}"
    );
    assert!(sim.p.v[0][2] > 0.0, "bounced off the cap");
}

/// Largest angle (degrees, signed, from the bottom towards +x) a particle resting on the
/// bottom of the curved wall reaches in an eighth of a rotation, and its final spin about z.
fn carried(ends: &str, omega: f64) -> (f64, f64) {
    let file = if ends == "periodic" {
        "periodic.toml"
    } else {
        "capped.toml"
    };
    // a short run keeps the step count bounded when the drum all but stands still
    let case = case_with(
        file,
        &[&format!("drum.omega={omega}"), "run.rotations=1e-6"],
    );
    let radius = 0.5 * case.drum.diameter;
    let a = ball(0, 1.0, [0.0, -(radius - 1.0), 0.0], [0.0; 3]);
    let comm = SerialComm;
    let mut sim = Sim::new(&case, &comm, &[a]).unwrap();
    let mut extreme: f64 = 0.0;
    let steps = (std::f64::consts::PI / 4.0 / 0.5 / case.dt()) as usize;
    for _ in 0..steps {
        sim.step();
        let x = sim.p.x[0];
        let angle = x[0].atan2(-x[1]).to_degrees();
        if angle.abs() > extreme.abs() {
            extreme = angle;
        }
        let rho = (x[0] * x[0] + x[1] * x[1]).sqrt();
        assert!(
            rho < radius && rho > radius - 1.2,
            "left the wall: rho = {rho}"
        );
    }
    (extreme, sim.p.w[0][2])
}

#[test]
fn turning_wall_carries_a_resting_particle_round() {
    for ends in ["periodic", "capped"] {
        // The wall at the bottom moves towards +x for omega > 0 (about +z): friction drags the
        // particle up that side and spins it in the drum's sense.
        let (up, spin) = carried(ends, 0.5);
        assert!(up > 2.0, "{ends}: dragged only to {up} degrees");
        assert!(spin > 0.1, "{ends}: spin {spin}");
        let (down, spin) = carried(ends, -0.5);
        assert!(
            down < -2.0 && spin < -0.1,
            "{ends}: reversed drum gives {down} degrees, spin {spin}"
        );
        // a wall at rest leaves it at rest
        let (still, spin) = carried(ends, 1e-9);
        assert!(
            still.abs() < 1e-3 && spin.abs() < 1e-6,
            "{ends}: {still} degrees, spin {spin}"
        );
    }
}
