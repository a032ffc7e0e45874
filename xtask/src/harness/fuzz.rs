//! `cargo xtask fuzz`: the libFuzzer targets in `fuzz/` (frame decoder, unit step, law, the
//! fixed-point backend's f32 conversions, the MAVLink endpoint's input path, the whole
//! endpoint, and the endpoint with signing on), each
//! started from its committed seed corpus (`fuzz/seeds/<target>`), with a time or run budget;
//! prints executions, corpus size and failures per target. `cargo xtask test` runs a short
//! smoke run of each; the long run is recorded in `docs/reliability.md`.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::util::workspace::root;

/// The fuzz targets.
pub const TARGETS: [&str; 7] = [
    "frame_decoder",
    "serial_endpoint",
    "law",
    "conversion",
    "mavlink_input",
    "mavlink_endpoint",
    "mavlink_signed",
];

/// Budget of one run.
#[derive(Clone, Copy, Debug)]
pub enum Budget {
    /// Wall-clock seconds per target.
    Seconds(u64),
    /// Executions per target.
    Runs(u64),
}

/// Outcome of one target's run.
#[derive(Debug)]
pub struct FuzzRun {
    /// Target name.
    pub target: &'static str,
    /// Executions reported by libFuzzer.
    pub executions: u64,
    /// Corpus entries at the end.
    pub corpus: u64,
    /// Whether the target failed (a crash, panic or timeout).
    pub failed: bool,
}

/// The flags `cargo fuzz run -s none -O` (cargo-fuzz 0.13) builds a target with: libFuzzer's
/// coverage instrumentation, `cfg(fuzzing)`, no sanitizer. Set here so that the targets
/// build with the pinned toolchain's cargo alone: installing cargo-fuzz from source costs a
/// bare machine about 3.5 minutes.
const RUSTFLAGS: [&str; 9] = [
    "-Cpasses=sancov-module",
    "-Cllvm-args=-sanitizer-coverage-level=4",
    "-Cllvm-args=-sanitizer-coverage-inline-8bit-counters",
    "-Cllvm-args=-sanitizer-coverage-pc-table",
    "-Cllvm-args=-sanitizer-coverage-trace-compares",
    "--cfg=fuzzing",
    "-Cllvm-args=-simplifycfg-branch-fold-threshold=0",
    // The sancov passes keep ThinLTO from importing across units: one unit, as cargo-fuzz.
    "-Ccodegen-units=1",
    // Linux only in cargo-fuzz; the targets run on the host.
    "-Cllvm-args=-sanitizer-coverage-stack-depth",
];

/// The host's target triple, from `rustc -vV`.
fn host_triple() -> Result<String, String> {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .map_err(|e| format!("rustc -vV: {e}"))?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .map(str::to_string)
        .ok_or_else(|| "rustc -vV gave no host".to_string())
}

/// Builds every fuzz target for the host with [`RUSTFLAGS`] (release, line tables, as
/// cargo-fuzz does); each target's executable.
pub fn build_targets() -> Result<Vec<(String, PathBuf)>, String> {
    crate::util::setup::cxx()?;
    let triple = host_triple()?;
    let mut flags = RUSTFLAGS.to_vec();
    if !triple.contains("-linux-") {
        flags.pop();
    }
    let mut rustflags = flags.join(" ");
    if let Ok(user) = std::env::var("RUSTFLAGS") {
        rustflags = format!("{rustflags} {user}");
    }
    let out = Command::new("cargo")
        .current_dir(root().join("fuzz"))
        // --target: the flags then reach the targets, not the build scripts.
        .args(["build", "--release", "--bins", "--target", &triple])
        .args(["--config", "profile.release.debug=\"line-tables-only\""])
        .args(["--message-format", "json-render-diagnostics"])
        .env("RUSTFLAGS", rustflags)
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| format!("cargo build of the fuzz targets: {e}"))?;
    if !out.status.success() {
        return Err("the fuzz targets did not build".to_string());
    }
    let mut built = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(message) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        let name = message["target"]["name"].as_str();
        if let (Some(name), Some(exe)) = (name, message["executable"].as_str()) {
            built.push((name.to_string(), PathBuf::from(exe)));
        }
    }
    Ok(built)
}

