//! `cargo xtask test`: every check the project has, as a list of named steps run in order;
//! stops at the first failure. `--quick` is the edit loop's tier, `--only` and `--skip` pick steps;
//! a step of the asked tier runs only where `--only` names it.

use super::Tally;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Instant;

/// Cortex-M targets the no_std core must build for.
const THUMB_TARGETS: [&str; 3] = [
    "thumbv7em-none-eabihf",
    "thumbv7m-none-eabi",
    "thumbv6m-none-eabi",
];

/// Runs `f`, then says how long `title` took (where the suite's time goes).
fn timed<T>(title: &str, f: impl FnOnce() -> T) -> T {
    let started = Instant::now();
    let out = f();
    println!(
        "== xtask test: {title} took {:.1} s",
        started.elapsed().as_secs_f64()
    );
    out
}

fn step(title: &str, program: &str, args: &[&str], env: &[(&str, &str)]) -> bool {
    println!("== xtask test: {title}");
    let mut command = Command::new(program);
    command.args(args);
    for (k, v) in env {
        command.env(k, v);
    }
    match timed(title, || command.status()) {
        Ok(status) if status.success() => true,
        Ok(status) => {
            eprintln!("== xtask test: `{title}` failed ({status})");
            false
        }
        Err(e) => {
            eprintln!("== xtask test: could not start `{program}`: {e}");
            false
        }
    }
}

/// Runs `cargo test`, echoing its output, and sums its `test result:` lines into (passed, failed).
fn host_tests(cargo: &str) -> Option<(u64, u64)> {
    println!("== xtask test: host tests");
    let mut child = Command::new(cargo)
        .args(["test", "--workspace", "--color", "never"])
        .stdout(Stdio::piped())
        .spawn()
        .ok()?;
    let (mut passed, mut failed) = (0, 0);
    if let Some(out) = child.stdout.take() {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            println!("{line}");
            if let Some(rest) = line.strip_prefix("test result: ") {
                let count = |word: &str| {
                    rest.split(';')
                        .find_map(|part| {
                            part.trim()
                                .trim_start_matches("ok. ")
                                .trim_start_matches("FAILED. ")
                                .strip_suffix(word)
                        })
                        .and_then(|n| n.trim().parse::<u64>().ok())
                        .unwrap_or(0)
                };
                passed += count(" passed");
                failed += count(" failed");
            }
        }
    }
    let status = child.wait().ok()?;
    if status.success() {
        Some((passed, failed))
    } else {
        eprintln!("== xtask test: `host tests` failed ({status})");
        None
    }
}

/// The on-target scenario tests (`bench/tests/on_target.rs`) on each Cortex-M target, run in QEMU by
/// `cargo test --target` through `.cargo/config.toml`'s runner: (target, features).
const ON_TARGET: [(&str, &str); 2] = [
    ("thumbv7em-none-eabihf", "qemu,micromath"),
    ("thumbv6m-none-eabi", "qemu,micromath"),
];

/// `cargo <subcommand>` of the on-target tests for `target` with `features`.
fn on_target_args<'a>(subcommand: &'a str, target: &'a str, features: &'a str) -> [&'a str; 10] {
    [
        subcommand,
        "-p",
        "twocars-bench",
        "--release",
        "--target",
        target,
        "--features",
        features,
        "--test",
        "on_target",
    ]
}

/// Runs the on-target tests, echoing their output; each run's `on_target: N passed, M failed`
/// line summed into (passed, failed), a run that does not report counting as one failure.
fn on_target(cargo: &str) -> (u64, u64) {
    let (mut passed, mut failed) = (0, 0);
    for (target, features) in ON_TARGET {
        println!("== xtask test: on-target tests on {target} in QEMU ({features})");
        let Ok(mut child) = Command::new(cargo)
            .args(on_target_args("test", target, features))
            .stdout(Stdio::piped())
            .spawn()
        else {
            failed += 1;
            continue;
        };
        let mut reported = None;
        if let Some(out) = child.stdout.take() {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                println!("{line}");
                if let Some(rest) = line.strip_prefix("on_target: ") {
                    let numbers: Vec<u64> = rest
                        .split(|c: char| !c.is_ascii_digit())
                        .filter_map(|n| n.parse().ok())
                        .collect();
                    if let [p, f] = numbers[..] {
                        reported = Some((p, f));
                    }
                }
            }
        }
        let success = child.wait().is_ok_and(|s| s.success());
        match reported {
            Some((p, f)) => {
                passed += p;
                failed += f + u64::from(f == 0 && !success);
            }
            None => failed += 1,
        }
    }
    (passed, failed)
}

