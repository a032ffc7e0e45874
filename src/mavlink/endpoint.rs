//! The MAVLink guidance endpoint (docs/mavlink.md): bytes from the autopilot's link in, frames
//! for it out. Pure: the board feeds it received bytes and its millisecond clock, and queues what
//! it hands to `send`.
//!
//! - Own state: GLOBAL_POSITION_INT from (TC_SYSID, component 1). Each one is a control period:
//!   while the target is fresh the law runs for the pursuer and a SET_ATTITUDE_TARGET goes to
//!   the autopilot, with NAMED_VALUE_FLOAT "TC_T" (the upper value, s).
//! - Target: GLOBAL_POSITION_INT from system TC_TGT_SYSID, or FOLLOW_TARGET from anyone.
//! - The control period is the own states' spacing on the autopilot's clock (`time_boot_ms`),
//!   100 ms until two have arrived; the staleness limit TC_TIMEOUT runs on our clock.
//! - HEARTBEAT at 1 Hz, with NAMED_VALUE_FLOAT "TC_BADFRM": the frames dropped so far; where
//!   signing is on, also the signature refusals by kind ([`SIGNATURE_COUNTERS`]).
//! - Signing (`with_signing`, [`super::signing`]): every frame in must be signed under the
//!   key, ours are signed; an image built without a key says "signing off" once.
//! - A board on its fallback clock says so in a STATUSTEXT (WARNING) with the first heartbeat
//!   and every [`BOARD_NOTICE_MS`] after, so that a station that joins later sees it too.
//! - No setpoint from stale or invalid input: one STATUSTEXT (WARNING) saying why when that
//!   begins, one (INFO) when setpoints resume.
//! - A target fix that jumps farther than the evader could have gone since the last one (plus
//!   [`JUMP_SLACK_M`]) is held until a second fix agrees with it: one GPS glitch moves no
//!   setpoint. A fix after the track went stale starts a new track.
//! - A fix at latitude and longitude 0 is an autopilot's "no fix yet".
//!
//! The law runs in f32 (an FPU core); positions are metres in the local north-east plane of
//! [`crate::geodetic`] about the first own fix, moved to the own fix whenever that is
//! [`REANCHOR_M`] away.

use ::mavlink::dialects::common::{MavSeverity, FOLLOW_TARGET_DATA, GLOBAL_POSITION_INT_DATA};

use super::departure::DepartureWatch;
use super::energy::{Energy, EnergyHold, Flight};
use super::frame::{Frame, FrameReader};
use super::messages::{decode, extra_crc, Message};
use super::outgoing::{Outbox, COMPONENT, MAX_PARAM_VALUE};
use super::params::{index, Params, Refusal, SPECS};
use super::setpoint::{setpoint, Address, Setpoint, Turn, FIXED_WING_ENERGY};
use super::signing::{SignatureRefusal, Signer, Verifier, KEY_LEN, LINK_ID, PROVISIONED};
#[cfg(feature = "mavlink-team")]
use super::team::{MateFix, TeamWatch, CHASER};
use super::tracking::{ClockRate, Tracking};
use crate::estimate::Stale;
use crate::geodetic::{
    course, heading_from_cdeg, valid_fix, yaw_from_quaternion, LocalFrame, HEADING_UNKNOWN,
};
use crate::guidance::{Guidance, Policy};
use crate::law::capture::Variant;
use crate::law::{Decision, Law};
use crate::status::Status;

/// The autopilot's component id (MAV_COMP_ID_AUTOPILOT1): own state comes from it, setpoints go
/// to it.
pub const AUTOPILOT_COMPONENT: u8 = 1;
/// The control period until the own states' spacing is known, ms.
pub const DEFAULT_PERIOD_MS: u32 = 100;
/// The heartbeat's period, ms.
pub const HEARTBEAT_MS: u32 = 1000;
/// The NAMED_VALUE_FLOAT sent with each heartbeat: frames dropped so far (bad checksum,
/// unsupported flags, fields that do not decode).
pub const BAD_FRAMES: &str = "TC_BADFRM";
/// The NAMED_VALUE_FLOATs sent with each heartbeat where signing is on: frames refused
/// unsigned, with a bad signature, and with a timestamp not newer than their stream's last.
/// Each is also in [`BAD_FRAMES`].
pub const SIGNATURE_COUNTERS: [&str; 3] = ["TC_NOSIG", "TC_BADSIG", "TC_OLDSIG"];
/// The STATUSTEXT (NOTICE) an image built without a key sends with its first heartbeat.
pub const UNSIGNED_TEXT: &str = "TC: signing off, any sender can steer";
/// The period of the fallback clock's STATUSTEXT, ms.
pub const BOARD_NOTICE_MS: u32 = 30_000;
/// The fallback clock's STATUSTEXT.
pub const FALLBACK_CLOCK_TEXT: &str = "TC: fallback clock, crystal or PLL did not start";
/// The local plane follows the own fix once it is this far (m) from the plane's reference:
/// within it a 100 m baseline is off by at most 1.6e-4 (relative) at 45 degrees (docs/mavlink.md).
pub const REANCHOR_M: f32 = 1_000.0;
/// A target fix farther than this (m) plus twice the evader's run since the last one is a jump.
pub const JUMP_SLACK_M: f32 = 100.0;
/// Below this ground speed (cm/s, MAVLink's velocity unit) a course is noise.
const MIN_COURSE_SPEED_CM_S: f32 = 20.0;
/// FOLLOW_TARGET's capability bits: position, velocity, attitude and rates.
const FOLLOW_POSITION: u8 = 1 << 0;
const FOLLOW_VELOCITY: u8 = 1 << 1;
const FOLLOW_ATTITUDE: u8 = 1 << 3;
/// Why no setpoint went out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Halt {
    /// The own fix is missing, zero or outside +-90 / +-180 degrees.
    OwnFix,
    /// The own heading is unknown (hdg unknown and too slow for a course).
    OwnHeading,
    /// No target state yet.
    NoTarget,
    /// The target jumped; waiting for a second fix to agree.
    TargetJump,
    /// The target's state is older than TC_TIMEOUT.
    TargetStale,
    /// The own state is older than TC_TIMEOUT.
    OwnStale,
    /// The law refused the states (non-finite or outside its envelope).
    Law(Status),
}

