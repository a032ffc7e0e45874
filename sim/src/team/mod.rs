//! The team's chase on the host: `N` pursuers, each with its own limits, against one evader,
//! all moved exactly (Dubins arcs) for a control period at a time. The pursuers fly as a team
//! (`twocars::team::Team`, the roles named on states with position noise), as `N` independent
//! 1-on-1 flight policies, or one of them alone; the evader goes straight, plays the law
//! against the pursuer it thinks will capture, or knows the team.

mod evader;
mod period;

use evader::team_aware;
pub use evader::{EvaderPlay, TeamEvader};
use period::{guidance, independent, narrow, Period};

use crate::kinematics::{advance, distance};
use crate::rng::Rng;
use twocars::team::Team;
use twocars::{Law, Limits, Variant};

/// How the pursuers fly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TeamPursuit {
    /// The team: roles on the time to go, each pursuer on its own flight policy.
    Team,
    /// Each on its own 1-on-1 flight policy, without roles.
    Independent,
    /// This pursuer alone, on its flight policy (the others take no part).
    Alone(usize),
}

/// A start: each pursuer's limits (v_pm, w_pm, v_em, w_em; m/s, 1/m: the evader's as each
/// pursuer's guidance assumes them, the same evader in all) and state, and the evader's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeamStart<const N: usize> {
    pub limits: [[f64; 4]; N],
    pub pursuers: [[f64; 3]; N],
    pub evader: [f64; 3],
}

impl<const N: usize> TeamStart<N> {
    /// A seeded start at `limits` for every pursuer: the evader at the origin, each pursuer 0.3
    /// to 1.5 thresholds away at a random bearing; every heading random. Drawn in this order:
    /// the evader's heading, then each pursuer's distance, bearing and heading.
    pub fn random(rng: &mut Rng, limits: [f64; 4]) -> Self {
        let threshold = crate::sim::theorem_threshold(limits);
        let pi = std::f64::consts::PI;
        let evader = [0.0, 0.0, rng.uniform(-pi, pi)];
        let pursuers = core::array::from_fn(|_| {
            let (d, bearing) = (threshold * rng.uniform(0.3, 1.5), rng.uniform(-pi, pi));
            [d * bearing.cos(), d * bearing.sin(), rng.uniform(-pi, pi)]
        });
        TeamStart {
            limits: [limits; N],
            pursuers,
            evader,
        }
    }
}

/// How a chase runs: period and length (s), capture radius (m), the standard deviation of
/// the noise on each position the team's roles are named from (m; the seed of its draws),
/// and how late each vehicle hears its teammates' states (s; `None`: one team, no views).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeamParams {
    pub dt: f64,
    pub t_max: f64,
    pub eps: f64,
    pub sigma: f64,
    pub seed: u64,
    pub teammate_lag: Option<f64>,
}

/// What a chase gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeamRun<const N: usize> {
    /// Time of capture (any pursuer that takes part within `eps`), s; `None` within `t_max`.
    pub captured: Option<f64>,
    /// The pursuer that captured (the first of those within `eps`).
    pub by: Option<usize>,
    /// The team's predicted capture time at the start, s.
    pub predicted: Option<f64>,
    /// How often each pursuer's role changed.
    pub swaps: [u32; N],
    /// With a teammate lag: the share of periods in which the vehicles' own teams named
    /// different chasers, and the longest such stretch (s).
    pub disagreement: Option<(f64, f64)>,
}

/// Each vehicle's own team, as it runs in that vehicle: its own state as it is, its
/// teammates' as heard `lag` periods ago and carried forward in a straight line, the evader's
/// as it is.
struct Views<const N: usize> {
    teams: Vec<Team<f32, N>>,
    dt: f64,
    limits: [[f64; 4]; N],
    heard: std::collections::VecDeque<[[f64; 3]; N]>,
    lag: usize,
    periods: u32,
    apart: u32,
    stretch: u32,
    longest: u32,
}

impl<const N: usize> Views<N> {
    fn new(team: &Team<f32, N>, lag: usize, dt: f64, limits: [[f64; 4]; N]) -> Self {
        Views {
            teams: vec![team.clone(); N],
            dt,
            limits,
            heard: std::collections::VecDeque::new(),
            lag,
            periods: 0,
            apart: 0,
            stretch: 0,
            longest: 0,
        }
    }

    /// One period: each vehicle's chaser, and whether they agree.
    fn step(&mut self, pursuers: &[[f64; 3]; N], evader: [f64; 3]) {
        self.heard.push_back(*pursuers);
        if self.heard.len() > self.lag + 1 {
            self.heard.pop_front();
        }
        // Each teammate's state as heard, carried forward along its heading at its speed to
        // now, as a vehicle's estimator would without its turn rate.
        let ahead = (self.heard.len() - 1) as f64 * self.dt;
        let carried: [[f64; 3]; N] =
            core::array::from_fn(|j| advance(self.heard[0][j], self.limits[j][0], 0.0, ahead));
        // Every vehicle decides every period (its team's hysteresis runs on), then they compare.
        let named: Vec<Option<usize>> = self
            .teams
            .iter_mut()
            .enumerate()
            .map(|(i, team)| {
                let mut seen = carried;
                seen[i] = pursuers[i];
                team.decide(&seen.map(narrow), narrow(evader)).chaser
            })
            .collect();
        let agree = named.iter().all(|&c| c == named[0]);
        self.periods += 1;
        self.stretch = if agree { 0 } else { self.stretch + 1 };
        self.apart += u32::from(!agree);
        self.longest = self.longest.max(self.stretch);
    }

    /// The share of periods apart, and the longest stretch (s).
    fn disagreement(&self, dt: f64) -> (f64, f64) {
        let share = f64::from(self.apart) / f64::from(self.periods.max(1));
        (share, f64::from(self.longest) * dt)
    }
}

