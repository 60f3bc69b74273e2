//! The `tumbler` command line.

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use tumbler::case::{load_case, CaseError};
use tumbler::comm::{Comm, MpiComm};
use tumbler::inspect::{
    band_table, export_lammps, export_vtu, import_lammps, info, BandsOptions, ImportOptions,
    InfoOptions, InspectError, LammpsKind, RunReader, EXIT_BAD_INPUT,
};
use tumbler::run::{run, RunEnd, RunOptions, EXIT_STOPPED};

/// Discrete element simulations of granular flow and segregation in rotating tumblers.
#[derive(Parser)]
#[command(version = concat!(env!("CARGO_PKG_VERSION"), " (", env!("TUMBLER_GIT_HASH"), ")"))]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a case (under `mpirun -np N` for N ranks).
    Run {
        /// The case file.
        case: PathBuf,
        /// The HDF5 file to write (default: the case name with `.h5`, in the current directory).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Override a case key, e.g. `--set run.rotations=10` (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Replace the output file if it exists.
        #[arg(long)]
        overwrite: bool,
        /// Continue from a checkpoint (`NAME.ckpt.h5`), appending to the output.
        #[arg(long, value_name = "CHECKPOINT")]
        restart: Option<PathBuf>,
        /// Restart even if the checkpoint's drum, model, species or time step differ.
        #[arg(long)]
        allow_different_case: bool,
        /// With --restart: write the continuation to a new file (-o, which must not exist)
        /// instead of continuing the output of the run that wrote the checkpoint.
        #[arg(long, requires = "restart")]
        new_output: bool,
    },
    /// Validate a case and print its derived quantities.
    Check {
        /// The case file.
        case: PathBuf,
        /// Override a case key (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Number of ranks to size the slabs for.
        #[arg(long, default_value_t = 1)]
        ranks: usize,
    },
    /// Show what a run's HDF5 file holds: case, version, ranks, time span, datasets.
    Info {
        /// The run's HDF5 file.
        file: PathBuf,
        /// Print the whole case text, not only its first lines.
        #[arg(long)]
        case: bool,
        /// List every group of a long series (such as each snapshot), not only the first.
        #[arg(long)]
        all: bool,
    },
    /// Print the band count of the big species over time (`rotations  bands`).
    Bands {
        /// The run's HDF5 file.
        file: PathBuf,
        /// Recompute with this threshold (departure from the drum-mean volume fraction).
        #[arg(long, value_name = "C")]
        threshold: Option<f64>,
        /// Recompute with this many slices as the narrowest band.
        #[arg(long, value_name = "N")]
        min_slices: Option<usize>,
    },
    /// Write a run's particles as a LAMMPS data file (`atom_style sphere`, with velocities),
    /// or its snapshots as VTK `.vtu` files with a `.pvd` series.
    Export {
        /// The run's HDF5 file.
        file: PathBuf,
        /// The LAMMPS data file to write (`id type diameter density x y z`; id = tumbler id
        /// + 1, type = species + 1; box around the drum).
        #[arg(
            long,
            value_name = "OUT.data",
            required_unless_present = "vtu",
            conflicts_with = "vtu"
        )]
        lammps: Option<PathBuf>,
        /// The folder for `STEM_NNNNNNNNNN.vtu` (one per snapshot), `STEM_drum.vtu` and
        /// `STEM.pvd` (docs/interop.md).
        #[arg(long, value_name = "DIR")]
        vtu: Option<PathBuf>,
        /// The group to export: `particles` (the final state) or `snapshots/NNNNNNNNNN`
        /// (default: `particles` for --lammps, every snapshot for --vtu).
        #[arg(long, value_name = "GROUP")]
        group: Option<String>,
    },
    /// Read a LAMMPS/LIGGGHTS data file or text dump into an HDF5 `/particles` file that
    /// `init.file` starts a run from (docs/interop.md).
    Import {
        /// `data` (a data file, atom_style sphere) or `dump` (a text dump).
        #[arg(long, value_enum, value_name = "data|dump")]
        lammps: LammpsArg,
        /// The LAMMPS/LIGGGHTS file.
        file: PathBuf,
        /// The HDF5 file to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Dump: the timestep to take (default the last).
        #[arg(long, value_name = "STEP")]
        timestep: Option<u64>,
        /// Atom type to species index, e.g. `1=0,2=1` (default: species = type - 1).
        #[arg(long, value_name = "TYPE=S,...")]
        species: Option<String>,
        /// The LAMMPS axes (signed) that become tumbler's x, y, z (axis z, gravity -y), e.g.
        /// `y,z,x` for a drum along LAMMPS x with gravity along -z (default `x,y,z`).
        #[arg(long, value_name = "A,B,C", allow_hyphen_values = true)]
        axes: Option<String>,
        /// Added to the positions after --axes (tumbler's origin: on the axis, mid-length).
        #[arg(long, value_name = "DX,DY,DZ", allow_hyphen_values = true)]
        offset: Option<String>,
        /// Replace the output if it exists.
        #[arg(long)]
        overwrite: bool,
    },
    /// Run reduced versions of the seed studies and check their results (under
    /// `mpirun -np N`; docs/validation.md). Exit code 4 if a check fails.
    Validate {
        /// `ci`: the few-minute subset CI runs; `full`: every check (about 18-26 hours on two
        /// cores, most of them the full-size sphere at 60 % fill).
        #[arg(long, value_enum, default_value_t = TierArg::Full)]
        tier: TierArg,
        /// Only these checks (comma-separated names; see `--list`).
        #[arg(long, value_delimiter = ',', value_name = "NAMES")]
        only: Vec<String>,
        /// The folder for the runs, the figures and `report.md`.
        #[arg(short, long, default_value = "validation")]
        out: PathBuf,
        /// Judge a finished run again instead of rerunning it, when its case has the same keys
        /// (the title and comments may differ); continue an unfinished one from its
        /// checkpoint.
        #[arg(long)]
        reuse: bool,
        /// List the checks and stop.
        #[arg(long)]
        list: bool,
    },
    /// Draw a picture of a run's HDF5 file as a PNG, an SVG or a PDF.
    Plot {
        /// The file format (default: from the extension of -o, else png).
        #[arg(long, value_enum, global = true)]
        format: Option<FormatArg>,
        #[command(subcommand)]
        what: PlotCommand,
    },
}

