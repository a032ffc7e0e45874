//! Seeded random starts, as the Monte Carlo reports and the adversary tests draw them.

use std::f64::consts::PI;

use crate::rng::Rng;
use crate::sim::SimParams;

/// Where the limits of a run come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitSet {
    /// Seeded random limits (Assumption 1: v_pm > v_em, w_pm > w_em).
    Random,
    /// The paper's 2, 2, 1, 1.
    Paper,
}

impl LimitSet {
    /// The reports' name of the set.
    pub fn name(self) -> &'static str {
        match self {
            LimitSet::Random => "random",
            LimitSet::Paper => "paper",
        }
    }
}

/// Random limits under Assumption 1 (m/s, 1/m), drawn in this order: v_em in [0.5, 3], v_pm
/// 1.1 to 3 times it, w_em in [0.2, 2], w_pm 1.1 to 4 times it.
pub fn random_limits(rng: &mut Rng) -> [f64; 4] {
    let v_em = rng.uniform(0.5, 3.0);
    let v_pm = v_em * rng.uniform(1.1, 3.0);
    let w_em = rng.uniform(0.2, 2.0);
    let w_pm = w_em * rng.uniform(1.1, 4.0);
    [v_pm, w_pm, v_em, w_em]
}

/// A start at `limits`: the pursuer at the origin, the evader `d0` (m) away; drawn in this
/// order: the evader's bearing, the pursuer's heading, the evader's heading (rad). The run
/// lasts no time until the caller sets `t_max`.
pub fn random_start(rng: &mut Rng, limits: [f64; 4], d0: f64, dt: f64, eps: f64) -> SimParams {
    let bearing = rng.uniform(-PI, PI);
    SimParams {
        limits,
        pursuer: [0.0, 0.0, rng.uniform(-PI, PI)],
        evader: [d0 * bearing.cos(), d0 * bearing.sin(), rng.uniform(-PI, PI)],
        dt,
        t_max: 0.0,
        eps,
    }
}
