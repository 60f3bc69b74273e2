//! Struct-of-arrays particle storage. The first `n_owned` entries are the particles this rank
//! owns; the rest are ghost copies of neighbours' particles (rebuilt with the halo).

mod history_blocks;
pub mod records;
pub use history_blocks::HistoryBlocks;
pub use records::{Field, Records};

use crate::physics::contact::{History, HISTORY_MAX};
use crate::physics::materials::WALLS;
use crate::physics::Materials;

/// Number of `f64` words of a particle's full state in a message (see [`Particles::pack`])
/// when each contact keeps `words` history words.
pub const fn packed_words(words: usize) -> usize {
    // a ghost's record, the wall histories, force and torque
    GHOST_WORDS + WALLS * words + 6
}

/// The most `f64` words of a particle's full state (with the largest history).
pub const PACKED_WORDS_MAX: usize = packed_words(HISTORY_MAX);
/// Number of `f64` words of a ghost's record at a halo build: what a pair force needs (id,
/// order key, species, diameter, position, velocity, spin), the head of the full record.
pub const GHOST_WORDS: usize = 13;
/// Number of `f64` words of a ghost update (position, velocity, angular velocity).
pub const UPDATE_WORDS: usize = 9;

/// Particles owned by this rank followed by its ghosts.
#[derive(Debug, Clone, Default)]
pub struct Particles {
    /// Number of owned particles (they come first).
    pub n_owned: usize,
    /// Global id, stable for the whole run.
    pub id: Vec<u64>,
    /// Order key: where the particle was at the last sort (`engine::order`); the pair list
    /// and the owned particles' storage follow the order of `(key, id)`.
    pub key: Vec<u64>,
    /// Species index.
    pub species: Vec<u8>,
    /// Diameter.
    pub diameter: Vec<f64>,
    /// `1/m`.
    pub inv_mass: Vec<f64>,
    /// `1/I` with `I = m d^2 / 10`.
    pub inv_inertia: Vec<f64>,
    /// Position (the axial coordinate wrapped into the drum for periodic ends).
    pub x: Vec<[f64; 3]>,
    /// Velocity.
    pub v: Vec<[f64; 3]>,
    /// Angular velocity.
    pub w: Vec<[f64; 3]>,
    /// Force.
    pub f: Vec<[f64; 3]>,
    /// Torque.
    pub t: Vec<[f64; 3]>,
    /// History of the contact with each wall (curved, cap low, cap high, lifter), zero when
    /// not touching: [`WALLS`] slots of [`Self::hist_words`] words per particle, held only for
    /// the particles touching a wall.
    pub wall_hist: HistoryBlocks,
    /// History words per contact (the law's `history_words`).
    pub hist_words: usize,
    /// Axial offset of a ghost's periodic image, used only to bin it (0 for owned particles).
    pub z_image: Vec<f64>,
}

/// One particle's full state, as created or received.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleState {
    /// Global id.
    pub id: u64,
    /// Order key (`engine::order`; 0 before the first sort).
    pub key: u64,
    /// Species index.
    pub species: u8,
    /// Diameter.
    pub diameter: f64,
    /// Position.
    pub x: [f64; 3],
    /// Velocity.
    pub v: [f64; 3],
    /// Angular velocity.
    pub w: [f64; 3],
    /// History with each wall (the first `history_words` of each used).
    pub wall_hist: [History; WALLS],
    /// Force of the last evaluation (what the next half kick uses).
    pub f: [f64; 3],
    /// Torque of the last evaluation.
    pub t: [f64; 3],
}

impl ParticleState {
    /// A particle with no wall contacts.
    pub fn new(id: u64, species: u8, diameter: f64, x: [f64; 3], v: [f64; 3], w: [f64; 3]) -> Self {
        ParticleState {
            id,
            key: 0,
            species,
            diameter,
            x,
            v,
            w,
            wall_hist: [[0.0; HISTORY_MAX]; WALLS],
            f: [0.0; 3],
            t: [0.0; 3],
        }
    }
}

impl Particles {
    /// No particles yet; contacts keep `hist_words` words of history.
    pub fn new(hist_words: usize) -> Self {
        Particles {
            hist_words,
            wall_hist: HistoryBlocks::new(WALLS * hist_words),
            ..Default::default()
        }
    }

    /// Words of this store's full-state record ([`Self::pack`]).
    pub fn packed_words(&self) -> usize {
        packed_words(self.hist_words)
    }

