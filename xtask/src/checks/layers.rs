//! xtask's layers: each file imports only from its own layer or the ones below, so a command's
//! work never leaks into what the others share. From the top: `main.rs`, `commands/`,
//! `checks/`, `harness/`, `image/`, `util/`.

use std::path::{Path, PathBuf};

use super::imports::Edges;

/// xtask's layer folders under `xtask/src`, from the top; `main.rs` stands above them all.
pub const LAYERS: [&str; 5] = ["commands", "checks", "harness", "image", "util"];

/// A file's height: `main.rs` is the highest, then each layer in [`LAYERS`]' order; `None` for a
/// file on no layer.
fn height(src: &Path, file: &Path) -> Option<usize> {
    let relative = file.strip_prefix(src).ok()?;
    if relative == Path::new("main.rs") {
        return Some(LAYERS.len());
    }
    let first = relative.components().next()?.as_os_str().to_str()?;
    let at = LAYERS.iter().position(|layer| *layer == first)?;
    Some(LAYERS.len() - 1 - at)
}

/// Every import that points up a layer, and every file on no layer (as an import from and to
/// itself), in the crate whose files are under `src`.
pub fn upward(src: &Path, edges: &Edges) -> Vec<(PathBuf, PathBuf)> {
    let mut found = Vec::new();
    for (from, targets) in edges {
        let Some(low) = height(src, from) else {
            found.push((from.clone(), from.clone()));
            continue;
        };
        for to in targets.keys() {
            if height(src, to).is_some_and(|high| high > low) {
                found.push((from.clone(), to.clone()));
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn edges(pairs: &[(&str, &str)]) -> Edges {
        let mut edges = Edges::new();
        for (from, to) in pairs {
            let names = BTreeMap::from([(PathBuf::from(to), Default::default())]);
            edges.entry(PathBuf::from(from)).or_default().extend(names);
        }
        edges
    }

    #[test]
    fn an_import_down_or_across_passes_and_one_up_is_named() {
        let src = Path::new("x");
        let down = edges(&[
            ("x/main.rs", "x/commands/run.rs"),
            ("x/commands/run.rs", "x/commands/csv.rs"),
            ("x/checks/suite.rs", "x/harness/fuzz.rs"),
            ("x/harness/px4/mod.rs", "x/util/setup.rs"),
        ]);
        assert!(upward(src, &down).is_empty());
        let up = edges(&[("x/harness/fuzz.rs", "x/commands/fuzz.rs")]);
        assert_eq!(
            upward(src, &up),
            [(
                PathBuf::from("x/harness/fuzz.rs"),
                PathBuf::from("x/commands/fuzz.rs")
            )]
        );
        let stray = edges(&[("x/stray.rs", "x/util/setup.rs")]);
        assert_eq!(upward(src, &stray).len(), 1);
    }
}
