//! `cargo xtask plot`'s near-field figures: the game's value V, solved on the
//! Hamilton-Jacobi-Isaacs grid (`hji`), beside the paper's upper value on the same
//! axes; and the pursuer's optimal turn from V (`hji::policy`) beside the
//! paper law's pursuer circle. The paper's limits; pursuer at the origin heading +y, evader
//! heading +y.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use hji::policy::{holding, relative, turn};
use hji::{Game, Solution, REACHED};
use twocars::Direction;
use twocars_sim::scenarios::PAPER_LIMITS;

use crate::commands::plot::figure::{metres, ramp, Figure};
use crate::commands::plot::paper::paper_report;

/// Cells per axis of the maps, over the solver's box.
const CELLS: usize = 97;
/// Top of the colour scale, s.
const TOP_S: f64 = 24.0;

const LEFT: &str = "#4e79a7";
const RIGHT: &str = "#f28e2b";
const STRAIGHT: &str = "#ffffff";
const NONE: &str = "#cccccc";

/// One map cell: the evader's position (m), the paper's upper value (s) and pursuer turn
/// (+1 anticlockwise, -1 clockwise), the table's V (s, capture radius's closing included) and
/// optimal turn (curvature sign; `None` where the table gives none it can trust).
struct Cell {
    x: f64,
    y: f64,
    paper: Option<(f64, f64)>,
    table_v: Option<f64>,
    table_turn: Option<f64>,
}

/// The cells over the outermost of `tables` (finest first), each read from the finest table
/// whose box holds it (less two cells).
fn cells(tables: &[Solution], game: Game) -> Vec<Cell> {
    let outer = &tables[tables.len() - 1];
    let [v_pm, w_pm, ..] = PAPER_LIMITS;
    // V in r_p / v_pm to seconds; the paper's value is a point's capture: add eps's closing.
    let seconds = 1.0 / (w_pm * v_pm);
    let closing = game.eps / (1.0 - game.speed_ratio);
    let half_m = outer.grid.half / w_pm;
    let step = 2.0 * half_m / CELLS as f64;
    let pursuer = [0.0, 0.0, FRAC_PI_2];
    let mut out = Vec::with_capacity(CELLS * CELLS);
    for i in 0..CELLS {
        for j in 0..CELLS {
            let x = -half_m + (i as f64 + 0.5) * step;
            let y = -half_m + (j as f64 + 0.5) * step;
            let evader = [x, y, FRAC_PI_2];
            let paper = paper_report(pursuer, evader).and_then(|r| {
                let turn = match r.solution.row {
                    Direction::Anticlockwise => 1.0,
                    Direction::Clockwise => -1.0,
                };
                r.solution.upper.map(|u| (u, turn))
            });
            let (rx, ry, phi) = relative(w_pm, pursuer, evader);
            let table = holding(tables, rx, ry).unwrap_or(outer);
            let v = table.value(rx, ry, phi);
            out.push(Cell {
                x,
                y,
                paper,
                table_v: (v < REACHED).then_some((v + closing) * seconds),
                // The tables play inside the threshold (the paper's law beyond it).
                table_turn: turn(tables, (rx, ry, phi)).map(|(u, _)| u),
            });
        }
    }
    out
}

/// A map panel: cells coloured by `colour`, the pursuer, the threshold circle, axes.
fn panel(
    cells: &[Cell],
    half_m: f64,
    colour: impl Fn(&Cell) -> String,
    threshold_m: f64,
    title: &str,
) -> Figure {
    let step = 2.0 * half_m / CELLS as f64;
    let mut fig = Figure::equal(640.0, (0.0, 0.0), half_m);
    for c in cells {
        let (x0, y0) = (c.x - step / 2.0, c.y - step / 2.0);
        fig.cell(x0, y0, step, step, &colour(c));
    }
    fig.circle(0.0, 0.0, threshold_m, "black", "none", "6 4");
    fig.dot(0.0, 0.0, 5.0, "black");
    fig.polyline(&[(0.0, 0.0), (0.0, 1.5)], "black", 2.0, "none");
    fig.axes((5.0, 5.0), metres, ("evader x (m)", "evader y (m)"), title);
    fig
}

fn value_colour(v: Option<f64>) -> String {
    v.map_or_else(|| NONE.to_string(), |v| ramp(v / TOP_S))
}

