//! The estimator's bench on the target: [`crate::ESTIMATE_FIXES`] target fixes of
//! [`crate::estimate_fix`] taken, and after each a decision's states carried 100 ms on, one
//! line per fix: `estimate <i> <fix ticks> <states ticks> <empty ticks> <stack> <x> <y> <u>`
//! (the states' target x, y and uncertainty in the backend's units, as f32 bits), over f32
//! (`estimate`) or fixed point (`estimate_fixed`).

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::estimate::{Estimated, Estimator, FieldSettings, Fix, FixNoise};
use twocars::Scalar;

use super::probe;
use crate::{estimate_fix, ESTIMATE_FIXES, ESTIMATE_INTERVAL_US, ESTIMATE_NOISE, LIMITS};

/// Runs the fixes and decisions over `S`, printing one `estimate` line each, and exits.
pub fn run<S: Scalar>() -> ! {
    probe::start();
    let [position, heading] = ESTIMATE_NOISE;
    let settings = FieldSettings {
        target_noise: FixNoise { position, heading },
        ..FieldSettings::exact(1.0)
    };
    let Ok(mut estimator) = Estimator::<S>::with_backend(LIMITS, settings) else {
        hprintln!("the bench estimator does not set up");
        probe::fail();
    };
    for i in 0..ESTIMATE_FIXES {
        let time_us = i * ESTIMATE_INTERVAL_US;
        let own = Fix {
            state: [0.0, 0.0, 0.0],
            time_us,
        };
        let _ = estimator.own_fix(&own);
        let target = Fix {
            state: estimate_fix(i),
            time_us,
        };
        let start = probe::now();
        let empty = take_nothing(black_box(&mut estimator), black_box(&target));
        let empty_ticks = probe::ticks_since(start);
        black_box(empty);
        let bottom = probe::paint();
        let start = probe::now();
        let taken = take(black_box(&mut estimator), black_box(&target));
        let fix_ticks = probe::ticks_since(start);
        let start = probe::now();
        let states = carry(black_box(&mut estimator), black_box(time_us + 100_000));
        let states_ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        let Some(s) = states.filter(|_| taken) else {
            hprintln!("estimate {} refused", i);
            probe::fail();
        };
        hprintln!(
            "estimate {} {} {} {} {} {:08x} {:08x} {:08x}",
            i,
            fix_ticks,
            states_ticks,
            empty_ticks,
            stack,
            s.target[0].to_f32().to_bits(),
            s.target[1].to_f32().to_bits(),
            s.uncertainty.to_f32().to_bits()
        );
    }
    probe::succeed()
}

/// One timed region: the target fix taken.
#[inline(never)]
fn take<S: Scalar>(estimator: &mut Estimator<S>, fix: &Fix) -> bool {
    estimator.target_fix(fix).is_ok()
}

/// The other: both states for a decision at `now_us`.
#[inline(never)]
fn carry<S: Scalar>(estimator: &mut Estimator<S>, now_us: u32) -> Option<Estimated<S>> {
    estimator.states(now_us).ok()
}

/// The same call doing nothing: its ticks are the call overhead.
#[inline(never)]
fn take_nothing<S: Scalar>(estimator: &mut Estimator<S>, fix: &Fix) -> bool {
    black_box((estimator, fix));
    false
}
