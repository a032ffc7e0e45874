//! The game's value V as a table the firmware reads (issue 30): the Hamilton-Jacobi-Isaacs
//! solution of `cargo xtask hj`, quantised to u16 per node, and the pursuer's optimal turn read
//! from its gradient.
//!
//! The reduced game (docs/near-field.md): `(x, y)` is the evader's position relative to the
//! pursuer (x along the pursuer's heading, y to its left), `phi` the evader's heading relative
//! to the pursuer's; lengths in r_p, times in r_p / v_pm. One table serves every pair of limits
//! with its two ratios v_em / v_pm and r_e / r_p.
//!
//! Format, little endian: the magic `TCV1`; f32 v_em / v_pm, the evader's turn rate (rad per
//! r_p / v_pm), the capture radius (r_p), half the box's side (r_p) and the time per code
//! (r_p / v_pm); u16 nodes per position axis `n` and headings per turn; then `n * n * headings`
//! u16 codes, node (i, j, k) at `(k n + j) n + i`, x = -half + i h, y = -half + j h,
//! phi = -pi + 2 pi k / headings. Code [`NEVER`]: capture within the box was not found there.
//!
//! Reads are bounds-checked and allocation-free; a malformed table is refused by
//! [`ValueTable::parse`], never read.

/// The table's magic bytes (format version 1).
pub const MAGIC: [u8; 4] = *b"TCV1";
/// Bytes before the codes.
pub const HEADER_LEN: usize = 4 + 5 * 4 + 2 * 2;
/// The code of a node from which capture was not found.
pub const NEVER: u16 = u16::MAX;
/// Below this |V_x y - V_y x - V_phi| the pursuer has no preference and runs straight.
const FLAT: f32 = 1e-3;

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
            && headings >= 2;
        if !valid {
            return Err(TableError::Header);
        }
        let count = n * n * headings;
        let codes = bytes
            .get(HEADER_LEN..HEADER_LEN + 2 * count)
            .ok_or(TableError::Short)?;
        Ok(ValueTable {
            speed_ratio,
            evader_turn,
            eps,
            half,
            scale,
            n,
            headings,
            spacing: 2.0 * half / (n - 1) as f32,
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

    fn code(&self, i: usize, j: usize, k: usize) -> u16 {
        let index = (k * self.n + j) * self.n + i;
        u16_at(self.codes, 2 * index).unwrap_or(NEVER)
    }

    /// V at `(x, y, phi)` (r_p, radians), r_p / v_pm: trilinear, periodic in phi; `None`
    /// outside the box or next to a node from which capture was not found.
    pub fn value(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let last = (self.n - 1) as f32;
        let fx = (x + self.half) / self.spacing;
        let fy = (y + self.half) / self.spacing;
        if !((0.0..=last).contains(&fx) && (0.0..=last).contains(&fy)) {
            return None;
        }
        let turn = core::f32::consts::TAU;
        let wrapped = libm::fmodf(phi + core::f32::consts::PI, turn);
        let wrapped = if wrapped < 0.0 {
            wrapped + turn
        } else {
            wrapped
        };
        let fk = wrapped / turn * self.headings as f32;
        if !fk.is_finite() {
            return None;
        }
        let (i0, j0) = ((fx as usize).min(self.n - 2), (fy as usize).min(self.n - 2));
        // fk is within [0, headings]; its top end is heading 0 again. No division: the
        // image's panic check cannot see that `headings` is not zero.
        let wrap = |k: usize| if k >= self.headings { 0 } else { k };
        let k0 = wrap(fk as usize);
        let (tx, ty, tk) = (fx - i0 as f32, fy - j0 as f32, fk - libm::floorf(fk));
        let k1 = wrap(k0 + 1);
        let mut v = 0.0;
        for (k, wk) in [(k0, 1.0 - tk), (k1, tk)] {
            for (j, wj) in [(j0, 1.0 - ty), (j0 + 1, ty)] {
                for (i, wi) in [(i0, 1.0 - tx), (i0 + 1, tx)] {
                    let code = self.code(i, j, k);
                    if code == NEVER {
                        return None;
                    }
                    v += wi * wj * wk * f32::from(code);
                }
            }
        }
        Some(v * self.scale)
    }

    /// The pursuer's optimal turn at `(x, y, phi)`: -1, 0 or 1, the sign of its turn rate u
    /// (positive: its heading grows, as the law's curvature). The turn enters V's rate as
    /// u (V_x y - V_y x - V_phi), so the full turn against that sign (central differences over
    /// one cell) makes V fall fastest whatever the evader does; 0 where it is flat. `None`
    /// within a cell of the box's edge or where [`ValueTable::value`] has no value.
    pub fn pursuer_turn(&self, x: f32, y: f32, phi: f32) -> Option<f32> {
        let h = self.spacing;
        let dphi = core::f32::consts::TAU / self.headings as f32;
        let v = |dx: f32, dy: f32, dp: f32| self.value(x + dx, y + dy, phi + dp);
        let v_x = (v(h, 0.0, 0.0)? - v(-h, 0.0, 0.0)?) / (2.0 * h);
        let v_y = (v(0.0, h, 0.0)? - v(0.0, -h, 0.0)?) / (2.0 * h);
        let v_phi = (v(0.0, 0.0, dphi)? - v(0.0, 0.0, -dphi)?) / (2.0 * dphi);
        let slope = v_x * y - v_y * x - v_phi;
        Some(if slope > FLAT {
            -1.0
        } else if slope < -FLAT {
            1.0
        } else {
            0.0
        })
    }
}
