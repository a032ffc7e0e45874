//! The guidance unit's serial-protocol endpoint: bytes in, bytes out. It deframes the serial
//! stream, answers Configure, State and ReadCounters, refuses every malformed input with an
//! Error, counts each kind, and emits the safe command when no valid State arrived within the
//! watchdog time.
//!
//! Pure and allocation-free: the firmware feeds it UART bytes and its clock; the host tests and
//! fuzzers feed it anything.

use crate::error::Error;
use crate::estimate::{Estimated, Estimator, FieldSettings, Fix, FixNoise, Stale};
use crate::guidance::{Guidance, Policy};
use crate::law::capture::Variant;
use crate::law::geometry::{Direction, Limits};
use crate::law::{Decision, Law};
use crate::num::{ieee, Scalar};
use crate::protocol::frame::{
    encode_frame_as, header_sequence, Deframer, Feed, Frame, WireError, MAX_ENCODED, MAX_FRAME,
    VERSION, VERSION_1,
};
use crate::protocol::message::{
    kind, policy_of_byte, CommandMsg, Configure, Counters, ErrorMsg, LineCounts, StateMsg,
    NO_CIRCLE, NO_MEMBER, ROLE_EVADER, ROLE_PURSUER,
};
#[cfg(feature = "serial-team")]
use crate::protocol::{message::TeammateMsg, team::Team};
use crate::status::Status;
use crate::value_tables::ValueTables;

/// Wire status code of the watchdog's safe command (the law's statuses are 0 to 5).
pub const STATUS_STALE_INPUT: u8 = 6;

/// Wire code of a law status.
pub fn status_code(status: Status) -> u8 {
    match status {
        Status::Ok => 0,
        Status::NonFiniteInput => 1,
        Status::InvalidLimits => 2,
        Status::OutOfRange => 3,
        Status::Captured => 4,
        Status::NoValidTangent => 5,
    }
}

fn circle_code(d: Direction) -> u8 {
    match d {
        Direction::Anticlockwise => 0,
        Direction::Clockwise => 1,
    }
}

/// The circle a turn rate turns on: A for > 0, C for < 0, none for straight.
fn turned_code<S: Scalar>(rate: S) -> u8 {
    if rate > S::zero() {
        circle_code(Direction::Anticlockwise)
    } else if rate < S::zero() {
        circle_code(Direction::Clockwise)
    } else {
        NO_CIRCLE
    }
}

/// A reply frame ready to send: COBS-encoded, delimiter included.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reply {
    bytes: [u8; MAX_ENCODED],
    len: usize,
    message_type: u8,
}

impl Reply {
    /// The bytes to write to the serial port.
    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&[])
    }

    /// Whether this acknowledges a Shutdown: the session is over once it is sent.
    pub fn is_shutdown(&self) -> bool {
        self.message_type == kind::SHUTDOWN_ACK
    }

    /// No reply yet: the place a reply is written into.
    const EMPTY: Reply = Reply {
        bytes: [0; MAX_ENCODED],
        len: 0,
        message_type: 0,
    };

    /// Writes the reply frame of `message_type` in protocol `version` in place (the payload
    /// written by the closure); false, and no reply, if it does not fit (no message of ours is
    /// that long).
    fn write(
        &mut self,
        version: u8,
        message_type: u8,
        sequence: u16,
        payload: impl FnOnce(&mut crate::protocol::frame::Writer<'_>) -> Option<()>,
    ) -> bool {
        let written = encode_frame_as(version, message_type, sequence, payload, &mut self.bytes);
        self.len = written.unwrap_or(0);
        self.message_type = message_type;
        written.is_some()
    }
}

#[derive(Clone, Copy, Debug)]
struct Configured<S> {
    guidance: Guidance<S>,
    /// The policy byte in effect: the Configure's, or 1 (flight) where it asked for tables
    /// and none fit.
    policy: u8,
    roles: u8,
    watchdog_ms: u32,
    /// Protocol version of the Configure: unasked replies are written in it.
    version: u8,
    /// Wire units per law unit: rad/s per turn rate, seconds per time (1 on SI backends).
    /// Derivable from the limits' units, kept to spare the M0 two soft-float divisions per
    /// State (+553 instructions per frame measured).
    rate_scale: f32,
    time_scale: f32,
}

