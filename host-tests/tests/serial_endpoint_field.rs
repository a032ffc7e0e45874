//! The serial unit's door to the estimator (protocol version 2): the evader's fix time and the
//! Configure's field settings reach `twocars::estimate` as the Rust API takes them, the counters
//! count what the estimator did, and version 1 is still answered in version 1.

use twocars::estimate::{Estimator, FieldSettings, Fix, FixNoise};
use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::{Endpoint, STATUS_STALE_INPUT};
use twocars::protocol::frame::WireError;
use twocars::protocol::message::{Configure, FieldConfig, StateMsg, ROLE_EVADER, ROLE_PURSUER};
use twocars::{Guidance, Law, Limits, Policy, Scalar, Variant};
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::session::{paper_configure, paper_state};

fn send<S: Scalar>(unit: &mut Endpoint<S>, bytes: &[u8], now_ms: u32) -> Vec<Reply> {
    let mut decoder = ReplyDecoder::default();
    let mut replies = Vec::new();
    for &b in bytes {
        if let Some(r) = unit.receive(b, now_ms) {
            replies.extend(decoder.feed(r.as_bytes()).into_iter().map(|r| r.unwrap()));
        }
    }
    replies
}

const FIELD: FieldConfig = FieldConfig {
    target_lag: 0.2,
    target_sigma: 0.1,
    target_heading_sigma: 0.05,
    own_lead: 0.1,
};

fn field_configure() -> Configure {
    Configure {
        roles: ROLE_PURSUER,
        policy: 1,
        field: FIELD,
        ..paper_configure()
    }
}

/// A chase's States: the pursuer every 20 ms heading +x at 2 m/s; the evader circling at
/// 1 m/s, its fix every 200 ms with a deterministic wobble of a few centimetres.
fn states() -> impl Iterator<Item = StateMsg> {
    (0..100u32).map(|k| {
        let t_ms = 1_000 + 20 * k;
        let fix_ms = t_ms - t_ms % 200;
        let s = fix_ms as f32 / 1000.0;
        let wobble = 0.03 * ((fix_ms / 200) as f32 * 2.1).sin();
        StateMsg {
            time_ms: t_ms,
            pursuer: [2.0 * t_ms as f32 / 1000.0 - 8.0, 0.5, 0.0],
            evader: [4.0 * s.sin() + wobble, 4.0 - 4.0 * s.cos(), s],
            evader_time_ms: fix_ms,
        }
    })
}

/// The unit's Command for each State equals `decide_estimated` on an estimator fed the same
/// fixes by the Rust API, bit for bit: the fix time, the lag and the lead reach it unchanged.
#[test]
fn late_noisy_fixes_are_steered_on_as_the_estimator_carries_them() {
    let mut unit = Endpoint::<f32>::new();
    send(&mut unit, &link::configure(1, &field_configure()), 0);
    let settings = FieldSettings {
        target_noise: FixNoise {
            position: FIELD.target_sigma,
            heading: FIELD.target_heading_sigma,
        },
        target_lag: FIELD.target_lag,
        own_lead: FIELD.own_lead,
        ..FieldSettings::exact(0.5)
    };
    let mut estimator = Estimator::new([2.0, 2.0, 1.0, 1.0], settings).unwrap();
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let mut guidance =
        Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Flight).unwrap();
    let mut last_fix = None;
    let mut turns = 0;
    for (k, state) in states().enumerate() {
        let replies = send(&mut unit, &link::state(k as u16, &state), state.time_ms);
        let [Reply::Command(_, c)] = replies[..] else {
            panic!("{replies:?}")
        };
        estimator
            .own_fix(&Fix {
                state: state.pursuer,
                time_us: state.time_ms * 1000,
            })
            .unwrap();
        if last_fix != Some(state.evader_time_ms) {
            last_fix = Some(state.evader_time_ms);
            estimator
                .target_fix_received(state.evader, state.evader_time_ms * 1000)
                .unwrap();
        }
        let estimated = estimator.states(state.time_ms * 1000).unwrap();
        let want = guidance.decide_estimated(&estimated).unwrap();
        assert_eq!(c.status, 0, "State {k}");
        assert_eq!(
            c.pursuer_rate.to_bits(),
            (2.0 * want.command.pursuer).to_bits(),
            "State {k}"
        );
        turns += usize::from(c.pursuer_rate != 0.0);
    }
    assert!(turns > 0, "the chase turns at least once");
    // The fix is taken 200 ms before its stamp: not where the State says the evader is.
    assert_ne!(
        estimator.target().last_fix_us(),
        Some(states().last().unwrap().evader_time_ms * 1000)
    );
    let replies = send(&mut unit, &link::read_counters(200), 4_000);
    let [Reply::Counters(_, counters)] = replies[..] else {
        panic!("{replies:?}")
    };
    // Ten States per fix: nine of them coast.
    assert_eq!(counters.coasted, estimator.counters().coasted);
    assert_eq!(counters.coasted, 90);
    assert_eq!(counters.fixes_refused, 0);
}

