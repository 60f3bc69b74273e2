//! A whole run: initial state, the step loop with sampling and progress, and the outputs.

use crate::case::{parse_case, Case, LoadedCase};
use crate::comm::Comm;
use crate::diag::count_bands;
use crate::engine::{Phase, Sim, PHASES};
use crate::init::{initial_particles, pour, Share};
use crate::output::checkpoint::{self, checkpoint_path, Checkpoint};
use crate::output::{diag_file, spacetime, RunFile, RunMeta};
use crate::particles::Records;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

mod diagnostics;
mod preflight;
pub mod run_log;
pub mod thermo;
pub use diagnostics::RunDiagnostics;
pub use preflight::same_file;

/// Steps between checks of the stop flag (a global reduction).
const STOP_CHECK_EVERY: u64 = 20;
/// Steps between two returns of the heap's free pages to the system ([`trim_heap`]).
const TRIM_EVERY: u64 = 1000;

/// Exit code of a run stopped by SIGTERM/SIGINT after writing its checkpoint.
pub const EXIT_STOPPED: u8 = 3;

/// Options of `tumbler run` beyond the case.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The HDF5 file to write.
    pub output: PathBuf,
    /// Replace an existing output file.
    pub overwrite: bool,
    /// Continue from this checkpoint (appending to `output`).
    pub restart: Option<PathBuf>,
    /// Accept a checkpoint whose drum, model, species or time step differ from the case.
    pub allow_different_case: bool,
    /// With `restart`: write the continuation to a new file `output` (which must not exist)
    /// instead of continuing the output of the run that wrote the checkpoint.
    pub new_output: bool,
    /// Set (by a signal handler) to ask every rank to checkpoint and stop.
    pub stop: Option<Arc<AtomicBool>>,
}

/// How a run ended.
#[derive(Debug, Clone)]
pub enum RunEnd {
    /// It ran to the end.
    Finished(RunSummary),
    /// It was asked to stop, and wrote a checkpoint at `step`.
    Stopped {
        /// The step the checkpoint holds.
        step: u64,
        /// The checkpoint to restart from.
        checkpoint: PathBuf,
    },
}

/// What a finished run reports.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// Particles in the run.
    pub particles: u64,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock seconds of the step loop.
    pub seconds: f64,
    /// Particle-steps per second over all ranks.
    pub particle_steps_per_second: f64,
}

/// Steps in `rotations` turns of the drum.
pub fn steps_for(rotations: f64, omega: f64, dt: f64) -> u64 {
    (rotations * 2.0 * std::f64::consts::PI / (omega.abs() * dt)).round() as u64
}

/// The PNG written next to `output` (`NAME.h5` -> `NAME_spacetime.png`).
pub fn spacetime_path(output: &Path) -> PathBuf {
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    output.with_file_name(format!("{stem}_spacetime.png"))
}

/// Run `lc` on the ranks of `comm`. Rank 0 writes the outputs and the log.
pub fn run(lc: &LoadedCase, comm: &dyn Comm, opts: &RunOptions) -> Result<RunEnd, String> {
    let root = comm.rank() == 0;
    // a rank count the drum cannot be cut into is refused before any file is touched (every
    // rank finds the same)
    crate::engine::sim::slabs_fit(&lc.case, comm.size())?;
    // Before anything is computed or written: rank 0 checks the run's files, locks the
    // output and opens the log (both held until this function returns, the log closed first).
    let mut held = None;
    let mut refused = String::new();
    if root {
        match preflight::prepare(lc, opts).and_then(|lock| Ok((open_log(lc, comm, opts)?, lock))) {
            Ok(h) => held = Some(h),
            Err(e) => refused = e,
        }
    }
    if !comm.all_ok(refused.is_empty()) {
        return Err(if root {
            refused
        } else {
            "rank 0 refused the run's files".into()
        });
    }
    let runlog = held.as_ref().and_then(|h| h.0.as_ref());
    let result = run_locked(lc, comm, opts, runlog);
    if let (Err(e), Some(log)) = (&result, runlog) {
        // `main` prints it on stderr
        log.file_only(&format!("error: {e}"));
    }
    result
}

