//! `cargo xtask hj --play RUNS`: the value tables' pursuer (on the host) against
//! every evader of the adversary suite, from seeded starts below the theorem's threshold at the
//! paper's limits (or `--limits`), beside the flight policy. The tables are the limits' near
//! field ([`crate::image::tables::solve::nested_tables`], `--levels`); their pursuer takes the turn whose worst case
//! one step ahead has the least V (`hji::policy`), the paper's law beyond the
//! threshold. The last row's evader plays the reference tables (its turn whose best case for
//! the pursuer one step ahead has the largest V), where both players play V's game. The runs
//! capture at the tables' radius, and each capture is compared with V(x0), the time to capture
//! under optimal play by both sides, read from the reference tables
//! ([`crate::image::tables::sets::NEAR_FIELD_LEVELS`]) whatever `--levels` the pursuer plays: a coarser table's V
//! is off by its grid's error, and would judge its own captures by it. Below the table, each
//! run past 10 % is listed beside the earliest capture of its evader by the open-loop plans of
//! `--probe` ([`crate::commands::hj::probe::best_plan`]). `cargo xtask report` judges the same policies
//! by the paper's upper value instead, over both sides of the threshold
//! ([`crate::commands::report`]).

use hji::policy::{evader_curvature, pursuer_curvature, relative};
use hji::{table_set_bytes, Solution};
use rayon::prelude::*;
use twocars::value_tables::ValueTables;
use twocars::{Policy, Variant};
use twocars_sim::adversary::{Adversary, EvaderKind, Opponent};
use twocars_sim::rng::Rng;
use twocars_sim::sim::{
    simulate_with, theorem_threshold, Setup, SimParams, SimResult, SimStatus, Turn,
};
use twocars_sim::stats::quantile_f64;

use crate::commands::hj::reference::{capture_radius, table_value, DT};
use crate::commands::report::{random_state, Regime};
use twocars_sim::starts::LimitSet;

/// One start, played by both pursuers.
struct Play {
    /// The table's V(x0), s.
    v0: f64,
    /// The start: pursuer and evader (m, rad), and the seed of the suite's evader.
    states: [[f64; 3]; 2],
    adversary_seed: u64,
    flight: SimResult,
    /// The host's pursuer on the tables (f64), unless only the flight policy plays.
    table: Option<SimResult>,
    /// The firmware's `Guidance` with `Policy::Table` on the quantised tables (f32), likewise.
    firmware: Option<SimResult>,
}

impl Play {
    /// Capture time less V(x0) and 5 dt, as a fraction of V(x0) (infinity if never captured).
    fn over(&self, r: &SimResult) -> f64 {
        if r.status != SimStatus::Captured {
            return f64::INFINITY;
        }
        (r.t_capture - self.v0 - 5.0 * DT) / self.v0
    }

    /// The start in the tables' frame at `limits` (r_p, radians).
    fn start(&self, limits: [f64; 4]) -> (f64, f64, f64) {
        let [pursuer, evader] = self.states;
        relative(limits[1], pursuer, evader)
    }
}

/// Who plays the evader: one of the adversary suite, or the table's own evader (the turn whose
/// best case for the pursuer one solver step ahead has the largest V).
#[derive(Clone, Copy)]
enum Evader {
    Suite(EvaderKind),
    Table,
}

impl Evader {
    fn name(self) -> &'static str {
        match self {
            Evader::Suite(kind) => kind.name(),
            Evader::Table => "the table's evader",
        }
    }
}

/// `runs` seeded starts below the threshold of `limits` that the reference tables capture
/// from: each with V(x0) and its adversary's seed. Drawn at the paper's limits and their
/// distance scaled to the threshold of `limits`: the same seeded starts, in units of the
/// threshold (and, at the paper's limits, the very same).
fn near_starts(
    limits: [f64; 4],
    reference: &[Solution],
    runs: usize,
    seed: u64,
) -> Vec<(SimParams, f64, u64)> {
    let mut rng = Rng::new(seed);
    let mut starts = Vec::new();
    while starts.len() < runs {
        let (params, regime) = random_state(&mut rng, DT, LimitSet::Paper);
        let adversary_seed = rng.next_u64();
        if regime != Regime::Near {
            continue;
        }
        let scale = theorem_threshold(limits) / theorem_threshold(params.limits);
        let [x, y, theta] = params.evader;
        let params = SimParams {
            limits,
            evader: [x * scale, y * scale, theta],
            ..params
        };
        if let Some(v0) = table_value(reference, limits, params.pursuer, params.evader) {
            starts.push((params, v0, adversary_seed));
        }
    }
    starts
}

