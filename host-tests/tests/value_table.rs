//! The value table as the firmware reads it (`twocars::value_tables::table`, no_std, f32, u16 codes)
//! against the solver's f64 table it was written from (`hji`): values within half a
//! code, the same optimal pursuer turn wherever the host's minimax says so clearly (one table
//! and a nested set, `twocars::value_tables`), the tail chase, and malformed tables refused
//! without a panic.

use std::sync::OnceLock;

use hji::policy::{evader_turn, finest, turn};
use hji::{solve, solve_with_boundary, table_set_bytes, Game, Grid, Solution, Step, Sweeps};
use twocars::value_tables::table::{TableError, ValueTable, HEADER_LEN, MAGIC, NEVER};
use twocars::value_tables::ValueTables;
use twocars_sim::rng::Rng;

/// The paper's game (v_em / v_pm = 1/2, r_e = 2 r_p) on the 41 x 41 x 24 grid, capture radius
/// 0.3 r_p: solved once for every test here.
fn solution() -> &'static Solution {
    static SOLUTION: OnceLock<Solution> = OnceLock::new();
    SOLUTION.get_or_init(|| {
        let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.3);
        let grid = Grid {
            n: 41,
            half: 6.0,
            headings: 24,
        };
        solve(game, grid, grid.step_time(), 1e-6, 5_000, |_, _| {})
    })
}

fn bytes() -> &'static [u8] {
    static BYTES: OnceLock<Vec<u8>> = OnceLock::new();
    BYTES.get_or_init(|| solution().table_bytes())
}

/// The solver's values at the eight nodes of the cell around `(x, y, phi)`.
fn corners(s: &Solution, x: f64, y: f64, phi: f64) -> Vec<f64> {
    let (h, turn) = (s.grid.spacing(), std::f64::consts::TAU);
    let dphi = turn / s.grid.headings as f64;
    let node = |v: f64, step: f64, from: f64| from + ((v - from) / step).floor() * step;
    let (x0, y0) = (node(x, h, -s.grid.half), node(y, h, -s.grid.half));
    let phi0 = node(phi, dphi, -std::f64::consts::PI);
    let mut out = Vec::new();
    for dp in [0.0, dphi] {
        for dy in [0.0, h] {
            for dx in [0.0, h] {
                out.push(s.value(x0 + dx, y0 + dy, phi0 + dp));
            }
        }
    }
    out
}

fn point(rng: &mut Rng, half: f64) -> (f64, f64, f64) {
    (
        rng.uniform(-half, half),
        rng.uniform(-half, half),
        rng.uniform(-std::f64::consts::PI, std::f64::consts::PI),
    )
}

#[test]
fn the_firmware_reads_the_values_the_solver_wrote_within_half_a_code() {
    let s = solution();
    let table = ValueTable::parse(bytes()).expect("the solver's table parses");
    assert_eq!(table.grid(), (41, 24));
    assert!((f64::from(table.speed_ratio) - 0.5).abs() < 1e-7);
    let scale = f64::from(table.scale);
    let mut rng = Rng::new(30);
    let (mut compared, mut never) = (0, 0);
    for _ in 0..20_000 {
        let (x, y, phi) = point(&mut rng, 5.9);
        let want = s.value(x, y, phi);
        match table.value(x as f32, y as f32, phi as f32) {
            Some(got) => {
                // Half a code of rounding, and f32's rounding of the weights and the sum.
                let bound = 0.5 * scale + 1e-5 * want;
                assert!(
                    (f64::from(got) - want).abs() <= bound,
                    "({x}, {y}, {phi}): table {got}, solver {want}"
                );
                compared += 1;
            }
            // The table refuses only next to a node beyond the longest time it keeps.
            None => {
                let corner = corners(s, x, y, phi).into_iter().fold(0.0_f64, f64::max);
                assert!(
                    corner > s.longest_kept(),
                    "({x}, {y}, {phi}): refused, solver {want}"
                );
                never += 1;
            }
        }
    }
    assert!(compared > 10_000, "{compared} compared, {never} refused");
    // Outside the box, and non-finite input: no value, no panic.
    assert_eq!(table.value(6.1, 0.0, 0.0), None);
    assert_eq!(table.value(f32::NAN, 0.0, 0.0), None);
    assert_eq!(table.value(0.0, 0.0, f32::INFINITY), None);
    // Headings within the law's envelope (1e4 rad) are reduced; beyond 1e5 rad, no value.
    assert!(table.value(1.0, 0.0, 1.0e4).is_some());
    assert_eq!(table.value(1.0, 0.0, 1.0e30), None);
}

