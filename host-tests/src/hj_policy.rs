//! The pursuer that plays the Hamilton-Jacobi-Isaacs value table ([`crate::hj`]) on the host:
//! in the table's box, away from its capture disc, the turn that makes V fall fastest against
//! the evader's best reply; elsewhere the flight policy (issue 30's policy, as a host
//! experiment; the firmware does not play a table yet).
//!
//! Along the game, V's rate is grad V . f(s, u, w). The pursuer's turn rate u enters f as
//! u (y, -x, -1), so the minimising u is a full turn against the sign of
//! V_x y - V_y x - V_phi (straight where that is flat), whatever the evader does.

use crate::hj::{Solution, REACHED};

/// Below this |V_x y - V_y x - V_phi| the pursuer runs straight (no preference).
const FLAT: f64 = 1e-3;

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
/// curvature is `w_pm` (1/m), for pursuer and evader states in metres and radians; `None` where
/// the table gives no preference it can trust: outside its box (less two cells), within three
/// capture radii of the capture disc (the terminal law's job), or where capture was not found.
pub fn pursuer_curvature(
    table: &Solution,
    w_pm: f64,
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    let (x, y, phi) = relative(w_pm, pursuer, evader);
    let grid = table.grid;
    let h = grid.spacing();
    let margin = grid.half - 2.0 * h;
    if x.abs() >= margin || y.abs() >= margin || x.hypot(y) <= 3.0 * table.game.eps {
        return None;
    }
    if table.value(x, y, phi) >= REACHED {
        return None;
    }
    let dphi = std::f64::consts::TAU / grid.headings as f64;
    let v_x = (table.value(x + h, y, phi) - table.value(x - h, y, phi)) / (2.0 * h);
    let v_y = (table.value(x, y + h, phi) - table.value(x, y - h, phi)) / (2.0 * h);
    let v_phi = (table.value(x, y, phi + dphi) - table.value(x, y, phi - dphi)) / (2.0 * dphi);
    let slope = v_x * y - v_y * x - v_phi;
    let u = if slope.abs() < FLAT {
        0.0
    } else {
        -slope.signum()
    };
    Some(u * w_pm)
}
