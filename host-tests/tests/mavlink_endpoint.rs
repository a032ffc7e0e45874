//! The MAVLink endpoint (`twocars::mavlink::Endpoint`) against `../shared/CONTRACTS.md`: frames
//! in written from the specification (`twocars_sim::mavlink_spec`), frames out read back by the
//! specification's checksum and field layout, never by the `mavlink` crate the firmware uses.

use std::f64::consts::{FRAC_PI_2, PI};
use twocars::mavlink::{Endpoint, SPECS};
use twocars::{Guidance, Law, Limits, Policy, Variant};
use twocars_sim::autopilot::{hdg_cdeg, velocity_cm_s, Plane, HOME};
use twocars_sim::mavlink_spec::{
    follow_target_payload, param_request_list_payload, param_request_read_payload,
    param_set_payload, position_payload_at, position_payload_in_air, read_v2, v2_from,
    vfr_hud_payload, Sent, FOLLOW_TARGET, GLOBAL_POSITION_INT, HEARTBEAT, NAMED_VALUE_FLOAT,
    NAMED_VALUE_INT, PARAM_REQUEST_LIST, PARAM_REQUEST_READ, PARAM_SET, PARAM_VALUE,
    SENT_BY_ENDPOINT, SET_ATTITUDE_TARGET, SET_POSITION_TARGET_LOCAL_NED, STATUSTEXT, VFR_HUD,
};

/// MAV_SEVERITY_WARNING and MAV_SEVERITY_INFO.
const WARNING: u8 = 4;
const INFO: u8 = 6;
/// The paper's limits at ten times its lengths: v_pm, w_pm, v_em, w_em.
const SCALED: [f32; 4] = [20.0, 0.2, 10.0, 0.1];

/// An endpoint on a simulated link: our clock, and what it sent, read back frame by frame.
struct Link {
    endpoint: Endpoint,
    now_ms: u32,
    sequence: u8,
    plane: Plane,
}

impl Link {
    fn new() -> Self {
        Link {
            endpoint: Endpoint::new(),
            now_ms: 0,
            sequence: 0,
            plane: Plane::new(HOME),
        }
    }

    /// Feeds `bytes`; the frames the endpoint sent meanwhile.
    fn feed(&mut self, bytes: &[u8]) -> Vec<Sent> {
        let mut out = Vec::new();
        for &b in bytes {
            self.endpoint
                .receive(b, self.now_ms, &mut |f| out.extend_from_slice(f));
        }
        read_v2(&out, &SENT_BY_ENDPOINT).expect("the endpoint's frames are well formed")
    }

    fn poll(&mut self) -> Vec<Sent> {
        let mut out = Vec::new();
        self.endpoint
            .poll(self.now_ms, &mut |f| out.extend_from_slice(f));
        read_v2(&out, &SENT_BY_ENDPOINT).expect("the endpoint's frames are well formed")
    }

    /// A message from (`system`, `component`).
    fn send(&mut self, from: (u8, u8), message: (u32, u8), payload: &[u8]) -> Vec<Sent> {
        self.sequence = self.sequence.wrapping_add(1);
        let frame = v2_from(self.sequence, from, message, payload, false);
        self.feed(&frame)
    }

    /// A GLOBAL_POSITION_INT from `from` at (north, east) metres and heading `theta`, stamped
    /// `time_ms` on the sender's clock, moving at `speed` m/s.
    fn position(&mut self, from: (u8, u8), time_ms: u32, state: [f64; 3], speed: f64) -> Vec<Sent> {
        let (lat, lon) = self.plane.fix(state[0], state[1]);
        let (vx, vy) = velocity_cm_s(speed, state[2]);
        let payload = position_payload_at(time_ms, lat, lon, vx, vy, hdg_cdeg(state[2]));
        self.send(from, GLOBAL_POSITION_INT, &payload)
    }

    fn set(&mut self, name: &str, value: f32) -> Vec<Sent> {
        self.send(
            (255, 190),
            PARAM_SET,
            &param_set_payload((1, 191), name, value, 9),
        )
    }

    /// Sets the paper's limits at ten times its lengths (in an order each step keeps valid).
    fn scale_tenfold(&mut self) {
        for (name, value) in [
            ("TC_V_PM", SCALED[0]),
            ("TC_V_EM", SCALED[2]),
            ("TC_W_EM", SCALED[3]),
            ("TC_W_PM", SCALED[1]),
        ] {
            let replies = self.set(name, value);
            assert_eq!(param(&replies[0]), (name.to_string(), value), "{name}");
        }
    }
}

fn of(sent: &[Sent], id: (u32, u8)) -> Vec<&Sent> {
    sent.iter().filter(|s| s.id == id.0).collect()
}

/// PARAM_VALUE's name and value.
fn param(s: &Sent) -> (String, f32) {
    assert_eq!(s.id, PARAM_VALUE.0);
    (s.text(8, 16), s.f32(0))
}

/// STATUSTEXT's severity and text.
fn status(s: &Sent) -> (u8, String) {
    assert_eq!(s.id, STATUSTEXT.0);
    (s.u8(0), s.text(1, 50))
}

/// SET_ATTITUDE_TARGET's (target system, target component, type_mask, body yaw rate, thrust,
/// quaternion).
fn attitude(s: &Sent) -> (u8, u8, u8, f32, f32, [f32; 4]) {
    assert_eq!(s.id, SET_ATTITUDE_TARGET.0);
    let q = [s.f32(4), s.f32(8), s.f32(12), s.f32(16)];
    (s.u8(36), s.u8(37), s.u8(38), s.f32(28), s.f32(32), q)
}

/// NAMED_VALUE_FLOAT's name and value.
fn named(s: &Sent) -> (String, f32) {
    assert_eq!(s.id, NAMED_VALUE_FLOAT.0);
    (s.text(8, 10), s.f32(4))
}

const OWN: (u8, u8) = (1, 1);
const TARGET: (u8, u8) = (2, 1);
/// The paper's case 1 at ten times its lengths: pursuer at home heading east (pi / 2 clockwise
/// from north), the evader 30 m south and 60 m west of it, heading east.
const CASE1: ([f64; 3], [f64; 3]) = ([0.0, 0.0, FRAC_PI_2], [-30.0, -60.0, FRAC_PI_2]);

