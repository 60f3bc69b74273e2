//! The validation checks: for each result of the seeds, the reduced runs that show it, and
//! how the result is read from their files. Each check states what the seed reports, prints
//! what the runs measured beside it, and passes or fails on a criterion written here, in
//! the open.

use super::analytic::{pair_collision, rolling, wall_collision};
use super::measure::{
    angle_by_composition, end_flow, ends_and_centre, segregation_index, surface_share, thirds,
    AxialSeries,
};
use super::{Finding, RunSpec, Runs, Tier, Verdict};
use crate::inspect::{InspectError, RunReader};
use crate::plot::{
    plot_field, plot_profile, plot_spacetime, FieldOptions, ProfileOptions, SpacetimeOptions,
};
use std::path::PathBuf;

/// One seed result and how it is checked.
pub struct Check {
    /// Name on the command line (`--only NAME`) and of the output folder.
    pub name: &'static str,
    /// Where the seed reports it.
    pub source: &'static str,
    /// The result, in a sentence.
    pub claim: &'static str,
    /// Whether the CI tier runs it.
    pub in_ci: bool,
    /// The runs of each tier (empty for the analytic checks).
    pub runs: fn(Tier) -> Vec<RunSpec>,
    /// Read the runs' files (in the order of `runs`), draw the figures, judge.
    pub judge: fn(&Runs) -> Result<Verdict, InspectError>,
}

/// Every check, in the order they run.
pub const CHECKS: &[Check] = &[
    Check {
        name: "restitution",
        source: "thesis ch. 2 (linear spring-dashpot, k_n = m_eff((pi/t_c)^2 + gamma^2))",
        claim: "binary and wall collisions give back e_n and last t_c",
        in_ci: true,
        runs: no_runs,
        judge: judge_restitution,
    },
    Check {
        name: "rolling",
        source: "thesis ch. 2 (Coulomb friction, sliding to rolling)",
        claim: "a sphere launched sliding on a wall ends up rolling at 5/7 of its speed",
        in_ci: true,
        runs: no_runs,
        judge: judge_rolling,
    },
    Check {
        name: "rapaport-bands",
        source: "Rapaport 2002, run #A, Fig. 1",
        claim: "a mixed bed whose wall grips the big particles harder forms about 8 bands \
                within 50 rotations",
        in_ci: false,
        runs: runs_bands,
        judge: judge_bands,
    },
    Check {
        name: "rapaport-friction-rule",
        source: "Rapaport 2002, runs #C-#H, Table I and sec. V.A",
        claim: "bands form when the wall grips the big particles harder (gamma_s^bw > \
                gamma_s^sw: #C, #D) or, with equal wall friction, when the big particles \
                are rougher (#E); not when the wall grips the small ones harder (#F-#H)",
        in_ci: true,
        runs: runs_friction_rule,
        judge: judge_friction_rule,
    },
    Check {
        name: "rapaport-capped",
        source: "Rapaport 2002, run #R, Fig. 12",
        claim: "in a capped cylinder the band count is odd and big particles occupy both \
                end bands",
        in_ci: false,
        runs: runs_capped,
        judge: judge_capped,
    },
    Check {
        name: "rapaport-segregated-start",
        source: "Rapaport 2002, runs #V, #W, #X, Table I, Fig. 15",
        claim: "a segregated start stays segregated (#V periodic, #X capped) but mixes \
                when all friction coefficients are equal (#W); here in a drum of L = 32 \
                (the paper: 128), so that mixing takes tens of rotations, not hundreds",
        in_ci: true,
        runs: runs_segregated_start,
        judge: judge_segregated_start,
    },
    Check {
        name: "ch3-endwall-flow",
        source: "thesis ch. 3, figs. 3.15-3.17",
        claim: "near a frictional end wall the surface flow turns away from the wall \
                upstream and back toward it downstream, at most O(0.1) u0; a frictionless \
                end wall has no such flow",
        in_ci: false,
        runs: runs_endwall_flow,
        judge: judge_endwall_flow,
    },
    Check {
        name: "ch4-endwall-bands",
        source: "thesis ch. 4, sec. 4.2, figs. 4.1-4.3",
        claim: "large particles gather at both end walls first, before any band forms \
                in the middle",
        in_ci: false,
        runs: runs_endwall_bands,
        judge: judge_endwall_bands,
    },
    Check {
        name: "ch4-periodic-speed",
        source: "thesis ch. 4, sec. 4.6, figs. 4.14-4.17",
        claim: "with periodic ends, bands form within 50 rotations at 6.28 rad/s but not at \
                3.14 rad/s",
        in_ci: false,
        runs: runs_periodic_speed,
        judge: judge_periodic_speed,
    },
    Check {
        name: "ch5-sphere-patterns",
        source: "thesis ch. 5, sec. 5.3, fig. 5.4",
        claim: "a sphere 20 % full segregates as SLS (large particles at the equator), \
                60 % full as LSL (large particles at the poles)",
        in_ci: false,
        runs: runs_sphere,
        judge: judge_sphere,
    },
];

