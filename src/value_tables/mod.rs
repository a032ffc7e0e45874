//! Nested value tables: the near field's V as a few [`ValueTable`]s of one game, the
//! finest over the smallest box, each solved with the next coarser one's values where its steps
//! leave its box (`cargo xtask hj --set FILE`, docs/near-field.md). A state is read from the
//! finest table whose box holds it less two cells; the tables play inside the theorem's
//! threshold and outside the capture disc (the paper's law beyond it).
//!
//! Format: the tables' bytes back to back, finest first, each in [`crate::value_tables::table`]'s
//! format; at most [`MAX_LEVELS`].

pub mod table;

use crate::num::f32_math::{sin_cos, wrap_signed};
use table::{TableError, ValueTable, PURSUER_TURNS};

/// The most tables a set holds.
pub const MAX_LEVELS: usize = 4;

/// A set of nested tables borrowed from flash, finest first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValueTables<'a> {
    levels: [Option<ValueTable<'a>>; MAX_LEVELS],
}

impl<'a> ValueTables<'a> {
    /// Reads the tables of `bytes` back to back, finest first.
    ///
    /// # Errors
    /// [`TableError`]: no table, a malformed one, more than [`MAX_LEVELS`], or tables of
    /// different games (ratios or capture radius).
    pub fn parse(bytes: &'a [u8]) -> Result<Self, TableError> {
        let mut levels = [None; MAX_LEVELS];
        let mut rest = bytes;
        for level in &mut levels {
            if rest.is_empty() {
                break;
            }
            let table = ValueTable::parse(rest)?;
            rest = rest.get(table.len_bytes()..).ok_or(TableError::Short)?;
            *level = Some(table);
        }
        let first = levels[0].ok_or(TableError::Short)?;
        let same_game = levels.iter().flatten().all(|t| {
            (t.speed_ratio, t.evader_turn, t.eps)
                == (first.speed_ratio, first.evader_turn, first.eps)
        });
        if !rest.is_empty() || !same_game {
            return Err(TableError::Header);
        }
        Ok(ValueTables { levels })
    }

    /// The finest table.
    pub fn finest_table(&self) -> Option<&ValueTable<'a>> {
        self.levels[0].as_ref()
    }

    /// The tables, finest first.
    pub fn tables(&self) -> impl Iterator<Item = &ValueTable<'a>> {
        self.levels.iter().flatten()
    }

    /// The finest table that plays at `(x, y)` (r_p): its box holds it less two cells, and it
    /// lies inside the theorem's threshold and outside the capture disc.
    fn finest(&self, x: f32, y: f32) -> Option<&ValueTable<'a>> {
        let table = self.tables().find(|t| {
            let margin = t.half - 2.0 * t.spacing();
            x.abs() < margin && y.abs() < margin
        })?;
        let r2 = x * x + y * y;
        let threshold = table.threshold();
        (r2 > table.eps * table.eps && r2 < threshold * threshold).then_some(table)
    }

    /// V at `(x, y, phi)` (r_p, radians), r_p / v_pm, from the finest table that plays there;
    /// `None` where none does or it has no value.
    pub fn value(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        self.finest(x, y)?.value(x, y, phi)
    }

    /// V where a step lands: from the finest table whose box holds it, to its edge. A landing
    /// in the capture disc was captured within the step, as the solver counts it: at most 0.
    fn landing(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let table = self.tables().find(|t| t.holds(x, y))?;
        let v = table.value(x, y, phi);
        if table.captures(x, y) {
            return Some(v.map_or(0.0, |v| v.min(0.0)));
        }
        v
    }

    /// The pursuer's optimal turn at `(x, y, phi)`: -1, 0 or 1, the sign of its turn rate u
    /// (positive: its heading grows, as the law's curvature). In the finest table that plays
    /// there: for each turn, the largest V over the evader's four controls one solver step
    /// ahead ([`crate::value_tables::table::step_time`], exact arcs), each landing read from the
    /// finest table whose box holds it; the turn whose worst case is least, straight keeping
    /// ties: the minimax the solver solved, read back (docs/near-field.md). A landing in the
    /// capture disc counts as captured (at most 0), one without a value as that turn's worst
    /// case. `None` where no table plays or has a value, or no turn keeps the evader in the
    /// tables.
    pub fn pursuer_turn(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let table = self.finest(x, y)?;
        table.value(x, y, phi)?;
        let phi = wrap_signed(phi);
        let heading = sin_cos(phi);
        let mut best: Option<(f32, f32)> = None;
        for (&u, row) in PURSUER_TURNS.iter().zip(table.steps()) {
            let mut worst = Some(f32::NEG_INFINITY);
            for step in row {
                let (nx, ny, nphi) = step.from(x, y, phi, heading);
                worst = match (worst, self.landing(nx, ny, nphi)) {
                    (Some(w), Some(v)) => Some(w.max(v)),
                    _ => None,
                };
            }
            if let Some(worst) = worst {
                if best.is_none_or(|(_, least)| worst < least) {
                    best = Some((u, worst));
                }
            }
        }
        best.map(|(u, _)| u)
    }

    /// The evader's optimal turn at `(x, y, phi)` at full speed: -1, 0 or 1, the sign of its
    /// turn rate. In the finest table that plays there: for each of its turns, the least V over
    /// the pursuer's three one solver step ahead; the turn whose best case for the pursuer is
    /// largest, straight keeping ties (the host's `hji::policy::evader_curvature`). A landing
    /// without a value counts as never captured (the evader's best). `None` where no table
    /// plays or has a value.
    pub fn evader_turn(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let table = self.finest(x, y)?;
        table.value(x, y, phi)?;
        let phi = wrap_signed(phi);
        let heading = sin_cos(phi);
        let steps = table.steps();
        let mut best: Option<(f32, f32)> = None;
        // The evader's full-speed controls are columns 0 (right), 1 (straight), 2 (left):
        // destructured, not indexed, so that no bounds check (a panic path) is left.
        for sign in [0.0_f32, 1.0, -1.0] {
            let mut least = f32::INFINITY;
            for [right, straight, left, _] in steps {
                let step = if sign > 0.0 {
                    left
                } else if sign < 0.0 {
                    right
                } else {
                    straight
                };
                let (nx, ny, nphi) = step.from(x, y, phi, heading);
                least = least.min(self.landing(nx, ny, nphi).unwrap_or(f32::INFINITY));
            }
            if best.is_none_or(|(_, most)| least > most) {
                best = Some((sign, least));
            }
        }
        best.map(|(w, _)| w)
    }
}
