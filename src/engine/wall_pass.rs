//! The force pass's first half: forces zeroed, then each owned particle's wall contacts and
//! gravity. Reads no ghost, so the step computes it while the ghosts' messages travel.
//!
//! Only the particles a rebuild found within reach of a wall (`NeighborList::near_walls`)
//! are tested against the walls, in three stages like the pairs' (`forces.rs`):
//! 1. **contacts**: each near particle's wall points (`DrumWalls::contacts`: the curved wall
//!    or sphere, the two caps, a lifter) are tested against its contact range, and those
//!    that touch are written to a scratch list in particle and slot order; the other slots'
//!    histories are cleared;
//! 2. **batches**: the contacts are gathered [`LANES`] at a time into a [`WallBatch`] and
//!    the run's law evaluates all lanes at once ([`BatchLaw::eval_walls`]), vectorised;
//! 3. **scatter**: each contact's force and torques are added to its particle in list
//!    order, so a particle sums its walls in slot order as the scalar law does.
//!
//! The result is the same bits as [`wall_and_body_forces_reference`], the walls one particle
//! at a time through the scalar law (`tests/contact_batch.rs`).

use super::forces::{body, with_law, Isa, LawPass};
use crate::particles::Particles;
use crate::physics::batch::{BatchLaw, LANES};
use crate::physics::rough_wall::is_fixed;
use crate::physics::wall_batch::WallBatch;
use crate::physics::walls::{wall_velocity, Touch, WALL_SLOTS};
use crate::physics::{ContactLaw, DrumWalls, Materials, V3};

/// What the walls' half of the force pass needs besides the particles.
#[derive(Debug, Clone, Copy)]
pub struct WallForces<'a> {
    /// The drum's walls, at the present angle.
    pub walls: &'a DrumWalls,
    /// The run's contact law.
    pub law: &'a ContactLaw,
    /// The particles' and walls' coefficients.
    pub mat: &'a Materials,
    /// Gravity, along `-y`.
    pub gravity: f64,
    /// Factor of every diameter (1 except while a pour fill grows its particles).
    pub scale: f64,
}

/// One wall contact of a particle found by the first stage.
#[derive(Debug, Clone, Copy)]
struct WallTouch {
    /// The particle.
    i: u32,
    /// Its wall slot (an index of [`WALL_SLOTS`]).
    slot: u8,
    /// The wall point as seen from the particle.
    touch: Touch,
}

/// The walls' pass's lists, kept from one step to the next so that they are not allocated
/// again each time.
#[derive(Debug, Clone, Default)]
pub struct WallScratch {
    /// This pass's touching contacts, in particle and slot order.
    touches: Vec<WallTouch>,
    /// The particles whose histories this pass holds in a block while it writes them.
    held: Vec<u32>,
}

/// Zero the forces and torques of all local particles, then give the owned ones their wall
/// forces and gravity (along `-y`). Only the particles of `near` (the list of those within
/// reach of a wall, [`NeighborList::list_near_walls`](super::neighbor::NeighborList::list_near_walls))
/// are tested against the walls; the others have no wall contact until the next rebuild,
/// and their force is gravity alone, the same bits as a wall sum of nothing plus gravity.
/// The contacts are computed in batches with the widest instruction set of this CPU
/// ([`Isa::detect`]); the same bits as [`wall_and_body_forces_reference`].
pub fn wall_and_body_forces(
    p: &mut Particles,
    near: &[u32],
    scratch: &mut WallScratch,
    env: &WallForces,
) {
    wall_and_body_forces_with(Isa::detect(), p, near, scratch, env)
}

/// [`wall_and_body_forces`] with a chosen instruction set (`Isa::Reference` is
/// [`wall_and_body_forces_reference`]).
pub fn wall_and_body_forces_with(
    isa: Isa,
    p: &mut Particles,
    near: &[u32],
    scratch: &mut WallScratch,
    env: &WallForces,
) {
    if isa == Isa::Reference {
        return wall_and_body_forces_reference(p, near, env);
    }
    zero_forces(p);
    let pass = WallPass {
        env,
        p: &mut *p,
        near,
        scratch,
    };
    with_law(isa, env.law, pass);
    add_gravity(p, env.gravity);
}

/// The reference walls' pass: each near particle in turn through the scalar law
/// (`DrumWalls::load`, [`ContactLaw::wall`]), then gravity.
pub fn wall_and_body_forces_reference(p: &mut Particles, near: &[u32], env: &WallForces) {
    zero_forces(p);
    for &i in near {
        let i = i as usize;
        let b = body(p, i, env.scale);
        let (species, x) = (p.species[i], V3::from(p.x[i]));
        let (walls, law, mat) = (env.walls, env.law, env.mat);
        let load = p
            .wall_hist
            .update(i, |h| walls.load(law, mat, species, x, &b, h));
        for k in 0..3 {
            p.f[i][k] += load.force[k];
            p.t[i][k] += load.torque[k];
        }
    }
    add_gravity(p, env.gravity);
}