/// The guidance unit's door for our serial protocol (the MAVLink door is `mavlink::Endpoint`,
/// with the `mavlink` feature): configuration, deframer, counters, watchdog, and its last
/// reply. Generic over the law's numeric backend: `f32` on cores with an FPU,
/// [`crate::num::fixed::Fixed`] (Q17.14) on those without, where the wire's `f32` values are
/// converted with integers only.
#[derive(Debug)]
pub struct Endpoint<S = f32> {
    deframer: Deframer<MAX_FRAME>,
    session: Session<S>,
    /// Written in place and lent to the caller: a reply by value would be copied (76 bytes) at
    /// each of its moves.
    reply: Reply,
}

/// Everything but the deframer: a decoded frame borrows the deframer's buffer while the session
/// handles it (no copy of the frame).
#[derive(Debug)]
struct Session<S> {
    configured: Option<Configured<S>>,
    /// The value tables the image carries, one set per pair of ratios ([`Endpoint::set_tables`]).
    tables: &'static [ValueTables<'static>],
    counters: Counters,
    watchdog: Watchdog,
    /// Protocol version of the last readable frame: the unit answers in it.
    version: u8,
    /// Both tracks, from a version-2 Configure, over the law's own number type (the
    /// fixed-point images track in fixed point); under version 1 the unit steers on the
    /// State's states as they are. Beside the configuration, not in it: a configuration is
    /// built on the stack.
    estimator: Option<Estimator<S>>,
    /// The last State's evader fix time, ms: the same again is no new fix.
    last_target_ms: Option<u32>,
    /// The team of a version-3 Configure, where it has one.
    #[cfg(feature = "serial-team")]
    team: Option<Team>,
}

/// The stale-input watchdog. Latched: once input went stale, States get the safe command until
/// a Configure or a Reset, so a unit never silently resumes after a gap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Watchdog {
    /// No valid State since the last Configure or Reset.
    Idle,
    /// The last valid State arrived at device time `arrived_ms`, stamped `stamp_ms` by its sender.
    Armed { arrived_ms: u32, stamp_ms: u32 },
    /// Input went stale: the safe command until Configure or Reset.
    Latched,
}

impl<S: Scalar> Default for Endpoint<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Scalar> Endpoint<S> {
    /// An unconfigured unit.
    pub const fn new() -> Self {
        Endpoint {
            deframer: Deframer::new(),
            session: Session {
                configured: None,
                tables: &[],
                counters: Counters {
                    accepted: 0,
                    stale: 0,
                    errors: [0; crate::protocol::frame::ERROR_KINDS],
                    line: LineCounts {
                        overrun: 0,
                        framing: 0,
                        noise: 0,
                        parity: 0,
                        rx_full: 0,
                        tx_full: 0,
                    },
                    board: 0,
                    coasted: 0,
                    fixes_refused: 0,
                },
                watchdog: Watchdog::Idle,
                version: VERSION,
                estimator: None,
                last_target_ms: None,
                #[cfg(feature = "serial-team")]
                team: None,
            },
            reply: Reply::EMPTY,
        }
    }