fn no_runs(_: Tier) -> Vec<RunSpec> {
    Vec::new()
}

fn pct(x: f64) -> String {
    format!("{:+.2} %", 100.0 * x)
}

// ---- analytic ----------------------------------------------------------------------------

fn judge_restitution(_: &Runs) -> Result<Verdict, InspectError> {
    let fail = |e: String| InspectError::Invalid(format!("restitution: {e}"));
    let mut findings = Vec::new();
    let mut table = |label: &str, got: Vec<(String, super::analytic::Collision, f64)>| {
        let worst_e = got
            .iter()
            .map(|(_, c, e)| c.restitution / e - 1.0)
            .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
        let worst_t = got
            .iter()
            .map(|(_, c, _)| c.duration / c.collision_time - 1.0)
            .fold(0.0f64, |a, b| if b.abs() > a.abs() { b } else { a });
        let cases: Vec<String> = got
            .iter()
            .map(|(what, c, _)| {
                format!(
                    "{what}: e {:.4}, t/t_c {:.3}",
                    c.restitution,
                    c.duration / c.collision_time
                )
            })
            .collect();
        findings.push(Finding::judged(
            format!("{label}: restitution"),
            "e_n exactly (0.89, 0.97)",
            format!("worst error {} ({})", pct(worst_e), cases.join("; ")),
            worst_e.abs() < 0.01,
        ));
        findings.push(Finding::judged(
            format!("{label}: contact duration"),
            "t_c exactly",
            format!("worst error {}", pct(worst_t)),
            worst_t.abs() < 0.03,
        ));
    };
    let mut pairs = Vec::new();
    let mut walls = Vec::new();
    for e in [0.89, 0.97] {
        for ratio in [1.0, 2.0] {
            let c = pair_collision(e, 0.002, 0.002 * ratio).map_err(fail)?;
            pairs.push((format!("e_n {e}, ratio {ratio}"), c, e));
        }
        for d in [0.002, 0.004] {
            let c = wall_collision(e, d).map_err(fail)?;
            walls.push((format!("e_n {e}, d {} mm", d * 1e3), c, e));
        }
    }
    table("pairs", pairs);
    table("end wall", walls);
    Ok(Verdict {
        findings,
        figures: Vec::new(),
    })
}

fn judge_rolling(_: &Runs) -> Result<Verdict, InspectError> {
    let mut findings = Vec::new();
    for tangential in ["viscous", "history"] {
        let r = rolling(tangential)
            .map_err(|e| InspectError::Invalid(format!("rolling ({tangential}): {e}")))?;
        let err = r.speed_ratio / (5.0 / 7.0) - 1.0;
        findings.push(Finding::judged(
            format!("{tangential} tangential force: final speed / launch speed"),
            "5/7 = 0.7143, rolling without slip",
            format!(
                "{:.4} ({}), (d/2) w / v = {:.4}",
                r.speed_ratio,
                pct(err),
                r.spin_ratio
            ),
            err.abs() < 0.01 && (r.spin_ratio - 1.0).abs() < 0.01,
        ));
    }
    Ok(Verdict {
        findings,
        figures: Vec::new(),
    })
}

// ---- Rapaport ----------------------------------------------------------------------------

/// The Rapaport runs' reduction: fewer rotations, and in the CI tier a shorter drum.
fn rapaport(
    case: &'static str,
    tier: Tier,
    rotations: f64,
    ci_length: f64,
    ci_rotations: f64,
) -> RunSpec {
    match tier {
        Tier::Full => RunSpec::new(
            case,
            &[
                &format!("run.rotations={rotations}"),
                "diagnostics.window=5",
            ],
        ),
        Tier::Ci => RunSpec::new(
            case,
            &[
                &format!("drum.length={ci_length}"),
                &format!("run.rotations={ci_rotations}"),
                "diagnostics.window=5",
            ],
        ),
    }
}

