//! rp2040js, Wokwi's RP2040 emulator (the npm registry), for the Raspberry Pi Pico image:
//! installed with npm into `target/rp2040js/` on first use, and run by our harness
//! (xtask/rp2040js_harness.mjs) with UART0 on a loopback TCP port.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The rp2040js release the harness is written against.
pub const VERSION: &str = "1.4.1";

fn dir() -> PathBuf {
    crate::util::workspace::target_dir().join("rp2040js")
}

fn harness() -> PathBuf {
    crate::util::workspace::root().join("xtask/rp2040js_harness.mjs")
}

/// Whether `dir` holds rp2040js [`VERSION`] (its manifest, as npm writes it, says so).
fn has_version(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join("node_modules/rp2040js/package.json"))
        .is_ok_and(|m| m.contains(&format!("\"version\": \"{VERSION}\"")))
}

/// The directory holding rp2040js [`VERSION`], installed with npm there when missing (Node.js
/// and npm first, with apt-get where this runs as root).
pub fn installed() -> Result<PathBuf, String> {
    let dir = dir();
    if has_version(&dir) {
        return Ok(dir);
    }
    crate::util::setup::node()?;
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    eprintln!(
        "xtask: installing rp2040js {VERSION} into {} (first use)",
        dir.display()
    );
    let ok = Command::new("npm")
        .args(["install", "--no-audit", "--no-fund", "--silent", "--prefix"])
        .arg(&dir)
        .arg(format!("rp2040js@{VERSION}"))
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if ok && has_version(&dir) {
        Ok(dir)
    } else {
        Err(format!(
            "could not install rp2040js {VERSION} into {} (is the npm registry reachable?)",
            dir.display()
        ))
    }
}

/// Node.js running the harness with `elf`, UART0 a TCP server on 127.0.0.1:`port`; its stdout
/// (the cycle count at the end) piped.
pub fn command(elf: &Path, port: u16) -> Result<Command, String> {
    let dir = installed()?;
    let mut command = Command::new("node");
    command
        .arg(harness())
        .arg(dir)
        .arg(elf)
        .arg(port.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped());
    Ok(command)
}
