//! The force pass: each owned particle's wall contacts and gravity, then the pair contacts
//! in canonical list order. The walls need no ghost, so the step computes them while the
//! ghosts' messages travel; every particle still sums its forces in the same order on any
//! number of ranks.

use super::neighbor::NeighborList;
use crate::particles::Particles;
use crate::physics::integrate::min_image;
use crate::physics::rough_wall::is_fixed;
use crate::physics::{Body, ContactLaw, DrumWalls, Materials, V3};

#[inline]
fn body(p: &Particles, i: usize, scale: f64) -> Body {
    Body {
        v: V3::from(p.v[i]),
        w: V3::from(p.w[i]),
        d: p.diameter[i] * scale,
        inv_mass: p.inv_mass[i],
    }
}

/// Add the pair contacts to the forces and torques of all local particles (after
/// [`wall_and_body_forces`]); `scale` multiplies every diameter (1 except while a pour
/// fill grows its particles).
pub fn pair_forces(
    p: &mut Particles,
    nl: &mut NeighborList,
    law: &ContactLaw,
    mat: &Materials,
    period: Option<f64>,
    scale: f64,
) {
    let full_size = scale == 1.0;
    for ((&(a, b), hist), &cut2) in nl.pairs.iter().zip(nl.hist.iter_mut()).zip(&nl.cut2) {
        let (a, b) = (a as usize, b as usize);
        let xa = p.x[a];
        let xb = p.x[b];
        let mut dz = xa[2] - xb[2];
        if let Some(l) = period {
            dz = min_image(dz, l);
        }
        let r = V3::new(xa[0] - xb[0], xa[1] - xb[1], dz);
        // Most listed pairs are within the skin but not touching: reject them before
        // gathering their velocities (the law makes the same test, bit for bit).
        let rc2 = if full_size {
            cut2
        } else {
            let rc = law.cutoff(p.diameter[a] * scale, p.diameter[b] * scale);
            rc * rc
        };
        if r.norm_squared() >= rc2 {
            if *hist != [0.0; 3] {
                *hist = [0.0; 3];
            }
            continue;
        }
        let (ba, bb) = (body(p, a, scale), body(p, b, scale));
        let Some(c) = law.pair(r, &ba, &bb, mat.pair(p.species[a], p.species[b]), hist) else {
            continue;
        };
        let ta = c.n_cross_fs * (0.5 * ba.d);
        let tb = c.n_cross_fs * (0.5 * bb.d);
        for k in 0..3 {
            p.f[a][k] += c.force[k];
            p.f[b][k] -= c.force[k];
            p.t[a][k] -= ta[k];
            p.t[b][k] -= tb[k];
        }
    }
}

/// Zero the forces and torques of all local particles, then give the owned ones their wall
/// forces and gravity (along `-y`). Reads no ghost.
pub fn wall_and_body_forces(
    p: &mut Particles,
    walls: &DrumWalls,
    law: &ContactLaw,
    mat: &Materials,
    gravity: f64,
    scale: f64,
) {
    for f in p.f.iter_mut() {
        *f = [0.0; 3];
    }
    for t in p.t.iter_mut() {
        *t = [0.0; 3];
    }
    for i in 0..p.n_owned {
        if is_fixed(p.species[i]) {
            continue;
        }
        let b = body(p, i, scale);
        let load = walls.load(
            law,
            mat,
            p.species[i],
            V3::from(p.x[i]),
            &b,
            &mut p.wall_hist[i],
        );
        for k in 0..3 {
            p.f[i][k] += load.force[k];
            p.t[i][k] += load.torque[k];
        }
        p.f[i][1] -= gravity / p.inv_mass[i];
    }
}
