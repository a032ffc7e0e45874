//! The game of two cars' value function V (the time to capture under optimal play by both
//! sides) by semi-Lagrangian value iteration on a grid: the discrete form of the
//! Hamilton-Jacobi-Isaacs equation, a monotone and consistent scheme.
//!
//! The reduced game, in the pursuer's frame: `(x, y)` is the evader's position relative to the
//! pursuer (x along the pursuer's heading, y to its left) and `phi` the evader's heading relative
//! to the pursuer's. Lengths are in units of the pursuer's turning radius r_p and times in
//! r_p / v_pm, so the pursuer runs at 1 and turns at most at 1 rad per unit time; one table
//! serves every vehicle pair with the same v_em / v_pm and r_e / r_p. With the pursuer's turn
//! rate u in [-1, 1] and the evader's w in [-w_e, w_e] (w_e = (v_em / v_pm) (r_p / r_e)):
//!
//! ```text
//! x' = a cos(phi) - 1 + u y,    y' = a sin(phi) - u x,    phi' = w - u,    a = v_em / v_pm
//! ```
//!
//! Capture is the disc x^2 + y^2 <= eps^2. One sweep sets, at every node outside it, V = max(0, min
//! over u max over w of (tau + V(s_tau(s, u, w)))), s_tau the exact step ([`Step`]), V read
//! between nodes by a filtered tricubic ([`Read`], periodic in phi) or, within two cells of the
//! capture disc, by one step of three tau ([`Scheme::near`], [`Scheme::read`]), starting from
//! V = [`NEVER`]: after k sweeps V is below it where capture within about k tau is guaranteed.
//! A path that is in the disc at a look within a step or at its end was captured at the time it
//! entered, found on its exact arc, whatever part of the edge it crossed. Nodes in the disc
//! behind the usable part of its edge (where the pursuer can force the distance down,
//! [`usable`]) keep minus their depth ([`disc_value`]), so that V's zero lies on the edge; on
//! grids that read by the cubic (two cells or more across the disc's radius, [`reads_cubic`];
//! coarser grids read trilinearly) they sweep with V continued from outside instead. Behind the
//! rest of the edge, where V jumps (an evader there slips past), each sweep sets them to V two
//! cells outside on their ray, so that the jump is not smeared toward zero, on grids that
//! resolve the disc (about five cells or more, [`resolves_disc`]). All are for reading outside
//! the disc. The pursuer tries [`TURNS`] turn rates evenly spaced over [-1, 1] ([`Sweeps`];
//! the tables' players try -1, 0 and 1); the evader
//! turns fully either way or runs straight at full speed, or stands still
//! ([`Game::evader_controls`]). Leaving the box counts as never captured unless a boundary value
//! is given ([`solve_with_boundary`]).

mod grid;
pub mod paper;
pub mod policy;
mod read;

pub use grid::{Grid, NEVER, REACHED};
pub use read::{Read, FILTER};

use rayon::prelude::*;

/// The game in the reduced units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Game {
    /// v_em / v_pm, in (0, 1).
    pub speed_ratio: f64,
    /// The evader's largest turn rate, rad per unit time: (v_em / v_pm) (r_p / r_e).
    pub evader_turn: f64,
    /// The capture radius, in r_p.
    pub eps: f64,
}

impl Game {
    /// The evader's extreme controls, (speed in units of v_pm, turn rate): full speed turning
    /// either way or straight, and standing still. A command is a curvature and a speed up to
    /// v_em (docs/contract.md), so the evader's reachable (speed, rate) pairs form a triangle
    /// whose corners are the two full turns and the stop.
    pub fn evader_controls(&self) -> [(f64, f64); 4] {
        let (a, w) = (self.speed_ratio, self.evader_turn);
        [(a, -w), (a, 0.0), (a, w), (0.0, 0.0)]
    }

