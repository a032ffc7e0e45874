//! Reading V between the grid's nodes: trilinear, a limited tricubic read that keeps smooth V
//! to third order in the spacing without new extrema, or that read filtered toward the
//! trilinear where V bends.

use crate::grid::{Grid, REACHED};

/// How the solver reads V where a step lands between nodes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Read {
    /// Trilinear on the cell's 8 corners: first order where V is smooth, and it never
    /// overshoots.
    Trilinear,
    /// Cubic Lagrange on the 4 x 4 x 4 nodes around the cell, clamped to the least and the
    /// largest of the cell's 8 corners, so that it adds no extremum where V jumps; trilinear
    /// where the stencil leaves the box or holds a node not captured, and on grids whose capture
    /// disc is less than two cells across its radius ([`crate::reads_cubic`]). Along a tail chase
    /// its error stays flat with the distance, where the trilinear read's grows by about a
    /// hundredth of r_p / v_pm per r_p on a 0.1 r_p grid.
    Cubic,
    /// The limited tricubic within [`FILTER`] h^2 of the trilinear read (h the spacing): a
    /// filtered scheme, high order where V is smooth and near the monotone trilinear scheme
    /// where V bends or jumps within a cell. Unfiltered, the cubic's undershoots at a bend are
    /// the pursuer's to pick: with five pursuer turn rates at 81 x 81 x 42, the evader 3 r_p
    /// dead ahead facing the pursuer read 2.374 r_p / v_pm, below the 2.4 it takes to close on
    /// an evader that stops.
    #[default]
    Filtered,
}

/// The filter's width, in units of the squared spacing (r_p / v_pm per r_p^2). Against
/// hj_reachability at 81 x 81 x 42 with five turn rates, the median difference where V is smooth
/// read 0.0166, 0.0107, 0.0119 and 0.0122 with 0.03, 0.1, 0.3 and 1, and 0.0165 unfiltered.
/// Widening it by the span of a cell's corners beyond 2 r_p / v_pm, so that the clamped cubic
/// keeps V's jumps (2.46 / 4.24 cells p50 / p90 at 81 x 81 x 42, against 2.81 / 4.68), left the
/// sweeps cycling at a residual of 0.1 r_p / v_pm on a 41 x 41 x 24 grid whose disc is two
/// cells across its radius, where the filter alone and the cubic alone converge.
pub const FILTER: f64 = 0.1;

/// The cell around a point of the box: its lower corner's indices (phi wrapped) and the
/// point's fractions of a cell along each axis.
struct Cell {
    corner: (usize, usize, usize),
    fraction: (f64, f64, f64),
}

impl Grid {
    /// The cell holding `(x, y, phi)`, none outside the box.
    #[inline]
    fn cell(&self, x: f64, y: f64, phi: f64) -> Option<Cell> {
        let h = self.spacing();
        let (fx, fy) = ((x + self.half) / h, (y + self.half) / h);
        let last = (self.n - 1) as f64;
        if !(0.0..=last).contains(&fx) || !(0.0..=last).contains(&fy) {
            return None;
        }
        // Turns from -pi, wrapped into [0, 1) by a truncating cast (no call to fmod).
        let turns = (phi + std::f64::consts::PI) / std::f64::consts::TAU;
        let wrapped = turns - (turns as i64) as f64;
        let fk = (wrapped + if wrapped < 0.0 { 1.0 } else { 0.0 }) * self.headings as f64;
        // The casts truncate: the floor of these non-negative fractions, without a call to
        // floor() on targets without a rounding instruction.
        let (i, j, k) = (
            (fx as usize).min(self.n - 2),
            (fy as usize).min(self.n - 2),
            fk as usize,
        );
        Some(Cell {
            corner: (i, j, k % self.headings),
            fraction: (fx - i as f64, fy - j as f64, fk - k as f64),
        })
    }
}

/// V at `(x, y, phi)` (r_p, radians) read from the node `values` by `read`, periodic in phi;
/// `None` outside the box.
pub(crate) fn read(
    grid: &Grid,
    values: &[f64],
    read: Read,
    (x, y, phi): (f64, f64, f64),
) -> Option<f64> {
    let cell = grid.cell(x, y, phi)?;
    let linear = trilinear(grid, values, &cell);
    if read == Read::Trilinear {
        return Some(linear);
    }
    // One call of the cubic, which the sweep's loop inlines: with a second, the 81-node solve
    // took 55 s, not 31.
    Some(cubic(grid, values, &cell).map_or(linear, |cubic| {
        if read == Read::Cubic {
            return cubic;
        }
        let h = grid.spacing();
        let width = FILTER * h * h;
        linear + (cubic - linear).clamp(-width, width)
    }))
}

