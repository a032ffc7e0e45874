//! What the plays and the probe are judged by: V(x0) read from the reference tables at their
//! capture radius, at the control period both run.

use hji::policy::{relative, value};
use hji::Solution;

/// Control period, s.
pub(crate) const DT: f64 = 0.01;

/// The tables' V(x0) (s) at `limits`, from the finest that plays there.
pub(crate) fn table_value(
    tables: &[Solution],
    limits: [f64; 4],
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<f64> {
    let [v_pm, w_pm, ..] = limits;
    value(tables, relative(w_pm, pursuer, evader)).map(|v| v / (w_pm * v_pm))
}

/// The table's capture radius at `limits`, m: the runs capture at the radius V was solved for.
pub(crate) fn capture_radius(tables: &[Solution], limits: [f64; 4]) -> f64 {
    tables[0].game.eps / limits[1]
}
