//! Which pursuer chases: the least time to go, with hysteresis. Needs only the times, so a
//! unit that runs its own guidance (the MAVLink endpoint on its estimator) can name the roles
//! from its teammates' states without deciding for them.

use crate::error::Error;
use crate::num::f32_math;

/// How much shorter, as a share of the chaser's time to go, another pursuer's must be to
/// take over.
pub const MARGIN: f32 = 0.3;

/// How long, in the chaser's full turns (2 pi / (v_pm w_pm)), a new chaser keeps its role
/// whatever the others' times: an evader turning from one pursuer toward another would
/// otherwise swap the roles at every turn.
pub const DWELL_TURNS: f32 = 3.0;

/// Within this many of its full turns of the capture (its time to go), the chaser keeps its
/// role: there a position's noise moves the bearing, and the time to go, the most.
pub const TERMINAL_TURNS: f32 = 1.0;

/// The chaser among `N` pursuers, named each period on their times to go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roles<const N: usize> {
    /// Each pursuer's full turn, s: 2 pi / (v_pm w_pm).
    turns: [f32; N],
    chaser: Option<usize>,
    margin: f32,
    /// Seconds since the chaser took its role.
    held: f32,
}

impl<const N: usize> Roles<N> {
    /// Roles for pursuers of these speeds and curvatures ([v_pm, w_pm]; m/s, 1/m), taken over
    /// at [`MARGIN`].
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN; `InvalidLimits` where a speed or curvature is not positive.
    pub fn new(pursuers: [[f32; 2]; N]) -> Result<Self, Error> {
        let mut turns = [0.0; N];
        for (turn, [v_pm, w_pm]) in turns.iter_mut().zip(pursuers) {
            if v_pm.is_nan() || w_pm.is_nan() {
                return Err(Error::NonFiniteInput);
            }
            *turn = core::f32::consts::TAU / (v_pm * w_pm);
            if !(v_pm > 0.0 && w_pm > 0.0 && turn.is_finite()) {
                return Err(Error::InvalidLimits);
            }
        }
        Ok(Roles {
            turns,
            chaser: None,
            margin: MARGIN,
            held: 0.0,
        })
    }

    /// The same roles, another pursuer taking over once its time to go is shorter than the
    /// chaser's by `margin` of the chaser's (0 to 1).
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN; `OutOfRange` outside [0, 1].
    pub fn with_margin(mut self, margin: f32) -> Result<Self, Error> {
        if margin.is_nan() {
            return Err(Error::NonFiniteInput);
        }
        if !(0.0..=1.0).contains(&margin) {
            return Err(Error::OutOfRange);
        }
        self.margin = margin;
        Ok(self)
    }

    /// The current chaser, if any.
    pub fn chaser(&self) -> Option<usize> {
        self.chaser
    }

    /// Forgets the chaser (a new engagement).
    pub fn reset(&mut self) {
        self.chaser = None;
        self.held = 0.0;
    }

    /// One period of `dt` seconds: the chaser after each pursuer's time to go (s; `None`
    /// where it has none, which never chases). The chaser keeps its role unless another's
    /// time is shorter by the margin, and in any case for [`DWELL_TURNS`] of its full turns
    /// after taking it and within [`TERMINAL_TURNS`] of one from the capture.
    pub fn name(&mut self, times: &[Option<f32>; N], dt: f32) -> Option<usize> {
        let held = self
            .chaser
            .is_some_and(|c| self.locked(c, times.get(c).copied().flatten()));
        let next = match held {
            true => self.chaser,
            false => next_chaser(self.chaser, times, self.margin),
        };
        self.held = match next == self.chaser {
            true => self.held + dt,
            false => 0.0,
        };
        self.chaser = next;
        next
    }

    /// Whether chaser `c`, with time to go `time` (s), keeps its role whatever the others'
    /// times. A pursuer without a time never does.
    fn locked(&self, c: usize, time: Option<f32>) -> bool {
        let (Some(time), Some(&turn)) = (time, self.turns.get(c)) else {
            return false;
        };
        self.held < DWELL_TURNS * turn || time < TERMINAL_TURNS * turn
    }
}

/// The chaser after `times`: the current one unless another is shorter by `margin` of its
/// time; the least time where there is no chaser yet or the chaser has no time.
fn next_chaser<const N: usize>(
    current: Option<usize>,
    times: &[Option<f32>; N],
    margin: f32,
) -> Option<usize> {
    let best = (0..N).filter_map(|i| Some((i, times[i]?))).fold(
        None,
        |best: Option<(usize, f32)>, (i, t)| match best {
            Some((_, b)) if b <= t => best,
            _ => Some((i, t)),
        },
    );
    let (i_best, t_best) = best?;
    match current.and_then(|c| Some((c, (*times.get(c)?)?))) {
        Some((c, t)) if t_best >= t * (1.0 - margin) => Some(c),
        _ => Some(i_best),
    }
}

