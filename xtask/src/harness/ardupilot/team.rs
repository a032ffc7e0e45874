//! A team of ArduPilot Rover SITL pursuers (`cargo xtask run --autopilot ardupilot --team`):
//! three rovers (instances 0 to 2), each with its own `twocars-companion` unit in a team
//! (TC_TEAM_N 3), against a fourth rover (instance 3) flown by the team's evaders. For each
//! chase all four start where the start puts them, at rest; the target's fixes reach each unit
//! through the rovers' radio ([`Radio::ROVER`]), with wind and GPS noise on the pursuers, and
//! each unit hears its teammates' fixes as their autopilots send them (docs/team.md).

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use twocars_sim::autopilot::{Plane, HOME};
use twocars_sim::rng::Rng;
use twocars_sim::sim::theorem_threshold;
use twocars_sim::team::{self as sim_team, TeamEvader, TeamParams, TeamPursuit, TeamStart};

use super::rover_evader::{pump, RoverSteer};
use super::sitl::{Frame, Launch, Sitl};
use super::vehicle::{make_ready, measure, set_autopilot_param};
use crate::harness::autopilot::field::Radio;
use crate::harness::autopilot::harness::Harness;
use crate::harness::autopilot::router::Router;
use crate::harness::autopilot::team::{chase, team_params, TeamFlown, TeamTerms, TEAM_TARGET};
use crate::harness::autopilot::unit::{build_companion, start_companion, Unit};
use crate::harness::autopilot::{configure_unit, law_limits, set_unit_params, CAPTURE_RADIUS};

/// The team's size.
pub const N: usize = 3;
/// The pursuers' speed at thrust 1 (WP_SPEED), m/s: the single rover's.
const WP_SPEED: f32 = 3.0;
/// The host report's starts' distances scaled by this: SITL runs at the wall clock's pace, and
/// 0.12 to 0.6 thresholds keep a chase within a minute or so.
const SCALE: f64 = 0.4;
/// The starts' seeds: each start flown against each evader.
const SEEDS: [u64; 2] = [2019, 2020];

/// A vehicle of the team's run: its SITL and, for a pursuer, its unit; both stop on drop.
struct Running {
    _sitl: Sitl,
    _unit: Option<Unit>,
}

/// Starts SITL instance `instance` at `state` (in the plane about home) with WP_SPEED
/// `wp_speed`, behind `companion` where given, and makes it ready; then reads its link until
/// `ready` counts every vehicle of the run.
fn launch(
    binary: &Path,
    (instance, state): (u16, [f64; 3]),
    wp_speed: f32,
    companion: Option<&Path>,
    ready: &AtomicUsize,
) -> Result<(Running, Harness), String> {
    let (lat, lon) = Plane::new(HOME).fix(state[0], state[1]);
    let launch = Launch {
        frame: Frame::Rover,
        instance,
        home: (f64::from(lat) * 1e-7, f64::from(lon) * 1e-7),
        heading: state[2].to_degrees().rem_euclid(360.0),
        speedup: 1,
    };
    let (unit, link) = match companion {
        Some(binary) => {
            let (unit, link) = start_companion(binary, None)?;
            (Some(unit), Some(link))
        }
        None => (None, None),
    };
    let (sitl, serial0) = Sitl::start(binary, launch)?;
    let router = match link {
        Some(link) => Router::new(serial0, link)?,
        None => Router::alone(serial0)?,
    };
    let mut harness = Harness::new(router, HOME, TEAM_TARGET);
    let made = make_ready(&mut harness, wp_speed);
    ready.fetch_add(1, Ordering::SeqCst);
    made?;
    while ready.load(Ordering::SeqCst) < N + 1 {
        pump(&mut harness)?;
    }
    let running = Running {
        _sitl: sitl,
        _unit: unit,
    };
    Ok((running, harness))
}

/// The team's pursuers and evader started at `start`, all at once, each ready: what runs,
/// the pursuers' harnesses and the evader's.
type Launched = (Vec<Running>, [Harness; N], Harness);

fn launch_all(
    binary: &Path,
    companion: &Path,
    start: &TeamStart<N>,
    v_em: f32,
) -> Result<Launched, String> {
    let ready = Arc::new(AtomicUsize::new(0));
    let mut threads = Vec::new();
    for (k, &state) in start.pursuers.iter().chain([&start.evader]).enumerate() {
        let (binary, companion, ready) =
            (binary.to_path_buf(), companion.to_path_buf(), ready.clone());
        let pursuer = k < N;
        let wp_speed = if pursuer { WP_SPEED } else { v_em };
        threads.push(std::thread::spawn(move || {
            let companion = pursuer.then_some(companion.as_path());
            launch(&binary, (k as u16, state), wp_speed, companion, &ready)
        }));
    }
    let (mut running, mut harnesses) = (Vec::new(), Vec::new());
    for t in threads {
        let (r, h) = t
            .join()
            .map_err(|_| "a vehicle's start panicked".to_string())??;
        running.push(r);
        harnesses.push(h);
    }
    let evader = harnesses.pop().ok_or("no evader")?;
    let pursuers = harnesses
        .try_into()
        .map_err(|_| "not every pursuer started")?;
    Ok((running, pursuers, evader))
}

