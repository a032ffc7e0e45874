//! `cargo xtask hj`: the game's value function V by value iteration on the Hamilton-Jacobi-
//! Isaacs grid (`hji`), and its validation against what is known exactly: the tail
//! chase, V = (d - eps) / (v_pm - v_em), on three grid sizes with the observed order of
//! convergence. With `--table FILE` it solves one grid and writes it as the firmware's value
//! table (`twocars::value_tables::table`), read back: the tail chase, and where the box reaches the
//! theorem's threshold, V against the paper's upper value beyond it.

pub mod compare;
pub mod play;
pub mod probe;
pub mod reference;

use hji::paper::PaperValue;
use hji::{Game, Grid, Read, Solution, Sweeps, REACHED};
use twocars_sim::scenarios::states_beyond;

use crate::image::tables::sets::NEAR_FIELD_LEVELS;
use crate::image::tables::solve::{solve_grid, write_set, Boundary};

/// `cargo xtask hj`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct HjArgs {
    /// Limits v_pm,w_pm,v_em,w_em (m/s, 1/m, m/s, 1/m); default the paper's 2,2,1,1.
    #[arg(long, default_value = "2,2,1,1", value_parser = crate::util::workspace::numbers::<4>)]
    limits: [f64; 4],
    /// Capture radius, in units of r_p (the default a whole number of cells on each of the
    /// three default grids, so that each resolves the same disc on its axes).
    #[arg(long, default_value_t = 0.6)]
    eps: f64,
    /// Half the box's side, r_p.
    #[arg(long, default_value_t = 6.0)]
    half: f64,
    /// Position nodes per axis of the finest grid (odd); the coarser two have 3/4 and 1/2 of
    /// its intervals.
    #[arg(long, default_value_t = 81)]
    nodes: usize,
    /// Relative headings per turn on every grid (even); default about as many as position
    /// nodes span 2 pi r_p, at least 24.
    #[arg(long)]
    headings: Option<usize>,
    /// Sweeps stop once no value changes by more than this (r_p / v_pm) and none is new.
    #[arg(long, default_value_t = 1e-6)]
    tolerance: f64,
    /// Solve the finest grid only, as the tables a pursuer plays are solved (read trilinearly,
    /// the pursuer's three turns), and write it as the firmware's value table (u16 per node,
    /// `twocars::value_tables::table`) to this file.
    #[arg(long)]
    table: Option<std::path::PathBuf>,
    /// A step that leaves the box beyond the theorem's threshold lands on the paper's upper
    /// value there (less eps / (1 - a)), where the law has a saddle; elsewhere leaving the box
    /// counts as never captured.
    #[arg(long)]
    paper_boundary: bool,
    /// Instead of the validation: solve the near field of `--limits` and play this many seeded
    /// starts below the threshold per evader of the adversary suite, the table's pursuer
    /// beside the flight policy (`--eps`, `--half`, `--nodes` do not apply).
    #[arg(long)]
    play: Option<usize>,
    /// `--play`'s pursuers: the flight policy beside the tables' (`all`), or the flight
    /// policy alone (`flight`: no tables but the reference, the quick tier).
    #[arg(long, value_enum, default_value_t = PlayPursuers::All)]
    pursuers: PlayPursuers,
    /// Instead of the validation: solve the near field of `--limits` on `--levels`, capture
    /// radius one r_p, and write its nested tables to this file as the firmware reads them
    /// (`twocars::value_tables`); an image includes it with feature `tables-in-flash` and
    /// `TWOCARS_VALUE_TABLES=FILE`.
    #[arg(long)]
    set: Option<std::path::PathBuf>,
    /// Instead of the validation: one start X,Y,PHI (the evader in the pursuer's frame: r_p,
    /// r_p, rad) of `--limits`: V(x0) from the reference and from `--levels`, the `--levels`
    /// pursuer against the reference tables' evader, and the best open-loop pursuer of three
    /// turns against that evader.
    #[arg(long, value_parser = crate::util::workspace::numbers::<3>)]
    probe: Option<[f64; 3]>,
    /// Instead of the validation: solve `--nodes` (and `--headings`) with ours and with
    /// hj_reachability (installed on first use into target/hj-peer-venv from the Python
    /// package index) and print both solvers' time, memory, tail chase, agreement where V is
    /// smooth and the width of V's jumps.
    #[arg(long)]
    compare: bool,
    /// How the solver reads V between nodes, in the validation and `--compare`.
    #[arg(long, value_enum, default_value_t = HjRead::Filtered)]
    read: HjRead,
    /// How many turn rates the pursuer tries per step, evenly spaced over [-1, 1] (odd, at
    /// least 3), in the validation and `--compare`.
    #[arg(long, default_value_t = hji::TURNS)]
    turns: usize,
    /// Seed of `--play`'s starts.
    #[arg(long, default_value_t = 2019)]
    seed: u64,
    /// `--play` from this many seeds, `--seed` and each 1,000 past the last, its figures over
    /// all their starts (seed s plays its k-th evader from the starts of s + k, so consecutive
    /// seeds would share starts).
    #[arg(long, default_value_t = 1)]
    seeds: u64,
    /// `--play`'s and `--set`'s nested tables, coarsest first, as n:half:headings (nodes per axis, half the
    /// box in r_p, relative headings); default the near field's three.
    #[arg(long, value_parser = level, value_delimiter = ',')]
    levels: Vec<Grid>,
}

