//! `cargo xtask report`: closed-loop Monte Carlo over seeded random initial states, both
//! policies, split at the theorem's threshold, against the adversary suite's evaders (our
//! pursuer) or pursuers (our evader), run in parallel over the cores. Each run is judged by
//! the paper's values at t = 0 (the upper value for our pursuer, the lower for our evader), in
//! seconds, on random limits as well as the paper's. `cargo xtask hj --play` is the other
//! reporter: below the threshold only, at fixed limits, judged by the HJI value V(x0) in per
//! cent; both draw their starts with [`random_state`] and their quantiles with
//! `twocars_sim::stats`.

use rayon::prelude::*;
use twocars::{Policy, Variant};
use twocars_sim::adversary::{EvaderKind, Opponent, PursuerKind};
use twocars_sim::rng::Rng;
use twocars_sim::scenarios::EPS;
use twocars_sim::scenarios::PAPER_LIMITS;
use twocars_sim::sim::{simulate_against, theorem_threshold, SimParams, SimResult, SimStatus};
use twocars_sim::starts::{random_limits, random_start, LimitSet};
use twocars_sim::stats::quantile_f64;

use crate::util::progress::Progress;

/// "Equals the prediction" within this many control periods.
const TOLERANCE_PERIODS: f64 = 5.0;

/// Which side of the theorem's threshold a run starts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    /// d0 >= 2 r_e + 2 pi r_e v_pm / v_em: the theorem's regime.
    Far,
    /// d0 below it.
    Near,
}

/// One seeded initial state: random limits (or the paper's), half the runs within the
/// threshold, half up to three times it; random bearing and headings.
pub fn random_state(rng: &mut Rng, dt: f64, limit_set: LimitSet) -> (SimParams, Regime) {
    // Drawn at the paper's limits too, so that both sets see the same starts.
    let random = random_limits(rng);
    let limits = match limit_set {
        LimitSet::Random => random,
        LimitSet::Paper => PAPER_LIMITS,
    };
    let threshold = theorem_threshold(limits);
    let near = rng.uniform(0.0, 1.0) < 0.5;
    let d0 = if near {
        rng.uniform(0.05, 1.0) * threshold
    } else {
        rng.uniform(1.0, 3.0) * threshold
    };
    let params = random_start(rng, limits, d0, dt, EPS);
    (params, if near { Regime::Near } else { Regime::Far })
}

/// One state run under both policies against one opponent.
pub struct Run {
    /// Initial state and run parameters.
    pub params: SimParams,
    /// Regime of the initial state.
    pub regime: Regime,
    /// The adversary's seed.
    pub seed: u64,
    /// The paper's law.
    pub paper: SimResult,
    /// The flight policy.
    pub flight: SimResult,
}

impl Run {
    /// Capture time plus the time to close the last eps, minus the prediction at t = 0.
    pub fn lateness(&self, r: &SimResult) -> f64 {
        r.point_capture(self.params.limits, EPS) - r.predicted
    }

    /// Capture time plus eps / (v_pm - v_em) minus the lower value at t = 0 (negative: the
    /// evader was caught before its guarantee).
    pub fn margin_over_lower(&self, r: &SimResult) -> f64 {
        r.point_capture(self.params.limits, EPS) - r.predicted_lower
    }

    /// Late: captured more than the tolerance after the upper value, or never.
    pub fn late(&self, r: &SimResult) -> bool {
        self.lateness(r) > TOLERANCE_PERIODS * self.params.dt
    }
}

