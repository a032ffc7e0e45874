//! The target's fixes as a radio brings them (`cargo xtask run --autopilot ardupilot --field`):
//! sampled every [`Radio::interval_s`], with GPS noise on position and heading, each put on the
//! unit's link [`Radio::lag_s`] after it was taken, stamped with the time it was taken
//! (docs/field.md). The velocity goes as the target's autopilot sent it.

use std::collections::VecDeque;

use mavlink::dialects::common::GLOBAL_POSITION_INT_DATA;
use twocars_sim::rng::Rng;

use super::harness::{Injector, RoverFix};

/// How a radio brings the target's fixes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radio {
    /// The fixes' transport lag, s.
    pub lag_s: f64,
    /// Time between fixes, s.
    pub interval_s: f64,
    /// One sigma of a fix's position, m.
    pub sigma_m: f64,
    /// One sigma of a fix's heading, rad.
    pub sigma_heading: f64,
}

impl Radio {
    /// Between rovers: 300 ms late, 5 a second, 1 m and 5 degrees.
    pub const ROVER: Radio = Radio {
        lag_s: 0.3,
        interval_s: 0.2,
        sigma_m: 1.0,
        sigma_heading: 0.087,
    };
    /// Between aircraft: 300 ms late, 2 a second, 1 m and 5 degrees.
    pub const AIRCRAFT: Radio = Radio {
        interval_s: 0.5,
        ..Radio::ROVER
    };

    /// The unit's parameters that tell it of this radio.
    pub fn unit_params(&self) -> [(&'static str, f64); 3] {
        [
            ("TC_TGT_LAG", self.lag_s),
            ("TC_TGT_SIG", self.sigma_m),
            ("TC_TGT_SIGH", self.sigma_heading),
        ]
    }

    /// A line saying what the radio does.
    pub fn line(&self) -> String {
        format!(
            "target fixes {} s late, every {} s, sigma {} m and {} rad",
            self.lag_s, self.interval_s, self.sigma_m, self.sigma_heading
        )
    }
}

/// Metres per degree of latitude (WGS-84 mean), for the noise on a fix.
const METRES_PER_DEGREE: f64 = 111_320.0;

/// A target whose fixes come late, sparse and noisy: `inner`'s fixes, sampled, noised and
/// delayed.
pub struct Delayed<T> {
    inner: T,
    radio: Radio,
    rng: Rng,
    last_sample_ms: Option<u32>,
    pending: VecDeque<(u32, GLOBAL_POSITION_INT_DATA)>,
}

impl<T> Delayed<T> {
    /// `inner`'s fixes through `radio`, the noise seeded by `seed`.
    pub fn new(inner: T, radio: Radio, seed: u64) -> Self {
        Delayed {
            inner,
            radio,
            rng: Rng::new(seed),
            last_sample_ms: None,
            pending: VecDeque::new(),
        }
    }

    /// The target underneath, to take its fixes as they are.
    pub fn inner_mut(&mut self) -> &mut T {
        &mut self.inner
    }

    fn noisy(&mut self, mut fix: GLOBAL_POSITION_INT_DATA) -> GLOBAL_POSITION_INT_DATA {
        let lat_deg = f64::from(fix.lat) * 1e-7;
        let north = self.radio.sigma_m * self.rng.normal();
        let east = self.radio.sigma_m * self.rng.normal();
        fix.lat += (north / METRES_PER_DEGREE * 1e7).round() as i32;
        let per_degree_east = METRES_PER_DEGREE * lat_deg.to_radians().cos();
        fix.lon += (east / per_degree_east * 1e7).round() as i32;
        let hdg =
            f64::from(fix.hdg) + self.radio.sigma_heading.to_degrees() * 100.0 * self.rng.normal();
        fix.hdg = hdg.rem_euclid(36_000.0) as u16;
        fix
    }
}

impl<T: Injector> Injector for Delayed<T> {
    fn before(&mut self, rover: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        // The target moves (and may be caught) at every rover fix, seen or not.
        let truth = self.inner.before(rover);
        if !self.inner.on() {
            self.pending.clear();
            return None;
        }
        let due = self.last_sample_ms.is_none_or(|last| {
            f64::from(rover.time_ms.wrapping_sub(last)) >= self.radio.interval_s * 1e3
        });
        if let (true, Some(truth)) = (due, truth) {
            self.last_sample_ms = Some(rover.time_ms);
            let noisy = self.noisy(truth);
            let arrives = rover.time_ms.wrapping_add((self.radio.lag_s * 1e3) as u32);
            self.pending.push_back((arrives, noisy));
        }
        let ready = self
            .pending
            .front()
            .is_some_and(|(at, _)| rover.time_ms.wrapping_sub(*at) as i32 >= 0);
        if ready {
            self.pending.pop_front().map(|(_, fix)| fix)
        } else {
            None
        }
    }

    fn on(&self) -> bool {
        self.inner.on()
    }

    fn captured_ms(&self) -> Option<u32> {
        self.inner.captured_ms()
    }
}