/// The formats `tumbler import --lammps` reads.
#[derive(Clone, Copy, clap::ValueEnum)]
enum LammpsArg {
    /// A data file (atom_style sphere).
    Data,
    /// A text dump (LAMMPS `dump custom`, LIGGGHTS).
    Dump,
}

/// The formats of `tumbler plot --format`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum FormatArg {
    /// A bitmap.
    Png,
    /// Vector graphics.
    Svg,
    /// Vector graphics with the font embedded, for a paper.
    Pdf,
}

/// The tiers of `tumbler validate`.
#[derive(Clone, Copy, clap::ValueEnum)]
enum TierArg {
    /// The subset CI runs.
    Ci,
    /// Every check.
    Full,
}

/// The pictures `tumbler plot` draws (default output `STEM_<what>.png` beside the file).
#[derive(Subcommand)]
enum PlotCommand {
    /// Space-time plot of the big species' volume fraction (time right, z up).
    Spacetime {
        /// The run's HDF5 file.
        file: PathBuf,
        /// The picture to write (default `STEM_spacetime.png` beside the file, or .svg/.pdf).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// The run's own picture: no axes, no labels.
        #[arg(long)]
        bare: bool,
    },
    /// Axial profiles in one window: concentrations, up/downstream fluxes, diffusivity.
    Profile {
        /// The run's HDF5 file.
        file: PathBuf,
        /// Window index (0 = first; default the last complete window).
        #[arg(long, value_name = "K")]
        window: Option<usize>,
        /// The picture to write (default `STEM_profile_K.png` beside the file, or .svg/.pdf).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// A binned field on a plane (or the free-surface layer) as a colour map.
    Field {
        /// The run's HDF5 file.
        file: PathBuf,
        /// number_density:S, volume_fraction:S, axial_flux:S (S a species index or name),
        /// u, v, w, ud, vd, wd, u_rms, v_rms, w_rms, rms, depth, boundary, surface.
        #[arg(long, value_name = "Q")]
        quantity: String,
        /// Window index (0 = first; default the last complete window).
        #[arg(long, value_name = "K")]
        window: Option<usize>,
        /// y=V, x=V, z=V or surface (default: surface for velocities, else the z plane
        /// nearest 0); ignored for depth, boundary and surface.
        #[arg(long, value_name = "PLANE")]
        plane: Option<String>,
        /// The picture to write (default `STEM_field_Q_PLANE_K.png` beside the file, or .svg/.pdf).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// |Q_up| and |Q_down| of the mixture along z, for every window.
    Flux {
        /// The run's HDF5 file.
        file: PathBuf,
        /// Only these windows, e.g. `0,5,10` (default: up to 6 complete windows spread over
        /// the run).
        #[arg(long, value_name = "LIST")]
        windows: Option<String>,
        /// The picture to write (default `STEM_flux.png` beside the file, or .svg/.pdf).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
}

fn report_case_errors(errs: &[CaseError]) {
    eprintln!("error: the case was refused:");
    for e in errs {
        eprintln!("  {e}");
    }
}

/// `info`, `bands` and `plot` only read: let them open the output of a job that is still
/// running (HDF5 refuses a file another process holds open unless file locking is off),
/// unless the user chose a locking mode. Called before any HDF5 call, on one thread.
fn read_without_locking() {
    if std::env::var_os("HDF5_USE_FILE_LOCKING").is_none() {
        std::env::set_var("HDF5_USE_FILE_LOCKING", "FALSE");
    }
}

/// Print what an `info`/`bands` command made, or its refusal (exit code 2).
fn report(result: Result<String, InspectError>) -> ExitCode {
    match result {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_BAD_INPUT)
        }
    }
}

/// Draw a picture and say where it went.
fn plot(what: PlotCommand, format: Option<FormatArg>) -> ExitCode {
    use tumbler::plot::*;
    let format = format.map(|f| match f {
        FormatArg::Png => Format::Png,
        FormatArg::Svg => Format::Svg,
        FormatArg::Pdf => Format::Pdf,
    });
    let written = match what {
        PlotCommand::Spacetime { file, output, bare } => {
            plot_spacetime_in(&file, &SpacetimeOptions { output, bare }, format)
        }
        PlotCommand::Profile {
            file,
            window,
            output,
        } => plot_profile_in(&file, &ProfileOptions { window, output }, format),
        PlotCommand::Field {
            file,
            quantity,
            window,
            plane,
            output,
        } => plot_field_in(
            &file,
            &FieldOptions {
                quantity,
                window,
                plane,
                output,
            },
            format,
        ),
        PlotCommand::Flux {
            file,
            windows,
            output,
        } => windows
            .as_deref()
            .map(parse_windows)
            .transpose()
            .and_then(|windows| plot_flux_in(&file, &FluxOptions { windows, output }, format)),
    };
    report(written.map(|path| format!("wrote {}\n", path.display())))
}

/// SIGTERM/SIGINT (what Slurm and a user send) set the returned flag, which makes a run
/// finish its step, checkpoint and stop with `EXIT_STOPPED`; a second one stops at once
/// (exit 130).
fn stop_on_signals() -> Result<Arc<AtomicBool>, String> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        signal_hook::flag::register_conditional_shutdown(sig, 130, Arc::clone(&stop))
            .and_then(|_| signal_hook::flag::register(sig, Arc::clone(&stop)))
            .map_err(|e| format!("cannot handle signal {sig}: {e}"))?;
    }
    Ok(stop)
}

