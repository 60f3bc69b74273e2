//! Migration of particles between slabs and the ghost halo, as one mechanism over the
//! [`Comm`] exchange with the two axial neighbours.
//!
//! Ghosts keep their owner's (wrapped) coordinates bit for bit; a ghost that is a periodic
//! image carries its axial offset in `z_image`, used only for binning. Pair forces use the
//! minimum image of the raw coordinates, so a pair is computed with the same arithmetic
//! whichever of its particles is the ghost.

use super::neighbor::SavedHistory;
use super::slabs::Slabs;
use crate::comm::Comm;
use crate::particles::{unpack, unpack_ghost, Particles, GHOST_WORDS, PACKED_WORDS, UPDATE_WORDS};
use crate::physics::Materials;

/// Which owned particles were sent as ghosts to each neighbour, and where their copies sit.
#[derive(Debug, Clone, Default)]
pub struct Halo {
    send_down: Vec<usize>,
    send_up: Vec<usize>,
    n_from_down: usize,
    n_from_up: usize,
}

/// Words of one saved contact history in a message: both ids and the vector.
const HISTORY_WORDS: usize = 5;

/// What a migration moved.
#[derive(Debug, Clone, Copy, Default)]
pub struct Migrated {
    /// Particles sent to neighbours.
    pub particles: usize,
    /// Contact histories sent with them.
    pub histories: usize,
}

/// Send every owned particle that left this rank's slab to the neighbour that now owns it,
/// with the histories of its contacts (`saved`, which receives the neighbours' in turn and
/// stays sorted). Ghosts must have been cleared.
pub fn migrate(
    p: &mut Particles,
    slabs: &Slabs,
    comm: &dyn Comm,
    mat: &Materials,
    saved: &mut SavedHistory,
) -> Migrated {
    debug_assert_eq!(p.n_owned, p.len());
    let me = comm.rank();
    let (down, up) = (slabs.down(me), slabs.up(me));
    let mut leave = vec![false; p.n_owned];
    let (mut to_down, mut to_up) = (Vec::new(), Vec::new());
    for (i, flag) in leave.iter_mut().enumerate() {
        let owner = slabs.owner(p.x[i][2]);
        if owner == me {
            continue;
        }
        *flag = true;
        if Some(owner) == up {
            p.pack(i, &mut to_up);
        } else if Some(owner) == down {
            p.pack(i, &mut to_down);
        } else {
            panic!(
                "particle {} at z = {} moved past a whole slab in one neighbour-list interval: \
                 the run has blown up (time step too large for the stiffness, or particles \
                 started too fast)",
                p.id[i], p.x[i][2]
            );
        }
    }
    let sent = leave.iter().filter(|&&l| l).count();
    if down.is_none() && up.is_none() {
        assert_eq!(sent, 0, "a particle left the only slab");
        return Migrated::default();
    }
    // Each message: particle count, particles, then the histories of their contacts.
    let mut out_down = vec![(to_down.len() / PACKED_WORDS) as f64];
    out_down.extend_from_slice(&to_down);
    let mut out_up = vec![(to_up.len() / PACKED_WORDS) as f64];
    out_up.extend_from_slice(&to_up);
    let mut histories = 0;
    if !saved.is_empty() && sent > 0 {
        let ids = |buf: &[f64]| -> Vec<u64> {
            let mut v: Vec<u64> = buf
                .chunks_exact(PACKED_WORDS)
                .map(|r| r[0] as u64)
                .collect();
            v.sort_unstable();
            v
        };
        let (ids_down, ids_up) = (ids(&to_down), ids(&to_up));
        let has = |v: &[u64], id: u64| v.binary_search(&id).is_ok();
        for &(a, b, h) in saved.iter() {
            for (ids, out) in [(&ids_down, &mut out_down), (&ids_up, &mut out_up)] {
                if has(ids, a) || has(ids, b) {
                    out.extend_from_slice(&[a as f64, b as f64, h[0], h[1], h[2]]);
                    histories += 1;
                }
            }
        }
    }
    p.remove_owned(&leave);
    let (from_down, from_up) = comm.exchange(down, &out_down, up, &out_up);
    let mut received_history = false;
    for msg in [&from_down, &from_up] {
        if msg.is_empty() {
            continue;
        }
        let n = msg[0] as usize;
        let (parts, hist) = msg[1..].split_at(n * PACKED_WORDS);
        for rec in parts.chunks_exact(PACKED_WORDS) {
            p.push_owned(&unpack(rec), mat);
        }
        for rec in hist.chunks_exact(HISTORY_WORDS) {
            saved.push((rec[0] as u64, rec[1] as u64, [rec[2], rec[3], rec[4]]));
            received_history = true;
        }
    }
    if received_history {
        // A contact both sides already evaluated arrives as an identical copy: keep one.
        saved.sort_unstable_by_key(|x| (x.0, x.1));
        saved.dedup_by(|x, y| (x.0, x.1) == (y.0, y.1));
    }
    Migrated {
        particles: sent,
        histories,
    }
}

