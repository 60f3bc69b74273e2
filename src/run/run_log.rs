//! The run's log: every line the program prints goes to stderr and, while rank 0 runs a
//! case, also to `NAME.log` beside the output (`NAME.h5` -> `NAME.log`).
//!
//! Levels: `error` and `warn` say what went wrong (`error: ...`, `warning: ...`), `info` is
//! what a user reads (the run's start, pour, progress, thermo lines, the closing summary),
//! `debug` adds the detail behind it (every load-balance check, rebuilds and phase times
//! between thermo lines, what each rank read of a checkpoint); `RUST_LOG` chooses, with
//! `env_logger`'s syntax (`RUST_LOG=debug`, `RUST_LOG=info,tumbler::run=debug`).
//!
//! A fresh run writes a new log (replacing one only with `--overwrite`, which the output's
//! checks already demand when the output exists); a log left by a run that wrote no output
//! is appended to, never replaced. A restart appends to the log of the run it continues.
//! Each run or restart starts with a separator line naming it, the version and the time.
//!
//! When stderr is a terminal, rank 0 shows a progress bar (`indicatif`) instead of the
//! plain progress lines, which still go to the file; elsewhere (CI, Slurm, `mpirun` piping)
//! the plain lines are printed.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use log::{Level, Log, Metadata, Record};
use std::fs::{File, OpenOptions};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Target of the progress lines: with a progress bar they go to the file only.
pub const PROGRESS: &str = "tumbler::progress";

/// Where lines go besides stderr.
struct Sink {
    file: Option<(File, PathBuf)>,
    bar: Option<ProgressBar>,
}

static SINK: Mutex<Sink> = Mutex::new(Sink {
    file: None,
    bar: None,
});

fn sink() -> MutexGuard<'static, Sink> {
    SINK.lock().unwrap_or_else(|e| e.into_inner())
}

/// The program's logger: `env_logger`'s filter, this module's format and sinks.
struct Logger(env_logger::Logger);

impl Log for Logger {
    fn enabled(&self, m: &Metadata) -> bool {
        self.0.enabled(m)
    }

    fn log(&self, r: &Record) {
        if self.0.matches(r) {
            emit(
                &format_line(r.level(), r.target(), r.args()),
                r.target() == PROGRESS,
            );
        }
    }

    fn flush(&self) {}
}

/// Install the logger (once, at the start of `main`): level `info` unless `RUST_LOG` says
/// otherwise.
pub fn init() {
    let filter =
        env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info")).build();
    log::set_max_level(filter.filter());
    // a second call (tests) keeps the first logger
    let _ = log::set_boxed_logger(Box::new(Logger(filter)));
}

/// How a line looks: `info` as it is (what a user reads), `warning: `/`error: ` before the
/// others, and the level and source for `debug` and `trace`.
pub fn format_line(level: Level, target: &str, args: &std::fmt::Arguments) -> String {
    match level {
        Level::Error => format!("error: {args}"),
        Level::Warn => format!("warning: {args}"),
        Level::Info => format!("{args}"),
        Level::Debug | Level::Trace => {
            format!("{} [{target}] {args}", level.as_str().to_lowercase())
        }
    }
}

/// Print `line` on stderr (above the bar, or not at all for a progress line when the bar
/// shows progress) and write it to the log file, if one is open.
fn emit(line: &str, progress: bool) {
    let mut sink = sink();
    match &sink.bar {
        Some(_) if progress => {}
        Some(bar) => bar.suspend(|| eprintln!("{line}")),
        None => eprintln!("{line}"),
    }
    let failed = match &mut sink.file {
        Some((file, path)) => writeln!(file, "{line}").err().map(|e| (e, path.clone())),
        None => None,
    };
    if let Some((e, path)) = failed {
        sink.file = None;
        eprintln!(
            "warning: cannot write the log {}: {e}; the run's messages go to stderr only from here",
            path.display()
        );
    }
}

/// The log beside an output: `NAME.h5` -> `NAME.log` (`NAME.log` -> `NAME.log.log`, so the
/// log is never the output itself).
pub fn log_path(output: &Path) -> PathBuf {
    if output.extension().is_some_and(|e| e == "log") {
        let mut s = output.as_os_str().to_owned();
        s.push(".log");
        PathBuf::from(s)
    } else {
        output.with_extension("log")
    }
}

/// How a run's log begins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogStart {
    /// A new run: replace an existing log only if `overwrite`, else append to it.
    Fresh {
        /// `--overwrite` was given.
        overwrite: bool,
    },
    /// A restart continuing the output: append.
    Continue,
}

/// The open log file of a run on rank 0; closing it (drop) stops writing lines to the file
/// and removes the progress bar.
#[derive(Debug)]
pub struct RunLog {
    path: PathBuf,
}

