//! The game's value V as a table the firmware reads: the Hamilton-Jacobi-Isaacs
//! solution of `cargo xtask hj`, quantised to u16 per node, and the pursuer's optimal turn read
//! from it by the solver's own one-step minimax.
//!
//! The reduced game (docs/near-field.md): `(x, y)` is the evader's position relative to the
//! pursuer (x along the pursuer's heading, y to its left), `phi` the evader's heading relative
//! to the pursuer's; lengths in r_p, times in r_p / v_pm. One table serves every pair of limits
//! with its two ratios v_em / v_pm and r_e / r_p.
//!
//! Format, little endian: the magic `TCV2`; f32 v_em / v_pm, the evader's turn rate (rad per
//! r_p / v_pm), the capture radius (r_p), half the box's side (r_p) and the time per code
//! (r_p / v_pm); u16 nodes per position axis `n` (odd) and headings per turn; then the u16
//! codes of the rows y >= 0 only, `n * (n + 1) / 2 * headings` of them: node (i, j, k) with
//! j >= c = (n - 1) / 2 at `(k (n - c) + j - c) n + i`, x = -half + i h, y = -half + j h,
//! phi = -pi + 2 pi k / headings. A row y < 0 is its mirror's: V(x, y, phi) = V(x, -y, -phi),
//! node (i, n - 1 - j, (headings - k) mod headings). Code [`NEVER`]: capture within the box was
//! not found there. A node inside the capture disc with code 0 is not read: its value is
//! r - eps, minus its depth (as the solver keeps it behind the usable part of the disc's edge),
//! so that V's zero lies on the edge; one with another code is read as any node (behind the
//! rest of the edge, where V jumps, the solver keeps V two cells outside). A table with code 0
//! at every node in the disc reads as the depth everywhere there.
//!
//! Reads are bounds-checked and allocation-free; a malformed table is refused by
//! [`ValueTable::parse`], never read.

use crate::law::geometry::theorem_threshold;
use crate::num::f32_math::{sin_cos, wrap_signed};

/// The table's magic bytes (format version 2: the rows y >= 0 only, the nodes in the capture
/// disc valued by their depth, the evader's stop among its controls).
pub const MAGIC: [u8; 4] = *b"TCV2";
/// Bytes before the codes.
pub const HEADER_LEN: usize = 4 + 5 * 4 + 2 * 2;
/// The code of a node from which capture was not found.
pub const NEVER: u16 = u16::MAX;
/// The pursuer's turns in the order ties keep: straight, left, right.
pub(crate) const PURSUER_TURNS: [f32; 3] = [0.0, 1.0, -1.0];

/// The shortest time step of the solver and of the reader's look-ahead, r_p / v_pm. Each
/// step interpolates V once, and interpolation smears V's jumps: half a cell's time on a
/// 0.05 r_p grid put V 30 % low where the evader grazes the capture disc (docs/near-field.md,
/// "The solver").
pub const MIN_STEP: f32 = 0.2;

/// The time step (r_p / v_pm) on a grid whose cells are `spacing` (r_p) across: half a cell's
/// time at the pursuer's speed, or [`MIN_STEP`] where that is shorter.
pub fn step_time(spacing: f32) -> f32 {
    (0.5 * spacing).max(MIN_STEP)
}

/// One step of the reduced game, both controls held for tau (the solver's `Step`, in f32): the
/// pursuer's displacement and the sine and cosine of its turn, the evader's displacement in
/// its own frame, the relative heading's change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Step {
    pursuer: (f32, f32),
    turn: (f32, f32),
    evader: (f32, f32),
    heading: f32,
}

impl Step {
    fn new(a: f32, tau: f32, u: f32, w: f32) -> Self {
        // A car's displacement over tau at unit speed turning at `rate`, and its small-rate
        // limit.
        let arc = |rate: f32| {
            let turn = rate * tau;
            if turn.abs() < 1e-4 {
                (tau, 0.5 * turn * tau)
            } else {
                let (s, c) = sin_cos(turn);
                (s / rate, (1.0 - c) / rate)
            }
        };
        let (ex, ey) = arc(w);
        Step {
            pursuer: arc(u),
            turn: sin_cos(u * tau),
            evader: (a * ex, a * ey),
            heading: tau * (w - u),
        }
    }