impl Halt {
    /// The STATUSTEXT's words.
    pub fn text(self) -> &'static str {
        match self {
            Halt::OwnFix => "TC: own fix invalid, no setpoint",
            Halt::OwnHeading => "TC: own heading unknown, no setpoint",
            Halt::NoTarget => "TC: no target, no setpoint",
            Halt::TargetJump => "TC: target jumped, no setpoint",
            Halt::TargetStale => "TC: target stale, no setpoint",
            Halt::OwnStale => "TC: own state stale, no setpoint",
            Halt::Law(_) => "TC: states outside the envelope, no setpoint",
        }
    }
}

/// What the endpoint counted (wrapping).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct EndpointCounters {
    /// Setpoints sent.
    pub setpoints: u32,
    /// Own states without a setpoint (stale or invalid input).
    pub halted: u32,
    /// Target fixes taken.
    pub target_fixes: u32,
    /// Target fixes refused (invalid position or heading).
    pub target_refused: u32,
    /// Target jumps.
    pub target_jumps: u32,
    /// Checked frames whose fields did not decode.
    pub malformed: u32,
    /// Messages not for us (other systems' requests, positions of other vehicles).
    pub ignored: u32,
    /// PARAM_SETs refused.
    pub param_refusals: u32,
    /// Frames refused where signing is on: unsigned, badly signed, and with a timestamp not
    /// newer than their stream's last (replays).
    pub unsigned: u32,
    /// See `unsigned`.
    pub bad_signature: u32,
    /// See `unsigned`.
    pub stale_signature: u32,
    /// Setpoints made with no new target fix since the one before: the target coasted on its
    /// track ([`crate::estimate`]).
    pub target_coasted: u32,
    /// Fixes the estimator refused (either vehicle): out of order or outliers of the track.
    pub fixes_refused: u32,
    /// Times the own vehicle was said to depart from TC_V_PM or v_pm w_pm
    /// ([`super::departure`]).
    pub own_departures: u32,
}

/// A vehicle's last fix: degE7, heading (rad, clockwise from north), speed over ground (m/s,
/// where the message carries it), the sender's clock and ours (ms).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Fix {
    lat: i32,
    lon: i32,
    heading: f32,
    speed: Option<f32>,
    sent_ms: u32,
    arrived_ms: u32,
}

/// The target's last fix and whether a jump still waits for confirmation.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Target {
    fix: Fix,
    confirmed: bool,
    /// Who sent it: system and component, and whether by FOLLOW_TARGET (each sender's clock
    /// is its own).
    source: (u8, u8, bool),
}

/// Whether setpoints are flowing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Health {
    /// Nothing evaluated yet.
    Starting,
    /// The last own state got a setpoint.
    Active,
    /// No setpoint, for this reason (announced once).
    Halted(Halt),
}

/// The endpoint: the frame reader and the session.
#[derive(Clone, Debug)]
pub struct Endpoint {
    reader: FrameReader,
    session: Session,
}

/// Everything but the frame reader (a frame borrows the reader's buffer while it is handled).
#[derive(Clone, Debug)]
struct Session {
    params: Params,
    guidance: Option<Guidance<f32>>,
    /// Both vehicles' tracks (TC_TGT_LAG, TC_TGT_SIG, TC_TGT_SIGH, TC_LEAD).
    tracking: Option<Tracking>,
    /// The target's last fix not yet in its track, and whether it starts a new track: placed
    /// on the autopilot's clock by the next own fix.
    pending_target: Option<(Fix, bool)>,
    /// The autopilot's clock against ours, for that placement; whether its first measurement
    /// came since the target's last placement (its track then restarts).
    clock: ClockRate,
    clock_measured: bool,
    period_ms: u32,
    origin: Option<LocalFrame>,
    own: Option<Fix>,
    /// The own aircraft's height, climb and ground speed at the last own state, and the
    /// seconds since the one before (TC_VEHICLE 4's energy hold).
    flight: Option<(Flight, f32)>,
    /// The autopilot's last VFR_HUD airspeed (m/s) and when it arrived (our ms).
    airspeed: Option<(f32, u32)>,
    energy: EnergyHold,
    /// The own vehicle's speed and turn rate under setpoints, against TC_V_PM and v_pm w_pm.
    departure: DepartureWatch,
    target: Option<Target>,
    health: Health,
    last_status: Status,
    outbox: Outbox,
    last_heartbeat_ms: Option<u32>,
    /// The board's status flags (`crate::protocol::message::BOARD_FALLBACK_CLOCK`).
    board: u32,
    last_board_notice_ms: Option<u32>,
    /// Checks incoming signatures where signing is on.
    verifier: Option<Verifier>,
    /// Whether the first heartbeat says the link is unsigned (an image built without a key).
    announce_unsigned: bool,
    /// The signing clock at our millisecond 0 (10 us since 2015-01-01).
    signing_base: u64,
    /// The next PARAM_VALUE of a PARAM_REQUEST_LIST still being answered.
    listing: Option<usize>,
    counters: EndpointCounters,
    /// The team of pursuers (TC_TEAM_SYS, TC_TEAM_N) and the own and target states (m, rad,
    /// the local plane) the law last decided on.
    #[cfg(feature = "mavlink-team")]
    team: TeamWatch,
    #[cfg(feature = "mavlink-team")]
    decided_on: Option<([f32; 3], [f32; 3])>,
}

