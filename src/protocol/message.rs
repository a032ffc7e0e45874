//! The messages of the wire protocol: their payloads as plain structs, with `parse` and `emit`.
//! Byte-by-byte layout in `docs/protocol.md`. Turn rates on the wire are rad/s (= v w).

use crate::guidance::Policy;
use crate::law::capture::Variant;
use crate::protocol::frame::{Reader, WireError, Writer};

/// Message type codes. Host to unit below 0x80, unit to host from 0x80.
pub mod kind {
    /// Host -> unit: limits, period, watchdog, roles, variant, policy.
    pub const CONFIGURE: u8 = 0x01;
    /// Host -> unit: timestamp and both vehicles' states.
    pub const STATE: u8 = 0x02;
    /// Host -> unit: ask for the counters.
    pub const READ_COUNTERS: u8 = 0x03;
    /// Host -> unit: end the session (a board may stop; QEMU exits with code 0).
    pub const SHUTDOWN: u8 = 0x04;
    /// Host -> unit: clear a latched watchdog (and the law's remembered choice); the
    /// configuration stays.
    pub const RESET: u8 = 0x05;
    /// Host -> unit: a teammate's state (protocol version 3).
    pub const TEAMMATE: u8 = 0x06;
    /// Unit -> host: Configure accepted.
    pub const CONFIGURE_ACK: u8 = 0x81;
    /// Unit -> host: the command for a State (or the watchdog's safe command).
    pub const COMMAND: u8 = 0x82;
    /// Unit -> host: the counters.
    pub const COUNTERS: u8 = 0x83;
    /// Unit -> host: Shutdown accepted; nothing follows.
    pub const SHUTDOWN_ACK: u8 = 0x84;
    /// Unit -> host: Reset accepted.
    pub const RESET_ACK: u8 = 0x85;
    /// Unit -> host: Teammate accepted.
    pub const TEAMMATE_ACK: u8 = 0x86;
    /// Unit -> host: an input was refused.
    pub const ERROR: u8 = 0x8F;
}

/// Bit of [`Configure::roles`]: this unit computes the pursuer's command.
pub const ROLE_PURSUER: u8 = 0b01;
/// Bit of [`Configure::roles`]: this unit computes the evader's command.
pub const ROLE_EVADER: u8 = 0b10;

/// A Configure's variant byte for `variant`: 0 paper, 1 clamped (the unit reads it back in
/// `protocol::endpoint`).
pub const fn variant_byte(variant: Variant) -> u8 {
    match variant {
        Variant::Paper => 0,
        Variant::Clamped => 1,
    }
}

/// A Configure's policy byte for `policy`: 0 paper, 1 flight, 2 value tables.
pub const fn policy_byte(policy: Policy) -> u8 {
    match policy {
        Policy::Paper => 0,
        Policy::Flight => 1,
        Policy::Table => 2,
    }
}

/// The policy a Configure's policy byte names, if any ([`policy_byte`]'s inverse).
pub const fn policy_of_byte(byte: u8) -> Option<Policy> {
    match byte {
        0 => Some(Policy::Paper),
        1 => Some(Policy::Flight),
        2 => Some(Policy::Table),
        _ => None,
    }
}

/// Configure: both vehicles' limits (m/s, 1/m), control period and watchdog time (s), roles,
/// Algorithm-2 variant (0 paper, 1 clamped) and policy (0 paper, 1 flight); from protocol
/// version 2 the field's settings (`crate::estimate::FieldSettings`), which version 1 leaves 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Configure {
    /// v_pm, w_pm, v_em, w_em.
    pub limits: [f32; 4],
    /// Control period dt, seconds.
    pub dt: f32,
    /// Watchdog: the safe command after this long without a valid State, seconds.
    pub watchdog: f32,
    /// [`ROLE_PURSUER`] | [`ROLE_EVADER`].
    pub roles: u8,
    /// 0 paper, 1 clamped.
    pub variant: u8,
    /// 0 paper, 1 flight ([`crate::Policy`]).
    pub policy: u8,
    /// The field's settings (protocol version 2; 0 in version 1).
    pub field: FieldConfig,
    /// The team this unit's pursuer is in (protocol version 3; none in earlier versions).
    pub team: TeamConfig,
}