/// `tumbler validate`: every rank runs; rank 0 judges, prints and sets the exit code.
fn validate(tier: TierArg, only: Vec<String>, out: PathBuf, reuse: bool, list: bool) -> ExitCode {
    use tumbler::validate::{
        select, validate, Tier, ValidateEnd, ValidateOptions, EXIT_CHECK_FAILED,
    };
    if list {
        print!("{}", tumbler::validate::list());
        return ExitCode::SUCCESS;
    }
    let mut opts = ValidateOptions {
        tier: match tier {
            TierArg::Ci => Tier::Ci,
            TierArg::Full => Tier::Full,
        },
        only,
        out,
        reuse,
        stop: None,
    };
    if let Err(e) = select(&opts) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let Some(universe) = mpi::initialize() else {
        eprintln!("error: MPI could not be initialised");
        return ExitCode::from(1);
    };
    let comm = MpiComm::new(&universe);
    let root = comm.rank() == 0;
    match stop_on_signals() {
        Ok(stop) => opts.stop = Some(stop),
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(1);
        }
    }
    let code = match validate(&comm, &opts) {
        Ok(ValidateEnd::Judged { passed: true, .. }) => ExitCode::SUCCESS,
        Ok(ValidateEnd::Judged { passed: false, .. }) if root => ExitCode::from(EXIT_CHECK_FAILED),
        Ok(ValidateEnd::Judged { .. }) => ExitCode::SUCCESS,
        Ok(ValidateEnd::Stopped { checkpoint }) => {
            if root {
                eprintln!(
                    "stopped by a signal after writing {}; the same command with --reuse continues",
                    checkpoint.display()
                );
            }
            ExitCode::from(EXIT_STOPPED)
        }
        Err(e) => {
            if root {
                eprintln!("error: {e}");
            }
            ExitCode::from(1)
        }
    };
    code
}

