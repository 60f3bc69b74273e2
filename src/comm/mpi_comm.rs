//! MPI through rsmpi: the only file in the crate that speaks MPI.

use super::{Comm, RawComm};
use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::raw::AsRaw;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

const TAG_UP: i32 = 11;
const TAG_DOWN: i32 = 12;
const TAG_ANY: i32 = 13;

/// Longest piece of an irregular message, in words (MPI counts are 32-bit).
const PIECE_WORDS: usize = 1 << 26;

/// A communicator over `MPI_COMM_WORLD`.
pub struct MpiComm {
    world: SimpleCommunicator,
}

impl MpiComm {
    /// Wrap the world communicator of an initialised MPI universe.
    pub fn new(universe: &mpi::environment::Universe) -> Self {
        MpiComm {
            world: universe.world(),
        }
    }

    /// Abort every rank with `code` (used when one rank fails alone).
    pub fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
}

impl Comm for MpiComm {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }

    fn size(&self) -> usize {
        self.world.size() as usize
    }

    fn exchange(
        &self,
        down: Option<usize>,
        to_down: &[f64],
        up: Option<usize>,
        to_up: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        mpi::request::scope(|scope| {
            let send_up = up.map(|u| {
                self.world
                    .process_at_rank(u as i32)
                    .immediate_send_with_tag(scope, to_up, TAG_UP)
            });
            let send_down = down.map(|d| {
                self.world
                    .process_at_rank(d as i32)
                    .immediate_send_with_tag(scope, to_down, TAG_DOWN)
            });
            let from_down = down
                .map(|d| {
                    self.world
                        .process_at_rank(d as i32)
                        .receive_vec_with_tag::<f64>(TAG_UP)
                        .0
                })
                .unwrap_or_default();
            let from_up = up
                .map(|u| {
                    self.world
                        .process_at_rank(u as i32)
                        .receive_vec_with_tag::<f64>(TAG_DOWN)
                        .0
                })
                .unwrap_or_default();
            if let Some(r) = send_up {
                r.wait();
            }
            if let Some(r) = send_down {
                r.wait();
            }
            (from_down, from_up)
        })
    }

    fn exchange_into(
        &self,
        down: Option<usize>,
        to_down: &[f64],
        from_down: &mut [f64],
        up: Option<usize>,
        to_up: &[f64],
        from_up: &mut [f64],
        work: &mut dyn FnMut(),
    ) {
        let (n_down, n_up) = (from_down.len(), from_up.len());
        mpi::request::scope(|scope| {
            let at = |r: usize| self.world.process_at_rank(r as i32);
            let recv_down =
                down.map(|d| at(d).immediate_receive_into_with_tag(scope, from_down, TAG_UP));
            let recv_up =
                up.map(|u| at(u).immediate_receive_into_with_tag(scope, from_up, TAG_DOWN));
            let send_up = up.map(|u| at(u).immediate_send_with_tag(scope, to_up, TAG_UP));
            let send_down = down.map(|d| at(d).immediate_send_with_tag(scope, to_down, TAG_DOWN));
            work();
            let words = |status: mpi::point_to_point::Status| {
                status.count(f64::equivalent_datatype()) as usize
            };
            if let Some(r) = recv_down {
                assert_eq!(words(r.wait()), n_down, "message length from below");
            }
            if let Some(r) = recv_up {
                assert_eq!(words(r.wait()), n_up, "message length from above");
            }
            for r in [send_up, send_down].into_iter().flatten() {
                r.wait();
            }
        })
    }

    fn all_to_all(&self, mut to: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        let n = self.size();
        assert_eq!(to.len(), n, "one message per rank");
        let counts: Vec<u64> = to.iter().map(|m| m.len() as u64).collect();
        let mut incoming = vec![0u64; n];
        self.world.all_to_all_into(&counts[..], &mut incoming[..]);
        let me = self.rank();
        // this rank's own message is handed back as it is; the others get exact buffers
        let mut from: Vec<Vec<f64>> = incoming
            .iter()
            .enumerate()
            .map(|(r, &c)| {
                if r == me {
                    Vec::new()
                } else {
                    vec![0.0; c as usize]
                }
            })
            .collect();
        from[me] = std::mem::take(&mut to[me]);
        mpi::request::scope(|scope| {
            let at = |r: usize| self.world.process_at_rank(r as i32);
            // pieces between one pair of ranks arrive in the order they were sent
            let mut receives = Vec::new();
            for (r, buf) in from.iter_mut().enumerate() {
                if r != me {
                    for piece in buf.chunks_mut(PIECE_WORDS) {
                        receives.push(at(r).immediate_receive_into_with_tag(scope, piece, TAG_ANY));
                    }
                }
            }
            let mut sends = Vec::new();
            for (r, msg) in to.iter().enumerate() {
                if r != me {
                    for piece in msg.chunks(PIECE_WORDS) {
                        sends.push(at(r).immediate_send_with_tag(scope, piece, TAG_ANY));
                    }
                }
            }
            for r in receives {
                r.wait();
            }
            for s in sends {
                s.wait();
            }
        });
        drop(to);
        from
    }

    fn max_f64(&self, x: f64) -> f64 {
        let mut y = 0.0;
        self.world
            .all_reduce_into(&x, &mut y, SystemOperation::max());
        y
    }

    fn max_f64_all(&self, v: &mut [f64]) {
        let mut out = vec![0.0; v.len()];
        self.world
            .all_reduce_into(&v[..], &mut out[..], SystemOperation::max());
        v.copy_from_slice(&out);
    }

    fn sum_u64(&self, x: u64) -> u64 {
        let mut y = 0u64;
        self.world
            .all_reduce_into(&x, &mut y, SystemOperation::sum());
        y
    }

    fn sum_u64_all(&self, v: &mut [u64]) {
        let mut out = vec![0u64; v.len()];
        self.world
            .all_reduce_into(&v[..], &mut out[..], SystemOperation::sum());
        v.copy_from_slice(&out);
    }

    fn sum_i64_to_root(&self, v: &mut [i64]) {
        let root = self.world.process_at_rank(0);
        if self.rank() == 0 {
            let mut out = vec![0i64; v.len()];
            root.reduce_into_root(&v[..], &mut out[..], SystemOperation::sum());
            v.copy_from_slice(&out);
        } else {
            root.reduce_into(&v[..], SystemOperation::sum());
        }
    }

    fn gather_f64(&self, local: &[f64]) -> Option<Vec<f64>> {
        let root = self.world.process_at_rank(0);
        let n = local.len() as i32;
        if self.rank() == 0 {
            let mut counts = vec![0i32; self.size()];
            root.gather_into_root(&n, &mut counts[..]);
            let displs: Vec<i32> = counts
                .iter()
                .scan(0, |acc, &c| {
                    let d = *acc;
                    *acc += c;
                    Some(d)
                })
                .collect();
            let total: i32 = counts.iter().sum();
            let mut all = vec![0.0f64; total as usize];
            {
                let mut part = PartitionMut::new(&mut all[..], counts, &displs[..]);
                root.gather_varcount_into_root(local, &mut part);
            }
            Some(all)
        } else {
            root.gather_into(&n);
            root.gather_varcount_into(local);
            None
        }
    }

    fn all_ok(&self, ok: bool) -> bool {
        let x = if ok { 0u64 } else { 1 };
        self.sum_u64(x) == 0
    }

    fn exscan_u64(&self, x: u64) -> u64 {
        let mut y = 0u64;
        self.world
            .exclusive_scan_into(&x, &mut y, SystemOperation::sum());
        // MPI leaves rank 0's result undefined
        if self.rank() == 0 {
            0
        } else {
            y
        }
    }

    fn raw(&self) -> Option<RawComm> {
        Some(RawComm(self.world.as_raw()))
    }
}