/// The team in a [`Configure`] (protocol version 3): how many pursuers, and which of them
/// this unit's is. Every member has the Configure's limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct TeamConfig {
    /// Members, 0 or 1 for no team, at most 8 (the `serial-team` feature's
    /// `protocol::team::MAX_TEAM`; without it a unit refuses a team).
    pub size: u8,
    /// This unit's pursuer's index in the team, below `size`.
    pub own: u8,
}

impl TeamConfig {
    /// No team.
    pub const NONE: TeamConfig = TeamConfig { size: 0, own: 0 };

    /// Whether this is no team (size 0 or 1, own 0).
    pub const fn is_none(&self) -> bool {
        self.size <= 1 && self.own == 0
    }

    /// Whether a unit that takes teams of up to `max` members can take this one: no team, or
    /// 2 to `max` members and an own index among them.
    pub const fn fits(&self, max: u8) -> bool {
        self.is_none() || (self.size >= 2 && self.size <= max && self.own < self.size)
    }
}

/// The field's settings in a [`Configure`] (protocol version 2): what the unit's estimator
/// (`crate::estimate`) is told of the target's fixes and of the own vehicle.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FieldConfig {
    /// The target fixes' transport lag before the sender stamped them, seconds, in
    /// [0, watchdog).
    pub target_lag: f32,
    /// One sigma of the target fixes' x and y, metres, in [0, 1e4].
    pub target_sigma: f32,
    /// One sigma of the target fixes' heading, radians, in [0, pi].
    pub target_heading_sigma: f32,
    /// How long after a Command the own vehicle turns as told, seconds, in [0, watchdog).
    pub own_lead: f32,
}

impl FieldConfig {
    /// Exact, instant fixes: every setting 0.
    pub const EXACT: FieldConfig = FieldConfig {
        target_lag: 0.0,
        target_sigma: 0.0,
        target_heading_sigma: 0.0,
        own_lead: 0.0,
    };
}

impl Configure {
    /// Payload length, bytes.
    pub const LEN: usize = 45;
    /// Payload length in protocol version 2, bytes.
    pub const LEN_V2: usize = 43;
    /// Payload length in protocol version 1, bytes.
    pub const LEN_V1: usize = 27;

    /// Parses a payload of the current version.
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        Self::parse_in(crate::protocol::frame::VERSION, payload)
    }

    /// Parses a payload of protocol version 2 (no team).
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse_v2(payload: &[u8]) -> Result<Self, WireError> {
        Self::parse_in(2, payload)
    }

    /// Parses a payload of protocol version 1 (the field's settings 0).
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse_v1(payload: &[u8]) -> Result<Self, WireError> {
        Self::parse_in(1, payload)
    }

    /// Parses a payload of protocol `version`: the field's settings from version 2, the team
    /// from 3. One body for every version, so that a unit carries one parser.
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse_in(version: u8, payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let mut m = Configure {
            limits: [r.f32()?, r.f32()?, r.f32()?, r.f32()?],
            dt: r.f32()?,
            watchdog: r.f32()?,
            roles: r.u8()?,
            variant: r.u8()?,
            policy: r.u8()?,
            field: FieldConfig::EXACT,
            team: TeamConfig::NONE,
        };
        if version >= 2 {
            m.field = FieldConfig {
                target_lag: r.f32()?,
                target_sigma: r.f32()?,
                target_heading_sigma: r.f32()?,
                own_lead: r.f32()?,
            };
        }
        if version >= 3 {
            m.team = TeamConfig {
                size: r.u8()?,
                own: r.u8()?,
            };
        }
        r.finish()?;
        Ok(m)
    }

    /// Writes the payload of the current version.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        self.emit_v2(w)?;
        w.u8(self.team.size)?;
        w.u8(self.team.own)
    }

    /// Writes the payload of protocol version 2 (without the team).
    pub fn emit_v2(&self, w: &mut Writer<'_>) -> Option<()> {
        self.emit_v1(w)?;
        let field = &self.field;
        w.f32(field.target_lag)?;
        w.f32(field.target_sigma)?;
        w.f32(field.target_heading_sigma)?;
        w.f32(field.own_lead)
    }

    /// Writes the payload of protocol version 1 (without the field's settings).
    pub fn emit_v1(&self, w: &mut Writer<'_>) -> Option<()> {
        for v in self.limits {
            w.f32(v)?;
        }
        w.f32(self.dt)?;
        w.f32(self.watchdog)?;
        w.u8(self.roles)?;
        w.u8(self.variant)?;
        w.u8(self.policy)
    }
}

