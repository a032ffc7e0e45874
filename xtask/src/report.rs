//! `cargo xtask report`: closed-loop Monte Carlo over seeded random initial states and limits,
//! both policies, split at the theorem's threshold, run in parallel over the cores.

use host_tests::sim::{simulate, theorem_threshold, SimParams, SimResult, SimStatus};
use rayon::prelude::*;
use twocars::{Policy, Variant};

/// Capture distance, metres.
const EPS: f64 = 0.01;
/// "Equals the prediction" within this many control periods.
const TOLERANCE_PERIODS: f64 = 5.0;

/// A small seeded generator (SplitMix64): the same states on every machine.
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Which side of the theorem's threshold a run starts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    /// d0 >= 2 r_e + 2 pi r_e v_pm / v_em: the theorem's regime.
    Far,
    /// d0 below it.
    Near,
}

/// One seeded initial state with random limits (Assumption 1: v_pm > v_em, w_pm > w_em).
pub fn random_state(rng: &mut Rng, dt: f64) -> (SimParams, Regime) {
    let v_em = rng.uniform(0.5, 3.0);
    let v_pm = v_em * rng.uniform(1.1, 3.0);
    let w_em = rng.uniform(0.2, 2.0);
    let w_pm = w_em * rng.uniform(1.1, 4.0);
    let limits = [v_pm, w_pm, v_em, w_em];
    let threshold = theorem_threshold(limits);
    // Half the runs start within the threshold, half up to 3 times it.
    let near = rng.uniform(0.0, 1.0) < 0.5;
    let d0 = if near {
        rng.uniform(0.05, 1.0) * threshold
    } else {
        rng.uniform(1.0, 3.0) * threshold
    };
    let bearing = rng.uniform(-std::f64::consts::PI, std::f64::consts::PI);
    let params = SimParams {
        limits,
        pursuer: [
            0.0,
            0.0,
            rng.uniform(-std::f64::consts::PI, std::f64::consts::PI),
        ],
        evader: [
            d0 * bearing.cos(),
            d0 * bearing.sin(),
            rng.uniform(-std::f64::consts::PI, std::f64::consts::PI),
        ],
        dt,
        t_max: 0.0,
        eps: EPS,
    };
    (params, if near { Regime::Near } else { Regime::Far })
}

/// One state run under both policies.
pub struct Run {
    /// Initial state and run parameters.
    pub params: SimParams,
    /// Regime of the initial state.
    pub regime: Regime,
    /// The paper's law.
    pub paper: SimResult,
    /// The near-field policy.
    pub near_field: SimResult,
}

impl Run {
    /// Capture time plus the time to close the last eps, minus the prediction at t = 0.
    pub fn lateness(&self, r: &SimResult) -> f64 {
        let [v_pm, _, v_em, _] = self.params.limits;
        r.t_capture + EPS / (v_pm - v_em) - r.predicted
    }

    /// Whether the run captured when predicted: within the tolerance of the upper value, or
    /// between lower and upper where the game has no pure saddle.
    pub fn as_predicted(&self, r: &SimResult) -> bool {
        let tolerance = TOLERANCE_PERIODS * self.params.dt;
        let closed = r.t_capture + EPS / (self.params.limits[0] - self.params.limits[2]);
        r.status == SimStatus::Captured
            && closed >= r.predicted_lower.min(r.predicted) - tolerance
            && closed <= r.predicted + tolerance
    }
}

