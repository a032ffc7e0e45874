//! `cargo xtask report --field`: the flight policy against the evaders of the field's sweep
//! with late, sparse and noisy target fixes and a lagging pursuer, with and without the
//! estimator, each chase against the same start with exact, instant states and a pursuer that
//! turns as told.
//!
//! Every start is also chased by the peers a user would fly instead (`twocars_sim::peers`): PX4
//! follow-target's filter with proportional navigation, and ArduPilot AP_Follow's dead-reckoned
//! pure pursuit, each at every value of its own parameter's sweep; a row reports each peer at
//! the value whose p90 is least there.
//!
//! The grid (in the pursuer's full turn T = 2 pi / (v_pm w_pm) and r_p = 1 / w_pm): lag
//! {0, 0.1, 0.2} T, position noise sigma {0, 0.1, 0.2} r_p with heading noise sigma / 1 m rad,
//! fixes at every period or 5 per T; the pursuer's yaw-rate lag tau = 0.1 T, the capture radius
//! 0.3 r_p; the paper's limits and 2, 2, 1.2, 1.2.

use rayon::prelude::*;
use twocars_sim::adversary::EvaderKind;
use twocars_sim::field::{chase, FieldModel, Receiver};
use twocars_sim::peers::Peer;
use twocars_sim::rng::Rng;
use twocars_sim::sim::{theorem_threshold, SimParams, SimResult, SimStatus};
use twocars_sim::starts::random_start;
use twocars_sim::stats::quantile_f64;

use crate::util::progress::Progress;

/// The limit sets of the sweep: (v_pm, w_pm, v_em, w_em).
pub const LIMIT_SETS: [[f64; 4]; 2] = [[2.0, 2.0, 1.0, 1.0], [2.0, 2.0, 1.2, 1.2]];
/// The capture radius, r_p.
const CAPTURE_RADII: f64 = 0.3;
/// The pursuer's yaw-rate lag, full turns.
const YAW_LAG_TURNS: f64 = 0.1;

/// One cell of the grid, in the pursuer's full turns and radii.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// Transport lag, full turns.
    pub lag_turns: f64,
    /// Position noise, r_p.
    pub sigma_radii: f64,
    /// Fixes per full turn; `None`: every period.
    pub fixes_per_turn: Option<f64>,
}

impl Cell {
    /// The field this cell makes at `limits`, seeded by `seed`.
    pub fn model(&self, limits: [f64; 4], seed: u64) -> FieldModel {
        let [v_pm, w_pm, _, _] = limits;
        let turn = std::f64::consts::TAU / (v_pm * w_pm);
        let sigma = self.sigma_radii / w_pm;
        FieldModel {
            lag: self.lag_turns * turn,
            fix_interval: self.fixes_per_turn.map_or(0.0, |n| turn / n),
            position_sigma: sigma,
            heading_sigma: sigma,
            dropout: 0.0,
            yaw_lag: YAW_LAG_TURNS * turn,
            seed,
        }
    }

    /// The cells of the sweep.
    pub fn grid() -> Vec<Cell> {
        let mut cells = Vec::new();
        for fixes_per_turn in [None, Some(5.0)] {
            for lag_turns in [0.0, 0.1, 0.2] {
                for sigma_radii in [0.0, 0.1, 0.2] {
                    cells.push(Cell {
                        lag_turns,
                        sigma_radii,
                        fixes_per_turn,
                    });
                }
            }
        }
        cells
    }

    /// The bound on p90 of the excess: +10 % where lag <= 0.1 T and sigma <= 0.1 r_p,
    /// +25 % elsewhere.
    pub fn bound(&self) -> f64 {
        if self.lag_turns <= 0.1 && self.sigma_radii <= 0.1 {
            0.10
        } else {
            0.25
        }
    }
}

/// A seeded start at `limits`: d0 uniform in [2 r_p, 1.5 threshold], bearing and headings
/// uniform.
fn start(rng: &mut Rng, limits: [f64; 4], dt: f64) -> SimParams {
    let r_p = 1.0 / limits[1];
    let d0 = rng.uniform(2.0 * r_p, 1.5 * theorem_threshold(limits));
    random_start(rng, limits, d0, dt, CAPTURE_RADII * r_p)
}

