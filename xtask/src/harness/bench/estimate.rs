//! The estimator's rows of `cargo xtask bench`: `twocars::estimate` taking a target fix and
//! giving a decision's states, on the Cortex-M4F (f32 with an FPU) and the Cortex-M0 (fixed
//! point, and the same f32 in software), checked against the same sequence on the host.

use twocars::estimate::{Estimator, FieldSettings, Fix, FixNoise};
use twocars::{Fixed, Scalar};
use twocars_bench::{estimate_fix, ESTIMATE_FIXES, ESTIMATE_INTERVAL_US, ESTIMATE_NOISE, LIMITS};

use crate::harness::bench::image::{build_and_print, Cpu, M0, M4F};

/// What the estimator costs on one CPU.
#[derive(Clone, Copy, Debug)]
pub struct EstimateMeasured {
    /// Instructions per target fix taken, mean and max.
    pub fix: (f64, f64),
    /// Instructions per decision's states, mean and max.
    pub states: (f64, f64),
    /// Stack of a fix and a decision, bytes.
    pub stack: u64,
    /// Flash of the image, bytes.
    pub flash: u64,
}

/// The host's states for each fix over `S`: target x, y and the uncertainty in its units.
fn host<S: Scalar>() -> Vec<[f32; 3]> {
    let [position, heading] = ESTIMATE_NOISE;
    let settings = FieldSettings {
        target_noise: FixNoise { position, heading },
        ..FieldSettings::exact(1.0)
    };
    let Ok(mut estimator) = Estimator::<S>::with_backend(LIMITS, settings) else {
        return Vec::new();
    };
    (0..ESTIMATE_FIXES)
        .filter_map(|i| {
            let time_us = i * ESTIMATE_INTERVAL_US;
            let _ = estimator.own_fix(&Fix {
                state: [0.0, 0.0, 0.0],
                time_us,
            });
            let _ = estimator.target_fix(&Fix {
                state: estimate_fix(i),
                time_us,
            });
            let s = estimator.states(time_us + 100_000).ok()?;
            Some([s.target[0], s.target[1], s.uncertainty].map(S::to_f32))
        })
        .collect()
}

/// Runs the estimator bench `image` over `S` on `cpu`; an error where a result is more than
/// 1e-5 (relative) from the host's (the M4F's square root is the FPU's, the host's a software
/// one; fixed point is the same integers on both).
pub fn measure<S: Scalar>(cpu: Cpu, image: &str) -> Result<EstimateMeasured, String> {
    let want = host::<S>();
    let (out, flash) = build_and_print(cpu, image)?;
    let (mut fix, mut states, mut stack) = (Vec::new(), Vec::new(), 0);
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let ["estimate", i, f, s, e, st, values @ ..] = fields.as_slice() else {
            continue;
        };
        let bad = || format!("bad line {line}");
        let i: usize = i.parse().map_err(|_| bad())?;
        let expected = want.get(i).ok_or_else(bad)?;
        for (v, w) in values.iter().zip(expected) {
            let got = f32::from_bits(u32::from_str_radix(v, 16).map_err(|_| bad())?);
            if (got - w).abs() > 1e-5 * w.abs().max(1.0) {
                return Err(format!(
                    "estimate {i} on {}: {got} against the host's {w}",
                    cpu.name()
                ));
            }
        }
        let empty: f64 = e.parse().map_err(|_| bad())?;
        fix.push((f.parse::<f64>().map_err(|_| bad())? - empty) / cpu.ticks_per_instruction);
        states.push((s.parse::<f64>().map_err(|_| bad())? - empty) / cpu.ticks_per_instruction);
        stack = stack.max(st.parse().map_err(|_| bad())?);
    }
    if fix.len() != want.len() || fix.is_empty() {
        return Err(format!(
            "the estimate bench reported {} of {} fixes:\n{out}",
            fix.len(),
            want.len()
        ));
    }
    let mean_max = |v: &[f64]| {
        (
            v.iter().sum::<f64>() / v.len() as f64,
            v.iter().copied().fold(0.0, f64::max),
        )
    };
    Ok(EstimateMeasured {
        fix: mean_max(&fix),
        states: mean_max(&states),
        stack,
        flash,
    })
}

/// The bench page's paragraph: f32 on both CPUs, fixed point on the M0.
pub fn section() -> Result<String, String> {
    let mut text = format!(
        "Estimator (`twocars::estimate`; `estimate` and `estimate_fixed` images: \
         {ESTIMATE_FIXES} target fixes 200 ms apart with noise, each followed by a decision's \
         states 100 ms on, every result within 1e-5 of the host's over the same number type; \
         the call overhead subtracted):\n\n| CPU | number type | per target fix | per decision (both states) | stack | image flash |\n|---|---|---|---|---|---|\n"
    );
    let rows: [(Cpu, &str, &str); 3] = [
        (M4F, "f32", "estimate"),
        (M0, "fixed point (Q17.14)", "estimate_fixed"),
        (M0, "f32 soft-float", "estimate"),
    ];
    for (cpu, number, image) in rows {
        let m = if image == "estimate_fixed" {
            measure::<Fixed>(cpu, image)?
        } else {
            measure::<f32>(cpu, image)?
        };
        text.push_str(&format!(
            "| {} | {number} | {:.0} instructions (max {:.0}) | {:.0} (max {:.0}) | {} B | {} B |\n",
            cpu.name(),
            m.fix.0,
            m.fix.1,
            m.states.0,
            m.states.1,
            m.stack,
            m.flash
        ));
    }
    text.push_str(
        "\nWhere a fix's instructions go: the gains of both channels, the spreads they leave and \
         the turn rate's noise (on the M0 most of a fix's library divisions and three square \
         roots) depend on the interval alone and are kept with it, so a fix at the interval \
         of the one before (all but the first two here) skips them and the max is a fix at a \
         new interval; the rest is the arc's prediction (a sine and cosine), the residual's \
         outlier test and the correction (docs/field.md, \"In fixed point\").\n",
    );
    Ok(text)
}
