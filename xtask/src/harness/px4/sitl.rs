//! PX4 SITL with its SIH simulator as a child process: found, started in its own working
//! directory under `target/px4/`, its offboard (API) MAVLink link joined over UDP, killed on
//! drop.

use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// Where `px4` is looked for when no path is given: beside the repository, as the team's
/// machines have it (its `etc/` beside `bin/`).
const SHARED: &str = "../shared/px4/bin/px4";

/// The PX4 binary: `explicit`, else `../shared/px4/bin/px4` from the workspace; `None` where
/// neither exists.
pub fn find(explicit: Option<&Path>) -> Option<PathBuf> {
    let candidates = [
        explicit.map(Path::to_path_buf),
        Some(crate::util::workspace::root().join(SHARED)),
    ];
    candidates.into_iter().flatten().find(|p| p.is_file())
}

/// PX4's start-up scripts run its commands as `px4-<command>`, each the `px4` binary under
/// another name, found on PATH; a copy of the build may hold them as plain files (a read-only
/// tree, its symbolic links flattened). In `dir`/bin: a link to `binary` for each such name
/// beside it, and its `px4-alias.sh`; that directory.
fn command_aliases(binary: &Path, dir: &Path) -> Result<PathBuf, String> {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).map_err(|e| format!("{}: {e}", bin.display()))?;
    let beside = binary.parent().ok_or("the px4 binary has no directory")?;
    let entries = std::fs::read_dir(beside).map_err(|e| format!("{}: {e}", beside.display()))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(text) = name.to_str() else { continue };
        let target = bin.join(text);
        if text == "px4-alias.sh" {
            std::fs::copy(entry.path(), &target).map_err(|e| e.to_string())?;
        } else if text.starts_with("px4-") {
            std::os::unix::fs::symlink(binary, &target).map_err(|e| e.to_string())?;
        }
    }
    Ok(bin)
}

/// A running PX4 instance.
pub struct Px4 {
    child: Child,
}

impl Drop for Px4 {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The offboard link's ports for `instance`: PX4 sends to 14540 + instance from 14580 +
/// instance (its `px4-rc.mavlink`).
pub fn api_ports(instance: u16) -> (u16, u16) {
    (14540 + instance, 14580 + instance)
}

impl Px4 {
    /// Starts `binary` as instance `instance` of the SIH vehicle `model`
    /// (`sihsim_rover_ackermann`, `sihsim_airplane`) at `home` (lat, lon in degrees), with its
    /// start-up scripts from `etc/` beside `bin/`; and binds the offboard link's port, connected
    /// to PX4's. Its console goes to `target/px4/instance<N>/console.log`.
    pub fn start(
        binary: &Path,
        model: &str,
        instance: u16,
        home: (f64, f64),
    ) -> Result<(Px4, UdpSocket), String> {
        let etc = binary
            .parent()
            .and_then(Path::parent)
            .map(|p| p.join("etc"))
            .filter(|p| p.is_dir())
            .ok_or_else(|| format!("no etc/ beside {}", binary.display()))?;
        let dir = crate::util::workspace::target_dir().join(format!("px4/instance{instance}"));
        // A fresh directory: PX4 keeps its parameters, dataman and logs there.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let (ours, theirs) = api_ports(instance);
        let socket = UdpSocket::bind(("127.0.0.1", ours))
            .map_err(|e| format!("UDP {ours} for PX4's offboard link: {e}"))?;
        socket
            .connect(("127.0.0.1", theirs))
            .map_err(|e| e.to_string())?;
        let aliases = command_aliases(binary, &dir)?;
        let path = match std::env::var_os("PATH") {
            Some(path) => {
                let mut joined = aliases.into_os_string();
                joined.push(":");
                joined.push(path);
                joined
            }
            None => aliases.into_os_string(),
        };
        let log = std::fs::File::create(dir.join("console.log")).map_err(|e| e.to_string())?;
        let child = Command::new(binary)
            .current_dir(&dir)
            .arg("-d")
            .arg(&etc)
            .arg("-i")
            .arg(instance.to_string())
            .env("PX4_SIM_MODEL", model)
            .env("PX4_SIMULATOR", "sihsim")
            .env("PX4_HOME_LAT", home.0.to_string())
            .env("PX4_HOME_LON", home.1.to_string())
            .env("PX4_HOME_ALT", "584")
            .env("PATH", path)
            .stdin(Stdio::null())
            .stdout(log.try_clone().map_err(|e| e.to_string())?)
            .stderr(log)
            .spawn()
            .map_err(|e| format!("{}: {e}", binary.display()))?;
        Ok((Px4 { child }, socket))
    }
}
