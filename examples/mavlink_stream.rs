//! The MAVLink endpoint on a byte stream, as a companion computer's serial port gives it: an
//! autopilot's GLOBAL_POSITION_INT for the own rover (system 1) and the target's (system 2)
//! five times a second, fed byte by byte; the frames the endpoint answers decoded with the
//! `mavlink` crate: the yaw rate it asks of the rover (SET_ATTITUDE_TARGET), the capture time
//! it predicts (NAMED_VALUE_FLOAT TC_T) and its status texts. The rover is moved by what it is
//! told, so the chase closes over the 30 s.
//!
//! ```sh
//! cargo run --example mavlink_stream --features mavlink
//! ```

use mavlink::dialects::common::{MavMessage, GLOBAL_POSITION_INT_DATA};
use mavlink::{MavlinkVersion, Message as _};
use twocars::geodetic::LocalFrame;
use twocars::mavlink::{Endpoint, FrameReader, Outbox};

/// The fixes' interval, milliseconds.
const EVERY_MS: u32 = 200;
/// Home, degE7.
const HOME: (i32, i32) = (473_977_420, 85_455_940);

/// A vehicle's fix: north, east (m) and heading (rad, clockwise from north) as an autopilot
/// reports them, from `system`, stamped `time_ms`.
fn position(
    home: &LocalFrame,
    [north, east, heading]: [f32; 3],
    time_ms: u32,
    speed: f32,
) -> GLOBAL_POSITION_INT_DATA {
    let (lat, lon) = home.to_fix(north, east).expect("within the local plane");
    let cdeg = heading.to_degrees().rem_euclid(360.0) * 100.0;
    GLOBAL_POSITION_INT_DATA {
        time_boot_ms: time_ms,
        lat,
        lon,
        alt: 100_000,
        relative_alt: 0,
        vx: (100.0 * speed * heading.cos()) as i16,
        vy: (100.0 * speed * heading.sin()) as i16,
        vz: 0,
        hdg: cdeg as u16 % 36_000,
    }
}

/// Moves (north, east, heading clockwise) `dt` seconds at `speed` and yaw rate `rate` (rad/s,
/// clockwise positive).
fn drive(s: &mut [f32; 3], speed: f32, rate: f32, dt: f32) {
    s[2] += rate * dt;
    s[0] += speed * dt * s[2].cos();
    s[1] += speed * dt * s[2].sin();
}

fn main() {
    let home = LocalFrame::new(HOME.0, HOME.1).expect("a valid home");
    let mut unit = Endpoint::new();
    // A rover at 3 m/s turning at most 1.5 rad/s (curvature 0.5 1/m) against a target at half
    // its speed and curvature; captured within 1 m. Each value is checked against the others
    // as it is set: the evader's first, so that it stays the slower, less agile one.
    for (name, value) in [
        ("TC_W_EM", 0.25),
        ("TC_V_EM", 1.5),
        ("TC_V_PM", 3.0),
        ("TC_W_PM", 0.5),
        ("TC_CAPTURE", 1.0),
    ] {
        unit.set_param(name.as_bytes(), value)
            .expect("within its range");
    }
    let (mut own, mut target) = ([0.0f32, 0.0, 0.0], [30.0f32, 20.0, 1.0]);
    let (mut autopilot, mut answers) = (Outbox::default(), FrameReader::default());
    let mut yaw_rate = 0.0;
    let mut captured = false;
    for step in 0..150 {
        let now_ms = step * EVERY_MS;
        let mut stream = Vec::new();
        let mut out = |bytes: &[u8]| stream.extend_from_slice(bytes);
        autopilot.send_as((2, 1), &position(&home, target, now_ms, 1.5), &mut out);
        autopilot.send_as((1, 1), &position(&home, own, now_ms, 3.0), &mut out);
        let mut sent = Vec::new();
        for byte in stream {
            unit.receive(byte, now_ms, &mut |frame| sent.extend_from_slice(frame));
        }
        unit.poll(now_ms, &mut |frame| sent.extend_from_slice(frame));
        for byte in sent {
            let Some(frame) = answers.push(byte, |id| Some(MavMessage::extra_crc(id))) else {
                continue;
            };
            match MavMessage::parse(MavlinkVersion::V2, frame.message_id, frame.payload) {
                Ok(MavMessage::SET_ATTITUDE_TARGET(s)) => yaw_rate = s.body_yaw_rate,
                Ok(MavMessage::NAMED_VALUE_FLOAT(v))
                    if step % 25 == 0 && v.name.starts_with(b"TC_T\0") =>
                {
                    let d = ((own[0] - target[0]).powi(2) + (own[1] - target[1]).powi(2)).sqrt();
                    println!(
                        "t {:4.1} s: {d:5.1} m apart, TC_T {:.2} s",
                        now_ms as f32 / 1e3,
                        v.value
                    );
                }
                Ok(MavMessage::STATUSTEXT(t)) => {
                    let text: Vec<u8> = t.text.iter().copied().take_while(|&c| c != 0).collect();
                    let text = String::from_utf8_lossy(&text);
                    println!("t {:4.1} s: \"{text}\"", now_ms as f32 / 1e3);
                    captured |= text.contains("captured");
                }
                _ => {}
            }
        }
        if captured {
            break;
        }
        // Both vehicles move until the next fixes: the rover as told, the target straight.
        drive(&mut own, 3.0, yaw_rate, EVERY_MS as f32 / 1e3);
        drive(&mut target, 1.5, 0.0, EVERY_MS as f32 / 1e3);
    }
}
