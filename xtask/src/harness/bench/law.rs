//! The law's rows of `cargo xtask bench`: instructions per evaluation, stack and flash per CPU
//! and backend, and the same outputs computed on the host.

use twocars::{Guidance, Law, Limits, Scalar, Variant};
use twocars_bench::{DT, LIMITS, STATES};

use std::fmt::Write as _;

use twocars::num::fixed::Fixed;
use twocars::num::micro::Micro;

use crate::harness::bench::image::{build_and_run, Cpu, M0, M4F};
use crate::util::progress::Progress;

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

/// Measures the law's image `bin` (`law`, `law_fixed`, ...) against its empty twin.
pub(crate) fn measure(cpu: Cpu, numeric: &'static str, bin: &str) -> Result<Row, String> {
    let law = build_and_run(cpu, bin)?;
    // The baseline: the same image (numeric backend, set-up, returned type) with the law
    // removed, so that neither the call overhead nor the backend's set-up code (limits, states
    // and guidance built before the timed region) is counted as the law's.
    let empty = build_and_run(cpu, &bin.replacen("law", "empty", 1))?;
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

/// The law's section of the report: per CPU and backend, instructions per evaluation, stack and
/// flash (each image against its empty twin), then the backends' accuracy on the host.
pub(crate) fn section() -> Result<String, String> {
    let images = [
        (M4F, "f32 (own polynomials + VSQRT)", "law"),
        (M4F, "micromath (f32)", "law_micromath"),
        (M0, "fixed point (Q17.14)", "law_fixed"),
        (M0, "f32 soft-float (own polynomials)", "law"),
        (M4F, "f32, `step` with the per-pair report", "law_report"),
    ];
    // Each row builds and runs two images (the law and its empty baseline).
    let progress = Progress::new(images.len() as u64, "bench images (law and baseline each)");
    let rows = images.map(|(cpu, numeric, bin)| {
        progress.step(&format!("{} {numeric}", cpu.name()));
        let row = measure(cpu, numeric, bin);
        progress.inc();
        row
    });
    progress.finish();
    let mut md = String::new();
    let _ = writeln!(
        md,
        "Law: one `Guidance::decide`, the firmware's path (both roles: 2 x 2 circles, 4 valid \
         tangents, 4 capture times, the matrix game, both sampled commands; the status, the game's \
         solution and the commands returned), and on the last row one `Guidance::step`, which also \
         returns the per-pair report the host tools print, at the paper's limits (v_pm = 2, w_pm = 2, v_em = 1, \
         w_em = 1), dt = 10 ms, over the {} states of `bench/src/lib.rs` (the paper's four cases, a tail \
         chase, no valid tangent, the overshoot entry, near and far states).\n",
        STATES.len()
    );
    let _ = writeln!(
        md,
        "Method: QEMU 7 with `-icount shift=6` (64 ns per instruction) and SysTick on the processor \
         clock: 25 MHz on mps2-an386 (1.6 ticks per instruction), 16 MHz on micro:bit (1.024); one \
         evaluation timed at a time; the call overhead (the same image with the law removed, \
         `empty`, `empty_fixed`, ...) subtracted. Resolution: one tick (0.6 instruction on M4F, 1 on M0). Stack: \
         4 KiB painted below the caller, high-water mark after the call, minus the empty image's. \
         Law flash: image minus the empty image (each row's own: the same numeric backend and \
         set-up, the law removed).\n"
    );
    let _ = writeln!(md, "| CPU | numeric | instructions per evaluation: mean (min - max) | law stack | law flash | bench image flash |");
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    let mut errors = Vec::new();
    for row in &rows {
        match row {
            Ok(r) => {
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.0} ({:.0} - {:.0}) | {} B | {} B | {} B |",
                    r.cpu, r.numeric, r.mean, r.min, r.max, r.stack, r.law_flash, r.image_flash
                );
            }
            Err(e) => errors.push(e.as_str()),
        }
    }
    let _ = writeln!(md);
    let _ = writeln!(
        md,
        "Accuracy on the bench states: largest relative error of the predicted capture time vs the \
         f64 path: f32 (own polynomials + VSQRT) {:.1e}, micromath {:.1e}, fixed point {:.1e}.",
        value_error::<f32>(),
        value_error::<Micro>(),
        value_error::<Fixed>()
    );
    if errors.is_empty() {
        Ok(md)
    } else {
        Err(errors.join("\n"))
    }
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
            let mut guidance =
                Guidance::new(Law::new(limits, Variant::Paper), DT, twocars::Policy::Paper).ok()?;
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
