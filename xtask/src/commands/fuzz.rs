//! `cargo xtask fuzz`: each libFuzzer target of `fuzz/` from its seed corpus with a time or run
//! budget ([`crate::harness::fuzz`]); prints executions, corpus size and failures per target.

use crate::harness::fuzz::{build_targets, run_target, write_seeds, Budget, TARGETS};
use crate::util::progress::Progress;

/// `cargo xtask fuzz`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct FuzzArgs {
    /// Wall-clock seconds per target (default 60).
    #[arg(long, conflicts_with = "runs")]
    seconds: Option<u64>,
    /// Executions per target instead of seconds.
    #[arg(long)]
    runs: Option<u64>,
    /// Regenerate the seed corpora in fuzz/seeds from the project's own cases, then stop.
    #[arg(long)]
    write_seeds: bool,
    /// Targets to run (default all).
    #[arg(value_parser = TARGETS)]
    targets: Vec<String>,
}

/// `cargo xtask fuzz [--seconds S | --runs N] [--write-seeds] [target...]`.
pub fn command(args: &FuzzArgs) -> i32 {
    if args.write_seeds {
        return match write_seeds() {
            Ok(()) => 0,
            Err(e) => {
                eprintln!("xtask fuzz: {e}");
                1
            }
        };
    }
    let budget = match (args.runs, args.seconds) {
        (Some(n), _) => Budget::Runs(n),
        (None, n) => Budget::Seconds(n.unwrap_or(60)),
    };
    let mut targets: Vec<&'static str> = TARGETS
        .into_iter()
        .filter(|t| args.targets.iter().any(|a| a == t))
        .collect();
    if targets.is_empty() {
        targets = TARGETS.to_vec();
    }
    let built = match build_targets() {
        Ok(built) => built,
        Err(e) => {
            eprintln!("xtask fuzz: {e}");
            return 1;
        }
    };
    let mut ok = true;
    println!("| target | budget | executions | corpus | failures |");
    println!("|---|---|---|---|---|");
    let progress = Progress::new(targets.len() as u64, "fuzz targets");
    for target in targets {
        progress.step(&format!("fuzzing {target} ({budget:?})"));
        let result = run_target(target, &built, budget);
        progress.inc();
        match result {
            Ok(r) => {
                println!(
                    "| {} | {budget:?} | {} | {} | {} |",
                    r.target,
                    r.executions,
                    r.corpus,
                    u8::from(r.failed)
                );
                ok &= !r.failed;
            }
            Err(e) => {
                eprintln!("xtask fuzz: {e}");
                ok = false;
            }
        }
    }
    progress.finish();
    i32::from(!ok)
}
