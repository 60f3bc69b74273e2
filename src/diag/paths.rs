//! Particle paths (thesis figs. 5.10-5.11): the positions and velocities of chosen
//! particles over time, gathered to rank 0 in the order of their ids.

use crate::case::Paths;
use crate::comm::Comm;
use crate::particles::Particles;
use crate::physics::rough_wall::is_fixed;

/// Words per tracked particle in a sample: position and velocity.
pub const PATH_WORDS: usize = 6;

/// The particles being followed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathTracker {
    /// Their ids, sorted.
    pub ids: Vec<u64>,
}

impl PathTracker {
    /// Follow `ids` exactly (a restart).
    pub fn from_ids(mut ids: Vec<u64>) -> Self {
        ids.sort_unstable();
        ids.dedup();
        PathTracker { ids }
    }

    /// The ids named in `cfg` and those of the particles whose centres lie in one of its
    /// regions now (all ranks call this together; every rank gets the same list).
    pub fn select(cfg: &Paths, p: &Particles, comm: &dyn Comm) -> Self {
        let mut ids = cfg.ids.clone();
        if !cfg.regions.is_empty() {
            let local: Vec<f64> = (0..p.n_owned)
                .filter(|&i| {
                    !is_fixed(p.species[i])
                        && cfg
                            .regions
                            .iter()
                            .any(|r| (0..3).all(|a| p.x[i][a] >= r.min[a] && p.x[i][a] < r.max[a]))
                })
                .map(|i| p.id[i] as f64)
                .collect();
            // ids are below 2^40, exact in f64; rank 0 gathers, then every rank learns them
            let all = comm.gather_f64(&local).unwrap_or_default();
            let mut n = vec![all.len() as f64];
            comm.max_f64_all(&mut n);
            let mut found = vec![f64::NEG_INFINITY; n[0] as usize];
            found[..all.len()].copy_from_slice(&all);
            comm.max_f64_all(&mut found);
            ids.extend(found.iter().map(|&x| x as u64));
        }
        Self::from_ids(ids)
    }

    /// Whether no particle is followed.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Positions and velocities of the followed particles, `P x 6` in id order, on rank 0
    /// (`None` elsewhere); NaN for an id no rank holds.
    pub fn gather(&self, p: &Particles, comm: &dyn Comm) -> Option<Vec<f64>> {
        let mut local = Vec::new();
        for i in 0..p.n_owned {
            if self.ids.binary_search(&p.id[i]).is_ok() {
                local.push(p.id[i] as f64);
                local.extend_from_slice(&p.x[i]);
                local.extend_from_slice(&p.v[i]);
            }
        }
        let all = comm.gather_f64(&local)?;
        let mut out = vec![f64::NAN; PATH_WORDS * self.ids.len()];
        for rec in all.chunks_exact(1 + PATH_WORDS) {
            if let Ok(k) = self.ids.binary_search(&(rec[0] as u64)) {
                out[PATH_WORDS * k..PATH_WORDS * (k + 1)].copy_from_slice(&rec[1..]);
            }
        }
        Some(out)
    }
}