/// `runs` seeded states (about half per regime), each simulated under both policies against
/// `opponent` (`None`: the law plays both players), in parallel.
pub fn monte_carlo(
    runs: usize,
    seed: u64,
    dt: f64,
    limit_set: LimitSet,
    opponent: Option<Opponent>,
    progress: Option<&Progress>,
) -> Vec<Run> {
    let mut rng = Rng::new(seed);
    let states: Vec<(SimParams, Regime, u64)> = (0..runs)
        .map(|_| {
            let (p, r) = random_state(&mut rng, dt, limit_set);
            (p, r, rng.next_u64())
        })
        .collect();
    states
        .into_par_iter()
        .map(|(params, regime, seed)| {
            let predicted = twocars::law::evaluate_observation::<f32>(
                &twocars::law::Observation {
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
            let sim = |policy| {
                simulate_against::<f32>(
                    &params,
                    Variant::Paper,
                    policy,
                    opponent.map(|o| (o, seed)),
                    false,
                )
            };
            let run = Run {
                params,
                regime,
                seed,
                paper: sim(Policy::Paper),
                flight: sim(Policy::Flight),
            };
            if let Some(p) = progress {
                p.inc();
            }
            run
        })
        .collect()
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

/// One state as a `cargo xtask sim` input row.
pub fn sim_row(p: &SimParams) -> String {
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

/// Figures of one policy on one set of runs.
pub struct Summary {
    /// Runs.
    pub runs: usize,
    /// Captured within t_max.
    pub captured: usize,
    /// Captured more than 5 dt after the upper value at t = 0, or never.
    pub late: usize,
    /// Captured more than 5 dt before the lower value at t = 0 (our evader's guarantee broken).
    pub early: usize,
    /// Lateness (s) of the captured runs, sorted.
    pub lateness: Vec<f64>,
    /// Sign flips per run, sorted.
    pub flips: Vec<f64>,
}

impl Summary {
    /// The figures of `pick`'s results over `runs`.
    pub fn of(runs: &[&Run], pick: Pick) -> Self {
        let captured: Vec<&&Run> = runs
            .iter()
            .filter(|r| pick(r).status == SimStatus::Captured)
            .collect();
        Summary {
            runs: runs.len(),
            captured: captured.len(),
            late: runs.iter().filter(|r| r.late(pick(r))).count(),
            early: captured
                .iter()
                .filter(|r| pick(r).predicted_lower.is_finite())
                .filter(|r| r.margin_over_lower(pick(r)) < -TOLERANCE_PERIODS * r.params.dt)
                .count(),
            lateness: sorted(captured.iter().map(|r| r.lateness(pick(r))).collect()),
            flips: sorted(runs.iter().map(|r| pick(r).sign_flips as f64).collect()),
        }
    }
}

fn print_row(label: &str, s: &Summary) {
    println!(
        "| {label} | {} | {} | {} | {} | {:.3} / {:.3} / {:.3} / {:.3} | {:.0} / {:.0} |",
        s.runs,
        s.captured,
        s.runs - s.captured,
        s.late,
        quantile_f64(&s.lateness, 0.5),
        quantile_f64(&s.lateness, 0.9),
        quantile_f64(&s.lateness, 0.99),
        quantile_f64(&s.lateness, 1.0),
        quantile_f64(&s.flips, 0.9),
        quantile_f64(&s.flips, 1.0),
    );
}

/// Which of a run's results a figure reads.
pub type Pick = fn(&Run) -> &SimResult;

/// The policies of a run, with their names.
const POLICIES: [(&str, Pick); 2] = [("paper", |r| &r.paper), ("flight", |r| &r.flight)];

/// Prints the table rows of one evader and limit set, and the flight policy's worst runs.
fn print_evader(name: &str, limit_set: LimitSet, runs: &[Run], worst: &mut Vec<String>) {
    for (regime, regime_name) in [
        (Regime::Far, "d0 >= threshold"),
        (Regime::Near, "d0 < threshold"),
    ] {
        let set: Vec<&Run> = runs.iter().filter(|r| r.regime == regime).collect();
        for (policy, pick) in POLICIES {
            let label = format!("{name} | {} | {regime_name} | {policy}", limit_set.name());
            print_row(&label, &Summary::of(&set, pick));
        }
        let mut bad: Vec<&&Run> = set
            .iter()
            .filter(|r| {
                r.flight.status != SimStatus::Captured
                    || (regime == Regime::Far && r.late(&r.flight))
            })
            .collect();
        bad.sort_by(|a, b| b.lateness(&b.flight).total_cmp(&a.lateness(&a.flight)));
        for r in bad.iter().take(3) {
            worst.push(format!(
                "- {name}, {} limits, {regime_name}: predicted {:.3} s, flight {:.3} s, paper {:.3} s: \
                 `printf '{}\\n{}\\n' | cargo xtask sim --policy flight --evader {name} --adversary-seed {}`",
                limit_set.name(),
                r.flight.predicted,
                r.flight.t_capture,
                r.paper.t_capture,
                crate::commands::sim::INPUT_HEADER,
                sim_row(&r.params),
                r.seed
            ));
        }
    }
}

/// Prints our evader's rows against one pursuer of the mirror suite.
fn print_pursuer(name: &str, limit_set: LimitSet, runs: &[Run]) {
    for (regime, regime_name) in [
        (Regime::Far, "d0 >= threshold"),
        (Regime::Near, "d0 < threshold"),
    ] {
        let set: Vec<&Run> = runs.iter().filter(|r| r.regime == regime).collect();
        for (policy, pick) in POLICIES {
            let s = Summary::of(&set, pick);
            let margins = sorted(
                set.iter()
                    .filter(|r| pick(r).status == SimStatus::Captured)
                    .filter(|r| pick(r).predicted_lower.is_finite())
                    .map(|r| r.margin_over_lower(pick(r)))
                    .collect(),
            );
            println!(
                "| {name} | {} | {regime_name} | {policy} | {} | {} | {} | {:.3} |",
                limit_set.name(),
                s.runs,
                s.captured,
                s.early,
                quantile_f64(&margins, 0.0),
            );
        }
    }
}

/// Options of `cargo xtask report`.
struct ReportOptions {
    runs: usize,
    seed: u64,
    dt: f64,
    limits: Vec<LimitSet>,
    evaders: Vec<Option<EvaderKind>>,
    pursuers: Vec<PursuerKind>,
}

/// Which limit sets `report` draws, as the command line names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LimitsArg {
    /// Seeded random limits.
    Random,
    /// The paper's 2, 2, 1, 1.
    Paper,
    /// Both, one table row pair each.
    Both,
}

/// `cargo xtask report`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct ReportArgs {
    /// Seeded starts per evader and limit set.
    #[arg(long, default_value_t = 2000)]
    runs: usize,
    /// The starts' seed.
    #[arg(long, default_value_t = 2019)]
    seed: u64,
    /// Control period, seconds (at most 0.1).
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// The limit sets.
    #[arg(long, value_enum, default_value = "random")]
    limits: LimitsArg,
    /// An evader of the adversary suite, or all (default: the law plays both players).
    #[arg(long, value_parser = names(&EvaderKind::FIELD.map(EvaderKind::name)))]
    evader: Option<String>,
    /// Our evader against a pursuer of the mirror suite, or all.
    #[arg(long, value_parser = names(&PursuerKind::ALL.map(PursuerKind::name)))]
    pursuer: Option<String>,
    /// The field's sweep instead (late, sparse, noisy fixes; a lagging pursuer), over the
    /// evaders of `--evader` (default all of the sweep's, zigzag among them).
    #[arg(long)]
    field: bool,
    /// With `--field`: how far ahead the estimator carries both states, in the pursuer's
    /// yaw-rate lags tau.
    #[arg(long, default_value_t = 1.0)]
    own_lead: f64,
    /// With `--field`: only the cells with a fix every period, or 5 per full turn.
    #[arg(long, value_enum, default_value = "all")]
    fixes: FixesArg,
    /// Instead: this many pursuers (2, 3, 4 or 8) against one evader, the team beside each
    /// pursuer alone and beside all flying their 1-on-1 flight policies without roles
    /// (docs/team.md).
    #[arg(long, conflicts_with = "field")]
    team: Option<usize>,
    /// With `--team`: the noise on each position the team's roles are named from, standard
    /// deviation in the pursuers' least turning radius r_p.
    #[arg(long, default_value_t = 0.1, requires = "team")]
    role_noise: f64,
    /// With `--team`: how late each vehicle hears its teammates' states, s, for the share of
    /// periods in which the vehicles' own roles disagree.
    #[arg(long, default_value_t = 0.3, requires = "team")]
    teammate_lag: f64,
}

/// The field's cells by their fixes.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
enum FixesArg {
    /// Every cell.
    All,
    /// A fix every control period.
    Every,
    /// 5 fixes per full turn.
    Sparse,
}

/// The suite's names and `all`.
fn names(names: &[&'static str]) -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(names.iter().copied().chain(["all"]))
}

fn parse(args: &ReportArgs) -> Result<ReportOptions, String> {
    if !(args.dt > 0.0 && args.dt <= 0.1) {
        return Err(format!("--dt {}: expected 0 < dt <= 0.1", args.dt));
    }
    Ok(ReportOptions {
        runs: args.runs,
        seed: args.seed,
        dt: args.dt,
        limits: match args.limits {
            LimitsArg::Random => vec![LimitSet::Random],
            LimitsArg::Paper => vec![LimitSet::Paper],
            LimitsArg::Both => vec![LimitSet::Random, LimitSet::Paper],
        },
        evaders: match args.evader.as_deref() {
            None => vec![None],
            Some("all") => EvaderKind::ALL.into_iter().map(Some).collect(),
            Some(name) => vec![EvaderKind::from_name(name)],
        },
        pursuers: match args.pursuer.as_deref() {
            None => Vec::new(),
            Some("all") => PursuerKind::ALL.to_vec(),
            Some(name) => PursuerKind::ALL
                .into_iter()
                .filter(|p| p.name() == name)
                .collect(),
        },
    })
}

/// `cargo xtask report [--runs N] [--seed S] [--dt S] [--limits ..] [--evader ..] [--pursuer ..]`.
pub fn command(args: &ReportArgs) -> i32 {
    if args.field {
        let evaders = match args.evader.as_deref() {
            None | Some("all") => EvaderKind::FIELD.to_vec(),
            Some(name) => EvaderKind::from_name(name).into_iter().collect(),
        };
        let sparse = match args.fixes {
            FixesArg::All => None,
            FixesArg::Every => Some(false),
            FixesArg::Sparse => Some(true),
        };
        return super::field::command(
            args.runs,
            args.seed,
            args.dt,
            &evaders,
            args.own_lead,
            sparse,
        );
    }
    let o = match parse(args) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("xtask report: {e}");
            return 2;
        }
    };
    if let Some(n) = args.team {
        return super::team::command(&super::team::TeamReport {
            n,
            runs: o.runs,
            seed: o.seed,
            dt: o.dt,
            sigma_rp: args.role_noise,
            teammate_lag: args.teammate_lag,
            sets: &o.limits,
        });
    }
    let started = std::time::Instant::now();
    println!(
        "# Closed-loop Monte Carlo: {} seeded states per table row pair (seed {}), dt = {} s, eps = {EPS} m\n",
        o.runs, o.seed, o.dt
    );
    let sets = (o.evaders.len() + o.pursuers.len()) * o.limits.len();
    let progress = Progress::new((sets * o.runs) as u64, "closed-loop runs, 2 policies each");
    let mut total = against_evaders(&o, &progress);
    if !o.pursuers.is_empty() {
        total += against_pursuers(&o, &progress);
    }
    progress.finish();
    println!(
        "\n({total} states x 2 policies in {:.1} s on {} threads)",
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    0
}

/// The report's section on our pursuer against each evader and limit set, and its worst runs;
/// the number of runs.
fn against_evaders(o: &ReportOptions, progress: &Progress) -> usize {
    println!(
        "Late: capture + eps / (v_pm - v_em) more than {TOLERANCE_PERIODS} dt after the upper value at t = 0 \
         (the pursuer's guarantee), or never. Lateness = that time minus the upper value, over captured runs.\n"
    );
    println!("## Our pursuer against the evaders\n");
    println!("| evader | limits | regime | policy | runs | captured | never | late | lateness p50 / p90 / p99 / max (s) | sign flips p90 / max |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut worst = Vec::new();
    let mut total = 0;
    for &evader in &o.evaders {
        for &limit_set in &o.limits {
            let name = evader.map_or("law (both players)", EvaderKind::name);
            progress.step(&format!("evader {name}, {} limits", limit_set.name()));
            let opponent = evader.map(Opponent::Evader);
            let runs = monte_carlo(o.runs, o.seed, o.dt, limit_set, opponent, Some(progress));
            total += runs.len();
            print_evader(name, limit_set, &runs, &mut worst);
        }
    }
    println!("\nThe flight policy's runs never captured, or late from beyond the threshold (worst first, up to 3 per row pair):\n");
    if worst.is_empty() {
        println!("- none");
    }
    for line in &worst {
        println!("{line}");
    }
    total
}

/// The report's section on our evader against each pursuer and limit set; the number of runs.
fn against_pursuers(o: &ReportOptions, progress: &Progress) -> usize {
    println!("\n## Our evader against the pursuers\n");
    println!("Early: capture + eps / (v_pm - v_em) more than {TOLERANCE_PERIODS} dt before the lower value at t = 0 (the evader's guarantee).\n");
    println!("| pursuer | limits | regime | our policy | runs | captured | early | least margin over lower (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    let mut total = 0;
    for &pursuer in &o.pursuers {
        for &limit_set in &o.limits {
            progress.step(&format!(
                "pursuer {}, {} limits",
                pursuer.name(),
                limit_set.name()
            ));
            let opponent = Some(Opponent::Pursuer(pursuer));
            let runs = monte_carlo(o.runs, o.seed, o.dt, limit_set, opponent, Some(progress));
            total += runs.len();
            print_pursuer(pursuer.name(), limit_set, &runs);
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_monte_carlo_is_seeded_and_covers_both_regimes() {
        let a = monte_carlo(24, 7, 0.01, LimitSet::Random, None, None);
        let b = monte_carlo(24, 7, 0.01, LimitSet::Random, None, None);
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
