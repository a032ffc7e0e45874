//! The serial unit in a team (protocol version 3, feature `serial-team`): its Configure of a
//! team, Teammate frames and the Command's chaser; the turn the same as a unit alone.

use twocars::protocol::endpoint::Endpoint;
use twocars::protocol::frame::WireError;
use twocars::protocol::message::{
    kind, CommandMsg, Configure, StateMsg, TeamConfig, TeammateMsg, NO_MEMBER,
};
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::session::paper_configure;

fn send(unit: &mut Endpoint<f32>, bytes: &[u8]) -> Reply {
    let mut decoder = ReplyDecoder::default();
    let mut replies = Vec::new();
    for &b in bytes {
        if let Some(r) = unit.receive(b, 0) {
            replies.extend(decoder.feed(r.as_bytes()).into_iter().map(|r| r.unwrap()));
        }
    }
    assert_eq!(replies.len(), 1, "{replies:?}");
    replies[0]
}

fn refused(reply: Reply) -> Option<WireError> {
    match reply {
        Reply::Error(_, e) => WireError::from_code(e.code),
        _ => None,
    }
}

fn command(reply: Reply) -> CommandMsg {
    match reply {
        Reply::Command(_, c) => c,
        other => panic!("not a command: {other:?}"),
    }
}

/// The paper's limits (a full turn 1.57 s), a team of three, this unit's pursuer index 0.
fn team_configure() -> Configure {
    Configure {
        team: TeamConfig { size: 3, own: 0 },
        ..paper_configure()
    }
}

/// The evader runs along +x at v_em from 20 m ahead of this unit's pursuer, which follows at
/// v_pm: state at `t_ms`.
fn tail_chase(t_ms: u32) -> StateMsg {
    let t = t_ms as f32 / 1000.0;
    StateMsg::exact(t_ms, [2.0 * t, 0.0, 0.0], [20.0 + t, 0.0, 0.0])
}

fn mate(index: u8, time_ms: u32, state: [f32; 3]) -> TeammateMsg {
    TeammateMsg {
        index,
        time_ms,
        state,
    }
}

#[test]
fn a_teammate_close_behind_the_evader_takes_the_chase_after_the_dwell() {
    let mut unit = Endpoint::<f32>::new();
    assert!(matches!(
        send(&mut unit, &link::configure(1, &team_configure())),
        Reply::ConfigureAck(1, _)
    ));
    let mut took_over = None;
    for k in 0..800u32 {
        let t_ms = 10 * k;
        let s = tail_chase(t_ms);
        // From 1 s, teammate 1 is heard 2 m behind the evader, each 100 ms.
        if t_ms >= 1_000 && t_ms % 100 == 0 {
            let near = mate(1, t_ms, [s.evader[0] - 2.0, 0.0, 0.0]);
            assert!(matches!(
                send(&mut unit, &link::teammate(2, &near)),
                Reply::TeammateAck(2)
            ));
        }
        let c = command(send(&mut unit, &link::state(3, &s)));
        match (c.chaser, took_over) {
            (0, None) => {}
            (1, None) => took_over = Some(t_ms),
            (1, Some(_)) => {}
            other => panic!("chaser {other:?} at {t_ms} ms"),
        }
    }
    // This unit chased from its first State; the dwell is 3 full turns (4.71 s).
    let took_over = took_over.expect("teammate 1 never took the chase");
    println!("teammate 1 took the chase at {took_over} ms");
    assert!((4_700..=4_800).contains(&took_over), "{took_over} ms");
}