/// The peers' sweeps at `limits`: each peer at each value of its parameter.
pub fn peer_sweeps(limits: [f64; 4]) -> [Vec<Peer>; 2] {
    let turn = std::f64::consts::TAU / (limits[0] * limits[1]);
    [
        Peer::TEXTBOOK_SWEEP
            .iter()
            .map(|&responsiveness| Peer::Textbook { responsiveness })
            .collect(),
        Peer::FOLLOW_SWEEP_TURNS
            .iter()
            .map(|&turns| Peer::Follow { lead: turns * turn })
            .collect(),
    ]
}

/// One start's chases: ideal, exact, through the raw fixes, through the estimator, and the
/// peers'.
pub struct Chases {
    /// Exact, instant states; the pursuer turns as told.
    pub ideal: SimResult,
    /// Exact, instant states; the pursuer's turn lags as in the field.
    pub exact: SimResult,
    /// The field's fixes as they came.
    pub raw: SimResult,
    /// The field's fixes through the estimator.
    pub estimated: SimResult,
    /// Each peer's chases, one per value of its sweep ([`peer_sweeps`]).
    pub peers: [Vec<SimResult>; 2],
}

impl Chases {
    /// The excess of `r` over `base`, as a fraction; infinite if never captured.
    pub fn excess(r: &SimResult, base: &SimResult) -> f64 {
        if r.status != SimStatus::Captured {
            return f64::INFINITY;
        }
        (r.t_capture - base.t_capture) / base.t_capture
    }
}

/// `runs` seeded starts of one evader in one cell at `limits`, three chases each.
pub fn sweep(
    cell: &Cell,
    limits: [f64; 4],
    evader: EvaderKind,
    runs: usize,
    seed: u64,
    dt: f64,
    own_lead_taus: f64,
) -> Vec<Chases> {
    let mut rng = Rng::new(seed);
    let starts: Vec<(SimParams, u64, u64)> = (0..runs)
        .map(|_| (start(&mut rng, limits, dt), rng.next_u64(), rng.next_u64()))
        .collect();
    starts
        .into_par_iter()
        .filter_map(|(params, evader_seed, field_seed)| {
            let field = cell.model(limits, field_seed);
            let long = SimParams {
                t_max: 120.0,
                ..params
            };
            let ideal = chase(
                &long,
                evader,
                evader_seed,
                &FieldModel::EXACT,
                Receiver::Raw,
            );
            let lagging = FieldModel {
                yaw_lag: field.yaw_lag,
                ..FieldModel::EXACT
            };
            let exact = chase(&long, evader, evader_seed, &lagging, Receiver::Raw);
            if exact.status != SimStatus::Captured || ideal.status != SimStatus::Captured {
                return None;
            }
            let params = SimParams {
                t_max: 4.0 * exact.t_capture + 30.0,
                ..params
            };
            let own_lead = own_lead_taus * field.yaw_lag;
            let peers = peer_sweeps(limits).map(|sweep| {
                sweep
                    .into_iter()
                    .map(|peer| chase(&params, evader, evader_seed, &field, peer))
                    .collect()
            });
            Some(Chases {
                peers,
                raw: chase(&params, evader, evader_seed, &field, Receiver::Raw),
                estimated: chase(
                    &params,
                    evader,
                    evader_seed,
                    &field,
                    Receiver::Estimator { own_lead },
                ),
                exact,
                ideal,
            })
        })
        .collect()
}

/// Which of a start's chases a figure reads.
pub type Pick = fn(&Chases) -> &SimResult;

