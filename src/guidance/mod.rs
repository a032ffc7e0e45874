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

mod homing;

use crate::error::Error;
use crate::estimate::Estimated;
use crate::law::geometry::{VehicleLimits, VehicleState};
use crate::law::{
    fallback_command, steer_along, Command, Decision, Evaluation, GameReport, Law, Period, Sampling,
};
#[cfg(feature = "value-tables")]
use crate::num::f32_math::{sin_cos, wrap_signed};
use crate::num::Scalar;
use crate::status::Status;
use crate::value_tables::ValueTables;
use homing::{lead_pursuit, HomingMemory, HomingTerms, Situation};

/// How many of the estimates' uncertainties (metres) a choice of circles must be beaten by
/// before the pursuer changes it ([`Guidance::decide_estimated`]).
pub const HYSTERESIS_SIGMAS: f32 = 1.0;

/// The widest cone about the pursuer's nose (half-angle, radians) within which an evader's
/// estimated bearing does not reverse its turn ([`Guidance::decide_estimated`]): near the
/// evader u / d grows past any bearing noise.
pub const NOISE_CONE: f32 = core::f32::consts::FRAC_PI_4;

/// Within this many of the pursuer's turning radii of the evader the pursuer does not hold a
/// course that misses it ([`Guidance::decide_estimated`]): past the evader, a pursuer that
/// held straight on noise loops a full turn to come back.
pub const TERMINAL_RADII: f32 = 2.0;

/// Which feedback a [`Guidance`] applies: [`Policy::Flight`] is the one to fly (the default);
/// [`Policy::Paper`] is the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Policy {
    /// The paper's law everywhere: the reference, which the theorem covers only from beyond
    /// its threshold.
    Paper,
    /// The paper's law while the players are at least the theorem's threshold apart
    /// ([`crate::Limits::theorem_threshold`]); below it the pursuer pursues (module docs).
    #[default]
    Flight,
    /// The flight policy, and below the threshold, where the game's value tables play
    /// ([`Guidance::with_tables`], [`crate::value_tables`]), both players' optimal turns from
    /// the tables (docs/near-field.md). Without tables, or built without the
    /// `value-tables` feature, the flight policy.
    Table,
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
    homing: HomingMemory<S>,
    homing_terms: HomingTerms<S>,
    /// The game's value tables of these limits' ratios, if any ([`Guidance::with_tables`]).
    tables: Option<&'static ValueTables<'static>>,
    /// This decision's hysteresis, seconds: the estimates' uncertainty as capture time
    /// ([`Guidance::decide_estimated`]); 0 on exact states.
    margin: S,
    /// This decision's estimates' uncertainty, its [`HYSTERESIS_SIGMAS`] multiple in the law's
    /// lengths ([`Guidance::decide_estimated`]); 0 on exact states.
    uncertainty: S,
    /// The side of the pursuer's last turn on estimated states (anticlockwise if `true`).
    side: Option<bool>,
}

