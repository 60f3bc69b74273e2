//! The thesis' spring-dashpot laws on the engine itself: binary collisions give the requested
//! restitution and collision time; a sphere launched sliding on a wall ends up rolling at 5/7
//! of its speed; a frictionless cap exerts no tangential force.

mod common;

use common::case_with;
use tumbler::comm::SerialComm;
use tumbler::engine::Sim;
use tumbler::particles::ParticleState;
use tumbler::validate::analytic::{self, collide};

fn ball(id: u64, d: f64, x: [f64; 3], v: [f64; 3]) -> ParticleState {
    ParticleState::new(id, 0, d, x, v, [0.0; 3])
}

fn sd_case(e: f64, tangential: &str, extra: &[&str]) -> tumbler::case::Case {
    let mut ov = vec![
        "model.gravity=0.0".to_string(),
        format!("model.restitution={e}"),
        format!("model.tangential=\"{tangential}\""),
        "drum.omega=1e-9".to_string(),
        // a drum that all but stands still: a short run keeps the step count bounded
        "run.rotations=1e-6".to_string(),
    ];
    ov.extend(extra.iter().map(|s| s.to_string()));
    let ov: Vec<&str> = ov.iter().map(String::as_str).collect();
    case_with("sd_capped.toml", &ov)
}

/// The measured restitution over a range of `e_n` (printed; `--ignored --nocapture`), for
/// docs/verification.md.
#[test]
#[ignore]
fn restitution_error_table() {
    for e in [0.3, 0.5, 0.7, 0.8, 0.89, 0.97] {
        let c = analytic::pair_collision(e, 0.002, 0.002).unwrap();
        println!(
            "e {e}: measured {:.5} ({:+.2} %), duration/t_c {:.4}",
            c.restitution,
            100.0 * (c.restitution / e - 1.0),
            c.duration / c.collision_time
        );
    }
}

#[test]
fn particle_collisions_give_the_restitution_and_collision_time() {
    // The thesis' values (0.89, 0.97) and one between. The dashpot switches on at first
    // overlap, so a step that straddles the start or end of a contact misses or gains up to
    // about -ln(e_n)/40 of the velocity at dt = t_c/40: 0.3 % at 0.89, but 0.9 % at 0.7
    // (see docs/verification.md for the measured table).
    for e in [0.89, 0.93, 0.97] {
        let case = analytic::stage(&[format!("model.restitution={e}")]).unwrap();
        let tc = case.model.collision_time.unwrap();
        assert_eq!(case.dt(), tc / 40.0);
        for ratio in [1.0, 1.5, 2.0] {
            let c = analytic::pair_collision(e, 0.002, 0.002 * ratio).unwrap();
            assert_eq!(c.collision_time, tc);
            assert!(
                (c.restitution - e).abs() < 0.01 * e,
                "e = {e}, size ratio {ratio}: restitution {}",
                c.restitution
            );
            assert!(
                (c.duration - tc).abs() < 0.03 * tc,
                "e = {e}, size ratio {ratio}: contact lasted {}, t_c = {tc}",
                c.duration
            );
        }
    }
}

#[test]
fn wall_collisions_give_the_restitution_and_collision_time() {
    for e in [0.89, 0.93, 0.97] {
        for d in [0.002, 0.004] {
            let c = analytic::wall_collision(e, d).unwrap();
            let tc = c.collision_time;
            assert!(
                (c.restitution - e).abs() < 0.01 * e,
                "e = {e}, d = {d}: restitution {}",
                c.restitution
            );
            assert!(
                (c.duration - tc).abs() < 0.03 * tc,
                "e = {e}, d = {d}: contact lasted {}, t_c = {tc}",
                c.duration
            );
        }
    }
}

#[test]
fn sliding_sphere_ends_up_rolling_at_five_sevenths() {
    for tangential in ["viscous", "history"] {
        let r = analytic::rolling(tangential).unwrap();
        // the spin matches the rolling: v = (d/2) w
        assert!(
            (r.spin_ratio - 1.0).abs() < 0.01,
            "{tangential}: (d/2) w / v = {}",
            r.spin_ratio
        );
        assert!(
            (r.speed_ratio - 5.0 / 7.0).abs() < 0.01 * 5.0 / 7.0,
            "{tangential}: rolling at {} of the launch speed",
            r.speed_ratio
        );
    }
}

