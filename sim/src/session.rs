//! A scripted session for the guidance unit: every kind of bad input, then valid states. The host
//! tests run it through `twocars::protocol::endpoint::Endpoint`; `cargo xtask test` runs it
//! through the firmware in QEMU and compares the replies byte for byte.

use crate::link;
use twocars::protocol::frame::{cobs_encode, crc16, WireError, VERSION};
use twocars::protocol::message::{
    Configure, FieldConfig, StateMsg, TeamConfig, ROLE_EVADER, ROLE_PURSUER,
};

/// What a step must get back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expect {
    /// ConfigureAck with the step's sequence.
    Ack,
    /// Error with this code (sequence echoed if `known`).
    Error(WireError, bool),
    /// Command with this wire status and the step's sequence.
    Command(u8),
    /// Counters.
    Counters,
}

/// One scripted input and its expected reply.
#[derive(Clone, Debug)]
pub struct Step {
    /// What the step exercises.
    pub name: &'static str,
    /// Sequence number of the input (where it has one).
    pub sequence: u16,
    /// Bytes sent.
    pub bytes: Vec<u8>,
    /// Reply expected.
    pub expect: Expect,
}

/// The paper's limits at 100 Hz, both roles, watchdog 0.5 s.
pub fn paper_configure() -> Configure {
    Configure {
        limits: [2.0, 2.0, 1.0, 1.0],
        dt: 0.01,
        watchdog: 0.5,
        roles: ROLE_PURSUER | ROLE_EVADER,
        variant: 0,
        policy: 0,
        field: FieldConfig::EXACT,
        team: TeamConfig::NONE,
    }
}

fn with_bad_version(sequence: u16) -> Vec<u8> {
    let mut raw = vec![VERSION + 1, 0x02, sequence as u8, (sequence >> 8) as u8];
    let crc = crc16(&raw);
    raw.extend(crc.to_le_bytes());
    let mut out = [0u8; 32];
    let n = cobs_encode(&raw, &mut out).expect("fits");
    out[..n].to_vec()
}

fn with_bad_crc(sequence: u16) -> Vec<u8> {
    // A valid State frame with one payload byte flipped after encoding (never to 0x00).
    let mut bytes = link::state(sequence, &paper_state(0, 0));
    let at = bytes.len() / 2;
    bytes[at] = if bytes[at] == 0x7F { 0x7E } else { 0x7F };
    bytes
}

/// The paper's case `case` (0..4) as a State at time `t_ms`.
pub fn paper_state(case: usize, t_ms: u32) -> StateMsg {
    let cases = crate::scenarios::paper_cases();
    let c = cases[case % cases.len()];
    StateMsg::exact(
        t_ms,
        c.pursuer.map(|v| v as f32),
        c.evader.map(|v| v as f32),
    )
}

/// The script.
pub fn script() -> Vec<Step> {
    let good = paper_configure();
    let step = |name, sequence, bytes, expect| Step {
        name,
        sequence,
        bytes,
        expect,
    };
    let mut nan_state = paper_state(0, 10);
    nan_state.evader[1] = f32::NAN;
    let mut far_state = paper_state(0, 10);
    far_state.pursuer[0] = 1.0e7;
    // The evader's fix 140 ms older than the State, carried to it by the unit's estimator.
    let late_state = StateMsg {
        evader_time_ms: 60,
        ..paper_state(1, 200)
    };
    vec![
        step(
            "state before configure",
            1,
            link::state(1, &paper_state(0, 0)),
            Expect::Error(WireError::NotConfigured, true),
        ),
        step(
            "slower pursuer",
            2,
            link::configure(
                2,
                &Configure {
                    limits: [1.0, 2.0, 2.0, 1.0],
                    ..good
                },
            ),
            Expect::Error(WireError::InvalidLimits, true),
        ),
        step(
            "zero period",
            3,
            link::configure(3, &Configure { dt: 0.0, ..good }),
            Expect::Error(WireError::InvalidConfig, true),
        ),
        step(
            "no role",
            4,
            link::configure(4, &Configure { roles: 0, ..good }),
            Expect::Error(WireError::InvalidConfig, true),
        ),
        step(
            "NaN limit",
            5,
            link::configure(
                5,
                &Configure {
                    limits: [2.0, f32::NAN, 1.0, 1.0],
                    ..good
                },
            ),
            Expect::Error(WireError::NonFiniteField, true),
        ),
        step(
            "absurd speed",
            6,
            link::configure(
                6,
                &Configure {
                    limits: [1.0e9, 2.0, 1.0, 1.0],
                    ..good
                },
            ),
            Expect::Error(WireError::OutOfRangeField, true),
        ),
        step("configure", 7, link::configure(7, &good), Expect::Ack),
        step(
            "bad CRC",
            8,
            with_bad_crc(8),
            Expect::Error(WireError::BadCrc, false),
        ),
        step(
            "truncated frame",
            9,
            vec![0x03, 0x01, 0x02, 0x00],
            Expect::Error(WireError::Truncated, false),
        ),
        step(
            "oversized frame",
            10,
            [vec![0x55; 150], vec![0x00]].concat(),
            Expect::Error(WireError::Oversized, false),
        ),
        step(
            "unknown type",
            11,
            link::raw(0x55, 11, &[1, 2, 3]),
            Expect::Error(WireError::UnknownType, true),
        ),
        step(
            "bad version",
            12,
            with_bad_version(12),
            Expect::Error(WireError::BadVersion, true),
        ),
        step(
            "bad COBS",
            13,
            vec![0x05, 0x11, 0x00],
            Expect::Error(WireError::BadFraming, false),
        ),
        step(
            "NaN in state",
            14,
            link::state(14, &nan_state),
            Expect::Error(WireError::NonFiniteField, true),
        ),
        step(
            "absurd coordinate",
            15,
            link::state(15, &far_state),
            Expect::Error(WireError::OutOfRangeField, true),
        ),
        step(
            "short state",
            16,
            link::raw(0x02, 16, &[0; 10]),
            Expect::Error(WireError::Truncated, true),
        ),
        step(
            "long state",
            17,
            link::raw(0x02, 17, &[0; 34]),
            Expect::Error(WireError::Oversized, true),
        ),
        step(
            "paper case 1",
            18,
            link::state(18, &paper_state(0, 20)),
            Expect::Command(0),
        ),
        step(
            "paper case 2",
            19,
            link::state(19, &paper_state(1, 30)),
            Expect::Command(0),
        ),
        step(
            "paper case 3",
            20,
            link::state(20, &paper_state(2, 40)),
            Expect::Command(0),
        ),
        step(
            "paper case 4",
            21,
            link::state(21, &paper_state(3, 50)),
            Expect::Command(0),
        ),
        step(
            "late target fix",
            22,
            link::state(22, &late_state),
            Expect::Command(0),
        ),
        step(
            "version 1 state",
            23,
            link::state_v1(23, &paper_state(1, 250)),
            Expect::Command(0),
        ),
        step(
            "lag beyond the watchdog",
            24,
            link::configure(
                24,
                &Configure {
                    field: FieldConfig {
                        target_lag: good.watchdog,
                        ..FieldConfig::EXACT
                    },
                    ..good
                },
            ),
            Expect::Error(WireError::InvalidConfig, true),
        ),
        step("counters", 25, link::read_counters(25), Expect::Counters),
    ]
}

/// Inputs the script's Counters count as accepted: its Acks and Commands.
pub fn accepted() -> u32 {
    let answered = |s: &&Step| matches!(s.expect, Expect::Ack | Expect::Command(_));
    script().iter().filter(answered).count() as u32
}