fn seeds(target: &str) -> Vec<Vec<u8>> {
    use twocars_sim::link;
    use twocars_sim::session::{paper_configure, paper_state, script};
    let mut out = Vec::new();
    match target {
        "frame_decoder" | "serial_endpoint" => {
            // serial_endpoint reads its first byte as "configure first" when odd.
            let prefix: &[u8] = if target == "serial_endpoint" {
                &[1]
            } else {
                &[]
            };
            for step in script() {
                out.push([prefix, &step.bytes].concat());
            }
            let mut session = prefix.to_vec();
            session.extend(link::configure(1, &paper_configure()));
            for (i, t) in [0u32, 10, 20, 900].into_iter().enumerate() {
                session.extend(link::state(2 + i as u16, &paper_state(i, t)));
            }
            session.extend(link::reset(9));
            session.extend(link::read_counters(10));
            out.push(session);
        }
        "mavlink_input" => {
            use twocars_sim::mavlink_spec::{
                param_set_payload, position_payload, v1, v2, GLOBAL_POSITION_INT, HEARTBEAT,
                PARAM_REQUEST_LIST, PARAM_SET,
            };
            let position = position_payload(473_977_420, 85_455_940, 150, -220, 9_000);
            out.push(v2(1, 1, GLOBAL_POSITION_INT, &position, false));
            out.push(v1(2, 2, GLOBAL_POSITION_INT, &position));
            out.push(v2(3, 2, GLOBAL_POSITION_INT, &position, true));
            let param = param_set_payload((1, 191), "TC_V_PM", 3.0, 9);
            let mut session = v2(4, 255, HEARTBEAT, &[0, 0, 0, 0, 6, 8, 0, 4, 3], false);
            session.extend(v2(5, 255, PARAM_SET, &param, false));
            session.extend(v2(6, 255, PARAM_REQUEST_LIST, &[1, 191], false));
            out.push(session);
        }
        "mavlink_endpoint" => out.extend(mavlink_sessions()),
        "mavlink_signed" => out.extend(signed_sessions()),
        _ => {
            for case in 0..4 {
                let s = paper_state(case, 0);
                let mut bytes = Vec::new();
                for v in [2.0f32, 2.0, 1.0, 1.0]
                    .iter()
                    .chain(&s.pursuer)
                    .chain(&s.evader)
                    .chain(&[0.01f32])
                {
                    bytes.extend(v.to_bits().to_le_bytes());
                }
                out.push(bytes);
            }
        }
    }
    out
}

/// The MAVLink endpoint's seeds: limits set at ten times the paper's scale, then target and
/// own states of the paper's case 1 (at 20 ms spacing), a FOLLOW_TARGET and a parameter list.
fn mavlink_sessions() -> Vec<Vec<u8>> {
    use twocars_sim::autopilot::{hdg_cdeg, Plane, HOME};
    use twocars_sim::mavlink_spec::{
        follow_target_payload, param_request_list_payload, param_set_payload, position_payload_at,
        v2_from, FOLLOW_TARGET, GLOBAL_POSITION_INT, PARAM_REQUEST_LIST, PARAM_SET,
    };
    let plane = Plane::new(HOME);
    let mut session = Vec::new();
    for (i, (name, value)) in [("TC_V_PM", 20.0), ("TC_V_EM", 10.0), ("TC_W_EM", 0.1)]
        .into_iter()
        .enumerate()
    {
        let payload = param_set_payload((1, 191), name, value, 9);
        session.extend(v2_from(i as u8, (255, 190), PARAM_SET, &payload, false));
    }
    let mut fixes = Vec::new();
    for k in 0..4_u32 {
        let t = k * 20;
        let east = f64::from(k) * 0.4;
        let (lat, lon) = plane.fix(-30.0, -60.0 + east * 0.5);
        let target =
            position_payload_at(t, lat, lon, 0, 1_000, hdg_cdeg(std::f64::consts::FRAC_PI_2));
        fixes.extend(v2_from(
            10 + k as u8,
            (2, 1),
            GLOBAL_POSITION_INT,
            &target,
            false,
        ));
        let (lat, lon) = plane.fix(0.0, east);
        let own = position_payload_at(t, lat, lon, 0, 2_000, hdg_cdeg(std::f64::consts::FRAC_PI_2));
        fixes.extend(v2_from(
            20 + k as u8,
            (1, 1),
            GLOBAL_POSITION_INT,
            &own,
            false,
        ));
    }
    let (lat, lon) = plane.fix(10.0, 10.0);
    let follow = follow_target_payload(lat, lon, [1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], 1 | 2 | 8);
    let mut others = v2_from(30, (7, 1), FOLLOW_TARGET, &follow, false);
    let list = param_request_list_payload((1, 191));
    others.extend(v2_from(31, (255, 190), PARAM_REQUEST_LIST, &list, false));
    vec![
        [&session[..], &fixes[..]].concat(),
        [&session[..], &fixes[..], &others[..]].concat(),
        fixes,
    ]
}

