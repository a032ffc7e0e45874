//! `cargo xtask test`: the suite's named steps ([`suite`]) and the checks they run: the
//! source's imports, the firmware in its emulators, the package as a user gets it.

pub mod firmware;
pub mod imports;
pub mod package;
pub mod sitl;
pub mod suite;
pub mod tables;

use crate::workspace::root;

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
    "host-tests/src/lib.rs",
    "bench/src/lib.rs",
    "hji/src/lib.rs",
    "companion/src/main.rs",
];

/// Prints every import cycle between the files of each crate, with the names that tie it;
/// (crates without a cycle, crates with one).
pub fn import_cycles() -> (u64, u64) {
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
    (passed, failed)
}

fn relative(path: &std::path::Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}
