//! `cargo xtask eval`: the law on CSV rows from stdin (format in docs/contract.md).

use crate::commands::csv::{narrow, number, optional, parse_fields, run_door};
use crate::harness::host::{with_numeric, Options};
use twocars::law::{evaluate_observation, Observation};
use twocars::{Evaluation, Scalar, Status};

/// Input header of `eval`.
pub const INPUT_HEADER: &str = "v_pm,w_pm,v_em,w_em,x_p,y_p,theta_p,x_e,y_e,theta_e";
/// Output header of `eval`.
pub const OUTPUT_HEADER: &str = "status,row,col,t_aa,t_ac,t_ca,t_cc,upper,lower,w_p,w_e";

/// Builds an observation from the ten CSV fields.
pub fn observation(f: &[f64; 10]) -> Observation {
    let n = |i: usize| f.get(i).copied().map_or(f32::NAN, narrow);
    Observation {
        limits: [n(0), n(1), n(2), n(3)],
        pursuer: [n(4), n(5), n(6)],
        evader: [n(7), n(8), n(9)],
    }
}

/// One output row for an evaluation.
pub fn row<S: Scalar>(evaluation: &Evaluation<S>) -> String {
    let status = evaluation.status.name();
    let units = evaluation.units;
    let w_p = number(units.curvature(evaluation.command.pursuer));
    let w_e = number(units.curvature(evaluation.command.evader));
    match (&evaluation.report, evaluation.status) {
        (Some(report), _) => {
            let m = report.matrix().entries;
            let v = |x: Option<S>| optional(x.map(|x| units.seconds(x)));
            format!(
                "{status},{},{},{},{},{},{},{},{},{w_p},{w_e}",
                report.solution.row.letter(),
                report.solution.col.letter(),
                v(m[0][0]),
                v(m[0][1]),
                v(m[1][0]),
                v(m[1][1]),
                v(report.solution.upper),
                v(report.solution.lower),
            )
        }
        (None, Status::Captured) => format!("{status},,,,,,,0,0,{w_p},{w_e}"),
        (None, _) => format!("{status},,,,,,,,,{w_p},{w_e}"),
    }
}

fn eval_line<S: Scalar>(line: &str, options: &Options) -> String {
    match parse_fields::<10>(line) {
        Ok(fields) => row(&evaluate_observation::<S>(
            &observation(&fields),
            options.variant,
        )),
        Err(e) => format!("{},,,,,,,,,0,0", e.status()),
    }
}

/// Runs the door: returns the /// Runs the door: returns the process exit code.
pub fn run(options: &Options) -> i32 {
    run_door(
        "eval",
        INPUT_HEADER,
        OUTPUT_HEADER,
        |line| with_numeric!(options.numeric, S => eval_line::<S>(line, options)),
    )
}