impl Default for Endpoint {
    fn default() -> Self {
        Self::new()
    }
}

impl Endpoint {
    /// An endpoint with the default parameters, before any fix.
    pub fn new() -> Self {
        let params = Params::new();
        let mut session = Session {
            params,
            guidance: None,
            tracking: None,
            pending_target: None,
            clock: ClockRate::new(),
            clock_measured: false,
            period_ms: DEFAULT_PERIOD_MS,
            origin: None,
            own: None,
            flight: None,
            airspeed: None,
            departure: DepartureWatch::default(),
            energy: EnergyHold::new(),
            target: None,
            health: Health::Starting,
            last_status: Status::Ok,
            outbox: Outbox::default(),
            last_heartbeat_ms: None,
            board: 0,
            last_board_notice_ms: None,
            verifier: None,
            announce_unsigned: false,
            signing_base: 0,
            listing: None,
            counters: EndpointCounters::default(),
            #[cfg(feature = "mavlink-team")]
            team: TeamWatch::new(&params),
            #[cfg(feature = "mavlink-team")]
            decided_on: None,
        };
        session.rebuild_guidance();
        Endpoint {
            reader: FrameReader::new(),
            session,
        }
    }

    /// The same endpoint with MAVLink 2 signing on (docs/mavlink.md, "Signing"): frames in
    /// must carry a good signature under `key` and a timestamp newer than their stream's last;
    /// ours are signed with `link_id`. `initial_timestamp` (10 us since 2015-01-01) starts the
    /// signing clock: the build's time, say; it moves up to the newest timestamp accepted.
    pub fn with_signing(mut self, key: [u8; KEY_LEN], link_id: u8, initial_timestamp: u64) -> Self {
        let s = &mut self.session;
        s.verifier = Some(Verifier::new(key, initial_timestamp));
        s.outbox.signer = Some(Signer::new(key, link_id));
        s.signing_base = initial_timestamp;
        self
    }

    /// The endpoint a firmware image runs: signing on with the key it was built with
    /// ([`PROVISIONED`]); without one, unsigned, and its first heartbeat says so
    /// ([`UNSIGNED_TEXT`]).
    pub fn provisioned() -> Self {
        match PROVISIONED {
            Some((key, time)) => Self::new().with_signing(key, LINK_ID, time),
            None => {
                let mut endpoint = Self::new();
                endpoint.session.announce_unsigned = true;
                endpoint
            }
        }
    }

    /// Whether signing is on.
    pub fn signing(&self) -> bool {
        self.session.verifier.is_some()
    }

    /// The board's status flags ([`crate::serial::Board::status_flags`]), for the STATUSTEXT
    /// that announces a fallback clock.
    pub fn set_board_status(&mut self, flags: u32) {
        self.session.board = flags;
    }

    /// The parameters now.
    pub fn params(&self) -> &Params {
        &self.session.params
    }

    /// Sets the parameter named `name` as a PARAM_SET would, without a reply: a host that
    /// configures its endpoint before the link starts (the companion's `--param`).
    ///
    /// # Errors
    /// The [`Refusal`] a PARAM_SET would get; the old value stays.
    pub fn set_param(&mut self, name: &[u8], value: f32) -> Result<(), Refusal> {
        let i = Params::find(name).ok_or(Refusal::UnknownName)?;
        self.session.apply_param(i, value)
    }

    /// Sets the parameters `values` (index, value) as one set, without a reply: a host that
    /// configures its endpoint before the link starts (the companion's `--param` and
    /// `--params`), in whatever order they were written ([`Params::set_all`]).
    ///
    /// # Errors
    /// As [`Params::set_all`]; every old value stays.
    pub fn set_params(&mut self, values: &[(usize, f32)]) -> Result<(), (Option<usize>, Refusal)> {
        self.session.params.set_all(values)?;
        self.session.rebuild_guidance();
        Ok(())
    }

    /// What the endpoint counted.
    pub fn counters(&self) -> EndpointCounters {
        let mut counters = self.session.counters;
        if let Some(t) = &self.session.tracking {
            counters.target_coasted = t.counters().coasted;
            counters.fixes_refused = t.counters().refused;
        }
        counters
    }

    /// What the frame reader counted.
    pub fn frame_counters(&self) -> super::frame::FrameCounters {
        self.reader.counters
    }

    /// Frames sent so far.
    pub fn frames_sent(&self) -> u32 {
        self.session.outbox.frames
    }

    /// The control period in use, ms.
    pub fn period_ms(&self) -> u32 {
        self.session.period_ms
    }

    /// One received byte at our time `now_ms`; frames to send go to `send`.
    pub fn receive(&mut self, byte: u8, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        let Endpoint { reader, session } = self;
        if let Some(frame) = reader.push(byte, extra_crc) {
            if session.signature_ok(&frame) {
                session.tick_signing_clock(now_ms);
                session.handle(&frame, now_ms, send);
            }
        }
    }

    /// The heartbeat (1 Hz), the staleness check and the rest of a parameter list, at our
    /// time `now_ms`: call it every pass of the loop. Where what is sent goes to a queue of
    /// bounded room, call [`Endpoint::poll_within`] instead.
    pub fn poll(&mut self, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        self.poll_within(now_ms, usize::MAX, send);
    }