    /// Gives the unit the game's value tables its image carries, one set per pair of ratios: a
    /// Configure with policy 2 plays the first set that fits its limits' ratios. In
    /// place: a builder moving the unit by value raised the M4F loop's peak stack by 64 B.
    pub fn set_tables(&mut self, tables: &'static [ValueTables<'static>]) {
        self.session.tables = tables;
    }

    /// Counters so far.
    pub fn counters(&self) -> &Counters {
        &self.session.counters
    }

    /// Records the serial line's fault counts (kept by the board's UART interrupt), for the
    /// next Counters reply.
    pub fn record_line(&mut self, line: LineCounts) {
        self.session.counters.line = line;
    }

    /// The board's status flags ([`crate::protocol::message::BOARD_FALLBACK_CLOCK`]),
    /// for the next Counters reply.
    pub fn set_board_status(&mut self, flags: u32) {
        self.session.counters.board = flags;
    }

    /// Feeds one received byte at device time `now_ms`; returns the reply to send, if any.
    pub fn receive(&mut self, byte: u8, now_ms: u32) -> Option<&Reply> {
        self.receive_slice(&[byte], now_ms).1
    }

    /// Feeds received bytes at device time `now_ms`, up to and including the first that ends a
    /// frame: how many it took, and the reply to send, if any. Feed the rest after sending it.
    /// (The firmware's loop: the deframer runs over the bytes without storing its state per byte.)
    pub fn receive_slice(&mut self, bytes: &[u8], now_ms: u32) -> (usize, Option<&Reply>) {
        let Endpoint {
            deframer,
            session,
            reply,
        } = self;
        let (taken, feed) = deframer.push_slice(bytes);
        let result = match feed {
            Feed::Pending => return (taken, None),
            Feed::Error(e) => Err((e, None)),
            Feed::Frame(bytes) => match Frame::new_checked(bytes) {
                Ok(frame) => session.handle(&frame, now_ms, reply),
                // The CRC held, so the header is readable: the refusal echoes its sequence.
                Err(WireError::BadVersion) => {
                    Err((WireError::BadVersion, Some(header_sequence(bytes))))
                }
                Err(e) => Err((e, None)),
            },
        };
        let written = match result {
            Ok(written) => {
                session.counters.accepted = session.counters.accepted.saturating_add(1);
                written
            }
            Err((error, sequence)) => {
                session.counters.count(error);
                let message = ErrorMsg {
                    code: error as u8,
                    sequence_known: u8::from(sequence.is_some()),
                };
                let version = session.version;
                reply.write(version, kind::ERROR, sequence.unwrap_or(0), |w| {
                    message.emit(w)
                })
            }
        };
        (taken, written.then_some(&*reply))
    }

    /// Checks the watchdog at device time `now_ms`: when no valid State arrived for longer than
    /// the configured time, latches and returns (once) the safe command with status
    /// `stale_input`.
    pub fn poll(&mut self, now_ms: u32) -> Option<&Reply> {
        self.session
            .poll(now_ms, &mut self.reply)
            .then_some(&self.reply)
    }
}

impl<S: Scalar> Session<S> {
    /// [`Endpoint::poll`]: whether the stale reply was written into `reply`.
    fn poll(&mut self, now_ms: u32, reply: &mut Reply) -> bool {
        let Some(configured) = self.configured else {
            return false;
        };
        match self.watchdog {
            Watchdog::Armed { arrived_ms, .. }
                if now_ms.wrapping_sub(arrived_ms) > configured.watchdog_ms =>
            {
                self.latch();
                let version = configured.version;
                reply.write(version, kind::COMMAND, 0, |w| {
                    stale_command(configured.roles).emit_in(version, w)
                })
            }
            _ => false,
        }
    }

    fn latch(&mut self) {
        self.watchdog = Watchdog::Latched;
        self.counters.stale = self.counters.stale.saturating_add(1);
    }

    /// Handles a checked frame, its reply written into `reply`: whether one was written, or the
    /// error to refuse the frame with (and its sequence number where known).
    fn handle(
        &mut self,
        frame: &Frame<'_>,
        now_ms: u32,
        reply: &mut Reply,
    ) -> Result<bool, (WireError, Option<u16>)> {
        let sequence = frame.sequence();
        self.version = frame.version();
        let handled = match frame.message_type() {
            kind::CONFIGURE => self.on_configure(frame.payload(), sequence, reply),
            kind::STATE => self.on_state(frame.payload(), sequence, now_ms, reply),
            #[cfg(feature = "serial-team")]
            kind::TEAMMATE if self.version == VERSION => {
                self.on_teammate(frame.payload(), sequence, reply)
            }
            request @ (kind::READ_COUNTERS | kind::RESET | kind::SHUTDOWN) => {
                self.on_request(request, frame.payload(), sequence, reply)
            }
            _ => Err(WireError::UnknownType),
        };
        handled.map_err(|e| (e, Some(sequence)))
    }

