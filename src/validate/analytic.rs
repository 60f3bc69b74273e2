//! Analytic checks of the thesis' spring-dashpot law on the engine itself (thesis ch. 2):
//! a binary or wall collision gives back the restitution `e_n` and lasts the collision time
//! `t_c` the stiffness and damping were chosen for, and a sphere launched sliding on a wall
//! ends up rolling at 5/7 of its launch speed. One rank, no files: each follows one or two
//! particles through [`Sim`] with a serial communicator.

use crate::case::{apply_overrides, parse_case, Case};
use crate::comm::SerialComm;
use crate::engine::Sim;
use crate::particles::ParticleState;

/// A small capped spring-dashpot drum without gravity whose wall barely turns: the stage for
/// the collisions (overridden per check).
const STAGE: &str = r#"
title = "analytic collisions"
seed = 1

[drum]
diameter = 0.03
length = 0.04
ends = "capped"
omega = 1e-9

[model]
family = "spring-dashpot"
normal = "linear"
tangential = "viscous"
gravity = 0.0
density = 2500.0
collision_time = 1.0e-3
restitution = 0.9

[[species]]
name = "beads"
diameter = 0.002
mu = 0.5

[init]
kind = "particles"

[[init.particle]]
species = 0
diameter = 0.002
position = [0.0, 0.0, 0.0]

[run]
rotations = 1e-9
"#;

/// The stage with `overrides` (`key=value`, as `--set` takes them).
pub fn stage(overrides: &[String]) -> Result<Case, String> {
    let text = apply_overrides(STAGE, overrides, "analytic stage").map_err(|e| e.to_string())?;
    parse_case(&text, "analytic stage").map_err(|errs| {
        errs.iter()
            .map(|e| e.to_string())
            .collect::<Vec<_>>()
            .join("; ")
    })
}

/// What one collision gave.
#[derive(Debug, Clone, Copy)]
pub struct Collision {
    /// Separation speed over approach speed along the normal.
    pub restitution: f64,
    /// Time in contact (between the interpolated instants the gap crosses zero).
    pub duration: f64,
    /// The collision time the law was set up for.
    pub collision_time: f64,
}

/// Step `sim` through one collision: `gap(sim)` is the surface separation (negative in
/// contact), `vn(sim)` the approach speed. Returns (restitution, duration); `None` if the
/// contact had not ended after 100,000 steps.
pub fn collide(
    sim: &mut Sim,
    gap: impl Fn(&Sim) -> f64,
    vn: impl Fn(&Sim) -> f64,
) -> Option<(f64, f64)> {
    let dt = sim.dt;
    let v_in = vn(sim);
    let (mut start, mut prev) = (None, gap(sim));
    for k in 0..100_000 {
        sim.step();
        let g = gap(sim);
        let t = (k + 1) as f64 * dt;
        if start.is_none() && g < 0.0 {
            start = Some(t - dt * g / (g - prev));
        }
        if let Some(t0) = start {
            if g >= 0.0 {
                let t1 = t - dt * g / (g - prev);
                return Some((-vn(sim) / v_in, t1 - t0));
            }
        }
        prev = g;
    }
    None
}

fn ball(id: u64, d: f64, x: [f64; 3], v: [f64; 3]) -> ParticleState {
    ParticleState::new(id, 0, d, x, v, [0.0; 3])
}

fn index(sim: &Sim, id: u64) -> usize {
    sim.p
        .id
        .iter()
        .position(|&x| x == id)
        .expect("the particle is in the drum")
}

/// Head-on collision of beads of diameters `d1`, `d2` (approach speed 0.5 m/s) under the
/// linear law with restitution `e`, on the drum's axis.
pub fn pair_collision(e: f64, d1: f64, d2: f64) -> Result<Collision, String> {
    let case = stage(&[format!("model.restitution={e}")])?;
    let tc = case.model.collision_time.unwrap_or(f64::NAN);
    let gap0 = 0.0002;
    let h = 0.5 * (0.5 * (d1 + d2) + gap0);
    let a = ball(0, d1, [0.0, 0.0, -h], [0.0, 0.0, 0.3]);
    let b = ball(1, d2, [0.0, 0.0, h], [0.0, 0.0, -0.2]);
    let mut sim = Sim::new(&case, &SerialComm, &[a, b]).map_err(|e| e.to_string())?;
    let gap = |s: &Sim| (s.p.x[index(s, 1)][2] - s.p.x[index(s, 0)][2]) - 0.5 * (d1 + d2);
    let vn = |s: &Sim| s.p.v[index(s, 0)][2] - s.p.v[index(s, 1)][2];
    let (restitution, duration) =
        collide(&mut sim, gap, vn).ok_or("the pair contact never ended")?;
    Ok(Collision {
        restitution,
        duration,
        collision_time: tc,
    })
}