/// The time to go, s: the straight-line collision time T with the evader held on its heading
/// at v_em (|r + u T| = v_pm T), plus the pursuer's turn onto the collision point at its full
/// rate v_pm w_pm; `None` for a non-finite input or result. States are (x, y, theta; m, m,
/// rad), limits (v_pm, w_pm, v_em, w_em; m/s, 1/m).
pub fn time_to_go(
    pursuer: [f32; 3],
    evader: [f32; 3],
    [v_pm, w_pm, v_em, _]: [f32; 4],
) -> Option<f32> {
    if !pursuer.iter().chain(&evader).all(|v| v.is_finite()) {
        return None;
    }
    let (rx, ry) = (evader[0] - pursuer[0], evader[1] - pursuer[1]);
    let d = f32_math::sqrt(rx * rx + ry * ry);
    if d <= 0.0 {
        return Some(0.0);
    }
    let (sin_e, cos_e) = f32_math::sin_cos(evader[2]);
    // The evader's speed along the line of sight, and the closing terms of the quadratic.
    let c = v_em * (rx * cos_e + ry * sin_e) / d;
    let a = v_pm * v_pm - v_em * v_em;
    let t = d * (c + f32_math::sqrt(c * c + a)) / a;
    let (ax, ay) = (rx + v_em * t * cos_e, ry + v_em * t * sin_e);
    let bearing = f32_math::wrap_signed(f32_math::atan2(ay, ax) - pursuer[2]);
    let time = t + libm::fabsf(bearing) / (v_pm * w_pm);
    time.is_finite().then_some(time)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f32::consts::PI;

    const LIMITS: [f32; 4] = [2.0, 1.0, 1.0, 0.5];

    #[test]
    fn the_chaser_changes_only_past_the_margin() {
        let times = [Some(10.0), Some(9.5), None];
        assert_eq!(next_chaser(None, &times, 0.1), Some(1));
        // 9.5 is within 10 % of 10: the chaser stays.
        assert_eq!(next_chaser(Some(0), &times, 0.1), Some(0));
        let sooner = [Some(10.0), Some(8.9), None];
        assert_eq!(next_chaser(Some(0), &sooner, 0.1), Some(1));
        // A chaser without a time gives way; nobody with a time, nobody chases.
        assert_eq!(next_chaser(Some(2), &times, 0.1), Some(1));
        assert_eq!(next_chaser::<2>(Some(0), &[None, None], 0.1), None);
    }

    #[test]
    fn a_new_chaser_keeps_its_role_for_the_dwell_and_near_the_capture() {
        let mut roles = Roles::new([[2.0, 1.0]; 2]).unwrap();
        let turn = core::f32::consts::TAU / 2.0;
        assert_eq!(roles.name(&[Some(5.0), Some(20.0)], 0.01), Some(0));
        // Pursuer 1 far sooner now: pursuer 0 keeps the role for DWELL_TURNS full turns.
        let periods = (DWELL_TURNS * turn / 0.01) as usize;
        for _ in 0..periods - 2 {
            assert_eq!(roles.name(&[Some(20.0), Some(5.0)], 0.01), Some(0));
        }
        let later: usize = (0..4)
            .map(|_| roles.name(&[Some(20.0), Some(5.0)], 0.01).unwrap())
            .sum();
        assert!(later > 0, "pursuer 1 takes over after the dwell");
        // Within a full turn of the capture the chaser stays past the dwell.
        roles.reset();
        assert_eq!(roles.name(&[Some(2.0), Some(20.0)], 0.01), Some(0));
        for _ in 0..2 * periods {
            assert_eq!(roles.name(&[Some(2.0), Some(0.5)], 0.01), Some(0));
        }
        // Without a time it gives way at once.
        assert_eq!(roles.name(&[None, Some(0.5)], 0.01), Some(1));
    }

    #[test]
    fn roles_refuse_limits_and_margins_outside_the_game() {
        assert_eq!(Roles::new([[0.0, 1.0]]).err(), Some(Error::InvalidLimits));
        assert_eq!(
            Roles::new([[f32::NAN, 1.0]]).err(),
            Some(Error::NonFiniteInput)
        );
        let roles = Roles::new([[2.0, 1.0]]).unwrap();
        assert_eq!(
            roles.with_margin(f32::NAN).err(),
            Some(Error::NonFiniteInput)
        );
        assert_eq!(roles.with_margin(1.5).err(), Some(Error::OutOfRange));
    }

    #[test]
    fn the_time_to_go_is_the_collision_time_and_the_turn() {
        // Head-on: closing at v_pm + v_em from 9 m, no turn.
        let t = time_to_go([0.0, 0.0, 0.0], [9.0, 0.0, PI], LIMITS).unwrap();
        assert!((t - 3.0).abs() < 1e-4, "{t}");
        // Fleeing along the line of sight: v_pm - v_em; pointing away adds a half turn at 2 rad/s.
        let t = time_to_go([0.0, 0.0, PI], [9.0, 0.0, 0.0], LIMITS).unwrap();
        assert!((t - (9.0 + PI / 2.0)).abs() < 1e-3, "{t}");
        assert_eq!(
            time_to_go([0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], LIMITS),
            None
        );
    }
}
