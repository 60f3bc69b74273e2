//! Cell lists and a Verlet half list of pairs in a canonical order.
//!
//! Particles are ordered by their *rank* `(key, id)` ([`rank_of`]; the keys, from
//! `engine::order`, follow where the particles were at the last sort). Each pair is stored
//! once per rank as `(a, b)` local indices with `id[a] < id[b]` (its orientation, which the
//! force arithmetic and the history follow), and the list is sorted by the ranks of its two
//! particles, lower first: each particle's block of partners of higher rank, the blocks in
//! order of rank (except where a rank holds a particle and its own periodic image: each
//! copy's block of pairs then follows the other). Accumulating pair forces in list order then
//! adds every particle's contributions in increasing order of its partners' ranks, whatever
//! the slab layout: the key to bit-identical states on any number of ranks.
//!
//! Tangential histories live beside the pairs, in the pair's orientation. At a rebuild they
//! are saved as a list in the list's order ([`SavedHistory`]), travel with migrating
//! particles, and are re-attached to the new list by one merge of the two sorted lists
//! (with a search where the list steps back, see [`NeighborList::save_histories`]).

use crate::engine::forces::Isa;
use crate::particles::{HistoryBlocks, Particles};
use crate::physics::contact::History;
use crate::physics::integrate::min_image;
use crate::physics::rough_wall::is_fixed;
use crate::physics::{ContactLaw, DrumWalls};

/// Cells searched on each side of a particle's own: cells are at least `reach / SPAN` wide,
/// so a particle's `(2 SPAN + 1)^3` cells hold every partner within `reach`, in a smaller
/// volume than 27 cells of `reach` (about 58 % of it for `SPAN = 2`).
pub const SPAN: usize = 2;

/// Bytes the list's build keeps per local particle (owned or ghost) from one build to the
/// next, besides the pairs: each particle's cell, the particles sorted by cell, the order of
/// rank and each particle's place in it (4 words of 4 B), and the search's slots (position
/// and half distance, place in the order of rank, flags). For `tumbler check`'s estimate.
pub const SCRATCH_BYTES: usize = 4 * 4 + 4 * 8 + 4 + 1;

/// Bytes per cell of the grid during a build: each cell's start in the sorted particles, and
/// the counting sort's copy of it. For `tumbler check`'s estimate.
pub const CELL_BYTES: usize = 2 * 4;

/// Candidates the neighbour search tests at once (a row of cells is a contiguous run of slots,
/// tested a block at a time).
const BLOCK: usize = 8;

/// Which of the [`BLOCK`] slots from `b` are closer to `xi` than their reach plus `skin`
/// (bit `l` for slot `b + l`). Written as lanes: each is the scalar test, so the same pairs
/// are found whatever the vector width.
#[inline(always)]
fn close_block(slot_x: &[Vec<f64>; 4], b: usize, xi: [f64; 3], half_i: f64, skin: f64) -> u32 {
    let lane = |k: usize| -> &[f64; BLOCK] {
        slot_x[k][b..b + BLOCK]
            .try_into()
            .expect("the slots are padded by a block")
    };
    let (x, y, z, h) = (lane(0), lane(1), lane(2), lane(3));
    let mut close = 0;
    for l in 0..BLOCK {
        let dx = xi[0] - x[l];
        let dy = xi[1] - y[l];
        let dz = xi[2] - z[l];
        // the list's range needs no last-bit care: a pair near it is a skin away from touching
        let reach = half_i + h[l] + skin;
        close |= ((dx * dx + dy * dy + dz * dz < reach * reach) as u32) << l;
    }
    close
}

/// Make `v` hold `n` copies of `value`, its capacity grown to no more than `n`.
fn refill<T: Copy>(v: &mut Vec<T>, n: usize, value: T) {
    v.clear();
    v.reserve_exact(n);
    v.resize(n, value);
}

