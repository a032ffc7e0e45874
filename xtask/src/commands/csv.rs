//! The CSV doors' shared pieces: header checks, field parsing, number printing.

use std::io::{BufRead, Write};

use twocars::Status;

/// Runs a CSV door on stdin/stdout: checks the input header (exit code 2 and nothing on stdout
/// otherwise), prints the output header, then one output line per non-blank input line, flushed
/// line by line. Returns the process exit code.
pub fn run_door(
    name: &str,
    input_header: &str,
    output_header: &str,
    mut each: impl FnMut(&str) -> String,
) -> i32 {
    let stdin = std::io::stdin();
    let mut lines = stdin.lock().lines();
    match lines.next() {
        Some(Ok(header)) if trim_cr(&header) == input_header => {}
        _ => {
            eprintln!("{name}: the first line must be exactly `{input_header}`");
            return 2;
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if writeln!(out, "{output_header}").is_err() {
        return 1;
    }
    for line in lines {
        let Ok(line) = line else {
            eprintln!("{name}: stdin is not UTF-8 text");
            return 2;
        };
        let line = trim_cr(&line);
        if line.trim().is_empty() {
            continue;
        }
        if writeln!(out, "{}", each(line))
            .and_then(|()| out.flush())
            .is_err()
        {
            return 1;
        }
    }
    0
}

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
