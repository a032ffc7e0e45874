//! A team's chase in SITL: `N` pursuers, each its own autopilot and unit behind its own router,
//! against an evader vehicle flown by one of the team's evaders (`twocars_sim::team`). Each unit
//! hears the target through the radio ([`Radio`]) and its teammates as their autopilots send
//! their fixes, re-sent under the team's system ids; the harness judges capture on the
//! vehicles' fixes and reads each unit's TC_CHASER.
//!
//! Every autopilot calls itself system 1, so each unit is told the team as it sees it: itself
//! system 1 (TC_SYSID, TC_TEAM_SYS), the teammate after it 2, and so on round the team.

use std::time::{Duration, Instant};

use mavlink::dialects::common::GLOBAL_POSITION_INT_DATA;
use twocars_sim::kinematics::distance;
use twocars_sim::team::{EvaderPlay, TeamEvader};

use super::evader::Steer;
use super::field::{Delayed, Radio};
use super::harness::{Harness, Injector, NoTarget, RoverFix};

/// The target's system id in a team's units (TC_TGT_SYSID): clear of the team's 1 to N.
pub const TEAM_TARGET: u8 = 20;

/// The unit parameters of a team of `n`: each unit system 1 of the team 1 to `n`.
pub fn team_params(n: usize) -> [(&'static str, f64); 4] {
    [
        ("TC_SYSID", 1.0),
        ("TC_TEAM_SYS", 1.0),
        ("TC_TEAM_N", n as f64),
        ("TC_TGT_SYSID", f64::from(TEAM_TARGET)),
    ]
}

/// The system id unit `k` of a team of `n` knows vehicle `j` by.
fn id_in(k: usize, j: usize, n: usize) -> u8 {
    1 + ((j + n - k) % n) as u8
}

/// The vehicle unit `k` of a team of `n` means by system id `id` (1 to `n`).
fn vehicle_of(k: usize, id: i32, n: usize) -> Option<usize> {
    let id = usize::try_from(id).ok().filter(|&i| (1..=n).contains(&i))?;
    Some((k + id - 1) % n)
}

/// The evader's latest fix handed to one pursuer's unit, once each.
struct Relay {
    fix: Option<GLOBAL_POSITION_INT_DATA>,
    given: Option<u32>,
    on: bool,
}

impl Injector for Relay {
    fn before(&mut self, _: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        let fix = self.fix.clone()?;
        if self.given == Some(fix.time_boot_ms) {
            return None;
        }
        self.given = Some(fix.time_boot_ms);
        Some(fix)
    }

    fn on(&self) -> bool {
        self.on
    }
}

/// How a team's chase is judged: the capture radius (m), the limits every vehicle's law
/// takes (v_pm, w_pm, v_em, w_em), the chase's length on the evader's clock (s), the radio,
/// its seed.
#[derive(Clone, Copy, Debug)]
pub struct TeamTerms {
    pub eps: f64,
    pub limits: [f64; 4],
    pub t_max: f64,
    pub radio: Radio,
    pub seed: u64,
}

/// What a team's chase gave.
#[derive(Clone, Debug)]
pub struct TeamFlown<const N: usize> {
    /// The evader's time from the start to capture (s), and the vehicle that captured.
    pub captured: Option<(f64, usize)>,
    /// Each unit's chaser as it named it (the vehicle; `None`: none named), at its vehicle's
    /// time since the start (s), each time it sent TC_CHASER.
    pub named: [Vec<(f64, Option<usize>)>; N],
    /// The vehicles' and the evader's states at the start (m, rad, in the plane about home).
    pub start: ([[f64; 3]; N], [f64; 3]),
}

/// Flies `kind` on the vehicle behind `evader` (steered by `steer`) against the team behind
/// `pursuers`, from where all are now, as `terms` say.
pub fn chase<const N: usize>(
    pursuers: &mut [Harness; N],
    evader: &mut Harness,
    steer: &mut dyn Steer,
    kind: TeamEvader,
    terms: TeamTerms,
) -> Result<TeamFlown<N>, String> {
    let states = |p: &[Harness; N]| -> Option<[[f64; 3]; N]> {
        let fixes: Vec<[f64; 3]> = p
            .iter()
            .map(|h| h.rover.map(|r| r.state))
            .collect::<Option<_>>()?;
        fixes.try_into().ok()
    };
    let start_states = states(pursuers).ok_or("no fix from a pursuer")?;
    let first = evader.rover.ok_or("no fix from the evader")?;
    let mut play = EvaderPlay::new(kind, [terms.limits; N], 0.05, terms.eps)
        .ok_or("the team's limits are invalid")?;
    let mut radios: [Delayed<Relay>; N] = core::array::from_fn(|k| {
        let relay = Relay {
            fix: None,
            given: None,
            on: true,
        };
        Delayed::new(relay, terms.radio, terms.seed + k as u64)
    });
    let marks: [(usize, u32); N] =
        core::array::from_fn(|k| (pursuers[k].chasers.len(), pursuers[k].now_ms()));
    let mut sent = [[None::<u32>; N]; N];
    let mut last_evader_ms = None;
    let mut captured = None;
    let wall = Instant::now() + Duration::from_secs_f64(terms.t_max * 2.0 + 20.0);
    loop {
        if Instant::now() > wall {
            return Err("the team's chase outran its wall-clock limit".to_string());
        }
        evader.pump_until(&mut NoTarget, Duration::from_millis(1), &mut |_| false)?;
        let e = evader.rover.ok_or("no fix from the evader")?;
        for (k, h) in pursuers.iter_mut().enumerate() {
            radios[k].inner_mut().fix = evader.position.clone();
            h.pump_until(&mut radios[k], Duration::from_millis(2), &mut |_| false)?;
        }
        relay_teammates(pursuers, &mut sent)?;
        let t = f64::from(e.time_ms.wrapping_sub(first.time_ms)) / 1000.0;
        let now = states(pursuers).ok_or("no fix from a pursuer")?;
        if let Some(k) = (0..N).find(|&k| distance(now[k], e.state) <= terms.eps) {
            captured = Some((t, k));
            break;
        }
        if t > terms.t_max {
            break;
        }
        if last_evader_ms != Some(e.time_ms) {
            last_evader_ms = Some(e.time_ms);
            let w = play.turn(&now, e.state);
            steer.steer(evader, w, terms.limits[2], e.speed)?;
        }
    }
    for radio in &mut radios {
        radio.inner_mut().on = false;
    }
    let speed = evader.rover.map_or(0.0, |r| r.speed);
    steer.steer(evader, 0.0, 0.0, speed)?;
    let named = core::array::from_fn(|k| {
        let (from, begun_ms) = marks[k];
        pursuers[k].chasers[from..]
            .iter()
            .map(|&(ms, id)| {
                let t = f64::from(ms.wrapping_sub(begun_ms)) / 1000.0;
                (t, vehicle_of(k, id, N))
            })
            .collect()
    });
    Ok(TeamFlown {
        captured,
        named,
        start: (start_states, first.state),
    })
}

/// Each vehicle's newest fix to every teammate's unit, once each, under the id that unit
/// knows it by; `sent[k][j]` is the time of vehicle `j`'s fix last sent to unit `k`.
fn relay_teammates<const N: usize>(
    pursuers: &mut [Harness; N],
    sent: &mut [[Option<u32>; N]; N],
) -> Result<(), String> {
    let fixes: Vec<Option<GLOBAL_POSITION_INT_DATA>> =
        pursuers.iter().map(|h| h.position.clone()).collect();
    for (k, h) in pursuers.iter_mut().enumerate() {
        for (j, fix) in fixes.iter().enumerate() {
            let Some(fix) = fix.as_ref().filter(|_| j != k) else {
                continue;
            };
            if sent[k][j] == Some(fix.time_boot_ms) {
                continue;
            }
            sent[k][j] = Some(fix.time_boot_ms);
            h.router.send_to_unit_as((id_in(k, j, N), 1), fix)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_unit_knows_itself_as_one_and_the_ids_map_back() {
        for n in 2..=4 {
            for k in 0..n {
                assert_eq!(id_in(k, k, n), 1);
                for j in 0..n {
                    assert_eq!(vehicle_of(k, i32::from(id_in(k, j, n)), n), Some(j));
                }
                assert_eq!(vehicle_of(k, 0, n), None);
            }
        }
    }
}