#[test]
fn rolling_resistance_slows_a_rolling_sphere_at_five_sevenths_mu_r_g() {
    // a torque mu_r (d/2) m g against a sphere rolling without slipping decelerates it at
    // 5 mu_r g / 7; once stopped it stays stopped
    for model in ["constant", "viscous", "sds"] {
        for mu_r in [0.05, 0.1] {
            let r = analytic::rolling_resistance(model, mu_r).unwrap();
            assert!(
                (r.deceleration / r.expected - 1.0).abs() < 0.02,
                "{model}, mu_r {mu_r}: decelerates at {} m/s^2, expected {}",
                r.deceleration,
                r.expected
            );
            assert!(
                r.speed_late.abs() < 1e-3,
                "{model}, mu_r {mu_r}: still moving at {} m/s",
                r.speed_late
            );
        }
    }
}

#[test]
fn cohesive_sphere_rests_deeper_as_the_simplified_jkr_balance_says() {
    let none = analytic::cohesive_rest(0.0).unwrap();
    assert!(
        (none.overlap / none.without - 1.0).abs() < 1e-3,
        "no cohesion: overlap {} against m g / k = {}",
        none.overlap,
        none.without
    );
    for k_c in [2.0e3, 5.0e3] {
        let r = analytic::cohesive_rest(k_c).unwrap();
        assert!(
            (r.overlap / r.expected - 1.0).abs() < 1e-3,
            "k_c {k_c}: overlap {} against {}",
            r.overlap,
            r.expected
        );
        assert!(
            r.overlap > 1.1 * r.without,
            "k_c {k_c}: no deeper than without"
        );
    }
}

#[test]
fn frictionless_cap_exerts_no_tangential_force() {
    // sd_capped has a frictionless cap at +L/2: a spinning particle pressed against it keeps
    // its spin and gains no sideways speed; against the frictional cap at -L/2 it does not.
    for (z_sign, frictional) in [(1.0, false), (-1.0, true)] {
        let case = sd_case(0.9, "history", &[]);
        let half = 0.5 * case.drum.axial_length();
        let d = 0.003;
        let mut a = ball(
            0,
            d,
            [0.0, 0.0, z_sign * (half - 0.5 * d + 0.00001)],
            [0.0, 0.0, z_sign * 0.01],
        );
        a.w = [100.0, 0.0, 0.0];
        let comm = SerialComm;
        let mut sim = Sim::new(&case, &comm, &[a]).unwrap();
        for _ in 0..400 {
            sim.step();
        }
        let (w, vy) = (sim.p.w[0][0], sim.p.v[0][1]);
        if frictional {
            assert!(
                w < 99.0 && vy.abs() > 1e-4,
                "the frictional cap grips: w = {w}, vy = {vy}"
            );
        } else {
            assert_eq!((w, vy), (100.0, 0.0), "the frictionless cap does not grip");
        }
    }
}