impl<S: Scalar> Guidance<S> {
    /// Guidance playing `policy` with control period `dt` seconds ([`Policy::Flight`] is the
    /// one to fly; [`Policy::Paper`] is the paper's law everywhere, the reference).
    ///
    /// # Errors
    /// [`Error::InvalidPeriod`] unless 0 < dt <= 1e3 s and finite, and its terms (dt plus the
    /// tie floor, 2 pi / (v_max dt)) are within the backend's [`Scalar::MAX_PERIOD_TERM`] in the
    /// law's units.
    pub fn new(law: Law<S>, dt: f32, policy: Policy) -> Result<Self, Error> {
        if !(dt.is_finite() && dt > 0.0 && dt <= 1.0e3) {
            return Err(Error::InvalidPeriod);
        }
        let dt = S::from_f32(law.limits.units.time_from_seconds(dt));
        let bound = S::from_f32(S::MAX_PERIOD_TERM);
        if !(dt.is_valid() && dt > S::zero() && dt <= bound) {
            return Err(Error::InvalidPeriod);
        }
        let pursuer_speed = law.limits.pursuer.v_max();
        let tie_floor = dt * pursuer_speed / (pursuer_speed - law.limits.evader.v_max());
        // Compared with bound - dt (>= 0 here): dt + tie_floor itself may leave the range.
        if !(tie_floor.is_valid() && tie_floor <= bound - dt) {
            return Err(Error::InvalidPeriod);
        }
        let period = Period::new(&law.limits, dt).ok_or(Error::InvalidPeriod)?;
        // A full turn's curvature, 2 pi / (v_max dt), within the bound as well.
        let per_radian_bound = bound / S::tau();
        if !(period.pursuer <= per_radian_bound && period.evader <= per_radian_bound) {
            return Err(Error::InvalidPeriod);
        }
        // An arc within one period's full turn of 2 pi is a hair past the tangent.
        let largest_arc = |limits: &VehicleLimits<S>| {
            S::tau() - (limits.max_turn_rate() * dt).max(S::from_f32(S::ARC_RESOLUTION))
        };
        Ok(Guidance {
            law,
            policy,
            dt,
            period,
            sampling: Sampling {
                pursuer_largest_arc: largest_arc(&law.limits.pursuer),
                evader_largest_arc: largest_arc(&law.limits.evader),
                previous: None,
                tie_floor,
            },
            homing: HomingMemory::FRESH,
            homing_terms: HomingTerms::new(&law.limits, dt, tie_floor, period.pursuer),
            tables: None,
            margin: S::zero(),
            uncertainty: S::zero(),
            side: None,
        })
    }

    /// The same guidance with the game's value `tables`, which [`Policy::Table`] plays.
    ///
    /// # Errors
    /// [`Error::TablesMismatch`] unless the tables were solved for this law's ratios
    /// v_em / v_pm and (v_em / v_pm) (w_em / w_pm), each within 1e-3 of its value.
    pub fn with_tables(mut self, tables: &'static ValueTables<'static>) -> Result<Self, Error> {
        self.set_tables(tables)?;
        Ok(self)
    }

    /// [`Guidance::with_tables`] in place.
    ///
    /// # Errors
    /// As [`Guidance::with_tables`]; the guidance is then unchanged.
    pub fn set_tables(&mut self, tables: &'static ValueTables<'static>) -> Result<(), Error> {
        let limits = &self.law.limits;
        let ratio = |a: S, b: S| a.to_f32() / b.to_f32();
        let speed_ratio = ratio(limits.evader.v_max(), limits.pursuer.v_max());
        let evader_turn = speed_ratio * ratio(limits.evader.w_max(), limits.pursuer.w_max());
        let close = |table: f32, limit: f32| (table - limit).abs() <= 1e-3 * limit;
        let table = tables.finest_table().ok_or(Error::TablesMismatch)?;
        if close(table.speed_ratio, speed_ratio) && close(table.evader_turn, evader_turn) {
            self.tables = Some(tables);
            Ok(())
        } else {
            Err(Error::TablesMismatch)
        }
    }

    /// The same guidance told the capture radius, `metres` from the pursuer: the flight
    /// policy's pursuer then turns onto an evader within that radius of its turning circle
    /// rather than opening the distance to meet it exactly, and leaves the law where homing to
    /// the radius is sooner than the law's promise. The default, 0, asks for the evader's
    /// position itself (the paper's point capture).
    ///
    /// # Errors
    /// [`Error::InvalidLimits`] unless 0 <= `metres` < the pursuer's turning radius times the
    /// backend's coordinate range, finite.
    pub fn with_capture_radius(mut self, metres: f32) -> Result<Self, Error> {
        let units = self.law.limits.units;
        let radius = S::from_f32(metres / units.metres);
        let bound = S::from_f32(S::MAX_COORDINATE);
        if !(metres.is_finite() && metres >= 0.0 && radius.is_valid() && radius < bound) {
            return Err(Error::InvalidLimits);
        }
        self.homing_terms.capture = radius;
        Ok(self)
    }

    /// The value tables [`Policy::Table`] plays, if any.
    pub fn tables(&self) -> Option<&'static ValueTables<'static>> {
        self.tables
    }