/// `1 band`, `2 bands`.
fn bands_word(n: usize) -> String {
    format!("{n} band{}", if n == 1 { "" } else { "s" })
}

/// The last rotations over which profiles are averaged.
const LATE: f64 = 5.0;

/// How much steeper (degrees) the slices richest in large beads must stand than the poorest
/// for a band of large beads to count as steeper. A slice's angle over a window scatters by
/// about 0.4 degree in a mixed drum, so the mean of a third of 32 slices by about 0.15.
const ANGLE_MARGIN: f64 = 1.0;

/// Space-time plots of every run, named after the run.
fn spacetime_figures(runs: &Runs) -> Result<Vec<PathBuf>, InspectError> {
    runs.files
        .iter()
        .map(|f| {
            plot_spacetime(
                f,
                &SpacetimeOptions {
                    output: Some(runs.figure(f, "spacetime")),
                    bare: false,
                },
            )
        })
        .collect()
}

/// Bands of the late profile and the segregation index, start and late, of one run.
struct Banding {
    bands: Vec<crate::diag::Band>,
    s_start: f64,
    s_late: f64,
    end: f64,
}

fn banding(series: &AxialSeries) -> Banding {
    let late = series.late_profile(LATE);
    Banding {
        bands: series.bands(&late),
        s_start: segregation_index(&series.initial_profile()),
        s_late: segregation_index(&late),
        end: series.end(),
    }
}

impl Banding {
    fn describe(&self) -> String {
        format!(
            "{} after {:.0} rotations, segregation index {:.2} -> {:.2}",
            bands_word(self.bands.len()),
            self.end,
            self.s_start,
            self.s_late
        )
    }
    /// Bands formed: at least two, and the index at least 1.5 times its start.
    fn segregated(&self) -> bool {
        self.bands.len() >= 2 && self.s_late >= 1.5 * self.s_start
    }
    /// Still mixed: no band, and the index below 1.3 times its start.
    fn mixed(&self) -> bool {
        self.bands.is_empty() && self.s_late < 1.3 * self.s_start
    }
}

fn runs_bands(tier: Tier) -> Vec<RunSpec> {
    vec![rapaport("rapaport2002-A", tier, 40.0, 64.0, 30.0)]
}

fn judge_bands(runs: &Runs) -> Result<Verdict, InspectError> {
    let series = AxialSeries::read(&runs.readers[0])?;
    let b = banding(&series);
    let onset = |n: usize| {
        series
            .first_with_bands(n)
            .map_or("not within the run".to_string(), |r| {
                format!("at rotation {r:.0}")
            })
    };
    let findings = vec![
        Finding::judged(
            "#A: bands of the big species".into(),
            "8 bands within the first 50 rotations (merging to 6 later)",
            format!(
                "{}; first 4 bands {}, first 8 {}",
                b.describe(),
                onset(4),
                onset(8)
            ),
            b.bands.len() >= 4 && b.s_late >= 2.0 * b.s_start,
        ),
        Finding::note(
            "#A: particles".into(),
            "N = 4664",
            format!("N = {}", runs.particles(0)?),
        ),
    ];
    Ok(Verdict {
        findings,
        figures: spacetime_figures(runs)?,
    })
}

/// #C-#H: whether each forms bands, the friction coefficients and Table I's band column.
const FRICTION_RULE: &[(&str, bool, &str, &str)] = &[
    (
        "rapaport2002-C",
        true,
        "P-P 2/2, wall 10/2",
        "bands form (Table I: 8)",
    ),
    (
        "rapaport2002-D",
        true,
        "P-P 10/10, wall 10/2",
        "bands form (Table I: 6)",
    ),
    (
        "rapaport2002-E",
        true,
        "P-P 10/2, wall 10/10",
        "bands form (Table I: 8)",
    ),
    (
        "rapaport2002-F",
        false,
        "P-P 2/10, wall 2/10",
        "no segregation (Table I: -)",
    ),
    (
        "rapaport2002-G",
        false,
        "P-P 2/2, wall 2/10",
        "no segregation (Table I: -)",
    ),
    (
        "rapaport2002-H",
        false,
        "P-P 10/2, wall 2/10",
        "no segregation (Table I: -)",
    ),
];