    /// Whether `(x, y)` (r_p) is in the capture disc. A point on its edge is inside whatever the
    /// rounding of its coordinates (-6 + 33 x 0.2 is 0.6000000000000005): without the margin,
    /// grids of equal spacing disagreed on a node there.
    #[inline]
    pub fn captures(&self, x: f64, y: f64) -> bool {
        x * x + y * y <= self.eps * self.eps * (1.0 + 1e-9)
    }

    /// The paper's theorem's threshold 2 r_e + 2 pi r_e v_pm / v_em, r_p: beyond it the
    /// paper's law is optimal, and the value is the paper's upper value where it has a saddle.
    pub fn threshold(&self) -> f64 {
        let r_e = self.speed_ratio / self.evader_turn;
        twocars::law::geometry::theorem_threshold(r_e, 1.0, self.speed_ratio)
    }

    /// The game of the limits v_pm, w_pm, v_em, w_em (m/s, 1/m) with capture radius `eps` in
    /// units of r_p.
    pub fn with_radius(limits: [f64; 4], eps: f64) -> Self {
        Game {
            eps,
            ..Self::of_limits(limits, 0.0)
        }
    }

    /// The game of the limits v_pm, w_pm, v_em, w_em (m/s, 1/m) with capture radius `eps` m.
    pub fn of_limits([v_pm, w_pm, v_em, w_em]: [f64; 4], eps: f64) -> Self {
        let speed_ratio = v_em / v_pm;
        Game {
            speed_ratio,
            evader_turn: speed_ratio * w_em / w_pm,
            eps: eps * w_pm,
        }
    }
}

/// The value table and how the iteration ended.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The game solved.
    pub game: Game,
    /// Its grid.
    pub grid: Grid,
    /// V at every node, in r_p / v_pm ([`NEVER`]: not captured from there within the box).
    pub values: Vec<f64>,
    /// The time step of one sweep, r_p / v_pm.
    pub tau: f64,
    /// Sweeps run.
    pub sweeps: usize,
    /// The last sweep's largest change over nodes reached before and after it.
    pub residual: f64,
    /// Nodes reached for the first time in the last sweep.
    pub newly_finite: usize,
}

impl Solution {
    /// V at `(x, y, phi)` (r_p, radians), trilinear and periodic in phi; [`NEVER`] outside the
    /// box.
    pub fn value(&self, x: f64, y: f64, phi: f64) -> f64 {
        interpolate(&self.grid, &self.values, x, y, phi)
    }

    /// V where a step of the scheme lands at `(x, y, phi)`, as the solver reads it
    /// ([`Scheme::read`] of [`Scheme::near`]: at most 0 in the disc, one step of three tau
    /// near it); [`NEVER`] outside the box.
    pub fn landing(&self, at: (f64, f64, f64)) -> f64 {
        if near_disc(&self.game, &self.grid, at.0, at.1) {
            Scheme::near(self.game, self.grid, self.tau).read(&self.values, at, NEVER)
        } else {
            self.interpolated_landing(at)
        }
    }

    /// V interpolated where a step lands at `(x, y, phi)`, at most 0 in the capture disc (the
    /// path was captured within the step); [`NEVER`] outside the box: the players' read.
    pub fn interpolated_landing(&self, at: (f64, f64, f64)) -> f64 {
        interpolated_landing(&self.game, &self.grid, &self.values, Read::Trilinear, at)
    }
}

impl Solution {
    /// The longest time the table keeps, r_p / v_pm: twice that of a pursuer that turns fully
    /// around and then closes the box's diagonal at v_pm - v_em. Larger values are the edge of
    /// the never-captured set smeared by the interpolation (on the 41 x 41 x 24 grid of the
    /// paper's game the median finite value is 8.5, the 99th percentile 4,136).
    pub fn longest_kept(&self) -> f64 {
        let diagonal = 2.0 * std::f64::consts::SQRT_2 * self.grid.half;
        2.0 * (std::f64::consts::TAU + diagonal) / (1.0 - self.game.speed_ratio)
    }