#[test]
fn the_heartbeat_names_an_onboard_controller_once_a_second() {
    let mut link = Link::new();
    let first = link.poll();
    assert_eq!(first.len(), 2);
    assert_eq!(named(&first[1]), ("TC_BADFRM".to_string(), 0.0));
    let h = &first[0];
    assert_eq!((h.id, h.system, h.component), (HEARTBEAT.0, 1, 191));
    // HEARTBEAT: custom_mode u32, type, autopilot, base_mode, system_status, mavlink_version.
    assert_eq!((h.u8(4), h.u8(5), h.u8(8)), (18, 8, 3));
    link.now_ms = 999;
    assert!(link.poll().is_empty());
    link.now_ms = 1000;
    assert_eq!(of(&link.poll(), HEARTBEAT).len(), 1);
}

/// A board on its fallback clock says so with the first heartbeat and every 30 s after; one on
/// its crystal says nothing.
#[test]
fn a_fallback_clock_is_announced_with_the_first_heartbeat_and_every_30_s() {
    use twocars::mavlink::{BOARD_NOTICE_MS, FALLBACK_CLOCK_TEXT};
    let fallback = twocars::protocol::message::BOARD_FALLBACK_CLOCK;
    let mut link = Link::new();
    link.endpoint.set_board_status(fallback);
    let mut notices = Vec::new();
    for second in 0..=60 {
        link.now_ms = second * 1000;
        for s in of(&link.poll(), STATUSTEXT) {
            assert_eq!(status(s), (WARNING, FALLBACK_CLOCK_TEXT.to_string()));
            notices.push(link.now_ms);
        }
    }
    assert_eq!(notices, [0, BOARD_NOTICE_MS, 2 * BOARD_NOTICE_MS]);
    assert!(FALLBACK_CLOCK_TEXT.len() <= 50);

    let mut crystal = Link::new();
    crystal.endpoint.set_board_status(0);
    for second in 0..=60 {
        crystal.now_ms = second * 1000;
        assert!(of(&crystal.poll(), STATUSTEXT).is_empty());
    }
}

#[test]
fn a_parameter_list_goes_out_as_the_transmit_queue_has_room() {
    let room = 120;
    let mut link = Link::new();
    link.poll();
    link.send(
        (255, 190),
        PARAM_REQUEST_LIST,
        &param_request_list_payload((1, 191)),
    );
    let (mut names, mut passes) = (Vec::new(), 0);
    loop {
        let mut out = Vec::new();
        link.endpoint
            .poll_within(link.now_ms, room, &mut |f| out.extend_from_slice(f));
        if out.is_empty() {
            break;
        }
        assert!(out.len() <= room, "{} bytes into {room}", out.len());
        let sent = read_v2(&out, &SENT_BY_ENDPOINT).unwrap();
        names.extend(sent.iter().map(|s| param(s).0));
        passes += 1;
    }
    assert_eq!(names, SPECS.map(|s| s.name.to_string()));
    assert!(passes > 1, "the list fit {room} bytes at once");
    // No room at all: nothing goes out, and the list waits.
    link.send(
        (255, 190),
        PARAM_REQUEST_LIST,
        &param_request_list_payload((1, 191)),
    );
    let mut out = Vec::new();
    link.endpoint
        .poll_within(link.now_ms, 0, &mut |f| out.extend_from_slice(f));
    assert!(out.is_empty());
    assert_eq!(link.poll().len(), SPECS.len());
}

#[test]
fn parameters_are_listed_read_and_set_as_the_contract_says() {
    let mut link = Link::new();
    link.poll(); // the first heartbeat
    let asked = link.send(
        (255, 190),
        PARAM_REQUEST_LIST,
        &param_request_list_payload((1, 191)),
    );
    assert!(asked.is_empty(), "the list goes out from the next poll on");
    let list = link.poll();
    let got: Vec<(String, f32)> = list.iter().map(param).collect();
    let want = [
        ("TC_V_PM", 2.0),
        ("TC_W_PM", 2.0),
        ("TC_V_EM", 1.0),
        ("TC_W_EM", 1.0),
        ("TC_TGT_SYSID", 2.0),
        ("TC_VEHICLE", 0.0),
        ("TC_POLICY", 1.0),
        ("TC_TIMEOUT", 1.0),
        ("TC_SYSID", 1.0),
        ("TC_CAPTURE", 0.0),
        ("TC_PERIOD", 0.0),
        ("TC_TGT_LAG", 0.0),
        ("TC_TGT_SIG", 0.0),
        ("TC_TGT_SIGH", 0.0),
        ("TC_LEAD", 0.0),
        ("TC_BANK_EFF", 1.0),
        ("TC_TEAM_SYS", 0.0),
        ("TC_TEAM_N", 0.0),
    ];
    assert_eq!(got, want.map(|(n, v)| (n.to_string(), v)));
    for (i, s) in list.iter().enumerate() {
        // param_count, param_index, param_type REAL32.
        assert_eq!(
            (s.u16(4), s.u16(6), s.u8(24)),
            (want.len() as u16, i as u16, 9)
        );
    }
    let by_name = link.send(
        (255, 190),
        PARAM_REQUEST_READ,
        &param_request_read_payload((1, 191), "TC_TIMEOUT", -1),
    );
    assert_eq!(param(&by_name[0]), ("TC_TIMEOUT".into(), 1.0));
    let by_index = link.send(
        (255, 190),
        PARAM_REQUEST_READ,
        &param_request_read_payload((1, 191), "", 4),
    );
    assert_eq!(param(&by_index[0]), ("TC_TGT_SYSID".into(), 2.0));
    // Addressed to another system: no answer.
    link.send(
        (255, 190),
        PARAM_REQUEST_LIST,
        &param_request_list_payload((7, 191)),
    );
    assert!(link.poll().is_empty());

    let ok = link.set("TC_TIMEOUT", 0.5);
    assert_eq!(ok.len(), 1);
    assert_eq!(param(&ok[0]), ("TC_TIMEOUT".into(), 0.5));
    for (name, value, kept) in [
        ("TC_V_EM", 3.0, 1.0),     // v_em above v_pm
        ("TC_W_PM", 0.5, 2.0),     // w_pm below w_em
        ("TC_VEHICLE", 5.0, 0.0),  // no such vehicle kind
        ("TC_BANK_EFF", 0.0, 1.0), // no turn at any bank
        ("TC_SYSID", 1.5, 1.0),    // not a whole number
        ("TC_TIMEOUT", f32::NAN, 0.5),
        ("TC_V_PM", 1.0e9, 2.0), // beyond the envelope
    ] {
        let r = link.set(name, value);
        assert_eq!(r.len(), 2, "{name} = {value}: {r:?}");
        assert_eq!(param(&r[0]), (name.to_string(), kept), "{name} = {value}");
        assert_eq!(status(&r[1]).0, WARNING, "{name} = {value}");
    }
    let unknown = link.set("TC_NOPE", 1.0);
    assert_eq!(unknown.len(), 1);
    assert_eq!(status(&unknown[0]).0, WARNING);
    assert_eq!(link.endpoint.counters().param_refusals, 8);
}

