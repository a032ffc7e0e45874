//! The grid of V over the reduced game's states, and the values that mean "not captured".

/// The value of a state from which capture within the box was not found: a large finite time,
/// so that interpolation near the edge of the capturable set stays a number (it smears that
/// edge over a cell; values below [`REACHED`] are read as found).
pub const NEVER: f64 = 1.0e4;
/// Values below this are times to capture; above, not captured.
pub const REACHED: f64 = 0.5 * NEVER;

/// The grid: `n` nodes on each of x and y over [-half, half], `headings` nodes of phi over a
/// turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Nodes per position axis (odd, so that 0 is a node).
    pub n: usize,
    /// Half the box's side, r_p.
    pub half: f64,
    /// Nodes over the relative heading's turn.
    pub headings: usize,
}

impl Grid {
    /// The position spacing, r_p.
    pub fn spacing(&self) -> f64 {
        2.0 * self.half / (self.n - 1) as f64
    }

    /// The solver's time step on this grid, r_p / v_pm: half a cell's time, or
    /// [`twocars::value_tables::table::MIN_STEP`] where that is shorter, as the firmware's reader
    /// looks ahead ([`twocars::value_tables::table::step_time`], in f32).
    pub fn step_time(&self) -> f64 {
        (0.5 * self.spacing()).max(f64::from(twocars::value_tables::table::MIN_STEP))
    }
    pub(crate) fn len(&self) -> usize {
        self.n * self.n * self.headings
    }
    #[inline]
    pub(crate) fn index(&self, i: usize, j: usize, k: usize) -> usize {
        (k * self.n + j) * self.n + i
    }
    #[inline]
    pub(crate) fn position(&self, i: usize) -> f64 {
        -self.half + i as f64 * self.spacing()
    }
    pub(crate) fn heading(&self, k: usize) -> f64 {
        -std::f64::consts::PI + k as f64 * std::f64::consts::TAU / self.headings as f64
    }
}