/// `cargo xtask test`'s options: the full run by default (README's command, CI's).
#[derive(Debug, Clone, clap::Args)]
pub struct TestArgs {
    /// The edit loop's tier: format, clippy on the host and the host tests (a few minutes).
    #[arg(long, conflicts_with = "only")]
    quick: bool,
    /// Only these steps, in the suite's order (comma-separated or repeated).
    #[arg(long, value_delimiter = ',', value_parser = step_name)]
    only: Vec<&'static str>,
    /// Every step but these (comma-separated or repeated).
    #[arg(long, value_delimiter = ',', value_parser = step_name)]
    skip: Vec<&'static str>,
}

/// A step's name as `--only` and `--skip` take it, refused by name if the suite has none such.
fn step_name(name: &str) -> Result<&'static str, String> {
    STEPS
        .iter()
        .find(|s| s.name == name)
        .map(|s| s.name)
        .ok_or_else(|| {
            let names: Vec<&str> = STEPS.iter().map(|s| s.name).collect();
            format!("no step `{name}`; the steps: {}", names.join(", "))
        })
}

/// What the steps share: cargo, the value tables' files once solved, and the counts of the
/// steps that count tests.
struct Suite {
    cargo: String,
    tables: Option<String>,
    passed: u64,
    failed: u64,
}

impl Suite {
    /// The value tables the tables images carry, solved the first time a step needs them
    /// (about two minutes on two cores, then read from the caches), as `PATH`-joined files.
    fn tables(&mut self) -> Option<String> {
        if self.tables.is_none() {
            println!("== xtask test: the value tables of the tables images");
            let sets = timed("the value tables", || {
                crate::image::tables::solve::flash_sets(
                    crate::image::Image::QemuTables.table_sets(),
                )
            });
            match sets.map(|paths| std::env::join_paths(paths).map_err(|e| e.to_string())) {
                Ok(Ok(joined)) => self.tables = Some(joined.to_string_lossy().into_owned()),
                Ok(Err(e)) | Err(e) => eprintln!("== xtask test: the value tables: {e}"),
            }
        }
        self.tables.clone()
    }

    /// Adds a step's test counts; true if none failed.
    fn count(&mut self, (passed, failed): (u64, u64)) -> bool {
        self.passed += passed;
        self.failed += failed;
        failed == 0
    }
}

/// Which runs take a step: `--quick` and the full run, the full run, or only `--only`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Tier {
    Quick,
    Full,
    Asked,
}

/// A step of the suite: its name for `--only` and `--skip`, its tier, and what it does (true
/// if it passed).
struct Step {
    name: &'static str,
    tier: Tier,
    run: fn(&mut Suite) -> bool,
}

impl Step {
    /// A step of the full run and of `--quick`.
    const fn quick(name: &'static str, run: fn(&mut Suite) -> bool) -> Self {
        let tier = Tier::Quick;
        Step { name, tier, run }
    }

    /// A step of the full run only.
    const fn full(name: &'static str, run: fn(&mut Suite) -> bool) -> Self {
        let tier = Tier::Full;
        Step { name, tier, run }
    }

    /// A step run only when `--only` names it.
    const fn asked(name: &'static str, run: fn(&mut Suite) -> bool) -> Self {
        let tier = Tier::Asked;
        Step { name, tier, run }
    }
}

