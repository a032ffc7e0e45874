//! One vehicle's track: its state carried from fix to fix on its own model and filtered.
//!
//! The model is the game's own car: speed s in [0, v_max] along the heading, turn rate omega
//! within +-v_max w_max, both held between fixes (a constant-turn arc). Each fix is compared
//! with the arc's prediction at the fix's time, and the residuals correct the state as a
//! steady-state Kalman filter of that model would (an alpha-beta filter per channel):
//!
//! - position x, y by alpha r and heading by alpha_h r_theta;
//! - speed by beta (r along the heading) / T and turn rate by beta_h r_theta / T,
//!   T being the time since the last fix.
//!
//! The gains follow from the tracking index lambda = a T^2 / sigma (Kalata's steady state of
//! the piecewise-constant-acceleration model): a the largest acceleration the car has
//! (v_max^2 w_max across the track; of turn rate, a full turn reversed in
//! [`REVERSAL_SECONDS`]), sigma the fix's noise. alpha = 1 where the noise is 0: the estimate
//! is then the fix itself, and speed and turn rate its differences (beta = alpha^2 / (2 - alpha),
//! Benedict and Bordner's pairing, which takes a new turn in one interval without overshoot).
//! Why not a full Kalman filter: five states' covariance costs a few hundred products a fix on
//! a core without an FPU, and a car at its limits turns far more than a filter's random-walk
//! model says; the steady-state gains for the measured interval keep its response.
//!
//! Times are microseconds on the unit's clock as a wrapping `u32` (71.6 minutes a lap): two
//! times are compared by their difference, which is right while they are within half a lap.
//! Units: metres, seconds, radians anticlockwise from +x; speed in m/s, turn rate in rad/s.

use crate::num::f32_math::{sin_cos, sqrt, wrap_signed};

/// One position fix: where a vehicle was, and when.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Fix {
    /// x, y (metres) and heading (radians anticlockwise from +x), in the frame the law is given.
    pub state: [f32; 3],
    /// When the vehicle was there: microseconds on the unit's clock (wrapping).
    pub time_us: u32,
}

/// One standard deviation of a fix's noise: what the filter weighs each fix by.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FixNoise {
    /// Of x and y, metres.
    pub position: f32,
    /// Of the heading, radians.
    pub heading: f32,
}

/// Why a fix was not taken. The track is unchanged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Refused {
    /// A NaN or infinite coordinate, or a position or heading outside the f32 envelope
    /// (|x|, |y| <= 1e6 m, |theta| <= 1e4 rad).
    NonFinite,
    /// Older than the fix the track holds, or the same time: out of order or repeated.
    OutOfOrder,
    /// Farther from the track's prediction than the car can go in the time plus six sigma of
    /// the noise. After [`OUTLIERS_TO_RESTART`] in a row the next one restarts the track; a
    /// track whose fixes have no noise restarts at the first.
    Outlier,
}

/// Outliers in a row after which the track trusts the fixes over itself and restarts: a
/// vehicle that really is elsewhere (a reset of the source's frame) is found again.
pub const OUTLIERS_TO_RESTART: u8 = 3;

/// The shortest time in which the filter expects a car to reverse a full turn, seconds: the
/// heading channel's acceleration is 2 v_max w_max over it. Shorter lets heading noise through
/// as turn rate, which the near field's homing feeds forward.
pub const REVERSAL_SECONDS: f32 = 0.5;

/// Microseconds per second.
const US: f32 = 1.0e6;

/// What a track holds at its last fix's time.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Estimate {
    /// x, y (metres), heading (radians).
    x: f32,
    y: f32,
    theta: f32,
    /// Speed along the heading, m/s, in [0, v_max].
    speed: f32,
    /// Turn rate, rad/s, within +-v_max w_max.
    turn_rate: f32,
    /// One sigma of the position just after the last fix, metres.
    spread: f32,
    /// One sigma of the heading just after the last fix, radians.
    heading_spread: f32,
    /// The last fix's time, microseconds.
    time_us: u32,
}

