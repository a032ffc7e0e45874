//! The evader against a team: its turn each period, in the host's chase and for an evader
//! flown elsewhere (a SITL vehicle) from the states it is given.

use super::period::{guidance, independent, narrow};
use crate::kinematics::{advance, distance};
use twocars::team::time_to_go;
use twocars::Guidance;

/// How the evader flies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TeamEvader {
    /// Of {-w_em, 0, +w_em} for one period, the turn whose least time to go over the pursuers
    /// afterwards is longest (`twocars::team::time_to_go`). Against one pursuer it flees its
    /// collision course. The law's game value would not do: below the theorem's threshold an
    /// evader that ascends it can run head-on into the pursuer (docs/team.md).
    TeamAware,
    /// The paper's law against the pursuer with the least game value (it does not see the
    /// team's roles).
    Law,
    /// Straight ahead.
    Straight,
}

impl TeamEvader {
    /// Every evader, with the report's names.
    pub const ALL: [(TeamEvader, &'static str); 3] = [
        (TeamEvader::TeamAware, "team-aware"),
        (TeamEvader::Law, "law"),
        (TeamEvader::Straight, "straight"),
    ];
}

/// The team-aware evader's turn: of {0, +w_em, -w_em}, the one whose least time to go over the
/// `active` pursuers (limits `limits`, the evader's those of the first), after each has flown
/// `curvatures` for `dt`, is longest; a turn that ends within `eps` of a pursuer is the worst.
pub(super) fn team_aware<const N: usize>(
    limits: &[[f64; 4]; N],
    (pursuers, evader): (&[[f64; 3]; N], [f64; 3]),
    (curvatures, active): (&[f64; N], &[bool; N]),
    (dt, eps): (f64, f64),
) -> f64 {
    let Some(&[_, _, v_em, w_em]) = limits.first() else {
        return 0.0;
    };
    let moved: [[f64; 3]; N] =
        core::array::from_fn(|i| advance(pursuers[i], limits[i][0], curvatures[i], dt));
    let score = |w: f64| {
        let e = advance(evader, v_em, w, dt);
        let mut least = f64::INFINITY;
        for i in (0..N).filter(|&i| active[i]) {
            if distance(moved[i], e) <= eps {
                return f64::NEG_INFINITY;
            }
            let t = time_to_go(narrow(moved[i]), narrow(e), narrow(limits[i]));
            least = least.min(t.map_or(f64::INFINITY, f64::from));
        }
        least
    };
    [0.0, w_em, -w_em]
        .into_iter()
        .map(|w| (w, score(w)))
        .fold(
            (0.0, f64::NEG_INFINITY),
            |b, c| if c.1 > b.1 { c } else { b },
        )
        .0
}

/// One of [`TeamEvader`]'s evaders flown from states given each period (m, rad, in one
/// plane), as the host's chase flies it: the pursuers taken to fly their own flight policies
/// from the same states.
pub struct EvaderPlay<const N: usize> {
    kind: TeamEvader,
    limits: [[f64; 4]; N],
    own: [Guidance<f32>; N],
    dt: f64,
    eps: f64,
}

impl<const N: usize> EvaderPlay<N> {
    /// `kind` against pursuers of `limits` (v_pm, w_pm, v_em, w_em each), judged a period of
    /// `dt` (s) ahead, captured within `eps` (m); `None` where a pursuer's limits are invalid.
    pub fn new(kind: TeamEvader, limits: [[f64; 4]; N], dt: f64, eps: f64) -> Option<Self> {
        Some(EvaderPlay {
            kind,
            limits,
            own: guidance(&limits, dt, eps)?,
            dt,
            eps,
        })
    }

    /// The evader's curvature (1/m, clockwise) with the pursuers at `pursuers` and the
    /// evader at `evader`.
    pub fn turn(&mut self, pursuers: &[[f64; 3]; N], evader: [f64; 3]) -> f64 {
        let active = [true; N];
        let period = independent(&mut self.own, &active, pursuers, evader);
        match self.kind {
            TeamEvader::Straight => 0.0,
            TeamEvader::Law => period.law_evader,
            TeamEvader::TeamAware => team_aware(
                &self.limits,
                (pursuers, evader),
                (&period.curvatures, &active),
                (self.dt, self.eps),
            ),
        }
    }
}
