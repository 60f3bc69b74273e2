//! The `tumbler` command line.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use tumbler::case::{load_case, CaseError};
use tumbler::comm::{Comm, MpiComm};
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
}

fn report_case_errors(errs: &[CaseError]) {
    eprintln!("error: the case was refused:");
    for e in errs {
        eprintln!("  {e}");
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .format_timestamp_secs()
        .init();
    match cli.command {
        Command::Check { case, set, ranks } => match load_case(&case, &set) {
            Ok(lc) => match tumbler::report::check_report(&lc.case, ranks.max(1)) {
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
            let output = output.unwrap_or_else(|| {
                let stem = case.file_stem().map(|s| s.to_owned()).unwrap_or_default();
                PathBuf::from(stem).with_extension("h5")
            });
            // SIGTERM/SIGINT (what Slurm and a user send): finish the step, checkpoint, stop
            // with EXIT_STOPPED; a second one stops at once (exit 130).
            let stop = Arc::new(AtomicBool::new(false));
            for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
                let registered =
                    signal_hook::flag::register_conditional_shutdown(sig, 130, Arc::clone(&stop))
                        .and_then(|_| signal_hook::flag::register(sig, Arc::clone(&stop)));
                if let Err(e) = registered {
                    eprintln!("error: cannot handle signal {sig}: {e}");
                    return ExitCode::from(1);
                }
            }
            let opts = RunOptions {
                output,
                overwrite,
                restart,
                allow_different_case,
                stop: Some(stop),
            };
            match run(&lc, &comm, &opts) {
                Ok(RunEnd::Finished(_)) => ExitCode::SUCCESS,
                Ok(RunEnd::Stopped { .. }) => ExitCode::from(EXIT_STOPPED),
                Err(e) => {
                    if root {
                        eprintln!("error: {e}");
                    }
                    ExitCode::from(1)
                }
            }
        }
    }
}