    /// [`Endpoint::poll`] where `room` bytes are free in the transmit queue: a parameter list
    /// goes out only as far as it fits, and goes on at the next pass, so a PARAM_REQUEST_LIST
    /// never overflows the queue (the autopilot's way, ArduPilot's deferred parameter sends).
    pub fn poll_within(&mut self, now_ms: u32, room: usize, send: &mut dyn FnMut(&[u8])) {
        let mut left = room;
        self.poll_periodic(now_ms, &mut |frame| {
            left = left.saturating_sub(frame.len());
            send(frame);
        });
        self.session.continue_listing(left, send);
    }

    fn poll_periodic(&mut self, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        let s = &mut self.session;
        s.tick_signing_clock(now_ms);
        let due = s
            .last_heartbeat_ms
            .is_none_or(|last| now_ms.wrapping_sub(last) >= HEARTBEAT_MS);
        if due {
            s.last_heartbeat_ms = Some(now_ms);
            s.outbox.heartbeat(s.sysid(), send);
            let f = self.reader.counters;
            let c = &s.counters;
            let bad = f
                .bad_checksum
                .wrapping_add(f.bad_flags)
                .wrapping_add(c.malformed)
                .wrapping_add(c.unsigned)
                .wrapping_add(c.bad_signature)
                .wrapping_add(c.stale_signature);
            s.outbox
                .named_value(s.sysid(), now_ms, BAD_FRAMES, bad as f32, send);
            if s.verifier.is_some() {
                let counts = [c.unsigned, c.bad_signature, c.stale_signature];
                for (name, count) in SIGNATURE_COUNTERS.into_iter().zip(counts) {
                    s.outbox
                        .named_value(s.sysid(), now_ms, name, count as f32, send);
                }
            }
            s.board_notice(now_ms, send);
            if core::mem::take(&mut s.announce_unsigned) {
                let severity = MavSeverity::MAV_SEVERITY_NOTICE;
                s.outbox
                    .status_text(s.sysid(), severity, UNSIGNED_TEXT, send);
            }
        }
        if s.health == Health::Active {
            if let Some(halt) = s.stale(now_ms) {
                s.halt(halt, send);
            }
        }
    }
}

impl Session {
    /// Whether `frame` passes the signature check (always, where signing is off); a refusal is
    /// counted.
    fn signature_ok(&mut self, frame: &Frame<'_>) -> bool {
        let Some(verifier) = self.verifier.as_mut() else {
            return true;
        };
        let sender = (frame.system, frame.component);
        let counter = match verifier.check(sender, frame.signed, frame.signature) {
            Ok(()) => return true,
            Err(SignatureRefusal::Unsigned) => &mut self.counters.unsigned,
            Err(SignatureRefusal::BadSignature) => &mut self.counters.bad_signature,
            Err(SignatureRefusal::Stale) => &mut self.counters.stale_signature,
        };
        *counter = counter.wrapping_add(1);
        false
    }

    /// Our signing clock at `now_ms`: the base plus our milliseconds, or the newest timestamp
    /// accepted where that is later (the spec's rule for a system without a real-time clock).
    fn tick_signing_clock(&mut self, now_ms: u32) {
        if let Some(verifier) = &self.verifier {
            let ours = self.signing_base + u64::from(now_ms) * 100;
            self.outbox.timestamp = ours.max(verifier.newest);
        }
    }

    /// The parameter list's next PARAM_VALUEs, while each fits in `room` bytes.
    fn continue_listing(&mut self, mut room: usize, send: &mut dyn FnMut(&[u8])) {
        while let Some(i) = self.listing {
            if i >= SPECS.len() {
                self.listing = None;
            } else if room < MAX_PARAM_VALUE {
                return;
            } else {
                let system = self.sysid();
                self.outbox
                    .param_value(system, &self.params, i, &mut |frame| {
                        room = room.saturating_sub(frame.len());
                        send(frame);
                    });
                self.listing = Some(i + 1);
            }
        }
    }

    /// The fallback clock's STATUSTEXT, where the board runs on it and the last one is
    /// [`BOARD_NOTICE_MS`] old (or none went out yet).
    fn board_notice(&mut self, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        let fallback = self.board & crate::protocol::message::BOARD_FALLBACK_CLOCK != 0;
        let due = self
            .last_board_notice_ms
            .is_none_or(|last| now_ms.wrapping_sub(last) >= BOARD_NOTICE_MS);
        if fallback && due {
            self.last_board_notice_ms = Some(now_ms);
            let severity = MavSeverity::MAV_SEVERITY_WARNING;
            self.outbox
                .status_text(self.sysid(), severity, FALLBACK_CLOCK_TEXT, send);
        }
    }

    fn sysid(&self) -> u8 {
        self.params.byte(index::SYSID)
    }

    /// The guidance's period for own states `spacing_ms` apart: TC_PERIOD where longer, s.
    fn guidance_period(&self, spacing_ms: u32) -> f32 {
        let spacing = spacing_ms as f32 / 1000.0;
        self.params
            .get(index::PERIOD)
            .map_or(spacing, |p| p.max(spacing))
    }

    /// The guidance for the parameters' limits and policy, with the current period.
    fn rebuild_guidance(&mut self) {
        let policy = match self.params.byte(index::POLICY) {
            0 => Policy::Paper,
            _ => Policy::Flight,
        };
        let period = self.guidance_period(self.period_ms);
        let capture = self.params.get(index::CAPTURE).unwrap_or(0.0);
        // TC_CAPTURE is within 0 to 100 m by `Params::set`, which f32 coordinates always hold.
        self.guidance = self.params.limits().and_then(|limits| {
            Guidance::new(Law::new(limits, Variant::Paper), period, policy)
                .and_then(|g| g.with_capture_radius(capture))
                .ok()
        });
        self.tracking = Tracking::new(&self.params);
        #[cfg(feature = "mavlink-team")]
        {
            self.team = TeamWatch::new(&self.params);
        }
    }

