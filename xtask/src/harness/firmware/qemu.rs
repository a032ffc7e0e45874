//! QEMU: the binary, and the command that runs an
//! image with its UART on a loopback TCP port (QEMU the server, the host the client).

use std::path::Path;

use crate::util::setup::qemu_binary;
use std::process::{Command, Stdio};

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