fn runs_friction_rule(tier: Tier) -> Vec<RunSpec> {
    FRICTION_RULE
        .iter()
        .filter(|(case, ..)| {
            tier == Tier::Full || ["rapaport2002-C", "rapaport2002-G"].contains(case)
        })
        .map(|(case, ..)| rapaport(case, tier, 100.0, 64.0, 60.0))
        .collect()
}

fn judge_friction_rule(runs: &Runs) -> Result<Verdict, InspectError> {
    let mut findings = Vec::new();
    for (k, spec) in runs.specs.iter().enumerate() {
        let (_, bands, friction, seed) = FRICTION_RULE
            .iter()
            .find(|(case, ..)| *case == spec.case)
            .expect("every run is in the table");
        let b = banding(&AxialSeries::read(&runs.readers[k])?);
        let label = spec.case.trim_start_matches("rapaport2002-");
        findings.push(Finding::judged(
            format!("#{label} (big/small: {friction})"),
            seed,
            b.describe(),
            if *bands { b.segregated() } else { b.mixed() },
        ));
    }
    Ok(Verdict {
        findings,
        figures: spacetime_figures(runs)?,
    })
}

fn runs_capped(tier: Tier) -> Vec<RunSpec> {
    vec![rapaport("rapaport2002-R", tier, 40.0, 64.0, 30.0)]
}

fn judge_capped(runs: &Runs) -> Result<Verdict, InspectError> {
    let b = banding(&AxialSeries::read(&runs.readers[0])?);
    let n = b.bands.len();
    let ends_big = n > 0 && b.bands[0].rich && b.bands[n - 1].rich;
    let findings = vec![
        Finding::judged(
            "#R: band count".into(),
            "odd: 11 bands merging to 9",
            format!(
                "{} (mean profile of the last {LATE} rotations)",
                b.describe()
            ),
            n % 2 == 1 && n >= 3,
        ),
        Finding::judged(
            "#R: end bands".into(),
            "big particles occupy both end bands",
            match (b.bands.first(), b.bands.last()) {
                (Some(f), Some(l)) => format!(
                    "{} at z = -L/2, {} at z = +L/2",
                    if f.rich { "big" } else { "small" },
                    if l.rich { "big" } else { "small" }
                ),
                _ => "no bands".into(),
            },
            ends_big,
        ),
    ];
    Ok(Verdict {
        findings,
        figures: spacetime_figures(runs)?,
    })
}

/// #V, #W, #X: whether each stays segregated.
const SEGREGATED_START: &[(&str, bool)] = &[
    ("rapaport2002-V", true),
    ("rapaport2002-W", false),
    ("rapaport2002-X", true),
];

fn runs_segregated_start(tier: Tier) -> Vec<RunSpec> {
    SEGREGATED_START
        .iter()
        .filter(|(case, _)| tier == Tier::Full || *case != "rapaport2002-X")
        .map(|(case, _)| {
            RunSpec::new(
                case,
                &[
                    "drum.length=32",
                    "run.rotations=100",
                    "diagnostics.window=5",
                ],
            )
        })
        .collect()
}

fn judge_segregated_start(runs: &Runs) -> Result<Verdict, InspectError> {
    let mut findings = Vec::new();
    for (k, spec) in runs.specs.iter().enumerate() {
        let (_, stays) = SEGREGATED_START
            .iter()
            .find(|(case, _)| *case == spec.case)
            .expect("every run is in the table");
        let b = banding(&AxialSeries::read(&runs.readers[k])?);
        let label = spec.case.trim_start_matches("rapaport2002-");
        let kept = b.s_late / b.s_start;
        findings.push(Finding::judged(
            format!("#{label}"),
            if *stays {
                "the segregated state persists (Table I: 2 bands)"
            } else {
                "the initial bands rapidly vanish (Table I: no bands)"
            },
            format!("{}; {:.0} % of the index kept", b.describe(), 100.0 * kept),
            if *stays {
                b.bands.len() == 2 && b.s_late >= 0.5
            } else {
                b.s_late < 0.4 && kept < 0.5
            },
        ));
    }
    Ok(Verdict {
        findings,
        figures: spacetime_figures(runs)?,
    })
}

// ---- thesis --------------------------------------------------------------------------------

