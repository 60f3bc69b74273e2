//! The force pass: pair contacts in canonical list order, then walls, then gravity.

use super::neighbor::NeighborList;
use crate::particles::Particles;
use crate::physics::integrate::min_image;
use crate::physics::{rapaport, DrumWalls, Materials, V3};

/// Counts from one force pass.
#[derive(Debug, Clone, Copy, Default)]
pub struct ForceStats {
    /// Pairs in contact.
    pub contacts: usize,
}

/// Zero the forces and torques of all local particles and add the pair contacts.
pub fn pair_forces(
    p: &mut Particles,
    nl: &NeighborList,
    mat: &Materials,
    period: Option<f64>,
) -> ForceStats {
    for f in p.f.iter_mut() {
        *f = [0.0; 3];
    }
    for t in p.t.iter_mut() {
        *t = [0.0; 3];
    }
    let mut contacts = 0;
    for &(a, b) in &nl.pairs {
        let (a, b) = (a as usize, b as usize);
        let xa = p.x[a];
        let xb = p.x[b];
        let mut dz = xa[2] - xb[2];
        if let Some(l) = period {
            dz = min_image(dz, l);
        }
        let r = V3::new(xa[0] - xb[0], xa[1] - xb[1], dz);
        let (da, db) = (p.diameter[a], p.diameter[b]);
        let Some(c) = rapaport::pair(
            r,
            V3::from(p.v[a]),
            V3::from(p.v[b]),
            V3::from(p.w[a]),
            V3::from(p.w[b]),
            da,
            db,
            mat.gamma_n,
            mat.pair(p.species[a], p.species[b]),
        ) else {
            continue;
        };
        contacts += 1;
        let ta = c.n_cross_fs * (0.5 * da);
        let tb = c.n_cross_fs * (0.5 * db);
        for k in 0..3 {
            p.f[a][k] += c.force[k];
            p.f[b][k] -= c.force[k];
            p.t[a][k] -= ta[k];
            p.t[b][k] -= tb[k];
        }
    }
    ForceStats { contacts }
}

/// Add the wall forces and gravity (along `-y`) to the owned particles.
pub fn wall_and_body_forces(p: &mut Particles, walls: &DrumWalls, mat: &Materials, gravity: f64) {
    for i in 0..p.n_owned {
        let load = walls.load(
            V3::from(p.x[i]),
            V3::from(p.v[i]),
            V3::from(p.w[i]),
            p.diameter[i],
            mat.wall(p.species[i]),
        );
        for k in 0..3 {
            p.f[i][k] += load.force[k];
            p.t[i][k] += load.torque[k];
        }
        p.f[i][1] -= gravity / p.inv_mass[i];
    }
}