/// `--read`: how the solver reads V between nodes (`hji::Read`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum HjRead {
    /// Limited tricubic, filtered toward the trilinear where V bends: the default.
    Filtered,
    /// Limited tricubic.
    Cubic,
    /// Trilinear.
    Trilinear,
}

impl HjArgs {
    /// The solver's sweeps on `grid`: its step time, `--tolerance`, `--read` and `--turns`.
    fn sweeps(&self, grid: &Grid) -> Sweeps {
        let read = match self.read {
            HjRead::Filtered => Read::Filtered,
            HjRead::Cubic => Read::Cubic,
            HjRead::Trilinear => Read::Trilinear,
        };
        Sweeps {
            read,
            turns: self.turns,
            ..Sweeps::on(grid, self.tolerance)
        }
    }
}

/// Who chases in `--play`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlayPursuers {
    /// The flight policy, the tables' pursuer on the host and the firmware's.
    All,
    /// The flight policy alone.
    Flight,
}

/// Parses one of `--levels`' grids: `n:half:headings`.
pub(crate) fn level(text: &str) -> Result<Grid, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [n, half, headings] = parts[..] else {
        return Err(format!("{text}: expected n:half:headings"));
    };
    let bad = |e: &dyn std::fmt::Display| format!("{text}: {e}");
    let grid = Grid {
        n: n.parse().map_err(|e| bad(&e))?,
        half: half.parse().map_err(|e| bad(&e))?,
        headings: headings.parse().map_err(|e| bad(&e))?,
    };
    let valid = grid.n >= 5 && grid.n % 2 == 1 && grid.half > 0.0 && grid.headings >= 4;
    valid
        .then_some(grid)
        .ok_or_else(|| format!("{text}: n odd and at least 5, half positive, headings at least 4"))
}

/// The tail-chase distances checked, r_p: the evader dead ahead with the pursuer's heading.
const TAIL_CHASE: [f64; 4] = [1.0, 2.0, 3.0, 4.0];

/// The grid of `n` nodes per axis over `--half`, with `--headings` or its default: about as
/// many per turn as position nodes span 2 pi r_p, at least 24, and even (0 and pi are nodes:
/// the tail chase lies on one, and the mirror symmetry maps nodes to nodes).
fn grid_of(n: usize, args: &HjArgs) -> Grid {
    let per_turn = (n - 1) as f64 * std::f64::consts::PI / args.half;
    Grid {
        n,
        half: args.half,
        headings: args
            .headings
            .unwrap_or(2 * ((0.5 * per_turn).round().max(12.0) as usize)),
    }
}

fn run_grid(game: Game, n: usize, args: &HjArgs) -> (Solution, f64) {
    let grid = grid_of(n, args);
    solve_grid(game, grid, args.sweeps(&grid), boundary(args))
}

