//! The feedback law F(x) for both players (the paper's Theorem 4): four valid tangents, four
//! capture times, the matrix game, and a command with a status for every input.
//!
//! Commands are curvatures in 1/m (theta_dot = v w); a turn rate in rad/s is v_max w.
//!
//! The paper's parts: [`geometry`] (the turning circles and Algorithm 1's tangents),
//! [`capture`] (Algorithm 2's capture times) and [`game`] (Table 1's matrix game).

pub mod capture;
pub mod game;
pub mod geometry;

use crate::error::Error;
use crate::num::Scalar;
use crate::status::Status;
use capture::{capture_time, CaptureTime, Variant};
use game::{solve_values, GameSolution, MatrixGame};
pub use geometry::CAPTURE_RADIUS_FRACTION;
use geometry::{CirclePairs, Direction, Limits, Units, ValidTangent, VehicleLimits, VehicleState};

/// Curvature command of both players, 1/m. Zero is straight ahead, the safe command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Command<S> {
    /// Pursuer curvature w_p, 1/m, within +-w_pm.
    pub pursuer: S,
    /// Evader curvature w_e, 1/m, within +-w_em.
    pub evader: S,
}

impl<S: Scalar> Command<S> {
    /// Both players straight ahead.
    pub fn straight() -> Self {
        Command {
            pursuer: S::zero(),
            evader: S::zero(),
        }
    }
}

/// One PE pair: its valid tangent and the time to capture along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairOutcome<S> {
    /// The valid tangent (Algorithm 1).
    pub tangent: ValidTangent<S>,
    /// Time to capture along it (Algorithm 2).
    pub capture: CaptureTime<S>,
}

/// Everything the law computed for a valid, uncaptured state. (The circles are not kept: they
/// follow from the states, [`crate::TurningCircle::both`].)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GameReport<S> {
    /// Per pair `[pursuer circle][evader circle]` (A, C): `None` where no valid tangent exists.
    pub pairs: [[Option<PairOutcome<S>>; 2]; 2],
    /// The solution of the matrix game: chosen circles and values.
    pub solution: GameSolution<S>,
}

impl<S: Scalar> GameReport<S> {
    /// No pairs, and a placeholder solution: the place a game is written into. Every game
    /// overwrites the solution, and it is read only where the status has a game. (A function,
    /// not a constant: a constant is copied whole from flash, where this stores a few tags. The
    /// placeholder's row is C so that it is not all zero, which a Cortex-M build clears with a
    /// `memclr` call.)
    #[inline]
    pub fn empty() -> Self {
        GameReport {
            pairs: [[None, None], [None, None]],
            solution: GameSolution {
                row: Direction::Clockwise,
                col: Direction::Anticlockwise,
                upper: None,
                lower: None,
            },
        }
    }

    /// The matrix of Table 1: each pair's time to capture, `None` (infinity) where it has no valid
    /// tangent.
    pub fn matrix(&self) -> MatrixGame<S> {
        MatrixGame {
            entries: self
                .pairs
                .map(|row| row.map(|p| p.map(|p| p.capture.value))),
        }
    }

    /// The pair the two players chose, if it has a valid tangent.
    pub fn chosen_pair(&self) -> Option<&PairOutcome<S>> {
        self.pair(self.solution.row, self.solution.col)
    }

    /// The pair of a pursuer circle and an evader circle, if it has a valid tangent.
    pub fn pair(&self, pursuer: Direction, evader: Direction) -> Option<&PairOutcome<S>> {
        self.pairs[pursuer as usize][evader as usize].as_ref()
    }

    /// Whether the game's prediction can be played: a finite upper value whose chosen pair
    /// captures after the evader reaches its tangent (not Algorithm 2's overshoot case, whose
    /// literal value is not a time the players can realise). A saddle is not required: without
    /// one the pursuer's min-max row still bounds the capture time. Below the theorem's
    /// threshold the flight policy replaces the pursuer's command where this is false.
    pub fn trusted(&self) -> bool {
        self.solution.upper.is_some() && self.chosen_pair().is_some_and(|p| !p.capture.overshoot)
    }

    /// Predicted capture time, seconds: the upper value, the pursuer's min-max guarantee
    /// (`None` = infinity).
    pub fn predicted_capture_time(&self) -> Option<S> {
        self.solution.upper
    }
}

