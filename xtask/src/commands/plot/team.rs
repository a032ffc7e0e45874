//! `cargo xtask plot`'s team figures: three pursuers at the paper's limits against each evader
//! of `twocars_sim::team`, from one seeded start, each pursuer's track drawn thick while it is
//! the chaser.

use std::path::{Path, PathBuf};

use twocars_sim::rng::Rng;
use twocars_sim::scenarios::PAPER_LIMITS;
use twocars_sim::team::{
    chase_traced, predicted, TeamEvader, TeamParams, TeamPursuit, TeamSample, TeamStart,
};

use super::figure::{metres, Figure};

const PURSUERS: [&str; 3] = ["#1f5fbf", "#2a9d3a", "#8a4fbf"];
const EVADER: &str = "#d62728";

/// The start: three pursuers as `report --team` draws them (seed 2019).
fn start() -> TeamStart<3> {
    TeamStart::random(&mut Rng::new(2019), PAPER_LIMITS)
}

/// One figure per evader: `team-vs-<evader>.svg`.
pub fn figures(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let start = start();
    let params = TeamParams {
        dt: 0.01,
        t_max: 3.0 * predicted(&start).ok_or("no prediction at the start")? + 30.0,
        eps: 0.1 / PAPER_LIMITS[1],
        sigma: 0.0,
        seed: 2019,
        teammate_lag: None,
    };
    let mut written = Vec::new();
    for (evader, name) in TeamEvader::ALL {
        let mut trace = Vec::new();
        let run = chase_traced(&start, TeamPursuit::Team, evader, params, Some(&mut trace))
            .ok_or("invalid limits")?;
        let captured = run.captured.map_or("not captured".to_string(), |t| {
            format!("captured at {t:.2} s")
        });
        let title = format!(
            "3 pursuers against the {name} evader: {captured} (predicted {:.2} s)",
            run.predicted.unwrap_or(f64::NAN)
        );
        let mut fig = view(&trace);
        draw(&mut fig, &trace);
        fig.axes((5.0, 5.0), metres, ("x (m)", "y (m)"), &title);
        fig.legend(&[
            "pursuers blue, green, purple (thick while the chaser), evader red;",
            "dots at t = 0, black at the capture",
        ]);
        let path = dir.join(format!("team-vs-{name}.svg"));
        fig.save(&path).map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(written)
}

/// A square view holding every track.
fn view(trace: &[TeamSample<3>]) -> Figure {
    let (x0, x1, y0, y1) = trace
        .iter()
        .flat_map(|(_, p, e, _)| p.iter().chain([e]).map(|s| (s[0], s[1])))
        .fold(
            (f64::MAX, f64::MIN, f64::MAX, f64::MIN),
            |(a, b, c, d), (x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
        );
    let half = 0.5 * (x1 - x0).max(y1 - y0) + 1.0;
    Figure::equal(640.0, (0.5 * (x0 + x1), 0.5 * (y0 + y1)), half)
}

/// Each track, split where its pursuer's role changes.
fn draw(fig: &mut Figure, trace: &[TeamSample<3>]) {
    let evader: Vec<(f64, f64)> = trace.iter().map(|(_, _, e, _)| (e[0], e[1])).collect();
    fig.polyline(&evader, EVADER, 1.8, "none");
    for (i, colour) in PURSUERS.iter().enumerate() {
        let mut run: Vec<(f64, f64)> = Vec::new();
        let mut chasing = None;
        for (_, p, _, chaser) in trace {
            let now = *chaser == Some(i);
            if chasing.is_some_and(|c| c != now) {
                let width = if chasing == Some(true) { 3.5 } else { 1.2 };
                fig.polyline(&run, colour, width, "none");
                run = run.last().copied().into_iter().collect();
            }
            chasing = Some(now);
            run.push((p[i][0], p[i][1]));
        }
        let width = if chasing == Some(true) { 3.5 } else { 1.2 };
        fig.polyline(&run, colour, width, "none");
        if let Some((_, p, _, _)) = trace.first() {
            fig.dot(p[i][0], p[i][1], 4.0, colour);
        }
    }
    if let Some((_, _, e, _)) = trace.first() {
        fig.dot(e[0], e[1], 4.0, EVADER);
    }
    if let Some((_, _, e, _)) = trace.last() {
        fig.dot(e[0], e[1], 5.0, "black");
    }
}
