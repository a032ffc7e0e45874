//! The serial unit's part in a team of pursuers (protocol version 3, feature `serial-team`;
//! docs/protocol.md, docs/team.md): the Configure says how many pursuers there are and which
//! is this unit's; each Teammate frame gives one teammate's state and its time on the States'
//! clock. Each State names the chaser ([`crate::team::Roles`]) from every member's time to go
//! against the State's evader, each teammate carried forward in a straight line at v_pm to the
//! State's time; the Command carries the chaser's index, and its turn does not depend on it.

use crate::num::f32_math;
use crate::protocol::frame::WireError;
use crate::protocol::message::{TeamConfig, TeammateMsg, NO_MEMBER};
use crate::team::{time_to_go, Roles};

/// The most members a team has.
pub const MAX_TEAM: usize = 8;

/// A teammate's last state: where it was and when (ms on the States' clock).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Mate {
    time_ms: u32,
    state: [f32; 3],
}

/// The team as this unit knows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Team {
    size: usize,
    own: usize,
    limits: [f32; 4],
    mates: [Option<Mate>; MAX_TEAM],
    roles: Roles<MAX_TEAM>,
}

impl Team {
    /// The team a Configure asks for, every member of `limits` (v_pm, w_pm, v_em, w_em; m/s,
    /// 1/m): `Ok(None)` for no team (size 0 or 1).
    ///
    /// # Errors
    /// `InvalidConfig` for more than [`MAX_TEAM`] members, an own index outside the team, or
    /// limits the roles cannot take.
    pub fn of(config: TeamConfig, limits: [f32; 4]) -> Result<Option<Team>, WireError> {
        if config.is_none() {
            return Ok(None);
        }
        if !config.fits(MAX_TEAM as u8) {
            return Err(WireError::InvalidConfig);
        }
        let (size, own) = (usize::from(config.size), usize::from(config.own));
        let [v_pm, w_pm, _, _] = limits;
        let roles = Roles::new([[v_pm, w_pm]; MAX_TEAM]).map_err(|_| WireError::InvalidConfig)?;
        Ok(Some(Team {
            size,
            own,
            limits,
            mates: [None; MAX_TEAM],
            roles,
        }))
    }

    /// A teammate's state, kept where it names a teammate.
    ///
    /// # Errors
    /// `OutOfRangeField` for this unit's own index or one outside the team;
    /// `NonFiniteField` for a NaN or infinite coordinate.
    pub fn hear(&mut self, m: &TeammateMsg) -> Result<(), WireError> {
        let index = usize::from(m.index);
        if !m.state.iter().all(|v| v.is_finite()) {
            return Err(WireError::NonFiniteField);
        }
        if index == self.own || index >= self.size {
            return Err(WireError::OutOfRangeField);
        }
        let slot = self
            .mates
            .get_mut(index)
            .ok_or(WireError::OutOfRangeField)?;
        *slot = Some(Mate {
            time_ms: m.time_ms,
            state: m.state,
        });
        Ok(())
    }

    /// The chaser's index this period of `period_s` (s), [`NO_MEMBER`] for none: this unit's
    /// pursuer at `own` and the evader at `evader` at `time_ms`; a teammate heard more than
    /// `timeout_ms` before that, or after it, has no time.
    pub fn name(
        &mut self,
        (own, evader): ([f32; 3], [f32; 3]),
        (time_ms, timeout_ms): (u32, u32),
        period_s: f32,
    ) -> u8 {
        let times: [Option<f32>; MAX_TEAM] = core::array::from_fn(|i| {
            if i == self.own {
                return time_to_go(own, evader, self.limits);
            }
            let mate = self.mates.get(i).copied().flatten()?;
            let age_ms = time_ms.wrapping_sub(mate.time_ms);
            if age_ms > timeout_ms {
                return None;
            }
            let run = self.limits[0] * age_ms as f32 / 1000.0;
            let (sin, cos) = f32_math::sin_cos(mate.state[2]);
            let [x, y, theta] = mate.state;
            time_to_go([x + run * cos, y + run * sin, theta], evader, self.limits)
        });
        self.roles
            .name(&times, period_s)
            .and_then(|c| u8::try_from(c).ok())
            .unwrap_or(NO_MEMBER)
    }

    /// Forgets the teammates and the roles (a Reset).
    pub fn clear(&mut self) {
        self.mates = [None; MAX_TEAM];
        self.roles.reset();
    }
}