/// The paper's case 1 at ten times its lengths: the setpoint is the sampled law's, its sign
/// clockwise-positive, to the autopilot, with the upper value as TC_T.
#[test]
fn a_ground_vehicle_gets_the_laws_yaw_rate_and_the_capture_time() {
    let mut link = Link::new();
    link.scale_tenfold();
    let (pursuer, evader) = CASE1;
    assert!(link.position(TARGET, 0, evader, 10.0).is_empty());
    let sent = link.position(OWN, 0, pursuer, 20.0);
    let texts = of(&sent, STATUSTEXT);
    assert_eq!(
        status(texts[0]),
        (INFO, "TC: input valid, setpoints on".into())
    );
    let (system, component, mask, rate, thrust, _) = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]);
    assert_eq!((system, component, mask, thrust), (1, 1, 1 | 2 | 128, 1.0));
    let (name, upper) = named(of(&sent, NAMED_VALUE_FLOAT)[0]);
    assert_eq!(name, "TC_T");
    assert!((upper - 5.6575).abs() < 2e-3, "TC_T = {upper}");

    // The same states through the law directly, at the default period (100 ms).
    let limits = Limits::<f32>::new(SCALED[0], SCALED[1], SCALED[2], SCALED[3]).unwrap();
    let f = |s: [f64; 3]| {
        let (n, e) = link.plane.local(link.plane.fix(s[0], s[1]));
        [n as f32, e as f32, s[2] as f32]
    };
    let (p, e) = limits.states(f(pursuer), f(evader)).unwrap();
    let mut guidance = Guidance::new(
        Law::new(limits, Variant::Paper),
        0.1,
        twocars::Policy::Paper,
    )
    .unwrap()
    .with_policy(Policy::Flight);
    let want = SCALED[0] * guidance.decide(&p, &e).command.pursuer;
    assert!(want != 0.0);
    assert!((rate - want).abs() <= 1e-3 * want.abs(), "{rate} vs {want}");
}

/// `s` (metres north and east of home, heading) as the endpoint sees it: through a GPS fix
/// and back to the local plane, in f32.
fn through_a_fix(plane: &Plane, s: [f64; 3]) -> [f32; 3] {
    let (n, e) = plane.local(plane.fix(s[0], s[1]));
    [n as f32, e as f32, s[2] as f32]
}

/// TC_CAPTURE tells the flight policy the capture radius: near the pursuer its setpoint is the
/// law's told that radius, which differs from point capture there; out-of-range values are
/// refused.
#[test]
fn tc_capture_gives_the_flight_policy_its_capture_radius() {
    const RADIUS: f32 = 4.0;
    let limits = Limits::<f32>::new(SCALED[0], SCALED[1], SCALED[2], SCALED[3]).unwrap();
    let plane = Plane::new(HOME);
    let f = |s: [f64; 3]| through_a_fix(&plane, s);
    let rate = |radius: f32, pursuer: [f64; 3], evader: [f64; 3]| {
        let (p, e) = limits.states(f(pursuer), f(evader)).unwrap();
        let guidance = Guidance::new(Law::new(limits, Variant::Paper), 0.1, Policy::Flight)
            .unwrap()
            .with_capture_radius(radius)
            .unwrap();
        SCALED[0] * { guidance }.decide(&p, &e).command.pursuer
    };
    // The first evader on a ring about the pursuer where the radius changes the command.
    let pursuer = [0.0, 0.0, 0.0];
    let evader = (0..360)
        .map(|k| {
            let a = f64::from(k).to_radians();
            [9.0 * a.cos(), 9.0 * a.sin(), a + 1.0]
        })
        .find(|&e| (rate(RADIUS, pursuer, e) - rate(0.0, pursuer, e)).abs() > 1e-3)
        .expect("a state where the capture radius matters");

    let mut link = Link::new();
    link.scale_tenfold();
    for bad in [-1.0, f32::NAN, 101.0] {
        let refused = link.set("TC_CAPTURE", bad);
        assert_eq!(param(&refused[0]), ("TC_CAPTURE".to_string(), 0.0));
    }
    assert_eq!(param(&link.set("TC_CAPTURE", RADIUS)[0]).1, RADIUS);
    link.position(TARGET, 0, evader, 10.0);
    let sent = link.position(OWN, 0, pursuer, 20.0);
    let got = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]).3;
    let want = rate(RADIUS, pursuer, evader);
    assert!(
        (got - want).abs() <= 1e-3 * want.abs().max(1.0),
        "{got} vs {want}"
    );
}

/// TC_PERIOD sets the guidance's period where it is longer than the own states' spacing: the
/// setpoint is the law's at that period (a turn planned over TC_PERIOD), not over the spacing.
#[test]
fn tc_period_plans_turns_over_the_longer_period() {
    let limits = Limits::<f32>::new(SCALED[0], SCALED[1], SCALED[2], SCALED[3]).unwrap();
    let plane = Plane::new(HOME);
    let f = |s: [f64; 3]| through_a_fix(&plane, s);
    let rate = |dt: f32, pursuer: [f64; 3], evader: [f64; 3]| {
        let (p, e) = limits.states(f(pursuer), f(evader)).unwrap();
        let guidance = Guidance::new(Law::new(limits, Variant::Paper), dt, Policy::Flight).unwrap();
        SCALED[0] * { guidance }.decide(&p, &e).command.pursuer
    };
    // Nearly on the law's tangent: a short alignment, sampled over 0.1 s or over 0.5 s.
    let pursuer = [0.0, 0.0, 0.0];
    let evader = (1..200)
        .map(|k| [80.0, 0.02 * f64::from(k), 0.3])
        .find(|&e| (rate(0.5, pursuer, e) - rate(0.1, pursuer, e)).abs() > 1e-3)
        .expect("a state where the period matters");

    let mut link = Link::new();
    link.scale_tenfold();
    assert_eq!(param(&link.set("TC_PERIOD", 1.5)[0]).1, 0.0);
    assert_eq!(param(&link.set("TC_PERIOD", 0.5)[0]).1, 0.5);
    link.position(TARGET, 0, evader, 10.0);
    let sent = link.position(OWN, 0, pursuer, 20.0);
    let got = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]).3;
    let want = rate(0.5, pursuer, evader);
    assert!(
        (got - want).abs() <= 1e-3 * want.abs().max(1.0),
        "{got} vs {want}"
    );
}

