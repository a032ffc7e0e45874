//! The guidance unit on the host: the scripted session, commands equal to the law, counters,
//! watchdog.

use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::{Endpoint, STATUS_STALE_INPUT};
use twocars::protocol::frame::WireError;
use twocars::protocol::message::ROLE_PURSUER;
use twocars::{Guidance, Law, Limits, Scalar, Variant, VehicleState};
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::session::{paper_configure, paper_state, script, Expect};

fn send<S: Scalar>(unit: &mut Endpoint<S>, bytes: &[u8], now_ms: u32) -> Vec<Reply> {
    let mut decoder = ReplyDecoder::default();
    let mut replies = Vec::new();
    for &b in bytes {
        if let Some(r) = unit.receive(b, now_ms) {
            replies.extend(
                decoder
                    .feed(r.as_bytes())
                    .into_iter()
                    .map(|r| r.expect("valid reply")),
            );
        }
    }
    replies
}

#[test]
fn the_scripted_session_gets_the_documented_replies_and_the_loop_survives() {
    let mut unit = Endpoint::<f32>::new();
    for step in script() {
        let replies = send(&mut unit, &step.bytes, 0);
        assert_eq!(replies.len(), 1, "{}: {replies:?}", step.name);
        let reply = replies[0];
        match (step.expect, reply) {
            (Expect::Ack, Reply::ConfigureAck(seq, _)) => assert_eq!(seq, step.sequence),
            (Expect::Error(code, known), Reply::Error(seq, e)) => {
                assert_eq!(WireError::from_code(e.code), Some(code), "{}", step.name);
                assert_eq!(seq.is_some(), known, "{}", step.name);
                if known {
                    assert_eq!(seq, Some(step.sequence), "{}", step.name);
                }
            }
            (Expect::Command(status), Reply::Command(seq, c)) => {
                assert_eq!((seq, c.status), (step.sequence, status), "{}", step.name);
            }
            (Expect::Counters, Reply::Counters(_, c)) => {
                // Every error kind at least once; five kinds twice.
                assert!(WireError::ALL.iter().all(|e| c.of(*e) >= 1), "{c:?}");
                assert_eq!(c.of(WireError::BadCrc), 1);
                assert_eq!(c.of(WireError::InvalidConfig), 3);
                assert_eq!(c.of(WireError::NonFiniteField), 2);
                assert_eq!(c.of(WireError::Truncated), 2);
                assert_eq!(c.of(WireError::Oversized), 2);
                assert_eq!(c.errors.iter().sum::<u32>(), 17);
                assert_eq!(c.accepted, twocars_sim::session::accepted());
            }
            (want, got) => panic!("{}: expected {want:?}, got {got:?}", step.name),
        }
    }
}

#[test]
fn commands_equal_the_host_law_bit_for_bit() {
    // Protocol version 1 steers on the states as they are; version 2 through the estimator,
    // which carries exact, instant fixes unchanged.
    for version in [1, 2] {
        let mut unit = Endpoint::<f32>::new();
        let configure = if version == 1 {
            link::configure_v1
        } else {
            link::configure
        };
        send(&mut unit, &configure(1, &paper_configure()), 0);
        each_paper_case_as_the_host_law(&mut unit, version);
    }
}

fn each_paper_case_as_the_host_law(unit: &mut Endpoint<f32>, version: u8) {
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let mut guidance = Guidance::new(
        Law::new(limits, Variant::Paper),
        0.01,
        twocars::Policy::Paper,
    )
    .unwrap();
    for case in 0..4 {
        let t_ms = 10 * case as u32;
        let s = paper_state(case, t_ms);
        let frame = if version == 1 {
            link::state_v1(2, &s)
        } else {
            link::state(2, &s)
        };
        let replies = send(unit, &frame, t_ms);
        let Reply::Command(_, c) = replies[0] else {
            panic!("{replies:?}")
        };
        let (p, e) = si_states(s.pursuer, s.evader);
        let ev = guidance.step(&p, &e);
        assert_eq!(
            c.pursuer_rate.to_bits(),
            (2.0 * ev.command.pursuer).to_bits()
        );
        assert_eq!(c.evader_rate.to_bits(), (1.0 * ev.command.evader).to_bits());
        let upper = ev.report.unwrap().solution.upper.unwrap();
        assert_eq!(c.predicted.to_bits(), upper.to_bits());
    }
}