/// `runs` seeded starts below the threshold of `limits` (those the reference tables capture
/// from) against `evader`, the pursuer playing `tables`.
fn play(
    limits: [f64; 4],
    reference: &[Solution],
    tables: &[Solution],
    firmware: &'static ValueTables<'static>,
    evader: Evader,
    (runs, seed): (usize, u64),
    tables_play: bool,
) -> Vec<Play> {
    let starts = near_starts(limits, reference, runs, seed);
    let [_, w_pm, _, w_em] = limits;
    let table_evader = |p, e| evader_curvature(reference, [w_pm, w_em], p, e);
    starts
        .into_par_iter()
        .map(|(params, v0, adversary_seed)| {
            let params = SimParams {
                t_max: 3.0 * v0 + 30.0,
                eps: capture_radius(reference, limits),
                ..params
            };
            // The table's evader overrides the law's evader wherever the table has a turn.
            let (opponent, evader_turn): (_, Option<Turn<'_>>) = match evader {
                Evader::Suite(kind) => (Some((Opponent::Evader(kind), adversary_seed)), None),
                Evader::Table => (None, Some(&table_evader)),
            };
            let run = |pursuer_turn: Option<Turn<'_>>, policy, setup: Setup<'_>| {
                let setup = Setup {
                    opponent,
                    turns: [pursuer_turn, evader_turn],
                    ..setup
                };
                simulate_with::<f32>(&params, Variant::Paper, policy, false, setup)
            };
            // The flight policy is told the capture radius V(x0) is solved for, as a user
            // whose vehicle captures at a radius tells it.
            let told = Setup {
                capture_radius: true,
                ..Setup::default()
            };
            let in_flash = Setup {
                tables: Some(firmware),
                ..Setup::default()
            };
            let host_tables = |p, e| pursuer_curvature(tables, w_pm, p, e);
            Play {
                v0,
                states: [params.pursuer, params.evader],
                adversary_seed,
                flight: run(None, Policy::Flight, told),
                table: tables_play
                    .then(|| run(Some(&host_tables), Policy::Flight, Setup::default())),
                firmware: tables_play.then(|| run(None, Policy::Table, in_flash)),
            }
        })
        .collect()
}

fn percent(v: f64) -> String {
    if v.is_finite() {
        format!("{:+.1} %", 100.0 * v)
    } else {
        "never".to_string()
    }
}

/// One pursuer's captures over V(x0) from a set of runs (infinity where never captured).
#[derive(Default)]
struct Over(Vec<f64>);

impl Over {
    fn of(plays: &[&Play], pick: fn(&Play) -> Option<&SimResult>) -> Self {
        let mut over: Vec<f64> = plays
            .iter()
            .filter_map(|p| pick(p).map(|r| p.over(r)))
            .collect();
        over.sort_by(f64::total_cmp);
        Over(over)
    }

    fn past(&self, bar: f64) -> usize {
        self.0.iter().filter(|&&o| o > bar).count()
    }

    /// `p50, p90, p99, past 10 % (share), past 5 %, never` as a table's cells.
    fn cells(&self) -> String {
        let Over(over) = self;
        if over.is_empty() {
            return "-".to_string();
        }
        let never = over.iter().filter(|o| o.is_infinite()).count();
        let share = |n: usize| 100.0 * n as f64 / over.len() as f64;
        let (p10, p5) = (self.past(0.10), self.past(0.05));
        format!(
            "{}, {}, {} | {p10} ({:.2} %), {p5} | {never}",
            percent(quantile_f64(over, 0.5)),
            percent(quantile_f64(over, 0.9)),
            percent(quantile_f64(over, 0.99)),
            share(p10),
        )
    }
}

