//! `cargo xtask report --team N`: `N` pursuers against one evader over seeded starts: the team
//! (`twocars::team`) beside each pursuer alone and beside the `N` flying their 1-on-1 flight
//! policies without roles, per evader (`twocars_sim::team`) and limit set; the team's roles
//! once more on states with position noise, to count how often they swap.

use rayon::prelude::*;
use twocars_sim::rng::Rng;
use twocars_sim::scenarios::PAPER_LIMITS;
use twocars_sim::starts::{random_limits, LimitSet};
use twocars_sim::stats::quantile_f64;
use twocars_sim::team::{chase, predicted, TeamEvader, TeamParams, TeamPursuit, TeamStart};

/// Capture radius, in the pursuers' least turning radius.
const EPS_RP: f64 = 0.1;

/// What `--team` measures: pursuers, starts per row, seed, period (s), the roles' noise
/// (standard deviation of each position, r_p), the limit sets.
pub struct TeamReport<'a> {
    pub n: usize,
    pub runs: usize,
    pub seed: u64,
    pub dt: f64,
    pub sigma_rp: f64,
    /// How late each vehicle hears its teammates' states, s.
    pub teammate_lag: f64,
    pub sets: &'a [LimitSet],
}

/// A start for `N`: the limit set's limits for every pursuer (`TeamStart::random`).
fn start<const N: usize>(rng: &mut Rng, set: LimitSet) -> TeamStart<N> {
    let limits = match set {
        LimitSet::Paper => PAPER_LIMITS,
        LimitSet::Random => random_limits(rng),
    };
    TeamStart::random(rng, limits)
}

/// One start's chases, capture times in s.
struct Chases {
    team: Option<f64>,
    independent: Option<f64>,
    best_alone: Option<f64>,
    /// The team's on noisy states: captured, and its pursuers' most role changes.
    noisy: Option<f64>,
    swaps: u32,
    /// Each vehicle's own roles, its teammates heard late: the share of periods they named
    /// different chasers, and the longest such stretch (s).
    apart: (f64, f64),
}

fn chases<const N: usize>(
    s: &TeamStart<N>,
    evader: TeamEvader,
    report: &TeamReport,
    seed: u64,
) -> Option<Chases> {
    let r_p = 1.0 / s.limits[0][1];
    // As long as the single-pursuer report gives a start: three times the prediction, and 30 s.
    let exact = TeamParams {
        dt: report.dt,
        t_max: 3.0 * predicted(s)?.max(1.0) + 30.0,
        eps: EPS_RP * r_p,
        sigma: 0.0,
        seed,
        teammate_lag: None,
    };
    let captured = |pursuit, params| Some(chase(s, pursuit, evader, params)?.captured);
    let mut best_alone: Option<f64> = None;
    for i in 0..N {
        if let Some(t) = captured(TeamPursuit::Alone(i), exact)? {
            best_alone = Some(best_alone.map_or(t, |b| b.min(t)));
        }
    }
    let noisy_params = TeamParams {
        sigma: report.sigma_rp * r_p,
        teammate_lag: Some(report.teammate_lag),
        ..exact
    };
    let noisy = chase(s, TeamPursuit::Team, evader, noisy_params)?;
    Some(Chases {
        team: captured(TeamPursuit::Team, exact)?,
        independent: captured(TeamPursuit::Independent, exact)?,
        best_alone,
        noisy: noisy.captured,
        swaps: noisy.swaps.into_iter().max().unwrap_or(0),
        apart: noisy.disagreement.unwrap_or((0.0, 0.0)),
    })
}

/// p50 / p90 of the captured times, s.
fn quantiles(times: impl Iterator<Item = Option<f64>>) -> String {
    let mut v: Vec<f64> = times.flatten().collect();
    v.sort_by(f64::total_cmp);
    match v.is_empty() {
        true => "- / -".to_string(),
        false => format!(
            "{:.2} / {:.2}",
            quantile_f64(&v, 0.5),
            quantile_f64(&v, 0.9)
        ),
    }
}

/// The share of starts where the team captures no later than the best single pursuer alone
/// (within 1.5 periods), %; and the worst excess, s.
fn at_or_below(all: &[Chases], dt: f64) -> (f64, f64) {
    let ok = all.iter().filter(|c| match (c.team, c.best_alone) {
        (Some(t), Some(a)) => t <= a + 1.5 * dt,
        (Some(_), None) => true,
        (None, _) => false,
    });
    let worst = all
        .iter()
        .filter_map(|c| Some(c.team? - c.best_alone?))
        .fold(0.0, f64::max);
    (100.0 * ok.count() as f64 / all.len().max(1) as f64, worst)
}

/// The table rows of `N` pursuers: one per limit set and evader.
fn rows<const N: usize>(report: &TeamReport) {
    for &set in report.sets {
        for (evader, name) in TeamEvader::ALL {
            let all: Vec<Chases> = (0..report.runs)
                .into_par_iter()
                .filter_map(|k| {
                    let seed = report.seed + k as u64;
                    chases(&start::<N>(&mut Rng::new(seed), set), evader, report, seed)
                })
                .collect();
            let never = all.iter().filter(|c| c.team.is_none()).count();
            let never_noisy = all.iter().filter(|c| c.noisy.is_none()).count();
            let (share, worst) = at_or_below(&all, report.dt);
            let mut swaps: Vec<f64> = all.iter().map(|c| f64::from(c.swaps)).collect();
            swaps.sort_by(f64::total_cmp);
            let apart =
                100.0 * all.iter().map(|c| c.apart.0).sum::<f64>() / all.len().max(1) as f64;
            let longest = all.iter().map(|c| c.apart.1).fold(0.0, f64::max);
            println!(
                "| {N} | {} | {name} | {} | {never} / {never_noisy} | {share:.1} % | {worst:.2} | {} | {} | {} | {:.0} / {:.0} | {apart:.2} % / {longest:.2} |",
                set.name(),
                all.len(),
                quantiles(all.iter().map(|c| c.team)),
                quantiles(all.iter().map(|c| c.best_alone)),
                quantiles(all.iter().map(|c| c.independent)),
                quantile_f64(&swaps, 0.5),
                swaps.last().copied().unwrap_or(0.0),
            );
        }
    }
}

/// `cargo xtask report --team N`; the exit code.
pub fn command(report: &TeamReport) -> i32 {
    let started = std::time::Instant::now();
    println!(
        "# {} pursuers against one evader: {} seeded starts per row (seed {}), dt = {} s, capture within {EPS_RP} r_p, roles' noise {} r_p, teammates heard {} s late\n",
        report.n, report.runs, report.seed, report.dt, report.sigma_rp, report.teammate_lag
    );
    println!("| pursuers | limits | evader | starts | never: team / noisy | team <= best alone + 1.5 dt | worst excess (s) | team p50 / p90 (s) | best alone p50 / p90 (s) | independent p50 / p90 (s) | role swaps, noisy: p50 / max | vehicles' chasers apart: periods / longest (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    match report.n {
        2 => rows::<2>(report),
        3 => rows::<3>(report),
        4 => rows::<4>(report),
        8 => rows::<8>(report),
        n => {
            eprintln!("xtask report --team {n}: 2, 3, 4 or 8 pursuers");
            return 2;
        }
    }
    println!(
        "\n({:.1} s on {} threads)",
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    0
}
