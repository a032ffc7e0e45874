//! `cargo xtask run` until the firmware lands: the paper's four cases through the law and the
//! host closed loop.

use crate::options::{Numeric, Options};
use host_tests::sim::SimParams;

/// Control period of the main job's closed loop, seconds.
const CLOSED_LOOP_DT: f64 = 0.001;
/// Capture distance of the main job's closed loop, metres.
const CLOSED_LOOP_EPS: f64 = 0.01;
use host_tests::scenarios::{paper_cases, PAPER_LIMITS};
use twocars::{evaluate_observation, Observation, Scalar};

fn show<S: Scalar>(options: &Options) -> i32 {
    let [v_pm, w_pm, v_em, w_em] = PAPER_LIMITS.map(|v| v as f32);
    println!("limits: v_pm = {v_pm} m/s, w_pm = {w_pm} 1/m, v_em = {v_em} m/s, w_em = {w_em} 1/m");
    println!("variant: {:?}", options.variant);
    let mut failures = 0;
    for case in paper_cases() {
        let observation = Observation {
            limits: [v_pm, w_pm, v_em, w_em],
            pursuer: case.pursuer.map(|v| v as f32),
            evader: case.evader.map(|v| v as f32),
        };
        let evaluation = evaluate_observation::<S>(&observation, options.variant);
        println!();
        println!(
            "{}: p0 = {:?}, e0 = {:?}: status {}",
            case.name,
            case.pursuer,
            case.evader,
            evaluation.status.name()
        );
        let Some(report) = evaluation.report else {
            failures += 1;
            continue;
        };
        let f = |v: Option<S>| v.map_or("inf".to_string(), |v| format!("{:9.4}", v.to_f64()));
        let m = report.matrix.entries;
        println!("           evader A   evader C");
        println!("  pursuer A {}  {}", f(m[0][0]), f(m[0][1]));
        println!("  pursuer C {}  {}", f(m[1][0]), f(m[1][1]));
        let s = report.solution;
        println!(
            "  pursuer plays {}, evader plays {}; upper {} s, lower {} s, saddle {}{}",
            s.row.letter(),
            s.col.letter(),
            f(s.upper).trim(),
            f(s.lower).trim(),
            s.saddle,
            s.mixed.map_or(String::new(), |v| format!(
                ", mixed value {:.4} s",
                v.to_f64()
            )),
        );
        let predicted = s.upper.map_or(f64::INFINITY, |v| v.to_f64());
        println!(
            "  predicted capture time {predicted:.4} s (independent f64: {:.4} s)",
            case.expected_value
        );
        if (predicted - case.expected_value).abs() > 1e-3 {
            failures += 1;
        }
        let params = SimParams {
            limits: PAPER_LIMITS,
            pursuer: case.pursuer,
            evader: case.evader,
            dt: CLOSED_LOOP_DT,
            t_max: 30.0,
            eps: CLOSED_LOOP_EPS,
        };
        let r = crate::sim::run_one(&params, options, false);
        let closed = r.t_capture + CLOSED_LOOP_EPS / (PAPER_LIMITS[0] - PAPER_LIMITS[2]);
        println!(
            "  closed loop (dt = {CLOSED_LOOP_DT} s): {}, captured to {CLOSED_LOOP_EPS} m at {:.4} s \
             (+ eps / (v_pm - v_em) = {closed:.4} s vs predicted {predicted:.4} s); \
             {} switches, {} sign flips",
            r.status.name(),
            r.t_capture,
            r.switches,
            r.sign_flips
        );
    }
    i32::from(failures > 0)
}

/// Prints the four cases; exit code 1 if a value is off by more than 1e-3 s.
pub fn run(options: &Options) -> i32 {
    match options.numeric {
        Numeric::F32 => show::<f32>(options),
        Numeric::F64 => show::<f64>(options),
    }
}