    /// Where the evader at `(x, y, phi)` (heading sine `s`, cosine `c`) is after the step.
    pub(crate) fn from(&self, x: f32, y: f32, phi: f32, (s, c): (f32, f32)) -> (f32, f32, f32) {
        let ((px, py), (ts, tc), (ex, ey)) = (self.pursuer, self.turn, self.evader);
        let (dx, dy) = (x + ex * c - ey * s - px, y + ex * s + ey * c - py);
        (dx * tc + dy * ts, -dx * ts + dy * tc, phi + self.heading)
    }
}

/// Why a table was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TableError {
    /// Shorter than its header, or than its header says.
    Short,
    /// Not a table of this format.
    Magic,
    /// A header field out of its range (ratios, radius, box, scale, grid).
    Header,
}

/// A value table borrowed from flash (or any byte slice).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValueTable<'a> {
    /// v_em / v_pm, in (0, 1).
    pub speed_ratio: f32,
    /// The evader's largest turn rate, rad per r_p / v_pm: (v_em / v_pm) (r_p / r_e).
    pub evader_turn: f32,
    /// The capture radius, r_p.
    pub eps: f32,
    /// Half the box's side, r_p.
    pub half: f32,
    /// Time per code, r_p / v_pm.
    pub scale: f32,
    n: usize,
    headings: usize,
    spacing: f32,
    /// The theorem's threshold, r_p.
    threshold: f32,
    /// The steps of the pursuer's turn `PURSUER_TURNS[p]` and the evader's control `e` (full
    /// speed turning right, straight, turning left; standing still) over the solver's tau
    /// ([`step_time`]).
    steps: [[Step; 4]; 3],
    codes: &'a [u8],
}

