//! Contact histories held only for the contacts that have one.
//!
//! Of a drum bed's listed pairs about a quarter touch, and about one particle in ten touches
//! a wall; a history is zero when its contact does not touch. Each item (a listed pair, or a
//! particle's [`WALLS`] wall slots) has the index of its block of history words, or none: a
//! block is taken when an item's history stops being all zero and given back when it is
//! all zero again, so "no block" and "a block of zeros" are the same state, bit for bit (a
//! zero is `+0.0`: a block holding a `-0.0` is kept, as a dense array would keep it).
//! Messages and files still carry whole histories (zeros where there is no block), so the
//! records do not change.

use super::WALLS;
use crate::physics::contact::HISTORY_MAX;

/// No block.
const NONE: u32 = u32::MAX;

/// Whether every word is `+0.0` (the state of an item with no contact). One OR of the bits,
/// without a branch per word.
#[inline]
fn is_clear(h: &[f64]) -> bool {
    h.iter().fold(0, |a, x| a | x.to_bits()) == 0
}

/// Whether some word compares unequal to zero (`-0.0` does not; a NaN does): the bits but
/// the sign, ORed.
#[inline]
fn any_nonzero(h: &[f64]) -> bool {
    h.iter().fold(0, |a, x| a | (x.to_bits() << 1)) != 0
}

/// The most words of an item's history: a particle's wall slots with the widest law.
pub const WIDTH_MAX: usize = WALLS * HISTORY_MAX;

/// Histories of a sequence of items, in blocks for those with a contact. With no history
/// words (a law without springs) nothing is stored, not even the items' indices.
#[derive(Debug, Clone, Default)]
pub struct HistoryBlocks {
    /// Words of an item's history (at most [`WIDTH_MAX`]).
    width: usize,
    /// Each item's block, or [`NONE`].
    slot: Vec<u32>,
    /// The blocks, `width` words each.
    blocks: Vec<f64>,
    /// Blocks given back, taken again first.
    free: Vec<u32>,
}

impl HistoryBlocks {
    /// No items yet; each has `width` words of history.
    pub fn new(width: usize) -> Self {
        assert!(width <= WIDTH_MAX, "a history of at most {WIDTH_MAX} words");
        HistoryBlocks {
            width,
            ..Default::default()
        }
    }

    /// Words of an item's history.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of items (0 with no history words).
    pub fn len(&self) -> usize {
        self.slot.len()
    }

    /// Whether there are no items.
    pub fn is_empty(&self) -> bool {
        self.slot.is_empty()
    }

    /// Number of items with a block.
    #[cfg(test)]
    fn in_contact(&self) -> usize {
        self.slot.iter().filter(|&&s| s != NONE).count()
    }

    /// `n` items, none with a history (the blocks' memory is kept for reuse).
    pub fn reset(&mut self, n: usize) {
        self.slot.clear();
        if self.width > 0 {
            self.slot.resize(n, NONE);
        }
        self.blocks.clear();
        self.free.clear();
    }

    /// Append an item with the history `h` ([`Self::width`] words).
    pub fn push(&mut self, h: &[f64]) {
        debug_assert_eq!(h.len(), self.width);
        if self.width == 0 {
            return;
        }
        self.slot.push(NONE);
        if !is_clear(h) {
            self.take(self.slot.len() - 1, h);
        }
    }

    /// Item `i`'s history, `None` when all zero.
    #[inline]
    pub fn get(&self, i: usize) -> Option<&[f64]> {
        if self.width == 0 {
            return None;
        }
        match self.slot[i] {
            NONE => None,
            s => Some(&self.blocks[s as usize * self.width..(s as usize + 1) * self.width]),
        }
    }

    /// Append item `i`'s history to `buf` ([`Self::width`] words, zeros if it has none).
    pub fn extend_into(&self, i: usize, buf: &mut Vec<f64>) {
        match self.get(i) {
            Some(h) => buf.extend_from_slice(h),
            None => buf.resize(buf.len() + self.width, 0.0),
        }
    }