fn runs_endwall_flow(_: Tier) -> Vec<RunSpec> {
    vec![RunSpec::new(
        "chen2008-ch3-L010-d3-frictionless-end",
        &["model.collision_time=1e-3", "run.rotations=1"],
    )]
}

fn judge_endwall_flow(runs: &Runs) -> Result<Verdict, InspectError> {
    let reader = &runs.readers[0];
    let last = reader.window("fields", None)?;
    let f = end_flow(reader, last.index, 3)?;
    let mm = |w: [f64; 2]| format!("{:+.1} / {:+.1} mm/s", 1e3 * w[0], 1e3 * w[1]);
    // frictional wall at z = +L/2: away from it is w < 0
    let [up, down] = f.high;
    let frictional = up.abs().min(down.abs());
    let frictionless = f.low[0].abs().max(f.low[1].abs());
    let findings = vec![
        Finding::judged(
            "frictional end wall (z = +L/2): surface w upstream / downstream".into(),
            "away from the wall upstream (w < 0), back toward it downstream (w > 0)",
            mm(f.high),
            up < 0.0 && down > 0.0,
        ),
        Finding::judged(
            "largest axial speed near the frictional wall / u0".into(),
            "O(0.1) at most",
            format!(
                "{:.3} (u0 = {:.3} m/s)",
                up.abs().max(down.abs()) / f.u0,
                f.u0
            ),
            up.abs().max(down.abs()) / f.u0 < 0.3,
        ),
        Finding::judged(
            "frictionless end wall (z = -L/2): surface w upstream / downstream".into(),
            "negligible",
            format!(
                "{}; at most {:.0} % of the frictional wall's",
                mm(f.low),
                100.0 * frictionless / frictional
            ),
            frictionless < 0.25 * frictional,
        ),
        Finding::note(
            "downstream vs upstream magnitude at the frictional wall".into(),
            "downstream larger at the surface, upstream larger deep in the layer",
            format!(
                "{} larger at the surface; mid-drum {}",
                if up.abs() > down.abs() {
                    "upstream"
                } else {
                    "downstream"
                },
                mm(f.centre)
            ),
        ),
    ];
    let figures = vec![plot_field(
        &runs.files[0],
        &FieldOptions {
            quantity: "w".into(),
            window: Some(last.index),
            plane: Some("surface".into()),
            output: Some(runs.figure(&runs.files[0], "w-surface")),
        },
    )?];
    Ok(Verdict { findings, figures })
}

fn runs_endwall_bands(_: Tier) -> Vec<RunSpec> {
    vec![RunSpec::new("chen2008-ch4-endwalls", &["run.rotations=5"])]
}

fn judge_endwall_bands(runs: &Runs) -> Result<Verdict, InspectError> {
    let series = AxialSeries::read(&runs.readers[0])?;
    let late = series.late_profile(1.0);
    // the two 5 mm slices nearest each wall, over rotation 4-5 (thesis fig. 4.1(b))
    let (low, high, centre) = ends_and_centre(&late, 2);
    let mean = super::measure::finite_mean(late.iter().copied());
    let bands = series.bands(&late);
    let inner = bands.len().saturating_sub(2);
    let findings = vec![
        Finding::judged(
            "large particles' volume fraction: ends vs middle".into(),
            "large particles accumulate at both end walls within 1 rotation; segregation \
             evident there after 4-5 rotations (fig. 4.1(b))",
            format!(
                "{low:.2} (z = -L/2), {high:.2} (z = +L/2), middle half {centre:.2}, drum \
                 {mean:.2}; over rotation {:.0}-{:.0}",
                series.end() - 1.0,
                series.end()
            ),
            low > centre + 0.05 && high > centre + 0.05,
        ),
        Finding::judged(
            "bands away from the ends".into(),
            "none yet: the end bands come first",
            format!(
                "{} in all, {inner} inside the end bands",
                bands_word(bands.len())
            ),
            inner <= 1,
        ),
        first_rotation_flux(&runs.readers[0])?,
        Finding::note(
            "large particles at the ends / in the middle, rotation by rotation".into(),
            "accumulating at the end walls from the first rotation (fig. 4.1(a)-(b))",
            (0..series.end().round() as usize)
                .filter_map(|k| {
                    let p = series.profile_between(k as f64, (k + 1) as f64);
                    (!p.is_empty()).then(|| {
                        let (lo, hi, mid) = ends_and_centre(&p, 2);
                        format!("{k}-{}: {lo:.2}, {hi:.2} / {mid:.2}", k + 1)
                    })
                })
                .collect::<Vec<_>>()
                .join("; "),
        ),
    ];
    let figures = vec![plot_profile(
        &runs.files[0],
        &ProfileOptions {
            window: None,
            output: Some(runs.figure(&runs.files[0], "profile")),
        },
    )?];
    Ok(Verdict {
        findings,
        figures: [figures, spacetime_figures(runs)?].concat(),
    })
}

