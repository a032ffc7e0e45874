//! `Policy::Table`: the firmware's `Guidance` playing the game's value tables
//! (`twocars::value_tables`) below the theorem's threshold, against the host's players of the
//! same tables (`hji::policy`) and in closed loop.

use std::sync::OnceLock;

use hji::policy::{pursuer_curvature, relative};
use hji::{solve, table_set_bytes, Game, Grid, Solution};
use twocars::value_tables::ValueTables;
use twocars::{Guidance, Law, Limits, Policy, Variant};
use twocars_sim::adversary::{EvaderKind, Opponent};
use twocars_sim::rng::Rng;
use twocars_sim::sim::{simulate_with, Setup, SimParams, SimStatus};

/// The paper's limits, v_pm, w_pm, v_em, w_em (r_p = 0.5 m).
const LIMITS: [f64; 4] = [2.0, 2.0, 1.0, 1.0];

/// The paper's game on a 41 x 41 x 24 grid over +-6 r_p, capture radius 0.6 r_p (0.3 m), and
/// the same table as the firmware reads it.
fn tables() -> &'static (Vec<Solution>, ValueTables<'static>) {
    static TABLES: OnceLock<(Vec<Solution>, ValueTables<'static>)> = OnceLock::new();
    TABLES.get_or_init(|| tables_of(LIMITS))
}

/// The game of `limits` on the grid of [`tables`].
fn tables_of(limits: [f64; 4]) -> (Vec<Solution>, ValueTables<'static>) {
    let grid = Grid {
        n: 41,
        half: 6.0,
        headings: 24,
    };
    let game = Game::with_radius(limits, 2.0 * grid.spacing());
    let solution = solve(game, grid, grid.step_time(), 1e-6, 5_000, |_, _| {});
    let bytes: &'static [u8] =
        Box::leak(table_set_bytes(std::slice::from_ref(&solution)).into_boxed_slice());
    (vec![solution], ValueTables::parse(bytes).unwrap())
}

fn guidance(policy: Policy) -> Guidance<f32> {
    let l = LIMITS.map(|v| v as f32);
    let law = Law::new(Limits::new(l[0], l[1], l[2], l[3]).unwrap(), Variant::Paper);
    Guidance::new(law, 0.01, twocars::Policy::Paper)
        .unwrap()
        .with_policy(policy)
}

/// Where the tables' reader has a turn for a player, the guidance commands that full turn (the
/// reader's turns are the host's players' in `tests/value_table.rs`); where the reader has
/// none, the guidance commands what the flight policy would.
#[test]
fn the_guidance_turns_as_the_host_players_of_the_tables() {
    let (_, set) = tables();
    let set: &'static ValueTables<'static> = set;
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let mut rng = Rng::new(41);
    let (mut pursuer_checked, mut evader_checked) = (0, 0);
    for _ in 0..4_000 {
        // Both players anywhere within 2.5 m of each other, any headings.
        let pi = std::f64::consts::PI;
        let p = [
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-pi, pi),
        ];
        let e = [
            p[0] + rng.uniform(-2.5, 2.5),
            p[1] + rng.uniform(-2.5, 2.5),
            rng.uniform(-pi, pi),
        ];
        let (ps, es) = limits
            .states(p.map(|v| v as f32), e.map(|v| v as f32))
            .unwrap();
        let mut with_tables = guidance(Policy::Table).with_tables(set).unwrap();
        let mut flight = guidance(Policy::Flight);
        let command = with_tables.step(&ps, &es).command;
        let flight_command = flight.step(&ps, &es).command;
        let at = relative(LIMITS[1], p, e);
        let (x, y, phi) = (at.0 as f32, at.1 as f32, at.2 as f32);
        // Where the reader has a turn (read at the state in the tables' frame computed here) the
        // guidance commands it in full; elsewhere the flight policy's command.
        match set.pursuer_turn(x, y, phi) {
            Some(read) => {
                assert_eq!(command.pursuer, read * 2.0, "{p:?} {e:?}");
                pursuer_checked += 1;
            }
            None => assert_eq!(command.pursuer, flight_command.pursuer, "{p:?} {e:?}"),
        }
        match set.evader_turn(x, y, phi) {
            Some(read) => {
                assert_eq!(command.evader, read * 1.0, "{p:?} {e:?}");
                evader_checked += 1;
            }
            None => assert_eq!(command.evader, flight_command.evader, "{p:?} {e:?}"),
        }
        assert!(command.pursuer.is_finite() && command.evader.is_finite());
    }
    assert!(pursuer_checked > 1_000, "{pursuer_checked}");
    assert!(evader_checked > 1_000, "{evader_checked}");
}

