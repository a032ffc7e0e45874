//! ArduPilot SITL (Rover or Plane) as a child process: found, started in its own working
//! directory under `target/ardupilot/`, its SERIAL0 (TCP 5760 + 10 x instance) connected, killed
//! on drop.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// Which ArduPilot vehicle: its binary, SITL model and default parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    Rover,
    Plane,
}

impl Frame {
    /// The binary's name, as the team's machines have it in `../shared/ardupilot/`.
    pub fn binary(self) -> &'static str {
        match self {
            Frame::Rover => "ardurover",
            Frame::Plane => "arduplane",
        }
    }

    /// The environment variable that names the binary.
    pub fn variable(self) -> &'static str {
        match self {
            Frame::Rover => "TWOCARS_ARDUROVER",
            Frame::Plane => "TWOCARS_ARDUPLANE",
        }
    }

    fn model(self) -> &'static str {
        match self {
            Frame::Rover => "rover",
            Frame::Plane => "plane",
        }
    }
}

/// The SITL binary for `frame`: `explicit`, else its variable ([`Frame::variable`]), else
/// `../shared/ardupilot/<binary>` from the workspace; `None` where none exists.
pub fn find(frame: Frame, explicit: Option<&Path>) -> Option<PathBuf> {
    let shared = format!("../shared/ardupilot/{}", frame.binary());
    let candidates = [
        explicit.map(Path::to_path_buf),
        std::env::var_os(frame.variable()).map(PathBuf::from),
        Some(crate::util::workspace::root().join(shared)),
    ];
    candidates.into_iter().flatten().find(|p| p.is_file())
}

/// A running SITL instance and its SERIAL0 link.
pub struct Sitl {
    child: Child,
}

impl Drop for Sitl {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The default parameters beside the binary (`rover.parm`, `plane.parm`), where present.
fn defaults(binary: &Path, frame: Frame) -> Option<PathBuf> {
    let p = binary.parent()?.join(format!("{}.parm", frame.model()));
    p.is_file().then_some(p)
}

/// How a SITL instance starts: its vehicle, its instance number (ports shifted by 10 N), home
/// (lat, lon in degrees) and heading (degrees clockwise from north), and how much faster than
/// the wall clock it runs.
#[derive(Clone, Copy, Debug)]
pub struct Launch {
    pub frame: Frame,
    pub instance: u16,
    pub home: (f64, f64),
    pub heading: f64,
    pub speedup: u32,
}

impl Sitl {
    /// Starts `binary` as `launch` says, with wiped parameters, and connects to its SERIAL0
    /// (SITL waits for that client before it runs).
    pub fn start(binary: &Path, launch: Launch) -> Result<(Sitl, TcpStream), String> {
        let instance = launch.instance;
        let dir =
            crate::util::workspace::target_dir().join(format!("ardupilot/instance{instance}"));
        // A fresh directory: SITL keeps a 16 MB dataflash log of every run in it.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let (lat, lon) = launch.home;
        let mut command = Command::new(binary);
        command
            .current_dir(&dir)
            .args(["--model", launch.frame.model(), "-w"])
            .arg(format!("--speedup={}", launch.speedup))
            .arg(format!("-I{instance}"))
            .arg(format!("--home={lat},{lon},584,{}", launch.heading))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        if let Some(parm) = defaults(binary, launch.frame) {
            command.arg("--defaults").arg(parm);
        }
        let child = command
            .spawn()
            .map_err(|e| format!("{}: {e}", binary.display()))?;
        let sitl = Sitl { child };
        let port = 5760 + 10 * instance;
        let stream = crate::harness::firmware::emulator::connect(port, "ArduPilot SITL")?;
        Ok((sitl, stream))
    }
}

/// SITL's SERIAL1 (TCP 5762 + 10 x instance): the companion computer's link, where ArduPilot,
/// once it has a key, signs what it sends and refuses what is unsigned.
pub fn connect_serial1(instance: u16) -> Result<TcpStream, String> {
    crate::harness::firmware::emulator::connect(5762 + 10 * instance, "ArduPilot SITL's SERIAL1")
}

/// Gives ArduPilot `key` with SETUP_SIGNING on `serial0` once its first heartbeat has come
/// there (before, the message may land before its MAVLink handler runs); the key's timestamp is
/// the wall clock's.
pub fn setup_signing(serial0: &mut TcpStream, key: [u8; 32]) -> Result<(), String> {
    use mavlink::dialects::common::{MavMessage, SETUP_SIGNING_DATA};
    use std::io::{Read, Write};
    serial0
        .set_read_timeout(Some(std::time::Duration::from_millis(200)))
        .map_err(|e| e.to_string())?;
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
    let mut splitter = crate::harness::autopilot::router::Splitter::default();
    let mut buf = [0u8; 4096];
    loop {
        if std::time::Instant::now() > deadline {
            return Err("no heartbeat from ArduPilot on SERIAL0 in 20 s".to_string());
        }
        if let Ok(n) = serial0.read(&mut buf) {
            splitter.push(buf.get(..n).unwrap_or(&[]));
        }
        let mut beat = false;
        while let Some(frame) = splitter.next_frame() {
            beat |= matches!(frame.message(), Some(MavMessage::HEARTBEAT(_)));
        }
        if beat {
            break;
        }
    }
    let message = SETUP_SIGNING_DATA {
        initial_timestamp: crate::image::signing::clock_now(),
        target_system: 1,
        target_component: 1,
        secret_key: key,
    };
    let mut bytes = Vec::new();
    twocars::mavlink::Outbox::default().send_as(
        crate::harness::autopilot::router::GCS,
        &message,
        &mut |f| bytes.extend_from_slice(f),
    );
    serial0
        .write_all(&bytes)
        .map_err(|e| format!("SETUP_SIGNING: {e}"))
}
