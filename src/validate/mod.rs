//! `tumbler validate`: reduced runs of the seed studies, each checked against a result the
//! seed reports (docs/validation.md).
//!
//! - [`checks`]: the checks — which runs, what the seed says, how it is judged;
//! - [`measure`]: the figures read from a run's file (profiles, bands, end-wall flow);
//! - [`analytic`]: collisions and rolling followed on the engine directly.
//!
//! Every rank takes part in every run; rank 0 reads the files, draws the figures and
//! judges. Runs go to `OUT/<check>/<case>.h5`; with `--reuse`, a finished file whose case
//! has every key the same as the one this check would run (the title and comments may
//! differ) is judged again instead of rerun, and an unfinished one (`<case>.h5.partial`)
//! continues from its checkpoint `<case>.ckpt.h5` when that holds the same case. A run
//! stopped by a signal checkpoints, as `tumbler run` does, so a check of hours survives a
//! batch system's time limit.

pub mod analytic;
pub mod checks;
pub mod measure;

use crate::case::{apply_overrides, parse_case, Case, LoadedCase};
use crate::comm::Comm;
use crate::inspect::{attr_string, InspectError, RunReader};
use crate::output::checkpoint::checkpoint_path;
use crate::output::partial_path;
use crate::run::{run, RunEnd, RunOptions};
use checks::{Check, CHECKS};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Exit code of `tumbler validate` when a check fails.
pub const EXIT_CHECK_FAILED: u8 = 4;

/// How much to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tier {
    /// The subset CI runs: a few minutes on two cores.
    Ci,
    /// Every check, each run reduced to minutes or tens of minutes on two cores.
    Full,
}

/// One run of a check: a case of `cases/` (compiled in) and its overrides.
#[derive(Debug, Clone)]
pub struct RunSpec {
    /// The case's name in `cases/`, without `.toml`.
    pub case: &'static str,
    /// `key=value` overrides, as `--set` takes them.
    pub overrides: Vec<String>,
}

impl RunSpec {
    /// `case` with `overrides`.
    pub fn new(case: &'static str, overrides: &[&str]) -> Self {
        RunSpec {
            case,
            overrides: overrides.iter().map(|s| s.to_string()).collect(),
        }
    }

    /// The effective case: the compiled-in text with the overrides applied.
    pub fn load(&self) -> Result<LoadedCase, String> {
        let name = format!("cases/{}.toml", self.case);
        let text = case_text(self.case).ok_or_else(|| format!("no case {name}"))?;
        let text = apply_overrides(text, &self.overrides, &name).map_err(|e| e.to_string())?;
        let case = parse_case(&text, &name).map_err(|errs| {
            errs.iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        })?;
        Ok(LoadedCase {
            case,
            text,
            path: name,
        })
    }
}

/// One measured figure beside the seed's.
#[derive(Debug, Clone)]
pub struct Finding {
    /// What was measured.
    pub what: String,
    /// What the seed reports.
    pub seed: String,
    /// What the runs gave.
    pub measured: String,
    /// Pass or fail; `None` for a figure reported beside the seed's but not judged.
    pub pass: Option<bool>,
}

impl Finding {
    /// A judged figure.
    pub fn judged(what: String, seed: &str, measured: String, pass: bool) -> Self {
        Finding {
            what,
            seed: seed.into(),
            measured,
            pass: Some(pass),
        }
    }

    /// A figure reported but not judged.
    pub fn note(what: String, seed: &str, measured: String) -> Self {
        Finding {
            what,
            seed: seed.into(),
            measured,
            pass: None,
        }
    }

    fn mark(&self) -> &'static str {
        match self.pass {
            Some(true) => "pass",
            Some(false) => "FAIL",
            None => "note",
        }
    }
}

/// What a check concluded.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// The figures measured.
    pub findings: Vec<Finding>,
    /// The pictures drawn.
    pub figures: Vec<PathBuf>,
}

impl Verdict {
    /// Whether every judged finding passed.
    pub fn passed(&self) -> bool {
        self.findings.iter().all(|f| f.pass != Some(false))
    }
}

/// A check's finished runs, open for reading (rank 0).
pub struct Runs {
    /// The runs, in the check's order.
    pub specs: Vec<RunSpec>,
    /// Their files.
    pub files: Vec<PathBuf>,
    /// The files, open.
    pub readers: Vec<RunReader>,
    /// The check's output folder.
    pub dir: PathBuf,
}

