//! The run's diagnostics schedule: when to sample the windows, close them, record paths and
//! take snapshots, and writing what rank 0 gathered (kernels in `crate::diag`, file layout in
//! `crate::output::diag_file`).

use super::steps_for;
use crate::case::Case;
use crate::comm::Comm;
use crate::diag::grid::velocity_scale;
use crate::diag::{AxialBins, BandRule, PathTracker, Windows};
use crate::engine::Sim;
use crate::output::checkpoint::{self, DiagState, SavedSums};
use crate::output::diag_file::{self, DiagLayout};
use crate::output::{xdmf, RunFile};
use std::path::{Path, PathBuf};

/// When the diagnostics' events happen.
///
/// Samples are numbered `j = 1, 2, ...`; sample `j` is taken at `j` sample intervals, in
/// rotations [`Schedule::sample_rotations`], on the step nearest to that time
/// ([`steps_for`]). A per-slice window is `per_window` samples and ends, by construction, at
/// a whole multiple of its length in rotations (`diagnostics.window`): the window `k` ends on
/// the step nearest `k * window` rotations, so windows do not drift however the steps per
/// rotation round; a field window likewise is `per_field_window` samples.
#[derive(Debug, Clone, Copy)]
struct Schedule {
    /// Per-slice window in rotations.
    window: f64,
    /// Samples per per-slice window.
    per_window: u64,
    /// Samples per field window.
    per_field_window: u64,
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

    /// The nominal time of sample `j`, in rotations: whole windows plus whole intervals.
    fn sample_rotations(&self, j: u64) -> f64 {
        let (k, r) = (j / self.per_window, j % self.per_window);
        k as f64 * self.window + r as f64 * (self.window / self.per_window as f64)
    }

    /// The step sample `j` is taken at.
    fn sample_step(&self, j: u64) -> u64 {
        steps_for(self.sample_rotations(j), self.omega, self.dt)
    }

    /// Samples taken by the end of `step` (steps of equal time share one sample only if
    /// the interval is below a step, which [`Schedule::new`] refuses).
    fn samples_by(&self, step: u64) -> u64 {
        let interval = self.window / self.per_window as f64 * 2.0 * std::f64::consts::PI
            / (self.omega.abs() * self.dt);
        // an estimate within a sample or two, then the exact count
        let mut j = (step as f64 / interval.max(1.0)) as u64;
        while self.sample_step(j + 1) <= step {
            j += 1;
        }
        while j > 0 && self.sample_step(j) > step {
            j -= 1;
        }
        j
    }
}