/// Solves the near field of `limits`, plays `runs` starts per evader from each of `seeds`,
/// prints the table over all of them; the exit code is 0 (the figures are a measurement, not a
/// test). With `tables_play` the tables' pursuers play beside the flight policy.
pub fn command(
    runs: usize,
    seeds: &[u64],
    levels: &[hji::Grid],
    limits: [f64; 4],
    tables_play: bool,
) -> i32 {
    use crate::image::tables::sets::{NEAR_FIELD_LEVELS, PLAYED, REFERENCE};
    use crate::image::tables::solve::nested_tables;
    let (reference, reference_how) = nested_tables(limits, &NEAR_FIELD_LEVELS, REFERENCE);
    let (tables, how) = if levels == NEAR_FIELD_LEVELS || !tables_play {
        (reference.clone(), reference_how.clone())
    } else {
        nested_tables(limits, levels, PLAYED)
    };
    // The firmware's reader of the same tables, quantised as they are written to flash.
    let bytes: &'static [u8] = Box::leak(table_set_bytes(&tables).into_boxed_slice());
    let firmware: &'static ValueTables<'static> = match ValueTables::parse(bytes) {
        Ok(set) => Box::leak(Box::new(set)),
        Err(e) => {
            eprintln!("xtask hj: the tables do not read back: {e:?}");
            return 1;
        }
    };
    let session = Session {
        limits,
        reference: &reference,
        tables: &tables,
        firmware,
        tables_play,
    };
    session.preamble(runs, seeds, &reference_how, &how, bytes.len());
    let evaders = EvaderKind::ALL
        .into_iter()
        .map(Evader::Suite)
        .chain([Evader::Table]);
    let mut late = Vec::new();
    let mut every: Vec<(u64, Play)> = Vec::new();
    for (k, evader) in evaders.enumerate() {
        let plays = session.plays(evader, k as u64, runs, seeds);
        println!(
            "| {} | {} |",
            evader.name(),
            row(&plays, limits, tables_play)
        );
        late.extend(session.late(evader, &plays));
        every.extend(plays);
    }
    println!("| every evader | {} |", row(&every, limits, tables_play));
    session.print_late(&late);
    0
}

/// What `--play` plays with: the limits, the reference tables V(x0) is read from, the tables
/// the pursuer plays (on the host, and as the firmware reads them), and whether they play.
struct Session<'a> {
    limits: [f64; 4],
    reference: &'a [Solution],
    tables: &'a [Solution],
    firmware: &'static ValueTables<'static>,
    tables_play: bool,
}

impl Session<'_> {
    /// The report's first lines: the set-up, what "over V" means, the table's header.
    fn preamble(&self, runs: usize, seeds: &[u64], reference_how: &str, how: &str, bytes: usize) {
        let grids = |tables: &[Solution]| -> String {
            let grids: Vec<String> = tables
                .iter()
                .map(|t| {
                    format!(
                        "{n} x {n} x {} over +-{} r_p",
                        t.grid.headings,
                        t.grid.half,
                        n = t.grid.n
                    )
                })
                .collect();
            grids.join(" in ")
        };
        let limits = self.limits;
        println!(
            "Limits {limits:?}, dt = {DT} s, eps = {} m (the tables'); V(x0) and the tables' evader from {} ({reference_how}). {runs} seeded starts per evader and seed below the threshold (seeds {seeds:?}), those the tables capture from.\n",
            capture_radius(self.tables, limits),
            grids(self.reference),
        );
        println!("Over V: (capture - V(x0) - 5 dt) / V(x0), as p50, p90, p99 | runs past +10 % (their share), past +5 % | never captured. The flight policy is `Policy::Flight`, the pursuer to fly, told the capture radius (`Guidance::with_capture_radius`).");
        if self.tables_play {
            println!("Beside it, the tables' pursuer ({}; {how}) on the host (f64) and in the firmware (`Policy::Table` on the tables as the firmware reads them: u16, f32, {bytes} B).", grids(self.tables));
        }
        println!();
        let header = if self.tables_play {
            "| evader | flight: p50, p90, p99 | past 10 %, 5 % | never | tables: p50, p90, p99 | past 10 %, 5 % | never | firmware: p50, p90, p99 | past 10 %, 5 % | never | the tables' worst start: x, y (r_p), phi (rad), V(x0), seed |\n|---|---|---|---|---|---|---|---|---|---|---|"
        } else {
            "| evader | flight: p50, p90, p99 | past 10 %, 5 % | never | the flight policy's worst start: x, y (r_p), phi (rad), V(x0), seed |\n|---|---|---|---|---|"
        };
        println!("{header}");
    }

    /// `runs` starts from each of `seeds` against `evader`, the `k`-th of the suite (seed s
    /// plays it from the starts of s + k), each with its seed.
    fn plays(&self, evader: Evader, k: u64, runs: usize, seeds: &[u64]) -> Vec<(u64, Play)> {
        seeds
            .iter()
            .flat_map(|&seed| {
                let starts = seed.wrapping_add(k);
                play(
                    self.limits,
                    self.reference,
                    self.tables,
                    self.firmware,
                    evader,
                    (runs, starts),
                    self.tables_play,
                )
                .into_iter()
                .map(move |p| (seed, p))
            })
            .collect()
    }

    /// The judged pursuer's runs past 10 % over V, each said in a line.
    fn late(&self, evader: Evader, plays: &[(u64, Play)]) -> Vec<String> {
        let judged = |p: &Play| {
            if self.tables_play {
                p.table.as_ref().map_or(0.0, |r| p.over(r))
            } else {
                p.over(&p.flight)
            }
        };
        plays
            .iter()
            .filter(|(_, p)| judged(p).is_finite() && judged(p) > 0.10)
            .map(|(seed, p)| {
                if self.tables_play {
                    beside_best_plan(self.limits, self.reference, evader, *seed, p, judged(p))
                } else {
                    late_run(self.limits, evader, *seed, p, judged(p))
                }
            })
            .collect()
    }

    /// The list of `late` runs, if any.
    fn print_late(&self, late: &[String]) {
        if late.is_empty() {
            return;
        }
        println!(
            "\nThe {} runs past 10 %{}:\n",
            if self.tables_play {
                "tables' pursuer's"
            } else {
                "flight policy's"
            },
            if self.tables_play {
                format!(", each beside the earliest capture of the same evader by the probe's {} open-loop plans (`--probe`; where no plan beats the pursuer, V(x0) is below what that evader allows)", crate::commands::hj::probe::PLANS)
            } else {
                String::new()
            }
        );
        for line in late {
            println!("- {line}");
        }
    }
}