/// Build the ghost halo: each rank sends the owned particles within `reach` of each face to
/// the neighbour across it, and appends what it receives as ghosts.
pub fn borders(
    p: &mut Particles,
    slabs: &Slabs,
    comm: &dyn Comm,
    mat: &Materials,
    reach: f64,
) -> Halo {
    p.clear_ghosts();
    let me = comm.rank();
    let (down, up) = (slabs.down(me), slabs.up(me));
    let (lo, hi) = slabs.range(me);
    let mut halo = Halo::default();
    for i in 0..p.n_owned {
        let z = p.x[i][2];
        if down.is_some() && z < lo + reach {
            halo.send_down.push(i);
        }
        if up.is_some() && z >= hi - reach {
            halo.send_up.push(i);
        }
    }
    let (mut to_down, mut to_up) = (Vec::new(), Vec::new());
    for &i in &halo.send_down {
        p.pack_ghost(i, &mut to_down);
    }
    for &i in &halo.send_up {
        p.pack_ghost(i, &mut to_up);
    }
    let (from_down, from_up) = comm.exchange(down, &to_down, up, &to_up);
    let last = slabs.size() - 1;
    // Images across the periodic ends sit one drum length away.
    let shift_down = if me == 0 { -slabs.length } else { 0.0 };
    let shift_up = if me == last { slabs.length } else { 0.0 };
    for rec in from_down.chunks_exact(GHOST_WORDS) {
        p.push(&unpack_ghost(rec), mat, shift_down);
    }
    for rec in from_up.chunks_exact(GHOST_WORDS) {
        p.push(&unpack_ghost(rec), mat, shift_up);
    }
    halo.n_from_down = from_down.len() / GHOST_WORDS;
    halo.n_from_up = from_up.len() / GHOST_WORDS;
    halo
}

/// The messages of the ghost updates, kept from step to step so that a step allocates
/// nothing.
#[derive(Debug, Clone, Default)]
pub struct UpdateBuffers {
    to_down: Vec<f64>,
    to_up: Vec<f64>,
    from_down: Vec<f64>,
    from_up: Vec<f64>,
}

/// Refresh the ghosts' positions, velocities and spins from their owners, running `work`
/// on the particles while the messages travel (it must not read the ghosts).
pub fn update_ghosts(
    p: &mut Particles,
    halo: &Halo,
    slabs: &Slabs,
    comm: &dyn Comm,
    bufs: &mut UpdateBuffers,
    work: &mut dyn FnMut(&mut Particles),
) {
    let me = comm.rank();
    let (down, up) = (slabs.down(me), slabs.up(me));
    let UpdateBuffers {
        to_down,
        to_up,
        from_down,
        from_up,
    } = bufs;
    to_down.clear();
    to_up.clear();
    for &i in &halo.send_down {
        p.pack_update(i, to_down);
    }
    for &i in &halo.send_up {
        p.pack_update(i, to_up);
    }
    from_down.resize(halo.n_from_down * UPDATE_WORDS, 0.0);
    from_up.resize(halo.n_from_up * UPDATE_WORDS, 0.0);
    comm.exchange_into(down, to_down, from_down, up, to_up, from_up, &mut || {
        work(p)
    });
    let first = p.n_owned;
    for (k, rec) in from_down.chunks_exact(UPDATE_WORDS).enumerate() {
        p.unpack_update(first + k, rec);
    }
    let first = p.n_owned + halo.n_from_down;
    for (k, rec) in from_up.chunks_exact(UPDATE_WORDS).enumerate() {
        p.unpack_update(first + k, rec);
    }
}