#[test]
fn a_silent_teammate_has_no_time_and_a_reset_forgets_it() {
    let mut unit = Endpoint::<f32>::new();
    send(&mut unit, &link::configure(1, &team_configure()));
    // Teammate 2 on the evader's tail before the first State: it chases at once.
    let s = tail_chase(0);
    send(&mut unit, &link::teammate(2, &mate(2, 0, [19.0, 0.0, 0.0])));
    assert_eq!(command(send(&mut unit, &link::state(3, &s))).chaser, 2);
    // Older than the watchdog (0.5 s) at the State's time: the chase is this unit's again,
    // however long the dwell.
    let later = tail_chase(450);
    assert_eq!(command(send(&mut unit, &link::state(4, &later))).chaser, 2);
    let stale = tail_chase(510);
    assert_eq!(command(send(&mut unit, &link::state(5, &stale))).chaser, 0);
    // Heard again, then a Reset: nothing heard, the roles named afresh.
    send(
        &mut unit,
        &link::teammate(6, &mate(2, 510, [20.0, 0.0, 0.0])),
    );
    assert!(matches!(
        send(&mut unit, &link::reset(7)),
        Reply::ResetAck(7)
    ));
    assert_eq!(
        command(send(&mut unit, &link::state(8, &tail_chase(520)))).chaser,
        0
    );
}

#[test]
fn teammates_outside_the_team_or_unconfigured_are_refused() {
    let mut unit = Endpoint::<f32>::new();
    let heard = link::teammate(1, &mate(1, 0, [1.0, 1.0, 0.0]));
    assert_eq!(
        refused(send(&mut unit, &heard)),
        Some(WireError::NotConfigured)
    );
    send(&mut unit, &link::configure(2, &paper_configure()));
    assert_eq!(
        refused(send(&mut unit, &heard)),
        Some(WireError::NotConfigured)
    );
    send(&mut unit, &link::configure(3, &team_configure()));
    for (m, error) in [
        (mate(0, 0, [1.0, 1.0, 0.0]), WireError::OutOfRangeField),
        (mate(3, 0, [1.0, 1.0, 0.0]), WireError::OutOfRangeField),
        (mate(1, 0, [f32::NAN, 1.0, 0.0]), WireError::NonFiniteField),
    ] {
        assert_eq!(
            refused(send(&mut unit, &link::teammate(4, &m))),
            Some(error)
        );
    }
    // A version-2 frame has no Teammate.
    let mut payload = [0u8; TeammateMsg::LEN];
    let mut w = twocars::protocol::frame::Writer::new(&mut payload);
    mate(1, 0, [1.0, 1.0, 0.0]).emit(&mut w).unwrap();
    let old = twocars_sim::link::raw_as(2, kind::TEAMMATE, 5, &payload);
    assert_eq!(refused(send(&mut unit, &old)), Some(WireError::UnknownType));
    for team in [
        TeamConfig { size: 9, own: 0 },
        TeamConfig { size: 3, own: 3 },
        TeamConfig { size: 0, own: 1 },
    ] {
        let c = Configure {
            team,
            ..paper_configure()
        };
        let reply = send(&mut unit, &link::configure(6, &c));
        assert_eq!(refused(reply), Some(WireError::InvalidConfig), "{team:?}");
    }
}

#[test]
fn the_turn_is_the_lone_units_and_version_2_has_no_chaser() {
    let mut team = Endpoint::<f32>::new();
    let mut alone = Endpoint::<f32>::new();
    send(&mut team, &link::configure(1, &team_configure()));
    send(&mut alone, &link::configure_v2(1, &paper_configure()));
    for k in 0..300u32 {
        let t_ms = 10 * k;
        let s = StateMsg::exact(t_ms, [0.0, 0.0, 0.0], [6.0, 3.0 - 0.01 * k as f32, 1.0]);
        send(
            &mut team,
            &link::teammate(2, &mate(1 + (k % 2) as u8, t_ms, [5.0, 5.0, 2.0])),
        );
        let with_team = command(send(&mut team, &link::state(3, &s)));
        let lone = command(send(&mut alone, &link::state_v2(3, &s)));
        assert_ne!(with_team.chaser, NO_MEMBER);
        assert_eq!(lone.chaser, NO_MEMBER);
        assert_eq!(
            CommandMsg {
                chaser: NO_MEMBER,
                ..with_team
            },
            lone
        );
    }
}