#[test]
fn the_fixed_point_unit_answers_with_the_fixed_point_law_in_wire_units() {
    let mut unit = Endpoint::<Fixed>::new();
    send(&mut unit, &link::configure(1, &paper_configure()), 0);
    let limits = Limits::<Fixed>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let mut guidance = Guidance::new(
        Law::new(limits, Variant::Paper),
        0.01,
        twocars::Policy::Paper,
    )
    .unwrap();
    let mut float = Endpoint::<f32>::new();
    send(&mut float, &link::configure(1, &paper_configure()), 0);
    for case in 0..4 {
        let t_ms = 10 * case as u32;
        let s = paper_state(case, t_ms);
        let want = f64::from(command(&send(&mut float, &link::state(2, &s), t_ms)).predicted);
        let c = command(&send(&mut unit, &link::state(2, &s), t_ms));
        let (p, e) = limits.states(s.pursuer, s.evader).unwrap();
        let ev = guidance.step(&p, &e);
        let units = ev.units;
        // Rates: v w in rad/s; the law's command converted in f64, rounded once to f32.
        let rate = |w: Fixed, v: f64| (units.curvature(w) * v) as f32;
        assert_eq!(c.pursuer_rate, rate(ev.command.pursuer, 2.0), "case {case}");
        assert_eq!(c.evader_rate, rate(ev.command.evader, 1.0), "case {case}");
        let upper = units.seconds(ev.report.unwrap().solution.upper.unwrap());
        assert_eq!(c.predicted, upper as f32, "case {case}");
        // Within the fixed-point law's documented error (docs/numeric.md: 5.3e-4 relative).
        let error = (f64::from(c.predicted) - want).abs() / want;
        assert!(error < 5.3e-4, "case {case}: {} vs f32 {want}", c.predicted);
    }
    // Outside the fixed-point envelope (200 r_p = 100 m here): out_of_range, safe command.
    let mut far = paper_state(0, 10);
    far.evader[0] = 150.0;
    let replies = send(&mut unit, &link::state(3, &far), 10);
    assert!(
        matches!(replies[..], [Reply::Error(Some(3), e)] if e.code == WireError::OutOfRangeField as u8),
        "{replies:?}"
    );
}

#[test]
fn a_role_not_computed_gets_zero_rate() {
    let mut unit = Endpoint::<f32>::new();
    let config = twocars::protocol::message::Configure {
        roles: ROLE_PURSUER,
        ..paper_configure()
    };
    send(&mut unit, &link::configure(1, &config), 0);
    let replies = send(&mut unit, &link::state(2, &paper_state(0, 0)), 0);
    let Reply::Command(_, c) = replies[0] else {
        panic!()
    };
    assert_eq!(c.evader_rate, 0.0);
    assert_eq!(c.pursuer_rate, 4.0);
}

fn command(replies: &[Reply]) -> twocars::protocol::message::CommandMsg {
    match replies {
        [Reply::Command(_, c)] => *c,
        other => panic!("expected one Command, got {other:?}"),
    }
}