/// The law's limits and period from one rover driven alone (instance 0 at home).
fn measure_rover(binary: &Path) -> Result<([f64; 4], f64), String> {
    let ready = AtomicUsize::new(N);
    let (_rover, mut h) = launch(binary, (0, [0.0; 3]), WP_SPEED, None, &ready)?;
    let m = measure(&mut h)?;
    println!(
        "the rover, driven: {:.2} m/s at thrust 1, largest turn rate {:.2} rad/s, yaw-rate response {:.2} s",
        m.speed, m.turn_rate, m.response
    );
    Ok((law_limits(&m), (m.response * 100.0).round() / 100.0))
}

/// The start: the host report's draw for `seed`, its distances scaled by [`SCALE`].
fn team_start(limits: [f64; 4], seed: u64) -> TeamStart<N> {
    let mut start = TeamStart::<N>::random(&mut Rng::new(seed), limits);
    for p in &mut start.pursuers {
        p[0] *= SCALE;
        p[1] *= SCALE;
    }
    start
}

/// Each unit's law, team, radio; each pursuer in wind with GPS noise.
fn configure(h: &mut Harness, limits: [f64; 4], period: f64) -> Result<(), String> {
    configure_unit(h, limits, CAPTURE_RADIUS, period)?;
    set_unit_params(h, &team_params(N))?;
    set_unit_params(h, &Radio::ROVER.unit_params())?;
    set_autopilot_param(h, "SIM_WIND_SPD", 3.0)?;
    set_autopilot_param(h, "SIM_GPS1_NOISE", 0.5)
}

/// One chase from `start` against `kind`: the team started, configured and flown; what it
/// gave. The units stop before their links close.
fn fly_one(
    (binary, companion): (&Path, &Path),
    (limits, period): ([f64; 4], f64),
    (start, seed): (&TeamStart<N>, u64),
    kind: TeamEvader,
    t_max: f64,
) -> Result<TeamFlown<N>, String> {
    let (running, mut team, mut evader) = launch_all(binary, companion, start, limits[2] as f32)?;
    for h in &mut team {
        configure(h, limits, period)?;
    }
    let terms = TeamTerms {
        eps: CAPTURE_RADIUS,
        limits,
        t_max,
        radio: Radio::ROVER,
        seed,
    };
    let mut steer = RoverSteer {
        wp_speed: limits[2],
    };
    let flown = chase(&mut team, &mut evader, &mut steer, kind, terms);
    drop(running);
    flown
}

/// The ideal team from the chase's start: the host's team of Dubins cars at full speed from
/// t = 0, exact states, against the same evader; its capture time (s) and capturer.
fn ideal(
    flown: &TeamFlown<N>,
    limits: [f64; 4],
    kind: TeamEvader,
    t_max: f64,
) -> Option<(f64, usize)> {
    let start = TeamStart {
        limits: [limits; N],
        pursuers: flown.start.0,
        evader: flown.start.1,
    };
    let params = TeamParams {
        dt: 0.05,
        t_max,
        eps: CAPTURE_RADIUS,
        sigma: 0.0,
        seed: 0,
        teammate_lag: None,
    };
    let run = sim_team::chase(&start, TeamPursuit::Team, kind, params)?;
    run.captured.zip(run.by)
}

/// How each unit named the chaser: the changes of its chaser, and the share of the chase's
/// tenths of a second in which the three units named the same one.
fn roles(flown: &TeamFlown<N>, end: f64) -> ([usize; N], f64) {
    let changes = flown
        .named
        .each_ref()
        .map(|named| named.windows(2).filter(|w| w[0].1 != w[1].1).count());
    let at = |named: &[(f64, Option<usize>)], t: f64| {
        named
            .iter()
            .take_while(|(s, _)| *s <= t)
            .last()
            .map(|n| n.1)
    };
    let ticks = (end / 0.1).floor() as usize;
    let agreed = (1..=ticks)
        .filter(|&i| {
            let t = i as f64 * 0.1;
            let seen: Vec<_> = flown.named.iter().map(|n| at(n, t)).collect();
            seen.iter().all(|s| *s == seen[0])
        })
        .count();
    (changes, agreed as f64 / ticks.max(1) as f64)
}

