//! The Hamilton-Jacobi-Isaacs value iteration (src/hj.rs) on a coarse grid: the tail chase's
//! exact value, the game's mirror symmetry, and capture from the whole interior.

use hji::{solve, solve_with_boundary, Game, Grid, Solution, Sweeps, REACHED};

/// The paper's limits (v_em / v_pm = 1/2, r_e = 2 r_p), capture radius 0.3 r_p, box +-6 r_p at
/// 0.3 r_p spacing: about 3 s in release on two threads, solved once for the tests that read it.
fn coarse() -> &'static Solution {
    static COARSE: std::sync::OnceLock<Solution> = std::sync::OnceLock::new();
    COARSE.get_or_init(|| {
        let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.3);
        let grid = Grid {
            n: 41,
            half: 6.0,
            headings: 24,
        };
        solve(game, grid, grid.step_time(), 1e-6, 5_000, |_, _| {})
    })
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

/// A full-rate circling evader whose circle meshes with the pursuer's (random limits,
/// v_em / v_pm = 0.79, r_e / r_p = 1.12; docs/closed-loop.md): the flight policy before its
/// turn-rate estimate passed it 11 cm off once a lap and never captured; the pursuer that plays
/// the table in the near field (the flight policy elsewhere) captures it at the table's radius
/// within 20 s (the flight policy's own capture is `tests/adversaries.rs`).
#[test]
fn the_table_pursuer_captures_a_meshing_circler() {
    use hji::policy::pursuer_curvature;
    use twocars::{Guidance, Law, Limits, Policy, Variant};
    use twocars_sim::adversary::{Adversary, EvaderKind, Opponent};
    use twocars_sim::sim::{closed_loop, SimParams, SimStatus, StepCommand};

    let limits = [2.330_756, 2.144_549, 1.851_558, 1.907_620];
    let params = SimParams {
        limits,
        pursuer: [0.0, 0.0, -1.028_521_469_192_557_3],
        evader: [
            -4.607_939_447_529_535,
            7.317_601_635_173_652,
            -2.792_037_322_979_150_6,
        ],
        dt: 0.01,
        t_max: 60.0,
        eps: 0.01,
    };
    let grid = Grid {
        n: 41,
        half: 6.0,
        headings: 24,
    };
    let game = Game::with_radius(limits, 2.0 * grid.spacing());
    let table = solve(game, grid, grid.step_time(), 1e-5, 20_000, |_, _| {});
    // Capture at the table's radius (m), the disc its V is the time to.
    let params = SimParams {
        eps: game.eps / limits[1],
        ..params
    };
    let narrow = limits.map(|v| v as f32);
    let law_limits = Limits::<f32>::new(narrow[0], narrow[1], narrow[2], narrow[3]).unwrap();
    let played = std::cell::Cell::new(0u32);
    let with_table = {
        let mut law = Guidance::new(
            Law::new(law_limits, Variant::Paper),
            0.01,
            twocars::Policy::Paper,
        )
        .unwrap()
        .with_policy(Policy::Flight);
        let circle = Opponent::Evader(EvaderKind::Circle {
            left: true,
            half: false,
        });
        let mut evader = Adversary::new(circle, limits, 0.01, 0.01, 1).unwrap();
        closed_loop(&params, false, |t, p, e| {
            let (ps, es) = law_limits
                .states(p.map(|v| v as f32), e.map(|v| v as f32))
                .map_err(|_| ())?;
            let flight = f64::from(law.step(&ps, &es).command.pursuer);
            let table_turn = pursuer_curvature(std::slice::from_ref(&table), limits[1], p, e);
            played.set(played.get() + u32::from(table_turn.is_some()));
            let (w, v) = evader.command(t, p, e);
            Ok::<_, ()>(StepCommand {
                pursuer: table_turn.unwrap_or(flight),
                evader: w,
                pursuer_speed: None,
                evader_speed: Some(v),
                choice: None,
            })
        })
        .unwrap()
    };
    assert_eq!(
        with_table.status,
        SimStatus::Captured,
        "d_min {}",
        with_table.d_min
    );
    assert!(with_table.t_capture < 20.0, "{}", with_table.t_capture);
    // The table steered the approach into its disc.
    assert!(played.get() > 0, "{}", played.get());
}