    /// The same guidance with `policy`.
    #[must_use]
    pub fn with_policy(self, policy: Policy) -> Self {
        Guidance { policy, ..self }
    }

    /// [`Guidance::with_policy`] in place.
    pub fn set_policy(&mut self, policy: Policy) {
        self.policy = policy;
    }

    /// The same guidance with control period `dt` seconds, its memory kept (the previous
    /// choice and the near field's): for a caller whose period is measured as it runs.
    ///
    /// # Errors
    /// As [`Guidance::new`].
    pub fn with_period(&self, dt: f32) -> Result<Self, Error> {
        let mut next = *self;
        next.set_period(dt)?;
        Ok(next)
    }

    /// [`Guidance::with_period`] in place: no copy of the guidance (a few hundred bytes).
    ///
    /// # Errors
    /// As [`Guidance::new`]; the guidance is then unchanged.
    pub fn set_period(&mut self, dt: f32) -> Result<(), Error> {
        let fresh = Guidance::new(self.law, dt, self.policy)?;
        // What dt sets; the choice, the near field's memory, capture radius, tables and side
        // stay.
        let (previous, capture) = (self.sampling.previous, self.homing_terms.capture);
        self.dt = fresh.dt;
        self.period = fresh.period;
        self.sampling = fresh.sampling;
        self.sampling.previous = previous;
        self.homing_terms = fresh.homing_terms;
        self.homing_terms.capture = capture;
        Ok(())
    }

    /// The law this guidance evaluates.
    pub fn law(&self) -> &Law<S> {
        &self.law
    }

    /// `decision`'s command as turn rates, rad/s: [pursuer, evader], each v_max w, what a
    /// yaw-rate setpoint takes. Fixed point forms them with integers (no soft-float product).
    pub fn turn_rates(&self, decision: &Decision<S>) -> [f32; 2] {
        let limits = &self.law.limits;
        let units = limits.units;
        let per_law_unit = units.metres_per_second / units.metres;
        [
            (decision.command.pursuer * limits.pursuer.v_max()).to_f32_scaled(per_law_unit),
            (decision.command.evader * limits.evader.v_max()).to_f32_scaled(per_law_unit),
        ]
    }

    /// The control period, s.
    pub fn period(&self) -> f32 {
        let units = self.law.limits.units;
        self.dt
            .to_f32_scaled(units.metres / units.metres_per_second)
    }

    /// Forgets the previous choice (a new engagement).
    pub fn reset(&mut self) {
        self.sampling.previous = None;
        self.side = None;
        self.homing = HomingMemory::FRESH;
    }

    /// Evaluates the law for this period and returns what a controller acts on: the status, the
    /// game's solution and the sampled command (as [`Guidance::step`], without the per-pair
    /// report).
    pub fn decide(&mut self, pursuer: &VehicleState<S>, evader: &VehicleState<S>) -> Decision<S> {
        let mut report = GameReport::empty();
        let (status, command) = self.play(pursuer, evader, &mut report);
        Decision::from_game(status, &report, command, self.law.limits.units)
    }

