//! Where the workspace is, and the command-line values the commands share.

use std::path::{Path, PathBuf};

/// Workspace root (xtask lives one level below).
pub fn root() -> PathBuf {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    manifest
        .parent()
        .map_or(manifest.clone(), Path::to_path_buf)
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