/// A fix older than the one held is refused and counted; a target whose last fix is older
/// than the watchdog time gets the safe command, latched as a gap in the States is.
#[test]
fn refused_and_stale_target_fixes_are_counted_and_get_the_safe_command() {
    let mut unit = Endpoint::<f32>::new();
    send(&mut unit, &link::configure(1, &field_configure()), 0);
    let first = paper_state(1, 1_000);
    let command = |replies: Vec<Reply>| match replies[..] {
        [Reply::Command(_, c)] => c,
        _ => panic!("{replies:?}"),
    };
    assert_eq!(
        command(send(&mut unit, &link::state(2, &first), 1_000)).status,
        0
    );
    let older = StateMsg {
        evader_time_ms: 900,
        ..paper_state(1, 1_050)
    };
    assert_eq!(
        command(send(&mut unit, &link::state(3, &older), 1_050)).status,
        0
    );
    // The last fix taken is at 1,000 ms less the 200 ms lag, 800 ms; a decision acts 100 ms
    // after its State. The same evader fix time again, acting 450 ms after the fix: coasted.
    let same = StateMsg {
        evader_time_ms: 900,
        ..paper_state(1, 1_150)
    };
    assert_eq!(
        command(send(&mut unit, &link::state(4, &same), 1_150)).status,
        0
    );
    // Acting 550 ms after it, past the 500 ms watchdog time: stale.
    let stale = StateMsg {
        evader_time_ms: 900,
        ..paper_state(1, 1_250)
    };
    let c = command(send(&mut unit, &link::state(5, &stale), 1_250));
    assert_eq!(c.status, STATUS_STALE_INPUT);
    assert_eq!(c.pursuer_rate, 0.0);
    // Latched: a fresh fix does not silently resume the law.
    let fresh = paper_state(1, 1_270);
    let c = command(send(&mut unit, &link::state(6, &fresh), 1_270));
    assert_eq!(c.status, STATUS_STALE_INPUT);
    let [Reply::Counters(_, counters)] = send(&mut unit, &link::read_counters(7), 1_280)[..] else {
        panic!()
    };
    assert_eq!(counters.fixes_refused, 1);
    // The refused fix's State and the repeated one's: no new fix taken.
    assert_eq!(counters.coasted, 2);
    assert_eq!(counters.stale, 1);
    // A Reset clears the latch and both tracks.
    send(&mut unit, &link::reset(8), 1_290);
    let c = command(send(
        &mut unit,
        &link::state(9, &paper_state(1, 1_300)),
        1_300,
    ));
    assert_eq!(c.status, 0);
}

