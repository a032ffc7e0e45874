//! Several pursuers, one evader: the roles of a team on each pursuer's time to capture.
//!
//! Every period each pursuer's guidance decides against the evader, as it would alone, and
//! the team names a **chaser**: the pursuer with the least time to go, kept until another
//! one's is shorter by [`MARGIN`] of the chaser's ([`Team::with_margin`]), and in any case
//! for [`DWELL_TURNS`] of its full turns after it takes the role and within [`TERMINAL_TURNS`]
//! of one from the capture, so that neither noise in the states nor an evader turning
//! between pursuers swaps the roles often. Every other pursuer is in **support**.
//!
//! Every pursuer, chaser or support, flies its own flight policy. Against an evader that
//! maximises the least capture time over the team, each pursuer's own policy is the fastest
//! way to make its time the one that binds the evader; the roles tried that steer the
//! others elsewhere (for the evader's escape point away from the chaser, or the straight-line
//! collision point) capture later (docs/team.md). The roles say who the team expects to
//! capture, for the operator and the links; the team's predicted time is the least of the
//! pursuers' game values.
//!
//! The time to go that names the chaser is the straight-line collision time with the evader
//! held on its heading, plus the pursuer's turn onto it: unlike the game's value below the
//! theorem's threshold, it does not jump by a full turn when the law's tangents change.
//!
//! A pursuer knows only the states it is given: the same code in each vehicle names the same
//! chaser where the states agree and the teams began together. Where they do not (one
//! vehicle's fixes late or lost), two vehicles may name different chasers; no command depends
//! on the role, so each still flies its own policy and the roles agree again once the states
//! do.
//!
//! Units: metres, seconds, radians anticlockwise from +x, curvature in 1/m (SI, f32, as
//! [`crate::Limits::states`] takes them); the guidance runs on its own backend `S`.

use crate::error::Error;
use crate::guidance::Guidance;
use crate::law::geometry::Limits;
use crate::law::Decision;
use crate::num::{f32_math, Scalar};

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

/// A pursuer's part in the team.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Role {
    /// The pursuer the team expects to capture: the least time to go, with hysteresis.
    Chaser,
    /// Any other pursuer.
    Support,
}

/// One period's decision for a team of `N`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeamDecision<S, const N: usize> {
    /// Each pursuer's guidance decision, or why its states were refused (its command is then
    /// straight ahead).
    pub decisions: [Result<Decision<S>, Error>; N],
    /// Each pursuer's time to go, s (`None` where its states are refused).
    pub times_to_go: [Option<f32>; N],
    /// Each pursuer's role.
    pub roles: [Role; N],
    /// The chaser, if any pursuer has a time to go.
    pub chaser: Option<usize>,
}

impl<S: Scalar, const N: usize> TeamDecision<S, N> {
    /// Pursuer `i`'s commanded curvature, 1/m: its guidance's, or 0 (straight) where its states
    /// were refused or `i` is not in the team.
    pub fn curvature(&self, i: usize) -> f32 {
        match self.decisions.get(i) {
            Some(Ok(decision)) => decision.curvatures()[0],
            _ => 0.0,
        }
    }

    /// The team's predicted capture time, s: the least of the pursuers' game values
    /// ([`Decision::value_seconds`]); `None` where no pursuer has one.
    pub fn team_time(&self) -> Option<f32> {
        self.decisions
            .iter()
            .filter_map(|d| d.as_ref().ok()?.value_seconds())
            .fold(None, |least, t| Some(least.map_or(t, |l: f32| l.min(t))))
    }
}

/// `N` pursuers, each with its own limits and guidance, against one evader.
#[derive(Clone, Debug)]
pub struct Team<S: Scalar, const N: usize> {
    guidance: [Guidance<S>; N],
    /// Each pursuer's limits, SI: v_pm, w_pm, and the evader's v_em, w_em as it sees them.
    limits: [[f32; 4]; N],
    chaser: Option<usize>,
    margin: f32,
    /// Seconds since the chaser took its role.
    held: f32,
}

impl<S: Scalar, const N: usize> Team<S, N> {
    /// A team of `guidance`, each pursuer's with its `limits` (v_pm, w_pm, v_em, w_em; m/s,
    /// 1/m, as its guidance was built with), roles taken over at [`MARGIN`].
    ///
    /// # Errors
    /// `InvalidLimits` or `OutOfRange` where a pursuer's limits are not a game
    /// ([`Limits::new`]).
    pub fn new(guidance: [Guidance<S>; N], limits: [[f32; 4]; N]) -> Result<Self, Error> {
        for [v_pm, w_pm, v_em, w_em] in limits {
            Limits::<f32>::new(v_pm, w_pm, v_em, w_em)?;
        }
        Ok(Team {
            guidance,
            limits,
            chaser: None,
            margin: MARGIN,
            held: 0.0,
        })
    }

    /// The same team, another pursuer taking over once its time to go is shorter than the
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

    /// Forgets the chaser and every guidance's memory (a new engagement).
    pub fn reset(&mut self) {
        self.chaser = None;
        self.guidance.iter_mut().for_each(Guidance::reset);
    }