/// State: the sender's timestamp (ms) and both vehicles' (x, y, theta) in metres and radians;
/// from protocol version 2 the time of the evader's fix on the sender's clock, which version 1
/// takes to be the timestamp (version 3's State is version 2's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateMsg {
    /// Sender's timestamp, milliseconds: when the pursuer was where it says.
    pub time_ms: u32,
    /// Pursuer x, y, theta.
    pub pursuer: [f32; 3],
    /// Evader x, y, theta.
    pub evader: [f32; 3],
    /// When the evader was where it says, milliseconds on the sender's clock (less the
    /// Configure's target lag). The previous State's value again: no new fix.
    pub evader_time_ms: u32,
}

impl StateMsg {
    /// Payload length, bytes.
    pub const LEN: usize = 32;
    /// Payload length in protocol version 1, bytes.
    pub const LEN_V1: usize = 28;

    /// A State of exact, instant fixes: the evader's fix at the timestamp.
    pub const fn exact(time_ms: u32, pursuer: [f32; 3], evader: [f32; 3]) -> Self {
        StateMsg {
            time_ms,
            pursuer,
            evader,
            evader_time_ms: time_ms,
        }
    }

    /// Parses a payload of the current version.
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let mut m = Self::parse_common(&mut r)?;
        m.evader_time_ms = r.u32()?;
        r.finish()?;
        Ok(m)
    }

    /// Parses a payload of protocol version 1 (the evader's fix at the timestamp).
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse_v1(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let m = Self::parse_common(&mut r)?;
        r.finish()?;
        Ok(m)
    }

    /// Inlined into each version's parse, so that the message is built where it goes: out
    /// of line, its 32 bytes were returned and moved on by five library memcpy calls, about
    /// 1,000 instructions a State frame on the Cortex-M4F.
    #[inline(always)]
    fn parse_common(r: &mut Reader<'_>) -> Result<Self, WireError> {
        let time_ms = r.u32()?;
        Ok(StateMsg {
            time_ms,
            pursuer: [r.f32()?, r.f32()?, r.f32()?],
            evader: [r.f32()?, r.f32()?, r.f32()?],
            evader_time_ms: time_ms,
        })
    }

    /// Writes the payload of the current version.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        self.emit_v1(w)?;
        w.u32(self.evader_time_ms)
    }

    /// Writes the payload of protocol version 1 (without the evader's fix time).
    pub fn emit_v1(&self, w: &mut Writer<'_>) -> Option<()> {
        w.u32(self.time_ms)?;
        for v in self.pursuer.iter().chain(self.evader.iter()) {
            w.f32(*v)?;
        }
        Some(())
    }
}

/// Teammate (protocol version 3): a teammate's (x, y, theta), metres and radians, in the
/// States' frame, and when it was there, ms on the States' sender's clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeammateMsg {
    /// The teammate's index in the team (not this unit's own).
    pub index: u8,
    /// When the teammate was where it says, milliseconds on the sender's clock.
    pub time_ms: u32,
    /// The teammate's x, y, theta.
    pub state: [f32; 3],
}

impl TeammateMsg {
    /// Payload length, bytes.
    pub const LEN: usize = 17;

    /// Parses a payload.
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let m = TeammateMsg {
            index: r.u8()?,
            time_ms: r.u32()?,
            state: [r.f32()?, r.f32()?, r.f32()?],
        };
        r.finish()?;
        Ok(m)
    }

    /// Writes the payload.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        w.u8(self.index)?;
        w.u32(self.time_ms)?;
        for v in self.state {
            w.f32(v)?;
        }
        Some(())
    }
}

/// Wire code of no team member: a Command's chaser where there is no team or no chaser.
pub const NO_MEMBER: u8 = 0xFF;

/// Wire code of a circle: 0 = A, 1 = C, 0xFF = none.
pub const NO_CIRCLE: u8 = 0xFF;