/// Thesis fig. 4.8(a): the mixture's upstream and downstream axial flow rates over the first
/// rotation, next to each end wall and in the middle.
fn first_rotation_flux(reader: &RunReader) -> Result<Finding, InspectError> {
    let up = reader.array("slices/q_up_mixture", &["W", "Z"])?;
    let down = reader.array("slices/q_down_mixture", &["W", "Z"])?;
    let row =
        |a: &ndarray::ArrayD<f64>| -> Vec<f64> { (0..a.shape()[1]).map(|k| a[[0, k]]).collect() };
    let (up, down) = (row(&up), row(&down));
    let (up_low, up_high, up_mid) = ends_and_centre(&up, 2);
    let (down_low, down_high, _) = ends_and_centre(&down, 2);
    // the middle's magnitude, not its signed mean (which may cancel)
    let magnitude: Vec<f64> = up.iter().map(|q| q.abs()).collect();
    let (_, _, mid) = ends_and_centre(&magnitude, 2);
    let end = up_low.abs().min(up_high.abs());
    let ml = |q: f64| format!("{:+.2}", q * 1e6);
    Ok(Finding::judged(
        "mixture's axial flow rates Q_up / Q_down over rotation 0-1 [mL/s]".into(),
        "away from each end wall upstream and back downstream from the first rotation; \
         quite small in the middle (fig. 4.8(a))",
        format!(
            "z = -L/2: {} / {}, z = +L/2: {} / {}, middle half: mean Q_up {}, mean |Q_up| {}",
            ml(up_low),
            ml(down_low),
            ml(up_high),
            ml(down_high),
            ml(up_mid),
            ml(mid).trim_start_matches('+')
        ),
        up_low > 0.0 && down_low < 0.0 && up_high < 0.0 && down_high > 0.0 && mid < end / 3.0,
    ))
}

fn runs_periodic_speed(_: Tier) -> Vec<RunSpec> {
    // the thesis' comparison point: fig. 4.15(d) (6.28 rad/s) and fig. 4.14 (3.14 rad/s)
    // at 49-50 rotations
    ["chen2008-ch4-periodic-w6.28", "chen2008-ch4-periodic-w3.14"]
        .iter()
        .map(|case| RunSpec::new(case, &["run.rotations=50"]))
        .collect()
}

fn judge_periodic_speed(runs: &Runs) -> Result<Verdict, InspectError> {
    let mut findings = Vec::new();
    let mut index = Vec::new();
    for (k, (speed, bands)) in [("6.28", true), ("3.14", false)].iter().enumerate() {
        let b = banding(&AxialSeries::read(&runs.readers[k])?);
        findings.push(Finding::judged(
            format!("{speed} rad/s: bands of the large beads"),
            if *bands {
                "some concentration extremes grow into bands within 50 rotations (fig. 4.15)"
            } else {
                "fluctuations stay small; no band even after 200 rotations (fig. 4.14)"
            },
            b.describe(),
            if *bands {
                b.segregated()
            } else {
                b.bands.is_empty()
            },
        ));
        index.push(b.s_late);
    }
    // fig. 4.17: after 50 rotations at 6.28 rad/s the large beads' band stands steeper
    let big = runs.readers[0].big_species()?;
    let a = angle_by_composition(&runs.readers[0], big)?;
    findings.push(Finding::judged(
        "6.28 rad/s: dynamic angle of repose of the slices richest and poorest in large beads"
            .into(),
        "the large beads' band has the higher angle (fig. 4.17)",
        format!(
            "richest third (large share {:.2}): {:.1} deg; poorest third ({:.2}): {:.1} deg ({})",
            a.rich[0],
            a.rich[1],
            a.poor[0],
            a.poor[1],
            a.window.label()
        ),
        a.rich[1] > a.poor[1] + ANGLE_MARGIN,
    ));
    findings.push(Finding::judged(
        "segregation index, 6.28 over 3.14 rad/s, after the same rotations".into(),
        "a larger speed promotes band formation",
        format!("{:.2}", index[0] / index[1]),
        index[0] > 1.5 * index[1],
    ));
    Ok(Verdict {
        findings,
        figures: spacetime_figures(runs)?,
    })
}

