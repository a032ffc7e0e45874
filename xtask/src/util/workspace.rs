//! Where the workspace is, and the command-line values the commands share.

use std::path::{Path, PathBuf};

/// Workspace root (xtask lives one level below).
pub fn root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest
        .parent()
        .map_or(manifest.clone(), Path::to_path_buf)
}

/// Cargo's target directory for this workspace, as `cargo metadata` reports it (so that
/// `CARGO_TARGET_DIR` and `build.target-dir` hold); `<root>/target` where cargo cannot say.
pub fn target_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
        std::process::Command::new(cargo)
            .current_dir(root())
            .args(["metadata", "--no-deps", "--format-version", "1"])
            .stderr(std::process::Stdio::null())
            .output()
            .ok()
            .and_then(|out| String::from_utf8(out.stdout).ok())
            .and_then(|json| json_string(&json, "target_directory"))
            .map_or_else(|| root().join("target"), PathBuf::from)
    })
    .clone()
}

/// The string value of `key` in a JSON object's text (escapes of `\\` and `\"` undone).
fn json_string(json: &str, key: &str) -> Option<String> {
    let start = json.find(&format!("\"{key}\":\""))? + key.len() + 4;
    let mut value = String::new();
    let mut chars = json[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '"' => return Some(value),
            '\\' => value.push(chars.next()?),
            c => value.push(c),
        }
    }
    None
}

/// `N` comma-separated numbers.
pub(crate) fn numbers<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let v: Vec<f64> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{text}: {e}"))?;
    <[f64; N]>::try_from(v).map_err(|_| format!("{text}: expected {N} comma-separated numbers"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_directory_is_read_from_cargo_metadata() {
        let json = r#"{"packages":[],"target_directory":"/tmp/a \"b\"\\c","version":1}"#;
        assert_eq!(
            json_string(json, "target_directory").as_deref(),
            Some(r#"/tmp/a "b"\c"#)
        );
        assert_eq!(json_string(json, "workspace_root"), None);
    }
}
