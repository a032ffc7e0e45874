//! The pursuer that plays the Hamilton-Jacobi-Isaacs value table ([`crate::hj`]) on the host:
//! in the table's box, away from its capture disc, the turn that makes V least against the
//! evader's best reply one solver step ahead; elsewhere the flight policy (issue 30's policy,
//! as a host experiment; the firmware does not play a table yet).

use crate::hj::{Solution, Step, REACHED};

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

/// The pursuer's curvature (1/m) from the table `table` solved for limits whose pursuer
/// curvature is `w_pm` (1/m), for pursuer and evader states in metres and radians: [`turn`].
/// `None` where the table gives no preference it can trust: outside its box (less two cells),
/// in the capture disc, or where capture was not found.
pub fn pursuer_curvature(
    table: &Solution,
    w_pm: f64,
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    let (x, y, phi) = relative(w_pm, pursuer, evader);
    let grid = table.grid;
    let margin = grid.half - 2.0 * grid.spacing();
    if x.abs() >= margin || y.abs() >= margin || x.hypot(y) <= table.game.eps {
        return None;
    }
    if table.value(x, y, phi) >= REACHED {
        return None;
    }
    turn(table, x, y, phi).map(|(u, _)| u * w_pm)
}

/// The evader's curvature (1/m) from the table `table` solved for limits whose pursuer and
/// evader curvatures are `w_pm` and `w_em` (1/m): the evader's turn whose best case for the
/// pursuer (the least V over its three turns, one solver step ahead) is largest, straight
/// keeping ties. `None` where [`pursuer_curvature`] has none.
pub fn evader_curvature(
    table: &Solution,
    [w_pm, w_em]: [f64; 2],
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    pursuer_curvature(table, w_pm, pursuer, evader)?;
    let (x, y, phi) = relative(w_pm, pursuer, evader);
    let (s, c) = phi.sin_cos();
    let game = table.game;
    let best_for_pursuer = |w: f64| {
        [-1.0, 0.0, 1.0]
            .into_iter()
            .map(|u| {
                let step = Step::new(game.speed_ratio, table.tau, u, w);
                table.value_at(step.from((x, y, phi, s, c)))
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut bests = [0.0, 1.0, -1.0].map(|sign| (sign, best_for_pursuer(sign * game.evader_turn)));
    // Stable: straight, then left, keep ties; the largest first.
    bests.sort_by(|a, b| b.1.total_cmp(&a.1));
    Some(bests[0].0 * w_em)
}

/// The pursuer's turn (-1, 0 or 1) at `(x, y, phi)` in the table's frame: the turn (full either
/// way, or straight) whose worst case over the evader's turns, one solver step `tau` ahead on
/// the exact motion, has the least V: the solver's own minimax, read back. Straight keeps
/// ties. With the margin (r_p / v_pm) by which that worst case beats the next turn's; `None`
/// if every turn's worst case is beyond the capture the table found.
pub fn turn(table: &Solution, x: f64, y: f64, phi: f64) -> Option<(f64, f64)> {
    let (s, c) = phi.sin_cos();
    let game = table.game;
    let worst = |u: f64| {
        [-game.evader_turn, 0.0, game.evader_turn]
            .into_iter()
            .map(|w| {
                let step = Step::new(game.speed_ratio, table.tau, u, w);
                table.value_at(step.from((x, y, phi, s, c)))
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mut worsts = [0.0, 1.0, -1.0].map(|u| (u, worst(u)));
    // Stable: straight, then left, keep ties.
    worsts.sort_by(|a, b| a.1.total_cmp(&b.1));
    let [(u, least), (_, next), _] = worsts;
    (least < REACHED).then_some((u, next - least))
}