/// The control period's cost (the paper's open question: what sampling does to optimality):
/// for each of `dts`, p90 over `runs` seeded starts of (capture at dt - capture at `base`) /
/// capture at `base`, exact states, the pursuer turning as told, against `evader`.
pub fn discretization(
    limits: [f64; 4],
    evader: EvaderKind,
    runs: usize,
    seed: u64,
    base: f64,
    dts: &[f64],
) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    let starts: Vec<(SimParams, u64)> = (0..runs)
        .map(|_| (start(&mut rng, limits, base), rng.next_u64()))
        .collect();
    let captured = |params: &SimParams, dt: f64, seed: u64| {
        let params = SimParams {
            dt,
            t_max: 120.0,
            ..*params
        };
        let r = chase(&params, evader, seed, &FieldModel::EXACT, Receiver::Raw);
        (r.status == SimStatus::Captured).then_some(r.t_capture)
    };
    dts.iter()
        .map(|&dt| {
            let mut excess: Vec<f64> = starts
                .par_iter()
                .filter_map(|(params, seed)| {
                    let at_base = captured(params, base, *seed)?;
                    Some(
                        captured(params, dt, *seed)
                            .map_or(f64::INFINITY, |t| (t - at_base) / at_base),
                    )
                })
                .collect();
            excess.sort_by(f64::total_cmp);
            quantile_f64(&excess, 0.9)
        })
        .collect()
}

/// Figures of one pursuer over a set of chases.
#[derive(Clone, Copy, Debug)]
pub struct Figures {
    /// Never captured.
    pub never: usize,
    /// p90 of the excess, fraction.
    pub p90: f64,
    /// p99 of the excess, fraction.
    pub p99: f64,
    /// Loops per chase, the mean.
    pub loops: f64,
    /// Share of chases past +10 %.
    pub past_10: f64,
    /// Median of the pursuer's sign flips.
    pub flips_p50: f64,
}

impl Figures {
    /// `pick`'s figures over `chases`, against `base`.
    pub fn of<F, B>(chases: &[Chases], pick: F, base: B) -> Self
    where
        F: for<'a> Fn(&'a Chases) -> &'a SimResult,
        B: for<'a> Fn(&'a Chases) -> &'a SimResult,
    {
        let mut excess: Vec<f64> = chases
            .iter()
            .map(|c| Chases::excess(pick(c), base(c)))
            .collect();
        excess.sort_by(f64::total_cmp);
        let mut flips: Vec<f64> = chases.iter().map(|c| pick(c).sign_flips as f64).collect();
        flips.sort_by(f64::total_cmp);
        Figures {
            never: chases
                .iter()
                .filter(|c| pick(c).status != SimStatus::Captured)
                .count(),
            p90: quantile_f64(&excess, 0.9),
            p99: quantile_f64(&excess, 0.99),
            loops: chases.iter().map(|c| pick(c).loops as f64).sum::<f64>()
                / chases.len().max(1) as f64,
            past_10: excess.iter().filter(|e| **e > 0.10).count() as f64
                / chases.len().max(1) as f64,
            flips_p50: quantile_f64(&flips, 0.5),
        }
    }

    /// Peer `index`'s figures at the value of its sweep whose p90 (then p99) is least, and
    /// that value's position in the sweep.
    pub fn best_peer(chases: &[Chases], index: usize) -> (usize, Self) {
        let values = chases.first().map_or(0, |c| c.peers[index].len());
        (0..values)
            .map(|i| (i, Figures::of(chases, |c| &c.peers[index][i], |c| &c.exact)))
            .min_by(|(_, a), (_, b)| a.p90.total_cmp(&b.p90).then(a.p99.total_cmp(&b.p99)))
            .unwrap_or((0, Figures::of(&[], |c| &c.exact, |c| &c.exact)))
    }

    /// Whether these figures meet `cell`'s bound: all captured, p90 within it, median flips
    /// at most 5.
    pub fn meets(&self, cell: &Cell) -> bool {
        self.never == 0 && self.p90 <= cell.bound() && self.flips_p50 <= 5.0
    }

    fn cell(&self) -> String {
        format!(
            "{:+.1} % / {:+.1} % / {:.0} % / {} / {:.0} / {:.2}",
            100.0 * self.p90,
            100.0 * self.p99,
            100.0 * self.past_10,
            self.never,
            self.flips_p50,
            self.loops
        )
    }
}

/// Which fixes a sweep covers: `None` for every cell, else only those with fixes every period
/// (`Some(false)`) or 5 per T (`Some(true)`).
pub type Sparse = Option<bool>;

/// What the sweep's rows add up to.
#[derive(Default)]
struct Tally {
    rows: usize,
    missed: usize,
    peer_ahead: usize,
    peer_meets_alone: usize,
    p99_storm: usize,
}

