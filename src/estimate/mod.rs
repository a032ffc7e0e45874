//! Both vehicles' states at the moment a decision acts, from fixes that come late, sparse and
//! noisy.
//!
//! The law wants both states now. A target's fix comes over a radio link 100-500 ms late, 1-10
//! times a second, with GPS noise, and sometimes not at all; the own vehicle answers a yaw-rate
//! setpoint with a lag. An [`Estimator`] holds a [`Track`] of each vehicle on the game's own car
//! model ([`track`]) and gives [`crate::Guidance::decide_estimated`] both states carried to the
//! decision's time plus the lead the own vehicle needs to act on it, with their uncertainty:
//!
//! - a target fix that carries its own time ([`Estimator::target_fix`]) is placed there; one
//!   that does not ([`Estimator::target_fix_received`]) is placed at its arrival less the
//!   known transport lag [`FieldSettings::target_lag`];
//! - a fix that carries the target's speed ([`Estimator::target_fix_with_speed`]) sets the
//!   track's speed; one that does not leaves it to the positions' differences;
//! - between fixes, and through dropouts up to [`FieldSettings::timeout`], the track coasts on
//!   its arc; beyond it the estimate is stale and no decision is made ([`Stale`]);
//! - the own state is carried [`FieldSettings::own_lead`] ahead, and the target with it, so
//!   that the turn the law picks is the one for where both will be when the vehicle turns.
//!
//! With no noise, no lag, no lead and a fix of each vehicle at every decision's time the states
//! are the fixes themselves and the decision is [`crate::Guidance::decide`]'s.
//!
//! Fixes and settings come in metres, seconds and radians anticlockwise from +x; clock times
//! in microseconds (wrapping `u32`). An `Estimator<S>` computes over the law's number type `S`
//! and in its units ([`Units`]), and gives states in them: on f32 and f64 metres as they came;
//! on fixed point units of r_p from an origin it keeps within 50 r_p of the own vehicle (a
//! fixed-point unit steers on fixes with no float arithmetic but a few conversions).

pub mod track;

pub use track::{Fix, FixNoise, Refused, Track};

use crate::error::Error;
use crate::law::geometry::{f32_envelope, Units};
use crate::num::convert::Reciprocal;
use crate::num::Scalar;

/// What an [`Estimator`] is told of the field: the fixes' noise and lag, the own vehicle's
/// response, and when an estimate is too old to steer by.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FieldSettings {
    /// One sigma of the target's fixes.
    pub target_noise: FixNoise,
    /// One sigma of the own vehicle's fixes.
    pub own_noise: FixNoise,
    /// The transport lag of a target fix that carries no time of its own, seconds, in
    /// [0, timeout).
    pub target_lag: f32,
    /// How long after a decision the own vehicle turns as told, seconds, in [0, timeout):
    /// its yaw-rate response (the time to 63 % of a step), or 0.
    pub own_lead: f32,
    /// The oldest fix a decision may be carried from, seconds, in (0, 1000].
    pub timeout: f32,
}

impl FieldSettings {
    /// Exact, instant fixes: no noise, no lag, no lead; stale after `timeout` seconds.
    pub const fn exact(timeout: f32) -> Self {
        FieldSettings {
            target_noise: FixNoise {
                position: 0.0,
                heading: 0.0,
            },
            own_noise: FixNoise {
                position: 0.0,
                heading: 0.0,
            },
            target_lag: 0.0,
            own_lead: 0.0,
            timeout,
        }
    }
}

/// Neither state can be carried to the decision's time: no fix yet, or the last one is older
/// than [`FieldSettings::timeout`]. The safe command applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Stale {
    /// The own vehicle's estimate.
    Own,
    /// The target's estimate.
    Target,
}

/// What the estimator has done, each count saturating.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct EstimatorCounters {
    /// Target fixes taken.
    pub target_fixes: u32,
    /// Fixes refused (either vehicle): non-finite, out of order, outliers.
    pub refused: u32,
    /// Decisions made with no new target fix since the decision before: the track coasted.
    pub coasted: u32,
    /// Decisions refused because an estimate was stale.
    pub stale: u32,
}

/// Both vehicles' states at a decision's time, and how far they may be off, in the law's units
/// and the estimator's frame ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimated<S = f32> {
    /// The own vehicle (the pursuer): x, y, heading radians.
    pub own: [S; 3],
    /// The target (the evader).
    pub target: [S; 3],
    /// The sum of both estimates' uncertainties ([`Track::at`]).
    pub uncertainty: S,
}

/// The own vehicle's and the target's tracks, and the settings they are carried by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimator<S = f32> {
    settings: FieldSettings,
    own: Track<S>,
    target: Track<S>,
    /// The law's units, and 1 / its length unit for fixed point's integer conversions.
    units: Units,
    per_metre: Reciprocal,
    /// The frame's origin in metres (normalised backends): the first fix, moved to the own
    /// fix where the own vehicle runs [`RECENTRE`] of the law's coordinate range from it.
    origin: Option<[f32; 2]>,
    lag_us: u32,
    lead_us: u32,
    stale_us: u32,
    /// The target's last fix time seen by the last decision.
    decided_on: Option<u32>,
    counters: EstimatorCounters,
}