/// The tail chase, read through the table: V = (d - eps) / (1 - a) within the grid's error.
#[test]
fn the_table_keeps_the_tail_chase_value() {
    let table = ValueTable::parse(bytes()).unwrap();
    let h = f64::from(table.spacing());
    for d in [1.0_f32, 2.0, 3.0, 4.0] {
        let got = f64::from(table.value(d, 0.0, 0.0).unwrap());
        let exact = (f64::from(d) - 0.3) / 0.5;
        assert!(
            got >= exact - 1e-3 && got - exact <= h / 0.5,
            "d = {d}: {got} vs {exact}"
        );
    }
}

/// Where the host's tables' pursuer (the solver's one-step minimax on the f64 values of
/// `tables`, finest first) prefers a turn by more than 20 codes and the reader of `set` has a
/// value at every landing, the reader's turn is the host's, and the evader's where its choice
/// is clear too; how many such states of `count` random ones within `half` (r_p) there were,
/// for the pursuer and for the evader.
fn turns_agree(
    tables: &[Solution],
    set: &ValueTables<'_>,
    half: f64,
    count: usize,
) -> (usize, usize) {
    let mut rng = Rng::new(31);
    let readers: Vec<ValueTable<'_>> = set.tables().copied().collect();
    let scale = readers.iter().map(|t| t.scale).fold(0.0, f32::max);
    let (mut clear, mut evader_clear) = (0, 0);
    for _ in 0..count {
        let (x, y, phi) = point(&mut rng, half);
        // Where the host's best turn beats the next by more than the codes' rounding can move
        // a worst case (half a code at each of eight nodes, and f32's arithmetic).
        let Some((host, margin)) = turn(tables, (x, y, phi)) else {
            continue;
        };
        if margin < 20.0 * f64::from(scale) {
            continue;
        }
        // Only where the reader has a value at every landing, read from the table the host
        // reads it from: beyond the longest time it keeps it reads "never" and drops that turn,
        // where the solver still has a large time.
        let Some(table) = finest(tables, (x, y, phi)) else {
            continue;
        };
        let (sin, cos) = phi.sin_cos();
        let game = table.game;
        let landings_read = [-1.0, 0.0, 1.0].iter().all(|&u| {
            game.evader_controls().iter().all(|&(speed, w)| {
                let (nx, ny, nphi) = Step::new(speed, table.tau, u, w).from((x, y, phi, sin, cos));
                let level = tables
                    .iter()
                    .position(|t| nx.abs() <= t.grid.half && ny.abs() <= t.grid.half);
                level.is_some_and(|l| {
                    readers[l]
                        .value(nx as f32, ny as f32, nphi as f32)
                        .is_some()
                })
            })
        });
        if !landings_read {
            continue;
        }
        let Some(read) = set.pursuer_turn(x as f32, y as f32, phi as f32) else {
            continue;
        };
        assert_eq!(f64::from(read), host, "({x}, {y}, {phi}): margin {margin}");
        clear += 1;
        // The evader's turn likewise, where its choice is clear (every landing was read).
        if let Some((w, margin)) = evader_turn(tables, (x, y, phi)) {
            if margin > 20.0 * f64::from(scale) {
                let read = set.evader_turn(x as f32, y as f32, phi as f32);
                assert_eq!(
                    read.map(f64::from),
                    Some(w),
                    "({x}, {y}, {phi}): evader margin {margin}"
                );
                evader_clear += 1;
            }
        }
    }
    (clear, evader_clear)
}

/// Where the host's table pursuer clearly prefers a turn, the firmware's reader of the
/// quantised table takes the same.
#[test]
fn the_optimal_turn_is_the_solvers() {
    let set = ValueTables::parse(bytes()).unwrap();
    let (clear, evader_clear) = turns_agree(std::slice::from_ref(solution()), &set, 5.5, 20_000);
    assert!(
        clear > 5_000 && evader_clear > 1_000,
        "{clear}, {evader_clear} clear states"
    );
}

/// Around a capture disc the grid resolves (radius 1 r_p, ten cells), where steps end in the
/// disc behind the part of its edge where the evader slips past (the nodes there keep V two
/// cells outside, for interpolating outside the disc), the reader counts such a landing as
/// captured, as the solver and the host's pursuer do, and takes the host's turn.
#[test]
fn around_the_disc_the_reader_turns_as_the_solver() {
    let game = Game::with_radius([2.0, 2.0, 1.2, 1.2], 1.0);
    let grid = Grid {
        n: 41,
        half: 2.0,
        headings: 36,
    };
    let solution = solve(game, grid, grid.step_time(), 1e-4, 200, |_, _| {});
    let bytes: &'static [u8] = Box::leak(solution.table_bytes().into_boxed_slice());
    let set = ValueTables::parse(bytes).unwrap();
    let (clear, _) = turns_agree(std::slice::from_ref(&solution), &set, 1.6, 20_000);
    assert!(clear > 2_000, "{clear} clear states");
}