/// Open the run's log (rank 0): a restart continuing its output appends, a fresh run starts
/// one. `None` for a restart with `--new-output` onto an existing output, which is refused
/// once the checkpoint is read, without writing into that output's log.
fn open_log(
    lc: &LoadedCase,
    comm: &dyn Comm,
    opts: &RunOptions,
) -> Result<Option<run_log::RunLog>, String> {
    let out = &opts.output;
    let exists = out.exists() || crate::output::partial_path(out).exists();
    let ranks = comm.size();
    let version = concat!("tumbler ", env!("CARGO_PKG_VERSION"));
    let (start, header) = match &opts.restart {
        Some(_) if opts.new_output && exists => return Ok(None),
        Some(ck) if !opts.new_output => (
            run_log::LogStart::Continue,
            format!(
                "{version} ({}): restart of {} from {} on {ranks} ranks, continuing {}",
                crate::GIT_HASH,
                lc.path,
                ck.display(),
                out.display()
            ),
        ),
        _ => (
            run_log::LogStart::Fresh {
                overwrite: opts.overwrite,
            },
            format!(
                "{version} ({}): run of {} on {ranks} ranks, writing {}",
                crate::GIT_HASH,
                lc.path,
                out.display()
            ),
        ),
    };
    run_log::RunLog::open(out, start, &header).map(Some)
}

