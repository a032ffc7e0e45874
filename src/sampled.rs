//! The sampled, non-chattering command a controller applies every control period dt.
//!
//! The paper's F(x) turns at +-w_max until the tangent point, then goes straight. Held for a whole
//! period, +-w_max overshoots the tangent and flips between circles every period. The sampled
//! command turns each player by the heading angle alpha it still has to go, at most its full rate
//! over one period: w = sigma min(w_max, alpha / (v_max dt)); w = 0 once on the tangent. An alpha
//! within one period's turn of 2 pi (alpha > 2 pi - v_max w_max dt) counts as 0. Where options tie,
//! the previous choice is kept, so a tail chase on a common line stays straight. Options count as
//! tied within the law's relative band or within one control period dt of each other: a sampled
//! controller cannot act on a shorter difference in capture time.

use crate::geometry::{Direction, VehicleLimits, VehicleState};
use crate::law::{fallback_command, steer, Command, Evaluation, Law, Sampling};
use crate::num::Scalar;
use crate::status::Status;

/// A stateful caller of the law (firmware, host simulator): the law, the control period, and the
/// previous choice of circles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guidance<S> {
    law: Law<S>,
    dt: S,
    previous: Option<(Direction, Direction)>,
}

/// Why a control period is not usable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidPeriod;

impl<S: Scalar> Guidance<S> {
    /// Guidance with control period `dt` seconds.
    ///
    /// # Errors
    /// [`InvalidPeriod`] unless 0 < dt <= 1e3 s and finite, and representable in the law's
    /// units on this backend.
    pub fn new(law: Law<S>, dt: f32) -> Result<Self, InvalidPeriod> {
        if !(dt.is_finite() && dt > 0.0 && dt <= 1.0e3) {
            return Err(InvalidPeriod);
        }
        let dt = S::from_f32(law.limits.units.time_from_seconds(dt));
        if !(dt.is_valid() && dt > S::zero()) {
            return Err(InvalidPeriod);
        }
        Ok(Guidance {
            law,
            dt,
            previous: None,
        })
    }

    /// The law this guidance evaluates.
    pub fn law(&self) -> &Law<S> {
        &self.law
    }

    /// Forgets the previous choice (a new engagement).
    pub fn reset(&mut self) {
        self.previous = None;
    }

    fn arc_tolerance(&self, limits: &VehicleLimits<S>) -> S {
        (limits.max_turn_rate() * self.dt).max(S::from_f32(S::ARC_RESOLUTION))
    }

    /// Evaluates the law for this period and returns the evaluation with the sampled command.
    pub fn step(&mut self, pursuer: &VehicleState<S>, evader: &VehicleState<S>) -> Evaluation<S> {
        let limits = self.law.limits;
        let sampling = Sampling {
            pursuer_arc_tolerance: self.arc_tolerance(&limits.pursuer),
            evader_arc_tolerance: self.arc_tolerance(&limits.evader),
            previous: self.previous,
            tie_floor: self.dt,
        };
        let mut evaluation = self.law.evaluate_sampled(pursuer, evader, &sampling);
        let dt = Some(self.dt);
        evaluation.command = match (evaluation.status, evaluation.report) {
            (Status::Ok, Some(report)) => {
                let s = report.solution;
                self.previous = Some((s.row, s.col));
                match report.chosen_pair() {
                    Some(pair) => Command {
                        pursuer: steer(
                            s.row.sigma::<S>() * pair.capture.pursuer_arc,
                            &limits.pursuer,
                            dt,
                        ),
                        evader: steer(
                            s.col.sigma::<S>() * pair.capture.evader_arc,
                            &limits.evader,
                            dt,
                        ),
                    },
                    // A finite upper value with an infinite chosen entry cannot happen (the chosen
                    // row's worst entry is finite); keep the instantaneous command if it ever did.
                    None => evaluation.command,
                }
            }
            (Status::NoValidTangent, _) => fallback_command(pursuer, evader, &limits, dt),
            _ => Command::straight(),
        };
        evaluation.check_command();
        evaluation
    }
}