fn zero_forces(p: &mut Particles) {
    for f in p.f.iter_mut() {
        *f = [0.0; 3];
    }
    for t in p.t.iter_mut() {
        *t = [0.0; 3];
    }
}

fn add_gravity(p: &mut Particles, gravity: f64) {
    for i in 0..p.n_owned {
        if !is_fixed(p.species[i]) {
            p.f[i][1] -= gravity / p.inv_mass[i];
        }
    }
}

/// The batched walls' pass with its particles, as a [`LawPass`].
struct WallPass<'a, 'b> {
    env: &'a WallForces<'a>,
    p: &'b mut Particles,
    near: &'b [u32],
    scratch: &'b mut WallScratch,
}

impl LawPass for WallPass<'_, '_> {
    #[inline(always)]
    fn go<L: BatchLaw>(self, law: &L) {
        let WallPass {
            env,
            p,
            near,
            scratch,
        } = self;
        find_touches::<L>(env, p, near, scratch);
        let rolling = env.law.has_rolling();
        let mut b = WallBatch {
            omega: env.walls.omega,
            ..WallBatch::default()
        };
        for chunk in scratch.touches.chunks(LANES) {
            gather::<L>(env, &mut b, chunk, p);
            law.eval_walls(&mut b);
            scatter::<L>(&b, chunk, p, rolling);
        }
        for &i in &scratch.held {
            p.wall_hist.release_if_clear(i as usize);
        }
    }
}

/// The first stage: the touching wall contacts of the particles of `near`, in particle and
/// slot order, with the test of [`ContactLaw::wall`]; the histories of the slots that do
/// not touch are cleared, and those of a particle that touches are held in a block.
#[inline(always)]
fn find_touches<L: BatchLaw>(
    env: &WallForces,
    p: &mut Particles,
    near: &[u32],
    scratch: &mut WallScratch,
) {
    let words = L::WORDS;
    let (touches, held) = (&mut scratch.touches, &mut scratch.held);
    touches.clear();
    held.clear();
    for &i in near {
        let iu = i as usize;
        let d = p.diameter[iu] * env.scale;
        let d_iw = env.law.normal.wall_contact(d);
        let rc = env.law.normal.range(d_iw);
        let found = env.walls.contacts(V3::from(p.x[iu]), env.law.wall_reach(d));
        let mut touching = [false; WALL_SLOTS.len()];
        for (slot, t) in found.into_iter().enumerate() {
            let Some(touch) = t else { continue };
            let r2 = touch.r.norm_squared();
            if !(r2 >= rc * rc || r2 == 0.0) {
                touching[slot] = true;
                let slot = slot as u8;
                touches.push(WallTouch { i, slot, touch });
            }
        }
        if words > 0 {
            if touching.contains(&true) {
                let h = p.wall_hist.hold(iu);
                for (slot, h) in h.chunks_exact_mut(words).enumerate() {
                    if !touching[slot] {
                        h.fill(0.0);
                    }
                }
                held.push(i);
            } else {
                p.wall_hist.clear(iu);
            }
        }
    }
}

/// Load a chunk of wall contacts into the batch's lanes.
#[inline(always)]
fn gather<L: BatchLaw>(env: &WallForces, b: &mut WallBatch, chunk: &[WallTouch], p: &Particles) {
    let words = L::WORDS;
    for (l, c) in chunk.iter().enumerate() {
        let i = c.i as usize;
        let v = V3::from(p.v[i]) - wall_velocity(c.touch.at, env.walls.omega);
        let (w, r) = (p.w[i], c.touch.r);
        for q in 0..3 {
            b.r[q][l] = r[q];
            b.v[q][l] = v[q];
            b.w[q][l] = w[q];
        }
        let d = p.diameter[i] * env.scale;
        b.d[l] = d;
        b.d_iw[l] = env.law.normal.wall_contact(d);
        b.im[l] = p.inv_mass[i];
        let fr = env.mat.wall(p.species[i], WALL_SLOTS[c.slot as usize]);
        b.coef.load::<L>(l, &fr);
        if words > 0 {
            // held in a block by the first stage
            let h = p
                .wall_hist
                .get(i)
                .expect("a touching particle's history is held");
            let s = c.slot as usize * words;
            for (q, &h) in h[s..s + words].iter().enumerate() {
                b.hist[q][l] = h;
            }
        }
    }
}

/// Add a batch's forces and torques to its particles in list order, and store their
/// histories.
#[inline(always)]
fn scatter<L: BatchLaw>(b: &WallBatch, chunk: &[WallTouch], p: &mut Particles, rolling: bool) {
    let words = L::WORDS;
    for (l, c) in chunk.iter().enumerate() {
        let i = c.i as usize;
        for q in 0..3 {
            p.f[i][q] += b.force[q][l];
            p.t[i][q] -= b.torque[q][l];
            if rolling {
                p.t[i][q] += b.roll[q][l];
            }
        }
        if words > 0 {
            let s = c.slot as usize * words;
            let h = &mut p.wall_hist.hold(i)[s..s + words];
            for (q, h) in h.iter_mut().enumerate() {
                *h = b.hist[q][l];
            }
        }
    }
}
