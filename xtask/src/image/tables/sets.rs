//! The value tables xtask solves: which limits on which nested grids (`cargo xtask hj`'s
//! reference near field, and the sets the tables images carry). Kept apart from the solver's
//! driver ([`super::solve`]), whose source stamps the solve cache: a change here names other files
//! in the cache and solves only what it changes.

use hji::{Grid, Read};

/// How a set of tables is solved: how the sweeps read V between nodes, and how many turn rates
/// the pursuer tries (`hji::Sweeps`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SolvedBy {
    pub(crate) read: Read,
    pub(crate) turns: usize,
}

/// How the reference near field ([`NEAR_FIELD_LEVELS`]) is solved: by the solver's default
/// scheme, the filtered tricubic read (which keeps V at or above the time to close on an
/// evader that stops) and [`hji::TURNS`] pursuer turn rates (docs/near-field.md). Plays are
/// judged by its V(x0).
pub(crate) const REFERENCE: SolvedBy = SolvedBy {
    read: Read::Filtered,
    turns: hji::TURNS,
};

/// How the tables a pursuer plays (the sets in flash, `--set`, `--levels`) are solved: read
/// trilinearly, as the firmware and the host's players read them, with the players' three turns.
/// Judged against a reference solved by the unfiltered cubic with three turns, on seeds
/// 170,000 to 199,999 (39,000 runs per pair), tables solved by the cubic put 1 and 5 runs past
/// +10 % at the paper's ratios and at 2, 2, 1.2, 1.2; trilinear ones 0 and 2.
pub(crate) const PLAYED: SolvedBy = SolvedBy {
    read: Read::Trilinear,
    turns: 3,
};

/// The near field's tables, coarsest first: a box of +-30 r_p (15 m, just past the theorem's
/// threshold of 14.57 m on the diagonals) at 0.5 r_p with 72 relative headings; +-6 r_p at
/// 0.2 r_p with 48; +-3 r_p at 0.05 r_p with 72. The outer grid alone puts V 10 to 40 % low
/// within two capture radii behind the pursuer; the inner one is as fine as the finest table a
/// set flies, since it is the reference their plays are judged by. With 24 headings outside,
/// V(x0) 8.5 r_p out reads 4.154 s at 2, 2, 1.2, 1.2, against 4.315 and 4.384 s with 48 and
/// 72.
pub(crate) const NEAR_FIELD_LEVELS: [Grid; 3] =
    [grid(121, 30.0, 72), grid(61, 6.0, 48), grid(121, 3.0, 72)];

/// A set of nested tables an image carries: the limits (v_pm, w_pm, v_em, w_em) whose ratios it
/// serves, and its levels, coarsest first.
pub(crate) struct FlashSet {
    pub limits: [f64; 4],
    pub levels: [Grid; 3],
}

const fn grid(n: usize, half: f64, headings: usize) -> Grid {
    Grid { n, half, headings }
}

/// The sets the tables images carry (docs/near-field.md, "Playing the tables"): the paper's
/// ratios (v_em / v_pm = 0.5, r_e / r_p = 2) on the levels chosen to fit the STM32F405
/// (499,308 B), and a faster, tighter-turning evader's (0.6 and
/// 5 / 3, threshold 20.8 r_p), whose outer table needs 0.75 r_p per cell (567,948 B). An
/// inner table at 0.05 r_p (121:3:72) removes a bang-bang evader's graze near the disc, but
/// costs 790 KB and 4 min of solve in every `cargo xtask test`, and the pair's worst runs stay
/// past 10 % on seeds kept aside either way ("The second pair at 0.05 r_p").
pub(crate) static FLASH_SETS: [FlashSet; 2] = [
    FlashSet {
        limits: twocars_sim::scenarios::PAPER_LIMITS,
        levels: [grid(61, 30.0, 24), grid(61, 6.0, 36), grid(61, 3.0, 72)],
    },
    FlashSet {
        limits: [2.0, 2.0, 1.2, 1.2],
        levels: [grid(81, 30.0, 24), grid(61, 6.0, 36), grid(61, 3.0, 72)],
    },
];