impl Runs {
    /// `DIR/<file stem>_<what>.png`.
    pub fn figure(&self, file: &Path, what: &str) -> PathBuf {
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        self.dir.join(format!("{stem}_{what}.png"))
    }

    /// Particles in run `k` (`/particles/id`).
    pub fn particles(&self, k: usize) -> Result<usize, InspectError> {
        Ok(self.readers[k].dataset("particles/id")?.size())
    }
}

/// Options of `tumbler validate`.
#[derive(Debug, Clone)]
pub struct ValidateOptions {
    /// Which tier.
    pub tier: Tier,
    /// Only these checks (all of the tier when empty).
    pub only: Vec<String>,
    /// The output folder.
    pub out: PathBuf,
    /// Judge finished files again instead of rerunning them, and continue unfinished ones
    /// from their checkpoints.
    pub reuse: bool,
    /// Set (by a signal handler) to make the current run checkpoint and stop.
    pub stop: Option<Arc<AtomicBool>>,
}

/// How `tumbler validate` ended.
#[derive(Debug, Clone)]
pub enum ValidateEnd {
    /// Every selected check was run and judged: the report (on rank 0; empty elsewhere) and
    /// whether every check passed.
    Judged {
        /// The Markdown report, also written to `OUT/report.md`.
        report: String,
        /// Whether every judged finding passed.
        passed: bool,
    },
    /// A signal stopped a run after it wrote `checkpoint`; `--reuse` continues it.
    Stopped {
        /// The checkpoint written.
        checkpoint: PathBuf,
    },
}

/// The checks `opts` selects, or the unknown names.
pub fn select(opts: &ValidateOptions) -> Result<Vec<&'static Check>, String> {
    let unknown: Vec<&String> = opts
        .only
        .iter()
        .filter(|n| !CHECKS.iter().any(|c| c.name == n.as_str()))
        .collect();
    if !unknown.is_empty() {
        let names: Vec<&str> = CHECKS.iter().map(|c| c.name).collect();
        return Err(format!(
            "--only: no check named {} (the checks: {})",
            unknown
                .iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(", "),
            names.join(", ")
        ));
    }
    Ok(CHECKS
        .iter()
        .filter(|c| {
            if opts.only.is_empty() {
                opts.tier == Tier::Full || c.in_ci
            } else {
                opts.only.iter().any(|n| n == c.name)
            }
        })
        .collect())
}

/// The list `tumbler validate --list` prints.
pub fn list() -> String {
    let mut s = String::new();
    for c in CHECKS {
        let tiers = if c.in_ci { "ci, full" } else { "full" };
        let _ = writeln!(s, "{:<26} [{tiers}] {}: {}", c.name, c.source, c.claim);
    }
    s
}