impl Tally {
    /// Counts one row: ours and the peers' best.
    fn add(&mut self, cell: &Cell, ours: &Figures, peers: &[Figures]) -> [bool; 3] {
        let met = ours.meets(cell);
        let ahead = peers.iter().any(|p| p.p90 < ours.p90 - 0.02);
        let best_p99 = peers.iter().map(|p| p.p99).fold(f64::INFINITY, f64::min);
        let storm = ours.p99 > 1.0 && ours.p99 > best_p99;
        self.rows += 1;
        self.missed += usize::from(!met);
        self.peer_ahead += usize::from(ahead);
        self.peer_meets_alone += usize::from(!met && peers.iter().any(|p| p.meets(cell)));
        self.p99_storm += usize::from(storm);
        [met, ahead, storm]
    }
}

/// Prints the sweep: one row per limit set, cell and evader.
pub fn command(
    runs: usize,
    seed: u64,
    dt: f64,
    evaders: &[EvaderKind],
    own_lead_taus: f64,
    sparse: Sparse,
) -> i32 {
    let started = std::time::Instant::now();
    let grid: Vec<Cell> = Cell::grid()
        .into_iter()
        .filter(|c| sparse.is_none_or(|s| s == c.fixes_per_turn.is_some()))
        .collect();
    println!(
        "# The field: {runs} seeded starts per row (seed {seed}), dt = {dt} s, capture radius \
         {CAPTURE_RADII} r_p, yaw-rate lag {YAW_LAG_TURNS} T, own lead {own_lead_taus} tau\n"
    );
    println!("Each figure: capture time over the same start with exact, instant states and the same lagging pursuer (exact states: over the pursuer that turns as told): p90 / p99 / share past +10 % / never captured / median sign flips / loops per chase of the pursuer. The peers: PX4 follow-target's filter with proportional navigation (textbook, responsiveness r) and AP_Follow's dead-reckoned pure pursuit (follow, lead in s), each at its sweep's value with the least p90.\n");
    println!("| limits | fixes | lag (T) | sigma (r_p) | evader | exact states | raw fixes | estimator | textbook | follow | bound | met | peer ahead by > 2 points |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let total = LIMIT_SETS.len() * grid.len() * evaders.len() * runs;
    let progress = Progress::new(total as u64, "field chases, 12 each");
    let mut tally = Tally::default();
    for limits in LIMIT_SETS {
        let sweeps = peer_sweeps(limits);
        for cell in &grid {
            for &evader in evaders {
                let chases = sweep(cell, limits, evader, runs, seed, dt, own_lead_taus);
                for _ in 0..runs {
                    progress.inc();
                }
                let exact: Pick = |c| &c.exact;
                let lagging = Figures::of(&chases, exact, |c| &c.ideal);
                let raw = Figures::of(&chases, |c| &c.raw, exact);
                let est = Figures::of(&chases, |c| &c.estimated, exact);
                let best = [0, 1].map(|i| Figures::best_peer(&chases, i));
                let peer = |i: usize| {
                    let (at, figures) = &best[i];
                    let value = sweeps[i].get(*at).map_or(String::new(), |p| p.parameter());
                    format!("{} ({value})", figures.cell())
                };
                let peers = [best[0].1, best[1].1];
                let [met, ahead, _] = tally.add(cell, &est, &peers);
                println!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | +{:.0} % | {} | {} |",
                    limits.map(|v| v.to_string()).join(", "),
                    cell.fixes_per_turn
                        .map_or("every period".to_string(), |n| format!("{n} per T")),
                    cell.lag_turns,
                    cell.sigma_radii,
                    evader.name(),
                    lagging.cell(),
                    raw.cell(),
                    est.cell(),
                    peer(0),
                    peer(1),
                    100.0 * cell.bound(),
                    if met { "yes" } else { "no" },
                    if ahead { "yes" } else { "no" },
                );
            }
        }
    }
    progress.finish();
    println!(
        "\n{} of {} rows miss their bound, {} of them where a peer meets it; a peer's p90 beats \
         ours by more than 2 points in {} rows; our p99 is past +100 % and worse than the best \
         peer's in {} rows ({:.1} s on {} threads)",
        tally.missed,
        tally.rows,
        tally.peer_meets_alone,
        tally.peer_ahead,
        tally.p99_storm,
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    0
}
