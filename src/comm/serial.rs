//! A single rank without MPI: exchanges with itself are buffer swaps.

use super::{Comm, RawComm};

/// The one-rank communicator.
#[derive(Debug, Default, Clone, Copy)]
pub struct SerialComm;

impl Comm for SerialComm {
    fn rank(&self) -> usize {
        0
    }
    fn size(&self) -> usize {
        1
    }
    fn exchange(
        &self,
        down: Option<usize>,
        to_down: &[f64],
        up: Option<usize>,
        to_up: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        // What we send up arrives from below, and vice versa.
        let from_down = if down.is_some() {
            to_up.to_vec()
        } else {
            Vec::new()
        };
        let from_up = if up.is_some() {
            to_down.to_vec()
        } else {
            Vec::new()
        };
        (from_down, from_up)
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
        work();
        let (d, u) = self.exchange(down, to_down, up, to_up);
        assert_eq!(d.len(), from_down.len(), "message length from below");
        assert_eq!(u.len(), from_up.len(), "message length from above");
        from_down.copy_from_slice(&d);
        from_up.copy_from_slice(&u);
    }
    fn all_to_all(&self, to: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        assert_eq!(to.len(), 1, "one message per rank");
        to
    }
    fn max_f64(&self, x: f64) -> f64 {
        x
    }
    fn max_f64_all(&self, _v: &mut [f64]) {}
    fn sum_u64(&self, x: u64) -> u64 {
        x
    }
    fn sum_u64_all(&self, _v: &mut [u64]) {}
    fn sum_i64_to_root(&self, _v: &mut [i64]) {}
    fn gather_f64(&self, local: &[f64]) -> Option<Vec<f64>> {
        Some(local.to_vec())
    }
    fn all_ok(&self, ok: bool) -> bool {
        ok
    }
    fn exscan_u64(&self, _x: u64) -> u64 {
        0
    }
    fn raw(&self) -> Option<RawComm> {
        None
    }
}
