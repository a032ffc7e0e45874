//! The endpoint's estimator ([`crate::estimate`]): both vehicles' fixes on the autopilot's
//! clock, carried to the moment a setpoint acts.
//!
//! The own GLOBAL_POSITION_INT's `time_boot_ms` is the clock. A target fix carries the time on
//! its own sender's clock (`time_boot_ms`, FOLLOW_TARGET's `timestamp`): the fixes' spacing is
//! exact there, but the two clocks' offset is unknown. The offset is taken as the least of
//! (the autopilot's clock when the fix arrives - the fix's time) over the track, the fix that
//! came soonest; TC_TGT_LAG is that soonest fix's transport lag, so that a fix's time is
//! its own time + offset - TC_TGT_LAG. The autopilot's clock when a target fix arrived is
//! read off the next own fix: its time less our clock from the one arrival to the other,
//! converted at the rate the two clocks run at ([`ClockRate`]; an autopilot streams its own
//! state far oftener than a radio brings the target's). A new track forgets its offset.

use super::params::{index, Params};
use crate::estimate::{Estimated, Estimator, FieldSettings, Fix, FixNoise, Refused, Stale};

/// Microseconds per millisecond.
const US_PER_MS: u32 = 1000;

/// The estimator and the target's clock offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Tracking {
    estimator: Estimator,
    /// Least (autopilot clock at arrival - the fix's own time) on this track, ms.
    offset_ms: Option<i32>,
    /// TC_TGT_LAG, ms.
    lag_ms: u32,
}

impl Tracking {
    /// The estimator the parameters describe, for limits (v_pm, w_pm, v_em, w_em); `None`
    /// where they make none (never after [`Params::set`], which keeps them valid together).
    pub fn new(params: &Params) -> Option<Self> {
        let get = |i| params.get(i).unwrap_or(0.0);
        let settings = FieldSettings {
            target_noise: FixNoise {
                position: get(index::TGT_SIG),
                heading: get(index::TGT_SIGH),
            },
            own_lead: get(index::LEAD),
            // The lag enters through the fixes' times (module docs).
            target_lag: 0.0,
            ..FieldSettings::exact(get(index::TIMEOUT))
        };
        let limits = [index::V_PM, index::W_PM, index::V_EM, index::W_EM].map(get);
        Some(Tracking {
            estimator: Estimator::new(limits, settings).ok()?,
            offset_ms: None,
            lag_ms: (get(index::TGT_LAG) * 1000.0) as u32,
        })
    }

    /// The own fix (x north, y east, metres; heading clockwise from north, rad) at
    /// `sent_ms` on the autopilot's clock.
    pub fn own(&mut self, state: [f32; 3], sent_ms: u32) -> Result<(), Refused> {
        let time_us = sent_ms.wrapping_mul(US_PER_MS);
        self.estimator.own_fix(&Fix { state, time_us })
    }

    /// A target fix, with its speed over ground (m/s) where the message carries one, stamped
    /// `sent_ms` on its sender's clock, arriving at `arrival_ms` on the autopilot's clock;
    /// `fresh_track` starts a new track at it (the last fix is stale, or the target jumped and
    /// a second fix agreed).
    pub fn target(
        &mut self,
        state: [f32; 3],
        speed: Option<f32>,
        sent_ms: u32,
        arrival_ms: u32,
        fresh_track: bool,
    ) -> Result<(), Refused> {
        if fresh_track {
            self.offset_ms = None;
            self.estimator.clear_target();
        }
        let offset = arrival_ms.wrapping_sub(sent_ms) as i32;
        let least = self.offset_ms.map_or(offset, |o| o.min(offset));
        self.offset_ms = Some(least);
        let time_ms = sent_ms.wrapping_add(least as u32).wrapping_sub(self.lag_ms);
        let time_us = time_ms.wrapping_mul(US_PER_MS);
        let fix = Fix { state, time_us };
        match speed {
            Some(speed) => self.estimator.target_fix_with_speed(&fix, speed),
            None => self.estimator.target_fix(&fix),
        }
    }

    /// Both states for the setpoint of the own fix at `own_ms` on the autopilot's clock.
    pub fn states(&mut self, own_ms: u32) -> Result<Estimated, Stale> {
        self.estimator.states(own_ms.wrapping_mul(US_PER_MS))
    }

    /// Whether the target has a track.
    pub fn has_target(&self) -> bool {
        self.estimator.target().last_fix_us().is_some()
    }

    /// Forgets every fix (the local plane moved).
    pub fn clear(&mut self) {
        self.estimator.clear();
        self.offset_ms = None;
    }

    /// The estimator's counters.
    pub fn counters(&self) -> crate::estimate::EstimatorCounters {
        self.estimator.counters()
    }
}

/// How fast the autopilot's clock runs against ours, from the own fixes: the autopilot's
/// milliseconds per one of ours, over at least [`ClockRate::BASELINE_MS`] of our clock (the
/// first measurement taken as it is, each later one averaged with the last). A gap measured on
/// our clock becomes the autopilot's through it: 1 on hardware; in a harness that steps the
/// autopilot's clock, its pace; on a board whose clock runs fast, the correction. Until the
/// first measurement a gap counts as nothing: a target fix is placed at the next own fix's
/// time, at most one own period late, and its track restarts once the rate is known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct ClockRate {
    anchor: Option<(u32, u32)>,
    rate: Option<f32>,
}

impl ClockRate {
    /// Our clock's milliseconds a measurement spans at the least.
    pub const BASELINE_MS: u32 = 200;
    /// The rates believed, autopilot ms per ours.
    const RANGE: (f32, f32) = (0.01, 100.0);

    /// No measurement yet.
    pub const fn new() -> Self {
        ClockRate {
            anchor: None,
            rate: None,
        }
    }

    /// An own fix `sent_ms` on the autopilot's clock, arrived at `arrived_ms` on ours;
    /// `stale`: the last one is older than the timeout (a new baseline). Whether this was the
    /// first measurement: the target's fixes placed before it were placed without the gap.
    pub fn own_fix(&mut self, sent_ms: u32, arrived_ms: u32, stale: bool) -> bool {
        let Some((sent0, arrived0)) = self.anchor.filter(|_| !stale) else {
            self.anchor = Some((sent_ms, arrived_ms));
            return false;
        };
        let ours = arrived_ms.wrapping_sub(arrived0);
        if ours < Self::BASELINE_MS {
            return false;
        }
        self.anchor = Some((sent_ms, arrived_ms));
        let rate = sent_ms.wrapping_sub(sent0) as f32 / ours as f32;
        if !(rate >= Self::RANGE.0 && rate <= Self::RANGE.1) {
            return false;
        }
        let first = self.rate.is_none();
        self.rate = Some(self.rate.map_or(rate, |last| 0.5 * (last + rate)));
        first
    }

    /// `ours_ms` of our clock in the autopilot's milliseconds (0 before the first
    /// measurement).
    pub fn theirs(&self, ours_ms: u32) -> u32 {
        (ours_ms as f32 * self.rate.unwrap_or(0.0)) as u32
    }
}
