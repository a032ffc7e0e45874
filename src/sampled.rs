//! The sampled, non-chattering command a controller applies every control period dt.
//!
//! The paper's F(x) turns at +-w_max until the tangent point, then goes straight. Held for a whole
//! period, +-w_max overshoots the tangent and flips between circles every period. The sampled
//! command turns each player by the heading angle alpha it still has to go, at most its full rate
//! over one period: w = sigma min(w_max, alpha / (v_max dt)); w = 0 once on the tangent. An alpha
//! within one period's turn of 2 pi (alpha > 2 pi - v_max w_max dt) counts as 0. Where options tie,
//! the previous choice is kept, so a tail chase on a common line stays straight. Options count as
//! tied within the law's relative band or within the capture-time equivalent of one period's
//! travel, dt v_pm / (v_pm - v_em): a sampled controller knows where the pursuer is along its path
//! only to within v_pm dt, which on a chase closing at v_pm - v_em is that much capture time.

use crate::geometry::{Limits, TurningCircle, VehicleLimits, VehicleState};
use crate::law::{
    bearing, fallback_command, steer, steer_along, Command, Decision, Evaluation, GameReport, Law,
    Period, Sampling,
};
use crate::num::Scalar;
use crate::status::Status;

/// Which feedback a [`Guidance`] applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Policy {
    /// The paper's law everywhere (the default).
    #[default]
    Paper,
    /// The paper's law while the players are at least the theorem's threshold apart
    /// ([`crate::Limits::theorem_threshold`]); below it the pursuer pursues (module docs).
    NearField,
}

/// A stateful caller of the law (firmware, host simulator): the law, the control period, the
/// policy and the previous choice of circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guidance<S> {
    law: Law<S>,
    policy: Policy,
    dt: S,
    period: Period<S>,
    /// Arc tolerances and tie floor, fixed by the limits and dt; `previous` is the last choice.
    sampling: Sampling<S>,
    near_field: NearFieldMemory<S>,
    near_field_terms: NearFieldTerms<S>,
}

/// What the near-field policy compares and scales by, fixed by the limits and dt (computed once
/// in [`Guidance::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct NearFieldTerms<S> {
    /// The theorem's distance threshold, metres ([`crate::Limits::theorem_threshold`]).
    threshold: S,
    /// Four periods' travel of the pursuer, 4 v_pm dt, metres: closer, a heading error is a
    /// miss distance.
    close: S,
    /// The pursuer's full turn over one period, v_pm w_pm dt, radians.
    period_turn: S,
    /// The lead distance per metre between the players, v_em / (2 v_pm): how far the evader runs
    /// in half the time the pursuer needs to cover that metre.
    lead_per_metre: S,
}

impl<S: Scalar> NearFieldTerms<S> {
    fn new(limits: &Limits<S>, dt: S) -> Self {
        let p = &limits.pursuer;
        NearFieldTerms {
            threshold: limits.theorem_threshold(),
            close: S::from_f32(4.0) * p.v_max() * dt,
            period_turn: p.max_turn_rate() * dt,
            lead_per_metre: limits.evader.v_max() / (p.v_max() + p.v_max()),
        }
    }
}

/// What the near-field policy remembers: the law's last upper value (seconds) and whether the
/// pursuer has left the law for lead pursuit.
#[derive(Clone, Copy, Debug, PartialEq)]
struct NearFieldMemory<S> {
    last_upper: Option<S>,
    pursuing: bool,
}

impl<S> NearFieldMemory<S> {
    /// Nothing remembered: the law is followed.
    const FRESH: Self = NearFieldMemory {
        last_upper: None,
        pursuing: false,
    };
}

/// Why a control period is not usable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidPeriod;

