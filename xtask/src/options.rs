//! Options shared by the doors: `--variant`, `--numeric`, `--policy`.

use twocars::{Policy, Variant};

/// Numeric backend of the law.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Numeric {
    /// The accurate f32 path (the default).
    F32,
    /// The f64 reference-grade path of the same generic law.
    F64,
    /// f32 with micromath's approximations (error reported, no bound).
    Micromath,
    /// Q17.14 fixed point, normalised by the pursuer's radius (envelope in `twocars::num::fixed`).
    Fixed,
}

/// Evaluates `$body` with the type name `$S` bound to the backend `$numeric` selects.
macro_rules! with_numeric {
    ($numeric:expr, $S:ident => $body:expr) => {
        match $numeric {
            $crate::options::Numeric::F32 => {
                type $S = f32;
                $body
            }
            $crate::options::Numeric::F64 => {
                type $S = f64;
                $body
            }
            $crate::options::Numeric::Micromath => {
                type $S = twocars::num::micro::Micro;
                $body
            }
            $crate::options::Numeric::Fixed => {
                type $S = twocars::num::fixed::Fixed;
                $body
            }
        }
    };
}
pub(crate) use with_numeric;

/// Options of `eval` and `sim`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    /// Algorithm 2's reading.
    pub variant: Variant,
    /// Numeric backend.
    pub numeric: Numeric,
    /// The paper's law everywhere, or ours below the theorem's threshold.
    pub policy: Policy,
}

/// Parses `--variant`, `--numeric` and `--policy` (`policy` where it is not given); other
/// arguments are returned for the command.
pub fn parse(args: &[String], policy: Policy) -> Result<(Options, Vec<String>), String> {
    let mut options = Options {
        variant: Variant::Paper,
        numeric: Numeric::F32,
        policy,
    };
    let mut rest = Vec::new();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let (key, inline) = match arg.split_once('=') {
            Some((k, v)) => (k, Some(v.to_string())),
            None => (arg.as_str(), None),
        };
        let mut value = || {
            inline
                .clone()
                .or_else(|| it.next().cloned())
                .ok_or(format!("{key} needs a value"))
        };
        match key {
            "--variant" => {
                options.variant = match value()?.as_str() {
                    "paper" => Variant::Paper,
                    "clamped" => Variant::Clamped,
                    v => return Err(format!("--variant {v}: expected paper or clamped")),
                }
            }
            "--numeric" => {
                options.numeric = match value()?.as_str() {
                    "f32" => Numeric::F32,
                    "f64" => Numeric::F64,
                    "micromath" => Numeric::Micromath,
                    "fixed" => Numeric::Fixed,
                    v => {
                        return Err(format!(
                            "--numeric {v}: expected f32, micromath, fixed or f64"
                        ))
                    }
                }
            }
            "--policy" => {
                options.policy = match value()?.as_str() {
                    "paper" => Policy::Paper,
                    // "near-field": the flight policy's name before issue 25, kept as an alias.
                    "flight" | "near-field" => Policy::Flight,
                    v => return Err(format!("--policy {v}: expected paper or flight")),
                }
            }
            _ => rest.push(arg.clone()),
        }
    }
    Ok((options, rest))
}