    /// The table as the firmware reads it (`twocars::value_tables::table`): the header, then the V of each
    /// node with y >= 0 quantised to u16, [`Solution::longest_kept`] at code 65534 (time per code
    /// `scale`), [`twocars::value_tables::table::NEVER`] where capture was not found or takes longer.
    pub fn table_bytes(&self) -> Vec<u8> {
        assert!(
            self.grid.n % 2 == 1,
            "the firmware's tables have an odd number of nodes"
        );
        use twocars::value_tables::table::{MAGIC, NEVER as NEVER_CODE};
        let cap = self.longest_kept().min(REACHED);
        let scale = cap / f64::from(NEVER_CODE - 1);
        let mut bytes = MAGIC.to_vec();
        for v in [
            self.game.speed_ratio,
            self.game.evader_turn,
            self.game.eps,
            self.grid.half,
            scale,
        ] {
            bytes.extend((v as f32).to_le_bytes());
        }
        bytes.extend((self.grid.n as u16).to_le_bytes());
        bytes.extend((self.grid.headings as u16).to_le_bytes());
        // The rows y >= 0 only: the others are their mirrors (V(x, y, phi) = V(x, -y, -phi)).
        let (n, centre) = (self.grid.n, self.grid.n / 2);
        let rows = (0..self.grid.headings).flat_map(|k| (centre..n).map(move |j| (j, k)));
        let kept = rows.flat_map(|(j, k)| (0..n).map(move |i| self.grid.index(i, j, k)));
        for v in kept.map(|index| self.values[index]) {
            let code = if v <= cap {
                // Nodes in the disc behind its usable edge (V = r - eps < 0): code 0, read
                // as r - eps; behind the rest, their V two cells outside.
                (v.max(0.0) / f64::from(scale as f32))
                    .round()
                    .min(f64::from(NEVER_CODE - 1)) as u16
            } else {
                NEVER_CODE
            };
            bytes.extend(code.to_le_bytes());
        }
        bytes
    }
}

/// Nested tables as the firmware reads them (`twocars::value_tables`): each table's
/// [`Solution::table_bytes`] back to back, `tables` finest first.
pub fn table_set_bytes(tables: &[Solution]) -> Vec<u8> {
    tables.iter().flat_map(Solution::table_bytes).collect()
}

fn interpolate(grid: &Grid, values: &[f64], x: f64, y: f64, phi: f64) -> f64 {
    read::read(grid, values, Read::Trilinear, (x, y, phi)).unwrap_or(NEVER)
}

/// Solves `game` on `grid` with time step `tau` until no value changes by more than `tolerance`
/// and none becomes finite, or `max_sweeps`, reading between nodes by the default [`Read`],
/// the pursuer turning fully either way or running straight as the tables' players do
/// ([`policy`]); `progress(sweep, residual)` after each sweep. Leaving the box counts as never
/// captured.
pub fn solve(
    game: Game,
    grid: Grid,
    tau: f64,
    tolerance: f64,
    max_sweeps: usize,
    progress: impl FnMut(usize, f64),
) -> Solution {
    let sweeps = Sweeps {
        tau,
        tolerance,
        max_sweeps,
        read: Read::default(),
        turns: 3,
    };
    solve_with_boundary(game, grid, sweeps, |_, _, _| NEVER, progress)
}

/// How the solver sweeps: its time step, when it stops, and how it reads V between nodes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweeps {
    /// The time step, r_p / v_pm ([`Grid::step_time`]).
    pub tau: f64,
    /// The sweeps stop once no value changes by more than this (r_p / v_pm) and none becomes
    /// finite ...
    pub tolerance: f64,
    /// ... or after this many.
    pub max_sweeps: usize,
    /// How a landing between nodes is read.
    pub read: Read,
    /// How many turn rates the pursuer tries, evenly spaced over [-1, 1] (odd, at least 3:
    /// straight is one of them).
    pub turns: usize,
}

impl Sweeps {
    /// `grid`'s time step, to `tolerance` within 20,000 sweeps, read by the default
    /// ([`Read::Filtered`]), the pursuer trying [`TURNS`] turn rates.
    pub fn on(grid: &Grid, tolerance: f64) -> Self {
        Sweeps {
            tau: grid.step_time(),
            tolerance,
            max_sweeps: 20_000,
            read: Read::default(),
            turns: TURNS,
        }
    }
}

