//! One vehicle's track: its state carried from fix to fix on its own model and filtered.
//!
//! The model is the game's own car: speed s in [0, v_max] along the heading, turn rate omega
//! within +-v_max w_max, both held between fixes (a constant-turn arc). Each fix is compared
//! with the arc's prediction at the fix's time, and the residuals correct the state as a
//! steady-state Kalman filter of that model would (an alpha-beta filter per channel):
//!
//! - position x, y by alpha r and heading by alpha_h r_theta;
//! - speed by beta (r along the heading) / T and turn rate by beta_h r_theta / T,
//!   T being the time since the last fix; where the fix carries the car's speed
//!   ([`Track::update_with_speed`]), speed is that.
//!
//! The gains follow from the tracking index lambda = a T^2 / sigma (Kalata's steady state of
//! the piecewise-constant-acceleration model): a the largest acceleration the car has
//! (v_max^2 w_max across the track; of turn rate, a full turn reversed in
//! [`REVERSAL_SECONDS`]), sigma the fix's noise. Kalata's alpha, written as 4 r / (1 + r)^2
//! with r = sqrt(1 + 8 / lambda) so that no term grows with lambda (fixed point holds it),
//! with 8 / lambda at most [`MAX_NOISE_INDEX`]. alpha = 1 where the noise is 0: the estimate
//! is then the fix itself, and speed and turn rate its differences (beta = alpha^2 / (2 - alpha),
//! Benedict and Bordner's pairing, which takes a new turn in one interval without overshoot).
//! Why not a full Kalman filter: five states' covariance costs a few hundred products a fix on
//! a core without an FPU, and a car at its limits turns far more than a filter's random-walk
//! model says; the steady-state gains for the measured interval keep its response.
//!
//! Times are microseconds on the unit's clock as a wrapping `u32` (71.6 minutes a lap): two
//! times are compared by their difference, which is right while they are within half a lap.
//!
//! A track is written over the law's number types ([`Scalar`]) and computes in the law's units
//! ([`Units`]): metres and seconds on f32 and f64; on fixed point units of the pursuer's turning
//! radius r_p and of r_p / v_pm seconds, positions from an origin the [`super::Estimator`]
//! keeps near the own vehicle. Radians anticlockwise from +x throughout.

use crate::law::geometry::Units;
use crate::num::Scalar;

/// One position fix: where a vehicle was, and when.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Fix<S = f32> {
    /// x, y and heading (radians anticlockwise from +x): metres in the frame the law is given
    /// for an [`super::Estimator`]; the law's units in the track's frame for a [`Track`].
    pub state: [S; 3],
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
    /// Inside the f32 envelope but farther from the track's origin than the number type
    /// holds ([`Track::update`]).
    OutOfRange,
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

/// The largest noise index 8 / lambda = 8 sigma / (a T^2) the gains are formed from: beyond
/// it (noise far above what the car moves in an interval) alpha stays at 4 r / (1 + r)^2 =
/// 0.031 for r = sqrt(1 + MAX_NOISE_INDEX), so that fixed point holds every term.
pub const MAX_NOISE_INDEX: f32 = 16_383.0;

/// The age (law time units) beyond which [`Track::at`]'s manoeuvre term grows no more: far
/// beyond what any margin of the law reads, and inside fixed point's range.
const MANOEUVRE_AGE: f32 = 64.0;

/// Microseconds per second.
const US: f32 = 1.0e6;

/// How many sigmas of the turn rate's noise ([`Track::at`]) a track's turn rate is shrunk by
/// toward 0 where it carries the car: a car that runs straight is carried straight, not on
/// the arc its heading's noise draws, and a car that turns is carried at what of its turn
/// stands out of the noise.
pub const STEADY_SIGMAS: f32 = 2.0;