/// The share of the law's coordinate range (`S::MAX_COORDINATE`, 200 r_p on fixed point) the
/// own vehicle runs from the frame's origin before the origin moves to it.
pub const RECENTRE: f32 = 0.25;

/// Seconds (finite, 0 to 1000) as microseconds.
fn micros(seconds: f32) -> u32 {
    (seconds * 1.0e6) as u32
}

impl Estimator<f32> {
    /// An estimator in f32, metres and seconds ([`Estimator::with_backend`]).
    ///
    /// # Errors
    /// As [`Estimator::with_backend`].
    pub fn new(limits: [f32; 4], settings: FieldSettings) -> Result<Self, Error> {
        Estimator::with_backend(limits, settings)
    }
}

impl<S: Scalar> Estimator<S> {
    /// An estimator over the law's number type `S`, in its units, for the pursuer's `v_pm` (m/s), `w_pm` (1/m) and the evader's `v_em`,
    /// `w_em`, told `settings`.
    ///
    /// # Errors
    /// [`Error::InvalidLimits`] unless the limits are finite and positive;
    /// [`Error::InvalidPeriod`] unless 0 < timeout <= 1000 s and the lag and the lead are in
    /// [0, timeout); [`Error::NonFiniteInput`] for a noise NaN, infinite or negative;
    /// [`Error::OutOfRange`] for limits or noise outside a normalised backend's envelope
    /// ([`Track::with_units`]).
    pub fn with_backend(limits: [f32; 4], settings: FieldSettings) -> Result<Self, Error> {
        let [v_pm, w_pm, v_em, w_em] = limits;
        let t = settings.timeout;
        if !(t.is_finite() && t > 0.0 && t <= 1.0e3) {
            return Err(Error::InvalidPeriod);
        }
        let within = |s: f32| s.is_finite() && s >= 0.0 && s < t;
        if !(within(settings.target_lag) && within(settings.own_lead)) {
            return Err(Error::InvalidPeriod);
        }
        let noise_ok = |n: FixNoise| {
            [n.position, n.heading]
                .iter()
                .all(|v| v.is_finite() && *v >= 0.0)
        };
        if !(noise_ok(settings.own_noise) && noise_ok(settings.target_noise)) {
            return Err(Error::NonFiniteInput);
        }
        let positive = |v: f32| v.is_finite() && v > 0.0;
        if !limits.iter().all(|&v| positive(v)) || !positive(v_pm * w_pm) {
            return Err(Error::InvalidLimits);
        }
        let units = Units::of::<S>(v_pm, w_pm);
        let track = |v, w, noise| Track::with_units(v, w, noise, units).ok_or(Error::OutOfRange);
        Ok(Estimator {
            settings,
            own: track(v_pm, w_pm, settings.own_noise)?,
            target: track(v_em, w_em, settings.target_noise)?,
            units,
            per_metre: if S::NORMALISED {
                Reciprocal::of(units.metres)
            } else {
                Reciprocal::ONE
            },
            origin: None,
            lag_us: micros(settings.target_lag),
            lead_us: micros(settings.own_lead),
            stale_us: micros(t),
            decided_on: None,
            counters: EstimatorCounters::default(),
        })
    }

    /// The settings it was made with.
    pub fn settings(&self) -> &FieldSettings {
        &self.settings
    }

    /// The law's units the estimator computes in.
    pub fn units(&self) -> Units {
        self.units
    }

    /// The frame's origin, metres: (0, 0) on SI backends; on a normalised backend where the
    /// states of [`Estimator::states`] are counted from (`None` before the first fix).
    pub fn origin(&self) -> Option<[f32; 2]> {
        if S::NORMALISED {
            self.origin
        } else {
            Some([0.0, 0.0])
        }
    }

    /// `fix` (metres) in the estimator's frame and units.
    fn in_frame(&mut self, fix: &Fix) -> Result<Fix<S>, Refused> {
        let [x, y, theta] = fix.state;
        f32_envelope(fix.state).map_err(|_| Refused::NonFinite)?;
        let time_us = fix.time_us;
        if !S::NORMALISED {
            let state = fix.state.map(S::from_f32);
            return Ok(Fix { state, time_us });
        }
        let [ox, oy] = *self.origin.get_or_insert([x, y]);
        // A radius of one unit: two points apart by more round to two offsets.
        let (dx, dy) =
            S::relative_position((ox, x), (oy, y), self.units.metres, &self.per_metre, 1.0)
                .map_err(|_| Refused::OutOfRange)?;
        if !track::in_range(dx, dy) {
            return Err(Refused::OutOfRange);
        }
        Ok(Fix {
            state: [dx, dy, S::reduced_heading(theta)],
            time_us,
        })
    }