impl<S: Scalar> Guidance<S> {
    /// Guidance with control period `dt` seconds.
    ///
    /// # Errors
    /// [`InvalidPeriod`] unless 0 < dt <= 1e3 s and finite, and its terms (dt plus the tie floor,
    /// 2 pi / (v_max dt)) are within the backend's [`Scalar::MAX_PERIOD_TERM`] in the law's units.
    pub fn new(law: Law<S>, dt: f32) -> Result<Self, InvalidPeriod> {
        if !(dt.is_finite() && dt > 0.0 && dt <= 1.0e3) {
            return Err(InvalidPeriod);
        }
        let dt = S::from_f32(law.limits.units.time_from_seconds(dt));
        let bound = S::from_f32(S::MAX_PERIOD_TERM);
        if !(dt.is_valid() && dt > S::zero() && dt <= bound) {
            return Err(InvalidPeriod);
        }
        let pursuer_speed = law.limits.pursuer.v_max();
        let tie_floor = dt * pursuer_speed / (pursuer_speed - law.limits.evader.v_max());
        // Compared with bound - dt (>= 0 here): dt + tie_floor itself may leave the range.
        if !(tie_floor.is_valid() && tie_floor <= bound - dt) {
            return Err(InvalidPeriod);
        }
        let period = Period::new(&law.limits, dt).ok_or(InvalidPeriod)?;
        // A full turn's curvature, 2 pi / (v_max dt), within the bound as well.
        let per_radian_bound = bound / S::tau();
        if !(period.pursuer <= per_radian_bound && period.evader <= per_radian_bound) {
            return Err(InvalidPeriod);
        }
        // An arc within one period's full turn of 2 pi is a hair past the tangent.
        let largest_arc = |limits: &VehicleLimits<S>| {
            S::tau() - (limits.max_turn_rate() * dt).max(S::from_f32(S::ARC_RESOLUTION))
        };
        Ok(Guidance {
            law,
            policy: Policy::Paper,
            dt,
            period,
            sampling: Sampling {
                pursuer_largest_arc: largest_arc(&law.limits.pursuer),
                evader_largest_arc: largest_arc(&law.limits.evader),
                previous: None,
                tie_floor,
            },
            near_field: NearFieldMemory::FRESH,
            near_field_terms: NearFieldTerms::new(&law.limits, dt),
        })
    }

    /// The same guidance with `policy`.
    #[must_use]
    pub fn with_policy(self, policy: Policy) -> Self {
        Guidance { policy, ..self }
    }

    /// The law this guidance evaluates.
    pub fn law(&self) -> &Law<S> {
        &self.law
    }

    /// Forgets the previous choice (a new engagement).
    pub fn reset(&mut self) {
        self.sampling.previous = None;
        self.near_field = NearFieldMemory::FRESH;
    }

    /// Evaluates the law for this period and returns what a controller acts on: the status, the
    /// game's solution and the sampled command (as [`Guidance::step`], without the per-pair
    /// report).
    pub fn decide(&mut self, pursuer: &VehicleState<S>, evader: &VehicleState<S>) -> Decision<S> {
        let mut report = GameReport::empty();
        let (status, command) = self.play(pursuer, evader, &mut report);
        Decision::from_game(status, &report, command, self.law.limits.units)
    }

    /// Evaluates the law for this period and returns the evaluation with the sampled command.
    pub fn step(&mut self, pursuer: &VehicleState<S>, evader: &VehicleState<S>) -> Evaluation<S> {
        let mut report = GameReport::empty();
        let (status, command) = self.play(pursuer, evader, &mut report);
        Evaluation::from_game(status, report, command, self.law.limits.units)
    }

    /// The law for this period, its game written into `report`: the status and the sampled
    /// command. Without a game the near-field memory is forgotten.
    #[inline]
    fn play(
        &mut self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        report: &mut GameReport<S>,
    ) -> (Status, Command<S>) {
        let sampling = self.sampling;
        let law = self.law;
        let (status, command) =
            law.decide_into(pursuer, evader, &sampling, report, |status, report| {
                self.sampled_command(status, report, pursuer, evader)
            });
        if !status.has_game() {
            self.near_field = NearFieldMemory::FRESH;
        }
        (status, command)
    }