/// Command: status, the roles computed, turn rates (rad/s; 0 for a role not computed), chosen
/// circles, predicted capture time and upper/lower values (s; +inf where none).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CommandMsg {
    /// Status code (see `docs/protocol.md`).
    pub status: u8,
    /// Roles computed.
    pub roles: u8,
    /// Pursuer turn rate v_pm w_p, rad/s.
    pub pursuer_rate: f32,
    /// Evader turn rate v_em w_e, rad/s.
    pub evader_rate: f32,
    /// Pursuer circle: 0 A, 1 C, 0xFF none.
    pub row: u8,
    /// Evader circle: 0 A, 1 C, 0xFF none.
    pub col: u8,
    /// Predicted capture time (the upper value), seconds.
    pub predicted: f32,
    /// Upper value, seconds.
    pub upper: f32,
    /// Lower value, seconds.
    pub lower: f32,
    /// The team's chaser (its index; [`NO_MEMBER`] without a team or a chaser): protocol
    /// version 3's append.
    pub chaser: u8,
}

impl CommandMsg {
    /// Payload length, bytes.
    pub const LEN: usize = 25;
    /// Payload length in protocol versions 1 and 2 (no chaser), bytes.
    pub const LEN_V2: usize = 24;

    /// Parses a payload: [`CommandMsg::LEN`] bytes, or [`CommandMsg::LEN_V2`] (no chaser).
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let mut m = CommandMsg {
            status: r.u8()?,
            roles: r.u8()?,
            pursuer_rate: r.f32()?,
            evader_rate: r.f32()?,
            row: r.u8()?,
            col: r.u8()?,
            predicted: r.f32()?,
            upper: r.f32()?,
            lower: r.f32()?,
            chaser: NO_MEMBER,
        };
        if payload.len() > Self::LEN_V2 {
            m.chaser = r.u8()?;
        }
        r.finish()?;
        Ok(m)
    }

    /// Writes the payload of the current version.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        self.emit_in(crate::protocol::frame::VERSION, w)
    }

    /// Writes the payload of protocol versions 1 and 2 (without the chaser).
    pub fn emit_v2(&self, w: &mut Writer<'_>) -> Option<()> {
        self.emit_in(2, w)
    }

    /// Writes the payload of protocol `version`: the chaser from version 3.
    pub fn emit_in(&self, version: u8, w: &mut Writer<'_>) -> Option<()> {
        w.u8(self.status)?;
        w.u8(self.roles)?;
        w.f32(self.pursuer_rate)?;
        w.f32(self.evader_rate)?;
        w.u8(self.row)?;
        w.u8(self.col)?;
        w.f32(self.predicted)?;
        w.f32(self.upper)?;
        w.f32(self.lower)?;
        if version >= 3 {
            w.u8(self.chaser)?;
        }
        Some(())
    }
}

/// Error: the [`WireError`] code, and whether the header's sequence echoes the input's (1) or is
/// unknown (0: the input was not readable).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ErrorMsg {
    /// [`WireError`] code.
    pub code: u8,
    /// 1 if the sequence is the refused input's.
    pub sequence_known: u8,
}

impl ErrorMsg {
    /// Payload length, bytes.
    pub const LEN: usize = 2;

    /// Parses a payload.
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let m = ErrorMsg {
            code: r.u8()?,
            sequence_known: r.u8()?,
        };
        r.finish()?;
        Ok(m)
    }

    /// Writes the payload.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        w.u8(self.code)?;
        w.u8(self.sequence_known)
    }
}

/// Faults of the serial line below the framing, counted by the UART's interrupt and the loop
/// (`crate::serial`): the bytes the line lost or damaged, not frames. Appended to [`Counters`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LineCounts {
    /// Receive overruns: a byte arrived before the previous one was read (one byte lost).
    pub overrun: u32,
    /// Framing errors: a byte without its stop bit (the byte is dropped).
    pub framing: u32,
    /// Noise flagged on a received byte (the byte is kept; its frame's CRC decides).
    pub noise: u32,
    /// Parity errors (the byte is dropped; the link is 8N1, so only a misconfigured peer).
    pub parity: u32,
    /// Received bytes dropped because the receive queue was full.
    pub rx_full: u32,
    /// Replies dropped whole because the transmit queue had no room for them.
    pub tx_full: u32,
}

impl LineCounts {
    /// Payload length, bytes.
    pub const LEN: usize = 24;