/// Tables of other ratios are refused, and without tables `Policy::Table` is the flight policy.
#[test]
fn tables_of_other_ratios_are_refused() {
    let (_, set) = tables();
    let set: &'static ValueTables<'static> = set;
    let other = Law::new(
        Limits::<f32>::new(2.0, 2.0, 1.2, 1.0).unwrap(),
        Variant::Paper,
    );
    let guidance_other = Guidance::new(other, 0.01, twocars::Policy::Paper).unwrap();
    assert!(guidance_other.with_tables(set).is_err());
    let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).unwrap();
    let (ps, es) = limits.states([0.0, 0.0, 0.3], [0.8, 1.1, -2.0]).unwrap();
    let mut table_without = guidance(Policy::Table);
    let mut flight = guidance(Policy::Flight);
    assert_eq!(table_without.step(&ps, &es), flight.step(&ps, &es));
}

/// In closed loop against the adversary suite's evaders, from seeded starts 0.5 to 2.5 m
/// apart, the guidance playing the tables captures every run at the tables' radius, and the
/// pursuer's captures match the host's pursuer of the same tables within a control period's
/// worth of difference per second of chase (u16 codes and f32 against f64).
#[test]
fn the_guidance_captures_as_the_host_pursuer_of_the_tables() {
    let (solutions, set) = tables();
    let set: &'static ValueTables<'static> = set;
    let mut rng = Rng::new(43);
    let host = |p, e| pursuer_curvature(solutions, LIMITS[1], p, e);
    let mut runs = 0;
    for kind in [
        EvaderKind::Straight,
        EvaderKind::Circle {
            left: true,
            half: false,
        },
        EvaderKind::BangBang,
        EvaderKind::Greedy { periods: 1 },
    ] {
        for _ in 0..10 {
            let pi = std::f64::consts::PI;
            let (d, bearing) = (rng.uniform(0.5, 2.5), rng.uniform(-pi, pi));
            let params = SimParams {
                limits: LIMITS,
                pursuer: [0.0, 0.0, rng.uniform(-pi, pi)],
                evader: [d * bearing.cos(), d * bearing.sin(), rng.uniform(-pi, pi)],
                dt: 0.01,
                t_max: 30.0,
                eps: solutions[0].game.eps / LIMITS[1],
            };
            let opponent = Some((Opponent::Evader(kind), rng.next_u64()));
            let firmware = simulate_with::<f32>(
                &params,
                Variant::Paper,
                Policy::Table,
                false,
                Setup {
                    tables: Some(set),
                    opponent,
                    ..Setup::default()
                },
            );
            let on_host = simulate_with::<f32>(
                &params,
                Variant::Paper,
                Policy::Flight,
                false,
                Setup {
                    opponent,
                    turns: [Some(&host), None],
                    ..Setup::default()
                },
            );
            assert_eq!(firmware.status, SimStatus::Captured, "{kind:?} {params:?}");
            assert_eq!(on_host.status, SimStatus::Captured, "{kind:?} {params:?}");
            let gap = (firmware.t_capture - on_host.t_capture).abs();
            assert!(
                gap <= 0.01 * (1.0 + on_host.t_capture),
                "{kind:?} {params:?}: {} vs {}",
                firmware.t_capture,
                on_host.t_capture
            );
            runs += 1;
        }
    }
    assert_eq!(runs, 40);
}

