//! Solving the game's value tables: the near field's nested tables, the sets the images carry,
//! and the cache in `target/hj-cache/` stamped with the solver's sources.

use std::time::Instant;

use hji::paper::PaperValue;
use hji::{solve_with_boundary, Game, Grid, Solution, Sweeps, NEVER};

use crate::image::tables::sets::{FlashSet, SolvedBy, PLAYED};
use crate::util::progress::Progress;

/// The game of `limits` (v_pm, w_pm, v_em, w_em) over its near field as nested tables
/// (`hji::policy`) on `levels`, coarsest first; returned finest first. Capture
/// radius one r_p (0.5 m at the paper's limits). The coarsest table lands on the paper's value
/// beyond the threshold, each finer one on the table before it; each is solved to a residual
/// of 1e-4 as `by` says, or read back from `target/hj-cache/` where the same
/// solver sources solved it; with how.
pub(crate) fn nested_tables(
    limits: [f64; 4],
    levels: &[Grid],
    by: SolvedBy,
) -> (Vec<Solution>, String) {
    let game = Game::with_radius(limits, 1.0);
    let started = Instant::now();
    let mut tables: Vec<Solution> = Vec::new();
    let mut hows = Vec::new();
    let [v_pm, w_pm, v_em, w_em] = limits;
    let mut name = format!("{v_pm}-{w_pm}-{v_em}-{w_em}-{:?}-{}", by.read, by.turns);
    let sweeps = |grid: &Grid| Sweeps {
        read: by.read,
        turns: by.turns,
        ..Sweeps::on(grid, 1e-4)
    };
    for &grid in levels {
        // The cache's name: the limits, this grid and every coarser one its boundary came from.
        name.push_str(&format!("_{}-{}-{}", grid.n, grid.half, grid.headings));
        let (table, how) = cached(game, grid, &name, |grid| match tables.last() {
            Some(coarser) => solve_grid(game, grid, sweeps(&grid), Boundary::Table(coarser)),
            None => solve_grid(game, grid, sweeps(&grid), Boundary::Paper),
        });
        hows.push(format!("+-{} r_p {how}", grid.half));
        tables.push(table);
    }
    tables.reverse();
    let how = format!(
        "{}; {:.0} s",
        hows.join(", "),
        started.elapsed().as_secs_f64()
    );
    (tables, how)
}

/// The files of `sets`, solved (or read from the cache) and written to `target/value-tables/`
/// (rewritten only where the bytes changed, so an image is not rebuilt for nothing).
pub(crate) fn flash_sets(sets: &[FlashSet]) -> Result<Vec<std::path::PathBuf>, String> {
    let dir = crate::util::workspace::target_dir().join("value-tables");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut paths = Vec::new();
    for set in sets {
        let (tables, how) = nested_tables(set.limits, &set.levels, PLAYED);
        let bytes = hji::table_set_bytes(&tables);
        let [v_pm, w_pm, v_em, w_em] = set.limits;
        let path = dir.join(format!("{v_pm}-{w_pm}-{v_em}-{w_em}.tcv"));
        if std::fs::read(&path).ok().as_deref() != Some(bytes.as_slice()) {
            std::fs::write(&path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        println!(
            "xtask: value tables {}: {} B ({how})",
            path.display(),
            bytes.len()
        );
        paths.push(path);
    }
    Ok(paths)
}

/// Writes the near field of `limits` on `levels` (coarsest first) to `path` as nested tables;
/// prints each table's bytes. The exit code.
pub(crate) fn write_set(path: &std::path::Path, limits: [f64; 4], levels: &[Grid]) -> i32 {
    let threshold = Game::with_radius(limits, 1.0).threshold();
    if levels.first().is_none_or(|g| g.half <= threshold) {
        eprintln!(
            "xtask hj: the coarsest table must reach beyond the threshold, {threshold:.1} r_p"
        );
        return 2;
    }
    let (tables, how) = nested_tables(limits, levels, PLAYED);
    let bytes = hji::table_set_bytes(&tables);
    if let Err(e) = std::fs::write(path, &bytes) {
        eprintln!("xtask hj: {}: {e}", path.display());
        return 1;
    }
    println!(
        "wrote {}: {} B, finest first ({how}):",
        path.display(),
        bytes.len()
    );
    for t in &tables {
        println!(
            "  {n} x {n} x {} over +-{} r_p: {} B",
            t.grid.headings,
            t.grid.half,
            t.table_bytes().len(),
            n = t.grid.n
        );
    }
    0
}

/// The sources a solution depends on: the solver and its time step (`value_tables::table::step_time`),
/// its boundaries (the paper's value comes from the law) and this module's nesting of grids
/// (not `crate::image::tables::sets`, which only says which grids: the cache's file names say that).
const SOLVER_SOURCES: [&str; 9] = [
    include_str!("../../../../hji/src/lib.rs"),
    include_str!("../../../../hji/src/grid.rs"),
    include_str!("../../../../hji/src/read.rs"),
    include_str!("../../../../src/value_tables/table.rs"),
    include_str!("../../../../hji/src/paper.rs"),
    include_str!("solve.rs"),
    include_str!("../../../../src/law/mod.rs"),
    include_str!("../../../../src/law/game.rs"),
    include_str!("../../../../src/law/geometry.rs"),
];

/// The cache's stamp: a hash of [`SOLVER_SOURCES`], so that a change to the solver solves
/// again and any other rebuild of xtask reads the cache (never 0, which reads as no stamp).
fn solver_stamp() -> u128 {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    SOLVER_SOURCES.hash(&mut hasher);
    u128::from(hasher.finish()) | 1
}

/// The machine's cache of solutions, beside the checkout's: `$XDG_CACHE_HOME/twocars/hj-cache`
/// (or `~/.cache/...`), so that a fresh clone on the same machine (CI's) does not solve again
/// what the same solver sources solved before. `None` without a home.
fn machine_cache() -> Option<std::path::PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| std::path::Path::new(&h).join(".cache")))?;
    Some(base.join("twocars/hj-cache"))
}

