//! `cargo xtask sim`: closed loop on the host, CSV rows from stdin (format in docs/contract.md).

use crate::commands::csv::{number, parse_fields, run_door};
use crate::harness::host::{run_one, LawArgs, Options};
use twocars_sim::adversary::{EvaderKind, Opponent};
use twocars_sim::sim::{SimParams, SimResult};

/// Input header of `sim`.
pub const INPUT_HEADER: &str = "v_pm,w_pm,v_em,w_em,x_p,y_p,theta_p,x_e,y_e,theta_e,dt,t_max,eps";
/// Output header of `sim`.
pub const OUTPUT_HEADER: &str = "status,t_capture,predicted,d_min,switches,sign_flips";

/// Parameters from the thirteen CSV fields.
pub fn params(f: &[f64; 13]) -> SimParams {
    SimParams {
        limits: [f[0], f[1], f[2], f[3]],
        pursuer: [f[4], f[5], f[6]],
        evader: [f[7], f[8], f[9]],
        dt: f[10],
        t_max: f[11],
        eps: f[12],
    }
}

/// `cargo xtask sim`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct SimArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// An evader of the adversary suite (sim/src/adversary.rs) in place of the law's.
    #[arg(long, value_parser = EvaderKind::ALL.map(EvaderKind::name))]
    evader: Option<String>,
    /// The adversary's seed.
    #[arg(long, default_value_t = 1, requires = "evader")]
    adversary_seed: u64,
}

impl SimArgs {
    /// The adversary and its seed, if one plays.
    pub fn opponent(&self) -> Option<(Opponent, u64)> {
        let evader = EvaderKind::from_name(self.evader.as_deref()?)?;
        Some((Opponent::Evader(evader), self.adversary_seed))
    }
}

/// One output row.
pub fn row(r: &SimResult) -> String {
    format!(
        "{},{},{},{},{},{}",
        r.status.name(),
        number(r.t_capture),
        number(r.predicted),
        number(r.d_min),
        r.switches,
        r.sign_flips
    )
}

/// Runs the door against `opponent` (`None`: the law plays both players): returns the process
/// exit code.
pub fn run(options: &Options, opponent: Option<(Opponent, u64)>) -> i32 {
    run_door(
        "sim",
        INPUT_HEADER,
        OUTPUT_HEADER,
        |line| match parse_fields::<13>(line) {
            Ok(fields) => row(&run_one(&params(&fields), options, opponent, false)),
            Err(e) => format!("{},inf,inf,inf,0,0", e.status()),
        },
    )
}