/// The unit's Configure: policy byte 2 plays the set of tables its image carries that fits the
/// limits' ratios, and the ConfigureAck says the policy in effect (2), else falls back to the
/// flight policy and says 1; a unit without tables says 1; policies 0 and 1 are echoed. With
/// the tables in effect, a State in the near field gets the turn of the set of its limits as
/// its pursuer rate.
#[test]
fn configure_selects_the_tables_of_its_ratios_and_says_so() {
    use twocars::protocol::endpoint::Endpoint;
    use twocars::protocol::message::{Configure, StateMsg};
    use twocars_sim::link::{self, Reply, ReplyDecoder};
    use twocars_sim::session::paper_configure;

    let (_, set) = tables();
    let set: &'static ValueTables<'static> = set;
    let ack = |unit: &mut Endpoint, configure: &Configure| -> Option<u8> {
        let mut decoder = ReplyDecoder::default();
        let mut out = None;
        for &b in &link::configure(7, configure) {
            if let Some(reply) = unit.receive(b, 0) {
                out = decoder.feed(reply.as_bytes()).pop();
            }
        }
        match out {
            Some(Ok(Reply::ConfigureAck(7, policy))) => policy,
            other => panic!("{other:?}"),
        }
    };
    // A State 1.2 m apart, the evader behind on the pursuer's left: the pursuer's rate.
    let rate = |unit: &mut Endpoint| -> f32 {
        let state = StateMsg::exact(10, [0.0, 0.0, 0.0], [-0.9, 0.8, 2.0]);
        let mut decoder = ReplyDecoder::default();
        let mut command = None;
        for &b in &link::state(8, &state) {
            if let Some(reply) = unit.receive(b, 5) {
                command = decoder.feed(reply.as_bytes()).pop();
            }
        }
        match command {
            Some(Ok(Reply::Command(8, c))) => c.pursuer_rate,
            other => panic!("{other:?}"),
        }
    };
    // The tables' pursuer turn there (r_p, radians), as a rate v_pm w_pm.
    let turn_rate = |set: &ValueTables<'_>| {
        4.0 * set
            .pursuer_turn(-1.8, 1.6, 2.0)
            .expect("the tables play there")
    };
    let paper = Configure {
        policy: 2,
        ..paper_configure()
    };
    let faster_evader = Configure {
        limits: [2.0, 2.0, 1.2, 1.0],
        ..paper
    };
    assert_eq!(ack(&mut Endpoint::new(), &paper), Some(1));
    let mut unit = Endpoint::new();
    unit.set_tables(std::slice::from_ref(set));
    assert_eq!(ack(&mut unit, &faster_evader), Some(1));
    for policy in [0, 1] {
        assert_eq!(ack(&mut unit, &Configure { policy, ..paper }), Some(policy));
    }
    assert_eq!(ack(&mut unit, &paper), Some(2));
    assert_eq!(rate(&mut unit), turn_rate(set));
    // Two sets, the other ratios' first: each limits play their own.
    let other: &'static ValueTables<'static> =
        Box::leak(Box::new(tables_of([2.0, 2.0, 1.2, 1.0]).1));
    let both: &'static [ValueTables<'static>] = Box::leak(Box::new([*other, *set]));
    let mut two = Endpoint::new();
    two.set_tables(both);
    for (configure, set) in [(&faster_evader, other), (&paper, set)] {
        assert_eq!(ack(&mut two, configure), Some(2));
        assert_eq!(rate(&mut two), turn_rate(set));
    }
}

/// The bench's serial session with the tables (`cargo xtask bench` times it on the M4F): one
/// Configure with policy 2, acknowledged 2, and a State per table point, each answered with the
/// table's pursuer and evader turns as full rates; the same session through the serial path's
/// queues writes the same bytes.
#[test]
fn the_bench_session_with_the_tables_commands_their_turns() {
    use twocars::protocol::endpoint::Endpoint;
    use twocars_bench::main_loop::{script, serve_script, state_frames, SCRIPT_CAPACITY};
    use twocars_bench::TABLE_POINTS;
    use twocars_sim::link::{Reply, ReplyDecoder};

    let bytes: &'static [u8] = twocars_bench::TABLE;
    let set: &'static [ValueTables<'static>] =
        Box::leak(Box::new([ValueTables::parse(bytes).unwrap()]));
    let mut out = [0u8; SCRIPT_CAPACITY];
    let n = script(true, true, &mut out).expect("the script fits");
    let mut unit = Endpoint::<f32>::new();
    unit.set_tables(set);
    let mut written = Vec::new();
    for &b in &out[..n] {
        if let Some(reply) = unit.receive(b, 0) {
            written.extend_from_slice(reply.as_bytes());
        }
    }
    let replies: Vec<Reply> = ReplyDecoder::default()
        .feed(&written)
        .into_iter()
        .map(|r| r.expect("a valid reply"))
        .collect();
    assert!(
        matches!(replies[0], Reply::ConfigureAck(_, Some(2))),
        "{replies:?}"
    );
    let commands: Vec<_> = replies
        .iter()
        .filter_map(|r| match r {
            Reply::Command(_, c) => Some(*c),
            _ => None,
        })
        .collect();
    // One per table point: the script's refused inputs get Error frames.
    assert_eq!(commands.len(), state_frames(true), "{replies:?}");
    let [v_pm, w_pm, v_em, w_em] = twocars_bench::LIMITS;
    for (c, &[x, y, phi]) in commands.iter().zip(&TABLE_POINTS) {
        let pursuer = set[0]
            .pursuer_turn(x, y, phi)
            .expect("the table plays there");
        let evader = set[0]
            .evader_turn(x, y, phi)
            .expect("the table plays there");
        assert_eq!(
            c.pursuer_rate,
            pursuer * v_pm * w_pm,
            "{c:?} at {x}, {y}, {phi}"
        );
        assert_eq!(
            c.evader_rate,
            evader * v_em * w_em,
            "{c:?} at {x}, {y}, {phi}"
        );
    }
    let served = serve_script(&mut twocars::serial::Line::new(), &out[..n], set);
    let digest = written
        .iter()
        .fold(0u32, |d, &b| d.rotate_left(5) ^ u32::from(b));
    assert!(served.shutdown);
    assert_eq!(served.digest, digest);
}