/// The signed endpoint's seeds, in its records (op, length, bytes; `fuzz_targets/
/// mavlink_signed.rs`): signed PARAM_SETs and positions, each refusal (unsigned, forged,
/// replayed, older) once, and a parameter list.
fn signed_sessions() -> Vec<Vec<u8>> {
    use twocars_sim::autopilot::{hdg_cdeg, Plane, HOME};
    use twocars_sim::mavlink_spec::{
        param_request_list_payload, param_set_payload, position_payload_at, v2_from, PARAM_SET,
    };
    // (op, sender, message index in the target's table, payload); op 2 takes its timestamp
    // offset first.
    fn record(op: u8, body: &[u8]) -> Vec<u8> {
        [&[op, body.len() as u8][..], body].concat()
    }
    let signed = |sender: (u8, u8), kind: u8, payload: &[u8]| {
        record(1, &[&[sender.0, sender.1, kind][..], payload].concat())
    };
    let set = |name, value| param_set_payload((1, 191), name, value, 9);
    let plane = Plane::new(HOME);
    let mut fixes = Vec::new();
    for k in 0..3_u32 {
        let (lat, lon) = plane.fix(-3.0, -6.0 + f64::from(k) * 0.02);
        let hdg = hdg_cdeg(std::f64::consts::FRAC_PI_2);
        fixes.extend(signed(
            (2, 1),
            1,
            &position_payload_at(k * 20, lat, lon, 0, 100, hdg),
        ));
        let (lat, lon) = plane.fix(0.0, f64::from(k) * 0.04);
        fixes.extend(signed(
            (1, 1),
            1,
            &position_payload_at(k * 20, lat, lon, 0, 200, hdg),
        ));
    }
    let mut refusals = signed((255, 190), 0, &set("TC_TIMEOUT", 0.5));
    refusals.extend(record(3, &[]));
    refusals.extend(record(
        0,
        &v2_from(9, (255, 190), PARAM_SET, &set("TC_TIMEOUT", 0.7), false),
    ));
    let back = [&[0x00, 0x80, 1, 255, 190, 0][..], &set("TC_TIMEOUT", 0.8)].concat();
    refusals.extend(record(2, &back));
    refusals.extend(record(
        0,
        &v2_from(10, (255, 190), PARAM_SET, &set("TC_SYSID", 3.0), true),
    ));
    refusals.extend(signed((255, 190), 3, &param_request_list_payload((1, 191))));
    vec![fixes.clone(), [refusals, fixes].concat()]
}

/// Writes the seed corpora (`cargo xtask fuzz --write-seeds`).
pub fn write_seeds() -> Result<(), String> {
    for target in TARGETS {
        let dir = root().join("fuzz/seeds").join(target);
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        for (i, bytes) in seeds(target).iter().enumerate() {
            std::fs::write(dir.join(format!("seed-{i:02}")), bytes).map_err(|e| e.to_string())?;
        }
    }
    Ok(())
}

/// Runs one target, built by [`build_targets`] as `built`, with `budget`.
pub fn run_target(
    target: &'static str,
    built: &[(String, PathBuf)],
    budget: Budget,
) -> Result<FuzzRun, String> {
    let fuzz = root().join("fuzz");
    let exe = built
        .iter()
        .find(|(name, _)| name == target)
        .map(|(_, exe)| exe)
        .ok_or_else(|| format!("the fuzz target {target} was not built"))?;
    let corpus = fuzz.join("corpus").join(target);
    let artifacts = fuzz.join("artifacts").join(target);
    for dir in [&corpus, &artifacts] {
        std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    }
    let limit = match budget {
        Budget::Seconds(s) => format!("-max_total_time={s}"),
        Budget::Runs(n) => format!("-runs={n}"),
    };
    let mut prefix = std::ffi::OsString::from("-artifact_prefix=");
    prefix.push(&artifacts);
    prefix.push("/");
    let output = Command::new(exe)
        .current_dir(&fuzz)
        .arg(prefix)
        .args([&limit, "-print_final_stats=1"])
        .arg(&corpus)
        .arg(fuzz.join("seeds").join(target))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .output()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    let log = String::from_utf8_lossy(&output.stderr);
    let stat = |name: &str| -> u64 {
        log.lines()
            .filter_map(|l| l.strip_prefix(name))
            .filter_map(|v| v.trim().trim_start_matches(':').trim().parse().ok())
            .next_back()
            .unwrap_or(0)
    };
    let executions = stat("stat::number_of_executed_units");
    let failed = !output.status.success();
    if failed {
        eprintln!("{}", failure_summary(&log));
        eprintln!("replay: {} <the test unit written above>", exe.display());
    }
    Ok(FuzzRun {
        target,
        executions,
        corpus: count_files(&corpus),
        failed,
    })
}

/// The lines of libFuzzer's log that say how to reproduce a failure.
const REPRODUCE: [&str; 3] = ["INFO: Seed:", "Test unit written to", "Base64:"];

/// What reproduces a failure from libFuzzer's log: its seed, the panic message and the
/// crashing input (path and Base64; the target's executable run on that path replays it);
/// the whole tail when none is found.
fn failure_summary(log: &str) -> String {
    let lines: Vec<&str> = log.lines().collect();
    let mut keep: Vec<&str> = Vec::new();
    for (i, &line) in lines.iter().enumerate() {
        if line.contains("panicked at") {
            keep.extend(&lines[i..(i + 2).min(lines.len())]);
        } else if REPRODUCE.iter().any(|key| line.contains(key)) {
            keep.push(line);
        }
    }
    if keep.is_empty() {
        keep = lines[lines.len().saturating_sub(30)..].to_vec();
    }
    keep.join("\n")
}

fn count_files(dir: &Path) -> u64 {
    std::fs::read_dir(dir).map_or(0, |d| d.filter_map(Result::ok).count() as u64)
}
