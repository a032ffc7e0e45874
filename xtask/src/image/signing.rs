//! The MAVLink signing key an image is built with and its peers sign with, passed explicitly:
//! to `cargo build` as the build script's `TWOCARS_MAVLINK_KEY`, to pymavlink and the router
//! as its bytes.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use twocars::mavlink::signing::{parse_key, timestamp_from_unix_us, KEY_LEN};

/// A key file, read and checked, with the signing clock's start for the images built with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SigningKey {
    path: PathBuf,
    key: [u8; KEY_LEN],
    /// The images' signing clock at start (10 us since 2015-01-01): now, as the key is read; a
    /// peer refuses a new stream more than a minute behind its own clock, and the unit has no
    /// real-time clock of its own.
    start: u64,
}

impl SigningKey {
    /// The key in the file at `path` (32 bytes or 64 hexadecimal digits).
    pub fn read(path: &Path) -> Result<SigningKey, String> {
        let path = std::fs::canonicalize(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let bytes = std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let key = parse_key(&bytes).ok_or(format!(
            "{}: a key file holds 32 bytes or 64 hexadecimal digits",
            path.display()
        ))?;
        Ok(SigningKey {
            path,
            key,
            start: clock_now(),
        })
    }

    /// The key a command's `--signing-key` names, if it names one; where the file does not
    /// hold a key, Err, the reason printed after `command`.
    pub fn given(path: Option<&Path>, command: &str) -> Result<Option<SigningKey>, ()> {
        path.map(SigningKey::read).transpose().map_err(|e| {
            eprintln!("{command}: {e}");
        })
    }

    /// The tests' fixed key, written to `target/mavlink-test.key`.
    pub fn for_tests() -> Result<SigningKey, String> {
        let path = crate::util::workspace::target_dir().join("mavlink-test.key");
        let hex: String = (0..32u8)
            .map(|b| format!("{:02x}", b.wrapping_mul(37)))
            .collect();
        std::fs::write(&path, hex).map_err(|e| format!("{}: {e}", path.display()))?;
        SigningKey::read(&path)
    }

    /// The key file, as read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The key's bytes.
    pub fn bytes(&self) -> [u8; KEY_LEN] {
        self.key
    }

    /// The key as 64 hexadecimal digits (pymavlink's argument).
    pub fn hex(&self) -> String {
        self.key.iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The build script's variables for an image that signs with this key.
    pub fn build_env(&self) -> [(&'static str, OsString); 2] {
        [
            ("TWOCARS_MAVLINK_KEY", self.path.clone().into_os_string()),
            ("TWOCARS_MAVLINK_KEY_TIME", self.start.to_string().into()),
        ]
    }
}

/// The wall clock on MAVLink's signing scale: 10 us since 2015-01-01T00:00:00Z.
pub fn clock_now() -> u64 {
    let unix_us = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros() as u64);
    timestamp_from_unix_us(unix_us)
}