/// 20 % full: a 0.06 m sphere for 20 rotations (SLS shows within 5-10). 60 % full: the
/// thesis' own 0.14 m sphere for 30 rotations (73,000 particles, 10 to 25 hours on two cores,
/// checkpointed every rotation so that `--reuse` continues it after a stop). The pattern at
/// high fill depends on the tumbler's size against the beads' (sec. 5.2: the same 2:1 ratio
/// changes pattern at 20-30 % fill with 1 + 2 mm beads and at 50-60 % with 2 + 4 mm ones), and
/// the reduced sphere, 15 large beads across instead of 35, reads SLS at 60 %.
fn runs_sphere(_: Tier) -> Vec<RunSpec> {
    vec![
        RunSpec::new(
            "chen2008-ch5-sphere-fill20",
            &["drum.diameter=0.06", "run.rotations=20"],
        ),
        RunSpec::new(
            "chen2008-ch5-sphere-fill60",
            &["run.rotations=30", "output.checkpoint_every=1"],
        ),
    ]
}

/// The large beads' share of the free surface in the pole / equator / pole thirds, in
/// field window `window`, and the pattern it reads.
fn surface_pattern(
    reader: &RunReader,
    window: usize,
    big: usize,
) -> Result<([f64; 3], &'static str), InspectError> {
    let [a, equator, b] = thirds(&surface_share(reader, window, big)?);
    let pattern = if equator > a.max(b) {
        "SLS"
    } else if equator < a.min(b) {
        "LSL"
    } else {
        "neither"
    };
    Ok(([a, equator, b], pattern))
}

fn judge_sphere(runs: &Runs) -> Result<Verdict, InspectError> {
    let mut findings = Vec::new();
    for (k, (fill, sls)) in [("20 %", true), ("60 %", false)].iter().enumerate() {
        let reader = &runs.readers[k];
        let series = AxialSeries::read(reader)?;
        let window = reader.window("fields", None)?;
        let big = reader.big_species()?;
        let ([a, equator, b], pattern) = surface_pattern(reader, window.index, big)?;
        findings.push(Finding::judged(
            format!(
                "{fill} full: large particles' share of the free surface, pole / equator / \
                 pole thirds"
            ),
            if *sls {
                "SLS: large at the equator, small at the poles, within 5-10 rotations"
            } else {
                "LSL: large at the poles, small at the equator, after 20 or more rotations"
            },
            format!(
                "{a:.2} / {equator:.2} / {b:.2}: {pattern} ({})",
                window.label()
            ),
            if *sls {
                pattern == "SLS"
            } else {
                pattern == "LSL"
            },
        ));
        if window.count > 1 {
            let each = (0..window.count)
                .map(|w| {
                    let ([a, e, b], p) = surface_pattern(reader, w, big)?;
                    let label = reader.window("fields", Some(w))?.label();
                    Ok(format!("{label}: {a:.2} / {e:.2} / {b:.2} {p}"))
                })
                .collect::<Result<Vec<_>, InspectError>>()?;
            findings.push(Finding::note(
                format!("{fill} full: the same, window by window"),
                if *sls {
                    "SLS develops within 5-10 rotations"
                } else {
                    "LSL develops slowly, nearly steady after about 30 rotations (sec. 5.3)"
                },
                each.join("; "),
            ));
        }
        let [a, equator, b] = thirds(&series.late_profile(2.0));
        findings.push(Finding::note(
            format!("{fill} full: large particles' volume fraction over the cross-section"),
            "fig. 5.7: the radial core of small particles reaches the poles in LSL",
            format!(
                "{a:.2} / {equator:.2} / {b:.2} over the last 2 of {:.0} rotations",
                series.end()
            ),
        ));
    }
    let mut figures = spacetime_figures(runs)?;
    for file in &runs.files {
        figures.push(plot_field(
            file,
            &FieldOptions {
                quantity: "volume_fraction:large".into(),
                window: None,
                plane: Some("surface".into()),
                output: Some(runs.figure(file, "surface")),
            },
        )?);
    }
    Ok(Verdict { findings, figures })
}
