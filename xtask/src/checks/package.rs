//! The crate as a user meets it: every command README shows, run as written from the
//! repository's root; every example built from the packaged crate; and the core's user
//! features on the oldest Rust the manifest claims (`rust-version`). `cargo xtask test` runs
//! all three.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::util::workspace::root;

/// What a README command must print, besides exiting with 0: (the command's start, the text).
const EXPECTED: [(&str, &str); 7] = [
    ("cargo run --example paper_case_1", "value: 5.6575 s"),
    ("cargo run --example closed_loop", "captured at 5.6"),
    ("cargo run --example field_chase", "captured within 0.3 m"),
    ("cargo run --example mavlink_stream", "\"TC: captured\""),
    (
        "cargo run --example table_policy",
        "the tables: captured within 0.5 m",
    ),
    ("cargo run --release --example cortex_m", "captured at 5.6"),
    ("cargo xtask run", "firmware exited with code 0"),
];

/// The `cargo` commands README shows: the lines of its `sh` blocks and its inline code, without
/// their comments, each once, in order.
pub fn readme_commands(readme: &str) -> Vec<String> {
    let mut commands: Vec<String> = Vec::new();
    let mut in_sh = false;
    for line in readme.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with("```") {
            in_sh = !in_sh && trimmed == "```sh";
            continue;
        }
        let found: Vec<String> = if in_sh {
            vec![trimmed.split(" #").next().unwrap_or("").trim().to_string()]
        } else {
            line.split('`')
                .skip(1)
                .step_by(2)
                .map(|code| code.trim().to_string())
                .collect()
        };
        for command in found {
            if command.starts_with("cargo ") && !commands.contains(&command) {
                commands.push(command);
            }
        }
    }
    commands
}

/// Runs README's commands from the root; (passed, failed). `cargo xtask test` itself (and its
/// tiers) is the suite running this, so it is named and not run again.
pub fn run_readme() -> (u64, u64) {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap_or_default();
    let (mut passed, mut failed) = (0, 0);
    for command in readme_commands(&readme) {
        if command.starts_with("cargo xtask test") {
            println!("readme: `{command}`: the suite itself, not run again");
            continue;
        }
        match run_one(&command) {
            Ok(()) => {
                println!("readme: `{command}` ... ok");
                passed += 1;
            }
            Err(e) => {
                eprintln!("readme: `{command}` FAILED: {e}");
                failed += 1;
            }
        }
    }
    if passed + failed == 0 {
        eprintln!("readme: no commands found in README.md");
        failed += 1;
    }
    (passed, failed)
}

/// Runs `command` through the shell from the root, its output captured; checks its exit code
/// and what [`EXPECTED`] says it prints.
fn run_one(command: &str) -> Result<(), String> {
    let out = Command::new("sh")
        .args(["-c", command])
        .current_dir(root())
        .stdin(Stdio::null())
        .output()
        .map_err(|e| e.to_string())?;
    let text = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let tail: Vec<&str> = err.lines().rev().take(5).collect();
        return Err(format!("{}: {}", out.status, tail.join(" | ")));
    }
    match EXPECTED
        .iter()
        .find(|(start, _)| command.starts_with(start))
    {
        Some((_, want)) if !text.contains(want) => Err(format!("no `{want}` in its output")),
        _ => Ok(()),
    }
}

/// The `rust-version` the core's manifest claims.
fn rust_version() -> Option<String> {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).ok()?;
    let value: toml::Table = manifest.parse().ok()?;
    let version = value.get("package")?.get("rust-version")?.as_str()?;
    Some(version.to_string())
}

/// Checks the core's user features (all but `mavlink`, whose crate needs a newer Rust) on the
/// manifest's `rust-version`, installing that toolchain with rustup (minimal profile) if
/// missing; (passed, failed).
pub fn check_rust_version() -> (u64, u64) {
    let Some(version) = rust_version() else {
        eprintln!("rust-version: none in Cargo.toml");
        return (0, 1);
    };
    let installed = Command::new("rustup")
        .args(["toolchain", "list"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains(&format!("{version}-")))
        .unwrap_or(false);
    if !installed {
        println!("rust-version: installing Rust {version} (minimal) with rustup");
        let ok = Command::new("rustup")
            .args(["toolchain", "install", &version, "--profile", "minimal"])
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            eprintln!("rust-version: could not install Rust {version}");
            return (0, 1);
        }
    }
    let features = "micromath,value-tables,firmware,defmt";
    let ok = Command::new("cargo")
        .arg(format!("+{version}"))
        .args(["check", "-p", "twocars", "--lib", "--features", features])
        .env(
            "CARGO_TARGET_DIR",
            crate::util::workspace::target_dir().join("rust-version"),
        )
        .current_dir(root())
        .status()
        .is_ok_and(|s| s.success());
    if ok {
        println!("rust-version: the core ({features}) builds on Rust {version} ... ok");
        (1, 0)
    } else {
        eprintln!("rust-version: the core ({features}) does not build on Rust {version}");
        (0, 1)
    }
}