    fn handle(&mut self, frame: &Frame<'_>, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        let message = match decode(frame) {
            Ok(m) => m,
            Err(_) => {
                self.counters.malformed = self.counters.malformed.wrapping_add(1);
                return;
            }
        };
        let for_us = |system: u8, component: u8| {
            (system == 0 || system == self.sysid()) && (component == 0 || component == COMPONENT)
        };
        match message {
            Message::GlobalPosition(m) => {
                if frame.system == self.sysid() && frame.component == AUTOPILOT_COMPONENT {
                    self.own_state(&m, now_ms, send);
                } else if frame.system == self.params.byte(index::TGT_SYSID) {
                    let fix = position_fix(&m, now_ms);
                    self.target_fix(fix, now_ms, (frame.system, frame.component, false));
                } else if !self.teammate_fix(frame.system, &m, now_ms) {
                    self.counters.ignored = self.counters.ignored.wrapping_add(1);
                }
            }
            Message::FollowTarget(m) => {
                let fix = follow_fix(&m, now_ms);
                self.target_fix(fix, now_ms, (frame.system, frame.component, true));
            }
            Message::ParamSet(m) if for_us(m.target_system, m.target_component) => {
                self.param_set(&m.param_id[..], m.param_value, send);
            }
            Message::ParamRequestRead(m) if for_us(m.target_system, m.target_component) => {
                let found = usize::try_from(m.param_index)
                    .ok()
                    .filter(|&i| i < SPECS.len())
                    .or_else(|| Params::find(&m.param_id[..]));
                match found {
                    Some(i) => self.outbox.param_value(self.sysid(), &self.params, i, send),
                    None => self.counters.ignored = self.counters.ignored.wrapping_add(1),
                }
            }
            Message::ParamRequestList(m) if for_us(m.target_system, m.target_component) => {
                // Sent from the next poll on, as the transmit queue has room.
                self.listing = Some(0);
            }
            Message::VfrHud(m) => {
                if frame.system == self.sysid() && frame.component == AUTOPILOT_COMPONENT {
                    self.airspeed = Some((m.airspeed, now_ms));
                    // Percent; the energy hold takes over at it (until it has flown).
                    self.energy.seed_throttle(f32::from(m.throttle) / 100.0);
                }
            }
            Message::Heartbeat(_) => {}
            _ => self.counters.ignored = self.counters.ignored.wrapping_add(1),
        }
    }

    fn param_set(&mut self, name: &[u8], value: f32, send: &mut dyn FnMut(&[u8])) {
        let Some(i) = Params::find(name) else {
            self.refuse(Refusal::UnknownName, send);
            return;
        };
        match self.apply_param(i, value) {
            Ok(()) => self.outbox.param_value(self.sysid(), &self.params, i, send),
            Err(refusal) => {
                self.outbox.param_value(self.sysid(), &self.params, i, send);
                self.refuse(refusal, send);
            }
        }
    }

    /// Sets parameter `i` and rebuilds what depends on it; the refusal where it stays.
    fn apply_param(&mut self, i: usize, value: f32) -> Result<(), Refusal> {
        self.params.set(i, value)?;
        let rebuilds = [index::POLICY, index::CAPTURE, index::PERIOD, index::TIMEOUT];
        if i <= index::W_EM || i >= index::TGT_LAG || rebuilds.contains(&i) {
            self.rebuild_guidance();
        }
        Ok(())
    }

    fn refuse(&mut self, refusal: Refusal, send: &mut dyn FnMut(&[u8])) {
        self.counters.param_refusals = self.counters.param_refusals.wrapping_add(1);
        let severity = MavSeverity::MAV_SEVERITY_WARNING;
        self.outbox
            .status_text(self.sysid(), severity, refusal.text(), send);
    }

    /// A target fix (`None`: invalid): taken, or held as a jump until confirmed.
    fn target_fix(&mut self, fix: Option<Fix>, now_ms: u32, source: (u8, u8, bool)) {
        let Some(fix) = fix else {
            self.counters.target_refused = self.counters.target_refused.wrapping_add(1);
            return;
        };
        self.counters.target_fixes = self.counters.target_fixes.wrapping_add(1);
        let timeout = self.params.timeout_ms();
        // A fix after a stale one starts a new track: only a live track can jump.
        let live = self
            .target
            .filter(|last| now_ms.wrapping_sub(last.fix.arrived_ms) <= timeout);
        // The limits validated when the guidance was built: not again per fix.
        let limits = self.guidance.as_ref().map(|g| g.law().limits);
        let jumped = match (live, self.origin, limits) {
            (Some(last), Some(origin), Some(limits)) => {
                let run_s = now_ms.wrapping_sub(last.fix.arrived_ms) as f32 / 1000.0;
                let reach = JUMP_SLACK_M + 2.0 * limits.evader.v_max() * run_s;
                match (
                    origin.to_local(last.fix.lat, last.fix.lon),
                    origin.to_local(fix.lat, fix.lon),
                ) {
                    (Some((n0, e0)), Some((n1, e1))) => {
                        // Finite: fixes are whole degE7 within the plane's range.
                        let (dn, de) = (n1 - n0, e1 - e0);
                        dn * dn + de * de > reach * reach
                    }
                    _ => true,
                }
            }
            _ => false,
        };
        if jumped {
            self.counters.target_jumps = self.counters.target_jumps.wrapping_add(1);
        }
        // A jump confirmed, a fix after a stale track, or one from another sender (another
        // clock) starts a new track.
        let fresh = live.is_none_or(|last| !last.confirmed || last.source != source);
        self.target = Some(Target {
            fix,
            confirmed: !jumped,
            source,
        });
        if !jumped {
            let fresh = fresh || self.pending_target.is_some_and(|(_, f)| f);
            self.pending_target = Some((fix, fresh));
        }
    }

    /// The own fix (at `(x, y)` in the plane, metres north and east) into its track, then the
    /// target's fix waiting for it (module docs of `tracking`), placed on the autopilot's
    /// clock by this own fix: its time less our clock from the target fix's arrival to its
    /// own, at the autopilot clock's rate. With no target track, the last confirmed fix
    /// starts one (a fix that came before the first own fix, or before the plane moved).
    fn track(&mut self, own: &Fix, (x, y): (f32, f32)) {
        let (Some(origin), Some(tracking)) = (self.origin, self.tracking.as_mut()) else {
            return;
        };
        let _ = tracking.own([x, y, own.heading], own.sent_ms);
        if self.pending_target.is_none() && !tracking.has_target() {
            self.pending_target = self.target.filter(|t| t.confirmed).map(|t| (t.fix, true));
        }
        let Some((fix, fresh)) = self.pending_target.take() else {
            return;
        };
        let fresh = fresh || core::mem::take(&mut self.clock_measured);
        if let Some((x, y)) = origin.to_local(fix.lat, fix.lon) {
            let before = self
                .clock
                .theirs(own.arrived_ms.wrapping_sub(fix.arrived_ms));
            let arrival_ms = own.sent_ms.wrapping_sub(before);
            // Refusals are counted by the estimator.
            let state = [x, y, fix.heading];
            let _ = tracking.target(state, fix.speed, fix.sent_ms, arrival_ms, fresh);
        }
    }

    fn own_state(
        &mut self,
        m: &GLOBAL_POSITION_INT_DATA,
        now_ms: u32,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let Some(fix) = position_fix(m, now_ms) else {
            let halt = if valid_position(m.lat, m.lon) {
                Halt::OwnHeading
            } else {
                Halt::OwnFix
            };
            self.own = None;
            self.halt(halt, send);
            return;
        };
        let interval_ms = self.own.map(|last| fix.sent_ms.wrapping_sub(last.sent_ms));
        if let Some(interval_ms) = interval_ms {
            self.measure_period(interval_ms);
        }
        self.flight = Some((flight(m), energy_step(interval_ms)));
        let timeout = self.params.timeout_ms();
        let stale = self
            .own
            .is_none_or(|last| fix.arrived_ms.wrapping_sub(last.arrived_ms) > timeout);
        self.clock_measured |= self.clock.own_fix(fix.sent_ms, fix.arrived_ms, stale);
        self.own = Some(fix);
        // The plane about the first own fix, moved to the own fix once that is REANCHOR_M
        // away: the projection's error grows with the square of the distance, the law only
        // reads the pursuer-target geometry.
        let near = self
            .origin
            .and_then(|origin| origin.to_local(fix.lat, fix.lon))
            .filter(|(n, e)| n * n + e * e <= REANCHOR_M * REANCHOR_M);
        let local = near.unwrap_or_else(|| {
            self.origin = LocalFrame::new(fix.lat, fix.lon);
            // The tracks were in the old plane: the target's last fix starts a new one.
            if let Some(tracking) = self.tracking.as_mut() {
                tracking.clear();
            }
            // The fix is the new plane's reference.
            (0.0, 0.0)
        });
        self.track(&fix, local);
        match self.evaluate(now_ms) {
            Ok(decision) => {
                self.setpoint(&decision, fix.heading, now_ms, send);
                self.watch_departure(&fix, now_ms, send);
                #[cfg(feature = "mavlink-team")]
                self.name_roles(now_ms, send);
            }
            Err(halt) => {
                self.departure.reset();
                self.halt(halt, send);
            }
        }
    }

    /// A teammate's GLOBAL_POSITION_INT (its autopilot's, from system `system`) into the team;
    /// whether it was one.
    #[cfg(feature = "mavlink-team")]
    fn teammate_fix(&mut self, system: u8, m: &GLOBAL_POSITION_INT_DATA, now_ms: u32) -> bool {
        if !self.team.is_teammate(&self.params, system) {
            return false;
        }
        let Some(fix) = position_fix(m, now_ms) else {
            return false;
        };
        let mate = MateFix {
            lat: fix.lat,
            lon: fix.lon,
            heading: fix.heading,
            speed: fix.speed.unwrap_or(0.0),
            arrived_ms: now_ms,
        };
        self.team.hear(&self.params, system, mate)
    }

    /// In a team: the roles of this period, NAMED_VALUE_INT [`CHASER`] (the chaser's system
    /// id, 0 for none), and a STATUSTEXT (INFO) when the chaser changes.
    #[cfg(feature = "mavlink-team")]
    fn name_roles(&mut self, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        let (Some(origin), Some(states)) = (self.origin, self.decided_on) else {
            return;
        };
        if !self.team.active() {
            return;
        }
        let period = self.guidance.as_ref().map_or(0.1, Guidance::period);
        let chaser = self
            .team
            .name(&self.params, &origin, states, (now_ms, period));
        let sysid = self.sysid();
        let value = chaser.map_or(0, i32::from);
        self.outbox.named_int(sysid, now_ms, CHASER, value, send);
        if self.team.changed(chaser) {
            let text = match chaser {
                Some(c) if c == sysid => "TC: team: this unit chases",
                Some(_) => "TC: team: a teammate chases (TC_CHASER)",
                None => "TC: team: no chaser",
            };
            let severity = MavSeverity::MAV_SEVERITY_INFO;
            self.outbox.status_text(sysid, severity, text, send);
        }
    }

    /// Without the `mavlink-team` feature no system is a teammate.
    #[cfg(not(feature = "mavlink-team"))]
    fn teammate_fix(&mut self, _: u8, _: &GLOBAL_POSITION_INT_DATA, _: u32) -> bool {
        false
    }

    /// The own fix under setpoints into the departure watch: its speed the autopilot's
    /// airspeed where one came within TC_TIMEOUT (an aircraft's wind is not its own), else
    /// its ground speed.
    fn watch_departure(&mut self, fix: &Fix, now_ms: u32, send: &mut dyn FnMut(&[u8])) {
        // The limits validated when the guidance was built: not again per fix.
        let limits = self.guidance.as_ref().map(|g| g.law().limits);
        let (Some((flight, _)), Some(limits)) = (self.flight, limits) else {
            return;
        };
        let timeout = self.params.timeout_ms();
        let speed = match self.airspeed {
            Some((airspeed, at)) if now_ms.wrapping_sub(at) <= timeout => airspeed,
            _ => flight.airspeed,
        };
        let v_pm = limits.pursuer.v_max();
        let turn_rate = limits.pursuer.max_turn_rate();
        let said = self
            .departure
            .own_fix(fix.sent_ms, speed, fix.heading, v_pm, turn_rate);
        if let Some(departure) = said {
            self.counters.own_departures = self.counters.own_departures.wrapping_add(1);
            let severity = MavSeverity::MAV_SEVERITY_WARNING;
            self.outbox
                .status_text(self.sysid(), severity, departure.text(), send);
        }
    }

    /// Takes the own states' spacing `interval_ms` as the period when it differs from the one in
    /// use by more than a quarter (between 1 ms and 1 s); the guidance keeps its memory.
    fn measure_period(&mut self, interval_ms: u32) {
        let current = self.period_ms;
        if !(1..=1000).contains(&interval_ms) || interval_ms.abs_diff(current) * 4 <= current {
            return;
        }
        let period = self.guidance_period(interval_ms);
        if let Some(guidance) = self.guidance.as_mut() {
            if guidance.set_period(period).is_ok() {
                self.period_ms = interval_ms;
            }
        }
    }

    /// Whether the own or the target state is older than TC_TIMEOUT at `now_ms`.
    fn stale(&self, now_ms: u32) -> Option<Halt> {
        let timeout = self.params.timeout_ms();
        let old = |fix: &Fix| now_ms.wrapping_sub(fix.arrived_ms) > timeout;
        match (&self.own, &self.target) {
            (None, _) => Some(Halt::OwnFix),
            (Some(own), _) if old(own) => Some(Halt::OwnStale),
            (_, None) => Some(Halt::NoTarget),
            (_, Some(target)) if old(&target.fix) => Some(Halt::TargetStale),
            _ => None,
        }
    }

    /// The law for the pursuer on the current fixes.
    fn evaluate(&mut self, now_ms: u32) -> Result<Decision<f32>, Halt> {
        if let Some(halt) = self.stale(now_ms) {
            return Err(halt);
        }
        let (Some(own), Some(target), Some(_)) = (self.own, self.target, self.origin) else {
            return Err(Halt::NoTarget);
        };
        if !target.confirmed {
            return Err(Halt::TargetJump);
        }
        let (Some(guidance), Some(tracking)) = (self.guidance.as_mut(), self.tracking.as_mut())
        else {
            return Err(Halt::Law(Status::InvalidLimits));
        };
        // Read where the estimator returned it: moved out of its Result, the 28 bytes went by
        // three library memcpy calls a period.
        let states = tracking.states(own.sent_ms);
        let estimated = match &states {
            Ok(estimated) => estimated,
            Err(Stale::Own) => return Err(Halt::OwnStale),
            Err(Stale::Target) => return Err(Halt::TargetStale),
        };
        // f32 is an SI backend: the estimated states are metres and radians.
        #[cfg(feature = "mavlink-team")]
        if self.team.active() {
            self.decided_on = Some((estimated.own, estimated.target));
        }
        let decision = guidance
            .decide_estimated(estimated)
            .map_err(|e| Halt::Law(e.status()))?;
        match decision.status {
            Status::Ok | Status::NoValidTangent | Status::Captured => Ok(decision),
            status => Err(Halt::Law(status)),
        }
    }

    /// The setpoint for `decision` (the pursuer at `heading`) and the predicted capture time.
    fn setpoint(
        &mut self,
        decision: &Decision<f32>,
        heading: f32,
        now_ms: u32,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let sysid = self.sysid();
        if self.health != Health::Active {
            self.health = Health::Active;
            let severity = MavSeverity::MAV_SEVERITY_INFO;
            let text = "TC: input valid, setpoints on";
            self.outbox.status_text(sysid, severity, text, send);
        }
        if decision.status != self.last_status && decision.status == Status::Captured {
            let severity = MavSeverity::MAV_SEVERITY_INFO;
            self.outbox
                .status_text(sysid, severity, "TC: captured", send);
        }
        self.last_status = decision.status;
        let speed = self.params.get(index::V_PM).unwrap_or(0.0);
        // f32 runs in SI units: the turn rate is v_pm w, rad/s, clockwise from above.
        let rate = speed * decision.command.pursuer;
        self.send_setpoint(speed, rate, heading, now_ms, send);
        let upper = decision
            .solution
            .and_then(|s| s.upper)
            .unwrap_or(f32::INFINITY);
        let upper = if decision.status == Status::Captured {
            0.0
        } else {
            upper
        };
        self.outbox.named_value(sysid, now_ms, "TC_T", upper, send);
        self.counters.setpoints = self.counters.setpoints.wrapping_add(1);
    }

    /// The setpoint for the vehicle TC_VEHICLE names: turn `rate` (rad/s, clockwise) at `speed`
    /// (m/s), the pursuer at `heading` (rad, clockwise from north).
    fn send_setpoint(
        &mut self,
        speed: f32,
        rate: f32,
        heading: f32,
        now_ms: u32,
        send: &mut dyn FnMut(&[u8]),
    ) {
        let sysid = self.sysid();
        let vehicle = self.params.byte(index::VEHICLE);
        let turn = Turn {
            speed,
            rate,
            heading,
            period: self.guidance_period(self.period_ms),
        };
        let energy = (vehicle == FIXED_WING_ENERGY)
            .then(|| self.energy_command(speed, now_ms))
            .flatten();
        let efficiency = self.params.get(index::BANK_EFF).unwrap_or(1.0);
        let to = Address {
            system: sysid,
            component: AUTOPILOT_COMPONENT,
            now_ms,
        };
        match setpoint(vehicle, &turn, efficiency, energy, to) {
            Setpoint::Attitude(m) => self.outbox.send(sysid, &m, send),
            Setpoint::Velocity(m) => self.outbox.send(sysid, &m, send),
        }
    }

    /// The energy hold's pitch and throttle on the last own state, at airspeed `speed` (m/s):
    /// the autopilot's VFR_HUD airspeed where one came within TC_TIMEOUT, else the ground
    /// speed.
    fn energy_command(&mut self, speed: f32, now_ms: u32) -> Option<Energy> {
        let (mut flight, dt) = self.flight?;
        let timeout = self.params.timeout_ms();
        if let Some((airspeed, arrived_ms)) = self.airspeed {
            if now_ms.wrapping_sub(arrived_ms) <= timeout {
                flight.airspeed = airspeed;
            }
        }
        Some(self.energy.command(flight, speed, dt))
    }

    /// No setpoint, for `halt`: announced when the halt begins (not again while it lasts).
    fn halt(&mut self, halt: Halt, send: &mut dyn FnMut(&[u8])) {
        self.counters.halted = self.counters.halted.wrapping_add(1);
        if matches!(self.health, Health::Halted(_)) {
            return;
        }
        self.health = Health::Halted(halt);
        if let Some(guidance) = self.guidance.as_mut() {
            guidance.reset();
        }
        self.energy.reset();
        let severity = MavSeverity::MAV_SEVERITY_WARNING;
        self.outbox
            .status_text(self.sysid(), severity, halt.text(), send);
    }
}