fn turn_colour(t: Option<f64>) -> String {
    match t {
        Some(t) if t > 0.0 => LEFT.to_string(),
        Some(t) if t < 0.0 => RIGHT.to_string(),
        Some(_) => STRAIGHT.to_string(),
        None => NONE.to_string(),
    }
}

/// Solves the paper's game on the near-field grid and writes the two side-by-side figures.
pub(super) fn maps(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let (tables, how) = crate::image::tables::solve::nested_tables(
        PAPER_LIMITS,
        &crate::image::tables::sets::NEAR_FIELD_LEVELS,
        crate::image::tables::sets::REFERENCE,
    );
    let outer = &tables[tables.len() - 1];
    let game = outer.game;
    let half_m = outer.grid.half / PAPER_LIMITS[1];
    let threshold_m = game.threshold() / PAPER_LIMITS[1];
    let cells = cells(&tables, game);

    // Where both give a turn, how often they agree; and V against the paper's upper value
    // beyond the threshold (the theorem: equal there).
    let both: Vec<(f64, f64)> = cells
        .iter()
        .filter_map(|c| Some((c.paper?.1, c.table_turn.filter(|t| *t != 0.0)?)))
        .collect();
    let agree = both.iter().filter(|(p, t)| p == t).count();
    let grids: Vec<String> = tables
        .iter()
        .map(|t| {
            format!(
                "{n} x {n} x {} over +-{:.1} m",
                t.grid.headings,
                t.grid.half / PAPER_LIMITS[1],
                n = t.grid.n
            )
        })
        .collect();
    let solved = format!(
        "eps = {} m; tables, finest first:",
        game.eps / PAPER_LIMITS[1]
    );
    let mut value_legend: Vec<&str> = vec![&solved];
    value_legend.extend(grids.iter().map(String::as_str));
    value_legend.push("grey: not captured within the box");

    let (value_left, value_right) = value_panels(&cells, half_m, threshold_m, &value_legend);
    let agreement = format!(
        "agrees with the paper's circle in {agree} of {} cells where both turn ({:.1} %)",
        both.len(),
        100.0 * agree as f64 / both.len().max(1) as f64
    );
    let (turn_left, turn_right) = turn_panels(&cells, half_m, threshold_m, &agreement);
    println!(
        "near field: {solved} {} ({how}); the optimal turn {agreement}",
        grids.join(", ")
    );

    let a = dir.join("near-field-value.svg");
    let b = dir.join("near-field-turn.svg");
    Figure::save_side_by_side(&value_left, &value_right, &a).map_err(|e| e.to_string())?;
    Figure::save_side_by_side(&turn_left, &turn_right, &b).map_err(|e| e.to_string())?;
    Ok(vec![a, b])
}

/// The paper's upper value beside V, in seconds on one colour scale.
fn value_panels(
    cells: &[Cell],
    half_m: f64,
    threshold_m: f64,
    legend: &[&str],
) -> (Figure, Figure) {
    let mut value_left = panel(
        cells,
        half_m,
        |c| value_colour(c.paper.map(|p| p.0)),
        threshold_m,
        "The paper's upper value (s)",
    );
    value_left.colour_scale(TOP_S);
    value_left.legend(&["dashed: the theorem's threshold; grey: no finite value"]);
    let mut value_right = panel(
        cells,
        half_m,
        |c| value_colour(c.table_v),
        threshold_m,
        "The game's value V (s), Hamilton-Jacobi-Isaacs",
    );
    value_right.colour_scale(TOP_S);
    value_right.legend(legend);
    (value_left, value_right)
}

/// The paper law's pursuer circle beside the turn V's one-step minimax gives, with how often
/// they agree (`agreement`).
fn turn_panels(cells: &[Cell], half_m: f64, threshold_m: f64, agreement: &str) -> (Figure, Figure) {
    let mut turn_left = panel(
        cells,
        half_m,
        |c| turn_colour(c.paper.map(|p| p.1)),
        threshold_m,
        "The paper law's pursuer circle",
    );
    turn_left.legend(&["blue: anticlockwise (left), orange: clockwise (right)"]);
    let mut turn_right = panel(
        cells,
        half_m,
        |c| turn_colour(c.table_turn),
        threshold_m,
        "The pursuer's optimal turn from V (one step's minimax)",
    );
    turn_right.legend(&[
        "blue: left, orange: right, white: straight",
        "grey: the table does not play (capture disc, beyond the threshold)",
        agreement,
    ]);
    (turn_left, turn_right)
}