/// Two nested tables (+-2 r_p at 0.1 r_p inside the 41-node table, solved with its values as
/// the boundary), written as one set: the reader's turn is the host's nested pursuer's, in the
/// inner box, across its edge and outside it.
#[test]
fn nested_tables_turn_as_the_solvers() {
    let outer = solution();
    let grid = Grid {
        n: 41,
        half: 2.0,
        headings: 32,
    };
    let inner = solve_with_boundary(
        outer.game,
        grid,
        Sweeps::on(&grid, 1e-6),
        |x, y, phi| outer.value(x, y, phi),
        |_, _| {},
    );
    let tables = [inner, outer.clone()];
    let bytes = table_set_bytes(&tables);
    let set = ValueTables::parse(&bytes).unwrap();
    assert_eq!(set.tables().count(), 2);
    // Half the points fall in the inner box.
    let (clear, evader_clear) = turns_agree(&tables, &set, 3.0, 20_000);
    assert!(
        clear > 5_000 && evader_clear > 1_000,
        "{clear}, {evader_clear} clear states"
    );
    // The set's V is the finest table's where it plays.
    let (x, y, phi) = (1.0_f32, -0.8_f32, 0.4_f32);
    let expected = tables[0].value(f64::from(x), f64::from(y), f64::from(phi));
    let read = f64::from(set.value(x, y, phi).unwrap());
    assert!((read - expected).abs() < 1e-3, "{read} vs {expected}");
    // A set of tables of different games, or with trailing bytes, is refused.
    let mut other = outer.clone();
    other.game.eps = 0.6;
    let mixed = table_set_bytes(&[tables[0].clone(), other]);
    assert_eq!(ValueTables::parse(&mixed), Err(TableError::Header));
    let mut trailing = bytes.clone();
    trailing.push(0);
    assert!(ValueTables::parse(&trailing).is_err());
}

#[test]
fn malformed_tables_are_refused_never_read() {
    let good = bytes();
    assert_eq!(ValueTable::parse(&good[..3]), Err(TableError::Short));
    assert_eq!(
        ValueTable::parse(&good[..HEADER_LEN]),
        Err(TableError::Short)
    );
    assert_eq!(
        ValueTable::parse(&good[..good.len() - 1]),
        Err(TableError::Short)
    );
    let mut magic = good.to_vec();
    magic[0] = b'X';
    assert_eq!(ValueTable::parse(&magic), Err(TableError::Magic));
    // Each header field made absurd in turn: NaN ratios, a speed ratio of 1.5, a radius as
    // large as the box, a zero scale, a grid of 2 nodes or 1 heading.
    for (at, bytes) in [
        (4, f32::NAN.to_le_bytes().to_vec()),
        (4, 1.5_f32.to_le_bytes().to_vec()),
        (8, f32::INFINITY.to_le_bytes().to_vec()),
        (12, 6.0_f32.to_le_bytes().to_vec()),
        (20, 0.0_f32.to_le_bytes().to_vec()),
        (24, 2_u16.to_le_bytes().to_vec()),
        (26, 1_u16.to_le_bytes().to_vec()),
    ] {
        let mut bad = good.to_vec();
        bad[at..at + bytes.len()].copy_from_slice(&bytes);
        assert_eq!(
            ValueTable::parse(&bad),
            Err(TableError::Header),
            "field at {at}"
        );
    }
    // A table of all "never": every read is None, the turn too.
    let mut never = good[..HEADER_LEN].to_vec();
    never.extend(std::iter::repeat_n(NEVER.to_le_bytes(), 41 * 21 * 24).flatten());
    let set = ValueTables::parse(&never).unwrap();
    assert_eq!(set.value(1.0, 1.0, 0.0), None);
    assert_eq!(set.pursuer_turn(1.0, 1.0, 0.0), None);
    // Random bytes behind a valid magic: refused or read, never a panic.
    let mut rng = Rng::new(32);
    for _ in 0..2_000 {
        let len = (rng.next_u64() % 200) as usize;
        let mut b = MAGIC.to_vec();
        b.extend((0..len).map(|_| rng.next_u64() as u8));
        if let Ok(t) = ValueTables::parse(&b) {
            let _ = t.value(0.5, -0.5, 1.0);
            let _ = t.pursuer_turn(0.5, -0.5, 1.0);
        }
    }
}

