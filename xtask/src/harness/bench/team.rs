//! The team's rows of `cargo xtask bench`: `twocars::team` deciding one period for 2, 4 and 8
//! pursuers, on the Cortex-M4F (f32 with an FPU) and the Cortex-M0 (fixed point, and the same
//! f32 in software), checked against the same periods on the host.

use twocars::team::Team;
use twocars::{Fixed, Guidance, Law, Limits, Policy, Scalar, Variant};
use twocars_bench::{team_evader, team_pursuer, DT, LIMITS, TEAM_PERIODS, TEAM_SIZES};

use crate::harness::bench::image::{build_and_print, Cpu, M0, M4F};

/// What a team's period costs on one CPU, per size of [`TEAM_SIZES`].
#[derive(Clone, Debug)]
pub struct TeamMeasured {
    /// Instructions per period, mean and max, per size.
    pub period: Vec<(f64, f64)>,
    /// The most stack of a period, bytes.
    pub stack: u64,
    /// Flash of the image, bytes.
    pub flash: u64,
}

/// The host's chaser and team time (f32 bits; 255 and 0 for none) per period of `N` over `S`.
fn host_sized<S: Scalar, const N: usize>() -> Vec<(u32, u32)> {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let guidance = Limits::<S>::new(v_pm, w_pm, v_em, w_em)
        .and_then(|limits| Guidance::new(Law::new(limits, Variant::Paper), DT, Policy::Flight));
    let Ok(mut team) = guidance.and_then(|g| Team::<S, N>::new([g; N], [LIMITS; N])) else {
        return Vec::new();
    };
    let pursuers: [[f32; 3]; N] = core::array::from_fn(team_pursuer);
    (0..TEAM_PERIODS)
        .map(|k| {
            let d = team.decide(&pursuers, team_evader(k));
            let chaser = d.chaser.map_or(255, |c| c as u32);
            (chaser, d.team_time().unwrap_or(0.0).to_bits())
        })
        .collect()
}

fn host<S: Scalar>(n: usize) -> Vec<(u32, u32)> {
    match n {
        2 => host_sized::<S, 2>(),
        4 => host_sized::<S, 4>(),
        _ => host_sized::<S, 8>(),
    }
}

/// Runs the team bench `image` over `S` on `cpu`; an error where a chaser differs from the
/// host's, or a team time is more than 1e-5 (relative) from it.
pub fn measure<S: Scalar>(cpu: Cpu, image: &str) -> Result<TeamMeasured, String> {
    let want: Vec<Vec<(u32, u32)>> = TEAM_SIZES.iter().map(|&n| host::<S>(n)).collect();
    let (out, flash) = build_and_print(cpu, image)?;
    let mut ticks: Vec<Vec<f64>> = vec![Vec::new(); TEAM_SIZES.len()];
    let mut stack = 0;
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let ["team", n, k, t, e, st, chaser, time] = fields.as_slice() else {
            continue;
        };
        let bad = || format!("bad line {line}");
        let n: usize = n.parse().map_err(|_| bad())?;
        let size = TEAM_SIZES.iter().position(|&s| s == n).ok_or_else(bad)?;
        let k: usize = k.parse().map_err(|_| bad())?;
        let &(want_chaser, want_time) = want[size].get(k).ok_or_else(bad)?;
        let got_time = f32::from_bits(u32::from_str_radix(time, 16).map_err(|_| bad())?);
        let want_time = f32::from_bits(want_time);
        let chaser: u32 = chaser.parse().map_err(|_| bad())?;
        if chaser != want_chaser || (got_time - want_time).abs() > 1e-5 * want_time.abs().max(1.0) {
            return Err(format!(
                "team of {n}, period {k} on {}: chaser {chaser}, {got_time} s against the host's {want_chaser}, {want_time} s",
                cpu.name()
            ));
        }
        let empty: f64 = e.parse().map_err(|_| bad())?;
        ticks[size]
            .push((t.parse::<f64>().map_err(|_| bad())? - empty) / cpu.ticks_per_instruction);
        stack = stack.max(st.parse().map_err(|_| bad())?);
    }
    if ticks.iter().any(|t| t.len() != TEAM_PERIODS as usize) {
        return Err(format!("the team bench reported too few periods:\n{out}"));
    }
    let period = ticks
        .iter()
        .map(|v| {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            (mean, v.iter().copied().fold(0.0, f64::max))
        })
        .collect();
    Ok(TeamMeasured {
        period,
        stack,
        flash,
    })
}

/// The bench page's paragraph: f32 on both CPUs, fixed point on the M0.
pub fn section() -> Result<String, String> {
    let mut text = format!(
        "Team (`twocars::team`; `team` and `team_fixed` images: {TEAM_PERIODS} periods per size \
         against an evader on a slow turn, the pursuers 4 to 25 m from it on both sides of the \
         threshold, every chaser and team time as the host's over the same number type; the \
         call overhead subtracted). A period is each pursuer's guidance decision, its time to \
         go and the roles:\n\n| CPU | number type | 2 pursuers | 4 pursuers | 8 pursuers | stack (8) | image flash |\n|---|---|---|---|---|---|---|\n"
    );
    let rows: [(Cpu, &str, &str); 3] = [
        (M4F, "f32", "team"),
        (M0, "fixed point (Q17.14)", "team_fixed"),
        (M0, "f32 soft-float", "team"),
    ];
    for (cpu, number, image) in rows {
        let m = if image == "team_fixed" {
            measure::<Fixed>(cpu, image)?
        } else {
            measure::<f32>(cpu, image)?
        };
        let cells: Vec<String> = m
            .period
            .iter()
            .map(|(mean, max)| format!("{mean:.0} (max {max:.0})"))
            .collect();
        text.push_str(&format!(
            "| {} | {number} | {} | {} B | {} B |\n",
            cpu.name(),
            cells.join(" | "),
            m.stack,
            m.flash
        ));
    }
    text.push_str(
        "\nWhere a period's instructions go: each pursuer's decision costs what one guidance's \
         does, and its time to go (a square root, an arctangent, a sine and cosine) is f32 on \
         every backend, in software on the M0.\n",
    );
    Ok(text)
}