    /// [`Guidance::decide`] on states estimated from fixes ([`crate::estimate`], in the law's
    /// units: an `Estimator<S>` of this backend), with hysteresis against their uncertainty u
    /// so that noise does not flip the turn (docs/contract.md):
    ///
    /// - the choice of circles is kept unless another is better by more than
    ///   [`HYSTERESIS_SIGMAS`] u / (v_pm - v_em) seconds (at most the pursuer's full turn's
    ///   time);
    /// - the pursuer turns to the other side than its last turn only where the evader's
    ///   bearing is outside the cone of half-angle [`HYSTERESIS_SIGMAS`] u / d about its nose
    ///   (d the players' distance; at most [`NOISE_CONE`]) and it is told more than that angle
    ///   needs in a period (at most w_pm); otherwise it runs straight;
    /// - but within [`TERMINAL_RADII`] of its turning radius it does not run straight where
    ///   that passes the evader by more than the capture radius, or the evader falls behind;
    /// - and below the theorem's threshold, with u past a quarter of the capture radius, the
    ///   flight policy's pursuer flies lead pursuit of the estimated evader's collision point
    ///   (docs/field.md, "The command that does not chatter").
    ///
    /// With u = 0 the decision is [`Guidance::decide`]'s.
    ///
    /// # Errors
    /// As [`crate::Limits::states_in_units`] for the estimated states.
    pub fn decide_estimated(&mut self, estimated: &Estimated<S>) -> Result<Decision<S>, Error> {
        let limits = self.law.limits;
        let (pursuer, evader) = limits.states_in_units(estimated.own, estimated.target)?;
        let full_turn = S::tau() / limits.pursuer.max_turn_rate();
        let uncertainty = S::from_f32(HYSTERESIS_SIGMAS) * estimated.uncertainty;
        let per_metre = limits.seconds_per_metre_closed();
        // The margin at most a full turn, its product formed only below it (fixed point's range).
        self.margin = if !uncertainty.is_number() {
            full_turn
        } else if uncertainty <= S::zero() {
            S::zero()
        } else if uncertainty >= full_turn / per_metre {
            full_turn
        } else {
            uncertainty * per_metre
        };
        // Not NaN: an uncertainty that is not a number is the largest there is.
        self.uncertainty = if uncertainty.is_number() {
            uncertainty.max(S::zero())
        } else {
            S::from_f32(S::MAX_COORDINATE)
        };
        let mut decision = self.decide(&pursuer, &evader);
        self.margin = S::zero();
        self.uncertainty = S::zero();
        if self.noise_reversal(estimated, uncertainty, decision.command.pursuer) {
            decision.command.pursuer = S::zero();
        }
        let w = decision.command.pursuer;
        if w != S::zero() {
            self.side = Some(w > S::zero());
        }
        Ok(decision)
    }

    /// Whether the pursuer's curvature `w` (law units) turns it to the other side than its last
    /// turn where the estimates' `uncertainty` (law units, its multiple) could explain it: the
    /// evader within the cone of half-angle uncertainty / d (at most [`NOISE_CONE`]) about
    /// the pursuer's nose, or `w` within the curvature that turns that angle in a period.
    fn noise_reversal(&self, estimated: &Estimated<S>, uncertainty: S, w: S) -> bool {
        let reverses = match self.side {
            Some(left) => (left && w < S::zero()) || (!left && w > S::zero()),
            None => false,
        };
        // Not `<= 0` alone: a NaN is no uncertainty either.
        if !reverses || uncertainty.partial_cmp(&S::zero()) != Some(core::cmp::Ordering::Greater) {
            return false;
        }
        let [px, py, heading] = estimated.own;
        let [ex, ey, _] = estimated.target;
        // Inside the law's envelope (checked by `decide_estimated`): the squares are held.
        let (dx, dy) = (ex - px, ey - py);
        let distance = (dx * dx + dy * dy).sqrt();
        let widest = S::from_f32(NOISE_CONE);
        let cone = if uncertainty >= widest * distance {
            widest
        } else {
            uncertainty / distance
        };
        if self.straight_misses(estimated, distance) {
            return false;
        }
        let bearing = (S::atan2(dy, dx) - heading).wrap_signed();
        let gate = (self.period.pursuer * cone).min(self.law.limits.pursuer.w_max());
        bearing.abs() <= cone || w.abs() < gate
    }

