//! The evader a vehicle of its own: a second SITL instance, flown by an evader of the adversary
//! suite through its own link, its GLOBAL_POSITION_INT (its own clock's `time_boot_ms`
//! included) the unit's target. How the strategy's turn becomes the vehicle's setpoint is the
//! vehicle's [`Steer`]: a rover's yaw rate and thrust, an aircraft's bank.

use std::time::Duration;

use mavlink::dialects::common::GLOBAL_POSITION_INT_DATA;
use twocars_sim::adversary::{Adversary, Opponent};
use twocars_sim::kinematics::distance;

use super::chase::{chase_params, pursue, Began, Outcome, Start};
use super::harness::{Harness, Injector, NoTarget, RoverFix};

/// How the evader's vehicle is told its strategy's command.
pub trait Steer {
    /// Sends the evader, on `h`'s link, the setpoint for curvature `w` (1/m, clockwise) at
    /// `speed` (m/s; 0 at the chase's end), the vehicle going at `measured` (m/s).
    fn steer(&mut self, h: &mut Harness, w: f64, speed: f64, measured: f64) -> Result<(), String>;
}

/// The evader's vehicle as the unit's target: on each of the pursuer's fixes the evader's link
/// is read, capture judged on both vehicles' fixes, and on each new evader fix its strategy's
/// command sent and the fix handed on.
struct VehicleTarget<'a> {
    evader: &'a mut Harness,
    steer: &'a mut dyn Steer,
    adversary: Adversary,
    start_ms: u32,
    eps: f64,
    t_max: f64,
    last_fix_ms: Option<u32>,
    captured_ms: Option<u32>,
    on: bool,
}

impl VehicleTarget<'_> {
    fn step(&mut self, pursuer: &RoverFix) -> Result<Option<GLOBAL_POSITION_INT_DATA>, String> {
        self.evader
            .pump_until(&mut NoTarget, Duration::from_millis(1), &mut |_| false)?;
        let Some(fix) = self.evader.rover else {
            return Ok(None);
        };
        let t = f64::from(pursuer.time_ms.wrapping_sub(self.start_ms)) / 1000.0;
        if distance(pursuer.state, fix.state) <= self.eps || t > self.t_max {
            if t <= self.t_max {
                self.captured_ms = Some(pursuer.time_ms);
            }
            self.on = false;
            self.steer.steer(self.evader, 0.0, 0.0, fix.speed)?;
            return Ok(None);
        }
        if self.last_fix_ms == Some(fix.time_ms) {
            return Ok(None);
        }
        self.last_fix_ms = Some(fix.time_ms);
        let (w, speed) = self.adversary.command(t, pursuer.state, fix.state);
        self.steer.steer(self.evader, w, speed, fix.speed)?;
        Ok(self.evader.position.clone())
    }
}

impl Injector for VehicleTarget<'_> {
    fn before(&mut self, pursuer: &RoverFix) -> Option<GLOBAL_POSITION_INT_DATA> {
        if !self.on {
            return None;
        }
        self.step(pursuer).unwrap_or_else(|e| {
            eprintln!("xtask: the evader's vehicle: {e}");
            self.on = false;
            None
        })
    }

    fn on(&self) -> bool {
        self.on
    }

    fn captured_ms(&self) -> Option<u32> {
        self.captured_ms
    }
}

/// How a chase against an evader vehicle is judged and run: the capture radius (m), the
/// strategy's seed, and the radio the target's fixes come through, if not exact.
#[derive(Clone, Copy, Debug)]
pub struct Terms {
    pub eps: f64,
    pub seed: u64,
    pub field: Option<super::field::Radio>,
}

/// Flies `start.evader` on the vehicle behind `evader` (steered by `steer`) against the
/// pursuer behind `h`, from where both are now, within `limits`; the outcome, and the
/// evader's peak and mean speed over the chase (m/s).
pub fn chase(
    h: &mut Harness,
    evader: &mut Harness,
    steer: &mut dyn Steer,
    start: Start,
    limits: [f64; 4],
    terms: Terms,
) -> Result<(Outcome, [f64; 2]), String> {
    let Terms { eps, seed, field } = terms;
    let pursuer = h.rover.ok_or("no fix from the pursuer")?;
    let evader0 = evader.rover.ok_or("no fix from the evader")?.state;
    let params = chase_params(limits, pursuer.state, evader0, eps, h.chase_limit_s);
    let adversary = Adversary::new(Opponent::Evader(start.evader), limits, params.dt, eps, seed)
        .ok_or("the adversary's limits are invalid")?;
    let fixes_before = evader.fixes.len();
    let target = VehicleTarget {
        evader: &mut *evader,
        steer,
        adversary,
        start_ms: pursuer.time_ms,
        eps,
        t_max: params.t_max,
        last_fix_ms: None,
        captured_ms: None,
        on: true,
    };
    let began = Began::new(start, pursuer, &params, seed);
    let outcome = pursue(h, target, &began, seed, field)?;
    let speeds: Vec<f64> = evader.fixes[fixes_before..]
        .iter()
        .map(|f| f.speed)
        .collect();
    let peak = speeds.iter().copied().fold(0.0, f64::max);
    let mean = speeds.iter().sum::<f64>() / speeds.len().max(1) as f64;
    Ok((outcome, [peak, mean]))
}