/// A particle's place in the canonical order: its order key, then its id.
#[inline]
pub fn rank_of(key: u64, id: u64) -> u128 {
    (key as u128) << 64 | id as u128
}

/// The history of one contact in force: the pair's ids `a < b`, their order keys, and the
/// history (the first `ContactLaw::history_words` words used).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SavedContact {
    /// The lower id.
    pub a: u64,
    /// The higher id.
    pub b: u64,
    /// The order key of `a`.
    pub key_a: u64,
    /// The order key of `b`.
    pub key_b: u64,
    /// The history, in the orientation from `a` to `b`.
    pub h: History,
}

impl SavedContact {
    /// A contact between ids `a < b` whose keys are not known yet (0).
    pub fn new(a: u64, b: u64, h: History) -> Self {
        SavedContact {
            a,
            b,
            key_a: 0,
            key_b: 0,
            h,
        }
    }

    /// The place of the contact's pair in a list: the ranks of its two particles, lower first.
    #[inline]
    pub fn order(&self) -> (u128, u128) {
        pair_order(rank_of(self.key_a, self.a), rank_of(self.key_b, self.b))
    }

    /// The pair's ids.
    pub fn ids(&self) -> (u64, u64) {
        (self.a, self.b)
    }
}

/// The place of a pair of particles of ranks `ra` and `rb` in a list.
#[inline]
fn pair_order(ra: u128, rb: u128) -> (u128, u128) {
    (ra.min(rb), ra.max(rb))
}

/// Histories of the contacts in force, each once, sorted by [`SavedContact::order`] (the
/// order of the pair list).
pub type SavedHistory = Vec<SavedContact>;

/// Sort saved histories into the list's order and keep one of each contact (a contact held
/// by two ranks arrives twice, identical).
pub fn sort_saved(saved: &mut SavedHistory) {
    saved.sort_unstable_by_key(SavedContact::order);
    saved.dedup_by_key(|x| x.order());
}

/// Words of one saved history in a message: both ids and both keys, then `words` history
/// words.
pub const fn record_words(words: usize) -> usize {
    4 + words
}

/// Append one saved history to a message (ids and keys as `f64`: exact below 2^53).
pub fn push_record(buf: &mut Vec<f64>, c: &SavedContact, words: usize) {
    buf.push(c.a as f64);
    buf.push(c.b as f64);
    buf.push(c.key_a as f64);
    buf.push(c.key_b as f64);
    buf.extend_from_slice(&c.h[..words]);
}

/// Decode one saved history written by [`push_record`].
pub fn read_record(rec: &[f64], words: usize) -> SavedContact {
    let mut h = History::default();
    h[..words].copy_from_slice(&rec[4..4 + words]);
    SavedContact {
        a: rec[0] as u64,
        b: rec[1] as u64,
        key_a: rec[2] as u64,
        key_b: rec[3] as u64,
        h,
    }
}