    /// Number of owned + ghost particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    /// Whether there are no particles at all.
    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Append a particle (owned if no ghosts exist yet; callers keep owned ones first).
    pub fn push(&mut self, p: &ParticleState, mat: &Materials, z_image: f64) {
        let m = mat.mass(p.diameter);
        // particles fixed to the drum have infinite mass: kicks leave them alone and a
        // contact with one has the mobile particle's mass as m_eff, as with a wall
        let fixed = crate::physics::rough_wall::is_fixed(p.species);
        self.id.push(p.id);
        self.key.push(p.key);
        self.species.push(p.species);
        self.diameter.push(p.diameter);
        self.inv_mass.push(if fixed { 0.0 } else { 1.0 / m });
        self.inv_inertia.push(if fixed {
            0.0
        } else {
            1.0 / (0.1 * m * p.diameter * p.diameter)
        });
        self.x.push(p.x);
        self.v.push(p.v);
        self.w.push(p.w);
        self.f.push(p.f);
        self.t.push(p.t);
        let w = self.hist_words;
        let mut h = [0.0; WALLS * HISTORY_MAX];
        for (k, slot) in p.wall_hist.iter().enumerate() {
            h[k * w..(k + 1) * w].copy_from_slice(&slot[..w]);
        }
        self.wall_hist.push(&h[..WALLS * w]);
        self.z_image.push(z_image);
    }

    /// Append an owned particle; no ghosts may be present.
    pub fn push_owned(&mut self, p: &ParticleState, mat: &Materials) {
        debug_assert_eq!(self.n_owned, self.len());
        self.push(p, mat, 0.0);
        self.n_owned += 1;
    }

    /// The state of particle `i`.
    pub fn state(&self, i: usize) -> ParticleState {
        ParticleState {
            id: self.id[i],
            key: self.key[i],
            species: self.species[i],
            diameter: self.diameter[i],
            x: self.x[i],
            v: self.v[i],
            w: self.w[i],
            wall_hist: self.wall_hist_of(i),
            f: self.f[i],
            t: self.t[i],
        }
    }

    fn wall_hist_of(&self, i: usize) -> [History; WALLS] {
        let w = self.hist_words;
        let mut out = [[0.0; HISTORY_MAX]; WALLS];
        if let Some(h) = self.wall_hist.get(i) {
            for (k, slot) in out.iter_mut().enumerate() {
                slot[..w].copy_from_slice(&h[k * w..(k + 1) * w]);
            }
        }
        out
    }

    /// Drop every ghost.
    pub fn clear_ghosts(&mut self) {
        self.truncate(self.n_owned);
    }

    /// Give back the arrays' spare capacity (after a migration, a halo build, a pour's cut:
    /// pushing one by one leaves up to as much again unused). With hysteresis: an array is
    /// shrunk only when more than a quarter of its capacity (and 64 entries) is spare, and
    /// keeps a sixteenth of room to grow, so that the halo's small changes from one build
    /// to the next do not reallocate every time.
    pub fn trim(&mut self) {
        trim(&mut self.id);
        trim(&mut self.key);
        trim(&mut self.species);
        trim(&mut self.diameter);
        trim(&mut self.inv_mass);
        trim(&mut self.inv_inertia);
        trim(&mut self.x);
        trim(&mut self.v);
        trim(&mut self.w);
        trim(&mut self.f);
        trim(&mut self.t);
        self.wall_hist.trim();
        trim(&mut self.z_image);
    }

    fn truncate(&mut self, n: usize) {
        self.id.truncate(n);
        self.key.truncate(n);
        self.species.truncate(n);
        self.diameter.truncate(n);
        self.inv_mass.truncate(n);
        self.inv_inertia.truncate(n);
        self.x.truncate(n);
        self.v.truncate(n);
        self.w.truncate(n);
        self.f.truncate(n);
        self.t.truncate(n);
        self.wall_hist.truncate(n);
        self.z_image.truncate(n);
    }

    /// Remove the owned particles whose `leave` flag is set (ghosts must be cleared first),
    /// keeping the others in their order.
    pub fn remove_owned(&mut self, leave: &[bool]) {
        debug_assert_eq!(self.n_owned, self.len());
        let mut k = 0;
        for i in 0..self.n_owned {
            if !leave[i] {
                if k != i {
                    self.id[k] = self.id[i];
                    self.key[k] = self.key[i];
                    self.species[k] = self.species[i];
                    self.diameter[k] = self.diameter[i];
                    self.inv_mass[k] = self.inv_mass[i];
                    self.inv_inertia[k] = self.inv_inertia[i];
                    self.x[k] = self.x[i];
                    self.v[k] = self.v[i];
                    self.w[k] = self.w[i];
                    self.f[k] = self.f[i];
                    self.t[k] = self.t[i];
                }
                k += 1;
            }
        }
        self.wall_hist
            .select((0..self.n_owned).filter(|&i| !leave[i]));
        self.truncate(k);
        self.n_owned = k;
    }