/// Where a step out of the box lands: `--paper-boundary`'s paper value, or never captured.
fn boundary(args: &HjArgs) -> Boundary<'static> {
    if args.paper_boundary {
        Boundary::Paper
    } else {
        Boundary::Never
    }
}

/// Runs the solver on three grids and prints the validation; returns the exit code.
pub fn command(args: &HjArgs) -> i32 {
    let levels = if args.levels.is_empty() {
        NEAR_FIELD_LEVELS.to_vec()
    } else {
        args.levels.clone()
    };
    if let Some(start) = args.probe {
        return probe::command(start, &levels, args.limits);
    }
    if let Some(runs) = args.play {
        let seeds: Vec<u64> = (0..args.seeds.max(1))
            .map(|i| args.seed.wrapping_add(1000 * i))
            .collect();
        let tables_play = args.pursuers == PlayPursuers::All;
        return play::command(runs, &seeds, &levels, args.limits, tables_play);
    }
    if let Some(path) = &args.set {
        return write_set(path, args.limits, &levels);
    }
    let game = Game::with_radius(args.limits, args.eps);
    if !(game.speed_ratio > 0.0 && game.speed_ratio < 1.0 && args.nodes >= 21 && args.eps > 0.0)
        || args.nodes % 4 != 1
        || args.headings.is_some_and(|h| h < 4 || h % 2 != 0)
        || args.turns < 3
        || args.turns.is_multiple_of(2)
    {
        eprintln!("xtask hj: need v_pm > v_em > 0, --eps > 0, --nodes >= 21 with nodes - 1 a multiple of 4, --headings even and at least 4, and --turns odd and at least 3");
        return 2;
    }
    println!(
        "# Hamilton-Jacobi-Isaacs value of the game of two cars\n\nv_em / v_pm = {:.4}, evader turn rate {:.4} rad per r_p / v_pm, capture radius {} r_p, box +-{} r_p; semi-Lagrangian value iteration, tau = half a cell at v_pm or {} r_p / v_pm, whichever is longer, a path into the disc within a step captured at its exact time of entry, the pursuer trying {} turn rates; V read between nodes {}, periodic in the relative heading; {} threads.\n",
        game.speed_ratio,
        game.evader_turn,
        game.eps,
        args.half,
        twocars::value_tables::table::MIN_STEP,
        args.turns,
        match args.read {
            HjRead::Filtered => "by a limited tricubic filtered toward the trilinear",
            HjRead::Cubic => "by a limited tricubic",
            HjRead::Trilinear => "trilinearly",
        },
        rayon::current_num_threads()
    );
    if let Some(path) = &args.table {
        return write_table(game, args, path);
    }
    if args.compare {
        let grid = grid_of(args.nodes, args);
        return compare::command(game, grid, args.sweeps(&grid));
    }
    validate(game, args)
}

