//! The paper's case 1 on the host: the four valid tangents' capture times (Table 1's matrix),
//! the game's value and both players' circles and commands.
//!
//! ```sh
//! cargo run --example paper_case_1
//! ```

use twocars::{Direction, Law, Limits, Variant};

fn main() -> Result<(), twocars::Error> {
    // v_pm, w_pm, v_em, w_em: m/s and 1/m (turning radii 0.5 m and 1 m).
    let limits = Limits::<f64>::new(2.0, 2.0, 1.0, 1.0)?;
    let law = Law::new(limits, Variant::Paper);
    // (x, y, theta): metres, radians anticlockwise from +x.
    let half_pi = core::f32::consts::FRAC_PI_2;
    let (pursuer, evader) = limits.states([0.0, 0.0, half_pi], [-3.0, -6.0, half_pi])?;
    let evaluation = law.evaluate(&pursuer, &evader);
    println!("status: {}", evaluation.status.name());
    let Some(report) = evaluation.report else {
        return Ok(());
    };
    let name = |d: Direction| match d {
        Direction::Anticlockwise => "A",
        Direction::Clockwise => "C",
    };
    println!("time to capture (s), pursuer circle by row, evader circle by column:");
    println!("        A         C");
    for (row, entries) in [Direction::Anticlockwise, Direction::Clockwise]
        .into_iter()
        .zip(report.matrix().entries)
    {
        let cell = |t: Option<f64>| t.map_or("       inf".to_string(), |t| format!("{t:10.4}"));
        println!("{} {}{}", name(row), cell(entries[0]), cell(entries[1]));
    }
    let solution = report.solution;
    if let Some(value) = solution.upper {
        println!("value: {value:.4} s");
    }
    println!(
        "pursuer turns on its {} circle (w = {} 1/m), evader on its {} circle (w = {} 1/m)",
        name(solution.row),
        evaluation.command.pursuer,
        name(solution.col),
        evaluation.command.evader
    );
    Ok(())
}