/// Field settings outside their ranges are refused with invalid_config; the unit keeps its
/// configuration.
#[test]
fn impossible_field_settings_are_refused() {
    let bad = [
        FieldConfig {
            target_lag: -0.1,
            ..FIELD
        },
        FieldConfig {
            target_lag: 0.5,
            ..FIELD
        },
        FieldConfig {
            own_lead: 0.6,
            ..FIELD
        },
        FieldConfig {
            target_sigma: -1.0,
            ..FIELD
        },
        FieldConfig {
            target_sigma: 2.0e4,
            ..FIELD
        },
        FieldConfig {
            target_heading_sigma: 4.0,
            ..FIELD
        },
        FieldConfig {
            target_sigma: f32::NAN,
            ..FIELD
        },
        FieldConfig {
            own_lead: f32::INFINITY,
            ..FIELD
        },
    ];
    for (i, field) in bad.into_iter().enumerate() {
        let mut unit = Endpoint::<f32>::new();
        let config = Configure {
            field,
            ..field_configure()
        };
        let replies = send(&mut unit, &link::configure(i as u16, &config), 0);
        assert!(
            matches!(replies[..], [Reply::Error(Some(_), e)] if WireError::from_code(e.code) == Some(WireError::InvalidConfig)),
            "{field:?}: {replies:?}"
        );
    }
}

/// A version-1 frame is answered in version 1, version 2's in 2, version 3's in 3; a version-1
/// Configure leaves the estimator out.
#[test]
fn version_1_frames_are_answered_in_version_1() {
    let version_of = |bytes: &[u8]| link::deframe(bytes, None)[0].as_ref().unwrap()[0];
    let mut unit = Endpoint::<f32>::new();
    let ack = unit_reply(&mut unit, &link::configure_v1(1, &field_configure()), 0);
    assert_eq!(version_of(&ack), 1);
    let reply = unit_reply(&mut unit, &link::state_v1(2, &paper_state(0, 10)), 10);
    assert_eq!(version_of(&reply), 1);
    let reply = unit_reply(&mut unit, &link::state_v2(3, &paper_state(0, 20)), 20);
    assert_eq!(version_of(&reply), 2);
    let reply = unit_reply(&mut unit, &link::state(3, &paper_state(0, 25)), 25);
    assert_eq!(version_of(&reply), 3);
    let counters = unit_reply(&mut unit, &link::read_counters(4), 30);
    let counters = ReplyDecoder::default().feed(&counters);
    let Ok(Reply::Counters(_, counters)) = counters[0] else {
        panic!("{counters:?}")
    };
    // Without the estimator nothing coasts, however the fixes come.
    assert_eq!(counters.coasted, 0);
}

fn unit_reply<S: Scalar>(unit: &mut Endpoint<S>, bytes: &[u8], now_ms: u32) -> Vec<u8> {
    let mut out = Vec::new();
    for &b in bytes {
        if let Some(r) = unit.receive(b, now_ms) {
            out.extend(r.as_bytes());
        }
    }
    out
}

/// The fixed-point unit steers through the same estimator: its commands turn the way the f32
/// unit's do on the chase, and its predicted times agree within the fixed-point law's error.
#[test]
fn the_fixed_point_unit_steers_through_the_estimator_as_the_f32_one() {
    let mut float = Endpoint::<f32>::new();
    let mut fixed = Endpoint::<Fixed>::new();
    let config = Configure {
        roles: ROLE_PURSUER | ROLE_EVADER,
        ..field_configure()
    };
    send(&mut float, &link::configure(1, &config), 0);
    send(&mut fixed, &link::configure(1, &config), 0);
    let mut agree = 0;
    for (k, state) in states().enumerate() {
        let frame = link::state(k as u16, &state);
        let [Reply::Command(_, a)] = send(&mut float, &frame, state.time_ms)[..] else {
            panic!()
        };
        let [Reply::Command(_, b)] = send(&mut fixed, &frame, state.time_ms)[..] else {
            panic!()
        };
        assert_eq!(b.status, a.status, "State {k}");
        agree += usize::from(a.pursuer_rate.signum() == b.pursuer_rate.signum());
        let error = (a.predicted - b.predicted).abs() / a.predicted;
        assert!(
            error < 1.0e-2,
            "State {k}: {} vs {}",
            b.predicted,
            a.predicted
        );
    }
    assert!(agree >= 95, "{agree} of 100 States turn the same way");
}