impl RunLog {
    /// Open the log of `output` and write the separator line `header` (with the time).
    pub fn open(output: &Path, start: LogStart, header: &str) -> Result<RunLog, String> {
        let path = log_path(output);
        let replace = start == (LogStart::Fresh { overwrite: true });
        let had_lines = !replace && std::fs::metadata(&path).is_ok_and(|m| m.len() > 0);
        let mut opts = OpenOptions::new();
        opts.create(true);
        if replace {
            opts.write(true).truncate(true);
        } else {
            opts.append(true);
        }
        let now = jiff::Timestamp::now().strftime("%Y-%m-%d %H:%M:%S UTC");
        let mut file = opts
            .open(&path)
            .and_then(|mut f| {
                if had_lines {
                    writeln!(f)?;
                }
                writeln!(f, "======== {header}, {now} ========")?;
                Ok(f)
            })
            .map_err(|e| format!("cannot write the run's log {}: {e}", path.display()))?;
        let _ = file.flush();
        sink().file = Some((file, path.clone()));
        Ok(RunLog { path })
    }

    /// The log file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Write `line` to the file only (what was already printed on stderr another way, such
    /// as the error `main` prints when a run fails).
    pub fn file_only(&self, line: &str) {
        if let Some((file, _)) = &mut sink().file {
            let _ = writeln!(file, "{line}");
        }
    }

    /// Show a progress bar of `total` steps, at `at` now, if stderr is a terminal; returns
    /// whether it does.
    pub fn show_progress(&self, total: u64, at: u64) -> bool {
        if !std::io::stderr().is_terminal() {
            return false;
        }
        let style = ProgressStyle::with_template(
            "{wide_bar} {percent:>3}%  {msg}  [{elapsed_precise}, ETA {eta_precise}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar());
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr())
            .with_style(style);
        bar.set_position(at);
        bar.reset_eta();
        sink().bar = Some(bar);
        true
    }

    /// Move the progress bar (if shown) to `step`, with `message` beside it.
    pub fn progress(&self, step: u64, message: impl FnOnce() -> String) {
        if let Some(bar) = &sink().bar {
            bar.set_position(step);
            bar.set_message(message());
        }
    }
}

impl RunLog {
    /// Remove the progress bar (the step loop is over; the summary follows as plain lines).
    pub fn end_progress(&self) {
        if let Some(bar) = sink().bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for RunLog {
    fn drop(&mut self) {
        let mut sink = sink();
        if let Some(bar) = sink.bar.take() {
            bar.finish_and_clear();
        }
        if let Some((mut file, _)) = sink.file.take() {
            let _ = file.flush();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_log_sits_beside_the_output_and_is_never_the_output() {
        assert_eq!(log_path(Path::new("d/run.h5")), PathBuf::from("d/run.log"));
        assert_eq!(log_path(Path::new("w6.28.h5")), PathBuf::from("w6.28.log"));
        assert_eq!(log_path(Path::new("run")), PathBuf::from("run.log"));
        assert_eq!(log_path(Path::new("a.log")), PathBuf::from("a.log.log"));
    }

    #[test]
    fn levels_are_marked_except_what_a_user_reads() {
        let f = |l: Level| format_line(l, "tumbler::run", &format_args!("x = {}", 1));
        assert_eq!(f(Level::Info), "x = 1");
        assert_eq!(f(Level::Warn), "warning: x = 1");
        assert_eq!(f(Level::Error), "error: x = 1");
        assert_eq!(f(Level::Debug), "debug [tumbler::run] x = 1");
    }

    #[test]
    fn a_fresh_log_replaces_only_with_overwrite_and_a_restart_appends() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("r.h5");
        let read = || std::fs::read_to_string(log_path(&out)).unwrap();
        let log = RunLog::open(&out, LogStart::Fresh { overwrite: false }, "first").unwrap();
        log.file_only("line of the first run");
        drop(log);
        let log = RunLog::open(&out, LogStart::Continue, "restart").unwrap();
        drop(log);
        let text = read();
        assert!(text.starts_with("======== first, "), "{text}");
        assert!(
            text.contains("line of the first run\n\n======== restart, "),
            "{text}"
        );
        drop(RunLog::open(&out, LogStart::Fresh { overwrite: false }, "second").unwrap());
        assert!(
            read().contains("line of the first run"),
            "kept without --overwrite"
        );
        drop(RunLog::open(&out, LogStart::Fresh { overwrite: true }, "third").unwrap());
        let text = read();
        assert!(
            text.starts_with("======== third, ") && text.lines().count() == 1,
            "{text}"
        );
    }
}