/// The examples as a user builds them from the published crate: (name, features, target; none
/// for the host).
const EXAMPLES: [(&str, &str, Option<&str>); 8] = [
    ("paper_case_1", "", None),
    ("closed_loop", "", None),
    ("field_chase", "", None),
    ("mavlink_stream", "mavlink", None),
    ("table_policy", "value-tables", None),
    ("cortex_m4f", "board-qemu", Some("thumbv7em-none-eabihf")),
    ("cortex_m0", "board-microbit", Some("thumbv6m-none-eabi")),
    (
        "stm32f4_hal",
        "board-stm32f405,polled",
        Some("thumbv7em-none-eabihf"),
    ),
];

/// Packages the core (`cargo package`, not verified: the examples are what this checks), unpacks
/// the .crate in the system's temporary directory and builds every example from it (into
/// `target/package-check/`), each with its features, the Cortex-M ones with cortex-m-rt's
/// linker script as a user's `.cargo/config.toml` gives it; then runs its doctests, README's
/// blocks among them; (passed, failed).
pub fn check_package() -> (u64, u64) {
    let dir = crate::util::workspace::target_dir().join("package-check");
    let _ = std::fs::remove_dir_all(&dir);
    let Some(crate_file) = package(&dir) else {
        eprintln!("package: cargo package made no .crate");
        return (0, 1);
    };
    // Outside the workspace, as a user's copy is: inside it, cargo takes it for a member.
    let unpacked = std::env::temp_dir().join(format!("twocars-package-{}", std::process::id()));
    let Some(source) = unpack(&crate_file, &unpacked) else {
        eprintln!("package: could not unpack {}", crate_file.display());
        return (0, 1);
    };
    let (mut passed, mut failed) = (0, 0);
    for (name, features, target) in EXAMPLES {
        if build_example(&source, &dir.join("build"), name, features, target) {
            println!("package: example {name} builds from the published crate ... ok");
            passed += 1;
        } else {
            eprintln!("package: example {name} does not build from the published crate");
            failed += 1;
        }
    }
    // README's Rust blocks are the crate's doctests (`#[doc = include_str!("../README.md")]`).
    let doctests = Command::new("cargo")
        .args(["test", "--doc"])
        .env("CARGO_TARGET_DIR", dir.join("build"))
        .current_dir(&source)
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if doctests {
        println!(
            "package: README's blocks and the doc examples run from the published crate ... ok"
        );
        passed += 1;
    } else {
        eprintln!("package: README's blocks or a doc example fail from the published crate");
        failed += 1;
    }
    let _ = std::fs::remove_dir_all(&unpacked);
    (passed, failed)
}

/// `cargo package` of the core into `dir` (not verified: the examples are what this checks);
/// the .crate made.
fn package(dir: &Path) -> Option<PathBuf> {
    let packaged = Command::new("cargo")
        .args(["package", "-p", "twocars", "--no-verify", "--allow-dirty"])
        .env("CARGO_TARGET_DIR", dir)
        .current_dir(root())
        .status()
        .is_ok_and(|s| s.success());
    let mut entries = std::fs::read_dir(dir.join("package")).ok()?;
    let found = entries.find_map(|e| {
        let p = e.ok()?.path();
        p.extension().is_some_and(|e| e == "crate").then_some(p)
    });
    found.filter(|_| packaged)
}

/// The .crate `crate_file` unpacked into `into` (emptied first); its source directory.
fn unpack(crate_file: &Path, into: &Path) -> Option<PathBuf> {
    let _ = std::fs::remove_dir_all(into);
    let _ = std::fs::create_dir_all(into);
    let untarred = Command::new("tar")
        .arg("xzf")
        .arg(crate_file)
        .arg("-C")
        .arg(into)
        .status()
        .is_ok_and(|s| s.success());
    let source = std::fs::read_dir(into).ok()?.next()?.ok()?.path();
    untarred.then_some(source)
}

/// Whether example `name` builds from `source` with `features`, for `target` with
/// cortex-m-rt's linker script where given.
fn build_example(
    source: &Path,
    target_dir: &Path,
    name: &str,
    features: &str,
    target: Option<&str>,
) -> bool {
    let mut build = Command::new("cargo");
    build
        .args(["build", "--release", "--example", name])
        .env("CARGO_TARGET_DIR", target_dir)
        .current_dir(source)
        .stdout(Stdio::null());
    if !features.is_empty() {
        build.args(["--features", features]);
    }
    if let Some(target) = target {
        build
            .args(["--target", target])
            .env("RUSTFLAGS", "-C link-arg=-Tlink.x");
    }
    build.status().is_ok_and(|s| s.success())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readme_commands_come_from_sh_blocks_and_inline_code() {
        let readme =
            "Run `cargo run --example a` or `git log`.\n\n```sh\ncargo xtask run     # the job\n\
                      cargo xtask run\n```\n\n```toml\ncargo = 1\n```\n| x | `cargo b` |\n";
        assert_eq!(
            readme_commands(readme),
            ["cargo run --example a", "cargo xtask run", "cargo b"]
        );
    }
}