/// Run and judge the checks `opts` selects. Returns, on rank 0, the report (also written to
/// `OUT/report.md`) and whether every check passed, on other ranks an empty report; or, when
/// the stop flag was set, the checkpoint the interrupted run wrote (on every rank).
pub fn validate(comm: &dyn Comm, opts: &ValidateOptions) -> Result<ValidateEnd, String> {
    let checks = select(opts)?;
    let root = comm.rank() == 0;
    let mut report = String::new();
    let mut all_passed = true;
    for check in checks {
        let specs = (check.runs)(opts.tier);
        let dir = opts.out.join(check.name);
        let mut files = Vec::new();
        for spec in &specs {
            let lc = spec
                .load()
                .map_err(|e| format!("{}: {}: {e}", check.name, spec.case))?;
            let file = dir.join(format!("{}.h5", spec.case));
            if root {
                std::fs::create_dir_all(&dir)
                    .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
            }
            // rank 0 looks at the files; every rank follows its decision
            let found = if root && opts.reuse {
                Found::of(&file, &lc.case)
            } else {
                Found::Nothing
            };
            let found = Found::decode(comm.sum_u64(found as u64));
            if found == Found::Finished {
                if root {
                    log::info!("{}: reusing {}", check.name, file.display());
                }
            } else {
                let restart = (found == Found::Checkpoint).then(|| checkpoint_path(&file));
                if let (true, Some(ck)) = (root, &restart) {
                    log::info!("{}: continuing from {}", check.name, ck.display());
                }
                let run_opts = RunOptions {
                    output: file.clone(),
                    overwrite: restart.is_none(),
                    restart,
                    allow_different_case: false,
                    new_output: false,
                    stop: opts.stop.clone(),
                };
                if let RunEnd::Stopped { checkpoint, .. } = run(&lc, comm, &run_opts)? {
                    return Ok(ValidateEnd::Stopped { checkpoint });
                }
            }
            files.push(file);
        }
        if !root {
            continue;
        }
        let runs = describe_runs(&specs);
        let verdict = judge(check, specs, files, dir);
        let (text, passed) = match verdict {
            Ok(v) => (render(check, &runs, &v, &opts.out), v.passed()),
            Err(e) => (format!("## {}\n\nerror: {e}\n\n", check.name), false),
        };
        print!("{text}");
        report.push_str(&text);
        all_passed &= passed;
    }
    if root {
        let summary = format!(
            "{} tier: {}\n",
            match opts.tier {
                Tier::Ci => "ci",
                Tier::Full => "full",
            },
            if all_passed {
                "every check passed"
            } else {
                "SOME CHECKS FAILED"
            }
        );
        print!("{summary}");
        report.push_str(&summary);
        let path = opts.out.join("report.md");
        std::fs::create_dir_all(&opts.out)
            .and_then(|_| std::fs::write(&path, &report))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(ValidateEnd::Judged {
        report,
        passed: all_passed,
    })
}

fn judge(
    check: &Check,
    specs: Vec<RunSpec>,
    files: Vec<PathBuf>,
    dir: PathBuf,
) -> Result<Verdict, InspectError> {
    let readers = files
        .iter()
        .map(|f| RunReader::open(f))
        .collect::<Result<Vec<_>, _>>()?;
    (check.judge)(&Runs {
        specs,
        files,
        readers,
        dir,
    })
}

/// What `--reuse` finds of a check's run in its folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Found {
    /// Nothing usable: the run is made from the start.
    Nothing = 0,
    /// A finished run of the case: judged again.
    Finished = 1,
    /// An unfinished run of the case and its checkpoint: continued.
    Checkpoint = 2,
}

impl Found {
    /// What there is of a run of `case` written to `file`.
    fn of(file: &Path, case: &Case) -> Found {
        if holds_run_of(file, case) {
            Found::Finished
        } else if partial_path(file).exists() && holds_run_of(&checkpoint_path(file), case) {
            Found::Checkpoint
        } else {
            Found::Nothing
        }
    }

    /// The value rank 0 sent (every other rank adds 0).
    fn decode(v: u64) -> Found {
        match v {
            1 => Found::Finished,
            2 => Found::Checkpoint,
            _ => Found::Nothing,
        }
    }
}

/// Whether the HDF5 file `file` (a run's output or its checkpoint) holds a run of `case`:
/// its stored case has every key the same but the title, so editing a case file's comments
/// does not throw a long run away.
fn holds_run_of(file: &Path, case: &Case) -> bool {
    hdf5::File::open(file)
        .ok()
        .and_then(|f| attr_string(&f, "case"))
        .and_then(|t| parse_case(&t, "stored case").ok())
        .is_some_and(|stored| stored.same_run_as(case))
}

/// `Runs: `case` (`key=value`, ...); ...`, or nothing for a check without runs.
fn describe_runs(specs: &[RunSpec]) -> String {
    if specs.is_empty() {
        return String::new();
    }
    let runs: Vec<String> = specs
        .iter()
        .map(|r| {
            let sets: Vec<String> = r.overrides.iter().map(|o| format!("`{o}`")).collect();
            format!("`{}` ({})", r.case, sets.join(", "))
        })
        .collect();
    format!("Runs: {}.\n\n", runs.join("; "))
}

