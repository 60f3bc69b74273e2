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
