//! A team of three ArduPilot Rover SITL pursuers, each with its companion unit, against a
//! fourth rover (`cargo xtask test --only ardupilot-team`; not in the full run, which it would
//! lengthen by about five minutes).

use crate::harness::ardupilot::team::{fly, Options, Outcome};

/// Each chase of `cargo xtask run --autopilot ardupilot --team` as a test: captured, and every
/// unit naming a chaser from its first TC_CHASER on.
pub fn record(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!("== xtask test: a team of three ArduPilot Rover SITL pursuers against a fourth rover");
    if super::skipped::rover_missing() {
        return;
    }
    let options = Options {
        ardurover: None,
        short: false,
    };
    match fly(&options) {
        Ok(outcomes) => {
            for o in &outcomes {
                let name = format!("ardupilot_team::start_{}_vs_{}", o.seed, o.evader);
                record(&name, check(o));
            }
        }
        Err(e) => record("ardupilot_team::the_team_flies", Err(e)),
    }
}

fn check(o: &Outcome) -> Result<String, String> {
    let line = format!("captured {:?}, the ideal team {:?}", o.captured, o.ideal);
    let (t, _) = o.captured.ok_or(format!("never captured; {line}"))?;
    let silent = o
        .named
        .iter()
        .position(|n| n.is_empty() || n.iter().any(|(_, c)| c.is_none()));
    match silent {
        Some(k) => Err(format!(
            "unit {k} named no chaser for part of the chase; {line}"
        )),
        None => Ok(format!("captured at {t:.2} s; {line}")),
    }
}