/// The pair list and what is needed to decide when to rebuild it.
#[derive(Debug, Clone, Default)]
pub struct NeighborList {
    /// Candidate pairs `(a, b)`, `id[a] < id[b]`, in the canonical order (see the module).
    pub pairs: Vec<(u32, u32)>,
    /// History of each pair, in list order: [`Self::words`] words, held only for the pairs
    /// whose history is not zero (those in contact).
    pub hist: HistoryBlocks,
    /// History words per pair (the law's `history_words`: 0, 3 or 6).
    pub words: usize,
    /// Square of each pair's contact distance at full size (the law's cutoff), so that the
    /// force loop rejects a listed pair that does not touch without asking the law.
    pub cut2: Vec<f64>,
    /// Positions of the owned particles when the list was built.
    x_build: Vec<[f64; 3]>,
    /// The owned mobile particles within reach of a wall at the last build, plus the skin:
    /// the only ones that can touch a wall before the next build.
    pub near_walls: Vec<u32>,
    /// Scratch of the pair pass (`engine::forces`): the list indices of the touching pairs.
    pub(crate) touch: Vec<u32>,
    /// The list indices of the pairs that touched at the last batched pair pass over this
    /// list, in list order, when known (`None` after a build, or after the reference pass):
    /// the only pairs whose history can be nonzero and not touch now, so the pass clears
    /// histories by a merge with it instead of reading every listed pair's history.
    pub(crate) touched_before: Option<Vec<u32>>,
    /// A spare buffer for `touched_before`, kept to reuse its allocation.
    pub(crate) touched_spare: Vec<u32>,
    /// Scratch: particles sorted by cell, and each cell's start in it.
    cell_items: Vec<u32>,
    cell_start: Vec<u32>,
    cell_of: Vec<u32>,
    /// Scratch: local indices in order of rank, each particle's place in that order (its
    /// rank as a 32-bit number: the search compares these), and one particle's partners.
    by_rank: Vec<u32>,
    ord: Vec<u32>,
    partners: Vec<(u32, u32)>,
    /// Scratch, in cell order (beside `cell_items`), what the search reads of a candidate:
    /// binning position and half its contact distance with its own kind, place in the order
    /// of rank (`ord`), and flags (1: owned, 2: fixed to the wall).
    /// (The positions and half distances are stored by coordinate, with [`BLOCK`] slots of
    /// padding that touch nothing, for the search's blocks of [`BLOCK`] candidates.)
    slot_x: [Vec<f64>; 4],
    slot_ord: Vec<u32>,
    slot_flags: Vec<u8>,
}

/// The box of cells covering a slab and its halo.
#[derive(Debug, Clone, Copy)]
pub struct Grid {
    /// Lower corner.
    pub lo: [f64; 3],
    /// Cells along each axis.
    pub n: [usize; 3],
    /// Cell size along each axis (at least the reach).
    pub size: [f64; 3],
}

impl Grid {
    /// Cells of size at least `reach` over `x, y` in `[-radius, radius]`, `z` in `[z_lo, z_hi]`.
    pub fn new(radius: f64, z_lo: f64, z_hi: f64, reach: f64) -> Self {
        Self::over([-radius, -radius, z_lo], [radius, radius, z_hi], reach)
    }

    /// Cells of size at least `reach` over the box `[lo, hi]`.
    pub fn over(lo: [f64; 3], hi: [f64; 3], reach: f64) -> Self {
        let mut n = [1usize; 3];
        let mut size = [0.0; 3];
        for k in 0..3 {
            let span = (hi[k] - lo[k]).max(reach);
            n[k] = ((span / reach).floor() as usize).max(1);
            size[k] = span / n[k] as f64;
        }
        Grid { lo, n, size }
    }