/// [`run`] once the output is locked and the log open.
fn run_locked(
    lc: &LoadedCase,
    comm: &dyn Comm,
    opts: &RunOptions,
    runlog: Option<&run_log::RunLog>,
) -> Result<RunEnd, String> {
    let case = &lc.case;
    let root = comm.rank() == 0;
    let (omega, dt) = (case.drum.omega, case.dt());
    let total = steps_for(case.run.rotations, omega, dt);
    let every = steps_for(case.output.sample_every, omega, dt).max(1);
    let mut pour_report = None;
    let mut restored_diag = None;
    let (mut sim, resumed_samples) = match &opts.restart {
        Some(path) => {
            // each rank reads its share of the particles and contacts
            let ck = checkpoint::read_share(path, comm.rank(), comm.size());
            if let (Err(e), false) = (&ck, root) {
                // only rank 0 prints the run's error: say what this rank's share showed
                log::error!("rank {}: {e}", comm.rank());
            }
            if !comm.all_ok(ck.is_ok()) {
                return Err(ck.err().unwrap_or_else(|| {
                    "another rank could not read its share of the checkpoint (see its message)"
                        .into()
                }));
            }
            let ck = ck?;
            check_compatible(&ck.case_text, case, opts.allow_different_case, path)?;
            if let Some(end) = no_steps_left(&ck, total, case, path, &opts.output)? {
                if root {
                    log::warn!("{end}");
                }
                return Ok(RunEnd::Finished(RunSummary {
                    particles: ck.n_particles,
                    steps: 0,
                    seconds: 0.0,
                    particle_steps_per_second: 0.0,
                }));
            }
            let refused = if root {
                preflight::check_restart_output(opts, path).err()
            } else {
                None
            };
            if !comm.all_ok(refused.is_none()) {
                return Err(refused.unwrap_or_else(|| "rank 0 refused the run's output".into()));
            }
            log::debug!(
                "rank {}: read {} of {} particles and {} contact histories of the checkpoint",
                comm.rank(),
                ck.particles.len(),
                ck.n_particles,
                ck.histories.len()
            );
            let sim = Sim::resume(case, comm, &ck.particles, ck.histories, ck.step)
                .map_err(|e| e.to_string())?;
            if root {
                log::info!(
                    "restart from {} at step {} ({:.3} rotations)",
                    path.display(),
                    ck.step,
                    sim.rotations()
                );
            }
            restored_diag = Some((ck.diag, path.clone()));
            (sim, Some(ck.samples))
        }
        None => {
            // each rank makes (or reads) the particles of its own slab: stop together, with
            // the first rank's reason, if one cannot
            let slabs = crate::engine::sim::initial_slabs(case, comm.size());
            let (me, (lo, hi)) = (comm.rank(), slabs.owned_span(comm.rank()));
            let owns = |z: f64| slabs.owner(z) == me;
            let init = initial_particles(case, &Share::new(lo, hi, &owns));
            let init = match (comm.first_error(init.as_ref().err().cloned()), init) {
                (Some(e), _) => return Err(e),
                (None, Ok(init)) => init,
                (None, Err(e)) => return Err(e),
            };
            let (initial, start_scale) = init;
            if let Some(id) = crate::init::duplicate_id(&initial, comm) {
                return Err(crate::init::duplicate(case, id));
            }
            let mut sim = Sim::new(case, comm, &initial).map_err(|e| e.to_string())?;
            drop(initial);
            if case.init.kind == crate::case::InitKind::Pour {
                let t0 = Instant::now();
                let r = pour::grow_settle_cut(&mut sim, case, start_scale)?;
                if root {
                    log::info!(
                        "pour: {} particles poured, {} kept below the cut at y = {:.5} (fill {:.4} requested, {:.4} measured from the bed top) in {:.1} s",
                        r.poured,
                        r.kept,
                        r.cut_height,
                        case.init.fill.unwrap_or(0.0),
                        r.measured_fill,
                        t0.elapsed().as_secs_f64()
                    );
                }
                pour_report = Some(r);
            }
            (sim, None)
        }
    };
    let n_total = sim.global_count();

    let mut diags = RunDiagnostics::new(
        case,
        &sim,
        comm,
        &opts.output,
        restored_diag.as_ref().map(|(d, p)| (d, p.as_path())),
    )?;
    let bins = diags.axial.clone();
    let balance_steps = steps_for(case.run.balance_every, case.drum.omega, case.dt()).max(1);
    let (band_rule, big) = (diags.rule, diags.big);
    // Open the output on rank 0 only once everything else is known to be fine.
    let mut file = None;
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut open_err = String::new();
    if root {
        let meta = RunMeta {
            case_text: lc.text.clone(),
            ranks: comm.size(),
            species: case.species.iter().map(|s| s.name.clone()).collect(),
        };
        let partial = crate::output::partial_path(&opts.output);
        let opened = match resumed_samples {
            Some(samples) if opts.output.exists() || partial.exists() => RunFile::reopen(
                &opts.output,
                samples as usize,
                big,
                comm.size(),
            )
            .and_then(|(f, c)| {
                columns = c;
                diags
                    .resume_file(&f, sim.step)
                    .and_then(|()| {
                        diag_file::prepare_balance(f.file(), comm.size(), Some(sim.rotations()))
                    })
                    .map_err(|e| {
                        format!("cannot continue output file {}: {e}", partial.display())
                    })?;
                Ok(f)
            }),
            _ => RunFile::create(&opts.output, &meta, &bins.centres(), &diags.layout())
                .and_then(|f| {
                    diag_file::prepare_balance(f.file(), comm.size(), None)?;
                    Ok(f)
                })
                .map_err(|e| format!("cannot open output file {}: {e}", opts.output.display())),
        };
        match opened {
            Ok(f) => file = Some(f),
            Err(e) => open_err = e,
        }
    }
    if !comm.all_ok(open_err.is_empty()) {
        return Err(if root {
            open_err
        } else {
            "rank 0 could not open the output".into()
        });
    }

    let progress_every = steps_for(case.output.progress_every, omega, dt).max(1);
    if root {
        log::info!(
            "{}: {} particles on {} ranks, {} steps ({} rotations), dt = {}",
            lc.path,
            n_total,
            comm.size(),
            total,
            case.run.rotations,
            dt
        );
        let isa = crate::engine::forces::Isa::detect();
        log::info!(
            "pair contacts: {} ({} on this CPU; TUMBLER_ISA=reference|base|avx2 caps it, with the same bits)",
            isa.name(),
            crate::engine::forces::Isa::of_cpu().name()
        );
    }

    let thermo_every = steps_for(case.thermo_every(), omega, dt).max(1);
    let mut thermo = thermo::Thermo::new(case, &bins, thermo_every);
    thermo.report(&sim, root);
    let bar = runlog.is_some_and(|l| l.show_progress(total, sim.step));

    let mut sample = |sim: &mut Sim, file: &mut Option<RunFile>| -> Result<(), String> {
        let s = bins.gather(&sim.p, comm);
        let mut ok = true;
        if let (Some(s), Some(f)) = (s, file.as_mut()) {
            let counted: u64 = s.count.iter().sum();
            if counted != n_total {
                log::error!(
                    "particle count is {counted} at step {}, expected {n_total}",
                    sim.step
                );
                ok = false;
            }
            let profile = &s.volume_fraction[big * bins.nz..(big + 1) * bins.nz];
            let bands = count_bands(profile, &band_rule) as u64;
            columns.push(profile.to_vec());
            if let Err(e) = f.append(sim.rotations(), &s, bands) {
                log::error!("writing the axial sample: {e}");
                ok = false;
            }
        }
        if comm.all_ok(ok) {
            Ok(())
        } else {
            Err("stopped: the particle count changed or the output could not be written".into())
        }
    };

    // Samples on the schedule (every `every` steps) are what a checkpoint counts; a final
    // sample off the schedule is written but dropped again by a restart.
    let mut imbalance = 1.0;
    let mut scheduled = match resumed_samples {
        Some(k) => {
            // a checkpoint at the last step of a run that had not been renamed yet: the
            // final sample, off the schedule, was cut with the file; take it again
            if sim.step == total && !total.is_multiple_of(every) {
                sample(&mut sim, &mut file)?;
            }
            k
        }
        None => {
            sample(&mut sim, &mut file)?;
            diags.after_step(&sim, comm, &mut file)?;
            imbalance = balance_check(&mut sim, case, file.as_ref())?;
            1
        }
    };
    let ck_every = case
        .output
        .checkpoint_every
        .map(|r| steps_for(r, omega, dt).max(1));
    let ck_path = checkpoint_path(&opts.output);
    let start = Instant::now();
    let first_step = sim.step;
    let mut last_report = (Instant::now(), sim.step);
    while sim.step < total {
        sim.step();
        let on_schedule = sim.step % every == 0;
        if on_schedule || sim.step == total {
            let t0 = Instant::now();
            sample(&mut sim, &mut file)?;
            if on_schedule {
                scheduled += 1;
            }
            sim.timers.add(Phase::Output, t0.elapsed().as_secs_f64());
        }
        let t0 = Instant::now();
        diags.after_step(&sim, comm, &mut file)?;
        sim.timers.add(Phase::Output, t0.elapsed().as_secs_f64());
        if sim.step % balance_steps == 0 {
            imbalance = balance_check(&mut sim, case, file.as_ref())?;
        }
        if sim.step % TRIM_EVERY == 0 {
            trim_heap();
        }
        if sim.step % STOP_CHECK_EVERY == 0 {
            let health = sim.health(case.run.max_overlap, "run.max_overlap");
            if let Err(e) = &health {
                log::error!("{e}");
            }
            if !comm.all_ok(health.is_ok()) {
                return Err(health.err().unwrap_or_else(|| {
                    "run stopped: another rank found an unhealthy particle (see its message)".into()
                }));
            }
        }
        if let Some(stop) = &opts.stop {
            if sim.step % STOP_CHECK_EVERY == 0 && !comm.all_ok(!stop.load(Ordering::SeqCst)) {
                // every rank finishes this step, then the state is saved and the run stops;
                // the output stays NAME.partial for the restart to continue
                save_checkpoint(
                    &sim,
                    &mut diags,
                    &lc.text,
                    scheduled,
                    &ck_path,
                    file.as_ref(),
                )?;
                drop(file);
                if root {
                    log::warn!(
                        "stopped by a signal at step {} ({:.3} rotations); checkpoint {}; continue with --restart",
                        sim.step,
                        sim.rotations(),
                        ck_path.display()
                    );
                }
                return Ok(RunEnd::Stopped {
                    step: sim.step,
                    checkpoint: ck_path,
                });
            }
        }
        if ck_every.is_some_and(|k| sim.step % k == 0) && sim.step < total {
            let t0 = Instant::now();
            save_checkpoint(
                &sim,
                &mut diags,
                &lc.text,
                scheduled,
                &ck_path,
                file.as_ref(),
            )?;
            sim.timers.add(Phase::Output, t0.elapsed().as_secs_f64());
        }
        if thermo.due(sim.step, total) {
            let t0 = Instant::now();
            thermo.report(&sim, root);
            sim.timers.add(Phase::Output, t0.elapsed().as_secs_f64());
        }
        if let (true, Some(l)) = (bar && sim.step % STOP_CHECK_EVERY == 0, runlog) {
            l.progress(sim.step, || {
                format!("rotation {:.2}/{}", sim.rotations(), case.run.rotations)
            });
        }
        if root && sim.step % progress_every == 0 {
            let (t_prev, s_prev) = last_report;
            let rate = (sim.step - s_prev) as f64 / t_prev.elapsed().as_secs_f64().max(1e-9);
            let eta = (total - sim.step) as f64 / rate;
            log::info!(
                target: run_log::PROGRESS,
                "rotation {:.1}/{} ({:.0}%), {:.2} M particle-steps/s, imbalance {:.3}, ETA {}",
                sim.rotations(),
                case.run.rotations,
                100.0 * sim.step as f64 / total as f64,
                rate * n_total as f64 / 1e6,
                imbalance,
                crate::report::duration(eta)
            );
            last_report = (Instant::now(), sim.step);
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    if let Some(l) = runlog {
        l.end_progress();
    }
    save_checkpoint(
        &sim,
        &mut diags,
        &lc.text,
        scheduled,
        &ck_path,
        file.as_ref(),
    )?;
    diags.finish(&sim, comm, file.as_ref())?;

    // every rank writes its share of the final state
    let states = sim.particles_by_id();
    crate::output::h5::write_particles(comm, &opts.output, &mut file, &states)
        .map_err(|e| format!("writing {}: {e}", opts.output.display()))?;
    drop(states);
    let migrations = comm.sum_u64(sim.migrated);
    let peak_rss = comm.max_f64(peak_rss_bytes() as f64);
    let histories_migrated = comm.sum_u64(sim.histories_migrated);
    let mut write_err = String::new();
    if let Some(f) = file {
        let written = f
            .write_number("steps", sim.step)
            .and_then(|_| f.write_number("rebuilds", sim.rebuilds))
            .and_then(|_| f.write_number("migrations", migrations))
            .and_then(|_| f.write_number("histories_migrated", histories_migrated))
            .and_then(|_| f.write_number("peak_rss_bytes_per_rank", peak_rss))
            .and_then(|_| match &pour_report {
                Some(r) => f
                    .write_number("pour_poured", r.poured)
                    .and_then(|_| f.write_number("pour_cut_height", r.cut_height))
                    .and_then(|_| f.write_number("pour_measured_fill", r.measured_fill)),
                None => Ok(()),
            })
            .map_err(|e| e.to_string())
            .and_then(|_| f.finish().map_err(|e| e.to_string()))
            .and_then(|path| {
                spacetime::write_png(&spacetime_path(&path), &columns).map_err(|e| e.to_string())
            });
        if let Err(e) = written {
            write_err = format!("writing {}: {e}", opts.output.display());
        }
    }
    if !comm.all_ok(write_err.is_empty()) {
        return Err(write_err);
    }

    let [owned, ghosts, bytes] = sim.spread();
    let steps = sim.step - first_step;
    let summary = RunSummary {
        particles: n_total,
        steps,
        seconds,
        particle_steps_per_second: n_total as f64 * steps as f64 / seconds.max(1e-12),
    };
    if root {
        log::info!(
            "done: {} steps in {:.1} s, {:.3} M particle-steps/s on {} ranks ({:.3} M per rank); {} rebuilds, {} migrations",
            summary.steps,
            seconds,
            summary.particle_steps_per_second / 1e6,
            comm.size(),
            summary.particle_steps_per_second / 1e6 / comm.size() as f64,
            sim.rebuilds,
            migrations
        );
        log::info!(
            "peak memory {:.1} MiB on the largest rank ({:.0} B per particle of that rank's share)",
            peak_rss / (1u64 << 20) as f64,
            peak_rss * comm.size() as f64 / n_total.max(1) as f64
        );
        log::info!(
            "per rank: {:.0} to {:.0} particles (rough-wall ones included), {:.0} to {:.0} ghosts, {:.1} to {:.1} kB sent per step to refresh the ghosts",
            owned.0,
            owned.1,
            ghosts.0,
            ghosts.1,
            bytes.0 / 1e3,
            bytes.1 / 1e3
        );
        let total_t = sim.timers.total().max(1e-12);
        for ph in PHASES {
            log::info!(
                "  {:<16} {:>9.2} s  {:>5.1}%",
                ph.name(),
                sim.timers.get(ph),
                100.0 * sim.timers.get(ph) / total_t
            );
        }
        log::info!(
            "wrote {} and {}",
            opts.output.display(),
            spacetime_path(&opts.output).display()
        );
    }
    Ok(RunEnd::Finished(summary))
}

/// Bytes from which glibc's `malloc` maps a block of its own ([`return_freed_memory`]).
pub const MMAP_THRESHOLD: usize = 128 << 10;

/// Have glibc's `malloc` give big freed blocks back to the system: every block of
/// [`MMAP_THRESHOLD`] or more is mapped on its own and unmapped when freed. By default glibc
/// raises that threshold to the largest block freed so far (up to 32 MiB), after which the
/// big transient buffers of a rebuild or a checkpoint (the particles in id order, the
/// exchanges, the cell lists) come from the heap, stay resident once freed, and fragment it,
/// so that the next big buffer adds to the peak instead of reusing them. Call it first, before
/// anything is allocated; nothing elsewhere (other C libraries, other platforms).
pub fn return_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets a parameter of the allocator; called before any thread.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD as i32);
    }
}

