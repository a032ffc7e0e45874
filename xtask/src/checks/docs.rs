//! The docs step of `cargo xtask test`: the crate's rustdoc without a warning with the default
//! features and with docs.rs's (Cargo.toml's `package.metadata.docs.rs`, `--cfg docsrs`), no
//! item of the core hidden from it, README's feature table the one the crate's front page
//! includes (docs/features.md), and the count of its public items in each.

use std::path::Path;
use std::process::Command;

use crate::util::workspace::{root, target_dir};

/// The features docs.rs builds the crate with, comma-separated.
fn docs_rs_features() -> Result<String, String> {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).map_err(|e| e.to_string())?;
    let table: toml::Table = manifest.parse().map_err(|e| format!("Cargo.toml: {e}"))?;
    let features = table
        .get("package")
        .and_then(|p| p.get("metadata"))
        .and_then(|m| m.get("docs"))
        .and_then(|d| d.get("rs"))
        .and_then(|r| r.get("features"))
        .and_then(toml::Value::as_array)
        .ok_or("Cargo.toml has no package.metadata.docs.rs.features")?;
    let names: Vec<&str> = features.iter().filter_map(toml::Value::as_str).collect();
    Ok(names.join(","))
}

/// The items rustdoc lists on the crate's "all items" page (types, traits, functions,
/// constants, macros; not methods or fields).
fn public_items() -> Result<usize, String> {
    let page = target_dir().join("doc/twocars/all.html");
    let html = std::fs::read_to_string(&page).map_err(|e| format!("{}: {e}", page.display()))?;
    Ok(html.matches("<li><a href=\"").count())
}

/// Each `#[doc(hidden)]` under `dir`, as `file:line`.
fn hidden(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return found;
    };
    for path in entries.filter_map(Result::ok).map(|e| e.path()) {
        if path.is_dir() {
            found.extend(hidden(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            for (i, line) in text.lines().enumerate() {
                if line.trim_start().starts_with("#[doc(hidden)]") {
                    found.push(format!("{}:{}", path.display(), i + 1));
                }
            }
        }
    }
    found
}

/// The lines of `text`'s table under the heading `## Features`.
fn features_table(text: &str) -> Vec<&str> {
    text.lines()
        .skip_while(|line| *line != "## Features")
        .skip(1)
        .take_while(|line| !line.starts_with("## "))
        .filter(|line| line.starts_with('|'))
        .collect()
}

/// Whether README's feature table is the one the crate's docs include (docs/features.md).
fn features_agree() -> Result<(), String> {
    let read =
        |name: &str| std::fs::read_to_string(root().join(name)).map_err(|e| format!("{name}: {e}"));
    let (readme, docs) = (read("README.md")?, read("docs/features.md")?);
    let (ours, theirs) = (features_table(&readme), features_table(&docs));
    match !ours.is_empty() && ours == theirs {
        true => Ok(()),
        false => Err("README.md's feature table differs from docs/features.md's".to_string()),
    }
}

/// `cargo doc` of the core with `features` (none: the defaults), warnings denied; its public
/// items.
fn document(cargo: &str, features: Option<&str>) -> Result<usize, String> {
    let mut command = Command::new(cargo);
    command.args(["doc", "--no-deps", "-p", "twocars"]);
    let mut flags = String::from("-D warnings");
    if let Some(features) = features {
        command.args(["--features", features]);
        // docs.rs's own flag: the `doc_cfg` marks on gated items (a nightly feature, so
        // RUSTC_BOOTSTRAP on the pinned stable toolchain).
        flags.push_str(" --cfg docsrs");
        command.env("RUSTC_BOOTSTRAP", "1");
    }
    let status = command
        .env("RUSTDOCFLAGS", flags)
        .status()
        .map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("cargo doc failed ({status})"));
    }
    public_items()
}

/// The core's docs with the default and with docs.rs's features; false on a warning or a
/// hidden item.
pub fn core(cargo: &str) -> bool {
    let hidden = hidden(&root().join("src"));
    for at in &hidden {
        eprintln!("== xtask test: {at}: #[doc(hidden)] (a public item is documented or private)");
    }
    let features = match docs_rs_features() {
        Ok(features) => features,
        Err(e) => {
            eprintln!("== xtask test: {e}");
            return false;
        }
    };
    if let Err(e) = features_agree() {
        eprintln!("== xtask test: {e}");
        return false;
    }
    let counted = document(cargo, None)
        .and_then(|default| document(cargo, Some(&features)).map(|all| (default, all)));
    match counted {
        Ok((default, all)) => {
            println!(
                "== xtask test: twocars's public items: {default} with the default features, {all} with docs.rs's ({features}); {} hidden",
                hidden.len()
            );
            hidden.is_empty()
        }
        Err(e) => {
            eprintln!("== xtask test: docs: {e}");
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::features_table;

    #[test]
    fn the_feature_table_is_the_rows_under_its_heading() {
        let text = "# A\n| not |\n## Features\n\nintro\n| f | g |\n|---|---|\n## Next\n| x |\n";
        assert_eq!(features_table(text), ["| f | g |", "|---|---|"]);
        assert!(features_table("| f |\n").is_empty());
    }
}