#[test]
fn the_watchdog_sends_the_safe_command_once_after_silence_and_stays_latched() {
    let mut unit = Endpoint::<f32>::new();
    assert!(unit.poll(10_000).is_none(), "unconfigured: silent");
    send(&mut unit, &link::configure(1, &paper_configure()), 0);
    assert!(
        unit.poll(10_000).is_none(),
        "configured but no state yet: not armed"
    );
    send(&mut unit, &link::state(2, &paper_state(0, 0)), 1000);
    assert!(unit.poll(1500).is_none(), "within 0.5 s");
    let reply = unit.poll(1501).expect("stale after 0.5 s");
    let c = command(
        &ReplyDecoder::default()
            .feed(reply.as_bytes())
            .into_iter()
            .map(Result::unwrap)
            .collect::<Vec<_>>(),
    );
    assert_eq!(c.status, STATUS_STALE_INPUT);
    assert_eq!((c.pursuer_rate, c.evader_rate), (0.0, 0.0));
    assert!(unit.poll(5000).is_none(), "once per silence");
    assert_eq!(unit.counters().stale, 1);
    // A fresh State does not silently resume: still the safe command.
    let c = command(&send(
        &mut unit,
        &link::state(3, &paper_state(0, 600)),
        6000,
    ));
    assert_eq!(c.status, STATUS_STALE_INPUT);
    assert_eq!((c.pursuer_rate, c.evader_rate), (0.0, 0.0));
    // An explicit Reset does.
    assert_eq!(
        send(&mut unit, &link::reset(4), 6001),
        vec![Reply::ResetAck(4)]
    );
    let c = command(&send(
        &mut unit,
        &link::state(5, &paper_state(0, 610)),
        6002,
    ));
    assert_eq!(c.status, 0);
    assert_eq!(c.pursuer_rate, 4.0);
}

#[test]
fn a_gap_in_the_senders_timestamps_latches_even_when_frames_keep_arriving() {
    let mut unit = Endpoint::<f32>::new();
    send(&mut unit, &link::configure(1, &paper_configure()), 0);
    assert_eq!(
        command(&send(&mut unit, &link::state(2, &paper_state(0, 100)), 0)).status,
        0
    );
    assert_eq!(
        command(&send(&mut unit, &link::state(3, &paper_state(0, 500)), 10)).status,
        0
    );
    // 0.6 s between the sender's stamps, although the frame came 10 ms later.
    let c = command(&send(&mut unit, &link::state(4, &paper_state(0, 1100)), 20));
    assert_eq!(c.status, STATUS_STALE_INPUT);
    // A timestamp going backwards (a replayed State) latches too, after a Configure clears it.
    send(&mut unit, &link::configure(5, &paper_configure()), 30);
    assert_eq!(
        command(&send(&mut unit, &link::state(6, &paper_state(0, 2000)), 40)).status,
        0
    );
    assert_eq!(
        command(&send(&mut unit, &link::state(7, &paper_state(0, 1990)), 50)).status,
        STATUS_STALE_INPUT
    );
    assert_eq!(unit.counters().stale, 2);
}

#[test]
fn the_configure_message_selects_the_policy() {
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let guidance = |policy| {
        Guidance::new(
            Law::new(limits, Variant::Paper),
            0.01,
            twocars::Policy::Paper,
        )
        .unwrap()
        .with_policy(policy)
    };
    // A near-field state (1 m apart, well below the threshold of 14.57 m) where the two
    // policies command the pursuer differently: its game is not a saddle.
    let state = (0..360)
        .map(|k| {
            let theta_e = k as f32 * core::f32::consts::TAU / 360.0;
            twocars::protocol::message::StateMsg::exact(0, [0.0, 0.0, 0.0], [0.6, 0.8, theta_e])
        })
        .find(|s| {
            let (p, e) = si_states(s.pursuer, s.evader);
            let paper = guidance(twocars::Policy::Paper).step(&p, &e).command;
            let near = guidance(twocars::Policy::Flight).step(&p, &e).command;
            paper.pursuer != near.pursuer
        })
        .expect("a state where the policies differ");
    let (p, e) = si_states(state.pursuer, state.evader);
    for (byte, policy) in [(0, twocars::Policy::Paper), (1, twocars::Policy::Flight)] {
        let mut unit = Endpoint::<f32>::new();
        let config = twocars::protocol::message::Configure {
            policy: byte,
            ..paper_configure()
        };
        send(&mut unit, &link::configure(1, &config), 0);
        let c = command(&send(&mut unit, &link::state(2, &state), 0));
        let want = guidance(policy).step(&p, &e).command;
        assert_eq!(c.pursuer_rate.to_bits(), (2.0 * want.pursuer).to_bits());
        assert_eq!(c.evader_rate.to_bits(), want.evader.to_bits());
    }
    // Policy 2 (the value tables) on a unit without tables: the flight policy, said in the ack
    // (tests/table_policy.rs has a unit with tables).
    let mut unit = Endpoint::<f32>::new();
    let config = twocars::protocol::message::Configure {
        policy: 2,
        ..paper_configure()
    };
    let replies = send(&mut unit, &link::configure(1, &config), 0);
    assert!(
        matches!(replies[..], [Reply::ConfigureAck(1, Some(1))]),
        "{replies:?}"
    );
    let mut unit = Endpoint::<f32>::new();
    let config = twocars::protocol::message::Configure {
        policy: 3,
        ..paper_configure()
    };
    let replies = send(&mut unit, &link::configure(1, &config), 0);
    assert!(
        matches!(replies[..], [Reply::Error(Some(1), e)] if WireError::from_code(e.code) == Some(WireError::InvalidConfig)),
        "{replies:?}"
    );
}

