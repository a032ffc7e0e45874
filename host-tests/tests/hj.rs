//! The Hamilton-Jacobi-Isaacs value iteration (src/hj.rs) on a coarse grid: the tail chase's
//! exact value, the game's mirror symmetry, and capture from the whole interior.

use host_tests::hj::{solve, Game, Grid, Solution, REACHED};

/// The paper's limits (v_em / v_pm = 1/2, r_e = 2 r_p), capture radius 0.3 r_p, box +-6 r_p at
/// 0.3 r_p spacing: about 3 s in release on two threads.
fn coarse() -> Solution {
    let game = Game {
        eps: 0.3,
        ..Game::of_limits([2.0, 2.0, 1.0, 1.0], 0.0)
    };
    let grid = Grid {
        n: 41,
        half: 6.0,
        headings: 24,
    };
    solve(game, grid, 0.5 * grid.spacing(), 1e-6, 5_000, |_, _| {})
}

#[test]
fn value_iteration_converges_to_the_tail_chase_value_within_its_grid_error() {
    let s = coarse();
    assert!(
        s.residual <= 1e-6 && s.newly_finite == 0,
        "{} sweeps, {}",
        s.sweeps,
        s.residual
    );
    let a = s.game.speed_ratio;
    let mut last = 0.0;
    for d in [1.0, 2.0, 3.0, 4.0] {
        let v = s.value(d, 0.0, 0.0);
        let exact = (d - s.game.eps) / (1.0 - a);
        // First order in the spacing h: the capture disc's edge smeared over a cell costs the
        // pursuer at most about one cell at the closing speed, h / (1 - a) = 0.6 here.
        assert!(
            (v - exact).abs() <= s.grid.spacing() / (1.0 - a),
            "d = {d}: V = {v}, exact {exact}"
        );
        // Farther is later.
        assert!(v > last, "d = {d}: {v} after {last}");
        last = v;
    }
}

#[test]
fn the_value_is_mirror_symmetric_and_finite_inside_the_box() {
    let s = coarse();
    let grid = s.grid;
    let h = grid.spacing();
    let mut checked = 0;
    for i in 0..grid.n {
        for j in 0..grid.n {
            for k in 0..grid.headings {
                let x = -grid.half + i as f64 * h;
                let y = -grid.half + j as f64 * h;
                let phi =
                    -std::f64::consts::PI + k as f64 * std::f64::consts::TAU / grid.headings as f64;
                let (v, mirror) = (s.value(x, y, phi), s.value(x, -y, -phi));
                assert!(
                    (v - mirror).abs() <= 1e-9 * v.max(1.0),
                    "({x}, {y}, {phi}): {v} vs {mirror}"
                );
                // Well inside the box every state is captured (the pursuer is faster and turns
                // tighter): within 2 r_p of the centre.
                if x.hypot(y) <= 2.0 {
                    assert!(v < REACHED, "({x}, {y}, {phi}) not captured");
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 1000, "{checked}");
}
