//! `cargo xtask run --link mavlink` and the MAVLink checks of `cargo xtask test`: the MAVLink
//! image in QEMU, pymavlink (from the Python package index, in a virtual environment under
//! `target/`) playing the autopilot and the target (`xtask/mavlink_peer.py`).
//!
//! In the closed loop this process integrates both vehicles exactly (`twocars_sim::sim`), turns
//! their states into the fixes an autopilot reports (`twocars_sim::autopilot`), applies the
//! commanded yaw rate to the pursuer and plays the paper's law for the evader. The paper's four
//! cases run at ten times its lengths and speeds (the same times), so that GPS resolution
//! (1 cm) is far below the capture radius.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use twocars::{Guidance, Law, Limits, Policy, Variant};
use twocars_sim::autopilot::{hdg_cdeg, velocity_cm_s, Plane, HOME};
use twocars_sim::scenarios::{paper_cases, Case, PAPER_LIMITS};
use twocars_sim::sim::{advance, closed_loop, wrap_pi, SimParams, SimStatus, StepCommand};

use crate::harness::firmware::emulator;
use crate::image::signing::SigningKey;
use crate::image::{self, Image};

/// pymavlink's version in the virtual environment.
const PYMAVLINK: &str = "pymavlink==2.4.49";
/// Lengths and speeds times this (times unchanged).
pub const SCALE: f64 = 10.0;
/// Control period, s.
pub const DT: f64 = 0.01;
/// Capture distance at the scale, metres (the paper's epsilon, scaled).
const EPS: f64 = twocars_sim::scenarios::EPS * SCALE;
/// A capture within this many periods of the reference counts as on time.
const ON_TIME_PERIODS: f64 = 5.0;
/// The paper's four cases' captures in `cargo xtask run` under the paper's law (plus
/// eps / (v_pm - v_em)), seconds: the reference. Case 3's upper value at t = 0 is 5.1641.
const REFERENCE: [f64; 4] = [5.6575, 6.6072, 5.1265, 5.9778];

/// The virtual environment's Python with pymavlink, created on first use.
pub fn python() -> Result<PathBuf, String> {
    crate::util::setup::venv("mavlink-venv", &[PYMAVLINK], "import pymavlink")
}

fn peer_script() -> PathBuf {
    crate::util::workspace::root().join("xtask/mavlink_peer.py")
}

/// `board`'s MAVLink image in QEMU and the scripted pymavlink session against it; Err with what
/// failed.
pub fn scripted_session(board: Image) -> Result<(), String> {
    let python = python()?;
    let (elf, _) = image::build_checked(board, None)?;
    let launched = emulator::launch(&elf, board, false)?;
    let status = Command::new(python)
        .arg(peer_script())
        .args(["session", &launched.port.to_string()])
        .status()
        .map_err(|e| format!("mavlink_peer.py: {e}"))?;
    drop(launched);
    if status.success() {
        Ok(())
    } else {
        Err("the scripted MAVLink session failed".to_string())
    }
}

/// The pymavlink peer in `serve` mode: one JSON request, one JSON answer.
pub struct Peer {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

impl Peer {
    /// The peer against the unit on TCP `port`, signing with `key` where given.
    pub fn start(port: u16, key: Option<&SigningKey>) -> Result<Peer, String> {
        let mut command = Command::new(python()?);
        command
            .arg(peer_script())
            .args(["serve", &port.to_string()]);
        if let Some(key) = key {
            command.arg(key.hex());
        }
        let mut child = command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .map_err(|e| format!("mavlink_peer.py: {e}"))?;
        let (Some(input), Some(output)) = (child.stdin.take(), child.stdout.take()) else {
            return Err("mavlink_peer.py: no pipes".to_string());
        };
        Ok(Peer {
            child,
            input,
            output: BufReader::new(output),
        })
    }