/// The bench's session of the serial loop (`twocars_bench::main_loop`, which `cargo xtask bench`
/// times on the Cortex-M4F): the interrupt handler and the loop over the scripted UART answer it
/// as the unit answers it byte by byte, ends at its Shutdown, and the script holds what it says: two
/// Configures, a Command for each State, four refusals, Counters.
#[test]
fn the_main_loop_bench_session_is_served_as_the_unit_answers_it() {
    use twocars_bench::main_loop::{script, serve_script, state_frames, SCRIPT_CAPACITY};
    for with_states in [true, false] {
        let mut bytes = [0u8; SCRIPT_CAPACITY];
        let n = script(with_states, false, &mut bytes).expect("the script fits its capacity");
        let script = &bytes[..n];
        let mut unit = Endpoint::<f32>::new();
        let mut written = Vec::new();
        for &b in script {
            if let Some(r) = unit.receive(b, 0) {
                written.extend_from_slice(r.as_bytes());
            }
        }
        let replies: Vec<Reply> = ReplyDecoder::default()
            .feed(&written)
            .into_iter()
            .map(|r| r.expect("valid reply"))
            .collect();
        let states = if with_states { state_frames(false) } else { 0 };
        assert_eq!(replies.len(), 2 + states + 4 + 2, "{replies:?}");
        let commands = replies
            .iter()
            .filter(|r| matches!(r, Reply::Command(s, c) if *s > 0 && c.status == 0))
            .count();
        // Every bench state has a game (status Ok) except the one without a valid tangent
        // (status 5), under each policy.
        let no_tangent = replies
            .iter()
            .filter(|r| matches!(r, Reply::Command(_, c) if c.status == 5))
            .count();
        assert_eq!(commands + no_tangent, states, "{replies:?}");
        assert_eq!(no_tangent, if with_states { 2 } else { 0 });
        let refused: Vec<_> = replies
            .iter()
            .filter_map(|r| match r {
                Reply::Error(_, e) => WireError::from_code(e.code),
                _ => None,
            })
            .collect();
        assert_eq!(
            refused,
            [
                WireError::UnknownType,
                WireError::Truncated,
                WireError::NonFiniteField,
                WireError::BadCrc
            ]
        );
        assert!(matches!(replies[replies.len() - 2], Reply::Counters(..)));
        assert!(matches!(replies[replies.len() - 1], Reply::ShutdownAck(_)));

        let digest = written
            .iter()
            .fold(0u32, |d, &b| d.rotate_left(5) ^ u32::from(b));
        let served = serve_script(&mut twocars::serial::Line::new(), script, &[]);
        let counters = unit.counters();
        assert!(served.shutdown);
        assert_eq!(served.replies as usize, replies.len());
        assert_eq!(served.digest, digest);
        assert_eq!(served.accepted, counters.accepted);
        assert_eq!(served.refused, counters.errors.iter().sum::<u32>());
    }
}

/// The raw bytes (COBS-framed) of the last reply `unit` wrote while fed `bytes` at `now_ms`.
fn last_reply_bytes(unit: &mut Endpoint, bytes: &[u8], now_ms: u32) -> Option<Vec<u8>> {
    let mut reply = None;
    for &b in bytes {
        if let Some(r) = unit.receive(b, now_ms) {
            reply = Some(r.as_bytes().to_vec());
        }
    }
    reply
}