    /// Run `f` on item `i`'s history (zeros if it has none), keeping it in a block while it
    /// is not all zero.
    #[inline]
    pub fn update<R>(&mut self, i: usize, f: impl FnOnce(&mut [f64]) -> R) -> R {
        let w = self.width;
        if w == 0 {
            return f(&mut []);
        }
        match self.slot[i] {
            NONE => {
                let mut scratch = [0.0; WIDTH_MAX];
                let h = &mut scratch[..w];
                let out = f(h);
                if !is_clear(h) {
                    self.take(i, h);
                }
                out
            }
            s => {
                let h = &mut self.blocks[s as usize * w..(s as usize + 1) * w];
                let out = f(h);
                if is_clear(h) {
                    self.give_back(i);
                }
                out
            }
        }
    }

    /// Item `i`'s history to write, given a block of zeros if it has none (for a pass that
    /// writes it piece by piece; [`Self::release_if_clear`] afterwards gives the block back
    /// if it ends all zero). Not for a law without history words.
    #[inline]
    pub fn hold(&mut self, i: usize) -> &mut [f64] {
        let w = self.width;
        if self.slot[i] == NONE {
            self.take(i, &[0.0; WIDTH_MAX][..w]);
        }
        let s = self.slot[i] as usize;
        &mut self.blocks[s * w..(s + 1) * w]
    }

    /// Give item `i`'s block back if its history is all zero ([`Self::hold`]).
    #[inline]
    pub fn release_if_clear(&mut self, i: usize) {
        if self.get(i).is_some_and(is_clear) {
            self.give_back(i);
        }
    }

    /// Make item `i`'s history `h` ([`Self::width`] words).
    #[inline]
    pub fn set(&mut self, i: usize, h: &[f64]) {
        let w = self.width;
        if w == 0 {
            return;
        }
        match (self.slot[i], is_clear(h)) {
            (NONE, true) => {}
            (NONE, false) => self.take(i, h),
            (_, true) => self.give_back(i),
            (s, false) => self.blocks[s as usize * w..(s as usize + 1) * w].copy_from_slice(h),
        }
    }

    /// Clear item `i`'s history (its contact ended).
    pub fn clear(&mut self, i: usize) {
        if self.width > 0 && self.slot[i] != NONE {
            self.give_back(i);
        }
    }

    /// Item `i`'s history if some word of it compares unequal to zero (a contact in force:
    /// a history of `-0.0`s is not).
    #[inline]
    pub fn in_use(&self, i: usize) -> Option<&[f64]> {
        self.get(i).filter(|h| any_nonzero(h))
    }

    /// Clear item `i`'s history if it is in use ([`Self::in_use`]; a history of `-0.0`s is
    /// left as it is, as a dense array's `if any != 0 { fill(0) }` leaves it).
    pub fn clear_nonzero(&mut self, i: usize) {
        if self.in_use(i).is_some() {
            self.give_back(i);
        }
    }

