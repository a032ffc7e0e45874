//! Whether the own vehicle flies as the unit is told: the law's promise (capture, its time)
//! assumes the pursuer at TC_V_PM, turning at most v_pm w_pm. An autopilot left at its own
//! speed setting (ArduPilot Rover's WP_SPEED) runs faster or slower than that and nothing in
//! the setpoints shows it, so the endpoint measures each second of own fixes under setpoints
//! and says when they depart by more than [`DEPARTURE_SHARE`].

use crate::num::Scalar;

/// The share of TC_V_PM (and of v_pm w_pm) the own vehicle's mean over a window may depart by.
pub const DEPARTURE_SHARE: f32 = 0.1;

/// A window of own fixes, ms of the autopilot's clock.
pub const WINDOW_MS: u32 = 1000;

/// A gap between own fixes past which a window starts again, ms.
const GAP_MS: u32 = 500;

/// How the own vehicle departs from what the unit is told.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Departure {
    /// Its mean speed is above TC_V_PM by more than the share.
    Faster,
    /// Its mean speed is below TC_V_PM by more than the share.
    Slower,
    /// Its mean turn rate is above v_pm w_pm by more than the share.
    TurnsFaster,
}

impl Departure {
    /// The STATUSTEXT's words (at most 50 characters).
    pub fn text(self) -> &'static str {
        match self {
            Departure::Faster => "TC: own speed over TC_V_PM by >10%",
            Departure::Slower => "TC: own speed under TC_V_PM by >10%",
            Departure::TurnsFaster => "TC: own turn rate over v_pm*w_pm by >10%",
        }
    }

    /// Windows in a row that must depart this way before it is said: three for a vehicle
    /// slower than told (a rover at a chase's start takes two seconds or more to reach
    /// speed), two otherwise.
    fn windows(self) -> u8 {
        match self {
            Departure::Slower => 3,
            _ => 2,
        }
    }
}

/// One window's sums.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    start_ms: u32,
    last_ms: u32,
    last_heading: f32,
    /// Metres run.
    run: f32,
    /// Radians turned, either way.
    turned: f32,
}

/// The own vehicle's speed and turn rate over windows of [`WINDOW_MS`] under setpoints.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct DepartureWatch {
    window: Option<Window>,
    /// The last windows' departure and how many in a row.
    streak: Option<(Departure, u8)>,
    /// Whether the streak was said.
    said: bool,
}

impl DepartureWatch {
    /// Forgets the windows (no setpoints: the vehicle is not the unit's).
    pub fn reset(&mut self) {
        *self = DepartureWatch::default();
    }

    /// An own fix under setpoints: its time (ms, the autopilot's clock), speed (m/s) and
    /// heading (rad), against the pursuer's `v_pm` (m/s) and `turn_rate` v_pm w_pm (rad/s).
    /// The departure to say, once, where enough windows in a row depart the same way.
    pub fn own_fix(
        &mut self,
        time_ms: u32,
        speed: f32,
        heading: f32,
        v_pm: f32,
        turn_rate: f32,
    ) -> Option<Departure> {
        let fresh = Window {
            start_ms: time_ms,
            last_ms: time_ms,
            last_heading: heading,
            run: 0.0,
            turned: 0.0,
        };
        let Some(mut w) = self.window.filter(|w| {
            let gap = time_ms.wrapping_sub(w.last_ms);
            gap > 0 && gap <= GAP_MS && speed.is_finite() && heading.is_finite()
        }) else {
            self.window = Some(fresh);
            return None;
        };
        let step = time_ms.wrapping_sub(w.last_ms) as f32 / 1000.0;
        w.run += speed * step;
        w.turned += (heading - w.last_heading).wrap_signed().abs();
        w.last_ms = time_ms;
        w.last_heading = heading;
        let elapsed = time_ms.wrapping_sub(w.start_ms);
        if elapsed < WINDOW_MS {
            self.window = Some(w);
            return None;
        }
        self.window = Some(fresh);
        let seconds = elapsed as f32 / 1000.0;
        self.judge(classify(
            w.run / seconds,
            w.turned / seconds,
            v_pm,
            turn_rate,
        ))
    }

    /// Counts a window's `departure` into the streak; the departure to say.
    fn judge(&mut self, departure: Option<Departure>) -> Option<Departure> {
        let Some(d) = departure else {
            self.streak = None;
            self.said = false;
            return None;
        };
        let count = match self.streak {
            Some((last, n)) if last == d => n.saturating_add(1),
            _ => {
                self.said = false;
                1
            }
        };
        self.streak = Some((d, count));
        if count >= d.windows() && !self.said {
            self.said = true;
            return Some(d);
        }
        None
    }
}

/// A window's departure from its mean `speed` (m/s) and `turn` rate (rad/s).
fn classify(speed: f32, turn: f32, v_pm: f32, turn_rate: f32) -> Option<Departure> {
    if speed > (1.0 + DEPARTURE_SHARE) * v_pm {
        Some(Departure::Faster)
    } else if speed < (1.0 - DEPARTURE_SHARE) * v_pm {
        Some(Departure::Slower)
    } else if turn > (1.0 + DEPARTURE_SHARE) * turn_rate {
        Some(Departure::TurnsFaster)
    } else {
        None
    }
}
