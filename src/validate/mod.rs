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
//! differ) is judged again instead of rerun.

pub mod analytic;
pub mod checks;
pub mod measure;

use crate::case::{apply_overrides, parse_case, Case, LoadedCase};
use crate::comm::Comm;
use crate::inspect::{attr_string, InspectError, RunReader};
use crate::run::{run, RunEnd, RunOptions};
use checks::{Check, CHECKS};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
    /// Judge finished files again instead of rerunning them.
    pub reuse: bool,
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
/// `OUT/report.md`) and whether every check passed; on other ranks an empty report.
pub fn validate(comm: &dyn Comm, opts: &ValidateOptions) -> Result<(String, bool), String> {
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
            let reuse = root && opts.reuse && finished_with(&file, &lc.case);
            if comm.sum_u64(reuse as u64) == 0 {
                let opts = RunOptions {
                    output: file.clone(),
                    overwrite: true,
                    restart: None,
                    allow_different_case: false,
                    stop: None,
                };
                match run(&lc, comm, &opts)? {
                    RunEnd::Finished(_) => {}
                    RunEnd::Stopped { .. } => return Err("stopped".into()),
                }
            } else if root {
                log::info!("{}: reusing {}", check.name, file.display());
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
    Ok((report, all_passed))
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

/// Whether `file` is a finished run of `case`: its stored case has every key the same but
/// the title, so editing a case file's comments does not throw a long run away.
fn finished_with(file: &Path, case: &Case) -> bool {
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

    #[test]
    fn unknown_names_are_refused_with_the_list() {
        let opts = ValidateOptions {
            tier: Tier::Ci,
            only: vec!["rolling".into(), "nope".into()],
            out: PathBuf::from("x"),
            reuse: false,
        };
        let e = select(&opts).err().unwrap();
        assert!(e.contains("`nope`") && e.contains("rapaport-capped"), "{e}");
    }
}