#[test]
fn a_fixed_wing_gets_the_bank_angle_of_a_coordinated_turn_and_its_heading() {
    let mut link = Link::new();
    link.scale_tenfold();
    link.set("TC_VEHICLE", 1.0);
    let (pursuer, evader) = CASE1;
    link.position(TARGET, 0, evader, 10.0);
    let sent = link.position(OWN, 0, pursuer, 20.0);
    let (_, _, mask, yaw_rate, thrust, q) = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]);
    assert_eq!((mask, yaw_rate, thrust), (1 | 2 | 4, 0.0, 1.0));
    let [w, x, y, z] = q.map(f64::from);
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    assert!(
        pitch.abs() < 1e-6 && (yaw - FRAC_PI_2).abs() < 1e-3,
        "{pitch} {yaw}"
    );
    // The ground vehicle's rate on the same states gives the bank angle.
    let mut ground = Link::new();
    ground.scale_tenfold();
    ground.position(TARGET, 0, evader, 10.0);
    let rate =
        f64::from(attitude(of(&ground.position(OWN, 0, pursuer, 20.0), SET_ATTITUDE_TARGET)[0]).3);
    let want = (20.0 * rate / 9.80665).atan();
    assert!(
        want.abs() > 0.1 && (roll - want).abs() < 1e-4,
        "{roll} vs {want}"
    );
}

/// TC_VEHICLE 3 (ArduPlane in GUIDED): the roll alone (type_mask 198: pitch, yaw and throttle
/// left to its energy controller), the bank of the law's rate over TC_BANK_EFF.
#[test]
fn a_roll_only_fixed_wing_gets_the_bank_for_its_share_of_a_coordinated_turn() {
    let (pursuer, evader) = CASE1;
    let mut ground = Link::new();
    ground.scale_tenfold();
    ground.position(TARGET, 0, evader, 10.0);
    let rate =
        f64::from(attitude(of(&ground.position(OWN, 0, pursuer, 20.0), SET_ATTITUDE_TARGET)[0]).3);
    for efficiency in [1.0, 0.75] {
        let mut link = Link::new();
        link.scale_tenfold();
        link.set("TC_VEHICLE", 3.0);
        let echo = link.set("TC_BANK_EFF", efficiency);
        assert_eq!(param(&echo[0]), ("TC_BANK_EFF".into(), efficiency));
        link.position(TARGET, 0, evader, 10.0);
        let sent = link.position(OWN, 0, pursuer, 20.0);
        let (_, _, mask, yaw_rate, _, q) = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]);
        assert_eq!((mask, yaw_rate), (2 | 4 | 64 | 128, 0.0));
        let [w, x, y, z] = q.map(f64::from);
        let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
        let want = (20.0 * rate / (f64::from(efficiency) * 9.80665)).atan();
        assert!(
            want.abs() > 0.1 && (roll - want).abs() < 1e-4,
            "TC_BANK_EFF {efficiency}: {roll} vs {want}"
        );
    }
}

/// TC_VEHICLE 4 (PX4 in offboard): the bank as TC_VEHICLE 1, and pitch and thrust from the
/// unit's energy hold: level at the height it starts at, nose up when the aircraft sinks below
/// it, more throttle when VFR_HUD's airspeed falls below TC_V_PM.
#[test]
fn an_energy_holding_fixed_wing_pitches_for_height_and_throttles_for_airspeed() {
    let mut link = Link::new();
    link.scale_tenfold();
    link.set("TC_VEHICLE", 4.0);
    let (pursuer, evader) = CASE1;
    let (lat, lon) = link.plane.fix(pursuer[0], pursuer[1]);
    let (vx, vy) = velocity_cm_s(20.0, pursuer[2]);
    let hdg = hdg_cdeg(pursuer[2]);
    let own = |link: &mut Link, time_ms: u32, height_mm: i32, vz: i16| {
        link.position(TARGET, time_ms, evader, 10.0);
        let payload = position_payload_in_air(time_ms, [lat, lon], [vx, vy, vz], hdg, height_mm);
        let sent = link.send(OWN, GLOBAL_POSITION_INT, &payload);
        let (_, _, mask, _, thrust, q) = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]);
        let [w, x, y, z] = q.map(f64::from);
        let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
        let pitch = (2.0 * (w * y - z * x)).asin();
        (mask, roll, pitch, thrust)
    };
    let (mask, roll, pitch, level_thrust) = own(&mut link, 0, 100_000, 0);
    assert_eq!(mask, 1 | 2 | 4);
    assert!(pitch.abs() < 1e-3, "level at the height held: {pitch}");
    assert!((0.0..=1.0).contains(&level_thrust));
    // The bank is TC_VEHICLE 1's on the same states.
    let mut bank = Link::new();
    bank.scale_tenfold();
    bank.set("TC_VEHICLE", 1.0);
    bank.position(TARGET, 0, evader, 10.0);
    let sent = bank.position(OWN, 0, pursuer, 20.0);
    let [w, x, y, z] = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]).5.map(f64::from);
    let want = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    assert!(
        want.abs() > 0.1 && (roll - want).abs() < 1e-4,
        "{roll} vs {want}"
    );
    // 10 m below the height held and sinking at 1 m/s: nose up.
    let (_, _, pitch, _) = own(&mut link, 50, 90_000, 100);
    assert!(pitch > 0.2, "{pitch}");
    // VFR_HUD says 15 m/s, a quarter below TC_V_PM: more throttle than at 20 m/s.
    link.send(OWN, VFR_HUD, &vfr_hud_payload(20.0));
    let (_, _, _, at_speed) = own(&mut link, 100, 100_000, 0);
    link.send(OWN, VFR_HUD, &vfr_hud_payload(15.0));
    let (_, _, _, slow) = own(&mut link, 150, 100_000, 0);
    assert!(slow > at_speed + 0.4, "{slow} vs {at_speed}");
}

/// TC_VEHICLE 4 takes over at the autopilot's throttle: VFR_HUD's throttle before the first
/// engagement is where the energy hold's trim starts, so on the airspeed and height held the
/// first setpoint's thrust is that throttle (not the hold's own start at half).
#[test]
fn an_energy_holding_fixed_wing_takes_over_at_the_autopilots_throttle() {
    for (percent, want) in [(80u16, 0.8f32), (30, 0.3)] {
        let mut link = Link::new();
        link.scale_tenfold();
        link.set("TC_VEHICLE", 4.0);
        let (pursuer, evader) = CASE1;
        let mut hud = vfr_hud_payload(20.0);
        hud[18..20].copy_from_slice(&percent.to_le_bytes());
        link.send(OWN, VFR_HUD, &hud);
        let (lat, lon) = link.plane.fix(pursuer[0], pursuer[1]);
        let (vx, vy) = velocity_cm_s(20.0, pursuer[2]);
        link.position(TARGET, 0, evader, 10.0);
        let payload =
            position_payload_in_air(0, [lat, lon], [vx, vy, 0], hdg_cdeg(pursuer[2]), 100_000);
        let sent = link.send(OWN, GLOBAL_POSITION_INT, &payload);
        let thrust = attitude(of(&sent, SET_ATTITUDE_TARGET)[0]).4;
        assert!((thrust - want).abs() < 1e-3, "{percent} %: thrust {thrust}");
    }
}

