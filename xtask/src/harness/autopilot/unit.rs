//! The unit beside the autopilot: the `twocars-qemu-mavlink` image in QEMU, or the
//! `twocars-companion` binary on the host (`--companion`), which connects to the router over
//! TCP as a companion computer's program would to a MAVLink router.

use std::net::{TcpListener, TcpStream};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::harness::firmware::emulator::{self, Launched};
use crate::image::signing::SigningKey;
use crate::image::{self, Image};

/// The unit's process, stopped on drop: the emulator, or the companion.
pub struct Unit {
    _emulator: Option<Launched>,
    companion: Option<Child>,
}

impl Drop for Unit {
    fn drop(&mut self) {
        if let Some(child) = self.companion.as_mut() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// Starts the unit and its link: the QEMU image, or the companion binary, each signing with
/// `key` where given.
pub fn start(companion: bool, key: Option<&SigningKey>) -> Result<(Unit, TcpStream), String> {
    if !companion {
        let (elf, _) = image::build_checked(Image::QemuMavlink, key)?;
        let launched = emulator::launch(&elf, Image::QemuMavlink, false)?;
        let link = emulator::connect(launched.port, "the unit")?;
        let unit = Unit {
            _emulator: Some(launched),
            companion: None,
        };
        return Ok((unit, link));
    }
    start_companion(&build_companion()?, key)
}

/// Starts the companion `binary` (built by [`build_companion`]) and its link, signing with
/// `key` where given.
pub fn start_companion(
    binary: &std::path::Path,
    key: Option<&SigningKey>,
) -> Result<(Unit, TcpStream), String> {
    let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let port = listener.local_addr().map_err(|e| e.to_string())?.port();
    let mut command = Command::new(binary);
    command
        .arg("--tcp")
        .arg(format!("127.0.0.1:{port}"))
        .stdout(Stdio::null());
    if let Some(key) = key {
        command.arg("--signing-key").arg(key.path());
    }
    let child = command
        .spawn()
        .map_err(|e| format!("{}: {e}", binary.display()))?;
    let unit = Unit {
        _emulator: None,
        companion: Some(child),
    };
    let link = accept(&listener, Duration::from_secs(20))?;
    Ok((unit, link))
}

/// `cargo build --release -p twocars-companion`; the binary's path.
pub fn build_companion() -> Result<std::path::PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let status = Command::new(cargo)
        .current_dir(crate::util::workspace::root())
        .args(["build", "--release", "-p", "twocars-companion"])
        .status()
        .map_err(|e| e.to_string())?;
    if !status.success() {
        return Err("cargo build -p twocars-companion failed".to_string());
    }
    Ok(crate::util::workspace::target_dir().join("release/twocars-companion"))
}

/// The first connection to `listener` within `wait`.
fn accept(listener: &TcpListener, wait: Duration) -> Result<TcpStream, String> {
    listener.set_nonblocking(true).map_err(|e| e.to_string())?;
    let deadline = Instant::now() + wait;
    loop {
        match listener.accept() {
            Ok((stream, _)) => return Ok(stream),
            Err(_) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => return Err(format!("the companion never connected: {e}")),
        }
    }
}