#[test]
fn hertz_collision_lasts_as_hertz_theory_says() {
    // Without damping, a Hertz collision is elastic and lasts
    // 2.868 (m_eff^2 / (R E*^2 v))^(1/5), with E* = Y / (2 (1 - nu^2)) for equal materials
    // and R the effective radius (eq. 2.13 is F = 4/3 E* sqrt(R) a^(3/2)).
    let (y, nu) = (1.0e7, 0.3);
    for (ratio, v) in [(1.0, 0.5), (2.0, 0.2)] {
        let case = sd_case(
            0.9,
            "viscous",
            &[
                "model.normal=\"hertz\"",
                &format!("model.youngs_modulus={y}"),
                &format!("model.poisson_ratio={nu}"),
                "model.hertz_damping=0.0",
                "run.dt=2e-6",
            ],
        );
        let (d1, d2) = (0.002, 0.002 * ratio);
        let a = ball(
            0,
            d1,
            [0.0, 0.0, -0.5 * (0.5 * (d1 + d2) + 1e-5)],
            [0.0, 0.0, 0.5 * v],
        );
        let b = ball(
            1,
            d2,
            [0.0, 0.0, 0.5 * (0.5 * (d1 + d2) + 1e-5)],
            [0.0, 0.0, -0.5 * v],
        );
        let comm = SerialComm;
        let mut sim = Sim::new(&case, &comm, &[a, b]).unwrap();
        let mass = |d: f64| 2500.0 * std::f64::consts::PI / 6.0 * d * d * d;
        let m_eff = mass(d1) * mass(d2) / (mass(d1) + mass(d2));
        let r_eff = 0.25 * d1 * d2 / (0.5 * (d1 + d2));
        let e_star = y / (2.0 * (1.0 - nu * nu));
        let t_theory = 2.868 * (m_eff * m_eff / (r_eff * e_star * e_star * v)).powf(0.2);
        let k = |s: &Sim, id: u64| s.p.id.iter().position(|&x| x == id).unwrap();
        let gap = |s: &Sim| (s.p.x[k(s, 1)][2] - s.p.x[k(s, 0)][2]) - 0.5 * (d1 + d2);
        let vn = |s: &Sim| s.p.v[k(s, 0)][2] - s.p.v[k(s, 1)][2];
        let (e_got, t_got) = collide(&mut sim, gap, vn).expect("the contact ends");
        assert!(
            (e_got - 1.0).abs() < 0.005,
            "undamped Hertz restitution {e_got}"
        );
        assert!(
            (t_got - t_theory).abs() < 0.03 * t_theory,
            "Hertz contact lasted {t_got}, theory {t_theory}"
        );
    }
}

#[test]
fn a_pair_with_its_own_restitution_rebounds_with_it_and_lasts_t_c() {
    // species 0 ("small", e_n 0.95 of its own), species 1 ("large", the model's 0.9): a
    // mixed pair rebounds with sqrt(0.95 0.9), or with the [[pairs]] override's 0.8; each
    // contact lasts t_c. A step of t_c/400 makes the straddled first and last steps'
    // error (about -ln(e_n)/400 of the velocity) small.
    let tc = 1.0e-3;
    let mixed = (0.95f64 * 0.9).sqrt();
    let pair = "pairs=[{species=[\"large\", \"small\"], restitution=0.8}]";
    for (e, extra) in [(mixed, None), (0.8, Some(pair))] {
        let mut ov = vec!["species.0.restitution=0.95", "run.dt=2.5e-6"];
        ov.extend(extra);
        let case = sd_case(0.9, "viscous", &ov);
        assert_eq!(case.model.collision_time, Some(tc));
        let (d1, d2, v) = (0.002, 0.003, 0.4);
        let gap0 = 0.5 * (d1 + d2) + 1e-5;
        let a = ball(0, d1, [0.0, 0.0, -0.5 * gap0], [0.0, 0.0, 0.5 * v]);
        let b = ParticleState::new(
            1,
            1,
            d2,
            [0.0, 0.0, 0.5 * gap0],
            [0.0, 0.0, -0.5 * v],
            [0.0; 3],
        );
        let comm = SerialComm;
        let mut sim = Sim::new(&case, &comm, &[a, b]).unwrap();
        let k = |s: &Sim, id: u64| s.p.id.iter().position(|&x| x == id).unwrap();
        let gap = |s: &Sim| (s.p.x[k(s, 1)][2] - s.p.x[k(s, 0)][2]) - 0.5 * (d1 + d2);
        let vn = |s: &Sim| s.p.v[k(s, 0)][2] - s.p.v[k(s, 1)][2];
        let (e_got, t_got) = collide(&mut sim, gap, vn).expect("the contact ends");
        assert!(
            (e_got - e).abs() < 2e-3 * e,
            "restitution {e_got}, the pair's {e}"
        );
        assert!((t_got - tc).abs() < 5e-3 * tc, "contact lasted {t_got}");
    }
}
