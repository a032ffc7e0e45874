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
//! [`Roles`] names the chaser from the times to go alone: a unit that runs its own guidance
//! (on its estimator's states) names the roles with it from its teammates' states, without
//! deciding for them.
//!
//! Units: metres, seconds, radians anticlockwise from +x, curvature in 1/m (SI, f32, as
//! [`crate::Limits::states`] takes them); the guidance runs on its own backend `S`.

mod roles;

pub use roles::{time_to_go, Roles, DWELL_TURNS, MARGIN, TERMINAL_TURNS};

use crate::error::Error;
use crate::guidance::Guidance;
use crate::law::geometry::Limits;
use crate::law::Decision;
use crate::num::Scalar;

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
    roles: Roles<N>,
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
            roles: Roles::new(limits.map(|[v_pm, w_pm, _, _]| [v_pm, w_pm]))?,
        })
    }

    /// The same team, another pursuer taking over once its time to go is shorter than the
    /// chaser's by `margin` of the chaser's (0 to 1).
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN; `OutOfRange` outside [0, 1].
    pub fn with_margin(mut self, margin: f32) -> Result<Self, Error> {
        self.roles = self.roles.with_margin(margin)?;
        Ok(self)
    }

    /// The current chaser, if any.
    pub fn chaser(&self) -> Option<usize> {
        self.roles.chaser()
    }

    /// Forgets the chaser and every guidance's memory (a new engagement).
    pub fn reset(&mut self) {
        self.roles.reset();
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
        // Every guidance runs at the same period; a team of none has no chaser.
        let period = self.guidance.first().map_or(0.0, Guidance::period);
        let chaser = self.roles.name(&times_to_go, period);
        let roles = core::array::from_fn(|i| match chaser == Some(i) {
            true => Role::Chaser,
            false => Role::Support,
        });
        TeamDecision {
            decisions,
            times_to_go,
            roles,
            chaser,
        }
    }
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
    fn a_team_of_none_decides_nothing() {
        let mut team = Team::<f32, 0>::new([], []).unwrap();
        let d = team.decide(&[], [0.0; 3]);
        assert_eq!((d.chaser, d.team_time(), d.curvature(0)), (None, None, 0.0));
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
