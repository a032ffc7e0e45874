//! ArduPilot Rover SITL as a child process: found, started in its own working directory under
//! `target/ardupilot/`, its SERIAL0 (TCP 5760 + 10 x instance) connected, killed on drop.

use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// Where `ardurover` is looked for when no path is given: beside the repository, as the team's
/// machines have it.
const SHARED: &str = "../shared/ardupilot/ardurover";

/// The SITL binary: `explicit`, else `TWOCARS_ARDUROVER`, else `../shared/ardupilot/ardurover`
/// from the workspace; `None` where none exists.
pub fn find(explicit: Option<&Path>) -> Option<PathBuf> {
    let candidates = [
        explicit.map(Path::to_path_buf),
        std::env::var_os("TWOCARS_ARDUROVER").map(PathBuf::from),
        Some(crate::workspace::root().join(SHARED)),
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

/// The default parameters beside the binary (`rover.parm`), where present.
fn defaults(binary: &Path) -> Option<PathBuf> {
    let p = binary.parent()?.join("rover.parm");
    p.is_file().then_some(p)
}

impl Sitl {
    /// Starts `binary` as instance `instance` with wiped parameters at `home` (lat, lon in
    /// degrees), and connects to its SERIAL0 (SITL waits for that client before it runs).
    pub fn start(
        binary: &Path,
        instance: u16,
        home: (f64, f64),
    ) -> Result<(Sitl, TcpStream), String> {
        let dir = crate::workspace::target_dir().join(format!("ardupilot/instance{instance}"));
        // A fresh directory: SITL keeps a 16 MB dataflash log of every run in it.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut command = Command::new(binary);
        command
            .current_dir(&dir)
            .args(["--model", "rover", "--speedup", "1", "-w"])
            .arg(format!("-I{instance}"))
            .arg(format!("--home={},{},584,0", home.0, home.1))
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null());
        if let Some(parm) = defaults(binary) {
            command.arg("--defaults").arg(parm);
        }
        let child = command
            .spawn()
            .map_err(|e| format!("{}: {e}", binary.display()))?;
        let sitl = Sitl { child };
        let port = 5760 + 10 * instance;
        let stream = crate::firmware::emulator::connect(port, "ArduPilot SITL")?;
        Ok((sitl, stream))
    }
}
