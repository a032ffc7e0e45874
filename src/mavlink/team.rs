//! The unit's part in a team of pursuers (docs/team.md, docs/mavlink.md): the team is the
//! systems TC_TEAM_SYS to TC_TEAM_SYS + TC_TEAM_N - 1, this unit's TC_SYSID among them. Each
//! teammate's GLOBAL_POSITION_INT is heard and carried forward in a straight line to the
//! control period; every member is taken to have this unit's limits. Each period the roles are
//! named ([`crate::team::Roles`]) from every member's time to go against the target state the
//! law decides on; the command does not depend on them.

use super::params::{index, Params};
use crate::geodetic::LocalFrame;
use crate::num::f32_math;
use crate::team::{time_to_go, Roles};

/// The most members a team has.
pub const MAX_TEAM: usize = 8;

/// The NAMED_VALUE_INT sent each period in a team: the chaser's system id (0: none).
pub const CHASER: &str = "TC_CHASER";

/// A teammate's last fix: degE7, heading (rad, clockwise from north), speed over ground
/// (m/s; 0 where its message has none), when it arrived (our ms).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct MateFix {
    pub lat: i32,
    pub lon: i32,
    pub heading: f32,
    pub speed: f32,
    pub arrived_ms: u32,
}

/// The team's members and what is heard of them.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct TeamWatch {
    mates: [Option<MateFix>; MAX_TEAM],
    roles: Option<Roles<MAX_TEAM>>,
    /// The chaser last announced (system id), once one was.
    announced: Option<Option<u8>>,
}

impl TeamWatch {
    /// No team heard yet, roles for members of these limits (none without a team).
    pub fn new(params: &Params) -> Self {
        let roles = members(params).and_then(|_| {
            let (v_pm, w_pm) = (params.get(index::V_PM)?, params.get(index::W_PM)?);
            Roles::new([[v_pm, w_pm]; MAX_TEAM]).ok()
        });
        TeamWatch {
            mates: [None; MAX_TEAM],
            roles,
            announced: None,
        }
    }

    /// Whether the parameters make a team.
    pub fn active(&self) -> bool {
        self.roles.is_some()
    }

    /// Whether system `system` is a teammate (not this unit).
    pub fn is_teammate(&self, params: &Params, system: u8) -> bool {
        self.slot(params, system).is_some()
    }

    /// A fix of system `system`: kept where it is a teammate; whether it was.
    pub fn hear(&mut self, params: &Params, system: u8, fix: MateFix) -> bool {
        let Some(slot) = self.slot(params, system) else {
            return false;
        };
        match self.mates.get_mut(slot) {
            Some(mate) => {
                *mate = Some(fix);
                true
            }
            None => false,
        }
    }

    /// Teammate `system`'s place in the team.
    fn slot(&self, params: &Params, system: u8) -> Option<usize> {
        self.roles?;
        let (first, size, own) = members(params)?;
        let slot = usize::from(system.wrapping_sub(first));
        (slot < size && slot != own).then_some(slot)
    }

    /// The chaser's system id this period of `period_s`, from the own state `own` and the
    /// target's `target` (x north, y east, m; heading rad, in `origin`'s plane) at `now_ms`;
    /// teammates heard more than `timeout_ms` ago have no time. `None` without a team.
    pub fn name(
        &mut self,
        params: &Params,
        origin: &LocalFrame,
        (own, target): ([f32; 3], [f32; 3]),
        (now_ms, period_s): (u32, f32),
    ) -> Option<u8> {
        let (first, size, own_slot) = members(params)?;
        let limits = params.limits_si()?;
        let timeout_ms = params.timeout_ms();
        let times: [Option<f32>; MAX_TEAM] = core::array::from_fn(|slot| {
            if slot == own_slot {
                return time_to_go(own, target, limits);
            }
            let fix = self
                .mates
                .get(slot)
                .copied()
                .flatten()
                .filter(|_| slot < size)?;
            let age_ms = now_ms.wrapping_sub(fix.arrived_ms);
            if age_ms > timeout_ms {
                return None;
            }
            let (north, east) = origin.to_local(fix.lat, fix.lon)?;
            let run = fix.speed * age_ms as f32 / 1000.0;
            let (sin, cos) = f32_math::sin_cos(fix.heading);
            let carried = [north + run * cos, east + run * sin, fix.heading];
            time_to_go(carried, target, limits)
        });
        let chaser = self.roles.as_mut()?.name(&times, period_s)?;
        u8::try_from(chaser).ok().map(|c| first.wrapping_add(c))
    }

    /// Whether `chaser` differs from the one last announced (and is now announced).
    pub fn changed(&mut self, chaser: Option<u8>) -> bool {
        let changed = self.announced != Some(chaser);
        self.announced = Some(chaser);
        changed
    }
}

/// The team's first system id, its size and this unit's place in it; `None` without a team
/// (TC_TEAM_N below 2) or where TC_SYSID is not a member.
pub(super) fn members(params: &Params) -> Option<(u8, usize, usize)> {
    let first = params.byte(index::TEAM_SYS);
    let size = usize::from(params.byte(index::TEAM_N));
    let own = usize::from(params.byte(index::SYSID).wrapping_sub(first));
    (size >= 2 && first > 0 && own < size).then_some((first, size, own))
}