/// A bead of diameter `d` hitting the end cap at 0.25 m/s on the axis (where the cap is
/// still), with the history tangential model, restitution `e`.
pub fn wall_collision(e: f64, d: f64) -> Result<Collision, String> {
    let case = stage(&[
        format!("model.restitution={e}"),
        "model.tangential=\"history\"".into(),
    ])?;
    let tc = case.model.collision_time.unwrap_or(f64::NAN);
    let half = 0.5 * case.drum.axial_length();
    let a = ball(
        0,
        d,
        [0.0, 0.0, -half + 0.5 * d + 0.0002],
        [0.0, 0.0, -0.25],
    );
    let mut sim = Sim::new(&case, &SerialComm, &[a]).map_err(|e| e.to_string())?;
    let gap = |s: &Sim| s.p.x[0][2] + half - 0.5 * d;
    let vn = |s: &Sim| -s.p.v[0][2];
    let (restitution, duration) =
        collide(&mut sim, gap, vn).ok_or("the wall contact never ended")?;
    Ok(Collision {
        restitution,
        duration,
        collision_time: tc,
    })
}

/// How a sliding sphere ended up.
#[derive(Debug, Clone, Copy)]
pub struct Rolling {
    /// Final axial speed over the launch speed (5/7 in theory).
    pub speed_ratio: f64,
    /// Final `(d/2) w` over the final speed (1 when it rolls without slipping).
    pub spin_ratio: f64,
}

/// Launch a 4 mm sphere sliding at 0.5 m/s along the axis on the bottom of a wide drum (a
/// flat floor along `z`, mu = 0.3, g = 9.8) with `tangential` (`"viscous"` or `"history"`)
/// and follow it for 0.4 s (it stops sliding after v0 / (7/2 mu g) = 0.05 s).
pub fn rolling(tangential: &str) -> Result<Rolling, String> {
    let case = stage(&[
        format!("model.tangential=\"{tangential}\""),
        "model.gravity=9.8".into(),
        "drum.diameter=2.0".into(),
        "drum.length=4.0".into(),
        "species.0.mu=0.3".into(),
    ])?;
    let d = 0.004;
    let radius = 0.5 * case.drum.diameter;
    let v0 = 0.5;
    let a = ball(0, d, [0.0, -(radius - 0.5 * d), -1.5], [0.0, 0.0, v0]);
    let mut sim = Sim::new(&case, &SerialComm, &[a]).map_err(|e| e.to_string())?;
    let steps = (0.4 / sim.dt) as usize;
    let mut tail = Vec::new();
    for k in 0..steps {
        sim.step();
        if k > steps - 2000 {
            tail.push(sim.p.v[0][2]);
        }
    }
    let v = tail.iter().sum::<f64>() / tail.len() as f64;
    Ok(Rolling {
        speed_ratio: v / v0,
        spin_ratio: 0.5 * d * sim.p.w[0][0] / v,
    })
}

/// How a sphere rolling on a floor against rolling resistance slowed down.
#[derive(Debug, Clone, Copy)]
pub struct RollingStop {
    /// Measured deceleration while it rolls (m/s^2), from the speeds at a quarter and at
    /// half of the time it takes to stop.
    pub deceleration: f64,
    /// `5 mu_r g / 7`: a constant rolling torque `mu_r (d/2) m g` against a sphere rolling
    /// without slipping (`I = m d^2 / 10` about its centre).
    pub expected: f64,
    /// Its speed after twice the time it would take to stop (0 when it has stopped).
    pub speed_late: f64,
}

