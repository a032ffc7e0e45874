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
/// curvature is `w_pm` (1/m), for pursuer and evader states in metres and radians: the turn
/// (full either way, or straight) whose worst case over the evader's turns, one solver step
/// `tau` ahead on the exact motion, has the least V: the solver's own minimax, read back.
/// `None` where the table gives no preference it can trust: outside its box (less two cells),
/// within three capture radii of the capture disc (the terminal law's job), or where capture
/// was not found.
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
    let (s, c) = phi.sin_cos();
    let game = table.game;
    let worst = |u: f64| {
        [-game.evader_turn, 0.0, game.evader_turn]
            .into_iter()
            .map(|w| {
                let step = Step::new(game.speed_ratio, table.tau, u, w);
                let (nx, ny, nphi) = step.from((x, y, phi, s, c));
                table.value(nx, ny, nphi)
            })
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // Straight first: it keeps ties.
    let (u, _) = [0.0, 1.0, -1.0].into_iter().map(|u| (u, worst(u))).fold(
        (0.0, f64::INFINITY),
        |best, (u, v)| if v < best.1 { (u, v) } else { best },
    );
    Some(u * w_pm)
}