/// One chase in one paragraph.
fn report(kind: &str, flown: &TeamFlown<N>, ideal: Option<(f64, usize)>, t_max: f64) -> String {
    let end = flown.captured.map_or(t_max, |(t, _)| t);
    let (changes, agreed) = roles(flown, end);
    let captured = flown
        .captured
        .map_or("NEVER CAPTURED".to_string(), |(t, k)| {
            format!("captured at {t:.2} s by rover {k}")
        });
    let ideal = ideal.map_or("never".to_string(), |(t, k)| {
        format!("{t:.2} s by rover {k}")
    });
    let named: Vec<String> = flown
        .named
        .iter()
        .enumerate()
        .map(|(k, named)| format!("unit {k}: {}", timeline(named)))
        .collect();
    format!(
        "team vs {kind}: {captured} (the ideal team {ideal}); the chaser named by {}; role changes {changes:?}; the three agree {:.1} % of the chase",
        named.join(", "),
        100.0 * agreed
    )
}

/// A unit's chasers as it named them, each from when it first named it: "rover 2 from 0.05 s".
fn timeline(named: &[(f64, Option<usize>)]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut last = None;
    for &(t, chaser) in named {
        if last != Some(chaser) {
            last = Some(chaser);
            let who = chaser.map_or("none".to_string(), |k| format!("rover {k}"));
            parts.push(format!("{who} from {t:.2} s"));
        }
    }
    match parts.is_empty() {
        true => "nothing".to_string(),
        false => parts.join(" then "),
    }
}

/// `cargo xtask run --autopilot ardupilot --team`'s options: the `ardurover` binary, and
/// whether to fly the team-aware evader alone.
pub struct Options {
    pub ardurover: Option<std::path::PathBuf>,
    pub short: bool,
}

/// A chase's outcome: the start's seed, the evader's name, the capture and the ideal team's
/// (time, s, and the capturer), and each unit's chasers as it named them.
pub struct Outcome {
    pub seed: u64,
    pub evader: &'static str,
    pub captured: Option<(f64, usize)>,
    pub ideal: Option<(f64, usize)>,
    pub named: [Vec<(f64, Option<usize>)>; N],
}

/// Measures a rover, then flies the team against each evader; the outcomes.
pub fn fly(options: &Options) -> Result<Vec<Outcome>, String> {
    let binary = super::find_rover(options.ardurover.as_deref())
        .ok_or("ArduPilot Rover SITL not found: give --ardurover PATH or set TWOCARS_ARDUROVER")?;
    let companion = build_companion()?;
    let (limits, period) = measure_rover(&binary)?;
    println!(
        "the team: {N} ArduPilot Rover SITL pursuers, each with its companion (TC_TEAM_N {N}), the evader a fourth rover; \
         the law {limits:?}, TC_PERIOD {period:.2} s, threshold {:.1} m; {}; wind 3 m/s and GPS noise 0.5 m on the pursuers",
        theorem_threshold(limits),
        Radio::ROVER.line()
    );
    let evaders = match options.short {
        true => &TeamEvader::ALL[..1],
        false => &TeamEvader::ALL[..],
    };
    let seeds = if options.short {
        &SEEDS[..1]
    } else {
        &SEEDS[..]
    };
    let mut outcomes = Vec::new();
    for &seed in seeds {
        let start = team_start(limits, seed);
        let predicted = sim_team::predicted(&start).unwrap_or(f64::NAN);
        let t_max = 3.0 * predicted + 30.0;
        println!(
            "start {seed} (distances x {SCALE}): pursuers {:?}, evader {:?}; the least game value {predicted:.2} s",
            start.pursuers.map(|p| p.map(|v| (v * 10.0).round() / 10.0)),
            start.evader.map(|v| (v * 100.0).round() / 100.0)
        );
        for &(kind, name) in evaders {
            let programs = (binary.as_path(), companion.as_path());
            let flown = fly_one(programs, (limits, period), (&start, seed), kind, t_max)?;
            let ideal = ideal(&flown, limits, kind, t_max);
            println!("{}", report(name, &flown, ideal, t_max));
            outcomes.push(Outcome {
                seed,
                evader: name,
                captured: flown.captured,
                ideal,
                named: flown.named,
            });
        }
    }
    Ok(outcomes)
}

/// `cargo xtask run --autopilot ardupilot --team`; the exit code.
pub fn run(options: &Options) -> i32 {
    match fly(options) {
        Ok(outcomes) => i32::from(!outcomes.iter().all(|o| o.captured.is_some())),
        Err(e) => {
            eprintln!("xtask run --autopilot ardupilot --team: {e}");
            1
        }
    }
}
