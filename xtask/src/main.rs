//! The project's own commands. `cargo xtask help` lists them.

mod bench;
mod csv;
mod eval;
mod firmware_loop;
mod fuzz;
mod options;
mod plot;
mod profile;
mod qemu;
mod qemu_tests;
mod report;
mod run;
mod setup;
mod sim;
mod size;
mod test;

use std::process::ExitCode;
use twocars::Policy;

const HELP: &str = "\
cargo xtask <command> [options]

  run     the main job: the firmware in QEMU in closed loop with the host simulator
          [--case paper1..paper4|all] [--dt S] [--t-max S] [--roles both|pursuer|evader]
          [--limits v,w,v,w] [--pursuer x,y,th --evader x,y,th] [--host-only]
          [--policy flight|paper] (default flight: the paper's law beyond the theorem's threshold,
          our pursuer below it) [--variant ..]
  build   build a firmware image and print its flash and RAM  [--board qemu|stm32f405|all]
  bench   instructions per law evaluation (M4F, M0), flash, stack, host throughput -> docs/bench.md
  profile instructions per law evaluation by function (QEMU exec log), M4F f32 and M0 fixed point
  fuzz    the libFuzzer targets from their seed corpora  [--seconds S | --runs N] [--write-seeds] [target..]
  test    every check: fmt, clippy (host and thumb), host tests, thumb builds, docs
  eval    the law on CSV rows from stdin  [--variant paper|clamped] [--numeric f32|f64]
  sim     closed loop on the host, CSV rows from stdin  [--variant ..] [--numeric ..] [--policy paper|flight] (default paper)
          [--evader NAME [--adversary-seed N]] (an evader of the adversary suite plays the evader)
  report  closed-loop Monte Carlo, both policies, split at the theorem's threshold  [--runs N] [--seed S] [--dt S]
          [--limits random|paper|both] [--evader NAME|all] [--pursuer NAME|all]
  plot    SVG plots to target/plots/: the paper's cases, a value map, the Monte-Carlo scatter
";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((command, rest)) = args.split_first() else {
        eprint!("{HELP}");
        return ExitCode::from(2);
    };
    // `run` flies the policy we recommend for flight; `eval` and `sim` default to the paper's law,
    // as the shared contract binds.
    let policy = if command == "run" {
        Policy::Flight
    } else {
        Policy::Paper
    };
    let parsed = options::parse(rest, policy);
    // What the command needs on this machine, installed (or the way to install it printed)
    // before it builds.
    let host_only = rest.iter().any(|a| a == "--host-only");
    let needs = match command.as_str() {
        "test" | "bench" | "profile" => Some(setup::Needs {
            toolchain: true,
            qemu: true,
        }),
        "run" if !host_only => Some(setup::Needs {
            toolchain: true,
            qemu: true,
        }),
        "build" => Some(setup::Needs {
            toolchain: true,
            qemu: false,
        }),
        _ => None,
    };
    if let Err(message) = needs.map_or(Ok(()), setup::ensure) {
        eprintln!("xtask {command}: {message}");
        return ExitCode::from(1);
    }
    let code = match (command.as_str(), parsed) {
        ("help" | "--help" | "-h", _) => {
            print!("{HELP}");
            0
        }
        (_, Err(message)) => {
            eprintln!("xtask {command}: {message}");
            2
        }
        ("eval", Ok((options, _))) => eval::run(&options),
        ("sim", Ok((options, rest))) => match sim::parse_opponent(&rest) {
            Ok(opponent) => sim::run(&options, opponent),
            Err(message) => {
                eprintln!("xtask sim: {message}");
                2
            }
        },
        ("run", Ok((options, rest))) => run::run(&options, &rest),
        ("test", Ok(_)) => test::run(),
        ("bench", Ok(_)) => bench::run(),
        ("fuzz", Ok((_, rest))) => fuzz::command(&rest),
        ("report", Ok((_, rest))) => report::command(&rest),
        ("plot", Ok(_)) => plot::command(),
        ("profile", Ok(_)) => profile::command(),
        ("build", Ok((_, rest))) => qemu::build_command(&rest),
        (other, Ok(_)) => {
            eprintln!("xtask: unknown command `{other}`\n{HELP}");
            2
        }
    };
    ExitCode::from(u8::try_from(code).unwrap_or(1))
}
