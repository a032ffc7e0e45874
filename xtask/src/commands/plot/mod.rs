//! `cargo xtask plot`: SVG figures in target/plots/ — the paper's four cases in closed loop, a
//! value map, and the Monte-Carlo scatter of simulated against predicted capture time.
//!
//! The SVG is written here by hand (lines, circles, rectangles, text): no font or plotting
//! dependency.

mod field;
mod figure;
mod near_field;
mod paper;
mod team;

use std::path::{Path, PathBuf};

use twocars::{Direction, Law, Policy, TurningCircle, ValidTangent, Variant};
use twocars_sim::scenarios::{paper_cases, PAPER_LIMITS};
use twocars_sim::sim::{simulate, SimParams, SimStatus};

use figure::{metres, ramp, Figure};
use paper::{observation, paper_report, state};

const PURSUER: &str = "#1f5fbf";
const EVADER: &str = "#d0402b";

/// One paper case: closed-loop trajectories, the four circles and the chosen tangent at t = 0.
fn paper_case(
    dir: &Path,
    name: &str,
    pursuer: [f64; 3],
    evader: [f64; 3],
) -> Result<PathBuf, String> {
    let params = SimParams {
        limits: PAPER_LIMITS,
        pursuer,
        evader,
        dt: 0.01,
        t_max: 30.0,
        eps: 0.01,
    };
    let run = simulate::<f32>(&params, Variant::Paper, Policy::Paper, true);
    let scene = twocars::law::validate::<f64>(&observation(PAPER_LIMITS, pursuer, evader))
        .map_err(|e| e.to_string())?;
    let (p, e) = (state(pursuer), state(evader));
    let evaluation = Law::new(scene.limits, Variant::Paper).evaluate(&p, &e);
    let report = evaluation.report.ok_or("no game at t = 0")?;
    let circles: Circles = [
        (TurningCircle::both(&p, &scene.limits.pursuer), PURSUER),
        (TurningCircle::both(&e, &scene.limits.evader), EVADER),
    ];
    let mut fig = square_view(&run.trajectory, &circles);
    for (pair, colour) in circles {
        for c in pair {
            let o = c.centre();
            fig.circle(o.x, o.y, c.radius, colour, "none", "4 3");
        }
    }
    let track = |i: usize| -> Vec<(f64, f64)> {
        run.trajectory
            .iter()
            .map(|(_, p, e)| if i == 0 { (p[0], p[1]) } else { (e[0], e[1]) })
            .collect()
    };
    fig.polyline(&track(0), PURSUER, 1.8, "none");
    fig.polyline(&track(1), EVADER, 1.8, "none");
    let (row, col) = (report.solution.row, report.solution.col);
    if let Some(chosen) = report.chosen_pair() {
        draw_tangent(&mut fig, &chosen.tangent, (row, col), &circles);
    }
    fig.dot(pursuer[0], pursuer[1], 4.0, PURSUER);
    fig.dot(evader[0], evader[1], 4.0, EVADER);
    if let Some((_, p, _)) = run.trajectory.last() {
        fig.dot(p[0], p[1], 5.0, "black");
    }
    let simulated = if run.status == SimStatus::Captured {
        format!("{:.3} s", run.t_capture)
    } else {
        "no capture".to_string()
    };
    let title = format!(
        "{name}: predicted {:.3} s ({}{}), simulated {simulated}",
        run.predicted,
        row.letter(),
        col.letter()
    );
    fig.axes((5.0, 5.0), metres, ("x (m)", "y (m)"), &title);
    fig.legend(&[
        "pursuer (blue), evader (red), turning circles at t = 0 (dashed),",
        "chosen valid tangent at t = 0 (green, dashed), capture point (black)",
    ]);
    let path = dir.join(format!("{name}.svg"));
    fig.save(&path).map_err(|e| e.to_string())?;
    Ok(path)
}