/// The bench's table (`bench/table.tcv`) is what `cargo xtask hj --nodes 21 --eps 0.6
/// --table bench/table.tcv` writes (the solver is deterministic), and the bench's points
/// all have a value in it.
#[test]
fn the_committed_bench_table_is_the_solvers() {
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.6);
    let grid = Grid {
        n: 21,
        half: 6.0,
        headings: 24,
    };
    let fresh = solve(game, grid, grid.step_time(), 1e-6, 20_000, |_, _| {}).table_bytes();
    let committed = twocars_bench::TABLE;
    assert!(fresh[..] == committed[..], "regenerate bench/table.tcv");
    let table = ValueTables::parse(committed).unwrap();
    for [x, y, phi] in twocars_bench::TABLE_POINTS {
        assert!(table.value(x, y, phi).is_some() && table.pursuer_turn(x, y, phi).is_some());
    }
}

/// On a grid that resolves the capture disc (its radius five cells), the nodes in the disc keep
/// minus their depth behind the usable part of its edge (`hj::usable`, itself checked against
/// exact steps off the edge) and V two cells outside behind the rest, and the firmware reads
/// the values around the disc as the solver wrote them, within half a code.
#[test]
fn behind_the_non_usable_edge_the_disc_keeps_the_value_outside() {
    use hji::usable;
    let game = Game::with_radius([2.0, 2.0, 1.0, 1.0], 0.5);
    let pi = std::f64::consts::PI;
    let mut rng = Rng::new(42);
    // The usable edge: the distance falls under every evader control, whatever the turn.
    let mut checked = 0;
    for _ in 0..2_000 {
        let (bearing, phi) = (rng.uniform(-pi, pi), rng.uniform(-pi, pi));
        let (x, y) = (game.eps * bearing.cos(), game.eps * bearing.sin());
        let rate = game.speed_ratio * (x * phi.cos() + y * phi.sin()) - x;
        if rate.abs() < 1e-2 {
            continue;
        }
        let (s, c) = phi.sin_cos();
        let falls = [-1.0, 0.0, 1.0].iter().all(|&u| {
            game.evader_controls().iter().all(|&(a, w)| {
                let (nx, ny, _) = Step::new(a, 1e-4, u, w).from((x, y, phi, s, c));
                nx.hypot(ny) < game.eps
            })
        });
        assert_eq!(usable(&game, x, y, phi), falls, "({x}, {y}, {phi})");
        checked += 1;
    }
    assert!(checked > 1_500);
    let grid = Grid {
        n: 41,
        half: 2.0,
        headings: 24,
    };
    let s = solve(game, grid, grid.step_time(), 1e-6, 5_000, |_, _| {});
    let h = grid.spacing();
    let (mut depth, mut kept) = (0, 0);
    for i in 0..grid.n {
        for j in 0..grid.n {
            let (x, y) = (-grid.half + i as f64 * h, -grid.half + j as f64 * h);
            if x.hypot(y) > game.eps || (x == 0.0 && y == 0.0) {
                continue;
            }
            for k in 0..grid.headings {
                let phi = -pi + k as f64 * std::f64::consts::TAU / grid.headings as f64;
                let v = s.value(x, y, phi);
                if usable(&game, x, y, phi) {
                    let want = x.hypot(y) - game.eps;
                    assert!((v - want).abs() < 1e-9, "({x}, {y}, {phi}): {v} vs {want}");
                    depth += 1;
                } else {
                    let out = (game.eps + 2.0 * h) / x.hypot(y);
                    let outside = s.value(x * out, y * out, phi);
                    assert!(
                        (v - outside).abs() < 1e-5,
                        "({x}, {y}, {phi}): {v} vs {outside}"
                    );
                    assert!(v > 0.0, "({x}, {y}, {phi}): {v}");
                    kept += 1;
                }
            }
        }
    }
    assert!(depth > 500 && kept > 500, "{depth} depths, {kept} kept");
    let bytes = s.table_bytes();
    let table = ValueTable::parse(&bytes).unwrap();
    let scale = f64::from(table.scale);
    let mut compared = 0;
    for _ in 0..5_000 {
        let r = game.eps + rng.uniform(0.0, 2.0 * h);
        let bearing = rng.uniform(-pi, pi);
        let (x, y, phi) = (r * bearing.cos(), r * bearing.sin(), rng.uniform(-pi, pi));
        let want = s.value(x, y, phi);
        if let Some(got) = table.value(x as f32, y as f32, phi as f32) {
            assert!(
                (f64::from(got) - want).abs() <= 0.5 * scale + 1e-5 * want.abs(),
                "({x}, {y}, {phi}): table {got}, solver {want}"
            );
            compared += 1;
        }
    }
    // The others are next to states from which capture within the box was not found.
    assert!(compared > 1_000, "{compared} compared");
}