/// The suite, in order; the full run stops at the first step that fails.
const STEPS: [Step; 21] = [
    Step::quick("format", format),
    Step::quick("imports", |suite| {
        println!(
            "== xtask test: no import cycle in any crate; xtask's imports point down its layers"
        );
        let counts = timed("the import check", crate::checks::imports_point_down);
        suite.count(counts)
    }),
    Step::quick("clippy-host", clippy_host),
    Step::full("clippy-core", clippy_core),
    Step::full("tables", |suite| suite.tables().is_some()),
    Step::full("clippy-firmware", clippy_firmware),
    Step::full("clippy-bench", clippy_bench),
    Step::full("images", images),
    Step::full("panic-free", panic_free),
    Step::quick("host-tests", host),
    Step::full("docs", docs),
    Step::full("qemu", |suite| {
        named_tests(
            suite,
            "the serial images' tests",
            crate::checks::firmware::serial_images,
        )
    }),
    Step::full("mavlink", |suite| {
        named_tests(
            suite,
            "the MAVLink images' tests",
            crate::checks::firmware::mavlink_images,
        )
    }),
    Step::full("ardupilot", |suite| {
        named_tests(suite, "the ArduPilot SITL tests", |tally| {
            crate::checks::sitl::ardupilot(&mut |name, outcome| tally.record(name, outcome))
        })
    }),
    Step::full("px4", |suite| {
        named_tests(suite, "the PX4 SITL tests", |tally| {
            crate::checks::sitl::px4(&mut |name, outcome| tally.record(name, outcome))
        })
    }),
    Step::full("on-target", on_target_tests),
    Step::full("readme", |suite| {
        println!("== xtask test: README's commands, as written, from the root");
        let counts = timed("README's commands", crate::checks::package::run_readme);
        suite.count(counts)
    }),
    Step::full("package", |suite| {
        println!("== xtask test: the examples built from the packaged crate");
        let counts = timed("the package check", crate::checks::package::check_package);
        suite.count(counts)
    }),
    Step::full("rust-version", |suite| {
        println!("== xtask test: the core on the manifest's rust-version");
        let counts = timed(
            "the rust-version check",
            crate::checks::package::check_rust_version,
        );
        suite.count(counts)
    }),
    Step::full("fuzz", fuzz),
    Step::asked("ardupilot-team", |suite| {
        named_tests(suite, "the ArduPilot SITL team's tests", |tally| {
            crate::checks::sitl::ardupilot_team(&mut |name, outcome| tally.record(name, outcome))
        })
    }),
];

/// Runs the steps `args` selects; returns the exit code. The last line is `N passed, N failed`.
pub fn run(args: &TestArgs) -> i32 {
    let started = Instant::now();
    let mut suite = Suite {
        cargo: std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string()),
        tables: None,
        passed: 0,
        failed: 0,
    };
    let chosen = |step: &&Step| {
        let asked = if args.quick {
            step.tier == Tier::Quick
        } else if args.only.is_empty() {
            step.tier != Tier::Asked
        } else {
            args.only.contains(&step.name)
        };
        asked && !args.skip.contains(&step.name)
    };
    let mut times = Vec::new();
    let mut ok = true;
    for step in STEPS.iter().filter(chosen) {
        let step_started = Instant::now();
        ok = (step.run)(&mut suite);
        times.push((step.name, step_started.elapsed().as_secs_f64()));
        if !ok {
            break;
        }
    }
    print_times(&times);
    if ok {
        println!(
            "== xtask test: all steps passed in {:.0} s",
            started.elapsed().as_secs_f64()
        );
    }
    // The closing line CI reads.
    println!("{} passed, {} failed", suite.passed, suite.failed);
    i32::from(!ok)
}

/// Each step's time, longest first, so that where the suite's time goes is read at its end.
fn print_times(times: &[(&str, f64)]) {
    let mut sorted = times.to_vec();
    sorted.sort_by(|a, b| b.1.total_cmp(&a.1));
    println!("== xtask test: time by step, longest first");
    for (name, seconds) in sorted {
        println!("==   {name:<16} {seconds:7.1} s");
    }
}

fn format(suite: &mut Suite) -> bool {
    step(
        "format",
        &suite.cargo,
        &["fmt", "--all", "--", "--check"],
        &[],
    )
}