/// How many turn rates the pursuer tries by default: full either way, half either way and
/// straight. With controls held over a step, a pursuer that follows a curve wider than its
/// turning circle alternates full turns and straight runs, and loses time at every step: with
/// three rates, V where it is 10 to 20 r_p / v_pm read 0.038 above hj_reachability's at
/// 81 x 81 x 42 and 0.035 at 121 x 121 x 62 (median, the unfiltered cubic read); with five,
/// 0.021 and 0.015.
pub const TURNS: usize = 5;

/// One step of the reduced game: the pursuer turning at `u` and the evader (speed `a`) at `w`,
/// both held for `tau`. Both cars move on their exact arcs and the frame turns with the
/// pursuer. (An Euler step `x + tau (a c - 1 + u y)` grows the radius by a factor
/// sqrt(1 + (u tau)^2) per turning step: 0.9 r_p per step at 30 r_p with tau = 0.25, which made
/// every turn far out look costly and V 20 % high at the threshold.)
#[derive(Clone, Copy, Debug)]
pub struct Step {
    /// The pursuer's displacement in its starting frame.
    pursuer: (f64, f64),
    /// Sine and cosine of its turn u tau.
    turn: (f64, f64),
    /// The evader's displacement in its own starting frame.
    evader: (f64, f64),
    /// The relative heading's change (w - u) tau.
    heading: f64,
    /// Its time, r_p / v_pm.
    tau: f64,
}

impl Step {
    /// The step for speed ratio `a`, time `tau` and turn rates `u`, `w` (rad per unit time).
    pub fn new(a: f64, tau: f64, u: f64, w: f64) -> Self {
        // A car's displacement over tau at unit speed, heading 0, turning at `rate`:
        // (sin(rt) / r, (1 - cos(rt)) / r), and its small-rate limit.
        let arc = |rate: f64| -> (f64, f64) {
            let turn = rate * tau;
            if turn.abs() < 1e-6 {
                (tau, 0.5 * turn * tau)
            } else {
                (turn.sin() / rate, (1.0 - turn.cos()) / rate)
            }
        };
        let (ex, ey) = arc(w);
        Step {
            pursuer: arc(u),
            turn: (u * tau).sin_cos(),
            evader: (a * ex, a * ey),
            heading: tau * (w - u),
            tau,
        }
    }

    /// Where the evader at `(x, y, phi)` in the pursuer's frame (heading sine `s`, cosine `c`)
    /// is after the step.
    #[inline]
    pub fn from(&self, (x, y, phi, s, c): (f64, f64, f64, f64, f64)) -> (f64, f64, f64) {
        let ((px, py), (ts, tc), (ex, ey)) = (self.pursuer, self.turn, self.evader);
        // The evader's displacement turned into the starting frame by its heading phi.
        let (dx, dy) = (x + ex * c - ey * s - px, y + ex * s + ey * c - py);
        // Into the pursuer's frame after its turn.
        (dx * tc + dy * ts, -dx * ts + dy * tc, phi + self.heading)
    }
}

/// Whether the disc's edge in the direction of `(x, y)` is usable with relative heading `phi`:
/// there the distance falls whatever the evader does. Its rate is
/// (a (x cos phi + y sin phi) - x) / r at full speed and -x / r standing still, the turns aside
/// (they turn the frame), so
/// the edge is usable where x > 0 and a (x cos phi + y sin phi) < x, by a margin of 1e-9 r_p
/// per unit time: a node where the rate is zero to rounding (as at (0.2, 0.4, pi / 2) with
/// a = 1/2) reads the same as its mirror image. The disc's centre counts as usable.
pub fn usable(game: &Game, x: f64, y: f64, phi: f64) -> bool {
    let (s, c) = phi.sin_cos();
    (x == 0.0 && y == 0.0) || (x > 0.0 && game.speed_ratio * (x * c + y * s) - x < -1e-9)
}