/// TC_VEHICLE 2 (a PX4 rover, which takes no yaw rate): a velocity setpoint in the local NED
/// frame, at v_pm, its course the heading advanced by the law's turn over the guidance's period
/// (TC_PERIOD 0.2 s), at most a quarter turn.
#[test]
fn a_velocity_vehicle_gets_v_pm_along_the_heading_advanced_by_the_turn() {
    let mut link = Link::new();
    link.scale_tenfold();
    link.set("TC_VEHICLE", 2.0);
    link.set("TC_PERIOD", 0.2);
    let (pursuer, evader) = CASE1;
    link.position(TARGET, 0, evader, 10.0);
    let sent = link.position(OWN, 0, pursuer, 20.0);
    assert!(of(&sent, SET_ATTITUDE_TARGET).is_empty());
    let setpoints = of(&sent, SET_POSITION_TARGET_LOCAL_NED);
    assert_eq!(setpoints.len(), 1);
    let s = setpoints[0];
    // type_mask, target system and component, MAV_FRAME_LOCAL_NED.
    assert_eq!((s.u16(48), s.u8(50), s.u8(51), s.u8(52)), (3527, 1, 1, 1));
    let (vx, vy) = (f64::from(s.f32(16)), f64::from(s.f32(20)));
    assert!((vx.hypot(vy) - 20.0).abs() < 1e-3, "{vx} {vy}");
    // The ground vehicle's rate on the same states, over the 0.2 s period.
    let mut ground = Link::new();
    ground.scale_tenfold();
    ground.set("TC_PERIOD", 0.2);
    ground.position(TARGET, 0, evader, 10.0);
    let rate =
        f64::from(attitude(of(&ground.position(OWN, 0, pursuer, 20.0), SET_ATTITUDE_TARGET)[0]).3);
    let course = vy.atan2(vx);
    assert!(
        rate.abs() > 0.1 && (course - (FRAC_PI_2 + 0.2 * rate)).abs() < 1e-3,
        "course {course} vs heading {FRAC_PI_2} + 0.2 x {rate}"
    );
    // A period long enough to turn past a quarter: the course a quarter turn off the heading.
    link.set("TC_PERIOD", 1.0);
    link.position(TARGET, 50, evader, 10.0);
    let sent = link.position(OWN, 50, pursuer, 20.0);
    let s = of(&sent, SET_POSITION_TARGET_LOCAL_NED)[0];
    let course = f64::from(s.f32(20)).atan2(f64::from(s.f32(16)));
    let want = FRAC_PI_2 + FRAC_PI_2 * rate.signum();
    let apart = (course - want + PI).rem_euclid(2.0 * PI) - PI;
    assert!(apart.abs() < 1e-3, "{course} vs {want}");
}

/// No setpoint from a stale target: one WARNING when that begins (at the check that finds it),
/// one INFO when a fresh target ends it.
#[test]
fn a_stale_target_silences_the_setpoints_with_one_warning() {
    let mut link = Link::new();
    let (pursuer, evader) = ([0.0, 0.0, 0.0], [50.0, 50.0, 1.0]);
    link.position(TARGET, 0, evader, 1.0);
    assert_eq!(
        of(&link.position(OWN, 0, pursuer, 2.0), SET_ATTITUDE_TARGET).len(),
        1
    );
    link.now_ms = 1000;
    assert_eq!(
        of(&link.position(OWN, 1000, pursuer, 2.0), SET_ATTITUDE_TARGET).len(),
        1
    );
    link.now_ms = 1001;
    let stale = link.position(OWN, 1001, pursuer, 2.0);
    assert!(of(&stale, SET_ATTITUDE_TARGET).is_empty() && of(&stale, NAMED_VALUE_FLOAT).is_empty());
    assert_eq!(
        status(of(&stale, STATUSTEXT)[0]),
        (WARNING, "TC: target stale, no setpoint".into())
    );
    for t in 1002..1010 {
        link.now_ms = t;
        let sent = link.position(OWN, t, pursuer, 2.0);
        assert!(sent.is_empty(), "{sent:?}");
    }
    link.position(TARGET, 0, evader, 1.0);
    let back = link.position(OWN, 1010, pursuer, 2.0);
    assert_eq!(status(of(&back, STATUSTEXT)[0]).0, INFO);
    assert_eq!(of(&back, SET_ATTITUDE_TARGET).len(), 1);
    // The loop's check finds a target gone stale between own states.
    link.now_ms = 2011;
    let polled = link.poll();
    assert_eq!(status(of(&polled, STATUSTEXT)[0]).0, WARNING);
}

#[test]
fn invalid_fixes_and_headings_give_no_setpoint() {
    let mut link = Link::new();
    // Before the first fix (0, 0): nothing placed, no setpoint.
    let zero = position_payload_at(0, 0, 0, 0, 0, 9_000);
    link.send(TARGET, GLOBAL_POSITION_INT, &zero);
    let own_zero = link.send(OWN, GLOBAL_POSITION_INT, &zero);
    assert_eq!(
        status(&own_zero[0]),
        (WARNING, "TC: own fix invalid, no setpoint".into())
    );
    assert_eq!(link.endpoint.counters().target_refused, 1);
    // Heading unknown and standing still: no heading.
    let (lat, lon) = HOME;
    let still = position_payload_at(10, lat, lon, 0, 0, u16::MAX);
    assert!(of(
        &link.send(OWN, GLOBAL_POSITION_INT, &still),
        SET_ATTITUDE_TARGET
    )
    .is_empty());
    // A target from FOLLOW_TARGET with a NaN attitude and no velocity flag: refused.
    let nan = follow_target_payload(lat + 500, lon, [1.0, 0.0, 0.0], [f32::NAN; 4], 1 | 8);
    link.send((9, 1), FOLLOW_TARGET, &nan);
    assert_eq!(link.endpoint.counters().target_refused, 2);
    // Heading unknown but moving north-east: the course (45 degrees) is the heading; the
    // target from FOLLOW_TARGET's velocity.
    let good = follow_target_payload(lat + 500, lon, [0.0, 1.0, 0.0], [0.0; 4], 1 | 2);
    link.send((9, 1), FOLLOW_TARGET, &good);
    let moving = position_payload_at(20, lat, lon, 100, 100, u16::MAX);
    let sent = link.send(OWN, GLOBAL_POSITION_INT, &moving);
    assert_eq!(of(&sent, SET_ATTITUDE_TARGET).len(), 1, "{sent:?}");
    // No NaN in any setpoint.
    assert!(sent
        .iter()
        .all(|s| s.id != SET_ATTITUDE_TARGET.0 || attitude(s).3.is_finite()));
}