/// What a track holds at its last fix's time, in the law's units.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Estimate<S> {
    /// Position and heading (radians).
    x: S,
    y: S,
    theta: S,
    /// Speed along the heading, in [0, v_max].
    speed: S,
    /// Turn rate, radians per time unit, within +-v_max w_max.
    turn_rate: S,
    /// One sigma of the turn rate the heading's noise leaves in it, radians per time unit,
    /// at most 2 v_max w_max: within [`STEADY_SIGMAS`] of it the car is carried straight.
    turn_spread: S,
    /// One sigma of the position just after the last fix.
    spread: S,
    /// One sigma of the heading just after the last fix, radians.
    heading_spread: S,
    /// The last fix's time, microseconds.
    time_us: u32,
}

/// What a fix's correction takes from the interval since the last fix alone: the gains and
/// the spreads they leave. A link that sends at a steady rate repeats its interval, and these
/// are then taken from the last fix's, not formed again (on the Cortex-M0 most of a fix's
/// divisions and square roots).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Steady<S> {
    /// The interval they are for, microseconds.
    interval_us: u32,
    /// Position and speed gains.
    alpha: S,
    beta: S,
    /// Heading and turn-rate gains.
    alpha_h: S,
    beta_h: S,
    /// [`Estimate::spread`], [`Estimate::heading_spread`], [`Estimate::turn_spread`].
    spread: S,
    heading_spread: S,
    turn_spread: S,
}

/// A vehicle's filtered state between fixes ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Track<S = f32> {
    /// v_max, law units.
    speed_max: S,
    /// v_max w_max, radians per law time unit.
    turn_rate_max: S,
    /// One sigma of x and y, law units.
    position_noise: S,
    /// One sigma of the heading, radians.
    heading_noise: S,
    /// Law time units per second (1 on SI backends).
    per_second: f32,
    /// Law time units per microsecond (normalised backends; SI divides by 1e6).
    units_per_us: f32,
    /// Metres per second per law speed unit (1 on SI backends).
    speed_unit: f32,
    /// The heading channel's acceleration, 2 v_max w_max / [`REVERSAL_SECONDS`], radians per
    /// law time unit squared.
    heading_acceleration: S,
    estimate: Option<Estimate<S>>,
    /// The last fix's interval terms.
    steady: Option<Steady<S>>,
    outliers: u8,
}

/// The steady-state gains (alpha, beta) of a channel whose car accelerates by at most `a`,
/// for fixes `t` apart with noise `sigma` ([module docs](self)); (1, 1) without noise.
fn gains<S: Scalar>(a: S, t: S, sigma: S) -> (S, S) {
    let one = S::one();
    if sigma <= S::zero() {
        return (one, one);
    }
    let most = S::from_f32(MAX_NOISE_INDEX);
    // Beyond 256 time units the noise index is far past its bound for any noise a track takes.
    let t = t.min(S::from_f32(256.0));
    let eight_sigma = S::from_f32(8.0) * sigma;
    // q = 8 sigma / (a t) / t, each quotient checked against its bound before it is formed.
    let at = a * t;
    let q = if at <= eight_sigma / S::from_f32(65_536.0) {
        most
    } else {
        let q = eight_sigma / at;
        if q / most >= t {
            most
        } else {
            q / t
        }
    };
    let r = (one + q).sqrt();
    let r1 = one + r;
    let alpha = (S::from_f32(4.0) * r / r1 / r1).min(one);
    (alpha, alpha * alpha / (S::from_f32(2.0) - alpha))
}

/// `delta / t` clamped to +-`bound` (`t`, `bound` > 0), without forming a quotient beyond it.
fn rate_within<S: Scalar>(delta: S, t: S, bound: S) -> S {
    if delta.abs() >= bound * t {
        if delta < S::zero() {
            -bound
        } else {
            bound
        }
    } else {
        delta / t
    }
}

