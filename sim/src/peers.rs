//! The pursuers a user would fly instead of ours, on the same fixes in the field's closed loop
//! ([`crate::field`]): what an autopilot's follow mode does with a target it hears of by radio.
//!
//! - [`Peer::Textbook`]: PX4 follow-target's estimator, a critically damped alpha-beta-gamma
//!   filter per axis fed each position fix on arrival, its gains set by the responsiveness
//!   parameter (FLW_TGT_RS): theta = r^(1/3), g = 1 - theta^3, h = 1.5 (1 - theta)^2 (1 + theta),
//!   k = 0.5 (1 - theta)^3, the acceleration held within 2 g as PX4 holds it. The pursuer flies
//!   pure proportional navigation on the estimate (N = 3, curvature N lambda' / v_pm) and a
//!   pursuit turn where the target's bearing is past 60 degrees.
//! - [`Peer::Follow`]: ArduPilot AP_Follow's way. The last fix, with its velocity (speed along
//!   its heading, as GLOBAL_POSITION_INT's vx, vy carry it), is dead-reckoned from the time a
//!   jitter-corrected clock gives it: the least transport delay seen is taken as the clocks'
//!   offset, so a steady lag is not seen and the fix counts from its arrival. The pursuer flies
//!   pure pursuit at the dead-reckoned point plus its velocity times a lead time.
//!
//! Both steer as our sampled command does: toward a bearing b by sign(b) min(w_max,
//! |b| / (v_pm period)), the period being the guidance period the field sets. Units: metres,
//! seconds, radians anticlockwise from +x; curvature in 1/m.

use crate::kinematics::wrap_pi;

/// Proportional navigation's gain.
const NAVIGATION_GAIN: f64 = 3.0;
/// Past this bearing (radians) the textbook pursuer turns toward the target instead.
const PURSUIT_BEARING: f64 = std::f64::consts::FRAC_PI_3;
/// PX4's acceleration saturation, m/s^2 (2 g).
const ACCELERATION_SATURATION: f64 = 20.0;

/// A peer and its own parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Peer {
    /// PX4 follow-target's filter with proportional navigation; FLW_TGT_RS in (0, 1].
    Textbook {
        /// The filter's responsiveness r: g = 1 - r.
        responsiveness: f64,
    },
    /// AP_Follow's dead-reckoned target with pure pursuit.
    Follow {
        /// How far ahead along the target's velocity the pursuer aims, seconds.
        lead: f64,
    },
}

impl Peer {
    /// The textbook pursuer's sweep of its responsiveness.
    pub const TEXTBOOK_SWEEP: [f64; 4] = [0.1, 0.3, 0.5, 0.7];
    /// The follow pursuer's sweep of its lead, in the pursuer's full turns T.
    pub const FOLLOW_SWEEP_TURNS: [f64; 4] = [0.0, 0.1, 0.2, 0.4];

    /// The peer's parameter as the report prints it.
    pub fn parameter(&self) -> String {
        match self {
            Peer::Textbook { responsiveness } => format!("r {responsiveness}"),
            Peer::Follow { lead } => format!("lead {lead:.2} s"),
        }
    }
}

/// One fix as a peer hears it: when it arrived (s), where (m), the target's velocity (m/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeardFix {
    /// Arrival on the pursuer's clock, seconds.
    pub arrival: f64,
    /// When the sender took it, seconds on the sender's clock.
    pub taken: f64,
    /// x, y, metres.
    pub position: [f64; 2],
    /// vx, vy, m/s.
    pub velocity: [f64; 2],
}

/// A critically damped alpha-beta-gamma filter on x and y (PX4's TargetEstimator's form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlphaBetaGamma {
    g: f64,
    h: f64,
    k: f64,
    /// Position (m), velocity (m/s), acceleration (m/s^2) at `time`.
    state: Option<([f64; 2], [f64; 2], [f64; 2])>,
    time: f64,
}

impl AlphaBetaGamma {
    /// A filter of responsiveness `r` in (0, 1].
    pub fn new(r: f64) -> Self {
        let theta = r.clamp(0.01, 1.0).cbrt();
        AlphaBetaGamma {
            g: 1.0 - theta.powi(3),
            h: 1.5 * (1.0 - theta).powi(2) * (1.0 + theta),
            k: 0.5 * (1.0 - theta).powi(3),
            state: None,
            time: 0.0,
        }
    }

    /// Position and velocity carried to `t` by the held acceleration; `None` before a fix.
    pub fn predict(&self, t: f64) -> Option<([f64; 2], [f64; 2])> {
        let (p, v, a) = self.state?;
        let dt = t - self.time;
        let at = |i: usize| p[i] + v[i] * dt + 0.5 * a[i] * dt * dt;
        Some(([at(0), at(1)], [v[0] + a[0] * dt, v[1] + a[1] * dt]))
    }

    /// Fuses a position fix `z` (m) at `t` (s).
    pub fn update(&mut self, z: [f64; 2], t: f64) {
        let dt = t - self.time;
        let (Some((p, v)), Some((_, _, a)), true) = (self.predict(t), self.state, dt > 1e-6) else {
            self.state = Some((z, [0.0; 2], [0.0; 2]));
            self.time = t;
            return;
        };
        let mut next = (p, v, a);
        for i in 0..2 {
            let r = z[i] - p[i];
            next.0[i] = p[i] + self.g * r;
            next.1[i] = v[i] + self.h / dt * r;
            next.2[i] = a[i] + 2.0 * self.k / (dt * dt) * r;
        }
        let norm = next.2[0].hypot(next.2[1]);
        if norm > ACCELERATION_SATURATION {
            next.2 = next.2.map(|c| c * ACCELERATION_SATURATION / norm);
        }
        self.state = Some(next);
        self.time = t;
    }
}

