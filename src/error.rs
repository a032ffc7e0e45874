//! The one error of setting guidance up: its limits, control period, value tables and capture
//! radius, and the states a caller gives in metres.

use core::fmt;

use crate::status::Status;

/// Why limits, a control period, value tables, a capture radius or a pair of states are refused.
///
/// ```
/// use twocars::{Error, Limits};
///
/// // The evader faster than the pursuer: outside the game (the paper's Assumption 1).
/// let refused = Limits::<f32>::new(1.0, 2.0, 2.0, 1.0);
/// assert_eq!(refused.unwrap_err(), Error::InvalidLimits);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Error {
    /// A NaN or infinite input.
    NonFiniteInput,
    /// Limits outside the game (not v_pm > v_em > 0 and w_pm > w_em > 0), or a capture radius
    /// below 0 or beyond the backend's range.
    InvalidLimits,
    /// A limit or a state outside the backend's envelope (`docs/numeric.md`).
    OutOfRange,
    /// A control period not in (0, 1000] s, or too long for the backend at these limits.
    InvalidPeriod,
    /// Value tables solved for speed and turn ratios other than the limits'.
    TablesMismatch,
}

impl Error {
    /// The contract's status for this error, as the CSV doors print it: set-up errors that
    /// have no status of their own (the period, the tables) are `InvalidLimits`.
    pub fn status(self) -> Status {
        match self {
            Error::NonFiniteInput => Status::NonFiniteInput,
            Error::OutOfRange => Status::OutOfRange,
            Error::InvalidLimits | Error::InvalidPeriod | Error::TablesMismatch => {
                Status::InvalidLimits
            }
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Error::NonFiniteInput => "an input is NaN or infinite",
            Error::InvalidLimits => {
                "limits must satisfy v_pm > v_em > 0 and w_pm > w_em > 0 (m/s, 1/m), and a \
                 capture radius must be at least 0 m and within the backend's range"
            }
            Error::OutOfRange => "a limit or a state is outside the backend's envelope",
            Error::InvalidPeriod => {
                "the control period must be finite, in (0, 1000] s, and within the backend's \
                 range at these limits"
            }
            Error::TablesMismatch => {
                "the value tables were solved for other speed and turn ratios than these limits'"
            }
        })
    }
}

impl core::error::Error for Error {}
