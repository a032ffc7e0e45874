//! What the commands need on this machine, made sure of before they build: the pinned
//! toolchain's Cortex-M targets and components (`rust-toolchain.toml`; rustup does not add them
//! to a toolchain that is already installed) and `qemu-system-arm`. Each install is said in one
//! line; where it cannot be done here (not root, or no apt-get), the exact command is printed and
//! the command stops.

use std::path::{Path, PathBuf};
use std::process::Command;

/// What a command needs.
#[derive(Clone, Copy, Debug)]
pub struct Needs {
    /// Of `rust-toolchain.toml`'s Cortex-M targets and components.
    pub toolchain: Toolchain,
    /// `qemu-system-arm`.
    pub qemu: bool,
}

/// What of the pinned toolchain a command needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Toolchain {
    /// Every target and component (the checks, the bench).
    All,
    /// One target, no component: a run builds one board's image, and each target more is a
    /// download on a bare machine.
    Target(&'static str),
}

/// Makes sure of `needs`; an error says what is missing and how to install it.
pub fn ensure(needs: Needs) -> Result<(), String> {
    toolchain(needs.toolchain)?;
    if needs.qemu {
        qemu()?;
    }
    Ok(())
}

/// The repository's root (the parent of `xtask/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// The `targets` and `components` arrays of `rust-toolchain.toml`.
fn pinned() -> Result<(Vec<String>, Vec<String>), String> {
    let path = root().join("rust-toolchain.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let table: toml::Table = text
        .parse()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let list = |key: &str| -> Vec<String> {
        table
            .get("toolchain")
            .and_then(|t| t.get(key))
            .and_then(|v| v.as_array())
            .map(|a| {
                a.iter()
                    .filter_map(|v| v.as_str().map(str::to_string))
                    .collect()
            })
            .unwrap_or_default()
    };
    Ok((list("targets"), list("components")))
}

/// Runs `rustup` with `args` (in the repository, so on the pinned toolchain); its stdout.
fn rustup(args: &[&str]) -> Result<String, String> {
    let out = Command::new("rustup")
        .current_dir(root())
        .args(args)
        .output()
        .map_err(|e| {
            format!(
                "rustup {}: {e} (without rustup, install the targets of rust-toolchain.toml yourself)",
                args.join(" ")
            )
        })?;
    if !out.status.success() {
        return Err(format!(
            "rustup {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

/// Adds the pinned toolchain's missing targets and components of those `wanted`.
fn toolchain(wanted: Toolchain) -> Result<(), String> {
    let (mut targets, mut components) = pinned()?;
    if let Toolchain::Target(one) = wanted {
        targets.retain(|t| t == one);
        components.clear();
    }
    add_missing("target", "targets", &targets, |line, t| line == t)?;
    // Installed components are listed with their host triple: `clippy-x86_64-unknown-linux-gnu`.
    add_missing("component", "components", &components, |line, c| {
        line == c
            || line
                .strip_prefix(c)
                .is_some_and(|rest| rest.starts_with('-'))
    })
}

/// `rustup <kind> add` of those `wanted` that no line of `rustup <kind> list --installed`
/// matches (`matches(line, name)`); says what it installs in one line.
fn add_missing(
    kind: &str,
    plural: &str,
    wanted: &[String],
    matches: impl Fn(&str, &str) -> bool,
) -> Result<(), String> {
    let installed = rustup(&[kind, "list", "--installed"])?;
    let missing: Vec<&str> = wanted
        .iter()
        .map(String::as_str)
        .filter(|w| !installed.lines().any(|l| matches(l.trim(), w)))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    eprintln!(
        "xtask: installing Rust {plural} {} (rustup {kind} add)",
        missing.join(", ")
    );
    let mut args = vec![kind, "add"];
    args.extend(&missing);
    rustup(&args).map(|_| ())
}

/// Whether this process runs as root (`id -u` prints 0).
fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.status.success() && String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// Installs `qemu-system-arm` with apt-get where this runs as root; otherwise the command for
/// this platform's package manager, as an error.
fn qemu() -> Result<(), String> {
    if qemu_binary().is_ok() {
        return Ok(());
    }
    if is_root() && on_path("apt-get").is_some() {
        if apt_install(&["qemu-system-arm"]) {
            return qemu_binary().map(|_| ());
        }
        return Err("apt-get could not install qemu-system-arm".to_string());
    }
    let command = [
        ("apt-get", "sudo apt-get install qemu-system-arm"),
        ("dnf", "sudo dnf install qemu-system-arm"),
        ("pacman", "sudo pacman -S qemu-system-arm"),
        ("brew", "brew install qemu"),
    ]
    .iter()
    .find(|(manager, _)| on_path(manager).is_some())
    .map_or(
        "your package manager's qemu-system-arm package",
        |(_, c)| *c,
    );
    Err(format!(
        "qemu-system-arm is not installed and this user cannot install it: run `{command}`, then the command again"
    ))
}

/// Installs Debian `packages` with apt-get (as root), saying so in one line; whether it worked.
fn apt_install(packages: &[&str]) -> bool {
    eprintln!("xtask: installing {} (apt-get install)", packages.join(" "));
    let apt = |args: &[&str]| {
        Command::new("apt-get")
            .args(args)
            .env("DEBIAN_FRONTEND", "noninteractive")
            .stdout(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    // Without recommends: qemu-system-arm's (its GUI, firmware for other machines) are most of
    // the download on a bare machine, and the emulators here run headless.
    let install = ["install", "-y", "-qq", "--no-install-recommends"];
    apt(&["update", "-qq"]) && apt(&[&install[..], packages].concat())
}

/// Python 3 with `venv` and `ensurepip` (pymavlink's virtual environment, docs/mavlink.md):
/// installed with apt-get where this runs as root; otherwise the command, as an error.
pub fn python_venv() -> Result<(), String> {
    let works = || {
        Command::new("python3")
            .args(["-c", "import venv, ensurepip"])
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if works() {
        return Ok(());
    }
    let root_with_apt = is_root() && on_path("apt-get").is_some();
    if root_with_apt && apt_install(&["python3", "python3-venv"]) && works() {
        return Ok(());
    }
    Err(
        "python3 with venv is needed for pymavlink and the HJI peer: run `sudo apt-get install python3-venv` \
         (or your system's Python 3 with venv), then the command again"
            .to_string(),
    )
}

/// The Python of the virtual environment `target/NAME`, created on first use with
/// `requirements` installed (pinned, from the Python package index); `probe` is the import that
/// tells it is ready.
pub fn venv(name: &str, requirements: &[&str], probe: &str) -> Result<PathBuf, String> {
    let venv = crate::util::workspace::target_dir().join(name);
    let python = venv.join("bin/python");
    let ready = |p: &PathBuf| {
        Command::new(p)
            .args(["-c", probe])
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if ready(&python) {
        return Ok(python);
    }
    python_venv()?;
    let wanted = requirements.join(" ");
    eprintln!("xtask: installing {wanted} into target/{name} (first use)");
    let created = Command::new("python3")
        .args(["-m", "venv"])
        .arg(&venv)
        .status()
        .is_ok_and(|s| s.success());
    let installed = created
        && Command::new(&python)
            .args(["-m", "pip", "install", "--quiet"])
            .args(requirements)
            .status()
            .is_ok_and(|s| s.success());
    if installed && ready(&python) {
        Ok(python)
    } else {
        Err(format!(
            "could not install {wanted} into {} (is the Python package index reachable?)",
            venv.display()
        ))
    }
}

/// Node.js and npm (rp2040js, the RP2040's emulator): installed with apt-get where this runs as
/// root; otherwise the command, as an error.
pub fn node() -> Result<(), String> {
    let works = |program: &str| {
        Command::new(program)
            .arg("--version")
            .stdout(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if works("node") && works("npm") {
        return Ok(());
    }
    let root_with_apt = is_root() && on_path("apt-get").is_some();
    if root_with_apt && apt_install(&["nodejs", "npm"]) && works("node") && works("npm") {
        return Ok(());
    }
    Err(
        "Node.js and npm are needed for rp2040js: run `sudo apt-get install nodejs npm` \
         (or your system's Node.js 18 or later), then the command again"
            .to_string(),
    )
}

/// A C++ compiler (`c++`), which libFuzzer's build needs: g++ installed with apt-get where
/// this runs as root; otherwise the command, as an error.
pub fn cxx() -> Result<(), String> {
    if on_path("c++").is_some() {
        return Ok(());
    }
    let root_with_apt = is_root() && on_path("apt-get").is_some();
    if root_with_apt && apt_install(&["g++"]) && on_path("c++").is_some() {
        return Ok(());
    }
    Err(
        "a C++ compiler is needed to build libFuzzer: run `sudo apt-get install g++` \
         (or your system's C++ compiler as `c++`), then the command again"
            .to_string(),
    )
}

/// `program` on the PATH (or in ~/.cargo/bin).
pub fn on_path(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    let mut dirs: Vec<PathBuf> = std::env::split_paths(&path).collect();
    if let Some(home) = std::env::var_os("HOME") {
        dirs.push(PathBuf::from(home).join(".cargo/bin"));
    }
    dirs.into_iter()
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// `qemu-system-arm`, or a message saying how to install it.
pub fn qemu_binary() -> Result<PathBuf, String> {
    on_path("qemu-system-arm").ok_or_else(|| {
        "qemu-system-arm is not installed: run `sudo apt-get install qemu-system-arm` \
         (Debian/Ubuntu), or `bash .ci/run` which installs it"
            .to_string()
    })
}