/// The turning circles of both vehicles at t = 0 with their colours.
type Circles = [([TurningCircle<f64>; 2], &'static str); 2];

/// A square figure holding both tracks of `trajectory` and all four `circles`.
fn square_view(trajectory: &[(f64, [f64; 3], [f64; 3])], circles: &Circles) -> Figure {
    let mut points: Vec<(f64, f64)> = trajectory
        .iter()
        .flat_map(|(_, p, e)| [(p[0], p[1]), (e[0], e[1])])
        .collect();
    for (pair, _) in circles {
        for c in pair {
            let o = c.centre();
            points.extend([
                (o.x - c.radius, o.y - c.radius),
                (o.x + c.radius, o.y + c.radius),
            ]);
        }
    }
    let (x0, x1, y0, y1) = points.iter().fold(
        (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
        |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
    );
    let half = 0.5 * (x1 - x0).max(y1 - y0) + 1.0;
    Figure::equal(640.0, (0.5 * (x0 + x1), 0.5 * (y0 + y1)), half)
}

/// The chosen tangent, from the pursuer's circle of `row` to the evader's of `col`.
fn draw_tangent(
    fig: &mut Figure,
    tangent: &ValidTangent<f64>,
    (row, col): (Direction, Direction),
    circles: &Circles,
) {
    let (sin, cos) = tangent.heading.sin_cos();
    let pick = |pair: [TurningCircle<f64>; 2], d: Direction| match d {
        Direction::Anticlockwise => pair[0],
        Direction::Clockwise => pair[1],
    };
    let a = pick(circles[0].0, row).point_with_heading(sin, cos);
    let b = pick(circles[1].0, col).point_with_heading(sin, cos);
    fig.polyline(&[(a.x, a.y), (b.x, b.y)], "#2a9d3a", 2.0, "6 4");
}

/// The upper value and the chosen pair over a grid of evader positions (pursuer at the origin
/// heading +y, evader heading +y, the paper's limits).
fn value_map(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let (half, n) = (12.0, 97usize);
    let step = 2.0 * half / n as f64;
    let pursuer = [0.0, 0.0, std::f64::consts::FRAC_PI_2];
    let mut cells = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let x = -half + (i as f64 + 0.5) * step;
            let y = -half + (j as f64 + 0.5) * step;
            cells.push((
                x,
                y,
                paper_report(pursuer, [x, y, std::f64::consts::FRAC_PI_2]),
            ));
        }
    }
    let top = 12.0;
    let mut value = Figure::equal(640.0, (0.0, 0.0), half);
    let mut choice = Figure::equal(640.0, (0.0, 0.0), half);
    for (x, y, report) in &cells {
        let square = (x - step / 2.0, y - step / 2.0, step);
        let found = report.and_then(|r| r.solution.upper.map(|u| (r, u)));
        draw_cell(&mut value, &mut choice, square, found, top);
    }
    for fig in [&mut value, &mut choice] {
        fig.dot(0.0, 0.0, 5.0, "white");
        fig.polyline(&[(0.0, 0.0), (0.0, 1.5)], "white", 2.0, "none");
    }
    value.axes(
        (4.0, 4.0),
        metres,
        ("evader x (m)", "evader y (m)"),
        "Upper value (s); pursuer at the origin heading +y, evader heading +y",
    );
    value.colour_scale(top);
    choice.axes(
        (4.0, 4.0),
        metres,
        ("evader x (m)", "evader y (m)"),
        "Chosen pair (pursuer, evader circle) over evader positions",
    );
    let (left, t, _, _) = choice.area;
    choice.text(
        left,
        t - 6.0,
        11.0,
        "start",
        "AA blue, AC orange, CA green, CC purple; black dot: no pure saddle; grey: no finite value",
    );
    let a = dir.join("value-map.svg");
    let b = dir.join("choice-map.svg");
    value.save(&a).map_err(|e| e.to_string())?;
    choice.save(&b).map_err(|e| e.to_string())?;
    Ok(vec![a, b])
}

/// One cell of the value map (its upper value `found.1` on the ramp to `top`) and of the
/// choice map (the chosen pair's colour, a black dot where there is no pure saddle); grey in
/// both where there is no finite value. `square`: lower-left corner and side, m.
fn draw_cell(
    value: &mut Figure,
    choice: &mut Figure,
    (x0, y0, step): (f64, f64, f64),
    found: Option<(twocars::GameReport<f64>, f64)>,
    top: f64,
) {
    match found {
        Some((r, upper)) => {
            value.cell(x0, y0, step, step, &ramp(upper / top));
            let colour = match (r.solution.row, r.solution.col) {
                (Direction::Anticlockwise, Direction::Anticlockwise) => "#4e79a7",
                (Direction::Anticlockwise, Direction::Clockwise) => "#f28e2b",
                (Direction::Clockwise, Direction::Anticlockwise) => "#59a14f",
                (Direction::Clockwise, Direction::Clockwise) => "#b07aa1",
            };
            choice.cell(x0, y0, step, step, colour);
            if !r.solution.saddle() {
                choice.cell(
                    x0 + step * 0.3,
                    y0 + step * 0.3,
                    step * 0.4,
                    step * 0.4,
                    "black",
                );
            }
        }
        None => {
            value.cell(x0, y0, step, step, "#cccccc");
            choice.cell(x0, y0, step, step, "#cccccc");
        }
    }
}

/// Simulated against predicted capture time (log axes) under one policy of a Monte Carlo.
fn scatter(
    dir: &Path,
    results: &[crate::commands::report::Run],
    policy: &str,
    pick: fn(&crate::commands::report::Run) -> &twocars_sim::sim::SimResult,
) -> Result<PathBuf, String> {
    let runs = results.len();
    let (lo, hi) = (-1.0, 3.0);
    let mut fig = Figure::new(720.0, 660.0, (lo, hi), (lo, hi));
    fig.polyline(&[(lo, lo), (hi, hi)], "#888888", 1.0, "4 3");
    let clamp = |t: f64| t.max(1e-9).log10().clamp(lo, hi);
    let mut missed = 0;
    for r in results {
        let colour = match r.regime {
            crate::commands::report::Regime::Far => PURSUER,
            crate::commands::report::Regime::Near => EVADER,
        };
        let p = pick(r);
        if p.predicted.is_finite() && p.predicted > 0.0 {
            let y = if p.t_capture.is_finite() {
                clamp(p.t_capture)
            } else {
                missed += 1;
                hi
            };
            fig.dot(clamp(p.predicted), y, 2.2, colour);
        }
    }
    fig.axes(
        (1.0, 1.0),
        |v| format!("{}", 10f64.powf(v)),
        (
            "predicted capture time at t = 0 (s, log)",
            "simulated capture time (s, log)",
        ),
        &format!("Closed loop, {policy}: {runs} seeded states, random limits, dt = 0.01 s"),
    );
    fig.legend(&[
        "blue: d0 >= threshold; red: d0 < threshold; dashed: simulated = predicted",
        &format!(
            "{missed} runs without capture plotted on the top edge; cargo xtask report for the tables"
        ),
    ]);
    let path = dir.join(format!("monte-carlo-{policy}.svg"));
    fig.save(&path).map_err(|e| e.to_string())?;
    Ok(path)
}

/// `cargo xtask plot`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct PlotArgs {
    /// The field's figures only (late, sparse, noisy fixes; the control period).
    #[arg(long)]
    field: bool,
    /// Only the team's figures (`team-vs-<evader>.svg`).
    #[arg(long, conflicts_with = "field")]
    team: bool,
}