    /// Cells of size at least `reach` over the bounding box of `p`'s particles (their binning
    /// coordinates) within `[limit_lo, limit_hi]`, so that the grid grows with the particles,
    /// not with the drum, and a particle flung far out (a run about to be stopped as
    /// unhealthy) cannot make it huge: such a particle is binned in an edge cell.
    pub fn around(p: &Particles, reach: f64, limit_lo: [f64; 3], limit_hi: [f64; 3]) -> Self {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for (x, zi) in p.x.iter().zip(&p.z_image) {
            let c = [x[0], x[1], x[2] + zi];
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        if p.is_empty() {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        for k in 0..3 {
            lo[k] = lo[k].clamp(limit_lo[k], limit_hi[k]);
            hi[k] = hi[k].clamp(limit_lo[k], limit_hi[k]);
        }
        Self::over(lo, hi, reach)
    }

    fn coord(&self, x: f64, k: usize) -> usize {
        let c = ((x - self.lo[k]) / self.size[k]).floor();
        if c < 0.0 {
            0
        } else {
            (c as usize).min(self.n[k] - 1)
        }
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }
}

impl NeighborList {
    /// Rebuild the list from the owned and ghost particles of `p`. A pair is kept when the
    /// centres are closer than its interaction range plus `skin`.
    pub fn build(&mut self, p: &Particles, grid: &Grid, skin: f64, law: &ContactLaw) {
        self.build_with(Isa::detect(), p, grid, skin, law)
    }

    /// [`Self::build`] compiled for a chosen instruction set (at most this CPU's; every
    /// choice lists the same pairs in the same order).
    pub fn build_with(
        &mut self,
        isa: Isa,
        p: &Particles,
        grid: &Grid,
        skin: f64,
        law: &ContactLaw,
    ) {
        match isa.min(Isa::of_cpu()) {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: this CPU has AVX-512 (`Isa::of_cpu`).
            Isa::Avx512 => unsafe { self.build_avx512(p, grid, skin, law) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: this CPU has AVX2 (`Isa::of_cpu`).
            Isa::Avx2 => unsafe { self.build_avx2(p, grid, skin, law) },
            _ => self.build_any(p, grid, skin, law),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    unsafe fn build_avx512(&mut self, p: &Particles, grid: &Grid, skin: f64, law: &ContactLaw) {
        self.build_any(p, grid, skin, law)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn build_avx2(&mut self, p: &Particles, grid: &Grid, skin: f64, law: &ContactLaw) {
        self.build_any(p, grid, skin, law)
    }

    /// The build itself, inlined into each instruction set's copy (the same pairs from every
    /// copy: the distance tests are exact comparisons of the same arithmetic).
    #[inline(always)]
    fn build_any(&mut self, p: &Particles, grid: &Grid, skin: f64, law: &ContactLaw) {
        let n = p.len();
        let ncell = grid.n[0] * grid.n[1] * grid.n[2];
        // The scratch is sized for this build (`reserve_exact`, not grown by doubling):
        // `SCRATCH_BYTES` a particle, `CELL_BYTES` a cell.
        self.cell_of.clear();
        self.cell_of.reserve_exact(n);
        self.cell_of.extend((0..n).map(|i| {
            let x = p.x[i];
            grid.index([
                grid.coord(x[0], 0),
                grid.coord(x[1], 1),
                grid.coord(x[2] + p.z_image[i], 2),
            ]) as u32
        }));
        // Counting sort of particles by cell.
        refill(&mut self.cell_start, ncell + 1, 0);
        for &c in &self.cell_of {
            self.cell_start[c as usize + 1] += 1;
        }
        for c in 0..ncell {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        refill(&mut self.cell_items, n, 0);
        let mut fill = self.cell_start.clone();
        for (i, &c) in self.cell_of.iter().enumerate() {
            self.cell_items[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        // the order of rank, and each particle's place in it
        self.by_rank.clear();
        self.by_rank.reserve_exact(n);
        self.by_rank.extend(0..n as u32);
        self.by_rank
            .sort_unstable_by_key(|&i| rank_of(p.key[i as usize], p.id[i as usize]));
        refill(&mut self.ord, n, 0);
        for (k, &i) in self.by_rank.iter().enumerate() {
            self.ord[i as usize] = k as u32;
        }
        // what the search needs of each candidate, contiguous in cell order
        let half = |i: usize| 0.5 * law.cutoff(p.diameter[i], p.diameter[i]);
        for v in &mut self.slot_x {
            v.clear();
            v.reserve_exact(n + BLOCK);
        }
        self.slot_ord.clear();
        self.slot_ord.reserve_exact(n);
        self.slot_flags.clear();
        self.slot_flags.reserve_exact(n);
        for &j in &self.cell_items {
            let j = j as usize;
            let x = p.x[j];
            let slot = [x[0], x[1], x[2] + p.z_image[j], half(j)];
            for (v, c) in self.slot_x.iter_mut().zip(slot) {
                v.push(c);
            }
            self.slot_ord.push(self.ord[j]);
            self.slot_flags
                .push((j < p.n_owned) as u8 | (2 * is_fixed(p.species[j]) as u8));
        }
        // padding for the last block: NaN is close to nothing
        for v in &mut self.slot_x {
            v.resize(v.len() + BLOCK, f64::NAN);
        }

        // Pairs are generated in canonical order: particles (owned and ghosts) in order of
        // rank, each with its partners of higher rank in order of rank. A pair is listed when
        // at least one of the two is owned: a pair with a ghost is also computed where the
        // ghost is owned (which may be this rank, for a periodic image of its own particle),
        // with the same arithmetic.
        self.pairs.clear();
        self.cut2.clear();
        for &i in &self.by_rank {
            let i = i as usize;
            let owned_i = i < p.n_owned;
            let fixed_i = is_fixed(p.species[i]);
            let (ord_i, half_i) = (self.ord[i], half(i));
            let xi = p.x[i];
            let zi = xi[2] + p.z_image[i];
            let c = [
                grid.coord(xi[0], 0),
                grid.coord(xi[1], 1),
                grid.coord(zi, 2),
            ];
            let range = |k: usize| c[k].saturating_sub(SPAN)..=(c[k] + SPAN).min(grid.n[k] - 1);
            // candidates are written always and kept (the count advanced) when they qualify:
            // no branch to mispredict in the inner loop
            let mut m = 0;
            // cells along x are adjacent in the cell order: one contiguous run of slots per row
            let (x_lo, x_hi) = (*range(0).start(), *range(0).end());
            for cz in range(2) {
                for cy in range(1) {
                    let s = self.cell_start[grid.index([x_lo, cy, cz])] as usize;
                    let e = self.cell_start[grid.index([x_hi, cy, cz]) + 1] as usize;
                    if self.partners.len() < m + (e - s) {
                        self.partners.resize(m + (e - s), (0, 0));
                    }
                    // the row's slots a block at a time: the distance test in lanes, then
                    // the few close ones one by one
                    for b in (s..e).step_by(BLOCK) {
                        let mut close =
                            close_block(&self.slot_x, b, [xi[0], xi[1], zi], half_i, skin);
                        if e - b < BLOCK {
                            close &= (1 << (e - b)) - 1;
                        }
                        while close != 0 {
                            let s = b + close.trailing_zeros() as usize;
                            close &= close - 1;
                            let ord_j = self.slot_ord[s];
                            let flags = self.slot_flags[s];
                            // higher ranks only; a ghost pairs only with owned particles; wall
                            // particles do not touch each other
                            let keep = (ord_j > ord_i)
                                & (owned_i | (flags & 1 != 0))
                                & !(fixed_i & (flags & 2 != 0));
                            self.partners[m] = (ord_j, self.cell_items[s]);
                            m += keep as usize;
                        }
                    }
                }
            }
            let partners = &mut self.partners[..m];
            partners.sort_unstable();
            for &(_, j) in partners.iter() {
                // oriented by id
                let (a, b) = if p.id[i] < p.id[j as usize] {
                    (i as u32, j)
                } else {
                    (j, i as u32)
                };
                self.pairs.push((a, b));
                let c = law.cutoff(p.diameter[a as usize], p.diameter[b as usize]);
                self.cut2.push(c * c);
            }
        }
        self.release_build_scratch();
        self.x_build.clear();
        self.x_build.extend_from_slice(&p.x[..p.n_owned]);
        self.words = law.history_words();
        if self.hist.width() != self.words {
            self.hist = HistoryBlocks::new(self.words);
        }
        self.hist.reset(self.pairs.len());
        self.forget_touching();
    }

    /// Forget which pairs touched at the last pass (the list or its histories changed).
    pub(crate) fn forget_touching(&mut self) {
        if let Some(v) = self.touched_before.take() {
            self.touched_spare = v;
        }
    }

    /// Free the build's scratch (cells, slots, the order by rank, about 70 bytes per particle
    /// and 4 per cell): kept between builds, it would add to the peak of what comes between
    /// them (a checkpoint's or a snapshot's particles in id order). The next build allocates
    /// it again (its big blocks are mapped and unmapped, see `run::return_freed_memory`).
    fn release_build_scratch(&mut self) {
        for v in [
            &mut self.cell_items,
            &mut self.cell_start,
            &mut self.cell_of,
            &mut self.by_rank,
            &mut self.ord,
        ] {
            *v = Vec::new();
        }
        self.partners = Vec::new();
        self.slot_x = Default::default();
        self.slot_ord = Vec::new();
        self.slot_flags = Vec::new();
    }

    /// List the owned mobile particles that may touch a wall before the next build (closer to
    /// it than their reach plus half the `skin`: a build comes before any particle has moved
    /// half the skin, and the walls' shapes do not change as the drum turns, lifters aside,
    /// which are tested over the whole annulus they sweep), and clear the wall histories of the
    /// others, which touch no wall. A particle's reach is taken at full size, so the list
    /// holds while a pour grows the particles.
    pub fn list_near_walls(
        &mut self,
        p: &mut Particles,
        walls: &DrumWalls,
        law: &ContactLaw,
        skin: f64,
    ) {
        self.near_walls.clear();
        for i in 0..p.n_owned {
            if is_fixed(p.species[i]) {
                continue;
            }
            if walls.near(p.x[i], law.wall_reach(p.diameter[i]) + 0.5 * skin) {
                self.near_walls.push(i as u32);
            } else {
                p.wall_hist.clear(i);
            }
        }
    }

    /// The histories of the contacts in force, in the list's order, each contact once, with
    /// the particles' keys of `p` (new ones, at a sort).
    ///
    /// With periodic ends a rank may hold a particle and its own image: a contact across the
    /// ends is then listed twice, as (owned, image) and (image, owned), after the blocks of
    /// pairs of each copy, so the list is not sorted there. Both copies evaluate the
    /// minimum image of the same raw coordinates and keep the same history, bit for bit.
    pub fn save_histories(&self, p: &Particles) -> SavedHistory {
        if self.words == 0 {
            return SavedHistory::new();
        }
        let mut saved: SavedHistory = self
            .pairs
            .iter()
            .zip(self.hist.iter_in_use())
            .filter_map(|(pair, h)| h.map(|h| (pair, h)))
            .map(|(&(a, b), h)| {
                let (a, b) = (a as usize, b as usize);
                let mut w = History::default();
                w[..h.len()].copy_from_slice(h);
                SavedContact {
                    a: p.id[a],
                    b: p.id[b],
                    key_a: p.key[a],
                    key_b: p.key[b],
                    h: w,
                }
            })
            .collect();
        sort_saved(&mut saved);
        saved
    }

    /// Number of pairs with a history ([`NeighborList::save_histories`] saves them).
    pub fn history_count(&self) -> usize {
        if self.words == 0 {
            return 0;
        }
        self.hist.iter_in_use().flatten().count()
    }

    /// Give each pair of a freshly built list its saved history (`saved` in the list's
    /// order, each contact once); saved contacts without a pair here are dropped.
    pub fn attach_histories(&mut self, p: &Particles, saved: &SavedHistory) {
        self.forget_touching();
        if saved.is_empty() || self.words == 0 {
            return;
        }
        let words = self.words;
        // one merge of two sorted lists, stepping back by a search where the list is not
        // sorted (the second copy's block of a particle and its own image)
        let mut k = 0;
        let mut last = (0, 0);
        let rank = |i: u32| rank_of(p.key[i as usize], p.id[i as usize]);
        for (i, pair) in self.pairs.iter().enumerate() {
            let key = pair_order(rank(pair.0), rank(pair.1));
            if key < last {
                k = saved.partition_point(|x| x.order() < key);
            }
            last = key;
            while k < saved.len() && saved[k].order() < key {
                k += 1;
            }
            if k < saved.len() && saved[k].order() == key {
                self.hist.set(i, &saved[k].h[..words]);
            }
        }
    }

    /// Largest displacement of an owned particle since the last build; NaN if some
    /// displacement is not finite.
    pub fn max_displacement(&self, p: &Particles, period: Option<f64>) -> f64 {
        let d2 = |x: &[f64; 3], x0: &[f64; 3]| {
            let dx = x[0] - x0[0];
            let dy = x[1] - x0[1];
            let mut dz = x[2] - x0[2];
            if let Some(l) = period {
                dz = min_image(dz, l);
            }
            dx * dx + dy * dy + dz * dz
        };
        // Lanes of running maxima and a finiteness test apart from them, so that the loop
        // is not one chain of dependent comparisons (a maximum is the same in any order).
        const LANES: usize = 4;
        let n = p.n_owned.min(self.x_build.len());
        let (x, x0) = (&p.x[..n], &self.x_build[..n]);
        let mut m2 = [0.0f64; LANES];
        let mut finite = true;
        let (xc, x0c) = (x.chunks_exact(LANES), x0.chunks_exact(LANES));
        let (xr, x0r) = (xc.remainder(), x0c.remainder());
        for (a, b) in xc.zip(x0c) {
            for k in 0..LANES {
                let d = d2(&a[k], &b[k]);
                finite &= d.is_finite();
                m2[k] = if d > m2[k] { d } else { m2[k] };
            }
        }
        for (k, (a, b)) in xr.iter().zip(x0r).enumerate() {
            let d = d2(a, b);
            finite &= d.is_finite();
            m2[k] = if d > m2[k] { d } else { m2[k] };
        }
        if !finite {
            return f64::NAN;
        }
        m2.into_iter().fold(0.0, f64::max).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The displacement as one loop in order would find it.
    fn one_by_one(x: &[[f64; 3]], x0: &[[f64; 3]], period: Option<f64>) -> f64 {
        let mut m2: f64 = 0.0;
        for (a, b) in x.iter().zip(x0) {
            let mut dz = a[2] - b[2];
            if let Some(l) = period {
                dz = min_image(dz, l);
            }
            let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + dz * dz;
            if !d2.is_finite() {
                return f64::NAN;
            }
            m2 = m2.max(d2);
        }
        m2.sqrt()
    }

    fn with(x: Vec<[f64; 3]>, x0: Vec<[f64; 3]>) -> (Particles, NeighborList) {
        let p = Particles {
            n_owned: x.len(),
            x,
            ..Particles::default()
        };
        let nl = NeighborList {
            x_build: x0,
            ..NeighborList::default()
        };
        (p, nl)
    }

    #[test]
    fn the_largest_displacement_is_found_in_every_lane_and_the_remainder() {
        for n in 0..12 {
            for far in 0..n {
                let x0: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.5, -0.25]).collect();
                let mut x = x0.clone();
                for (i, xi) in x.iter_mut().enumerate() {
                    xi[0] += 1e-3 * (i % 3) as f64;
                    xi[2] -= 1e-4 * i as f64;
                }
                x[far][1] += 0.25;
                let (p, nl) = with(x.clone(), x0.clone());
                for period in [None, Some(4.0)] {
                    let m = nl.max_displacement(&p, period);
                    assert_eq!(m.to_bits(), one_by_one(&x, &x0, period).to_bits());
                    assert!(m >= 0.25, "n = {n}, far = {far}: {m}");
                }
            }
        }
    }

    #[test]
    fn a_position_that_is_not_finite_anywhere_gives_nan() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for n in 1..10 {
                for at in 0..n {
                    let x0 = vec![[0.0; 3]; n];
                    let mut x = x0.clone();
                    x[at][at % 3] = bad;
                    let (p, nl) = with(x, x0);
                    assert!(
                        nl.max_displacement(&p, None).is_nan(),
                        "{bad} at {at} of {n}"
                    );
                }
            }
        }
    }
}