    /// Each item's history if in use ([`Self::in_use`]), in order (nothing with no history
    /// words).
    pub fn iter_in_use(&self) -> impl Iterator<Item = Option<&[f64]>> + '_ {
        (0..self.len()).map(|i| self.in_use(i))
    }

    /// Give item `i` a block holding `h`.
    fn take(&mut self, i: usize, h: &[f64]) {
        let w = self.width;
        let s = match self.free.pop() {
            Some(s) => {
                self.blocks[s as usize * w..(s as usize + 1) * w].copy_from_slice(h);
                s
            }
            None => {
                self.blocks.extend_from_slice(h);
                (self.blocks.len() / w - 1) as u32
            }
        };
        self.slot[i] = s;
    }

    /// Give item `i`'s block back (its words are left: [`Self::take`] overwrites them all).
    fn give_back(&mut self, i: usize) {
        self.free.push(self.slot[i]);
        self.slot[i] = NONE;
    }

    /// Keep the first `n` items.
    pub fn truncate(&mut self, n: usize) {
        for i in n..self.slot.len() {
            self.clear(i);
        }
        self.slot.truncate(n);
    }

    /// The items `order[k]`, in that order (each at most once; the others are dropped), their
    /// blocks packed in the same order.
    pub fn select(&mut self, order: impl Iterator<Item = usize>) {
        let w = self.width;
        if w == 0 {
            return;
        }
        let mut slot = Vec::with_capacity(self.slot.len());
        let mut blocks = Vec::new();
        for i in order {
            match self.get(i) {
                Some(h) => {
                    blocks.extend_from_slice(h);
                    slot.push((blocks.len() / w - 1) as u32);
                }
                None => slot.push(NONE),
            }
        }
        self.slot = slot;
        self.blocks = blocks;
        self.free = Vec::new();
    }

    /// Give back spare capacity, as [`Particles::trim`](super::Particles::trim) does.
    pub fn trim(&mut self) {
        super::trim(&mut self.slot);
        super::trim(&mut self.blocks);
        super::trim(&mut self.free);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_block_is_held_only_while_the_histories_are_not_zero() {
        let mut h = HistoryBlocks::new(WALLS * 3);
        let w = h.width();
        assert_eq!(w, 12);
        h.push(&vec![0.0; w]);
        let mut one = vec![0.0; w];
        one[4] = 2.5;
        h.push(&one);
        h.push(&vec![0.0; w]);
        assert_eq!(h.in_contact(), 1);
        assert_eq!(h.get(1), Some(&one[..]));
        assert_eq!(h.get(0), None);
        // a contact starts: a block taken
        h.update(2, |x| x[0] = -1.0);
        assert_eq!(h.in_contact(), 2);
        // a contact ends: its block given back, and taken again by the next
        h.update(1, |x| x.fill(0.0));
        assert_eq!(h.get(1), None);
        h.update(0, |x| x[11] = 3.0);
        assert_eq!(h.blocks.len(), 2 * w);
        assert_eq!(h.get(0).unwrap()[11], 3.0);
        assert_eq!(h.get(0).unwrap()[..11], [0.0; 11]);
        // -0.0 is not cleared: the bits are kept as they were
        h.update(2, |x| x[0] = -0.0);
        assert_eq!(h.get(2).unwrap()[0].to_bits(), (-0.0f64).to_bits());
        let mut buf = Vec::new();
        h.extend_into(1, &mut buf);
        assert_eq!(buf, vec![0.0; w]);
        // reordered and packed: every particle keeps its histories
        h.select([2, 0].into_iter());
        assert_eq!(h.len(), 2);
        assert_eq!(h.blocks.len(), 2 * w);
        assert_eq!(h.get(0).unwrap()[0].to_bits(), (-0.0f64).to_bits());
        assert_eq!(h.get(1).unwrap()[11], 3.0);
        h.truncate(1);
        assert_eq!(h.in_contact(), 1);
        assert_eq!(h.free.len(), 1);
        // set: a block taken, overwritten, given back; clear_nonzero keeps -0.0
        h.reset(3);
        assert_eq!((h.len(), h.in_contact(), h.blocks.len()), (3, 0, 0));
        h.set(1, &one);
        h.set(1, &buf);
        assert_eq!(h.get(1), None);
        let mut neg = vec![0.0; w];
        neg[3] = -0.0;
        h.set(2, &neg);
        h.clear_nonzero(2);
        assert!(h.get(2).is_some());
        h.set(0, &one);
        // in use: item 0 (a nonzero word), not item 2 (a block of -0.0, kept, not in use)
        let in_use: Vec<bool> = h.iter_in_use().map(|x| x.is_some()).collect();
        assert_eq!(in_use, [true, false, false]);
        h.clear_nonzero(0);
        assert_eq!(h.iter_in_use().filter(Option::is_some).count(), 0);
        assert_eq!(h.in_contact(), 1);
    }

    #[test]
    fn zero_tests_read_the_bits() {
        assert!(is_clear(&[0.0, 0.0]));
        assert!(!is_clear(&[0.0, -0.0]));
        assert!(!any_nonzero(&[-0.0, 0.0, -0.0]));
        for x in [
            1e-300,
            -2.0,
            f64::NAN,
            f64::INFINITY,
            f64::MIN_POSITIVE / 4.0,
        ] {
            assert!(any_nonzero(&[0.0, x]), "{x}");
            assert!(!is_clear(&[x, 0.0]), "{x}");
        }
    }

    #[test]
    fn no_history_words_hold_nothing() {
        let mut h = HistoryBlocks::new(0);
        h.push(&[]);
        h.push(&[]);
        assert_eq!(h.update(1, |x| x.len()), 0);
        h.set(1, &[]);
        h.clear(1);
        assert_eq!(h.get(1), None);
        h.reset(5);
        h.select([1, 0].into_iter());
        h.truncate(1);
        assert_eq!((h.len(), h.in_contact(), h.blocks.capacity()), (0, 0, 0));
    }
}