/// Give the heap's free pages back to the system (glibc's `malloc_trim`): the chunks freed
/// between the blocks still in use stay resident otherwise, and a run's many small
/// messages, lists and output buffers of varying size leave more of them as it goes on
/// (3-5 MiB over 20,000 steps of the bench bed on 2 ranks, about 0.2 MiB per 1,000 steps).
/// Called every [`TRIM_EVERY`] steps, so that they do not pile up, and before a
/// checkpoint's gather of the particles in id order, so that the peak does not come on top
/// of them.
pub fn trim_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only returns free memory of the allocator to the system.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Peak resident memory of this process (`VmHWM` of `/proc/self/status`), in bytes; 0 where
/// it cannot be read.
pub fn peak_rss_bytes() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<u64>().ok())
        })
        .map_or(0, |kb| kb * 1024)
}

/// Check the load balance (all ranks together), move the slab boundaries if it is uneven,
/// and record the check; returns the imbalance now.
fn balance_check(sim: &mut Sim, case: &Case, file: Option<&RunFile>) -> Result<f64, String> {
    let t0 = Instant::now();
    let check = sim.rebalance(case.run.balance_tolerance);
    let (before, after) = (check.before, check.after);
    let mut ok = true;
    if let Some(f) = file {
        if let Err(e) =
            diag_file::append_balance(f.file(), sim.rotations(), &check, &sim.slabs.bounds)
        {
            log::error!("writing a load-balance check: {e}");
            ok = false;
        }
        log::debug!(
            "load-balance check at rotation {:.2}: work per rank max/mean {before:.3}, {:.3} after; slab bounds {:?}",
            sim.rotations(),
            after,
            sim.slabs.bounds
        );
        if after < before {
            log::info!(
                "load balance at rotation {:.2}: imbalance {before:.3} -> {after:.3}, slab bounds {:?}",
                sim.rotations(),
                sim.slabs.bounds
            );
        }
    }
    sim.timers.add(Phase::Output, t0.elapsed().as_secs_f64());
    if sim.comm().all_ok(ok) {
        Ok(after)
    } else {
        Err("stopped: the load-balance record could not be written".into())
    }
}

