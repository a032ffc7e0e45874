//! The 2x2 matrix game over turn directions (the paper's Table 1): the pursuer plays the min-max
//! row, the evader the max-min column.
//!
//! An entry is `None` where its pair has no valid tangent: an infinite time to capture.

use crate::law::geometry::Direction;
use crate::num::Scalar;

/// Times to capture, seconds, indexed `[pursuer circle][evader circle]` in the order (A, C):
/// `t_aa`, `t_ac`, `t_ca`, `t_cc`. `None` is infinity (no valid tangent).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MatrixGame<S> {
    /// The entries of Table 1.
    pub entries: [[Option<S>; 2]; 2],
}

/// Solution of the matrix game at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GameSolution<S> {
    /// The pursuer's circle: the row reaching the upper value (within the tie band, where rows
    /// tie).
    pub row: Direction,
    /// The evader's circle: the column reaching the lower value (within the tie band).
    pub col: Direction,
    /// min over rows of max over columns, seconds; `None` = infinity.
    pub upper: Option<S>,
    /// max over columns of min over rows, seconds; `None` = infinity.
    pub lower: Option<S>,
}

impl<S: Scalar> GameSolution<S> {
    /// Whether upper == lower within the tie band: a pure saddle point (two infinite values
    /// tie; an infinite and a finite one do not). Computed where it is asked for: the firmware
    /// never reads it.
    pub fn saddle(&self) -> bool {
        self.saddle_within(S::zero())
    }

    /// Whether upper == lower within the tie band or within `floor` seconds (two infinite
    /// values tie; an infinite and a finite one do not).
    pub fn saddle_within(&self, floor: S) -> bool {
        match (self.upper, self.lower) {
            (Some(upper), Some(lower)) => ties_within(upper, lower, floor),
            (None, None) => true,
            _ => false,
        }
    }
}

/// Whether two values (seconds) tie within the backend's relative band `S::TIE_BAND`.
pub fn ties<S: Scalar>(a: S, b: S) -> bool {
    ties_within(a, b, S::zero())
}

/// Whether two values (seconds) tie within the relative band `S::TIE_BAND` or within an absolute
/// `floor` (seconds): a sampled caller passes its control period, the shortest difference in
/// capture time it can act on.
pub fn ties_within<S: Scalar>(a: S, b: S, floor: S) -> bool {
    let band = a.abs().max(b.abs()).tie_band().max(floor);
    (a - b).abs() <= band
}

/// Picks between the two options of one player, values in seconds with [`Scalar::never`] for
/// infinity. `prefer_smaller` for the pursuer's min, else the evader's max. Tied options go to
/// `previous` if given, else to A. (Two infinities tie; an infinity and a time do not: the
/// difference is far beyond the band.) The value is the min (max) itself, whichever option the
/// tie gave: the choice may reach it only within the band.
// Inlined into the solver's two calls: on a Cortex-M0 the compiler kept it out of line, and the
// calls cost more than the second copy's 40 B (M0 2,507 -> 2,469 instructions per evaluation).
#[inline(always)]
fn pick<S: Scalar>(
    options: [S; 2],
    prefer_smaller: bool,
    previous: Option<Direction>,
    floor: S,
) -> (Direction, S) {
    let [a, c] = options;
    // A is the min (the max) itself, or equal to C.
    let a_extreme = (a < c) == prefer_smaller;
    let choice = if ties_within(a, c, floor) {
        previous.unwrap_or(Direction::Anticlockwise)
    } else if a_extreme {
        Direction::Anticlockwise
    } else {
        Direction::Clockwise
    };
    (choice, if a_extreme { a } else { c })
}

/// A value of the game in seconds, `None` for [`Scalar::never`] (infinity).
fn finite<S: Scalar>(value: S) -> Option<S> {
    (value != S::never()).then_some(value)
}

/// Solves the game of four times to capture `[pursuer circle][evader circle]` (seconds,
/// [`Scalar::never`] where a pair has no valid tangent): the min-max row, the max-min column,
/// options within the tie band or within `floor` seconds going to `previous` (A if none). The one
/// solver: [`MatrixGame::solve_sampled`] and the law both call it. An infinity is a number here,
/// so that the max and min of the rows and columns are plain compares.
pub(crate) fn solve_values<S: Scalar>(
    values: [[S; 2]; 2],
    previous: Option<(Direction, Direction)>,
    floor: S,
) -> GameSolution<S> {
    let [[aa, ac], [ca, cc]] = values;
    let row_worst = [aa.max(ac), ca.max(cc)];
    let col_best = [aa.min(ca), ac.min(cc)];
    let (row, upper) = pick(row_worst, true, previous.map(|p| p.0), floor);
    let (col, lower) = pick(col_best, false, previous.map(|p| p.1), floor);
    GameSolution {
        row,
        col,
        upper: finite(upper),
        lower: finite(lower),
    }
}

impl<S: Scalar> MatrixGame<S> {
    /// The entry for a pursuer circle and an evader circle, seconds (`None` = infinity).
    pub fn entry(&self, pursuer: Direction, evader: Direction) -> Option<S> {
        self.entries[pursuer as usize][evader as usize]
    }

    /// Value of the mixed extension, (ad - bc) / (a + d - b - c), in the law's time unit, where
    /// the game has no pure saddle and all four entries are finite; `None` otherwise. A report:
    /// formed in f64, as the products of two capture times can leave a fixed-point range.
    pub fn mixed_value(&self) -> Option<f64> {
        let [[aa, ac], [ca, cc]] = self.entries;
        match (self.solve().saddle(), aa, ac, ca, cc) {
            (false, Some(a), Some(b), Some(c), Some(d)) => {
                let [a, b, c, d] = [a, b, c, d].map(S::to_f64);
                let denominator = a + d - b - c;
                (denominator != 0.0).then(|| (a * d - b * c) / denominator)
            }
            _ => None,
        }
    }

    /// Solves the game. Options within the tie band count as equal and go to A.
    pub fn solve(&self) -> GameSolution<S> {
        self.solve_sampled(None, S::zero())
    }

    /// Solves the game for a stateful caller: options within the tie band, or within `floor`
    /// seconds of each other, count as equal and go to the `previous` choice (A if none), so that
    /// a tail chase stays on its line.
    pub fn solve_sampled(
        &self,
        previous: Option<(Direction, Direction)>,
        floor: S,
    ) -> GameSolution<S> {
        let values = self
            .entries
            .map(|row| row.map(|v| v.unwrap_or_else(S::never)));
        solve_values(values, previous, floor)
    }
}