/// Result of one evaluation: a status, what was computed, and the command to apply.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Evaluation<S> {
    /// The contract's status.
    pub status: Status,
    /// The game, for `Ok` and `NoValidTangent`.
    pub report: Option<GameReport<S>>,
    /// The command: the law's for `Ok`, the documented safe command otherwise.
    pub command: Command<S>,
    /// The units of every time, length and curvature above ([`Units::SI`] unless the backend
    /// is normalised).
    pub units: Units,
}

impl<S: Scalar> Evaluation<S> {
    /// The evaluation of a game written into `report` (valid where `status` has one); without a
    /// game, the safe command.
    pub fn from_game(
        status: Status,
        report: GameReport<S>,
        command: Command<S>,
        units: Units,
    ) -> Self {
        if status.has_game() {
            Evaluation {
                status,
                report: Some(report),
                command,
                units,
            }
        } else {
            Evaluation::safe(status)
        }
    }

    /// The safe command (straight ahead) with a status that says why.
    pub fn safe(status: Status) -> Self {
        Evaluation {
            status,
            report: None,
            command: Command::straight(),
            units: Units::SI,
        }
    }
}

/// What a controller acts on from one evaluation: the status, the game's solution and the
/// command, without the per-pair report ([`Evaluation`] keeps it; the firmware has no use for it,
/// and not copying its hundred-odd bytes is a tenth of an evaluation on a Cortex-M4F).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decision<S> {
    /// The contract's status.
    pub status: Status,
    /// The game's solution, for `Ok` and `NoValidTangent`.
    pub solution: Option<GameSolution<S>>,
    /// The command: the law's for `Ok`, the documented safe command otherwise.
    pub command: Command<S>,
    /// The units of the values and the command (see [`Evaluation::units`]).
    pub units: Units,
}

impl<S: Scalar> Decision<S> {
    /// The game's upper value, seconds: the time to capture the pursuer's strategy guarantees
    /// (`None` without a game or where it is infinite). Fixed point converts with integers.
    pub fn value_seconds(&self) -> Option<f32> {
        let upper = self.solution.and_then(|s| s.upper)?;
        Some(upper.to_f32_scaled(self.units.metres / self.units.metres_per_second))
    }

    /// The command as curvatures, 1/m: [pursuer, evader] (a turn rate is v_max w:
    /// [`Guidance::turn_rates`](crate::Guidance::turn_rates)).
    pub fn curvatures(&self) -> [f32; 2] {
        let per_law_unit = 1.0 / self.units.metres;
        [
            self.command.pursuer.to_f32_scaled(per_law_unit),
            self.command.evader.to_f32_scaled(per_law_unit),
        ]
    }

    /// The decision of an evaluation whose game (valid where `status` has one) was written into
    /// `report`; without a game, the safe command.
    pub fn from_game(
        status: Status,
        report: &GameReport<S>,
        command: Command<S>,
        units: Units,
    ) -> Self {
        if status.has_game() {
            Decision {
                status,
                solution: Some(report.solution),
                command,
                units,
            }
        } else {
            Evaluation::safe(status).into()
        }
    }
}

impl<S: Scalar> From<Evaluation<S>> for Decision<S> {
    #[inline]
    fn from(evaluation: Evaluation<S>) -> Self {
        Decision {
            status: evaluation.status,
            solution: evaluation.report.map(|r| r.solution),
            command: evaluation.command,
            units: evaluation.units,
        }
    }
}

/// Raw input of the law, as it arrives from a door (CSV, wire): m/s, 1/m, metres, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// v_pm, w_pm, v_em, w_em.
    pub limits: [f32; 4],
    /// x_p, y_p, theta_p.
    pub pursuer: [f32; 3],
    /// x_e, y_e, theta_e.
    pub evader: [f32; 3],
}

/// How the arcs to the tangent points are read and ties are broken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sampling<S> {
    /// Largest arc (radians, 2 pi less a tolerance) the pursuer still turns through: beyond it,
    /// a hair short of a full turn, it counts as on its tangent ([`Direction::arc_to`]).
    pub pursuer_largest_arc: S,
    /// The same for the evader.
    pub evader_largest_arc: S,
    /// A stateful caller's previous (pursuer, evader) circles, kept where options tie.
    pub previous: Option<(Direction, Direction)>,
    /// Absolute tie floor, seconds: for a sampled caller the capture-time equivalent of one
    /// period's travel, dt v_pm / (v_pm - v_em) (0 for the instantaneous law, whose ties are the
    /// relative band alone).
    pub tie_floor: S,
}

