//! The 2x2 matrix game over turn directions (the paper's Table 1): the pursuer plays the min-max
//! row, the evader the max-min column.
//!
//! An entry is `None` where its pair has no valid tangent: an infinite time to capture.

use crate::geometry::Direction;
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
    /// The pursuer's circle: the row reaching the upper value.
    pub row: Direction,
    /// The evader's circle: the column reaching the lower value.
    pub col: Direction,
    /// min over rows of max over columns, seconds; `None` = infinity.
    pub upper: Option<S>,
    /// max over columns of min over rows, seconds; `None` = infinity.
    pub lower: Option<S>,
    /// upper == lower within the tie band: a pure saddle point.
    pub saddle: bool,
}

impl<S> GameSolution<S> {
    /// The solution of a game without a valid tangent (every entry infinite): both circles A,
    /// both values infinite, a saddle at infinity ([`MatrixGame::solve`] gives the same). The
    /// place a solution is written into.
    pub const NO_TANGENT: Self = GameSolution {
        row: Direction::Anticlockwise,
        col: Direction::Anticlockwise,
        upper: None,
        lower: None,
        saddle: true,
    };
}

/// Whether two values (seconds) tie within the backend's relative band `S::TIE_BAND`.
pub fn ties<S: Scalar>(a: S, b: S) -> bool {
    ties_within(a, b, S::zero())
}

/// Whether two values (seconds) tie within the relative band `S::TIE_BAND` or within an absolute
/// `floor` (seconds): a sampled caller passes its control period, the shortest difference in
/// capture time it can act on.
pub fn ties_within<S: Scalar>(a: S, b: S, floor: S) -> bool {
    let band = (S::from_f32(S::TIE_BAND) * a.abs().max(b.abs())).max(floor);
    (a - b).abs() <= band
}

/// Picks between the two options of one player. `prefer_smaller` for the pursuer's min, else the
/// evader's max; `None` is infinity. Tied options go to `previous` if given, else to A.
fn pick<S: Scalar>(
    options: [Option<S>; 2],
    prefer_smaller: bool,
    previous: Option<Direction>,
    floor: S,
) -> (Direction, Option<S>) {
    let [a, c] = options;
    let a_wins = match (a, c) {
        (None, None) => None,
        (Some(_), None) => Some(prefer_smaller),
        (None, Some(_)) => Some(!prefer_smaller),
        (Some(x), Some(y)) if ties_within(x, y, floor) => None,
        (Some(x), Some(y)) => Some((x < y) == prefer_smaller),
    };
    let choice = match a_wins {
        Some(true) => Direction::Anticlockwise,
        Some(false) => Direction::Clockwise,
        None => previous.unwrap_or(Direction::Anticlockwise),
    };
    let value = match choice {
        Direction::Anticlockwise => a,
        Direction::Clockwise => c,
    };
    (choice, value)
}

fn max_opt<S: Scalar>(a: Option<S>, b: Option<S>) -> Option<S> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        _ => None,
    }
}

fn min_opt<S: Scalar>(a: Option<S>, b: Option<S>) -> Option<S> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (Some(x), None) | (None, Some(x)) => Some(x),
        (None, None) => None,
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
        match (self.solve().saddle, aa, ac, ca, cc) {
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
        let [[aa, ac], [ca, cc]] = self.entries;
        let row_worst = [max_opt(aa, ac), max_opt(ca, cc)];
        let col_best = [min_opt(aa, ca), min_opt(ac, cc)];
        let (row, upper) = pick(row_worst, true, previous.map(|p| p.0), floor);
        let (col, lower) = pick(col_best, false, previous.map(|p| p.1), floor);
        let saddle = match (upper, lower) {
            (Some(u), Some(l)) => ties(u, l),
            (None, None) => true,
            _ => false,
        };
        GameSolution {
            row,
            col,
            upper,
            lower,
            saddle,
        }
    }
}