/// Write a checkpoint of `sim` (all ranks call this together; rank 0 writes). The output
/// `file` is synced to disk first, so that the records the checkpoint counts are there
/// before it is; if that fails, no checkpoint is written and the previous one stays.
fn save_checkpoint(
    sim: &Sim,
    diags: &mut RunDiagnostics,
    case_text: &str,
    samples: u64,
    path: &Path,
    file: Option<&RunFile>,
) -> Result<(), String> {
    let comm = sim.comm();
    trim_heap();
    let diag = diags.state(comm);
    let mut err = String::new();
    if let Some(Err(e)) = file.map(RunFile::sync) {
        err = format!("{e}; no checkpoint written (the previous one, if any, is kept)");
    }
    // every rank writes its share of the particles and contacts, once rank 0's output is on
    // disk
    if !comm.all_ok(err.is_empty()) {
        diags.restore(diag);
        return Err(if err.is_empty() {
            "rank 0 could not write the output to disk; no checkpoint written".into()
        } else {
            err
        });
    }
    let ck = Checkpoint {
        case_text: case_text.to_string(),
        step: sim.step,
        samples,
        n_particles: 0,
        particles: Records::default(),
        histories: Vec::new(),
        history_words: sim.law.history_words(),
        diag,
    };
    let written = checkpoint::write(comm, path, &ck, &mut SimRows(sim));
    diags.restore(ck.diag);
    written
}