/// The schedule for `case`, with the adjustments it needed said (`notes`).
fn schedule(case: &Case, notes: &mut Vec<String>) -> Result<Schedule, String> {
    let (omega, dt) = (case.drum.omega, case.dt());
    let g = &case.diagnostics;
    let per_window = ((g.window / g.sample_every).round() as u64).max(1);
    let interval = g.window / per_window as f64;
    if (interval - g.sample_every).abs() > 1e-9 * g.sample_every {
        notes.push(format!(
            "diagnostics.sample_every = {} does not divide diagnostics.window = {} into whole samples: samples are taken every {interval} rotations, {per_window} to a window",
            g.sample_every, g.window
        ));
    }
    let steps_per_interval = interval * 2.0 * std::f64::consts::PI / (omega.abs() * dt);
    if steps_per_interval < 1.0 {
        return Err(format!(
            "diagnostics.sample_every: samples every {interval} rotations would be {steps_per_interval:.3} time steps apart; it must be at least one step (run.dt = {dt})"
        ));
    }
    let per_field_window = ((g.fields.window / interval).round() as u64).max(1);
    let field_window = per_field_window as f64 * interval;
    if (field_window - g.fields.window).abs() > 1e-9 * g.fields.window {
        notes.push(format!(
            "diagnostics.fields.window = {} is not a whole number of samples ({interval} rotations): field windows hold {per_field_window} samples, {field_window} rotations",
            g.fields.window
        ));
    }
    Ok(Schedule {
        window: g.window,
        per_window,
        per_field_window,
        paths: steps_for(g.paths.every.unwrap_or(g.sample_every), omega, dt).max(1),
        snapshots: g.snapshots.every.map(|e| steps_for(e, omega, dt).max(1)),
        dt,
        omega,
    })
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
    /// The number of the next sample to take.
    next_sample: u64,
    units: crate::output::series::Units,
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
        restored: Option<(&DiagState, &Path)>,
    ) -> Result<Self, String> {
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
        let mut notes = Vec::new();
        let sched = schedule(case, &mut notes)?;
        if comm.rank() == 0 && restored.is_none() {
            for n in notes {
                log::warn!("{n}");
            }
        }
        let mut windows = Windows::new(case, &axial);
        windows.hold_own(comm.rank(), comm.size());
        let paths = match restored {
            Some((d, _)) if !d.whole_windows => {
                return Err("the checkpoint was written by a tumbler whose diagnostics windows were whole numbers of steps, not of rotations; its windows (in progress and in the output) cannot be continued on this schedule: finish that run with the version that started it".into());
            }
            Some((d, path)) => {
                let grid = case.field_grid();
                let differ = |what: &str, a: usize, b: usize| {
                    let mut m = format!(
                        "the checkpoint's diagnostics windows hold {a} {what}, this case's {b}: diagnostics.fields.grid or output.slice_width differ"
                    );
                    if case.diagnostics.fields.grid.is_none() {
                        m += &format!(
                            " (this case's grid is the default {grid:?}, bins a particle wide; a checkpoint written before that default kept [40, 40, 16]: set diagnostics.fields.grid = [40, 40, 16] to continue it)"
                        );
                    }
                    m
                };
                for (name, acc, saved) in [
                    ("slices", &mut windows.slices, &d.slices),
                    ("fields", &mut windows.fields, &d.fields),
                ] {
                    if saved.len != acc.len() {
                        return Err(differ("sums", saved.len, acc.len()));
                    }
                    acc.samples = saved.samples;
                    acc.angle_sum = saved.angle_sum;
                    // each rank reads its own block, whatever number of ranks wrote them
                    let read = checkpoint::read_sums(path, name, acc.blocks());
                    if let (Err(e), false) = (&read, comm.rank() == 0) {
                        log::error!("rank {}: {e}", comm.rank());
                    }
                    if !comm.all_ok(read.is_ok()) {
                        return Err(read.err().unwrap_or_else(|| {
                            "another rank could not read its block of the checkpoint's window sums (see its message)".into()
                        }));
                    }
                    acc.sums = read?;
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
            next_sample: sched.samples_by(sim.step) + 1,
            units: crate::output::series::Units::of(case),
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
            samples_per_window: self.sched.per_window,
            samples_per_field_window: self.sched.per_field_window,
            units: self.units,
        }
    }

    /// Records a checkpoint at `step` has behind it: `(slice windows, field windows, path
    /// samples)`.
    pub fn records_at(&self, step: u64) -> (usize, usize, usize) {
        let samples = self.sched.samples_by(step);
        (
            (samples / self.sched.per_window) as usize,
            (samples / self.sched.per_field_window) as usize,
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
        let j = self.next_sample;
        if step > 0 && step == s.sample_step(j) {
            self.next_sample += 1;
            self.windows.sample(&sim.p, comm);
            if j.is_multiple_of(s.per_window) {
                any = true;
                let start = s.sample_step(j - s.per_window);
                ok &= self.close(false, comm, file_now, start, step);
            }
            if j.is_multiple_of(s.per_field_window) {
                any = true;
                let start = s.sample_step(j - s.per_field_window);
                ok &= self.close(true, comm, file_now, start, step);
            }
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
        let taken = self.next_sample - 1;
        let mut ok = true;
        // a trailing partial window is written, with fewer samples than the group's
        // `samples_per_window`, so that readers can tell it from the whole ones
        if self.windows.slices.samples > 0 {
            let start = s.sample_step(taken - taken % s.per_window);
            ok &= self.close(false, comm, file, start, step);
        }
        if self.windows.fields.samples > 0 {
            let start = s.sample_step(taken - taken % s.per_field_window);
            ok &= self.close(true, comm, file, start, step);
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

    /// The state a checkpoint keeps (all ranks call this): each rank's block of the window
    /// sums, and the rest, the same on every rank.
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
            blocks: b.blocks(),
            sums: std::mem::take(&mut b.sums),
        };
        DiagState {
            slices: saved(&mut w.slices),
            fields: saved(&mut w.fields),
            angles: w.angles.clone(),
            path_ids: self.paths.ids.clone(),
            whole_windows: true,
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The quick case's schedule: 2513.27 steps per rotation, 50 samples a window.
    fn quick(window: f64, per_window: u64) -> Schedule {
        Schedule {
            window,
            per_window,
            per_field_window: 10 * per_window,
            paths: 50,
            snapshots: None,
            dt: 0.005,
            omega: 0.5,
        }
    }

    #[test]
    fn windows_end_on_the_step_nearest_whole_rotations_without_drift() {
        let s = quick(1.0, 50);
        let per_rotation = 2.0 * std::f64::consts::PI / (0.5 * 0.005);
        for k in [1u64, 2, 80, 4300, 1_000_000] {
            let end = s.sample_step(k * 50);
            assert!(
                (end as f64 - k as f64 * per_rotation).abs() <= 0.5,
                "window {k} ends at step {end}"
            );
            assert!((s.rotations(end) - k as f64).abs() <= 0.5 / per_rotation * 1.0001);
        }
    }

    #[test]
    fn samples_counted_by_a_step_are_those_taken_up_to_it() {
        for s in [quick(1.0, 50), quick(0.5, 7), quick(2.0, 3)] {
            for j in (1..3000).chain([123_456, 7_654_321]) {
                let at = s.sample_step(j);
                assert!(
                    at > s.sample_step(j - 1),
                    "samples {j} and {} share a step",
                    j - 1
                );
                assert_eq!(s.samples_by(at), j);
                assert_eq!(s.samples_by(at - 1), j - 1);
            }
        }
    }
}