/// One period of a traced chase: time (s), the pursuers' and the evader's states (m, rad),
/// and the chaser (the team's; `None` without roles).
pub type TeamSample<const N: usize> = (f64, [[f64; 3]; N], [f64; 3], Option<usize>);

/// The least game value over the pursuers at `start`, s: what the team predicts.
pub fn predicted<const N: usize>(start: &TeamStart<N>) -> Option<f64> {
    let mut least: Option<f64> = None;
    for (limits, pursuer) in start.limits.iter().zip(&start.pursuers) {
        let [v_pm, w_pm, v_em, w_em] = narrow(*limits);
        let law = Law::new(
            Limits::<f32>::new(v_pm, w_pm, v_em, w_em).ok()?,
            Variant::Paper,
        );
        let Ok((p, e)) = law.limits.states(narrow(*pursuer), narrow(start.evader)) else {
            continue;
        };
        if let Some(upper) = law.evaluate(&p, &e).report.and_then(|r| r.solution.upper) {
            least = Some(least.map_or(f64::from(upper), |l| l.min(f64::from(upper))));
        }
    }
    least
}

/// Chases from `start` with `params`; captured within `eps` of any pursuer that takes part.
/// `None` where a pursuer's limits are invalid.
pub fn chase<const N: usize>(
    start: &TeamStart<N>,
    pursuit: TeamPursuit,
    evader_kind: TeamEvader,
    params: TeamParams,
) -> Option<TeamRun<N>> {
    chase_traced(start, pursuit, evader_kind, params, None)
}

/// [`chase`], each period's states and chaser pushed to `trace`.
pub fn chase_traced<const N: usize>(
    start: &TeamStart<N>,
    pursuit: TeamPursuit,
    evader_kind: TeamEvader,
    params: TeamParams,
    mut trace: Option<&mut Vec<TeamSample<N>>>,
) -> Option<TeamRun<N>> {
    let TeamParams { dt, eps, .. } = params;
    let mut own = guidance(&start.limits, dt, eps)?;
    let mut team = Team::new(own, start.limits.map(narrow)).ok()?;
    let active: [bool; N] = core::array::from_fn(|i| match pursuit {
        TeamPursuit::Alone(k) => i == k,
        _ => true,
    });
    let mut noise = Rng::new(params.seed);
    let (mut pursuers, mut evader) = (start.pursuers, start.evader);
    let mut chaser = None;
    let mut run = TeamRun {
        captured: None,
        by: None,
        predicted: None,
        swaps: [0; N],
        disagreement: None,
    };
    let mut views = params
        .teammate_lag
        .map(|lag| Views::new(&team, (lag / dt).round() as usize, dt, start.limits));
    let v_em = start.limits[0][2];
    for k in 0..=(params.t_max / dt).ceil() as u64 {
        if let Some(i) = (0..N).find(|&i| active[i] && distance(pursuers[i], evader) <= eps) {
            run.captured = Some(k as f64 * dt);
            run.by = Some(i);
            if let Some(trace) = trace.as_deref_mut() {
                trace.push((k as f64 * dt, pursuers, evader, chaser));
            }
            break;
        }
        let period = match pursuit {
            TeamPursuit::Team => {
                let mut seen = |s: [f64; 3]| {
                    let (dx, dy) = (params.sigma * noise.normal(), params.sigma * noise.normal());
                    narrow([s[0] + dx, s[1] + dy, s[2]])
                };
                let (period, named) = team_period(&mut team, pursuers.map(&mut seen), seen(evader));
                if k > 0 && named != chaser {
                    for i in [chaser, named].into_iter().flatten() {
                        run.swaps[i] += 1;
                    }
                }
                chaser = named;
                if let Some(views) = views.as_mut() {
                    views.step(&pursuers, evader);
                }
                period
            }
            _ => independent(&mut own, &active, &pursuers, evader),
        };
        if k == 0 {
            run.predicted = period.predicted.map(f64::from);
        }
        if let Some(trace) = trace.as_deref_mut() {
            trace.push((k as f64 * dt, pursuers, evader, chaser));
        }
        let w_e = match evader_kind {
            TeamEvader::Straight => 0.0,
            TeamEvader::Law => period.law_evader,
            TeamEvader::TeamAware => team_aware(
                &start.limits,
                (&pursuers, evader),
                (&period.curvatures, &active),
                (dt, eps),
            ),
        };
        for i in (0..N).filter(|&i| active[i]) {
            pursuers[i] = advance(pursuers[i], start.limits[i][0], period.curvatures[i], dt);
        }
        evader = advance(evader, v_em, w_e, dt);
    }
    run.disagreement = views.map(|v| v.disagreement(dt));
    Some(run)
}

/// The team's period on the states as seen, and its chaser: each pursuer's command, the law's
/// evader against the least game value (as without roles), the team's time.
fn team_period<const N: usize>(
    team: &mut Team<f32, N>,
    pursuers: [[f32; 3]; N],
    evader: [f32; 3],
) -> (Period<N>, Option<usize>) {
    let d = team.decide(&pursuers, evader);
    let least = d
        .decisions
        .iter()
        .flatten()
        .fold(None, |best: Option<(f32, f32)>, d| {
            match (d.value_seconds(), best) {
                (Some(t), Some((b, _))) if t >= b => best,
                (Some(t), _) => Some((t, d.curvatures()[1])),
                (None, _) => best,
            }
        });
    let period = Period {
        curvatures: core::array::from_fn(|i| f64::from(d.curvature(i))),
        law_evader: least.map_or(0.0, |(_, w)| f64::from(w)),
        predicted: d.team_time(),
    };
    (period, d.chaser)
}