    /// One period: each pursuer's state `pursuers[i]` and the evader's (x, y, theta; m, m,
    /// rad) to each pursuer's decision and role.
    pub fn decide(&mut self, pursuers: &[[f32; 3]; N], evader: [f32; 3]) -> TeamDecision<S, N> {
        let decisions: [Result<Decision<S>, Error>; N] = core::array::from_fn(|i| {
            let guidance = &mut self.guidance[i];
            let (p, e) = guidance.law().limits.states(pursuers[i], evader)?;
            Ok(guidance.decide(&p, &e))
        });
        let times_to_go: [Option<f32>; N] = core::array::from_fn(|i| match decisions[i] {
            Ok(_) => time_to_go(pursuers[i], evader, self.limits[i]),
            Err(_) => None,
        });
        let next = match self.chaser.is_some_and(|c| self.locked(c, times_to_go[c])) {
            true => self.chaser,
            false => next_chaser(self.chaser, &times_to_go, self.margin),
        };
        self.held = match next == self.chaser {
            true => self.held + self.guidance[0].period(),
            false => 0.0,
        };
        self.chaser = next;
        let roles = core::array::from_fn(|i| match self.chaser == Some(i) {
            true => Role::Chaser,
            false => Role::Support,
        });
        TeamDecision {
            decisions,
            times_to_go,
            roles,
            chaser: self.chaser,
        }
    }
}

impl<S: Scalar, const N: usize> Team<S, N> {
    /// Whether chaser `c`, with time to go `time` (s), keeps its role whatever the others'
    /// times: for [`DWELL_TURNS`] of its full turns after taking it, and within
    /// [`TERMINAL_TURNS`] of one from the capture. A refused state never locks.
    fn locked(&self, c: usize, time: Option<f32>) -> bool {
        let Some(time) = time else {
            return false;
        };
        let [v_pm, w_pm, _, _] = self.limits[c];
        let turn = core::f32::consts::TAU / (v_pm * w_pm);
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
/// rate v_pm w_pm; `None` for a non-finite result.
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
    use crate::{Law, Policy, Variant};
    use core::f32::consts::PI;

    const LIMITS: [f32; 4] = [2.0, 1.0, 1.0, 0.5];

    fn team<const N: usize>() -> Team<f32, N> {
        let [v_pm, w_pm, v_em, w_em] = LIMITS;
        let limits = Limits::new(v_pm, w_pm, v_em, w_em).unwrap();
        let guidance = Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Flight);
        Team::new([guidance.unwrap(); N], [LIMITS; N]).unwrap()
    }

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

    #[test]
    fn the_nearer_pursuer_chases_and_every_pursuer_flies_its_own_guidance() {
        let mut team = team::<2>();
        let mut alone = team.guidance[1];
        let pursuers = [[-20.0, 0.0, 0.0], [0.0, -8.0, PI / 2.0]];
        let evader = [0.0, 0.0, 0.0];
        let d = team.decide(&pursuers, evader);
        assert_eq!(d.chaser, Some(1));
        assert_eq!(d.roles, [Role::Support, Role::Chaser]);
        let (p, e) = alone.law().limits.states(pursuers[1], evader).unwrap();
        assert_eq!(d.decisions[1], Ok(alone.decide(&p, &e)));
        let least = d
            .decisions
            .iter()
            .filter_map(|d| d.unwrap().value_seconds());
        assert_eq!(d.team_time(), least.reduce(f32::min));
    }

    #[test]
    fn a_new_chaser_keeps_its_role_for_the_dwell_and_near_the_capture() {
        let mut team = team::<2>();
        let evader = [0.0, 0.0, 0.0];
        let near = [[-10.0, 0.0, 0.0], [-40.0, 0.0, 0.0]];
        assert_eq!(team.decide(&near, evader).chaser, Some(0));
        // Pursuer 1 far sooner now: pursuer 0 keeps the role for DWELL_TURNS full turns.
        let swapped = [[-40.0, 0.0, 0.0], [-10.0, 0.0, 0.0]];
        let turn = core::f32::consts::TAU / (LIMITS[0] * LIMITS[1]);
        let periods = (DWELL_TURNS * turn / 0.01) as usize;
        for _ in 0..periods - 2 {
            assert_eq!(team.decide(&swapped, evader).chaser, Some(0));
        }
        let later: usize = (0..4)
            .map(|_| team.decide(&swapped, evader).chaser.unwrap())
            .sum();
        assert!(later > 0, "pursuer 1 takes over after the dwell");
        // Within a full turn of the capture the chaser stays past the dwell.
        team.reset();
        let close = [[-1.0, 0.0, 0.0], [-40.0, 0.0, 0.0]];
        assert_eq!(team.decide(&close, evader).chaser, Some(0));
        let closer = [[-1.0, 0.0, PI], [-0.5, 0.0, 0.0]];
        for _ in 0..2 * periods {
            assert_eq!(team.decide(&closer, evader).chaser, Some(0));
        }
    }

    #[test]
    fn a_refused_state_flies_straight_and_never_chases() {
        let mut team = team::<2>();
        let d = team.decide(&[[f32::NAN, 0.0, 0.0], [-30.0, 0.0, 0.0]], [0.0; 3]);
        assert_eq!(d.decisions[0], Err(Error::NonFiniteInput));
        assert_eq!(d.curvature(0), 0.0);
        assert_eq!(d.times_to_go[0], None);
        assert_eq!(d.chaser, Some(1));
        // Every state refused: no chaser, no team time.
        let d = team.decide(&[[f32::NAN, 0.0, 0.0]; 2], [0.0; 3]);
        assert_eq!((d.chaser, d.team_time()), (None, None));
    }

    #[test]
    fn limits_and_margins_outside_the_game_are_refused() {
        let guidance = team::<1>().guidance;
        let err = Team::new(guidance, [[1.0, 1.0, 2.0, 0.5]]).err();
        assert_eq!(err, Some(Error::InvalidLimits));
        assert_eq!(
            team::<1>().with_margin(f32::NAN).err(),
            Some(Error::NonFiniteInput)
        );
        assert_eq!(team::<1>().with_margin(1.5).err(), Some(Error::OutOfRange));
    }
}