/// Whether the residual (`rx`, `ry`) is longer than `reach` (>= 0), without squaring a length
/// fixed point cannot hold.
fn beyond<S: Scalar>(rx: S, ry: S, reach: S) -> bool {
    let (ax, ay) = (rx.abs(), ry.abs());
    if ax > reach || ay > reach {
        return true;
    }
    if !S::NORMALISED {
        return rx * rx + ry * ry > reach * reach;
    }
    if reach <= S::zero() {
        return ax > S::zero() || ay > S::zero();
    }
    let (ux, uy) = (rx / reach, ry / reach);
    ux * ux + uy * uy > S::one()
}

/// The point `run` along an arc turning by `turned` radians from heading `theta`: the
/// chord run sin(h) / h at theta + h, h = turned / 2. Below |h| = 1e-3 (0.5 on a normalised
/// backend, whose sine is within 2e-4 absolute: 4e-4 of sin(h) / h there) by its series
/// 1 - h^2 / 6 + h^4 / 120, within 3e-6.
fn along_arc<S: Scalar>(theta: S, run: S, turned: S) -> (S, S) {
    let half = S::from_f32(0.5) * turned;
    let series_below = S::from_f32(if S::NORMALISED { 0.5 } else { 1.0e-3 });
    let chord = if half.abs() > series_below {
        run * half.sin_cos().0 / half
    } else {
        let h2 = half * half;
        run * (S::one() - h2 / S::from_f32(6.0) + h2 * h2 / S::from_f32(120.0))
    };
    let (s, c) = (theta + half).sin_cos();
    (chord * c, chord * s)
}

impl<S: Scalar> Estimate<S> {
    /// Carried `t` (law time units) ahead on its arc.
    fn after(&self, t: S) -> [S; 3] {
        self.after_turning(self.turn_rate, t)
    }

    /// The turn rate a car is carried at: the estimate's where it stands out of its noise by
    /// more than [`STEADY_SIGMAS`], else 0 (a steady car).
    fn steady_turn_rate(&self) -> S {
        let band = S::from_f32(STEADY_SIGMAS) * self.turn_spread;
        if self.turn_rate.abs() > band {
            self.turn_rate
        } else {
            S::zero()
        }
    }

    /// Carried `t` ahead on the arc of `turn_rate`.
    fn after_turning(&self, turn_rate: S, t: S) -> [S; 3] {
        let turned = turn_rate * t;
        let (dx, dy) = along_arc(self.theta, self.speed * t, turned);
        [
            self.x + dx,
            self.y + dy,
            (self.theta + turned).wrap_signed(),
        ]
    }
}

/// The largest |x|, |y| a track holds, law units: the f32 envelope on SI backends; on a
/// normalised backend 32 times the law's own (6,400 r_p on fixed point), which the origin
/// kept near the own vehicle leaves room for.
fn coordinate_range<S: Scalar>() -> S {
    S::from_f32(if S::NORMALISED {
        32.0 * S::MAX_COORDINATE
    } else {
        S::MAX_COORDINATE
    })
}

impl Track<f32> {
    /// A track in metres and seconds ([`Track::with_units`] in [`Units::SI`]).
    pub fn new(v_max: f32, w_max: f32, noise: FixNoise) -> Option<Self> {
        Track::with_units(v_max, w_max, noise, Units::SI)
    }
}

/// Whether a position is within [`coordinate_range`].
pub(crate) fn in_range<S: Scalar>(x: S, y: S) -> bool {
    let range = coordinate_range::<S>();
    x.abs() <= range && y.abs() <= range
}