/// The value a solution keeps at a node inside the capture disc behind the usable part of its
/// edge ([`usable`]): minus its depth, r - eps (r_p, a time at unit closing speed). Interpolated
/// with the nodes outside, it puts V's zero on the disc's edge instead of smearing the edge
/// over a cell; the firmware's tables read it so ([`twocars::value_tables::table`]).
pub fn disc_value(game: &Game, x: f64, y: f64) -> f64 {
    x.hypot(y) - game.eps
}

/// The value the solver sweeps with at a node inside the capture disc behind the usable part
/// of its edge: minus its depth over the speed at which the distance falls there (the evader
/// running straight at full speed or standing still, whichever closes slower), at least
/// 1 - a, the tail chase's. It continues V from outside the disc along the ray, so that a
/// cubic read across the edge keeps V's slope: with minus the depth alone (slope 1 inside,
/// 1 / (1 - a) = 2 outside in the paper's game) the tail chase read 0.015 r_p / v_pm low on a
/// 0.15 r_p grid. A solution keeps [`disc_value`] there; grids that read trilinearly
/// ([`reads_cubic`]) sweep with it too.
fn disc_slope_value(game: &Game, (x, y, phi): (f64, f64, f64)) -> f64 {
    let r = x.hypot(y);
    if r == 0.0 {
        return disc_value(game, x, y);
    }
    let (s, c) = phi.sin_cos();
    let a = game.speed_ratio;
    let closing = (x - a * (x * c + y * s).max(0.0)) / r;
    disc_value(game, x, y) / closing.max(1.0 - a)
}

/// One step of the scheme: the steps under each pair of controls held for `tau`, and the looks
/// within a step longer than half a cell's time.
pub struct Scheme {
    game: Game,
    grid: Grid,
    tau: f64,
    /// The pursuer's turn rates (rad per unit time).
    turns: Vec<f64>,
    /// The steps under each pursuer turn and evader control.
    steps: Vec<[Step; 4]>,
    /// The looks within a step: the same steps cut short at `m / looks` of `tau`, m = 1 ..
    sub_steps: Vec<Vec<[Step; 4]>>,
    looks: usize,
    /// How landings between nodes are read.
    read: Read,
}

impl Scheme {
    /// The scheme of `game` on `grid` with time step `tau` (r_p / v_pm), the pursuer turning
    /// fully either way or running straight, as the tables' players do.
    pub fn new(game: Game, grid: Grid, tau: f64) -> Self {
        Scheme::turning(game, grid, tau, 3)
    }

    /// [`Scheme::new`] with the pursuer trying `turns` turn rates evenly spaced over [-1, 1].
    pub fn turning(game: Game, grid: Grid, tau: f64, turns: usize) -> Self {
        // Odd and at least three, so that full turns and straight are among them.
        let n = turns.max(3) | 1;
        let turns: Vec<f64> = (0..n)
            .map(|i| 2.0 * i as f64 / (n - 1) as f64 - 1.0)
            .collect();
        let steps_for = |t: f64| -> Vec<[Step; 4]> {
            turns
                .iter()
                .map(|&u| {
                    game.evader_controls()
                        .map(|(speed, w)| Step::new(speed, t, u, w))
                })
                .collect()
        };
        // A step longer than half a cell's time is looked at every half a cell's time (or
        // less): a path that enters the disc between them is captured there, not carried past.
        let looks = ((tau / (0.5 * grid.spacing())) - 1e-9).ceil().max(1.0) as usize;
        let (steps, sub_steps) = (
            steps_for(tau),
            (1..looks)
                .map(|m| steps_for(tau * m as f64 / looks as f64))
                .collect(),
        );
        Scheme {
            game,
            grid,
            tau,
            turns,
            steps,
            sub_steps,
            looks,
            read: Read::Trilinear,
        }
    }

    /// The scheme reading landings between nodes by `read`.
    pub fn reading(self, read: Read) -> Self {
        Scheme { read, ..self }
    }