/// A vehicle's filtered state between fixes ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Track {
    /// v_max, m/s.
    speed_max: f32,
    /// v_max w_max, rad/s.
    turn_rate_max: f32,
    noise: FixNoise,
    estimate: Option<Estimate>,
    outliers: u8,
}

/// The steady-state gains (alpha, beta) for tracking index `lambda` (Kalata): alpha from the
/// index, beta = alpha^2 / (2 - alpha). An infinite or NaN index (no noise) gives (1, 1).
fn gains(lambda: f32) -> (f32, f32) {
    if !(lambda.is_finite() && lambda >= 0.0) {
        return (1.0, 1.0);
    }
    let l2 = lambda * lambda;
    let root = sqrt(l2 + 8.0 * lambda);
    let alpha = (-(l2 + 8.0 * lambda - (lambda + 4.0) * root) / 8.0).clamp(0.0, 1.0);
    (alpha, alpha * alpha / (2.0 - alpha))
}

/// The point `run` metres along an arc turning by `turned` radians from heading `theta`: the
/// chord run sin(h) / h at theta + h, h = turned / 2.
fn along_arc(theta: f32, run: f32, turned: f32) -> (f32, f32) {
    let half = 0.5 * turned;
    let chord = if half.abs() > 1.0e-3 {
        run * sin_cos(half).0 / half
    } else {
        run * (1.0 - half * half / 6.0)
    };
    let (s, c) = sin_cos(theta + half);
    (chord * c, chord * s)
}

impl Estimate {
    /// Carried `seconds` ahead on its arc.
    fn after(&self, seconds: f32) -> [f32; 3] {
        let turned = self.turn_rate * seconds;
        let (dx, dy) = along_arc(self.theta, self.speed * seconds, turned);
        [self.x + dx, self.y + dy, wrap_signed(self.theta + turned)]
    }
}

/// Seconds from `from` to `to` (microseconds, wrapping).
fn seconds_between(from: u32, to: u32) -> f32 {
    to.wrapping_sub(from) as i32 as f32 / US
}

