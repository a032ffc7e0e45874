//! The companion binary over UDP, as an autopilot on the same host would meet it: its
//! heartbeat, its parameters (given on the command line), a chase's setpoints, signing, and a
//! clear refusal of a bad parameter.

use std::net::UdpSocket;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use mavlink::dialects::common::{
    MavMessage, GLOBAL_POSITION_INT_DATA, HEARTBEAT_DATA, PARAM_REQUEST_LIST_DATA,
};
use mavlink::{MavlinkVersion, Message};
use twocars::mavlink::signing::Signer;
use twocars::mavlink::Outbox;
use twocars_sim::autopilot::{hdg_cdeg, Plane, HOME};

const BINARY: &str = env!("CARGO_BIN_EXE_twocars-companion");

/// The companion on a free UDP port, killed on drop.
struct Companion {
    child: Child,
    port: u16,
}

impl Drop for Companion {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn free_port() -> u16 {
    let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
    socket.local_addr().unwrap().port()
}

fn start(extra: &[&str]) -> Companion {
    let port = free_port();
    let child = Command::new(BINARY)
        .arg("--udp")
        .arg(format!("127.0.0.1:{port}"))
        .args(extra)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Bound within moments of its start.
    std::thread::sleep(Duration::from_millis(300));
    Companion { child, port }
}

/// The autopilot's end: system 1, component 1.
struct Autopilot {
    socket: UdpSocket,
    outbox: Outbox,
    port: u16,
}

impl Autopilot {
    fn new(port: u16) -> Autopilot {
        let socket = UdpSocket::bind("127.0.0.1:0").unwrap();
        socket
            .set_read_timeout(Some(Duration::from_millis(20)))
            .unwrap();
        Autopilot {
            socket,
            outbox: Outbox::default(),
            port,
        }
    }

    fn send<M: mavlink::MessageData>(&mut self, sender: (u8, u8), message: &M) {
        let mut bytes = Vec::new();
        self.outbox
            .send_as(sender, message, &mut |f| bytes.extend_from_slice(f));
        self.socket
            .send_to(&bytes, ("127.0.0.1", self.port))
            .unwrap();
    }

    /// Every message received within `wait`, with its sender.
    fn receive(&self, wait: Duration) -> Vec<((u8, u8), MavMessage)> {
        let deadline = Instant::now() + wait;
        let mut out = Vec::new();
        let mut buf = [0u8; 4096];
        while Instant::now() < deadline {
            if let Ok(n) = self.socket.recv(&mut buf) {
                out.extend(split(&buf[..n]));
            }
        }
        out
    }
}

/// The MAVLink 2 frames of a datagram, decoded.
fn split(mut bytes: &[u8]) -> Vec<((u8, u8), MavMessage)> {
    let mut out = Vec::new();
    while let [0xFD, length, flags, ..] = *bytes {
        let total = 12 + usize::from(length) + if flags & 1 != 0 { 13 } else { 0 };
        let Some(frame) = bytes.get(..total) else {
            break;
        };
        let id = u32::from_le_bytes([frame[7], frame[8], frame[9], 0]);
        let payload = &frame[10..10 + usize::from(length)];
        if let Ok(m) = MavMessage::parse(MavlinkVersion::V2, id, payload) {
            out.push(((frame[5], frame[6]), m));
        }
        bytes = &bytes[total..];
    }
    out
}

fn fix(plane: &Plane, time_ms: u32, north: f64, east: f64, theta: f64) -> GLOBAL_POSITION_INT_DATA {
    let (lat, lon) = plane.fix(north, east);
    GLOBAL_POSITION_INT_DATA {
        time_boot_ms: time_ms,
        lat,
        lon,
        hdg: hdg_cdeg(theta),
        ..Default::default()
    }
}

#[test]
fn it_answers_an_autopilot_with_its_parameters_and_setpoints() {
    let companion = start(&["--param", "TC_V_PM=3", "--param", "TC_TIMEOUT=2"]);
    let mut autopilot = Autopilot::new(companion.port);
    autopilot.send((1, 1), &HEARTBEAT_DATA::default());
    let heard = autopilot.receive(Duration::from_millis(1500));
    assert!(
        heard
            .iter()
            .any(|(s, m)| *s == (1, 191) && matches!(m, MavMessage::HEARTBEAT(_))),
        "no heartbeat from (1, 191): {heard:?}"
    );
    autopilot.send(
        (255, 190),
        &PARAM_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 191,
        },
    );
    let values: Vec<(String, f32)> = autopilot
        .receive(Duration::from_millis(500))
        .into_iter()
        .filter_map(|(_, m)| match m {
            MavMessage::PARAM_VALUE(p) => Some((
                String::from_utf8_lossy(&p.param_id[..])
                    .trim_end_matches('\0')
                    .to_string(),
                p.param_value,
            )),
            _ => None,
        })
        .collect();
    assert_eq!(values.len(), twocars::mavlink::SPECS.len(), "{values:?}");
    assert!(values.contains(&("TC_V_PM".to_string(), 3.0)), "{values:?}");
    assert!(
        values.contains(&("TC_TIMEOUT".to_string(), 2.0)),
        "{values:?}"
    );
    // The paper's case 1 at ten times its scale: a setpoint to the autopilot for each own fix.
    let plane = Plane::new(HOME);
    let mut setpoints = 0;
    for k in 0..20u32 {
        let t = 1_000 + 50 * k;
        autopilot.send((2, 1), &fix(&plane, t, -30.0, 60.0, 0.0));
        autopilot.send((1, 1), &fix(&plane, t, 0.0, 0.0, 0.0));
        setpoints += autopilot
            .receive(Duration::from_millis(40))
            .iter()
            .filter(|(s, m)| *s == (1, 191) && matches!(m, MavMessage::SET_ATTITUDE_TARGET(_)))
            .count();
    }
    assert!(setpoints >= 18, "{setpoints} setpoints for 20 own fixes");
}