    /// Configure: the unit set up afresh, acknowledged with the policy it plays. Inlined, as
    /// each handler is, so that the loop's stack holds one frame for all of them.
    #[inline(always)]
    fn on_configure(
        &mut self,
        payload: &[u8],
        sequence: u16,
        reply: &mut Reply,
    ) -> Result<bool, WireError> {
        let version = self.version;
        let message = Configure::parse_in(version, payload)?;
        check_team(&message)?;
        // Written in place; only its policy byte is read back (a copy of the whole
        // configuration kept for the ack cost the M0's loop 264 B of stack).
        let configured = self
            .configured
            .insert(configure(&message, version, self.tables)?);
        #[cfg(feature = "serial-team")]
        {
            self.team = Team::of(message.team, message.limits).ok().flatten();
        }
        self.last_target_ms = None;
        self.estimator = None;
        if version != VERSION_1 {
            install_estimator(&mut self.estimator, &message);
        }
        let policy = configured.policy;
        self.watchdog = Watchdog::Idle;
        Ok(reply.write(version, kind::CONFIGURE_ACK, sequence, |w| w.u8(policy)))
    }

    /// State: the law's Command for the configured roles, or the stale command once the
    /// sender's timestamps show a gap longer than the watchdog time.
    #[inline(always)]
    fn on_state(
        &mut self,
        payload: &[u8],
        sequence: u16,
        now_ms: u32,
        reply: &mut Reply,
    ) -> Result<bool, WireError> {
        let version = self.version;
        let message = if version == VERSION_1 {
            StateMsg::parse_v1(payload)?
        } else {
            StateMsg::parse(payload)?
        };
        let configured = self.configured.as_mut().ok_or(WireError::NotConfigured)?;
        // The contract's order: a non-finite field anywhere before any envelope check
        // (on the bits: no float operation on a core without an FPU).
        let mut fields = message.pursuer.iter().chain(message.evader.iter());
        if fields.any(|v| !ieee::is_finite_bits(v.to_bits())) {
            return Err(WireError::NonFiniteField);
        }
        let limits = &configured.guidance.law().limits;
        let (pursuer, evader) =
            limits
                .states(message.pursuer, message.evader)
                .map_err(|error| match error {
                    Error::NonFiniteInput => WireError::NonFiniteField,
                    _ => WireError::OutOfRangeField,
                })?;
        let roles = configured.roles;
        // Staleness by the sender's own timestamps: a gap longer than the watchdog time
        // (or a timestamp going backwards, which wraps to a huge gap) latches.
        let stale = match self.watchdog {
            Watchdog::Latched => true,
            Watchdog::Armed { stamp_ms, .. } => {
                message.time_ms.wrapping_sub(stamp_ms) > configured.watchdog_ms
            }
            Watchdog::Idle => false,
        };
        if stale {
            if self.watchdog != Watchdog::Latched {
                self.latch();
            }
            return Ok(reply.write(version, kind::COMMAND, sequence, |w| {
                stale_command(roles).emit_in(version, w)
            }));
        }
        let decision = if let Some(estimator) = self.estimator.as_mut() {
            let tracks = (estimator, &mut self.last_target_ms);
            let Some(decision) = decide_on_estimates(
                &mut configured.guidance,
                tracks,
                &message,
                &mut self.counters,
            )?
            else {
                // The target's track is older than the watchdog time: stale as a gap in the
                // States is.
                self.latch();
                return Ok(reply.write(version, kind::COMMAND, sequence, |w| {
                    stale_command(roles).emit_in(version, w)
                }));
            };
            decision
        } else {
            configured.guidance.decide(&pursuer, &evader)
        };
        #[cfg_attr(not(feature = "serial-team"), allow(unused_mut))]
        let mut command = command_message(&decision, configured);
        #[cfg(feature = "serial-team")]
        if let Some(team) = self.team.as_mut() {
            let timing = (message.time_ms, configured.watchdog_ms);
            let period = configured.guidance.period();
            command.chaser = team.name((message.pursuer, message.evader), timing, period);
        }
        self.watchdog = Watchdog::Armed {
            arrived_ms: now_ms,
            stamp_ms: message.time_ms,
        };
        Ok(reply.write(version, kind::COMMAND, sequence, |w| {
            command.emit_in(version, w)
        }))
    }