/// `solve(grid)`, or its solution read back from `target/hj-cache/NAME.bin` or the machine's
/// cache where the same solver sources wrote it; with how.
fn cached(
    game: Game,
    grid: Grid,
    name: &str,
    solve: impl FnOnce(Grid) -> (Solution, f64),
) -> (Solution, String) {
    let file = format!("near-field-{name}.bin");
    let caches: Vec<std::path::PathBuf> = [
        Some(crate::util::workspace::target_dir().join("hj-cache")),
        machine_cache(),
    ]
    .into_iter()
    .flatten()
    .map(|dir| dir.join(&file))
    .collect();
    let stamp = solver_stamp();
    for cache in &caches {
        if let Some(solution) = read_cache(cache, stamp, game, grid) {
            for other in caches.iter().filter(|c| *c != cache) {
                if read_cache(other, stamp, game, grid).is_none() {
                    write_cache(other, stamp, &solution);
                }
            }
            return (solution, format!("read from {}", cache.display()));
        }
    }
    let (solution, seconds) = solve(grid);
    for cache in &caches {
        write_cache(cache, stamp, &solution);
    }
    let how = format!(
        "{} sweeps in {seconds:.0} s, residual {:.1e}",
        solution.sweeps, solution.residual
    );
    (solution, how)
}

/// The cache's layout: the stamp (u128), sweeps (u64), residual (f64), then each node's V
/// (f64), all little-endian.
fn read_cache(path: &std::path::Path, stamp: u128, game: Game, grid: Grid) -> Option<Solution> {
    let bytes = std::fs::read(path).ok()?;
    let (head, body) = bytes.split_at_checked(32)?;
    let field = |at: usize| -> Option<[u8; 8]> { head.get(at..at + 8)?.try_into().ok() };
    let written = u128::from_le_bytes(head.get(..16)?.try_into().ok()?);
    let values: Vec<f64> = body
        .chunks_exact(8)
        .filter_map(|c| Some(f64::from_le_bytes(c.try_into().ok()?)))
        .collect();
    if written != stamp || stamp == 0 || values.len() != grid.n * grid.n * grid.headings {
        return None;
    }
    Some(Solution {
        game,
        grid,
        values,
        tau: grid.step_time(),
        sweeps: u64::from_le_bytes(field(16)?) as usize,
        residual: f64::from_le_bytes(field(24)?),
        newly_finite: 0,
    })
}

fn write_cache(path: &std::path::Path, stamp: u128, solution: &Solution) {
    let mut bytes = Vec::with_capacity(32 + 8 * solution.values.len());
    bytes.extend(stamp.to_le_bytes());
    bytes.extend((solution.sweeps as u64).to_le_bytes());
    bytes.extend(solution.residual.to_le_bytes());
    for v in &solution.values {
        bytes.extend(v.to_le_bytes());
    }
    // A cache that cannot be written only costs the next run its solve.
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let _ = std::fs::write(path, bytes);
}

/// Solves `game` on `grid` by `sweeps`, progress shown, a step out of the box landing on
/// `boundary`. The solution and the seconds taken.
pub(crate) fn solve_grid(
    game: Game,
    grid: Grid,
    sweeps: Sweeps,
    boundary: Boundary,
) -> (Solution, f64) {
    let progress = Progress::new(
        0,
        &format!(
            "sweeps on the {n} x {n} x {} grid",
            grid.headings,
            n = grid.n
        ),
    );
    let started = Instant::now();
    let report = |sweep: usize, residual: f64| {
        if sweep.is_multiple_of(25) {
            progress.step(&format!("sweep {sweep}, residual {residual:.2e}"));
        }
    };
    let solution = match (boundary, PaperValue::of(game)) {
        (Boundary::Paper, Some(paper)) => solve_with_boundary(
            game,
            grid,
            sweeps,
            |x, y, phi| paper.beyond_threshold(x, y, phi).unwrap_or(NEVER),
            report,
        ),
        (Boundary::Table(outer), _) => solve_with_boundary(
            game,
            grid,
            sweeps,
            |x, y, phi| outer.value(x, y, phi),
            report,
        ),
        _ => solve_with_boundary(game, grid, sweeps, |_, _, _| NEVER, report),
    };
    progress.finish();
    (solution, started.elapsed().as_secs_f64())
}

/// What a step out of the box lands on.
#[derive(Clone, Copy)]
pub(crate) enum Boundary<'a> {
    /// Never captured.
    Never,
    /// Beyond the theorem's threshold, the paper's upper value where the law has a saddle
    /// (less eps / (1 - a)); never captured elsewhere.
    Paper,
    /// A coarser table's value over a larger box.
    Table(&'a Solution),
}