fn f32_at(bytes: &[u8], at: usize) -> Option<f32> {
    let b = bytes.get(at..at + 4)?;
    Some(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn u16_at(bytes: &[u8], at: usize) -> Option<u16> {
    let b = bytes.get(at..at + 2)?;
    Some(u16::from_le_bytes([b[0], b[1]]))
}

impl<'a> ValueTable<'a> {
    /// Reads a table's header and checks its length.
    ///
    /// # Errors
    /// [`TableError`]: too short, wrong magic, or a header field out of range.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, TableError> {
        if bytes.get(..4).ok_or(TableError::Short)? != MAGIC {
            return Err(TableError::Magic);
        }
        let field = |i: usize| f32_at(bytes, 4 + 4 * i).ok_or(TableError::Short);
        let (speed_ratio, evader_turn, eps, half, scale) =
            (field(0)?, field(1)?, field(2)?, field(3)?, field(4)?);
        let n = usize::from(u16_at(bytes, 24).ok_or(TableError::Short)?);
        let headings = usize::from(u16_at(bytes, 26).ok_or(TableError::Short)?);
        let positive = |v: f32| v.is_finite() && v > 0.0;
        let valid = positive(speed_ratio)
            && speed_ratio < 1.0
            && positive(evader_turn)
            && positive(eps)
            && positive(half)
            && eps < half
            && positive(scale)
            && n >= 3
            && n % 2 == 1
            && headings >= 2;
        if !valid {
            return Err(TableError::Header);
        }
        let count = n * n.div_ceil(2) * headings;
        let codes = bytes
            .get(HEADER_LEN..HEADER_LEN + 2 * count)
            .ok_or(TableError::Short)?;
        let spacing = 2.0 * half / (n - 1) as f32;
        let tau = step_time(spacing);
        let evader = [
            (speed_ratio, -evader_turn),
            (speed_ratio, 0.0),
            (speed_ratio, evader_turn),
            (0.0, 0.0),
        ];
        let steps = PURSUER_TURNS.map(|u| evader.map(|(a, w)| Step::new(a, tau, u, w)));
        let r_e = speed_ratio / evader_turn;
        Ok(ValueTable {
            threshold: theorem_threshold(r_e, 1.0, speed_ratio),
            speed_ratio,
            evader_turn,
            eps,
            half,
            scale,
            n,
            headings,
            spacing,
            steps,
            codes,
        })
    }

    /// Nodes per position axis and headings per turn.
    pub fn grid(&self) -> (usize, usize) {
        (self.n, self.headings)
    }

    /// The position spacing, r_p.
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// Where row j of heading k starts among the codes (a node index): rows below the x axis
    /// are their mirrors'.
    fn row(&self, j: usize, k: usize) -> usize {
        let centre = self.n / 2;
        let (j, k) = if j < centre {
            (self.n - 1 - j, if k == 0 { 0 } else { self.headings - k })
        } else {
            (j, k)
        };
        (k * (self.n - centre) + j - centre) * self.n
    }

    /// V at node i of row j (r_p / v_pm), its codes starting at `row`: its code, or, if
    /// `near_disc`, in the capture disc with code 0, minus its depth; `None` for a node from
    /// which capture was not found.
    fn node(&self, i: usize, j: usize, row: usize, near_disc: bool) -> Option<f32> {
        if near_disc {
            let (x, y) = (
                i as f32 * self.spacing - self.half,
                j as f32 * self.spacing - self.half,
            );
            // In the disc, code 0 is behind its usable edge: minus the node's depth. Any other
            // code is the value behind the rest of the edge (V two cells outside).
            if self.captures(x, y) {
                return match u16_at(self.codes, 2 * (row + i))? {
                    0 => Some(libm::sqrtf(x * x + y * y) - self.eps),
                    NEVER => None,
                    code => Some(f32::from(code) * self.scale),
                };
            }
        }
        match u16_at(self.codes, 2 * (row + i)) {
            Some(code) if code != NEVER => Some(f32::from(code) * self.scale),
            _ => None,
        }
    }

    /// V at `(x, y, phi)` (r_p, radians), r_p / v_pm: trilinear, periodic in phi; `None`
    /// outside the box, next to a node from which capture was not found, or for a heading
    /// beyond 1e5 rad (the law's envelope is 1e4).
    pub fn value(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let last = (self.n - 1) as f32;
        let fx = (x + self.half) / self.spacing;
        let fy = (y + self.half) / self.spacing;
        if !((0.0..=last).contains(&fx) && (0.0..=last).contains(&fy)) {
            return None;
        }
        // wrap_signed's range: beyond it (or NaN) no value.
        if phi.is_nan() || phi.abs() > 1e5 {
            return None;
        }
        let turn = core::f32::consts::TAU;
        let wrapped = (wrap_signed(phi) + core::f32::consts::PI).max(0.0);
        let fk = wrapped / turn * self.headings as f32;
        let (i0, j0) = ((fx as usize).min(self.n - 2), (fy as usize).min(self.n - 2));
        // fk is within [0, headings]; its top end is heading 0 again. No division: the
        // image's panic check cannot see that `headings` is not zero.
        let wrap = |k: usize| if k >= self.headings { 0 } else { k };
        let below = fk as usize;
        let k0 = wrap(below);
        let (tx, ty, tk) = (fx - i0 as f32, fy - j0 as f32, fk - below as f32);
        let k1 = wrap(k0 + 1);
        // A corner of the cell can be in the disc only if (x, y) is within a cell's diagonal
        // of it.
        let reach = self.eps + 1.5 * self.spacing;
        let near_disc = x * x + y * y <= reach * reach;
        let mut v = 0.0;
        for (k, wk) in [(k0, 1.0 - tk), (k1, tk)] {
            for (j, wj) in [(j0, 1.0 - ty), (j0 + 1, ty)] {
                let row = self.row(j, k);
                for (i, wi) in [(i0, 1.0 - tx), (i0 + 1, tx)] {
                    v += wi * wj * wk * self.node(i, j, row, near_disc)?;
                }
            }
        }
        Some(v)
    }

    /// The byte length of this table in its source: header and codes.
    pub fn len_bytes(&self) -> usize {
        HEADER_LEN + self.codes.len()
    }

    /// Whether `(x, y)` (r_p) is in the capture disc; with the solver's margin, a point on its
    /// edge is inside whatever its rounding.
    pub(crate) fn captures(&self, x: f32, y: f32) -> bool {
        x * x + y * y <= self.eps * self.eps * (1.0 + 1e-6)
    }

    /// Whether `(x, y)` (r_p) lies in the box.
    pub(crate) fn holds(&self, x: f32, y: f32) -> bool {
        x.abs() <= self.half && y.abs() <= self.half
    }

    /// The theorem's threshold 2 r_e + 2 pi r_e v_pm / v_em of this table's game, r_p.
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// The steps of the pursuer's turn `PURSUER_TURNS[p]` under each of the evader's controls.
    pub(crate) fn steps(&self) -> &[[Step; 4]; 3] {
        &self.steps
    }
}
