//! The log macro: defmt when the `defmt` feature is on, nothing otherwise (host builds, flight
//! builds without a log transport). Crate-private: a user's firmware logs with its own.

/// Logs at warn level.
macro_rules! log_warn {
    ($($arg:tt)*) => {{
        #[cfg(feature = "defmt")]
        defmt::warn!($($arg)*);
    }};
}
pub(crate) use log_warn;
