//! `cargo xtask hj --probe X,Y,PHI`: one near-field start looked at closely. It
//! prints V(x0) from the reference tables and from `--levels`, the capture when the pursuer
//! plays `--levels` and the evader plays the reference tables (the `--play` row "the table's
//! evader"), and the best pursuer of a family of open-loop plans against that same evader: a
//! turn held for t1, another for t2, a third to the end (turns full either way or straight,
//! t1 and t2 on a 25 ms grid up to 1.5 s). A pursuer that plays V exactly captures every evader
//! by V(x0); where the tables' pursuer is late against this evader, a plan that captures well
//! before it shows what that pursuer left, and V(x0) on two grids shows how far V itself moves.
//! `--play` sets the same plans ([`best_plan`]) beside each of its runs past 10 %, against that
//! run's evader: where none captures much earlier than the tables' pursuer, no pursuer of the
//! family does better, and the run's distance past V(x0) says more about V(x0) than about it.

use hji::policy::{evader_curvature, pursuer_curvature, relative};

use crate::commands::hj::reference::{capture_radius, table_value, DT};
use rayon::prelude::*;
use twocars_sim::sim::{advance, capture_within, distance};

/// The longest run, s.
const T_MAX: f64 = 10.0;

/// A pursuer's open-loop plan: turn signs held for the first two durations (s), then the third.
type Plan = ([f64; 3], [f64; 2]);

/// Solves (or reads) the tables of `limits`, plays the start `(x, y, phi)` (the evader in the
/// pursuer's frame: r_p, r_p, rad) and prints what it found; exit code 0.
pub fn command(start: [f64; 3], levels: &[hji::Grid], limits: [f64; 4]) -> i32 {
    use crate::image::tables::sets::{NEAR_FIELD_LEVELS, PLAYED, REFERENCE};
    use crate::image::tables::solve::nested_tables;
    let (reference, _) = nested_tables(limits, &NEAR_FIELD_LEVELS, REFERENCE);
    let tables = if levels == NEAR_FIELD_LEVELS {
        reference.clone()
    } else {
        nested_tables(limits, levels, PLAYED).0
    };
    let [_, w_pm, v_em, w_em] = limits;
    let eps = capture_radius(&reference, limits);
    let pursuer0 = [0.0, 0.0, 0.0];
    let evader0 = [start[0] / w_pm, start[1] / w_pm, start[2]];
    let at = relative(w_pm, pursuer0, evader0);
    let seconds = |tables: &[hji::Solution]| {
        table_value(tables, limits, pursuer0, evader0)
            .map_or("none".to_string(), |v| format!("{v:.3} s"))
    };
    let tables_evader = || -> EvaderRun<'_> {
        Box::new(|_, p, e| {
            let w_e = evader_curvature(&reference, [w_pm, w_em], p, e).unwrap_or(0.0);
            (w_e, v_em)
        })
    };
    let closed_loop = chase(
        limits,
        eps,
        [pursuer0, evader0],
        T_MAX,
        |_, p, e| pursuer_curvature(&tables, w_pm, p, e).unwrap_or(0.0),
        tables_evader(),
    );
    let (best, plan) = best_plan(limits, eps, [pursuer0, evader0], T_MAX, &tables_evader);
    println!(
        "Limits {limits:?}, start (x, y, phi) = ({:.3}, {:.3}, {:.3}) (r_p, rad), capture at {eps} m, dt = {DT} s.",
        at.0, at.1, at.2
    );
    println!(
        "V(x0): reference {}, --levels {}",
        seconds(&reference),
        seconds(&tables)
    );
    println!(
        "the --levels pursuer against the reference tables' evader: capture at {closed_loop:.3} s"
    );
    println!(
        "the best of {PLANS} open-loop plans against the same evader: capture at {best:.3} s (turns {:?} for {:.3} s, {:.3} s, then to the end)",
        plan.0,
        plan.1[0],
        plan.1[1]
    );
    0
}