    /// Teammate: kept, acknowledged (protocol version 3, a team configured).
    #[cfg(feature = "serial-team")]
    #[inline(never)]
    fn on_teammate(
        &mut self,
        payload: &[u8],
        sequence: u16,
        reply: &mut Reply,
    ) -> Result<bool, WireError> {
        let message = TeammateMsg::parse(payload)?;
        let team = self.team.as_mut().ok_or(WireError::NotConfigured)?;
        team.hear(&message)?;
        let version = self.version;
        Ok(reply.write(version, kind::TEAMMATE_ACK, sequence, |_| Some(())))
    }

    /// ReadCounters, Reset and Shutdown: requests without a payload.
    #[inline(always)]
    fn on_request(
        &mut self,
        request: u8,
        payload: &[u8],
        sequence: u16,
        reply: &mut Reply,
    ) -> Result<bool, WireError> {
        if !payload.is_empty() {
            return Err(WireError::Oversized);
        }
        let version = self.version;
        Ok(match request {
            kind::READ_COUNTERS => {
                let counters = self.counters;
                reply.write(version, kind::COUNTERS, sequence, |w| counters.emit(w))
            }
            kind::RESET => {
                self.watchdog = Watchdog::Idle;
                if let Some(c) = self.configured.as_mut() {
                    c.guidance.reset();
                }
                self.last_target_ms = None;
                if let Some(estimator) = self.estimator.as_mut() {
                    estimator.clear();
                }
                #[cfg(feature = "serial-team")]
                if let Some(team) = self.team.as_mut() {
                    team.clear();
                }
                reply.write(version, kind::RESET_ACK, sequence, |_| Some(()))
            }
            _ => reply.write(version, kind::SHUTDOWN_ACK, sequence, |_| Some(())),
        })
    }
}

/// A team a Configure may ask for: none (size 0 or 1, own 0), or with the `serial-team`
/// feature 2 to 8 members and an own index among them.
///
/// # Errors
/// `InvalidConfig` for any other.
fn check_team(message: &Configure) -> Result<(), WireError> {
    #[cfg(feature = "serial-team")]
    let max = crate::protocol::team::MAX_TEAM as u8;
    #[cfg(not(feature = "serial-team"))]
    let max = 0;
    if message.team.fits(max) {
        Ok(())
    } else {
        Err(WireError::InvalidConfig)
    }
}

/// Largest watchdog time accepted, seconds.
pub const MAX_WATCHDOG_S: f32 = 3600.0;

