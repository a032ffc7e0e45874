//! `cargo xtask test`: every check the project has, in order; stops at the first failure.

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

/// The on-target scenario tests (`tests/on_target.rs`) on each Cortex-M target, run in QEMU by
/// `cargo test --target` through `.cargo/config.toml`'s runner: (target, features).
const ON_TARGET: [(&str, &str); 2] = [
    ("thumbv7em-none-eabihf", "on-target"),
    ("thumbv6m-none-eabi", "on-target,board-microbit"),
];

/// `cargo <subcommand>` of the on-target tests for `target` with `features`.
fn on_target_args<'a>(subcommand: &'a str, target: &'a str, features: &'a str) -> [&'a str; 10] {
    [
        subcommand,
        "-p",
        "twocars",
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

/// Runs every step; returns the exit code.
pub fn run() -> i32 {
    let started = Instant::now();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let mut ok = step("format", &cargo, &["fmt", "--all", "--", "--check"], &[])
        && step(
            "clippy (host)",
            &cargo,
            &[
                "clippy",
                "--workspace",
                "--all-targets",
                "--",
                "-D",
                "warnings",
            ],
            &[],
        );
    for target in THUMB_TARGETS {
        // The MAVLink endpoint's core too: it must compile without `std` on every target. Clippy
        // type-checks it there; code generation for the M4F and the M0 is the images' build
        // below (a release build of the bare library here cost ~32 s per target on a clean
        // clone and proved nothing more).
        let clippy = [
            "clippy",
            "-p",
            "twocars",
            "--release",
            "--features",
            "mavlink",
            "--target",
            target,
            "--",
            "-D",
            "warnings",
        ];
        ok = ok
            && step(
                &format!("clippy of the no_std core for {target}"),
                &cargo,
                &clippy,
                &[],
            );
    }
    const M4F: &str = "thumbv7em-none-eabihf";
    // The value tables the tables images carry: solved here (about two minutes on two cores,
    // then read from target/hj-cache), before their images' clippy and builds.
    let tables = if ok {
        println!("== xtask test: the value tables of the tables images");
        let sets = timed("the value tables", || {
            crate::hj::flash_sets(crate::qemu::Board::QemuTables.table_sets())
        });
        match sets.map(|paths| std::env::join_paths(paths).map_err(|e| e.to_string())) {
            Ok(Ok(joined)) => joined.to_string_lossy().into_owned(),
            Ok(Err(e)) | Err(e) => {
                eprintln!("== xtask test: the value tables: {e}");
                ok = false;
                String::new()
            }
        }
    } else {
        String::new()
    };
    for (feature, name, target) in [
        ("qemu-log", "QEMU", M4F),
        ("board-stm32f405", "STM32F405", M4F),
        ("board-qemu,mavlink", "QEMU MAVLink", M4F),
        ("board-stm32f405,mavlink", "STM32F405 MAVLink", M4F),
        ("firmware-microbit", "micro:bit", "thumbv6m-none-eabi"),
        ("firmware-rp2040", "RP2040", "thumbv6m-none-eabi"),
        ("bench-firmware", "bench", M4F),
        ("bench-empty", "empty bench", M4F),
        ("bench-fixed", "fixed-point bench", M4F),
        ("bench-micromath", "micromath bench", M4F),
        ("bench-report", "report bench", M4F),
        ("bench-loop", "serial loop bench", M4F),
        ("bench-mavlink", "MAVLink bench", M4F),
        ("bench-table", "value table bench", M4F),
        ("qemu-log,tables-in-flash", "QEMU tables", M4F),
        ("board-stm32f405,tables-in-flash", "STM32F405 tables", M4F),
    ] {
        let firmware_clippy = [
            "clippy",
            "-p",
            "twocars",
            "--release",
            "--target",
            target,
            "--features",
            feature,
            "--bins",
            "--",
            "-D",
            "warnings",
        ];
        ok = ok
            && step(
                &format!("clippy of the {name} firmware"),
                &cargo,
                &firmware_clippy,
                &[("TWOCARS_VALUE_TABLES", tables.as_str())],
            );
    }
    for (target, features) in ON_TARGET {
        let mut clippy = on_target_args("clippy", target, features).to_vec();
        clippy.extend(["--", "-D", "warnings"]);
        ok = ok
            && step(
                &format!("clippy of the on-target tests for {target}"),
                &cargo,
                &clippy,
                &[],
            );
    }
    if ok {
        println!(
            "== xtask test: firmware images build, vector tables at their boards' flash origins"
        );
        timed("the firmware images", || {
            for board in crate::qemu::Board::ALL {
                if let Err(e) = crate::qemu::build_checked(board) {
                    eprintln!("== xtask test: {e}");
                    ok = false;
                }
            }
        });
    }
    if ok {
        println!("== xtask test: panic freedom of the flight images, proven at link time");
        timed("the panic-freedom links", || {
            for board in crate::qemu::Board::ALL {
                if let Err(e) = crate::qemu::prove_panic_free(board) {
                    eprintln!("== xtask test: {e}");
                    ok = false;
                }
            }
        });
    }
    let counts = if ok {
        timed("the host tests", || host_tests(&cargo))
    } else {
        None
    };
    ok = ok
        && counts.is_some()
        && step(
            "docs",
            &cargo,
            &[
                "doc",
                "--no-deps",
                "-p",
                "twocars",
                "--features",
                "mavlink,firmware,bench",
            ],
            &[("RUSTDOCFLAGS", "-D warnings")],
        );
    let (mut passed, mut failed) = counts.unwrap_or((0, 0));
    if ok {
        let (p, f) = timed("the QEMU tests", crate::qemu_tests::run);
        passed += p;
        failed += f;
        ok = f == 0;
    }
    if ok {
        let (p, f) = timed("the on-target tests", || on_target(&cargo));
        passed += p;
        failed += f;
        ok = f == 0;
    }
    if ok {
        println!("== xtask test: fuzz smoke run, 10 s per target from the seed corpora");
        let fuzzing = Instant::now();
        if !crate::fuzz::ensure_cargo_fuzz() {
            eprintln!("== xtask test: cargo-fuzz is not available");
            failed += 1;
            ok = false;
        }
        for target in crate::fuzz::TARGETS {
            if !ok {
                break;
            }
            match crate::fuzz::run_target(target, crate::fuzz::Budget::Seconds(10)) {
                Ok(r) if !r.failed && r.executions > 0 => {
                    println!(
                        "test fuzz::{target} ... ok ({} executions, corpus {})",
                        r.executions, r.corpus
                    );
                    passed += 1;
                }
                Ok(r) => {
                    println!(
                        "test fuzz::{target} ... FAILED ({} executions)",
                        r.executions
                    );
                    failed += 1;
                    ok = false;
                }
                Err(e) => {
                    println!("test fuzz::{target} ... FAILED: {e}");
                    failed += 1;
                    ok = false;
                }
            }
        }
        println!(
            "== xtask test: the fuzz smoke run took {:.1} s",
            fuzzing.elapsed().as_secs_f64()
        );
    }
    if ok {
        println!(
            "== xtask test: all steps passed in {:.0} s",
            started.elapsed().as_secs_f64()
        );
    }
    // The closing line CI reads.
    println!("{passed} passed, {failed} failed");
    i32::from(!ok)
}
