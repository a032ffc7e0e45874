//! Closed loop on the host: both players apply the sampled command every dt (zero-order hold)
//! and move exactly (a constant-curvature arc within a step), in f64.
//!
//! Capture is the first time the distance falls to `eps`, interpolated within its step.

use crate::adversary::{Adversary, Opponent};
pub use crate::kinematics::{advance, angle_error, distance, wrap_pi};
use twocars::law::geometry::Units;
use twocars::law::Observation;
use twocars::law::Scene;
use twocars::{Direction, Guidance, Law, Policy, Scalar, Status, Variant};

/// Number of sub-samples per step used to find the capture instant and the minimum distance.
const SUBSAMPLES: usize = 16;

/// Parameters of one closed-loop run: the law's observation at t = 0 plus dt, t_max, eps.
#[derive(Clone, Copy, Debug)]
pub struct SimParams {
    /// v_pm, w_pm, v_em, w_em (m/s, 1/m).
    pub limits: [f64; 4],
    /// Pursuer x, y, theta at t = 0 (metres, radians).
    pub pursuer: [f64; 3],
    /// Evader x, y, theta at t = 0.
    pub evader: [f64; 3],
    /// Control period, seconds.
    pub dt: f64,
    /// Time limit, seconds.
    pub t_max: f64,
    /// Capture distance, metres.
    pub eps: f64,
}

/// Outcome class of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimStatus {
    /// Captured within t_max.
    Captured,
    /// Not captured within t_max.
    Timeout,
    /// dt, t_max or eps not finite and positive, or t_max / dt > 1e7.
    InvalidSimParams,
    /// The law's status for the initial state when it is an input error or already captured.
    Law(Status),
}

impl SimStatus {
    /// The contract's name of the status.
    pub fn name(self) -> &'static str {
        match self {
            SimStatus::Captured => "ok",
            SimStatus::Timeout => "timeout",
            SimStatus::InvalidSimParams => "invalid_sim_params",
            SimStatus::Law(s) => s.name(),
        }
    }
}

/// What a run shows.
#[derive(Clone, Debug)]
pub struct SimResult {
    /// Outcome.
    pub status: SimStatus,
    /// Capture time, seconds (infinity on timeout).
    pub t_capture: f64,
    /// Upper value at t = 0, seconds (infinity if none).
    pub predicted: f64,
    /// Lower value at t = 0, seconds.
    pub predicted_lower: f64,
    /// Minimum distance seen, metres.
    pub d_min: f64,
    /// Steps whose (row, col) differs from the step before.
    pub switches: u64,
    /// Steps, summed over both players, whose w has the opposite sign to that player's last w
    /// with |w| > 1e-6 w_max.
    pub sign_flips: u64,
    /// The sign flips counted while the players were closer than the theorem's threshold
    /// 2 r_e + 2 pi r_e v_pm / v_em (the near field).
    pub near_field_sign_flips: u64,
    /// Loops of the pursuer: a pass within three capture radii, then a turn of more than pi
    /// before capture (counted by the field's chase, [`crate::field::Loops`]; 0 elsewhere).
    pub loops: u64,
    /// Both trajectories, one (t, pursuer, evader) per step, if recording was asked for.
    pub trajectory: Vec<(f64, [f64; 3], [f64; 3])>,
}

impl SimResult {
    /// When a point capture would be (s): the capture time plus the time to close the last
    /// `eps` (m) at v_pm - v_em, the moment the law's values at t = 0 promise.
    pub fn point_capture(&self, limits: [f64; 4], eps: f64) -> f64 {
        self.t_capture + eps / (limits[0] - limits[2])
    }

    /// A result with `status`, nothing simulated yet: times infinite, no switches or flips.
    pub fn empty(status: SimStatus, d_min: f64) -> Self {
        SimResult {
            status,
            t_capture: f64::INFINITY,
            predicted: f64::INFINITY,
            predicted_lower: f64::INFINITY,
            d_min,
            switches: 0,
            sign_flips: 0,
            near_field_sign_flips: 0,
            loops: 0,
            trajectory: Vec::new(),
        }
    }
}

