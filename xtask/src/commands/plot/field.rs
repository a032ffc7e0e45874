//! The field's figures (docs/field.md): the capture time's excess against the transport lag
//! and against the fixes' noise, per evader, through the estimator and for the peers (each at
//! its sweep's best value per point); and against the control period, the paper's open
//! question of what sampling does to optimality.

use std::path::{Path, PathBuf};

use twocars_sim::adversary::EvaderKind;

use super::figure::Figure;
use crate::commands::field::{discretization, sweep, Cell, Chases, Figures, Pick, LIMIT_SETS};

/// Seeded starts per point.
const RUNS: usize = 60;
/// The starts' seed.
const SEED: u64 = 2019;
/// The evaders drawn, with their colours.
const EVADERS: [(EvaderKind, &str); 5] = [
    (EvaderKind::Law, "#1f5fbf"),
    (EvaderKind::Straight, "#2a9d3a"),
    (
        EvaderKind::Circle {
            left: true,
            half: false,
        },
        "#d0402b",
    ),
    (EvaderKind::BangBang, "#8a4fbf"),
    (EvaderKind::Zigzag, "#c08a1f"),
];

/// p90 of the excess (per cent, clamped to the plot) of `pick` over the exact chase.
fn p90(chases: &[Chases], pick: Pick, top: f64) -> f64 {
    (100.0 * Figures::of(chases, pick, |c| &c.exact).p90).min(top)
}

/// p90 of the excess (per cent, clamped) of peer `index` at its sweep's best value.
fn peer_p90(chases: &[Chases], index: usize, top: f64) -> f64 {
    (100.0 * Figures::best_peer(chases, index).1.p90).min(top)
}

/// One figure of p90 excess against one of the field's settings: `cells` along the x axis at
/// `xs`, per evader the estimator's line solid, the textbook peer's dashed and the follow
/// peer's dotted; the raw fixes' figures are printed, not drawn.
fn against(
    dir: &Path,
    file: &str,
    title: &str,
    x_name: &str,
    xs: &[f64],
    cells: &[Cell],
) -> Result<PathBuf, String> {
    let top = 100.0;
    let x_max = xs.last().copied().unwrap_or(1.0);
    let mut fig = Figure::new(720.0, 520.0, (0.0, x_max), (0.0, top));
    for (evader, colour) in EVADERS {
        let runs: Vec<Vec<Chases>> = cells
            .iter()
            .map(|cell| sweep(cell, LIMIT_SETS[0], evader, RUNS, SEED, 0.01, 1.0))
            .collect();
        let line = |of: &dyn Fn(&[Chases]) -> f64| -> Vec<(f64, f64)> {
            xs.iter().zip(&runs).map(|(&x, c)| (x, of(c))).collect()
        };
        let estimated = line(&|c| p90(c, |c| &c.estimated, top));
        let raw = line(&|c| p90(c, |c| &c.raw, top));
        let textbook = line(&|c| peer_p90(c, 0, top));
        let follow = line(&|c| peer_p90(c, 1, top));
        let row = |points: &[(f64, f64)]| {
            points
                .iter()
                .map(|(_, p)| format!("{p:+.1} %"))
                .collect::<Vec<_>>()
                .join(" | ")
        };
        println!(
            "| {file} | {} | estimator | {} |",
            evader.name(),
            row(&estimated)
        );
        println!("| {file} | {} | raw fixes | {} |", evader.name(), row(&raw));
        println!(
            "| {file} | {} | textbook | {} |",
            evader.name(),
            row(&textbook)
        );
        println!("| {file} | {} | follow | {} |", evader.name(), row(&follow));
        fig.polyline(&estimated, colour, 2.0, "none");
        fig.polyline(&textbook, colour, 1.0, "6 4");
        fig.polyline(&follow, colour, 1.0, "1 3");
    }
    fig.axes(
        (0.05, 20.0),
        |v| format!("{}", (v * 100.0).round() / 100.0),
        (x_name, "capture over exact states, p90 (%)"),
        title,
    );
    fig.legend(&[
        "solid: ours, through the estimator; dashed: PX4's filter with PN; dotted: AP_Follow's pursuit",
        "each peer at its sweep's best value per point; clamped at 100 %",
        "law blue, straight green, circle-left red, bang-bang purple, zigzag ochre",
        &format!("paper's limits, {RUNS} starts a point, tau 0.1 T, capture radius 0.3 r_p"),
    ]);
    let path = dir.join(file);
    fig.save(&path).map_err(|e| e.to_string())?;
    Ok(path)
}

/// The control period's figure: p90 of the capture time over the same start at 1 ms.
fn control_period(dir: &Path) -> Result<PathBuf, String> {
    let dts: [f64; 6] = [0.002, 0.005, 0.01, 0.02, 0.05, 0.1];
    let top = 5.0;
    let mut fig = Figure::new(720.0, 520.0, (0.0, 100.0), (0.0, top));
    for (evader, colour) in EVADERS {
        let p90s = discretization(LIMIT_SETS[0], evader, RUNS, SEED, 0.001, &dts);
        let row: Vec<String> = p90s
            .iter()
            .map(|p| format!("{:+.2} %", 100.0 * p))
            .collect();
        println!(
            "| field-dt.svg | {} | exact states | {} |",
            evader.name(),
            row.join(" | ")
        );
        let line: Vec<(f64, f64)> = dts
            .iter()
            .zip(p90s)
            .map(|(dt, p)| (1e3 * dt, (100.0 * p).min(top)))
            .collect();
        fig.polyline(&line, colour, 2.0, "none");
    }
    fig.axes(
        (20.0, 1.0),
        |v| format!("{v}"),
        (
            "control period dt (ms)",
            "capture over the same start at dt = 1 ms, p90 (%)",
        ),
        "What sampling costs: the flight policy on exact states",
    );
    fig.legend(&[
        "law blue, straight green, circle-left red, bang-bang purple, zigzag ochre",
        &format!("paper's limits, {RUNS} starts, capture radius 0.3 r_p; clamped at 5 %"),
    ]);
    let path = dir.join("field-dt.svg");
    fig.save(&path).map_err(|e| e.to_string())?;
    Ok(path)
}

/// The field's three figures in `dir`.
pub fn figures(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let lags = [0.0, 0.05, 0.1, 0.15, 0.2, 0.3];
    let lag_cells: Vec<Cell> = lags
        .iter()
        .map(|&lag_turns| Cell {
            lag_turns,
            sigma_radii: 0.0,
            fixes_per_turn: None,
        })
        .collect();
    let sigmas = [0.0, 0.05, 0.1, 0.2, 0.3];
    let noise_cells: Vec<Cell> = sigmas
        .iter()
        .map(|&sigma_radii| Cell {
            lag_turns: 0.1,
            sigma_radii,
            fixes_per_turn: Some(5.0),
        })
        .collect();
    Ok(vec![
        against(
            dir,
            "field-lag.svg",
            "Transport lag: fixes every period, no noise",
            "lag (the pursuer's full turns T)",
            &lags,
            &lag_cells,
        )?,
        against(
            dir,
            "field-noise.svg",
            "Noise: 5 fixes per T, 0.1 T late",
            "sigma (r_p; heading sigma / 1 m rad)",
            &sigmas,
            &noise_cells,
        )?,
        control_period(dir)?,
    ])
}
