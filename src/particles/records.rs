//! Full particle states held as packed records ([`Particles::pack`]'s layout) in one buffer:
//! what the files' writers and a restart hold of the particles in id order. A record is 19
//! words plus 4 per history word (248 B with a tangential spring), where a
//! [`ParticleState`] is 344 B whatever the law keeps; the columns of a file are read from,
//! and written into, the records one at a time.

use super::{packed_words, ParticleState, GHOST_WORDS, WALLS};

/// Where each field starts in a record (the head is a ghost's record, see
/// [`Particles::pack_ghost`]).
mod at {
    pub const ID: usize = 0;
    pub const KEY: usize = 1;
    pub const SPECIES: usize = 2;
    pub const DIAMETER: usize = 3;
    pub const X: usize = 4;
    pub const V: usize = 7;
    pub const W: usize = 10;
    pub const WALL: usize = 13;
}
const _: () = assert!(at::WALL == GHOST_WORDS);

/// A field of a record, the columns of a file ([`Records::column`], [`Records::set_column`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    /// Global id (1 value).
    Id,
    /// Order key (1 value).
    Key,
    /// Species index (1 value).
    Species,
    /// Diameter (1 value).
    Diameter,
    /// Position (3 values).
    Position,
    /// Velocity (3 values).
    Velocity,
    /// Angular velocity (3 values).
    AngularVelocity,
    /// Wall histories: [`WALLS`] slots of the records' history words.
    WallHistory,
    /// Force of the last evaluation (3 values).
    Force,
    /// Torque of the last evaluation (3 values).
    Torque,
}

/// Particle states, one packed record of [`packed_words`]`(hist_words)` values each.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Records {
    hist_words: usize,
    data: Vec<f64>,
}

impl Records {
    /// The records in `data` (whole records of `hist_words` history words per contact).
    pub fn new(hist_words: usize, data: Vec<f64>) -> Self {
        assert_eq!(
            data.len() % packed_words(hist_words),
            0,
            "a buffer of whole records"
        );
        Records { hist_words, data }
    }

    /// `n` records of zeros, to be filled column by column ([`Records::set_column`]).
    pub fn zeros(n: usize, hist_words: usize) -> Self {
        Records::new(hist_words, vec![0.0; n * packed_words(hist_words)])
    }

    /// The records of `states`, `hist_words` history words of each wall slot kept.
    #[cfg(test)]
    pub fn of_states(states: &[ParticleState], hist_words: usize) -> Self {
        let mut r = Records::zeros(states.len(), hist_words);
        let w = r.words();
        for (rec, s) in r.data.chunks_exact_mut(w).zip(states) {
            rec[at::ID] = s.id as f64;
            rec[at::KEY] = s.key as f64;
            rec[at::SPECIES] = s.species as f64;
            rec[at::DIAMETER] = s.diameter;
            for (k, v) in [(at::X, s.x), (at::V, s.v), (at::W, s.w)] {
                rec[k..k + 3].copy_from_slice(&v);
            }
            for (k, h) in s.wall_hist.iter().enumerate() {
                let a = at::WALL + k * hist_words;
                rec[a..a + hist_words].copy_from_slice(&h[..hist_words]);
            }
            let tail = at::WALL + WALLS * hist_words;
            rec[tail..tail + 3].copy_from_slice(&s.f);
            rec[tail + 3..tail + 6].copy_from_slice(&s.t);
        }
        r
    }

    /// Values per record.
    pub fn words(&self) -> usize {
        packed_words(self.hist_words)
    }

    /// Number of records.
    pub fn len(&self) -> usize {
        self.data.len() / self.words()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Where `field` starts in a record, and how many values it has.
    fn span(&self, field: Field) -> (usize, usize) {
        let tail = at::WALL + WALLS * self.hist_words;
        match field {
            Field::Id => (at::ID, 1),
            Field::Key => (at::KEY, 1),
            Field::Species => (at::SPECIES, 1),
            Field::Diameter => (at::DIAMETER, 1),
            Field::Position => (at::X, 3),
            Field::Velocity => (at::V, 3),
            Field::AngularVelocity => (at::W, 3),
            Field::WallHistory => (at::WALL, WALLS * self.hist_words),
            Field::Force => (tail, 3),
            Field::Torque => (tail + 3, 3),
        }
    }

    /// Values of `field` per record.
    pub fn width(&self, field: Field) -> usize {
        self.span(field).1
    }

    /// The id of record `i`.
    pub fn id(&self, i: usize) -> u64 {
        self.data[i * self.words() + at::ID] as u64
    }

    /// Record `i` as a [`ParticleState`].
    pub fn state(&self, i: usize) -> ParticleState {
        let w = self.words();
        super::unpack(&self.data[i * w..(i + 1) * w], self.hist_words)
    }

    /// The states, in the records' order (one at a time).
    pub fn states(&self) -> impl Iterator<Item = ParticleState> + '_ {
        (0..self.len()).map(|i| self.state(i))
    }

    /// `field` of every record, as `f64` values (rows of its width, in the records' order).
    pub fn column(&self, field: Field) -> Vec<f64> {
        self.column_as(field, |x| x)
    }

