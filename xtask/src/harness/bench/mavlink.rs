//! The MAVLink endpoint's rows of `cargo xtask bench`: its serial path on the Cortex-M4F
//! (the `mavlink` image, the sessions of `bench/src/mavlink.rs`), checked against the same
//! sessions on the host.

use twocars_bench::mavlink::{
    script, serve_script, Outcome, Session, PERIODS, SCRIPT_CAPACITY, SESSIONS,
};

use crate::harness::bench::image::{build_and_print, M4F};

/// What one kind of MAVLink session costs on the Cortex-M4F, unsigned or signed.
#[derive(Clone, Copy, Debug)]
pub struct Costs {
    /// Instructions per control period: a target and an own GLOBAL_POSITION_INT found, checked
    /// and decoded, the law, SET_ATTITUDE_TARGET and NAMED_VALUE_FLOAT encoded and sent.
    pub per_period: f64,
    /// Instructions per GLOBAL_POSITION_INT from a system the endpoint ignores (frame search,
    /// checksum, signature where signed, decode).
    pub per_parse: f64,
    /// The empty session (one heartbeat and its companions), instructions.
    pub fixed: f64,
    /// Stack high-water mark of the guided session, bytes.
    pub stack: u64,
    /// Frames sent in the guided session.
    pub frames: u32,
}

/// What the MAVLink sessions cost on the Cortex-M4F.
#[derive(Clone, Copy, Debug)]
pub struct MavlinkMeasured {
    /// Signing off.
    pub unsigned: Costs,
    /// Signed both ways.
    pub signed: Costs,
}

fn host(session: Session, signed: bool) -> Result<Outcome, String> {
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let n = script(session, signed, &mut bytes).ok_or("the MAVLink script does not fit")?;
    Ok(serve_script(
        &mut twocars::serial::Line::new(),
        &bytes[..n],
        signed,
    ))
}

/// One session's line from the image: (its index in `SESSIONS`, instructions, stack, frames),
/// checked against the same session on the host.
fn session_line(line: &str) -> Result<Option<(usize, f64, u64, u32)>, String> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    let ["mavlink", i, t, s, f, d] = fields.as_slice() else {
        return Ok(None);
    };
    let bad = || format!("bad line {line}");
    let i: usize = i.parse().map_err(|_| bad())?;
    let (session, signed) = *SESSIONS.get(i).ok_or_else(bad)?;
    let got = Outcome {
        frames: f.parse().map_err(|_| bad())?,
        digest: u32::from_str_radix(d, 16).map_err(|_| bad())?,
    };
    let want = host(session, signed)?;
    if got != want {
        return Err(format!(
            "MAVLink session {session:?} (signed {signed}): Cortex-M4F {got:?}, host {want:?}"
        ));
    }
    let instructions = t.parse::<f64>().map_err(|_| bad())? / M4F.ticks_per_instruction;
    Ok(Some((
        i,
        instructions,
        s.parse().map_err(|_| bad())?,
        got.frames,
    )))
}

/// Runs the six sessions on the Cortex-M4F; an error where what it sent differs from the
/// host's.
pub fn measure() -> Result<MavlinkMeasured, String> {
    let (out, _) = build_and_print(M4F, "mavlink")?;
    let mut seen = [None; SESSIONS.len()];
    for line in out.lines() {
        if let Some((i, instructions, stack, frames)) = session_line(line)? {
            seen[i] = Some((instructions, stack, frames));
        }
    }
    let costs = |first: usize| -> Result<Costs, String> {
        let (Some(empty), Some(ignored), Some(guided)) =
            (seen[first], seen[first + 1], seen[first + 2])
        else {
            return Err(format!(
                "the MAVLink bench did not report every session:\n{out}"
            ));
        };
        Ok(Costs {
            per_period: (guided.0 - empty.0) / PERIODS as f64,
            per_parse: (ignored.0 - empty.0) / (2 * PERIODS) as f64,
            fixed: empty.0,
            stack: guided.1,
            frames: guided.2,
        })
    };
    Ok(MavlinkMeasured {
        unsigned: costs(0)?,
        signed: costs(3)?,
    })
}

