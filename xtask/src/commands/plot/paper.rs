//! The paper's law as the figures read it: states, observations and the law's report at the
//! paper's limits.

use twocars::law::Observation;
use twocars::{Variant, VehicleState};
use twocars_sim::scenarios::PAPER_LIMITS;

pub(crate) fn state(s: [f64; 3]) -> VehicleState<f64> {
    VehicleState {
        x: s[0],
        y: s[1],
        theta: s[2],
    }
}

pub(crate) fn observation(limits: [f64; 4], p: [f64; 3], e: [f64; 3]) -> Observation {
    Observation {
        limits: limits.map(|v| v as f32),
        pursuer: p.map(|v| v as f32),
        evader: e.map(|v| v as f32),
    }
}

/// The paper law's report (its matrix game's solution) for `pursuer` and `evader` at the
/// paper's limits; `None` where it has none.
pub(crate) fn paper_report(
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Option<twocars::GameReport<f64>> {
    twocars::law::evaluate_observation::<f64>(
        &observation(PAPER_LIMITS, pursuer, evader),
        Variant::Paper,
    )
    .report
}
