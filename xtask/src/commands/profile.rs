//! `cargo xtask profile`: where the instructions of one law evaluation go, function by function,
//! on the bench images (M4F f32 and M0 fixed point). QEMU runs the image one instruction per
//! translation block (`-singlestep -d exec,nochain`) and logs every executed instruction with its
//! function; the instructions logged between the bench's call of `evaluate` and the return to its
//! `main` are counted per function (callees included under their own names) and divided by the
//! number of calls. Deterministic, exact to the instruction; a diagnosis, not the bench figure
//! (that is `cargo xtask bench`, which subtracts the call overhead).

use std::collections::HashMap;
use std::process::Stdio;

use crate::harness::bench::image::{self, Cpu};

/// Instructions per call of `evaluate`, per function, most first.
pub struct Profile {
    /// Calls of the timed function seen.
    pub calls: u64,
    /// (function, instructions per call).
    pub functions: Vec<(String, f64)>,
}

/// The function name QEMU's exec log gives at the end of a line, demangled without its hash.
fn function(line: &str) -> Option<String> {
    let name = line.rsplit(']').next()?.trim();
    (!name.is_empty()).then(|| format!("{:#}", rustc_demangle::demangle(name)))
}

/// Counts the instructions of each call of the bench image `bin`'s `evaluate` in QEMU's exec
/// log: from its entry to the return into the harness that calls it.
pub fn count(log: &str, bin: &str) -> Profile {
    let evaluate = format!("{bin}::evaluate");
    let mut per_function: HashMap<String, u64> = HashMap::new();
    let (mut inside, mut calls) = (false, 0u64);
    for name in log.lines().filter_map(function) {
        if name == evaluate && !inside {
            inside = true;
            calls += 1;
        } else if name.starts_with("twocars_bench::target::law::run") {
            inside = false;
        }
        if inside {
            *per_function.entry(name).or_default() += 1;
        }
    }
    let mut functions: Vec<(String, f64)> = per_function
        .into_iter()
        .map(|(name, n)| (name, n as f64 / calls.max(1) as f64))
        .collect();
    functions.sort_by(|a, b| b.1.total_cmp(&a.1));
    Profile { calls, functions }
}

/// Builds the bench image, runs it single-stepped with the exec log, and profiles it.
pub fn profile(cpu: Cpu, bin: &str) -> Result<Profile, String> {
    let elf = image::build(cpu, bin)?;
    let log = crate::util::workspace::target_dir().join("profile-exec.log");
    let status = cpu
        .qemu(&elf)?
        .args(["-singlestep", "-d", "exec,nochain", "-D"])
        .arg(&log)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .map_err(|e| e.to_string())?;
    if !status.success() {
        return Err(format!("profiling run exited with {status}"));
    }
    let text = std::fs::read_to_string(&log).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_file(&log);
    Ok(count(&text, bin))
}

/// `cargo xtask profile`.
pub fn command() -> i32 {
    let mut code = 0;
    for (cpu, numeric, bin) in [
        (image::M4F, "f32", "law"),
        (image::M0, "fixed point", "law_fixed"),
    ] {
        match profile(cpu, bin) {
            Ok(p) => {
                let total: f64 = p.functions.iter().map(|f| f.1).sum();
                println!(
                    "\n{} / {numeric}: {total:.0} instructions per call of evaluate ({} calls), by function:",
                    cpu.name(),
                    p.calls
                );
                for (name, n) in p.functions.iter().take(15) {
                    println!("{n:9.1}  {name}");
                }
            }
            Err(e) => {
                eprintln!("xtask profile: {e}");
                code = 1;
            }
        }
    }
    code
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_only_inside_the_timed_calls() {
        let log = "\
Trace 0: 0x1 [00000000/00000400/0/0] _ZN13twocars_bench6target3law3run17h4dbc46d4c6d4b986E
Trace 0: 0x1 [00000000/00000500/0/0] _ZN3law8evaluate17h0fd53f7a438d4392E
Trace 0: 0x1 [00000000/00000502/0/0] _ZN3law8evaluate17h0fd53f7a438d4392E
Trace 0: 0x1 [00000000/00000600/0/0] _ZN7twocars3num8f32_math5atan217h8977c07e3b9a37e7E
Trace 0: 0x1 [00000000/00000404/0/0] _ZN13twocars_bench6target3law3run17h4dbc46d4c6d4b986E
Trace 0: 0x1 [00000000/00000500/0/0] _ZN3law8evaluate17h0fd53f7a438d4392E
Trace 0: 0x1 [00000000/00000404/0/0] _ZN13twocars_bench6target3law3run17h4dbc46d4c6d4b986E
";
        let p = count(log, "law");
        assert_eq!(p.calls, 2);
        let get = |n: &str| p.functions.iter().find(|f| f.0 == n).map(|f| f.1);
        assert_eq!(get("law::evaluate"), Some(1.5));
        assert_eq!(get("twocars::num::f32_math::atan2"), Some(0.5));
        assert_eq!(get("twocars_bench::target::law::run"), None);
    }
}
