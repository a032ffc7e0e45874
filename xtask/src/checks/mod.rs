//! `cargo xtask test`: the suite's named steps ([`suite`]) and the checks they run: the
//! source's imports, the firmware in its emulators, the package as a user gets it.

pub mod docs;
pub mod firmware;
pub mod imports;
pub mod layers;
pub mod package;
pub mod sitl;
pub mod suite;
pub mod tables;

use crate::util::workspace::root;

/// Named tests' outcomes, each printed as `cargo test` prints its tests, and counted.
#[derive(Debug, Default)]
pub struct Tally {
    pub passed: u64,
    pub failed: u64,
}

impl Tally {
    /// Prints and counts the outcome of the test `name`: Ok with what it saw, or Err with why
    /// it failed.
    pub fn record(&mut self, name: &str, outcome: Result<String, String>) {
        match outcome {
            Ok(detail) => {
                println!("test {name} ... ok ({detail})");
                self.passed += 1;
            }
            Err(e) => {
                println!("test {name} ... FAILED: {e}");
                self.failed += 1;
            }
        }
    }
}

/// The crates whose files must not import each other in a circle: their roots.
const CRATES: [&str; 6] = [
    "src/lib.rs",
    "xtask/src/main.rs",
    "sim/src/lib.rs",
    "bench/src/lib.rs",
    "hji/src/lib.rs",
    "companion/src/main.rs",
];

/// Prints every import cycle between the files of each crate, with the names that tie it, and
/// every import of xtask up its layers; (checks passed, checks failed).
pub fn imports_point_down() -> (u64, u64) {
    let (mut passed, mut failed) = (0, 0);
    for crate_root in CRATES {
        let edges = imports::graph(&root().join(crate_root));
        let cycles = imports::cycles(&edges);
        let files = edges.len();
        if cycles.is_empty() {
            println!("imports: {crate_root}: {files} files, no cycle ... ok");
            passed += 1;
            continue;
        }
        failed += 1;
        eprintln!("imports: {crate_root}: {} cycle(s)", cycles.len());
        for set in cycles {
            eprintln!("  a cycle of {} files:", set.len());
            for from in &set {
                for (to, names) in &edges[from] {
                    if set.contains(to) {
                        let names: Vec<&str> = names.iter().map(String::as_str).collect();
                        eprintln!(
                            "    {} -> {}: {}",
                            relative(from),
                            relative(to),
                            names.join(", ")
                        );
                    }
                }
            }
        }
    }
    let (layers_passed, layers_failed) = xtask_layers();
    (passed + layers_passed, failed + layers_failed)
}

/// Prints each import of xtask that points up its layers ([`layers::LAYERS`]); (1, 0) when
/// there is none, else (0, 1).
fn xtask_layers() -> (u64, u64) {
    let src = root().join("xtask/src");
    let upward = layers::upward(&src, &imports::graph(&src.join("main.rs")));
    if upward.is_empty() {
        println!("imports: xtask/src: {} ... ok", layers::LAYERS.join(" > "));
        return (1, 0);
    }
    eprintln!("imports: xtask/src: {} import(s) up a layer", upward.len());
    for (from, to) in &upward {
        eprintln!("    {} -> {}", relative(from), relative(to));
    }
    (0, 1)
}

fn relative(path: &std::path::Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}
