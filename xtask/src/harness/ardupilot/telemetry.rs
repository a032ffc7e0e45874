//! ArduPilot's telemetry as the unit met it: the frames the autopilot sent by message, and the
//! whole byte stream the unit's UART received replayed through the same endpoint on the host
//! (`twocars::mavlink::Endpoint`, the code the image runs): frames parsed, skipped and dropped.

use std::fmt;

use twocars::mavlink::{Endpoint, EndpointCounters, FrameCounters};

use crate::harness::autopilot::harness::Harness;

/// What the link carried over a run.
pub struct Summary {
    /// (message id, frames, bytes) from the autopilot, most frames first.
    pub by_message: Vec<(u32, u64, u64)>,
    /// The rover's time the run covered, s.
    pub seconds: f64,
    /// Bytes the unit received.
    pub bytes_to_unit: usize,
    /// The replay's counters.
    pub frames: FrameCounters,
    pub endpoint: EndpointCounters,
    /// The unit's own last TC_BADFRM.
    pub unit_bad_frames: Option<f32>,
    /// Setpoints the unit sent (seen by the harness), and the replay's.
    pub unit_setpoints: usize,
}

/// The run's telemetry figures.
pub fn summary(h: &Harness) -> Summary {
    let mut by_message: Vec<(u32, u64, u64)> = h
        .autopilot_frames
        .iter()
        .map(|(&id, &(n, b))| (id, n, b))
        .collect();
    by_message.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let seconds = match (h.fixes.first(), h.fixes.last()) {
        (Some(a), Some(b)) => f64::from(b.time_ms.wrapping_sub(a.time_ms)) / 1000.0,
        _ => 0.0,
    };
    let mut endpoint = Endpoint::new();
    let mut bytes_to_unit = 0;
    for (t, bytes) in &h.router.to_unit_log {
        bytes_to_unit += bytes.len();
        for &b in bytes {
            endpoint.receive(b, *t, &mut |_| {});
        }
        endpoint.poll(*t, &mut |_| {});
    }
    Summary {
        by_message,
        seconds,
        bytes_to_unit,
        frames: endpoint.frame_counters(),
        endpoint: endpoint.counters(),
        unit_bad_frames: h.bad_frames,
        unit_setpoints: h.setpoints.len(),
    }
}

/// Writes what the unit's UART received as a capture (`twocars_bench::replay`'s records), for
/// the bench's `replay` image; its path.
pub fn write_capture(h: &Harness) -> Result<std::path::PathBuf, String> {
    let mut out = Vec::new();
    for (ms, bytes) in &h.router.to_unit_log {
        twocars_bench::replay::push_record(&mut out, *ms, bytes);
    }
    let path = crate::util::workspace::target_dir().join("ardupilot/telemetry.capture");
    std::fs::write(&path, out).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path)
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total: u64 = self.by_message.iter().map(|m| m.1).sum();
        let per_s = |n: u64| n as f64 / self.seconds.max(1e-9);
        writeln!(
            f,
            "telemetry: {total} frames from ArduPilot over {:.0} s ({:.1} frames/s) of {} message kinds; the unit received {} bytes ({:.0} B/s) with the target's",
            self.seconds,
            per_s(total),
            self.by_message.len(),
            self.bytes_to_unit,
            self.bytes_to_unit as f64 / self.seconds.max(1e-9),
        )?;
        let top: Vec<String> = self
            .by_message
            .iter()
            .take(8)
            .map(|(id, n, _)| format!("{id}: {:.1}/s", per_s(*n)))
            .collect();
        writeln!(f, "  most frequent (message id: rate): {}", top.join(", "))?;
        let c = &self.frames;
        write!(
            f,
            "  the endpoint on that stream (replayed on the host): {} frames parsed, {} skipped (messages it does not use), {} dropped (checksum {}, flags {}), {} bytes outside frames; {} setpoints (the unit sent {}); the unit's TC_BADFRM {}",
            c.frames,
            c.unknown,
            c.bad_checksum + c.bad_flags,
            c.bad_checksum,
            c.bad_flags,
            c.skipped_bytes,
            self.endpoint.setpoints,
            self.unit_setpoints,
            self.unit_bad_frames.map_or("none".to_string(), |v| format!("{v}")),
        )
    }
}
