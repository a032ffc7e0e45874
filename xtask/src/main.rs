//! The project's own commands, parsed by clap. `cargo xtask help` lists them; `cargo xtask
//! <command> --help` gives each one's options and units.

mod checks;
mod commands;
mod harness;
mod image;
mod util;

use clap::{Parser, Subcommand};
use commands::{bench, build, eval, fuzz, hj, plot, profile, report, run, sim};
use harness::host as options;
use std::process::ExitCode;
use twocars::Policy;
use util::setup;

/// The project's own commands (units: metres, seconds, radians anticlockwise from +x; curvature
/// in 1/m).
#[derive(Debug, Parser)]
#[command(
    name = "cargo xtask",
    bin_name = "cargo xtask",
    arg_required_else_help = true
)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Debug, Subcommand)]
enum Cmd {
    /// The main job: the firmware in QEMU in closed loop with the host simulator.
    Run(run::RunArgs),
    /// Every check: fmt, clippy (host and thumb), builds, host tests, docs, QEMU, on-target
    /// tests, fuzz smoke runs; the last line is `N passed, N failed`.
    Test(checks::suite::TestArgs),
    /// Build the firmware images and print their flash and RAM.
    Build(build::BuildArgs),
    /// Instructions per law evaluation (M4F, M0), flash, stack, host throughput ->
    /// docs/bench.md.
    Bench,
    /// Instructions per law evaluation by function (QEMU exec log), M4F f32 and M0 fixed point.
    Profile,
    /// The libFuzzer targets from their seed corpora.
    Fuzz(fuzz::FuzzArgs),
    /// The law on CSV rows from stdin (docs/contract.md).
    Eval {
        #[command(flatten)]
        law: options::LawArgs,
    },
    /// Closed loop on the host, CSV rows from stdin (docs/contract.md).
    Sim(sim::SimArgs),
    /// Closed-loop Monte Carlo, both policies, split at the theorem's threshold, per evader.
    Report(report::ReportArgs),
    /// The game's value function by value iteration on the Hamilton-Jacobi-Isaacs grid, checked
    /// against the tail chase's exact value on three grid sizes.
    Hj(hj::HjArgs),
    /// SVG plots to target/plots/: the paper's cases, a value map, the Monte-Carlo scatters,
    /// the field's figures.
    Plot(plot::PlotArgs),
    /// Import cycles between the files of each of the workspace's crates, with what ties them,
    /// and any import of xtask's that points up its layers.
    Imports,
}

impl Cmd {
    /// What the command needs on this machine.
    fn needs(&self) -> Option<setup::Needs> {
        let all = setup::Needs {
            toolchain: setup::Toolchain::All,
            qemu: true,
        };
        match self {
            Cmd::Test(_) | Cmd::Bench | Cmd::Profile => Some(all),
            Cmd::Run(args) if !args.host_only => Some(setup::Needs {
                toolchain: setup::Toolchain::Target(args.target()),
                qemu: true,
            }),
            Cmd::Build(_) => Some(setup::Needs {
                toolchain: setup::Toolchain::All,
                qemu: false,
            }),
            _ => None,
        }
    }
}

fn main() -> ExitCode {
    // Usage errors exit 2 naming the option; --help exits 0.
    let cli = Cli::parse();
    // What the command needs on this machine, installed (or the way to install it printed)
    // before it builds.
    if let Err(message) = cli.command.needs().map_or(Ok(()), setup::ensure) {
        eprintln!("xtask: {message}");
        return ExitCode::from(1);
    }
    let code = match &cli.command {
        // `eval` and `sim` default to the paper's law, as the shared contract binds; `run`
        // flies the policy we recommend for flight.
        Cmd::Eval { law } => eval::run(&law.options(Policy::Paper)),
        Cmd::Sim(args) => sim::run(&args.law.options(Policy::Paper), args.opponent()),
        Cmd::Run(args) => run::run(args),
        Cmd::Test(args) => checks::suite::run(args),
        Cmd::Bench => bench::run(),
        Cmd::Fuzz(args) => fuzz::command(args),
        Cmd::Report(args) => report::command(args),
        Cmd::Hj(args) => hj::command(args),
        Cmd::Plot(args) => plot::command(args),
        Cmd::Profile => profile::command(),
        Cmd::Build(args) => build::command(args),
        Cmd::Imports => i32::from(checks::imports_point_down().1 > 0),
    };
    ExitCode::from(u8::try_from(code).unwrap_or(1))
}