fn configure<S: Scalar>(
    message: &Configure,
    version: u8,
    tables: &'static [ValueTables<'static>],
) -> Result<Configured<S>, WireError> {
    let [v_pm, w_pm, v_em, w_em] = message.limits;
    let limits = Limits::<S>::new(v_pm, w_pm, v_em, w_em).map_err(|error| match error {
        Error::NonFiniteInput => WireError::NonFiniteField,
        Error::InvalidLimits => WireError::InvalidLimits,
        _ => WireError::OutOfRangeField,
    })?;
    // `message::variant_byte`'s inverse, matched in place: read through an `Option`, the
    // serial loop's stack grows by 196 B on the M4F and 292 B on the M0 (`cargo xtask bench`).
    let variant = match message.variant {
        0 => Variant::Paper,
        1 => Variant::Clamped,
        _ => return Err(WireError::InvalidConfig),
    };
    let Some(policy) = policy_of_byte(message.policy) else {
        return Err(WireError::InvalidConfig);
    };
    let roles_valid = message.roles != 0 && message.roles & !(ROLE_PURSUER | ROLE_EVADER) == 0;
    let watchdog = message.watchdog;
    if !(roles_valid && watchdog.is_finite() && watchdog > 0.0 && watchdog <= MAX_WATCHDOG_S) {
        return Err(WireError::InvalidConfig);
    }
    let mut guidance = Guidance::new(Law::new(limits, variant), message.dt, policy)
        .map_err(|_| WireError::InvalidConfig)?;
    // Tables asked for: those of the limits' ratios, or the flight policy, said in the ack.
    // In place: a second guidance on the stack cost the M0's loop over 200 B.
    let mut policy_byte = message.policy;
    if policy == Policy::Table && !attach_tables(&mut guidance, tables) {
        guidance.set_policy(Policy::Flight);
        policy_byte = 1;
    }
    // In range by the check above: at most 3.6e6 ms.
    let watchdog_ms = libm::ceilf(watchdog * 1000.0) as u32;
    if version != VERSION_1 {
        check_field::<S>(message)?;
    }
    let units = limits.units;
    Ok(Configured {
        guidance,
        policy: policy_byte,
        roles: message.roles,
        watchdog_ms,
        rate_scale: units.metres_per_second / units.metres,
        time_scale: units.metres / units.metres_per_second,
        version,
    })
}

/// Whether a version-2 Configure's field settings make an estimator.
///
/// # Errors
/// As [`estimator`].
#[inline(never)]
fn check_field<S: Scalar>(message: &Configure) -> Result<(), WireError> {
    estimator::<S>(message).map(|_| ())
}

/// The estimator of a version-2 Configure (checked by [`check_field`]), written into `slot`.
/// Out of line, as the check is: the loop's stack frame holds no estimator of its own.
#[inline(never)]
fn install_estimator<S: Scalar>(slot: &mut Option<Estimator<S>>, message: &Configure) {
    *slot = estimator(message).ok();
}

/// Largest target position sigma accepted, metres.
pub const MAX_TARGET_SIGMA: f32 = 1.0e4;

/// The estimator a version-2 Configure asks for: its timeout the watchdog time.
///
/// # Errors
/// `InvalidConfig` for a lag or lead outside [0, watchdog) or a sigma outside its range.
fn estimator<S: Scalar>(message: &Configure) -> Result<Estimator<S>, WireError> {
    let field = &message.field;
    let sigma_ok = (0.0..=MAX_TARGET_SIGMA).contains(&field.target_sigma)
        && (0.0..=core::f32::consts::PI).contains(&field.target_heading_sigma);
    if !sigma_ok {
        return Err(WireError::InvalidConfig);
    }
    let settings = FieldSettings {
        target_noise: FixNoise {
            position: field.target_sigma,
            heading: field.target_heading_sigma,
        },
        target_lag: field.target_lag,
        own_lead: field.own_lead,
        ..FieldSettings::exact(message.watchdog)
    };
    Estimator::with_backend(message.limits, settings).map_err(|_| WireError::InvalidConfig)
}

/// Microseconds on the estimator's clock of a sender's `ms` (wrapping: differences hold).
fn sender_us(ms: u32) -> u32 {
    ms.wrapping_mul(1000)
}

/// `guidance`'s decision on both states as the estimator of `tracks` carries them (`None`: the
/// target's track is stale). Out of line: the exact-state path's stack frame holds nothing of
/// the estimator.
#[inline(never)]
fn decide_on_estimates<S: Scalar>(
    guidance: &mut Guidance<S>,
    (estimator, last_target_ms): (&mut Estimator<S>, &mut Option<u32>),
    message: &StateMsg,
    counters: &mut Counters,
) -> Result<Option<Decision<S>>, WireError> {
    let Ok(estimated) = estimate(estimator, message, last_target_ms, counters) else {
        return Ok(None);
    };
    guidance
        .decide_estimated(&estimated)
        .map(Some)
        .map_err(|_| WireError::OutOfRangeField)
}

