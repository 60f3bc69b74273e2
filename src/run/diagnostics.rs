//! The run's diagnostics schedule: when to sample the windows, close them, record paths and
//! take snapshots, and writing what rank 0 gathered (kernels in `crate::diag`, file layout in
//! `crate::output::diag_file`).

use super::steps_for;
use crate::case::Case;
use crate::comm::Comm;
use crate::diag::grid::velocity_scale;
use crate::diag::{AxialBins, BandRule, PathTracker, Windows};
use crate::engine::Sim;
use crate::output::checkpoint::{DiagState, SavedSums};
use crate::output::diag_file::{self, DiagLayout};
use crate::output::{xdmf, RunFile};
use std::path::{Path, PathBuf};

/// Steps between the events of the diagnostics.
#[derive(Debug, Clone, Copy)]
struct Schedule {
    sample: u64,
    window: u64,
    field_window: u64,
    paths: u64,
    snapshots: Option<u64>,
    dt: f64,
    omega: f64,
}

impl Schedule {
    /// Rotations at `step`, computed as `Sim::rotations` does (the same bits).
    fn rotations(&self, step: u64) -> f64 {
        step as f64 * self.dt * self.omega.abs() / (2.0 * std::f64::consts::PI)
    }
}

/// Everything the run samples beyond the axial profiles.
pub struct RunDiagnostics {
    /// The axial slices.
    pub axial: AxialBins,
    /// Window accumulators.
    pub windows: Windows,
    /// Particles followed.
    pub paths: PathTracker,
    /// How bands are counted.
    pub rule: BandRule,
    /// The species whose bands are counted (the biggest).
    pub big: usize,
    sched: Schedule,
    snapshots: Vec<(String, f64, usize)>,
    output: PathBuf,
}