/// The bench page's paragraph.
pub fn paragraph(m: &MavlinkMeasured) -> String {
    let (u, s) = (m.unsigned, m.signed);
    format!(
        "MAVLink endpoint (Cortex-M4F, f32; `mavlink` image: the serial path of the \
         `twocars-qemu-mavlink` image, the UART interrupt's handler and \
         `twocars::mavlink::service::service` over the same queues, fed by a scripted UART 32 \
         bytes per pass the bench states as an autopilot reports them, a target and an own \
         GLOBAL_POSITION_INT per control period; {} frames sent, byte for byte the host's): \
         **{:.0} instructions per control period** (two positions found, checked and decoded, \
         the law for the pursuer, SET_ATTITUDE_TARGET and NAMED_VALUE_FLOAT encoded with their \
         checksums and queued: the guided session less the empty one, {:.0}, over its {} periods); \
         **{:.0} instructions per GLOBAL_POSITION_INT parsed** (the same positions from systems \
         the endpoint ignores); **stack {} B** (the endpoint, its frame buffers and the law below \
         the loop's frame).\n\n\
         Signed both ways (the same sessions with every position signed, the endpoint built \
         with the key; {} frames sent, byte for byte the host's): **{:.0} instructions per \
         control period** (+{:.0}: two signatures checked, the setpoint and TC_T signed); \
         **{:.0} instructions per signed GLOBAL_POSITION_INT parsed** (+{:.0}: one SHA-256 of \
         the key and the frame, two 64-byte blocks); the empty session costs {:.0} (the heartbeat and \
         its four named values signed); **stack {} B**.\n\n\
         Where a period's instructions go (QEMU's exec log of this image by function, \
         docs/mavlink.md, \"Cost\"): most to bytes moved one at a time, the UART handler's \
         interrupt per byte both ways, the frame search and the queues; then the law and the \
         guidance, the two frames out, their X.25 checksums, the estimator and the fixes' \
         projection.\n",
        u.frames,
        u.per_period,
        u.fixed,
        PERIODS,
        u.per_parse,
        u.stack,
        s.frames,
        s.per_period,
        s.per_period - u.per_period,
        s.per_parse,
        s.per_parse - u.per_parse,
        s.fixed,
        s.stack,
    )
}

/// What a captured stream cost on the Cortex-M4F (the `replay` image).
#[derive(Clone, Copy, Debug)]
pub struct ReplayMeasured {
    /// Instructions over the whole capture.
    pub instructions: f64,
    /// The capture's span, s.
    pub seconds: f64,
    /// Stack high-water mark, bytes.
    pub stack: u64,
    /// Frames the endpoint sent (equal to the host's).
    pub frames: u32,
    /// Setpoints among them.
    pub setpoints: u32,
}

/// Replays `capture` (records of `twocars_bench::replay`) on the Cortex-M4F and on the host; an
/// error where what the two sent differs.
pub fn measure_replay(capture: &std::path::Path) -> Result<ReplayMeasured, String> {
    let bytes = std::fs::read(capture).map_err(|e| format!("{}: {e}", capture.display()))?;
    let host =
        twocars_bench::replay::serve_replay(&mut twocars::serial::Line::new(), &bytes, &|| 0);
    let env = [("TWOCARS_MAVLINK_CAPTURE", capture.as_os_str())];
    let (out, _) = crate::harness::bench::image::build_and_print_with(M4F, "replay", &env)?;
    let line = out
        .lines()
        .find(|l| l.starts_with("replay "))
        .ok_or_else(|| format!("the replay image printed no figures:\n{out}"))?;
    let bad = || format!("bad line {line}");
    let f: Vec<&str> = line.split_whitespace().collect();
    let [_, ticks, span, stack, frames, setpoints, digest] = f.as_slice() else {
        return Err(bad());
    };
    let got = (
        frames.parse::<u32>().map_err(|_| bad())?,
        setpoints.parse::<u32>().map_err(|_| bad())?,
        u32::from_str_radix(digest, 16).map_err(|_| bad())?,
    );
    if got != (host.frames, host.setpoints, host.digest)
        || span.parse::<u32>().ok() != Some(host.span_ms)
    {
        return Err(format!("replay: Cortex-M4F {line}, host {host:?}"));
    }
    Ok(ReplayMeasured {
        instructions: ticks.parse::<f64>().map_err(|_| bad())? / M4F.ticks_per_instruction,
        seconds: f64::from(host.span_ms) / 1000.0,
        stack: stack.parse().map_err(|_| bad())?,
        frames: got.0,
        setpoints: got.1,
    })
}
