//! A team of pursuers (`twocars::team`) against one evader on the host simulator: it
//! captures every evader, no later than its best pursuer alone would, and its roles swap
//! rarely on noisy states. `cargo xtask report --team N` measures the same over 1,000 starts.

use twocars_sim::rng::Rng;
use twocars_sim::scenarios::PAPER_LIMITS;
use twocars_sim::team::{chase, predicted, TeamEvader, TeamParams, TeamPursuit, TeamStart};

/// Seeded starts of three pursuers at the paper's limits (`TeamStart::random`).
fn starts(n: usize) -> Vec<TeamStart<3>> {
    (0..n as u64)
        .map(|seed| TeamStart::random(&mut Rng::new(7000 + seed), PAPER_LIMITS))
        .collect()
}

fn params(start: &TeamStart<3>, sigma: f64) -> TeamParams {
    let r_p = 1.0 / PAPER_LIMITS[1];
    TeamParams {
        dt: 0.01,
        t_max: 3.0 * predicted(start).unwrap() + 30.0,
        eps: 0.1 * r_p,
        sigma: sigma * r_p,
        seed: 1,
        teammate_lag: None,
    }
}

#[test]
fn the_team_captures_no_later_than_its_best_pursuer_alone() {
    for (k, start) in starts(12).iter().enumerate() {
        for (evader, name) in TeamEvader::ALL {
            let p = params(start, 0.0);
            let team = chase(start, TeamPursuit::Team, evader, p).unwrap();
            let team = team
                .captured
                .unwrap_or_else(|| panic!("{name} {k}: never captured"));
            let alone = (0..3)
                .filter_map(|i| chase(start, TeamPursuit::Alone(i), evader, p)?.captured)
                .fold(f64::INFINITY, f64::min);
            assert!(
                team <= alone + 0.015,
                "{name} {k}: {team} s, alone {alone} s"
            );
        }
    }
}

#[test]
fn roles_on_noisy_states_swap_at_most_twice() {
    for (k, start) in starts(12).iter().enumerate() {
        let run = chase(
            start,
            TeamPursuit::Team,
            TeamEvader::TeamAware,
            params(start, 0.1),
        );
        let run = run.unwrap();
        assert!(run.captured.is_some(), "{k}: never captured");
        assert!(run.swaps.iter().all(|&s| s <= 2), "{k}: {:?}", run.swaps);
    }
}