/// Whether (`lat`, `lon`) is a fix: within +-90 and +-180 degrees and not (0, 0), an
/// autopilot's "no fix yet".
fn valid_position(lat: i32, lon: i32) -> bool {
    (lat, lon) != (0, 0) && valid_fix(lat, lon)
}

/// The fix of a GLOBAL_POSITION_INT: heading from `hdg`, or the course from `vx`, `vy` when it
/// is unknown; `None` without a valid position or heading.
fn position_fix(m: &GLOBAL_POSITION_INT_DATA, now_ms: u32) -> Option<Fix> {
    if !valid_position(m.lat, m.lon) {
        return None;
    }
    let heading = if m.hdg == HEADING_UNKNOWN {
        course(f32::from(m.vx), f32::from(m.vy), MIN_COURSE_SPEED_CM_S)
    } else {
        heading_from_cdeg(m.hdg)
    }?;
    // (0, 0) is what a sender that fills no velocity sends: the track's positions tell the
    // speed then (a target that is still is found still by them as well).
    let speed = (m.vx != 0 || m.vy != 0).then(|| {
        let (vx, vy) = (f32::from(m.vx), f32::from(m.vy));
        crate::num::f32_math::sqrt(vx * vx + vy * vy) / 100.0
    });
    Some(Fix {
        lat: m.lat,
        lon: m.lon,
        heading,
        speed,
        sent_ms: m.time_boot_ms,
        arrived_ms: now_ms,
    })
}