/// How many plans [`best_plan`] tries: 12 sequences of three turns (no two neighbours the
/// same), each with 61 x 61 durations.
pub(crate) const PLANS: usize = 12 * 61 * 61;

/// An evader in one run: its curvature (1/m) and speed (m/s) at time t (s) from both states
/// (m, rad).
pub(crate) type EvaderRun<'a> = Box<dyn FnMut(f64, [f64; 3], [f64; 3]) -> (f64, f64) + 'a>;

/// A fresh evader for each plan's run.
pub(crate) type EvaderMaker<'a> = dyn Fn() -> EvaderRun<'a> + Sync + 'a;

/// The earliest capture (s) of the evader that `evader` makes, from the start `[pursuer,
/// evader]` (m, rad) at `limits`, capture at `eps` m, by the open-loop plans of the family
/// ([`PLANS`] of them: a turn held for t1, another for t2, a third to the end; full turns or
/// straight, t1 and t2 on a 25 ms grid up to 1.5 s), with the best plan; infinite where none
/// captures before `t_max`.
pub(crate) fn best_plan(
    limits: [f64; 4],
    eps: f64,
    [pursuer0, evader0]: [[f64; 3]; 2],
    t_max: f64,
    evader: &EvaderMaker<'_>,
) -> (f64, Plan) {
    let w_pm = limits[1];
    let durations: Vec<f64> = (0..=60).map(|i| f64::from(i) * 0.025).collect();
    let mut plans: Vec<Plan> = Vec::new();
    for turns in plan_turns() {
        for &t1 in &durations {
            for &t2 in &durations {
                plans.push((turns, [t1, t2]));
            }
        }
    }
    plans
        .par_iter()
        .map(|&(turns, [t1, t2])| {
            let turn = |t: f64| match t {
                t if t < t1 => turns[0],
                t if t < t1 + t2 => turns[1],
                _ => turns[2],
            };
            let time = chase(
                limits,
                eps,
                [pursuer0, evader0],
                t_max,
                |t, _, _| w_pm * turn(t),
                evader(),
            );
            (time, (turns, [t1, t2]))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((f64::INFINITY, ([0.0; 3], [0.0; 2])))
}

/// The capture time (s) of the pursuer whose curvature (1/m) is `pursuer(t, pursuer, evader)`
/// against the evader whose curvature and speed are `evader(t, pursuer, evader)`, from the
/// start `[pursuer, evader]` (m, rad) at `limits`, both commands held for a control period,
/// capture at `eps` m found within a period as the closed loop finds it
/// ([`capture_within`]); infinite where it does not come before `t_max`.
fn chase(
    [v_pm, ..]: [f64; 4],
    eps: f64,
    [mut p, mut e]: [[f64; 3]; 2],
    t_max: f64,
    pursuer: impl Fn(f64, [f64; 3], [f64; 3]) -> f64,
    mut evader: impl FnMut(f64, [f64; 3], [f64; 3]) -> (f64, f64),
) -> f64 {
    let mut t = 0.0;
    while t < t_max {
        if distance(p, e) <= eps {
            return t;
        }
        let (w_e, v_e) = evader(t, p, e);
        let w_p = pursuer(t, p, e);
        let gap = |s: f64| distance(advance(p, v_pm, w_p, s), advance(e, v_e, w_e, s));
        let mut closest = f64::INFINITY;
        if let Some(s) = capture_within(DT, eps, gap, &mut closest) {
            return t + s;
        }
        p = advance(p, v_pm, w_p, DT);
        e = advance(e, v_e, w_e, DT);
        t += DT;
    }
    f64::INFINITY
}

/// The three turns of a plan, each full right (-1), straight or full left, no two neighbours
/// the same (a plan with fewer changes is one of these with a zero duration).
fn plan_turns() -> Vec<[f64; 3]> {
    let turns = [-1.0, 0.0, 1.0];
    let mut out = Vec::new();
    for a in turns {
        for b in turns {
            for c in turns {
                if a != b && b != c {
                    out.push([a, b, c]);
                }
            }
        }
    }
    out
}