/// The tail chase on three grids (half, three quarters and all of `--nodes`' intervals) against
/// its exact value, and the observed order of convergence; the exit code.
fn validate(game: Game, args: &HjArgs) -> i32 {
    println!("| grid | spacing (r_p) | sweeps | residual | solve time (s) | tail chase errors at d = 1, 2, 3, 4 r_p (r_p / v_pm) |");
    println!("|---|---|---|---|---|---|");
    let mut errors = Vec::new();
    let mut ok = true;
    let intervals = args.nodes - 1;
    for n in [intervals / 2 + 1, intervals * 3 / 4 + 1, args.nodes] {
        let (s, seconds) = run_grid(game, n, args);
        let e: Vec<f64> = TAIL_CHASE
            .iter()
            .map(|&d| s.value(d, 0.0, 0.0) - (d - game.eps) / (1.0 - game.speed_ratio))
            .collect();
        ok &= TAIL_CHASE.iter().all(|&d| s.value(d, 0.0, 0.0) < REACHED);
        println!(
            "| {n} x {n} x {} | {:.4} | {} | {:.1e} | {seconds:.1} | {} |",
            s.grid.headings,
            s.grid.spacing(),
            s.sweeps,
            s.residual,
            e.iter()
                .map(|v| format!("{v:+.4}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        errors.push((
            s.grid.spacing(),
            e.iter().fold(0.0f64, |m, v| m.max(v.abs())),
        ));
    }
    if let [(h0, e0), (h1, e1), (h2, e2)] = errors[..] {
        println!(
            "\nObserved order of convergence of the largest tail-chase error: {:.2} (coarse to middle), {:.2} (middle to fine).",
            (e0 / e1).ln() / (h0 / h1).ln(),
            (e1 / e2).ln() / (h1 / h2).ln()
        );
    }
    i32::from(!ok)
}

/// Solves the finest grid and writes its table to `path`; read back through the firmware's
/// reader, its tail chase is printed beside the exact value.
fn write_table(game: Game, args: &HjArgs, path: &std::path::Path) -> i32 {
    // Solved as the tables a pursuer plays are: read trilinearly, with the players' turns.
    let grid = grid_of(args.nodes, args);
    let played = crate::image::tables::sets::PLAYED;
    let sweeps = Sweeps {
        read: played.read,
        turns: played.turns,
        ..args.sweeps(&grid)
    };
    let (s, seconds) = solve_grid(game, grid, sweeps, boundary(args));
    let bytes = s.table_bytes();
    if let Err(e) = std::fs::write(path, &bytes) {
        eprintln!("xtask hj: {}: {e}", path.display());
        return 1;
    }
    let Ok(table) = twocars::value_tables::table::ValueTable::parse(&bytes) else {
        eprintln!("xtask hj: the table written does not parse");
        return 1;
    };
    println!(
        "wrote {}: {} B ({} x {} x {} nodes, u16, {:.2e} r_p / v_pm per code, times above {:.1} kept as never); {} sweeps, residual {:.1e}, {seconds:.1} s",
        path.display(),
        bytes.len(),
        s.grid.n,
        s.grid.n,
        s.grid.headings,
        table.scale,
        s.longest_kept(),
        s.sweeps,
        s.residual
    );
    for d in TAIL_CHASE {
        let exact = (d - game.eps) / (1.0 - game.speed_ratio);
        let read = table.value(d as f32, 0.0, 0.0).map_or(f64::NAN, f64::from);
        println!("  tail chase at d = {d} r_p: table {read:.4}, exact {exact:.4}");
    }
    threshold_comparison(game, &table);
    0
}

/// Beyond the theorem's threshold, where the paper's law has a saddle, V is the paper's upper
/// value (plus the capture radius's closing time eps / (1 - a), the law's capture being a
/// point's): prints V - that over seeded states 0 to 2 r_p beyond the threshold, where the box
/// reaches them.
fn threshold_comparison(game: Game, table: &twocars::value_tables::table::ValueTable<'_>) {
    let Some(paper) = PaperValue::of(game) else {
        return;
    };
    let threshold = paper.threshold;
    let far = (threshold + 2.0).min(0.95 * f64::from(table.half));
    if far <= threshold {
        println!(
            "  the theorem's threshold, {threshold:.2} r_p, is beyond the box: no comparison with the paper's value"
        );
        return;
    }
    let (gaps, refused) = paper.gaps(states_beyond(threshold, far), |x, y, phi| {
        table.value(x as f32, y as f32, phi as f32).map(f64::from)
    });
    let relative = gaps
        .iter()
        .fold(0.0f64, |m, (gap, paper)| m.max((gap / paper).abs()));
    let mut gaps: Vec<f64> = gaps.into_iter().map(|(gap, _)| gap).collect();
    gaps.sort_by(f64::total_cmp);
    if let (Some(first), Some(last)) = (gaps.first(), gaps.last()) {
        println!(
            "  beyond the threshold ({threshold:.2} to {far:.2} r_p), {} states with a saddle: V + eps / (1 - a) - upper value: min {first:+.3}, median {:+.3}, max {last:+.3} r_p / v_pm (largest {:.2} % of the value); {refused} without a value",
            gaps.len(),
            gaps[gaps.len() / 2],
            100.0 * relative,
        );
    }
}
