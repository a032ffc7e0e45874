//! The field in the closed loop: the target's fixes come late, sparse, noisy and sometimes not
//! at all, and the pursuer answers its yaw-rate setpoint with a first-order lag.
//!
//! Both vehicles move exactly as in [`crate::sim`] (f64, zero-order hold), the pursuer's
//! curvature following its command as w' = (w_cmd - w) / tau within sub-steps of the period.
//! Every [`FieldModel::fix_interval`] the target's true state is sampled, noised (Gaussian on
//! x, y and heading) and, unless dropped, delivered [`FieldModel::lag`] later. The pursuer's
//! own state is known exactly at each decision (its autopilot's estimate). The guidance sees
//! the fixes through a [`Receiver`]: as they came (what an endpoint without an estimator does:
//! the last fix as the target's state) or through [`twocars::estimate::Estimator`].

use std::collections::VecDeque;

use crate::adversary::{Adversary, EvaderKind, Opponent};
use crate::kinematics::{advance, distance, wrap_pi};
use crate::peers::{HeardFix, Peer, PeerPursuer};
use crate::rng::Rng;
use crate::sim::{capture_within, valid_params, SignFlips, SimParams, SimResult, SimStatus};
use twocars::estimate::{Estimator, FieldSettings, FixNoise};
use twocars::{Guidance, Law, Limits, Policy, Variant};

/// How long the target has been tracked when the chase begins, seconds: fixes from its
/// straight run before t = 0, so that no chase begins blind.
pub const HISTORY: f64 = 1.0;

/// Sub-steps per control period of the pursuer's lagging turn.
const SUBSTEPS: usize = 8;

/// What the field does to the target's fixes and to the pursuer's turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldModel {
    /// Transport lag of each fix, seconds.
    pub lag: f64,
    /// Time between fixes, seconds; 0: one at every control period.
    pub fix_interval: f64,
    /// One sigma of the fixes' x and y, metres.
    pub position_sigma: f64,
    /// One sigma of the fixes' heading, radians.
    pub heading_sigma: f64,
    /// The chance that a fix is lost, in [0, 1).
    pub dropout: f64,
    /// The pursuer's yaw-rate time constant tau, seconds; 0: it turns as told.
    pub yaw_lag: f64,
    /// The noise's and the dropouts' seed.
    pub seed: u64,
}

impl FieldModel {
    /// Exact states at every period, a pursuer that turns as told.
    pub const EXACT: FieldModel = FieldModel {
        lag: 0.0,
        fix_interval: 0.0,
        position_sigma: 0.0,
        heading_sigma: 0.0,
        dropout: 0.0,
        yaw_lag: 0.0,
        seed: 0,
    };
}

/// How the guidance hears of the target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Receiver {
    /// Its last fix as its present state.
    Raw,
    /// Through the estimator, told the field's noise, each fix with the time it was taken and
    /// its speed (as GLOBAL_POSITION_INT carries them), carrying both states `own_lead` seconds
    /// ahead.
    Estimator {
        /// [`FieldSettings::own_lead`], seconds.
        own_lead: f64,
    },
}

/// Who pursues in the field: ours, hearing of the target through a [`Receiver`], or a peer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pursuer {
    /// The flight policy (f32, told the capture radius).
    Ours(Receiver),
    /// An autopilot's follow mode ([`crate::peers`]).
    Peer(Peer),
}

impl From<Receiver> for Pursuer {
    fn from(receiver: Receiver) -> Self {
        Pursuer::Ours(receiver)
    }
}

impl From<Peer> for Pursuer {
    fn from(peer: Peer) -> Self {
        Pursuer::Peer(peer)
    }
}

/// One fix on its way: when it arrives and when it was taken (s), and the noisy state taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pending {
    /// Arrival, seconds.
    pub arrival: f64,
    /// When the target was there, seconds.
    pub taken: f64,
    /// x, y (metres), heading (radians), with the field's noise.
    pub state: [f64; 3],
    /// The target's velocity as its fix reports it, m/s: its speed along the noisy heading.
    pub velocity: [f64; 2],
}

/// The fixes of one run: sampled from the target's path, noised, dropped, delayed.
pub struct Fixes {
    model: FieldModel,
    rng: Rng,
    next_sample: f64,
    pending: VecDeque<Pending>,
}

impl Fixes {
    /// The fixes `model` makes, from [`HISTORY`] before t = 0.
    pub fn new(model: FieldModel) -> Self {
        Fixes {
            model,
            rng: Rng::new(model.seed),
            next_sample: -HISTORY,
            pending: VecDeque::new(),
        }
    }