/// A target that jumps kilometres moves no setpoint until a second fix confirms it.
#[test]
fn a_target_jump_is_held_until_a_second_fix_agrees() {
    let mut link = Link::new();
    let pursuer = [0.0, 0.0, 0.0];
    link.position(TARGET, 0, [40.0, 30.0, 0.0], 1.0);
    assert_eq!(
        of(&link.position(OWN, 0, pursuer, 2.0), SET_ATTITUDE_TARGET).len(),
        1
    );
    link.now_ms = 100;
    link.position(TARGET, 100, [4_000.0, 3_000.0, 0.0], 1.0);
    let held = link.position(OWN, 100, pursuer, 2.0);
    assert!(of(&held, SET_ATTITUDE_TARGET).is_empty());
    assert_eq!(
        status(of(&held, STATUSTEXT)[0]),
        (WARNING, "TC: target jumped, no setpoint".into())
    );
    assert_eq!(link.endpoint.counters().target_jumps, 1);
    link.now_ms = 200;
    link.position(TARGET, 200, [4_000.1, 3_000.0, 0.0], 1.0);
    assert_eq!(
        of(&link.position(OWN, 200, pursuer, 2.0), SET_ATTITUDE_TARGET).len(),
        1
    );
}

/// The control period is the own states' spacing on the autopilot's clock; a target from
/// another system is not the target.
#[test]
fn the_period_follows_the_own_states_and_only_the_target_system_is_chased() {
    let mut link = Link::new();
    assert_eq!(link.endpoint.period_ms(), 100);
    let evader = [60.0, 0.0, PI];
    assert!(link.position((3, 1), 0, evader, 1.0).is_empty());
    assert_eq!(link.endpoint.counters().ignored, 1);
    let first = link.position(OWN, 1_000, [0.0, 0.0, 0.0], 2.0);
    assert_eq!(
        status(&first[0]),
        (WARNING, "TC: no target, no setpoint".into())
    );
    link.set("TC_TGT_SYSID", 3.0);
    link.position((3, 1), 0, evader, 1.0);
    for k in 1..4 {
        let sent = link.position(OWN, 1_000 + 20 * k, [0.0, 0.0, 0.0], 2.0);
        assert_eq!(of(&sent, SET_ATTITUDE_TARGET).len(), 1);
    }
    assert_eq!(link.endpoint.period_ms(), 20);
}

/// Corrupt frames are counted and dropped; random bytes never make a NaN setpoint or a
/// malformed frame.
#[test]
fn line_noise_is_counted_and_never_answered() {
    let mut link = Link::new();
    let mut frame = v2_from(
        1,
        TARGET,
        GLOBAL_POSITION_INT,
        &position_payload_at(0, HOME.0, HOME.1, 0, 0, 0),
        false,
    );
    let last = frame.len() - 1;
    frame[last] ^= 0x40;
    assert!(link.feed(&frame).is_empty());
    assert_eq!(link.endpoint.frame_counters().bad_checksum, 1);
    // The heartbeat's companion reports it.
    assert_eq!(named(of(&link.poll(), NAMED_VALUE_FLOAT)[0]).1, 1.0);
    let mut rng = twocars_sim::rng::Rng::new(29);
    let mut noise = Vec::new();
    for _ in 0..200_000 {
        noise.push((rng.next_u64() >> 32) as u8);
    }
    for chunk in noise.chunks(997) {
        link.now_ms += 10;
        link.position(TARGET, link.now_ms, [30.0, 10.0, 1.0], 1.0);
        let sent = link.feed(chunk);
        let mut own = link.position(OWN, link.now_ms, [0.0, 0.0, 0.0], 2.0);
        own.extend(sent);
        for s in of(&own, SET_ATTITUDE_TARGET) {
            assert!(attitude(s).3.is_finite());
        }
    }
    assert!(link.endpoint.counters().setpoints > 150);
}

/// Every STATUSTEXT fits MAVLink's 50 characters whole.
#[test]
fn status_texts_fit_fifty_characters() {
    use twocars::mavlink::{Halt, Refusal};
    let halts = [
        Halt::OwnFix,
        Halt::OwnHeading,
        Halt::NoTarget,
        Halt::TargetJump,
        Halt::TargetStale,
        Halt::OwnStale,
        Halt::Law(twocars::Status::OutOfRange),
    ];
    let refusals = [
        Refusal::UnknownName,
        Refusal::OutOfRange,
        Refusal::InvalidLimits,
        Refusal::LagBeyondTimeout,
    ];
    for text in halts
        .iter()
        .map(|h| h.text())
        .chain(refusals.iter().map(|r| r.text()))
    {
        assert!(text.len() <= 50, "{text:?} is {} characters", text.len());
    }
}

/// Far from the first fix the plane follows the pursuer: the same relative geometry 9 km away
/// gives the capture time it gives at home (without the move, the projection's error there
/// shifted it by 7.3e-4, relative).
#[test]
fn the_local_plane_follows_the_pursuer_far_from_the_first_fix() {
    let tc_t = |offset: [f64; 2]| {
        let mut link = Link::new();
        link.position(OWN, 0, [0.0, 0.0, 0.0], 2.0);
        // The engagement's geometry laid out about its own place, 100 ms later on both
        // clocks.
        link.plane = Plane::new(link.plane.fix(offset[0], offset[1]));
        link.now_ms = 100;
        link.position(TARGET, 100, [30.0, 40.0, 1.0], 1.0);
        let sent = link.position(OWN, 100, [0.0, 0.0, 0.3], 2.0);
        f64::from(named(of(&sent, NAMED_VALUE_FLOAT)[0]).1)
    };
    let home = tc_t([0.0, 0.0]);
    let far = tc_t([6_400.0, 6_400.0]);
    assert!(
        home.is_finite() && ((far - home) / home).abs() < 1e-4,
        "{home} vs {far}"
    );
}