#[test]
fn with_a_key_it_answers_signed_frames_only() {
    let dir = std::env::temp_dir().join(format!("twocars-companion-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let key_file = dir.join("key.hex");
    let key = [0x5Au8; 32];
    let hex: String = key.iter().map(|b| format!("{b:02x}")).collect();
    std::fs::write(&key_file, hex).unwrap();
    let companion = start(&["--signing-key", key_file.to_str().unwrap()]);
    let mut autopilot = Autopilot::new(companion.port);
    let ask = PARAM_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 191,
    };
    autopilot.send((255, 190), &ask);
    let unsigned = autopilot.receive(Duration::from_millis(1200));
    assert!(
        !unsigned
            .iter()
            .any(|(_, m)| matches!(m, MavMessage::PARAM_VALUE(_))),
        "an unsigned request was answered"
    );
    autopilot.outbox.signer = Some(Signer::new(key, 1));
    autopilot.outbox.timestamp = twocars_clock_now();
    autopilot.send((255, 190), &ask);
    let signed = autopilot.receive(Duration::from_millis(500));
    let values = signed
        .iter()
        .filter(|(_, m)| matches!(m, MavMessage::PARAM_VALUE(_)))
        .count();
    assert_eq!(values, twocars::mavlink::SPECS.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The signing clock now: 10 us since 2015-01-01 UTC.
fn twocars_clock_now() -> u64 {
    let since_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap();
    since_unix.as_micros() as u64 / 10 - 1_420_070_400 * 100_000
}

#[test]
fn a_bad_parameter_or_no_link_is_refused_with_a_reason() {
    let out = Command::new(BINARY)
        .args(["--udp", "127.0.0.1:0", "--param", "TC_V_PM=0.5"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("TC_V_PM = 0.5, TC_W_PM = 2, TC_V_EM = 1, TC_W_EM = 1: TC: limits invalid"),
        "{said}"
    );
    let out = Command::new(BINARY).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("give one link"));
}

/// Two peers on the port (an autopilot and a ground station) both hear the unit.
#[test]
fn every_peer_that_spoke_hears_the_unit() {
    let companion = start(&[]);
    let mut autopilot = Autopilot::new(companion.port);
    let mut station = Autopilot::new(companion.port);
    autopilot.send((1, 1), &HEARTBEAT_DATA::default());
    station.send((255, 190), &HEARTBEAT_DATA::default());
    for peer in [&autopilot, &station] {
        let heard = peer.receive(Duration::from_millis(1500));
        assert!(
            heard
                .iter()
                .any(|(s, m)| *s == (1, 191) && matches!(m, MavMessage::HEARTBEAT(_))),
            "{heard:?}"
        );
    }
}