/// `runs` seeded states (about half per regime), each simulated under both policies in parallel.
pub fn monte_carlo(runs: usize, seed: u64, dt: f64) -> Vec<Run> {
    let mut rng = Rng::new(seed);
    let states: Vec<(SimParams, Regime)> = (0..runs).map(|_| random_state(&mut rng, dt)).collect();
    states
        .into_par_iter()
        .map(|(params, regime)| {
            let predicted = twocars::evaluate_observation::<f32>(
                &twocars::Observation {
                    limits: params.limits.map(|v| v as f32),
                    pursuer: params.pursuer.map(|v| v as f32),
                    evader: params.evader.map(|v| v as f32),
                },
                Variant::Paper,
            )
            .report
            .and_then(|r| r.solution.upper)
            .map_or(60.0, f64::from);
            let params = SimParams {
                t_max: 3.0 * predicted.max(1.0) + 30.0,
                ..params
            };
            let sim = |policy| simulate::<f32>(&params, Variant::Paper, policy, false);
            Run {
                params,
                regime,
                paper: sim(Policy::Paper),
                near_field: sim(Policy::NearField),
            }
        })
        .collect()
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

/// One state as a `cargo xtask sim` input row.
fn sim_row(p: &SimParams) -> String {
    let f = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    format!(
        "{},{},{},{},{},{}",
        f(&p.limits),
        f(&p.pursuer),
        f(&p.evader),
        p.dt,
        p.t_max,
        p.eps
    )
}

fn print_policy(name: &str, runs: &[&Run], pick: fn(&Run) -> &SimResult) {
    let n = runs.len();
    let captured = runs
        .iter()
        .filter(|r| pick(r).status == SimStatus::Captured)
        .count();
    let as_predicted = runs.iter().filter(|r| r.as_predicted(pick(r))).count();
    let late = sorted(
        runs.iter()
            .filter(|r| pick(r).status == SimStatus::Captured)
            .map(|r| r.lateness(pick(r)))
            .collect(),
    );
    let capture = sorted(
        runs.iter()
            .map(|r| pick(r).t_capture)
            .filter(|t| t.is_finite())
            .collect(),
    );
    let mean = capture.iter().sum::<f64>() / capture.len().max(1) as f64;
    let switches = sorted(runs.iter().map(|r| pick(r).switches as f64).collect());
    let flips = sorted(runs.iter().map(|r| pick(r).sign_flips as f64).collect());
    println!(
        "| {name} | {n} | {captured} | {as_predicted} ({:.1}%) | {:.3} / {:.3} / {:.3} / {:.3} | {mean:.2} | {:.0} / {:.0} | {:.0} / {:.0} / {:.0} |",
        100.0 * as_predicted as f64 / n.max(1) as f64,
        quantile(&late, 0.1),
        quantile(&late, 0.5),
        quantile(&late, 0.9),
        quantile(&late, 1.0),
        quantile(&switches, 0.5),
        quantile(&switches, 1.0),
        quantile(&flips, 0.5),
        quantile(&flips, 0.9),
        quantile(&flips, 1.0),
    );
}

/// Prints the report for `runs`.
pub fn print(runs: &[Run], seed: u64, dt: f64) {
    println!(
        "# Closed-loop Monte Carlo: {} seeded states (seed {seed}), random limits, dt = {dt} s, eps = {EPS} m\n",
        runs.len()
    );
    println!(
        "\"As predicted\": capture time + eps / (v_pm - v_em) within {TOLERANCE_PERIODS} dt of the upper value at t = 0, \
         or between lower and upper where there is no pure saddle. Lateness = that time minus the upper value.\n"
    );
    for (regime, title) in [
        (
            Regime::Far,
            "d0 >= threshold 2 r_e + 2 pi r_e v_pm / v_em (the theorem's regime)",
        ),
        (Regime::Near, "d0 < threshold (the near field)"),
    ] {
        let set: Vec<&Run> = runs.iter().filter(|r| r.regime == regime).collect();
        println!("## {title}\n");
        println!("| policy | runs | captured | as predicted | lateness p10 / median / p90 / max (s) | mean capture (s) | switches median / max | sign flips median / p90 / max |");
        println!("|---|---|---|---|---|---|---|---|");
        print_policy("paper", &set, |r| &r.paper);
        print_policy("near-field", &set, |r| &r.near_field);
        let longer = set
            .iter()
            .filter(|r| r.near_field.t_capture > r.paper.t_capture + TOLERANCE_PERIODS * dt)
            .count();
        let shorter = set
            .iter()
            .filter(|r| r.near_field.t_capture < r.paper.t_capture - TOLERANCE_PERIODS * dt)
            .count();
        let longer_where_paper_held = set
            .iter()
            .filter(|r| {
                r.as_predicted(&r.paper)
                    && r.near_field.t_capture > r.paper.t_capture + TOLERANCE_PERIODS * dt
            })
            .count();
        println!(
            "\nnear-field vs paper on the same states: shorter by > {TOLERANCE_PERIODS} dt in {shorter}, longer in {longer} \
             ({longer_where_paper_held} of them where the paper's law captured as predicted).\n"
        );
        for r in set
            .iter()
            .filter(|r| r.near_field.t_capture > r.paper.t_capture + TOLERANCE_PERIODS * dt)
            .take(5)
        {
            println!(
                "- longer with near-field: predicted {:.3} s, paper {:.3} s, near-field {:.3} s: `{}`",
                r.paper.predicted,
                r.paper.t_capture,
                r.near_field.t_capture,
                sim_row(&r.params)
            );
        }
        println!();
        for (name, pick) in [
            (
                "the paper's law",
                (|r: &Run| &r.paper) as fn(&Run) -> &SimResult,
            ),
            ("the near-field policy", |r: &Run| &r.near_field),
        ] {
            let mut latest: Vec<&Run> = set.clone();
            latest.sort_by(|a, b| b.lateness(pick(b)).total_cmp(&a.lateness(pick(a))));
            print_rows(&format!("Latest captures under {name}"), &latest);
            let mut flippiest: Vec<&Run> = set.clone();
            flippiest.sort_by_key(|r| std::cmp::Reverse(pick(r).sign_flips));
            print_rows(&format!("Most sign flips under {name}"), &flippiest);
        }
    }
}

/// The first three runs of `runs` as `sim` rows, with both policies' outcomes.
fn print_rows(title: &str, runs: &[&Run]) {
    println!("{title} (re-run a row with `cargo xtask sim [--policy near-field]`):\n");
    println!("```\n{}", crate::sim::INPUT_HEADER);
    for r in runs.iter().take(3) {
        println!("{}", sim_row(&r.params));
    }
    println!("```\n");
    for r in runs.iter().take(3) {
        println!(
            "- predicted {:.3} s; paper captured at {:.3} s ({} flips), near-field at {:.3} s ({} flips)",
            r.paper.predicted,
            r.paper.t_capture,
            r.paper.sign_flips,
            r.near_field.t_capture,
            r.near_field.sign_flips
        );
    }
    println!();
}

/// `cargo xtask report [--runs N] [--seed S] [--dt S]`.
pub fn command(args: &[String]) -> i32 {
    let mut runs = 2000usize;
    let mut seed = 2019u64;
    let mut dt = 0.01f64;
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let value = it.next();
        let ok = match (arg.as_str(), value) {
            ("--runs", Some(v)) => v.parse().map(|v| runs = v).is_ok(),
            ("--seed", Some(v)) => v.parse().map(|v| seed = v).is_ok(),
            ("--dt", Some(v)) => v.parse().map(|v| dt = v).is_ok() && dt > 0.0 && dt <= 0.1,
            _ => false,
        };
        if !ok {
            eprintln!(
                "xtask report: usage: cargo xtask report [--runs N] [--seed S] [--dt S (<= 0.1)]"
            );
            return 2;
        }
    }
    let started = std::time::Instant::now();
    let results = monte_carlo(runs, seed, dt);
    print(&results, seed, dt);
    println!(
        "({} runs x 2 policies in {:.1} s on {} threads)",
        results.len(),
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_monte_carlo_is_seeded_and_covers_both_regimes() {
        let a = monte_carlo(24, 7, 0.01);
        let b = monte_carlo(24, 7, 0.01);
        assert_eq!(a.len(), 24);
        assert!(a.iter().any(|r| r.regime == Regime::Far));
        assert!(a.iter().any(|r| r.regime == Regime::Near));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.paper.t_capture.to_bits(), y.paper.t_capture.to_bits());
            let d0 = (x.params.evader[0]).hypot(x.params.evader[1]);
            assert_eq!(
                d0 >= theorem_threshold(x.params.limits),
                x.regime == Regime::Far
            );
        }
    }
}