/// The first time (s) within a step of `dt` at which `gap(t)`, the players' distance t into
/// the step (m), falls to `eps`: the first of [`SUBSAMPLES`] sub-samples at or below it, the
/// crossing bisected within it. `None` if every sub-sample is above; `d_min` keeps the least
/// distance sampled.
pub fn capture_within(dt: f64, eps: f64, gap: impl Fn(f64) -> f64, d_min: &mut f64) -> Option<f64> {
    let h = dt / SUBSAMPLES as f64;
    let mut before = 0.0;
    for i in 1..=SUBSAMPLES {
        let tau = h * i as f64;
        let d = gap(tau);
        *d_min = d_min.min(d);
        if d <= eps {
            let (mut lo, mut hi) = (before, tau);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if gap(mid) <= eps {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        before = tau;
    }
    None
}

/// The theorem's distance threshold 2 r_e + 2 pi r_e v_pm / v_em, metres, for limits
/// (v_pm, w_pm, v_em, w_em).
pub fn theorem_threshold(limits: [f64; 4]) -> f64 {
    let [v_pm, _, v_em, w_em] = limits;
    twocars::law::geometry::theorem_threshold(1.0 / w_em, v_pm, v_em)
}

/// Sign flips of the players' curvature commands (0: the pursuer, 1: the evader): a command
/// whose sign differs from the last one above 1e-6 of the player's largest curvature.
#[derive(Clone, Copy, Debug, Default)]
pub struct SignFlips {
    last: [f64; 2],
    /// Flips of both players.
    pub count: u64,
    /// Those recorded as in the near field.
    pub near_field: u64,
}

impl SignFlips {
    /// Records `player`'s command `w` (1/m) of at most `w_max`.
    pub fn record(&mut self, player: usize, w: f64, w_max: f64, near_field: bool) {
        let Some(last) = self.last.get_mut(player) else {
            return;
        };
        if w.abs() > 1e-6 * w_max {
            if *last != 0.0 && last.signum() != w.signum() {
                self.count += 1;
                self.near_field += u64::from(near_field);
            }
            *last = w;
        }
    }
}

/// One control period's command: curvatures (1/m), speeds (m/s) and, where known, the chosen
/// circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepCommand {
    /// Pursuer curvature, 1/m.
    pub pursuer: f64,
    /// Evader curvature, 1/m.
    pub evader: f64,
    /// Pursuer speed, m/s, in [0, v_pm]; `None` = full speed (the law's players).
    pub pursuer_speed: Option<f64>,
    /// Evader speed, m/s, in [0, v_em]; `None` = full speed.
    pub evader_speed: Option<f64>,
    /// Chosen (pursuer, evader) circles, if the law reported them.
    pub choice: Option<(Direction, Direction)>,
}

impl StepCommand {
    /// Both players at full speed on curvatures `pursuer` and `evader` (1/m).
    pub fn full_speed(pursuer: f64, evader: f64, choice: Option<(Direction, Direction)>) -> Self {
        StepCommand {
            pursuer,
            evader,
            pursuer_speed: None,
            evader_speed: None,
            choice,
        }
    }
}

/// Whether dt, t_max and eps are usable (finite, positive, t_max / dt <= 1e7).
pub fn valid_params(params: &SimParams) -> bool {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    positive(params.dt)
        && positive(params.t_max)
        && positive(params.eps)
        && params.t_max / params.dt <= 1e7
}

/// Runs the closed loop with any controller (the host law, or the firmware over a serial link):
/// every dt the controller sees time and both states and returns the command, held for the step;
/// both vehicles move exactly, at full speed unless the command says less (clamped to
/// [0, v_max]). The result's `predicted` fields are left infinite for
/// the caller. `Err` if the controller fails.
///
/// The controller sees the states in a frame centred on the pursuer's position (axes and
/// headings unchanged), as an autopilot's local navigation frame would give them: the game is
/// the same under translation, and the f32 the law reads then resolves the players' relative
/// geometry to 1e-7 of their distance, not of their distance from the origin (after a chase
/// of 700 m, f32 absolute positions are 6e-5 m apart: a slow chase in absolute positions
/// dithers in its last centimetres, 1,141 sign flips where the local frame gives 1;
/// docs/closed-loop.md).
pub fn closed_loop<E>(
    params: &SimParams,
    record: bool,
    mut controller: impl FnMut(f64, [f64; 3], [f64; 3]) -> Result<StepCommand, E>,
) -> Result<SimResult, E> {
    let mut result = SimResult::empty(SimStatus::Timeout, distance(params.pursuer, params.evader));
    let threshold = theorem_threshold(params.limits);
    let SimParams { dt, t_max, eps, .. } = *params;
    let [v_pm, w_pm, v_em, w_em] = params.limits;
    let (mut p, mut e) = (params.pursuer, params.evader);
    let mut previous: Option<(Direction, Direction)> = None;
    let mut flips = SignFlips::default();
    let steps = (t_max / dt).ceil() as u64;
    for k in 0..steps {
        let t0 = k as f64 * dt;
        if record {
            result.trajectory.push((t0, p, e));
        }
        let local = |s: [f64; 3]| [s[0] - p[0], s[1] - p[1], s[2]];
        let command = controller(t0, local(p), local(e))?;
        if let Some(choice) = command.choice {
            if previous.is_some_and(|prev| prev != choice) {
                result.switches += 1;
            }
            previous = Some(choice);
        }
        let near_field = distance(p, e) < threshold;
        flips.record(0, command.pursuer, w_pm, near_field);
        flips.record(1, command.evader, w_em, near_field);
        // Find the first sub-sample at or below eps; bisect the crossing within it.
        let speed = |v: Option<f64>, v_max: f64| v.map_or(v_max, |v| v.clamp(0.0, v_max));
        let (v_p, v_e) = (
            speed(command.pursuer_speed, v_pm),
            speed(command.evader_speed, v_em),
        );
        let at = |tau: f64| {
            (
                advance(p, v_p, command.pursuer, tau),
                advance(e, v_e, command.evader, tau),
            )
        };
        let gap = |tau: f64| {
            let (a, b) = at(tau);
            distance(a, b)
        };
        if let Some(tau) = capture_within(dt, eps, gap, &mut result.d_min) {
            result.status = SimStatus::Captured;
            result.t_capture = t0 + tau;
            result.sign_flips = flips.count;
            result.near_field_sign_flips = flips.near_field;
            result.d_min = result.d_min.min(eps);
            return Ok(result);
        }
        let (np, ne) = at(dt);
        p = [np[0], np[1], wrap_pi(np[2])];
        e = [ne[0], ne[1], wrap_pi(ne[2])];
    }
    result.sign_flips = flips.count;
    result.near_field_sign_flips = flips.near_field;
    Ok(result)
}

/// Runs the closed loop with the law on backend `S`, read with `variant`, under `policy`.
pub fn simulate<S: Scalar>(
    params: &SimParams,
    variant: Variant,
    policy: Policy,
    record: bool,
) -> SimResult {
    simulate_against::<S>(params, variant, policy, None, record)
}

/// Runs the closed loop with the law on backend `S` playing both players, or, with an
/// `opponent` (an adversary of [`crate::adversary`] and its seed), the other player replaced by
/// it. `predicted` and `predicted_lower` are the law's values at t = 0 whoever plays.
pub fn simulate_against<S: Scalar>(
    params: &SimParams,
    variant: Variant,
    policy: Policy,
    opponent: Option<(Opponent, u64)>,
    record: bool,
) -> SimResult {
    let setup = Setup {
        opponent,
        ..Setup::default()
    };
    simulate_with::<S>(params, variant, policy, record, setup)
}

/// A player's curvature (1/m) from both states (metres and radians), where it has one.
pub type Turn<'a> = &'a (dyn Fn([f64; 3], [f64; 3]) -> Option<f64> + Sync);

/// A run's set-up beyond the law and the policy: what the simulated guidance is given, an
/// adversary in place of one player, and turns that override either player's.
#[derive(Clone, Copy, Default)]
pub struct Setup<'a> {
    /// Value tables it plays ([`Guidance::with_tables`]; ignored if they do not fit the limits).
    pub tables: Option<&'static twocars::value_tables::ValueTables<'static>>,
    /// Whether it is told the run's capture radius ([`Guidance::with_capture_radius`]).
    pub capture_radius: bool,
    /// The adversary of [`crate::adversary`] that plays the other player, and its seed.
    pub opponent: Option<(Opponent, u64)>,
    /// The pursuer's and the evader's curvatures (1/m) wherever these give one; the
    /// guidance's (or the opponent's) elsewhere. The guidance still steps every period.
    pub turns: [Option<Turn<'a>>; 2],
}

/// The closed loop of [`simulate_against`] with everything `setup` gives (a host experiment:
/// the value table's players override turns).
pub fn simulate_with<S: Scalar>(
    params: &SimParams,
    variant: Variant,
    policy: Policy,
    record: bool,
    setup: Setup<'_>,
) -> SimResult {
    let idle = SimResult::empty(
        SimStatus::InvalidSimParams,
        distance(params.pursuer, params.evader),
    );
    if !valid_params(params) {
        return idle;
    }
    let (scene, units, [predicted, predicted_lower]) =
        match predict::<S>(params, variant, idle.clone()) {
            Ok(predicted) => predicted,
            Err(ended) => return ended,
        };
    let Some(guidance) = guidance_for(&scene, variant, policy, params, &setup) else {
        return idle;
    };
    let mut guidance = guidance;
    // The vehicles move with the limits the law was given (f32), so both see the same car.
    let params = SimParams {
        limits: params.limits.map(|v| f64::from(v as f32)),
        ..*params
    };
    let mut adversary = match setup.opponent {
        Some((opponent, seed)) => {
            match Adversary::new(opponent, params.limits, params.dt, params.eps, seed) {
                Some(a) => Some(a),
                None => return idle,
            }
        }
        None => None,
    };
    let [pursuer_turn, evader_turn] = setup.turns;
    let result = closed_loop(&params, record, |t, p, e| {
        let narrow = |s: [f64; 3]| s.map(|v| v as f32);
        let mut command = match scene.limits.states(narrow(p), narrow(e)) {
            Ok((ps, es)) => {
                let ev = guidance.step(&ps, &es);
                StepCommand::full_speed(
                    units.curvature(ev.command.pursuer),
                    units.curvature(ev.command.evader),
                    ev.report.map(|r| (r.solution.row, r.solution.col)),
                )
            }
            Err(_) => StepCommand::full_speed(0.0, 0.0, None),
        };
        if let Some(turn) = pursuer_turn.and_then(|turn| turn(p, e)) {
            command.pursuer = turn;
        }
        if let Some(turn) = evader_turn.and_then(|turn| turn(p, e)) {
            command.evader = turn;
        }
        if let Some(adversary) = adversary.as_mut() {
            adversary_plays(adversary, t, p, e, &mut command);
        }
        Ok::<_, core::convert::Infallible>(command)
    });
    match result {
        Ok(r) => SimResult {
            predicted,
            predicted_lower,
            ..r
        },
        Err(never) => match never {},
    }
}

/// The law's scene at t = 0, its units and its upper and lower values (s; infinite without
/// them); Err with the run's result where the law ends it there (captured, or refused).
fn predict<S: Scalar>(
    params: &SimParams,
    variant: Variant,
    idle: SimResult,
) -> Result<(Scene<S>, Units, [f64; 2]), SimResult> {
    let observation = Observation {
        limits: params.limits.map(|v| v as f32),
        pursuer: params.pursuer.map(|v| v as f32),
        evader: params.evader.map(|v| v as f32),
    };
    let initial = twocars::law::evaluate_observation::<S>(&observation, variant);
    let units = initial.units;
    let (predicted, predicted_lower) = initial.report.map_or((f64::INFINITY, f64::INFINITY), |r| {
        let s = r.solution;
        (
            s.upper.map_or(f64::INFINITY, |v| units.seconds(v)),
            s.lower.map_or(f64::INFINITY, |v| units.seconds(v)),
        )
    });
    match (initial.status, twocars::law::validate::<S>(&observation)) {
        (Status::Ok | Status::NoValidTangent, Ok(scene)) => {
            Ok((scene, units, [predicted, predicted_lower]))
        }
        (Status::Captured, _) => Err(SimResult {
            status: SimStatus::Law(Status::Captured),
            t_capture: 0.0,
            predicted: 0.0,
            predicted_lower: 0.0,
            ..idle
        }),
        (status, _) => Err(SimResult {
            status: SimStatus::Law(status),
            predicted,
            predicted_lower,
            ..idle
        }),
    }
}

/// The guidance of `scene` with `policy` and what `setup` gives it; `None` for a control
/// period it refuses.
fn guidance_for<S: Scalar>(
    scene: &Scene<S>,
    variant: Variant,
    policy: Policy,
    params: &SimParams,
    setup: &Setup<'_>,
) -> Option<Guidance<S>> {
    let guidance = Guidance::new(
        Law::new(scene.limits, variant),
        params.dt as f32,
        twocars::Policy::Paper,
    )
    .ok()?;
    let mut guidance = guidance.with_policy(policy);
    if let Some(tables) = setup.tables {
        guidance = guidance.with_tables(tables).unwrap_or(guidance);
    }
    if setup.capture_radius {
        guidance = guidance
            .with_capture_radius(params.eps as f32)
            .unwrap_or(guidance);
    }
    Some(guidance)
}

/// The adversary's command for its player, in place of the guidance's.
fn adversary_plays(
    adversary: &mut Adversary,
    t: f64,
    p: [f64; 3],
    e: [f64; 3],
    command: &mut StepCommand,
) {
    let (w, v) = adversary.command(t, p, e);
    match adversary.opponent() {
        Opponent::Evader(_) => {
            command.evader = w;
            command.evader_speed = Some(v);
        }
        Opponent::Pursuer(_) => {
            command.pursuer = w;
            command.pursuer_speed = Some(v);
        }
    }
}