fn clippy_host(suite: &mut Suite) -> bool {
    let args = [
        "clippy",
        "--workspace",
        "--all-targets",
        "--",
        "-D",
        "warnings",
    ];
    step("clippy (host)", &suite.cargo, &args, &[])
}

/// The no_std core with the MAVLink endpoint's core on every Cortex-M target: it must compile
/// without `std` there. Clippy type-checks it; code generation for the M4F and the M0 is the
/// images' build (a release build of the bare library here cost ~32 s per target on a clean
/// clone and proved nothing more).
fn clippy_core(suite: &mut Suite) -> bool {
    // The team's doors, which no image carries, on the M0 (no FPU, no atomics) once.
    let team = (
        "mavlink,mavlink-team,serial-team,polled",
        "thumbv6m-none-eabi",
    );
    let runs = THUMB_TARGETS.iter().map(|&t| ("mavlink,polled", t));
    runs.chain([team]).all(|(features, target)| {
        let clippy = [
            "clippy",
            "-p",
            "twocars",
            "--release",
            "--features",
            features,
            "--target",
            target,
            "--",
            "-D",
            "warnings",
        ];
        let title = format!("clippy of the no_std core for {target} ({features})");
        step(&title, &suite.cargo, &clippy, &[])
    })
}

const M4F: &str = "thumbv7em-none-eabihf";

/// Every firmware image's features, its name, its target.
const FIRMWARE: [(&str, &str, &str); 8] = [
    ("qemu-log", "QEMU", M4F),
    ("board-stm32f405", "STM32F405", M4F),
    ("board-qemu,mavlink", "QEMU MAVLink", M4F),
    ("board-stm32f405,mavlink", "STM32F405 MAVLink", M4F),
    ("board-microbit", "micro:bit", "thumbv6m-none-eabi"),
    ("board-rp2040", "RP2040", "thumbv6m-none-eabi"),
    ("qemu-log,tables-in-flash", "QEMU tables", M4F),
    ("board-stm32f405,tables-in-flash", "STM32F405 tables", M4F),
];

/// The examples that run on a Cortex-M: their name, features and target.
const TARGET_EXAMPLES: [(&str, &str, &str); 3] = [
    ("cortex_m4f", "board-qemu", M4F),
    ("cortex_m0", "board-microbit", "thumbv6m-none-eabi"),
    ("stm32f4_hal", "board-stm32f405,polled", M4F),
];

fn clippy_firmware(suite: &mut Suite) -> bool {
    let Some(tables) = suite.tables() else {
        return false;
    };
    let examples = TARGET_EXAMPLES.iter().all(|(example, features, target)| {
        let title = format!("clippy of the example {example}");
        let clippy = clippy_twocars(target, features, &["--example", example]);
        step(&title, &suite.cargo, &clippy, &[])
    });
    examples
        && FIRMWARE.iter().all(|(feature, name, target)| {
            let title = format!("clippy of the {name} firmware");
            let clippy = clippy_twocars(target, feature, &["--bins"]);
            let tables = [("TWOCARS_VALUE_TABLES", tables.as_str())];
            step(&title, &suite.cargo, &clippy, &tables)
        })
}

/// `cargo clippy` of twocars's `what` (`--bins`, `--example NAME`) in release for `target`
/// with `features`, warnings denied.
fn clippy_twocars<'a>(target: &'a str, features: &'a str, what: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["clippy", "-p", "twocars", "--release", "--target", target];
    args.extend(["--features", features]);
    args.extend(what);
    args.extend(["--", "-D", "warnings"]);
    args
}

/// The bench images and the on-target tests (`twocars-bench`, every image's features at once)
/// on both of their CPUs.
fn clippy_bench(suite: &mut Suite) -> bool {
    ON_TARGET.iter().all(|(target, _)| {
        let clippy = [
            "clippy",
            "-p",
            "twocars-bench",
            "--release",
            "--target",
            target,
            "--features",
            "qemu,micromath,mavlink,tables",
            "--bins",
            "--tests",
            "--",
            "-D",
            "warnings",
        ];
        let title = format!("clippy of the bench images and on-target tests for {target}");
        step(&title, &suite.cargo, &clippy, &[])
    })
}