/// A check's findings as a Markdown section.
fn render(check: &Check, runs: &str, v: &Verdict, out: &Path) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "## {} — {}\n\n{}: {}\n\n{runs}",
        check.name,
        if v.passed() { "pass" } else { "FAIL" },
        check.source,
        check.claim
    );
    let _ = writeln!(s, "| | measured | seed |\n|---|---|---|");
    let cell = |t: &str| t.replace('|', "\\|");
    for f in &v.findings {
        let _ = writeln!(
            s,
            "| **{}** {} | {} | {} |",
            f.mark(),
            cell(&f.what),
            cell(&f.measured),
            cell(&f.seed)
        );
    }
    for fig in &v.figures {
        let shown = fig.strip_prefix(out).unwrap_or(fig);
        let _ = writeln!(s, "\n![{}]({})", check.name, shown.display());
    }
    s.push('\n');
    s
}

/// The compiled-in text of `cases/<name>.toml`.
pub fn case_text(name: &str) -> Option<&'static str> {
    macro_rules! cases {
        ($($n:literal),* $(,)?) => {
            match name {
                $($n => Some(include_str!(concat!("../../cases/", $n, ".toml"))),)*
                _ => None,
            }
        };
    }
    cases!(
        "rapaport2002-A",
        "rapaport2002-C",
        "rapaport2002-D",
        "rapaport2002-E",
        "rapaport2002-F",
        "rapaport2002-G",
        "rapaport2002-H",
        "rapaport2002-R",
        "rapaport2002-V",
        "rapaport2002-W",
        "rapaport2002-X",
        "chen2008-ch3-L010-d3-frictionless-end",
        "chen2008-ch4-endwalls",
        "chen2008-ch4-periodic-w6.28",
        "chen2008-ch4-periodic-w3.14",
        "chen2008-ch5-sphere-fill20",
        "chen2008-ch5-sphere-fill60",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_run_of_every_tier_loads() {
        for tier in [Tier::Ci, Tier::Full] {
            for c in CHECKS {
                for spec in (c.runs)(tier) {
                    spec.load()
                        .unwrap_or_else(|e| panic!("{} ({tier:?}): {e}", c.name));
                }
            }
        }
    }

    /// An HDF5 file at `path` whose `case` attribute is `text`, as a run's output and its
    /// checkpoint store it.
    fn file_with_case(path: &Path, text: &str) {
        use hdf5::types::VarLenUnicode;
        use std::str::FromStr;
        let f = hdf5::File::create(path).unwrap();
        f.new_attr::<VarLenUnicode>()
            .create("case")
            .unwrap()
            .write_scalar(&VarLenUnicode::from_str(text).unwrap())
            .unwrap();
    }

    #[test]
    fn reuse_judges_finished_runs_and_continues_checkpointed_ones_of_the_same_case() {
        let dir = tempfile::tempdir().unwrap();
        let spec = RunSpec::new("rapaport2002-W", &["drum.length=32", "run.rotations=100"]);
        let lc = spec.load().unwrap();
        let other = RunSpec::new("rapaport2002-W", &["drum.length=32", "run.rotations=50"])
            .load()
            .unwrap();
        // nothing yet
        let file = dir.path().join("W.h5");
        assert_eq!(Found::of(&file, &lc.case), Found::Nothing);
        // a checkpoint without the unfinished output is not continued (the output is gone)
        file_with_case(&checkpoint_path(&file), &lc.text);
        assert_eq!(Found::of(&file, &lc.case), Found::Nothing);
        // with it, it is; but not a checkpoint of a run of other keys
        file_with_case(&partial_path(&file), &lc.text);
        assert_eq!(Found::of(&file, &lc.case), Found::Checkpoint);
        assert_eq!(Found::of(&file, &other.case), Found::Nothing);
        // a finished output of the same keys, under another title and comments, is judged
        let retitled = lc
            .text
            .replacen("title = ", "# edited\ntitle = \"x\"\n# was ", 1);
        file_with_case(&file, &retitled);
        assert_eq!(Found::of(&file, &lc.case), Found::Finished);
        assert_eq!(Found::of(&file, &other.case), Found::Nothing);
        // what rank 0 decides reaches every rank through a sum
        for f in [Found::Nothing, Found::Finished, Found::Checkpoint] {
            assert_eq!(Found::decode(f as u64), f);
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_list() {
        let opts = ValidateOptions {
            tier: Tier::Ci,
            only: vec!["rolling".into(), "nope".into()],
            out: PathBuf::from("x"),
            reuse: false,
            stop: None,
        };
        let e = select(&opts).err().unwrap();
        assert!(e.contains("`nope`") && e.contains("rapaport-capped"), "{e}");
    }
}