/// The boundary value is what a step out of the box lands on: with the box's edge a capture
/// (value 0), an evader 0.5 r_p from the edge behind the pursuer is "caught" once the pursuer
/// runs straight on for a unit of time; with the edge never captured, the pursuer must turn
/// around for it.
#[test]
fn a_step_out_of_the_box_lands_on_the_boundary_value() {
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.6);
    let grid = Grid {
        n: 21,
        half: 6.0,
        headings: 24,
    };
    let tau = grid.step_time();
    let sweeps = Sweeps::on(&grid, 1e-6);
    let edge_captures = solve_with_boundary(game, grid, sweeps, |_, _, _| 0.0, |_, _| {});
    let never = solve(game, grid, tau, 1e-6, 5_000, |_, _| {});
    // Relative x falls at 1 - a = 0.5 per unit time while the pursuer runs straight.
    let behind = (-5.4, 0.0, 0.0);
    let with_edge = edge_captures.value(behind.0, behind.1, behind.2);
    let without = never.value(behind.0, behind.1, behind.2);
    assert!(with_edge <= 1.2 + tau, "{with_edge}");
    assert!(without > 5.0, "{without}");
}

/// A step longer than half a cell's time captures a path that enters the disc within it: an
/// evader that barely moves, 1.8 r_p ahead and 0.3 r_p aside, with a 0.6 r_p disc. Run straight
/// at it, the pursuer enters the disc after 1.28 r_p / v_pm and is out again at 2.32; after one
/// sweep of a 2.4 step every landing (straight, or either full turn) is outside the disc, so
/// only the looks within the step (every 0.15) see the capture; its time is the entry's, found
/// between the last look outside (1.20) and the first inside (1.35).
#[test]
fn a_long_step_captures_a_path_through_the_disc() {
    let game = Game::with_radius([1.0, 1.0, 1e-3, 1.0], 0.6);
    let grid = Grid {
        n: 41,
        half: 6.0,
        headings: 24,
    };
    let one_sweep = solve(game, grid, 2.4, 1e-6, 1, |_, _| {});
    let v = one_sweep.value(1.8, 0.3, 0.0);
    // (1.8 - t)^2 + 0.3^2 = 0.6^2; the evader's 1e-3 r_p per unit time delays it by 2e-3 at most.
    let entry = 1.8 - (0.6f64 * 0.6 - 0.3 * 0.3).sqrt();
    assert!(
        v >= entry - 1e-6 && v <= entry + 0.002,
        "{v}, entry at {entry}"
    );
}