fn main() -> ExitCode {
    tumbler::run::return_freed_memory();
    tumbler::output::pario::start_library();
    let cli = Cli::parse();
    // stderr, and the run's NAME.log while a run is going on (src/run/run_log.rs)
    tumbler::run::run_log::init();
    if matches!(
        cli.command,
        Command::Info { .. }
            | Command::Bands { .. }
            | Command::Plot { .. }
            | Command::Export { .. }
    ) {
        read_without_locking();
    }
    match cli.command {
        Command::Info { file, case, all } => report(RunReader::open(&file).and_then(|r| {
            info(
                &r,
                &InfoOptions {
                    full_case: case,
                    all_groups: all,
                },
            )
        })),
        Command::Bands {
            file,
            threshold,
            min_slices,
        } => report(RunReader::open(&file).and_then(|r| {
            band_table(
                &r,
                &BandsOptions {
                    threshold,
                    min_slices,
                },
            )
            .map(|t| t.to_string())
        })),
        Command::Plot { what, format } => plot(what, format),
        Command::Export {
            file,
            lammps,
            vtu,
            group,
        } => report(RunReader::open(&file).and_then(|r| match (&lammps, &vtu) {
            (Some(out), _) => export_lammps(&r, out, group.as_deref()).map(|e| e.to_string()),
            (None, Some(dir)) => export_vtu(&r, dir, group.as_deref()).map(|e| e.to_string()),
            (None, None) => Err(InspectError::Invalid(
                "export: give --lammps OUT.data or --vtu DIR".into(),
            )),
        })),
        Command::Import {
            lammps,
            file,
            output,
            timestep,
            species,
            axes,
            offset,
            overwrite,
        } => report(
            import_lammps(&ImportOptions {
                input: file,
                kind: match lammps {
                    LammpsArg::Data => LammpsKind::Data,
                    LammpsArg::Dump => LammpsKind::Dump,
                },
                output,
                timestep,
                species,
                axes,
                offset,
                overwrite,
            })
            .map(|i| i.to_string()),
        ),
        Command::Validate {
            tier,
            only,
            out,
            reuse,
            list,
        } => validate(tier, only, out, reuse, list),
        Command::Check { case, set, ranks } => match load_case(&case, &set) {
            Ok(lc) => match tumbler::report::check_report(&lc.case, ranks) {
                Ok(text) => {
                    print!("{text}");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::from(2)
                }
            },
            Err(errs) => {
                report_case_errors(&errs);
                ExitCode::from(2)
            }
        },
        Command::Run {
            case,
            output,
            set,
            overwrite,
            restart,
            allow_different_case,
            new_output,
        } => {
            let Some(universe) = mpi::initialize() else {
                eprintln!("error: MPI could not be initialised");
                return ExitCode::from(1);
            };
            let comm = MpiComm::new(&universe);
            let root = comm.rank() == 0;
            let lc = match load_case(&case, &set) {
                Ok(lc) => lc,
                Err(errs) => {
                    if root {
                        report_case_errors(&errs);
                    }
                    return ExitCode::from(2);
                }
            };
            // the initial state on this many ranks, before anything is built
            if let Err(e) = tumbler::case::initial_memory(&lc.case, comm.size()) {
                if root {
                    report_case_errors(&[e]);
                }
                return ExitCode::from(2);
            }
            let output = output.unwrap_or_else(|| default_output(&case));
            let stop = match stop_on_signals() {
                Ok(stop) => stop,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::from(1);
                }
            };
            let opts = RunOptions {
                output,
                overwrite,
                restart,
                allow_different_case,
                new_output,
                stop: Some(stop),
            };
            let code = match run(&lc, &comm, &opts) {
                Ok(RunEnd::Finished(_)) => ExitCode::SUCCESS,
                Ok(RunEnd::Stopped { .. }) => ExitCode::from(EXIT_STOPPED),
                Err(e) => {
                    if root {
                        eprintln!("error: {e}");
                    }
                    ExitCode::from(1)
                }
            };
            code
        }
    }
}

/// The run's file when `--output` is not given: the case's file name with `.toml` replaced
/// by `.h5`, in the current directory. Only the last extension goes, so a case named after
/// its speed (`w6.28.toml`) keeps the `.28`.
fn default_output(case: &Path) -> PathBuf {
    let mut name = case.file_stem().map(|s| s.to_owned()).unwrap_or_default();
    name.push(".h5");
    PathBuf::from(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_output_keeps_dots_in_the_case_name() {
        let out = default_output(Path::new("cases/chen2008-ch4-periodic-w6.28.toml"));
        assert_eq!(out, PathBuf::from("chen2008-ch4-periodic-w6.28.h5"));
        assert_eq!(
            default_output(Path::new("quickstart.toml")),
            PathBuf::from("quickstart.h5")
        );
    }
}
