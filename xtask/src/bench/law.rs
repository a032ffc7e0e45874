//! The law's rows of `cargo xtask bench`: instructions per evaluation, stack and flash per CPU
//! and backend, and the same outputs computed on the host.

use twocars::bench::{DT, LIMITS, STATES};
use twocars::{Guidance, Law, Limits, Scalar, Variant};

use crate::bench::image::{build_and_run, Cpu};

/// Instructions per evaluation (mean, min, max), the law's stack and flash on one CPU.
pub(crate) struct Row {
    pub(crate) cpu: &'static str,
    pub(crate) numeric: &'static str,
    pub(crate) mean: f64,
    pub(crate) min: f64,
    pub(crate) max: f64,
    pub(crate) stack: u64,
    pub(crate) law_flash: u64,
    pub(crate) image_flash: u64,
}

pub(crate) fn measure(cpu: Cpu, numeric: &'static str, features: &str) -> Result<Row, String> {
    let law = build_and_run(cpu, features)?;
    // The baseline: the same image (numeric backend, set-up, returned type) with the law
    // removed, so that neither the call overhead nor the backend's set-up code (limits, states
    // and guidance built before the timed region) is counted as the law's.
    let empty = build_and_run(cpu, &format!("{features},bench-empty"))?;
    let overhead = empty.ticks.iter().sum::<f64>() / empty.ticks.len() as f64;
    let instructions: Vec<f64> = law
        .ticks
        .iter()
        .map(|t| (t - overhead) / cpu.ticks_per_instruction)
        .collect();
    let mean = instructions.iter().sum::<f64>() / instructions.len() as f64;
    let min = instructions.iter().copied().fold(f64::INFINITY, f64::min);
    let max = instructions.iter().copied().fold(0.0, f64::max);
    let base_stack = empty.stack.iter().copied().max().unwrap_or(0);
    let stack = law
        .stack
        .iter()
        .copied()
        .max()
        .unwrap_or(0)
        .saturating_sub(base_stack);
    Ok(Row {
        cpu: cpu.name,
        numeric,
        mean,
        min,
        max,
        stack,
        law_flash: law.flash.saturating_sub(empty.flash),
        image_flash: law.flash,
    })
}

/// Upper value (s) and commands w_p, w_e (1/m) of one `Guidance::step` on backend `S` per bench
/// state, on the host: what the bench image computes on the target.
pub fn host_outputs<S: Scalar>() -> Vec<Option<[f64; 3]>> {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    STATES
        .iter()
        .map(|&(p, e)| {
            let limits = Limits::<S>::new(v_pm, w_pm, v_em, w_em).ok()?;
            let (p, e) = limits.states(p, e).ok()?;
            let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), DT).ok()?;
            let ev = guidance.step(&p, &e);
            let units = ev.units;
            let upper = ev.report.and_then(|r| r.solution.upper);
            Some([
                upper.map_or(f64::INFINITY, |v| units.seconds(v)),
                units.curvature(ev.command.pursuer),
                units.curvature(ev.command.evader),
            ])
        })
        .collect()
}

/// Largest relative error of the predicted value (upper) on the bench states vs the f64 law.
pub(crate) fn value_error<S: Scalar>() -> f64 {
    host_outputs::<f64>()
        .iter()
        .zip(host_outputs::<S>())
        .filter_map(|(a, b)| Some((a.as_ref()?[0], b?[0])))
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (a - b).abs() / a.abs().max(1.0))
        .fold(0.0, f64::max)
}