impl<S: Scalar> Track<S> {
    /// A track of a car of speed `v_max` (m/s) and curvature `w_max` (1/m) whose fixes carry
    /// `noise`, computing in `units`; `None` unless both limits are finite and positive and the
    /// noise finite and not negative, and (normalised backends) the car's speed and turn rate
    /// and the noise inside the backend's envelope (fixed point: v_max <= v_pm, v_max w_max
    /// between 1/256 and 1 of the pursuer's turn rate, which is 1/64 to 32 rad/s, sigma within
    /// 200 r_p and 4 rad).
    pub fn with_units(v_max: f32, w_max: f32, noise: FixNoise, units: Units) -> Option<Self> {
        let per_second = units.metres_per_second / units.metres;
        let speed = v_max / units.metres_per_second;
        let turn_rate = speed * (w_max * units.metres);
        let position = noise.position / units.metres;
        let limits_ok =
            speed.is_finite() && speed > 0.0 && turn_rate.is_finite() && turn_rate > 0.0;
        let noise_ok = [position, noise.heading]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0);
        let envelope = !S::NORMALISED
            || (speed <= 1.0
                && (1.0 / 256.0..=1.0).contains(&turn_rate)
                && (1.0 / 64.0..=32.0).contains(&per_second)
                && position <= S::MAX_COORDINATE
                && noise.heading <= 4.0);
        (limits_ok && noise_ok && envelope).then(|| {
            let mut track = Track {
                speed_max: S::from_f32(speed),
                turn_rate_max: if S::NORMALISED {
                    S::from_f32(turn_rate)
                } else {
                    S::from_f32(v_max) * S::from_f32(w_max)
                },
                position_noise: S::from_f32(position),
                heading_noise: S::from_f32(noise.heading),
                per_second,
                units_per_us: per_second / US,
                speed_unit: units.metres_per_second,
                heading_acceleration: S::zero(),
                estimate: None,
                steady: None,
                outliers: 0,
            };
            let reversal = S::from_f32(REVERSAL_SECONDS * per_second);
            track.heading_acceleration = S::from_f32(2.0) * track.turn_rate_max / reversal;
            track
        })
    }

    /// Law time units from `from` to `to` (microseconds, wrapping).
    fn between(&self, from: u32, to: u32) -> S {
        let us = to.wrapping_sub(from) as i32 as f32;
        if S::NORMALISED {
            S::from_f32(us * self.units_per_us)
        } else {
            S::from_f32(us / US)
        }
    }

    /// Forgets every fix.
    pub fn clear(&mut self) {
        self.estimate = None;
        self.outliers = 0;
    }

    /// Moves the track's origin by (`dx`, `dy`) law units (each within the track's range):
    /// the estimate's position less them; a track left beyond its range is forgotten.
    pub fn shift_origin(&mut self, dx: S, dy: S) {
        if let Some(e) = self.estimate.as_mut() {
            e.x = e.x - dx;
            e.y = e.y - dy;
            if !in_range(e.x, e.y) {
                self.clear();
            }
        }
    }

    /// The last fix's time, microseconds, if the track has one.
    pub fn last_fix_us(&self) -> Option<u32> {
        self.estimate.map(|e| e.time_us)
    }

    /// Takes a fix in the law's units: the first one, or one after `stale_us` microseconds
    /// without, restarts the track at it (at full speed, not turning).
    ///
    /// # Errors
    /// [`Refused`] says why the fix was not taken; the track is then unchanged but for its
    /// count of outliers in a row.
    pub fn update(&mut self, fix: &Fix<S>, stale_us: u32) -> Result<(), Refused> {
        self.take(fix, None, stale_us)
    }

    /// Takes a fix that carries the car's speed over ground, metres per second (finite, not
    /// negative; above v_max taken as v_max): the track's speed is then that speed, not one
    /// differenced from positions. A GPS's Doppler speed is good to a few cm/s where a
    /// speed from two fixes a fifth of a turn apart carries their noise twice over, so it
    /// is taken whole, not weighed.
    ///
    /// # Errors
    /// As [`Track::update`]; a speed NaN, infinite or negative is [`Refused::NonFinite`].
    pub fn update_with_speed(
        &mut self,
        fix: &Fix<S>,
        speed: f32,
        stale_us: u32,
    ) -> Result<(), Refused> {
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(Refused::NonFinite);
        }
        self.take(fix, Some(speed), stale_us)
    }

    /// The speed `metres_per_second` (finite, not negative) in law units, within v_max.
    fn measured_speed(&self, metres_per_second: f32) -> S {
        S::from_f32(metres_per_second / self.speed_unit).min(self.speed_max)
    }

    fn take(&mut self, fix: &Fix<S>, speed: Option<f32>, stale_us: u32) -> Result<(), Refused> {
        let speed = speed.map(|s| self.measured_speed(s));
        let [x, y, theta] = fix.state;
        if !(x.is_number() && y.is_number() && theta.is_number()) {
            return Err(Refused::NonFinite);
        }
        let heading_range = S::from_f32(if S::NORMALISED { 4.0 } else { S::MAX_HEADING });
        if !in_range(x, y) || theta.abs() > heading_range {
            return Err(if S::NORMALISED {
                Refused::OutOfRange
            } else {
                Refused::NonFinite
            });
        }
        let Some(last) = self.estimate else {
            self.restart(fix, speed);
            return Ok(());
        };
        let elapsed = fix.time_us.wrapping_sub(last.time_us) as i32;
        if elapsed <= 0 {
            return Err(Refused::OutOfOrder);
        }
        if elapsed as u32 > stale_us {
            self.restart(fix, speed);
            return Ok(());
        }
        let interval = self.between(last.time_us, fix.time_us);
        let [px, py, ptheta] = last.after(interval);
        let (rx, ry) = (x - px, y - py);
        let two = S::from_f32(2.0);
        let reach = two * self.speed_max * interval
            + S::from_f32(6.0) * (self.position_noise + last.spread);
        if beyond(rx, ry, reach) {
            self.outliers = self.outliers.saturating_add(1);
            // Fixes said to be exact are the truth: the model was wrong (a target faster than
            // v_max, another source), and the track restarts at once.
            if self.outliers > OUTLIERS_TO_RESTART || self.position_noise <= S::zero() {
                self.restart(fix, speed);
                return Ok(());
            }
            return Err(Refused::Outlier);
        }
        self.outliers = 0;
        let steady = self.steady(elapsed as u32, interval);
        let mut corrected = self.corrected(&last, fix, [px, py, ptheta], interval, &steady);
        if let Some(speed) = speed {
            corrected.speed = speed;
        }
        self.estimate = Some(corrected);
        Ok(())
    }

    /// The interval terms for fixes `interval_us` (`interval` law units) apart: the last
    /// fix's where it was the same interval.
    fn steady(&mut self, interval_us: u32, interval: S) -> Steady<S> {
        if let Some(steady) = self.steady.filter(|s| s.interval_us == interval_us) {
            return steady;
        }
        let lateral = self.speed_max * self.turn_rate_max;
        let (alpha, beta) = gains(lateral, interval, self.position_noise);
        let (alpha_h, beta_h) = gains(self.heading_acceleration, interval, self.heading_noise);
        let steady = Steady {
            interval_us,
            alpha,
            beta,
            alpha_h,
            beta_h,
            spread: self.position_noise * alpha.sqrt(),
            heading_spread: self.heading_noise * alpha_h.sqrt(),
            turn_spread: self.turn_spread(alpha_h, beta_h, interval),
        };
        self.steady = Some(steady);
        steady
    }

    /// `last` corrected by `fix` against its prediction `[px, py, ptheta]` `interval` on,
    /// with that interval's `steady` terms.
    fn corrected(
        &self,
        last: &Estimate<S>,
        fix: &Fix<S>,
        predicted: [S; 3],
        interval: S,
        steady: &Steady<S>,
    ) -> Estimate<S> {
        let [x, y, theta] = fix.state;
        let [px, py, ptheta] = predicted;
        let (rx, ry) = (x - px, y - py);
        let r_theta = (theta - ptheta).wrap_signed();
        let one = S::one();
        let Steady {
            alpha,
            beta,
            alpha_h,
            beta_h,
            ..
        } = *steady;
        // Written so that alpha = 1 (no noise) gives the fix itself, bit for bit.
        let heading = if alpha_h >= one {
            theta.wrap_signed()
        } else {
            (ptheta + alpha_h * r_theta).wrap_signed()
        };
        let (s, c) = ptheta.sin_cos();
        let along = rx * c + ry * s;
        let speed =
            last.speed + rate_within(beta * along, interval, self.speed_max + self.speed_max);
        let turn_rate = last.turn_rate
            + rate_within(
                beta_h * r_theta,
                interval,
                self.turn_rate_max + self.turn_rate_max,
            );
        Estimate {
            x: x * alpha + px * (one - alpha),
            y: y * alpha + py * (one - alpha),
            theta: heading,
            speed: speed.max(S::zero()).min(self.speed_max),
            turn_rate: turn_rate.max(-self.turn_rate_max).min(self.turn_rate_max),
            turn_spread: steady.turn_spread,
            spread: steady.spread,
            heading_spread: steady.heading_spread,
            time_us: fix.time_us,
        }
    }

    /// One sigma of the turn rate the heading's noise leaves after a fix `interval` after the
    /// last, filtered by (`alpha`, `beta`): sigma_h sqrt(2 beta^2 / (alpha (4 - 2 alpha -
    /// beta))) / interval, the alpha-beta filter's steady-state rate noise (Kalata), at most
    /// 2 v_max w_max. 0 without noise, so that exact fixes are carried as they were.
    fn turn_spread(&self, alpha: S, beta: S, interval: S) -> S {
        if self.heading_noise <= S::zero() {
            return S::zero();
        }
        let two = S::from_f32(2.0);
        // 4 - 2 alpha - beta >= 1 - beta >= 0 for alpha, beta <= 1 (Benedict-Bordner).
        let den = alpha * (S::from_f32(4.0) - two * alpha - beta);
        let bound = two * self.turn_rate_max;
        if den <= S::zero() {
            return bound;
        }
        let ratio = (two * beta * beta / den).sqrt();
        rate_within(self.heading_noise * ratio, interval, bound)
    }

    /// Restarts at `fix`, at its `speed` (law units) or v_max, not turning.
    fn restart(&mut self, fix: &Fix<S>, speed: Option<S>) {
        let [x, y, theta] = fix.state;
        self.outliers = 0;
        self.estimate = Some(Estimate {
            x,
            y,
            theta: theta.wrap_signed(),
            speed: speed.unwrap_or(self.speed_max),
            turn_rate: S::zero(),
            turn_spread: S::zero(),
            spread: self.position_noise,
            heading_spread: self.heading_noise,
            time_us: fix.time_us,
        });
    }

    /// The state (position and heading in the law's units) carried to `time_us` on the track's
    /// arc, and its uncertainty (law units): the filtered position noise, the filtered heading
    /// noise's move of the car's turning circles (times 1 / w_max), and half of what a turn
    /// reversed at the last fix moves the car since, v_max (v_max w_max) age^2 / 2 (the age
    /// at most 64 time units). `None` without a fix, where the last is more than `stale_us`
    /// old or later than `time_us` by more than that, or where it carries the car beyond the
    /// track's range (a normalised backend's: 6,400 r_p from the origin on fixed point).
    pub fn at(&self, time_us: u32, stale_us: u32) -> Option<([S; 3], S)> {
        let last = self.estimate?;
        let age_us = time_us.wrapping_sub(last.time_us) as i32;
        if age_us.unsigned_abs() > stale_us {
            return None;
        }
        let age = self.between(last.time_us, time_us);
        let held = age.abs().min(S::from_f32(MANOEUVRE_AGE));
        let manoeuvre = S::from_f32(0.5) * self.speed_max * self.turn_rate_max * held * held;
        let circles = last.heading_spread * self.speed_max / self.turn_rate_max;
        let carried = last.after_turning(last.steady_turn_rate(), age);
        if !in_range(carried[0], carried[1]) {
            return None;
        }
        Some((carried, last.spread + circles + manoeuvre))
    }

    /// The track's speed (law units) and turn rate (radians per law time unit) at its last fix.
    pub fn rates(&self) -> Option<(S, S)> {
        self.estimate.map(|e| (e.speed, e.turn_rate))
    }
}