    /// Samples the target on its path from `start` (its state at `t0`) at speed `v` and
    /// curvature `w`, at the fix times in [t0, t0 + dt).
    pub fn sample(&mut self, t0: f64, dt: f64, start: [f64; 3], v: f64, w: f64) {
        let interval = if self.model.fix_interval > 0.0 {
            self.model.fix_interval
        } else {
            dt
        };
        while self.next_sample < t0 + dt - 1e-9 {
            let at = self.next_sample;
            // Before the chase the target ran straight at full speed.
            let [x, y, theta] = if at < t0 {
                advance(start, v, 0.0, at - t0)
            } else {
                advance(start, v, w, at - t0)
            };
            self.next_sample += interval;
            let lost = self.rng.uniform(0.0, 1.0) < self.model.dropout;
            let m = self.model;
            let noisy = [
                x + m.position_sigma * self.rng.normal(),
                y + m.position_sigma * self.rng.normal(),
                wrap_pi(theta + m.heading_sigma * self.rng.normal()),
            ];
            if !lost {
                self.pending.push_back(Pending {
                    arrival: at + m.lag,
                    taken: at,
                    state: noisy,
                    velocity: [v * noisy[2].cos(), v * noisy[2].sin()],
                });
            }
        }
    }

    /// The fixes that have arrived by `t`, oldest first.
    pub fn arrived(&mut self, t: f64) -> impl Iterator<Item = Pending> + '_ {
        let count = self
            .pending
            .iter()
            .take_while(|p| p.arrival <= t + 1e-9)
            .count();
        self.pending.drain(..count)
    }
}

/// Microseconds of the unit's clock at `t` seconds (wrapping: the history before t = 0 is
/// late in the clock's lap).
fn micros(t: f64) -> u32 {
    (t * 1.0e6).round() as i64 as u32
}

/// The pursuer's curvature over a sub-step of `h` seconds, and at its end, from `w` at its
/// start toward the command `target` with time constant `tau` (0: at once).
fn lagged(w: f64, target: f64, tau: f64, h: f64) -> (f64, f64) {
    if tau <= 0.0 {
        return (target, target);
    }
    let decay = (-h / tau).exp();
    let mean = target + (w - target) * tau / h * (1.0 - decay);
    (mean, target + (w - target) * decay)
}

/// Our pursuer in the field: the flight policy (f32, told the capture radius), hearing of the
/// target through its [`Receiver`].
struct FieldPursuer {
    guidance: Guidance<f32>,
    estimator: Estimator,
    limits: Limits<f32>,
    receiver: Receiver,
    /// The last fix to arrive, as it came.
    last_fix: Option<[f64; 3]>,
}

impl FieldPursuer {
    /// `None` where the limits or the field's settings are invalid.
    fn new(params: &SimParams, field: &FieldModel, receiver: Receiver) -> Option<Self> {
        let limits32 = params.limits.map(|v| v as f32);
        let [v_pm, w_pm, v_em, w_em] = limits32;
        let limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em).ok()?;
        // The guidance period is the pursuer's response where longer than dt, as the MAVLink
        // endpoint's TC_PERIOD sets it: steering to close a bearing within one period of a
        // vehicle that takes tau to answer over-commands it and flips full turns.
        let period = params.dt.max(field.yaw_lag) as f32;
        let guidance = Guidance::new(Law::new(limits, Variant::Paper), period, Policy::Flight)
            .and_then(|g| g.with_capture_radius(params.eps as f32))
            .ok()?;
        let settings = FieldSettings {
            target_noise: FixNoise {
                position: field.position_sigma as f32,
                heading: field.heading_sigma as f32,
            },
            own_lead: match receiver {
                Receiver::Estimator { own_lead } => own_lead as f32,
                Receiver::Raw => 0.0,
            },
            target_lag: field.lag as f32,
            ..FieldSettings::exact(1.0e3)
        };
        let estimator = Estimator::new(limits32, settings).ok()?;
        Some(FieldPursuer {
            guidance,
            estimator,
            limits,
            receiver,
            last_fix: None,
        })
    }

    /// Hears the fixes that arrived by `t0` and its own state `p`; its curvature command, 0
    /// where it has nothing to steer by.
    fn command(&mut self, t0: f64, p: [f64; 3], arrived: impl Iterator<Item = Pending>) -> f64 {
        let now = micros(t0);
        for fix in arrived {
            self.last_fix = Some(fix.state);
            let located = twocars::estimate::Fix {
                state: fix.state.map(|v| v as f32),
                time_us: micros(fix.taken),
            };
            // The fix's velocity, as GLOBAL_POSITION_INT carries it: its length is the speed.
            let [vx, vy] = fix.velocity;
            let _ = self
                .estimator
                .target_fix_with_speed(&located, vx.hypot(vy) as f32);
        }
        let _ = self.estimator.own_fix(&twocars::estimate::Fix {
            state: p.map(|v| v as f32),
            time_us: now,
        });
        let seen = match self.receiver {
            Receiver::Raw => self.last_fix.and_then(|target| {
                // The law's frame centred on the pursuer, formed as for the estimates below.
                let (own, target) = (p.map(|v| v as f32), target.map(|v| v as f32));
                let local = |s: [f32; 3]| [s[0] - own[0], s[1] - own[1], s[2]];
                let (ps, es) = self.limits.states(local(own), local(target)).ok()?;
                Some(self.guidance.decide(&ps, &es))
            }),
            Receiver::Estimator { .. } => self.estimator.states(now).ok().and_then(|mut est| {
                // The law's frame centred on the pursuer, as `sim::closed_loop` gives it.
                let origin = [est.own[0], est.own[1]];
                est.own = [0.0, 0.0, est.own[2]];
                est.target = [
                    est.target[0] - origin[0],
                    est.target[1] - origin[1],
                    est.target[2],
                ];
                self.guidance.decide_estimated(&est).ok()
            }),
        };
        seen.map_or(0.0, |d| f64::from(d.command.pursuer))
    }
}