    /// The sampled command for a game: each player steers toward its chosen tangent by what one
    /// period needs (or the fallback's bearings); under the near-field policy the pursuer may
    /// leave the law (module docs). Records the choice for the next period.
    fn sampled_command(
        &mut self,
        status: Status,
        report: &GameReport<S>,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
    ) -> Command<S> {
        let limits = self.law.limits;
        let mut command = match status {
            Status::Ok => {
                let s = report.solution;
                self.sampling.previous = Some((s.row, s.col));
                match report.chosen_pair() {
                    Some(pair) => Command {
                        pursuer: steer_along(
                            s.row,
                            pair.capture.pursuer_arc,
                            &limits.pursuer,
                            self.period.pursuer,
                        ),
                        evader: steer_along(
                            s.col,
                            pair.capture.evader_arc,
                            &limits.evader,
                            self.period.evader,
                        ),
                    },
                    // A finite upper value with an infinite chosen entry cannot happen (the chosen
                    // row's worst entry is finite); the instantaneous command if it ever did.
                    None => self.law.instantaneous_command(&s, pursuer, evader),
                }
            }
            _ => fallback_command(pursuer, evader, &limits, Some(&self.period)),
        };
        match self.policy {
            Policy::NearField => self.near_field(report, pursuer, evader, &mut command),
            Policy::Paper => self.near_field = NearFieldMemory::FRESH,
        }
        command
    }

    /// The near-field policy's part: below the theorem's threshold, the pursuer's command becomes
    /// lead pursuit once the law has lost its prediction; at or above it the memory is forgotten.
    /// Out of line: the paper policy never runs it (its 816 B stay off the paper path).
    #[inline(never)]
    fn near_field(
        &mut self,
        report: &GameReport<S>,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        command: &mut Command<S>,
    ) {
        let terms = &self.near_field_terms;
        let distance = pursuer.position().distance(evader.position());
        if distance >= terms.threshold {
            self.near_field = NearFieldMemory::FRESH;
            return;
        }
        if self.near_field_lost(report, distance) {
            self.near_field.pursuing = true;
        }
        if self.near_field.pursuing {
            command.pursuer = lead_pursuit(
                pursuer,
                evader,
                distance,
                &self.law.limits.pursuer,
                &self.near_field_terms,
                self.period.pursuer,
            );
        }
    }
}

impl<S: Scalar> Guidance<S> {
    /// Whether, in the near field, the law has lost its own prediction: on the first near-field
    /// period its game is not trusted ([`crate::GameReport::trusted`]); later, its upper value
    /// rose instead of falling by dt (beyond the tie floor), or it has no finite value while the
    /// players are more than four periods' travel apart (closer, the law's fallback aims at the
    /// evader, as lead pursuit would). Records the upper value.
    fn near_field_lost(&mut self, report: &GameReport<S>, distance: S) -> bool {
        let upper = report.solution.upper;
        let lost = match (self.near_field.last_upper, upper) {
            (_, None) => distance >= self.near_field_terms.close,
            (None, Some(_)) => !report.trusted(self.sampling.tie_floor),
            (Some(last), Some(now)) => now > last - self.dt + self.sampling.tie_floor,
        };
        self.near_field.last_upper = upper;
        lost
    }
}

/// The near-field pursuer where the law's game is not to be trusted: it turns toward a lead point
/// ahead of the evader, at most what one period needs, unless the evader is inside the pursuer's
/// turning circle on that side and more than one period's turn off the nose, where turning cannot
/// bring it ahead: then it goes straight to open the distance. The lead point is where the evader
/// would be, holding its course, after half the time the pursuer needs to reach the evader's
/// present position (a full lead overshoots an evader that turns); `distance` is the players',
/// metres. A bearing within half a period's turn counts as on course (straight), except within
/// four periods' travel.
fn lead_pursuit<S: Scalar>(
    pursuer: &VehicleState<S>,
    evader: &VehicleState<S>,
    distance: S,
    p: &VehicleLimits<S>,
    terms: &NearFieldTerms<S>,
    per_radian: S,
) -> S {
    let lead = distance.mul_small(terms.lead_per_metre);
    let (sin, cos) = evader.theta.sin_cos();
    let to_go = bearing(pursuer, evader.x + lead * cos, evader.y + lead * sin);
    let [a, c] = TurningCircle::both(pursuer, p);
    let side = if to_go >= S::zero() { a } else { c };
    let period_turn = terms.period_turn;
    // Within a few periods' travel a heading error is a miss distance: aim exactly there.
    let close = distance < terms.close;
    let on_course = !close && to_go.abs() + to_go.abs() <= period_turn;
    let out_of_reach = to_go.abs() > period_turn
        && side.centre().distance_squared(evader.position()) < side.radius * side.radius;
    if on_course || out_of_reach {
        S::zero()
    } else {
        steer(to_go, p, Some(per_radian))
    }
}