/// A table row's cells after the evader's name: each pursuer's figures over `plays`, then the
/// judged pursuer's worst start.
fn row(plays: &[(u64, Play)], limits: [f64; 4], tables_play: bool) -> String {
    let all: Vec<&Play> = plays.iter().map(|(_, p)| p).collect();
    let flight = Over::of(&all, |p| Some(&p.flight));
    let worst_of = |pick: fn(&Play) -> Option<&SimResult>| {
        plays
            .iter()
            .filter_map(|(seed, p)| pick(p).map(|r| (seed, p, p.over(r))))
            .max_by(|a, b| a.2.total_cmp(&b.2))
            .map(|(seed, p, _)| {
                let (x, y, phi) = p.start(limits);
                format!("({x:.2}, {y:.2}, {phi:.2}), {:.2} s, seed {seed}", p.v0)
            })
            .unwrap_or_default()
    };
    if tables_play {
        let table = Over::of(&all, |p| p.table.as_ref());
        let firmware = Over::of(&all, |p| p.firmware.as_ref());
        format!(
            "{} | {} | {} | {}",
            flight.cells(),
            table.cells(),
            firmware.cells(),
            worst_of(|p| p.table.as_ref())
        )
    } else {
        format!("{} | {}", flight.cells(), worst_of(|p| Some(&p.flight)))
    }
}

/// A run past 10 %: its evader, start, V(x0) and capture.
fn late_run(limits: [f64; 4], evader: Evader, seed: u64, p: &Play, over: f64) -> String {
    let (x, y, phi) = p.start(limits);
    format!(
        "{} from ({x:.2}, {y:.2}, {phi:.2}) r_p, seed {seed}, adversary seed {}: V(x0) {:.2} s, captured at {:.2} s ({})",
        evader.name(),
        p.adversary_seed,
        p.v0,
        p.flight.t_capture,
        percent(over),
    )
}

/// A run past 10 % beside the earliest capture of the same evader (the same seed) by the
/// probe's open-loop plans, each run as the play ran it, from the same start.
fn beside_best_plan(
    limits: [f64; 4],
    reference: &[Solution],
    evader: Evader,
    seed: u64,
    p: &Play,
    over: f64,
) -> String {
    let [_, w_pm, v_em, w_em] = limits;
    let eps = capture_radius(reference, limits);
    let maker = || -> crate::commands::hj::probe::EvaderRun<'_> {
        match evader {
            Evader::Suite(kind) => {
                let opponent = Opponent::Evader(kind);
                match Adversary::new(opponent, limits, DT, eps, p.adversary_seed) {
                    Some(mut adversary) => Box::new(move |t, pu, ev| adversary.command(t, pu, ev)),
                    None => Box::new(|_, _, _| (0.0, v_em)),
                }
            }
            Evader::Table => Box::new(move |_, pu, ev| {
                let w = evader_curvature(reference, [w_pm, w_em], pu, ev).unwrap_or(0.0);
                (w, v_em)
            }),
        }
    };
    let capture = p.v0 * (1.0 + over) + 5.0 * DT;
    let (best, _) =
        crate::commands::hj::probe::best_plan(limits, eps, p.states, capture + DT, &maker);
    let (x, y, phi) = p.start(limits);
    let best = if best.is_finite() {
        format!(
            "the best plan {best:.2} s ({})",
            percent((best - p.v0 - 5.0 * DT) / p.v0)
        )
    } else {
        "no plan earlier".to_string()
    };
    format!(
        "{} from ({x:.2}, {y:.2}, {phi:.2}) r_p, seed {seed}: V(x0) {:.2} s, captured at {capture:.2} s ({}); {best}",
        evader.name(),
        p.v0,
        percent(over),
    )
}