    /// `field` of every record, each value converted by `f` (ids, keys and species are
    /// held as `f64`, exact below 2^53).
    pub fn column_as<T>(&self, field: Field, f: impl Fn(f64) -> T) -> Vec<T> {
        let (a, n) = self.span(field);
        // exact size: a column is one of a file write's transients
        let mut out = Vec::with_capacity(self.len() * n);
        for rec in self.data.chunks_exact(self.words()) {
            out.extend(rec[a..a + n].iter().map(|&x| f(x)));
        }
        out
    }

    /// The wall histories, `width` words per slot (`width` ≥ the records' history words;
    /// zeros beyond them).
    pub fn wall_history(&self, width: usize) -> Vec<f64> {
        assert!(width >= self.hist_words);
        let (a, _) = self.span(Field::WallHistory);
        let mut out = Vec::with_capacity(self.len() * WALLS * width);
        for rec in self.data.chunks_exact(self.words()) {
            for k in 0..WALLS {
                let h = a + k * self.hist_words;
                out.extend_from_slice(&rec[h..h + self.hist_words]);
                out.resize(out.len() + width - self.hist_words, 0.0);
            }
        }
        out
    }

    /// Set `field` of every record from `values` (rows of its width, converted by `f`).
    /// Returns an error if `values` is not one row per record.
    pub fn set_column<T: Copy>(
        &mut self,
        field: Field,
        values: &[T],
        f: impl Fn(T) -> f64,
    ) -> Result<(), String> {
        let (a, n) = self.span(field);
        if values.len() != self.len() * n {
            return Err(format!(
                "{} values are not {} rows of {n}",
                values.len(),
                self.len()
            ));
        }
        if n == 0 {
            return Ok(());
        }
        let w = self.words();
        for (rec, v) in self.data.chunks_exact_mut(w).zip(values.chunks_exact(n)) {
            for (d, &s) in rec[a..a + n].iter_mut().zip(v) {
                *d = f(s);
            }
        }
        Ok(())
    }

    /// Sort the records by id, in place: an index sorted by id (ids are unique, so an
    /// unstable sort gives the one order), then the permutation applied by cycles, one
    /// record of scratch.
    pub fn sort_by_id(&mut self) {
        let w = self.words();
        let n = self.len();
        let mut order: Vec<(u64, usize)> = (0..n).map(|i| (self.id(i), i)).collect();
        order.sort_unstable();
        // place[i]: the record that goes to slot i
        let mut place: Vec<usize> = order.into_iter().map(|(_, k)| k).collect();
        let mut tmp = vec![0.0; w];
        for start in 0..n {
            if place[start] == start {
                continue;
            }
            tmp.copy_from_slice(&self.data[start * w..(start + 1) * w]);
            let mut slot = start;
            loop {
                let from = place[slot];
                place[slot] = slot;
                if from == start {
                    self.data[slot * w..(slot + 1) * w].copy_from_slice(&tmp);
                    break;
                }
                self.data.copy_within(from * w..(from + 1) * w, slot * w);
                slot = from;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(id: u64, words: usize) -> ParticleState {
        let f = id as f64;
        let mut s =
            ParticleState::new(id, (id % 3) as u8, 1.0 + f, [f, 2.0, 3.0], [4.0; 3], [f; 3]);
        s.key = 7 * id;
        s.f = [-f; 3];
        s.t = [0.5 * f; 3];
        for (k, h) in s.wall_hist.iter_mut().enumerate() {
            for (j, x) in h[..words].iter_mut().enumerate() {
                *x = f + 0.1 * k as f64 + 0.01 * j as f64;
            }
        }
        s
    }

    #[test]
    fn records_keep_every_field_and_sort_by_id_in_place() {
        for words in [0, 3, 6] {
            let ids = [5u64, 0, 9, 3, 7, 1, 8, 2, 6, 4];
            let states: Vec<ParticleState> = ids.iter().map(|&i| state(i, words)).collect();
            let mut r = Records::of_states(&states, words);
            assert_eq!(r.len(), ids.len());
            for (i, s) in states.iter().enumerate() {
                assert_eq!(format!("{:?}", r.state(i)), format!("{s:?}"));
            }
            r.sort_by_id();
            let mut sorted = states.clone();
            sorted.sort_by_key(|s| s.id);
            let back: Vec<ParticleState> = r.states().collect();
            assert_eq!(format!("{back:?}"), format!("{sorted:?}"));
            // the columns, and a copy rebuilt from them, are the same records
            let mut c = Records::zeros(r.len(), words);
            for f in [
                Field::Id,
                Field::Key,
                Field::Species,
                Field::Diameter,
                Field::Position,
                Field::Velocity,
                Field::AngularVelocity,
                Field::WallHistory,
                Field::Force,
                Field::Torque,
            ] {
                c.set_column(f, &r.column(f), |x| x).unwrap();
            }
            assert_eq!(c, r);
            assert_eq!(
                r.column_as(Field::Id, |x| x as u64),
                (0..10).collect::<Vec<u64>>()
            );
            let wide = r.wall_history(6);
            assert_eq!(wide.len(), 10 * WALLS * 6);
            assert_eq!(&wide[6..6 + words], &sorted[0].wall_hist[1][..words]);
            assert!(wide[6 + words..12].iter().all(|&x| x == 0.0));
            assert!(c.set_column(Field::Position, &[0.0; 3], |x| x).is_err());
        }
    }
}