/// Golden bytes: a State of protocol version 4, sequence 0x0278, valid CRC.
/// Its header is readable, so the Error (code 6, bad_version) echoes its sequence: reply body
/// `03 8f 78 02 06 01` (in the unit's own version, 3) with CRC 0x9488, COBS-framed.
#[test]
fn a_frame_of_another_version_gets_bad_version_with_its_sequence_echoed() {
    let mut body = vec![0x04, 0x02, 0x78, 0x02];
    body.extend([0x5a; 44]);
    let crc = twocars::protocol::frame::crc16(&body);
    body.extend(crc.to_le_bytes());
    let mut encoded = [0u8; 80];
    let n = twocars::protocol::frame::cobs_encode(&body, &mut encoded).expect("fits");
    let mut frame = encoded[..n].to_vec();
    frame.push(0);
    let reply = last_reply_bytes(&mut Endpoint::<f32>::new(), &frame, 0);
    assert_eq!(
        reply.as_deref(),
        Some(&[0x09, 0x03, 0x8f, 0x78, 0x02, 0x06, 0x01, 0x88, 0x94, 0x00][..])
    );
}

/// Golden bytes: the contract checks non-finite fields before the envelope,
/// across the whole State. A State (sequence 0x0102) whose pursuer heading is out of the envelope
/// (2e4 rad) and whose evader y is NaN gets Error 7 (non_finite_field) with its sequence echoed,
/// `03 8f 02 01 07 01` with CRC 0xd437, not Error 8 (out_of_range_field) for the heading met
/// first.
#[test]
fn a_non_finite_field_is_refused_before_an_out_of_range_one_anywhere_in_the_state() {
    let mut unit = Endpoint::<f32>::new();
    let acks = send(&mut unit, &link::configure(1, &paper_configure()), 0);
    assert_eq!(acks.len(), 1);
    let mut state = paper_state(0, 10);
    state.pursuer[2] = 2.0e4;
    state.evader[1] = f32::NAN;
    let reply = last_reply_bytes(&mut unit, &link::state(0x0102, &state), 10);
    assert_eq!(
        reply.as_deref(),
        Some(&[0x09, 0x03, 0x8f, 0x02, 0x01, 0x07, 0x01, 0x37, 0xd4, 0x00][..])
    );
}

/// Under the fallback (status 5, no valid tangent) the Command's circle bytes
/// name the circle each player actually turns on, 0xFF where it goes straight (the shared
/// contract), not the game's row and column. Over a scan of states within 2 m at the paper's
/// limits, every status-5 Command's bytes agree with the signs of its rates.
#[test]
fn fallback_commands_name_the_circle_actually_turned() {
    let mut unit = Endpoint::<f32>::new();
    assert_eq!(
        send(&mut unit, &link::configure(1, &paper_configure()), 0).len(),
        1
    );
    let code = |rate: f32| match rate.partial_cmp(&0.0) {
        Some(std::cmp::Ordering::Greater) => 0,
        Some(std::cmp::Ordering::Less) => 1,
        _ => 0xFF,
    };
    let (mut fallbacks, mut t_ms) = (0, 10);
    for i in 0..21 {
        for j in 0..21 {
            for k in 0..8 {
                let evader = [
                    -2.0 + 0.2 * i as f32,
                    -2.0 + 0.2 * j as f32,
                    -3.0 + 0.75 * k as f32,
                ];
                let state =
                    twocars::protocol::message::StateMsg::exact(t_ms, [0.0, 0.0, 0.0], evader);
                let replies = send(&mut unit, &link::state(7, &state), t_ms);
                t_ms += 10;
                let c = command(&replies);
                if c.status == 5 {
                    fallbacks += 1;
                    assert_eq!(
                        (c.row, c.col),
                        (code(c.pursuer_rate), code(c.evader_rate)),
                        "{evader:?}: {c:?}"
                    );
                }
            }
        }
    }
    assert!(fallbacks >= 10, "{fallbacks} fallback states");
}

/// Both states on an SI backend, metres and radians.
fn si_states(pursuer: [f32; 3], evader: [f32; 3]) -> (VehicleState<f32>, VehicleState<f32>) {
    let limits = twocars::Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).expect("the paper's limits");
    limits.states(pursuer, evader).expect("in the envelope")
}