/// The own aircraft's height (relative_alt, mm), climb (-vz, cm/s) and ground speed (cm/s) in
/// SI units.
fn flight(m: &GLOBAL_POSITION_INT_DATA) -> Flight {
    let (vx, vy) = (f32::from(m.vx), f32::from(m.vy));
    Flight {
        height: m.relative_alt as f32 / 1000.0,
        climb: -f32::from(m.vz) / 100.0,
        airspeed: crate::num::f32_math::sqrt(vx * vx + vy * vy) / 100.0,
    }
}

/// The energy hold's step for an own-state spacing (ms): within 1 ms to 200 ms, a gap
/// integrates no more than 200 ms; the default period before the second state.
fn energy_step(interval_ms: Option<u32>) -> f32 {
    interval_ms.unwrap_or(DEFAULT_PERIOD_MS).clamp(1, 200) as f32 / 1000.0
}

/// The fix of a FOLLOW_TARGET: its position if flagged valid; heading from its attitude, or
/// the course from its velocity.
fn follow_fix(m: &FOLLOW_TARGET_DATA, now_ms: u32) -> Option<Fix> {
    let caps = m.est_capabilities;
    if caps & FOLLOW_POSITION == 0 || !valid_position(m.lat, m.lon) {
        return None;
    }
    let attitude = (caps & FOLLOW_ATTITUDE != 0)
        .then(|| yaw_from_quaternion(m.attitude_q))
        .flatten();
    let [north, east, _] = m.vel;
    let moving = caps & FOLLOW_VELOCITY != 0;
    let velocity = moving
        .then(|| course(north, east, MIN_COURSE_SPEED_CM_S / 100.0))
        .flatten();
    let speed = moving
        .then(|| crate::num::f32_math::sqrt(north * north + east * east))
        .filter(|s| s.is_finite());
    Some(Fix {
        lat: m.lat,
        lon: m.lon,
        heading: attitude.or(velocity)?,
        speed,
        sent_ms: m.timestamp as u32,
        arrived_ms: now_ms,
    })
}