    /// One JSON request; its JSON answer.
    pub fn ask(&mut self, request: &str) -> Result<String, String> {
        writeln!(self.input, "{request}").map_err(|e| format!("to mavlink_peer.py: {e}"))?;
        let mut line = String::new();
        self.output
            .read_line(&mut line)
            .map_err(|e| format!("from mavlink_peer.py: {e}"))?;
        if line.is_empty() {
            return Err("mavlink_peer.py stopped".to_string());
        }
        Ok(line.trim().to_string())
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A number after `"key": ` in a flat JSON answer.
pub fn field(answer: &str, key: &str) -> Option<f64> {
    let at = answer.find(&format!("\"{key}\": "))? + key.len() + 4;
    let rest = answer.get(at..)?;
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    let text = rest.get(..end)?.trim();
    match text {
        "Infinity" => Some(f64::INFINITY),
        "-Infinity" => Some(f64::NEG_INFINITY),
        "NaN" => Some(f64::NAN),
        t => t.parse().ok(),
    }
}

/// The GLOBAL_POSITION_INT fields of a vehicle at `state` (metres north and east of home,
/// heading clockwise from north) moving at `speed`, stamped `time_ms`, as a JSON array.
pub fn report(plane: &Plane, time_ms: u32, state: [f64; 3], speed: f64) -> String {
    let (lat, lon) = plane.fix(state[0], state[1]);
    let (vx, vy) = velocity_cm_s(speed, state[2]);
    format!(
        "[{time_ms}, [{lat}, {lon}], [{vx}, {vy}], {}]",
        hdg_cdeg(state[2])
    )
}

/// The paper's limits at [`SCALE`]: speeds times it, curvatures divided by it.
pub fn scaled_limits() -> [f32; 4] {
    let limits = PAPER_LIMITS.map(|v| v as f32);
    [
        limits[0] * SCALE as f32,
        limits[1] / SCALE as f32,
        limits[2] * SCALE as f32,
        limits[3] / SCALE as f32,
    ]
}

/// The paper's `case` at [`SCALE`] with the [`scaled_limits`], period [`DT`], time limit
/// `t_max` (s) and capture distance `eps` (m).
pub fn scaled_case(case: &twocars_sim::scenarios::Case, t_max: f64, eps: f64) -> SimParams {
    let scale = |s: [f64; 3]| [s[0] * SCALE, s[1] * SCALE, s[2]];
    SimParams {
        limits: scaled_limits().map(f64::from),
        pursuer: scale(case.pursuer),
        evader: scale(case.evader),
        dt: DT,
        t_max,
        eps,
    }
}

/// PARAM_SETs of `values`, in order; whether each was read back as set.
pub fn set_params(peer: &mut Peer, values: &[(&str, f32)]) -> Result<bool, String> {
    let mut ok = true;
    for &(name, value) in values {
        let answer = peer.ask(&format!(
            r#"{{"op": "set", "name": "{name}", "value": {value}}}"#
        ))?;
        println!("PARAM_SET {name} = {value}: PARAM_VALUE {answer}");
        ok &= field(&answer, "value") == Some(f64::from(value));
    }
    Ok(ok)
}

/// The unit's limits set to [`scaled_limits`], in an order each step keeps valid: speeds
/// first, then the evader's curvature; whether each was read back.
pub fn set_scaled_limits(peer: &mut Peer) -> Result<bool, String> {
    let scaled = scaled_limits();
    set_params(
        peer,
        &[
            ("TC_V_PM", scaled[0]),
            ("TC_V_EM", scaled[2]),
            ("TC_W_EM", scaled[3]),
            ("TC_W_PM", scaled[1]),
        ],
    )
}

/// `cargo xtask run --link mavlink`: the paper's cases at ten times their scale with `board`'s
/// MAVLink image flying the pursuer, signed with `key` where given; returns the exit code.
pub fn run(board: Image, key: Option<&SigningKey>) -> i32 {
    match run_cases(board, key) {
        Ok(true) => 0,
        Ok(false) => 1,
        Err(e) => {
            eprintln!("xtask run --link mavlink: {e}");
            1
        }
    }
}

/// Where the image is signed: a PARAM_SET of TC_TIMEOUT to 0.7 unsigned, under a wrong key,
/// replayed, with its timestamp gone back and with its signature cut short, sent by pymavlink;
/// whether each went unanswered and was counted once in its own counter, TC_TIMEOUT kept its
/// value, and pymavlink found every frame of the unit well signed.
fn signature_refusals(peer: &mut Peer) -> Result<bool, String> {
    let answer =
        peer.ask(r#"{"op": "refusals", "name": "TC_TIMEOUT", "value": 0.7, "kept": 1.0}"#)?;
    let mut ok = true;
    for case in answer.split(r#"{"case": "#).skip(1) {
        let name = case.split('"').nth(1).unwrap_or("?");
        let counter = case
            .split(r#""counter": ""#)
            .nth(1)
            .and_then(|c| c.split('"').next());
        let refused = case.contains(r#""answered": false"#);
        let counted = case.contains(r#""counted": true"#);
        println!(
            "signed link, PARAM_SET TC_TIMEOUT 0.7 {name}: {}, {} {} (now {})",
            if refused { "refused" } else { "ANSWERED" },
            if counted {
                "counted in"
            } else {
                "NOT counted once in"
            },
            counter.unwrap_or("?"),
            field(case, "now").map_or("?".to_string(), |v| v.to_string()),
        );
        ok &= refused && counted;
    }
    let kept = field(&answer, "value");
    let (good, bad) = (field(&answer, "good"), field(&answer, "bad"));
    println!(
        "TC_TIMEOUT read back: {kept:?} (kept 1.0); the unit's frames checked by pymavlink: \
         {good:?} well signed, {bad:?} badly signed"
    );
    Ok(ok
        && answer.matches(r#"{"case": "#).count() == 5
        && kept == Some(1.0)
        && good > Some(0.0)
        && bad == Some(0.0))
}

/// The closed loop of `run --link mavlink` on `board`'s image, signed with `key` where given:
/// whether every capture was on time.
pub fn run_cases(board: Image, key: Option<&SigningKey>) -> Result<bool, String> {
    let (elf, size) = image::build_checked(board, key)?;
    println!(
        "{}: {} B flash; pymavlink plays the autopilot (system 1) and the target (system 2)",
        board.bin(),
        size.flash()
    );
    let launched = emulator::launch(&elf, board, false)?;
    let mut peer = Peer::start(launched.port, key)?;
    let mut ok = greet(&mut peer, board, key)?;
    let [v_pm, w_pm, v_em, w_em] = scaled_limits();
    let law_limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em).map_err(|e| e.to_string())?;
    let mut clock_ms = 0_u32;
    for (case, reference) in paper_cases().into_iter().zip(REFERENCE) {
        ok &= fly_case(&mut peer, &case, reference, law_limits, &mut clock_ms)?;
        // The next case starts fresh: both states go stale (TC_TIMEOUT 1 s), which the unit
        // announces and which resets its guidance.
        peer.ask(r#"{"op": "quiet", "seconds": 1.2}"#)?;
        clock_ms += 10_000;
    }
    drop(peer);
    drop(launched);
    Ok(ok)
}

/// The unit's first words: its heartbeat (the fallback clock's and an unsigned image's
/// STATUSTEXT with it where they apply), the scaled limits set, every parameter listed, and
/// where signed the refusals of bad signatures; whether all were as expected.
fn greet(peer: &mut Peer, board: Image, key: Option<&SigningKey>) -> Result<bool, String> {
    let heartbeat = peer.ask(r#"{"op": "heartbeat"}"#)?;
    println!("unit's heartbeat: {heartbeat}");
    let mut ok = heartbeat.contains("\"component\": 191") && heartbeat.contains("\"type\": 18");
    let fallback =
        board.status_in_emulator() & twocars::protocol::message::BOARD_FALLBACK_CLOCK != 0;
    ok &= heartbeat.contains(twocars::mavlink::FALLBACK_CLOCK_TEXT) == fallback;
    ok &= heartbeat.contains(twocars::mavlink::UNSIGNED_TEXT) == key.is_none();
    ok &= set_scaled_limits(peer)?;
    // Every parameter listed: the list is paced to the transmit queue's room.
    let list = peer.ask(r#"{"op": "list"}"#)?;
    println!("PARAM_REQUEST_LIST: {list}");
    ok &= list.matches(r#"["TC_"#).count() == twocars::mavlink::SPECS.len();
    if key.is_some() {
        ok &= signature_refusals(peer)?;
    }
    Ok(ok)
}

/// One paper case through the unit: pymavlink reports both fixes each period, the unit's yaw
/// rate steers the pursuer, the evader plays the paper's law on the exact states; whether the
/// capture came within [`ON_TIME_PERIODS`] of `reference`.
fn fly_case(
    peer: &mut Peer,
    case: &Case,
    reference: f64,
    law_limits: Limits<f32>,
    clock_ms: &mut u32,
) -> Result<bool, String> {
    let plane = Plane::new(HOME);
    let params = scaled_case(case, 30.0, EPS);
    let mut evader_law = Guidance::new(
        Law::new(law_limits, Variant::Paper),
        DT as f32,
        twocars::Policy::Paper,
    )
    .map_err(|_| "invalid dt".to_string())?
    .with_policy(Policy::Paper);
    let mut pursuer = params.pursuer;
    let mut first_tc_t = None;
    let mut setpoints = 0_u64;
    let result = closed_loop(&params, false, |_, local_p, local_e| {
        // closed_loop gives the states about the pursuer; the autopilot reports fixes.
        let evader = [pursuer[0] + local_e[0], pursuer[1] + local_e[1], local_e[2]];
        let request = format!(
            r#"{{"op": "step", "own": {}, "target": {}}}"#,
            report(&plane, *clock_ms, pursuer, params.limits[0]),
            report(&plane, *clock_ms, evader, params.limits[2]),
        );
        *clock_ms += (DT * 1000.0) as u32;
        let answer = peer.ask(&request)?;
        let rate = field(&answer, "yaw_rate")
            .ok_or_else(|| format!("no setpoint for the own state: {answer}"))?;
        setpoints += 1;
        if first_tc_t.is_none() {
            first_tc_t = field(&answer, "tc_t");
        }
        let evader_w = match evader_law
            .law()
            .limits
            .states(local_p.map(|v| v as f32), local_e.map(|v| v as f32))
        {
            Ok((p, e)) => f64::from(evader_law.step(&p, &e).command.evader),
            Err(_) => 0.0,
        };
        let pursuer_w = rate / params.limits[0];
        // The same step closed_loop takes: the pursuer's absolute state for the next fix.
        let next = advance(pursuer, params.limits[0], pursuer_w, DT);
        pursuer = [next[0], next[1], wrap_pi(next[2])];
        Ok::<_, String>(StepCommand::full_speed(pursuer_w, evader_w, None))
    })?;
    let closing = result.point_capture(params.limits, EPS);
    let late = (closing - reference) / DT;
    let on_time = result.status == SimStatus::Captured && late.abs() <= ON_TIME_PERIODS;
    println!(
        "{}: firmware over MAVLink: {}, captured to {EPS} m at {:.4} s (+ eps / (v_pm - v_em) = {:.4} s); \
         reference {reference:.4} s: {:+.2} control periods ({}); first TC_T {:.4} s (upper value {:.4} s); {setpoints} setpoints",
        case.name,
        result.status.name(),
        result.t_capture,
        closing,
        late,
        if on_time { "within 5" } else { "NOT WITHIN 5" },
        first_tc_t.unwrap_or(f64::NAN),
        case.expected_value,
    );
    Ok(on_time)
}