/// Both states for a State's Command: the pursuer's fix taken at the State's time, the evader's
/// at its own (when new), both carried to the State's time; the estimator's counts added to
/// `counters`.
fn estimate<S: Scalar>(
    estimator: &mut Estimator<S>,
    message: &StateMsg,
    last_target_ms: &mut Option<u32>,
    counters: &mut Counters,
) -> Result<Estimated<S>, Stale> {
    let before = estimator.counters();
    let now_us = sender_us(message.time_ms);
    // Refusals are counted; the tracks coast on what they hold.
    let _ = estimator.own_fix(&Fix {
        state: message.pursuer,
        time_us: now_us,
    });
    if *last_target_ms != Some(message.evader_time_ms) {
        *last_target_ms = Some(message.evader_time_ms);
        let _ = estimator.target_fix_received(message.evader, sender_us(message.evader_time_ms));
    }
    let estimated = estimator.states(now_us);
    let after = estimator.counters();
    counters.coasted = counters
        .coasted
        .saturating_add(after.coasted.wrapping_sub(before.coasted));
    counters.fixes_refused = counters
        .fixes_refused
        .saturating_add(after.refused.wrapping_sub(before.refused));
    estimated
}

/// Gives `guidance` the first set of `tables` that fits its limits' ratios; whether one did
/// (feature `value-tables`; without it no image can play tables, and none is taken).
fn attach_tables<S: Scalar>(
    guidance: &mut Guidance<S>,
    tables: &'static [ValueTables<'static>],
) -> bool {
    #[cfg(feature = "value-tables")]
    return tables.iter().any(|t| guidance.set_tables(t).is_ok());
    #[cfg(not(feature = "value-tables"))]
    {
        let _ = (guidance, tables);
        false
    }
}

/// The safe command (zero turn rates) with status `stale_input`.
fn stale_command(roles: u8) -> CommandMsg {
    CommandMsg {
        status: STATUS_STALE_INPUT,
        roles,
        pursuer_rate: 0.0,
        evader_rate: 0.0,
        row: NO_CIRCLE,
        col: NO_CIRCLE,
        predicted: f32::INFINITY,
        upper: f32::INFINITY,
        lower: f32::INFINITY,
        chaser: NO_MEMBER,
    }
}

fn command_message<S: Scalar>(evaluation: &Decision<S>, configured: &Configured<S>) -> CommandMsg {
    let limits = &configured.guidance.law().limits;
    let roles = configured.roles;
    // Turn rates v w in the law's units (zero for a role not played), then in rad/s.
    let rate = |role: u8, w: S, v: S| if roles & role != 0 { v * w } else { S::zero() };
    let solution = evaluation.solution;
    let value = |v: Option<Option<S>>| {
        v.flatten()
            .map_or(f32::INFINITY, |v| v.to_f32_scaled(configured.time_scale))
    };
    let pursuer_rate = rate(
        ROLE_PURSUER,
        evaluation.command.pursuer,
        limits.pursuer.v_max(),
    );
    let evader_rate = rate(
        ROLE_EVADER,
        evaluation.command.evader,
        limits.evader.v_max(),
    );
    // The game's circles where it has a saddle to play; under the fallback (no valid tangent)
    // the circle each player actually turns on (none when straight), as the contract binds.
    let (row, col) = match (evaluation.status, solution) {
        (Status::NoValidTangent, _) => (turned_code(pursuer_rate), turned_code(evader_rate)),
        (_, Some(s)) => (circle_code(s.row), circle_code(s.col)),
        (_, None) => (NO_CIRCLE, NO_CIRCLE),
    };
    CommandMsg {
        status: status_code(evaluation.status),
        roles,
        pursuer_rate: pursuer_rate.to_f32_scaled(configured.rate_scale),
        evader_rate: evader_rate.to_f32_scaled(configured.rate_scale),
        row,
        col,
        predicted: value(solution.map(|s| s.upper)),
        upper: value(solution.map(|s| s.upper)),
        lower: value(solution.map(|s| s.lower)),
        chaser: NO_MEMBER,
    }
}