fn images(_: &mut Suite) -> bool {
    let what = "firmware images build, vector tables at their boards' flash origins";
    every_board(what, "the firmware images", |board| {
        crate::image::build_checked(board, None)
    })
}

fn panic_free(_: &mut Suite) -> bool {
    let what = "panic freedom of the flight images, proven at link time";
    every_board(
        what,
        "the panic-freedom links",
        crate::image::prove_panic_free,
    )
}

/// `check` on every board, each error printed (every board is checked even after one fails);
/// true if none failed.
fn every_board<T>(
    what: &str,
    title: &str,
    check: fn(crate::image::Image) -> Result<T, String>,
) -> bool {
    println!("== xtask test: {what}");
    timed(title, || {
        let mut ok = true;
        for board in crate::image::Image::ALL {
            if let Err(e) = check(board) {
                eprintln!("== xtask test: {e}");
                ok = false;
            }
        }
        ok
    })
}

fn host(suite: &mut Suite) -> bool {
    match timed("the host tests", || host_tests(&suite.cargo)) {
        Some(counts) => suite.count(counts),
        None => false,
    }
}

fn docs(suite: &mut Suite) -> bool {
    let args = [
        "doc",
        "--no-deps",
        "-p",
        "twocars",
        "-p",
        "twocars-bench",
        "--features",
        "twocars/micromath,twocars/value-tables,twocars/polled,twocars-bench/mavlink,twocars-bench/tables",
    ];
    step(
        "docs",
        &suite.cargo,
        &args,
        &[("RUSTDOCFLAGS", "-D warnings")],
    ) && timed("the core's docs", || super::docs::core(&suite.cargo))
}

fn on_target_tests(suite: &mut Suite) -> bool {
    let counts = timed("the on-target tests", || on_target(&suite.cargo));
    suite.count(counts)
}

/// A step of named tests, run into one [`Tally`] and counted.
fn named_tests(suite: &mut Suite, title: &str, run: impl FnOnce(&mut Tally)) -> bool {
    let mut tally = Tally::default();
    timed(title, || run(&mut tally));
    suite.count((tally.passed, tally.failed))
}

/// Each libFuzzer target for 10 s from its seed corpus, two at a time (one per core: each
/// run is one process on one thread).
fn fuzz(suite: &mut Suite) -> bool {
    use crate::harness::fuzz::{run_target, Budget, FuzzRun, TARGETS};
    println!("== xtask test: fuzz smoke run, 10 s per target from the seed corpora");
    let fuzzing = Instant::now();
    let built = match crate::harness::fuzz::build_targets() {
        Ok(built) => built,
        Err(e) => {
            eprintln!("== xtask test: {e}");
            suite.failed += 1;
            return false;
        }
    };
    let half = TARGETS.len().div_ceil(2);
    let runs: Vec<(&str, Result<FuzzRun, String>)> = std::thread::scope(|scope| {
        let built = &built;
        let workers: Vec<_> = TARGETS
            .chunks(half)
            .map(|chunk| {
                scope.spawn(move || {
                    let run = |&t: &&'static str| (t, run_target(t, built, Budget::Seconds(10)));
                    chunk.iter().map(run).collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_default())
            .collect()
    });
    let mut ok = runs.len() == TARGETS.len();
    if !ok {
        println!("test fuzz ... FAILED: a worker stopped before its targets ran");
        suite.failed += 1;
    }
    for (target, run) in runs {
        let line = match run {
            Ok(r) if !r.failed && r.executions > 0 => {
                suite.passed += 1;
                format!("ok ({} executions, corpus {})", r.executions, r.corpus)
            }
            Ok(r) => format!("FAILED ({} executions)", r.executions),
            Err(e) => format!("FAILED: {e}"),
        };
        ok &= line.starts_with("ok");
        suite.failed += u64::from(!line.starts_with("ok"));
        println!("test fuzz::{target} ... {line}");
    }
    println!(
        "== xtask test: the fuzz smoke run took {:.1} s",
        fuzzing.elapsed().as_secs_f64()
    );
    ok
}