impl RunDiagnostics {
    /// Diagnostics for `case` writing next to `output`; a restart passes the checkpoint's
    /// state, a fresh run selects the particles to follow now.
    pub fn new(
        case: &Case,
        sim: &Sim,
        comm: &dyn Comm,
        output: &Path,
        restored: Option<&DiagState>,
    ) -> Result<Self, String> {
        let (omega, dt) = (case.drum.omega, case.dt());
        let g = &case.diagnostics;
        let d_max = case.d_max();
        let axial = AxialBins::new(
            case.drum.axial_length(),
            case.slice_width(),
            case.species.len(),
            d_max,
            velocity_scale(case),
        );
        let big = case
            .species
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.diameter.total_cmp(&b.1.diameter))
            .map(|(k, _)| k)
            .unwrap_or(0);
        let min_width = g.bands.min_width.unwrap_or(2.0 * d_max);
        let rule = BandRule {
            threshold: g.bands.threshold,
            min_slices: ((min_width / axial.width).round() as usize).max(1),
            periodic: case.drum.periodic(),
        };
        // windows hold a whole number of samples
        let sample = steps_for(g.sample_every, omega, dt).max(1);
        let whole = |w: f64| sample * ((w / g.sample_every).round() as u64).max(1);
        let sched = Schedule {
            sample,
            window: whole(g.window),
            field_window: whole(g.fields.window),
            paths: steps_for(g.paths.every.unwrap_or(g.sample_every), omega, dt).max(1),
            snapshots: g.snapshots.every.map(|e| steps_for(e, omega, dt).max(1)),
            dt,
            omega,
        };
        let mut windows = Windows::new(case, &axial);
        if comm.rank() == 0 {
            windows.slices.hold_whole();
            windows.fields.hold_whole();
        }
        let paths = match restored {
            Some(d) => {
                let root = comm.rank() == 0;
                let differ = |what: &str, a: usize, b: usize| {
                    format!(
                        "the checkpoint's diagnostics windows hold {a} {what}, this case's {b}: diagnostics.fields.grid or output.slice_width differ"
                    )
                };
                for (acc, saved) in [
                    (&mut windows.slices, &d.slices),
                    (&mut windows.fields, &d.fields),
                ] {
                    if saved.len != acc.len() {
                        return Err(differ("sums", saved.len, acc.len()));
                    }
                    acc.samples = saved.samples;
                    acc.angle_sum = saved.angle_sum;
                    if root {
                        acc.sums = saved.sums.clone();
                    }
                }
                let (a, b) = (d.angles.slice_sum.len(), windows.angles.slice_sum.len());
                if a != b {
                    return Err(differ("slice angles", a, b));
                }
                windows.angles = d.angles.clone();
                PathTracker::from_ids(d.path_ids.clone())
            }
            None => {
                let paths = PathTracker::select(&g.paths, &sim.p, comm);
                missing_path_ids(&paths.ids, sim, comm)?;
                paths
            }
        };
        Ok(RunDiagnostics {
            axial,
            windows,
            paths,
            rule,
            big,
            sched,
            snapshots: Vec::new(),
            output: output.to_path_buf(),
        })
    }

    /// The shapes of the datasets, for creating the file.
    pub fn layout(&self) -> DiagLayout {
        let (s, f) = (&self.windows.slices.grid, &self.windows.fields.grid);
        DiagLayout {
            ns: self.axial.ns,
            z: self.axial.centres(),
            x: s.centres(0),
            y: s.centres(1),
            zf: f.centres(2),
            path_ids: self.paths.ids.clone(),
            bands: self.rule,
            band_species: self.big,
        }
    }

    /// Records a checkpoint at `step` has behind it: `(slice windows, field windows, path
    /// samples)`.
    pub fn records_at(&self, step: u64) -> (usize, usize, usize) {
        (
            (step / self.sched.window) as usize,
            (step / self.sched.field_window) as usize,
            (step / self.sched.paths) as usize + 1,
        )
    }

    /// After a restart: cut the file back to the checkpoint at `step` and list its snapshots.
    pub fn resume_file(&mut self, file: &RunFile, step: u64) -> hdf5::Result<()> {
        let (s, f, p) = self.records_at(step);
        diag_file::truncate(file.file(), s, f, p, step)?;
        self.snapshots = diag_file::snapshots(file.file())?;
        xdmf::write(&self.output, file.file()).map_err(|e| hdf5::Error::from(e.as_str()))?;
        Ok(())
    }

    /// What happens at `sim.step` (every rank calls this after every step, and once at the
    /// start of a fresh run).
    pub fn after_step(
        &mut self,
        sim: &Sim,
        comm: &dyn Comm,
        file: &mut Option<RunFile>,
    ) -> Result<(), String> {
        let step = sim.step;
        let s = self.sched;
        let mut ok = true;
        let file_now = file.as_ref();
        let mut any = false;
        if step > 0 && step.is_multiple_of(s.sample) {
            self.windows.sample(&sim.p, comm);
        }
        if step > 0 && step.is_multiple_of(s.window) {
            any = true;
            ok &= self.close(false, comm, file_now, step - s.window, step);
        }
        if step > 0 && step.is_multiple_of(s.field_window) {
            any = true;
            ok &= self.close(true, comm, file_now, step - s.field_window, step);
        }
        if !self.paths.is_empty() && step.is_multiple_of(s.paths) {
            any = true;
            let d = self.paths.gather(&sim.p, comm);
            if let (Some(d), Some(f)) = (d, file_now) {
                ok &= logged(
                    diag_file::append_path(f.file(), sim.rotations(), &d),
                    "a path sample",
                );
            }
        }
        if s.snapshots.is_some_and(|k| step.is_multiple_of(k)) {
            // every rank writes its share: the other records of this step must agree first
            if any && !comm.all_ok(ok) {
                return Err("stopped: a diagnostic could not be written to the output".into());
            }
            let states = sim.particles_by_id();
            let n = comm.sum_u64(states.len() as u64);
            let rotations = sim.rotations();
            crate::output::h5::write_together(comm, &self.output, file, |f| {
                diag_file::write_snapshot(comm, f, step, rotations, &states)
            })
            .map_err(|e| format!("stopped: writing a snapshot: {e}"))?;
            if comm.rank() == 0 {
                self.snapshots
                    .push((diag_file::snapshot_name(step), rotations, n as usize));
                ok &= file.as_ref().is_none_or(|f| self.write_xdmf(f));
            }
            any = true;
        }
        if !any || comm.all_ok(ok) {
            Ok(())
        } else {
            Err("stopped: a diagnostic could not be written to the output".into())
        }
    }

    /// At the end of the run (after its checkpoint): close the windows still open.
    pub fn finish(
        &mut self,
        sim: &Sim,
        comm: &dyn Comm,
        file: Option<&RunFile>,
    ) -> Result<(), String> {
        let step = sim.step;
        let s = self.sched;
        let mut ok = true;
        if !step.is_multiple_of(s.window) && self.windows.slices.samples > 0 {
            ok &= self.close(false, comm, file, step - step % s.window, step);
        }
        if !step.is_multiple_of(s.field_window) && self.windows.fields.samples > 0 {
            ok &= self.close(true, comm, file, step - step % s.field_window, step);
        }
        if comm.all_ok(ok) {
            Ok(())
        } else {
            Err("writing the last diagnostics windows failed".into())
        }
    }

    /// Close the per-slice (`fields == false`) or field window of steps `(start, end]` and
    /// write it (rank 0); whether that went well.
    fn close(
        &mut self,
        fields: bool,
        comm: &dyn Comm,
        file: Option<&RunFile>,
        start: u64,
        end: u64,
    ) -> bool {
        let (a, b) = (self.sched.rotations(start), self.sched.rotations(end));
        let written = if fields {
            let w = self.windows.flush_fields(comm);
            file.zip(w).map(|(f, w)| {
                (
                    diag_file::append_fields(f.file(), a, b, &w),
                    "a field window",
                )
            })
        } else {
            let r = self.windows.flush_slices(comm);
            file.zip(r).map(|(f, r)| {
                (
                    diag_file::append_slices(f.file(), a, b, &r),
                    "a slice window",
                )
            })
        };
        let ok = written.is_none_or(|(r, what)| logged(r, what));
        // the new field window in the XDMF file
        ok && !(fields && file.is_some_and(|f| !self.write_xdmf(f)))
    }

    /// Rewrite the XDMF file from what the output holds now (rank 0); whether that went well.
    fn write_xdmf(&self, file: &RunFile) -> bool {
        match xdmf::write(&self.output, file.file()) {
            Ok(_) => true,
            Err(e) => {
                log::error!("{e}");
                false
            }
        }
    }

    /// The state a checkpoint keeps (all ranks call this; meaningful on rank 0).
    ///
    /// The window sums are moved into the state, not copied (they are the largest part of a
    /// checkpoint of a small run); give them back with [`restore`](Self::restore).
    pub fn state(&mut self, comm: &dyn Comm) -> DiagState {
        self.windows.consolidate(comm);
        let w = &mut self.windows;
        let saved = |b: &mut crate::diag::grid::BinnedSums| SavedSums {
            samples: b.samples,
            angle_sum: b.angle_sum,
            len: b.len(),
            sums: std::mem::take(&mut b.sums),
        };
        DiagState {
            slices: saved(&mut w.slices),
            fields: saved(&mut w.fields),
            angles: w.angles.clone(),
            path_ids: self.paths.ids.clone(),
        }
    }

    /// Take back the window sums lent to a checkpoint by [`state`](Self::state).
    pub fn restore(&mut self, state: DiagState) {
        self.windows.slices.sums = state.slices.sums;
        self.windows.fields.sums = state.fields.sums;
    }
}

/// Refuse followed ids that no particle of the initial state has (every rank counts its
/// own, the counts are summed, so every rank gives the same answer).
fn missing_path_ids(ids: &[u64], sim: &Sim, comm: &dyn Comm) -> Result<(), String> {
    let mut present = vec![0u64; ids.len()];
    for &id in &sim.p.id[..sim.p.n_owned] {
        if let Ok(k) = ids.binary_search(&id) {
            present[k] += 1;
        }
    }
    comm.sum_u64_all(&mut present);
    let missing: Vec<String> = ids
        .iter()
        .zip(&present)
        .filter(|(_, &n)| n == 0)
        .map(|(id, _)| id.to_string())
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let n = sim.global_count();
    Err(format!(
        "diagnostics.paths.ids: no particle has id {} (the initial state has {n} particles{})",
        missing.join(", "),
        if n > 0 {
            ", ids from 0; a pour removes the ids of the particles it cuts"
        } else {
            ""
        }
    ))
}

/// Log a failed write; whether it succeeded.
fn logged(r: hdf5::Result<()>, what: &str) -> bool {
    match r {
        Ok(()) => true,
        Err(e) => {
            log::error!("writing {what}: {e}");
            false
        }
    }
}