impl<S: Scalar> Sampling<S> {
    /// The instantaneous law: the backend's arc resolution, ties to A.
    pub fn instantaneous() -> Self {
        let largest = S::tau() - S::from_f32(S::ARC_RESOLUTION);
        Sampling {
            pursuer_largest_arc: largest,
            evader_largest_arc: largest,
            previous: None,
            tie_floor: S::zero(),
        }
    }
}

/// The law for one pair of validated limits and one Algorithm-2 variant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Law<S> {
    /// Both players' limits.
    pub limits: Limits<S>,
    /// Algorithm 2's reading.
    pub variant: Variant,
}

impl<S: Scalar> Law<S> {
    /// The law for validated limits.
    pub fn new(limits: Limits<S>, variant: Variant) -> Self {
        Law { limits, variant }
    }

    /// The instantaneous feedback law F(x): each player at +-w_max of its chosen circle.
    pub fn evaluate(&self, pursuer: &VehicleState<S>, evader: &VehicleState<S>) -> Evaluation<S> {
        self.evaluate_sampled(pursuer, evader, &Sampling::instantaneous())
    }

    /// One pair of circles: its valid tangent (Algorithm 1) and the time to capture along it
    /// (Algorithm 2), written to `outcome` (`None` without a valid tangent); returns the time, the
    /// matrix entry ([`Scalar::never`] without a valid tangent). Kept out of line: the law calls
    /// it four times, and four inlined copies cost more flash than the calls cost time. The
    /// outcome is written where the report keeps it, never moved.
    #[inline(never)]
    fn pair(
        &self,
        circles: &CirclePairs<S>,
        row: Direction,
        col: Direction,
        sampling: &Sampling<S>,
        outcome: &mut Option<PairOutcome<S>>,
    ) -> S {
        let Some(tangent) = circles.tangent(row, col) else {
            *outcome = None;
            return S::never();
        };
        let alpha_p = row.arc_to(
            circles.pursuer_heading,
            tangent.heading,
            sampling.pursuer_largest_arc,
        );
        let alpha_e = col.arc_to(
            circles.evader_heading,
            tangent.heading,
            sampling.evader_largest_arc,
        );
        let capture = capture_time(&self.limits, tangent.length, alpha_p, alpha_e, self.variant);
        *outcome = Some(PairOutcome { tangent, capture });
        capture.value
    }

    /// Evaluates the law with a caller's arc tolerances and previous choice; the command is the
    /// instantaneous one ([`Law::instantaneous_command`]).
    pub(crate) fn evaluate_sampled(
        &self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        sampling: &Sampling<S>,
    ) -> Evaluation<S> {
        self.evaluate_with(pursuer, evader, sampling, |_, report| {
            self.instantaneous_command(&report.solution, pursuer, evader)
        })
    }

    /// The instantaneous command of a game's solution: each player at +-w_max of its chosen
    /// circle, or, where no pursuer row has a finite value, the unsampled fallback (the pursuer
    /// turns toward the evader, the evader away from it). Computed where a caller asks for it:
    /// a sampled caller (the firmware) replaces it.
    pub fn instantaneous_command(
        &self,
        solution: &GameSolution<S>,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
    ) -> Command<S> {
        if solution.upper.is_none() {
            return fallback_command(pursuer, evader, &self.limits, None);
        }
        Command {
            pursuer: solution.row.signed(self.limits.pursuer.w_max()),
            evader: solution.col.signed(self.limits.evader.w_max()),
        }
    }

    /// Evaluates the law, and where there is a game (`Ok`, `NoValidTangent`) lets `command`
    /// choose the command from the status and the report (the instantaneous command is
    /// [`Law::instantaneous_command`]). A command outside the backend's range turns the
    /// evaluation into `OutOfRange` with the safe command.
    pub(crate) fn evaluate_with(
        &self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        sampling: &Sampling<S>,
        command: impl FnOnce(Status, &GameReport<S>) -> Command<S>,
    ) -> Evaluation<S> {
        let mut report = GameReport::empty();
        let (status, command) = self.decide_into(pursuer, evader, sampling, &mut report, command);
        Evaluation::from_game(status, report, command, self.limits.units)
    }

