//! Migration of particles between slabs and the ghost halo, as one mechanism over the
//! [`Comm`] exchange with the two axial neighbours (and, after the slab boundaries moved,
//! the irregular exchange that takes a particle to any rank).
//!
//! Ghosts keep their owner's (wrapped) coordinates bit for bit; a ghost that is a periodic
//! image carries its axial offset in `z_image`, used only for binning. Pair forces use the
//! minimum image of the raw coordinates, so a pair is computed with the same arithmetic
//! whichever of its particles is the ghost.

use super::neighbor::{push_record, read_record, record_words, sort_saved, SavedHistory};
use super::slabs::Slabs;
use crate::comm::Comm;
use crate::particles::{unpack, unpack_ghost, Particles, GHOST_WORDS, UPDATE_WORDS};
use crate::physics::Materials;

/// Which owned particles were sent as ghosts to each neighbour, and where their copies sit.
#[derive(Debug, Clone, Default)]
pub struct Halo {
    send_down: Vec<usize>,
    send_up: Vec<usize>,
    n_from_down: usize,
    n_from_up: usize,
}

impl Halo {
    /// Ghosts this rank holds.
    pub fn ghosts(&self) -> usize {
        self.n_from_down + self.n_from_up
    }

    /// Bytes this rank sends in one refresh of its neighbours' ghosts (once per step).
    pub fn update_bytes(&self) -> usize {
        (self.send_down.len() + self.send_up.len()) * UPDATE_WORDS * std::mem::size_of::<f64>()
    }
}

/// What a migration moved.
#[derive(Debug, Clone, Copy, Default)]
pub struct Migrated {
    /// Particles sent to other ranks.
    pub particles: usize,
    /// Contact histories sent with them.
    pub histories: usize,
    /// Whether the irregular exchange was needed: some particle, on some rank, was owned by a
    /// rank that is not a neighbour of the one holding it.
    pub irregular: bool,
    /// The first particle of this rank that went to a rank other than a neighbour: its id, `z`
    /// and new owner.
    pub far: Option<(u64, f64, usize)>,
}

/// Send every owned particle that left this rank's slab to the rank that now owns it, with
/// the histories of its contacts (`saved`, which receives the other ranks' in turn and stays
/// sorted). Ghosts must have been cleared.
///
/// In a step a particle can only have crossed into a neighbour's slab (slabs are at least the
/// halo width thick and a list is rebuilt before anything moves half the skin), and the
/// exchange is the two-neighbour one. After the boundaries moved (a rebalance), or when a
/// particle really moved past a whole slab, the ranks agree on it (one flag reduced over all
/// of them) and every particle goes straight to its owner in one irregular exchange.
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
    let owners: Vec<usize> = (0..p.n_owned).map(|i| slabs.owner(p.x[i][2])).collect();
    let far = owners
        .iter()
        .enumerate()
        .find(|&(_, &o)| o != me && Some(o) != up && Some(o) != down)
        .map(|(i, &o)| (p.id[i], p.x[i][2], o));
    // with two slabs, or three around periodic ends, every rank neighbours every other
    let all_neighbours = slabs.size() <= 2 || (slabs.size() == 3 && slabs.periodic);
    let irregular = !all_neighbours && !comm.all_ok(far.is_none());
    let leave: Vec<bool> = owners.iter().map(|&o| o != me).collect();
    let sent = leave.iter().filter(|&&l| l).count();
    if down.is_none() && up.is_none() && !irregular {
        assert_eq!(sent, 0, "a particle left the only slab");
        return Migrated::default();
    }
    // One message per destination: particle count, particles, then the histories of their
    // contacts. The neighbour exchange uses slots `down` and `up` only.
    let dest_slot = |o: usize| -> usize {
        if irregular {
            o
        } else if Some(o) == up {
            1
        } else {
            0
        }
    };
    let (words, packed) = (p.hist_words, p.packed_words());
    let n_slots = if irregular { slabs.size() } else { 2 };
    let mut parts: Vec<Vec<f64>> = vec![Vec::new(); n_slots];
    let mut leaving: Vec<(u64, usize)> = Vec::with_capacity(sent);
    for (i, &o) in owners.iter().enumerate() {
        if o != me {
            let slot = dest_slot(o);
            p.pack(i, &mut parts[slot]);
            leaving.push((p.id[i], slot));
        }
    }
    let mut out: Vec<Vec<f64>> = parts
        .iter()
        .map(|m| {
            let mut v = Vec::with_capacity(m.len() + 1);
            v.push((m.len() / packed) as f64);
            v.extend_from_slice(m);
            v
        })
        .collect();
    drop(parts);
    let mut histories = 0;
    if !saved.is_empty() && sent > 0 {
        leaving.sort_unstable();
        let slot_of = |id: u64| {
            leaving
                .binary_search_by_key(&id, |x| x.0)
                .ok()
                .map(|k| leaving[k].1)
        };
        for rec in saved.iter() {
            let (sa, sb) = (slot_of(rec.a), slot_of(rec.b));
            for slot in [sa, sb.filter(|&s| Some(s) != sa)].into_iter().flatten() {
                push_record(&mut out[slot], rec, p.hist_words);
                histories += 1;
            }
        }
    }
    p.remove_owned(&leave);
    let received: Vec<Vec<f64>> = if irregular {
        comm.all_to_all(out)
    } else {
        let (from_down, from_up) = comm.exchange(down, &out[0], up, &out[1]);
        drop(out);
        vec![from_down, from_up]
    };
    let mut received_history = false;
    for msg in &received {
        if msg.is_empty() {
            continue;
        }
        let n = msg[0] as usize;
        let (parts, hist) = msg[1..].split_at(n * packed);
        for rec in parts.chunks_exact(packed) {
            p.push_owned(&unpack(rec, words), mat);
        }
        for rec in hist.chunks_exact(record_words(words)) {
            saved.push(read_record(rec, words));
            received_history = true;
        }
    }
    if received_history {
        // A contact both sides already evaluated arrives as an identical copy: keep one.
        sort_saved(saved);
    }
    Migrated {
        particles: sent,
        histories,
        irregular,
        far,
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
    for (to, send) in [
        (&mut *to_down, &halo.send_down),
        (&mut *to_up, &halo.send_up),
    ] {
        to.resize(send.len() * UPDATE_WORDS, 0.0);
        for (rec, &i) in to.chunks_exact_mut(UPDATE_WORDS).zip(send) {
            p.pack_update(i, rec);
        }
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
