//! The whole unit, bytes in -> bytes out: after an optional valid Configure (first input byte
//! odd; in a team of three where its bit 2 is set), arbitrary bytes; every reply must itself be a valid frame of a known type whose payload
//! parses, every command finite and within +-v_max w_max, and never `ok` for a refused input;
//! on the f32 and the fixed-point backends.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::Endpoint;
use twocars::protocol::frame::{encode_frame, Deframer, Feed, Frame, MAX_ENCODED, MAX_FRAME};
use twocars::protocol::message::{
    kind, CommandMsg, Configure, Counters, ErrorMsg, FieldConfig, TeamConfig, NO_MEMBER,
};
use twocars::Scalar;

const LIMITS: [f32; 4] = [2.0, 2.0, 1.0, 1.0];

fn check_reply(bytes: &[u8]) {
    assert_eq!(bytes.last(), Some(&0), "a reply ends with its delimiter");
    let mut deframer = Deframer::<MAX_FRAME>::new();
    let mut frames = 0;
    for &b in bytes {
        match deframer.push(b) {
            Feed::Pending => {}
            Feed::Error(e) => panic!("reply does not deframe: {e:?}"),
            Feed::Frame(f) => {
                frames += 1;
                let frame = Frame::new_checked(f).expect("reply frame passes its own checks");
                let p = frame.payload();
                match frame.message_type() {
                    kind::COMMAND => {
                        let c = CommandMsg::parse(p).expect("command parses");
                        for (rate, max) in [(c.pursuer_rate, 4.0f32), (c.evader_rate, 1.0)] {
                            assert!(
                                rate.is_finite() && rate.abs() <= max * (1.0 + 1e-6),
                                "rate {rate}"
                            );
                        }
                        assert!(!c.predicted.is_nan() && !c.upper.is_nan() && !c.lower.is_nan());
                        assert!(c.chaser < 3 || c.chaser == NO_MEMBER, "chaser {}", c.chaser);
                    }
                    kind::ERROR => {
                        ErrorMsg::parse(p).expect("error parses");
                    }
                    kind::COUNTERS => {
                        Counters::parse(p).expect("counters parse");
                    }
                    // The policy in effect (docs/protocol.md).
                    kind::CONFIGURE_ACK => assert!(matches!(p, [0..=2])),
                    kind::SHUTDOWN_ACK | kind::RESET_ACK | kind::TEAMMATE_ACK => {
                        assert!(p.is_empty())
                    }
                    other => panic!("unknown reply type {other:#x}"),
                }
            }
        }
    }
    assert_eq!(frames, 1, "one frame per reply");
}

fuzz_target!(|data: &[u8]| {
    // The f32 unit (the M4F images) and the fixed-point one (the micro:bit's).
    session::<f32>(data);
    session::<Fixed>(data);
});

fn session<S: Scalar>(data: &[u8]) {
    let mut unit = Endpoint::<S>::new();
    let mut now = 0u32;
    if data.first().is_some_and(|b| b & 1 == 1) {
        let c = Configure {
            limits: LIMITS,
            dt: 0.01,
            watchdog: 0.5,
            roles: 3,
            variant: 0,
            policy: 0,
            // Half the sessions through the estimator with every setting of the field.
            field: if data.first().is_some_and(|b| b & 2 == 2) {
                FieldConfig {
                    target_lag: 0.1,
                    target_sigma: 0.2,
                    target_heading_sigma: 0.1,
                    own_lead: 0.05,
                }
            } else {
                FieldConfig::EXACT
            },
            // A quarter of them in a team of three, this unit's pursuer the second.
            team: if data.first().is_some_and(|b| b & 4 == 4) {
                TeamConfig { size: 3, own: 1 }
            } else {
                TeamConfig::NONE
            },
        };
        let mut out = [0u8; MAX_ENCODED];
        let n = encode_frame(kind::CONFIGURE, 1, |w| c.emit(w), &mut out).expect("fits");
        for &b in &out[..n] {
            if let Some(r) = unit.receive(b, now) {
                check_reply(r.as_bytes());
            }
        }
    }
    for &b in data.iter().skip(1) {
        now = now.wrapping_add(u32::from(b & 0x0F));
        if let Some(r) = unit.receive(b, now) {
            check_reply(r.as_bytes());
        }
        if let Some(r) = unit.poll(now) {
            check_reply(r.as_bytes());
        }
    }
}