    /// Whether, with the players `distance` apart (law units) within [`TERMINAL_RADII`] of
    /// the pursuer's turning radius, running straight passes the estimated target by more than
    /// the capture radius (both at full speed along their headings, the law's model), or the
    /// target is already falling behind: a held course there is a miss, and a miss is a loop.
    fn straight_misses(&self, estimated: &Estimated<S>, distance: S) -> bool {
        let limits = &self.law.limits;
        if distance * limits.pursuer.w_max() >= S::from_f32(TERMINAL_RADII) {
            return false;
        }
        let [px, py, own_heading] = estimated.own;
        let [ex, ey, target_heading] = estimated.target;
        let (dx, dy) = (ex - px, ey - py);
        let (sp, cp) = own_heading.sin_cos();
        let (se, ce) = target_heading.sin_cos();
        let (vp, ve) = (limits.pursuer.v_max(), limits.evader.v_max());
        // The target's velocity relative to the pursuer's.
        let (vx, vy) = (ve * ce - vp * cp, ve * se - vp * sp);
        if dx * vx + dy * vy >= S::zero() {
            return true;
        }
        // The miss distance is |r x v| / |v|; compared squared, both sides within a few radii.
        let cross = dx * vy - dy * vx;
        let capture = self.homing_terms.capture;
        cross * cross > capture * capture * (vx * vx + vy * vy)
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
        let mut sampling = self.sampling;
        sampling.tie_floor = sampling.tie_floor + self.margin;
        let law = self.law;
        let (status, command) =
            law.decide_into(pursuer, evader, &sampling, report, |status, report| {
                self.sampled_command(status, report, pursuer, evader)
            });
        if !status.has_game() {
            self.homing = HomingMemory::FRESH;
        }
        (status, command)
    }

    /// The sampled command for a game: each player steers toward its chosen tangent by what one
    /// period needs (or the fallback's bearings); under the flight policy the pursuer may
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
            Policy::Flight => self.homing(report, pursuer, evader, &mut command),
            Policy::Table => {
                self.homing(report, pursuer, evader, &mut command);
                #[cfg(feature = "value-tables")]
                self.table_turns(pursuer, evader, &mut command);
            }
            Policy::Paper => self.homing = HomingMemory::FRESH,
        }
        command
    }

    /// The tables' turns (feature `value-tables`): where the value tables play (below the threshold, outside the capture
    /// disc, in their boxes), each player turns fully or runs straight as the tables' minimax
    /// says for the period. Out of line: only [`Policy::Table`] runs it.
    #[cfg(feature = "value-tables")]
    #[inline(never)]
    fn table_turns(
        &self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        command: &mut Command<S>,
    ) {
        let Some(tables) = self.tables else {
            return;
        };
        let limits = &self.law.limits;
        // The evader in the pursuer's frame, lengths in r_p (= 1 / w_pm, in any units).
        let per_radius = limits.pursuer.w_max().to_f32();
        let (dx, dy) = (
            (evader.x - pursuer.x).to_f32() * per_radius,
            (evader.y - pursuer.y).to_f32() * per_radius,
        );
        let (s, c) = sin_cos(wrap_signed(pursuer.theta.to_f32()));
        let (x, y) = (dx * c + dy * s, -dx * s + dy * c);
        let phi = (evader.theta - pursuer.theta).to_f32();
        if let Some(u) = tables.pursuer_turn(x, y, phi) {
            command.pursuer = S::from_f32(u) * limits.pursuer.w_max();
        }
        if let Some(w) = tables.evader_turn(x, y, phi) {
            command.evader = S::from_f32(w) * limits.evader.w_max();
        }
    }

    /// The flight policy's near field: below the theorem's threshold the pursuer's command may
    /// home on the evader ([`crate::guidance::homing`]); at or above it the memory is forgotten.
    /// Out of line: the paper policy never runs it.
    #[inline(never)]
    fn homing(
        &mut self,
        report: &GameReport<S>,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        command: &mut Command<S>,
    ) {
        let terms = &self.homing_terms;
        let distance = pursuer.position().distance(evader.position());
        if distance >= terms.threshold {
            self.homing = HomingMemory::FRESH;
            return;
        }
        let now = Situation {
            report,
            pursuer,
            evader,
            distance,
            limits: &self.law.limits.pursuer,
            law: command.pursuer,
        };
        if self.uncertainty > terms.lead_pursuit_floor() {
            self.homing = HomingMemory::FRESH;
            command.pursuer = lead_pursuit(&now, terms, self.period.pursuer);
        } else {
            command.pursuer = self.homing.pursuer_command(&now, terms);
        }
    }
}
