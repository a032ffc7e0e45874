//! The CSV doors' shared pieces: header checks, field parsing, number printing.

use twocars::Status;

/// Why a data row could not become an observation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowError {
    /// Wrong field count or an unparsable number.
    Parse,
    /// NaN or infinity in a field.
    NonFinite,
}

impl RowError {
    /// The contract's status name.
    pub fn status(self) -> &'static str {
        match self {
            RowError::Parse => "parse_error",
            RowError::NonFinite => Status::NonFiniteInput.name(),
        }
    }
}

/// Strips one trailing `\r`.
pub fn trim_cr(line: &str) -> &str {
    line.strip_suffix('\r').unwrap_or(line)
}

/// Parses exactly `N` comma-separated decimal fields.
pub fn parse_fields<const N: usize>(line: &str) -> Result<[f64; N], RowError> {
    let mut out = [0.0; N];
    let mut count = 0;
    for (i, field) in line.split(',').enumerate() {
        let slot = out.get_mut(i).ok_or(RowError::Parse)?;
        *slot = field.trim().parse::<f64>().map_err(|_| RowError::Parse)?;
        count += 1;
    }
    if count != N {
        return Err(RowError::Parse);
    }
    if out.iter().any(|v| !v.is_finite()) {
        return Err(RowError::NonFinite);
    }
    Ok(out)
}

/// Narrows a finite f64 to f32, saturating at +-f32::MAX so that a huge value is reported as out
/// of range by the core rather than as infinity.
pub fn narrow(value: f64) -> f32 {
    value.clamp(-f64::from(f32::MAX), f64::from(f32::MAX)) as f32
}

/// A number as the contract prints it: shortest decimal, `inf` for infinity, never NaN.
pub fn number(value: f64) -> String {
    if value.is_nan() {
        // The core never produces NaN; if it ever did, print the safe zero rather than NaN.
        "0".to_string()
    } else if value.is_infinite() {
        if value > 0.0 { "inf" } else { "-inf" }.to_string()
    } else {
        format!("{value}")
    }
}

/// An optional value (`None` = infinity).
pub fn optional(value: Option<f64>) -> String {
    number(value.unwrap_or(f64::INFINITY))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_fields_counts_and_classifies() {
        assert_eq!(parse_fields::<2>("1,2"), Ok([1.0, 2.0]));
        assert_eq!(parse_fields::<2>("1,2,3"), Err(RowError::Parse));
        assert_eq!(parse_fields::<2>("1"), Err(RowError::Parse));
        assert_eq!(parse_fields::<2>("1,x"), Err(RowError::Parse));
        assert_eq!(parse_fields::<2>("1,nan"), Err(RowError::NonFinite));
        assert_eq!(parse_fields::<2>("inf,1"), Err(RowError::NonFinite));
    }

    #[test]
    fn numbers_print_for_python_float() {
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(-0.25), "-0.25");
        assert_eq!(optional(None), "inf");
        assert_eq!(narrow(1e300), f32::MAX);
    }
}
