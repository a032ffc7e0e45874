//! The law on the host simulator: its options (`--variant`, `--numeric`, `--policy`, shared by
//! `eval`, `sim` and `run`) and one closed-loop run on the chosen backend.

use twocars::{Policy, Variant};
use twocars_sim::adversary::Opponent;
use twocars_sim::sim::{simulate_against, SimParams, SimResult};

/// Numeric backend of the law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
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
            $crate::harness::host::Numeric::F32 => {
                type $S = f32;
                $body
            }
            $crate::harness::host::Numeric::F64 => {
                type $S = f64;
                $body
            }
            $crate::harness::host::Numeric::Micromath => {
                type $S = twocars::num::micro::Micro;
                $body
            }
            $crate::harness::host::Numeric::Fixed => {
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

/// Algorithm 2's reading, as the command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum VariantArg {
    /// As published.
    Paper,
    /// The evader's overshoot clamped.
    Clamped,
}

/// The policy, as the command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PolicyArg {
    /// The paper's law everywhere: the reference for research.
    Paper,
    /// The paper's law beyond the theorem's threshold, our pursuer below it: the one to fly.
    /// `near-field` is an alias.
    #[value(alias = "near-field")]
    Flight,
}

/// `--variant`, `--numeric` and `--policy`, shared by `eval`, `sim` and `run`.
#[derive(Debug, Clone, clap::Args)]
pub struct LawArgs {
    /// Algorithm 2's reading.
    #[arg(long, value_enum, default_value = "paper")]
    variant: VariantArg,
    /// Numeric backend (docs/numeric.md): f32, f64, micromath (error reported, no bound), fixed
    /// (Q17.14, within its envelope).
    #[arg(long, value_enum, default_value = "f32")]
    numeric: Numeric,
    /// Policy (Configure's policy byte 0 or 1); default paper for eval and sim (the shared
    /// contract), flight for run.
    #[arg(long, value_enum)]
    policy: Option<PolicyArg>,
}

impl LawArgs {
    /// The options, with `policy` where `--policy` was not given.
    pub fn options(&self, policy: Policy) -> Options {
        Options {
            variant: match self.variant {
                VariantArg::Paper => Variant::Paper,
                VariantArg::Clamped => Variant::Clamped,
            },
            numeric: self.numeric,
            policy: match self.policy {
                None => policy,
                Some(PolicyArg::Paper) => Policy::Paper,
                Some(PolicyArg::Flight) => Policy::Flight,
            },
        }
    }
}

/// Runs one set of parameters on the chosen backend; with an `opponent` (an adversary and its
/// seed) in place of the law's other player.
pub fn run_one(
    p: &SimParams,
    options: &Options,
    opponent: Option<(Opponent, u64)>,
    record: bool,
) -> SimResult {
    with_numeric!(options.numeric, S => simulate_against::<S>(p, options.variant, options.policy, opponent, record))
}