/// A step whose path ends in the capture disc was captured, whatever part of the disc's edge it
/// crossed: on a grid that resolves the disc (radius 1 r_p, ten cells), every node from which
/// one of the pursuer's turns ends in the disc under each of the evader's controls has V at most
/// tau. Without that rule such a landing behind the edge where the evader slips past reads the
/// value the disc keeps there for interpolating outside it, and many of those are above 0.
#[test]
fn a_step_that_ends_in_the_disc_is_captured() {
    use hji::Step;
    let game = Game::with_radius([2.0, 2.0, 1.2, 1.2], 1.0);
    let grid = Grid {
        n: 41,
        half: 2.0,
        headings: 36,
    };
    let tau = grid.step_time();
    let solution = solve(game, grid, tau, 1e-6, 30, |_, _| {});
    let h = grid.spacing();
    let (mut ending_in_disc, mut read_above_zero) = (0, 0);
    for k in 0..grid.headings {
        let phi = -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / grid.headings as f64;
        let (s, c) = phi.sin_cos();
        for j in 0..grid.n {
            for i in 0..grid.n {
                let (x, y) = (-grid.half + i as f64 * h, -grid.half + j as f64 * h);
                if game.captures(x, y) {
                    continue;
                }
                for u in [-1.0, 0.0, 1.0] {
                    let landings = game
                        .evader_controls()
                        .map(|(a, w)| Step::new(a, tau, u, w).from((x, y, phi, s, c)));
                    if landings.iter().all(|&(lx, ly, _)| game.captures(lx, ly)) {
                        ending_in_disc += 1;
                        let v = solution.value(x, y, phi);
                        assert!(v <= tau + 1e-9, "V {v} at ({x}, {y}, {phi}), turn {u}");
                        if landings
                            .iter()
                            .any(|&(lx, ly, lphi)| solution.value(lx, ly, lphi) > 0.0)
                        {
                            read_above_zero += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(
        ending_in_disc > 100 && read_above_zero > 10,
        "{ending_in_disc} {read_above_zero}"
    );
}

/// The solver's step is the relative motion integrated exactly: it agrees with the equations
/// of motion in the pursuer's frame integrated in 10,000 small Euler steps, far out too, where
/// one Euler step of the whole tau is off by about a cell.
#[test]
fn the_step_follows_the_relative_motion_exactly() {
    use hji::Step;
    let (a, tau) = (0.5, 0.25);
    let mut worst: f64 = 0.0;
    for &(x, y, phi) in &[(1.0, 2.0, 0.3), (-30.0, 12.0, -2.0), (25.0, -28.0, 3.0)] {
        for u in [-1.0, 0.0, 1.0] {
            for w in [-0.25, 0.0, 0.25] {
                let (mut sx, mut sy, mut sphi) = (x, y, phi);
                let n = 10_000;
                let dt = tau / n as f64;
                for _ in 0..n {
                    let (s, c) = f64::sin_cos(sphi);
                    let (nx, ny) = (sx + dt * (a * c - 1.0 + u * sy), sy + dt * (a * s - u * sx));
                    (sx, sy, sphi) = (nx, ny, sphi + dt * (w - u));
                }
                let (s, c) = f64::sin_cos(phi);
                let (ex, ey, ephi) = Step::new(a, tau, u, w).from((x, y, phi, s, c));
                worst = worst.max((ex - sx).hypot(ey - sy)).max((ephi - sphi).abs());
            }
        }
    }
    // Euler over 10,000 steps of 2.5e-5 at radius 42: its own error is about 1e-4.
    assert!(worst < 5e-4, "{worst}");
}

/// The theorem: beyond the threshold, wherever the paper's law has a saddle, V is the paper's
/// upper value. The paper's game (threshold 29.1 r_p) on a box of +-36 r_p at one r_p per
/// cell, the paper's value as the boundary beyond the threshold: over the states 0 to 2 r_p
/// beyond it, V + eps / (1 - a) is the upper value within 5 % (the grid's first-order error at
/// this spacing; at half of it the median gap is 0.02 %, `cargo xtask hj`, docs/near-field.md).
#[test]
fn beyond_the_threshold_the_value_is_the_papers() {
    use hji::paper::PaperValue;
    use hji::NEVER;
    use twocars_sim::scenarios::states_beyond;
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 1.0);
    let grid = Grid {
        n: 73,
        half: 36.0,
        headings: 24,
    };
    let paper = PaperValue::of(game).unwrap();
    let s = solve_with_boundary(
        game,
        grid,
        Sweeps::on(&grid, 1e-4),
        |x, y, phi| paper.beyond_threshold(x, y, phi).unwrap_or(NEVER),
        |_, _| {},
    );
    let (gaps, refused) = paper.gaps(
        states_beyond(paper.threshold, paper.threshold + 2.0),
        |x, y, phi| {
            let v = s.value(x, y, phi);
            (v < REACHED).then_some(v)
        },
    );
    assert_eq!(refused, 0);
    assert!(gaps.len() > 2_000, "{}", gaps.len());
    for (gap, value) in gaps {
        assert!(gap.abs() <= 0.05 * value, "V off by {gap} from {value}");
    }
}

/// By the centre of the pursuer's right turning circle, an evader running back past the
/// pursuer 0.01 r_p outside the capture disc (eps = 1 r_p) is not captured by any turn: it
/// passes by and leaves the box. Its cell's corner (0.1, -1.0), 0.005 r_p outside the disc, is
/// captured as its evader passes, so V interpolated there reads the pass captured; the solver
/// reads a landing within two cells of the disc by one more step of the scheme (of three tau),
/// which sees the pass. A pass 0.03 r_p inside the edge is captured within the step either
/// way.
#[test]
fn a_pass_just_outside_the_disc_is_read_by_one_more_step() {
    let game = Game::with_radius([2.0, 2.0, 1.2, 1.2], 1.0);
    let grid = Grid {
        n: 41,
        half: 2.0,
        headings: 36,
    };
    let solution = solve(game, grid, grid.step_time(), 1e-6, 2_000, |_, _| {});
    let pi = std::f64::consts::PI;
    let pass = (0.1, -1.01, pi);
    let (read, interpolated) = (solution.landing(pass), solution.value(pass.0, pass.1, pi));
    assert!(
        read >= REACHED && interpolated < REACHED,
        "read {read}, interpolated {interpolated}"
    );
    // Enters the disc 0.036 r_p / v_pm into the step (straight on, closing at 1.6).
    let caught = solution.landing((0.3, -0.97, pi));
    assert!(caught < 0.15, "{caught}");
}

/// On a grid that resolves the disc (radius 1 r_p, five cells) with 64 relative headings,
/// the tail chase (exact V = (d - eps) / (1 - a)) is read to within a thousandth of r_p / v_pm
/// by the filtered cubic read at every distance; the trilinear read's error grows with the
/// distance, by about 0.0025 per r_p here with five turn rates (0.007 with three; more with finer
/// headings: the evader's turn within a step moves phi by a fraction of a cell, which the linear
/// read in phi smears toward V's ridge at phi = 0).
#[test]
fn the_filtered_read_keeps_the_tail_chase_where_the_trilinear_drifts() {
    use hji::{Read, Sweeps};
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 1.0);
    let grid = Grid {
        n: 41,
        half: 4.0,
        headings: 64,
    };
    let errors = |read: Read| {
        let sweeps = Sweeps {
            read,
            ..Sweeps::on(&grid, 1e-6)
        };
        let s = solve_with_boundary(game, grid, sweeps, |_, _, _| hji::NEVER, |_, _| {});
        [1.5, 2.0, 2.5, 3.0]
            .map(|d| s.value(d, 0.0, 0.0) - (d - game.eps) / (1.0 - game.speed_ratio))
    };
    let (filtered, trilinear) = (errors(Read::Filtered), errors(Read::Trilinear));
    assert!(
        filtered.iter().all(|e| e.abs() < 1e-3),
        "filtered {filtered:?}"
    );
    // From 1.5 to 3 r_p the trilinear's error grows by three times the filtered's bound.
    assert!(
        trilinear[3] - trilinear[0] > 3e-3,
        "trilinear {trilinear:?}"
    );
}

/// An evader can always stand still, and the pursuer closes on it at most at v_pm: V is at
/// least r - eps at every state. The trilinear read keeps that bound (r - eps is convex, so
/// its interpolant lies above it); the unfiltered cubic's undershoots at V's bends are the
/// pursuer's to pick, and take V below it; filtered, each read is at most the filter's width
/// below the trilinear's, and V falls below the bound by a few widths at most. On a 0.15 r_p grid
/// with a 0.6 r_p disc (as `cargo xtask hj --compare`'s 81-node grid, in a +-3 r_p box).
#[test]
fn the_filtered_read_keeps_v_above_what_an_evader_that_stops_forces() {
    use hji::{Read, Sweeps};
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.6);
    let grid = Grid {
        n: 41,
        half: 3.0,
        headings: 42,
    };
    let lowest = |read: Read| {
        let sweeps = Sweeps {
            read,
            ..Sweeps::on(&grid, 1e-6)
        };
        let s = solve_with_boundary(game, grid, sweeps, |_, _, _| hji::NEVER, |_, _| {});
        let h = grid.spacing();
        let mut lowest = f64::INFINITY;
        for (index, &v) in s.values.iter().enumerate() {
            let (i, j) = (index % grid.n, index / grid.n % grid.n);
            let r = (-grid.half + i as f64 * h).hypot(-grid.half + j as f64 * h);
            if v < REACHED && r > game.eps * (1.0 + 1e-9) {
                lowest = lowest.min(v - (r - game.eps));
            }
        }
        lowest
    };
    let (filtered, cubic) = (lowest(Read::Filtered), lowest(Read::Cubic));
    println!("V - (r - eps), least: filtered {filtered:.4}, cubic {cubic:.4}");
    let width = hji::FILTER * grid.spacing() * grid.spacing();
    assert!(filtered > -5.0 * width, "filtered {filtered}");
    assert!(cubic < 5.0 * filtered.min(-width), "cubic {cubic}");
}