    /// The scheme that reads landings near the disc ([`Scheme::read`]) for a solver stepping
    /// `tau`: one step of [`NEAR_STEPS`] times `tau`, with its looks. A pass that skims the
    /// edge slowly can still be within two cells of the disc after one step of tau, where V
    /// jumps within a cell (a traced run passed at 1.018 r_p, and one step of
    /// tau from 1.056 r_p landed still in that band). On seeds 130,000 to 139,000, every run
    /// past 10 % of `cargo xtask hj --play` ends 1 to 8 points earlier than with one step of
    /// tau, and no other worst run rises by more than 0.1 point.
    pub fn near(game: Game, grid: Grid, tau: f64) -> Self {
        Scheme::new(game, grid, NEAR_STEPS * tau)
    }

    /// [`Scheme::near`] with `turns` pursuer turn rates ([`Scheme::turning`]).
    fn near_turning(game: Game, grid: Grid, tau: f64, turns: usize) -> Self {
        Scheme::turning(game, grid, NEAR_STEPS * tau, turns)
    }

    /// The scheme's value at `at` (a state and its heading's sine and cosine): the least over
    /// the pursuer's turns of the most over the evader's controls of the time the path enters
    /// the disc, where it is in the disc at a look within the step or at its end, or tau plus
    /// `land(turn, control, where the step ends)`.
    pub fn minimax(
        &self,
        at: (f64, f64, f64, f64, f64),
        land: impl Fn(usize, usize, (f64, f64, f64)) -> f64,
    ) -> f64 {
        let (game, tau, looks) = (self.game, self.tau, self.looks);
        self.steps
            .iter()
            .enumerate()
            .map(|(p, row)| {
                row.iter()
                    .enumerate()
                    .map(|(e, step)| {
                        let mut outside = 0.0;
                        for (m, sub) in self.sub_steps.iter().enumerate() {
                            let (sx, sy, _) = sub[p][e].from(at);
                            if game.captures(sx, sy) {
                                return self.entry(at, (p, e), outside, sub[p][e].tau);
                            }
                            outside = tau * (m + 1) as f64 / looks as f64;
                        }
                        let next = step.from(at);
                        if game.captures(next.0, next.1) {
                            return self.entry(at, (p, e), outside, tau);
                        }
                        (tau + land(p, e, next)).min(NEVER)
                    })
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .fold(f64::INFINITY, f64::min)
            .max(0.0)
    }

    /// The time the path from `at` under the pursuer's turn `p` and the evader's control `e`
    /// enters the disc, between `outside` (out of it) and `inside` (in it), r_p / v_pm: by
    /// halving on the exact arcs to a millionth of the interval. Counting the look at which the
    /// path is first in the disc instead puts V's zero up to a look outside the disc's edge,
    /// an error that does not shrink with the spacing where the step does not (near the disc
    /// the scheme reads by a step of three tau): the tail chase at 1 r_p read 0.016 high on a
    /// 0.1 r_p grid and 0.005 high on a 0.15 r_p one.
    fn entry(
        &self,
        at: (f64, f64, f64, f64, f64),
        (p, e): (usize, usize),
        outside: f64,
        inside: f64,
    ) -> f64 {
        let u = self.turns[p];
        let (speed, w) = self.game.evader_controls()[e];
        let (mut outside, mut inside) = (outside, inside);
        for _ in 0..20 {
            let mid = 0.5 * (outside + inside);
            let (x, y, _) = Step::new(speed, mid, u, w).from(at);
            if self.game.captures(x, y) {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        inside
    }

    /// V where a step lands, from the node values `values`: in the capture disc at most 0 (it was
    /// captured within the step); within two cells of the disc ([`near_disc`]) one step of this
    /// scheme (the solver reads with [`Scheme::near`]), its landings interpolated; elsewhere in the
    /// box interpolated trilinearly; `outside` beyond the box. Near the disc V jumps within a cell:
    /// by the centres of the pursuer's turning circles an evader that passes a hundredth of r_p
    /// outside the edge escapes for a loop, and its neighbour node a thousandth outside is
    /// captured; interpolating the two read the pass as half captured.
    pub fn read(&self, values: &[f64], (x, y, phi): (f64, f64, f64), outside: f64) -> f64 {
        let (game, grid) = (&self.game, &self.grid);
        let plain = |(x, y, phi): (f64, f64, f64)| {
            if x.abs() <= grid.half && y.abs() <= grid.half {
                interpolated_landing(game, grid, values, self.read, (x, y, phi))
            } else {
                outside
            }
        };
        if near_disc(game, grid, x, y) {
            let (s, c) = phi.sin_cos();
            self.minimax((x, y, phi, s, c), |_, _, next| plain(next))
        } else {
            plain((x, y, phi))
        }
    }
}

/// V interpolated from the node `values` where a step lands at `(x, y, phi)`, at most 0 in the
/// capture disc: a path that ends the step there was captured within it, whatever part of the
/// disc's edge it crossed (behind the part where the evader slips past, the disc's nodes keep
/// V from outside, for interpolating there). [`NEVER`] outside the box.
fn interpolated_landing(
    game: &Game,
    grid: &Grid,
    values: &[f64],
    how: Read,
    (x, y, phi): (f64, f64, f64),
) -> f64 {
    let v = read::read(grid, values, how, (x, y, phi)).unwrap_or(NEVER);
    if game.captures(x, y) {
        v.min(0.0)
    } else {
        v
    }
}

/// How many steps of the solver's tau one step of [`Scheme::near`] takes.
pub const NEAR_STEPS: f64 = 3.0;

/// Whether `grid` resolves the capture disc of `game`: its radius more than 4.5 cells. Only
/// there does the solver keep V's jump behind the disc's non-usable edge and read landings
/// near the disc by one more step of the scheme: on a 0.3 r_p grid with eps = 0.3 r_p the
/// tail chase's V at 1 r_p doubled, the disc's few nodes feeding each other's values.
pub fn resolves_disc(game: &Game, grid: &Grid) -> bool {
    game.eps > 4.5 * grid.spacing()
}

/// Whether the solver may read `grid` by the cubic ([`Read::Cubic`]): where the capture disc's
/// radius is two cells or more. The cubic read needs V smooth over its stencil; on coarser
/// grids V bends within a cell of the disc (the tail chase on a 0.3 r_p grid with eps 0.3 r_p
/// read 0.6 r_p / v_pm low at 2 r_p), and they read trilinearly.
pub fn reads_cubic(game: &Game, grid: &Grid) -> bool {
    game.eps >= 2.0 * grid.spacing() * (1.0 - 1e-9)
}

/// Whether a landing at `(x, y)` (r_p) is read by one more step of the scheme
/// ([`Scheme::near`], [`Scheme::read`]): outside the disc and within two cells of its edge,
/// on grids that resolve it ([`resolves_disc`]).
pub fn near_disc(game: &Game, grid: &Grid, x: f64, y: f64) -> bool {
    resolves_disc(game, grid)
        && !game.captures(x, y)
        && x.hypot(y) < game.eps + 2.0 * grid.spacing()
}

/// [`solve`] with `boundary(x, y, phi)` the value of a state outside the box (r_p / v_pm;
/// [`NEVER`] for never captured): for example the paper's upper value beyond the theorem's
/// threshold. It is called once per node and control pair whose step leaves the box.
pub fn solve_with_boundary(
    game: Game,
    grid: Grid,
    sweeps: Sweeps,
    boundary: impl Fn(f64, f64, f64) -> f64 + Sync,
    mut progress: impl FnMut(usize, f64),
) -> Solution {
    let captured = |i: usize, j: usize| game.captures(grid.position(i), grid.position(j));
    let mut values: Vec<f64> = (0..grid.len())
        .map(|index| {
            let i = index % grid.n;
            let j = index / grid.n % grid.n;
            if captured(i, j) {
                let k = index / (grid.n * grid.n);
                let at = (grid.position(i), grid.position(j), grid.heading(k));
                if reads_cubic(&game, &grid) && usable(&game, at.0, at.1, at.2) {
                    disc_slope_value(&game, at)
                } else {
                    disc_value(&game, at.0, at.1)
                }
            } else {
                NEVER
            }
        })
        .collect();
    // A node's state and its heading's sine and cosine.
    let node = |index: usize| {
        let (i, j, k) = (
            index % grid.n,
            index / grid.n % grid.n,
            index / (grid.n * grid.n),
        );
        let (x, y, phi) = (grid.position(i), grid.position(j), grid.heading(k));
        let (s, c) = phi.sin_cos();
        (x, y, phi, s, c)
    };
    let Sweeps {
        tau,
        tolerance,
        max_sweeps,
        read,
        turns,
    } = sweeps;
    let cubic = reads_cubic(&game, &grid);
    let read = if cubic { read } else { Read::Trilinear };
    let scheme = Scheme::turning(game, grid, tau, turns).reading(read);
    let near = Scheme::near_turning(game, grid, tau, turns).reading(read);
    let steps = &scheme.steps;
    let inside = |x: f64, y: f64| x.abs() <= grid.half && y.abs() <= grid.half;
    // The jump behind the disc's non-usable edge is kept only where the grid resolves the disc.
    let resolved = resolves_disc(&game, &grid);
    // The boundary's values, fixed: the steps that leave the box do not depend on V.
    let exits: std::collections::HashMap<(usize, usize, usize), f64> = (0..grid.len())
        .into_par_iter()
        .flat_map_iter(|index| {
            let at = node(index);
            let mut out = Vec::new();
            for (p, row) in steps.iter().enumerate() {
                for (e, step) in row.iter().enumerate() {
                    let (nx, ny, nphi) = step.from(at);
                    if !inside(nx, ny) {
                        out.push(((index, p, e), boundary(nx, ny, nphi).min(NEVER)));
                    }
                }
            }
            out
        })
        .collect();
    let mut solution = Solution {
        game,
        grid,
        values: Vec::new(),
        tau,
        sweeps: 0,
        residual: f64::INFINITY,
        newly_finite: 0,
    };
    for sweep in 1..=max_sweeps {
        let old = &values;
        let next: Vec<f64> = (0..grid.len())
            .into_par_iter()
            .map(|index| {
                let i = index % grid.n;
                let j = index / grid.n % grid.n;
                if captured(i, j) {
                    let (x, y, phi, ..) = node(index);
                    if !resolved || usable(&game, x, y, phi) {
                        return old[index];
                    }
                    // Behind a non-usable edge: V two cells outside on the node's ray, where
                    // no corner of its cell is in the disc.
                    let out = (game.eps + 2.0 * grid.spacing()) / x.hypot(y);
                    return interpolate(&grid, old, x * out, y * out, phi).min(NEVER);
                }
                let at = node(index);
                scheme.minimax(at, |p, e, next| {
                    let (nx, ny, _) = next;
                    if inside(nx, ny) {
                        near.read(old, next, NEVER)
                    } else {
                        exits.get(&(index, p, e)).copied().unwrap_or(NEVER)
                    }
                })
            })
            .collect();
        let (residual, newly_finite) = old
            .par_iter()
            .zip(next.par_iter())
            .map(|(&o, &n)| match (o < REACHED, n < REACHED) {
                (true, true) => ((o - n).abs(), 0),
                (false, true) => (0.0, 1),
                _ => (0.0, 0),
            })
            .reduce(|| (0.0, 0), |p, q| (p.0.max(q.0), p.1 + q.1));
        values = next;
        solution.sweeps = sweep;
        solution.residual = residual;
        solution.newly_finite = newly_finite;
        progress(sweep, residual);
        if residual <= tolerance && newly_finite == 0 {
            break;
        }
    }
    // The disc's nodes behind its usable edge as the tables keep them.
    for (index, v) in values.iter_mut().enumerate() {
        let (x, y, phi, ..) = node(index);
        if game.captures(x, y) && (!resolved || usable(&game, x, y, phi)) {
            *v = disc_value(&game, x, y);
        }
    }
    solution.values = values;
    solution
}