/// One control period of `dt` from `t0`: the pursuer at `v_pm`, its curvature lagging toward
/// `command` with time constant `yaw_lag`; the evader holding (`v_e`, `w_e`); capture at `eps`.
struct Period {
    t0: f64,
    dt: f64,
    command: f64,
    v_pm: f64,
    yaw_lag: f64,
    evader: (f64, f64),
    eps: f64,
}

impl Period {
    /// Moves the pursuer `p` (curvature `w_actual`) and the evader `e` over the period in
    /// [`SUBSTEPS`]; the capture time where the gap closes to `eps` within it (the states then
    /// left at the sub-step's start).
    fn fly(
        &self,
        p: &mut [f64; 3],
        w_actual: &mut f64,
        e: &mut [f64; 3],
        d_min: &mut f64,
    ) -> Option<f64> {
        let (v_e, w_e) = self.evader;
        let (v_pm, yaw_lag, eps) = (self.v_pm, self.yaw_lag, self.eps);
        let h = self.dt / SUBSTEPS as f64;
        for i in 0..SUBSTEPS {
            let (w_p, w_end) = lagged(*w_actual, self.command, yaw_lag, h);
            let offset = i as f64 * h;
            let start = *p;
            let at = |tau: f64| {
                (
                    advance(start, v_pm, w_p, tau),
                    advance(advance(*e, v_e, w_e, offset), v_e, w_e, tau),
                )
            };
            let gap = |tau: f64| {
                let (a, b) = at(tau);
                distance(a, b)
            };
            if let Some(tau) = capture_within(h, eps, gap, d_min) {
                return Some(self.t0 + offset + tau);
            }
            *p = at(h).0;
            *w_actual = w_end;
        }
        p[2] = wrap_pi(p[2]);
        *e = advance(*e, v_e, w_e, self.dt);
        e[2] = wrap_pi(e[2]);
        None
    }
}

/// The pursuer flying a chase: ours or a peer, and the fixes it has heard.
enum Flyer {
    Ours(Box<FieldPursuer>),
    Peer(PeerPursuer),
}

impl Flyer {
    /// `None` where the limits or the field's settings are invalid.
    fn new(params: &SimParams, field: &FieldModel, pursuer: Pursuer) -> Option<Self> {
        match pursuer {
            Pursuer::Ours(receiver) => {
                FieldPursuer::new(params, field, receiver).map(|p| Flyer::Ours(Box::new(p)))
            }
            Pursuer::Peer(peer) => {
                let [v_pm, w_pm, _, _] = params.limits;
                let period = params.dt.max(field.yaw_lag);
                Some(Flyer::Peer(PeerPursuer::new(peer, v_pm, w_pm, period)))
            }
        }
    }