    /// Put the owned particles (no ghosts may be present) in the order of `(key, id)`, so
    /// that particles near each other in the drum are near each other in memory.
    pub fn sort_owned(&mut self) {
        debug_assert_eq!(self.n_owned, self.len());
        let mut order: Vec<u32> = (0..self.n_owned as u32).collect();
        order.sort_unstable_by_key(|&i| (self.key[i as usize], self.id[i as usize]));
        if order.iter().enumerate().all(|(k, &i)| k == i as usize) {
            return;
        }
        fn gather<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            *v = order.iter().map(|&i| v[i as usize]).collect();
        }
        gather(&mut self.id, &order);
        gather(&mut self.key, &order);
        gather(&mut self.species, &order);
        gather(&mut self.diameter, &order);
        gather(&mut self.inv_mass, &order);
        gather(&mut self.inv_inertia, &order);
        gather(&mut self.x, &order);
        gather(&mut self.v, &order);
        gather(&mut self.w, &order);
        gather(&mut self.f, &order);
        gather(&mut self.t, &order);
        gather(&mut self.z_image, &order);
        self.wall_hist.select(order.iter().map(|&i| i as usize));
    }

    /// Append particle `i`'s full state to a message buffer ([`Self::packed_words`] words).
    pub fn pack(&self, i: usize, buf: &mut Vec<f64>) {
        self.pack_ghost(i, buf);
        self.wall_hist.extend_into(i, buf);
        buf.extend_from_slice(&self.f[i]);
        buf.extend_from_slice(&self.t[i]);
    }

    /// Append what a ghost of particle `i` needs (the first [`GHOST_WORDS`] of its record).
    pub fn pack_ghost(&self, i: usize, buf: &mut Vec<f64>) {
        buf.push(self.id[i] as f64);
        buf.push(self.key[i] as f64);
        buf.push(self.species[i] as f64);
        buf.push(self.diameter[i]);
        buf.extend_from_slice(&self.x[i]);
        buf.extend_from_slice(&self.v[i]);
        buf.extend_from_slice(&self.w[i]);
    }

    /// Write particle `i`'s moving state (position, velocity, spin) into a ghost-update
    /// record of a message.
    #[inline]
    pub fn pack_update(&self, i: usize, rec: &mut [f64]) {
        rec[0..3].copy_from_slice(&self.x[i]);
        rec[3..6].copy_from_slice(&self.v[i]);
        rec[6..9].copy_from_slice(&self.w[i]);
    }

    /// Overwrite particle `i`'s moving state from a ghost-update record.
    #[inline]
    pub fn unpack_update(&mut self, i: usize, rec: &[f64]) {
        self.x[i].copy_from_slice(&rec[0..3]);
        self.v[i].copy_from_slice(&rec[3..6]);
        self.w[i].copy_from_slice(&rec[6..9]);
    }
}

/// Give back a vector's spare capacity when more than a quarter of it (and 64 entries) is
/// spare, keeping a sixteenth of room to grow ([`Particles::trim`]).
fn trim<T>(v: &mut Vec<T>) {
    let (len, cap) = (v.len(), v.capacity());
    if cap > len + len / 4 + 64 {
        v.shrink_to(len + len / 16);
    }
}

/// Decode one ghost record written by [`Particles::pack_ghost`].
pub fn unpack_ghost(rec: &[f64]) -> ParticleState {
    let v3 = |k: usize| [rec[k], rec[k + 1], rec[k + 2]];
    let mut s = ParticleState::new(rec[0] as u64, rec[2] as u8, rec[3], v3(4), v3(7), v3(10));
    s.key = rec[1] as u64;
    s
}

/// Decode one full-state record written by [`Particles::pack`] with `words` history words
/// per contact.
pub fn unpack(rec: &[f64], words: usize) -> ParticleState {
    let v3 = |k: usize| [rec[k], rec[k + 1], rec[k + 2]];
    // the head of the record is a ghost's
    let mut s = unpack_ghost(&rec[..GHOST_WORDS]);
    for (k, h) in s.wall_hist.iter_mut().enumerate() {
        let at = GHOST_WORDS + words * k;
        h[..words].copy_from_slice(&rec[at..at + words]);
    }
    let tail = GHOST_WORDS + words * WALLS;
    s.f = v3(tail);
    s.t = v3(tail + 3);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sort_owned_moves_every_field_of_a_particle_together() {
        let case = crate::case::parse_case(include_str!("../cases/quickstart.toml"), "quickstart")
            .unwrap();
        let mat = Materials::new(&case);
        let mut p = Particles::new(3);
        // keys out of order, two equal keys ordered by id
        for (id, key) in [(0u64, 9u64), (1, 2), (2, 9), (3, 0), (4, 2)] {
            let f = id as f64;
            let mut s = ParticleState::new(id, 0, 1.0 + f, [f; 3], [2.0 * f; 3], [3.0 * f; 3]);
            s.key = key;
            s.f = [4.0 * f; 3];
            s.t = [5.0 * f; 3];
            s.wall_hist = [[6.0 * f; HISTORY_MAX]; WALLS];
            p.push_owned(&s, &mat);
        }
        let before: Vec<ParticleState> = (0..p.len()).map(|i| p.state(i)).collect();
        p.sort_owned();
        assert_eq!(p.id, vec![3, 1, 4, 0, 2]);
        for i in 0..p.len() {
            let s = p.state(i);
            let mut want = before[s.id as usize];
            for h in want.wall_hist.iter_mut() {
                h[3..].fill(0.0);
            }
            assert_eq!(s, want);
            assert_eq!(
                p.inv_mass[i].to_bits(),
                (1.0 / mat.mass(s.diameter)).to_bits()
            );
        }
    }
}