    /// [`Law::evaluate_with`] with the game written into the caller's `report` (valid where the
    /// status is `Ok` or `NoValidTangent`): the status and the command (the safe command for
    /// every other status). A caller that does not keep the report (the firmware) does not copy
    /// its hundred-odd bytes.
    pub(crate) fn decide_into(
        &self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        sampling: &Sampling<S>,
        report: &mut GameReport<S>,
        command: impl FnOnce(Status, &GameReport<S>) -> Command<S>,
    ) -> (Status, Command<S>) {
        match self.play(pursuer, evader, sampling, report) {
            Ok(status) => {
                let command = command(status, report);
                if command.pursuer.is_valid() && command.evader.is_valid() {
                    (status, command)
                } else {
                    (Status::OutOfRange, Command::straight())
                }
            }
            Err(status) => (status, Command::straight()),
        }
    }

    /// The game of one state, written into `report`: the four pairs and the solution. Returns
    /// the status (`Ok`, or `NoValidTangent` where no pursuer row has a finite value), or the
    /// status that ends the evaluation (`Captured`, or `OutOfRange` where a backend's arithmetic
    /// left its range).
    fn play(
        &self,
        pursuer: &VehicleState<S>,
        evader: &VehicleState<S>,
        sampling: &Sampling<S>,
        report: &mut GameReport<S>,
    ) -> Result<Status, Status> {
        let capture_radius = self
            .limits
            .pursuer_radius_times(S::from_f32(CAPTURE_RADIUS_FRACTION));
        // The squared distance (the circles' |Delta|^2 as well), and on a normalised backend
        // each offset too: on fixed point the radius rounds to zero, and so does the square of
        // an offset below 2^-7.5 r_p, so only coincident positions are a capture.
        let gap_squared = pursuer.position().distance_squared(evader.position());
        let (dx, dy) = (evader.x - pursuer.x, evader.y - pursuer.y);
        if gap_squared <= capture_radius * capture_radius
            && (!S::NORMALISED || (dx.abs() <= capture_radius && dy.abs() <= capture_radius))
        {
            return Err(Status::Captured);
        }
        let circles = CirclePairs::new(pursuer, evader, &self.limits);
        let (a, c) = (Direction::Anticlockwise, Direction::Clockwise);
        let [[aa, ac], [ca, cc]] = &mut report.pairs;
        let pair = |row, col, outcome| self.pair(&circles, row, col, sampling, outcome);
        let values = [
            [pair(a, a, aa), pair(a, c, ac)],
            [pair(c, a, ca), pair(c, c, cc)],
        ];
        // An invalid entry (fixed point: a checked division or function that left the range; the
        // envelope keeps its unchecked sums and products in range) ends the game, never guessed.
        // Written out: an iterator over the four is a loop on a Cortex-M0 (about 40 instructions).
        let [[v_aa, v_ac], [v_ca, v_cc]] = values;
        if !(v_aa.is_valid() && v_ac.is_valid() && v_ca.is_valid() && v_cc.is_valid()) {
            return Err(Status::OutOfRange);
        }
        let solution = solve_values(values, sampling.previous, sampling.tie_floor);
        report.solution = solution;
        if solution.upper.is_none() {
            return Ok(Status::NoValidTangent);
        }
        Ok(Status::Ok)
    }
}

/// Signed angle (radians, in [-pi, pi]) from a vehicle's heading to the direction of the point
/// (x, y), anticlockwise positive.
pub fn bearing<S: Scalar>(from: &VehicleState<S>, x: S, y: S) -> S {
    (S::atan2(y - from.y, x - from.x) - from.theta).wrap_signed()
}

/// The documented fallback where no pursuer row has a finite value: the pursuer turns toward the
/// evader's bearing, the evader toward the direction pointing away from the pursuer; with a
/// control `period` each turns at most what one period needs (see [`steer`]).
pub(crate) fn fallback_command<S: Scalar>(
    pursuer: &VehicleState<S>,
    evader: &VehicleState<S>,
    limits: &Limits<S>,
    period: Option<&Period<S>>,
) -> Command<S> {
    // One direction for both: from the pursuer toward the evader, which is also the evader's
    // direction away from the pursuer (one arctangent, not two).
    let toward_evader = bearing(pursuer, evader.x, evader.y);
    let away_from_pursuer = (toward_evader + pursuer.theta - evader.theta).wrap_signed();
    Command {
        pursuer: steer(toward_evader, &limits.pursuer, period.map(|p| p.pursuer)),
        evader: steer(away_from_pursuer, &limits.evader, period.map(|p| p.evader)),
    }
}