/// TC_TGT_LAG places a target fix that long before it arrived, and the estimator carries the
/// target to the own fix's time: a fix 0.4 s late, of a target running straight north at
/// v_em, steers the pursuer as an on-time fix of where the target is now; without the lag it
/// steers toward where the target was.
#[test]
fn tc_tgt_lag_carries_a_late_target_to_the_own_fix() {
    let tc_t = |lag: f32, late: bool| {
        let mut link = Link::new();
        link.scale_tenfold();
        assert_eq!(param(&link.set("TC_TGT_LAG", lag)[0]).1, lag);
        let mut upper = f32::NAN;
        // The target's fixes every 100 ms on its clock; each arrives 0.4 s later when `late`.
        for k in 4..12_u32 {
            let t = 100 * k;
            link.now_ms = t;
            let seen = if late { t - 400 } else { t };
            let north = 80.0 + 10.0 * f64::from(seen) / 1000.0;
            link.position(TARGET, seen, [north, 60.0, 0.0], 10.0);
            let sent = link.position(OWN, t, [0.0, 0.0, 0.4], 20.0);
            if let Some(v) = of(&sent, NAMED_VALUE_FLOAT).first() {
                upper = named(v).1;
            }
        }
        upper
    };
    let on_time = tc_t(0.0, false);
    let carried = tc_t(0.4, true);
    let uncarried = tc_t(0.0, true);
    assert!(on_time.is_finite());
    assert!(
        (carried - on_time).abs() < 0.01 * on_time,
        "{carried} vs {on_time} on time"
    );
    assert!(
        (uncarried - on_time).abs() > 0.1,
        "the late fix as it came: {uncarried} vs {on_time}"
    );
}

/// TC_TGT_LAG and TC_LEAD stay below TC_TIMEOUT: a fix carried that far would be stale.
#[test]
fn a_lag_at_or_beyond_the_timeout_is_refused() {
    let mut link = Link::new();
    let replies = link.set("TC_TGT_LAG", 1.0);
    assert_eq!(param(&replies[0]), ("TC_TGT_LAG".into(), 0.0));
    assert_eq!(
        status(of(&replies, STATUSTEXT)[0]),
        (
            WARNING,
            "TC: lag and lead must stay below TC_TIMEOUT".into()
        )
    );
    assert_eq!(param(&link.set("TC_LEAD", 0.5)[0]).1, 0.5);
    let replies = link.set("TC_TIMEOUT", 0.5);
    assert_eq!(param(&replies[0]), ("TC_TIMEOUT".into(), 1.0));
    assert_eq!(param(&link.set("TC_TIMEOUT", 2.0)[0]).1, 2.0);
    assert_eq!(param(&link.set("TC_TGT_LAG", 1.0)[0]).1, 1.0);
}

/// A target from another sender, on another clock (FOLLOW_TARGET stamped 5,000 ms while the
/// positions are stamped 100 ms apart from 0), starts a new track: the setpoint follows it,
/// and then follows the first sender again when it speaks.
#[test]
fn a_target_from_another_sender_starts_its_own_track() {
    let tc_t = |sent: &[Sent]| named(of(sent, NAMED_VALUE_FLOAT)[0]).1;
    let mut link = Link::new();
    link.scale_tenfold();
    // 72 m away, then 14 m away by the other sender (within the 100 m a fix may move).
    link.position(TARGET, 100, [60.0, 40.0, 0.0], 10.0);
    let first = tc_t(&link.position(OWN, 100, [0.0, 0.0, 0.3], 20.0));
    link.now_ms = 100;
    let (lat, lon) = link.plane.fix(10.0, 10.0);
    let other = follow_target_payload(lat, lon, [1.0, 0.0, 0.0], [0.0; 4], 1 | 2);
    link.send((7, 1), FOLLOW_TARGET, &other);
    let followed = tc_t(&link.position(OWN, 200, [0.0, 0.0, 0.3], 20.0));
    link.now_ms = 200;
    link.position(TARGET, 300, [60.0, 40.0, 0.0], 10.0);
    let back = tc_t(&link.position(OWN, 300, [0.0, 0.0, 0.3], 20.0));
    assert!((followed - first).abs() > 1.0, "{first} then {followed}");
    assert!((back - first).abs() < 0.5, "{first} then back to {back}");
    assert_eq!(link.endpoint.counters().fixes_refused, 0);
}

/// On a unit whose clock runs ten times the autopilot's (an STM32F405 image in QEMU), a target
/// fix that came 500 of our milliseconds before the own fix came 50 of the autopilot's
/// before it: the rate, measured over the own fixes, places it there.
#[test]
fn a_fast_unit_clock_is_read_at_the_autopilots_rate() {
    let tc_t = |ours_per_theirs: u32| {
        let mut link = Link::new();
        link.scale_tenfold();
        let mut upper = f32::NAN;
        for k in 1..8_u32 {
            let t = 100 * k;
            // The target stamped and sent 50 ms (the autopilot's) before the own fix.
            link.now_ms = (t - 50) * ours_per_theirs;
            let north = 80.0 + 10.0 * f64::from(t - 50) / 1000.0;
            link.position(TARGET, t - 50, [north, 60.0, 0.0], 10.0);
            link.now_ms = t * ours_per_theirs;
            let sent = link.position(OWN, t, [0.0, 0.0, 0.4], 20.0);
            if let Some(v) = of(&sent, NAMED_VALUE_FLOAT).first() {
                upper = named(v).1;
            }
        }
        upper
    };
    let (alike, fast) = (tc_t(1), tc_t(10));
    assert!((fast - alike).abs() < 2e-3, "{fast} against {alike}");
}

/// A target's GLOBAL_POSITION_INT velocity is its track's speed: a target running north at
/// 4 m/s (v_em 10 m/s), its fixes 0.5 s apart and said to carry 2 m of noise, steers the
/// pursuer as fixes of where it is every 100 ms would. With vx = vy = 0 (a sender that fills
/// no velocity) the track takes its speed from the positions, starting at v_em.
#[test]
fn a_targets_velocity_is_its_tracks_speed() {
    let tc_t = |every_ms: u32, sigma: f32, reported: bool| {
        let mut link = Link::new();
        link.scale_tenfold();
        assert_eq!(param(&link.set("TC_TGT_SIG", sigma)[0]).1, sigma);
        let mut upper = f32::NAN;
        for k in 0..15_u32 {
            let t = 100 * k;
            link.now_ms = t;
            if t % every_ms == 0 {
                let north = 80.0 + 4.0 * f64::from(t) / 1000.0;
                let speed = if reported { 4.0 } else { 0.0 };
                link.position(TARGET, t, [north, 60.0, 0.0], speed);
            }
            let sent = link.position(OWN, t, [0.0, 0.0, 0.4], 20.0);
            if let Some(v) = of(&sent, NAMED_VALUE_FLOAT).first() {
                upper = named(v).1;
            }
        }
        upper
    };
    let every_fix = tc_t(100, 0.0, true);
    let with_speed = tc_t(500, 2.0, true);
    let without = tc_t(500, 2.0, false);
    assert!(every_fix.is_finite());
    assert!(
        (with_speed - every_fix).abs() < 1e-3 * every_fix,
        "{with_speed} vs {every_fix} from a fix every period"
    );
    assert!(
        (without - every_fix).abs() > 0.01 * every_fix,
        "without the velocity: {without} vs {every_fix}"
    );
}