    /// Takes the own vehicle's fix (metres).
    ///
    /// # Errors
    /// As [`Track::update`]; counted in [`EstimatorCounters::refused`].
    pub fn own_fix(&mut self, fix: &Fix) -> Result<(), Refused> {
        let taken = self.in_frame(fix).and_then(|mut local| {
            let [x, y, _] = local.state;
            let far = S::from_f32(RECENTRE * S::MAX_COORDINATE);
            if S::NORMALISED && (x.abs() > far || y.abs() > far) {
                self.own.shift_origin(x, y);
                self.target.shift_origin(x, y);
                self.origin = Some([fix.state[0], fix.state[1]]);
                local.state[0] = S::zero();
                local.state[1] = S::zero();
            }
            self.own.update(&local, self.stale_us)
        });
        self.count(taken)
    }

    /// Takes a target fix (metres) that carries the time the target was there.
    ///
    /// # Errors
    /// As [`Track::update`]; counted in [`EstimatorCounters::refused`].
    pub fn target_fix(&mut self, fix: &Fix) -> Result<(), Refused> {
        self.take_target(fix, None)
    }

    /// Takes a target fix (metres) that carries the time the target was there and its speed
    /// over ground, m/s: the length of GLOBAL_POSITION_INT's (vx, vy) or FOLLOW_TARGET's
    /// velocity. The track then carries the target at that speed ([`Track::update_with_speed`]),
    /// not at one differenced from sparse, noisy positions.
    ///
    /// # Errors
    /// As [`Track::update_with_speed`]; counted in [`EstimatorCounters::refused`].
    pub fn target_fix_with_speed(&mut self, fix: &Fix, speed: f32) -> Result<(), Refused> {
        self.take_target(fix, Some(speed))
    }

    fn take_target(&mut self, fix: &Fix, speed: Option<f32>) -> Result<(), Refused> {
        let stale_us = self.stale_us;
        let taken = self.in_frame(fix).and_then(|local| match speed {
            Some(speed) => self.target.update_with_speed(&local, speed, stale_us),
            None => self.target.update(&local, stale_us),
        });
        if taken.is_ok() {
            self.counters.target_fixes = self.counters.target_fixes.saturating_add(1);
        }
        self.count(taken)
    }

    /// Takes a target fix `state` (metres) that carries no time of its own, received at
    /// `received_us`: placed at that time less [`FieldSettings::target_lag`].
    ///
    /// # Errors
    /// As [`Estimator::target_fix`].
    pub fn target_fix_received(
        &mut self,
        state: [f32; 3],
        received_us: u32,
    ) -> Result<(), Refused> {
        let time_us = received_us.wrapping_sub(self.lag_us);
        self.target_fix(&Fix { state, time_us })
    }

    fn count(&mut self, taken: Result<(), Refused>) -> Result<(), Refused> {
        if taken.is_err() {
            self.counters.refused = self.counters.refused.saturating_add(1);
        }
        taken
    }

    /// Both states for a decision made at `now_us`, carried to the moment it acts
    /// (`now_us` plus [`FieldSettings::own_lead`]), in the law's units and the estimator's
    /// frame.
    ///
    /// # Errors
    /// [`Stale`] names the estimate that is missing or older than the timeout (counted).
    pub fn states(&mut self, now_us: u32) -> Result<Estimated<S>, Stale> {
        let acts = now_us.wrapping_add(self.lead_us);
        let carried = match (
            self.own.at(acts, self.stale_us),
            self.target.at(acts, self.stale_us),
        ) {
            (None, _) => Err(Stale::Own),
            (_, None) => Err(Stale::Target),
            (Some(own), Some(target)) => Ok((own, target)),
        };
        let ((own, own_spread), (target, target_spread)) = carried.inspect_err(|_| {
            self.counters.stale = self.counters.stale.saturating_add(1);
        })?;
        let last = self.target.last_fix_us();
        if last == self.decided_on {
            self.counters.coasted = self.counters.coasted.saturating_add(1);
        }
        self.decided_on = last;
        Ok(Estimated {
            own,
            target,
            uncertainty: own_spread + target_spread,
        })
    }

    /// The counters so far.
    pub fn counters(&self) -> EstimatorCounters {
        self.counters
    }

    /// The target's track.
    pub fn target(&self) -> &Track<S> {
        &self.target
    }

    /// The own vehicle's track.
    pub fn own(&self) -> &Track<S> {
        &self.own
    }

    /// Forgets the target's fixes (a new track of it).
    pub fn clear_target(&mut self) {
        self.target.clear();
        self.decided_on = None;
    }

    /// Forgets every fix (a new engagement); the counters stay.
    pub fn clear(&mut self) {
        self.own.clear();
        self.target.clear();
        self.origin = None;
        self.decided_on = None;
    }
}
