//! QEMU and its tools: the binary, `defmt-print` for the logs, and the command that runs an
//! image with its UART on a loopback TCP port (QEMU the server, the host the client).

use std::path::{Path, PathBuf};

use crate::setup::{on_path, qemu_binary};
use std::process::{Command, Stdio};

/// `defmt-print`, installed with `cargo install` when missing; `None` if that fails (logs are
/// then not shown).
pub fn defmt_print() -> Option<PathBuf> {
    if let Some(p) = on_path("defmt-print") {
        return Some(p);
    }
    eprintln!("xtask: installing defmt-print (cargo install defmt-print --locked) to decode logs");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let ok = Command::new(cargo)
        .args(["install", "defmt-print", "--version", "1.2.0", "--locked"])
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("xtask: could not install defmt-print; firmware logs will not be decoded");
    }
    on_path("defmt-print")
}

/// QEMU with machine options `machine` running `elf`, its first serial port a TCP server on
/// 127.0.0.1:`port` that holds the guest until one client connects; its stdout (the defmt log
/// stream over semihosting) piped.
pub fn command(machine: &[&str], elf: &Path, port: u16) -> Result<Command, String> {
    let mut command = Command::new(qemu_binary()?);
    command
        .args(machine)
        .args(["-display", "none", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .arg("-serial")
        // nodelay: QEMU writes a reply byte by byte; with Nagle's algorithm against the
        // client's delayed ACK every round trip cost 44 ms (measured), with it about 2 ms.
        .arg(format!("tcp:127.0.0.1:{port},server=on,wait=on,nodelay=on"))
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .stdout(Stdio::piped());
    Ok(command)
}