/// Launch a 4 mm sphere rolling without slipping at 0.3 m/s along the axis on the bottom of
/// a wide drum (mu = 0.5, g = 9.8) with the rolling model `rolling` (`"constant"`,
/// `"viscous"`, `"sds"`) and `mu_r`, and measure how fast it slows down.
pub fn rolling_resistance(rolling: &str, mu_r: f64) -> Result<RollingStop, String> {
    let mut sets = vec![
        "model.tangential=\"history\"".into(),
        format!("model.rolling=\"{rolling}\""),
        "model.gravity=9.8".into(),
        "drum.diameter=2.0".into(),
        "drum.length=4.0".into(),
        "species.0.mu=0.5".into(),
        format!("species.0.mu_roll={mu_r}"),
    ];
    if rolling == "viscous" {
        // viscous enough to sit at the cap throughout
        sets.push("model.rolling_viscosity=1.0".into());
    }
    let case = stage(&sets)?;
    let (d, g, v0) = (0.004, 9.8, 0.3);
    let radius = 0.5 * case.drum.diameter;
    let mut a = ball(0, d, [0.0, -(radius - 0.5 * d), -1.5], [0.0, 0.0, v0]);
    // rolling along +z on the floor at -y: w_x = v / (d/2)
    a.w = [v0 / (0.5 * d), 0.0, 0.0];
    let mut sim = Sim::new(&case, &SerialComm, &[a]).map_err(|e| e.to_string())?;
    let expected = 5.0 * mu_r * g / 7.0;
    let t_stop = v0 / expected;
    let speed_at = |t: f64, sim: &mut Sim| {
        while (sim.step as f64) * sim.dt < t {
            sim.step();
        }
        sim.p.v[0][2]
    };
    let v1 = speed_at(0.25 * t_stop, &mut sim);
    let v2 = speed_at(0.5 * t_stop, &mut sim);
    let speed_late = speed_at(2.0 * t_stop, &mut sim);
    Ok(RollingStop {
        deceleration: (v1 - v2) / (0.25 * t_stop),
        expected,
        speed_late,
    })
}

/// Where a cohesive sphere came to rest on a floor.
#[derive(Debug, Clone, Copy)]
pub struct CohesiveRest {
    /// Its overlap with the floor at rest.
    pub overlap: f64,
    /// The overlap at which the linear spring balances gravity plus the simplified-JKR
    /// attraction `k_c pi ((d/2)^2 - (d/2 - delta)^2)`.
    pub expected: f64,
    /// The overlap without cohesion (`m g / k`).
    pub without: f64,
}

/// Set a 2 mm sphere on the bottom of a wide drum under gravity with cohesion energy
/// density `k_c` (simplified JKR) and let it settle.
pub fn cohesive_rest(k_c: f64) -> Result<CohesiveRest, String> {
    let case = stage(&[
        "model.cohesion=\"sjkr\"".into(),
        "model.gravity=9.8".into(),
        "model.restitution=0.3".into(),
        "drum.diameter=2.0".into(),
        format!("species.0.cohesion_energy={k_c}"),
    ])?;
    let d = 0.002;
    let radius = 0.5 * case.drum.diameter;
    let a = ball(0, d, [0.0, -(radius - 0.5 * d), 0.0], [0.0; 3]);
    let mut sim = Sim::new(&case, &SerialComm, &[a]).map_err(|e| e.to_string())?;
    let tc = case.model.collision_time.unwrap_or(f64::NAN);
    while (sim.step as f64) * sim.dt < 200.0 * tc {
        sim.step();
    }
    let y = sim.p.x[0][1];
    let overlap = 0.5 * d - (radius + y);
    // the linear law's spring m (pi^2/t_c^2 + gamma^2) (a wall: m_eff = m)
    let e = case.model.restitution.unwrap_or(1.0);
    let gamma = -e.ln() / tc;
    let m = case.model.density * std::f64::consts::PI / 6.0 * d * d * d;
    let k = m * ((std::f64::consts::PI / tc).powi(2) + gamma * gamma);
    let (g, r) = (case.model.gravity, 0.5 * d);
    let balance = |delta: f64| {
        k * delta - m * g - k_c * std::f64::consts::PI * (r * r - (r - delta) * (r - delta))
    };
    // bisection on [0, r/2]: the spring wins at depth for any cohesion this test uses
    let (mut lo, mut hi) = (0.0, 0.5 * r);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if balance(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(CohesiveRest {
        overlap,
        expected: 0.5 * (lo + hi),
        without: m * g / k,
    })
}