/// `cargo xtask plot [--field]`.
pub fn command(args: &PlotArgs) -> i32 {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/plots");
    let result = (|| -> Result<Vec<PathBuf>, String> {
        std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
        if args.field {
            return field::figures(&dir);
        }
        if args.team {
            return team::figures(&dir);
        }
        let mut written = Vec::new();
        for case in paper_cases() {
            written.push(paper_case(&dir, case.name, case.pursuer, case.evader)?);
        }
        written.extend(value_map(&dir)?);
        written.extend(near_field::maps(&dir)?);
        written.extend(field::figures(&dir)?);
        written.extend(team::figures(&dir)?);
        let evaders = twocars_sim::adversary::EvaderKind::ALL;
        let progress = crate::util::progress::Progress::new(
            600 + 300 * evaders.len() as u64,
            "closed-loop runs for the Monte-Carlo scatters",
        );
        progress.step("the law against itself");
        let runs = crate::commands::report::monte_carlo(
            600,
            2019,
            0.01,
            twocars_sim::starts::LimitSet::Random,
            None,
            Some(&progress),
        );
        written.push(scatter(&dir, &runs, "paper", |r| &r.paper)?);
        written.push(scatter(&dir, &runs, "flight", |r| &r.flight)?);
        // One figure per evader of the adversary suite, the flight policy's pursuer.
        for evader in evaders {
            progress.step(&format!("flight against {}", evader.name()));
            let opponent = Some(twocars_sim::adversary::Opponent::Evader(evader));
            let runs = crate::commands::report::monte_carlo(
                300,
                2019,
                0.01,
                twocars_sim::starts::LimitSet::Random,
                opponent,
                Some(&progress),
            );
            let name = format!("flight-vs-{}", evader.name());
            written.push(scatter(&dir, &runs, &name, |r| &r.flight)?);
        }
        progress.finish();
        Ok(written)
    })();
    match result {
        Ok(paths) => {
            for p in paths {
                println!("wrote {}", p.canonicalize().unwrap_or(p).display());
            }
            0
        }
        Err(e) => {
            eprintln!("xtask plot: {e}");
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_points_map_into_the_plot_area() {
        let mut fig = Figure::new(400.0, 300.0, (0.0, 10.0), (-5.0, 5.0));
        fig.text(0.0, 0.0, 10.0, "start", "d0 < threshold & more");
        assert!(
            fig.body.contains("d0 &lt; threshold &amp; more"),
            "{}",
            fig.body
        );
        let (left, top, w, h) = fig.area;
        assert_eq!(fig.px(0.0, -5.0), (left, top + h));
        assert_eq!(fig.px(10.0, 5.0), (left + w, top));
    }

    #[test]
    fn a_paper_case_figure_names_its_prediction_and_its_capture() {
        let dir = std::env::temp_dir().join(format!("twocars-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let case = paper_cases()[0];
        let path = paper_case(&dir, case.name, case.pursuer, case.evader).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(
            svg.contains("paper1: predicted 5.657 s (AA), simulated 5.6"),
            "title"
        );
        // Four turning circles, two start dots and the capture point.
        assert_eq!(svg.matches("<circle").count(), 7);
        assert!(svg.trim_end().ends_with("</svg>"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