/// A peer pursuer's memory.
#[derive(Clone, Debug, PartialEq)]
pub struct PeerPursuer {
    peer: Peer,
    filter: AlphaBetaGamma,
    last: Option<HeardFix>,
    /// The least (arrival - taken) seen: the jitter-corrected clock's offset, seconds.
    offset: f64,
    /// v_pm (m/s), w_pm (1/m), the guidance period (s).
    speed: f64,
    w_max: f64,
    period: f64,
}

impl PeerPursuer {
    /// `peer` flying at `v_pm`, turning at most `w_pm`, steering over `period` seconds.
    pub fn new(peer: Peer, v_pm: f64, w_pm: f64, period: f64) -> Self {
        let responsiveness = match peer {
            Peer::Textbook { responsiveness } => responsiveness,
            Peer::Follow { .. } => 1.0,
        };
        PeerPursuer {
            peer,
            filter: AlphaBetaGamma::new(responsiveness),
            last: None,
            offset: f64::INFINITY,
            speed: v_pm,
            w_max: w_pm,
            period,
        }
    }

    /// Hears one fix.
    pub fn hear(&mut self, fix: &HeardFix) {
        self.filter.update(fix.position, fix.arrival);
        self.offset = self.offset.min(fix.arrival - fix.taken);
        self.last = Some(*fix);
    }

    /// The curvature command (1/m) at `t` for the pursuer at `own`; 0 before any fix.
    pub fn command(&self, t: f64, own: [f64; 3]) -> f64 {
        match self.peer {
            Peer::Textbook { .. } => self
                .filter
                .predict(t)
                .map_or(0.0, |(p, v)| self.navigate(own, p, v)),
            Peer::Follow { lead } => self.last.map_or(0.0, |fix| {
                let age = t - (fix.taken + self.offset) + lead;
                let aim = [
                    fix.position[0] + fix.velocity[0] * age,
                    fix.position[1] + fix.velocity[1] * age,
                ];
                self.steer(bearing(own, aim))
            }),
        }
    }

    /// Pure proportional navigation on the target at `p` (m) moving at `v` (m/s); a pursuit
    /// turn past [`PURSUIT_BEARING`].
    fn navigate(&self, own: [f64; 3], p: [f64; 2], v: [f64; 2]) -> f64 {
        let b = bearing(own, p);
        if b.abs() > PURSUIT_BEARING {
            return self.steer(b);
        }
        let (rx, ry) = (p[0] - own[0], p[1] - own[1]);
        let (vx, vy) = (
            v[0] - self.speed * own[2].cos(),
            v[1] - self.speed * own[2].sin(),
        );
        let range2 = (rx * rx + ry * ry).max(1e-12);
        let los_rate = (rx * vy - ry * vx) / range2;
        (NAVIGATION_GAIN * los_rate / self.speed).clamp(-self.w_max, self.w_max)
    }

    /// The sampled command toward bearing `b` (radians off the nose).
    fn steer(&self, b: f64) -> f64 {
        b.signum() * self.w_max.min(b.abs() / (self.speed * self.period))
    }
}

/// The bearing (radians, (-pi, pi]) of `aim` off the nose of `own`.
fn bearing(own: [f64; 3], aim: [f64; 2]) -> f64 {
    wrap_pi((aim[1] - own[1]).atan2(aim[0] - own[0]) - own[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_filter_follows_a_straight_target_exactly_once_settled() {
        let mut f = AlphaBetaGamma::new(0.5);
        for i in 0..200 {
            let t = 0.1 * i as f64;
            f.update([1.0 + 2.0 * t, -3.0 + 0.5 * t], t);
        }
        let (p, v) = f.predict(20.0).unwrap();
        assert!(
            (p[0] - 41.0).abs() < 1e-6 && (p[1] - 7.0).abs() < 1e-6,
            "{p:?}"
        );
        assert!(
            (v[0] - 2.0).abs() < 1e-6 && (v[1] - 0.5).abs() < 1e-6,
            "{v:?}"
        );
    }

    #[test]
    fn the_follow_pursuer_aims_ahead_of_a_late_fix() {
        let mut peer = PeerPursuer::new(Peer::Follow { lead: 0.0 }, 2.0, 2.0, 0.1);
        // Taken at 0.0, arrived at 0.2: the offset is the lag, so the fix counts from 0.2.
        peer.hear(&HeardFix {
            arrival: 0.2,
            taken: 0.0,
            position: [5.0, 0.0],
            velocity: [0.0, 1.0],
        });
        // At 1.2 the target is dead-reckoned to (5, 1): left of a pursuer facing +x.
        let w = peer.command(1.2, [0.0, 0.0, 0.0]);
        let expected = (1.0_f64 / 5.0).atan() / (2.0 * 0.1);
        assert!((w - expected).abs() < 1e-9, "{w} against {expected}");
    }

    #[test]
    fn the_textbook_pursuer_turns_toward_a_target_behind_it() {
        let mut peer = PeerPursuer::new(
            Peer::Textbook {
                responsiveness: 0.3,
            },
            2.0,
            2.0,
            0.1,
        );
        peer.hear(&HeardFix {
            arrival: 0.0,
            taken: 0.0,
            position: [-5.0, -1.0],
            velocity: [0.0; 2],
        });
        assert_eq!(peer.command(0.0, [0.0, 0.0, 0.0]), -2.0);
    }
}