fn trilinear(grid: &Grid, values: &[f64], cell: &Cell) -> f64 {
    let ((i0, j0, k0), (tx, ty, tk)) = (cell.corner, cell.fraction);
    let k1 = (k0 + 1) % grid.headings;
    let mut v = 0.0;
    for (k, wk) in [(k0, 1.0 - tk), (k1, tk)] {
        for (j, wj) in [(j0, 1.0 - ty), (j0 + 1, ty)] {
            for (i, wi) in [(i0, 1.0 - tx), (i0 + 1, tx)] {
                let w = wi * wj * wk;
                if w > 0.0 {
                    v += w * values[grid.index(i, j, k)];
                }
            }
        }
    }
    v
}

/// The cubic Lagrange weights of the nodes at -1, 0, 1 and 2 for a point at `t` in [0, 1].
fn weights(t: f64) -> [f64; 4] {
    let (a, b, c, d) = (t + 1.0, t, t - 1.0, t - 2.0);
    [
        -b * c * d / 6.0,
        a * c * d / 2.0,
        -a * b * d / 2.0,
        a * b * c / 6.0,
    ]
}

/// The limited tricubic read, none where its stencil leaves the box or holds a node not
/// captured ([`REACHED`] or more).
fn cubic(grid: &Grid, values: &[f64], cell: &Cell) -> Option<f64> {
    let ((i0, j0, k0), (tx, ty, tk)) = (cell.corner, cell.fraction);
    if i0 == 0 || j0 == 0 || i0 + 2 >= grid.n || j0 + 2 >= grid.n {
        return None;
    }
    let (wx, wy, wk) = (weights(tx), weights(ty), weights(tk));
    let h = grid.headings;
    let (mut v, mut low, mut high) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    for (dk, wk) in wk.iter().enumerate() {
        let k = (k0 + h + dk - 1) % h;
        for (dj, wj) in wy.iter().enumerate() {
            let j = j0 + dj - 1;
            let row = &values[grid.index(i0 - 1, j, k)..=grid.index(i0 + 2, j, k)];
            if row.iter().any(|&node| node >= REACHED) {
                return None;
            }
            let along: f64 = row.iter().zip(wx).map(|(node, w)| node * w).sum();
            v += wk * wj * along;
            if (1..=2).contains(&dk) && (1..=2).contains(&dj) {
                for &node in &row[1..=2] {
                    low = low.min(node);
                    high = high.max(node);
                }
            }
        }
    }
    Some(v.clamp(low, high))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::NEVER;

    const GRID: Grid = Grid {
        n: 9,
        half: 2.0,
        headings: 8,
    };

    /// The nodes' values of `f(x, y, phi)`, in the solver's layout.
    fn nodes(f: impl Fn(f64, f64, f64) -> f64) -> Vec<f64> {
        let h = GRID.spacing();
        let turn = std::f64::consts::TAU / GRID.headings as f64;
        let mut values = vec![0.0; GRID.n * GRID.n * GRID.headings];
        for k in 0..GRID.headings {
            for j in 0..GRID.n {
                for i in 0..GRID.n {
                    let (x, y) = (-GRID.half + i as f64 * h, -GRID.half + j as f64 * h);
                    let phi = -std::f64::consts::PI + k as f64 * turn;
                    values[GRID.index(i, j, k)] = f(x, y, phi);
                }
            }
        }
        values
    }

    #[test]
    fn the_cubic_read_is_exact_for_a_cubic_and_the_trilinear_is_not() {
        // Rising along each axis, so that the clamp to the cell's corners does not cut it.
        let f = |x: f64, y: f64| x * x * x + 2.0 * x + 0.5 * y * y * y + y;
        let values = nodes(|x, y, _| f(x, y));
        let at = (0.37, -0.81, 0.3);
        let cubic = read(&GRID, &values, Read::Cubic, at).unwrap();
        let trilinear = read(&GRID, &values, Read::Trilinear, at).unwrap();
        assert!((cubic - f(at.0, at.1)).abs() < 1e-12, "{cubic}");
        assert!((trilinear - f(at.0, at.1)).abs() > 1e-3, "{trilinear}");
    }

    #[test]
    fn the_filtered_read_is_the_cubic_where_v_is_smooth_and_near_the_trilinear_at_a_bend() {
        // Gentle: the cubic's correction of the trilinear is within the filter.
        let gentle = |x: f64, y: f64| 0.01 * x * x * x + x + 0.02 * y * y;
        let values = nodes(|x, y, _| gentle(x, y));
        let at = (0.37, -0.81, 0.3);
        let filtered = read(&GRID, &values, Read::Filtered, at).unwrap();
        assert!((filtered - gentle(at.0, at.1)).abs() < 1e-12, "{filtered}");
        // A bend (|x|, rising along y so that the clamp does not cut it) between nodes: the
        // cubic reads below the trilinear by more than the filter lets through.
        let values = nodes(|x, y, _| (x - 0.1).abs() + y);
        let at = (0.1, 0.2, 0.3);
        let h = GRID.spacing();
        let [cubic, filtered, trilinear] = [Read::Cubic, Read::Filtered, Read::Trilinear]
            .map(|how| read(&GRID, &values, how, at).unwrap());
        assert!(trilinear - cubic > FILTER * h * h, "{cubic} {trilinear}");
        assert!(
            (trilinear - filtered - FILTER * h * h).abs() < 1e-12,
            "{filtered}"
        );
    }

    #[test]
    fn the_filtered_read_stays_within_the_filter_of_the_trilinear_across_a_jump() {
        let values = nodes(|x, _, _| if x > 0.25 { 10.0 } else { 0.0 });
        let width = FILTER * GRID.spacing() * GRID.spacing();
        for t in [0.1, 0.3, 0.7, 0.9] {
            let at = (0.5 * t, 0.2, 1.0);
            let filtered = read(&GRID, &values, Read::Filtered, at).unwrap();
            let trilinear = read(&GRID, &values, Read::Trilinear, at).unwrap();
            let cubic = read(&GRID, &values, Read::Cubic, at).unwrap();
            assert!(
                (filtered - trilinear).abs() <= width + 1e-12,
                "{t}: {filtered}"
            );
            assert!((cubic - trilinear).abs() > width, "{t}: {cubic}");
        }
    }

    #[test]
    fn the_cubic_read_stays_within_its_cells_corners_at_a_jump() {
        // V jumps from 0 to 10 between x = 0 and x = 0.5: the cubic overshoots there unclamped.
        let values = nodes(|x, _, _| if x > 0.25 { 10.0 } else { 0.0 });
        for t in [0.1, 0.3, 0.5, 0.7, 0.9] {
            let v = read(&GRID, &values, Read::Cubic, (0.5 * t, 0.2, 1.0)).unwrap();
            assert!((0.0..=10.0).contains(&v), "{t}: {v}");
        }
        // Beside the jump's cell, both corners are 0: so is the read.
        let v = read(&GRID, &values, Read::Cubic, (-0.3, 0.2, 1.0)).unwrap();
        assert_eq!(v, 0.0);
    }

    #[test]
    fn the_cubic_read_falls_back_to_trilinear_beside_never_and_at_the_box_edge() {
        let values = nodes(|x, y, phi| {
            if x > 1.2 {
                NEVER
            } else {
                x * x * x + y + phi.cos()
            }
        });
        // The stencil of the cell [0.5, 1] reaches x = 1.5: never captured.
        let beside = (0.8, 0.1, 0.4);
        // The cell [-2, -1.5] has no node left of it.
        let edge = (-1.9, 0.1, 0.4);
        for at in [beside, edge] {
            let cubic = read(&GRID, &values, Read::Cubic, at);
            assert_eq!(cubic, read(&GRID, &values, Read::Trilinear, at), "{at:?}");
        }
        assert_eq!(read(&GRID, &values, Read::Cubic, (2.1, 0.0, 0.0)), None);
    }

    #[test]
    fn the_read_is_periodic_in_the_relative_heading() {
        let values = nodes(|x, y, phi| x + y * phi.sin() + (2.0 * phi).cos());
        for how in [Read::Cubic, Read::Trilinear] {
            let a = read(&GRID, &values, how, (0.3, 0.4, 3.0)).unwrap();
            let b = read(&GRID, &values, how, (0.3, 0.4, 3.0 - std::f64::consts::TAU)).unwrap();
            let c = read(&GRID, &values, how, (0.3, 0.4, 3.0 + std::f64::consts::TAU)).unwrap();
            assert!(
                (a - b).abs() < 1e-9 && (a - c).abs() < 1e-9,
                "{how:?}: {a} {b} {c}"
            );
        }
    }
}
