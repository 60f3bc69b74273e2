//! The communication layer: everything the engine asks of other ranks, behind one trait.
//! [`SerialComm`] is the single-process implementation (tests, one rank without MPI);
//! [`MpiComm`] is the only code in the crate that speaks MPI.

mod mpi_comm;
mod serial;

pub use mpi_comm::MpiComm;
pub use serial::SerialComm;

/// An MPI communicator as the C library knows it, for the HDF5 MPI-IO file driver
/// (`output::pario`): opaque everywhere else.
#[derive(Clone, Copy)]
pub struct RawComm(pub mpi::ffi::MPI_Comm);

/// What the engine needs from the ranks around it.
pub trait Comm {
    /// This rank's index.
    fn rank(&self) -> usize;
    /// Number of ranks.
    fn size(&self) -> usize;
    /// Send `to_down` to rank `down` and `to_up` to rank `up` (either may be absent), and
    /// return `(from_down, from_up)`: what `down` sent up to us and what `up` sent down.
    /// `down` and `up` may be the same rank, or this rank itself.
    fn exchange(
        &self,
        down: Option<usize>,
        to_down: &[f64],
        up: Option<usize>,
        to_up: &[f64],
    ) -> (Vec<f64>, Vec<f64>);
    /// Like [`Comm::exchange`], into buffers the caller has sized to the messages it
    /// expects (`from_down` from `down`, `from_up` from `up`), running `work` while the
    /// messages travel. Panics if a message's length differs from its buffer's.
    #[allow(clippy::too_many_arguments)]
    fn exchange_into(
        &self,
        down: Option<usize>,
        to_down: &[f64],
        from_down: &mut [f64],
        up: Option<usize>,
        to_up: &[f64],
        from_up: &mut [f64],
        work: &mut dyn FnMut(),
    );

    /// The irregular exchange: send `to[r]` to rank `r` for every rank (most of them empty)
    /// and return what every rank sent to this one, in rank order (`to.len()` must be the
    /// number of ranks). Counts travel as 64-bit numbers and long messages in pieces, so a
    /// message may hold any number of words. Used where particles go to whichever rank owns
    /// them (after a rebalance); the per-step path is [`Comm::exchange`]. The messages are
    /// taken by value: this rank's own is handed back without a copy, and the others are
    /// freed as soon as they are sent, so that a big exchange (the files' id order) does not
    /// hold its send buffers beside what it receives.
    fn all_to_all(&self, to: Vec<Vec<f64>>) -> Vec<Vec<f64>>;

    /// Maximum of `x` over all ranks.
    fn max_f64(&self, x: f64) -> f64;
    /// Element-wise maximum of `v` over all ranks, on every rank.
    fn max_f64_all(&self, v: &mut [f64]);
    /// Sum of `x` over all ranks, on every rank.
    fn sum_u64(&self, x: u64) -> u64;
    /// Element-wise sum of `v` over all ranks, on every rank.
    fn sum_u64_all(&self, v: &mut [u64]);
    /// Element-wise sum of `v` over all ranks, delivered to rank 0 (others get `v` unchanged).
    fn sum_i64_to_root(&self, v: &mut [i64]);
    /// Concatenation of every rank's `local` in rank order, on rank 0 (`None` elsewhere).
    fn gather_f64(&self, local: &[f64]) -> Option<Vec<f64>>;
    /// Whether `ok` holds on every rank.
    fn all_ok(&self, ok: bool) -> bool;

    /// The error of the lowest rank that has one, on every rank (`None` when no rank has):
    /// what a rank found wrong in its own part of the input reaches the rank that reports.
    fn first_error(&self, err: Option<String>) -> Option<String> {
        let mut flags = vec![0u64; self.size()];
        if err.is_some() {
            flags[self.rank()] = 1;
        }
        self.sum_u64_all(&mut flags);
        let first = flags.iter().position(|&f| f > 0)?;
        let text: Vec<f64> = match (&err, self.rank() == first) {
            (Some(e), true) => e.bytes().map(f64::from).collect(),
            _ => Vec::new(),
        };
        let to: Vec<Vec<f64>> = (0..self.size()).map(|_| text.clone()).collect();
        let bytes: Vec<u8> = self.all_to_all(to)[first]
            .iter()
            .map(|&b| b as u8)
            .collect();
        Some(String::from_utf8_lossy(&bytes).into_owned())
    }
    /// Sum of `x` over the ranks below this one (0 on rank 0): where this rank's rows start
    /// in a dataset every rank writes a part of.
    fn exscan_u64(&self, x: u64) -> u64;
    /// The communicator for files every rank opens together (HDF5's MPI-IO driver); `None`
    /// without MPI, where files are written with HDF5's default driver.
    fn raw(&self) -> Option<RawComm>;
}