impl Track {
    /// A track of a car of speed `v_max` (m/s) and curvature `w_max` (1/m) whose fixes carry
    /// `noise`; `None` unless both limits are finite and positive and the noise finite and
    /// not negative.
    pub fn new(v_max: f32, w_max: f32, noise: FixNoise) -> Option<Self> {
        let turn_rate_max = v_max * w_max;
        let limits_ok = v_max.is_finite() && v_max > 0.0 && turn_rate_max.is_finite();
        let noise_ok = [noise.position, noise.heading]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0);
        (limits_ok && turn_rate_max > 0.0 && noise_ok).then_some(Track {
            speed_max: v_max,
            turn_rate_max,
            noise,
            estimate: None,
            outliers: 0,
        })
    }

    /// Forgets every fix.
    pub fn clear(&mut self) {
        self.estimate = None;
        self.outliers = 0;
    }

    /// The last fix's time, microseconds, if the track has one.
    pub fn last_fix_us(&self) -> Option<u32> {
        self.estimate.map(|e| e.time_us)
    }

    /// Takes a fix: the first one, or one after `stale_us` microseconds without, restarts the
    /// track at it (at full speed, not turning).
    ///
    /// # Errors
    /// [`Refused`] says why the fix was not taken; the track is then unchanged but for its
    /// count of outliers in a row.
    pub fn update(&mut self, fix: &Fix, stale_us: u32) -> Result<(), Refused> {
        let [x, y, theta] = fix.state;
        let envelope = x.abs() <= 1.0e6 && y.abs() <= 1.0e6 && theta.abs() <= 1.0e4;
        if !(x.is_finite() && y.is_finite() && theta.is_finite() && envelope) {
            return Err(Refused::NonFinite);
        }
        let Some(last) = self.estimate else {
            self.restart(fix);
            return Ok(());
        };
        let elapsed = fix.time_us.wrapping_sub(last.time_us) as i32;
        if elapsed <= 0 {
            return Err(Refused::OutOfOrder);
        }
        if elapsed as u32 > stale_us {
            self.restart(fix);
            return Ok(());
        }
        let interval = elapsed as f32 / US;
        let [px, py, ptheta] = last.after(interval);
        let (rx, ry) = (x - px, y - py);
        let reach = 2.0 * self.speed_max * interval + 6.0 * (self.noise.position + last.spread);
        if rx * rx + ry * ry > reach * reach {
            self.outliers = self.outliers.saturating_add(1);
            // Fixes said to be exact are the truth: the model was wrong (a target faster than
            // v_max, another source), and the track restarts at once.
            if self.outliers > OUTLIERS_TO_RESTART || self.noise.position <= 0.0 {
                self.restart(fix);
                return Ok(());
            }
            return Err(Refused::Outlier);
        }
        self.outliers = 0;
        let r_theta = wrap_signed(theta - ptheta);
        let squared = interval * interval;
        let lateral = self.speed_max * self.turn_rate_max;
        let (alpha, beta) = gains(lateral * squared / self.noise.position);
        let turn_acceleration = 2.0 * self.turn_rate_max / REVERSAL_SECONDS;
        let (alpha_h, beta_h) = gains(turn_acceleration * squared / self.noise.heading);
        // Written so that alpha = 1 (no noise) gives the fix itself, bit for bit.
        let heading = if alpha_h >= 1.0 {
            wrap_signed(theta)
        } else {
            wrap_signed(ptheta + alpha_h * r_theta)
        };
        let (s, c) = sin_cos(ptheta);
        let along = rx * c + ry * s;
        self.estimate = Some(Estimate {
            x: x * alpha + px * (1.0 - alpha),
            y: y * alpha + py * (1.0 - alpha),
            theta: heading,
            // `max` and `min`, not `clamp`: `f32::clamp` asserts bounds it cannot see are
            // ordered, a panic path.
            speed: (last.speed + beta * along / interval)
                .max(0.0)
                .min(self.speed_max),
            turn_rate: (last.turn_rate + beta_h * r_theta / interval)
                .max(-self.turn_rate_max)
                .min(self.turn_rate_max),
            spread: self.noise.position * sqrt(alpha),
            heading_spread: self.noise.heading * sqrt(alpha_h),
            time_us: fix.time_us,
        });
        Ok(())
    }

    fn restart(&mut self, fix: &Fix) {
        let [x, y, theta] = fix.state;
        self.outliers = 0;
        self.estimate = Some(Estimate {
            x,
            y,
            theta: wrap_signed(theta),
            speed: self.speed_max,
            turn_rate: 0.0,
            spread: self.noise.position,
            heading_spread: self.noise.heading,
            time_us: fix.time_us,
        });
    }

    /// The state (x, y metres, heading radians) carried to `time_us` on the track's arc, and
    /// its uncertainty (metres): the filtered position noise, the filtered heading noise's
    /// move of the car's turning circles (times 1 / w_max), and half of what a turn reversed
    /// at the last fix moves the car since, v_max (v_max w_max) age^2 / 2. `None` without a fix, or
    /// where the last is more than `stale_us` old or later than `time_us` by more than that.
    pub fn at(&self, time_us: u32, stale_us: u32) -> Option<([f32; 3], f32)> {
        let last = self.estimate?;
        let age_us = time_us.wrapping_sub(last.time_us) as i32;
        if age_us.unsigned_abs() > stale_us {
            return None;
        }
        let age = seconds_between(last.time_us, time_us);
        let manoeuvre = 0.5 * self.speed_max * self.turn_rate_max * age * age;
        let circles = last.heading_spread * self.speed_max / self.turn_rate_max;
        Some((last.after(age), last.spread + circles + manoeuvre))
    }

    /// The track's speed (m/s) and turn rate (rad/s) at its last fix.
    pub fn rates(&self) -> Option<(f32, f32)> {
        self.estimate.map(|e| (e.speed, e.turn_rate))
    }
}