    fn parse(r: &mut Reader<'_>) -> Result<Self, WireError> {
        Ok(LineCounts {
            overrun: r.u32()?,
            framing: r.u32()?,
            noise: r.u32()?,
            parity: r.u32()?,
            rx_full: r.u32()?,
            tx_full: r.u32()?,
        })
    }

    fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        w.u32(self.overrun)?;
        w.u32(self.framing)?;
        w.u32(self.noise)?;
        w.u32(self.parity)?;
        w.u32(self.rx_full)?;
        w.u32(self.tx_full)
    }
}

/// Counters: valid messages handled, watchdog expiries, refused inputs per [`WireError`] code,
/// then the line's faults, the board's status and the estimator's counts (each appended: a
/// reader of the first [`Counters::LEN_V1`], [`Counters::LEN_V2`] or [`Counters::LEN_V3`]
/// bytes keeps working).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Valid messages handled.
    pub accepted: u32,
    /// Watchdog expiries (stale input).
    pub stale: u32,
    /// Refused inputs, index = code - 1.
    pub errors: [u32; crate::protocol::frame::ERROR_KINDS],
    /// Faults of the serial line (0 where the unit has no UART of its own, as on the host).
    pub line: LineCounts,
    /// The board's status flags ([`BOARD_FALLBACK_CLOCK`]; 0 on the host).
    pub board: u32,
    /// States answered with no new evader fix since the State before: the target coasted
    /// (protocol version 2).
    pub coasted: u32,
    /// Fixes the estimator refused: out of order, repeated or outliers (protocol version 2).
    pub fixes_refused: u32,
}

/// Board status flag: the board runs on its fallback clock (its crystal or PLL did not start).
pub const BOARD_FALLBACK_CLOCK: u32 = 1;

impl Counters {
    /// Payload length of the first release (no line faults), bytes.
    pub const LEN_V1: usize = 8 + 4 * crate::protocol::frame::ERROR_KINDS;
    /// Payload length with the line's faults and without the board's status, bytes.
    pub const LEN_V2: usize = Self::LEN_V1 + LineCounts::LEN;
    /// Payload length with the board's status and without the estimator's counts, bytes.
    pub const LEN_V3: usize = Self::LEN_V2 + 4;
    /// Payload length, bytes.
    pub const LEN: usize = Self::LEN_V3 + 8;

    /// Counts one refused input.
    pub fn count(&mut self, error: WireError) {
        let index = usize::from(error as u8).saturating_sub(1);
        if let Some(c) = self.errors.get_mut(index) {
            *c = c.saturating_add(1);
        }
    }

    /// The count for one kind.
    pub fn of(&self, error: WireError) -> u32 {
        let index = usize::from(error as u8).saturating_sub(1);
        self.errors.get(index).copied().unwrap_or(0)
    }

    /// Parses a payload: [`Counters::LEN`] bytes, or the earlier [`Counters::LEN_V1`],
    /// [`Counters::LEN_V2`] or [`Counters::LEN_V3`] (what a shorter payload lacks then 0).
    ///
    /// # Errors
    /// `Truncated` if short, `Oversized` if long.
    pub fn parse(payload: &[u8]) -> Result<Self, WireError> {
        let mut r = Reader::new(payload);
        let mut m = Counters {
            accepted: r.u32()?,
            stale: r.u32()?,
            ..Counters::default()
        };
        for c in m.errors.iter_mut() {
            *c = r.u32()?;
        }
        if payload.len() > Self::LEN_V1 {
            m.line = LineCounts::parse(&mut r)?;
        }
        if payload.len() > Self::LEN_V2 {
            m.board = r.u32()?;
        }
        if payload.len() > Self::LEN_V3 {
            m.coasted = r.u32()?;
            m.fixes_refused = r.u32()?;
        }
        r.finish()?;
        Ok(m)
    }

    /// Writes the payload.
    pub fn emit(&self, w: &mut Writer<'_>) -> Option<()> {
        w.u32(self.accepted)?;
        w.u32(self.stale)?;
        for c in self.errors {
            w.u32(c)?;
        }
        self.line.emit(w)?;
        w.u32(self.board)?;
        w.u32(self.coasted)?;
        w.u32(self.fixes_refused)
    }
}