    /// The curvature command at `t0` for the pursuer at `p`, having heard `arrived`.
    fn command(&mut self, t0: f64, p: [f64; 3], arrived: impl Iterator<Item = Pending>) -> f64 {
        match self {
            Flyer::Ours(ours) => ours.command(t0, p, arrived),
            Flyer::Peer(peer) => {
                for fix in arrived {
                    peer.hear(&HeardFix {
                        arrival: fix.arrival,
                        taken: fix.taken,
                        position: [fix.state[0], fix.state[1]],
                        velocity: fix.velocity,
                    });
                }
                peer.command(t0, p)
            }
        }
    }
}

/// Loops of a chase: a pass within three capture radii, then a turn of more than pi before
/// capture.
#[derive(Clone, Copy, Debug)]
pub struct Loops {
    /// Distances at the last two periods' ends, metres.
    last: [f64; 2],
    /// The pursuer's signed turn since the last pass, radians; `None` until a pass.
    turned: Option<f64>,
    /// Loops counted.
    pub count: u64,
}

impl Default for Loops {
    fn default() -> Self {
        Loops {
            last: [f64::INFINITY; 2],
            turned: None,
            count: 0,
        }
    }
}

impl Loops {
    /// Records a period's end: the players' distance `d` (m), the pursuer's heading change
    /// over the period `turn` (rad), the capture radius `eps` (m).
    pub fn record(&mut self, d: f64, turn: f64, eps: f64) {
        let [before, last] = self.last;
        if last < 3.0 * eps && last <= before && d > last {
            self.turned = Some(0.0);
        }
        if let Some(turned) = self.turned.as_mut() {
            *turned += turn;
            if turned.abs() > std::f64::consts::PI {
                self.count += 1;
                self.turned = None;
            }
        }
        self.last = [last, d];
    }
}

/// One chase of `pursuer` against `evader` (seeded by `evader_seed`) in `field`. `sign_flips`
/// counts the pursuer's alone; `loops` counts its loops ([`Loops`]).
pub fn chase(
    params: &SimParams,
    evader: EvaderKind,
    evader_seed: u64,
    field: &FieldModel,
    pursuer: impl Into<Pursuer>,
) -> SimResult {
    let (p, e) = (params.pursuer, params.evader);
    let pursuer = Flyer::new(params, field, pursuer.into());
    let adversary = Adversary::new(
        Opponent::Evader(evader),
        params.limits,
        params.dt,
        params.eps,
        evader_seed,
    );
    let (Some(mut pursuer), Some(mut adversary), true) = (pursuer, adversary, valid_params(params))
    else {
        return SimResult::empty(SimStatus::InvalidSimParams, distance(p, e));
    };
    let [v_pm, w_pm, _, _] = params.limits;
    let (dt, eps) = (params.dt, params.eps);
    let (mut p, mut e) = (p, e);
    let mut result = SimResult::empty(SimStatus::Timeout, distance(p, e));
    let mut fixes = Fixes::new(*field);
    let (mut w_actual, mut flips) = (0.0_f64, SignFlips::default());
    let mut loops = Loops::default();
    let steps = (params.t_max / dt).ceil() as u64;
    for k in 0..steps {
        let t0 = k as f64 * dt;
        let (w_e, v_e) = adversary.command(t0, p, e);
        fixes.sample(t0, dt, e, v_e, w_e);
        let command = pursuer.command(t0, p, fixes.arrived(t0));
        flips.record(0, command, w_pm, false);
        result.sign_flips = flips.count;
        let period = Period {
            t0,
            dt,
            command,
            v_pm,
            yaw_lag: field.yaw_lag,
            evader: (v_e, w_e),
            eps,
        };
        let heading = p[2];
        if let Some(t) = period.fly(&mut p, &mut w_actual, &mut e, &mut result.d_min) {
            result.status = SimStatus::Captured;
            result.t_capture = t;
            return result;
        }
        loops.record(distance(p, e), wrap_pi(p[2] - heading), eps);
        result.loops = loops.count;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::Loops;

    #[test]
    fn a_pass_then_a_full_turn_is_a_loop_and_a_turn_without_a_pass_is_not() {
        let eps = 0.1;
        let mut loops = Loops::default();
        // Closing far out, turning: no pass within 3 eps, no loop.
        for d in [2.0, 1.5, 1.0, 1.2, 1.4] {
            loops.record(d, 1.0, eps);
        }
        assert_eq!(loops.count, 0);
        // A pass at 0.2 (within 0.3), then 3.5 rad of turn over five periods.
        for d in [0.5, 0.2, 0.4, 0.6, 0.8, 0.7, 0.5] {
            loops.record(d, 0.7, eps);
        }
        assert_eq!(loops.count, 1);
    }
}
