//! The players that play the Hamilton-Jacobi-Isaacs value tables ([`crate`]) on the host:
//! inside the theorem's threshold, in a table's box and outside its capture disc, the pursuer
//! takes the turn that makes V least against the evader's best reply one solver step ahead;
//! elsewhere the flight policy, the paper's law beyond the threshold (`Policy::Table`). This is
//! the f64 reference of the player the core's `value_tables` module plays in f32 on the unit.
//!
//! The tables are nested: a list, finest first, each solved with the next one's values where
//! its steps leave its box (`cargo xtask hj`'s near field). A state is read from the finest
//! table whose box holds it (less two cells).

use crate::{Solution, Step, REACHED};

/// The evader in the table's frame (r_p, radians): position relative to the pursuer, x along
/// its heading, y to its left, and the relative heading; for limits whose pursuer curvature is
/// `w_pm` (1/m) and states in metres and radians.
pub fn relative(w_pm: f64, pursuer: [f64; 3], evader: [f64; 3]) -> (f64, f64, f64) {
    let (dx, dy) = (
        (evader[0] - pursuer[0]) * w_pm,
        (evader[1] - pursuer[1]) * w_pm,
    );
    let (s, c) = pursuer[2].sin_cos();
    (dx * c + dy * s, -dx * s + dy * c, evader[2] - pursuer[2])
}

/// The finest of `tables` (finest first) that plays at `(x, y)` (r_p): inside the theorem's
/// threshold and outside the capture disc, in its box less two cells, captured from there.
/// `None` where none does.
pub fn finest(tables: &[Solution], (x, y, phi): (f64, f64, f64)) -> Option<&Solution> {
    let table = holding(tables, x, y)?;
    let r = x.hypot(y);
    let plays =
        r > table.game.eps && r < table.game.threshold() && table.value(x, y, phi) < REACHED;
    plays.then_some(table)
}

/// The finest of `tables` (finest first) whose box holds `(x, y)` (r_p) less two cells.
pub fn holding(tables: &[Solution], x: f64, y: f64) -> Option<&Solution> {
    tables.iter().find(|table| {
        let margin = table.grid.half - 2.0 * table.grid.spacing();
        x.abs() < margin && y.abs() < margin
    })
}

/// V at `(x, y, phi)` (r_p / v_pm) from the finest of `tables` that plays there ([`finest`]),
/// read as the solver reads where a step lands ([`Solution::landing`]: within two cells of the
/// capture disc, one step of three tau).
pub fn value(tables: &[Solution], at: (f64, f64, f64)) -> Option<f64> {
    finest(tables, at).map(|table| table.landing(at))
}

/// V at `(x, y, phi)` from the finest of `tables` whose box holds it, to its edge: where a
/// step from a state lands ([`crate::NEVER`] outside every box), interpolated as the
/// firmware reads it ([`Solution::interpolated_landing`]: at most 0 in the capture disc). The
/// solver reads a landing within two cells of the disc by one more step of the scheme
/// ([`Solution::landing`]); the players reading it so (with a step of tau) played
/// the same rows of `--play`.
fn landing(tables: &[Solution], (x, y, phi): (f64, f64, f64)) -> f64 {
    let Some(table) = tables
        .iter()
        .find(|table| x.abs() <= table.grid.half && y.abs() <= table.grid.half)
    else {
        return crate::NEVER;
    };
    table.interpolated_landing((x, y, phi))
}

/// The pursuer's curvature (1/m) from `tables` solved for limits whose pursuer curvature is
/// `w_pm` (1/m), for pursuer and evader states in metres and radians: [`turn`] in the finest
/// table that plays there ([`finest`]); `None` where none does.
pub fn pursuer_curvature(
    tables: &[Solution],
    w_pm: f64,
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    let at = relative(w_pm, pursuer, evader);
    turn(tables, at).map(|(u, _)| u * w_pm)
}

/// The evader's curvature (1/m) from `tables` solved for limits whose pursuer and evader
/// curvatures are `w_pm` and `w_em` (1/m): [`evader_turn`]. `None` where
/// [`pursuer_curvature`] has none.
pub fn evader_curvature(
    tables: &[Solution],
    [w_pm, w_em]: [f64; 2],
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    evader_turn(tables, relative(w_pm, pursuer, evader)).map(|(w, _)| w * w_em)
}

/// The evader's turn (-1, 0 or 1) at full speed at `(x, y, phi)` in the tables' frame, from
/// the finest of `tables` that plays there: its turn whose best case for the pursuer (the
/// least V over the pursuer's three turns, one step ahead, each landing read from the finest
/// table whose box holds it) is largest, straight keeping ties; with the margin (r_p / v_pm)
/// by which it beats the next. `None` where no table plays.
pub fn evader_turn(tables: &[Solution], (x, y, phi): (f64, f64, f64)) -> Option<(f64, f64)> {
    let table = finest(tables, (x, y, phi))?;
    let (s, c) = phi.sin_cos();
    let game = table.game;
    let best_for_pursuer = |w: f64| {
        [-1.0, 0.0, 1.0]
            .into_iter()
            .map(|u| {
                let step = Step::new(game.speed_ratio, table.tau, u, w);
                landing(tables, step.from((x, y, phi, s, c)))
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut bests = [0.0, 1.0, -1.0].map(|sign| (sign, best_for_pursuer(sign * game.evader_turn)));
    // Stable: straight, then left, keep ties; the largest first.
    bests.sort_by(|a, b| b.1.total_cmp(&a.1));
    let [(w, most), (_, next), _] = bests;
    Some((w, most - next))
}

/// The pursuer's turn (-1, 0 or 1) at `(x, y, phi)` in the tables' frame, from the finest of
/// `tables` that plays there ([`finest`]): the turn (full either way, or straight) whose worst
/// case over the evader's controls ([`crate::Game::evader_controls`]), one step of that
/// table's `tau` ahead on the exact motion, has the least V (each landing read from the finest
/// table whose box holds it): the solver's own minimax, read back. Straight keeps ties. With
/// the margin (r_p / v_pm) by which that worst case beats the next turn's; `None` where no
/// table plays, or every turn's worst case is beyond the capture the tables found.
pub fn turn(tables: &[Solution], (x, y, phi): (f64, f64, f64)) -> Option<(f64, f64)> {
    let table = finest(tables, (x, y, phi))?;
    let (s, c) = phi.sin_cos();
    let game = table.game;
    let worst = |u: f64| {
        game.evader_controls()
            .into_iter()
            .map(|(speed, w)| {
                let step = Step::new(speed, table.tau, u, w);
                landing(tables, step.from((x, y, phi, s, c)))
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mut worsts = [0.0, 1.0, -1.0].map(|u| (u, worst(u)));
    // Stable: straight, then left, keep ties.
    worsts.sort_by(|a, b| a.1.total_cmp(&b.1));
    let [(u, least), (_, next), _] = worsts;
    (least < REACHED).then_some((u, next - least))
}