/// The own vehicle's speed and turn rate under setpoints, each second, against TC_V_PM and
/// v_pm w_pm (20 m/s, 4 rad/s here): 25 m/s is said within 2 s, once; 15 m/s after 3 s (a
/// rover reaching speed is not); 5 rad/s of turn within 2 s; 20 m/s and 3 rad/s never.
#[test]
fn an_own_vehicle_off_its_speed_or_turn_rate_is_said_once() {
    let said = |speed: f64, turn_rate: f64| {
        let mut link = Link::new();
        link.scale_tenfold();
        let mut texts = Vec::new();
        for k in 0..60_u32 {
            let t = 100 * k;
            link.now_ms = t;
            link.position(TARGET, t, [300.0, 60.0, 0.0], 0.0);
            let heading = 0.4 + turn_rate * f64::from(t) / 1000.0;
            let sent = link.position(OWN, t, [0.0, 0.0, heading], speed);
            texts.extend(
                of(&sent, STATUSTEXT)
                    .into_iter()
                    .map(|s| (t, status(s)))
                    .filter(|(_, (_, text))| text.contains("own")),
            );
        }
        (texts, link.endpoint.counters().own_departures)
    };
    let (faster, count) = said(25.0, 0.0);
    assert_eq!(count, 1);
    assert_eq!(faster.len(), 1, "{faster:?}");
    let (t, (severity, text)) = &faster[0];
    assert!(*t <= 2_100, "said at {t} ms");
    assert_eq!(
        (*severity, text.as_str()),
        (WARNING, "TC: own speed over TC_V_PM by >10%")
    );
    let (slower, _) = said(15.0, 0.0);
    assert_eq!(slower.len(), 1, "{slower:?}");
    assert!((3_000..=3_100).contains(&slower[0].0), "{slower:?}");
    assert_eq!(slower[0].1 .1, "TC: own speed under TC_V_PM by >10%");
    let (turning, _) = said(20.0, 5.0);
    assert_eq!(turning.len(), 1, "{turning:?}");
    assert!(turning[0].0 <= 2_100, "{turning:?}");
    assert_eq!(turning[0].1 .1, "TC: own turn rate over v_pm*w_pm by >10%");
    for (speed, turn_rate) in [(20.0, 0.0), (21.5, 3.0), (18.5, -3.0)] {
        let (none, count) = said(speed, turn_rate);
        assert!(
            none.is_empty() && count == 0,
            "{speed} m/s, {turn_rate} rad/s: {none:?}"
        );
    }
}

/// NAMED_VALUE_INT's name and value.
fn named_int(s: &Sent) -> (String, i32) {
    assert_eq!(s.id, NAMED_VALUE_INT.0);
    (s.text(8, 10), s.i32(4))
}

/// In a team (TC_TEAM_SYS 1, TC_TEAM_N 3: systems 1 to 3) each period says the chaser's system
/// id (NAMED_VALUE_INT TC_CHASER), with a STATUSTEXT when it changes: this unit chases while
/// its teammates are far or unheard; a teammate near the target takes over after the dwell
/// (three full turns, 4.7 s here); a teammate heard more than TC_TIMEOUT ago gives the role
/// back. Without a team nothing is said.
#[test]
fn a_team_names_its_chaser_each_period_and_says_when_it_changes() {
    let mut link = Link::new();
    link.scale_tenfold();
    link.set("TC_TGT_SYSID", 9.0);
    let (target, mate) = ((9, 1), (2, 1));
    let (pursuer, evader) = CASE1;
    link.position(target, 0, evader, 0.0);
    let sent = link.position(OWN, 0, pursuer, 0.0);
    assert!(!of(&sent, SET_ATTITUDE_TARGET).is_empty());
    assert!(
        of(&sent, NAMED_VALUE_INT).is_empty(),
        "no team, no TC_CHASER"
    );
    link.set("TC_TEAM_SYS", 1.0);
    link.set("TC_TEAM_N", 3.0);
    // Every 100 ms: the target, the teammate (far for the first second, then 20 m behind the
    // target, then silent after 8 s), our own state; what each period said.
    let mut said: Vec<(u32, i32, Vec<String>)> = Vec::new();
    for k in 1..=120u32 {
        link.now_ms = 100 * k;
        link.position(target, 100 * k, evader, 0.0);
        let near = [evader[0] - 20.0, evader[1], evader[2]];
        let far = [5_000.0, 5_000.0, 0.0];
        match k {
            1..=10 => link.position(mate, 100 * k, far, 0.0),
            11..=80 => link.position(mate, 100 * k, near, 0.0),
            _ => Vec::new(),
        };
        let sent = link.position(OWN, 100 * k, pursuer, 0.0);
        let chasers = of(&sent, NAMED_VALUE_INT);
        assert_eq!(chasers.len(), 1, "one TC_CHASER a period");
        let (name, chaser) = named_int(chasers[0]);
        assert_eq!(name, "TC_CHASER");
        // The own vehicle stands still here: the departure watch's texts aside.
        let texts = of(&sent, STATUSTEXT)
            .iter()
            .map(|s| status(s).1)
            .filter(|text| text.starts_with("TC: team"))
            .collect();
        said.push((link.now_ms, chaser, texts));
    }
    let changes: Vec<(u32, i32, &str)> = said
        .iter()
        .filter(|(_, _, texts)| !texts.is_empty())
        .map(|(t, c, texts)| (*t, *c, texts[0].as_str()))
        .collect();
    assert_eq!(changes.len(), 3, "{changes:?}");
    assert_eq!(changes[0], (100, 1, "TC: team: this unit chases"));
    // The teammate near from 1.1 s: it takes over once our dwell of 4.7 s is over.
    let (t, chaser, text) = changes[1];
    assert!((4_700..=5_000).contains(&t), "{t}");
    assert_eq!(
        (chaser, text),
        (2, "TC: team: a teammate chases (TC_CHASER)")
    );
    // Silent from 8.1 s: past TC_TIMEOUT (1 s) it has no time and gives the role back.
    let (t, chaser, text) = changes[2];
    assert!((9_000..=9_200).contains(&t), "{t}");
    assert_eq!((chaser, text), (1, "TC: team: this unit chases"));
}