/// A checkpoint's rows gathered from the run as they are written.
struct SimRows<'s, 'c>(&'s Sim<'c>);

impl checkpoint::Gather for SimRows<'_, '_> {
    fn counts(&self) -> [u64; 2] {
        self.0.checkpoint_rows()
    }
    fn particles(&mut self) -> Records {
        self.0.particles_by_id()
    }
    fn histories(&mut self) -> crate::engine::neighbor::SavedHistory {
        self.0.histories_by_ids()
    }
}

/// Refuse a checkpoint from another drum, model, species set or time step (unless `allow`).
fn check_compatible(text: &str, case: &Case, allow: bool, path: &Path) -> Result<(), String> {
    let old = parse_case(text, "checkpoint").map_err(|e| {
        format!(
            "checkpoint {}: its case no longer parses: {}",
            path.display(),
            e.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        )
    })?;
    let differ: Vec<&str> = [
        (
            "drum",
            format!("{:?}", old.drum) != format!("{:?}", case.drum),
        ),
        (
            "model",
            format!("{:?}", old.model) != format!("{:?}", case.model),
        ),
        (
            "species",
            format!("{:?}", old.species) != format!("{:?}", case.species),
        ),
        ("run.dt", old.dt() != case.dt()),
    ]
    .into_iter()
    .filter_map(|(k, d)| d.then_some(k))
    .collect();
    // the windows in progress and the file's series follow the diagnostics' schedule and
    // grids: those cannot change mid-run, even when asked
    if format!("{:?}", old.diagnostics) != format!("{:?}", case.diagnostics)
        || old.output.slice_width != case.output.slice_width
    {
        return Err(format!(
            "checkpoint {} comes from a case with different diagnostics (diagnostics.* or output.slice_width); the windows in progress and the series in the file follow them, so they cannot change in a restart",
            path.display()
        ));
    }
    if differ.is_empty() || allow {
        if !differ.is_empty() {
            log::warn!("restarting with a different {}", differ.join(", "));
        }
        Ok(())
    } else {
        Err(format!(
            "checkpoint {} comes from a case with a different {}; pass --allow-different-case to restart anyway",
            path.display(),
            differ.join(", ")
        ))
    }
}

/// A restart whose checkpoint leaves no step to take: `Some(message)` when the finished
/// output is there (nothing to do, it is left as it is), an error when the checkpoint is
/// past `run.rotations`, `None` when there is something to do (steps, or the last step's
/// output to finish).
fn no_steps_left(
    ck: &Checkpoint,
    total: u64,
    case: &Case,
    path: &Path,
    output: &Path,
) -> Result<Option<String>, String> {
    let done =
        |step: u64| step as f64 * case.dt() * case.drum.omega.abs() / (2.0 * std::f64::consts::PI);
    if ck.step > total {
        return Err(format!(
            "checkpoint {} is at step {} ({:.4} rotations), past run.rotations = {} (step {total}): there is nothing to continue; raise run.rotations to go on",
            path.display(),
            ck.step,
            done(ck.step),
            case.run.rotations
        ));
    }
    let finished = output.exists() && !crate::output::partial_path(output).exists();
    Ok((ck.step == total && finished).then(|| {
        format!(
            "nothing to do: checkpoint {} is at the end of the run (step {total}, run.rotations = {}), and {} holds the whole run; it is left unchanged (raise run.rotations to continue it)",
            path.display(),
            case.run.rotations,
            output.display()
        )
    }))
}