/// A control period as each vehicle's steering sees it: the curvature per radian of heading
/// still to go, 1 / (v_max dt) (1/m per radian; over one period a curvature w turns the vehicle
/// through v_max w dt radians). Precomputed: a division on a core without a divider is a
/// library call.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Period<S> {
    /// The pursuer's 1 / (v_pm dt).
    pub pursuer: S,
    /// The evader's 1 / (v_em dt).
    pub evader: S,
}

impl<S: Scalar> Period<S> {
    /// The period `dt` (in the law's time unit) for `limits`; `None` where a reciprocal leaves
    /// the backend's range.
    pub fn new(limits: &Limits<S>, dt: S) -> Option<Self> {
        let period = Period {
            pursuer: S::one() / (limits.pursuer.v_max() * dt),
            evader: S::one() / (limits.evader.v_max() * dt),
        };
        (period.pursuer.is_valid() && period.evader.is_valid()).then_some(period)
    }
}

/// Curvature (1/m) that turns a vehicle through the signed heading angle `to_go` (radians):
/// sigma w_max, or with a control period at most what one period needs,
/// sigma min(w_max, |to_go| / (v_max dt)), where `per_radian` is 1 / (v_max dt).
/// Zero when nothing is left to turn.
pub fn steer<S: Scalar>(to_go: S, limits: &VehicleLimits<S>, per_radian: Option<S>) -> S {
    let direction = if to_go > S::zero() {
        Direction::Anticlockwise
    } else {
        Direction::Clockwise
    };
    match per_radian {
        Some(per_radian) => steer_along(direction, to_go.abs(), limits, per_radian),
        None if to_go == S::zero() => S::zero(),
        None => direction.signed(limits.w_max()),
    }
}

/// Curvature (1/m) that turns a vehicle through `arc` radians (>= 0) in `direction` within one
/// control period: sigma min(w_max, arc / (v_max dt)), `per_radian` being 1 / (v_max dt)
/// ([`Period`]); +0 for a zero arc. The sampled command toward a chosen tangent, whose arc is
/// already a magnitude: no sign to take apart and put back.
pub(crate) fn steer_along<S: Scalar>(
    direction: Direction,
    arc: S,
    limits: &VehicleLimits<S>,
    per_radian: S,
) -> S {
    let magnitude = limits.w_max().min(per_radian.mul_small(arc));
    match direction {
        Direction::Anticlockwise => magnitude,
        // 0 - m, not -m: a zero arc gives +0 on either circle, as straight ahead is written.
        Direction::Clockwise => S::zero() - magnitude,
    }
}

/// The contract's door: validates a raw observation and evaluates the instantaneous law.
/// Checks in the contract's order: non-finite fields, limits, envelope, capture, tangents.
pub fn evaluate_observation<S: Scalar>(
    observation: &Observation,
    variant: Variant,
) -> Evaluation<S> {
    match validate::<S>(observation) {
        Ok(scene) => Law::new(scene.limits, variant).evaluate(&scene.pursuer, &scene.evader),
        Err(error) => Evaluation::safe(error.status()),
    }
}

/// A validated observation in the backend's numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scene<S> {
    /// Both players' limits.
    pub limits: Limits<S>,
    /// The pursuer's state.
    pub pursuer: VehicleState<S>,
    /// The evader's state.
    pub evader: VehicleState<S>,
}

/// Validates a raw observation into limits and both states.
///
/// # Errors
/// `NonFiniteInput` if any field is NaN or infinite, then `InvalidLimits`, then `OutOfRange`.
pub fn validate<S: Scalar>(observation: &Observation) -> Result<Scene<S>, Error> {
    let Observation {
        limits: [v_pm, w_pm, v_em, w_em],
        pursuer: [x_p, y_p, theta_p],
        evader: [x_e, y_e, theta_e],
    } = *observation;
    let finite = [x_p, y_p, theta_p, x_e, y_e, theta_e]
        .iter()
        .all(|v| v.is_finite());
    if !finite {
        return Err(Error::NonFiniteInput);
    }
    let limits = Limits::new(v_pm, w_pm, v_em, w_em)?;
    let (pursuer, evader) = limits.states([x_p, y_p, theta_p], [x_e, y_e, theta_e])?;
    Ok(Scene {
        limits,
        pursuer,
        evader,
    })
}
